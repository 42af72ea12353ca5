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
//! The sweep is cut into bands of block rows resolved in parallel, each band but for its
//! first odd row, which all go after (see `split`). The 1% margin on the cell side absorbs
//! rounding in the cell coordinates, whose magnitude is capped at 2^30 cells.

use std::ops::Range;

use crate::broadphase::{BANDS, Broadphase, Pair, Strays, floor_to_isize, wrap_index};
use crate::context::StepContext;
use crate::geometry::{Geometry, OrderAxisFrame};
use crate::law::{Law, may_touch, sqrt_limit, touching};
use crate::parallel::{SharedSlice, prefetch};
use crate::part::Tally;
use crate::particles::{ParticleId, Particles, ordered};

/// Order-grid cells are this much wider than the largest collision distance.
const CELL_MARGIN: f64 = 1.01;
/// Cell coordinates of a grid without a periodic box are clamped to `±2^30`.
const HALF_RANGE: isize = 1 << 30;
/// The sweep is cut into bands of about this many contacts for parallel resolution.
const CONTACTS_PER_PIECE: usize = 256;
/// At most this many bands.
const MAX_PIECES: usize = 128;

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
#[derive(Debug, Default)]
pub(crate) struct Contacts {
    /// Contacts found per candidate block, before sorting.
    found: Vec<Vec<Contact>>,
    /// All contacts in canonical order.
    pub(crate) list: Vec<Contact>,
    /// Runs of `list` of one colour in one block row: whole blocks that touch disjoint
    /// discs.
    pub(crate) segments: Vec<Range<usize>>,
    /// Work that may be resolved in parallel with the other pieces of its phase: ranges of
    /// `segments`, resolved in order.
    pub(crate) pieces: Vec<[Range<usize>; 2]>,
    /// Ranges of `pieces`, resolved one after the other: the bands, then their first odd
    /// rows.
    pub(crate) phases: Vec<Range<usize>>,
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

/// The near band's candidates in canonical order: each pair lower id first, in the order
/// their contacts take (block of the lower-id disc when sorted, then ids). Contacts then
/// come out of the test in order, but for the few whose lower-id disc has since moved to
/// another block.
#[derive(Debug, Default)]
struct Presorted {
    /// The broadphase listing these were made from (`None`: none yet).
    generation: Option<u64>,
    pairs: Vec<Pair>,
    /// The blocks: the key their contacts have while in place, and where their pairs end.
    blocks: Vec<(u64, u32)>,
    /// Each block's span ([`OrderGrid::span`]): a lower-id disc inside it is in place,
    /// without working out its key.
    spans: Vec<[f64; 4]>,
    /// Chunks of whole blocks tested in parallel: ranges of `blocks`.
    chunks: Vec<Range<usize>>,
}

/// Discs a task keys for the presort.
const KEY_CHUNK: usize = 16 * crate::parallel::CHUNK;
/// Blocks of presorted candidates tested together: about this many candidates.
const CANDIDATES_PER_CHUNK: usize = 16384;
/// Candidates are presorted once this many detections have tested them: sorting them costs
/// a few detections' sorts, worth it only for lists that last (a resting pile keeps one for
/// dozens of substeps; a fast gas lists anew every step or two).
const DETECTIONS_BEFORE_PRESORT: u32 = 3;
/// A new list is presorted at once when the one before it was tested more often than this:
/// lists last about as long as the one before.
const LASTING_LISTING_USES: u32 = 4 * DETECTIONS_BEFORE_PRESORT;
/// Contacts are dense (a pile: the candidates are worth keeping in canonical order) when
/// at least this share of the candidates tested collide. A gas has about 1.5 %, a pile 35 %.
const DENSE_SHARE: f64 = 0.125;

/// The order-grid blocks contacts fall in: their waves and columns, lowest and highest.
#[derive(Clone, Copy, Debug, PartialEq)]
struct BlockBounds {
    waves: [u64; 2],
    columns: [u64; 2],
}

/// The bits of a block column in a contact's key (columns are below 2^30).
const COLUMN_BITS: u64 = (1 << 31) - 1;

/// The wave of a key: its block row rounded up to even (colours 2 and 3 of an odd row come
/// after colours 0 and 1 of the next row).
fn wave_of(key: u64) -> u64 {
    key >> 33
}

/// 0 for the colours of even block rows (0, 1), 1 for those of odd ones (2, 3).
fn row_parity_of(key: u64) -> u64 {
    (key >> 32) & 1
}

fn column_of(key: u64) -> u64 {
    key & COLUMN_BITS
}

/// The key of block `(column, row)` in the wave order: wave, row parity, column parity,
/// column.
fn block_key(column: u64, row: u64) -> u64 {
    let parity = row & 1;
    ((row + parity) << 33) | (parity << 32) | ((column & 1) << 31) | column
}

/// The segment of a key: its wave, row parity and colour.
fn segment_of(key: u64) -> u64 {
    key >> 31
}

impl BlockBounds {
    /// Bounds of no contact (any union replaces them).
    const EMPTY: BlockBounds = BlockBounds {
        waves: [u64::MAX, 0],
        columns: [u64::MAX, 0],
    };

    fn of(contacts: &[Contact]) -> BlockBounds {
        contacts.iter().fold(BlockBounds::EMPTY, |b, c| {
            let (wave, column) = (wave_of(c.key), column_of(c.key));
            BlockBounds {
                waves: [b.waves[0].min(wave), b.waves[1].max(wave)],
                columns: [b.columns[0].min(column), b.columns[1].max(column)],
            }
        })
    }

    fn union(self, other: &BlockBounds) -> BlockBounds {
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
        // Candidate indices are storage indices of this many discs (the list is rebuilt
        // whenever discs are added or reordered): what `test` relies on.
        assert_eq!(
            broadphase.listed_count(),
            Some(p.len()),
            "stale candidate list"
        );
        let bands = bands.clamp(1, BANDS);
        let tested: usize = broadphase
            .candidates
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
        let candidates = &broadphase.candidates;
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
                    let tested = unsafe { test_case(pairs, p, key, ctx, uniform, strays, emit) };
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

    /// Puts the near band's candidates in canonical order, once per listing: each pair
    /// lower id first, by the block of its lower-id disc now (the listing's positions) and
    /// its ids, the order their contacts take as long as that disc stays in its block.
    fn presort(
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
        let candidates = &broadphase.candidates;
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
    fn find_presorted(
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
                let key = |k: usize, x: f64, y: f64| {
                    debug_assert!(first + k < blocks.last().map_or(0, |b| b.1 as usize));
                    debug_assert_eq!(blocks.len(), spans.len());
                    // SAFETY: candidate `k` of `pairs` lies in one of the chunk's blocks, and
                    // the last of them ends `pairs`: the walk stops within `blocks` (and
                    // `spans`, one a block).
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
                unsafe { test_case(pairs, p, key, ctx, uniform, strays, emit) }
            });
        let mut max_overlap = overlaps.into_iter().fold(0.0, f64::max);
        far.clear();
        if bands > 1 {
            let candidates = &broadphase.candidates;
            let work = candidates.iter().map(|b| b[1].len()).sum();
            let tested = ctx.exec.map_index(work, 0..candidates.len(), |block| {
                let mut found = Vec::new();
                // SAFETY: as above.
                let overlap = unsafe {
                    test_case(
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
    /// by more than four to one (a dilute gas) the contacts are counted into their segments
    /// (one colour of one block row) instead and each segment sorted by key; where even
    /// segments do, a comparison sort does it all.
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
        let segment = move |c: &Contact| -> u64 {
            (wave_of(c.key) - wave_min) / 2 * 4 + row_parity_of(c.key) * 2 + (column_of(c.key) & 1)
        };
        // Counting costs a pass over the buckets as well as the contacts: one bucket per
        // block where there are few blocks per contact (a pile); else one per segment (one
        // colour of one block row: the 1M gas has 22,000 contacts in 3,200 segments, against
        // 1.3 million blocks), each then sorted by key; else a comparison sort.
        let few = |buckets: u64| buckets <= 4 * total as u64 + 1024;
        let blocks = waves.saturating_mul(4).saturating_mul(width);
        if few(blocks) {
            // Buckets in key order: wave, row parity, column parity, column.
            let block =
                |c: &Contact| (segment(c) * width + (column_of(c.key) / 2 - column_min)) as usize;
            self.bucket_sort(blocks as usize, block, &within, ctx);
        } else if few(waves.saturating_mul(4)) {
            let by_key = |c: &Contact| (c.key, within(c));
            self.bucket_sort(waves as usize * 4, |c| segment(c) as usize, &by_key, ctx);
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
            // of the found lists counting into its own buckets: see `place_in_parts`.
            place_in_parts(&self.found, parts, buckets, &bucket, starts, spare, ctx);
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
    fn split(&mut self) {
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
    fn halves_of(&self, range: Range<usize>) -> [Range<usize>; 2] {
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

/// [`Contacts::bucket_sort`]'s counting and placing on `parts` threads: the found lists are
/// cut into `parts` runs of about equal contacts, each run counts its contacts into
/// `buckets` counts of its own, each bucket's slots go to the runs in order, and each run
/// places its own contacts into `spare` (every slot of which is written). Afterwards
/// `starts[b]` holds the end of bucket `b`, as after the serial placement, and every bucket
/// holds the same contacts in the same order (the runs' in turn, each in its lists' order).
fn place_in_parts(
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

/// Sorts one block's contacts by `within` (short runs: insertion sort; long ones, as in a
/// dense block of a polydisperse world, the standard sort).
fn sort_block<K: Ord>(block: &mut [Contact], within: &impl Fn(&Contact) -> K) {
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
fn from_ordered_bits(u: u64) -> f64 {
    if u >> 63 == 1 {
        f64::from_bits(u & !(1 << 63))
    } else {
        f64::from_bits(!u)
    }
}

/// [`test`] with the loop for this world's case: one per case, so the common ones (no
/// minimum image; all radii equal, `uniform`, when the collision distance is one constant
/// with the same bits; no strays) do no extra work. Pairs with a stray in them are left to
/// [`Contacts::stray_contacts`].
///
/// # Safety
/// Every index in `candidates` is below `p.len()`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn test_case(
    candidates: &[Pair],
    p: &Particles,
    key_of: impl FnMut(usize, f64, f64) -> u64,
    ctx: &StepContext,
    uniform: Option<f64>,
    strays: &Strays,
    emit: impl FnMut(usize, Contact),
) -> f64 {
    // SAFETY: the caller's promise.
    unsafe {
        if strays.is_empty() {
            test_kind(candidates, p, key_of, ctx, uniform, |_, _| false, emit)
        } else {
            let skip = |i: usize, j: usize| strays.contains(i) || strays.contains(j);
            test_kind(candidates, p, key_of, ctx, uniform, skip, emit)
        }
    }
}

/// [`test_case`] for one way of skipping pairs.
///
/// # Safety
/// Every index in `candidates` is below `p.len()`.
#[inline(always)]
unsafe fn test_kind(
    candidates: &[Pair],
    p: &Particles,
    key_of: impl FnMut(usize, f64, f64) -> u64,
    ctx: &StepContext,
    uniform: Option<f64>,
    skip: impl Fn(usize, usize) -> bool,
    emit: impl FnMut(usize, Contact),
) -> f64 {
    let law = ctx.law;
    let min_image = ctx.geometry.min_image();
    let plain = |x1: f64, y1: f64, x2: f64, y2: f64| [x1 - x2, y1 - y2];
    let image = |x1, y1, x2, y2| min_image.diff(x1, y1, x2, y2);
    let pair = |i: usize, j: usize| {
        // SAFETY: every candidate index is below `p.len()` (the callers' promise), the
        // radii's length.
        unsafe { law.collision_distance(*p.radius.get_unchecked(i), *p.radius.get_unchecked(j)) }
    };
    let uniform = uniform
        .map(|r| law.collision_distance(r, r))
        .filter(|d| d.is_finite());
    // SAFETY: the caller's promise.
    unsafe {
        match (min_image.is_periodic(), uniform) {
            (false, Some(d)) => test::<true>(candidates, p, key_of, skip, emit, plain, |_, _| d),
            (true, Some(d)) => test::<true>(candidates, p, key_of, skip, emit, image, |_, _| d),
            (false, None) => test::<false>(candidates, p, key_of, skip, emit, plain, pair),
            (true, None) => test::<false>(candidates, p, key_of, skip, emit, image, pair),
        }
    }
}

/// Writes into `list` the merge of the runs of `found` (each in canonical order, and so is
/// their concatenation) with `moved` (in canonical order), in parallel: each run takes the
/// moved contacts that fall before the next run's first, found by binary search, so the
/// runs' places in `list` are known before any is written. (Against one serial merge, the
/// settled 100k pile's detection is 6–14 % faster on two threads, and its resolution too:
/// each core then resolves contacts it wrote itself.)
fn merge_sorted(
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
/// A pile's segments are a few hundred contacts of a list of a hundred thousand: bisecting
/// the whole rest for each missed the cache at nearly every probe, while these stay near
/// `from`, in order.
fn prefix_end<T>(items: &[T], from: usize, holds: impl Fn(&T) -> bool) -> usize {
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

/// Tests candidate pairs with the seed's rule, giving each contact (lower id first) to
/// `emit` with the index of its candidate, in candidate order; returns the largest overlap.
/// `diff` is `p1 - p2` (the minimum image in a periodic box), `reach` the collision distance
/// of a pair, and pairs `skip` accepts (checked only for those that pass the screen) are
/// left out.
///
/// # Safety
/// Every index in `candidates` is below `p.len()`.
#[inline(always)]
unsafe fn test<const UNIFORM: bool>(
    candidates: &[Pair],
    p: &Particles,
    mut key_of: impl FnMut(usize, f64, f64) -> u64,
    skip: impl Fn(usize, usize) -> bool,
    mut emit: impl FnMut(usize, Contact),
    diff: impl Fn(f64, f64, f64, f64) -> [f64; 2],
    reach: impl Fn(usize, usize) -> f64,
) -> f64 {
    let mut max_overlap = 0.0f64;
    // With one collision distance for every pair, the seed's test `sqrt(d2) <= reach` is
    // `d2 <= limit` for one limit (no square root per pair, whose latency dominated the
    // test), and the largest overlap is that of the nearest pair.
    let limit = if UNIFORM {
        sqrt_limit(reach(0, 0))
    } else {
        0.0
    };
    let mut nearest2 = f64::INFINITY;
    let (x, y, id) = (&p.x[..], &p.y[..], &p.id[..]);
    // Screen: the candidates within the squared reach (with a margin), written branch-free
    // (in a pile a third of the candidates collide, at random: a branch there mispredicts
    // often). Each chunk's survivors are then given the seed's exact test.
    const SCREEN: usize = 256;
    /// Hits are sparse, their ids worth asking for ahead, when at most one candidate in this
    /// many is one: in a gas about one in 50, in a pile one in 3.
    const SPARSE_HITS: usize = 8;
    let mut hits = [0u16; SCREEN];
    for (c, chunk) in candidates.chunks(SCREEN).enumerate() {
        let mut n = 0;
        for (k, &[i, j]) in chunk.iter().enumerate() {
            let (i, j) = (i as usize, j as usize);
            debug_assert!(i < x.len() && j < x.len());
            // SAFETY: in bounds by the caller's promise; every particle array has `p.len()`.
            let (xi, yi, xj, yj) = unsafe {
                (
                    *x.get_unchecked(i),
                    *y.get_unchecked(i),
                    *x.get_unchecked(j),
                    *y.get_unchecked(j),
                )
            };
            let [dx, dy] = diff(xi, yi, xj, yj);
            let d2 = dx * dx + dy * dy;
            debug_assert!(n <= k && k < SCREEN);
            // SAFETY: `n` counts hits among the `k` candidates before this one, and a chunk
            // holds at most `SCREEN`: `n <= k < SCREEN`.
            unsafe { *hits.get_unchecked_mut(n) = k as u16 };
            n += if UNIFORM {
                d2 <= limit
            } else {
                may_touch(d2, reach(i, j))
            } as usize;
        }
        if n <= SCREEN / SPARSE_HITS {
            // Few hits (a gas): their ids were never read and are far from cache, so ask for
            // them all first and let the misses overlap. (In a pile they are in cache.)
            for &k in &hits[..n] {
                for i in chunk[k as usize] {
                    prefetch(id.as_ptr().wrapping_add(i as usize));
                }
            }
        }
        for &k in &hits[..n] {
            // SAFETY: `k < chunk.len()` (a place the screen wrote), and the indices are in
            // bounds as above.
            let [i, j] = unsafe { *chunk.get_unchecked(k as usize) };
            let (i, j) = (i as usize, j as usize);
            if skip(i, j) {
                continue;
            }
            // SAFETY: `i` and `j` are candidate indices, below the arrays' length.
            let (at_i, at_j) = unsafe {
                (
                    [*x.get_unchecked(i), *y.get_unchecked(i)],
                    [*x.get_unchecked(j), *y.get_unchecked(j)],
                )
            };
            let [dx, dy] = diff(at_i[0], at_i[1], at_j[0], at_j[1]);
            if UNIFORM {
                // The screen was the exact test; the same bits give the same distance.
                // (Neither is ever NaN here: a NaN distance fails the screen.)
                let d2 = dx * dx + dy * dy;
                nearest2 = if d2 < nearest2 { d2 } else { nearest2 };
            } else {
                // The seed's exact test on the distance itself.
                let Some(overlap) = touching([dx, dy], reach(i, j)) else {
                    continue;
                };
                max_overlap = max_overlap.max(overlap);
            }
            let k = c * SCREEN + k as usize;
            // SAFETY: as above.
            let ids = unsafe { [*id.get_unchecked(i), *id.get_unchecked(j)] };
            let contact = Contact::of_values([i, j], ids, [at_i, at_j], |x, y| key_of(k, x, y));
            emit(k, contact);
        }
    }
    if UNIFORM && nearest2 < f64::INFINITY {
        // `reach - sqrt(d2)` falls as `d2` grows (both roundings are monotone), so the
        // nearest pair's overlap is the largest, bit for bit.
        max_overlap = max_overlap.max(reach(0, 0) - nearest2.sqrt());
    }
    max_overlap
}

/// The order grid along one axis.
#[derive(Clone, Copy, Debug)]
struct OrderAxis {
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
    fn span(&self, b: u64) -> [f64; 2] {
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
fn cell_width(law: &Law, max_radius: f64) -> f64 {
    // The same bits as `CELL_MARGIN * 2.0 * max_radius * collision_radius_scale`.
    law.reach(CELL_MARGIN * 2.0 * max_radius)
}

/// The order grid's cell width for discs up to `max_radius` under `config` (a periodic box
/// rounds it up to fit a whole number of cells): how far a contact reaches, and the unit in
/// which a distributed run measures its ghost layers.
pub fn order_cell_width(config: &crate::Config, max_radius: f64) -> f64 {
    cell_width(&Law::new(config), max_radius)
}

/// Where the order block holding coordinate `v` along `axis` (0: x, 1: y) begins, for discs
/// up to `max_radius` under `config`: a distributed run cuts its domains there, so each
/// block's contacts are resolved and counted by one rank.
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
pub(crate) struct OrderGrid([OrderAxis; 2]);

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
    use crate::{Boundary, Config};

    fn order_grid(config: &Config, max_radius: f64) -> OrderGrid {
        OrderGrid::new(&Geometry::new(config), &Law::new(config), max_radius)
    }

    /// A 31-bit pseudo-random number generator (a linear congruential one's high bits).
    fn random(seed: u64) -> impl FnMut() -> u64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        }
    }

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
        // columns in few rows (buckets per segment), many of both (the comparison sort).
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
