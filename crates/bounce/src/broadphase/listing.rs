//! Candidate listing: every pair within its collision distance plus a margin (the skin),
//! found through the grids of the last binning.
//!
//! Each candidate pair is listed once, by one cell: the cell of the finer disc, or for discs
//! of one level, the cell visited first by the forward half-stencil. A disc meets discs of its
//! own level through the 3×3 stencil, and discs of each coarser level through the at most
//! 3×3 cells of that grid under its reach (coarser cells are at least that reach). Blocks of
//! whole cell rows list in parallel, each into its own lists, in storage order.
//!
//! Each block's pairs go into two bands by how far they were from colliding (see `Bands`):
//! a pair of the far band was more than half the margin beyond its collision distance, so
//! until the discs have moved that far it cannot collide, and detection skips the band.

use std::ops::Range;

use super::Bands;
use super::levels::{LevelGrid, floor_to_isize, wrap_index};
use super::sort::Block;
use crate::context::StepContext;
use crate::geometry::MinImage;
use crate::law::Law;

/// Lists, per block, every pair within its collision distance plus `margin`, for discs at
/// `x`, `y` of radii `radius`, in the cell order of the binning that made `grids`,
/// `cell_start` and `blocks`.
#[allow(clippy::too_many_arguments)]
pub(super) fn list_candidates(
    grids: &[LevelGrid],
    cell_start: &[u32],
    blocks: &[Block],
    [x, y, radius]: [&[f64]; 3],
    ctx: &StepContext,
    margin: f64,
    candidates: &mut [Bands],
) {
    let min_image = ctx.geometry.min_image();
    let search = Context {
        x,
        y,
        radius,
        levels: grids,
        cell_start,
        law: ctx.law,
        margin,
        min_image,
        slide: ctx.geometry.slide().map(|slide| slide.offset),
    };
    ctx.exec.for_each_mut(x.len(), candidates, |b, bands| {
        for pairs in bands.iter_mut() {
            pairs.clear();
        }
        let pairwise = grids[blocks[b].level].pairwise;
        match (min_image.is_periodic(), pairwise) {
            (true, false) => search.block_pairs::<true, false>(&blocks[b], bands),
            (false, false) => search.block_pairs::<false, false>(&blocks[b], bands),
            (true, true) => search.block_pairs::<true, true>(&blocks[b], bands),
            (false, true) => search.block_pairs::<false, true>(&blocks[b], bands),
        }
        for pairs in bands.iter_mut() {
            // A list kept from a larger block of an earlier grid gives back its excess.
            if pairs.capacity() > 2 * pairs.len() + 1024 {
                pairs.shrink_to(pairs.len() + pairs.len() / 4);
            }
        }
    });
}

/// Makes room in both bands for `n` more pairs.
#[inline(always)]
fn reserve(out: &mut Bands, n: usize) {
    for pairs in out.iter_mut() {
        if pairs.capacity() - pairs.len() < n {
            // Grow by a quarter, not double: the lists are a large part of the memory.
            pairs.reserve_exact(n.max(pairs.capacity() / 4));
        }
    }
}

/// The bits of the pair `[a, b]` as one `u64`, as they lie in memory.
#[inline(always)]
fn packed(a: u32, b: u32) -> u64 {
    u64::from_ne_bytes(bytemuck::cast([a, b]))
}

/// The squared distances that sort a run's pairs into bands: the end of the near band, and
/// the cut (the end of the far one).
#[derive(Clone, Copy)]
struct Cuts {
    near2: f64,
    cut2: f64,
}

/// Whether the cell's forward half-stencil is the full one with no edge in between:
/// `(cx + 1, cy)` and `(cx - 1..=cx + 1, cy + 1)`, all inside the grid.
#[inline]
fn interior(g: &LevelGrid, cx: usize, cy: usize) -> bool {
    g.forward.len() == 4 && cx >= 1 && cx + 1 < g.n[0] && cy + 1 < g.n[1]
}

/// Read-only view the candidate search of one block needs. Its methods' `PERIODIC` picks
/// the minimum image at compile time, and `PAIRWISE` whether each pair is cut at its own
/// collision distance (in a merged level, whose radii differ by more than a factor 2) or
/// all at the run's `Cuts`.
pub(super) struct Context<'a> {
    x: &'a [f64],
    y: &'a [f64],
    radius: &'a [f64],
    levels: &'a [LevelGrid],
    cell_start: &'a [u32],
    law: Law,
    /// Added to each pair's collision distance: the skin.
    margin: f64,
    min_image: MinImage,
    /// The offset of the images above, in a Lees–Edwards box: the row across the top
    /// holds a disc's partners that much further left.
    slide: Option<f64>,
}

impl Context<'_> {
    #[inline]
    fn cell_range(&self, cell: usize) -> Range<usize> {
        self.cell_start[cell] as usize..self.cell_start[cell + 1] as usize
    }

    /// The squared distances that bound the bands of pairs whose collision distance is at
    /// most `reach` (the run's largest): the near band ends half the margin beyond it, the
    /// far one at the whole margin.
    #[inline]
    fn cuts(&self, reach: f64) -> Cuts {
        let near = reach + 0.5 * self.margin;
        let cut = reach + self.margin;
        Cuts {
            near2: near * near,
            cut2: cut * cut,
        }
    }

    /// Lists `a` with each disc of `others` within the cut of `cuts` (at least the collision
    /// distance plus the margin of every pair tested, so each list is a superset and one
    /// constant serves a whole run), each pair in its band.
    #[inline(always)]
    fn list_near<const PERIODIC: bool, const PAIRWISE: bool>(
        &self,
        a: usize,
        others: Range<usize>,
        cuts: &Cuts,
        out: &mut Bands,
    ) {
        reserve(out, others.len());
        let none = others.end..others.end;
        // SAFETY: room reserved just now.
        unsafe { self.list_near_in_room::<PERIODIC, PAIRWISE>(a, [others, none], cuts, out) };
    }

    /// [`Context::list_near`] over two runs (the second often empty) in one loop, where each band
    /// already has room for both: in a gas the runs are a disc or two each, of random
    /// lengths, so each loop's end is a mispredicted branch, and one loop has one end.
    ///
    /// # Safety
    /// Each band's spare capacity is at least the two runs' length together.
    #[inline(always)]
    unsafe fn list_near_in_room<const PERIODIC: bool, const PAIRWISE: bool>(
        &self,
        a: usize,
        [first, second]: [Range<usize>; 2],
        cuts: &Cuts,
        out: &mut Bands,
    ) {
        let (xa, ya, ra) = (self.x[a], self.y[a], self.radius[a]);
        let n1 = first.len();
        let total = n1 + second.len();
        // Checked once here, so the loop reads without bounds checks.
        let len = self.x.len().min(self.y.len()).min(self.radius.len());
        assert!(first.end <= len && second.end <= len);
        // About one test in four is a candidate, so a branch on it would mispredict often:
        // every pair is written to its band's spare capacity and that band's length only
        // advances on a hit.
        let [near, far] = out;
        debug_assert!(near.capacity() - near.len() >= total);
        debug_assert!(far.capacity() - far.len() >= total);
        let (mut near_len, mut far_len) = (near.len(), far.len());
        let (near_spare, far_spare) = (near.as_mut_ptr(), far.as_mut_ptr());
        // Index `k` of the joined runs is disc `k + offset`, the offset chosen without a
        // branch. The second's is its start less the first run's length, in wrapping
        // arithmetic: below zero, it comes back with `k >= n1`.
        let offsets = [first.start, second.start.wrapping_sub(n1)];
        for k in 0..total {
            let b = k.wrapping_add(offsets[(k >= n1) as usize]);
            // SAFETY: `b` is in one of the runs, within the discs (asserted above).
            let (xb, yb) = unsafe { (*self.x.get_unchecked(b), *self.y.get_unchecked(b)) };
            let [dx, dy] = if PERIODIC {
                self.min_image.diff(xa, ya, xb, yb)
            } else {
                [xa - xb, ya - yb]
            };
            let d2 = dx * dx + dy * dy;
            let Cuts { near2, cut2 } = if PAIRWISE {
                // SAFETY: as above.
                let rb = unsafe { *self.radius.get_unchecked(b) };
                self.cuts(self.law.collision_distance(ra, rb))
            } else {
                *cuts
            };
            // One 64-bit store per band instead of two 32-bit ones: the loop is bound by its
            // stores.
            let pair = packed(a as u32, b as u32);
            // SAFETY: each band has room for `total` more pairs (the caller's promise) and
            // advances by at most one per iteration; a `Pair` is 8 bytes, aligned to 4.
            unsafe {
                near_spare.add(near_len).cast::<u64>().write_unaligned(pair);
                far_spare.add(far_len).cast::<u64>().write_unaligned(pair);
            }
            // Near pairs are within the cut too (`near2 <= cut2`): the far band takes those
            // within the cut less those near, with no third comparison. (NaN is in neither.)
            let near = (d2 <= near2) as usize;
            near_len += near;
            far_len += (d2 <= cut2) as usize - near;
        }
        // SAFETY: the pairs up to these lengths were written above (or before).
        unsafe {
            near.set_len(near_len);
            far.set_len(far_len);
        }
    }

    /// All candidates listed by the cells of `block`.
    fn block_pairs<const PERIODIC: bool, const PAIRWISE: bool>(
        &self,
        block: &Block,
        out: &mut Bands,
    ) {
        let g = &self.levels[block.level];
        // Pairs across levels are listed by the finer disc: a coarser grid's cells are at
        // least the reach, so it scans at most 3×3 of them.
        let coarser = &self.levels[block.level + 1..];
        // Discs of one level are at most its largest radius.
        let own_cuts = self.cuts(self.law.interaction_diameter(g.max_radius));
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
                    // Room for every pair of the cell's discs with the two runs, at once.
                    let per_disc = first_end - own.start + upper.len();
                    for a in own.clone() {
                        reserve(out, per_disc);
                        // SAFETY: room for `per_disc` pairs, at least what the two runs hold.
                        unsafe {
                            self.list_near_in_room::<PERIODIC, PAIRWISE>(
                                a,
                                [a + 1..first_end, upper.clone()],
                                &own_cuts,
                                out,
                            );
                        }
                        for level in coarser {
                            self.scan_level::<PERIODIC>(a, level, out);
                        }
                    }
                    continue;
                }
                // The own cell and the forward half-stencil, in stencil order, with cells that
                // follow each other in memory merged into one run: (cx, cy) and (cx + 1, cy)
                // are one run, and so is the row above. Fewer, longer loops.
                // In a Lees–Edwards box the row across the top slides: its cells come from
                // `seam_cells`, not the stencil.
                let seam = self.slide.filter(|_| cy + 1 == g.n[1] && g.n[1] > 1);
                let mut runs = [(own_cell, own_cell); 5];
                let mut count = 1;
                let mut add = |cell: usize| {
                    if cell == runs[count - 1].1 + 1 {
                        runs[count - 1].1 = cell;
                    } else {
                        runs[count] = (cell, cell);
                        count += 1;
                    }
                };
                for &[dx, dy] in &g.forward {
                    if let (Some(nx), Some(ny)) = (
                        g.neighbour(cx as isize + dx, 0),
                        g.neighbour(cy as isize + dy, 1),
                    ) && (seam.is_none() || dy == 0)
                    {
                        add(g.cell_index(nx, ny));
                    }
                }
                if let Some(offset) = seam {
                    for column in seam_cells(g, cx, offset) {
                        add(g.cell_index(column, 0));
                    }
                }
                let mut ranges = [0..0, 0..0, 0..0, 0..0, 0..0];
                for (slot, &(first, last)) in ranges.iter_mut().zip(&runs[..count]) {
                    *slot = self.cell_start[first] as usize..self.cell_start[last + 1] as usize;
                }
                let first_end = ranges[0].end;
                for a in own.clone() {
                    // The own cell's later discs (and what follows it in memory), then the rest.
                    self.list_near::<PERIODIC, PAIRWISE>(a, a + 1..first_end, &own_cuts, out);
                    for range in &ranges[1..count] {
                        self.list_near::<PERIODIC, PAIRWISE>(a, range.clone(), &own_cuts, out);
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
    fn scan_level<const PERIODIC: bool>(&self, a: usize, grid: &LevelGrid, out: &mut Bands) {
        let cuts = self.cuts(self.law.collision_distance(self.radius[a], grid.max_radius));
        let reach = self.law.collision_distance(self.radius[a], grid.max_radius) + self.margin;
        let pos = [self.x[a], self.y[a]];
        // The cells under the reach along one axis: a first cell and a count (wrapping in a
        // periodic grid).
        let span = |axis: usize, v: f64| -> (isize, usize) {
            let lo = floor_to_isize((v - reach - grid.origin[axis]) * grid.inv_cell[axis]);
            let hi = floor_to_isize((v + reach - grid.origin[axis]) * grid.inv_cell[axis]);
            let n = grid.n[axis] as isize;
            // Far beyond any grid (cells per axis are capped at 10^6), and fits 32-bit isize.
            let (lo, hi) = (lo.max(-(1 << 28)), hi.min(1 << 28));
            if grid.wrap {
                if hi - lo + 1 >= n {
                    (0, n as usize)
                } else {
                    (wrap_index(lo, n), (hi - lo + 1) as usize)
                }
            } else {
                // Clamped like `coord`, so outliers in edge cells are still met.
                let (lo, hi) = (lo.clamp(0, n - 1), hi.clamp(0, n - 1));
                (lo, (hi - lo + 1) as usize)
            }
        };
        let (x_first, x_count) = span(0, pos[0]);
        let (y_first, y_count) = span(1, pos[1]);
        // The first row before wrapping (for the rows across a Lees–Edwards box's edges).
        let y_lowest = floor_to_isize((pos[1] - reach - grid.origin[1]) * grid.inv_cell[1]);
        let (nx, ny) = (grid.n[0] as isize, grid.n[1] as isize);
        for k in 0..y_count as isize {
            // Below two periods: one subtraction, not a division.
            let cy = wrap_index(y_first + k, ny) as usize;
            // In a Lees–Edwards box a row across the top holds the partners of a disc at
            // `x` near `x - offset`, one across the bottom near `x + offset` (`y_first` is
            // wrapped: which side a row is on goes by the unwrapped one).
            let (x_first, x_count) = match self.slide {
                None => (x_first, x_count),
                Some(_) if y_count as isize >= ny => (0, nx as usize),
                Some(offset) => match y_lowest + k {
                    row if row >= ny => span(0, pos[0] - offset),
                    row if row < 0 => span(0, pos[0] + offset),
                    _ => (x_first, x_count),
                },
            };
            // The row's cells are contiguous in memory: one range, or two where it wraps.
            let end = x_first + x_count as isize;
            let first_run = (x_first as usize, (end.min(nx) - 1) as usize);
            let runs = [first_run, (0, (end - nx - 1).max(-1) as usize)];
            let wrapped = end > nx;
            for &(c0, c1) in &runs[..if wrapped { 2 } else { 1 }] {
                let range = self.cell_start[grid.cell_index(c0, cy)] as usize
                    ..self.cell_start[grid.cell_index(c1, cy) + 1] as usize;
                self.list_near::<PERIODIC, false>(a, range, &cuts, out);
            }
        }
    }
}

/// The columns of the bottom row that hold the partners, across the top of a Lees–Edwards
/// box whose images above stand `offset` along x, of the discs in column `cx` of the top
/// row: each partner is within a cell (at least its reach) of a point `offset` left of the
/// disc, so four columns from one and a bit left of the cell, wrapped (the whole row when it
/// has at most four).
fn seam_cells(g: &LevelGrid, cx: usize, offset: f64) -> impl Iterator<Item = usize> {
    let n = g.n[0] as isize;
    let first = floor_to_isize(cx as f64 - 1.0 - offset * g.inv_cell[0]);
    let (first, count) = if n <= 4 { (0, n) } else { (first, 4) };
    (first..first + count).map(move |c| wrap_index(c, n) as usize)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::broadphase::Pair;

    #[test]
    fn a_packed_pair_is_the_pair_in_memory() {
        // The listing writes each pair as one u64: read back as a `Pair`, it is `[a, b]`.
        let mut out: Vec<Pair> = Vec::with_capacity(2);
        for (k, pair) in [[3u32, 0x8000_0001], [u32::MAX, 0]].into_iter().enumerate() {
            // SAFETY: room for two pairs; a `Pair` is 8 bytes.
            unsafe {
                let slot = out.as_mut_ptr().add(k);
                slot.cast::<u64>().write_unaligned(packed(pair[0], pair[1]));
            }
        }
        // SAFETY: both written above.
        unsafe { out.set_len(2) };
        assert_eq!(out, vec![[3, 0x8000_0001], [u32::MAX, 0]]);
    }
}
