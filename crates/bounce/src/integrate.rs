//! Time integration: semi-implicit (symplectic) Euler with uniform gravity, then the boundary.
//!
//! `v += g h; x += v h` for each disc, and the boundary applied right after it moves, in one
//! pass over memory. The same pass measures how far each disc now is from its broadphase
//! reference position, so checking the candidate list costs no extra pass. It runs over
//! fixed chunks; the wall impulses are summed exactly (`sum`), so they depend on neither the
//! thread count nor the storage order.
//!
//! The pass is compute-bound, so the boundary and the reference check are chosen once per
//! pass, not per disc, and walls only read a disc's radius and mass when it is within the
//! largest radius of a wall.

use crate::broadphase::Reference;
use crate::context::StepContext;
use crate::geometry::{Geometry, MinImage, reflect, wrap};
use crate::parallel::{CHUNK, Executor};
use crate::particles::Particles;
use crate::sum::WallSums;

/// What integration reports.
#[derive(Clone, Debug, Default)]
pub(crate) struct Moved {
    /// Momentum given to each wall (by the discs the step's tally counts).
    pub impulse: WallSums,
    /// The largest squared distance of a disc from its reference position (infinite when
    /// there is no reference).
    pub max_displacement2: f64,
    /// The longest distance a disc moved in this substep.
    pub max_stride: f64,
}

/// One chunk of the arrays a pass writes, and the index of its first disc.
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
    let reference = reference.positions(n);
    let law = ctx.law;
    let tally = ctx.tally;
    let (radius, mass) = (&p.radius, &p.mass);
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
    let pass = Pass {
        gravity: ctx.gravity,
        h: ctx.h,
        min_image: ctx.geometry.min_image(),
        reference,
    };
    let chunks = &mut chunks[..];
    let exec = ctx.exec;
    let partial = match ctx.geometry {
        Geometry::Open => pass.run(
            exec,
            chunks,
            #[inline(always)]
            |_, _, _, _| {},
        ),
        Geometry::Periodic { min, size, .. } => pass.run(
            exec,
            chunks,
            #[inline(always)]
            |_, [x, y, _, _], image, _| {
                image[0] += wrap(x, min[0], size[0]);
                image[1] += wrap(y, min[1], size[1]);
            },
        ),
        Geometry::Walls {
            min,
            max,
            restitution: e,
        } => pass.run(
            exec,
            chunks,
            #[inline(always)]
            |i, [x, y, vx, vy], _, impulse| {
                // Radii are at most `max_radius`, so a disc farther from every wall touches
                // none (rounding is monotone, so this never skips a disc `reflect` would move).
                let near = *x - max_radius < min[0]
                    || *x + max_radius > max[0]
                    || *y - max_radius < min[1]
                    || *y + max_radius > max[1];
                if near {
                    let r = radius[i];
                    let m = law.mass(r, mass[i]);
                    let (left, right) = reflect(x, vx, r, min[0], max[0], e, m);
                    let (bottom, top) = reflect(y, vy, r, min[1], max[1], e, m);
                    if left != 0.0 || right != 0.0 || bottom != 0.0 || top != 0.0 {
                        record_hit(impulse, [left, right, bottom, top], [*x, *y], tally);
                    }
                }
            },
        ),
    };
    let mut moved = Moved {
        max_displacement2: if reference.is_some() {
            0.0
        } else {
            f64::INFINITY
        },
        ..Moved::default()
    };
    let mut max_speed2 = 0.0f64;
    for (impulse, d2, v2) in &partial {
        moved.impulse.merge(impulse);
        moved.max_displacement2 = moved.max_displacement2.max(*d2);
        max_speed2 = max_speed2.max(*v2);
    }
    moved.max_stride = max_speed2.sqrt() * ctx.h;
    moved
}

/// Adds a wall hit's impulses, if the tally counts the disc: out of line, so the pass's
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

/// The constants of one pass.
struct Pass<'r> {
    gravity: [f64; 2],
    h: f64,
    min_image: MinImage,
    reference: Option<(&'r [f32], &'r [f32])>,
}

impl Pass<'_> {
    /// The pass over the chunks, with the boundary and the reference check chosen once;
    /// per chunk the wall impulse, the largest squared displacement and speed.
    fn run(
        &self,
        exec: &Executor,
        chunks: &mut [Chunk],
        boundary: impl Fn(usize, &mut [f64; 4], &mut [i32; 2], &mut WallSums) + Sync,
    ) -> Vec<(WallSums, f64, f64)> {
        let n = chunks.iter().map(|c| c.x.len()).sum();
        match self.reference {
            Some((rx, ry)) => exec.map_mut(n, chunks, |_, chunk| {
                self.chunk(chunk, &boundary, |i, x, y| {
                    let [dx, dy] = self.min_image.diff(x, y, rx[i] as f64, ry[i] as f64);
                    dx * dx + dy * dy
                })
            }),
            None => exec.map_mut(n, chunks, |_, chunk| {
                self.chunk(chunk, &boundary, |_, _, _| 0.0)
            }),
        }
    }

    /// One chunk: the wall impulse, the largest squared displacement and the largest squared
    /// speed. `boundary` gets the disc's index,
    /// `[x, y, vx, vy]` and its image counts.
    #[inline(always)]
    fn chunk(
        &self,
        chunk: &mut Chunk,
        boundary: &impl Fn(usize, &mut [f64; 4], &mut [i32; 2], &mut WallSums),
        displacement2: impl Fn(usize, f64, f64) -> f64,
    ) -> (WallSums, f64, f64) {
        let [gx, gy] = self.gravity;
        let h = self.h;
        let mut impulse = WallSums::default();
        let mut max_displacement2 = 0.0f64;
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
        for (k, ((((x, y), vx), vy), image)) in discs.enumerate() {
            let (vxi, vyi) = (*vx + gx * h, *vy + gy * h);
            let mut state = [*x + vxi * h, *y + vyi * h, vxi, vyi];
            boundary(*base + k, &mut state, image, &mut impulse);
            let [xi, yi, vxi, vyi] = state;
            (*x, *y, *vx, *vy) = (xi, yi, vxi, vyi);
            max_speed2 = max_speed2.max(vxi * vxi + vyi * vyi);
            max_displacement2 = max_displacement2.max(displacement2(*base + k, xi, yi));
        }
        (impulse, max_displacement2, max_speed2)
    }
}
