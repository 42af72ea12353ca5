//! Cutting the ordered contacts for parallel resolution: colour rows (runs of one colour in
//! one block row), pieces resolved side by side in a phase, and the phases in order.

use std::ops::Range;

use super::Contacts;
use super::order::{colour_row_of, row_parity_of, wave_of};
use super::presort::prefix_end;

/// The sweep is cut into stripes of about this many contacts for parallel resolution.
const CONTACTS_PER_PIECE: usize = 256;
/// At most this many stripes.
const MAX_PIECES: usize = 128;

impl Contacts {
    /// Cuts the sorted list into colour rows (one colour of one block row), the sweep into
    /// stripes of whole waves, and the work into two phases: first every stripe but for its
    /// first wave's odd row, all stripes in parallel; then those rows, in parallel.
    ///
    /// Why that gives the serial bits: the contacts of block row `r` touch discs in cell
    /// rows `2r − 1 ..= 2r + 2`. A stripe of waves `T..U` (`T`, `U` even) leaves out the odd
    /// row `T − 1`, so it touches cell rows `2T − 1 ..= 2U − 2`, apart from every other stripe.
    /// The rows left out, `T − 1` of each stripe, are two block rows apart from each other,
    /// and each goes after both of its neighbouring even rows (`T − 2` and `T`, the first in
    /// the stripe before, the other resolved in phase one) as in the serial order, and before
    /// nothing that shares a disc with it (`T + 1`, two rows on, is in no conflict). In a
    /// periodic box the last odd row neighbours row 0 across the edge: its wave starts a
    /// stripe of its own, so it goes in phase two too.
    pub(super) fn split(&mut self) {
        self.colour_rows.clear();
        self.pieces.clear();
        self.phases.clear();
        let list = &self.list;
        if list.is_empty() {
            return;
        }
        let mut start = 0;
        while start < list.len() {
            let colour_row = colour_row_of(list[start].key);
            let end = prefix_end(list, start, |c| colour_row_of(c.key) == colour_row);
            self.colour_rows.push(start..end);
            start = end;
        }
        let colour_rows = &self.colour_rows;
        let wave = |s: usize| wave_of(list[colour_rows[s].start].key);
        let odd_row = |s: usize| row_parity_of(list[colour_rows[s].start].key) == 1;
        let last_wave = wave(colour_rows.len() - 1);
        // Bands: runs of whole waves, closed once they hold enough contacts; the last wave
        // starts a stripe of its own when it holds only an odd row (see above).
        let target = CONTACTS_PER_PIECE.max(list.len().div_ceil(MAX_PIECES));
        let mut stripes: Vec<Range<usize>> = Vec::new();
        let mut stripe_start = 0;
        for s in 1..colour_rows.len() {
            if wave(s) == wave(s - 1) {
                continue;
            }
            let full = colour_rows[s].start - colour_rows[stripe_start].start >= target;
            let lone_last = wave(s) == last_wave && odd_row(s);
            if full || lone_last {
                stripes.push(stripe_start..s);
                stripe_start = s;
            }
        }
        stripes.push(stripe_start..colour_rows.len());
        // Phase one: each stripe without its first wave's odd row; phase two: those rows.
        let first_odd = |stripe: &Range<usize>| {
            let first = wave(stripe.start);
            let odd_start = (stripe.start..stripe.end)
                .find(|&s| wave(s) != first || odd_row(s))
                .unwrap_or(stripe.end);
            let odd_end = (odd_start..stripe.end)
                .find(|&s| wave(s) != first)
                .unwrap_or(stripe.end);
            odd_start..odd_end
        };
        let odd_rows: Vec<Range<usize>> = stripes.iter().map(first_odd).collect();
        for (stripe, odd) in stripes.iter().zip(&odd_rows) {
            self.pieces
                .push([stripe.start..odd.start, odd.end..stripe.end]);
        }
        self.phases.push(0..self.pieces.len());
        let second = self.pieces.len();
        for odd in odd_rows.iter().filter(|odd| !odd.is_empty()) {
            self.pieces.push([odd.clone(), odd.end..odd.end]);
        }
        self.phases.push(second..self.pieces.len());
    }

    /// How many contacts piece `piece` holds.
    pub(crate) fn piece_contacts(&self, piece: usize) -> usize {
        self.pieces[piece]
            .iter()
            .map(|colour_rows| {
                colour_rows
                    .clone()
                    .map(|s| self.colour_rows[s].len())
                    .sum::<usize>()
            })
            .sum()
    }

    /// Colour row `colour row` cut in four at block boundaries, as [`Contacts::halves_of`] cuts it
    /// and then each half: whole blocks of one colour in one row each, so the quarters touch
    /// disjoint discs and may be resolved side by side. (A quarter is empty where there are
    /// too few blocks.)
    pub(crate) fn quarters(&self, colour_row: usize) -> [[Range<usize>; 2]; 2] {
        self.halves_of(self.colour_rows[colour_row].clone())
            .map(|half| self.halves_of(half))
    }

    /// The contacts `range` of one colour row cut in two at the block boundary nearest its
    /// middle (the second half empty when it is one block).
    pub(super) fn halves_of(&self, range: Range<usize>) -> [Range<usize>; 2] {
        let Range { start, end } = range;
        if start == end {
            return [start..end, end..end];
        }
        let list = &self.list;
        let same_block = |k: usize| list[k].key == list[k - 1].key;
        let middle = start + (end - start) / 2;
        // The nearest boundaries above and below the middle.
        let mut up = middle.max(start + 1);
        while up < end && same_block(up) {
            up += 1;
        }
        let mut down = middle;
        while down > start && same_block(down) {
            down -= 1;
        }
        let cut = if down > start && middle - down < up - middle {
            down
        } else {
            up.min(end)
        };
        [start..cut, cut..end]
    }
}
