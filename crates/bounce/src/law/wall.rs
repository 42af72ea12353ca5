//! What a wall does to a disc: the walls' one restitution rule (a disc moving into a wall
//! leaves with its normal velocity reversed and scaled by the walls' restitution, or
//! stopped when it rests, the momentum it gave recorded), their friction for rough discs,
//! and the hold that keeps a centre its radius inside them. The integration's reflection,
//! the solver's walls as contacts and its hold after a push all apply these.

use crate::lanes::Lanes;

use super::Restitution;
use super::rough::{Rough, rub_fixed};

/// The unit normals of the left, right, bottom and top walls, into the box.
const NORMALS: [[f64; 2]; 4] = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]];

/// Rough walls after a disc of radius `r` and mass `m` bounced off them: `hits` is the
/// momentum each wall took (left, right, bottom, top; 0 where the disc did not bounce),
/// the normal impulse of that wall's friction ([`super::rough`], lever arm `r`). Returns
/// the energy removed.
#[inline(never)]
pub(crate) fn rub_walls(
    hits: [f64; 4],
    velocity: &mut [f64; 2],
    omega: &mut f64,
    r: f64,
    m: f64,
    rough: &Rough,
) -> f64 {
    let mut work = 0.0;
    for (&hit, normal) in hits.iter().zip(NORMALS) {
        if hit != 0.0 {
            let inertia = rough.inertia(m, r);
            let friction = rough.wall_friction;
            let (_, w) = rub_fixed(
                normal, [0.0; 2], velocity, omega, r, m, inertia, hit, friction, rough,
            );
            work += w;
        }
    }
    work
}

/// One axis of the walls; returns the impulse given to the low and the high wall.
///
/// A disc whose centre is within its radius of a wall is put back at that distance, and its
/// normal velocity, if it still moves into the wall, is reversed and scaled by `e` (see
/// [`bounce`]).
#[inline]
pub(crate) fn reflect(
    x: &mut f64,
    v: &mut f64,
    r: f64,
    lo: f64,
    hi: f64,
    e: Restitution,
    m: f64,
) -> (f64, f64) {
    if *x - r < lo {
        *x = lo + r;
        if *v < 0.0 {
            return (bounce(v, e, m), 0.0);
        }
    } else if *x + r > hi {
        *x = hi - r;
        if *v > 0.0 {
            return (0.0, bounce(v, e, m));
        }
    }
    (0.0, 0.0)
}

/// One axis of the walls as contacts (the solver's later passes): a disc of radius `r` and
/// mass `m` at `position` that touches a wall and moves into it bounces. Returns the impulse
/// given to the low and the high wall.
#[inline]
pub(crate) fn touch_walls(
    position: f64,
    v: &mut f64,
    r: f64,
    m: f64,
    lo: f64,
    hi: f64,
    e: Restitution,
) -> [f64; 2] {
    if position <= lo + r && *v < 0.0 {
        [bounce(v, e, m), 0.0]
    } else if position >= hi - r && *v > 0.0 {
        [0.0, bounce(v, e, m)]
    } else {
        [0.0; 2]
    }
}

/// A wall's bounce of a disc of mass `m` moving into it at normal velocity `v`: reversed and
/// scaled by `e`'s restitution at that speed (0 for a resting contact: the disc stops).
/// Returns the momentum given to the wall, `m |Δv|`.
#[inline]
pub(crate) fn bounce(v: &mut f64, e: Restitution, m: f64) -> f64 {
    let new_v = -*v * e.at(v.abs());
    let impulse = m * (new_v - *v).abs();
    *v = new_v;
    impulse
}

/// The walls' hold of one coordinate of a disc of radius `r`, per lane, `lo` and `hi` the
/// walls: a centre closer to a wall than `r` is put back at that distance; the others keep
/// their bits, and a NaN is left for the step's check to find.
#[inline(always)]
pub(crate) fn hold<L: Lanes>(v: L, r: L, lo: f64, hi: f64) -> L {
    let (lo, hi) = (L::splat(lo) + r, L::splat(hi) - r);
    // `hi` where `v > hi`, then `lo` where `v < lo` (NaN kept): one instruction each.
    lo.max_else(hi.min_else(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(e: f64) -> Restitution {
        Restitution {
            e,
            rest_below: None,
        }
    }

    #[test]
    fn a_wall_reflects_and_records_the_impulse() {
        let (mut x, mut v) = (0.2, -3.0);
        let (low, high) = reflect(&mut x, &mut v, 0.5, 0.0, 10.0, e(0.5), 2.0);
        assert_eq!((x, v), (0.5, 1.5));
        assert_eq!((low, high), (2.0 * 4.5, 0.0));
    }

    #[test]
    fn a_disc_leaving_the_wall_keeps_its_velocity() {
        let (mut x, mut v) = (9.8, -1.0);
        assert_eq!(
            reflect(&mut x, &mut v, 0.5, 0.0, 10.0, e(1.0), 1.0),
            (0.0, 0.0)
        );
        assert_eq!((x, v), (9.5, -1.0));
    }

    #[test]
    fn a_resting_disc_stops_at_the_wall_and_an_impact_bounces() {
        // Resting below 0.4: a disc pulled into the floor at 0.1 stops there, giving the
        // wall its momentum m 0.1; one arriving at 3 bounces at e = 0.5.
        let rest = Restitution {
            e: 0.5,
            rest_below: Some(0.4),
        };
        let (mut y, mut v) = (0.49, -0.1);
        let (low, _) = reflect(&mut y, &mut v, 0.5, 0.0, 10.0, rest, 2.0);
        assert_eq!((y, v.to_bits(), low), (0.5, 0.0f64.to_bits(), 2.0 * 0.1));
        let (mut y, mut v) = (9.6, 0.4);
        let (_, high) = reflect(&mut y, &mut v, 0.5, 0.0, 10.0, rest, 2.0);
        assert_eq!((y, v, high), (9.5, 0.0, 2.0 * 0.4));
        let (mut y, mut v) = (0.2, -3.0);
        reflect(&mut y, &mut v, 0.5, 0.0, 10.0, rest, 2.0);
        assert_eq!(v, 1.5);
        // As a contact of a later pass, the same.
        let mut v = -0.3;
        assert_eq!(
            touch_walls(0.5, &mut v, 0.5, 1.0, 0.0, 10.0, rest),
            [0.3, 0.0]
        );
        assert_eq!(v, 0.0);
    }

    #[test]
    fn the_hold_puts_a_centre_a_radius_inside_and_keeps_the_rest() {
        assert_eq!(hold(0.2, 0.5, 0.0, 10.0), 0.5);
        assert_eq!(hold(9.8, 0.5, 0.0, 10.0), 9.5);
        assert_eq!(hold(5.0, 0.5, 0.0, 10.0).to_bits(), 5.0f64.to_bits());
        assert!(hold(f64::NAN, 0.5, 0.0, 10.0).is_nan());
    }
}
