//! Rough discs: what friction and rolling resistance add to a contact after the normal
//! update. Off by default (smooth discs never spin); on when [`crate::Config::is_rough`].
//!
//! The model, with every formula, is the user guide's `docs/src/concepts/rough-discs.md`;
//! the names here are that page's: the lever arms `l1`, `l2` (`r s` against a disc or an
//! obstacle, `r` against a wall), the slip `g = (v1 − v2)·t − l1 ω1 − l2 ω2`, the weight
//! `w = 1/m1 + 1/m2 + l1²/I1 + l2²/I2`, the tangential impulse
//! `J_t = clamp(−(1 + β) g / w, ±μ |J_n|)` with `J_n` the normal update's impulse (for a
//! pair its antisymmetric part `½ (m1 Δv1n − m2 Δv2n)`, which the virial counts too), and the
//! rolling couple `M = clamp(Ω / (1/I1 + 1/I2), ±μ_r |J_n| r_eff)`. Each contact reports the
//! energy the two removed, `−J_t (g + g′)/2 + M (Ω + Ω′)/2`, as its `friction_work`.

use crate::lanes::Lanes;

/// The rough discs' coefficients, as [`super::Law`] holds them (see the module docs).
///
/// ```
/// use bounce::{Config, law::Law};
/// let law = Law::new(&Config { friction: 0.5, wall_friction: Some(0.0), ..Config::default() });
/// let rough = law.rough.unwrap(); // smooth discs (the seed's) have none
/// assert!(rough.rubs_pairs() && !rough.rubs_walls());
/// assert!(rough.rubs_with(0.5) && !rough.rubs_with(0.0));
/// assert_eq!(rough.inertia(2.0, 3.0), 0.5 * 2.0 * 9.0); // a uniform disc, k = ½
/// assert!(Law::new(&Config::default()).rough.is_none());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rough {
    /// Coulomb's `μ` of disc–disc contacts.
    pub friction: f64,
    /// Coulomb's `μ` at the walls of the box.
    pub wall_friction: f64,
    /// Walton's `β`.
    pub tangential_restitution: f64,
    /// `μ_r`.
    pub rolling_resistance: f64,
    /// `k` in `I = k m r²`.
    pub inertia_factor: f64,
}

impl Rough {
    /// Whether disc–disc contacts do anything beyond the seed's update.
    /// See [`Rough`] for an example.
    #[inline]
    pub fn rubs_pairs(&self) -> bool {
        self.rubs_with(self.friction)
    }

    /// Whether the walls of the box do anything beyond the seed's bounce.
    /// See [`Rough`] for an example.
    #[inline]
    pub fn rubs_walls(&self) -> bool {
        self.rubs_with(self.wall_friction)
    }

    /// Whether a contact of friction `friction` does anything beyond the normal update.
    /// See [`Rough`] for an example.
    #[inline]
    pub fn rubs_with(&self, friction: f64) -> bool {
        friction > 0.0 || self.rolling_resistance > 0.0
    }

    /// The moment of inertia of a disc of mass `m` and radius `r`, `k m r²`.
    /// See [`Rough`] for an example.
    #[inline(always)]
    pub fn inertia(&self, m: f64, r: f64) -> f64 {
        self.inertia_factor * m * r * r
    }
}

/// One side of a rough contact, in lanes: after the normal update.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Side<L> {
    pub velocity: [L; 2],
    pub omega: L,
    /// From the centre to the contact point.
    pub lever: L,
    pub inverse_mass: L,
    pub inverse_inertia: L,
}

/// What the tangential impulse and the rolling couple leave: both sides' velocities and
/// angular velocities, and the energy they removed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rubbed<L> {
    pub v1: [L; 2],
    pub v2: [L; 2],
    pub omega1: L,
    pub omega2: L,
    pub work: L,
}

/// The tangential impulse and the rolling couple of one contact per lane (see the module
/// docs): `normal` from side 2 to side 1, `normal_impulse` the update's `J_n` (either sign),
/// `friction` Coulomb's `μ`, `rolling_lever` the `r_eff` of the rolling couple.
#[inline(always)]
pub(crate) fn rub<L: Lanes>(
    normal: [L; 2],
    one: Side<L>,
    two: Side<L>,
    normal_impulse: L,
    friction: f64,
    rolling_lever: L,
    rough: &Rough,
) -> Rubbed<L> {
    let zero = L::splat(0.0);
    let abs = |v: L| L::select(v.lt(zero), -v, v);
    let clamp = |v: L, limit: L| (-limit).max_else(limit.min_else(v));
    let half = L::splat(0.5);
    let jn = abs(normal_impulse);
    let t = [-normal[1], normal[0]];
    let along = |v: [L; 2]| v[0] * t[0] + v[1] * t[1];
    // The slip of the surfaces, and how a tangential impulse changes it.
    let slip =
        along(one.velocity) - one.lever * one.omega - (along(two.velocity) + two.lever * two.omega);
    let w = one.inverse_mass
        + two.inverse_mass
        + one.lever * one.lever * one.inverse_inertia
        + two.lever * two.lever * two.inverse_inertia;
    let stick = -(L::splat(1.0 + rough.tangential_restitution) * slip) / w;
    let j = clamp(stick, L::splat(friction) * jn);
    let slip_after = slip + j * w;
    let v1 = [
        one.velocity[0] + j * one.inverse_mass * t[0],
        one.velocity[1] + j * one.inverse_mass * t[1],
    ];
    let v2 = [
        two.velocity[0] - j * two.inverse_mass * t[0],
        two.velocity[1] - j * two.inverse_mass * t[1],
    ];
    let omega1 = one.omega - one.lever * j * one.inverse_inertia;
    let omega2 = two.omega - two.lever * j * two.inverse_inertia;
    let mut work = -(j * (slip + slip_after)) * half;
    if rough.rolling_resistance == 0.0 {
        return Rubbed {
            v1,
            v2,
            omega1,
            omega2,
            work,
        };
    }
    // The rolling couple: brakes the relative rotation.
    let spin = omega1 - omega2;
    let inverse = one.inverse_inertia + two.inverse_inertia;
    let couple = clamp(
        spin / inverse,
        L::splat(rough.rolling_resistance) * jn * rolling_lever,
    );
    let spin_after = spin - couple * inverse;
    work = work + couple * (spin + spin_after) * half;
    Rubbed {
        v1,
        v2,
        omega1: omega1 - couple * one.inverse_inertia,
        omega2: omega2 + couple * two.inverse_inertia,
        work,
    }
}

/// A disc against a wall or an obstacle after its normal bounce: `normal` from the obstacle
/// to the disc, `obstacle` its velocity, `lever` the disc's lever arm, `normal_impulse` the
/// disc's `m |Δv_n|`. Updates the disc's velocity and angular velocity; returns the momentum
/// the obstacle received from the tangential impulse and the energy removed.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn rub_fixed(
    normal: [f64; 2],
    obstacle: [f64; 2],
    velocity: &mut [f64; 2],
    omega: &mut f64,
    lever: f64,
    mass: f64,
    inertia: f64,
    normal_impulse: f64,
    friction: f64,
    rough: &Rough,
) -> ([f64; 2], f64) {
    let one = Side {
        velocity: *velocity,
        omega: *omega,
        lever,
        inverse_mass: 1.0 / mass,
        inverse_inertia: 1.0 / inertia,
    };
    let two = Side {
        velocity: obstacle,
        omega: 0.0,
        lever: 0.0,
        inverse_mass: 0.0,
        inverse_inertia: 0.0,
    };
    let out = rub(normal, one, two, normal_impulse, friction, lever, rough);
    let given = [
        mass * (velocity[0] - out.v1[0]),
        mass * (velocity[1] - out.v1[1]),
    ];
    *velocity = out.v1;
    *omega = out.omega1;
    (given, out.work)
}

/// A pair's tangential impulse and rolling couple per lane, after the normal update
/// `before` → `after` along `normal` (from disc 2 to disc 1): see the module docs. `scale`
/// is the `collision_radius_scale`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn rub_pair<L: Lanes>(
    normal: [L; 2],
    before: [[L; 2]; 2],
    after: [[L; 2]; 2],
    omega: [L; 2],
    radius: [L; 2],
    mass: [L; 2],
    scale: f64,
    rough: &Rough,
) -> Rubbed<L> {
    let (one, half) = (L::splat(1.0), L::splat(0.5));
    let along = |v: [L; 2]| v[0] * normal[0] + v[1] * normal[1];
    let change = |k: usize| along(after[k]) - along(before[k]);
    // The update's normal impulse on disc 1: the antisymmetric part of the two changes.
    let normal_impulse = half * (mass[0] * change(0) - mass[1] * change(1));
    let k = L::splat(rough.inertia_factor);
    let side = |i: usize| Side {
        velocity: after[i],
        omega: omega[i],
        lever: radius[i] * L::splat(scale),
        inverse_mass: one / mass[i],
        inverse_inertia: one / (k * mass[i] * radius[i] * radius[i]),
    };
    let (a, b) = (side(0), side(1));
    let rolling_lever = a.lever * b.lever / (a.lever + b.lever);
    rub(
        normal,
        a,
        b,
        normal_impulse,
        rough.friction,
        rolling_lever,
        rough,
    )
}
