//! What a step reports: energy, momentum, collisions, wall impulses, overlap.

use serde::{Deserialize, Serialize};

use crate::config::MassModel;
use crate::parallel::{CHUNK, Executor};
use crate::particles::Particles;
use crate::sum::WallImpulse;

/// Measurements of the last [`crate::World::step`].
///
/// ```
/// use bounce::{Boundary, Config, Particle, World};
/// let mut world = World::new(Config {
///     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
///     ..Config::default()
/// })?;
/// world.add_particle(Particle::new([3.0, 5.0], [1.0, 0.0], 1.0))?;
/// world.add_particle(Particle::new([5.5, 5.0], [-1.0, 0.0], 1.0))?;
/// let stats = *world.step(0.3)?; // they meet head-on and swap velocities
/// assert_eq!((stats.collisions, stats.pairs, stats.substeps), (1, 1, 1));
/// assert_eq!(stats.kinetic_energy, 1.0); // ½ · 1 · 1 twice: kept
/// assert_eq!(stats.momentum, [0.0, 0.0]);
/// assert_eq!(stats.wall_impulse.total(), 0.0);
/// assert!(stats.pressure.is_some() && stats.virial > 0.0);
/// assert!(world.profile().total() >= 0.0); // wall-clock seconds of its stages
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepStats {
    /// Total kinetic energy `Σ ½ m v²` after the step, with the active mass model.
    pub kinetic_energy: f64,
    /// Total linear momentum `Σ m v` after the step, with the active mass model.
    pub momentum: [f64; 2],
    /// Contacts: colliding pairs found (distance <= collision distance), summed over the
    /// substeps. A resting contact counts in every substep it lasts.
    pub pairs: usize,
    /// Collisions: the contacts that were impacts ([`crate::law::is_impact`]: approaching
    /// faster than gravity's pull over a few substeps, [`crate::law::resting_speed`]),
    /// summed over the substeps. A blow down a touching Newton's cradle is one per pair; a
    /// pile at rest has none.
    pub collisions: usize,
    /// Momentum delivered to each wall during the step, summed over the substeps.
    pub wall_impulse: WallImpulse,
    /// Largest `collision_distance - distance` among the pairs found in any substep, or 0.
    pub max_overlap: f64,
    /// The collision virial of the step, `W = (1/2) Σ r_ij · Δp_ij / dt` over the pairs
    /// resolved in all its substeps (`r_ij = p_i - p_j`, `Δp_ij` the impulse on `i`): the
    /// interaction part of the 2D virial equation `P A = N kT + W`. Energy units.
    pub virial: f64,
    /// The pressure `(K + W) / A` where `K` is the kinetic energy in the centre-of-mass
    /// frame (`N kT` in 2D) and `A` the area the centres move in: the periodic box's area,
    /// or between walls `(width − d)(height − d)` with `d` the mean diameter (walls stop a
    /// centre one radius short; exact for equal discs). `None` in an open world, which has no
    /// area. Force per length in 2D (M T⁻²); in a walled box it matches the walls' impulse per
    /// time and length.
    pub pressure: Option<f64>,
    /// The substeps the step took: `Config::substeps`, or more when `Config::max_travel`
    /// asked for them.
    pub substeps: u32,
    /// Work done on the discs by moving obstacles during the step, `Σ J · u` over their
    /// collisions (`J` the disc's impulse, `u` the obstacle's velocity): what a piston puts
    /// into the gas.
    pub obstacle_work: f64,
    /// The energy friction and rolling resistance removed during the step (rough discs,
    /// [`crate::law::rough`]); 0 for smooth ones. [`crate::World::friction_work`] adds it up.
    pub friction_work: f64,
    /// The kinetic energy the thermostat added at the end of the step (negative where it
    /// took energy away; [`crate::Config::thermostat`]); 0 without one.
    pub thermostat_work: f64,
    /// The collision virial tensor of the step, `[W_xx, W_yy, W_xy]` with
    /// `W_ab = Σ r_a J_b / dt` over the pairs resolved in all its substeps (`xy`
    /// symmetrised), so that [`StepStats::virial`] is `(W_xx + W_yy) / 2`; measured only
    /// with [`crate::Config::pressure_tensor`] (zero otherwise). See
    /// [`crate::World::pressure_tensor`].
    pub virial_tensor: [f64; 3],
    /// Discs the emitters added at the start of the step.
    pub emitted: usize,
    /// Discs the sinks removed at the end of the step.
    pub removed: usize,
}

impl StepStats {
    /// The first measured value that is not finite, by name (`None` when all are).
    pub(crate) fn first_non_finite(&self) -> Option<&'static str> {
        let w = &self.wall_impulse;
        [
            ("kinetic_energy", self.kinetic_energy),
            ("momentum", self.momentum[0]),
            ("momentum", self.momentum[1]),
            ("max_overlap", self.max_overlap),
            ("virial", self.virial),
            ("wall_impulse", w.left),
            ("wall_impulse", w.right),
            ("wall_impulse", w.bottom),
            ("wall_impulse", w.top),
            ("pressure", self.pressure.unwrap_or(0.0)),
            ("obstacle_work", self.obstacle_work),
            ("friction_work", self.friction_work),
            ("thermostat_work", self.thermostat_work),
        ]
        .into_iter()
        .find(|(_, v)| !v.is_finite())
        .map(|(name, _)| name)
    }
}

/// Wall-clock seconds spent in each stage of the last step, summed over its substeps.
/// All zero on `wasm32`, which has no clock in `std`. See [`StepStats`] for an example.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepProfile {
    /// Integration: gravity, drift and the walls.
    pub integrate: f64,
    /// Broadphase upkeep: checking the candidate list and, when discs have moved too far,
    /// rebuilding it (levels, grids, counting sort, reordering into cell order, listing).
    pub bin: f64,
    /// Testing the candidates and sorting the contacts into canonical order.
    pub pairs: f64,
    /// Pair resolution.
    pub resolve: f64,
    /// Obstacles: moving them, sending back discs that crossed a segment, and meeting
    /// them after each solver pass.
    pub obstacles: f64,
    /// Holding the walls after the later solver passes (`solver_iterations` > 1).
    pub walls: f64,
    /// Energy and momentum sums.
    pub measure: f64,
    /// How many substeps rebuilt the candidate list.
    pub rebuilds: usize,
    /// The most discs past the list's allowance in a substep that kept the list (met
    /// alone: `broadphase::strays`).
    pub strays: usize,
    /// Detections that sorted their contacts into the canonical order; the others (in dense
    /// worlds) found them in the order of candidates presorted at the listing.
    pub sorted_detections: usize,
    /// Contacts the presorted detections found out of place (a disc changed order block
    /// since the presort), sorted apart and merged in.
    pub out_of_place: usize,
}

impl StepProfile {
    /// Total over the stages. See [`StepStats`] for an example.
    pub fn total(&self) -> f64 {
        self.integrate
            + self.bin
            + self.pairs
            + self.resolve
            + self.obstacles
            + self.walls
            + self.measure
    }
}

/// A stopwatch that reads nothing where `std` has no clock.
pub(crate) struct Stopwatch {
    #[cfg(not(target_arch = "wasm32"))]
    last: std::time::Instant,
}

impl Stopwatch {
    pub(crate) fn start() -> Self {
        Stopwatch {
            #[cfg(not(target_arch = "wasm32"))]
            last: std::time::Instant::now(),
        }
    }

    /// Seconds since the last lap (or the start).
    pub(crate) fn lap(&mut self) -> f64 {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let now = std::time::Instant::now();
            let dt = (now - self.last).as_secs_f64();
            self.last = now;
            dt
        }
        #[cfg(target_arch = "wasm32")]
        0.0
    }
}

/// What one pass over the discs measures: the sums of the step's statistics and what the
/// next step needs to choose its substeps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Measured {
    pub kinetic_energy: f64,
    pub momentum: [f64; 2],
    /// The total mass (set by the world, in id order, when discs or the config change).
    pub total_mass: f64,
    /// The largest squared speed (only measured for adaptive substeps).
    pub max_speed2: f64,
    /// The smallest radius (infinite without discs; only for adaptive substeps).
    pub min_radius: f64,
    /// The sum of the radii (set by the world like the total mass).
    pub radius_sum: f64,
}

/// Kinetic energy and momentum of all discs, and with `extremes` the
/// largest speed and the smallest radius (what adaptive substeps need; the minimum and
/// maximum cost as much as the rest of the sweep, so only then), summed in fixed chunks
/// (thread-count independent).
///
/// The total mass and the radius sum change only when discs or the configuration do: the
/// world sums them in id order then (`World::totals_by_id`), not here.
pub(crate) fn measure(
    p: &Particles,
    mass_model: MassModel,
    uniform_radius: Option<f64>,
    exec: &Executor,
    extremes: bool,
) -> Measured {
    if extremes {
        measure_pass::<true>(p, mass_model, uniform_radius, exec)
    } else {
        measure_pass::<false>(p, mass_model, uniform_radius, exec)
    }
}

/// A chunk's running sums (a small `Copy` struct the loop keeps in registers).
#[derive(Clone, Copy)]
struct ChunkSums {
    e: f64,
    px: f64,
    py: f64,
    max_speed2: f64,
    min_radius: f64,
}

impl ChunkSums {
    /// Adds a disc of mass `m`, velocity `(vx, vy)` and radius `r` (used only with
    /// `EXTREMES`).
    #[inline(always)]
    fn add<const EXTREMES: bool>(&mut self, m: f64, vx: f64, vy: f64, r: f64) {
        let v2 = vx * vx + vy * vy;
        self.e += 0.5 * m * v2;
        self.px += m * vx;
        self.py += m * vy;
        if EXTREMES {
            self.max_speed2 = self.max_speed2.max(v2);
            self.min_radius = self.min_radius.min(r);
        }
    }
}

/// [`measure`] with `extremes` fixed. Where every disc has radius `uniform_radius` and the
/// mass follows the radius (the seed's model, or the area's), every disc weighs the same and
/// the sweep reads the velocities alone: a third less memory for the same bits (each disc's
/// mass is the same value either way).
fn measure_pass<const EXTREMES: bool>(
    p: &Particles,
    mass_model: MassModel,
    uniform_radius: Option<f64>,
    exec: &Executor,
) -> Measured {
    let n = p.len();
    let one_mass = match mass_model {
        MassModel::Radius | MassModel::Area => uniform_radius,
        MassModel::PerParticle => None,
    };
    let partial = exec.map_index(n, 0..n.div_ceil(CHUNK), |chunk| {
        let range = chunk * CHUNK..((chunk + 1) * CHUNK).min(n);
        let (vx, vy) = (&p.vx[range.clone()], &p.vy[range.clone()]);
        let mut sums = ChunkSums {
            e: 0.0,
            px: 0.0,
            py: 0.0,
            max_speed2: 0.0,
            min_radius: f64::INFINITY,
        };
        match one_mass {
            Some(r) => {
                let m = mass_model.mass(r, 0.0);
                for (&vx, &vy) in vx.iter().zip(vy) {
                    sums.add::<EXTREMES>(m, vx, vy, r);
                }
            }
            None => {
                let (radius, mass) = (&p.radius[range.clone()], &p.mass[range]);
                for (((&vx, &vy), &r), &mass) in vx.iter().zip(vy).zip(radius).zip(mass) {
                    sums.add::<EXTREMES>(mass_model.mass(r, mass), vx, vy, r);
                }
            }
        }
        Measured {
            kinetic_energy: sums.e,
            momentum: [sums.px, sums.py],
            max_speed2: sums.max_speed2,
            min_radius: sums.min_radius,
            ..Measured::default()
        }
    });
    partial.iter().fold(
        Measured {
            min_radius: f64::INFINITY,
            ..Measured::default()
        },
        |a, b| Measured {
            kinetic_energy: a.kinetic_energy + b.kinetic_energy,
            momentum: [a.momentum[0] + b.momentum[0], a.momentum[1] + b.momentum[1]],
            total_mass: 0.0,
            max_speed2: a.max_speed2.max(b.max_speed2),
            min_radius: a.min_radius.min(b.min_radius),
            radius_sum: 0.0,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::{Particle, ParticleId};

    #[test]
    fn equal_discs_measure_the_same_bits_without_reading_their_radii() {
        // Velocities over many magnitudes (so rounding shows), in two chunks and a tail, and
        // masses of their own that only the per-particle model reads.
        let n = 2 * CHUNK + 123;
        let mut p = Particles::default();
        for i in 0..n {
            let s = (i as f64 * 0.618_033_988_7).fract();
            let v = [(s - 0.5) * 10f64.powi((i % 7) as i32 - 3), s * 3.7 - 1.1];
            let mut disc = Particle::new([i as f64, 0.0], v, 0.37);
            disc.mass = Some(1.0 + s);
            p.push(ParticleId(i as u32), &disc);
        }
        let exec = Executor::new(2).unwrap();
        for model in [MassModel::Radius, MassModel::Area, MassModel::PerParticle] {
            for extremes in [false, true] {
                let read = measure(&p, model, None, &exec, extremes);
                let known = measure(&p, model, Some(0.37), &exec, extremes);
                let bits = |m: &Measured| {
                    [
                        m.kinetic_energy,
                        m.momentum[0],
                        m.momentum[1],
                        m.max_speed2,
                        m.min_radius,
                    ]
                    .map(f64::to_bits)
                };
                assert_eq!(bits(&known), bits(&read), "{model:?}, extremes {extremes}");
                // And against the definition, summed one chunk at a time.
                let mass = |i: usize| model.mass(p.radius[i], p.mass[i]);
                let mut energy = 0.0;
                for chunk in (0..n).collect::<Vec<_>>().chunks(CHUNK) {
                    let part: f64 = chunk.iter().fold(0.0, |e, &i| {
                        e + 0.5 * mass(i) * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i])
                    });
                    energy += part;
                }
                assert_eq!(
                    known.kinetic_energy.to_bits(),
                    energy.to_bits(),
                    "{model:?}"
                );
                if extremes {
                    assert_eq!(known.min_radius, 0.37);
                }
            }
        }
    }
}
