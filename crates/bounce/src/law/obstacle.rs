//! What an obstacle does to a disc: the seed's rule with an immovable partner. A disc of
//! radius `r` collides with a segment when its centre is within `r * collision_radius_scale`
//! of the segment's nearest point, and with a peg of radius `R` within `(r + R) *
//! collision_radius_scale` of its centre; it is pushed out of the overlap by the whole
//! amount, and if it moves into the obstacle (in the obstacle's frame) its normal velocity
//! is reversed and scaled by the obstacle's restitution (0 for a resting contact, see
//! [`crate::RestingContacts`]); a rough disc then gets the obstacle's friction
//! ([`super::rough`], lever arm `r * collision_radius_scale`). A disc already leaving is not
//! turned back: with an immovable partner the seed's step 6 would send it in again.

use crate::config::Shape;

use super::rough::rub_fixed;
use super::{COINCIDENT_NORMAL, Law, may_touch, within};

/// The point of `shape` nearest to `p` (a peg's centre) and the squared distance from it
/// (to the centre for a peg: its radius is in the reach, [`reach_of`]).
#[inline]
pub(crate) fn nearest(shape: &Shape, p: [f64; 2]) -> ([f64; 2], f64) {
    let q = match *shape {
        Shape::Segment { a, b } => {
            let ab = [b[0] - a[0], b[1] - a[1]];
            let t =
                ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / (ab[0] * ab[0] + ab[1] * ab[1]);
            let t = t.clamp(0.0, 1.0);
            [a[0] + t * ab[0], a[1] + t * ab[1]]
        }
        Shape::Peg { centre, .. } => centre,
    };
    let d = [p[0] - q[0], p[1] - q[1]];
    (q, d[0] * d[0] + d[1] * d[1])
}

/// The collision distance of a disc of radius `r` and `shape`: `r s` for a segment,
/// `(r + R) s` for a peg of radius `R`.
#[inline]
pub(crate) fn reach_of(shape: &Shape, r: f64, law: &Law) -> f64 {
    match *shape {
        Shape::Segment { .. } => law.reach(r),
        Shape::Peg { radius, .. } => law.collision_distance(r, radius),
    }
}

/// Whether a disc of radius `r` at `p` collides with `shape` (what placement avoids).
pub(crate) fn touches(shape: &Shape, p: [f64; 2], r: f64, law: &Law) -> bool {
    within(nearest(shape, p).1.sqrt(), reach_of(shape, r, law))
}

/// One disc as [`collide`] sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Disc {
    pub position: [f64; 2],
    pub velocity: [f64; 2],
    pub radius: f64,
    pub mass: f64,
    /// Angular velocity (read and changed only by a rough law).
    pub omega: f64,
}

/// A disc against one obstacle moving at `u` with restitution `e` and friction `friction`:
/// the disc's position, velocity (and a rough one's angular velocity) updated; returns the
/// momentum given to the obstacle (zero when they do not collide or the disc already
/// leaves) and the energy friction removed.
#[inline]
pub(crate) fn collide(
    shape: &Shape,
    u: [f64; 2],
    [e, friction]: [f64; 2],
    law: &Law,
    disc: &mut Disc,
) -> ([f64; 2], f64) {
    let Disc {
        position,
        velocity,
        radius: r,
        mass: m,
        omega,
    } = disc;
    let (r, m) = (*r, *m);
    let (q, distance2) = nearest(shape, *position);
    let reach = reach_of(shape, r, law);
    // A cheap squared early-out, then the rule on the distance itself.
    if !may_touch(distance2, reach) {
        return ([0.0, 0.0], 0.0);
    }
    let distance = distance2.sqrt();
    if !within(distance, reach) {
        return ([0.0, 0.0], 0.0);
    }
    // The normal from the obstacle's nearest point to the centre; on the segment itself,
    // its left normal (a fixed choice, as the seed's coincident normal).
    let n = if distance > 0.0 {
        [
            (position[0] - q[0]) / distance,
            (position[1] - q[1]) / distance,
        ]
    } else {
        match *shape {
            Shape::Segment { a, b } => {
                let ab = [b[0] - a[0], b[1] - a[1]];
                let l = (ab[0] * ab[0] + ab[1] * ab[1]).sqrt();
                [-ab[1] / l, ab[0] / l]
            }
            Shape::Peg { .. } => COINCIDENT_NORMAL,
        }
    };
    // Pushed out of the overlap by the whole amount.
    if distance < reach {
        let overlap = reach - distance;
        position[0] += n[0] * overlap;
        position[1] += n[1] * overlap;
    }
    // The normal velocity in the obstacle's frame, reversed and scaled if it moves in.
    let vn = (velocity[0] - u[0]) * n[0] + (velocity[1] - u[1]) * n[1];
    if vn >= 0.0 {
        return ([0.0, 0.0], 0.0);
    }
    let dv = -(1.0 + law.restitution_of(e).at(-vn)) * vn;
    velocity[0] += dv * n[0];
    velocity[1] += dv * n[1];
    let given = [-m * dv * n[0], -m * dv * n[1]];
    let Some(rough) = law.rough.filter(|rough| rough.rubs_with(friction)) else {
        return (given, 0.0);
    };
    let inertia = rough.inertia(m, r);
    let lever = law.reach(r);
    let (tangential, work) = rub_fixed(
        n,
        u,
        velocity,
        omega,
        lever,
        m,
        inertia,
        m * dv,
        friction,
        &rough,
    );
    ([given[0] + tangential[0], given[1] + tangential[1]], work)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;

    fn law() -> Law {
        Law::new(&Config::default())
    }

    fn disc(position: [f64; 2], velocity: [f64; 2], radius: f64, mass: f64) -> Disc {
        Disc {
            position,
            velocity,
            radius,
            mass,
            omega: 0.0,
        }
    }

    #[test]
    fn a_disc_hitting_a_segment_head_on_is_pushed_out_and_reflected() {
        // A horizontal floor from (-5, 0) to (5, 0); a disc of radius 0.5 at height 0.4
        // moving down at 2 with e = 0.5: pushed up by the whole overlap 0.1, vy = +1,
        // the floor receives m (1 + e) 2 downwards.
        let floor = Shape::Segment {
            a: [-5.0, 0.0],
            b: [5.0, 0.0],
        };
        let mut d = disc([1.0, 0.4], [3.0, -2.0], 0.5, 0.5);
        let j = collide(&floor, [0.0; 2], [0.5, 0.0], &law(), &mut d).0;
        assert_eq!(d.position, [1.0, 0.5]);
        assert_eq!(d.velocity, [3.0, 1.0]);
        assert_eq!(j, [0.0, -0.5 * 1.5 * 2.0]);
    }

    #[test]
    fn a_segment_end_acts_like_a_point() {
        // The end (0, 0) of a segment to (-4, 0); a disc at (0.3, 0.4) (distance 0.5 from
        // the end) of radius 1 moving at (-1, -1) towards it: normal (0.6, 0.8), overlap
        // 0.5, so the centre goes to (0.6, 0.8); vn = -1.4, reversed at e = 1: v = (0.68, 1.24).
        let segment = Shape::Segment {
            a: [-4.0, 0.0],
            b: [0.0, 0.0],
        };
        let mut d = disc([0.3, 0.4], [-1.0, -1.0], 1.0, 1.0);
        collide(&segment, [0.0; 2], [1.0, 0.0], &law(), &mut d);
        let (p, v) = (d.position, d.velocity);
        assert!(
            (p[0] - 0.6).abs() < 1e-15 && (p[1] - 0.8).abs() < 1e-15,
            "{p:?}"
        );
        assert!(
            (v[0] - 0.68).abs() < 1e-15 && (v[1] - 1.24).abs() < 1e-15,
            "{v:?}"
        );
    }

    #[test]
    fn a_peg_uses_the_sum_of_radii_and_keeps_the_tangential_velocity() {
        // Peg of radius 1 at the origin, disc of radius 0.5 at (1.2, 0) moving at (-2, 3)
        // with collision_radius_scale 1: overlap 0.3, pushed to (1.5, 0); vn = -2 reversed
        // at e = 0.8 gives 1.6; vt = 3 kept.
        let peg = Shape::Peg {
            centre: [0.0, 0.0],
            radius: 1.0,
        };
        let mut d = disc([1.2, 0.0], [-2.0, 3.0], 0.5, 2.0);
        let j = collide(&peg, [0.0; 2], [0.8, 0.0], &law(), &mut d).0;
        assert_eq!(d.position, [1.5, 0.0]);
        assert_eq!(d.velocity, [1.6, 3.0]);
        assert_eq!(j, [-2.0 * 3.6, 0.0]);
        // A disc leaving the peg is pushed out but keeps its velocity.
        let mut d = disc([1.2, 0.0], [2.0, 0.0], 0.5, 2.0);
        assert_eq!(
            collide(&peg, [0.0; 2], [0.8, 0.0], &law(), &mut d).0,
            [0.0, 0.0]
        );
        assert_eq!((d.position, d.velocity), ([1.5, 0.0], [2.0, 0.0]));
    }

    #[test]
    fn a_resting_disc_stops_on_a_segment_or_a_peg_and_an_impact_bounces() {
        // Resting below 0.4 (gravity 10, substep 0.01): pulled into the floor at 0.1, the
        // disc stops on it; the floor takes its momentum. Arriving at 0.5, it bounces.
        let law = Law::at_substep(
            &Config {
                gravity: [0.0, -10.0],
                resting_contacts: crate::RestingContacts::Rest,
                ..Config::default()
            },
            0.01,
        );
        let floor = Shape::Segment {
            a: [-5.0, 0.0],
            b: [5.0, 0.0],
        };
        let mut d = disc([1.0, 0.499], [2.0, -0.1], 0.5, 3.0);
        let j = collide(&floor, [0.0; 2], [0.9, 0.0], &law, &mut d).0;
        assert_eq!((d.position, d.velocity), ([1.0, 0.5], [2.0, 0.0]));
        assert_eq!(j, [-0.0, -0.30000000000000004]);
        let mut d = disc([1.0, 0.499], [2.0, -0.5], 0.5, 3.0);
        collide(&floor, [0.0; 2], [0.9, 0.0], &law, &mut d);
        assert!(d.velocity[0] == 2.0 && (d.velocity[1] - 0.45).abs() < 1e-15);
        // On top of a peg, the same; on a floor rising at 1 the disc leaves at its speed.
        let peg = Shape::Peg {
            centre: [0.0, 0.0],
            radius: 1.0,
        };
        let mut d = disc([0.0, 1.499], [0.0, -0.2], 0.5, 1.0);
        collide(&peg, [0.0; 2], [1.0, 0.0], &law, &mut d);
        assert_eq!(d.velocity, [0.0, 0.0]);
        let mut d = disc([0.0, 0.499], [0.0, 0.9], 0.5, 1.0);
        collide(&floor, [0.0, 1.0], [1.0, 0.0], &law, &mut d);
        assert_eq!(d.velocity, [0.0, 1.0]);
        // Without the option (or gravity), the seed's bounce however slow.
        let mut d = disc([1.0, 0.499], [2.0, -0.1], 0.5, 3.0);
        collide(&floor, [0.0; 2], [0.9, 0.0], &self::law(), &mut d);
        assert_eq!(d.velocity, [2.0, 0.09]);
    }

    #[test]
    fn a_moving_wall_reflects_in_its_own_frame() {
        // A floor rising at 1: a disc at rest on it leaves at 2 (e = 1), and the disc's
        // kinetic energy gain equals the work J_disc · u.
        let floor = Shape::Segment {
            a: [-5.0, 0.0],
            b: [5.0, 0.0],
        };
        let mut d = disc([0.0, 0.5], [0.0, 0.0], 0.5, 1.0);
        let j = collide(&floor, [0.0, 1.0], [1.0, 0.0], &law(), &mut d).0;
        let v = d.velocity;
        assert_eq!(v, [0.0, 2.0]);
        assert_eq!(j, [0.0, -2.0]);
        let gain = 0.5 * (v[0] * v[0] + v[1] * v[1]);
        assert_eq!(gain, -j[1] * 1.0);
    }
}
