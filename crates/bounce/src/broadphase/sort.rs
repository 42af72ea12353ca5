//! Binning: a stable counting sort of the discs by grid cell, and the blocks of cell rows
//! whose candidates are listed together.
//!
//! The sort gives `order` (new index `k` holds old index `order[k]`) and `cell_start` (global
//! cell `c` holds new indices `cell_start[c]..cell_start[c + 1]`). There is no fixed cell
//! capacity: a cell holds however many discs fall in it. Storage is in cell order from the
//! last rebuild except for discs that changed cell, so the sweeps walk memory in order.
//!
//! That near order also lets several threads place the discs: each run of storage counts
//! and places its own discs, within the window of cells its keys span (about its own share
//! of the grid), and the result is the serial sort's (see [`place_in_windows`]).

use std::mem::MaybeUninit;
use std::ops::Range;

use super::levels::{Level, LevelGrid, clamp_cell};
use crate::parallel::{CHUNK, Executor, SharedSlice};

/// Blocks aim to hold about this many discs: enough work per task, enough tasks.
const DISCS_PER_BLOCK: f64 = 1024.0;

/// Cell rows of one level whose candidates are listed together.
#[derive(Clone, Debug)]
pub(super) struct Block {
    pub level: usize,
    pub x: Range<usize>,
    pub y: Range<usize>,
}

/// Sorts discs at `x`, `y` (of levels `level_of`, empty for one level) by global cell index
/// into `order` and `cell_start`; `keys` is scratch of at least `x.len()`, and what it has
/// beyond that (see [`scratch_for_counts`]) lets the discs be placed on several threads.
#[allow(clippy::too_many_arguments)]
pub(super) fn counting_sort(
    grids: &[LevelGrid],
    level_of: &[u8],
    x: &[f64],
    y: &[f64],
    keys: &mut [u32],
    cell_start: &mut Vec<u32>,
    order: &mut Vec<u32>,
    exec: &Executor,
) {
    let count = x.len();
    let total_cells = grids.last().map_or(0, |g| g.cell_offset + g.n[0] * g.n[1]);
    let (keys, counts) = keys.split_at_mut(count);
    let windows;
    {
        let mut chunks: Vec<(usize, &mut [u32])> = keys.chunks_mut(CHUNK).enumerate().collect();
        // Each chunk's window of cells, while its keys are in cache (only where the
        // placement can use them: with room for the counts).
        let want_windows = !counts.is_empty();
        windows = exec.map_mut(count, &mut chunks, |_, (c, keys)| {
            let base = *c * CHUNK;
            let (x, y) = (&x[base..base + keys.len()], &y[base..base + keys.len()]);
            if level_of.is_empty() && !grids[0].wrap {
                // One walled or open grid, the common case: `LevelGrid::coord`'s clamp with
                // its constants in registers and 32-bit cells (the grid has fewer than 2^32),
                // a loop the compiler can run two discs at a time.
                let g = &grids[0];
                let [ox, oy] = g.origin;
                let [ix, iy] = g.inv_cell;
                let (top_x, top_y) = ((g.n[0] - 1) as f64, (g.n[1] - 1) as f64);
                let (nx, offset) = (g.n[0] as u32, g.cell_offset as u32);
                for ((key, &x), &y) in keys.iter_mut().zip(x).zip(y) {
                    let cx = clamp_cell((x - ox) * ix, top_x) as u32;
                    let cy = clamp_cell((y - oy) * iy, top_y) as u32;
                    *key = offset + cy * nx + cx;
                }
            } else if level_of.is_empty() {
                let g = &grids[0];
                for ((key, &x), &y) in keys.iter_mut().zip(x).zip(y) {
                    *key = g.cell_index(g.coord(x, 0), g.coord(y, 1)) as u32;
                }
            } else {
                let level_of = &level_of[base..base + keys.len()];
                for (((key, &x), &y), &level) in keys.iter_mut().zip(x).zip(y).zip(level_of) {
                    let g = &grids[level as usize];
                    *key = g.cell_index(g.coord(x, 0), g.coord(y, 1)) as u32;
                }
            }
            if want_windows { window_of(keys) } else { 0..0 }
        });
    }
    if !place_in_windows(keys, &windows, counts, total_cells, cell_start, order, exec) {
        place(keys, total_cells, cell_start, order);
    }
}

/// How many `u32`s of scratch beyond the keys [`counting_sort`] can use for `total_cells`
/// cells on `exec` (none when it places on one thread).
pub(super) fn scratch_for_counts(count: usize, total_cells: usize, exec: &Executor) -> usize {
    // A pool has at least two threads.
    if exec.is_parallel(count) {
        total_cells + total_cells / MAX_WINDOW_EXCESS + exec.threads()
    } else {
        0
    }
}

/// The parts' cell windows together may be this fraction (one over it) more than all the
/// cells; beyond that the keys are far from sorted and one thread places them.
const MAX_WINDOW_EXCESS: usize = 4;

/// The cells `keys` fall in: the smallest key to one past the largest (empty for no keys).
fn window_of(keys: &[u32]) -> Range<usize> {
    let (lo, hi) = keys
        .iter()
        .fold((u32::MAX, 0), |(lo, hi), &k| (lo.min(k), hi.max(k)));
    if keys.is_empty() {
        0..0
    } else {
        lo as usize..hi as usize + 1
    }
}

/// The serial stable counting sort of `keys` into `cell_start` and `order`.
fn place(keys: &[u32], total_cells: usize, cell_start: &mut Vec<u32>, order: &mut Vec<u32>) {
    let count = keys.len();
    cell_start.clear();
    cell_start.resize(total_cells + 1, 0);
    for &k in keys.iter() {
        cell_start[k as usize + 1] += 1;
    }
    // The running sum in a register: a sum through memory waits on each store.
    let mut sum = 0;
    for start in cell_start.iter_mut() {
        sum += *start;
        *start = sum;
    }
    order.clear();
    order.resize(count, 0);
    // Place each disc at its cell's next free slot; afterwards slot `c` holds the end of cell
    // `c`, and one shift restores the starts.
    for (i, &k) in keys.iter().enumerate() {
        let slot = &mut cell_start[k as usize];
        order[*slot as usize] = i as u32;
        *slot += 1;
    }
    cell_start.copy_within(0..total_cells, 1);
    cell_start[0] = 0;
}

/// [`place`] in parallel, over as many runs of storage as there are threads, each of whole
/// chunks of [`CHUNK`] discs, whose windows of cells (see [`window_of`]) the key loop found:
/// `chunk_windows`. Storage is in the cell order of the last rebuild but for the discs that
/// changed cell since, so each run's keys fall in a window of cells about its own share,
/// overlapping its neighbours' only at the edges. Each run counts its window's cells (in
/// `counts`), the counts give the cell starts and each run's first slot in each cell (the
/// runs before it in storage take theirs first: the sort stays stable), and each run places
/// its discs. The result is the serial sort's, whatever the number of runs. Returns `false`,
/// having done nothing, when the sort runs on one thread, or the windows overlap so much
/// that together they are more than a quarter larger than the grid, or `counts` is too
/// short for them.
fn place_in_windows(
    keys: &[u32],
    chunk_windows: &[Range<usize>],
    counts: &mut [u32],
    total_cells: usize,
    cell_start: &mut Vec<u32>,
    order: &mut Vec<u32>,
    exec: &Executor,
) -> bool {
    let count = keys.len();
    let parts = exec.threads();
    let chunks = chunk_windows.len();
    debug_assert_eq!(chunks, count.div_ceil(CHUNK));
    if !exec.is_parallel(count) || chunks < parts || counts.is_empty() {
        return false;
    }
    // Runs of whole chunks, each with its window of cells: its chunks' together.
    let chunk_runs: Vec<Range<usize>> = (0..parts)
        .map(|p| p * chunks / parts..(p + 1) * chunks / parts)
        .collect();
    let runs: Vec<Range<usize>> = chunk_runs
        .iter()
        .map(|r| r.start * CHUNK..(r.end * CHUNK).min(count))
        .collect();
    let windows: Vec<Range<usize>> = chunk_runs
        .iter()
        .map(|r| {
            let (lo, end) = chunk_windows[r.clone()]
                .iter()
                .fold((usize::MAX, 0), |(lo, end), w| {
                    (lo.min(w.start), end.max(w.end))
                });
            lo..end
        })
        .collect();
    let widths: usize = windows.iter().map(Range::len).sum();
    if widths > total_cells + total_cells / MAX_WINDOW_EXCESS || widths > counts.len() {
        return false;
    }
    // 1. Each run counts the discs per cell of its window.
    let mut slices = Vec::with_capacity(parts);
    let mut rest = &mut counts[..widths];
    for window in &windows {
        let (slice, tail) = std::mem::take(&mut rest).split_at_mut(window.len());
        slices.push(slice);
        rest = tail;
    }
    exec.for_each_mut(count, &mut slices, |p, cells| {
        cells.fill(0);
        let lo = windows[p].start;
        for &k in &keys[runs[p].clone()] {
            cells[k as usize - lo] += 1;
        }
    });
    // 2. The cell starts, in parallel over ranges of cells: each cell's discs summed over
    // the windows that hold it, each range's running sum, then the earlier ranges' totals.
    cell_start.clear();
    cell_start.resize(total_cells + 1, 0);
    {
        let per_range = total_cells.div_ceil(parts).max(1);
        let mut ranges: Vec<&mut [u32]> = cell_start[1..].chunks_mut(per_range).collect();
        let counted: &[&mut [u32]] = &slices;
        let totals = exec.map_mut(total_cells, &mut ranges, |r, starts| {
            let first = r * per_range;
            for (window, cells) in windows.iter().zip(counted) {
                let shared = window.start.max(first)..window.end.min(first + starts.len());
                if shared.is_empty() {
                    continue;
                }
                let own = &mut starts[shared.start - first..shared.end - first];
                let theirs = &cells[shared.start - window.start..shared.end - window.start];
                for (start, &n) in own.iter_mut().zip(theirs) {
                    *start += n;
                }
            }
            // The running sum in a register: a sum through memory waits on each store.
            let mut sum = 0;
            for start in starts.iter_mut() {
                sum += *start;
                *start = sum;
            }
            sum
        });
        let offsets: Vec<u32> = totals
            .iter()
            .scan(0, |before, &total| {
                let offset = *before;
                *before += total;
                Some(offset)
            })
            .collect();
        exec.for_each_mut(total_cells, &mut ranges, |r, starts| {
            for start in starts.iter_mut() {
                *start += offsets[r];
            }
        });
    }
    // 3. Each run's first slot per cell: the cell's start and the counts of the runs before
    // it. From the last run back, so the earlier runs still hold their counts.
    for p in (0..parts).rev() {
        let (before, after) = slices.split_at_mut(p);
        let (window, first) = (&windows[p], &mut after[0]);
        first.copy_from_slice(&cell_start[window.clone()]);
        for (earlier, cells) in windows[..p].iter().zip(before.iter()) {
            let shared = window.start.max(earlier.start)..window.end.min(earlier.end);
            for cell in shared {
                first[cell - window.start] += cells[cell - earlier.start];
            }
        }
    }
    // 4. Each run places its discs.
    // Every slot is written below: no need to clear them first.
    order.clear();
    order.reserve(count);
    let slots = SharedSlice::new(&mut order.spare_capacity_mut()[..count]);
    exec.for_each_mut(count, &mut slices, |p, next| {
        let (run, lo) = (runs[p].clone(), windows[p].start);
        for (i, &k) in run.clone().zip(&keys[run]) {
            let slot = &mut next[k as usize - lo];
            // SAFETY: run `p`'s slots in cell `c` start after the earlier runs' discs in `c`
            // and number its own, so the runs' slots tile each cell's range: every slot of
            // `order` is written by exactly one run, once.
            unsafe { slots.set(*slot as usize, MaybeUninit::new(i as u32)) };
            *slot += 1;
        }
    });
    // SAFETY: the runs wrote every one of the first `count` slots (above).
    unsafe { order.set_len(count) };
    true
}

/// Strips of whole cell rows, about [`DISCS_PER_BLOCK`] discs each, so a block's discs are
/// one run of storage and its candidates come out in storage order.
pub(super) fn blocks(grids: &[LevelGrid], levels: &[Level], out: &mut Vec<Block>) {
    out.clear();
    for (level, g) in grids.iter().enumerate() {
        let per_row = levels[level].count as f64 / g.n[1] as f64;
        let rows = (DISCS_PER_BLOCK / per_row).ceil().max(1.0) as usize;
        for y0 in (0..g.n[1]).step_by(rows) {
            out.push(Block {
                level,
                x: 0..g.n[0],
                y: y0..(y0 + rows).min(g.n[1]),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Config;
    use crate::context::StepContext;
    use crate::law::Law;
    use std::cell::RefCell;

    /// The 4×4 grid of cells of 1 (radius 0.5, no skin) over a walled box of side 4, for
    /// discs at `x`, `y`, and its levels.
    fn walled_grid(x: &[f64], y: &[f64]) -> (LevelGrid, Vec<Level>, Vec<u8>) {
        let config = Config {
            boundary: crate::Boundary::walls([0.0, 0.0], [4.0, 4.0]),
            ..Config::default()
        };
        let exec = Executor::default();
        let ctx = StepContext::new(&config, 0.1, &exec, None);
        let radius = vec![0.5; x.len()];
        let mut level_of = Vec::new();
        let (levels, _) = super::super::levels::assign(&radius, &Law::new(&config), &mut level_of);
        let scratch = RefCell::new(Vec::new());
        let discs = super::super::levels::Discs {
            level_of: &level_of,
            scratch: &scratch,
        };
        let extent = ctx.geometry.grid_extent();
        let grid =
            super::super::levels::level_grid([x, y], extent, &ctx, 0.0, levels[0], 0, &discs);
        assert_eq!(grid.n, [4, 4]);
        (grid, levels, level_of)
    }

    /// The counting sort's keys, cell starts and order for discs at `x`, `y`.
    fn sorted(
        grids: &[LevelGrid],
        level_of: &[u8],
        x: &[f64],
        y: &[f64],
    ) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        let (mut cell_start, mut order, mut keys) = (Vec::new(), Vec::new(), vec![0; x.len()]);
        let exec = Executor::default();
        counting_sort(
            grids,
            level_of,
            x,
            y,
            &mut keys,
            &mut cell_start,
            &mut order,
            &exec,
        );
        (keys, cell_start, order)
    }

    #[test]
    fn the_sort_is_stable_and_groups_cells() {
        let x = [3.5, 0.5, 3.6, 0.6, 2.0];
        let y = [0.5, 0.5, 0.5, 3.5, 0.5];
        let (grid, levels, level_of) = walled_grid(&x, &y);
        let grids = [grid];
        let (_, cell_start, order) = sorted(&grids, &level_of, &x, &y);
        // Row 0: cells 0 (disc 1), 2 (disc 4), 3 (discs 0 then 2, in storage order); row 3:
        // cell 12 (disc 3).
        assert_eq!(order, vec![1, 4, 0, 2, 3]);
        assert_eq!(cell_start[..5], [0, 1, 1, 2, 4]);
        assert_eq!(cell_start[16], 5);
        let mut out = Vec::new();
        blocks(&grids, &levels, &mut out);
        assert_eq!(out.len(), 1);
        assert_eq!((out[0].x.clone(), out[0].y.clone()), (0..4, 0..4));
    }

    #[test]
    fn the_keys_are_the_clamped_cells_of_any_position() {
        // Positions at and a unit in the last place around every cell edge, outside the box,
        // infinite and NaN: the sort's keys (its own loop for one walled grid) are the cells
        // `LevelGrid::coord` gives.
        let mut values = vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            -1e300,
            1e300,
            -0.0,
        ];
        for edge in -1..=5 {
            let v = edge as f64;
            values.extend([v.next_down(), v, v.next_up()]);
        }
        let x: Vec<f64> = values
            .iter()
            .flat_map(|&v| values.iter().map(move |_| v))
            .collect();
        let y: Vec<f64> = values.iter().flat_map(|_| values.iter().copied()).collect();
        let (grid, _, level_of) = walled_grid(&x, &y);
        assert!(level_of.is_empty() && !grid.wrap);
        let grids = [grid];
        let (keys, _, _) = sorted(&grids, &level_of, &x, &y);
        let g = &grids[0];
        for i in 0..x.len() {
            let cell = g.cell_index(g.coord(x[i], 0), g.coord(y[i], 1));
            assert_eq!(keys[i] as usize, cell, "({}, {})", x[i], y[i]);
        }
        // Each corner and edge of the grid was met.
        assert!(keys.contains(&0) && keys.contains(&15) && keys.contains(&3) && keys.contains(&12));
    }

    #[test]
    fn placing_in_parts_gives_the_serial_sort() {
        // Keys in cell order but for a share of discs moved to a nearby cell (the storage of
        // a rebuild after the last), to any cell (windows overlapping past the limit: the
        // serial sort), and all in one cell; on 2 and 3 threads, runs of unequal windows.
        let cells = 5000;
        let n = 20_000;
        let mut state = 12345u64;
        let mut random = |m: usize| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) % m as u64) as usize
        };
        let sorted: Vec<u32> = (0..n).map(|i| (i * cells / n) as u32).collect();
        let near: Vec<u32> = sorted
            .iter()
            .map(|&k| match random(10) {
                0 => (k as usize + random(60)).min(cells - 1) as u32,
                1 => (k as usize).saturating_sub(random(60)) as u32,
                _ => k,
            })
            .collect();
        let mut far = near.clone();
        far[3] = (cells - 1) as u32;
        far[n - 3] = 0;
        let one = vec![7u32; n];
        for threads in [2, 3] {
            let mut exec = Executor::new(threads).unwrap();
            exec.min_work = 0;
            for (keys, in_parts) in [(&sorted, true), (&near, true), (&far, false), (&one, true)] {
                let (mut serial_start, mut serial_order) = (Vec::new(), Vec::new());
                place(keys, cells, &mut serial_start, &mut serial_order);
                // Room for any windows: the limit on their overlap decides.
                assert!(scratch_for_counts(n, cells, &exec) > cells);
                let mut counts = vec![0; threads * cells];
                let (mut start, mut order) = (vec![9; 3], vec![9; 5]);
                let windows: Vec<_> = keys.chunks(CHUNK).map(window_of).collect();
                let placed = place_in_windows(
                    keys,
                    &windows,
                    &mut counts,
                    cells,
                    &mut start,
                    &mut order,
                    &exec,
                );
                assert_eq!(placed, in_parts, "{threads} threads");
                if placed {
                    assert_eq!(start, serial_start);
                    assert_eq!(order, serial_order);
                }
                // Too little scratch for the windows: the serial sort's turn (one cell's
                // windows fit in anything).
                let mut short = vec![0; 10];
                let fits = place_in_windows(
                    keys, &windows, &mut short, cells, &mut start, &mut order, &exec,
                );
                assert_eq!(fits, std::ptr::eq(keys, &one));
            }
        }
        // One thread: always the serial sort.
        let mut counts = vec![0; 2 * cells];
        let (mut start, mut order) = (Vec::new(), Vec::new());
        let serial = Executor::default();
        assert_eq!(scratch_for_counts(n, cells, &serial), 0);
        let windows: Vec<_> = near.chunks(CHUNK).map(window_of).collect();
        assert!(!place_in_windows(
            &near,
            &windows,
            &mut counts,
            cells,
            &mut start,
            &mut order,
            &serial
        ));
        // The sort is stable: within a cell, storage order.
        place(&near, cells, &mut start, &mut order);
        for cell in 0..cells {
            let run = &order[start[cell] as usize..start[cell + 1] as usize];
            assert!(run.windows(2).all(|w| w[0] < w[1]));
            assert!(run.iter().all(|&i| near[i as usize] as usize == cell));
        }
    }
}
