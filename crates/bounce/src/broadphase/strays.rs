//! Strays: the few discs past the allowance, handled alone instead of listing all anew.
//!
//! A list stays valid while every disc is within the allowance of its reference position.
//! In a gas that is decided by its fastest few: at 1M discs the fastest is about 1.5 times
//! as fast as the 2,000th, so the list is rebuilt half again as often as the bulk needs.
//! Instead, a disc past the allowance becomes a *stray* (integration finds them, in storage
//! order), and while there are at most [`max_strays`] of them the list is kept (where
//! contacts are dense, only while the others need the near band alone: [`worth_keeping`]):
//!
//! - every other disc is within the allowance, so the listed pairs of two of them still
//!   hold every such pair that can collide, and detection drops the listed pairs that
//!   involve a stray (a bit per disc, looked up only for pairs that pass the screen);
//! - a stray meets the other discs through the grids of the last rebuild: they were binned
//!   where they were then and are within the allowance of it, so the cells within its
//!   collision distance plus half the skin of the stray's *current* place hold all of them;
//! - strays meet each other by a sweep along the axis they spread most on.
//!
//! Each pair is tested once, with the seed's exact test, and its contact sorted into the
//! canonical order with the others, so results do not depend on which discs were strays
//! (tests compare against never keeping a stray, and against the brute-force oracle).

use super::Broadphase;
use super::levels::LevelGrid;
use crate::context::StepContext;
use crate::particles::Particles;

/// At most this many strays keep a list: twice the square root of the discs (so the sweep of
/// strays against strays costs at most twice as many tests as there are discs, however they
/// bunch: (2√N)²/2), and never more than a sixteenth of them.
pub(crate) fn max_strays(count: usize) -> usize {
    let root = 2.0 * (count as f64).sqrt();
    (root as usize).min(count / 16)
}

/// Below this many contacts per disc and substep, contacts are dilute (a gas: 0.02 to 0.2;
/// a resting pile: 1.7).
const DILUTE_CONTACTS: f64 = 0.5;

/// Whether a list with strays is worth keeping, given the contacts per disc and substep of
/// the last step and whether the other discs need the near band alone. Where contacts are
/// dense (a pile) the far band is the next shell of neighbours, as large as the near one:
/// testing it every substep soon costs more than a new list, so strays keep a list only
/// while the others need the near band alone. In a gas the far band is a small share, and
/// the list is kept. (Both from saved state, so a loaded world decides the same.)
pub(super) fn worth_keeping(contacts_per_disc: f64, near_band_holds: bool) -> bool {
    contacts_per_disc < DILUTE_CONTACTS || near_band_holds
}

/// The discs past the allowance at the last integration, by storage index.
#[derive(Debug, Default)]
pub(crate) struct Strays {
    /// Ascending storage indices.
    list: Vec<u32>,
    /// One bit per disc: whether it is a stray.
    flags: Vec<u64>,
}

impl Strays {
    /// Whether there are none.
    #[inline]
    pub(crate) fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    pub(crate) fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether disc `i` is a stray.
    #[inline(always)]
    pub(crate) fn contains(&self, i: usize) -> bool {
        self.flags
            .get(i / 64)
            .is_some_and(|word| word >> (i % 64) & 1 == 1)
    }

    /// Takes `list` (ascending storage indices below `count`) as the strays.
    pub(super) fn set(&mut self, list: &[u32], count: usize) {
        self.clear();
        self.flags.resize(count.div_ceil(64), 0);
        self.list.extend_from_slice(list);
        for &i in list {
            self.flags[i as usize / 64] |= 1 << (i % 64);
        }
    }

    /// No strays (the flags stay allocated, all clear).
    pub(super) fn clear(&mut self) {
        for &i in &self.list {
            self.flags[i as usize / 64] = 0;
        }
        self.list.clear();
    }
}

impl Broadphase {
    /// The strays the candidates leave out (see the module's doc).
    pub(crate) fn strays(&self) -> &Strays {
        &self.strays
    }

    /// Every colliding pair with a stray in it, each once, by the seed's exact test: `emit`
    /// gets the storage indices and the overlap.
    pub(crate) fn stray_pairs(
        &self,
        p: &Particles,
        ctx: &StepContext,
        mut emit: impl FnMut(usize, usize, f64),
    ) {
        if self.strays.is_empty() {
            return;
        }
        // After a listing in place (a loaded world), the cells index a sorted copy.
        let order = (!self.in_cell_order).then_some(&self.order[..]);
        let min_image = ctx.geometry.min_image();
        let law = ctx.law;
        let mut test = |i: usize, j: usize| {
            let diff = min_image.diff(p.x[i], p.y[i], p.x[j], p.y[j]);
            if let Some(overlap) = law.overlap(diff, p.radius[i], p.radius[j]) {
                emit(i, j, overlap);
            }
        };
        // Another disc is at most half the skin (with the rounding of the stored reference)
        // from where it was binned (its position at the rebuild, or its stored reference
        // for a listing in place); a relative margin covers the rounding of the cells'
        // bounds.
        let drift = 0.5 * self.reference.skin + self.reference.slack;
        for &s in &self.strays.list {
            let s = s as usize;
            for grid in &self.grids {
                let reach = law.collision_distance(p.radius[s], grid.max_radius) + drift;
                let reach = reach * (1.0 + 1e-9) + 1e-9 * (p.x[s].abs() + p.y[s].abs());
                let [xs, ys] =
                    [0, 1].map(|axis| cells_within(grid, [p.x[s], p.y[s]][axis], reach, axis));
                for cy in ys.clone() {
                    for cx in xs.clone() {
                        let cell = grid.cell_index(cx, cy);
                        let start = self.cell_start[cell] as usize;
                        let end = self.cell_start[cell + 1] as usize;
                        for k in start..end {
                            let j = order.map_or(k, |order| order[k] as usize);
                            if !self.strays.contains(j) {
                                test(s, j);
                            }
                        }
                    }
                }
            }
        }
        self.strays_among_themselves(p, ctx, &mut test);
    }

    /// Every pair of strays within the largest collision distance along the axis the strays
    /// spread most on (both images across a periodic edge), given to `test`.
    fn strays_among_themselves(
        &self,
        p: &Particles,
        ctx: &StepContext,
        test: &mut impl FnMut(usize, usize),
    ) {
        let strays = &self.strays.list;
        let spread = |v: &[f64]| {
            let (lo, hi) = strays
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &s| {
                    (lo.min(v[s as usize]), hi.max(v[s as usize]))
                });
            hi - lo
        };
        let axis = if spread(&p.x) >= spread(&p.y) { 0 } else { 1 };
        let along = [&p.x, &p.y][axis];
        let mut sorted: Vec<(f64, u32)> = strays.iter().map(|&s| (along[s as usize], s)).collect();
        sorted.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let width = ctx.law.collision_distance(self.max_radius, self.max_radius);
        let width =
            width * (1.0 + 1e-9) + 1e-9 * sorted.iter().map(|s| s.0.abs()).fold(0.0, f64::max);
        // With a period under three widths a pair may be near both ways round: test all.
        let seam = match ctx.geometry.period(axis) {
            _ if !width.is_finite() => return every_pair(&sorted, test),
            Some(period) if period <= 3.0 * width => return every_pair(&sorted, test),
            period => period.map(|period| period - width),
        };
        for (k, &(u, a)) in sorted.iter().enumerate() {
            for &(v, b) in &sorted[k + 1..] {
                if v - u > width {
                    break;
                }
                test(a as usize, b as usize);
            }
            // Near across the periodic edge: the last ones, a period less than a width on.
            if let Some(seam) = seam {
                for &(v, b) in sorted[k + 1..].iter().rev() {
                    if v - u < seam {
                        break;
                    }
                    test(a as usize, b as usize);
                }
            }
        }
    }
}

/// Every pair of `sorted`, given to `test`.
fn every_pair(sorted: &[(f64, u32)], test: &mut impl FnMut(usize, usize)) {
    for (k, &(_, a)) in sorted.iter().enumerate() {
        for &(_, b) in &sorted[k + 1..] {
            test(a as usize, b as usize);
        }
    }
}

/// The cells along `axis` that hold every disc binned within `reach` of `v`: the clamped
/// range of its bounds (the cell of a coordinate is monotone in it), or in a periodic grid
/// the cells around `v`'s with one to spare on each side for rounding across the edge.
fn cells_within(grid: &LevelGrid, v: f64, reach: f64, axis: usize) -> CellRange {
    let n = grid.n[axis];
    if !grid.wrap {
        return CellRange {
            start: grid.coord(v - reach, axis) as isize,
            end: grid.coord(v + reach, axis) as isize + 1,
            n,
        };
    }
    let spare = (reach * grid.inv_cell[axis]).ceil() + 1.0;
    // (A NaN reach scans every cell too.)
    if spare.is_nan() || spare >= n as f64 / 2.0 {
        return CellRange {
            start: 0,
            end: n as isize,
            n,
        };
    }
    let (c, spare) = (grid.coord(v, axis) as isize, spare as isize);
    CellRange {
        start: c - spare,
        end: c + spare + 1,
        n,
    }
}

/// Grid coordinates `start..end`, wrapped into `0..n`.
#[derive(Clone)]
struct CellRange {
    start: isize,
    end: isize,
    n: usize,
}

impl Iterator for CellRange {
    type Item = usize;

    fn next(&mut self) -> Option<usize> {
        (self.start < self.end).then(|| {
            let c = super::levels::wrap_index(self.start, self.n as isize);
            self.start += 1;
            c as usize
        })
    }
}

#[cfg(test)]
mod tests {
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    use super::*;
    use crate::broadphase::brute_force_pairs;
    use crate::parallel::Executor;
    use crate::particles::{Particle, ParticleId, ordered};
    use crate::{Boundary, Config};

    /// 600 discs in a 40 × 40 box are listed; then every disc but the strays moves just
    /// under the allowance, and the strays (every 20th, and a bunch) go anywhere: across the
    /// box, into a heap of each other, across the periodic edge from one another.
    fn scatter(boundary: &Boundary, radius: [f64; 2], in_place: bool) -> (Broadphase, Particles) {
        let config = Config {
            boundary: boundary.clone(),
            ..Config::default()
        };
        let exec = Executor::default();
        let ctx = StepContext::new(&config, 0.1, &exec, None);
        let mut rng = Pcg64Mcg::seed_from_u64(7);
        let mut p = Particles::default();
        for k in 0..600 {
            let at = [rng.random_range(1.0..39.0), rng.random_range(1.0..39.0)];
            let r = rng.random_range(radius[0]..=radius[1]);
            p.push(ParticleId(k), &Particle::new(at, [0.0, 0.0], r));
        }
        let mut bp = Broadphase::default();
        if in_place {
            // As a loaded world lists: in place, at the reference, storage order kept.
            let skin = 0.6;
            bp.list_in_place([&p.x, &p.y, &p.radius], &ctx, skin);
            bp.reference.record(&p.x, &p.y, skin, &exec);
        } else {
            bp.rebuild(&mut p, &ctx, 0.0);
        }
        let allowance = bp.reference.allowance();
        assert!(allowance > 0.05, "{allowance}");
        let mut strays = Vec::new();
        for i in 0..p.len() {
            let (x, y) = (&mut p.x[i], &mut p.y[i]);
            if i % 20 == 0 || i % 97 == 1 {
                strays.push(i as u32);
                [*x, *y] = match i % 5 {
                    // Into a heap near the left edge.
                    0 | 1 => [
                        0.2 + rng.random_range(0.0..1.5),
                        20.0 + rng.random_range(0.0..1.5),
                    ],
                    // Near the right edge, across the period from the heap.
                    2 => [
                        39.7 + rng.random_range(0.0..0.25),
                        20.0 + rng.random_range(0.0..1.5),
                    ],
                    _ => [rng.random_range(0.5..39.5), rng.random_range(0.5..39.5)],
                };
            } else {
                let angle = rng.random_range(0.0..std::f64::consts::TAU);
                let d = 0.99 * allowance;
                (*x, *y) = (*x + d * angle.cos(), *y + d * angle.sin());
            }
            if matches!(boundary, Boundary::Periodic { .. }) {
                (*x, *y) = (x.rem_euclid(40.0), y.rem_euclid(40.0));
            }
        }
        bp.strays.set(&strays, p.len());
        (bp, p)
    }

    #[test]
    fn strays_meet_exactly_the_discs_they_touch() {
        for boundary in [
            Boundary::walls([0.0, 0.0], [40.0, 40.0]),
            Boundary::periodic([0.0, 0.0], [40.0, 40.0]),
            Boundary::Open,
        ] {
            for radius in [[0.5, 0.5], [0.1, 1.2]] {
                for in_place in [false, true] {
                    let (bp, p) = scatter(&boundary, radius, in_place);
                    let config = Config {
                        boundary: boundary.clone(),
                        ..Config::default()
                    };
                    let exec = Executor::default();
                    let ctx = StepContext::new(&config, 0.1, &exec, None);
                    let mut got = Vec::new();
                    let mut among = 0;
                    bp.stray_pairs(&p, &ctx, |i, j, overlap| {
                        assert!(overlap >= 0.0);
                        among += (bp.strays.contains(i) && bp.strays.contains(j)) as usize;
                        got.push(ordered(p.id[i], p.id[j]));
                    });
                    got.sort_unstable();
                    let stray = |id: ParticleId| {
                        let i = p.id.iter().position(|&k| k == id).unwrap();
                        bp.strays.contains(i)
                    };
                    let expected: Vec<_> = brute_force_pairs(&p, &ctx)
                        .into_iter()
                        .filter(|&(a, b)| stray(a) || stray(b))
                        .collect();
                    let case = format!("{boundary:?} {radius:?} in place {in_place}");
                    // Each pair once, and every one of them.
                    assert_eq!(got, expected, "{case}");
                    assert!(expected.len() > 40 && among > 10, "{case}: {got:?}");
                }
            }
        }
    }

    #[test]
    fn dense_contacts_keep_a_list_with_strays_only_on_the_near_band() {
        // A gas (0.02 contacts per disc and substep) keeps it with both bands; a pile (1.7)
        // only while the near band holds every contact of the other discs.
        assert!(worth_keeping(0.02, false) && worth_keeping(0.02, true));
        assert!(worth_keeping(1.7, true) && !worth_keeping(1.7, false));
        assert!(!worth_keeping(DILUTE_CONTACTS, false));
    }

    #[test]
    fn strays_across_a_periodic_edge_meet() {
        // Two strays 0.6 apart across the edge at x = 0 = 40, and one 0.99 from the first
        // within the box; the sweep must find both pairs and nothing else.
        let (mut bp, mut p) = scatter(
            &Boundary::periodic([0.0, 0.0], [40.0, 40.0]),
            [0.5, 0.5],
            false,
        );
        let config = Config {
            boundary: Boundary::periodic([0.0, 0.0], [40.0, 40.0]),
            ..Config::default()
        };
        let exec = Executor::default();
        let ctx = StepContext::new(&config, 0.1, &exec, None);
        // Far from every other disc: a clear row at y = 39.9 ± 0.5 (made so below).
        for i in 0..p.len() {
            if (p.y[i] - 39.9).abs() < 1.6 || p.y[i] < 0.7 {
                p.y[i] = 30.0 + (p.y[i] % 1.0);
            }
        }
        let (a, b, c) = (3, 4, 5);
        [p.x[a], p.y[a]] = [0.3, 39.9];
        [p.x[b], p.y[b]] = [39.7, 39.9];
        [p.x[c], p.y[c]] = [1.29, 39.9];
        bp.strays.set(&[a as u32, b as u32, c as u32], p.len());
        let mut got = Vec::new();
        bp.stray_pairs(&p, &ctx, |i, j, _| got.push([i.min(j), i.max(j)]));
        got.sort_unstable();
        assert_eq!(got, vec![[a, b], [a, c]]);
    }
}
