//! Reference positions and the skin: how long a candidate list stays valid.
//!
//! A rebuild lists every pair within its collision distance plus a *skin* and records where
//! each disc was. As long as no disc has moved [`ALLOWANCE_FRACTION`] of the skin from its
//! reference, every pair that can collide is still on the list (two discs closed in by less
//! than one skin together). The positions are stored as `f32` to save memory, with a bound on
//! their rounding (the *slack*) taken off the allowance.

use serde::{Deserialize, Serialize};

use crate::lanes::max_skipping_nan;
use crate::law::Law;
use crate::parallel::{CHUNK, Executor};
use crate::sum::WallSums;

/// The skin is at least this fraction of the interaction diameter of the finest level's
/// largest disc. A wider skin lists more candidates and rebuilds less often.
const SKIN_FRACTION: f64 = 0.75;
/// And wide enough for the fastest disc to take this many substeps to use up the allowance.
const MIN_SUBSTEPS_PER_REBUILD: f64 = 4.0;
/// A rebuild follows once some disc has moved this fraction of the skin (a little under one
/// half, so rounding in the distance tests can never matter).
const ALLOWANCE_FRACTION: f64 = 0.49;

/// How a rebuild sizes the skin.
#[derive(Clone, Copy, Debug)]
pub(super) enum Skin {
    /// The larger of the size rule and `stride` (the fastest disc's distance per substep)
    /// times the substeps wanted between rebuilds.
    Stride(f64),
    /// This skin.
    Fixed(f64),
}

impl Skin {
    /// The skin for discs whose finest level's largest radius is `finest_radius` and whose
    /// largest radius is `largest_radius`.
    pub(super) fn width(self, law: &Law, finest_radius: f64, largest_radius: f64) -> f64 {
        match self {
            Skin::Fixed(skin) => skin,
            Skin::Stride(stride) => {
                let by_motion = MIN_SUBSTEPS_PER_REBUILD * stride / ALLOWANCE_FRACTION;
                let skin = f64::max(law.reach(SKIN_FRACTION * 2.0 * finest_radius), by_motion);
                // Never wider than the largest interaction diameter: cells stay about
                // disc-sized.
                skin.min(law.interaction_diameter(largest_radius))
            }
        }
    }
}

/// Where the discs were when the candidates were listed, and how far they may move before
/// the list must be rebuilt. Part of a saved world: the rebuild schedule decides the storage
/// order, and with it the last bits of sums such as the kinetic energy.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct Reference {
    /// Candidates are listed up to the collision distance plus this.
    pub(super) skin: f64,
    /// A bound on the rounding of the stored positions (they are `f32`, to save memory).
    pub(super) slack: f64,
    /// Reference positions in storage order; empty when there are none.
    pub(super) x: Vec<f32>,
    pub(super) y: Vec<f32>,
    /// When the candidates were listed: in a Lees–Edwards box the copies across the top and
    /// bottom slide past each other from then on.
    pub(super) time: f64,
}

impl Reference {
    /// The reference positions, when they match `count` discs.
    pub(crate) fn positions(&self, count: usize) -> Option<(&[f32], &[f32])> {
        (count > 0 && self.x.len() == count).then_some((&self.x, &self.y))
    }

    /// Whether candidates listed at the reference positions still hold every pair that can
    /// collide, given the largest squared displacement of any disc since.
    pub(crate) fn covers(&self, max_displacement2: f64) -> bool {
        let allowance = self.allowance();
        allowance > 0.0 && max_displacement2 < allowance * allowance
    }

    /// Whether discs within `sqrt(max_displacement2)` of their references can only collide
    /// with pairs listed in the near band (within half the skin beyond their collision
    /// distance), with a margin: decided from the saved reference alone, so a loaded world
    /// decides as the original did (detection itself asks `Broadphase::bands_within`).
    pub(crate) fn near_band_holds(&self, max_displacement2: f64) -> bool {
        let closing = 2.0 * max_displacement2.sqrt() + self.slack;
        closing * (1.0 + 1e-6) < 0.5 * self.skin * (1.0 - 1e-6)
    }

    /// How far a disc may move from its reference position before the list is rebuilt.
    pub(crate) fn allowance(&self) -> f64 {
        ALLOWANCE_FRACTION * self.skin - self.slack
    }

    /// Takes `x`, `y` (with candidates listed up to `skin`) as the reference; none when the
    /// coordinates are so large that `f32` cannot place them within the skin (then every
    /// step rebuilds). Returns whether every coordinate is finite.
    pub(super) fn record(&mut self, x: &[f64], y: &[f64], skin: f64, exec: &Executor) -> bool {
        let largest = f64::max(to_f32(x, &mut self.x, exec), to_f32(y, &mut self.y, exec));
        self.skin = skin;
        // Rounding to f32 moves a coordinate by at most half an f32 epsilon of it; the slack
        // covers two discs.
        self.slack = largest * f32::EPSILON as f64;
        if x.is_empty() || !self.covers(0.0) {
            *self = Reference::default();
        }
        largest.is_finite()
    }

    /// A reference at `x`, `y` for candidates listed up to `skin` (for tests elsewhere).
    #[cfg(test)]
    pub(crate) fn at(x: &[f64], y: &[f64], skin: f64) -> Reference {
        let mut reference = Reference::default();
        reference.record(x, y, skin, &Executor::default());
        reference
    }

    /// Checks loaded data against the particle count; says what is wrong.
    pub(crate) fn check(&self, count: usize) -> Result<(), String> {
        let lengths_ok =
            self.x.len() == self.y.len() && (self.x.is_empty() || self.x.len() == count);
        if !lengths_ok {
            return Err(format!(
                "reference positions for {} and {} discs, but there are {count}",
                self.x.len(),
                self.y.len()
            ));
        }
        let finite = self.x.iter().chain(&self.y).all(|v| v.is_finite());
        // With positions, the skin is what the list was listed with: positive.
        let skin_ok = if self.x.is_empty() {
            self.skin >= 0.0
        } else {
            self.skin > 0.0
        };
        if !(finite
            && self.skin.is_finite()
            && skin_ok
            && self.slack.is_finite()
            && self.slack >= 0.0
            && self.time.is_finite())
        {
            return Err(format!(
                "reference positions, skin {}, slack {} or time {} are not finite and >= 0 (the \
                 skin > 0 with positions)",
                self.skin, self.slack, self.time
            ));
        }
        Ok(())
    }
}

/// Stores `v` as `f32` in `out` (in parallel chunks); returns the largest `|v|`.
fn to_f32(v: &[f64], out: &mut Vec<f32>, exec: &Executor) -> f64 {
    out.resize(v.len(), 0.0);
    let mut chunks: Vec<_> = out
        .chunks_mut(16 * CHUNK)
        .zip(v.chunks(16 * CHUNK))
        .collect();
    exec.map_mut(v.len(), &mut chunks, |_, (out, v)| {
        // Four running maxima, not one: each `max` waits on the last, and one chain of them
        // was the whole loop's time. A maximum is exact, so any grouping gives the same
        // bits; NaN is skipped (as `f64::max` skips it).
        let max = max_skipping_nan;
        let mut largest = [0.0f64; 4];
        let (quads, rest) = v.as_chunks::<4>();
        let (out_quads, out_rest) = out.as_chunks_mut::<4>();
        for (o, v) in out_quads.iter_mut().zip(quads) {
            for k in 0..4 {
                o[k] = v[k] as f32;
                largest[k] = max(largest[k], v[k].abs());
            }
        }
        for (o, &v) in out_rest.iter_mut().zip(rest) {
            *o = v as f32;
            largest[0] = max(largest[0], v.abs());
        }
        largest.into_iter().fold(0.0, max)
    })
    .into_iter()
    .fold(0.0, f64::max)
}

/// What integration reports: the displacement check against the reference, made while
/// integrating (the discs are in cache then), and the walls' impulses.
#[derive(Clone, Debug, Default)]
pub(crate) struct Moved {
    /// Momentum given to each wall (by the discs the step's tally counts).
    pub impulse: WallSums,
    /// The largest squared distance of a disc from its reference position (infinite when
    /// there is no reference).
    pub max_displacement2: f64,
    /// The discs at or past the allowance from their reference positions (the broadphase's
    /// strays), ascending; complete unless `too_many_strays`.
    pub strays: Vec<u32>,
    /// Whether more than [`max_strays`] discs strayed, or more than [`CHUNK_STRAYS`] in a
    /// chunk.
    pub too_many_strays: bool,
    /// The largest squared displacement of the other discs.
    pub max_kept2: f64,
    /// The longest distance a disc moved in this substep.
    pub max_stride: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reference_covers_less_than_half_the_skin() {
        let r = Reference {
            skin: 1.0,
            slack: 0.0,
            x: vec![0.0],
            y: vec![0.0],
            time: 0.0,
        };
        assert!(r.covers(0.0) && r.covers(0.48 * 0.48));
        assert!(!r.covers(0.5 * 0.5) && !r.covers(f64::INFINITY));
        assert!(
            !Reference {
                slack: 0.5,
                ..r.clone()
            }
            .covers(0.0)
        );
        assert!(r.positions(1).is_some() && r.positions(2).is_none());
    }

    #[test]
    fn a_saved_reference_has_a_skin_where_it_has_positions() {
        let r = Reference {
            skin: 1.0,
            slack: 0.0,
            x: vec![0.0],
            y: vec![0.0],
            time: 0.0,
        };
        assert!(r.check(1).is_ok());
        assert!(r.check(2).is_err());
        let no_skin = Reference {
            skin: 0.0,
            ..r.clone()
        };
        assert!(no_skin.check(1).unwrap_err().contains("skin 0"));
        let none = Reference {
            skin: 0.0,
            x: Vec::new(),
            y: Vec::new(),
            ..r
        };
        assert!(none.check(5).is_ok());
    }

    #[test]
    fn the_near_band_holds_while_two_discs_close_in_by_under_half_the_skin() {
        let r = Reference {
            skin: 1.0,
            slack: 0.01,
            x: vec![0.0],
            y: vec![0.0],
            time: 0.0,
        };
        // Two discs 0.24 each from their references close in by 0.48, plus the slack.
        assert!(r.near_band_holds(0.0) && r.near_band_holds(0.24 * 0.24));
        assert!(!r.near_band_holds(0.245 * 0.245));
        assert!(!r.near_band_holds(f64::INFINITY) && !r.near_band_holds(f64::NAN));
    }

    #[test]
    fn the_skin_follows_the_fastest_disc_within_bounds() {
        let law = Law::new(&crate::Config::default());
        assert_eq!(Skin::Fixed(0.3).width(&law, 0.5, 2.0), 0.3);
        // Slow discs: 0.75 of the finest diameter.
        assert_eq!(Skin::Stride(0.0).width(&law, 0.5, 2.0), 0.75);
        // Fast ones: 4 substeps of travel per allowance, capped at the largest diameter.
        assert_eq!(Skin::Stride(0.2).width(&law, 0.5, 2.0), 4.0 * 0.2 / 0.49);
        assert_eq!(Skin::Stride(10.0).width(&law, 0.5, 2.0), 4.0);
    }

    #[test]
    fn the_f32_copy_keeps_the_largest_magnitude_of_any_length() {
        // Lengths around the four-way split and past a 16-chunk piece, the largest magnitude
        // in each place (a negative one too), with NaN (skipped) and -0.0: the same as one
        // running `f64::max`, on one thread and two.
        for threads in [1, 2] {
            let mut exec = Executor::new(threads).unwrap();
            exec.min_work = 0;
            for len in [0, 1, 3, 4, 5, 7, 8, 16 * CHUNK + 5] {
                for top in 0..len.min(9) {
                    let mut v: Vec<f64> =
                        (0..len).map(|k| (k as f64 * 0.37).sin() * 10.0).collect();
                    v[top] = if top % 2 == 0 { -1e3 } else { 1e3 };
                    if len > 2 {
                        v[(top + 1) % len] = f64::NAN;
                        v[(top + 2) % len] = -0.0;
                    }
                    let mut out = Vec::new();
                    let largest = to_f32(&v, &mut out, &exec);
                    let expected = v.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                    assert_eq!(largest.to_bits(), expected.to_bits(), "{len} {top}");
                    let copied: Vec<u32> = v.iter().map(|&v| (v as f32).to_bits()).collect();
                    let got: Vec<u32> = out.iter().map(|v| v.to_bits()).collect();
                    assert_eq!(got, copied, "{len} {top}");
                }
            }
        }
    }
}
