//! The seed's collision test and pair resolution, as small pure functions.
//!
//! [`is_colliding`] is the seed's detection rule and [`resolve_pair`] its steps 1–7, written
//! term for term so a test can check them against a hand calculation. The model options of
//! [`crate::Config`] are the only departures, and each is off by default.

use crate::config::{RestitutionModel, VelocityUpdate};

/// The normal used when two centres coincide (distance 0): `+x`. The seed divides by the
/// distance there; any fixed unit vector keeps the result finite and deterministic, and `+x`
/// pushes the first disc of the pair to the right.
pub const COINCIDENT_NORMAL: [f64; 2] = [1.0, 0.0];

/// The seed's detection rule: `distance <= (r1 + r2) * collision_radius_scale`, where
/// `diff = p1 - p2` (already the minimum image in a periodic box).
///
/// ```
/// use bounce::collision::is_colliding;
/// assert!(is_colliding([2.3, 0.0], 1.0, 1.0, 1.2));
/// assert!(!is_colliding([2.5, 0.0], 1.0, 1.0, 1.2));
/// ```
#[inline]
pub fn is_colliding(diff: [f64; 2], r1: f64, r2: f64, collision_radius_scale: f64) -> bool {
    let distance = (diff[0] * diff[0] + diff[1] * diff[1]).sqrt();
    distance <= (r1 + r2) * collision_radius_scale
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

/// The parameters of [`resolve_pair`] taken from [`crate::Config`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolveParams {
    /// The seed's `collision_radius_scale`.
    pub collision_radius_scale: f64,
    /// The seed's `COEFFICIENT_OF_RESTITUTION`.
    pub restitution: f64,
    /// How the restitution is applied.
    pub restitution_model: RestitutionModel,
    /// Which pairs get the velocity update.
    pub velocity_update: VelocityUpdate,
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
/// use bounce::collision::{resolve_pair, Body, ResolveParams};
/// use bounce::{RestitutionModel, VelocityUpdate};
/// let params = ResolveParams {
///     collision_radius_scale: 1.0,
///     restitution: 1.0,
///     restitution_model: RestitutionModel::ScaleEachNormalVelocity,
///     velocity_update: VelocityUpdate::AllDetected,
/// };
/// let a = Body { velocity: [1.0, 0.0], radius: 1.0, mass: 1.0 };
/// let b = Body { velocity: [-1.0, 0.0], radius: 1.0, mass: 1.0 };
/// // Equal discs head on at e = 1 exchange their normal velocities.
/// let out = resolve_pair([-2.0, 0.0], &a, &b, &params);
/// assert_eq!((out.v1, out.v2), ([-1.0, 0.0], [1.0, 0.0]));
/// ```
#[inline]
pub fn resolve_pair(diff: [f64; 2], a: &Body, b: &Body, params: &ResolveParams) -> Resolution {
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
    let collision_distance = (a.radius + b.radius) * params.collision_radius_scale;
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
    if params.velocity_update == VelocityUpdate::ApproachingOnly && !approaching {
        return Resolution {
            push,
            v1: a.velocity,
            v2: b.velocity,
        };
    }

    // Step 6: the 1D elastic collision with the masses, then the restitution.
    let (m1, m2) = (a.mass, b.mass);
    let e = params.restitution;
    let (v1n_new, v2n_new) = match params.restitution_model {
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
