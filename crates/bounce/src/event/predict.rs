//! When things meet in flight: the exact contact time of two discs (their relative motion is
//! linear, gravity or not), when a coordinate on a parabola crosses a level (a wall, a cell
//! side, a segment's face), and the first contact of a falling disc with a point or a peg
//! (a quartic, isolated by its derivatives). Written in the numerically stable forms of
//! event-driven dynamics (Bannerman, Lue et al.): a disc that round-off left a hair past a
//! contact and still moving in meets it at once, instead of being missed or found twice.

/// The time from now at which two discs with centre difference `dr = r1 − r2` and velocity
/// difference `dv = v1 − v2` come to distance `sigma` (their collision distance), if they
/// approach and do; `None` otherwise.
///
/// With `b = dr·dv < 0` (approaching), the smaller root of `|dr + dv t|² = σ²` is
/// `t = (|dr|² − σ²) / (−b + √(b² − |dv|² (|dr|² − σ²)))`: no cancellation between `b` and the
/// root (the usual `(−b − √…)/|dv|²` loses digits when `|dr|` is near `σ`). A pair already
/// at or inside `σ` and approaching collides now (`Some(0)`).
#[inline]
pub(crate) fn contact_time(dr: [f64; 2], dv: [f64; 2], sigma: f64) -> Option<f64> {
    let b = dr[0] * dv[0] + dr[1] * dv[1];
    if b >= 0.0 {
        return None;
    }
    let gap = dr[0] * dr[0] + dr[1] * dr[1] - sigma * sigma;
    if gap <= 0.0 {
        return Some(0.0);
    }
    let v2 = dv[0] * dv[0] + dv[1] * dv[1];
    let discriminant = b * b - v2 * gap;
    if discriminant < 0.0 {
        return None;
    }
    Some(gap / (-b + discriminant.sqrt()))
}

/// The first time `t >= 0` at which `f(t) = c + v t + ½ a t²` goes down through 0 (a
/// coordinate `c` above a level, moving at `v` with acceleration `a`, reaching it from
/// above); `None` if it never does. At or below 0 and going down (or at rest and pulled
/// down) already: now. Below and rising: when it comes down again (at its top, if it never
/// gets above).
#[inline]
pub(crate) fn fall_to(c: f64, v: f64, a: f64) -> Option<f64> {
    if c <= 0.0 {
        if v < 0.0 || (v == 0.0 && a < 0.0) {
            return Some(0.0);
        }
        if a >= 0.0 {
            return None;
        }
        // Rising against a pull: down again through 0 at the larger root, or at the top.
        let d = v * v - 2.0 * a * c;
        return Some((-v - d.max(0.0).sqrt()) / a);
    }
    if a == 0.0 {
        return (v < 0.0).then(|| c / -v);
    }
    let d = v * v - 2.0 * a * c;
    if d < 0.0 {
        return None;
    }
    let root = d.sqrt();
    // The root where f' = v + a t = −√d; of the two forms, the one without cancellation.
    let t = if v < 0.0 {
        2.0 * c / (root - v)
    } else {
        -(v + root) / a
    };
    (t >= 0.0).then_some(t)
}

/// The first time `t >= 0` at which `c + v t + ½ a t²` goes up through 0: [`fall_to`] upside
/// down.
#[inline]
pub(crate) fn rise_to(c: f64, v: f64, a: f64) -> Option<f64> {
    fall_to(-c, -v, -a)
}

/// The first time in `[0, horizon]` at which a disc at `d` from a point (its centre minus the
/// point), moving at `v` with acceleration `a`, comes within `sigma` of it approaching.
/// Linear without acceleration ([`contact_time`]); otherwise the first root of the quartic
/// `|d + v t + ½ a t²|² − σ²` where it goes down, found by isolating the roots of its
/// derivatives and bisecting each bracket to the last bit.
pub(crate) fn point_contact(
    d: [f64; 2],
    v: [f64; 2],
    a: [f64; 2],
    sigma: f64,
    horizon: f64,
) -> Option<f64> {
    if a == [0.0, 0.0] {
        return contact_time(d, v, sigma).filter(|&t| t <= horizon);
    }
    // |p(t)|² − σ² with p = d + v t + ½ a t², lowest power first.
    let dot = |p: [f64; 2], q: [f64; 2]| p[0] * q[0] + p[1] * q[1];
    let f = [
        dot(d, d) - sigma * sigma,
        2.0 * dot(d, v),
        dot(v, v) + dot(d, a),
        dot(v, a),
        0.25 * dot(a, a),
    ];
    if f[0] <= 0.0 {
        // At or within σ by round-off: now if it moves in (or rests, pulled in).
        if f[1] < 0.0 || (f[1] == 0.0 && f[2] < 0.0) {
            return Some(0.0);
        }
    }
    first_fall(&f, 0.0, horizon)
}

/// The value of the polynomial `p` (lowest power first) at `t`.
#[inline]
fn eval(p: &[f64], t: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, &c| acc * t + c)
}

/// The polynomial's derivative.
fn derivative(p: &[f64]) -> Vec<f64> {
    p.iter()
        .enumerate()
        .skip(1)
        .map(|(k, &c)| k as f64 * c)
        .collect()
}

/// Every root of `p` in `(lo, hi]` where it changes sign, ascending, each with whether `p`
/// falls through it: its derivative's roots cut `[lo, hi]` into pieces on which `p` is
/// monotone, and a piece whose ends differ in sign holds exactly one, bisected until the
/// bracket cannot shrink (the end returned is on the far side of 0).
fn roots(p: &[f64], lo: f64, hi: f64) -> Vec<(f64, bool)> {
    if p.len() < 2 {
        return Vec::new();
    }
    let mut cuts = vec![lo];
    cuts.extend(roots(&derivative(p), lo, hi).into_iter().map(|(t, _)| t));
    cuts.push(hi);
    let mut out = Vec::new();
    for w in cuts.windows(2) {
        let (mut a, mut b) = (w[0], w[1]);
        let (fa, fb) = (eval(p, a), eval(p, b));
        if fa == 0.0 || (fa > 0.0) == (fb > 0.0) {
            continue;
        }
        let falling = fa > 0.0;
        loop {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if (eval(p, m) > 0.0) == falling {
                a = m;
            } else {
                b = m;
            }
        }
        out.push((b, falling));
    }
    out
}

/// The first time in `[lo, hi]` at which `p` goes from above 0 to 0 or below (`hi` cut to
/// Cauchy's bound on the roots, so an endless horizon is bisected too).
fn first_fall(p: &[f64], lo: f64, hi: f64) -> Option<f64> {
    let lead = p[p.len() - 1];
    let bound = 1.0
        + p[..p.len() - 1]
            .iter()
            .map(|c| (c / lead).abs())
            .fold(0.0, f64::max);
    let hi = hi.min(bound);
    if hi.is_nan() || hi <= lo {
        return None;
    }
    roots(p, lo, hi)
        .into_iter()
        .find_map(|(t, falling)| falling.then_some(t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn head_on_discs_meet_when_the_gap_closes() {
        // Centres 5 apart, closing at 2, collision distance 2: they touch after 1.5.
        assert_eq!(contact_time([-5.0, 0.0], [2.0, 0.0], 2.0), Some(1.5));
        // Moving apart, or passing by: never.
        assert_eq!(contact_time([-5.0, 0.0], [-2.0, 0.0], 2.0), None);
        assert_eq!(contact_time([-5.0, 3.0], [2.0, 0.0], 2.0), None);
        // Glancing: dr = (−4, 1), dv = (1, 0), σ = 2: x = −4 + t, 1 + x² = 4 → t = 4 − √3.
        let t = contact_time([-4.0, 1.0], [1.0, 0.0], 2.0).unwrap();
        assert!((t - (4.0 - 3f64.sqrt())).abs() < 1e-15, "{t}");
        // Overlapping by round-off and approaching: now; separating: never.
        assert_eq!(
            contact_time([-1.999_999_999_999, 0.0], [1.0, 0.0], 2.0),
            Some(0.0)
        );
        assert_eq!(
            contact_time([-1.999_999_999_999, 0.0], [-1.0, 0.0], 2.0),
            None
        );
    }

    #[test]
    fn the_stable_form_keeps_its_digits_for_nearly_touching_discs() {
        // A gap of 1e-12 at unit closing speed: t = 1e-12 to relative 1e-3 at least, where
        // the textbook root loses every digit.
        let t = contact_time([-(2.0 + 1e-12), 0.0], [1.0, 0.0], 2.0).unwrap();
        assert!((t / 1e-12 - 1.0).abs() < 1e-3, "{t}");
    }

    #[test]
    fn a_coordinate_on_a_parabola_crosses_a_level_when_the_hand_calculation_says() {
        // Straight lines: 1 above, falling at 2: 0.5; rising: never.
        assert_eq!(fall_to(1.0, -2.0, 0.0), Some(0.5));
        assert_eq!(fall_to(1.0, 2.0, 0.0), None);
        // Dropped from 5 under g = 10: √1 = 1; thrown up at 10: 1 + √2 (5 + 10t − 5t² = 0).
        assert_eq!(fall_to(5.0, 0.0, -10.0), Some(1.0));
        let t = fall_to(5.0, 10.0, -10.0).unwrap();
        assert!((t - (1.0 + 2f64.sqrt())).abs() < 1e-14, "{t}");
        // Just bounced off the level at 3: back at 2·3/10.
        assert_eq!(fall_to(0.0, 3.0, -10.0), Some(0.6));
        // On it, at rest, pulled down: now (the caller's stall to report).
        assert_eq!(fall_to(0.0, 0.0, -10.0), Some(0.0));
        // Pushed away by its acceleration: never; rising to a ceiling 1 above at 2 under
        // −2: 2t − t² = 1 at t = 1 (touching at the top).
        assert_eq!(fall_to(1.0, 1.0, 3.0), None);
        assert_eq!(rise_to(-1.0, 2.0, -2.0), Some(1.0));
        // Round-off below and still falling: now.
        assert_eq!(fall_to(-1e-17, -1.0, -10.0), Some(0.0));
    }

    #[test]
    fn a_falling_disc_meets_a_point_at_the_quartics_first_root() {
        // Dropped from 3 above a point, σ = 1, g = 10: 3 − 5t² = 1, t = √0.4.
        let t = point_contact([0.0, 3.0], [0.0, 0.0], [0.0, -10.0], 1.0, 10.0).unwrap();
        assert!((t - 0.4f64.sqrt()).abs() < 1e-15, "{t}");
        // Beside it, 2 across, σ = 1: it falls past.
        assert_eq!(
            point_contact([2.0, 3.0], [0.0, 0.0], [0.0, -10.0], 1.0, 10.0),
            None
        );
        // Thrown sideways from (−4, 0) at 2 with g = −0.1 along y toward a point at the
        // origin, σ = 1: x = −4 + 2t, y = −t²/20, (−4 + 2t)² + t⁴/400 = 1, just after 1.5.
        let t = point_contact([-4.0, 0.0], [2.0, 0.0], [0.0, -0.1], 1.0, 10.0).unwrap();
        let r = (-4.0 + 2.0 * t).powi(2) + t.powi(4) / 400.0 - 1.0;
        assert!(r.abs() < 1e-14 && t > 1.5 && t < 1.51, "{t} {r}");
        // With g = −1 it falls under the point: x = −4 + 2t, y = −t²/2 never come within 1.
        assert_eq!(
            point_contact([-4.0, 0.0], [2.0, 0.0], [0.0, -1.0], 1.0, 10.0),
            None
        );
        // Beyond the horizon: not yet.
        assert_eq!(
            point_contact([0.0, 3.0], [0.0, 0.0], [0.0, -10.0], 1.0, 0.5),
            None
        );
    }
}
