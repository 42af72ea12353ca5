//! Detection's kernel: the law's test on a block of candidates, pair by pair, with the
//! squared-distance screen, the contacts emitted with their order keys.

use crate::broadphase::{Pair, Strays};
use crate::context::StepContext;
use crate::law::{may_touch, sqrt_limit, touching};
use crate::parallel::prefetch;
use crate::particles::Particles;

use super::Contact;

/// [`detect_with`] with the loop for this world's case: one per case, so the common ones (no
/// minimum image; all radii equal, `uniform`, when the collision distance is one constant
/// with the same bits; no strays) do no extra work. Pairs with a stray in them are left to
/// [`Contacts::stray_contacts`].
///
/// # Safety
/// Every index in `candidates` is below `p.len()`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn detect(
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
            detect_skipping(candidates, p, key_of, ctx, uniform, |_, _| false, emit)
        } else {
            let skip = |i: usize, j: usize| strays.contains(i) || strays.contains(j);
            detect_skipping(candidates, p, key_of, ctx, uniform, skip, emit)
        }
    }
}

/// [`detect`] for one way of skipping pairs.
///
/// # Safety
/// Every index in `candidates` is below `p.len()`.
#[inline(always)]
unsafe fn detect_skipping(
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
            (false, Some(d)) => {
                detect_with::<true>(candidates, p, key_of, skip, emit, plain, |_, _| d)
            }
            (true, Some(d)) => {
                detect_with::<true>(candidates, p, key_of, skip, emit, image, |_, _| d)
            }
            (false, None) => detect_with::<false>(candidates, p, key_of, skip, emit, plain, pair),
            (true, None) => detect_with::<false>(candidates, p, key_of, skip, emit, image, pair),
        }
    }
}

/// Tests candidate pairs with the seed's rule, giving each contact (lower id first) to
/// `emit` with the index of its candidate, in candidate order; returns the largest overlap.
/// `diff` is `p1 - p2` (the minimum image in a periodic box), `reach` the collision distance
/// of a pair, and pairs `skip` accepts (checked only for those that pass the screen) are
/// left out. `key_of(k, x, y)` gives a contact's order key from its candidate's index `k`
/// (always below `candidates.len()`) and its lower-id disc's position.
///
/// # Safety
/// Every index in `candidates` is below `p.len()`.
#[inline(always)]
unsafe fn detect_with<const UNIFORM: bool>(
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
