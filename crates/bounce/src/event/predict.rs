//! When things meet in free flight: the exact contact time of two discs moving at constant
//! relative velocity, and when a disc leaves its cell. Written in the numerically stable
//! forms of event-driven hard-disc dynamics (Bannerman, Lue et al.): a pair that round-off
//! left overlapping and still approaching collides at once, instead of being missed or found
//! twice.

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

/// The time from now at which a coordinate `x` moving at `v` leaves the cell `[lo, hi)`:
/// through `hi` moving up, `lo` moving down; infinite at rest.
#[inline]
pub(crate) fn exit_time(x: f64, v: f64, lo: f64, hi: f64) -> f64 {
    if v > 0.0 {
        ((hi - x) / v).max(0.0)
    } else if v < 0.0 {
        ((lo - x) / v).max(0.0)
    } else {
        f64::INFINITY
    }
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
    fn a_coordinate_leaves_its_cell_through_the_side_it_moves_to() {
        assert_eq!(exit_time(1.0, 2.0, 0.0, 4.0), 1.5);
        assert_eq!(exit_time(1.0, -0.5, 0.0, 4.0), 2.0);
        assert_eq!(exit_time(1.0, 0.0, 0.0, 4.0), f64::INFINITY);
        // Already past the side it moves to (round-off): now.
        assert_eq!(exit_time(4.0 + 1e-15, 1.0, 0.0, 4.0), 0.0);
    }
}
