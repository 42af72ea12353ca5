//! Broadphase: which pairs may collide, found in O(N) and kept for several steps.
//!
//! | file | owns |
//! |---|---|
//! | `levels.rs` | levels by interaction diameter (merged where sparse), each level's grid and cell size |
//! | `sort.rs` | the stable counting sort into cell order, the blocks of cell rows |
//! | `listing.rs` | candidate listing through the grids (the stencils, cross-level scans) |
//! | `reference.rs` | reference positions and the skin: when the list must be rebuilt |
//! | `strays.rs` | the few discs past the allowance, met alone while the list is kept |
//! | `mod.rs` | the upkeep: keep, rebuild (reordering storage) or list in place |
//!
//! # Candidates with a skin
//! A rebuild lists every pair whose distance is within its collision distance plus a *skin*,
//! and records where each disc was (the *reference* positions). As long as no disc has moved
//! more than half the skin from its reference, every pair that can collide is still on the
//! list (two discs closed in by at most one skin together), so a step only tests the listed
//! candidates; the step's integration sweep measures the largest displacement and a rebuild
//! follows when it reaches the allowance. What collides, and in which order it is resolved,
//! is decided afterwards from the current state alone (see `contacts`), so when the list is
//! rebuilt changes nothing but speed.
//!
//! # Grids
//! Discs are binned into uniform grids (cell lists) with no fixed cell capacity: a stable
//! counting sort by cell index reorders the particle arrays so each cell is a contiguous run,
//! and neighbour search walks memory in order. The cell side is at least the largest
//! interaction diameter (the law's collision distance of two such discs) plus the skin, so every candidate lies in
//! the 3×3 cells around a disc.
//!
//! # Polydisperse radii: a hierarchy of grids
//! One grid sized for the largest disc would put thousands of small discs in a cell when radii
//! span 0.1 to 5. Instead each disc gets a *level* by its interaction diameter `d`:
//! level `k` holds `d_min 2^k < d <= d_min 2^(k+1)` (level 0 includes `d_min`), and each
//! non-empty level has its own grid sized for its largest disc. A disc meets discs of its own
//! level through the 3×3 stencil, and discs of each coarser level through the at most 3×3
//! cells of that grid under its reach (coarser cells are at least that reach). Cost stays
//! proportional to the number of discs, whatever the mix.
//!
//! A grid has at most about one cell per disc, so when the small discs are few (radii
//! uniform in 0.05–5) every level's cells are far wider than its discs, about one disc
//! each. Then adjacent levels share one grid ([`levels::merge`], while it holds at most 1.5
//! discs per cell): a disc tests as many neighbours as in its own level's grid, and no
//! coarser grids are scanned. Such a merged level cuts each pair at its own collision
//! distance plus the skin (not at its largest disc's), so two small discs in a large
//! disc's cell are listed only when they are near each other.
//!
//! # Ownership and blocks
//! Each candidate pair is listed once, by one cell: the cell of the finer disc, or for discs
//! of one level, the cell visited first by the forward half-stencil. Cells are grouped into
//! blocks of whole rows, about a thousand discs each: the units of parallel work, each one
//! run of storage, so candidates are listed and later tested in storage order.
//!
//! # Open worlds
//! Cell coordinates are clamped to the grid (wrapped, in a periodic box). Clamping never
//! increases the distance between two cell coordinates, so partners stay within one cell of
//! each other and the stencil argument holds. An open world's grid covers the bulk of its
//! discs (around the median position, capped at about one cell per disc); discs far away pile
//! into edge cells, which costs time but never misses a pair.

mod levels;
mod listing;
mod reference;
mod sort;
mod strays;

use std::cell::RefCell;

pub(crate) use levels::{floor_to_isize, wrap_index};
pub(crate) use reference::{Moved, Reference};
pub(crate) use strays::{Strays, max_strays};

use crate::context::StepContext;
use crate::particles::{ParticleId, Particles, PermuteScratch, ordered};
use levels::{Discs, LevelGrid};
use reference::Skin;
use sort::Block;

/// A pair of storage indices.
pub(crate) type Pair = [u32; 2];

/// Each block keeps its candidates in this many bands by how near they were to colliding
/// when listed (see [`Bands`]).
pub(crate) const BANDS: usize = 2;

/// A block's candidates in two bands: the near one holds the pairs whose distance at the
/// listing was at most their collision distance plus half the skin, the far one the rest.
/// Two discs close in by at most the sum of their displacements, so while every disc is
/// within a quarter of the skin of its reference position, no far pair can collide:
/// detection tests only the bands the displacements reach ([`Broadphase::bands_within`]).
/// In a gas that skips the far band (about 40 % of the candidates) for the first half of
/// the steps between rebuilds; in a resting pile, whose discs hardly move, nearly always
/// (the next-nearest neighbours, √3 diameters apart, are all far).
pub(crate) type Bands = [Vec<Pair>; BANDS];

/// The grids, the blocks and the candidate pairs of the last rebuild.
#[derive(Debug, Default)]
pub(crate) struct Broadphase {
    grids: Vec<LevelGrid>,
    /// Global cell `c` holds storage indices `cell_start[c]..cell_start[c + 1]`.
    cell_start: Vec<u32>,
    blocks: Vec<Block>,
    /// Candidate pairs listed by each block, in bands. Written only here: every index is
    /// below `count`, which detection's unchecked reads rely on.
    candidates: Vec<Bands>,
    /// The width of a band at the last listing (half its margin).
    band_width: f64,
    /// A bound on the rounding of the listing's distances (a billionth of its longest cut).
    band_slop: f64,
    pub(crate) reference: Reference,
    /// Whether `candidates` were listed for `reference` (not so after loading a world).
    listed: bool,
    /// Whether storage is in the cell order of the grids (after a rebuild; not after a
    /// listing in place, whose cells index a sorted copy: `order` maps them).
    in_cell_order: bool,
    /// The discs past the allowance at the last update, met alone (see `strays`).
    strays: Strays,
    /// How much of the list's life the last update found used (1: it is listed anew).
    worn: f64,
    /// The number of discs at the last listing.
    count: usize,
    /// Counts the listings: a list made for other storage indices has another number.
    generation: u64,
    /// The largest radius at the last rebuild.
    max_radius: f64,
    /// Whether every disc had the same radius at the last rebuild.
    uniform_radius: bool,
    /// Whether a position was infinite at the last rebuild. A disc whose position overflows
    /// has moved infinitely far from its reference, so the next update always rebuilds and
    /// sees it, at no cost to the steps in between.
    overflowed: bool,
    // Scratch reused between rebuilds (the cell keys live in `scratch`).
    order: Vec<u32>,
    /// Per-disc level; empty when all discs share level 0.
    level_of: Vec<u8>,
    f64_scratch: RefCell<Vec<f64>>,
    scratch: PermuteScratch,
}

impl Broadphase {
    /// The largest radius at the last rebuild: what the contact order's grid is sized for.
    pub(crate) fn max_radius(&self) -> f64 {
        self.max_radius
    }

    /// The radius of every disc, when all are equal (as at the last listing): detection,
    /// resolution and measurement then read one number instead of an array.
    pub(crate) fn uniform_radius(&self) -> Option<f64> {
        (self.listed && self.uniform_radius).then_some(self.max_radius)
    }

    /// How many grid levels the last binning used.
    #[cfg(test)]
    pub(crate) fn levels(&self) -> usize {
        self.grids.len()
    }

    /// Which listing the candidates are from (see `contacts`' presorted candidates).
    pub(crate) fn generation(&self) -> u64 {
        self.generation
    }

    /// The candidate pairs of each block, in bands: storage indices below
    /// [`Broadphase::listed_count`].
    pub(crate) fn candidates(&self) -> &[Bands] {
        &self.candidates
    }

    /// How many discs the candidates were listed for, if they are listed.
    pub(crate) fn listed_count(&self) -> Option<usize> {
        self.listed.then_some(self.count)
    }

    /// The largest squared displacement `max_kept2` of the kept discs, as far as the list's
    /// pairs can have closed in: in a Lees–Edwards box, three times the copies' slide since
    /// the listing more (a pair across the top and bottom closes by the slide itself, and a
    /// disc that crossed since is measured against the slide now, not the one it crossed
    /// at, by up to the slide each way).
    pub(crate) fn kept2(&self, max_kept2: f64, ctx: &StepContext) -> f64 {
        match ctx.geometry.slide() {
            Some(slide) => {
                let reach = max_kept2.sqrt() + 3.0 * slide.drift_since(self.reference.time);
                reach * reach
            }
            None => max_kept2,
        }
    }

    /// How many bands (from the nearest) hold every candidate that can collide, when no
    /// disc is farther than `sqrt(max_displacement2)` from its reference position (infinite
    /// or NaN: all of them).
    pub(crate) fn bands_within(&self, max_displacement2: f64) -> usize {
        // A disc is within its measured displacement of the stored (f32) reference, and
        // that within half the slack of where it was listed; two discs close in by twice
        // that. The relative margin covers the rounding of the listing's squared distances.
        let closing = 2.0 * max_displacement2.sqrt() + self.reference.slack;
        let reach = closing * (1.0 + 1e-9) + self.band_slop;
        if !(reach.is_finite() && self.band_width > 0.0) {
            return BANDS;
        }
        // Band `k` starts `k` widths beyond the collision distance.
        (1..BANDS)
            .find(|&k| k as f64 * self.band_width > reach)
            .unwrap_or(BANDS)
    }

    /// How much of the list's life the last update found used: the kept discs' largest
    /// displacement over the allowance, or the strays' count over one more than their cap,
    /// whichever is larger (at 1 the next update lists anew).
    pub(crate) fn worn(&self) -> f64 {
        self.worn
    }

    /// Whether the last rebuild met an infinite position.
    pub(crate) fn overflowed(&self) -> bool {
        self.overflowed
    }

    /// A bound on every radius: the largest at the last listing while the list stands (no
    /// disc added since), else infinite.
    pub(crate) fn radius_bound(&self) -> f64 {
        if self.listed {
            self.max_radius
        } else {
            f64::INFINITY
        }
    }

    /// Forgets the candidates and the reference: the next [`Broadphase::update`] rebuilds.
    /// Called whenever discs or the configuration change outside the step.
    pub(crate) fn invalidate(&mut self) {
        self.reference = Reference::default();
        self.listed = false;
        self.in_cell_order = false;
        self.strays = Strays::default();
        self.worn = 0.0;
        self.max_radius = f64::INFINITY;
    }

    /// Makes the candidates cover the current positions, given what the last integration
    /// measured: the discs past the allowance (strays), the largest squared displacement of
    /// the others (infinite when unknown) and the longest distance a disc moved (to size the
    /// skin), and how many contacts per disc a substep found in the last step. The list is
    /// kept while at most [`max_strays`] discs stray (see `strays`). Returns whether the
    /// storage order changed.
    pub(crate) fn update(
        &mut self,
        p: &mut Particles,
        ctx: &StepContext,
        moved: &Moved,
        contacts_per_disc: f64,
    ) -> bool {
        self.strays.clear();
        let sheared = ctx.geometry.slide().is_some();
        let max_kept2 = self.kept2(moved.max_kept2, ctx);
        // An infinite position (overflow) always rebuilds, which finds it. In a Lees–Edwards
        // box strays are not kept: their search does not slide across the top and bottom.
        let few_strays = !moved.too_many_strays
            && (!sheared || moved.strays.is_empty())
            && (moved.strays.is_empty()
                || (moved.strays.len() <= max_strays(p.len())
                    && moved.max_displacement2.is_finite()
                    && strays::worth_keeping(
                        contacts_per_disc,
                        self.reference.near_band_holds(max_kept2),
                    )));
        let kept = self.reference.positions(p.len()).is_some()
            && self.reference.covers(max_kept2)
            && few_strays;
        if kept {
            if !self.listed {
                // A loaded world: list candidates for its reference positions, keeping the
                // storage order it was saved in.
                let rx: Vec<f64> = self.reference.x.iter().map(|&v| v as f64).collect();
                let ry: Vec<f64> = self.reference.y.iter().map(|&v| v as f64).collect();
                // The stored positions are within `slack` of the true ones, twice over.
                let margin = self.reference.skin + 2.0 * self.reference.slack;
                // (A Lees–Edwards box's copies stood where they were at the listing.)
                let then = StepContext {
                    geometry: ctx.geometry.at_time(self.reference.time),
                    ..*ctx
                };
                self.list_in_place([&rx, &ry, &p.radius], &then, margin);
            }
            self.strays.set(&moved.strays, p.len());
            // How much of the list's life is used: the kept discs' share of the allowance,
            // or the strays' share of their cap.
            let allowance = self.reference.allowance();
            let cap = max_strays(p.len()) + 1;
            self.worn = f64::max(
                max_kept2.sqrt() / allowance,
                moved.strays.len() as f64 / cap as f64,
            );
            false
        } else {
            self.rebuild(p, ctx, moved.max_stride);
            self.worn = 0.0;
            true
        }
    }

    /// Bins the discs, reorders the particle arrays into cell order, lists the candidates and
    /// takes the current positions as the new reference. `stride` is how far the fastest
    /// disc moves per substep.
    pub(crate) fn rebuild(&mut self, p: &mut Particles, ctx: &StepContext, stride: f64) {
        let skin = self.bin([&p.x, &p.y, &p.radius], ctx, Skin::Stride(stride));
        p.permute(
            &self.order,
            &mut self.scratch,
            ctx.exec,
            ctx.geometry.is_periodic(),
            self.uniform_radius,
        );
        self.list([&p.x, &p.y, &p.radius], ctx, skin);
        self.overflowed = !self.reference.record(&p.x, &p.y, skin, ctx.exec);
        self.reference.time = ctx.geometry.slide().map_or(0.0, |slide| slide.time);
        self.listed = true;
        self.in_cell_order = true;
        self.count = p.len();
    }

    /// Lists candidates within `margin` for discs at `x`, `y` without reordering them: bins
    /// a sorted copy and maps the pairs back to the given order.
    pub(crate) fn list_in_place(
        &mut self,
        [x, y, radius]: [&[f64]; 3],
        ctx: &StepContext,
        margin: f64,
    ) {
        // In a Lees–Edwards box a centre pushed past the top or bottom is binned as its
        // image in the box (the stencil across the top expects the slid columns there).
        let inside: Option<[Vec<f64>; 2]> = ctx.geometry.slide().map(|_| {
            let slid: Vec<[f64; 2]> = (x.iter().zip(y))
                .map(|(&x, &y)| ctx.geometry.slid_into_box([x, y]))
                .collect();
            [0, 1].map(|k| slid.iter().map(|p| p[k]).collect())
        });
        let [x, y] = inside.as_ref().map_or([x, y], |[x, y]| [&x[..], &y[..]]);
        self.bin([x, y, radius], ctx, Skin::Fixed(margin));
        let gather =
            |v: &[f64]| -> Vec<f64> { self.order.iter().map(|&i| v[i as usize]).collect() };
        let (sx, sy, sr) = (gather(x), gather(y), gather(radius));
        self.list([&sx, &sy, &sr], ctx, margin);
        let order = &self.order;
        for pairs in self.candidates.iter_mut().flatten() {
            for pair in pairs.iter_mut() {
                *pair = pair.map(|k| order[k as usize]);
            }
        }
        self.listed = true;
        self.in_cell_order = false;
        self.count = x.len();
    }

    /// Levels, grids, the stable counting sort into `order` (new index `k` holds old index
    /// `order[k]`) and the blocks, for discs at `x`, `y`, with cells sized for the skin.
    /// Returns the skin.
    fn bin(&mut self, [x, y, radius]: [&[f64]; 3], ctx: &StepContext, skin: Skin) -> f64 {
        self.grids.clear();
        self.blocks.clear();
        self.order.clear();
        self.cell_start.clear();
        self.cell_start.push(0);
        self.max_radius = 0.0;
        if radius.is_empty() {
            // No discs (all removed by a sink, say): no blocks, no candidates.
            self.candidates.clear();
            return 0.0;
        }
        // 1. Levels: a band of interaction diameters each.
        let (mut levels, [r_min, r_max]) = levels::assign(radius, &ctx.law, &mut self.level_of);
        self.max_radius = r_max;
        self.uniform_radius = r_min == r_max;
        let skin = skin.width(&ctx.law, levels[0].max_radius, r_max);
        // Levels whose grids would all be about one disc per cell share one.
        let extent = levels::extent([x, y], ctx);
        levels::merge(&mut levels, &mut self.level_of, &ctx.law, skin, extent);

        // 2. One grid per level.
        let discs = Discs {
            level_of: &self.level_of,
            scratch: &self.f64_scratch,
        };
        let mut cell_offset = 0;
        for &level in &levels {
            let grid = levels::level_grid([x, y], extent, ctx, skin, level, cell_offset, &discs);
            cell_offset += grid.n[0] * grid.n[1];
            self.grids.push(grid);
        }

        // 3. The counting sort (its keys in the permutation scratch) and 4. the blocks.
        let extra = sort::scratch_for_counts(radius.len(), cell_offset, ctx.exec);
        let keys = self.scratch.u32s_and_room(radius.len(), extra);
        sort::counting_sort(
            &self.grids,
            &self.level_of,
            x,
            y,
            keys,
            &mut self.cell_start,
            &mut self.order,
            ctx.exec,
        );
        sort::blocks(&self.grids, &levels, &mut self.blocks);
        self.candidates
            .resize_with(self.blocks.len(), Bands::default);
        self.candidates.truncate(self.blocks.len());
        skin
    }

    /// Lists the candidates of discs in the cell order of the last `bin`.
    fn list(&mut self, discs: [&[f64]; 3], ctx: &StepContext, margin: f64) {
        self.generation += 1;
        self.band_width = margin / BANDS as f64;
        self.band_slop = 1e-9 * (ctx.law.interaction_diameter(self.max_radius) + margin);
        listing::list_candidates(
            &self.grids,
            &self.cell_start,
            &self.blocks,
            discs,
            ctx,
            margin,
            &mut self.candidates,
        );
    }
}

/// Every pair within the collision distance by testing all N(N-1)/2 pairs: the oracle the
/// grid is tested against. Returns sorted id pairs.
pub(crate) fn brute_force_pairs(p: &Particles, ctx: &StepContext) -> Vec<(ParticleId, ParticleId)> {
    let min_image = ctx.geometry.min_image();
    let mut out = Vec::new();
    for a in 0..p.len() {
        for b in a + 1..p.len() {
            let diff = min_image.diff(p.x[a], p.y[a], p.x[b], p.y[b]);
            if ctx.law.is_colliding(diff, p.radius[a], p.radius[b]) {
                out.push(ordered(p.id[a], p.id[b]));
            }
        }
    }
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parallel::Executor;
    use crate::{Boundary, Config};

    /// Every listed pair, by storage indices, with its band.
    fn listed(bp: &Broadphase) -> Vec<(Pair, usize)> {
        let mut out: Vec<(Pair, usize)> = bp
            .candidates
            .iter()
            .flat_map(|bands| {
                bands.iter().enumerate().flat_map(|(band, pairs)| {
                    pairs
                        .iter()
                        .map(move |&[a, b]| ([a.min(b), a.max(b)], band))
                })
            })
            .collect();
        out.sort_unstable();
        out
    }

    #[test]
    fn a_merged_level_cuts_each_pair_at_its_own_distance() {
        // Four large discs and three small ones in a 100 × 100 box: every level's grid would
        // be nearly empty, so they share one, with cells for the large discs. The small
        // discs' pairs are still cut at 0.2 + margin (and banded at 0.2 + margin / 2), not
        // at the large discs' 10 + margin.
        let config = Config {
            boundary: Boundary::walls([0.0, 0.0], [100.0, 100.0]),
            ..Config::default()
        };
        let exec = Executor::default();
        let ctx = StepContext::new(&config, 0.1, &exec, None);
        let margin = 0.15;
        let x = [10.0, 30.0, 50.0, 70.0, 50.0, 50.0 + 0.3, 50.0 - 0.34, 50.0];
        let y = [10.0, 10.0, 80.0, 10.0, 50.0, 50.0, 50.0, 50.4];
        let radius = [5.0, 5.0, 5.0, 5.0, 0.1, 0.1, 0.1, 0.1];
        let mut bp = Broadphase::default();
        bp.list_in_place([&x, &y, &radius], &ctx, margin);
        assert_eq!(bp.grids.len(), 1, "the levels share one grid");
        assert!(bp.grids[0].pairwise);
        // 4–5: 0.3 apart, past 0.2 + 0.075: far band. 4–6: 0.34 ≤ 0.35: far. 4–7: 0.4 >
        // 0.35: not listed, though well within the large discs' reach. 5–6 (0.64) and the
        // rest are farther still; no large disc is within reach of another or a small one.
        assert_eq!(listed(&bp), vec![([4, 5], 1), ([4, 6], 1)]);
        let near = [50.0 + 0.27];
        let x2 = [&x[..5], &near[..]].concat();
        bp.list_in_place([&x2, &y[..6], &radius[..6]], &ctx, margin);
        // 0.27 ≤ 0.275: near.
        assert_eq!(listed(&bp), vec![([4, 5], 0)]);
    }
}
