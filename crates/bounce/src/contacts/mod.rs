//! Contacts: the pairs that collide in one substep, and the canonical order they are resolved
//! in.
//!
//! Detection applies the law's test (the seed's `distance <= collision_distance`) to the
//! broadphase's candidates. The order of resolution then depends on the current state
//! alone, never on the candidates, their age, the storage order or the thread count:
//!
//! - An *order grid* of cells at least `1.01 d_max` wide (`d_max` the largest collision
//!   distance, the law's interaction diameter of the largest disc) is laid over the world,
//!   fixed by the configuration and the largest radius. Cells are paired into blocks two cells wide,
//!   and blocks are coloured 2×2 by the parity of their coordinates.
//! - A contact is written with the lower id first, and belongs to the block of that disc.
//!   Its partner is within `d_max`, so in the same cell or the next: a block's contacts touch
//!   only discs in its cells and their one-cell ring.
//! - The canonical order is colour, block (row-major), lower id, higher id.
//!
//! Blocks of one colour are at least two cells apart, so their contacts touch disjoint discs.
//! A disc can only be touched by the 2×2 blocks around it, one of each colour, so what
//! decides its result is that those blocks take their turns in colour order: any order of
//! resolution that keeps that, and the order within each block, gives the same bits. The
//! contacts are therefore resolved in a *wave* order that sweeps the grid once instead of
//! four times (the contacts of colours 0 and 1 in block row `2m`, then those of colours 2 and
//! 3 in block row `2m − 1`, then `2m + 2`, ...), sorted by a key that says so ([`OrderGrid::key`]).
//! The sweep is cut into stripes of block rows resolved in parallel, each stripe but for its
//! first odd row, which all go after (see `split`). The 1% margin on the cell side absorbs
//! rounding in the cell coordinates, whose magnitude is capped at 2^30 cells.

mod colour_rows;
mod detect;
mod order;
mod presort;

use std::ops::Range;

use crate::broadphase::{BANDS, Broadphase};
use crate::context::StepContext;
use crate::part::Tally;
use crate::particles::{ParticleId, Particles, ordered};

use crate::law::touching;
use detect::detect;
use order::{BlockBounds, column_of, row_parity_of, wave_of};
pub(crate) use order::{OrderGrid, ordered_bits};
pub use order::{order_block_start, order_cell_width, order_pass_reach};
use presort::{
    DENSE_SHARE, DETECTIONS_BEFORE_PRESORT, LASTING_LISTING_USES, Presorted, place_by_bucket,
};

/// One colliding pair: storage indices `a` (the lower id) and `b`, and its sort key.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Contact {
    /// The block's place in the wave order: see [`OrderGrid::key`].
    key: u64,
    /// Lower id (high half), higher id (low half).
    ids: u64,
    pub(crate) a: u32,
    pub(crate) b: u32,
}

impl Contact {
    /// The contact of discs `i` and `j` (storage indices into `id`, `x`, `y`): lower id
    /// first, keyed by its block. (Slices, not `Particles`: the hot loop keeps them in
    /// registers.)
    #[inline(always)]
    fn of(id: &[ParticleId], [x, y]: [&[f64]; 2], grid: &OrderGrid, i: usize, j: usize) -> Self {
        let at = |k: usize| [x[k], y[k]];
        Self::of_values([i, j], [id[i], id[j]], [at(i), at(j)], |x, y| {
            grid.key(x, y)
        })
    }

    /// The contact of discs `i` and `j` (storage indices into `id` and `keys`, each disc's
    /// block key): lower id first, keyed by its disc's key.
    #[inline(always)]
    fn of_keys([i, j]: [usize; 2], id: &[ParticleId], keys: &[u64]) -> Self {
        let (id_i, id_j) = (u64::from(id[i].0), u64::from(id[j].0));
        // (Without a branch, as in `of_values`.)
        let lower_first = id_i < id_j;
        let select =
            |first: u64, second: u64| std::hint::select_unpredictable(lower_first, first, second);
        Contact {
            key: select(keys[i], keys[j]),
            ids: (select(id_i, id_j) << 32) | select(id_j, id_i),
            a: select(i as u64, j as u64) as u32,
            b: select(j as u64, i as u64) as u32,
        }
    }

    /// The contact of discs `i` and `j` given their ids and positions (which the test has
    /// read already): lower id first, keyed by `key` of the lower-id disc's position.
    #[inline(always)]
    fn of_values(
        [i, j]: [usize; 2],
        [id_i, id_j]: [ParticleId; 2],
        [at_i, at_j]: [[f64; 2]; 2],
        key: impl FnOnce(f64, f64) -> u64,
    ) -> Self {
        // Which id is lower is a coin toss, and in a gas the ids are far from cache: a branch
        // on it would mispredict half the time and each flush would wait for the miss.
        let lower_first = id_i < id_j;
        let select =
            |first: u64, second: u64| std::hint::select_unpredictable(lower_first, first, second);
        let (a, b) = (select(i as u64, j as u64), select(j as u64, i as u64));
        let (id_a, id_b) = (
            select(id_i.0.into(), id_j.0.into()),
            select(id_j.0.into(), id_i.0.into()),
        );
        let x_a = f64::from_bits(select(at_i[0].to_bits(), at_j[0].to_bits()));
        let y_a = f64::from_bits(select(at_i[1].to_bits(), at_j[1].to_bits()));
        Contact {
            key: key(x_a, y_a),
            ids: (id_a << 32) | id_b,
            a: a as u32,
            b: b as u32,
        }
    }
}

/// What detection measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Detection {
    pub pairs: usize,
    pub max_overlap: f64,
    /// Whether the contacts were sorted (else they came in presorted order).
    pub sorted: bool,
    /// Contacts a presorted detection found out of place (sorted apart and merged in).
    pub out_of_place: usize,
}

/// The contacts of the last detection, in canonical order.
///
/// What the solver's unsafe code relies on is kept here, in private fields that only this
/// module writes: every index of `list` is below `found_for` (the storage the detection
/// tested), and the pieces of one phase touch disjoint discs (see [`Contacts::split`]).
/// The solver checks `found_for` against the particles it is given.
#[derive(Debug, Default)]
pub(crate) struct Contacts {
    /// Contacts found per candidate block, before sorting.
    found: Vec<Vec<Contact>>,
    /// The number of discs whose storage indices the contacts hold.
    found_for: usize,
    /// All contacts in canonical order.
    list: Vec<Contact>,
    /// Runs of `list` of one colour in one block row: whole blocks that touch disjoint
    /// discs.
    colour_rows: Vec<Range<usize>>,
    /// Work that may be resolved in parallel with the other pieces of its phase: ranges of
    /// `colour_rows`, resolved in order.
    pieces: Vec<[Range<usize>; 2]>,
    /// Ranges of `pieces`, resolved one after the other: the stripes, then their first odd
    /// rows.
    phases: Vec<Range<usize>>,
    /// Scratch of the bucket sort: contacts per order block, then block starts.
    bucket_start: Vec<u32>,
    /// The near candidates in canonical order, when contacts are dense.
    presorted: Presorted,
    /// Each disc's order-grid block key, for the presort (kept between presorts).
    disc_keys: Vec<u64>,
    /// Contacts the presorted path found out of place (their lower-id disc changed block
    /// since the presort, or from the far band), per chunk.
    out_of_place: Vec<Vec<Contact>>,
    /// Whether the last detection found contacts dense among the candidates (a pile): then
    /// the candidates are kept in canonical order instead of sorting the contacts.
    dense: bool,
    /// The listing the last detection tested, and how many detections have tested it.
    listing: (u64, u32),
    /// How many detections tested the listing before it.
    last_listing_uses: u32,
    /// How many contacts the last presorted detection found out of place.
    out_of_place_count: usize,
}

impl Contacts {
    /// Tests the candidates of `broadphase` (which must cover the current positions) in its
    /// first `bands` bands (the others cannot collide: see `Bands`) and puts the colliding
    /// pairs in canonical order.
    pub(crate) fn find(
        &mut self,
        broadphase: &Broadphase,
        bands: usize,
        p: &Particles,
        ctx: &StepContext,
    ) -> Detection {
        let radius = broadphase.max_radius().max(ctx.order_radius);
        let grid = OrderGrid::new(&ctx.geometry, &ctx.law, radius);
        // Candidate indices are storage indices of this many discs (the broadphase keeps
        // every index below its listed count, and lists anew whenever discs are added or
        // reordered): what `detect` relies on.
        assert_eq!(
            broadphase.listed_count(),
            Some(p.len()),
            "stale candidate list"
        );
        self.found_for = p.len();
        let bands = bands.clamp(1, BANDS);
        let tested: usize = broadphase
            .candidates()
            .iter()
            .flat_map(|b| &b[..bands])
            .map(Vec::len)
            .sum();
        let generation = broadphase.generation();
        self.listing = match self.listing {
            (listed, count) if listed == generation => (listed, count.saturating_add(1)),
            (_, count) => {
                self.last_listing_uses = count;
                (generation, 1)
            }
        };
        // A list lasts once enough detections have tested it, or at once where the last
        // one lasted: a resting pile lists anew every dozen steps or so, each time for
        // dozens of detections, and three of them sorted before the presort cost as much
        // again as the presort.
        let lasting = self.listing.1 > DETECTIONS_BEFORE_PRESORT
            || self.last_listing_uses > LASTING_LISTING_USES
            || self.presorted.generation == Some(generation);
        // With several passes under gravity the order within a block depends on the
        // current heights, so the contacts are sorted then.
        let presorted = self.dense && lasting && ctx.stack_order.is_none();
        let max_overlap = if presorted {
            self.presort(broadphase, p, &grid, ctx);
            self.find_presorted(broadphase, bands, p, &grid, ctx)
        } else {
            self.find_sorting(broadphase, bands, p, &grid, ctx, tested)
        };
        self.split();
        self.dense = self.list.len() as f64 >= DENSE_SHARE * tested as f64;
        Detection {
            pairs: self.list.len(),
            max_overlap,
            sorted: !presorted,
            out_of_place: if presorted {
                self.out_of_place_count
            } else {
                0
            },
        }
    }

    /// Detection that sorts the contacts found: tests each candidate block's bands, then
    /// puts their contacts in canonical order (`gather_in_order`). Returns the largest
    /// overlap.
    fn find_sorting(
        &mut self,
        broadphase: &Broadphase,
        bands: usize,
        p: &Particles,
        grid: &OrderGrid,
        ctx: &StepContext,
        work: usize,
    ) -> f64 {
        let candidates = broadphase.candidates();
        // One list per candidate block, and the strays' last.
        self.found.resize_with(candidates.len() + 1, Vec::new);
        self.found.truncate(candidates.len() + 1);
        let uniform = broadphase.uniform_radius();
        let strays = broadphase.strays();
        let (blocks, stray_found) = self.found.split_at_mut(candidates.len());
        stray_found[0].clear();
        let stray_overlap = Self::stray_contacts(broadphase, p, grid, ctx, &mut stray_found[0]);
        let stray_bounds = BlockBounds::of(&stray_found[0]);
        let found = ctx.exec.map_mut(work, blocks, |block, found| {
            found.clear();
            let overlap = candidates[block][..bands]
                .iter()
                .fold(0.0f64, |overlap, pairs| {
                    let emit = |_, c| found.push(c);
                    let key = |_, x, y| grid.key(x, y);
                    // SAFETY: every candidate indexes the current storage of `p` (checked by
                    // `find`: the list was made for exactly these discs).
                    let tested = unsafe { detect(pairs, p, key, ctx, uniform, strays, emit) };
                    overlap.max(tested)
                });
            // The blocks these contacts fall in, while they are still in cache.
            (overlap, BlockBounds::of(found))
        });
        let bounds = found.iter().fold(stray_bounds, |all, (_, b)| all.union(b));
        let min_image = ctx.geometry.min_image();
        match ctx.stack_order {
            None => self.gather_in_order(bounds, ctx, |c: &Contact| c.ids),
            Some(gravity) => {
                // Lowest first: ascending in the midpoint's height against gravity.
                let rise = |c: &Contact| {
                    let (a, b) = (c.a as usize, c.b as usize);
                    let d = min_image.diff(p.x[a], p.y[a], p.x[b], p.y[b]);
                    let mid = [p.x[a] - 0.5 * d[0], p.y[a] - 0.5 * d[1]];
                    (
                        ordered_bits(-(gravity[0] * mid[0] + gravity[1] * mid[1])),
                        c.ids,
                    )
                };
                self.gather_in_order(bounds, ctx, rise)
            }
        }
        found
            .iter()
            .map(|(overlap, _)| *overlap)
            .fold(stray_overlap, f64::max)
    }

    /// Appends the contacts with a stray in them (see `broadphase::strays`) to `out`;
    /// returns their largest overlap.
    fn stray_contacts(
        broadphase: &Broadphase,
        p: &Particles,
        grid: &OrderGrid,
        ctx: &StepContext,
        out: &mut Vec<Contact>,
    ) -> f64 {
        let mut max_overlap = 0.0f64;
        broadphase.stray_pairs(p, ctx, |i, j, overlap| {
            max_overlap = max_overlap.max(overlap);
            out.push(Contact::of(&p.id, [&p.x, &p.y], grid, i, j));
        });
        max_overlap
    }

    /// What detection measured over the contacts `tally` counts (by the lower-id disc's
    /// place), with the same arithmetic as `find`'s test (the minimum image is antisymmetric
    /// bit for bit, so the pair's order does not matter).
    pub(crate) fn tallied(&self, p: &Particles, ctx: &StepContext, tally: Tally) -> Detection {
        let min_image = ctx.geometry.min_image();
        let mut detection = Detection::default();
        for c in &self.list {
            let (a, b) = (c.a as usize, c.b as usize);
            if !tally.counts(p.x[a], p.y[a]) {
                continue;
            }
            let diff = min_image.diff(p.x[a], p.y[a], p.x[b], p.y[b]);
            // Every listed contact collides: the overlap is the rule's.
            let reach = ctx.law.collision_distance(p.radius[a], p.radius[b]);
            let overlap = touching(diff, reach).unwrap_or(0.0);
            detection.pairs += 1;
            detection.max_overlap = detection.max_overlap.max(overlap);
        }
        detection
    }

    /// Gathers the contacts found per candidate block into `list`, in canonical order. Keys
    /// with ids are unique, so every sort gives the same order; but a settled pile has
    /// about 1.5 contacts per disc every substep, and a comparison sort of them was 60 % of
    /// its detection. So the contacts are counted into their order blocks (colour-major,
    /// then row, then column: the key's order), placed straight from the found lists, and
    /// only each block's few contacts are sorted by ids. Where blocks outnumber the contacts
    /// by more than four to one (a dilute gas) the contacts are counted into their colour rows
    /// (one colour of one block row) instead and each colour row sorted by key; where even
    /// colour rows do, a comparison sort does it all.
    ///
    /// Within a block the order is `within` (the id pair; with more than one solver pass
    /// under gravity, the contact's height first, lowest first: each pass then carries the
    /// floor's support up through a whole block instead of one contact, and the shipped pile
    /// settles under a momentum-conserving model, as measured in `ARCHITECTURE.md`).
    fn gather_in_order<K: Ord + Send>(
        &mut self,
        bounds: BlockBounds,
        ctx: &StepContext,
        within: impl Fn(&Contact) -> K + Sync + Send,
    ) {
        let total: usize = self.found.iter().map(Vec::len).sum();
        self.list.clear();
        if total == 0 {
            return;
        }
        // Waves are even; within a colour, columns share a parity: halving keeps the order.
        let [column_min, wave_min] = [bounds.columns[0] / 2, bounds.waves[0]];
        let width = bounds.columns[1] / 2 - column_min + 1;
        let waves = (bounds.waves[1] - wave_min) / 2 + 1;
        let colour_row = move |c: &Contact| -> u64 {
            (wave_of(c.key) - wave_min) / 2 * 4 + row_parity_of(c.key) * 2 + (column_of(c.key) & 1)
        };
        // Counting costs a pass over the buckets as well as the contacts: one bucket per
        // block where there are few blocks per contact (a pile); else one per colour row (one
        // colour of one block row: the 1M gas has 22,000 contacts in 3,200 colour rows, against
        // 1.3 million blocks), each then sorted by key; else a comparison sort.
        let few = |buckets: u64| buckets <= 4 * total as u64 + 1024;
        let blocks = waves.saturating_mul(4).saturating_mul(width);
        if few(blocks) {
            // Buckets in key order: wave, row parity, column parity, column.
            let block = |c: &Contact| {
                (colour_row(c) * width + (column_of(c.key) / 2 - column_min)) as usize
            };
            self.bucket_sort(blocks as usize, block, &within, ctx);
        } else if few(waves.saturating_mul(4)) {
            let by_key = |c: &Contact| (c.key, within(c));
            self.bucket_sort(waves as usize * 4, |c| colour_row(c) as usize, &by_key, ctx);
        } else {
            for found in &self.found {
                self.list.extend_from_slice(found);
            }
            ctx.exec
                .sort_unstable_by_key(&mut self.list, |c| (c.key, within(c)));
        }
    }

    /// Gathers the found contacts into `list` by a counting sort into `buckets` buckets
    /// (`bucket` gives each contact's, in canonical order), then sorts each bucket by
    /// `order`, groups of whole buckets in parallel (buckets are independent, so the result
    /// is the same on any thread count).
    fn bucket_sort<K: Ord>(
        &mut self,
        buckets: usize,
        bucket: impl Fn(&Contact) -> usize + Sync,
        order: &(impl Fn(&Contact) -> K + Sync),
        ctx: &StepContext,
    ) {
        let total: usize = self.found.iter().map(Vec::len).sum();
        let starts = &mut self.bucket_start;
        starts.clear();
        starts.resize(buckets + 1, 0);
        self.list.reserve(total);
        let spare = &mut self.list.spare_capacity_mut()[..total];
        let parts = ctx.exec.threads();
        if parts > 1 && ctx.exec.is_parallel(total) && buckets <= total {
            // In parallel (a pile's presort: millions of candidates), each of `parts` runs
            // of the found lists counting into its own buckets: see `place_by_bucket`.
            place_by_bucket(&self.found, parts, buckets, &bucket, starts, spare, ctx);
        } else {
            for c in self.found.iter().flatten() {
                starts[bucket(c) + 1] += 1;
            }
            for b in 0..buckets {
                starts[b + 1] += starts[b];
            }
            // Place each contact at its bucket's next slot (afterwards slot `b` holds the end
            // of bucket `b`), straight from the found lists into the list's spare capacity.
            for c in self.found.iter().flatten() {
                let slot = &mut starts[bucket(c)];
                spare[*slot as usize].write(*c);
                *slot += 1;
            }
        }
        // SAFETY: the buckets partition `0..total` and each slot of a bucket is written by
        // exactly one contact counted into it above, so all `total` slots are initialised.
        unsafe { self.list.set_len(total) };
        let starts = &starts[..buckets];
        let groups = 64.min(starts.len());
        // Each group: its contacts, the ends of its buckets, and where its contacts start.
        let mut pieces: Vec<(&mut [Contact], &[u32], usize)> = Vec::with_capacity(groups);
        let mut rest = &mut self.list[..];
        let mut consumed = 0usize;
        for g in 0..groups {
            let ends = &starts[g * starts.len() / groups..(g + 1) * starts.len() / groups];
            let end = ends.last().map_or(consumed, |&e| e as usize);
            let (piece, tail) = std::mem::take(&mut rest).split_at_mut(end - consumed);
            pieces.push((piece, ends, consumed));
            rest = tail;
            consumed = end;
        }
        ctx.exec
            .for_each_mut(total, &mut pieces, |_, (piece, ends, base)| {
                let mut start = 0;
                for &end in ends.iter() {
                    let end = end as usize - *base;
                    if end - start > 1 {
                        sort_block(&mut piece[start..end], order);
                    }
                    start = end;
                }
            });
    }

    /// Whether the last detections went through presorted candidates.
    #[cfg(test)]
    pub(crate) fn presorted(&self) -> bool {
        self.presorted.generation.is_some()
    }

    /// How many detections have tested the current listing.
    #[cfg(test)]
    pub(crate) fn listing_uses(&self) -> u32 {
        self.listing.1
    }

    /// The listing the presorted candidates are from.
    #[cfg(test)]
    pub(crate) fn presorted_generation(&self) -> Option<u64> {
        self.presorted.generation
    }

    /// The contacts in canonical order.
    pub(crate) fn list(&self) -> &[Contact] {
        &self.list
    }

    /// The number of discs whose storage indices the contacts hold.
    pub(crate) fn found_for(&self) -> usize {
        self.found_for
    }

    /// Ranges of [`Contacts::pieces`] resolved one after the other; the pieces of one
    /// phase touch disjoint discs.
    pub(crate) fn phases(&self) -> &[Range<usize>] {
        &self.phases
    }

    /// The colour rows of each piece, resolved in order (two ranges: its band, then the rest).
    pub(crate) fn pieces(&self) -> &[[Range<usize>; 2]] {
        &self.pieces
    }

    /// The contacts as sorted id pairs.
    pub(crate) fn pair_ids(&self, p: &Particles) -> Vec<(ParticleId, ParticleId)> {
        let mut out: Vec<_> = self
            .list
            .iter()
            .map(|c| ordered(p.id[c.a as usize], p.id[c.b as usize]))
            .collect();
        out.sort_unstable();
        out
    }
}

/// Sorts one block's contacts by `within` (short runs: insertion sort; long ones, as in a
/// dense block of a polydisperse world, the standard sort).
pub(super) fn sort_block<K: Ord>(block: &mut [Contact], within: &impl Fn(&Contact) -> K) {
    if block.len() > 32 {
        block.sort_unstable_by_key(within);
        return;
    }
    // Insertion by shifting: each contact is moved once, the larger ones slide up.
    for i in 1..block.len() {
        let contact = block[i];
        let key = within(&contact);
        let mut j = i;
        while j > 0 && within(&block[j - 1]) > key {
            block[j] = block[j - 1];
            j -= 1;
        }
        block[j] = contact;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Config;
    use order::block_key;

    /// A 31-bit pseudo-random number generator (a linear congruential one's high bits).
    pub(super) fn random(seed: u64) -> impl FnMut() -> u64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        }
    }

    #[test]
    fn the_bucket_sort_gives_the_canonical_order() {
        // Contacts with keys as `OrderGrid::key` makes them (`block_key`),
        // dense (the bucket sort) and sparse (the comparison sort), against a plain sort; on
        // one thread and on several (the bucket sort counting and placing in parts).
        for threads in [1, 2, 3] {
            let mut exec = crate::parallel::Executor::new(threads).unwrap();
            exec.min_work = 0;
            bucket_sort_cases(&exec);
        }
    }

    fn bucket_sort_cases(exec: &crate::parallel::Executor) {
        let config = Config::default();
        let ctx = StepContext::new(&config, 0.1, exec, None);
        let mut next = random(12345);
        // Blocks over [0, span_x) × [0, span_y): few per contact (buckets per block), many
        // columns in few rows (buckets per colour row), many of both (the comparison sort).
        for (count, [span_x, span_y]) in [
            (5000u64, [40u64, 40]),
            (3000, [1 << 30, 1 << 30]),
            (3000, [1 << 20, 40]),
            (200, [1 << 16, 1]),
            (1, [1, 1]),
            (2000, [3, 3]),
            (9, [2, 2]),
        ] {
            let list: Vec<Contact> = (0..count)
                .map(|k| {
                    let (bx, by) = (next() % span_x + 7, next() % span_y + 11);
                    let lower = next() % 50;
                    Contact {
                        key: block_key(bx, by),
                        ids: (lower << 32) | (lower + 1 + k),
                        a: k as u32,
                        b: 0,
                    }
                })
                .collect();
            // Within blocks: the ids (the seed's passes), or another key first (the height,
            // with several passes under gravity; here a stand-in) then the ids.
            let height = |c: &Contact| (u64::from(c.a) * 7919 % 13, c.ids);
            for stacked in [false, true] {
                let mut expected = list.clone();
                if stacked {
                    expected.sort_unstable_by_key(|c| (c.key, height(c)));
                } else {
                    expected.sort_unstable_by_key(|c| (c.key, c.ids));
                }
                // Found in candidate blocks, as `find` leaves them: uneven, one empty.
                let (third, two_thirds) =
                    (list.len() / 3, (2 * list.len() / 3 + 1).min(list.len()));
                let found = vec![
                    list[..third].to_vec(),
                    Vec::new(),
                    list[third..two_thirds].to_vec(),
                    list[two_thirds..].to_vec(),
                ];
                let bounds = found
                    .iter()
                    .fold(BlockBounds::EMPTY, |all, f| all.union(&BlockBounds::of(f)));
                let mut contacts = Contacts {
                    found,
                    ..Contacts::default()
                };
                if stacked {
                    contacts.gather_in_order(bounds, &ctx, height);
                } else {
                    contacts.gather_in_order(bounds, &ctx, |c: &Contact| c.ids);
                }
                assert_eq!(
                    contacts.list,
                    expected,
                    "{count} contacts over {span_x} × {span_y} blocks, stacked {stacked}, {} threads",
                    exec.threads()
                );
            }
        }
    }
}
