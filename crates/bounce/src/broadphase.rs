//! Broadphase: which pairs may collide, found in O(N) and kept for several steps.
//!
//! # Candidates with a skin
//! A rebuild lists every pair whose distance is within its collision distance plus a *skin*,
//! and records where each disc was (the *reference* positions). As long as no disc has moved
//! more than half the skin from its reference, every pair that can collide is still on the
//! list (two discs closed in by at most one skin together), so a step only tests the listed
//! candidates; the step's integration pass measures the largest displacement and a rebuild
//! follows when it reaches the allowance. What collides, and in which order it is resolved,
//! is decided afterwards from the current state alone (see `contacts`), so when the list is
//! rebuilt changes nothing but speed.
//!
//! # Grids
//! Discs are binned into uniform grids (cell lists) with no fixed cell capacity: a stable
//! counting sort by cell index reorders the particle arrays so each cell is a contiguous run,
//! and neighbour search walks memory in order. The cell side is at least the largest
//! interaction diameter `2 r collision_radius_scale` plus the skin, so every candidate lies in
//! the 3×3 cells around a disc.
//!
//! # Polydisperse radii: a hierarchy of grids
//! One grid sized for the largest disc would put thousands of small discs in a cell when radii
//! span 0.1 to 5. Instead each disc gets a *level* by its interaction diameter `d`:
//! level `k` holds `d_min 2^k < d <= d_min 2^(k+1)` (level 0 includes `d_min`), and each
//! non-empty level has its own grid sized for its largest disc. A disc meets discs of its own
//! level through the 3×3 stencil, and discs of each coarser level through the at most 3×3
//! cells of that grid under its reach (coarser cells are at least that reach). Cost stays
//! proportional to the number of discs, whatever the mix.
//!
//! # Ownership and blocks
//! Each candidate pair is listed once, by one cell: the cell of the finer disc, or for discs
//! of one level, the cell visited first by the forward half-stencil. Cells are grouped into
//! blocks of whole rows, about a thousand discs each: the units of parallel work, each one
//! run of storage, so candidates are listed and later tested in storage order.
//!
//! # Open worlds
//! Cell coordinates are clamped to the grid (wrapped, in a periodic box). Clamping never
//! increases the distance between two cell coordinates, so partners stay within one cell of
//! each other and the stencil argument holds. An open world's grid covers the bulk of its
//! discs (around the median position, capped at about one cell per disc); discs far away pile
//! into edge cells, which costs time but never misses a pair.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use crate::config::{Boundary, Config};
use crate::parallel::{CHUNK, Executor};
use crate::particles::{ParticleId, Particles, PermuteScratch};

/// At most this many grid levels (interaction diameters spanning a factor 2^16).
const MAX_LEVELS: usize = 16;
/// Blocks aim to hold about this many discs: enough work per task, enough tasks.
const DISCS_PER_BLOCK: f64 = 1024.0;
/// The skin is at least this fraction of the interaction diameter of the finest level's
/// largest disc. A wider skin lists more candidates and rebuilds less often.
const SKIN_FRACTION: f64 = 0.75;
/// And wide enough for the fastest disc to take this many substeps to use up the allowance.
const MIN_SUBSTEPS_PER_REBUILD: f64 = 4.0;
/// A rebuild follows once some disc has moved this fraction of the skin (a little under one
/// half, so rounding in the distance tests can never matter).
const ALLOWANCE_FRACTION: f64 = 0.49;

/// A pair of storage indices.
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

/// Cell rows of one level whose candidates are listed together.
#[derive(Clone, Debug)]
struct Block {
    level: usize,
    x: Range<usize>,
    y: Range<usize>,
}

/// How `bin` sizes the skin.
#[derive(Clone, Copy, Debug)]
enum Skin {
    /// The larger of the size rule and `stride` (the fastest disc's distance per substep)
    /// times the substeps wanted between rebuilds.
    Stride(f64),
    /// This skin.
    Fixed(f64),
}

/// Where the discs were when the candidates were listed, and how far they may move before
/// the list must be rebuilt. Part of a saved world: the rebuild schedule decides the storage
/// order, and with it the last bits of sums such as the kinetic energy.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct Reference {
    /// Candidates are listed up to the collision distance plus this.
    skin: f64,
    /// A bound on the rounding of the stored positions (they are `f32`, to save memory).
    slack: f64,
    /// Reference positions in storage order; empty when there are none.
    x: Vec<f32>,
    y: Vec<f32>,
}

impl Reference {
    /// The reference positions, when they match `count` discs.
    pub(crate) fn positions(&self, count: usize) -> Option<(&[f32], &[f32])> {
        (count > 0 && self.x.len() == count).then_some((&self.x, &self.y))
    }

    /// Whether candidates listed at the reference positions still hold every pair that can
    /// collide, given the largest squared displacement of any disc since.
    pub(crate) fn covers(&self, max_displacement2: f64) -> bool {
        let allowance = ALLOWANCE_FRACTION * self.skin - self.slack;
        allowance > 0.0 && max_displacement2 < allowance * allowance
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
        if !(finite
            && self.skin.is_finite()
            && self.skin >= 0.0
            && self.slack.is_finite()
            && self.slack >= 0.0)
        {
            return Err("reference positions, skin or slack are not finite and >= 0".into());
        }
        Ok(())
    }
}

/// The grids, the blocks and the candidate pairs of the last rebuild.
#[derive(Debug, Default)]
pub(crate) struct Broadphase {
    levels: Vec<LevelGrid>,
    /// Global cell `c` holds storage indices `cell_start[c]..cell_start[c + 1]`.
    cell_start: Vec<u32>,
    blocks: Vec<Block>,
    /// Candidate pairs listed by each block.
    pub(crate) candidates: Vec<Vec<Pair>>,
    pub(crate) reference: Reference,
    /// Whether `candidates` were listed for `reference` (not so after loading a world).
    listed: bool,
    /// The number of discs at the last listing.
    count: usize,
    /// The largest radius at the last rebuild.
    max_radius: f64,
    /// Whether every disc had the same radius at the last rebuild.
    uniform_radius: bool,
    // Scratch reused between rebuilds (the cell keys live in `scratch`).
    order: Vec<u32>,
    /// Per-disc level; empty when all discs share level 0.
    level_of: Vec<u8>,
    f64_scratch: Vec<f64>,
    scratch: PermuteScratch,
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

    /// Whether positions wrap.
    pub(crate) fn is_periodic(&self) -> bool {
        self.0.is_some()
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

impl Broadphase {
    /// The largest radius at the last rebuild: what the contact order's grid is sized for.
    pub(crate) fn max_radius(&self) -> f64 {
        self.max_radius
    }

    /// The radius of every disc, when all are equal (as at the last listing).
    pub(crate) fn uniform_radius(&self) -> Option<f64> {
        (self.listed && self.uniform_radius).then_some(self.max_radius)
    }

    /// How many discs the candidates were listed for, if they are listed.
    pub(crate) fn listed_count(&self) -> Option<usize> {
        self.listed.then_some(self.count)
    }

    /// A bound on every radius: the largest at the last listing while the list stands (no
    /// disc added since), else infinite.
    pub(crate) fn radius_bound(&self) -> f64 {
        if self.listed {
            self.max_radius
        } else {
            f64::INFINITY
        }
    }

    /// Forgets the candidates and the reference: the next [`Broadphase::update`] rebuilds.
    /// Called whenever discs or the configuration change outside the step.
    pub(crate) fn invalidate(&mut self) {
        self.reference = Reference::default();
        self.listed = false;
        self.max_radius = f64::INFINITY;
    }

    /// Makes the candidates cover the current positions, given the largest squared
    /// displacement since the reference (infinite when unknown) and the longest distance a
    /// disc moved in the last substep (to size the skin). Returns whether the storage order
    /// changed.
    pub(crate) fn update(
        &mut self,
        p: &mut Particles,
        config: &Config,
        exec: &Executor,
        max_displacement2: f64,
        stride: f64,
    ) -> bool {
        if self.reference.positions(p.len()).is_some() && self.reference.covers(max_displacement2) {
            if !self.listed {
                // A loaded world: list candidates for its reference positions, keeping the
                // storage order it was saved in.
                self.list_at_reference(p, config, exec);
            }
            false
        } else {
            self.rebuild(p, config, exec, stride);
            true
        }
    }

    /// The largest squared displacement of any disc from its reference position (infinite
    /// when there is no reference).
    pub(crate) fn max_displacement2(&self, p: &Particles, config: &Config) -> f64 {
        let Some((rx, ry)) = self.reference.positions(p.len()) else {
            return f64::INFINITY;
        };
        let periodicity = Periodicity::of(config);
        (0..p.len()).fold(0.0, |max, i| {
            let [dx, dy] = periodicity.diff(p.x[i], p.y[i], rx[i] as f64, ry[i] as f64);
            f64::max(max, dx * dx + dy * dy)
        })
    }

    /// Bins the discs, reorders the particle arrays into cell order, lists the candidates and
    /// takes the current positions as the new reference. `stride` is how far the fastest
    /// disc moves per substep.
    pub(crate) fn rebuild(
        &mut self,
        p: &mut Particles,
        config: &Config,
        exec: &Executor,
        stride: f64,
    ) {
        let count = p.len();
        let skin = self.bin(&p.x, &p.y, &p.radius, config, Skin::Stride(stride), exec);
        p.permute(&self.order, &mut self.scratch, exec);
        self.list_candidates(&p.x, &p.y, &p.radius, config, skin, exec);
        let largest = f64::max(
            to_f32(&p.x, &mut self.reference.x, exec),
            to_f32(&p.y, &mut self.reference.y, exec),
        );
        self.reference.skin = skin;
        // Rounding to f32 moves a coordinate by at most half an f32 epsilon of it; the slack
        // covers two discs.
        self.reference.slack = largest * f32::EPSILON as f64;
        if count == 0 || !self.reference.covers(0.0) {
            // Coordinates so large that f32 cannot place them within the skin: no reference,
            // so every step rebuilds.
            self.reference = Reference::default();
        }
        self.listed = true;
        self.count = p.len();
    }

    /// Lists candidates for the stored reference positions without reordering storage: bins a
    /// sorted copy of the reference positions and maps the pairs back.
    fn list_at_reference(&mut self, p: &Particles, config: &Config, exec: &Executor) {
        let rx: Vec<f64> = self.reference.x.iter().map(|&v| v as f64).collect();
        let ry: Vec<f64> = self.reference.y.iter().map(|&v| v as f64).collect();
        // The stored positions are within `slack` of the true ones, twice over.
        let margin = self.reference.skin + 2.0 * self.reference.slack;
        self.bin(&rx, &ry, &p.radius, config, Skin::Fixed(margin), exec);
        let gather =
            |v: &[f64]| -> Vec<f64> { self.order.iter().map(|&i| v[i as usize]).collect() };
        let (sx, sy, sr) = (gather(&rx), gather(&ry), gather(&p.radius));
        self.list_candidates(&sx, &sy, &sr, config, margin, exec);
        let order = &self.order;
        for pairs in &mut self.candidates {
            for pair in pairs.iter_mut() {
                *pair = pair.map(|k| order[k as usize]);
            }
        }
        self.listed = true;
        self.count = p.len();
    }

    /// Levels, grids, the stable counting sort into `order` (new index `k` holds old index
    /// `order[k]`) and the blocks, for discs at `x`, `y`, with cells sized for `skin`.
    /// Returns the skin.
    fn bin(
        &mut self,
        x: &[f64],
        y: &[f64],
        radius: &[f64],
        config: &Config,
        skin: Skin,
        exec: &Executor,
    ) -> f64 {
        let count = radius.len();
        self.levels.clear();
        self.blocks.clear();
        self.order.clear();
        self.cell_start.clear();
        self.cell_start.push(0);
        self.max_radius = 0.0;
        if count == 0 {
            return 0.0;
        }
        let s = config.collision_radius_scale;

        // 1. Levels: a band of interaction diameters each. One band is the common case
        // (equal or similar discs): then no per-disc level is stored at all.
        let (r_min, r_max) = radius.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
            (lo.min(r), hi.max(r))
        });
        self.max_radius = r_max;
        self.uniform_radius = r_min == r_max;
        let d_min = 2.0 * r_min * s;
        let single_level = level_of(2.0 * r_max * s, d_min) == 0;
        let mut used = Vec::new();
        self.level_of.clear();
        if single_level {
            used.push((count, r_max));
        } else {
            self.level_of
                .extend(radius.iter().map(|&r| level_of(2.0 * r * s, d_min) as u8));
            let mut stats = [(0usize, 0.0f64); MAX_LEVELS];
            for (&l, &r) in self.level_of.iter().zip(radius) {
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
        let skin = match skin {
            Skin::Fixed(skin) => skin,
            Skin::Stride(stride) => {
                let by_motion = MIN_SUBSTEPS_PER_REBUILD * stride / ALLOWANCE_FRACTION;
                let skin = f64::max(SKIN_FRACTION * 2.0 * used[0].1 * s, by_motion);
                // Never wider than the largest interaction diameter: cells stay about
                // disc-sized.
                skin.min(2.0 * r_max * s)
            }
        };

        // 2. One grid per level.
        let mut cell_offset = 0;
        for (level, &(n_level, max_r)) in used.iter().enumerate() {
            let grid = self.level_grid([x, y], config, skin, level, n_level, max_r, cell_offset);
            cell_offset += grid.n[0] * grid.n[1];
            self.levels.push(grid);
        }
        let total_cells = cell_offset;

        // 3. Stable counting sort by global cell index. Storage is in cell order from the
        // last rebuild except for discs that changed cell, so this walks memory in order.
        let keys = self.scratch.u32s(count);
        {
            let (levels, level_of) = (&self.levels, &self.level_of);
            let mut chunks: Vec<(usize, &mut [u32])> = keys.chunks_mut(CHUNK).enumerate().collect();
            exec.for_each_mut(count, &mut chunks, |_, (c, keys)| {
                let base = *c * CHUNK;
                for (k, key) in keys.iter_mut().enumerate() {
                    let i = base + k;
                    let g = if level_of.is_empty() {
                        &levels[0]
                    } else {
                        &levels[level_of[i] as usize]
                    };
                    let (cx, cy) = (g.coord(x[i], 0), g.coord(y[i], 1));
                    *key = g.cell_index(cx, cy) as u32;
                }
            });
        }
        self.cell_start.resize(total_cells + 1, 0);
        for &k in keys.iter() {
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
            for (i, &k) in keys.iter().enumerate() {
                let slot = &mut next[k as usize];
                self.order[*slot as usize] = i as u32;
                *slot += 1;
            }
            next.copy_within(0..total_cells, 1);
            next[0] = 0;
        }

        // 4. Blocks: strips of whole cell rows, so a block's discs are one run of storage
        // and its candidates come out in storage order.
        for (level, g) in self.levels.iter().enumerate() {
            let per_row = used[level].0 as f64 / g.n[1] as f64;
            let rows = (DISCS_PER_BLOCK / per_row).ceil().max(1.0) as usize;
            for y0 in (0..g.n[1]).step_by(rows) {
                self.blocks.push(Block {
                    level,
                    x: 0..g.n[0],
                    y: y0..(y0 + rows).min(g.n[1]),
                });
            }
        }
        self.candidates.resize_with(self.blocks.len(), Vec::new);
        self.candidates.truncate(self.blocks.len());
        skin
    }

    /// The grid for one level.
    #[allow(clippy::too_many_arguments)]
    fn level_grid(
        &mut self,
        positions: [&[f64]; 2],
        config: &Config,
        skin: f64,
        level: usize,
        n_level: usize,
        max_radius: f64,
        cell_offset: usize,
    ) -> LevelGrid {
        let min_cell = 2.0 * max_radius * config.collision_radius_scale + skin;
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
                    let (lo, hi, median) = self.spread(positions[axis], level);
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

    /// Lists, per block, every pair within its collision distance plus `margin`, for discs
    /// at `x`, `y` already in the cell order of the last `bin`.
    fn list_candidates(
        &mut self,
        x: &[f64],
        y: &[f64],
        radius: &[f64],
        config: &Config,
        margin: f64,
        exec: &Executor,
    ) {
        let periodicity = Periodicity::of(config);
        let blocks = &self.blocks;
        let (levels, cell_start) = (&self.levels[..], &self.cell_start[..]);
        let scale = config.collision_radius_scale;
        let ctx = Context {
            x,
            y,
            radius,
            levels,
            cell_start,
            scale,
            margin,
            periodicity,
        };
        exec.for_each_mut(x.len(), &mut self.candidates, |b, pairs| {
            pairs.clear();
            if periodicity.is_periodic() {
                ctx.block_pairs::<true>(&blocks[b], pairs);
            } else {
                ctx.block_pairs::<false>(&blocks[b], pairs);
            }
            // A list kept from a larger block of an earlier grid gives back its excess.
            if pairs.capacity() > 2 * pairs.len() + 1024 {
                pairs.shrink_to(pairs.len() + pairs.len() / 4);
            }
        });
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
        let mut largest = 0.0f64;
        for (o, &v) in out.iter_mut().zip(v.iter()) {
            *o = v as f32;
            largest = largest.max(v.abs());
        }
        largest
    })
    .into_iter()
    .fold(0.0, f64::max)
}

/// Whether the cell's forward half-stencil is the full one with no edge in between:
/// `(cx + 1, cy)` and `(cx - 1..=cx + 1, cy + 1)`, all inside the grid.
#[inline]
fn interior(g: &LevelGrid, cx: usize, cy: usize) -> bool {
    g.forward.len() == 4 && cx >= 1 && cx + 1 < g.n[0] && cy + 1 < g.n[1]
}

/// Read-only view the candidate search of one block needs. Its methods' `PERIODIC` picks
/// the minimum image at compile time.
struct Context<'a> {
    x: &'a [f64],
    y: &'a [f64],
    radius: &'a [f64],
    levels: &'a [LevelGrid],
    cell_start: &'a [u32],
    scale: f64,
    /// Added to each pair's collision distance: the skin.
    margin: f64,
    periodicity: Periodicity,
}

impl Context<'_> {
    #[inline]
    fn cell_range(&self, cell: usize) -> Range<usize> {
        self.cell_start[cell] as usize..self.cell_start[cell + 1] as usize
    }

    /// Lists `a` with each disc of `others` within distance `sqrt(cut2)`: at least the
    /// collision distance plus the margin of every pair tested, so each list is a superset
    /// and one constant serves a whole run.
    #[inline(always)]
    fn test<const PERIODIC: bool>(
        &self,
        a: usize,
        others: Range<usize>,
        cut2: f64,
        out: &mut Vec<Pair>,
    ) {
        let (xa, ya) = (self.x[a], self.y[a]);
        let start = others.start;
        // Slices first: the loop then runs without bounds checks.
        let (xs, ys) = (&self.x[others.clone()], &self.y[others]);
        // About one test in four is a candidate, so a branch on it would mispredict often:
        // every pair is written to the spare capacity and the length only advances on a hit.
        if out.capacity() - out.len() < xs.len() {
            // Grow by a quarter, not double: the lists are a large part of the memory.
            out.reserve_exact(xs.len().max(out.capacity() / 4));
        }
        let mut len = out.len();
        let spare = out.spare_capacity_mut();
        let mut written = 0;
        for (k, (&xb, &yb)) in xs.iter().zip(ys).enumerate() {
            let [dx, dy] = if PERIODIC {
                self.periodicity.diff(xa, ya, xb, yb)
            } else {
                [xa - xb, ya - yb]
            };
            let hit = dx * dx + dy * dy <= cut2;
            // `written <= k < xs.len()`, within the reserved spare capacity.
            spare[written].write([a as u32, (start + k) as u32]);
            written += hit as usize;
        }
        len += written;
        // SAFETY: the first `written` spare slots were initialised above.
        unsafe { out.set_len(len) };
    }

    /// All candidates listed by the cells of `block`.
    fn block_pairs<const PERIODIC: bool>(&self, block: &Block, out: &mut Vec<Pair>) {
        let g = &self.levels[block.level];
        // Pairs across levels are listed by the finer disc: a coarser grid's cells are at
        // least the reach, so it scans at most 3×3 of them.
        let coarser = &self.levels[block.level + 1..];
        // Discs of one level are at most its largest radius.
        let own_cut = 2.0 * g.max_radius * self.scale + self.margin;
        let own_cut2 = own_cut * own_cut;
        for cy in block.y.clone() {
            for cx in block.x.clone() {
                let own_cell = g.cell_index(cx, cy);
                let own = self.cell_range(own_cell);
                if own.is_empty() {
                    continue;
                }
                if interior(g, cx, cy) {
                    // The common case, without the edge logic below: the own cell with the
                    // next, and the three cells of the row above, are each one run.
                    let above = own_cell + g.n[0];
                    let first_end = self.cell_start[own_cell + 2] as usize;
                    let upper =
                        self.cell_start[above - 1] as usize..self.cell_start[above + 2] as usize;
                    for a in own.clone() {
                        self.test::<PERIODIC>(a, a + 1..first_end, own_cut2, out);
                        self.test::<PERIODIC>(a, upper.clone(), own_cut2, out);
                        for level in coarser {
                            self.scan_level::<PERIODIC>(a, level, out);
                        }
                    }
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
                let mut ranges = [0..0, 0..0, 0..0, 0..0, 0..0];
                for (slot, &(first, last)) in ranges.iter_mut().zip(&runs[..count]) {
                    *slot = self.cell_start[first] as usize..self.cell_start[last + 1] as usize;
                }
                let first_end = ranges[0].end;
                for a in own.clone() {
                    // The own cell's later discs (and what follows it in memory), then the rest.
                    self.test::<PERIODIC>(a, a + 1..first_end, own_cut2, out);
                    for range in &ranges[1..count] {
                        self.test::<PERIODIC>(a, range.clone(), own_cut2, out);
                    }
                    // Coarser levels: every cell under this disc's reach.
                    for level in coarser {
                        self.scan_level::<PERIODIC>(a, level, out);
                    }
                }
            }
        }
    }

    /// Lists disc `a` with the discs of another level's grid within its reach.
    fn scan_level<const PERIODIC: bool>(&self, a: usize, grid: &LevelGrid, out: &mut Vec<Pair>) {
        let reach = (self.radius[a] + grid.max_radius) * self.scale + self.margin;
        let pos = [self.x[a], self.y[a]];
        // The cells under the reach along one axis: a first cell and a count (wrapping in a
        // periodic grid).
        let span = |axis: usize| -> (isize, usize) {
            let lo = floor_to_isize((pos[axis] - reach - grid.origin[axis]) * grid.inv_cell[axis]);
            let hi = floor_to_isize((pos[axis] + reach - grid.origin[axis]) * grid.inv_cell[axis]);
            let n = grid.n[axis] as isize;
            // Far beyond any grid (cells per axis are capped at 10^6), and fits 32-bit isize.
            let (lo, hi) = (lo.max(-(1 << 28)), hi.min(1 << 28));
            if grid.wrap {
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
        let (nx, ny) = (grid.n[0] as isize, grid.n[1] as isize);
        for k in 0..y_count as isize {
            let cy = ((y_first + k) % ny) as usize;
            // The row's cells are contiguous in memory: one range, or two where it wraps.
            let end = x_first + x_count as isize;
            let first_run = (x_first as usize, (end.min(nx) - 1) as usize);
            let runs = [first_run, (0, (end - nx - 1).max(-1) as usize)];
            let wrapped = end > nx;
            for &(c0, c1) in &runs[..if wrapped { 2 } else { 1 }] {
                let range = self.cell_start[grid.cell_index(c0, cy)] as usize
                    ..self.cell_start[grid.cell_index(c1, cy) + 1] as usize;
                self.test::<PERIODIC>(a, range, reach * reach, out);
            }
        }
    }
}

pub(crate) fn ordered(a: ParticleId, b: ParticleId) -> (ParticleId, ParticleId) {
    if a < b { (a, b) } else { (b, a) }
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
    fn a_reference_covers_less_than_half_the_skin() {
        let r = Reference {
            skin: 1.0,
            slack: 0.0,
            x: vec![0.0],
            y: vec![0.0],
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
    fn minimum_image_picks_the_nearest_copy() {
        let p = Periodicity(Some([10.0, 10.0]));
        assert_eq!(p.diff(9.5, 0.5, 0.5, 9.5), [-1.0, 1.0]);
        assert_eq!(p.diff(3.0, 3.0, 1.0, 1.0), [2.0, 2.0]);
        // Pushed slightly outside the box.
        assert_eq!(p.diff(10.25, 5.0, 0.25, 5.0), [0.0, 0.0]);
    }
}
