//! The presort: where contacts are dense (a resting pile), the near candidates are kept in
//! canonical order, so the contacts come out of detection in order but for the few whose
//! lower-id disc has since changed block; those are sorted apart and merged in.

use std::ops::Range;

use crate::broadphase::{Broadphase, Pair};
use crate::context::StepContext;
use crate::parallel::SharedSlice;
use crate::particles::Particles;

use super::detect::detect;
use super::order::{BlockBounds, OrderGrid, column_of, row_parity_of, wave_of};
use super::{Contact, Contacts};

/// The near band's candidates in canonical order: each pair lower id first, in the order
/// their contacts take (block of the lower-id disc when sorted, then ids). Contacts then
/// come out of the test in order, but for the few whose lower-id disc has since moved to
/// another block.
#[derive(Debug, Default)]
pub(super) struct Presorted {
    /// The broadphase listing these were made from (`None`: none yet).
    pub(super) generation: Option<u64>,
    pub(super) pairs: Vec<Pair>,
    /// The blocks: the key their contacts have while in place, and where their pairs end.
    pub(super) blocks: Vec<(u64, u32)>,
    /// Each block's span ([`OrderGrid::span`]): a lower-id disc inside it is in place,
    /// without working out its key.
    pub(super) spans: Vec<[f64; 4]>,
    /// Chunks of whole blocks tested in parallel: ranges of `blocks`.
    pub(super) chunks: Vec<Range<usize>>,
}

/// Discs a task keys for the presort.
pub(super) const KEY_CHUNK: usize = 16 * crate::parallel::CHUNK;
/// Blocks of presorted candidates tested together: about this many candidates.
pub(super) const CANDIDATES_PER_CHUNK: usize = 16384;
/// Candidates are presorted once this many detections have tested them: sorting them costs
/// a few detections' sorts, worth it only for lists that last (a resting pile keeps one for
/// dozens of substeps; a fast gas lists anew every step or two).
pub(super) const DETECTIONS_BEFORE_PRESORT: u32 = 3;
/// A new list is presorted at once when the one before it was tested more often than this:
/// lists last about as long as the one before.
pub(super) const LASTING_LISTING_USES: u32 = 4 * DETECTIONS_BEFORE_PRESORT;
/// Contacts are dense (a pile: the candidates are worth keeping in canonical order) when
/// at least this share of the candidates tested collide. A gas has about 1.5 %, a pile 35 %.
pub(super) const DENSE_SHARE: f64 = 0.125;

impl Contacts {
    /// Puts the near band's candidates in canonical order, once per listing: each pair
    /// lower id first, by the block of its lower-id disc now (the listing's positions) and
    /// its ids, the order their contacts take as long as that disc stays in its block.
    pub(super) fn presort(
        &mut self,
        broadphase: &Broadphase,
        p: &Particles,
        grid: &OrderGrid,
        ctx: &StepContext,
    ) {
        if self.presorted.generation == Some(broadphase.generation()) {
            return;
        }
        // Each disc's block, worked out once: a pile's disc has four or five near
        // candidates, and the key was most of making each one a contact-to-be.
        let n = p.len();
        self.disc_keys.resize(n, 0);
        let mut chunks: Vec<(usize, &mut [u64])> =
            self.disc_keys.chunks_mut(KEY_CHUNK).enumerate().collect();
        ctx.exec.for_each_mut(n, &mut chunks, |_, (c, keys)| {
            let base = *c * KEY_CHUNK;
            let (x, y) = (&p.x[base..base + keys.len()], &p.y[base..base + keys.len()]);
            for ((key, &x), &y) in keys.iter_mut().zip(x).zip(y) {
                *key = grid.key(x, y);
            }
        });
        // Every near candidate as a contact-to-be, sorted like contacts.
        let candidates = broadphase.candidates();
        self.found.resize_with(candidates.len(), Vec::new);
        self.found.truncate(candidates.len());
        let work = candidates.iter().map(|b| b[0].len()).sum();
        let disc_keys = &self.disc_keys[..];
        let bounds = ctx.exec.map_mut(work, &mut self.found, |block, found| {
            found.clear();
            found.extend(
                candidates[block][0]
                    .iter()
                    .map(|&[i, j]| Contact::of_keys([i as usize, j as usize], &p.id, disc_keys)),
            );
            BlockBounds::of(found)
        });
        let bounds = bounds
            .iter()
            .fold(BlockBounds::EMPTY, |all, b| all.union(b));
        self.gather_in_order(bounds, ctx, |c: &Contact| c.ids);
        let presorted = &mut self.presorted;
        presorted.pairs.clear();
        presorted.blocks.clear();
        presorted.chunks.clear();
        // Chunks end at block boundaries once they hold enough candidates.
        let (mut chunk_start, mut chunk_first_pair) = (0, 0);
        for (k, c) in self.list.iter().enumerate() {
            match presorted.blocks.last_mut() {
                Some((key, end)) if *key == c.key => *end += 1,
                _ => {
                    if k - chunk_first_pair >= CANDIDATES_PER_CHUNK {
                        presorted.chunks.push(chunk_start..presorted.blocks.len());
                        (chunk_start, chunk_first_pair) = (presorted.blocks.len(), k);
                    }
                    presorted.blocks.push((c.key, k as u32 + 1));
                }
            }
            presorted.pairs.push([c.a, c.b]);
        }
        if chunk_start < presorted.blocks.len() {
            presorted.chunks.push(chunk_start..presorted.blocks.len());
        }
        // Blocks share columns and rows: each axis's spans worked out once.
        let mut columns = std::collections::HashMap::new();
        let mut rows = std::collections::HashMap::new();
        presorted.spans.clear();
        presorted
            .spans
            .extend(presorted.blocks.iter().map(|&(key, _)| {
                let row = wave_of(key) - row_parity_of(key);
                let [x_lo, x_hi] = *columns
                    .entry(column_of(key))
                    .or_insert_with(|| grid.0[0].span(column_of(key)));
                let [y_lo, y_hi] = *rows.entry(row).or_insert_with(|| grid.0[1].span(row));
                [x_lo, x_hi, y_lo, y_hi]
            }));
        presorted.generation = Some(broadphase.generation());
        // The candidates' copies are done with, but their room is kept: the next presort
        // needs as much again (a resting pile presorts every dozen steps or so), and memory
        // given back comes back as page faults in the next placement, a large part of it.
        self.list.clear();
    }

    /// Detection through the presorted near candidates: contacts whose lower-id disc is
    /// still in its block come out of the test in canonical order; the others (and the far
    /// band's, if tested) are sorted apart and merged in. Returns the largest overlap.
    pub(super) fn find_presorted(
        &mut self,
        broadphase: &Broadphase,
        bands: usize,
        p: &Particles,
        grid: &OrderGrid,
        ctx: &StepContext,
    ) -> f64 {
        let presorted = &self.presorted;
        let uniform = broadphase.uniform_radius();
        let strays = broadphase.strays();
        let chunks = presorted.chunks.len();
        self.found.resize_with(chunks, Vec::new);
        self.found.truncate(chunks);
        self.out_of_place.resize_with(chunks + 1, Vec::new);
        self.out_of_place.truncate(chunks + 1);
        let (far, near_out) = self.out_of_place.split_last_mut().expect("one more");
        let mut work: Vec<_> = self.found.iter_mut().zip(near_out.iter_mut()).collect();
        let overlaps = ctx
            .exec
            .map_mut(presorted.pairs.len(), &mut work, |chunk, (found, out)| {
                found.clear();
                out.clear();
                let range = presorted.chunks[chunk].clone();
                let (blocks, spans) = (&presorted.blocks[range.clone()], &presorted.spans[range]);
                let first = presorted.blocks[..presorted.chunks[chunk].start]
                    .last()
                    .map_or(0, |b| b.1 as usize);
                let pairs = &presorted.pairs[first..blocks.last().map_or(first, |b| b.1 as usize)];
                // The contacts come in candidate order: follow the blocks alongside. A disc
                // inside its block's span has its key without the arithmetic.
                // Whether the last contact keyed has its block's key (is in place).
                let (block, in_place) = (std::cell::Cell::new(0), std::cell::Cell::new(true));
                // What the unchecked walk below relies on, checked once a chunk: a span per
                // block. The last block ends `pairs` (as `pairs` is cut), so for a candidate
                // `k` of `pairs` (`detect` keys only those) the walk stops within `blocks`.
                assert_eq!(blocks.len(), spans.len(), "a span per presorted block");
                let key = |k: usize, x: f64, y: f64| {
                    debug_assert!(first + k < blocks.last().map_or(0, |b| b.1 as usize));
                    // SAFETY: `k < pairs.len()`, and the last of `blocks` ends at
                    // `first + pairs.len()`: the walk stops at a block of `blocks` (and of
                    // `spans`, as long), starting from one it stopped at before.
                    let (block_key, [x_lo, x_hi, y_lo, y_hi]) = unsafe {
                        let mut b = block.get();
                        while blocks.get_unchecked(b).1 as usize <= first + k {
                            b += 1;
                        }
                        block.set(b);
                        (blocks.get_unchecked(b).0, *spans.get_unchecked(b))
                    };
                    if x >= x_lo && x < x_hi && y >= y_lo && y < y_hi {
                        in_place.set(true);
                        block_key
                    } else {
                        let key = grid.key(x, y);
                        in_place.set(key == block_key);
                        key
                    }
                };
                let emit = |_, c: Contact| {
                    if in_place.get() {
                        found.push(c);
                    } else {
                        out.push(c);
                    }
                };
                // SAFETY: the presorted pairs are the current listing's (see `presort`), which
                // indexes the current storage of `p` (checked by `find`).
                unsafe { detect(pairs, p, key, ctx, uniform, strays, emit) }
            });
        let mut max_overlap = overlaps.into_iter().fold(0.0, f64::max);
        far.clear();
        if bands > 1 {
            let candidates = broadphase.candidates();
            let work = candidates.iter().map(|b| b[1].len()).sum();
            let tested = ctx.exec.map_index(work, 0..candidates.len(), |block| {
                let mut found = Vec::new();
                // SAFETY: as above.
                let overlap = unsafe {
                    detect(
                        &candidates[block][1],
                        p,
                        |_, x, y| grid.key(x, y),
                        ctx,
                        uniform,
                        strays,
                        |_, c| found.push(c),
                    )
                };
                (overlap, found)
            });
            for (overlap, found) in tested {
                max_overlap = max_overlap.max(overlap);
                far.extend(found);
            }
        }
        // In place, in canonical order: the found lists in chunk order. Out of place: a few,
        // sorted and merged in.
        let mut moved: Vec<Contact> = self.out_of_place.iter().flatten().copied().collect();
        let stray_overlap = Self::stray_contacts(broadphase, p, grid, ctx, &mut moved);
        max_overlap = max_overlap.max(stray_overlap);
        moved.sort_unstable_by_key(|c| (c.key, c.ids));
        self.out_of_place_count = moved.len();
        merge_sorted(&self.found, &moved, &mut self.list, ctx);
        max_overlap
    }
}

/// [`Contacts::bucket_sort`]'s counting and placing on `parts` threads: the found lists are
/// cut into `parts` runs of about equal contacts, each run counts its contacts into
/// `buckets` counts of its own, each bucket's slots go to the runs in order, and each run
/// places its own contacts into `spare` (every slot of which is written). Afterwards
/// `starts[b]` holds the end of bucket `b`, as after the serial placement, and every bucket
/// holds the same contacts in the same order (the runs' in turn, each in its lists' order).
pub(super) fn place_by_bucket(
    found: &[Vec<Contact>],
    parts: usize,
    buckets: usize,
    bucket: &(impl Fn(&Contact) -> usize + Sync),
    starts: &mut [u32],
    spare: &mut [std::mem::MaybeUninit<Contact>],
    ctx: &StepContext,
) {
    let total = spare.len();
    // Runs of whole lists: run `p` starts at the first list with at least `p / parts` of
    // the contacts before it.
    let mut cuts = vec![0];
    let mut before = 0;
    for (k, list) in found.iter().enumerate() {
        while cuts.len() < parts && before >= cuts.len() * total / parts {
            cuts.push(k);
        }
        before += list.len();
    }
    cuts.resize(parts + 1, found.len());
    let runs: Vec<&[Vec<Contact>]> = (0..parts).map(|p| &found[cuts[p]..cuts[p + 1]]).collect();
    let mut counts = ctx.exec.map_index(total, 0..parts, |p| {
        let mut counts = vec![0u32; buckets];
        for c in runs[p].iter().flatten() {
            counts[bucket(c)] += 1;
        }
        counts
    });
    // Each run's first slot in each bucket: the bucket's start and the earlier runs' counts.
    let mut start = 0;
    for b in 0..buckets {
        for counts in counts.iter_mut() {
            let n = counts[b];
            counts[b] = start;
            start += n;
        }
        starts[b] = start;
    }
    starts[buckets] = start;
    let slots = SharedSlice::new(spare);
    let mut work: Vec<(usize, Vec<u32>)> = counts.into_iter().enumerate().collect();
    ctx.exec.for_each_mut(total, &mut work, |_, (p, next)| {
        for c in runs[*p].iter().flatten() {
            let slot = &mut next[bucket(c)];
            // SAFETY: run `p`'s slots in bucket `b` follow the earlier runs' and number its
            // own contacts there, so the runs' slots tile each bucket: every slot is written
            // by exactly one contact, once.
            unsafe { slots.set(*slot as usize, std::mem::MaybeUninit::new(*c)) };
            *slot += 1;
        }
    });
}

/// Writes into `list` the merge of the runs of `found` (each in canonical order, and so is
/// their concatenation) with `moved` (in canonical order), in parallel: each run takes the
/// moved contacts that fall before the next run's first, found by binary search, so the
/// runs' places in `list` are known before any is written. (Against one serial merge, the
/// settled 100k pile's detection is 6–14 % faster on two threads, and its resolution too:
/// each core then resolves contacts it wrote itself.)
pub(super) fn merge_sorted(
    found: &[Vec<Contact>],
    moved: &[Contact],
    list: &mut Vec<Contact>,
    ctx: &StepContext,
) {
    let order = |c: &Contact| (c.key, c.ids);
    // Where each run's moved contacts end: before the first contact of the next non-empty
    // run (all of them after the last).
    let mut moved_end = vec![moved.len(); found.len()];
    let mut next_first = None;
    for (k, run) in found.iter().enumerate().rev() {
        moved_end[k] = next_first.map_or(moved.len(), |first| {
            moved.partition_point(|m| order(m) < first)
        });
        if let Some(first) = run.first() {
            next_first = Some(order(first));
        }
    }
    let total = found.iter().map(Vec::len).sum::<usize>() + moved.len();
    list.clear();
    list.reserve(total);
    let mut rest = &mut list.spare_capacity_mut()[..total];
    let mut pieces = Vec::with_capacity(found.len());
    let mut moved_start = 0;
    for (run, &end) in found.iter().zip(&moved_end) {
        let (piece, tail) = std::mem::take(&mut rest).split_at_mut(run.len() + end - moved_start);
        pieces.push((piece, run.as_slice(), &moved[moved_start..end]));
        rest = tail;
        moved_start = end;
    }
    debug_assert!(rest.is_empty() && moved_start == moved.len());
    ctx.exec
        .for_each_mut(total, &mut pieces, |_, (out, run, moved)| {
            // Moved contacts are few: each finds its place in the run by a walk from the
            // last one's, and the run's contacts between two places are copied as one block
            // (a piece with none is one copy). The walk reads the lines
            // the copy reads next, in order; a bisection of the run (a pile's hundred moved
            // contacts a run) waited for a cache miss at nearly every probe, 5 % of the
            // settled pile's time.
            let (mut r, mut at) = (0, 0);
            for m in moved.iter() {
                let mut place = r;
                while place < run.len() && order(&run[place]) < order(m) {
                    place += 1;
                }
                let next = at + place - r;
                out[at..next].write_copy_of_slice(&run[r..place]);
                out[next].write(*m);
                (r, at) = (place, next + 1);
            }
            out[at..].write_copy_of_slice(&run[r..]);
        });
    // SAFETY: the pieces partition the first `total` slots, and each piece's loop wrote
    // every one of its slots (it holds exactly its run and its moved contacts).
    unsafe { list.set_len(total) };
}

/// The end of the run of `items` from `from` on that `holds` (which holds for a prefix of
/// `items[from..]`): the places 1, 2, 4, ... ahead are probed, then the last step bisected.
/// A pile's colour rows are a few hundred contacts of a list of a hundred thousand: bisecting
/// the whole rest for each missed the cache at nearly every probe, while these stay near
/// `from`, in order.
pub(super) fn prefix_end<T>(items: &[T], from: usize, holds: impl Fn(&T) -> bool) -> usize {
    // Every item of `items[from..lo]` holds; `items[hi]` does not (or `hi` is the end).
    let (mut lo, mut step) = (from, 1);
    let hi = loop {
        let probe = from + step - 1;
        if probe >= items.len() {
            break items.len();
        }
        if !holds(&items[probe]) {
            break probe;
        }
        lo = probe + 1;
        step *= 2;
    };
    lo + items[lo..hi].partition_point(holds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Config;
    use crate::contacts::tests::random;

    #[test]
    fn merging_runs_with_moved_contacts_gives_the_canonical_order() {
        // Runs of contacts in order (some empty, first and last among them), merged with
        // moved contacts that fall before, inside, between and after the runs, on one
        // thread and two: the same as sorting them all.
        let mut next = random(99);
        for threads in [1, 2] {
            let mut exec = crate::parallel::Executor::new(threads).unwrap();
            exec.min_work = 0;
            let config = Config::default();
            let ctx = StepContext::new(&config, 0.1, &exec, None);
            for (count, runs, moved_count) in [(3000, 7, 40), (500, 1, 0), (0, 3, 5), (800, 9, 300)]
            {
                let mut all: Vec<Contact> = (0..count + moved_count)
                    .map(|k| Contact {
                        key: next() % 64,
                        ids: (next() << 16) | k,
                        a: k as u32,
                        b: 0,
                    })
                    .collect();
                let mut moved = all.split_off(count as usize);
                moved.sort_unstable_by_key(|c| (c.key, c.ids));
                all.sort_unstable_by_key(|c| (c.key, c.ids));
                // Cut the in-place contacts into runs, the first and last empty.
                let mut found = vec![Vec::new()];
                for (k, chunk) in all.chunks(all.len().div_ceil(runs).max(1)).enumerate() {
                    found.push(chunk.to_vec());
                    if k % 3 == 1 {
                        found.push(Vec::new());
                    }
                }
                found.push(Vec::new());
                let mut expected: Vec<Contact> = all.iter().chain(&moved).copied().collect();
                expected.sort_unstable_by_key(|c| (c.key, c.ids));
                let mut list = vec![Contact::default(); 3];
                merge_sorted(&found, &moved, &mut list, &ctx);
                assert_eq!(list, expected, "{count} {runs} {moved_count} on {threads}");
            }
        }
    }

    #[test]
    fn a_prefix_ends_where_the_bisection_says() {
        // Every start and every cut of runs from empty to past a few doublings, against the
        // standard bisection of the rest.
        for len in [0usize, 1, 2, 3, 7, 8, 9, 64, 100] {
            let items: Vec<usize> = (0..len).collect();
            for from in 0..=len {
                for cut in 0..=len + 1 {
                    let holds = |&v: &usize| v < cut;
                    let expected = from + items[from..].partition_point(holds);
                    assert_eq!(
                        prefix_end(&items, from, holds),
                        expected,
                        "{len} {from} {cut}"
                    );
                }
            }
        }
    }
}
