//! Particle storage: the hot state as struct-of-arrays of `f64`, plus stable ids.
//!
//! The broadphase keeps the arrays sorted by grid cell (reordering them at each rebuild), so a
//! particle's index changes now and then; its [`ParticleId`] never does. Everything a step
//! reads or writes per particle lives here; a checkpoint is this struct, the config and the
//! broadphase's reference positions. `view.rs` holds the reading side: the slices and one
//! particle by its index.

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::parallel::{CHUNK, Executor};

mod view;

/// A particle's stable identity, assigned in order of addition from 0. A `u32` in memory
/// (`repr(transparent)`), so a slice of ids can be shared as `u32`s (the Python view does).
///
/// ```
/// use bounce::{Config, Particle, ParticleId, World};
/// let mut world = World::new(Config::default())?;
/// let a = world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 0.5))?;
/// let b = world.add_particle(Particle::new([3.0, 0.0], [0.0, 0.0], 0.5))?;
/// assert_eq!((a, b), (ParticleId(0), ParticleId(1)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[repr(transparent)]
pub struct ParticleId(pub u32);

/// A pair of ids, the lower first.
pub(crate) fn ordered(a: ParticleId, b: ParticleId) -> (ParticleId, ParticleId) {
    if a < b { (a, b) } else { (b, a) }
}

/// One disc as the user describes it: what goes into [`crate::World::add_particle`] and comes
/// out of [`crate::World::particle`].
///
/// ```
/// use bounce::{Config, Particle, World};
/// let disc = Particle {
///     mass: Some(2.0), // used by MassModel::PerParticle; other models derive it
///     angular_velocity: 1.5,
///     ..Particle::new([1.0, 2.0], [0.5, 0.0], 0.25).with_tag(42)
/// };
/// assert!(disc.turns() && disc.validate_values().is_ok());
/// let mut world = World::new(Config::default())?;
/// let id = world.add_particle(disc)?;
/// assert_eq!(world.particle(id).unwrap().tag, 42);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Particle {
    /// Centre, in length units.
    pub position: [f64; 2],
    /// Velocity, in length per time unit.
    pub velocity: [f64; 2],
    /// Radius, `> 0`.
    pub radius: f64,
    /// Mass used by [`crate::MassModel::PerParticle`]; `None` means π r² (areal density 1).
    /// Ignored by the other mass models.
    pub mass: Option<f64>,
    /// Angular velocity, counter-clockwise, in radians per time unit. Default 0. A disc
    /// given one spins (its orientation turns) even among smooth discs; only rough ones
    /// ([`crate::Config::is_rough`]) change it.
    #[serde(default)]
    pub angular_velocity: f64,
    /// Orientation, in radians counter-clockwise, kept in `[0, 2π)` as the disc turns.
    /// Default 0.
    #[serde(default)]
    pub orientation: f64,
    /// The user's own number for the disc (a game's entity, a species, a label): it
    /// follows the disc through every step, checkpoint and front end and changes nothing.
    /// Default 0.
    #[serde(default)]
    pub tag: u64,
}

impl Particle {
    /// A disc at `position` with `velocity` and `radius`, mass from the mass model (no
    /// per-particle mass, no spin, tag 0). See [`Particle`] for an example.
    pub fn new(position: [f64; 2], velocity: [f64; 2], radius: f64) -> Self {
        Particle {
            position,
            velocity,
            radius,
            mass: None,
            angular_velocity: 0.0,
            orientation: 0.0,
            tag: 0,
        }
    }

    /// The same disc with `tag` ([`Particle::tag`]). See [`Particle`] for an example.
    pub fn with_tag(self, tag: u64) -> Self {
        Particle { tag, ..self }
    }

    /// Whether it spins or has turned: a world of smooth discs keeps no rotation state until
    /// it gets such a disc.
    ///
    /// ```
    /// use bounce::Particle;
    /// let still = Particle::new([0.0, 0.0], [1.0, 0.0], 0.5);
    /// assert!(!still.turns());
    /// assert!(Particle { angular_velocity: 2.0, ..still }.turns());
    /// ```
    pub fn turns(&self) -> bool {
        self.angular_velocity != 0.0 || self.orientation != 0.0
    }
}

/// Why a particle was refused. The world is unchanged when this is returned.
///
/// ```
/// use bounce::{Boundary, Config, Particle, ParticleError, World};
/// let mut world = World::new(Config {
///     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
///     ..Config::default()
/// })?;
/// let outside = Particle::new([12.0, 5.0], [0.0, 0.0], 0.5);
/// assert!(matches!(world.add_particle(outside), Err(ParticleError::OutsideBox { .. })));
/// let bad = Particle::new([5.0, 5.0], [f64::NAN, 0.0], 0.5);
/// assert_eq!(
///     world.add_particle(bad).unwrap_err().to_string(),
///     "velocity [NaN, 0.0] is not finite"
/// );
/// assert_eq!(world.len(), 0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Error)]
pub enum ParticleError {
    /// A position component is NaN or infinite.
    #[error("position {0:?} is not finite")]
    NonFinitePosition([f64; 2]),
    /// A velocity component is NaN or infinite.
    #[error("velocity {0:?} is not finite")]
    NonFiniteVelocity([f64; 2]),
    /// The angular velocity or the orientation is NaN or infinite.
    #[error("angular velocity {0} or orientation {1} is not finite")]
    NonFiniteRotation(f64, f64),
    /// The radius is not a finite number `> 0`.
    #[error("radius {0} must be finite and > 0")]
    InvalidRadius(f64),
    /// The given mass is not a finite number `> 0`.
    #[error("mass {0} must be finite and > 0")]
    InvalidMass(f64),
    /// The centre lies outside the walls or the periodic box.
    #[error("centre {position:?} is outside the box {min:?}..{max:?}")]
    OutsideBox {
        /// The refused centre.
        position: [f64; 2],
        /// The box's lower-left corner.
        min: [f64; 2],
        /// The box's upper-right corner.
        max: [f64; 2],
    },
    /// The disc cannot fit the box (walls: its diameter exceeds a side; periodic: its
    /// interaction diameter exceeds half a side).
    #[error("radius {radius} is too large for the box of size {size:?}: {rule}")]
    TooLarge {
        /// The refused radius.
        radius: f64,
        /// Width and height of the box.
        size: [f64; 2],
        /// The rule that is broken.
        rule: &'static str,
    },
    /// The disc's collision distance with its like, `2 r collision_radius_scale`, exceeds
    /// [`MAX_INTERACTION_DIAMETER`](crate::law::MAX_INTERACTION_DIAMETER): squared (as the
    /// detection rule compares squares) it would overflow `f64`.
    #[error(
        "radius {radius} reaches {reach} (2 r collision_radius_scale), beyond 1e150: \
         the collision test squares it, which would overflow f64"
    )]
    ReachTooLarge {
        /// The refused radius.
        radius: f64,
        /// `2 r collision_radius_scale`.
        reach: f64,
    },
    /// No particle has this id.
    #[error("no particle has id {}", .0.0)]
    UnknownId(ParticleId),
    /// The disc's kinetic energy `½ m v²` overflows `f64`.
    #[error("velocity {velocity:?} gives a kinetic energy beyond f64 (mass {mass})")]
    EnergyOverflow {
        /// The refused velocity.
        velocity: [f64; 2],
        /// The disc's mass under the mass model.
        mass: f64,
    },
    /// The disc's rotational energy `½ I ω²` overflows `f64`.
    #[error(
        "angular velocity {angular_velocity} gives a rotational energy beyond f64 (moment of \
         inertia {inertia})"
    )]
    SpinEnergyOverflow {
        /// The refused angular velocity.
        angular_velocity: f64,
        /// The disc's moment of inertia.
        inertia: f64,
    },
    /// A whole-world setter was given the wrong number of values.
    #[error("{given} values for {expected} particles")]
    WrongCount {
        /// The world's particle count.
        expected: usize,
        /// How many were given.
        given: usize,
    },
    /// The world already holds `u32::MAX` particles.
    #[error("too many particles: ids are 32-bit")]
    TooMany,
}

impl Particle {
    /// Checks that every value is finite and radius and mass are positive (the box is
    /// [`Particle::validate`]'s).
    ///
    /// ```
    /// use bounce::{Particle, ParticleError};
    /// let disc = Particle::new([0.0, 0.0], [1.0, 0.0], 0.5);
    /// assert!(disc.validate_values().is_ok());
    /// let flat = Particle { radius: 0.0, ..disc };
    /// assert!(matches!(flat.validate_values(), Err(ParticleError::InvalidRadius(_))));
    /// ```
    pub fn validate_values(&self) -> Result<(), ParticleError> {
        let [x, y] = self.position;
        if !(x.is_finite() && y.is_finite()) {
            return Err(ParticleError::NonFinitePosition(self.position));
        }
        if !self.velocity.iter().all(|v| v.is_finite()) {
            return Err(ParticleError::NonFiniteVelocity(self.velocity));
        }
        if !(self.angular_velocity.is_finite() && self.orientation.is_finite()) {
            return Err(ParticleError::NonFiniteRotation(
                self.angular_velocity,
                self.orientation,
            ));
        }
        let r = self.radius;
        if !(r.is_finite() && r > 0.0) {
            return Err(ParticleError::InvalidRadius(r));
        }
        match self.mass {
            Some(m) if !(m.is_finite() && m > 0.0) => Err(ParticleError::InvalidMass(m)),
            _ => Ok(()),
        }
    }
}

/// The particles of a world, struct-of-arrays. Read it through [`crate::World::particles`];
/// index `i` addresses the same particle in every slice during one step.
///
/// ```
/// use bounce::{Config, Particle, World};
/// let mut world = World::new(Config::default())?;
/// world.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 0.5))?;
/// world.add_particle(Particle::new([4.0, 0.0], [0.0, 2.0], 1.0))?;
/// world.step(0.5)?;
/// let p = world.particles();
/// // The storage order is the engine's: find a disc by its id, or use `get`.
/// let i = p.ids().iter().position(|id| id.0 == 1).unwrap();
/// assert_eq!((p.x()[i], p.y()[i], p.vy()[i], p.radius()[i]), (4.0, 1.0, 2.0, 1.0));
/// assert_eq!(p.get(i).unwrap().position, [4.0, 1.0]);
/// assert_eq!(p.image()[i], [0, 0]); // no periodic box
/// assert!(!p.turns() && p.angular_velocity().is_empty() && p.tag().is_empty());
/// assert!(p.orientation().is_empty() && p.tag_of(i) == 0);
/// assert_eq!(p.per_particle_mass()[i], std::f64::consts::PI); // π r², none given
/// assert_eq!((p.len(), p.is_empty()), (2, false));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Particles {
    pub(crate) id: Vec<ParticleId>,
    pub(crate) x: Vec<f64>,
    pub(crate) y: Vec<f64>,
    pub(crate) vx: Vec<f64>,
    pub(crate) vy: Vec<f64>,
    pub(crate) radius: Vec<f64>,
    /// The per-particle mass (π r² when not given); used by `MassModel::PerParticle`.
    pub(crate) mass: Vec<f64>,
    /// Periodic image counts: how many box widths each disc has been wrapped by.
    pub(crate) image: Vec<[i32; 2]>,
    /// Angular velocities: empty while no disc turns (smooth discs, the seed's), one per
    /// disc from the first that does or the first rough configuration on.
    pub(crate) omega: Vec<f64>,
    /// Orientations in `[0, 2π)`, like `omega`.
    pub(crate) theta: Vec<f64>,
    /// Whether `omega` and `theta` are kept (then one per disc).
    pub(crate) turning: bool,
    /// The users' tags: empty while every disc's is 0 (no step moves them then), one per
    /// disc from the first non-zero one on.
    pub(crate) tag: Vec<u64>,
}

impl Particles {
    /// Sets disc `i`'s tag (keeping one per disc from the first non-zero one on).
    pub(crate) fn set_tag(&mut self, i: usize, tag: u64) {
        if self.tag.is_empty() && tag != 0 {
            self.tag = vec![0; self.len()];
        }
        if let Some(t) = self.tag.get_mut(i) {
            *t = tag;
        }
    }

    /// Starts keeping rotation state (zeros) for every disc, if not yet.
    pub(crate) fn start_turning(&mut self) {
        if !self.turning {
            self.turning = true;
            self.omega = vec![0.0; self.len()];
            self.theta = vec![0.0; self.len()];
        }
    }

    pub(crate) fn push(&mut self, id: ParticleId, p: &Particle) {
        if p.turns() {
            self.start_turning();
        }
        if self.turning {
            self.omega.push(p.angular_velocity);
            self.theta.push(p.orientation);
        }
        self.id.push(id);
        self.x.push(p.position[0]);
        self.y.push(p.position[1]);
        self.vx.push(p.velocity[0]);
        self.vy.push(p.velocity[1]);
        self.radius.push(p.radius);
        self.mass
            .push(p.mass.unwrap_or(std::f64::consts::PI * p.radius * p.radius));
        self.image.push([0, 0]);
        self.push_tag(p.tag);
    }

    /// Appends the tag of a disc just pushed.
    pub(crate) fn push_tag(&mut self, tag: u64) {
        if !self.tag.is_empty() {
            self.tag.push(tag);
        } else if tag != 0 {
            self.tag = vec![0; self.len()];
            *self.tag.last_mut().expect("a disc") = tag;
        }
    }

    /// Keeps the discs `keep` says (by storage index), in order; returns how many went.
    pub(crate) fn retain(&mut self, keep: impl Fn(usize) -> bool) -> usize {
        let n = self.len();
        let mut to = 0;
        for i in 0..n {
            if keep(i) {
                self.id[to] = self.id[i];
                self.x[to] = self.x[i];
                self.y[to] = self.y[i];
                self.vx[to] = self.vx[i];
                self.vy[to] = self.vy[i];
                self.radius[to] = self.radius[i];
                self.mass[to] = self.mass[i];
                self.image[to] = self.image[i];
                if self.turning {
                    self.omega[to] = self.omega[i];
                    self.theta[to] = self.theta[i];
                }
                if !self.tag.is_empty() {
                    self.tag[to] = self.tag[i];
                }
                to += 1;
            }
        }
        self.truncate(to);
        n - to
    }

    pub(crate) fn truncate(&mut self, len: usize) {
        self.id.truncate(len);
        self.x.truncate(len);
        self.y.truncate(len);
        self.vx.truncate(len);
        self.vy.truncate(len);
        self.radius.truncate(len);
        self.mass.truncate(len);
        self.image.truncate(len);
        self.omega.truncate(len);
        self.theta.truncate(len);
        self.tag.truncate(len);
    }

    /// Reorders every array so that new index `k` holds old index `order[k]`. Each array is
    /// gathered into the scratch array in parallel chunks and swapped in, so the old array
    /// becomes the scratch for the next one; the ids (and, in a periodic box, the image
    /// counts, which stay zero elsewhere) are gathered into the scratch viewed as their type
    /// and copied back. An array whose values all have the same bits (the radii and masses
    /// of equal discs) is the same in any order and is left alone: a scan that reads it once
    /// in order instead of a gather that reads it out of order and writes it again. Extra
    /// memory: one `f64` array. With `equal_radii` the caller knows every radius is the same
    /// (the broadphase found the smallest and largest equal), and the radii are not scanned.
    pub(crate) fn permute(
        &mut self,
        order: &[u32],
        scratch: &mut PermuteScratch,
        exec: &Executor,
        periodic: bool,
        equal_radii: bool,
    ) {
        let n = self.len();
        debug_assert_eq!(order.len(), n);
        debug_assert!(!equal_radii || self.radius.iter().all(|r| *r == self.radius[0]));
        for (v, known_same) in [
            (&mut self.x, false),
            (&mut self.y, false),
            (&mut self.vx, false),
            (&mut self.vy, false),
            (&mut self.radius, equal_radii),
            (&mut self.mass, false),
            // (Empty while no disc turns: nothing to move.)
            (&mut self.omega, false),
            (&mut self.theta, false),
        ] {
            if known_same || all_same_bits(v, exec) {
                continue;
            }
            let out = scratch.f64s(n);
            gather(v, order, out, exec, |&v| v);
            std::mem::swap(v, &mut scratch.f64);
        }
        let out = scratch.u32s(n);
        gather(&self.id, order, out, exec, |id| id.0);
        // Copied back in parallel chunks too: a serial copy was a twentieth of the 1M gas's
        // rebuild on two threads.
        let mut chunks: Vec<_> = self
            .id
            .chunks_mut(GATHER_CHUNK)
            .zip(out.chunks(GATHER_CHUNK))
            .collect();
        exec.for_each_mut(n, &mut chunks, |_, (ids, values)| {
            for (id, &v) in ids.iter_mut().zip(values.iter()) {
                *id = ParticleId(v);
            }
        });
        if periodic {
            let out: &mut [[i32; 2]] = bytemuck::cast_slice_mut(scratch.f64s(n));
            gather(&self.image, order, out, exec, |&v| v);
            self.image.copy_from_slice(out);
        }
        // (Empty while every tag is 0.)
        if !self.tag.is_empty() {
            let out: &mut [u64] = bytemuck::cast_slice_mut(scratch.f64s(n));
            gather(&self.tag, order, out, exec, |&v| v);
            self.tag.copy_from_slice(out);
        }
    }
}

/// Discs per parallel piece of a gather.
const GATHER_CHUNK: usize = 16 * CHUNK;

/// Whether every value of `v` has the bits of the first, scanned in parallel chunks; the
/// positions and velocities of a gas differ at once, so their scans stop at the second
/// value.
fn all_same_bits(v: &[f64], exec: &Executor) -> bool {
    let Some(first) = v.first().map(|f| f.to_bits()) else {
        return true;
    };
    if v.get(1).is_some_and(|s| s.to_bits() != first) {
        return false;
    }
    let mut chunks: Vec<&[f64]> = v.chunks(GATHER_CHUNK).collect();
    exec.map_mut(v.len(), &mut chunks, |_, chunk| {
        // Branch-free within a block of values: the common answer reads the whole array.
        chunk.chunks(64).all(|block| {
            block
                .iter()
                .fold(true, |same, v| same & (v.to_bits() == first))
        })
    })
    .into_iter()
    .all(|same| same)
}

/// `out[k] = f(v[order[k]])`, in parallel chunks.
fn gather<S: Sync, T: Send>(
    v: &[S],
    order: &[u32],
    out: &mut [T],
    exec: &Executor,
    f: impl Fn(&S) -> T + Sync,
) {
    let mut chunks: Vec<_> = out
        .chunks_mut(GATHER_CHUNK)
        .zip(order.chunks(GATHER_CHUNK))
        .collect();
    exec.for_each_mut(order.len(), &mut chunks, |_, (slots, order)| {
        for (slot, &i) in slots.iter_mut().zip(order.iter()) {
            *slot = f(&v[i as usize]);
        }
    });
}

/// Buffers [`Particles::permute`] reuses between steps.
#[derive(Debug, Default)]
pub(crate) struct PermuteScratch {
    f64: Vec<f64>,
}

impl PermuteScratch {
    /// The scratch as `n` `f64`s (contents unspecified).
    pub(crate) fn f64s(&mut self, n: usize) -> &mut [f64] {
        self.f64.resize(n, 0.0);
        &mut self.f64
    }

    /// The scratch as at least `n` `u32`s (contents unspecified): the broadphase sorts its
    /// cell keys here, so no array of its own is needed.
    pub(crate) fn u32s(&mut self, n: usize) -> &mut [u32] {
        // Grow only: shrinking would make the next `f64s` fill the tail again.
        if self.f64.len() < n.div_ceil(2) {
            self.f64.resize(n.div_ceil(2), 0.0);
        }
        &mut bytemuck::cast_slice_mut(&mut self.f64[..])[..n]
    }

    /// [`PermuteScratch::u32s`], and up to `extra` more where the scratch already has them
    /// (after a permutation it holds `n` `f64`s, room for `2n` `u32`s): it never grows for
    /// them, so they cost no memory.
    pub(crate) fn u32s_and_room(&mut self, n: usize, extra: usize) -> &mut [u32] {
        self.u32s(n);
        let all: &mut [u32] = bytemuck::cast_slice_mut(&mut self.f64[..]);
        let len = all.len().min(n + extra);
        &mut all[..len]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permuting_moves_every_array_and_skips_none_that_differ() {
        // Equal radii and masses (skipped, since any order is the same), then differing ones
        // (gathered); both on one and two threads, every chunk of the scan met (three
        // gather chunks and a tail).
        let n = 3 * GATHER_CHUNK + 77;
        let order: Vec<u32> = (0..n as u32).map(|k| (k * 7919) % n as u32).collect();
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert!(
            sorted.iter().enumerate().all(|(k, &i)| i as usize == k),
            "a permutation"
        );
        for threads in [1, 2] {
            let mut exec = Executor::new(threads).unwrap();
            exec.min_work = 0;
            for differ in [None, Some(1), Some(n - 1), Some(GATHER_CHUNK + 5)] {
                let mut p = Particles::default();
                for i in 0..n {
                    let radius = if Some(i) == differ { 0.75 } else { 0.5 };
                    let particle = Particle {
                        mass: Some(if Some(i) == differ { 2.0 } else { 1.0 }),
                        ..Particle::new([i as f64, -(i as f64)], [0.5 * i as f64, 1.0], radius)
                    };
                    p.push(ParticleId(i as u32 + 10), &particle);
                    p.image[i] = [i as i32, -1];
                }
                let before = p.clone();
                // Told the radii are equal when they are: the same result, unscanned.
                let equal_radii = differ.is_none();
                p.permute(
                    &order,
                    &mut PermuteScratch::default(),
                    &exec,
                    true,
                    equal_radii,
                );
                for (k, &old) in order.iter().enumerate() {
                    let old = old as usize;
                    assert_eq!(p.id[k], before.id[old]);
                    assert_eq!(p.image[k], before.image[old]);
                    for (now, then) in [
                        (&p.x, &before.x),
                        (&p.y, &before.y),
                        (&p.vx, &before.vx),
                        (&p.vy, &before.vy),
                        (&p.radius, &before.radius),
                        (&p.mass, &before.mass),
                    ] {
                        assert_eq!(now[k].to_bits(), then[old].to_bits(), "{differ:?} {k}");
                    }
                }
            }
        }
        assert!(all_same_bits(&[], &Executor::default()));
        assert!(!all_same_bits(&[0.0, -0.0], &Executor::default()));
    }

    #[test]
    fn the_scratch_gives_room_it_has_and_never_grows_for_it() {
        let mut scratch = PermuteScratch::default();
        // Fresh: room for the keys alone (rounded up to whole f64s).
        assert_eq!(scratch.u32s_and_room(7, 100).len(), 8);
        assert_eq!(scratch.f64.len(), 4);
        // After a permutation's f64s: twice the keys, at most what is asked.
        scratch.f64s(7);
        assert_eq!(scratch.u32s_and_room(7, 3).len(), 10);
        assert_eq!(scratch.u32s_and_room(7, 100).len(), 14);
        assert_eq!(scratch.f64.len(), 7);
    }
}
