//! Parts of a world: what a distributed run (the CLI's MPI front end) needs from the core to
//! step one world as many, each rank holding the discs of its region and a halo of copies
//! of its neighbours' ("ghosts"), and still get one process's bits.
//!
//! Three things make a part step exactly as the whole world would, for the discs far enough
//! from its halo's edge:
//! - the state's evolution depends on the discs' positions, radii, ids and the
//!   configuration only, never on storage order or which discs are stored (the contact order
//!   is canonical, `contacts`), so a part holding every disc within the reach of the step's
//!   chains of contacts computes those discs' new states exactly;
//! - the contact order's grid is sized for the largest radius of the *whole* world
//!   (`World::set_order_radius`), not the part's;
//! - the step's sums are exact ([`crate::ExactSum`]), and each part counts only the events in
//!   its region (`World::set_tally`: contacts by their lower-id disc's place, wall hits by
//!   the disc's place), so the ranks' sums merge into the whole world's, bit for bit.
//!
//! [`DiscRecord`] is a disc's whole state, for moving discs between parts.

use serde::{Deserialize, Serialize};

use crate::particles::ParticleId;

/// Which events a part's sums count: those whose place (after wrapping into a periodic box)
/// lies in a rectangle `[x0, x1) × [y0, y1)`. The parts' rectangles tile the world, so every
/// event is counted once.
///
/// ```
/// use bounce::{Tally, wrap_coordinate};
/// // The left half of a periodic box [0, 10) × [0, 10): x in [0, 5), any y.
/// let left = Tally::new([0.0, 5.0], [f64::NEG_INFINITY, f64::INFINITY], [Some((0.0, 10.0)), None]);
/// assert!(left.counts(2.0, 7.0) && !left.counts(6.0, 7.0));
/// assert!(left.counts(10.5, 0.0)); // wrapped to x = 0.5 first
/// assert_eq!(wrap_coordinate(-1.0, 0.0, 10.0), 9.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tally {
    axes: [Span; 2],
}

/// One axis of a [`Tally`]: `[lo, hi)`, and `(min, size)` of a periodic box.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Span {
    lo: f64,
    hi: f64,
    period: Option<(f64, f64)>,
}

impl Tally {
    /// Events with `lo <= v < hi` along each axis (`x` then `y`), `v` first wrapped into
    /// `[min, min + size)` where that axis's `period` is `Some((min, size))`. Use infinite
    /// ends at the world's edges. See [`Tally`] for an example.
    pub fn new(x: [f64; 2], y: [f64; 2], period: [Option<(f64, f64)>; 2]) -> Tally {
        let span = |[lo, hi]: [f64; 2], period| Span { lo, hi, period };
        Tally {
            axes: [span(x, period[0]), span(y, period[1])],
        }
    }

    /// Whether an event at `(x, y)` is counted here. See [`Tally`] for an example.
    #[inline]
    pub fn counts(&self, x: f64, y: f64) -> bool {
        [x, y].iter().zip(&self.axes).all(|(&v, span)| {
            let v = match span.period {
                Some((min, size)) => wrap_coordinate(v, min, size),
                None => v,
            };
            span.lo <= v && v < span.hi
        })
    }
}

/// `v` wrapped into `[min, min + size)` by the periodic box's own wrap (the one integration
/// applies, `geometry::wrap`, so a stored position is its own wrap): the one formula every
/// rank uses to say which region a place is in. See [`Tally`] for an example.
#[inline]
pub fn wrap_coordinate(v: f64, min: f64, size: f64) -> f64 {
    let mut v = v;
    crate::geometry::wrap(&mut v, min, size);
    v
}

/// Upper bounds on how far any disc of a world has moved, kept at no cost from the
/// broadphase's own check (each disc's distance from where it was at the last listing of the
/// candidates). No per-disc state: a distributed run asks this instead of remembering where
/// each of its discs was. Distances are as measured (from `f32` reference positions: within
/// about 10^-7 of the box's size), and the pushes of the step's last pass are seen at the
/// next integration. See [`crate::World::regroup`] for an example.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Travel {
    /// How far any disc can be from where it was when the world was made.
    pub since_start: f64,
    /// How far any disc is from where it was at the last listing (the broadphase's
    /// reference), as of the last integration.
    pub since_listing: f64,
}

impl Travel {
    /// One substep's integration measured `displacement2` (the largest squared distance from
    /// the reference; infinite without one) and `stride` (the fastest disc's move); `rebuilt`:
    /// the candidates were listed again, from here.
    pub(crate) fn note(&mut self, displacement2: f64, stride: f64, rebuilt: bool) {
        let done = self.since_start - self.since_listing;
        if !displacement2.is_finite() {
            // No reference: from the last known bound, one stride.
            self.since_start += stride;
            self.since_listing = 0.0;
            return;
        }
        let d = displacement2.sqrt();
        self.since_start = done + d;
        self.since_listing = if rebuilt { 0.0 } else { d };
    }
}

/// One disc's whole state: what moves between the parts of a distributed world.
///
/// ```
/// use bounce::{Config, DiscRecord, Particle, World};
/// let mut world = World::new(Config::default())?;
/// world.add_particle(Particle::new([1.0, 2.0], [3.0, 4.0], 0.5).with_tag(9))?;
/// let record = world.record(0);
/// let words = record.to_words();
/// assert_eq!(words.len(), DiscRecord::WORDS);
/// assert_eq!(DiscRecord::from_words(&words), record);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DiscRecord {
    /// Its id in the whole world.
    pub id: ParticleId,
    /// Centre.
    pub position: [f64; 2],
    /// Velocity.
    pub velocity: [f64; 2],
    /// Radius.
    pub radius: f64,
    /// The per-particle mass (see [`crate::Particle::mass`]).
    pub mass: f64,
    /// Periodic image counts.
    pub image: [i32; 2],
    /// Angular velocity (0 for a disc that never turned).
    pub angular_velocity: f64,
    /// Orientation.
    pub orientation: f64,
    /// The user's tag.
    pub tag: u64,
}

impl DiscRecord {
    /// How many `f64` words [`DiscRecord::to_words`] writes. See [`DiscRecord`] for an example.
    pub const WORDS: usize = 12;

    /// The record as words (ids and image counts are exact in an `f64`; the tag travels as
    /// its bits). See [`DiscRecord`] for an example.
    pub fn to_words(&self) -> [f64; Self::WORDS] {
        [
            f64::from(self.id.0),
            self.position[0],
            self.position[1],
            self.velocity[0],
            self.velocity[1],
            self.radius,
            self.mass,
            f64::from(self.image[0]),
            f64::from(self.image[1]),
            self.angular_velocity,
            self.orientation,
            f64::from_bits(self.tag),
        ]
    }

    /// The record [`DiscRecord::to_words`] wrote. See [`DiscRecord`] for an example.
    pub fn from_words(w: &[f64]) -> DiscRecord {
        DiscRecord {
            id: ParticleId(w[0] as u32),
            position: [w[1], w[2]],
            velocity: [w[3], w[4]],
            radius: w[5],
            mass: w[6],
            image: [w[7] as i32, w[8] as i32],
            angular_velocity: w[9],
            orientation: w[10],
            tag: w[11].to_bits(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Boundary, Config, Particle, World};

    #[test]
    fn tallies_wrap_periodic_places_and_tile_the_box() {
        let (inf, period) = (f64::INFINITY, [Some((0.0, 10.0)), Some((-5.0, 20.0))]);
        // Four quarters of a periodic box.
        let quarters: Vec<Tally> = [[-inf, 5.0], [5.0, inf]]
            .iter()
            .flat_map(|&x| [[-inf, 3.0], [3.0, inf]].map(|y| Tally::new(x, y, period)))
            .collect();
        for x in [-0.5, 0.0, 4.999, 5.0, 9.99, 10.0, 10.5, 23.0] {
            for y in [-5.5, -5.0, 2.99, 3.0, 14.9, 15.0, 40.0] {
                let count = quarters.iter().filter(|t| t.counts(x, y)).count();
                assert_eq!(count, 1, "({x}, {y}) counted once");
            }
        }
        assert!(quarters[3].counts(-0.5, 14.0)); // x wraps to 9.5
        assert!(quarters[1].counts(10.5, -6.0)); // x wraps to 0.5, y to 14
        let open = Tally::new([-inf, inf], [1.0, 2.0], [None, None]);
        assert!(open.counts(7.0, 1.0) && !open.counts(7.0, 2.0) && !open.counts(7.0, 11.5));
    }

    #[test]
    fn travel_bounds_how_far_every_disc_has_moved() {
        // A gas with walls: every disc's distance from its start stays under the bound.
        let config = Config {
            boundary: Boundary::Walls {
                min: [0.0, 0.0],
                max: [30.0, 30.0],
                wall_restitution: None,
            },
            ..Config::default()
        };
        let mut world = World::new(config).unwrap();
        world
            .add_particles((0..200).map(|k| {
                let (x, y) = (1.0 + (k % 14) as f64 * 2.0, 1.0 + (k / 14) as f64 * 2.0);
                Particle::new(
                    [x, y],
                    [((k * 7) % 5) as f64 - 2.0, ((k * 3) % 7) as f64 - 3.0],
                    0.4,
                )
            }))
            .unwrap();
        let start: Vec<_> = world.particles_by_id();
        let mut last_bound = 0.0;
        for _ in 0..300 {
            world.step(0.02).unwrap();
            let bound = world.travel().since_start;
            assert!(bound >= last_bound, "the bound never shrinks");
            last_bound = bound;
            let farthest = start
                .iter()
                .map(|(id, p)| {
                    let now = world.particle(*id).unwrap().position;
                    (now[0] - p.position[0]).hypot(now[1] - p.position[1])
                })
                .fold(0.0, f64::max);
            // Pushes of the step's last pass are seen at the next integration: one
            // diameter's slack.
            assert!(farthest <= bound + 0.8, "moved {farthest} > bound {bound}");
        }
        assert!(last_bound > 1.0, "the discs did move");
    }

    #[test]
    fn records_round_trip_through_words_and_parts() {
        let config = Config {
            boundary: Boundary::Periodic {
                min: [0.0, 0.0],
                max: [10.0, 10.0],
            },
            ..Config::default()
        };
        let mut world = World::new(config).unwrap();
        world
            .add_particles((0..5).map(|k| {
                Particle::new(
                    [1.0 + 2.0 * k as f64, 5.0],
                    [k as f64, -1.0],
                    0.1 + k as f64 * 0.1,
                )
            }))
            .unwrap();
        for _ in 0..30 {
            world.step(0.1).unwrap();
        }
        let all: Vec<DiscRecord> = (0..world.len()).map(|i| world.record(i)).collect();
        assert!(all.iter().any(|r| r.image != [0, 0]), "some disc wrapped");
        for r in &all {
            assert_eq!(DiscRecord::from_words(&r.to_words()), *r);
        }
        // A part of discs 3 and 1, in that order, with the clock.
        let picked = [all[3], all[1]];
        let part = world.part(&picked).unwrap();
        assert_eq!(part.len(), 2);
        assert_eq!(part.step_count(), world.step_count());
        assert_eq!(part.time(), world.time());
        assert_eq!(part.record(0), picked[0]);
        assert_eq!(part.particle(all[1].id), world.particle(all[1].id));
        // The whole, rebuilt from its records in reverse, steps to the same bits.
        let mut reversed = all.clone();
        reversed.reverse();
        let mut whole = world.part(&reversed).unwrap();
        assert_eq!(whole.state_hash(), world.state_hash());
        for _ in 0..20 {
            world.step(0.1).unwrap();
            whole.step(0.1).unwrap();
        }
        assert_eq!(whole.state_hash(), world.state_hash());
        // Overwriting puts a disc's state back; an unknown id is an error.
        let moved = picked[1].id;
        let mut part = world.part(&picked).unwrap();
        part.overwrite(&[(moved, [7.5, 7.5, 1.0, 2.0, 3.0])])
            .unwrap();
        let disc = part.particle(moved).unwrap();
        assert_eq!((disc.position, disc.velocity), ([7.5, 7.5], [1.0, 2.0]));
        assert_eq!(disc.angular_velocity, 0.0, "smooth discs keep no spin");
        assert!(part.overwrite(&[(all[4].id, [0.0; 5])]).is_err());
        // Repeated ids are refused.
        assert!(world.part(&[all[0], all[0]]).is_err());
        // Regrouping: discs 1 and 3 leave, 0 arrives; one held already is refused.
        let mut part = world.part(&[all[1], all[2], all[3]]).unwrap();
        let leaving = [all[1].id, all[3].id];
        let ids: Vec<_> = part.particles().ids().to_vec();
        part.regroup(|i| !leaving.contains(&ids[i]), &[all[0]])
            .unwrap();
        let mut held: Vec<_> = part.particles().ids().to_vec();
        held.sort();
        assert_eq!(held, [all[0].id, all[2].id]);
        assert!(part.regroup(|_| true, &[all[2]]).is_err());
        assert_eq!(part.len(), 2, "nothing changed");
    }
}
