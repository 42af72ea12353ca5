//! Binning: a stable counting sort of the discs by grid cell, and the blocks of cell rows
//! whose candidates are listed together.
//!
//! The sort gives `order` (new index `k` holds old index `order[k]`) and `cell_start` (global
//! cell `c` holds new indices `cell_start[c]..cell_start[c + 1]`). There is no fixed cell
//! capacity: a cell holds however many discs fall in it. Storage is in cell order from the
//! last rebuild except for discs that changed cell, so the passes walk memory in order.

use std::ops::Range;

use super::levels::{Level, LevelGrid, clamp_cell};
use crate::parallel::{CHUNK, Executor};

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
/// into `order` and `cell_start`; `keys` is scratch of at least `x.len()`.
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
    let keys = &mut keys[..count];
    {
        let mut chunks: Vec<(usize, &mut [u32])> = keys.chunks_mut(CHUNK).enumerate().collect();
        exec.for_each_mut(count, &mut chunks, |_, (c, keys)| {
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
        });
    }
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
}
