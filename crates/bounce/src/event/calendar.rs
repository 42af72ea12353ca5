//! The event calendar: one slot per disc holding the time of its next event, and a
//! tournament tree over the slots whose root is the earliest (ties to the lower slot, so the
//! order of events is a function of the state alone). Setting a slot replays the matches on
//! its path to the root: `O(log n)`, no stale entries to skip or collect.

/// A complete binary tournament over `n` slots (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) struct Calendar {
    /// Each slot's time (`∞`: nothing to come).
    time: Vec<f64>,
    /// Node `k`'s winner; the leaves `size + i` are the slots, padded with `u32::MAX`.
    tree: Vec<u32>,
    size: usize,
}

impl Calendar {
    /// `n` slots, every one empty (at `∞`).
    pub(crate) fn new(n: usize) -> Calendar {
        let size = n.next_power_of_two().max(1);
        let mut tree = vec![u32::MAX; 2 * size];
        for i in 0..n {
            tree[size + i] = i as u32;
        }
        let mut calendar = Calendar {
            time: vec![f64::INFINITY; n],
            tree,
            size,
        };
        for k in (1..size).rev() {
            calendar.tree[k] = calendar.winner(calendar.tree[2 * k], calendar.tree[2 * k + 1]);
        }
        calendar
    }

    /// The bytes the calendar holds.
    pub(crate) fn memory_bytes(&self) -> usize {
        8 * self.time.capacity() + 4 * self.tree.capacity()
    }

    /// The earlier of two slots (the lower on a tie; padding never wins).
    #[inline]
    fn winner(&self, a: u32, b: u32) -> u32 {
        if b == u32::MAX {
            return a;
        }
        if a == u32::MAX {
            return b;
        }
        let (ta, tb) = (self.time[a as usize], self.time[b as usize]);
        if tb < ta || (tb == ta && b < a) { b } else { a }
    }

    /// Slot `i`'s event is now at `t`.
    #[inline]
    pub(crate) fn set(&mut self, i: usize, t: f64) {
        self.time[i] = t;
        let mut k = (self.size + i) / 2;
        while k >= 1 {
            let w = self.winner(self.tree[2 * k], self.tree[2 * k + 1]);
            if self.tree[k] == w && w as usize != i {
                // The path above already holds this winner's result unless `i` changed it.
                break;
            }
            self.tree[k] = w;
            k /= 2;
        }
    }

    /// The earliest slot and its time, or `None` with no slots.
    #[inline]
    pub(crate) fn first(&self) -> Option<(usize, f64)> {
        let w = *self.tree.get(1).unwrap_or(&self.tree[0]);
        (w != u32::MAX).then(|| (w as usize, self.time[w as usize]))
    }
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
