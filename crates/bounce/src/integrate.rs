//! Time integration: semi-implicit (symplectic) Euler with uniform gravity, then the boundary.
//!
//! `v += g h; x += v h` for each disc, and the boundary applied right after it moves, in one
//! pass over memory. The same pass measures how far each disc now is from its broadphase
//! reference position, so checking the candidate list costs no extra pass. It runs over
//! fixed chunks so the wall-impulse sums do not depend on the thread count.
//!
//! The pass is compute-bound, so the boundary and the reference check are chosen once per
//! pass, not per disc, and walls only read a disc's radius and mass when it is within the
//! largest radius of a wall.

use crate::boundary::{Edge, WallImpulse, reflect, wrap};
use crate::broadphase::{Periodicity, Reference};
use crate::config::Config;
use crate::parallel::{CHUNK, Executor, SharedSlice};
use crate::particles::Particles;

/// What integration reports.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Moved {
    /// Momentum given to each wall.
    pub impulse: WallImpulse,
    /// The largest squared distance of a disc from its reference position (infinite when
    /// there is no reference).
    pub max_displacement2: f64,
    /// The longest distance a disc moved in this substep.
    pub max_stride: f64,
}

/// Advances every disc by `h`, applies the boundary, and measures displacements from
/// `reference`. `max_radius` bounds every radius (infinite when unknown).
pub(crate) fn integrate(
    p: &mut Particles,
    config: &Config,
    h: f64,
    reference: &Reference,
    max_radius: f64,
    exec: &Executor,
) -> Moved {
    let n = p.len();
    let reference = reference.positions(n);
    let periodicity = Periodicity::of(config);
    let mass_model = config.mass_model;
    let (radius, mass) = (&p.radius, &p.mass);
    let state = State {
        x: SharedSlice::new(&mut p.x),
        y: SharedSlice::new(&mut p.y),
        vx: SharedSlice::new(&mut p.vx),
        vy: SharedSlice::new(&mut p.vy),
        gravity: config.gravity,
        h,
        n,
    };
    let partial = match Edge::of(config) {
        Edge::Open => state.run(exec, reference, periodicity, |_, _, _, _, _, _| {}),
        Edge::Periodic { min, size } => {
            state.run(exec, reference, periodicity, |_, x, y, _, _, _| {
                wrap(x, min[0], size[0]);
                wrap(y, min[1], size[1]);
            })
        }
        Edge::Walls {
            min,
            max,
            restitution: e,
        } => state.run(exec, reference, periodicity, |i, x, y, vx, vy, impulse| {
            // Radii are at most `max_radius`, so a disc farther from every wall touches
            // none (rounding is monotone, so this never skips a disc `reflect` would move).
            let near = *x - max_radius < min[0]
                || *x + max_radius > max[0]
                || *y - max_radius < min[1]
                || *y + max_radius > max[1];
            if near {
                let r = radius[i];
                let m = mass_model.mass(r, mass[i]);
                let (left, right) = reflect(x, vx, r, min[0], max[0], e, m);
                let (bottom, top) = reflect(y, vy, r, min[1], max[1], e, m);
                impulse.left += left;
                impulse.right += right;
                impulse.bottom += bottom;
                impulse.top += top;
            }
        }),
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
        moved.impulse.add(impulse);
        moved.max_displacement2 = moved.max_displacement2.max(*d2);
        max_speed2 = max_speed2.max(*v2);
    }
    moved.max_stride = max_speed2.sqrt() * h;
    moved
}

/// The arrays one pass writes, shared by the chunks.
struct State<'a> {
    x: SharedSlice<'a, f64>,
    y: SharedSlice<'a, f64>,
    vx: SharedSlice<'a, f64>,
    vy: SharedSlice<'a, f64>,
    gravity: [f64; 2],
    h: f64,
    n: usize,
}

impl State<'_> {
    /// The pass over fixed chunks; per chunk the wall impulse, the largest squared
    /// displacement and the largest squared speed.
    fn run(
        &self,
        exec: &Executor,
        reference: Option<(&[f32], &[f32])>,
        periodicity: Periodicity,
        boundary: impl Fn(usize, &mut f64, &mut f64, &mut f64, &mut f64, &mut WallImpulse) + Sync,
    ) -> Vec<(WallImpulse, f64, f64)> {
        let chunks = 0..self.n.div_ceil(CHUNK);
        match reference {
            Some((rx, ry)) => exec.map_index(self.n, chunks, |chunk| {
                self.chunk(chunk, &boundary, |i, x, y| {
                    let [dx, dy] = periodicity.diff(x, y, rx[i] as f64, ry[i] as f64);
                    dx * dx + dy * dy
                })
            }),
            None => exec.map_index(self.n, chunks, |chunk| {
                self.chunk(chunk, &boundary, |_, _, _| 0.0)
            }),
        }
    }

    #[inline(always)]
    fn chunk(
        &self,
        chunk: usize,
        boundary: &impl Fn(usize, &mut f64, &mut f64, &mut f64, &mut f64, &mut WallImpulse),
        displacement2: impl Fn(usize, f64, f64) -> f64,
    ) -> (WallImpulse, f64, f64) {
        let [gx, gy] = self.gravity;
        let h = self.h;
        let mut impulse = WallImpulse::default();
        let mut max_displacement2 = 0.0f64;
        let mut max_speed2 = 0.0f64;
        for i in chunk * CHUNK..((chunk + 1) * CHUNK).min(self.n) {
            // SAFETY: chunks are disjoint index ranges within the arrays.
            unsafe {
                let (mut vxi, mut vyi) = (self.vx.get(i) + gx * h, self.vy.get(i) + gy * h);
                let (mut xi, mut yi) = (self.x.get(i) + vxi * h, self.y.get(i) + vyi * h);
                boundary(i, &mut xi, &mut yi, &mut vxi, &mut vyi, &mut impulse);
                self.x.set(i, xi);
                self.y.set(i, yi);
                self.vx.set(i, vxi);
                self.vy.set(i, vyi);
                max_speed2 = max_speed2.max(vxi * vxi + vyi * vyi);
                max_displacement2 = max_displacement2.max(displacement2(i, xi, yi));
            }
        }
        (impulse, max_displacement2, max_speed2)
    }
}
