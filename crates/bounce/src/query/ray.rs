//! A ray through the snapshot's grid: the cells it crosses in order ([`Walk`]), and where it
//! enters a disc ([`entry`]).

use super::Queries;

/// Where the ray `origin + t direction` enters the disc of radius `r` around `c`: the
/// smaller root `t >= 0`, or `None` when it misses or starts inside.
pub(super) fn entry(origin: [f64; 2], direction: [f64; 2], c: [f64; 2], r: f64) -> Option<f64> {
    let m = [origin[0] - c[0], origin[1] - c[1]];
    let a = direction[0] * direction[0] + direction[1] * direction[1];
    let b = m[0] * direction[0] + m[1] * direction[1];
    let cc = m[0] * m[0] + m[1] * m[1] - r * r;
    if cc <= 0.0 || b >= 0.0 {
        // Inside (or on the edge), or moving away.
        return None;
    }
    let disc = b * b - a * cc;
    if disc < 0.0 {
        return None;
    }
    // The stable form of the smaller root (`b < 0`).
    let q = -b + disc.sqrt();
    Some(cc / q)
}

/// The cells a ray crosses, in order, with the ray's fraction on entering each (a grid
/// walk in unbounded cell indices; outside a bounded grid it ends).
pub(super) struct Walk<'q> {
    queries: &'q Queries,
    cell: [i64; 2],
    step: [i64; 2],
    /// The fraction at which the ray crosses the next cell side, per axis, and per cell.
    next: [f64; 2],
    delta: [f64; 2],
    t: f64,
    end: f64,
    /// Cells left to cross (a ray in a periodic box may never meet a disc).
    left: u64,
}

impl<'q> Walk<'q> {
    pub(super) fn new(
        queries: &'q Queries,
        origin: [f64; 2],
        direction: [f64; 2],
        end: f64,
    ) -> Walk<'q> {
        let mut t = 0.0;
        let mut end = end;
        if queries.period.is_none() {
            // Clip to the grid's rectangle and one cell around it (a disc at the edge
            // reaches into that ring).
            for k in 0..2 {
                let lo = queries.origin[k] - queries.width[k];
                let hi = queries.origin[k] + queries.width[k] * (queries.cells[k] + 1) as f64;
                if direction[k] == 0.0 {
                    if origin[k] < lo || origin[k] > hi {
                        end = -1.0;
                    }
                    continue;
                }
                let (a, b) = (
                    (lo - origin[k]) / direction[k],
                    (hi - origin[k]) / direction[k],
                );
                t = f64::max(t, a.min(b));
                end = end.min(a.max(b));
            }
        }
        let at = [origin[0] + t * direction[0], origin[1] + t * direction[1]];
        let mut cell = queries.cell_at_unclamped(at);
        if queries.period.is_none() {
            cell = [0, 1].map(|k| cell[k].clamp(-1, queries.cells[k]));
        }
        let mut step = [0i64; 2];
        let mut next = [f64::INFINITY; 2];
        let mut delta = [f64::INFINITY; 2];
        for k in 0..2 {
            if direction[k] > 0.0 {
                step[k] = 1;
                let side = queries.origin[k] + (cell[k] + 1) as f64 * queries.width[k];
                next[k] = (side - origin[k]) / direction[k];
                delta[k] = queries.width[k] / direction[k];
            } else if direction[k] < 0.0 {
                step[k] = -1;
                let side = queries.origin[k] + cell[k] as f64 * queries.width[k];
                next[k] = (side - origin[k]) / direction[k];
                delta[k] = -queries.width[k] / direction[k];
            }
        }
        let cells = (queries.cells[0] * queries.cells[1]) as u64;
        Walk {
            queries,
            cell,
            step,
            next,
            delta,
            t,
            end,
            left: 4 * cells + 64,
        }
    }

    /// The next cell and the fraction the ray enters it at.
    pub(super) fn next(&mut self) -> Option<([i64; 2], f64)> {
        if self.t > self.end || self.left == 0 {
            return None;
        }
        self.left -= 1;
        if self.queries.period.is_none()
            && (0..2).any(|k| self.cell[k] < -1 || self.cell[k] > self.queries.cells[k])
        {
            return None;
        }
        let out = (self.cell, self.t);
        let k = if self.next[0] < self.next[1] { 0 } else { 1 };
        self.t = self.next[k];
        self.next[k] += self.delta[k];
        self.cell[k] += self.step[k];
        Some(out)
    }
}
