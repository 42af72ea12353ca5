//! The domains: the box cut into rows across y and each row into columns across x, each
//! holding about as many discs, and how far a place is from each domain (who holds its ghost).

use bounce::{Tally, wrap_coordinate};

/// Height bins of the histogram the cuts are taken from.
pub(super) const BINS: usize = 4096;

/// Cuts along one axis: part `k` is `[cuts[k], cuts[k + 1])` of the (wrapped) coordinate;
/// the first and last cuts are infinite.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Cuts {
    pub(super) cuts: Vec<f64>,
    /// `(min, size)` of a periodic box along this axis.
    pub(super) period: Option<(f64, f64)>,
}

impl Cuts {
    pub(super) fn parts(&self) -> usize {
        self.cuts.len() - 1
    }

    pub(super) fn wrapped(&self, v: f64) -> f64 {
        match self.period {
            Some((min, size)) => wrap_coordinate(v, min, size),
            None => v,
        }
    }

    /// The part holding `v`.
    pub(super) fn part_of(&self, v: f64) -> usize {
        let v = self.wrapped(v);
        self.cuts[1..self.parts()].partition_point(|&c| c <= v)
    }

    /// How far `v` is from part `k` (0 inside), across a periodic box's edge too.
    pub(super) fn gap(&self, v: f64, k: usize) -> f64 {
        let v = self.wrapped(v);
        let (mut a, mut b) = (self.cuts[k], self.cuts[k + 1]);
        let (first, last) = (k == 0, k == self.parts() - 1);
        match self.period {
            Some((min, size)) => {
                if first {
                    a = min;
                }
                if last {
                    b = min + size;
                }
                if (a <= v && v < b) || (first && v < a) || (last && v >= b) {
                    0.0
                } else {
                    (a - v).rem_euclid(size).min((v - b).rem_euclid(size))
                }
            }
            None if v < a => a - v,
            None if v >= b => v - b,
            None => 0.0,
        }
    }

    pub(super) fn range(&self, k: usize) -> [f64; 2] {
        [self.cuts[k], self.cuts[k + 1]]
    }
}

/// The domains: rows across y, each cut across x into as many columns; rank
/// `row × columns + column`. Rows and columns hold about as many discs each.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Domains {
    pub(super) rows: Cuts,
    /// Each row's columns.
    pub(super) columns: Vec<Cuts>,
}

impl Domains {
    #[cfg(test)]
    pub(super) fn ranks(&self) -> usize {
        self.rows.parts() * self.columns[0].parts()
    }

    /// The row and column of rank `k`.
    pub(super) fn place(&self, k: usize) -> (usize, usize) {
        let columns = self.columns[0].parts();
        (k / columns, k % columns)
    }

    /// The rank owning the place `(x, y)`.
    pub(super) fn owner(&self, x: f64, y: f64) -> usize {
        let row = self.rows.part_of(y);
        row * self.columns[0].parts() + self.columns[row].part_of(x)
    }

    /// How far `(x, y)` is from rank `k`'s domain (0 inside).
    pub(super) fn gap(&self, x: f64, y: f64, k: usize) -> f64 {
        let (row, column) = self.place(k);
        self.columns[row]
            .gap(x, column)
            .hypot(self.rows.gap(y, row))
    }

    pub(super) fn tally(&self, k: usize) -> Tally {
        let (row, column) = self.place(k);
        Tally::new(
            self.columns[row].range(column),
            self.rows.range(row),
            [self.columns[row].period, self.rows.period],
        )
    }
}

/// Rows and columns for `ranks`: as square as divides evenly (columns = the largest divisor
/// up to the square root), more rows than columns.
pub(super) fn grid_shape(ranks: usize) -> (usize, usize) {
    let columns = (1..=ranks)
        .take_while(|c| c * c <= ranks)
        .filter(|c| ranks.is_multiple_of(*c))
        .last()
        .unwrap_or(1);
    (ranks / columns, columns)
}

/// `parts` cuts from a histogram of `counts` over `[lo, lo + bins × width)`: about as many
/// counted in each part.
pub(super) fn cuts_by_count(counts: &[u64], lo: f64, width: f64, parts: usize) -> Vec<f64> {
    let mut cuts = vec![f64::NEG_INFINITY; parts + 1];
    cuts[parts] = f64::INFINITY;
    let n: u64 = counts.iter().sum();
    let mut below = 0u64;
    let mut k = 1;
    for (bin, &c) in counts.iter().enumerate() {
        below += c;
        while k < parts && below * parts as u64 >= n * k as u64 {
            cuts[k] = lo + (bin + 1) as f64 * width;
            k += 1;
        }
    }
    let hi = lo + counts.len() as f64 * width;
    for cut in &mut cuts[k..parts] {
        *cut = hi;
    }
    cuts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuts_own_every_coordinate_once_and_measure_gaps_across_a_periodic_edge() {
        let cuts = Cuts {
            cuts: vec![f64::NEG_INFINITY, 3.0, 7.0, f64::INFINITY],
            period: Some((0.0, 10.0)),
        };
        assert_eq!(cuts.part_of(-0.5), 2); // wraps to 9.5
        assert_eq!(cuts.part_of(3.0), 1);
        assert_eq!(cuts.part_of(12.0), 0);
        assert_eq!(cuts.gap(5.0, 1), 0.0);
        assert!((cuts.gap(9.5, 0) - 0.5).abs() < 1e-12, "across the edge");
        assert!((cuts.gap(2.0, 2) - 2.0).abs() < 1e-12, "across the edge");
        assert!((cuts.gap(2.0, 1) - 1.0).abs() < 1e-12);
        let walls = Cuts {
            cuts: vec![f64::NEG_INFINITY, 3.0, f64::INFINITY],
            period: None,
        };
        assert_eq!(walls.gap(-100.0, 0), 0.0);
        assert_eq!(walls.gap(1.0, 1), 2.0);
        assert_eq!(walls.gap(5.0, 0), 2.0);
    }

    #[test]
    fn domains_tile_the_plane_in_rows_of_columns() {
        assert_eq!(grid_shape(1), (1, 1));
        assert_eq!(grid_shape(2), (2, 1));
        assert_eq!(grid_shape(3), (3, 1));
        assert_eq!(grid_shape(4), (2, 2));
        assert_eq!(grid_shape(12), (4, 3));
        assert_eq!(grid_shape(1000), (40, 25));
        let inf = f64::INFINITY;
        let domains = Domains {
            rows: Cuts {
                cuts: vec![-inf, 5.0, inf],
                period: None,
            },
            columns: vec![
                Cuts {
                    cuts: vec![-inf, 2.0, inf],
                    period: None,
                },
                Cuts {
                    cuts: vec![-inf, 8.0, inf],
                    period: None,
                },
            ],
        };
        assert_eq!(domains.ranks(), 4);
        assert_eq!(domains.owner(1.0, 1.0), 0);
        assert_eq!(domains.owner(3.0, 1.0), 1);
        assert_eq!(domains.owner(3.0, 6.0), 2);
        assert_eq!(domains.owner(9.0, 6.0), 3);
        // From (3, 4) to rank 2's domain (x < 8, y >= 5): 1 up; to rank 3's: the corner.
        assert_eq!(domains.gap(3.0, 4.0, 2), 1.0);
        assert!((domains.gap(3.0, 4.0, 3) - 26f64.sqrt()).abs() < 1e-12);
        for k in 0..4 {
            let t = domains.tally(k);
            assert_eq!(t.counts(3.0, 6.0), k == 2);
        }
        // Cuts by count: 10 in the first bin, 10 spread over the rest.
        let mut counts = vec![0u64; 10];
        counts[0] = 10;
        for c in &mut counts[1..] {
            *c = 1;
        }
        counts[9] = 2;
        assert_eq!(cuts_by_count(&counts, 0.0, 1.0, 2), vec![-inf, 1.0, inf]);
    }
}
