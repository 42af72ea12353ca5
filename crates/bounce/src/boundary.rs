//! The edge of the world, applied to one disc at a time right after it moves.
//!
//! Walls put a disc that crossed back at the wall (its centre one radius away) and reverse
//! its normal velocity if it still moves into the wall, scaled by the wall restitution; the
//! momentum handed to the wall is recorded for pressure. A periodic box wraps centres back
//! into `[min, max)`. An open world does nothing.

use serde::{Deserialize, Serialize};

use crate::config::{Boundary, Config};

/// Momentum magnitude delivered to each wall (sum of `m |Δv|` of the discs it reflected).
/// Divide by the elapsed time and the wall's length for the pressure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WallImpulse {
    /// The wall at `min[0]`.
    pub left: f64,
    /// The wall at `max[0]`.
    pub right: f64,
    /// The wall at `min[1]`.
    pub bottom: f64,
    /// The wall at `max[1]`.
    pub top: f64,
}

impl WallImpulse {
    /// Sum over the four walls.
    pub fn total(&self) -> f64 {
        self.left + self.right + self.bottom + self.top
    }

    pub(crate) fn add(&mut self, other: &WallImpulse) {
        self.left += other.left;
        self.right += other.right;
        self.bottom += other.bottom;
        self.top += other.top;
    }
}

/// The boundary in the form the per-disc pass uses.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Edge {
    Open,
    Walls {
        min: [f64; 2],
        max: [f64; 2],
        restitution: f64,
    },
    Periodic {
        min: [f64; 2],
        size: [f64; 2],
    },
}

impl Edge {
    pub(crate) fn of(config: &Config) -> Self {
        match config.boundary {
            Boundary::Open => Edge::Open,
            Boundary::Walls { min, max, .. } => Edge::Walls {
                min,
                max,
                restitution: config.wall_restitution(),
            },
            Boundary::Periodic { min, max } => Edge::Periodic {
                min,
                size: [max[0] - min[0], max[1] - min[1]],
            },
        }
    }
}

/// One axis of the walls; returns the impulse given to the low and the high wall.
#[inline]
pub(crate) fn reflect(
    x: &mut f64,
    v: &mut f64,
    r: f64,
    lo: f64,
    hi: f64,
    e: f64,
    m: f64,
) -> (f64, f64) {
    if *x - r < lo {
        *x = lo + r;
        if *v < 0.0 {
            let new_v = -*v * e;
            let impulse = m * (new_v - *v);
            *v = new_v;
            return (impulse, 0.0);
        }
    } else if *x + r > hi {
        *x = hi - r;
        if *v > 0.0 {
            let new_v = -*v * e;
            let impulse = m * (*v - new_v);
            *v = new_v;
            return (0.0, impulse);
        }
    }
    (0.0, 0.0)
}

/// One axis of the periodic box: back into `[lo, lo + size)`.
#[inline]
pub(crate) fn wrap(x: &mut f64, lo: f64, size: f64) {
    if *x < lo {
        *x += size;
    } else if *x >= lo + size {
        *x -= size;
    }
    // A disc faster than a box width per substep: reduce fully.
    if !(*x >= lo && *x < lo + size) {
        *x = lo + (*x - lo).rem_euclid(size);
        if *x >= lo + size {
            *x = lo;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wall_reflects_and_records_the_impulse() {
        let (mut x, mut v) = (0.2, -3.0);
        let (low, high) = reflect(&mut x, &mut v, 0.5, 0.0, 10.0, 0.5, 2.0);
        assert_eq!((x, v), (0.5, 1.5));
        assert_eq!((low, high), (2.0 * 4.5, 0.0));
    }

    #[test]
    fn a_disc_leaving_the_wall_keeps_its_velocity() {
        let (mut x, mut v) = (9.8, -1.0);
        assert_eq!(
            reflect(&mut x, &mut v, 0.5, 0.0, 10.0, 1.0, 1.0),
            (0.0, 0.0)
        );
        assert_eq!((x, v), (9.5, -1.0));
    }

    #[test]
    fn wrapping_lands_in_the_half_open_box() {
        for (x0, want) in [
            (-0.5, 9.5),
            (10.0, 0.0),
            (10.5, 0.5),
            (35.0, 5.0),
            (-25.0, 5.0),
        ] {
            let mut x = x0;
            wrap(&mut x, 0.0, 10.0);
            assert_eq!(x, want, "from {x0}");
        }
        let mut tiny = -1e-17;
        wrap(&mut tiny, 0.0, 10.0);
        assert!((0.0..10.0).contains(&tiny));
    }
}
