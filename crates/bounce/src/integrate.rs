//! Time integration: semi-implicit (symplectic) Euler with uniform gravity, then the boundary.
//!
//! `v += g h; x += v h` for each disc, and the boundary applied right after it moves, in one
//! sweep over memory. The same sweep measures how far each disc now is from its broadphase
//! reference position, so checking the candidate list costs no extra sweep, and notes the
//! discs past the list's allowance (the broadphase's strays) without a branch. It runs over fixed chunks; the wall impulses
//! are summed exactly (`sum`), so they depend on neither the thread count nor the storage
//! order.
//!
//! The sweep is compute-bound, so the boundary and the reference check are chosen once per
//! sweep, not per disc, their constants are copied into each chunk's frame (kept in
//! registers), and walls only read a disc's radius and mass when it is outside inner bounds
//! a largest radius (and a little more) from each wall. Outside a periodic box, with a
//! reference, two discs go through the sweep at a time in the lanes of `F64x2` (the scalar
//! operations in each lane, so the same bits; the boundary per disc only for a pair with a
//! disc outside the inner bounds): a third less time for the stage, in cache and out.

use crate::broadphase::{Moved, Reference, max_strays};
use crate::context::StepContext;
use crate::geometry::{Geometry, MinImage, wrap};
use crate::lanes::{F64x2, Lanes, max_skipping_nan};
use crate::law::{Rough, reflect, rub_walls};
use crate::parallel::{CHUNK, Executor, SharedSlice};
use crate::particles::Particles;
use crate::sum::WallSums;

/// One chunk of the arrays a sweep writes, and the index of its first disc.
struct Chunk<'a> {
    base: usize,
    x: &'a mut [f64],
    y: &'a mut [f64],
    vx: &'a mut [f64],
    vy: &'a mut [f64],
    image: &'a mut [[i32; 2]],
}

/// Advances every disc by `ctx.h`, applies the boundary, and measures displacements from
/// `reference`. `max_radius` bounds every radius (infinite when unknown).
pub(crate) fn integrate(
    p: &mut Particles,
    ctx: &StepContext,
    reference: &Reference,
    max_radius: f64,
) -> Moved {
    let n = p.len();
    // A disc this far from its reference is a stray (`covers` fails from here on).
    let allowance = reference.allowance();
    let stray2 = if allowance > 0.0 {
        allowance * allowance
    } else {
        f64::INFINITY
    };
    let reference = reference.positions(n);
    let law = ctx.law;
    let tally = ctx.tally;
    let (radius, mass) = (&p.radius, &p.mass);
    // Rough walls turn the discs that bounce (each chunk its own).
    let rubbing = law.rough.filter(|rough| rough.rubs_walls());
    let omega = &SharedSlice::new(&mut p.omega);
    let mut chunks: Vec<Chunk> =
        p.x.chunks_mut(CHUNK)
            .zip(p.y.chunks_mut(CHUNK))
            .zip(p.vx.chunks_mut(CHUNK))
            .zip(p.vy.chunks_mut(CHUNK))
            .zip(p.image.chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, ((((x, y), vx), vy), image))| Chunk {
                base: c * CHUNK,
                x,
                y,
                vx,
                vy,
                image,
            })
            .collect();
    let sweep = Sweep {
        gravity: ctx.gravity,
        h: ctx.h,
        min_image: ctx.geometry.min_image(),
        reference,
        stray2,
    };
    let chunks = &mut chunks[..];
    let exec = ctx.exec;
    let partial = match ctx.geometry {
        Geometry::Open => sweep.run(
            exec,
            chunks,
            Some(([f64::NEG_INFINITY; 2], [f64::INFINITY; 2])),
            #[inline(always)]
            |_, _, _, _| {},
        ),
        Geometry::Periodic {
            min,
            size,
            slide: Some(slide),
            ..
        } => sweep.run(
            exec,
            chunks,
            None,
            #[inline(always)]
            move |_, [x, y, vx, _], image, _| {
                let crossed = slide.wrap([x, y, vx], min, size);
                image[0] = image[0].wrapping_add(crossed[0]);
                image[1] = image[1].wrapping_add(crossed[1]);
            },
        ),
        Geometry::Periodic { min, size, .. } => sweep.run(
            exec,
            chunks,
            None,
            #[inline(always)]
            move |_, [x, y, _, _], image, _| {
                image[0] = image[0].wrapping_add(wrap(x, min[0], size[0]));
                image[1] = image[1].wrapping_add(wrap(y, min[1], size[1]));
            },
        ),
        Geometry::Walls {
            min,
            max,
            restitution: e,
        } => {
            let e = law.restitution_of(e);
            // Radii are at most `max_radius`, so a disc whose centre is inside these bounds
            // touches no wall. They are widened by a billionth of the box's scale, far more
            // than the rounding of `reflect`'s `x - r < lo`, so they never skip a disc it
            // would move (an infinite `max_radius` sends every disc to it).
            let scale = [min, max]
                .iter()
                .flatten()
                .fold(max_radius, |s, v| s.max(v.abs()));
            let slack = 1e-9 * scale;
            let inner_min = [0, 1].map(|a| min[a] + max_radius + slack);
            let inner_max = [0, 1].map(|a| max[a] - max_radius - slack);
            sweep.run(
                exec,
                chunks,
                Some((inner_min, inner_max)),
                #[inline(always)]
                move |i, [x, y, vx, vy], _, impulse| {
                    let near = *x < inner_min[0]
                        || *x > inner_max[0]
                        || *y < inner_min[1]
                        || *y > inner_max[1];
                    if near {
                        let r = radius[i];
                        let m = law.mass(r, mass[i]);
                        let (left, right) = reflect(x, vx, r, min[0], max[0], e, m);
                        let (bottom, top) = reflect(y, vy, r, min[1], max[1], e, m);
                        if left != 0.0 || right != 0.0 || bottom != 0.0 || top != 0.0 {
                            let hits = [left, right, bottom, top];
                            record_hit(impulse, hits, [*x, *y], tally);
                            if let Some(rough) = &rubbing {
                                // SAFETY: disc `i` is this chunk's alone.
                                unsafe {
                                    rub(hits, [x, y, vx, vy], omega, i, r, m, rough, impulse, tally)
                                };
                            }
                        }
                    }
                },
            )
        }
    };
    let unknown = if reference.is_some() {
        0.0
    } else {
        f64::INFINITY
    };
    let mut moved = Moved {
        max_displacement2: unknown,
        max_kept2: unknown,
        ..Moved::default()
    };
    let mut max_speed2 = 0.0f64;
    for part in &partial {
        moved.impulse.merge(&part.impulse);
        moved.max_displacement2 = moved.max_displacement2.max(part.max_displacement2);
        moved.max_kept2 = moved.max_kept2.max(part.max_kept2);
        max_speed2 = max_speed2.max(part.max_speed2);
        match &part.strays {
            Some(strays) => moved.strays.extend_from_slice(strays),
            None => moved.too_many_strays = true,
        }
    }
    moved.too_many_strays |= moved.strays.len() > max_strays(n);
    moved.max_stride = max_speed2.sqrt() * ctx.h;
    moved
}

/// Adds a wall hit's impulses, if the tally counts the disc: out of line, so the sweep's
/// per-disc closure stays small enough to be inlined (hits are rare).
#[inline(never)]
fn record_hit(
    impulse: &mut WallSums,
    hit: [f64; 4],
    [x, y]: [f64; 2],
    tally: Option<crate::part::Tally>,
) {
    if tally.is_none_or(|t| t.counts(x, y)) {
        impulse.add(hit);
    }
}

/// Rough walls' friction on disc `i` after it bounced with `hits` ([`rub_walls`]), the
/// energy removed added to `impulse` where the tally counts the disc.
///
/// # Safety
/// No other thread touches `omega[i]` meanwhile, and `i` is in bounds.
#[allow(clippy::too_many_arguments)]
#[inline(never)]
unsafe fn rub(
    hits: [f64; 4],
    [x, y, vx, vy]: [&mut f64; 4],
    omega: &SharedSlice<f64>,
    i: usize,
    r: f64,
    m: f64,
    rough: &Rough,
    impulse: &mut WallSums,
    tally: Option<crate::part::Tally>,
) {
    let mut velocity = [*vx, *vy];
    // SAFETY: as the caller promises.
    let mut w = unsafe { omega.get(i) };
    let work = rub_walls(hits, &mut velocity, &mut w, r, m, rough);
    // SAFETY: as the caller promises.
    unsafe { omega.set(i, w) };
    [*vx, *vy] = velocity;
    if tally.is_none_or(|t| t.counts(*x, *y)) {
        impulse.friction.add(work);
    }
}

/// Each disc's orientation turned by its angular velocity over `h`, kept within one turn,
/// in fixed chunks (discs that turn only).
pub(crate) fn turn(p: &mut Particles, h: f64, exec: &Executor) {
    let mut chunks: Vec<_> = p
        .theta
        .chunks_mut(CHUNK)
        .zip(p.omega.chunks(CHUNK))
        .collect();
    exec.for_each_mut(p.x.len(), &mut chunks, |_, (theta, omega)| {
        for (theta, &w) in theta.iter_mut().zip(omega.iter()) {
            *theta = turned(*theta, w, h);
        }
    });
}

/// An orientation `theta` turned at `omega` for `h`, kept within one turn (`[0, 2π]`).
#[inline(always)]
pub(crate) fn turned(theta: f64, omega: f64, h: f64) -> f64 {
    let turned = theta + omega * h;
    // One remainder per turn, not per substep.
    if (0.0..std::f64::consts::TAU).contains(&turned) {
        turned
    } else {
        turned.rem_euclid(std::f64::consts::TAU)
    }
}

/// Stores `new` in `slot` only where its bits differ. Without gravity (along an axis) a
/// velocity changes only at a wall, so its cache line stays clean and is never written back:
/// at 10^7 discs, beyond the last-level cache, that is two of the sweep's eight streams of
/// memory traffic. The bits stored are the same either way.
#[inline(always)]
fn store_changed(slot: &mut f64, new: f64) {
    if slot.to_bits() != new.to_bits() {
        *slot = new;
    }
}

/// The squared distance of a disc at `(x, y)` from its reference, the `k`th of `rx`, `ry`,
/// outside a periodic box (the plain difference).
#[inline(always)]
fn plain_displacement2<'a>(rx: &'a [f32], ry: &'a [f32]) -> impl Fn(usize, f64, f64) -> f64 + 'a {
    move |k, x, y| {
        let (dx, dy) = (x - rx[k] as f64, y - ry[k] as f64);
        dx * dx + dy * dy
    }
}

/// A chunk with more strays than this (of [`CHUNK`] discs) rebuilds the list: strays are
/// the few, and a bunch of them in one place is better listed anew.
const CHUNK_STRAYS: usize = 64;

/// The constants of one sweep.
struct Sweep<'r> {
    gravity: [f64; 2],
    h: f64,
    min_image: MinImage,
    reference: Option<(&'r [f32], &'r [f32])>,
    /// The squared displacement that makes a disc a stray.
    stray2: f64,
}

/// What one chunk of the sweep measured.
struct ChunkMoved {
    impulse: WallSums,
    max_displacement2: f64,
    max_kept2: f64,
    max_speed2: f64,
    /// Storage indices of its strays; none if more than [`CHUNK_STRAYS`].
    strays: Option<Vec<u32>>,
}

impl ChunkMoved {
    /// What a chunk starting at disc `base` measured: its wall impulse, its largest squared
    /// displacement (all discs), that of the discs kept, its largest squared speed, and its
    /// strays' places in it (none past the cap: then the list is made anew, and no disc can
    /// be said to be within less than the largest displacement).
    fn new(
        base: usize,
        impulse: WallSums,
        [max_displacement2, max_kept2, max_speed2]: [f64; 3],
        strays: Option<&[u32]>,
    ) -> Self {
        ChunkMoved {
            impulse,
            max_displacement2,
            max_kept2: if strays.is_some() {
                max_kept2
            } else {
                max_displacement2
            },
            max_speed2,
            strays: strays.map(|strays| strays.iter().map(|&k| base as u32 + k).collect()),
        }
    }
}

impl<'r> Sweep<'r> {
    /// The sweep over the chunks, with the boundary and the reference check chosen once;
    /// per chunk the wall impulse, the largest squared displacements and speed, the strays.
    /// `inner`, when given, is a box inside which `boundary` leaves a disc as it is.
    fn run(
        &self,
        exec: &Executor,
        chunks: &mut [Chunk],
        inner: Option<([f64; 2], [f64; 2])>,
        boundary: impl Fn(usize, &mut [f64; 4], &mut [i32; 2], &mut WallSums) + Sync + Clone,
    ) -> Vec<ChunkMoved> {
        let n = chunks.iter().map(|c| c.x.len()).sum();
        let min_image = self.min_image;
        match (self.reference, inner) {
            (Some(reference), Some(inner)) if !min_image.is_periodic() => {
                exec.map_mut(n, chunks, |_, chunk| {
                    self.chunk_in_pairs(chunk, &boundary, inner, reference)
                })
            }
            (Some(reference), _) => {
                let image = move |x1, y1, x2, y2| min_image.diff(x1, y1, x2, y2);
                self.run_displaced(exec, chunks, &boundary, reference, image)
            }
            (None, _) => exec.map_mut(n, chunks, |_, chunk| {
                self.chunk(chunk, &boundary, |_, _, _| 0.0)
            }),
        }
    }

    /// [`Sweep::run`] with reference positions `(rx, ry)`, one disc at a time (a periodic
    /// box): each chunk measures displacements from its slice of them, `diff` giving
    /// position minus reference.
    fn run_displaced(
        &self,
        exec: &Executor,
        chunks: &mut [Chunk],
        boundary: &(impl Fn(usize, &mut [f64; 4], &mut [i32; 2], &mut WallSums) + Sync + Clone),
        (rx, ry): (&'r [f32], &'r [f32]),
        diff: impl Fn(f64, f64, f64, f64) -> [f64; 2] + Sync + Copy,
    ) -> Vec<ChunkMoved> {
        let n = chunks.iter().map(|c| c.x.len()).sum();
        exec.map_mut(n, chunks, |_, chunk| {
            // Indexed by the disc's place in the chunk.
            let range = chunk.base..chunk.base + chunk.x.len();
            let (rx, ry) = (&rx[range.clone()], &ry[range]);
            self.chunk(chunk, boundary, move |k, x, y| {
                let [dx, dy] = diff(x, y, rx[k] as f64, ry[k] as f64);
                dx * dx + dy * dy
            })
        })
    }

    /// One chunk: the wall impulse, the largest squared displacement (of all discs and of
    /// those that do not stray), the largest squared speed and the strays. `boundary` gets
    /// the disc's index, `[x, y, vx, vy]` and its image counts; `displacement2` the disc's
    /// place in the chunk and its new position.
    #[inline(always)]
    fn chunk(
        &self,
        chunk: &mut Chunk,
        boundary: &(impl Fn(usize, &mut [f64; 4], &mut [i32; 2], &mut WallSums) + Clone),
        displacement2: impl Fn(usize, f64, f64) -> f64,
    ) -> ChunkMoved {
        // A copy of the boundary's constants in this frame (the closures capture by value):
        // the loop then keeps them in registers instead of loading them through a
        // reference for every disc, which it cannot prove the disc stores leave alone.
        let boundary = boundary.clone();
        let [gx, gy] = self.gravity;
        let h = self.h;
        let mut impulse = WallSums::default();
        let mut max_speed2 = 0.0f64;
        let Chunk {
            base,
            x,
            y,
            vx,
            vy,
            image,
        } = chunk;
        let discs = x
            .iter_mut()
            .zip(y.iter_mut())
            .zip(vx.iter_mut())
            .zip(vy.iter_mut())
            .zip(image.iter_mut());
        let stray2 = self.stray2;
        let mut max_displacement2 = 0.0f64;
        let mut max_kept2 = 0.0f64;
        // The strays' places in the chunk, written without a branch: past the cap they go
        // to the last slot, which is never read (the count says the chunk overflowed).
        let mut strays = [0u32; CHUNK_STRAYS + 1];
        let mut stray_count = 0usize;
        for (k, ((((x, y), vx), vy), image)) in discs.enumerate() {
            let (vxi, vyi) = (*vx + gx * h, *vy + gy * h);
            let mut state = [*x + vxi * h, *y + vyi * h, vxi, vyi];
            boundary(*base + k, &mut state, image, &mut impulse);
            let [xi, yi, vxi, vyi] = state;
            (*x, *y) = (xi, yi);
            store_changed(vx, vxi);
            store_changed(vy, vyi);
            max_speed2 = max_skipping_nan(max_speed2, vxi * vxi + vyi * vyi);
            let d2 = displacement2(k, xi, yi);
            max_displacement2 = max_skipping_nan(max_displacement2, d2);
            let strayed = d2 >= stray2;
            max_kept2 = max_skipping_nan(max_kept2, if strayed { 0.0 } else { d2 });
            strays[stray_count.min(CHUNK_STRAYS)] = k as u32;
            stray_count += strayed as usize;
        }
        let strays = (stray_count <= CHUNK_STRAYS).then(|| &strays[..stray_count]);
        ChunkMoved::new(
            *base,
            impulse,
            [max_displacement2, max_kept2, max_speed2],
            strays,
        )
    }

    /// [`Sweep::chunk`] for plain (not periodic) displacements from `(rx, ry)`, two discs at
    /// a time in the lanes of [`F64x2`], every lane with the scalar operations in the scalar
    /// order (so the same bits): the sweep is compute-bound while the arrays are in cache.
    /// `boundary` leaves discs inside `inner` as they are, so it is called (per disc, as the
    /// scalar sweep calls it) only for a pair with a disc outside; an odd last disc goes
    /// through [`Sweep::chunk`].
    #[inline(always)]
    fn chunk_in_pairs(
        &self,
        chunk: &mut Chunk,
        boundary: &(impl Fn(usize, &mut [f64; 4], &mut [i32; 2], &mut WallSums) + Clone),
        (inner_min, inner_max): ([f64; 2], [f64; 2]),
        (rx, ry): (&[f32], &[f32]),
    ) -> ChunkMoved {
        let boundary = boundary.clone();
        let base = chunk.base;
        let len = chunk.x.len();
        let (rx, ry) = (&rx[base..base + len], &ry[base..base + len]);
        let paired = len / 2 * 2;
        let (gxh, gyh) = (
            F64x2::splat(self.gravity[0] * self.h),
            F64x2::splat(self.gravity[1] * self.h),
        );
        let h = F64x2::splat(self.h);
        let stray2 = F64x2::splat(self.stray2);
        let (lo_x, lo_y) = (F64x2::splat(inner_min[0]), F64x2::splat(inner_min[1]));
        let (hi_x, hi_y) = (F64x2::splat(inner_max[0]), F64x2::splat(inner_max[1]));
        let zero = F64x2::splat(0.0);
        // `v` where `v > acc`, else `acc` (NaN skipped): `maxpd`, one instruction.
        let max = |acc: F64x2, v: F64x2| v.max_else(acc);
        let (mut speed2, mut displacement2, mut kept2) = (zero, zero, zero);
        let mut impulse = WallSums::default();
        let mut strays = [0u32; CHUNK_STRAYS + 1];
        let mut stray_count = 0usize;
        let Chunk {
            x,
            y,
            vx,
            vy,
            image,
            ..
        } = chunk;
        // Checked once, so the loop indexes without bounds checks.
        let (x, y, vx, vy) = (&mut x[..len], &mut y[..len], &mut vx[..len], &mut vy[..len]);
        let (rx, ry, image) = (&rx[..len], &ry[..len], &mut image[..len]);
        for k in (0..paired).step_by(2) {
            let pair = |v: &[f64]| F64x2::new(v[k], v[k + 1]);
            let (mut vxi, mut vyi) = (pair(vx) + gxh, pair(vy) + gyh);
            let (mut xi, mut yi) = (pair(x) + vxi * h, pair(y) + vyi * h);
            let outside = xi.lt(lo_x) | xi.gt(hi_x) | yi.lt(lo_y) | yi.gt(hi_y);
            if outside.any() {
                let ([x0, x1], [y0, y1]) = (xi.lanes(), yi.lanes());
                let ([vx0, vx1], [vy0, vy1]) = (vxi.lanes(), vyi.lanes());
                let mut first = [x0, y0, vx0, vy0];
                let mut second = [x1, y1, vx1, vy1];
                boundary(base + k, &mut first, &mut image[k], &mut impulse);
                boundary(base + k + 1, &mut second, &mut image[k + 1], &mut impulse);
                (xi, yi) = (
                    F64x2::new(first[0], second[0]),
                    F64x2::new(first[1], second[1]),
                );
                (vxi, vyi) = (
                    F64x2::new(first[2], second[2]),
                    F64x2::new(first[3], second[3]),
                );
            }
            [x[k], x[k + 1]] = xi.lanes();
            [y[k], y[k + 1]] = yi.lanes();
            let ([vx0, vx1], [vy0, vy1]) = (vxi.lanes(), vyi.lanes());
            store_changed(&mut vx[k], vx0);
            store_changed(&mut vx[k + 1], vx1);
            store_changed(&mut vy[k], vy0);
            store_changed(&mut vy[k + 1], vy1);
            speed2 = max(speed2, vxi * vxi + vyi * vyi);
            let reference = |r: &[f32]| F64x2::new(r[k] as f64, r[k + 1] as f64);
            let (dx, dy) = (xi - reference(rx), yi - reference(ry));
            let d2 = dx * dx + dy * dy;
            displacement2 = max(displacement2, d2);
            let strayed = d2.ge(stray2);
            kept2 = max(kept2, F64x2::select(strayed, zero, d2));
            let [strayed0, strayed1] = strayed.lanes();
            strays[stray_count.min(CHUNK_STRAYS)] = k as u32;
            stray_count += strayed0 as usize;
            strays[stray_count.min(CHUNK_STRAYS)] = k as u32 + 1;
            stray_count += strayed1 as usize;
        }
        // The odd last disc, if any, through the scalar sweep.
        let last = (paired < len).then(|| {
            let mut rest = Chunk {
                base: base + paired,
                x: &mut x[paired..],
                y: &mut y[paired..],
                vx: &mut vx[paired..],
                vy: &mut vy[paired..],
                image: &mut image[paired..],
            };
            let displacement2 = plain_displacement2(&rx[paired..], &ry[paired..]);
            self.chunk(&mut rest, &boundary, displacement2)
        });
        // Maxima are exact, so lanes and the last disc combine in any order.
        let fold = |acc: F64x2| {
            let [a, b] = acc.lanes();
            max_skipping_nan(max_skipping_nan(0.0, a), b)
        };
        let (mut max_speed2, mut max_displacement2, mut max_kept2) =
            (fold(speed2), fold(displacement2), fold(kept2));
        let mut overflowed = stray_count > CHUNK_STRAYS;
        if let Some(last) = last {
            impulse.merge(&last.impulse);
            max_speed2 = max_skipping_nan(max_speed2, last.max_speed2);
            max_displacement2 = max_skipping_nan(max_displacement2, last.max_displacement2);
            max_kept2 = max_skipping_nan(max_kept2, last.max_kept2);
            match last.strays {
                Some(last) if !overflowed => {
                    for k in last {
                        strays[stray_count.min(CHUNK_STRAYS)] = k - base as u32;
                        stray_count += 1;
                    }
                    overflowed = stray_count > CHUNK_STRAYS;
                }
                _ => overflowed = true,
            }
        }
        let strays = (!overflowed).then(|| &strays[..stray_count]);
        ChunkMoved::new(
            base,
            impulse,
            [max_displacement2, max_kept2, max_speed2],
            strays,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::{Particle, ParticleId};
    use crate::{Boundary, Config};

    /// `count` discs on a unit lattice at rest, but for `moved`: (index, displacement in
    /// one substep along x), integrated once from a reference at their starting places.
    fn integrate_once(count: usize, moved: &[(usize, f64)]) -> (Particles, Reference, Moved) {
        let h = 0.01;
        let mut p = Particles::default();
        for i in 0..count {
            let position = [(i % 128) as f64, (i / 128) as f64];
            let v = moved.iter().find(|m| m.0 == i).map_or(0.0, |m| m.1 / h);
            p.push(ParticleId(i as _), &Particle::new(position, [v, 0.0], 0.25));
        }
        let reference = Reference::at(&p.x, &p.y, 1.0);
        let config = Config::default();
        let exec = Executor::default();
        let ctx = StepContext::new(&config, h, &exec, None);
        let moved = integrate(&mut p, &ctx, &reference, 0.25);
        (p, reference, moved)
    }

    /// What integration should report of the strays, from the positions it left: the strays
    /// (at or past the allowance), the largest squared displacement and that of the others.
    fn strays_by_hand(p: &Particles, reference: &Reference) -> (Vec<u32>, f64, f64) {
        let (rx, ry) = reference.positions(p.len()).expect("a reference");
        let a2 = reference.allowance() * reference.allowance();
        let (mut strays, mut all, mut kept) = (Vec::new(), 0.0f64, 0.0f64);
        for i in 0..p.len() {
            let (dx, dy) = (p.x[i] - rx[i] as f64, p.y[i] - ry[i] as f64);
            let d2 = dx * dx + dy * dy;
            all = all.max(d2);
            if d2 >= a2 {
                strays.push(i as u32);
            } else {
                kept = kept.max(d2);
            }
        }
        (strays, all, kept)
    }

    #[test]
    fn integration_finds_every_stray_and_the_largest_displacements() {
        // Two chunks and a bit; the allowance is 0.49 of the skin (1.0). Strays in the first
        // chunk (at its ends too), exactly the per-chunk cap in the second, one in the last;
        // others moved a little, the largest of them (0.3) in the second chunk.
        let a = 0.49;
        let mut moved = vec![(0, 2.0 * a), (5, 0.2), (17, 1.5 * a), (CHUNK - 1, a + 0.01)];
        moved.extend((0..CHUNK_STRAYS).map(|k| (CHUNK + 3 * k, a + 0.05)));
        moved.extend([
            (CHUNK + 1, 0.3),
            (CHUNK + 2, -0.25),
            (2 * CHUNK + 4, -3.0 * a),
        ]);
        let (p, reference, found) = integrate_once(2 * CHUNK + 10, &moved);
        let (strays, all, kept) = strays_by_hand(&p, &reference);
        assert_eq!(strays.len(), 4 + CHUNK_STRAYS);
        assert!(!found.too_many_strays);
        assert_eq!(found.strays, strays);
        assert_eq!(found.max_displacement2, all);
        assert_eq!(found.max_kept2, kept);
        assert!((kept - 0.09).abs() < 1e-12 && (all - 9.0 * a * a).abs() < 1e-12);
        assert!((found.max_stride - 3.0 * a).abs() < 1e-12);
    }

    #[test]
    fn a_chunk_with_more_strays_than_its_cap_asks_for_a_new_list() {
        // One stray past the cap in the first chunk: the list is made anew, and no disc can
        // be said to be within less than the largest displacement.
        let moved: Vec<_> = (0..=CHUNK_STRAYS).map(|k| (7 * k, 0.6)).collect();
        let (_, _, found) = integrate_once(CHUNK + 100, &moved);
        assert!(found.too_many_strays);
        assert_eq!(found.max_kept2, found.max_displacement2);
        assert!((found.max_displacement2 - 0.36).abs() < 1e-12);
    }

    #[test]
    fn the_walls_prefilter_never_skips_a_disc_a_wall_would_move() {
        // Discs a few units in the last place either side of touching each wall (centre at
        // exactly its radius, the largest radius or a smaller one, from the wall), moving
        // into it, along it and away, in a box far from the origin: integrating with the
        // radius bound (the prefilter) gives the same bits as sending every disc to the
        // walls (an infinite bound).
        let (min, max) = ([1e6 - 3.0, -7.25], [1e6 + 40.0, 12.5]);
        let config = Config {
            boundary: Boundary::walls(min, max),
            coefficient_of_restitution: 0.9,
            ..Config::default()
        };
        let exec = Executor::default();
        let h = 1e-3;
        let ctx = StepContext::new(&config, h, &exec, None);
        let (r_max, radii) = (0.75, [0.75, 0.5]);
        let mut p = Particles::default();
        let mut next = 0;
        let mut add = |p: &mut Particles, x: f64, y: f64, v: [f64; 2], r: f64| {
            p.push(ParticleId(next), &Particle::new([x, y], v, r));
            next += 1;
        };
        let nudge = |v: f64, ulps: i64| {
            let mut v = v;
            for _ in 0..ulps.abs() {
                v = if ulps > 0 { v.next_up() } else { v.next_down() };
            }
            v
        };
        let mid = [0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1])];
        for r in radii {
            for ulps in -3..=3 {
                for v in [-2.0, 0.0, 2.0] {
                    // The disc ends the substep `ulps` from touching each wall.
                    let back = v * h;
                    add(&mut p, nudge(min[0] + r, ulps) - back, mid[1], [v, 0.3], r);
                    add(&mut p, nudge(max[0] - r, ulps) - back, mid[1], [v, -0.3], r);
                    add(&mut p, mid[0], nudge(min[1] + r, ulps) - back, [0.3, v], r);
                    add(&mut p, mid[0], nudge(max[1] - r, ulps) - back, [-0.3, v], r);
                }
            }
        }
        let bits = |p: &Particles| -> Vec<u64> {
            [&p.x, &p.y, &p.vx, &p.vy]
                .iter()
                .flat_map(|v| v.iter().map(|v| v.to_bits()))
                .collect()
        };
        // Without a reference (the scalar sweep) and with one (two discs at a time).
        let recorded = Reference::at(&p.x, &p.y, 1.0);
        assert!(recorded.positions(p.len()).is_some(), "a reference");
        for reference in [Reference::default(), recorded] {
            let mut filtered = p.clone();
            let moved = integrate(&mut filtered, &ctx, &reference, r_max);
            let mut every = p.clone();
            let all = integrate(&mut every, &ctx, &reference, f64::INFINITY);
            assert_eq!(bits(&filtered), bits(&every));
            assert_eq!(moved.impulse, all.impulse);
            // And the walls did act: some discs were put back and bounced.
            assert_ne!(bits(&filtered), bits(&p));
            assert_ne!(all.impulse, WallSums::default());
        }
    }

    /// One chunk of all the discs `[x, y, vx, vy]`, with their image counts.
    fn chunk_of<'a>([x, y, vx, vy]: &'a mut [Vec<f64>; 4], image: &'a mut [[i32; 2]]) -> Chunk<'a> {
        Chunk {
            base: 0,
            x,
            y,
            vx,
            vy,
            image,
        }
    }

    #[test]
    fn the_pass_in_pairs_gives_the_scalar_bits() {
        // Discs moving under gravity in a walled box, many crossing a wall, one with a NaN
        // velocity and one flung far: the sweep two at a time leaves the same bits and
        // measures the same as the scalar sweep, for even and odd chunks, with strays below,
        // at and past the cap (the odd last disc tipping it over).
        use rand::{RngExt, SeedableRng};
        let (min, max, r) = ([0.0, 0.0], [10.0, 10.0], 0.25);
        let e = crate::law::Restitution {
            e: 0.8,
            rest_below: None,
        };
        let (inner_min, inner_max) = ([min[0] + r, min[1] + r], [max[0] - r, max[1] - r]);
        let boundary = move |_: usize,
                             [x, y, vx, vy]: &mut [f64; 4],
                             _: &mut [i32; 2],
                             sums: &mut WallSums| {
            let outside =
                *x < inner_min[0] || *x > inner_max[0] || *y < inner_min[1] || *y > inner_max[1];
            if outside {
                let (left, right) = reflect(x, vx, r, min[0], max[0], e, r);
                let (bottom, top) = reflect(y, vy, r, min[1], max[1], e, r);
                sums.add([left, right, bottom, top]);
            }
        };
        let allowance: f64 = 0.2;
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
        let mut uniform = |lo: f64, hi: f64, n: usize| -> Vec<f64> {
            (0..n).map(|_| rng.random_range(lo..hi)).collect()
        };
        // (discs, far references, strays expected: the far ones, the flung disc and the one
        // exactly at the allowance; none when past the cap).
        for (len, far, expected) in [
            (1000, 10, Some(12)),
            (1001, 10, Some(12)),
            (1001, CHUNK_STRAYS - 2, Some(CHUNK_STRAYS)),
            (1001, CHUNK_STRAYS - 1, None),
            (1000, CHUNK_STRAYS - 1, None),
        ] {
            // Within 0.18 of their references but for the far ones (the last disc among
            // them) and the flung one: offsets 0.02, moves 0.12, wall pushes 0.05.
            let (x, y) = (uniform(0.2, 9.8, len), uniform(0.2, 9.8, len));
            let (mut vx, mut vy) = (uniform(-4.0, 4.0, len), uniform(-4.0, 4.0, len));
            (vx[3], vy[8]) = (f64::NAN, 1e300);
            let offsets = uniform(-0.02, 0.02, len);
            let mut rx: Vec<f32> = x
                .iter()
                .zip(&offsets)
                .map(|(x, o)| (x + o) as f32)
                .collect();
            let ry: Vec<f32> = y.iter().map(|&v| v as f32).collect();
            for k in 0..far {
                rx[len - 1 - 5 * k] += 1.0;
            }
            let pass_with = |stray2| Sweep {
                gravity: [0.3, -9.81],
                h: 0.02,
                min_image: Geometry::Open.min_image(),
                reference: Some((&rx, &ry)),
                stray2,
            };
            let mut image = vec![[0i32; 2]; len];
            let displacement2 = plain_displacement2(&rx, &ry);
            let mut scalar = [x, y, vx, vy];
            let mut paired = scalar.clone();
            // The allowance: exactly the largest displacement of the near discs, so that
            // disc strays too (at the allowance is past it).
            let stray2 = {
                let mut dry = scalar.clone();
                let mut dry_image = image.clone();
                let near = pass_with(allowance * allowance).chunk(
                    &mut chunk_of(&mut dry, &mut dry_image),
                    &boundary,
                    &displacement2,
                );
                near.max_kept2
            };
            assert!(stray2 > 0.01 && stray2 < allowance * allowance);
            let sweep = pass_with(stray2);
            let mut paired_image = image.clone();
            let one = sweep.chunk(
                &mut chunk_of(&mut scalar, &mut image),
                &boundary,
                &displacement2,
            );
            let two = sweep.chunk_in_pairs(
                &mut chunk_of(&mut paired, &mut paired_image),
                &boundary,
                (inner_min, inner_max),
                (&rx, &ry),
            );
            let case = format!("{len} discs, {far} far");
            let bits = |v: &[f64]| v.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            for (a, b) in scalar.iter().zip(&paired) {
                assert_eq!(bits(a), bits(b), "{case}");
            }
            assert_eq!(one.impulse, two.impulse, "{case}");
            assert_ne!(one.impulse, WallSums::default(), "{case}: walls met");
            for (a, b) in [
                (one.max_displacement2, two.max_displacement2),
                (one.max_kept2, two.max_kept2),
                (one.max_speed2, two.max_speed2),
            ] {
                assert_eq!(a.to_bits(), b.to_bits(), "{case}");
            }
            assert_eq!(one.strays, two.strays, "{case}");
            assert_eq!(two.strays.as_ref().map(Vec::len), expected, "{case}");
            // The kept discs' largest displacement, or with too many strays everyone's.
            if expected.is_some() {
                assert!(two.max_kept2 < stray2, "{case}");
            } else {
                assert_eq!(two.max_kept2, two.max_displacement2, "{case}");
            }
        }
    }
}
