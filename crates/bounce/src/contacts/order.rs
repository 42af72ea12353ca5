//! The canonical order's grid: cells at least `1.01 d_max` wide, blocks two cells wide
//! coloured 2×2, and the key that puts a contact's block in the wave order (see the module
//! `contacts`). Fixed by the configuration and the largest radius, never by where the discs
//! happen to be.

use crate::broadphase::{floor_to_isize, wrap_index};
use crate::geometry::{Geometry, OrderAxisFrame};
use crate::law::Law;

use super::Contact;

/// Order-grid cells are this much wider than the largest collision distance.
const CELL_MARGIN: f64 = 1.01;
/// Cell coordinates of a grid without a periodic box are clamped to `±2^30`.
const HALF_RANGE: isize = 1 << 30;

/// The order-grid blocks contacts fall in: their waves and columns, lowest and highest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct BlockBounds {
    pub(super) waves: [u64; 2],
    pub(super) columns: [u64; 2],
}

/// The bits of a block column in a contact's key (columns are below 2^30).
pub(super) const COLUMN_BITS: u64 = (1 << 31) - 1;

/// The wave of a key: its block row rounded up to even (colours 2 and 3 of an odd row come
/// after colours 0 and 1 of the next row).
pub(super) fn wave_of(key: u64) -> u64 {
    key >> 33
}

/// 0 for the colours of even block rows (0, 1), 1 for those of odd ones (2, 3).
pub(super) fn row_parity_of(key: u64) -> u64 {
    (key >> 32) & 1
}

pub(super) fn column_of(key: u64) -> u64 {
    key & COLUMN_BITS
}

/// The key of block `(column, row)` in the wave order: wave, row parity, column parity,
/// column.
pub(super) fn block_key(column: u64, row: u64) -> u64 {
    let parity = row & 1;
    ((row + parity) << 33) | (parity << 32) | ((column & 1) << 31) | column
}

/// The colour row of a key: its wave, row parity and colour.
pub(super) fn colour_row_of(key: u64) -> u64 {
    key >> 31
}

impl BlockBounds {
    /// Bounds of no contact (any union replaces them).
    pub(super) const EMPTY: BlockBounds = BlockBounds {
        waves: [u64::MAX, 0],
        columns: [u64::MAX, 0],
    };

    pub(super) fn of(contacts: &[Contact]) -> BlockBounds {
        contacts.iter().fold(BlockBounds::EMPTY, |b, c| {
            let (wave, column) = (wave_of(c.key), column_of(c.key));
            BlockBounds {
                waves: [b.waves[0].min(wave), b.waves[1].max(wave)],
                columns: [b.columns[0].min(column), b.columns[1].max(column)],
            }
        })
    }

    pub(super) fn union(self, other: &BlockBounds) -> BlockBounds {
        BlockBounds {
            waves: [
                self.waves[0].min(other.waves[0]),
                self.waves[1].max(other.waves[1]),
            ],
            columns: [
                self.columns[0].min(other.columns[0]),
                self.columns[1].max(other.columns[1]),
            ],
        }
    }
}

/// `v`'s bits mapped so that unsigned order is `f64::total_cmp`'s order.
pub(crate) fn ordered_bits(v: f64) -> u64 {
    let bits = v.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | (1 << 63)
    }
}

/// The `f64` whose [`ordered_bits`] are `u`.
pub(super) fn from_ordered_bits(u: u64) -> f64 {
    if u >> 63 == 1 {
        f64::from_bits(u & !(1 << 63))
    } else {
        f64::from_bits(!u)
    }
}

/// The order grid along one axis.
#[derive(Clone, Copy, Debug)]
pub(super) struct OrderAxis {
    origin: f64,
    inv_cell: f64,
    /// Cells across a periodic box (a multiple of 4), or 0 without one.
    wrap: isize,
    /// All discs in one block along this axis (a periodic box too narrow for 4 cells).
    single: bool,
}

impl OrderAxis {
    /// The block coordinate of `v`, below 2^30.
    #[inline]
    fn block(&self, v: f64) -> u64 {
        if self.single {
            return 0;
        }
        let cell = self.raw_cell(v);
        let cell = if self.wrap > 0 {
            wrap_index(cell, self.wrap)
        } else {
            // Clamping never moves two cell coordinates further apart.
            cell.clamp(-HALF_RANGE, HALF_RANGE - 1) + HALF_RANGE
        };
        (cell / 2) as u64
    }

    /// The cell of `v` before wrapping or clamping: non-decreasing in `v`.
    #[inline(always)]
    fn raw_cell(&self, v: f64) -> isize {
        floor_to_isize((v - self.origin) * self.inv_cell)
    }

    /// Coordinates `lo..hi` that all lie in block `b` ([`OrderAxis::block`] gives `b` for
    /// each): those whose raw cell is one of the block's two (wrapped or clamped cells, and
    /// NaN, are left out: a test against the span may send them to `block` instead).
    pub(super) fn span(&self, b: u64) -> [f64; 2] {
        if self.single {
            return [f64::NEG_INFINITY, f64::INFINITY];
        }
        let first = 2 * b as isize - if self.wrap > 0 { 0 } else { HALF_RANGE };
        let in_range = if self.wrap > 0 {
            first + 1 < self.wrap
        } else {
            first + 1 < HALF_RANGE - 1
        };
        if b > (1 << 31) || !in_range {
            return [f64::INFINITY, f64::NEG_INFINITY];
        }
        [self.first_at(first), self.first_at(first + 2)]
    }

    /// The smallest `v` (not NaN) whose raw cell is at least `cell` (+∞ if none is).
    fn first_at(&self, cell: isize) -> f64 {
        // Bisection over the coordinates in order (`ordered_bits`), where the raw cell
        // never decreases: `low` below the answer, `high` at or above it.
        let reaches = |u: u64| self.raw_cell(from_ordered_bits(u)) >= cell;
        let (mut low, mut high) = (ordered_bits(f64::NEG_INFINITY), ordered_bits(f64::INFINITY));
        if reaches(low) {
            return f64::NEG_INFINITY;
        }
        if !reaches(high) {
            return f64::INFINITY;
        }
        while high - low > 1 {
            let middle = low + (high - low) / 2;
            if reaches(middle) {
                high = middle;
            } else {
                low = middle;
            }
        }
        from_ordered_bits(high)
    }
}

/// The order grid's cell width for discs up to `max_radius` (before a periodic box rounds
/// it to fit): 1.01 times the largest collision distance.
pub(super) fn cell_width(law: &Law, max_radius: f64) -> f64 {
    // The same bits as `CELL_MARGIN * 2.0 * max_radius * collision_radius_scale`.
    law.reach(CELL_MARGIN * 2.0 * max_radius)
}

/// The order grid's cell width for discs up to `max_radius` under `config` (a periodic box
/// rounds it up to fit a whole number of cells): how far a contact reaches, and the unit in
/// which a distributed run measures its ghost layers. See [`order_block_start`] for an
/// example.
pub fn order_cell_width(config: &crate::Config, max_radius: f64) -> f64 {
    cell_width(&Law::new(config), max_radius)
}

/// Order-grid cells a chain of contacts can cross in one solver pass: 4 colour phases, each
/// within one block and its ring (3 cells), plus the cell a disc sits in.
const CELLS_PER_PASS: f64 = 13.0;

/// How far one solver pass's chains of contacts can carry an effect, for discs up to
/// `max_radius` under `config`: a disc's new state depends on no disc farther than this per
/// pass (plus what the discs move), so a distributed run's ghost layers are at least this
/// thick for every pass of every substep.
///
/// ```
/// use bounce::{Config, order_cell_width, order_pass_reach};
/// let config = Config::default();
/// assert_eq!(order_pass_reach(&config, 0.5), 13.0 * order_cell_width(&config, 0.5));
/// ```
pub fn order_pass_reach(config: &crate::Config, max_radius: f64) -> f64 {
    CELLS_PER_PASS * order_cell_width(config, max_radius)
}

/// Where the order block holding coordinate `v` along `axis` (0: x, 1: y) begins, for discs
/// up to `max_radius` under `config`: a distributed run cuts its domains there, so each
/// block's contacts are resolved and counted by one rank.
///
/// ```
/// use bounce::{Config, order_block_start, order_cell_width};
/// let config = Config::default();
/// // Discs up to radius 0.5: cells 1.01 wide, blocks of two cells.
/// let cell = order_cell_width(&config, 0.5);
/// assert!((cell - 1.01).abs() < 1e-12);
/// let start = order_block_start(&config, 0.5, 0, 5.3);
/// assert!(start <= 5.3 && 5.3 < start + 2.0 * cell);
/// ```
pub fn order_block_start(config: &crate::Config, max_radius: f64, axis: usize, v: f64) -> f64 {
    let grid = OrderGrid::new(&Geometry::new(config), &Law::new(config), max_radius);
    let axis = &grid.0[axis.min(1)];
    if axis.single || axis.inv_cell.is_nan() || axis.inv_cell <= 0.0 {
        return v;
    }
    let cell = ((v - axis.origin) * axis.inv_cell).floor();
    let start = cell - cell.rem_euclid(2.0);
    axis.origin + start / axis.inv_cell
}

/// The grid that fixes the canonical order of contacts.
#[derive(Clone, Copy, Debug)]
pub(crate) struct OrderGrid(pub(super) [OrderAxis; 2]);

impl OrderGrid {
    pub(crate) fn new(geometry: &Geometry, law: &Law, max_radius: f64) -> Self {
        let cell = cell_width(law, max_radius);
        OrderGrid([0, 1].map(|axis| match geometry.order_axis(axis) {
            OrderAxisFrame {
                origin,
                period: Some(width),
            } => {
                let n = (width / cell).floor();
                let n = if n.is_finite() {
                    n.min(1e9) as isize
                } else {
                    0
                };
                // Blocks of two cells, an even number of them, so colours alternate across
                // the periodic edge too.
                let n = n - n % 4;
                OrderAxis {
                    origin,
                    inv_cell: n as f64 / width,
                    wrap: n,
                    single: n < 4,
                }
            }
            OrderAxisFrame {
                origin,
                period: None,
            } => OrderAxis {
                origin,
                inv_cell: 1.0 / cell,
                wrap: 0,
                single: false,
            },
        }))
    }

    /// The sort key of a contact whose lower-id disc is at `(x, y)`: its block in the wave
    /// order (see the module docs), wave first (the block row rounded up to even), then the
    /// row's parity (colours 0 and 1 before 2 and 3), the column's (the colour within the
    /// pair) and the column.
    #[inline]
    pub(crate) fn key(&self, x: f64, y: f64) -> u64 {
        block_key(self.0[0].block(x), self.0[1].block(y))
    }

    /// Positions that all have key `key`: `[x_lo, x_hi, y_lo, y_hi]`, half-open (see
    /// [`OrderAxis::span`]).
    #[cfg(test)]
    fn span(&self, key: u64) -> [f64; 4] {
        let row = wave_of(key) - row_parity_of(key);
        let ([x_lo, x_hi], [y_lo, y_hi]) = (self.0[0].span(column_of(key)), self.0[1].span(row));
        [x_lo, x_hi, y_lo, y_hi]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contacts::tests::random;
    use crate::{Boundary, Config};

    fn order_grid(config: &Config, max_radius: f64) -> OrderGrid {
        OrderGrid::new(&Geometry::new(config), &Law::new(config), max_radius)
    }

    #[test]
    fn order_blocks_start_where_their_discs_fall() {
        for config in [
            Config::default(),
            Config {
                boundary: Boundary::Periodic {
                    min: [-5.0, -7.0],
                    max: [95.0, 93.0],
                },
                ..Config::default()
            },
        ] {
            let grid = order_grid(&config, 0.5);
            for (axis, v) in [0, 1]
                .into_iter()
                .flat_map(|a| [-3.3, 0.0, 0.7, 12.34, 50.0, 91.0].map(|v| (a, v)))
            {
                let start = order_block_start(&config, 0.5, axis, v);
                assert!(start <= v, "{start} <= {v}");
                // The block's first and last points are in v's block, its next one is not.
                let block = grid.0[axis].block(v);
                assert_eq!(grid.0[axis].block(start + 1e-9), block);
                let width = 2.0 / grid.0[axis].inv_cell;
                assert_eq!(grid.0[axis].block(start + width - 1e-9), block);
                assert_ne!(grid.0[axis].block(start + width + 1e-9), block);
            }
        }
    }

    #[test]
    fn a_block_span_holds_exactly_its_blocks_positions() {
        // Around each point, open, in walls and periodic, near the origin and far from it:
        // the point lies in its block's span; the span's first point and the last before its
        // end have the block's key, the points just outside do not, nor does one in between
        // give another key.
        for boundary in [
            Boundary::Open,
            Boundary::walls([-3.0, 1e6], [40.0, 1e6 + 50.0]),
            Boundary::periodic([-5.0, -7.0], [95.0, 93.0]),
        ] {
            let config = Config {
                boundary: boundary.clone(),
                ..Config::default()
            };
            let grid = order_grid(&config, 0.37);
            let mut next = random(5);
            for _ in 0..300 {
                let u = |r: u64| r as f64 / (1u64 << 31) as f64;
                let (x, y) = match boundary {
                    Boundary::Walls { .. } => (-3.0 + 43.0 * u(next()), 1e6 + 50.0 * u(next())),
                    _ => (-5.0 + 100.0 * u(next()), -7.0 + 100.0 * u(next())),
                };
                let key = grid.key(x, y);
                let [x_lo, x_hi, y_lo, y_hi] = grid.span(key);
                let case = format!("{boundary:?} ({x}, {y})");
                assert!(x_lo <= x && x < x_hi && y_lo <= y && y < y_hi, "{case}");
                for (a, b) in [(x_lo, y_lo), (x_hi.next_down(), y_hi.next_down())] {
                    assert_eq!(grid.key(a, b), key, "{case}");
                }
                for (a, b) in [
                    (x_lo.next_down(), y),
                    (x_hi, y),
                    (x, y_lo.next_down()),
                    (x, y_hi),
                ] {
                    assert_ne!(grid.key(a, b), key, "{case}");
                }
                let t = u(next());
                let inside = (x_lo + t * (x_hi - x_lo)).min(x_hi.next_down());
                assert_eq!(grid.key(inside, y), key, "{case}");
            }
        }
    }

    #[test]
    fn partners_within_the_largest_collision_distance_are_in_neighbouring_cells() {
        // Cells of 1.01 for d_max = 1, far from the origin too.
        let config = Config {
            boundary: Boundary::Open,
            ..Config::default()
        };
        let grid = order_grid(&config, 0.5);
        for base in [0.0, -3.7, 1e6 + 0.123, -1e8] {
            for k in 0..1000 {
                let x = base + k as f64 * 0.0137;
                let (c1, c2) = (
                    floor_to_isize((x - grid.0[0].origin) * grid.0[0].inv_cell),
                    floor_to_isize((x + 1.0 - grid.0[0].origin) * grid.0[0].inv_cell),
                );
                assert!((c2 - c1).abs() <= 1, "{x}: cells {c1} {c2}");
            }
        }
    }

    #[test]
    fn colours_alternate_between_neighbouring_blocks() {
        let config = Config {
            boundary: Boundary::walls([0.0, 0.0], [100.0, 100.0]),
            ..Config::default()
        };
        let grid = order_grid(&config, 0.5);
        // Blocks are two cells of 1.01 wide.
        let colour = |x: f64, y: f64| {
            let key = grid.key(x, y);
            row_parity_of(key) * 2 + (column_of(key) & 1)
        };
        assert_eq!(colour(0.5, 0.5), 0);
        assert_eq!(colour(2.5, 0.5), 1);
        assert_eq!(colour(0.5, 2.5), 2);
        assert_eq!(colour(2.5, 2.5), 3);
        assert_eq!(colour(4.5, 4.5), 0);
        // Slightly outside the walls: still an ordinary block.
        assert_eq!(colour(-0.1, 0.5), 1);
    }

    #[test]
    fn a_periodic_box_has_an_even_number_of_blocks_or_one() {
        for width in [3.0, 4.5, 5.0, 7.9, 8.1, 100.0] {
            let config = Config {
                boundary: Boundary::Periodic {
                    min: [0.0, 0.0],
                    max: [width, width],
                },
                ..Config::default()
            };
            let axis = order_grid(&config, 0.5).0[0];
            assert!(
                axis.single || (axis.wrap % 4 == 0 && axis.wrap >= 4),
                "{width}: {axis:?}"
            );
            // The wrap-around neighbours of the last block have the other parity.
            if !axis.single {
                let last = axis.block(width - 1e-9);
                assert_eq!(last % 2, 1);
                assert_eq!(axis.block(width + 1e-9), 0);
            }
        }
    }
}
