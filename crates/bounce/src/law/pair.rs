//! What a collision does to a pair of discs: the seed's steps 1–7, written once over
//! [`Lanes`] for one pair, two or four at a time, with the same bits either way; for rough
//! discs, then the tangential impulse and the rolling couple of [`super::rough`].

use crate::config::{RestitutionModel, VelocityUpdate};
use crate::lanes::Lanes;

use super::{COINCIDENT_NORMAL, Law};

/// One side of a pair going into [`resolve_pair`]. See there (or [`Law`]) for an example.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Velocity.
    pub velocity: [f64; 2],
    /// Radius (the seed's `r` in the collision distance).
    pub radius: f64,
    /// Mass under the active [`crate::MassModel`] (the radius, for the seed).
    pub mass: f64,
    /// Angular velocity (counter-clockwise), read only by a rough law
    /// ([`Law::rough`](super::Law::rough)).
    pub angular_velocity: f64,
}

impl Body {
    /// A body that does not spin. See [`resolve_pair`] for an example.
    pub fn new(velocity: [f64; 2], radius: f64, mass: f64) -> Body {
        Body {
            velocity,
            radius,
            mass,
            angular_velocity: 0.0,
        }
    }
}

/// What resolving a pair changes. See [`resolve_pair`] (or [`Law`]) for an example.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    /// Displacement of the first disc; the second moves by its negation (step 3, half each).
    pub push: [f64; 2],
    /// New velocity of the first disc.
    pub v1: [f64; 2],
    /// New velocity of the second disc.
    pub v2: [f64; 2],
    /// How fast the discs approached along the normal before the update (`v2n - v1n`;
    /// negative when they were separating): what tells an impact from a resting contact.
    pub approach: f64,
    /// New angular velocity of the first disc (its old one under a smooth law).
    pub w1: f64,
    /// New angular velocity of the second disc.
    pub w2: f64,
    /// The energy friction and rolling resistance removed (0 under a smooth law).
    pub friction_work: f64,
}

/// The seed's steps 1–7 for one detected pair, on the current state. `diff = p1 - p2` is the
/// current position difference (step 1; the minimum image in a periodic box).
///
/// Step 3 pushes the discs apart, half each, only while `distance < collision_distance`.
/// Steps 4–7 replace the normal velocities with the 1D elastic result for masses `m1`, `m2`
/// (the seed uses the radii), scaled by the restitution, and keep the tangential ones.
/// Rough discs then get the tangential impulse and the rolling couple of [`super::rough`].
///
/// ```
/// use bounce::law::{resolve_pair, Body, Law};
/// use bounce::Config;
/// let law = Law::new(&Config::default());
/// let a = Body::new([1.0, 0.0], 1.0, 1.0);
/// let b = Body::new([-1.0, 0.0], 1.0, 1.0);
/// // Equal discs head on at e = 1 exchange their normal velocities.
/// let out = resolve_pair([-2.0, 0.0], &a, &b, &law);
/// assert_eq!((out.v1, out.v2), ([-1.0, 0.0], [1.0, 0.0]));
/// ```
#[inline]
pub fn resolve_pair(diff: [f64; 2], a: &Body, b: &Body, law: &Law) -> Resolution {
    let out = resolve_lanes(
        diff,
        [a.velocity, b.velocity],
        [a.radius, b.radius],
        [a.mass, b.mass],
        law,
    );
    let smooth = Resolution {
        push: out.push,
        v1: out.v1,
        v2: out.v2,
        approach: out.approach,
        w1: a.angular_velocity,
        w2: b.angular_velocity,
        friction_work: 0.0,
    };
    let Some(rough) = law.rough.filter(|r| r.rubs_pairs()) else {
        return smooth;
    };
    let rubbed = super::rough::rub_pair(
        out.normal,
        [a.velocity, b.velocity],
        [out.v1, out.v2],
        [a.angular_velocity, b.angular_velocity],
        [a.radius, b.radius],
        [a.mass, b.mass],
        law.collision_radius_scale,
        &rough,
    );
    Resolution {
        v1: rubbed.v1,
        v2: rubbed.v2,
        w1: rubbed.omega1,
        w2: rubbed.omega2,
        friction_work: rubbed.work,
        ..smooth
    }
}

impl Resolution {
    /// The pair's impulse on the first disc: the antisymmetric part of the two momentum
    /// changes, `(m₁Δv₁ − m₂Δv₂) / 2`, which is the impulse itself when the model conserves
    /// momentum (and what the virial and the contact reports count when it does not).
    ///
    /// ```
    /// use bounce::law::{resolve_pair, Body, Law};
    /// use bounce::Config;
    /// let law = Law::new(&Config::default());
    /// // Equal discs head on at ±1 along x, elastic: they swap velocities.
    /// let (a, b) = (Body::new([1.0, 0.0], 1.0, 1.0), Body::new([-1.0, 0.0], 1.0, 1.0));
    /// let out = resolve_pair([-2.0, 0.0], &a, &b, &law);
    /// assert_eq!(out.impulse(&a, &b), [-2.0, 0.0]);
    /// ```
    pub fn impulse(&self, a: &Body, b: &Body) -> [f64; 2] {
        pair_impulse(
            [a.velocity, b.velocity],
            [self.v1, self.v2],
            [a.mass, b.mass],
        )
    }
}

/// The pair's impulse on the first disc from the velocities `before` and `after` and the
/// masses ([`Resolution::impulse`]), in lanes: every pair's bookkeeping (the virial and its
/// tensor, contact reports, the event engine's sums) takes its impulse from here.
#[inline(always)]
pub(crate) fn pair_impulse<L: Lanes>(
    before: [[L; 2]; 2],
    after: [[L; 2]; 2],
    mass: [L; 2],
) -> [L; 2] {
    let half = L::splat(0.5);
    // (Written out, not `[0, 1].map`: the compiler left that closure out of line.)
    let along = |k: usize| {
        half * (mass[0] * (after[0][k] - before[0][k]) - mass[1] * (after[1][k] - before[1][k]))
    };
    [along(0), along(1)]
}

/// A pair's terms of the collision virial: `r · J` and the tensor's
/// `[r_x J_x, r_y J_y, ½ (r_x J_y + r_y J_x)]` (its trace is `r · J`), `r` the separation
/// `x₁ − x₂` and `J` the impulse on the first disc ([`pair_impulse`]).
#[inline(always)]
pub(crate) fn virial_terms<L: Lanes>(diff: [L; 2], impulse: [L; 2]) -> (L, [L; 3]) {
    let half = L::splat(0.5);
    (
        diff[0] * impulse[0] + diff[1] * impulse[1],
        [
            diff[0] * impulse[0],
            diff[1] * impulse[1],
            half * (diff[0] * impulse[1] + diff[1] * impulse[0]),
        ],
    )
}

/// [`Resolution`] in lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LaneResolution<L> {
    /// The collision normal, from disc 2 to disc 1.
    pub normal: [L; 2],
    pub push: [L; 2],
    pub v1: [L; 2],
    pub v2: [L; 2],
    pub approach: L,
}

/// The seed's steps 1–7 ([`resolve_pair`]) for a pair per lane: written once, for one pair
/// (`f64`) or two at once (`lanes::F64x2`), with the same operations in the same order
/// either way, so both give the same bits (see `lanes`). Branches of the scalar form are
/// selections here: both sides are computed and each lane keeps its own.
#[inline(always)]
pub(crate) fn resolve_lanes<L: Lanes>(
    diff: [L; 2],
    velocity: [[L; 2]; 2],
    radius: [L; 2],
    mass: [L; 2],
    law: &Law,
) -> LaneResolution<L> {
    let (zero, one) = (L::splat(0.0), L::splat(1.0));
    // Step 2: the current distance.
    let distance = (diff[0] * diff[0] + diff[1] * diff[1]).sqrt();
    // Step 4: the collision normal (from 2 to 1) and tangent; fixed normal at distance 0.
    let apart = distance.gt(zero);
    let n = [
        L::select(apart, diff[0] / distance, L::splat(COINCIDENT_NORMAL[0])),
        L::select(apart, diff[1] / distance, L::splat(COINCIDENT_NORMAL[1])),
    ];
    let t = [-n[1], n[0]];

    // Step 3: push apart half each while overlapping.
    let collision_distance = (radius[0] + radius[1]) * L::splat(law.collision_radius_scale);
    let overlapping = distance.lt(collision_distance);
    let overlap = collision_distance - distance;
    let two = one + one;
    let push = [
        L::select(overlapping, n[0] * overlap / two, zero),
        L::select(overlapping, n[1] * overlap / two, zero),
    ];

    // Step 5: normal and tangent components.
    let dot = |v: [L; 2], u: [L; 2]| v[0] * u[0] + v[1] * u[1];
    let [va, vb] = velocity;
    let (v1n, v1t) = (dot(va, n), dot(va, t));
    let (v2n, v2t) = (dot(vb, n), dot(vb, t));

    // Step 6: the 1D elastic collision with the masses, then the restitution.
    let [m1, m2] = mass;
    let approach = v2n - v1n;
    let e = L::splat(law.restitution);
    // A resting contact (`RestingContacts::Rest`), approaching or separating no faster than
    // `rest_below`, gets restitution 0.
    let e = match law.rest_below {
        None => e,
        Some(rest) => {
            let rest = L::splat(rest);
            let approaching_fast = L::select(approach.gt(rest), e, zero);
            L::select(approach.lt(-rest), e, approaching_fast)
        }
    };
    let (v1n_new, v2n_new) = match law.restitution_model {
        RestitutionModel::ScaleEachNormalVelocity => (
            (v1n * (m1 - m2) + two * m2 * v2n) / (m1 + m2) * e,
            (v2n * (m2 - m1) + two * m1 * v1n) / (m1 + m2) * e,
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
    let v1 = [v1n_new * n[0] + v1t * t[0], v1n_new * n[1] + v1t * t[1]];
    let v2 = [v2n_new * n[0] + v2t * t[0], v2n_new * n[1] + v2t * t[1]];
    if law.velocity_update == VelocityUpdate::ApproachingOnly {
        // Separating pairs keep their velocities.
        let approaching = (v1n - v2n).lt(zero);
        let keep = |new: [L; 2], old: [L; 2]| {
            [
                L::select(approaching, new[0], old[0]),
                L::select(approaching, new[1], old[1]),
            ]
        };
        return LaneResolution {
            normal: n,
            push,
            v1: keep(v1, va),
            v2: keep(v2, vb),
            approach,
        };
    }
    LaneResolution {
        normal: n,
        push,
        v1,
        v2,
        approach,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::MassModel;

    #[test]
    fn two_pairs_in_lanes_give_each_pair_its_scalar_bits() {
        use crate::lanes::F64x2;
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        type Case = ([f64; 2], Body, Body);
        let bodies = |next: &mut dyn FnMut() -> f64| -> Case {
            let r = [0.1 + next(), 0.1 + 2.0 * next()];
            // Overlapping, touching, apart, coincident.
            let d = match (next() * 4.0) as u32 {
                0 => (r[0] + r[1]) * next(),
                1 => r[0] + r[1],
                2 => (r[0] + r[1]) * (1.0 + next()),
                _ => 0.0,
            };
            let angle = std::f64::consts::TAU * next();
            let diff = [d * libm::cos(angle), d * libm::sin(angle)];
            let body = |r: f64, next: &mut dyn FnMut() -> f64| {
                Body::new(
                    [4.0 * next() - 2.0, 4.0 * next() - 2.0],
                    r,
                    r * (0.5 + next()),
                )
            };
            (diff, body(r[0], next), body(r[1], next))
        };
        for restitution_model in [
            RestitutionModel::ScaleEachNormalVelocity,
            RestitutionModel::RelativeNormalVelocity,
        ] {
            for (velocity_update, rest_below) in [
                (VelocityUpdate::AllDetected, None),
                (VelocityUpdate::ApproachingOnly, None),
                (VelocityUpdate::AllDetected, Some(1.5)),
                (VelocityUpdate::ApproachingOnly, Some(1.5)),
            ] {
                let law = Law {
                    collision_radius_scale: 1.1,
                    restitution: 0.8,
                    restitution_model,
                    velocity_update,
                    mass_model: MassModel::Radius,
                    rest_below,
                    rough: None,
                };
                for _ in 0..2000 {
                    let (one, two) = (bodies(&mut next), bodies(&mut next));
                    let lanes = |f: &dyn Fn(&Case) -> f64| F64x2::new(f(&one), f(&two));
                    let out = resolve_lanes(
                        [lanes(&|c| c.0[0]), lanes(&|c| c.0[1])],
                        [
                            [lanes(&|c| c.1.velocity[0]), lanes(&|c| c.1.velocity[1])],
                            [lanes(&|c| c.2.velocity[0]), lanes(&|c| c.2.velocity[1])],
                        ],
                        [lanes(&|c| c.1.radius), lanes(&|c| c.2.radius)],
                        [lanes(&|c| c.1.mass), lanes(&|c| c.2.mass)],
                        &law,
                    );
                    for (lane, (diff, a, b)) in [one, two].iter().enumerate() {
                        let scalar = resolve_pair(*diff, a, b, &law);
                        let lane_of = |v: [F64x2; 2]| v.map(|v| v.lanes()[lane].to_bits());
                        let bits = |v: [f64; 2]| v.map(f64::to_bits);
                        assert_eq!(lane_of(out.push), bits(scalar.push), "{diff:?} {a:?} {b:?}");
                        assert_eq!(lane_of(out.v1), bits(scalar.v1), "{diff:?} {a:?} {b:?}");
                        assert_eq!(lane_of(out.v2), bits(scalar.v2), "{diff:?} {a:?} {b:?}");
                    }
                }
            }
        }
    }
}
