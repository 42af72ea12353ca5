//! Cutting the ordered contacts for parallel resolution: segments (runs of one colour in
//! one block row), pieces resolved side by side in a phase, and the phases in order.

use std::ops::Range;

use super::Contacts;
use super::order::{row_parity_of, segment_of, wave_of};
use super::presort::prefix_end;

/// The sweep is cut into bands of about this many contacts for parallel resolution.
const CONTACTS_PER_PIECE: usize = 256;
/// At most this many bands.
const MAX_PIECES: usize = 128;

impl Contacts {
    /// Cuts the sorted list into segments (one colour of one block row), the sweep into
    /// bands of whole waves, and the work into two phases: first every band but for its
    /// first wave's odd row, all bands in parallel; then those rows, in parallel.
    ///
    /// Why that gives the serial bits: the contacts of block row `r` touch discs in cell
    /// rows `2r − 1 ..= 2r + 2`. A band of waves `T..U` (`T`, `U` even) leaves out the odd
    /// row `T − 1`, so it touches cell rows `2T − 1 ..= 2U − 2`, apart from every other band.
    /// The rows left out, `T − 1` of each band, are two block rows apart from each other,
    /// and each goes after both of its neighbouring even rows (`T − 2` and `T`, the first in
    /// the band before, the other resolved in phase one) as in the serial order, and before
    /// nothing that shares a disc with it (`T + 1`, two rows on, is in no conflict). In a
    /// periodic box the last odd row neighbours row 0 across the edge: its wave starts a
    /// band of its own, so it goes in phase two too.
    pub(super) fn split(&mut self) {
        self.segments.clear();
        self.pieces.clear();
        self.phases.clear();
        let list = &self.list;
        if list.is_empty() {
            return;
        }
        let mut start = 0;
        while start < list.len() {
            let segment = segment_of(list[start].key);
            let end = prefix_end(list, start, |c| segment_of(c.key) == segment);
            self.segments.push(start..end);
            start = end;
        }
        let segments = &self.segments;
        let wave = |s: usize| wave_of(list[segments[s].start].key);
        let odd_row = |s: usize| row_parity_of(list[segments[s].start].key) == 1;
        let last_wave = wave(segments.len() - 1);
        // Bands: runs of whole waves, closed once they hold enough contacts; the last wave
        // starts a band of its own when it holds only an odd row (see above).
        let target = CONTACTS_PER_PIECE.max(list.len().div_ceil(MAX_PIECES));
        let mut bands: Vec<Range<usize>> = Vec::new();
        let mut band_start = 0;
        for s in 1..segments.len() {
            if wave(s) == wave(s - 1) {
                continue;
            }
            let full = segments[s].start - segments[band_start].start >= target;
            let lone_last = wave(s) == last_wave && odd_row(s);
            if full || lone_last {
                bands.push(band_start..s);
                band_start = s;
            }
        }
        bands.push(band_start..segments.len());
        // Phase one: each band without its first wave's odd row; phase two: those rows.
        let first_odd = |band: &Range<usize>| {
            let first = wave(band.start);
            let odd_start = (band.start..band.end)
                .find(|&s| wave(s) != first || odd_row(s))
                .unwrap_or(band.end);
            let odd_end = (odd_start..band.end)
                .find(|&s| wave(s) != first)
                .unwrap_or(band.end);
            odd_start..odd_end
        };
        let odd_rows: Vec<Range<usize>> = bands.iter().map(first_odd).collect();
        for (band, odd) in bands.iter().zip(&odd_rows) {
            self.pieces.push([band.start..odd.start, odd.end..band.end]);
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
            .map(|segments| {
                segments
                    .clone()
                    .map(|s| self.segments[s].len())
                    .sum::<usize>()
            })
            .sum()
    }

    /// Segment `segment` cut in four at block boundaries, as [`Contacts::halves_of`] cuts it
    /// and then each half: whole blocks of one colour in one row each, so the quarters touch
    /// disjoint discs and may be resolved side by side. (A quarter is empty where there are
    /// too few blocks.)
    pub(crate) fn quarters(&self, segment: usize) -> [[Range<usize>; 2]; 2] {
        self.halves_of(self.segments[segment].clone())
            .map(|half| self.halves_of(half))
    }

    /// The contacts `range` of one segment cut in two at the block boundary nearest its
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
