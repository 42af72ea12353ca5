//! Broadphase: which pairs are within the seed's collision distance, found in O(N).
//!
//! # Grids
//! Discs are binned into uniform grids (cell lists) with no fixed cell capacity: a counting
//! sort by cell index reorders the particle arrays so each cell is a contiguous run. The cell
//! side is at least the largest interaction diameter `2 r collision_radius_scale` of the
//! discs in the grid, so every partner lies in the 3×3 cells around a disc.
//!
//! # Polydisperse radii: a hierarchy of grids
//! One grid sized for the largest disc would put thousands of small discs in a cell when radii
//! span 0.1 to 5. Instead each disc gets a *level* by its interaction diameter `d`:
//! level `k` holds `d_min 2^k < d <= d_min 2^(k+1)` (level 0 includes `d_min`), and each
//! non-empty level has its own grid sized for its largest disc. A disc meets discs of its own
//! level through the 3×3 stencil, and discs of finer levels by scanning the finer grid's cells
//! under its reach. Cost stays proportional to the area actually covered, whatever the mix.
//!
//! # Canonical order and blocks
//! Each pair is *owned* by one cell: the cell of the coarser disc, or for discs of one level,
//! the cell visited first by the forward half-stencil. Both discs lie in the 3×3 cells around
//! the owner cell. Each level's cells are tiled into blocks at least two cells wide, coloured
//! 2×2 (with an even block count across periodic edges). Blocks of one colour are then at
//! least two cells apart, so their pairs touch disjoint discs and can be resolved at once.
//! The canonical resolution order is: level (fine to coarse), colour, block (row-major),
//! cell (row-major), owner disc (by id), partner (in scan order). It depends on the particle
//! data only, so one thread and eight give the same bits.
//!
//! # Open worlds
//! Cell coordinates are clamped to the grid (wrapped, in a periodic box). Clamping never increases the distance between
//! two cell coordinates, so partners stay within one cell of each other and the stencil and
//! block arguments hold. An open world's grid covers the bulk of its discs (around the median
//! position, capped at a few cells per disc); discs far away pile into edge cells, which
//! costs time but never misses a pair.

use std::ops::Range;

use crate::config::{Boundary, Config};
use crate::parallel::{CHUNK, Executor};
use crate::particles::{ParticleId, Particles, PermuteScratch};

/// At most this many grid levels (interaction diameters spanning a factor 2^16).
const MAX_LEVELS: usize = 16;
/// At most this many blocks along one axis of a level.
const MAX_BLOCKS_PER_AXIS: usize = 32;
/// Blocks aim to hold about this many discs: enough work per task, enough tasks per colour.
const DISCS_PER_BLOCK: f64 = 256.0;

/// A pair of storage indices found within the collision distance, owner first.
pub(crate) type Pair = [u32; 2];

/// One level's uniform grid.
#[derive(Clone, Debug)]
struct LevelGrid {
    origin: [f64; 2],
    inv_cell: [f64; 2],
    n: [usize; 2],
    /// Whether cell coordinates wrap (periodic box).
    wrap: bool,
    /// First global cell index of this level.
    cell_offset: usize,
    /// Largest radius at this level, for cross-level reach.
    max_radius: f64,
    /// Forward half-stencil: neighbour offsets whose pairs this cell owns.
    forward: Vec<[isize; 2]>,
}

impl LevelGrid {
    /// The (clamped) cell coordinate of `v` along `axis`.
    #[inline]
    fn coord(&self, v: f64, axis: usize) -> usize {
        let c = floor_to_isize((v - self.origin[axis]) * self.inv_cell[axis]);
        // A periodic coordinate wraps, since an overlap push can leave a centre a little
        // outside the box.
        let n = self.n[axis] as isize;
        if self.wrap {
            c.rem_euclid(n) as usize
        } else {
            c.clamp(0, n - 1) as usize
        }
    }

    /// Maps a possibly out-of-range cell coordinate to the grid: wrapped when periodic,
    /// `None` when outside a non-periodic grid.
    #[inline]
    fn neighbour(&self, c: isize, axis: usize) -> Option<usize> {
        let n = self.n[axis] as isize;
        if self.wrap {
            Some(c.rem_euclid(n) as usize)
        } else {
            (0..n).contains(&c).then_some(c as usize)
        }
    }

    #[inline]
    fn cell_index(&self, cx: usize, cy: usize) -> usize {
        self.cell_offset + cy * self.n[0] + cx
    }
}

/// A rectangle of cells of one level whose pairs are found and resolved together.
#[derive(Clone, Debug)]
pub(crate) struct Block {
    level: usize,
    x: Range<usize>,
    y: Range<usize>,
}

/// The grids, the blocks and the pairs found in the last substep.
#[derive(Debug, Default)]
pub(crate) struct Broadphase {
    levels: Vec<LevelGrid>,
    /// Global cell `c` holds storage indices `cell_start[c]..cell_start[c + 1]`.
    cell_start: Vec<u32>,
    blocks: Vec<Block>,
    /// Ranges of `blocks` that may run at the same time, in canonical order.
    pub(crate) phases: Vec<Range<usize>>,
    /// Pairs owned by each block, in canonical order.
    pub(crate) pairs: Vec<Vec<Pair>>,
    // Scratch reused between steps.
    key: Vec<u32>,
    order: Vec<u32>,
    /// Per-disc level; empty when all discs share level 0.
    level_of: Vec<u8>,
    f64_scratch: Vec<f64>,
    scratch: PermuteScratch,
}

/// What pair detection measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Detection {
    pub pairs: usize,
    pub max_overlap: f64,
}

/// The minimum-image helper: box sizes, or `None` when not periodic.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Periodicity(Option<[f64; 2]>);

impl Periodicity {
    pub(crate) fn of(config: &Config) -> Self {
        match config.boundary {
            Boundary::Periodic { min, max } => {
                Periodicity(Some([max[0] - min[0], max[1] - min[1]]))
            }
            _ => Periodicity(None),
        }
    }

    /// `p1 - p2`, as the minimum image in a periodic box. Positions may sit slightly outside
    /// the box after an overlap push; one correction per axis still finds the nearest image.
    #[inline]
    pub(crate) fn diff(&self, x1: f64, y1: f64, x2: f64, y2: f64) -> [f64; 2] {
        let (mut dx, mut dy) = (x1 - x2, y1 - y2);
        if let Some([lx, ly]) = self.0 {
            if dx > 0.5 * lx {
                dx -= lx;
            } else if dx < -0.5 * lx {
                dx += lx;
            }
            if dy > 0.5 * ly {
                dy -= ly;
            } else if dy < -0.5 * ly {
                dy += ly;
            }
        }
        [dx, dy]
    }
}

/// `floor(v)` as an integer, saturating (NaN gives 0). Inlined, unlike `f64::floor` on
/// baseline x86-64, which calls libm.
#[inline(always)]
fn floor_to_isize(v: f64) -> isize {
    let t = v as isize;
    if (t as f64) > v { t - 1 } else { t }
}

/// The level of a disc of interaction diameter `d` given the smallest one, `d_min`.
#[inline]
fn level_of(d: f64, d_min: f64) -> usize {
    let mut level = 0;
    let mut band = 2.0 * d_min;
    while d > band && level < MAX_LEVELS - 1 {
        band *= 2.0;
        level += 1;
    }
    level
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

/// Splits `n` cells into blocks of about `side` cells, at least 2 each; an even count (or 1)
/// so the 2-colouring also holds across a periodic edge.
fn block_splits(n: usize, side: usize) -> Vec<usize> {
    let mut nb = (n / side.max(2)).clamp(1, MAX_BLOCKS_PER_AXIS);
    if nb >= 2 {
        nb -= nb % 2;
    }
    (0..=nb).map(|b| b * n / nb).collect()
}

impl Broadphase {
    /// Bins the discs into the level grids and reorders the particle arrays into canonical
    /// cell order (by level, cell, then id).
    pub(crate) fn rebuild(&mut self, p: &mut Particles, config: &Config, exec: &Executor) {
        let count = p.len();
        self.levels.clear();
        self.blocks.clear();
        self.phases.clear();
        if count == 0 {
            self.cell_start.clear();
            self.cell_start.push(0);
            return;
        }
        let s = config.collision_radius_scale;

        // 1. Levels: a band of interaction diameters each. One band is the common case
        // (equal or similar discs): then no per-disc level is stored at all.
        let (r_min, r_max) = p
            .radius
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
                (lo.min(r), hi.max(r))
            });
        let d_min = 2.0 * r_min * s;
        let single_level = level_of(2.0 * r_max * s, d_min) == 0;
        let mut used = Vec::new();
        if single_level {
            self.level_of.clear();
            used.push((count, r_max));
        } else {
            self.level_of.clear();
            self.level_of
                .extend(p.radius.iter().map(|&r| level_of(2.0 * r * s, d_min) as u8));
            let mut stats = [(0usize, 0.0f64); MAX_LEVELS];
            for (&l, &r) in self.level_of.iter().zip(&p.radius) {
                let (n, max_r) = &mut stats[l as usize];
                *n += 1;
                *max_r = max_r.max(r);
            }
            // Compact the non-empty levels.
            let mut compact = [0u8; MAX_LEVELS];
            for (l, &(n, max_r)) in stats.iter().enumerate() {
                if n > 0 {
                    compact[l] = used.len() as u8;
                    used.push((n, max_r));
                }
            }
            for l in &mut self.level_of {
                *l = compact[*l as usize];
            }
        }

        // 2. One grid per level.
        let mut cell_offset = 0;
        for (level, &(n_level, max_r)) in used.iter().enumerate() {
            let grid = self.level_grid(p, config, level, n_level, max_r, cell_offset);
            cell_offset += grid.n[0] * grid.n[1];
            self.levels.push(grid);
        }
        let total_cells = cell_offset;

        // 3. Counting sort by global cell index.
        self.key.resize(count, 0);
        {
            let (levels, level_of, p) = (&self.levels, &self.level_of, &*p);
            let mut chunks: Vec<(usize, &mut [u32])> =
                self.key.chunks_mut(CHUNK).enumerate().collect();
            exec.for_each_mut(&mut chunks, |_, (c, keys)| {
                let base = *c * CHUNK;
                for (k, key) in keys.iter_mut().enumerate() {
                    let i = base + k;
                    let g = if level_of.is_empty() {
                        &levels[0]
                    } else {
                        &levels[level_of[i] as usize]
                    };
                    let (cx, cy) = (g.coord(p.x[i], 0), g.coord(p.y[i], 1));
                    *key = g.cell_index(cx, cy) as u32;
                }
            });
        }
        self.cell_start.clear();
        self.cell_start.resize(total_cells + 1, 0);
        for &k in &self.key {
            self.cell_start[k as usize + 1] += 1;
        }
        for c in 0..total_cells {
            self.cell_start[c + 1] += self.cell_start[c];
        }
        self.order.resize(count, 0);
        {
            // Place each disc at its cell's next free slot; afterwards slot `c` holds the end
            // of cell `c`, and one shift restores the starts.
            let next = &mut self.cell_start;
            for (i, &k) in self.key.iter().enumerate() {
                let slot = &mut next[k as usize];
                self.order[*slot as usize] = i as u32;
                *slot += 1;
            }
            next.copy_within(0..total_cells, 1);
            next[0] = 0;
        }
        // Within a cell, order by id, so the canonical order does not depend on storage order.
        // Storage is already in this order from the last step except for discs that changed
        // cell, so an insertion sort does almost no work.
        for c in 0..total_cells {
            let (lo, hi) = (self.cell_start[c] as usize, self.cell_start[c + 1] as usize);
            if hi - lo > 1 {
                insertion_sort_by_id(&mut self.order[lo..hi], &p.id);
            }
        }
        p.permute(&self.order, &mut self.scratch, exec);

        // 4. Blocks and phases.
        for (level, g) in self.levels.iter().enumerate() {
            let cells = (g.n[0] * g.n[1]) as f64;
            let n_level = used[level].0 as f64;
            let side = (DISCS_PER_BLOCK * cells / n_level).sqrt().ceil() as usize;
            let xs = block_splits(g.n[0], side);
            let ys = block_splits(g.n[1], side);
            for colour in 0..4 {
                let start = self.blocks.len();
                for by in (colour / 2..ys.len() - 1).step_by(2) {
                    for bx in (colour % 2..xs.len() - 1).step_by(2) {
                        self.blocks.push(Block {
                            level,
                            x: xs[bx]..xs[bx + 1],
                            y: ys[by]..ys[by + 1],
                        });
                    }
                }
                if self.blocks.len() > start {
                    self.phases.push(start..self.blocks.len());
                }
            }
        }
        self.pairs.resize_with(self.blocks.len(), Vec::new);
    }

    /// The grid for one level.
    fn level_grid(
        &mut self,
        p: &Particles,
        config: &Config,
        level: usize,
        n_level: usize,
        max_radius: f64,
        cell_offset: usize,
    ) -> LevelGrid {
        let min_cell = 2.0 * max_radius * config.collision_radius_scale;
        // A few cells per disc at most: enough for an O(1) stencil, bounded memory.
        // About one cell per disc at most: fewer, fuller cells beat many empty ones (a
        // dense gas at cell side = diameter would leave most cells empty).
        let max_cells = n_level + 64;
        let (origin, width, wrap) = match config.boundary {
            Boundary::Walls { min, max, .. } => (min, [max[0] - min[0], max[1] - min[1]], false),
            Boundary::Periodic { min, max } => (min, [max[0] - min[0], max[1] - min[1]], true),
            Boundary::Open => {
                let side = (max_cells as f64).sqrt() * min_cell;
                let mut origin = [0.0; 2];
                let mut width = [0.0; 2];
                for axis in 0..2 {
                    let coords = if axis == 0 { &p.x } else { &p.y };
                    let (lo, hi, median) = self.spread(coords, level);
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
            forward,
        }
    }

    /// Minimum, maximum and median of one coordinate over the discs of `level`.
    fn spread(&mut self, coords: &[f64], level: usize) -> (f64, f64, f64) {
        self.f64_scratch.clear();
        if self.level_of.is_empty() {
            self.f64_scratch.extend_from_slice(coords);
        } else {
            self.f64_scratch.extend(
                coords
                    .iter()
                    .zip(&self.level_of)
                    .filter(|&(_, &l)| l as usize == level)
                    .map(|(&v, _)| v),
            );
        }
        let v = &mut self.f64_scratch;
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mid = v.len() / 2;
        let (_, &mut median, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
        (lo, hi, median)
    }

    /// Finds every pair within the collision distance into the per-block lists.
    pub(crate) fn find_pairs(
        &mut self,
        p: &Particles,
        config: &Config,
        exec: &Executor,
    ) -> Detection {
        let ctx = Context {
            p,
            levels: &self.levels,
            cell_start: &self.cell_start,
            scale: config.collision_radius_scale,
            periodicity: Periodicity::of(config),
        };
        let blocks = &self.blocks;
        let mut overlaps = vec![0.0f64; blocks.len()];
        let mut work: Vec<(&mut Vec<Pair>, &mut f64)> =
            self.pairs.iter_mut().zip(overlaps.iter_mut()).collect();
        exec.for_each_mut(&mut work, |b, (pairs, overlap)| {
            pairs.clear();
            **overlap = ctx.block_pairs(&blocks[b], pairs);
        });
        Detection {
            pairs: self.pairs.iter().map(Vec::len).sum(),
            max_overlap: overlaps.into_iter().fold(0.0, f64::max),
        }
    }

    /// The pairs found by the last [`Broadphase::find_pairs`], as sorted id pairs.
    pub(crate) fn pair_ids(&self, p: &Particles) -> Vec<(ParticleId, ParticleId)> {
        let mut out: Vec<_> = self
            .pairs
            .iter()
            .flatten()
            .map(|&[a, b]| ordered(p.id[a as usize], p.id[b as usize]))
            .collect();
        out.sort_unstable();
        out
    }
}

/// Sorts storage indices by particle id; linear when already sorted.
fn insertion_sort_by_id(run: &mut [u32], id: &[ParticleId]) {
    for k in 1..run.len() {
        let v = run[k];
        let mut j = k;
        while j > 0 && id[run[j - 1] as usize] > id[v as usize] {
            run[j] = run[j - 1];
            j -= 1;
        }
        run[j] = v;
    }
}

fn ordered(a: ParticleId, b: ParticleId) -> (ParticleId, ParticleId) {
    if a < b { (a, b) } else { (b, a) }
}

/// Read-only view the detection of one block needs.
struct Context<'a> {
    p: &'a Particles,
    levels: &'a [LevelGrid],
    cell_start: &'a [u32],
    scale: f64,
    periodicity: Periodicity,
}

impl Context<'_> {
    #[inline]
    fn cell_range(&self, cell: usize) -> Range<usize> {
        self.cell_start[cell] as usize..self.cell_start[cell + 1] as usize
    }

    /// Tests `a` against each disc of `others`, recording hits and the largest overlap.
    #[inline(always)]
    fn test(&self, a: usize, others: Range<usize>, out: &mut Vec<Pair>, max_overlap: &mut f64) {
        let p = self.p;
        let (xa, ya, ra) = (p.x[a], p.y[a], p.radius[a]);
        let start = others.start;
        // Slices first: the loop then runs without bounds checks.
        let (xs, ys, rs) = (
            &p.x[others.clone()],
            &p.y[others.clone()],
            &p.radius[others],
        );
        for (k, ((&xb, &yb), &rb)) in xs.iter().zip(ys).zip(rs).enumerate() {
            let [dx, dy] = self.periodicity.diff(xa, ya, xb, yb);
            let d2 = dx * dx + dy * dy;
            let reach = (ra + rb) * self.scale;
            // Cheap squared early-out with a margin, then the seed's exact test on the
            // distance itself (so rounding matches `collision::is_colliding`).
            if d2 <= reach * reach * (1.0 + 1e-12) {
                let distance = d2.sqrt();
                if distance <= reach {
                    out.push([a as u32, (start + k) as u32]);
                    *max_overlap = max_overlap.max(reach - distance);
                }
            }
        }
    }

    /// All pairs owned by the cells of `block`, in canonical order.
    fn block_pairs(&self, block: &Block, out: &mut Vec<Pair>) -> f64 {
        let g = &self.levels[block.level];
        let mut max_overlap = 0.0;
        let finer = &self.levels[..block.level];
        for cy in block.y.clone() {
            for cx in block.x.clone() {
                let own_cell = g.cell_index(cx, cy);
                let own = self.cell_range(own_cell);
                if own.is_empty() {
                    continue;
                }
                // The own cell and the forward half-stencil, in stencil order, with cells that
                // follow each other in memory merged into one run: (cx, cy) and (cx + 1, cy)
                // are one run, and so is the row above. Fewer, longer loops.
                let mut runs = [(own_cell, own_cell); 5];
                let mut count = 1;
                for &[dx, dy] in &g.forward {
                    if let (Some(nx), Some(ny)) = (
                        g.neighbour(cx as isize + dx, 0),
                        g.neighbour(cy as isize + dy, 1),
                    ) {
                        let cell = g.cell_index(nx, ny);
                        if cell == runs[count - 1].1 + 1 {
                            runs[count - 1].1 = cell;
                        } else {
                            runs[count] = (cell, cell);
                            count += 1;
                        }
                    }
                }
                let ranges = runs[..count].iter().map(|&(first, last)| {
                    self.cell_start[first] as usize..self.cell_start[last + 1] as usize
                });
                let mut ranges_buf = [0..0, 0..0, 0..0, 0..0, 0..0];
                for (slot, range) in ranges_buf.iter_mut().zip(ranges) {
                    *slot = range;
                }
                let first_end = ranges_buf[0].end;
                for a in own.clone() {
                    // The own cell's later discs (and what follows it in memory), then the rest.
                    self.test(a, a + 1..first_end, out, &mut max_overlap);
                    for range in &ranges_buf[1..count] {
                        self.test(a, range.clone(), out, &mut max_overlap);
                    }
                    // Finer levels: every cell under this disc's reach.
                    for fine in finer {
                        self.scan_finer(a, fine, out, &mut max_overlap);
                    }
                }
            }
        }
        max_overlap
    }

    /// Tests disc `a` against the discs of a finer level's grid within its reach.
    fn scan_finer(&self, a: usize, fine: &LevelGrid, out: &mut Vec<Pair>, max_overlap: &mut f64) {
        let p = self.p;
        let reach = (p.radius[a] + fine.max_radius) * self.scale;
        let pos = [p.x[a], p.y[a]];
        // The cells under the reach along one axis: a first cell and a count (wrapping in a
        // periodic grid).
        let span = |axis: usize| -> (isize, usize) {
            let lo = floor_to_isize((pos[axis] - reach - fine.origin[axis]) * fine.inv_cell[axis]);
            let hi = floor_to_isize((pos[axis] + reach - fine.origin[axis]) * fine.inv_cell[axis]);
            let n = fine.n[axis] as isize;
            // Far beyond any grid (cells per axis are capped at 10^6), and fits 32-bit isize.
            let (lo, hi) = (lo.max(-(1 << 28)), hi.min(1 << 28));
            if fine.wrap {
                if hi - lo + 1 >= n {
                    (0, n as usize)
                } else {
                    (lo.rem_euclid(n), (hi - lo + 1) as usize)
                }
            } else {
                // Clamped like `coord`, so outliers in edge cells are still met.
                let (lo, hi) = (lo.clamp(0, n - 1), hi.clamp(0, n - 1));
                (lo, (hi - lo + 1) as usize)
            }
        };
        let (x_first, x_count) = span(0);
        let (y_first, y_count) = span(1);
        let (nx, ny) = (fine.n[0] as isize, fine.n[1] as isize);
        for k in 0..y_count as isize {
            let cy = ((y_first + k) % ny) as usize;
            // The row's cells are contiguous in memory: one range, or two where it wraps.
            let end = x_first + x_count as isize;
            let first_run = (x_first as usize, (end.min(nx) - 1) as usize);
            let runs = [first_run, (0, (end - nx - 1).max(-1) as usize)];
            let wrapped = end > nx;
            for &(c0, c1) in &runs[..if wrapped { 2 } else { 1 }] {
                let range = self.cell_start[fine.cell_index(c0, cy)] as usize
                    ..self.cell_start[fine.cell_index(c1, cy) + 1] as usize;
                self.test(a, range, out, max_overlap);
            }
        }
    }
}

/// Every pair within the collision distance by testing all N(N-1)/2 pairs: the oracle the
/// grid is tested against. Returns sorted id pairs.
pub fn brute_force_pairs(p: &Particles, config: &Config) -> Vec<(ParticleId, ParticleId)> {
    let periodicity = Periodicity::of(config);
    let mut out = Vec::new();
    for a in 0..p.len() {
        for b in a + 1..p.len() {
            let diff = periodicity.diff(p.x[a], p.y[a], p.x[b], p.y[b]);
            if crate::collision::is_colliding(
                diff,
                p.radius[a],
                p.radius[b],
                config.collision_radius_scale,
            ) {
                out.push(ordered(p.id[a], p.id[b]));
            }
        }
    }
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn periodic_grids_never_have_two_cells_on_an_axis() {
        assert_eq!(cells_along(10.0, 4.0, true), 1);
        assert_eq!(cells_along(10.0, 4.0, false), 2);
        assert_eq!(cells_along(10.0, 3.0, true), 3);
        assert_eq!(cells_along(0.0, 3.0, false), 1);
    }

    #[test]
    fn blocks_are_even_in_number_and_at_least_two_cells_wide() {
        for n in 1..200 {
            for side in [1, 2, 3, 7, 50] {
                let s = block_splits(n, side);
                let nb = s.len() - 1;
                assert!(
                    nb == 1 || nb.is_multiple_of(2),
                    "n {n} side {side}: {nb} blocks"
                );
                assert!(s.windows(2).all(|w| nb == 1 || w[1] - w[0] >= 2));
                assert_eq!((s[0], s[nb]), (0, n));
            }
        }
    }

    #[test]
    fn minimum_image_picks_the_nearest_copy() {
        let p = Periodicity(Some([10.0, 10.0]));
        assert_eq!(p.diff(9.5, 0.5, 0.5, 9.5), [-1.0, 1.0]);
        assert_eq!(p.diff(3.0, 3.0, 1.0, 1.0), [2.0, 2.0]);
        // Pushed slightly outside the box.
        assert_eq!(p.diff(10.25, 5.0, 0.25, 5.0), [0.0, 0.0]);
    }
}
