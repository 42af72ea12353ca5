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

use crate::config::{Config, MassModel, RestitutionModel, VelocityUpdate};

/// The normal used when two centres coincide (distance 0): `+x`. The seed divides by the
/// distance there; any fixed unit vector keeps the result finite and deterministic, and `+x`
/// pushes the first disc of the pair to the right.
pub const COINCIDENT_NORMAL: [f64; 2] = [1.0, 0.0];

/// The collision law of a world: the seed's parameters and the model options, taken from
/// [`Config`] once ([`Law::new`]).
///
/// ```
/// use bounce::{Config, law::Law};
/// let law = Law::new(&Config { collision_radius_scale: 1.2, ..Config::default() });
/// assert_eq!(law.collision_distance(1.0, 1.0), 2.4);
/// assert!(law.is_colliding([2.3, 0.0], 1.0, 1.0));
/// assert!(!law.is_colliding([2.5, 0.0], 1.0, 1.0));
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
}

impl Law {
    /// The law `config` describes (which should be valid: see [`Config::validate`]).
    pub fn new(config: &Config) -> Law {
        Law {
            collision_radius_scale: config.collision_radius_scale,
            restitution: config.coefficient_of_restitution,
            restitution_model: config.restitution_model,
            velocity_update: config.velocity_update,
            mass_model: config.mass_model,
        }
    }

    /// The centre distance within which two discs whose radii add up to `radius_sum`
    /// collide: `radius_sum * collision_radius_scale`. Every reach in the engine (pair
    /// collision distances, a disc's interaction diameter, grid cells, placement spacing) is
    /// this of some sum of radii, so the detection law changes here alone.
    #[inline(always)]
    pub fn reach(&self, radius_sum: f64) -> f64 {
        radius_sum * self.collision_radius_scale
    }

    /// The seed's `collision_distance = (r1 + r2) * collision_radius_scale`.
    #[inline(always)]
    pub fn collision_distance(&self, r1: f64, r2: f64) -> f64 {
        self.reach(r1 + r2)
    }

    /// The collision distance of two discs of radius `r`: how far a disc's influence
    /// extends, what grid cells must hold.
    #[inline(always)]
    pub fn interaction_diameter(&self, r: f64) -> f64 {
        self.reach(2.0 * r)
    }

    /// The seed's detection rule, `distance <= collision_distance`, where `diff = p1 - p2`
    /// (already the minimum image in a periodic box).
    #[inline(always)]
    pub fn is_colliding(&self, diff: [f64; 2], r1: f64, r2: f64) -> bool {
        let distance = (diff[0] * diff[0] + diff[1] * diff[1]).sqrt();
        distance <= self.collision_distance(r1, r2)
    }

    /// The mass of a disc of `radius` whose per-particle mass is `per_particle`.
    #[inline(always)]
    pub fn mass(&self, radius: f64, per_particle: f64) -> f64 {
        self.mass_model.mass(radius, per_particle)
    }

    /// The seed's steps 1–7 for one detected pair: see [`resolve_pair`].
    #[inline(always)]
    pub fn resolve(&self, diff: [f64; 2], a: &Body, b: &Body) -> Resolution {
        resolve_pair(diff, a, b, self)
    }
}

/// One side of a pair going into [`resolve_pair`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Velocity.
    pub velocity: [f64; 2],
    /// Radius (the seed's `r` in the collision distance).
    pub radius: f64,
    /// Mass under the active [`crate::MassModel`] (the radius, for the seed).
    pub mass: f64,
}

/// What resolving a pair changes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    /// Displacement of the first disc; the second moves by its negation (step 3, half each).
    pub push: [f64; 2],
    /// New velocity of the first disc.
    pub v1: [f64; 2],
    /// New velocity of the second disc.
    pub v2: [f64; 2],
}

/// The seed's steps 1–7 for one detected pair, on the current state. `diff = p1 - p2` is the
/// current position difference (step 1; the minimum image in a periodic box).
///
/// Step 3 pushes the discs apart, half each, only while `distance < collision_distance`.
/// Steps 4–7 replace the normal velocities with the 1D elastic result for masses `m1`, `m2`
/// (the seed uses the radii), scaled by the restitution, and keep the tangential ones.
///
/// ```
/// use bounce::law::{resolve_pair, Body, Law};
/// use bounce::Config;
/// let law = Law::new(&Config::default());
/// let a = Body { velocity: [1.0, 0.0], radius: 1.0, mass: 1.0 };
/// let b = Body { velocity: [-1.0, 0.0], radius: 1.0, mass: 1.0 };
/// // Equal discs head on at e = 1 exchange their normal velocities.
/// let out = resolve_pair([-2.0, 0.0], &a, &b, &law);
/// assert_eq!((out.v1, out.v2), ([-1.0, 0.0], [1.0, 0.0]));
/// ```
#[inline]
pub fn resolve_pair(diff: [f64; 2], a: &Body, b: &Body, law: &Law) -> Resolution {
    // Step 2: the current distance.
    let distance = (diff[0] * diff[0] + diff[1] * diff[1]).sqrt();
    // Step 4: the collision normal (from 2 to 1) and tangent; fixed normal at distance 0.
    let n = if distance > 0.0 {
        [diff[0] / distance, diff[1] / distance]
    } else {
        COINCIDENT_NORMAL
    };
    let t = [-n[1], n[0]];

    // Step 3: push apart half each while overlapping.
    let collision_distance = law.collision_distance(a.radius, b.radius);
    let push = if distance < collision_distance {
        let overlap = collision_distance - distance;
        [n[0] * overlap / 2.0, n[1] * overlap / 2.0]
    } else {
        [0.0, 0.0]
    };

    // Step 5: normal and tangent components.
    let dot = |v: [f64; 2], u: [f64; 2]| v[0] * u[0] + v[1] * u[1];
    let (v1n, v1t) = (dot(a.velocity, n), dot(a.velocity, t));
    let (v2n, v2t) = (dot(b.velocity, n), dot(b.velocity, t));

    let approaching = v1n - v2n < 0.0;
    if law.velocity_update == VelocityUpdate::ApproachingOnly && !approaching {
        return Resolution {
            push,
            v1: a.velocity,
            v2: b.velocity,
        };
    }

    // Step 6: the 1D elastic collision with the masses, then the restitution.
    let (m1, m2) = (a.mass, b.mass);
    let e = law.restitution;
    let (v1n_new, v2n_new) = match law.restitution_model {
        RestitutionModel::ScaleEachNormalVelocity => (
            (v1n * (m1 - m2) + 2.0 * m2 * v2n) / (m1 + m2) * e,
            (v2n * (m2 - m1) + 2.0 * m1 * v1n) / (m1 + m2) * e,
        ),
        RestitutionModel::RelativeNormalVelocity => {
            let momentum = m1 * v1n + m2 * v2n;
            (
                (momentum + m2 * e * (v2n - v1n)) / (m1 + m2),
                (momentum + m1 * e * (v1n - v2n)) / (m1 + m2),
            )
        }
    };

    // Step 7: recombine normal and tangent parts.
    Resolution {
        push,
        v1: [v1n_new * n[0] + v1t * t[0], v1n_new * n[1] + v1t * t[1]],
        v2: [v2n_new * n[0] + v2t * t[0], v2n_new * n[1] + v2t * t[1]],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
