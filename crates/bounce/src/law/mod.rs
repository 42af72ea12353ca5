//! The collision law: when two discs collide and what a collision does to them.
//!
//! This module is the one place that knows the seed's rule,
//! `distance <= (r_i + r_j) * collision_radius_scale`, and its pair resolution (steps 1–7),
//! written term for term so a test can check them against a hand calculation. A [`Law`] is
//! built once from [`Config`]; the broadphase asks it for interaction reaches, detection for
//! collision distances, the solver for resolutions, and scene placement and the scenario's
//! blocks for the spacing that keeps discs apart. Changing the detection law is a change
//! here and nowhere else.
//!
//! The model options of [`Config`] are the only departures from the seed, each off by default.

use crate::config::{Config, MassModel, RestingContacts, RestitutionModel, VelocityUpdate};

mod obstacle;
mod pair;
pub mod rough;
mod wall;

pub(crate) use obstacle::{Disc, collide, nearest, reach_of, touches};
pub use pair::{Body, Resolution, resolve_pair};
pub(crate) use pair::{pair_impulse, resolve_lanes, virial_terms};
pub use rough::Rough;
pub(crate) use wall::{hold, reflect, rub_walls, touch_walls};

/// The normal used when two centres coincide (distance 0): `+x`. The seed divides by the
/// distance there; any fixed unit vector keeps the result finite and deterministic, and `+x`
/// pushes the first disc of the pair to the right.
///
/// ```
/// use bounce::{Config, law::{Body, COINCIDENT_NORMAL, Law}};
/// // Two equal discs on the same spot: pushed apart along ±x, half the overlap (2) each.
/// let (a, b) = (Body::new([0.0, 0.0], 1.0, 1.0), Body::new([0.0, 0.0], 1.0, 1.0));
/// let out = Law::new(&Config::default()).resolve([0.0, 0.0], &a, &b);
/// assert_eq!(out.push, [COINCIDENT_NORMAL[0], COINCIDENT_NORMAL[1]]);
/// ```
pub const COINCIDENT_NORMAL: [f64; 2] = [1.0, 0.0];

/// The largest collision distance a disc may have with its like, `2 r collision_radius_scale`:
/// the detection rule compares squared distances, and `1e150²` is still far inside `f64`
/// (its largest is about `1.8e308`), with room for the sums of two such reaches.
///
/// ```
/// use bounce::{Config, Particle, ParticleError, World, law::MAX_INTERACTION_DIAMETER};
/// let mut world = World::new(Config::default())?;
/// let huge = Particle::new([0.0, 0.0], [0.0, 0.0], MAX_INTERACTION_DIAMETER);
/// assert!(matches!(world.add_particle(huge), Err(ParticleError::ReachTooLarge { .. })));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub const MAX_INTERACTION_DIAMETER: f64 = 1e150;

/// The collision law of a world: the seed's parameters and the model options, taken from
/// [`Config`] once ([`Law::new`]).
///
/// ```
/// use bounce::{Config, law::{Body, Law}};
/// let law = Law::new(&Config { collision_radius_scale: 1.2, ..Config::default() });
/// assert_eq!(law.collision_distance(1.0, 1.0), 2.4);
/// assert_eq!((law.reach(2.0), law.interaction_diameter(1.0)), (2.4, 2.4));
/// assert!(law.is_colliding([2.3, 0.0], 1.0, 1.0));
/// assert!(!law.is_colliding([2.5, 0.0], 1.0, 1.0));
/// assert!((law.overlap([2.3, 0.0], 1.0, 1.0).unwrap() - 0.1).abs() < 1e-12);
/// assert_eq!(law.mass(2.0, 7.0), 2.0); // the seed's mass = radius
/// // The seed's steps 1–7 for a head-on pair of equal discs, e = 1: they swap velocities,
/// // and the overlap (2.4 − 2.3 = 0.1) is pushed apart half each.
/// let (a, b) = (Body::new([1.0, 0.0], 1.0, 1.0), Body::new([-1.0, 0.0], 1.0, 1.0));
/// let out = law.for_pass(0).resolve([-2.3, 0.0], &a, &b);
/// assert_eq!((out.v1, out.v2), ([-1.0, 0.0], [1.0, 0.0]));
/// assert!((out.push[0] + 0.05).abs() < 1e-12 && out.approach == 2.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Law {
    /// The seed's `collision_radius_scale`.
    pub collision_radius_scale: f64,
    /// The seed's `COEFFICIENT_OF_RESTITUTION`.
    pub restitution: f64,
    /// How the restitution is applied.
    pub restitution_model: RestitutionModel,
    /// Which pairs get the velocity update.
    pub velocity_update: VelocityUpdate,
    /// The mass each disc has in the collision.
    pub mass_model: MassModel,
    /// The normal speed at or below which a contact rests (is resolved as perfectly
    /// inelastic; see [`RestingContacts::Rest`]): `None`, no contact rests, under the seed's
    /// [`RestingContacts::Bounce`], without gravity, and in a law from [`Law::new`], which
    /// knows no substep; the [`resting_speed`] of the substep in one from [`Law::at_substep`].
    pub rest_below: Option<f64>,
    /// Friction and rolling resistance ([`rough`]); `None` for the seed's smooth discs
    /// ([`Config::is_rough`]).
    pub rough: Option<Rough>,
}

impl Law {
    /// The law `config` describes (which should be valid: see [`Config::validate`]), at no
    /// particular substep: what detection and placement need. Resting contacts depend on the
    /// substep, and here none rests; the law a step applies is [`Law::at_substep`]. See
    /// [`Law`] for an example.
    pub fn new(config: &Config) -> Law {
        Law {
            collision_radius_scale: config.collision_radius_scale,
            restitution: config.coefficient_of_restitution,
            restitution_model: config.restitution_model,
            velocity_update: config.velocity_update,
            mass_model: config.mass_model,
            rest_below: None,
            rough: config.is_rough().then(|| Rough {
                friction: config.friction,
                wall_friction: config.wall_friction(),
                tangential_restitution: config.tangential_restitution,
                rolling_resistance: config.rolling_resistance,
                inertia_factor: config.inertia_factor,
            }),
        }
    }

    /// The law a substep of length `h` under `config` applies: [`Law::new`] with, under
    /// [`RestingContacts::Rest`] and gravity, the contacts at or below the
    /// [`resting_speed`] resting.
    ///
    /// ```
    /// use bounce::{Config, RestingContacts, law::Law};
    /// let config = Config { gravity: [0.0, -10.0], ..Config::default() };
    /// assert_eq!(Law::at_substep(&config, 0.01).rest_below, None);
    /// let rest = Config { resting_contacts: RestingContacts::Rest, ..config };
    /// assert_eq!(Law::at_substep(&rest, 0.01).rest_below, Some(0.4));
    /// ```
    pub fn at_substep(config: &Config, h: f64) -> Law {
        let speed = resting_speed(config.gravity, h);
        Law {
            rest_below: (config.resting_contacts == RestingContacts::Rest && speed > 0.0)
                .then_some(speed),
            ..Law::new(config)
        }
    }

    /// The restitution `e` of a wall or an obstacle as this law applies it: see
    /// [`Restitution`]. See there for an example.
    #[inline(always)]
    pub fn restitution_of(&self, e: f64) -> Restitution {
        Restitution {
            e,
            rest_below: self.rest_below,
        }
    }

    /// The centre distance within which two discs whose radii add up to `radius_sum`
    /// collide: `radius_sum * collision_radius_scale`. Every reach in the engine (pair
    /// collision distances, a disc's interaction diameter, grid cells, placement spacing) is
    /// this of some sum of radii, so the detection law changes here alone. See [`Law`] for
    /// an example.
    #[inline(always)]
    pub fn reach(&self, radius_sum: f64) -> f64 {
        radius_sum * self.collision_radius_scale
    }

    /// The seed's `collision_distance = (r1 + r2) * collision_radius_scale`. See [`Law`] for
    /// an example.
    #[inline(always)]
    pub fn collision_distance(&self, r1: f64, r2: f64) -> f64 {
        self.reach(r1 + r2)
    }

    /// The collision distance of two discs of radius `r`: how far a disc's influence
    /// extends, what grid cells must hold. See [`Law`] for an example.
    #[inline(always)]
    pub fn interaction_diameter(&self, r: f64) -> f64 {
        self.reach(2.0 * r)
    }

    /// The seed's detection rule, `distance <= collision_distance`, where `diff = p1 - p2`
    /// (already the minimum image in a periodic box). See [`Law`] for an example.
    #[inline(always)]
    pub fn is_colliding(&self, diff: [f64; 2], r1: f64, r2: f64) -> bool {
        self.overlap(diff, r1, r2).is_some()
    }

    /// The seed's detection rule with what it measured: `Some(overlap)`, the collision
    /// distance less the distance (0 when touching), when the pair collides. See [`Law`] for
    /// an example.
    #[inline(always)]
    pub fn overlap(&self, diff: [f64; 2], r1: f64, r2: f64) -> Option<f64> {
        touching(diff, self.collision_distance(r1, r2))
    }

    /// The mass of a disc of `radius` whose per-particle mass is `per_particle`. See [`Law`]
    /// for an example.
    #[inline(always)]
    pub fn mass(&self, radius: f64, per_particle: f64) -> f64 {
        self.mass_model.mass(radius, per_particle)
    }

    /// The law solver pass `pass` (from 0) applies. The first is this law; a later one
    /// (`solver_iterations > 1`) updates the velocities only of pairs still approaching,
    /// whatever `velocity_update` says. The first pass leaves a pair it pushed apart at
    /// exactly its collision distance, which `<=` detects again: under the seed's update of
    /// every detected pair, a later pass would send two discs that had just met head on back
    /// into each other (they would lock), and apply the restitution once a pass. The push is
    /// the same in every pass (only while the pair overlaps), and a single pass is the
    /// seed's. See [`Law`] for an example.
    pub fn for_pass(&self, pass: u32) -> Law {
        if pass == 0 {
            *self
        } else {
            Law {
                velocity_update: VelocityUpdate::ApproachingOnly,
                ..*self
            }
        }
    }

    /// The seed's steps 1–7 for one detected pair: see [`resolve_pair`]. See [`Law`] for an
    /// example.
    #[inline(always)]
    pub fn resolve(&self, diff: [f64; 2], a: &Body, b: &Body) -> Resolution {
        resolve_pair(diff, a, b, self)
    }

    /// [`Law::resolve`] with `b` seen from `a`'s side of a Lees–Edwards box's top or
    /// bottom: the law gets `b`'s image, `image_velocity` faster along x, and `b` keeps its
    /// own velocity (the same as `resolve` when it is 0).
    #[inline(always)]
    pub(crate) fn resolve_seen(
        &self,
        diff: [f64; 2],
        a: &Body,
        b: &Body,
        image_velocity: f64,
    ) -> Resolution {
        if image_velocity == 0.0 {
            return self.resolve(diff, a, b);
        }
        let mut seen = *b;
        seen.velocity[0] += image_velocity;
        let mut out = self.resolve(diff, a, &seen);
        out.v2[0] -= image_velocity;
        out
    }
}

/// A wall's or an obstacle's restitution `e` as a step applies it: a disc meeting it at a
/// normal speed at or below `rest_below` (a resting contact, [`RestingContacts::Rest`]) gets
/// restitution 0 instead. See [`Restitution::at`] for an example.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restitution {
    /// The restitution of impacts.
    pub e: f64,
    /// The normal speed at or below which a contact rests ([`Law::rest_below`]).
    pub rest_below: Option<f64>,
}

impl Restitution {
    /// The restitution of a contact met at normal speed `speed` (`>= 0`).
    ///
    /// ```
    /// use bounce::{Config, RestingContacts, law::Law};
    /// let law = Law::at_substep(
    ///     &Config { gravity: [0.0, -10.0], resting_contacts: RestingContacts::Rest, ..Config::default() },
    ///     0.01,
    /// );
    /// let wall = law.restitution_of(0.8);
    /// assert_eq!((wall.at(0.3), wall.at(5.0)), (0.0, 0.8)); // resting below 4 |g| h = 0.4
    /// ```
    #[inline(always)]
    pub fn at(self, speed: f64) -> f64 {
        match self.rest_below {
            Some(rest) if speed <= rest => 0.0,
            _ => self.e,
        }
    }
}

/// How many substeps of gravity's pull a resting contact's approach speed may hold: a disc
/// resting on another (or on a wall-held one) is pulled into it by `|g| h` each substep,
/// and the seed's exchange of normal velocities passes that speed up and down a stack, so
/// resting contacts approach at a few `|g| h`; impacts (a drop of even one disc radius) come
/// far faster. See [`resting_speed`] for an example.
pub const RESTING_SUBSTEPS: f64 = 4.0;

/// The approach speed below which a detected pair is a resting contact, not an impact:
/// [`RESTING_SUBSTEPS`] substeps `h` of gravity `g` (0 without gravity: every approaching
/// pair is an impact).
///
/// ```
/// use bounce::law::{is_impact, resting_speed};
/// let rest = resting_speed([0.0, -9.81], 0.01); // 4 substeps of gravity's pull
/// assert!((rest - 0.3924).abs() < 1e-12);
/// assert!(is_impact(1.0, rest) && !is_impact(0.2, rest));
/// assert!(is_impact(1e-9, resting_speed([0.0, 0.0], 0.01))); // no gravity: any approach
/// ```
#[inline]
pub fn resting_speed(gravity: [f64; 2], h: f64) -> f64 {
    RESTING_SUBSTEPS * gravity[0].hypot(gravity[1]) * h
}

/// Whether a detected pair that approached at `approach` (the normal speed before the update,
/// [`Resolution::approach`]) is an **impact**, which the step's `collisions` count, rather
/// than a resting contact, which only its `contacts` count: it approached faster than
/// `resting_speed`. See [`resting_speed`] for an example.
#[inline(always)]
pub fn is_impact(approach: f64, resting_speed: f64) -> bool {
    approach > resting_speed
}

/// **The detection rule**, the one place it is written: two things whose centre difference
/// (to a peg's centre, or a segment's nearest point) is `diff` and whose collision distance
/// is `reach` collide when `distance <= reach`; then `Some(reach - distance)`, the overlap.
/// Every kernel asks this (or [`within`] on a distance it has, [`sqrt_limit`] and
/// [`may_touch`], which answer from the squared distance): pairs, strays, the obstacles, the plain step. A NaN
/// distance never collides.
///
/// ```
/// use bounce::law::{may_touch, sqrt_limit, touching, within};
/// assert_eq!(touching([3.0, 4.0], 6.0), Some(1.0)); // distance 5, reach 6: overlap 1
/// assert_eq!(touching([3.0, 4.0], 5.0), Some(0.0)); // touching counts
/// assert_eq!(touching([3.0, 4.0], 4.9), None);
/// assert!(within(5.0, 5.0) && !within(f64::NAN, 5.0));
/// // From the squared distance: a cheap screen, and the exact limit.
/// assert!(may_touch(25.0, 5.0) && !may_touch(30.0, 5.0));
/// assert!(25.0 <= sqrt_limit(5.0));
/// ```
#[inline(always)]
pub fn touching(diff: [f64; 2], reach: f64) -> Option<f64> {
    let distance = (diff[0] * diff[0] + diff[1] * diff[1]).sqrt();
    within(distance, reach).then_some(reach - distance)
}

/// [`touching`] for a kernel that has the distance already (and needs it after). See
/// [`touching`] for an example.
#[inline(always)]
pub fn within(distance: f64, reach: f64) -> bool {
    distance <= reach
}

/// A screen before [`touching`]: `false` only where the squared distance `d2` rules a
/// collision at `reach` out (a relative margin far wider than the rounding of `reach²`), so
/// a kernel may skip the square root for most candidates. See [`touching`] for an example.
#[inline(always)]
pub fn may_touch(d2: f64, reach: f64) -> bool {
    d2 <= reach * reach * (1.0 + 1e-12)
}

/// The largest `d2` whose correctly rounded square root is at most `reach` (finite, `>= 0`):
/// `d2 <= sqrt_limit(reach)` exactly when [`touching`] is `Some` for a squared distance
/// `d2`, as the square root is monotone. A couple of steps of one unit in the last place
/// from `reach²`. Kernels with one collision distance for every pair test with it. See
/// [`touching`] for an example.
pub fn sqrt_limit(reach: f64) -> f64 {
    let mut limit = reach * reach;
    while limit.next_up().sqrt() <= reach {
        limit = limit.next_up();
    }
    while limit.sqrt() > reach {
        limit = limit.next_down();
    }
    limit
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_impact_approaches_faster_than_four_substeps_of_gravity() {
        // |g| = 5 (a 3-4-5 vector), h = 0.01: resting contacts approach at up to 0.2.
        assert_eq!(resting_speed([3.0, -4.0], 0.01), 0.2);
        assert!(is_impact(0.21, 0.2) && !is_impact(0.2, 0.2) && !is_impact(-1.0, 0.2));
        // Without gravity every approaching pair is an impact; a separating one is not.
        assert_eq!(resting_speed([0.0, 0.0], 0.01), 0.0);
        assert!(is_impact(1e-12, 0.0) && !is_impact(0.0, 0.0));
        // The approach is v2n − v1n along the normal from 2 to 1: head on at 1 each, 2.
        let law = Law::new(&Config::default());
        let body = |vx: f64| Body::new([vx, 0.0], 1.0, 1.0);
        let out = resolve_pair([-2.0, 0.0], &body(1.0), &body(-1.0), &law);
        assert_eq!(out.approach, 2.0);
    }

    #[test]
    fn every_reach_is_a_scaled_sum_of_radii() {
        let law = Law::new(&Config {
            collision_radius_scale: 1.5,
            ..Config::default()
        });
        assert_eq!(law.reach(2.0), 3.0);
        assert_eq!(law.collision_distance(1.0, 3.0), 6.0);
        assert_eq!(law.interaction_diameter(0.5), 1.5);
        // The rule is `<=`: touching at exactly the collision distance collides.
        assert!(law.is_colliding([0.0, 6.0], 1.0, 3.0));
        assert!(!law.is_colliding([0.0, 6.000001], 1.0, 3.0));
    }
}
