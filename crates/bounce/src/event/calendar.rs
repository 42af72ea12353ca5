//! The event calendar: one slot per disc holding the time of its next event, and a
//! tournament tree over the slots whose root is the earliest (ties to the lower slot, so the
//! order of events is a function of the state alone). Setting a slot replays the matches on
//! its path to the root: `O(log n)`, no stale entries to skip or collect. Each node keeps
//! its winner's time beside its number, so a replay reads one sibling node per level, next
//! to the node it updates, instead of looking two slots' times up. The tree is the
//! bottom-up kind with `n` leaves, not padded to a power of two: node `k`'s children are
//! `2k` and `2k + 1`, the leaves `n..2n`, and the root (node 1) holds the earliest of all,
//! whatever the shape, because the match's order is a total one.

/// A match's winner: its slot and that slot's time.
#[derive(Clone, Copy, Debug)]
struct Entry {
    time: f64,
    slot: u32,
}

/// No slot (the root of an empty calendar): never wins.
const PAD: Entry = Entry {
    time: f64::INFINITY,
    slot: u32::MAX,
};

impl Entry {
    /// The same slot at the same time, to the bit (so the root's time is the slot's own).
    #[inline]
    fn same(self, other: Entry) -> bool {
        self.slot == other.slot && self.time.to_bits() == other.time.to_bits()
    }

    /// Whether `self` wins against `other`: earlier, or as early and a lower slot.
    #[inline]
    fn beats(self, other: Entry) -> bool {
        self.time < other.time || (self.time == other.time && self.slot < other.slot)
    }
}

/// A binary tournament over `n` slots (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) struct Calendar {
    /// Node `k`'s winner; the leaves `n + i` are the slots.
    tree: Vec<Entry>,
    n: usize,
}

impl Calendar {
    /// `n` slots, every one empty (at `∞`).
    pub(crate) fn new(n: usize) -> Calendar {
        let mut tree = vec![PAD; (2 * n).max(2)];
        for i in 0..n {
            tree[n + i] = Entry {
                time: f64::INFINITY,
                slot: i as u32,
            };
        }
        for k in (1..n).rev() {
            tree[k] = winner(tree[2 * k], tree[2 * k + 1]);
        }
        Calendar { tree, n }
    }

    /// The bytes the calendar holds.
    pub(crate) fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Entry>() * self.tree.capacity()
    }

    /// Slot `i`'s event is now at `t`.
    #[inline]
    pub(crate) fn set(&mut self, i: usize, t: f64) {
        let mut k = self.n + i;
        let mut w = Entry {
            time: t,
            slot: i as u32,
        };
        self.tree[k] = w;
        while k > 1 {
            w = winner(w, self.tree[k ^ 1]);
            k /= 2;
            if self.tree[k].same(w) {
                // The path above already holds this result.
                break;
            }
            self.tree[k] = w;
        }
    }

    /// The earliest slot and its time, or `None` with no slots.
    #[inline]
    pub(crate) fn first(&self) -> Option<(usize, f64)> {
        let w = self.tree[1];
        (w.slot != u32::MAX).then_some((w.slot as usize, w.time))
    }
}

/// The winner of a match (the lower slot on a tie; `PAD` never wins).
#[inline]
fn winner(a: Entry, b: Entry) -> Entry {
    if b.beats(a) { b } else { a }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_root_is_the_earliest_slot_ties_to_the_lower() {
        let mut c = Calendar::new(5);
        for (i, t) in [3.0, 1.0, 4.0, 1.0, 5.0].into_iter().enumerate() {
            c.set(i, t);
        }
        assert_eq!(c.first(), Some((1, 1.0)));
        c.set(1, 9.0);
        assert_eq!(c.first(), Some((3, 1.0)));
        c.set(3, 6.0);
        assert_eq!(c.first(), Some((0, 3.0)));
        // A slot that was winning and moves later, then earlier again.
        c.set(0, 7.0);
        assert_eq!(c.first(), Some((2, 4.0)));
        c.set(4, 0.5);
        assert_eq!(c.first(), Some((4, 0.5)));
        assert_eq!(Calendar::new(0).first(), None);
        let mut one = Calendar::new(1);
        one.set(0, 2.0);
        assert_eq!(one.first(), Some((0, 2.0)));
    }

    #[test]
    fn it_agrees_with_a_scan_over_many_updates() {
        let n = 37;
        let mut c = Calendar::new(n);
        let mut times = vec![f64::INFINITY; n];
        let mut s = 12345u64;
        for _ in 0..5000 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let i = (s >> 33) as usize % n;
            let t = ((s >> 11) % 64) as f64;
            c.set(i, t);
            times[i] = t;
            let best = (0..n)
                .min_by(|&a, &b| times[a].total_cmp(&times[b]).then(a.cmp(&b)))
                .unwrap();
            assert_eq!(c.first(), Some((best, times[best])));
        }
    }
}
