//! The event engine's cells: a grid whose cells are at least the largest collision distance
//! wide, so a disc can only meet discs in the 3 × 3 cells around its own, and the obstacles
//! each cell's discs can reach. Each cell's discs are a doubly linked list through the discs
//! (moving one is `O(1)`, nothing allocated per event). In a periodic box the grid wraps;
//! otherwise its outer cells reach out to infinity, so a disc that leaves the region the grid
//! was laid over (an open world) is still in a cell, only a crowded one.

use crate::config::Shape;

/// No disc (the end of a cell's list).
const NONE: u32 = u32::MAX;

/// The cells (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) struct Grid {
    min: [f64; 2],
    width: [f64; 2],
    pub dims: [usize; 2],
    wrap: bool,
    head: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    /// Each disc's cell, `[x, y]`.
    pub cell: Vec<[u32; 2]>,
    /// The obstacles each cell's discs may reach: `obstacles[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    obstacles: Vec<u32>,
}

impl Grid {
    /// A grid over `[min, min + size]` for `n` discs with cells at least `reach` wide and at
    /// most about `4 n + 16` of them; wrapping or not.
    pub(crate) fn new(min: [f64; 2], size: [f64; 2], reach: f64, n: usize, wrap: bool) -> Grid {
        // A hair over `reach`, so round-off at a cell's side cannot hide a neighbour.
        let reach = reach * (1.0 + 1e-9);
        let mut dims = size.map(|s| ((s / reach).floor() as usize).clamp(1, 1 << 15));
        let most = 4 * n + 16;
        while dims[0] * dims[1] > most {
            dims = dims.map(|d| d.div_ceil(2));
        }
        Grid {
            min,
            width: [size[0] / dims[0] as f64, size[1] / dims[1] as f64],
            dims,
            wrap,
            head: vec![NONE; dims[0] * dims[1]],
            next: vec![NONE; n],
            prev: vec![NONE; n],
            cell: vec![[0, 0]; n],
            start: Vec::new(),
            obstacles: Vec::new(),
        }
    }

    /// The bytes the grid holds.
    pub(crate) fn memory_bytes(&self) -> usize {
        4 * (self.head.capacity()
            + self.next.capacity()
            + self.prev.capacity()
            + 2 * self.cell.capacity()
            + self.start.capacity()
            + self.obstacles.capacity())
    }

    /// The cells' width along each axis.
    pub(crate) fn width(&self) -> [f64; 2] {
        self.width
    }

    /// The cell a point is in (the outer cells taking everything beyond).
    pub(crate) fn cell_of(&self, p: [f64; 2]) -> [u32; 2] {
        [0, 1].map(|a| {
            let k = ((p[a] - self.min[a]) / self.width[a]).floor();
            k.clamp(0.0, (self.dims[a] - 1) as f64) as u32
        })
    }

    fn index(&self, c: [u32; 2]) -> usize {
        c[1] as usize * self.dims[0] + c[0] as usize
    }

    /// Lists disc `i` in cell `c`.
    pub(crate) fn insert(&mut self, i: usize, c: [u32; 2]) {
        let k = self.index(c);
        let h = self.head[k];
        self.next[i] = h;
        self.prev[i] = NONE;
        if h != NONE {
            self.prev[h as usize] = i as u32;
        }
        self.head[k] = i as u32;
        self.cell[i] = c;
    }

    /// Puts disc `i` in cell `c` without listing it (a large disc: see `EventDriven`).
    pub(crate) fn place(&mut self, i: usize, c: [u32; 2]) {
        self.cell[i] = c;
    }

    /// Takes disc `i` off its cell's list.
    pub(crate) fn remove(&mut self, i: usize) {
        let (p, n) = (self.prev[i], self.next[i]);
        if p == NONE {
            let k = self.index(self.cell[i]);
            self.head[k] = n;
        } else {
            self.next[p as usize] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
    }

    /// Cell `c`'s sides along `axis`, `−∞`/`∞` at the outer sides of a grid that does not
    /// wrap.
    pub(crate) fn sides(&self, c: [u32; 2], axis: usize) -> (f64, f64) {
        let k = c[axis] as usize;
        let lo = self.min[axis] + k as f64 * self.width[axis];
        let hi = self.min[axis] + (k + 1) as f64 * self.width[axis];
        if self.wrap {
            return (lo, hi);
        }
        let lo = if k == 0 { f64::NEG_INFINITY } else { lo };
        let hi = if k + 1 == self.dims[axis] {
            f64::INFINITY
        } else {
            hi
        };
        (lo, hi)
    }

    /// The cell past side `side` (0 +x, 1 −x, 2 +y, 3 −y) of `c`, and how many box widths a
    /// centre crossing it is moved by (−1, 0 or 1; only where a periodic grid wraps).
    pub(crate) fn beyond(&self, c: [u32; 2], side: u8) -> ([u32; 2], i32) {
        let axis = (side / 2) as usize;
        let n = self.dims[axis] as u32;
        let mut out = c;
        let mut shift = 0;
        if side % 2 == 1 {
            if c[axis] == 0 {
                out[axis] = n - 1;
                shift = 1;
            } else {
                out[axis] -= 1;
            }
        } else if c[axis] + 1 == n {
            out[axis] = 0;
            shift = -1;
        } else {
            out[axis] += 1;
        }
        (out, shift)
    }

    /// Calls `f` with each disc in the 3 × 3 cells around `c`.
    #[inline]
    pub(crate) fn for_each_near(&self, c: [u32; 2], mut f: impl FnMut(usize)) {
        let [nx, ny] = self.dims;
        if self.wrap && (nx < 3 || ny < 3) {
            return self.for_each_within(c, 1, f);
        }
        // The (up to) nine cells' first discs read in one go, before any branch on what
        // they hold: the loads overlap instead of waiting on each other.
        let (columns, rows) = (self.around(c[0], 0), self.around(c[1], 1));
        let mut heads = [NONE; 9];
        let mut k = 0;
        for &row in rows.0.iter().take(rows.1) {
            for &column in columns.0.iter().take(columns.1) {
                heads[k] = self.head[row * nx + column];
                k += 1;
            }
        }
        for mut j in heads {
            while j != NONE {
                f(j as usize);
                j = self.next[j as usize];
            }
        }
    }

    /// The cells next to `k` along `axis` and `k` itself, ascending from the one before
    /// (wrapping round a periodic grid, cut at the edge of one that does not), and how many.
    #[inline]
    fn around(&self, k: u32, axis: usize) -> ([usize; 3], usize) {
        let (k, n) = (k as usize, self.dims[axis]);
        if self.wrap {
            let before = if k == 0 { n - 1 } else { k - 1 };
            let after = if k + 1 == n { 0 } else { k + 1 };
            ([before, k, after], 3)
        } else {
            let lo = k.saturating_sub(1);
            let hi = (k + 1).min(n - 1);
            ([lo, lo + 1, lo + 2], hi + 1 - lo)
        }
    }

    /// Calls `f` with each disc listed in the cells at most `k` cells from `c` along each
    /// axis (the grid wrapping or not; where `2k + 1` cells reach round a periodic grid,
    /// each cell once), row by row from the lowest. The cells are stepped through with a
    /// wrap at the edge, not a division per cell.
    #[inline]
    pub(crate) fn for_each_within(&self, c: [u32; 2], k: u32, mut f: impl FnMut(usize)) {
        // Each axis's first cell (wrapped into the grid) and how many cells it spans.
        let range = |axis: usize| -> (usize, usize) {
            let (n, c, k) = (self.dims[axis], c[axis] as usize, k as usize);
            if self.wrap && 2 * k + 1 >= n {
                (0, n)
            } else if self.wrap {
                (if c >= k { c - k } else { c + n - k }, 2 * k + 1)
            } else {
                let lo = c.saturating_sub(k);
                (lo, (c + k).min(n - 1) + 1 - lo)
            }
        };
        let [nx, ny] = self.dims;
        let ((y0, rows), (x0, columns)) = (range(1), range(0));
        let mut y = y0;
        for _ in 0..rows {
            let mut x = x0;
            for _ in 0..columns {
                let mut j = self.head[y * nx + x];
                while j != NONE {
                    f(j as usize);
                    j = self.next[j as usize];
                }
                x += 1;
                if x == nx {
                    x = 0;
                }
            }
            y += 1;
            if y == ny {
                y = 0;
            }
        }
    }

    /// Bins `shapes` into the cells from which a disc can reach them: a shape whose box,
    /// grown by `reach` (its reach for the largest disc), meets the cell.
    pub(crate) fn bin_obstacles(&mut self, shapes: &[Shape], reach: impl Fn(&Shape) -> f64) {
        let boxes: Vec<[[f64; 2]; 2]> = shapes
            .iter()
            .map(|s| {
                let d = reach(s);
                let (lo, hi) = match *s {
                    Shape::Segment { a, b } => (
                        [a[0].min(b[0]), a[1].min(b[1])],
                        [a[0].max(b[0]), a[1].max(b[1])],
                    ),
                    Shape::Peg { centre, .. } => (centre, centre),
                };
                [[lo[0] - d, lo[1] - d], [hi[0] + d, hi[1] + d]]
            })
            .collect();
        // Count each cell's obstacles, then fill: cells a box covers, by `cell_of`'s
        // clamping (a box beyond the grid lands in the outer cells, which reach out).
        let cells = self.dims[0] * self.dims[1];
        let mut count = vec![0u32; cells + 1];
        let ranges: Vec<[[u32; 2]; 2]> = boxes
            .iter()
            .map(|b| [self.cell_of(b[0]), self.cell_of(b[1])])
            .collect();
        let each = |r: &[[u32; 2]; 2], f: &mut dyn FnMut(usize)| {
            for y in r[0][1]..=r[1][1] {
                for x in r[0][0]..=r[1][0] {
                    f(y as usize * self.dims[0] + x as usize);
                }
            }
        };
        for r in &ranges {
            each(r, &mut |k| count[k + 1] += 1);
        }
        for k in 0..cells {
            count[k + 1] += count[k];
        }
        let mut fill = count.clone();
        let mut obstacles = vec![0u32; count[cells] as usize];
        for (o, r) in ranges.iter().enumerate() {
            each(r, &mut |k| {
                obstacles[fill[k] as usize] = o as u32;
                fill[k] += 1;
            });
        }
        self.start = count;
        self.obstacles = obstacles;
    }

    /// The obstacles a disc in cell `c` may reach.
    pub(crate) fn obstacles_near(&self, c: [u32; 2]) -> &[u32] {
        if self.start.is_empty() {
            return &[];
        }
        let k = self.index(c);
        &self.obstacles[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_periodic_grid_wraps_and_an_open_one_reaches_out() {
        let mut g = Grid::new([0.0, 0.0], [10.0, 10.0], 2.0, 4, true);
        assert_eq!(g.dims, [4, 4]);
        assert_eq!(g.cell_of([9.9, 0.1]), [3, 0]);
        assert_eq!(g.beyond([3, 0], 0), ([0, 0], -1));
        assert_eq!(g.beyond([3, 0], 3), ([3, 3], 1));
        assert_eq!(g.beyond([3, 2], 3), ([3, 1], 0));
        assert_eq!(g.beyond([0, 1], 1), ([3, 1], 1));
        g.insert(0, [3, 3]);
        g.insert(1, [0, 0]);
        g.insert(2, [1, 1]);
        g.insert(3, [2, 0]);
        let mut near = Vec::new();
        g.for_each_near([0, 0], |j| near.push(j));
        near.sort();
        assert_eq!(near, vec![0, 1, 2], "the corner cell's neighbours wrap");
        // Two cells round a 4-cell grid reach every cell once.
        near.clear();
        g.for_each_within([0, 0], 2, |j| near.push(j));
        near.sort();
        assert_eq!(near, vec![0, 1, 2, 3]);
        g.remove(1);
        near.clear();
        g.for_each_near([0, 0], |j| near.push(j));
        near.sort();
        assert_eq!(near, vec![0, 2]);

        let open = Grid::new([0.0, 0.0], [10.0, 10.0], 2.0, 4, false);
        assert_eq!(open.cell_of([-50.0, 99.0]), [0, 3]);
        assert_eq!(open.sides([0, 1], 0), (f64::NEG_INFINITY, 2.5));
        assert_eq!(open.sides([3, 1], 0), (7.5, f64::INFINITY));
    }

    #[test]
    fn the_nine_cells_come_in_the_order_of_the_general_walk() {
        // Every cell of a wrapping and an edged grid, 40 discs in a 5 × 4 grid: the
        // neighbourhood read nine heads at a time gives the same discs in the same order
        // (the order decides ties between equally early events).
        for wrap in [true, false] {
            let mut g = Grid::new([0.0, 0.0], [10.5, 8.5], 2.0, 40, wrap);
            assert_eq!(g.dims, [5, 4]);
            for i in 0..40 {
                g.insert(i, [(i * 7 % 5) as u32, (i * 3 % 4) as u32]);
            }
            for x in 0..5 {
                for y in 0..4 {
                    let (mut fast, mut general) = (Vec::new(), Vec::new());
                    g.for_each_near([x, y], |j| fast.push(j));
                    g.for_each_within([x, y], 1, |j| general.push(j));
                    assert_eq!(fast, general, "cell {x}, {y}, wrapping {wrap}");
                    assert!(!fast.is_empty());
                }
            }
        }
    }

    #[test]
    fn a_cell_lists_the_obstacles_its_discs_can_reach() {
        let mut g = Grid::new([0.0, 0.0], [10.0, 10.0], 2.0, 4, false);
        let shapes = [
            Shape::Peg {
                centre: [1.0, 1.0],
                radius: 0.5,
            },
            Shape::Segment {
                a: [0.0, 9.0],
                b: [10.0, 9.0],
            },
        ];
        g.bin_obstacles(&shapes, |_| 1.0);
        assert_eq!(g.obstacles_near([0, 0]), &[0]);
        assert_eq!(g.obstacles_near([2, 3]), &[1]);
        assert!(g.obstacles_near([2, 1]).is_empty());
    }
}
