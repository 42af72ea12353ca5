//! Levels and their grids: which grid a disc is binned in, and how each grid is laid out.
//!
//! Each disc gets a *level* by its interaction diameter `d`: level `k` holds
//! `d_min 2^k < d <= d_min 2^(k+1)` (level 0 includes `d_min`), and each non-empty level has
//! its own uniform grid with cells at least its largest `d` plus the skin, and levels whose
//! grids would be sparse share one ([`merge`]). In a box the grid covers the box (wrapping
//! when periodic; a distributed run's part of a walled box, only its discs' bounding box);
//! in an open world it covers the bulk of the level's discs around their median, at most
//! about one cell per disc, and outliers share the edge cells (clamping never moves two cell
//! coordinates further apart).

use std::cell::RefCell;

use crate::context::StepContext;
use crate::geometry::Extent;
use crate::law::Law;

/// At most this many grid levels (interaction diameters spanning a factor 2^16).
pub(super) const MAX_LEVELS: usize = 16;

/// Adjacent levels share one grid ([`merge`]) while it would hold at most this many discs
/// per cell on average. A grid is capped at about one cell per disc, so when the small discs
/// are few (radii uniform in 0.05–5: 16 % of the discs below radius 0.8) every level's grid
/// has cells far wider than its discs, about one disc each, and one grid for all of them
/// costs a disc no more own-grid tests than its level's grid did, without the scans of the
/// coarser grids. Many small discs among a few large ones would crowd the large discs' cells:
/// then the levels stay apart.
const MERGED_OCCUPANCY: f64 = 1.5;

/// The most cells a grid for `count` discs gets: about one per disc (fewer, fuller cells
/// beat many empty ones: a dense gas at cell side = diameter would leave most cells empty).
fn max_cells(count: usize) -> usize {
    count + 64
}

/// A non-empty level: its index among the non-empty ones, its disc count, its largest radius.
#[derive(Clone, Copy, Debug)]
pub(super) struct Level {
    pub index: usize,
    pub count: usize,
    pub max_radius: f64,
    /// Whether it holds discs of several bands (more than a factor 2 apart in diameter, see
    /// [`merge`]): its pairs are then cut at their own collision distance, one by one, not
    /// at the level's largest.
    pub merged: bool,
}

/// What laying out a grid reads about the discs besides their positions.
pub(super) struct Discs<'a> {
    /// Per-disc level; empty when all discs share level 0.
    pub level_of: &'a [u8],
    /// Scratch for the medians of an open world.
    pub scratch: &'a RefCell<Vec<f64>>,
}

/// One level's uniform grid.
#[derive(Clone, Debug)]
pub(super) struct LevelGrid {
    pub(super) origin: [f64; 2],
    pub(super) inv_cell: [f64; 2],
    pub(super) n: [usize; 2],
    /// Whether cell coordinates wrap (periodic box).
    pub(super) wrap: bool,
    /// First global cell index of this level.
    pub(super) cell_offset: usize,
    /// Largest radius at this level, for cross-level reach.
    pub(super) max_radius: f64,
    /// Whether pairs of this level are cut at their own collision distance (a merged
    /// level), not at the level's largest.
    pub(super) pairwise: bool,
    /// Forward half-stencil: neighbour offsets whose pairs this cell owns.
    pub(super) forward: Vec<[isize; 2]>,
}

impl LevelGrid {
    /// The (clamped) cell coordinate of `v` along `axis`.
    #[inline(always)]
    pub(super) fn coord(&self, v: f64, axis: usize) -> usize {
        let t = (v - self.origin[axis]) * self.inv_cell[axis];
        let n = self.n[axis] as isize;
        if self.wrap {
            // A periodic coordinate wraps, since an overlap push can leave a centre a little
            // outside the box.
            wrap_index(floor_to_isize(t), n) as usize
        } else {
            clamp_cell(t, (n - 1) as f64) as usize
        }
    }

    /// Maps a possibly out-of-range cell coordinate to the grid: wrapped when periodic,
    /// `None` when outside a non-periodic grid.
    #[inline]
    pub(super) fn neighbour(&self, c: isize, axis: usize) -> Option<usize> {
        let n = self.n[axis] as isize;
        if self.wrap {
            Some(wrap_index(c, n) as usize)
        } else {
            (0..n).contains(&c).then_some(c as usize)
        }
    }

    #[inline(always)]
    pub(super) fn cell_index(&self, cx: usize, cy: usize) -> usize {
        self.cell_offset + cy * self.n[0] + cx
    }
}

/// Cell coordinate `t` (in cells from the grid's origin) clamped to `[0, top]` before it is
/// an integer: on `[0, top]` truncation is the floor, below it both give cell 0, above it
/// cell `top`, and NaN goes to 0, as flooring then clamping does; without a branch or a
/// saturating conversion.
#[inline(always)]
pub(super) fn clamp_cell(t: f64, top: f64) -> f64 {
    t.max(0.0).min(top)
}

/// `c` modulo `n > 0`, in `0..n`: one comparison for the common case of a coordinate
/// at most one period outside (an integer division costs tens of cycles).
#[inline(always)]
pub(crate) fn wrap_index(c: isize, n: isize) -> isize {
    if c >= 0 && c < n {
        c
    } else if c < 0 && c >= -n {
        c + n
    } else if c >= n && c < 2 * n {
        c - n
    } else {
        c.rem_euclid(n)
    }
}

/// `floor(v)` as an integer, saturating (NaN gives 0). Inlined, unlike `f64::floor` on
/// baseline x86-64, which calls libm.
#[inline(always)]
pub(crate) fn floor_to_isize(v: f64) -> isize {
    let t = v as isize;
    if (t as f64) > v {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// The level of a disc of interaction diameter `d` given the smallest one, `d_min`.
#[inline]
pub(super) fn level_of(d: f64, d_min: f64) -> usize {
    let mut level = 0;
    let mut band = 2.0 * d_min;
    while d > band && level < MAX_LEVELS - 1 {
        band *= 2.0;
        level += 1;
    }
    level
}

/// The upper bounds of the levels but the last, `d_min 2^(k+1)`: [`level_of`] without its
/// loop. A disc's level is how many bounds its diameter exceeds (they increase, so that is
/// the loop's count), found with comparisons and no branch: with radii spread at random,
/// the loop's exit mispredicted about once a disc.
struct LevelBounds([f64; MAX_LEVELS - 1]);

impl LevelBounds {
    fn new(d_min: f64) -> Self {
        let mut bound = d_min;
        // Doubled like the loop's band, so the same values (and infinities) come out.
        LevelBounds(std::array::from_fn(|_| {
            bound *= 2.0;
            bound
        }))
    }

    #[inline(always)]
    fn level(&self, d: f64) -> usize {
        self.0.iter().map(|&bound| (d > bound) as usize).sum()
    }
}

/// Cells along one axis of width `width` for cells of at least `min_cell`.
fn cells_along(width: f64, min_cell: f64, wrap: bool) -> usize {
    let n = (width / min_cell).floor();
    let n = if n.is_finite() && n >= 1.0 {
        // Bounded so cell counts never overflow, even with 32-bit usize.
        n.min(1e6) as usize
    } else {
        1
    };
    // With 1 or 2 cells a periodic stencil would meet the same cell twice: use one cell.
    if wrap && n < 3 { 1 } else { n }
}

/// The levels of discs with radii `radius`: the non-empty levels in order, and in
/// `level_of` each disc's (compacted) level, left empty when there is only one. One level is
/// the common case (equal or similar discs): then no per-disc level is stored at all. Also
/// returns the smallest and largest radius.
pub(super) fn assign(radius: &[f64], law: &Law, level_of: &mut Vec<u8>) -> (Vec<Level>, [f64; 2]) {
    let [r_min, r_max] = radius_bounds(radius);
    let d_min = law.interaction_diameter(r_min);
    level_of.clear();
    if level_of_radius(law, r_max, d_min) == 0 {
        let single = Level {
            index: 0,
            count: radius.len(),
            max_radius: r_max,
            merged: false,
        };
        return (vec![single], [r_min, r_max]);
    }
    let bounds = LevelBounds::new(d_min);
    level_of.extend(
        radius
            .iter()
            .map(|&r| bounds.level(law.interaction_diameter(r)) as u8),
    );
    let mut stats = [(0usize, 0.0f64); MAX_LEVELS];
    for (&l, &r) in level_of.iter().zip(radius) {
        let (n, max_r) = &mut stats[l as usize];
        *n += 1;
        *max_r = max_r.max(r);
    }
    // Compact the non-empty levels.
    let mut used = Vec::new();
    let mut compact = [0u8; MAX_LEVELS];
    for (l, &(count, max_radius)) in stats.iter().enumerate() {
        if count > 0 {
            compact[l] = used.len() as u8;
            used.push(Level {
                index: used.len(),
                count,
                max_radius,
                merged: false,
            });
        }
    }
    for l in level_of.iter_mut() {
        *l = compact[*l as usize];
    }
    (used, [r_min, r_max])
}

/// The smallest and largest of `radius` (finite and positive: the particles' rule), or
/// infinity and zero for none. Four running minima and maxima, not one: each waits on the
/// last, and one chain of them was most of the 1M gas's levels (`minsd`'s latency a disc);
/// a minimum or maximum of numbers is exact, so any grouping gives the same bits.
fn radius_bounds(radius: &[f64]) -> [f64; 2] {
    let (mut lo, mut hi) = ([f64::INFINITY; 4], [0.0f64; 4]);
    let (quads, rest) = radius.as_chunks::<4>();
    for quad in quads {
        for k in 0..4 {
            lo[k] = if quad[k] < lo[k] { quad[k] } else { lo[k] };
            hi[k] = if quad[k] > hi[k] { quad[k] } else { hi[k] };
        }
    }
    for &r in rest {
        lo[0] = if r < lo[0] { r } else { lo[0] };
        hi[0] = if r > hi[0] { r } else { hi[0] };
    }
    [
        lo.into_iter().fold(f64::INFINITY, f64::min),
        hi.into_iter().fold(0.0, f64::max),
    ]
}

/// Merges adjacent levels, from the coarsest down, while the merged grid of a box of
/// `extent` with cells for `skin` would hold at most [`MERGED_OCCUPANCY`] discs per cell,
/// renumbering `level_of` (cleared when one level is left). In an open world the grid
/// covers the bulk of a level's discs, which is not known before its median is: the levels
/// stay apart.
pub(super) fn merge(
    levels: &mut Vec<Level>,
    level_of: &mut Vec<u8>,
    law: &Law,
    skin: f64,
    extent: Option<Extent>,
) {
    let Some(extent) = extent else { return };
    if levels.len() < 2 {
        return;
    }
    // Discs per cell of a grid like `level_grid`'s: cells of at least `min_cell`, at most
    // about one per disc.
    let occupancy = |count: usize, max_radius: f64| {
        let min_cell = law.interaction_diameter(max_radius) + skin;
        let cells = cells_along(extent.width[0], min_cell, extent.wrap) as f64
            * cells_along(extent.width[1], min_cell, extent.wrap) as f64;
        count as f64 / cells.min(max_cells(count) as f64)
    };
    // Coarsest first; `group_of[k]` counts from the coarsest too until the renumbering.
    let mut merged: Vec<Level> = Vec::with_capacity(levels.len());
    let mut group_of = [0u8; MAX_LEVELS];
    for level in levels.iter().rev() {
        match merged.last_mut() {
            Some(last)
                if occupancy(last.count + level.count, last.max_radius) <= MERGED_OCCUPANCY =>
            {
                last.count += level.count;
                last.merged = true;
            }
            _ => merged.push(*level),
        }
        group_of[level.index] = (merged.len() - 1) as u8;
    }
    if merged.len() == levels.len() {
        return;
    }
    let groups = merged.len();
    merged.reverse();
    for (index, level) in merged.iter_mut().enumerate() {
        level.index = index;
    }
    if groups == 1 {
        level_of.clear();
    } else {
        for l in level_of.iter_mut() {
            *l = (groups - 1) as u8 - group_of[*l as usize];
        }
    }
    *levels = merged;
}

#[inline]
fn level_of_radius(law: &Law, r: f64, d_min: f64) -> usize {
    level_of(law.interaction_diameter(r), d_min)
}

/// The region the grids cover: the box, or none in an open world (whose grids follow their
/// discs). A part of a walled world (a distributed run's, told by its tally) holds only the
/// discs of its region and a halo, so its grids cover the box cut down to their bounding
/// box: with at most about one cell per disc over the whole box, a part of `R` had about
/// `R` discs in each cell of its region.
pub(super) fn extent([x, y]: [&[f64]; 2], ctx: &StepContext) -> Option<Extent> {
    let whole = ctx.geometry.grid_extent()?;
    if whole.wrap || ctx.tally.is_none() || x.is_empty() {
        return Some(whole);
    }
    let mut cut = whole;
    for (axis, v) in [x, y].into_iter().enumerate() {
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let (lo, hi) = (
            lo.max(whole.origin[axis]),
            hi.min(whole.origin[axis] + whole.width[axis]),
        );
        if lo <= hi {
            cut.origin[axis] = lo;
            cut.width[axis] = hi - lo;
        }
    }
    Some(cut)
}

/// The grid for one level, over `extent` (see [`extent`]).
pub(super) fn level_grid(
    positions: [&[f64]; 2],
    extent: Option<Extent>,
    ctx: &StepContext,
    skin: f64,
    level: Level,
    cell_offset: usize,
    discs: &Discs,
) -> LevelGrid {
    let Level {
        index: level,
        count: n_level,
        max_radius,
        merged,
    } = level;
    let min_cell = ctx.law.interaction_diameter(max_radius) + skin;
    let max_cells = max_cells(n_level);
    let (origin, width, wrap) = match extent {
        Some(Extent {
            origin,
            width,
            wrap,
        }) => (origin, width, wrap),
        None => {
            let side = (max_cells as f64).sqrt() * min_cell;
            let mut origin = [0.0; 2];
            let mut width = [0.0; 2];
            for axis in 0..2 {
                let (lo, hi, median) = spread(positions[axis], level, discs);
                // The bulk around the median; outliers fall into the edge cells.
                let lo = lo.max(median - side / 2.0);
                let hi = hi.min(median + side / 2.0);
                origin[axis] = lo;
                width[axis] = hi - lo;
            }
            (origin, width, false)
        }
    };
    let mut n = [
        cells_along(width[0], min_cell, wrap),
        cells_along(width[1], min_cell, wrap),
    ];
    let total = n[0] as f64 * n[1] as f64;
    if total > max_cells as f64 {
        let shrink = (total / max_cells as f64).sqrt();
        for cells in &mut n {
            let fewer = ((*cells as f64 / shrink).floor() as usize).max(1);
            *cells = if wrap && fewer < 3 { 1 } else { fewer };
        }
    }
    if ctx.geometry.slide().is_some() && n[1] == 1 {
        // A Lees–Edwards box one cell high: partners across the top and bottom may be
        // anywhere along x, so the level is one cell.
        n[0] = 1;
    }
    let cell = [0, 1].map(|axis| {
        if n[axis] == 1 && !wrap {
            width[axis].max(min_cell)
        } else {
            width[axis] / n[axis] as f64
        }
    });
    let axis_offsets = |axis: usize| -> Vec<isize> {
        if wrap && n[axis] == 1 {
            vec![0]
        } else {
            vec![-1, 0, 1]
        }
    };
    let mut forward = Vec::new();
    for &dy in &axis_offsets(1) {
        for &dx in &axis_offsets(0) {
            if dy > 0 || (dy == 0 && dx > 0) {
                forward.push([dx, dy]);
            }
        }
    }
    LevelGrid {
        origin,
        inv_cell: [1.0 / cell[0], 1.0 / cell[1]],
        n,
        wrap,
        cell_offset,
        max_radius,
        pairwise: merged,
        forward,
    }
}

/// Minimum, maximum and median of one coordinate over the discs of `level`.
fn spread(coords: &[f64], level: usize, discs: &Discs) -> (f64, f64, f64) {
    let mut v = discs.scratch.borrow_mut();
    v.clear();
    if discs.level_of.is_empty() {
        v.extend_from_slice(coords);
    } else {
        v.extend(
            coords
                .iter()
                .zip(discs.level_of)
                .filter(|&(_, &l)| l as usize == level)
                .map(|(&v, _)| v),
        );
    }
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mid = v.len() / 2;
    let (_, &mut median, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    (lo, hi, median)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_radius_bounds_are_the_smallest_and_largest() {
        // Every length from none to past a few quads, extremes anywhere (in a quad's lanes
        // and in the tail), against the plain fold.
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            0.01 + (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for len in 0..19 {
            for _ in 0..20 {
                let radius: Vec<f64> = (0..len).map(|_| next()).collect();
                let expected = radius.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
                    (lo.min(r), hi.max(r))
                });
                assert_eq!(
                    radius_bounds(&radius),
                    [expected.0, expected.1],
                    "{radius:?}"
                );
            }
        }
    }

    #[test]
    fn a_clamped_coordinate_is_the_floor_clamped() {
        // Around every cell edge (a few units in the last place either side), far outside,
        // at the infinities and NaN: the same cell as the floor clamped to the grid.
        let grid = |wrap| LevelGrid {
            origin: [-3.25, 0.0],
            inv_cell: [1.0 / 0.7, 1.0],
            n: [9, 1],
            wrap,
            cell_offset: 0,
            max_radius: 0.5,
            pairwise: false,
            forward: Vec::new(),
        };
        let g = grid(false);
        let by_floor = |v: f64| {
            let c = floor_to_isize((v - g.origin[0]) * g.inv_cell[0]);
            c.clamp(0, g.n[0] as isize - 1) as usize
        };
        let mut values = vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e300,
            -1e300,
            -0.0,
        ];
        for edge in -3..=12 {
            let mut v = g.origin[0] + edge as f64 * 0.7;
            for _ in 0..4 {
                v = v.next_down();
            }
            for _ in 0..8 {
                values.push(v);
                v = v.next_up();
            }
        }
        for v in values {
            assert_eq!(g.coord(v, 0), by_floor(v), "{v}");
        }
        // A periodic grid still wraps.
        assert_eq!(grid(true).coord(-3.25 - 0.1, 0), 8);
    }

    #[test]
    fn the_bounds_give_the_levels_of_the_loop() {
        for d_min in [1e-300, 1e-3, 0.1, 1.0, 3.7, 1e300] {
            let bounds = LevelBounds::new(d_min);
            let mut d = d_min;
            while d.is_finite() {
                for v in [d, d.next_up(), d * 1.37, d.next_down()] {
                    assert_eq!(bounds.level(v), level_of(v, d_min), "{v} over {d_min}");
                }
                d *= 2.0;
            }
            for v in [f64::INFINITY, f64::NAN, 0.0] {
                assert_eq!(bounds.level(v), level_of(v, d_min), "{v} over {d_min}");
            }
        }
    }

    #[test]
    fn levels_band_by_factor_two() {
        assert_eq!(level_of(1.0, 1.0), 0);
        assert_eq!(level_of(2.0, 1.0), 0);
        assert_eq!(level_of(2.01, 1.0), 1);
        assert_eq!(level_of(4.0, 1.0), 1);
        assert_eq!(level_of(50.0, 1.0), 5);
        assert_eq!(level_of(f64::MAX, 1e-300), MAX_LEVELS - 1);
    }

    #[test]
    fn wrapping_is_the_euclidean_remainder() {
        for n in [1isize, 2, 3, 7, 1000] {
            for c in -3 * n - 2..3 * n + 2 {
                assert_eq!(wrap_index(c, n), c.rem_euclid(n), "{c} mod {n}");
            }
        }
        assert_eq!(
            wrap_index(isize::MIN / 2, 7),
            (isize::MIN / 2).rem_euclid(7)
        );
    }

    #[test]
    fn periodic_grids_never_have_two_cells_on_an_axis() {
        assert_eq!(cells_along(10.0, 4.0, true), 1);
        assert_eq!(cells_along(10.0, 4.0, false), 2);
        assert_eq!(cells_along(10.0, 3.0, true), 3);
        assert_eq!(cells_along(0.0, 3.0, false), 1);
    }

    /// The levels of `radius` in a `side` × `side` box with a skin of 0.15, merged.
    fn merged(radius: &[f64], side: f64) -> (Vec<Level>, Vec<u8>) {
        let law = Law::new(&crate::Config::default());
        let mut level_of = Vec::new();
        let (mut levels, _) = assign(radius, &law, &mut level_of);
        let extent = Extent {
            origin: [0.0, 0.0],
            width: [side, side],
            wrap: false,
        };
        merge(&mut levels, &mut level_of, &law, 0.15, Some(extent));
        (levels, level_of)
    }

    #[test]
    fn sparse_levels_share_a_grid_and_crowded_ones_do_not() {
        // Radii uniform in 0.05–5 at packing 0.3 (the benchmark's polydisperse gas): seven
        // bands, each grid about one disc per cell; all of them in one grid (diameter 10 +
        // 0.15) hold 1.2 per cell.
        let count = 20_000;
        let radius: Vec<f64> = (0..count)
            .map(|i| 0.05 + 4.95 * (i as f64 + 0.5) / count as f64)
            .collect();
        let side = (count as f64 * std::f64::consts::PI * 8.4175 / 0.3).sqrt();
        let law = Law::new(&crate::Config::default());
        assert_eq!(assign(&radius, &law, &mut Vec::new()).0.len(), 7);
        let (levels, level_of) = merged(&radius, side);
        assert_eq!(levels.len(), 1);
        assert!(levels[0].merged && levels[0].count == count && levels[0].max_radius > 4.99);
        assert!(level_of.is_empty());

        // Nine small discs to each large one, as dense: one grid for both would put 3.9
        // discs in a cell; they stay apart.
        let radius: Vec<f64> = (0..count)
            .map(|i| if i % 10 == 0 { 5.0 } else { 0.1 })
            .collect();
        let side = (count as f64 * std::f64::consts::PI * (0.9 * 0.01 + 0.1 * 25.0) / 0.3).sqrt();
        let (levels, level_of) = merged(&radius, side);
        assert_eq!(levels.len(), 2);
        assert!(!levels[0].merged && !levels[1].merged);
        assert_eq!((level_of[0], level_of[1]), (1, 0));

        // Bands 0.1, 2, 4: the two large ones merge (each alone sparse), the crowd of small
        // discs stays apart, and the levels are renumbered.
        let radius: Vec<f64> = (0..count)
            .map(|i| match i % 10 {
                0 => 4.0,
                1 => 2.0,
                _ => 0.1,
            })
            .collect();
        let (levels, level_of) = merged(&radius, side);
        assert_eq!(levels.len(), 2);
        assert!(!levels[0].merged && levels[1].merged);
        assert_eq!((levels[1].index, levels[1].count), (1, count / 5));
        assert_eq!(&level_of[..3], &[1, 1, 0]);
    }

    #[test]
    fn a_part_of_a_walled_world_grids_its_discs_bounding_box() {
        // Discs in [10, 30] × [40, 45] of a 100 × 100 box: a part (with a tally) covers just
        // that; the whole world, or a periodic part (it must wrap), the box.
        let x = [10.0, 30.0, 20.0];
        let y = [45.0, 40.0, 42.0];
        let exec = crate::parallel::Executor::default();
        let tally = crate::Tally::new([0.0, 50.0], [f64::NEG_INFINITY, f64::INFINITY], [None; 2]);
        for (boundary, tally, expected) in [
            (
                crate::Boundary::walls([0.0, 0.0], [100.0, 100.0]),
                Some(tally),
                ([10.0, 40.0], [20.0, 5.0]),
            ),
            (
                crate::Boundary::walls([0.0, 0.0], [100.0, 100.0]),
                None,
                ([0.0, 0.0], [100.0, 100.0]),
            ),
            (
                crate::Boundary::periodic([0.0, 0.0], [100.0, 100.0]),
                Some(tally),
                ([0.0, 0.0], [100.0, 100.0]),
            ),
        ] {
            let config = crate::Config {
                boundary,
                ..crate::Config::default()
            };
            let ctx = StepContext::new(&config, 0.1, &exec, tally);
            let extent = extent([&x, &y], &ctx).unwrap();
            assert_eq!(
                (extent.origin, extent.width),
                expected,
                "{:?}",
                config.boundary
            );
        }
        // A disc pushed just outside a wall is clamped back into the box.
        let config = crate::Config {
            boundary: crate::Boundary::walls([0.0, 0.0], [100.0, 100.0]),
            ..crate::Config::default()
        };
        let ctx = StepContext::new(&config, 0.1, &exec, Some(tally));
        let clamped = extent([&[-1.0, 5.0], &[50.0, 101.0]], &ctx).unwrap();
        assert_eq!((clamped.origin, clamped.width), ([0.0, 50.0], [5.0, 50.0]));
        // An open world has none: its grids follow their discs.
        let config = crate::Config::default();
        let ctx = StepContext::new(&config, 0.1, &exec, Some(tally));
        assert!(extent([&[1.0], &[2.0]], &ctx).is_none());
    }

    #[test]
    fn levels_in_an_open_world_stay_apart() {
        let law = Law::new(&crate::Config::default());
        let mut level_of = Vec::new();
        let (mut levels, _) = assign(&[0.1, 5.0], &law, &mut level_of);
        merge(&mut levels, &mut level_of, &law, 0.15, None);
        assert_eq!((levels.len(), level_of), (2, vec![0, 1]));
    }

    #[test]
    fn similar_discs_share_one_level_and_store_none() {
        let law = Law::new(&crate::Config::default());
        let mut level_of = vec![7];
        let (levels, radii) = assign(&[0.5, 0.9, 1.0], &law, &mut level_of);
        assert_eq!((levels.len(), radii), (1, [0.5, 1.0]));
        assert!(level_of.is_empty());
        let (levels, _) = assign(&[0.5, 5.0, 1.5], &law, &mut level_of);
        assert_eq!(levels.len(), 3);
        assert_eq!(level_of, vec![0, 2, 1]);
    }
}
