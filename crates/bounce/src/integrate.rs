//! Time integration: semi-implicit (symplectic) Euler with uniform gravity, then the boundary.
//!
//! `v += g h; x += v h` for each disc, and the boundary applied right after it moves, in one
//! pass over memory. The pass runs over fixed chunks so the wall-impulse sums do not depend on
//! the thread count.

use crate::boundary::{Edge, WallImpulse};
use crate::config::Config;
use crate::parallel::{CHUNK, Executor, SharedSlice};
use crate::particles::Particles;

/// Advances every disc by `h` and applies the boundary; returns the wall impulses.
pub(crate) fn integrate(
    p: &mut Particles,
    config: &Config,
    h: f64,
    exec: &Executor,
) -> WallImpulse {
    let [gx, gy] = config.gravity;
    let edge = Edge::of(config);
    let mass_model = config.mass_model;
    let n = p.len();
    let (radius, mass) = (&p.radius, &p.mass);
    let x = SharedSlice::new(&mut p.x);
    let y = SharedSlice::new(&mut p.y);
    let vx = SharedSlice::new(&mut p.vx);
    let vy = SharedSlice::new(&mut p.vy);
    let partial = exec.map_index(0..n.div_ceil(CHUNK), |chunk| {
        let mut impulse = WallImpulse::default();
        for i in chunk * CHUNK..((chunk + 1) * CHUNK).min(n) {
            // SAFETY: chunks are disjoint index ranges within the arrays.
            unsafe {
                let (mut vxi, mut vyi) = (vx.get(i) + gx * h, vy.get(i) + gy * h);
                let (mut xi, mut yi) = (x.get(i) + vxi * h, y.get(i) + vyi * h);
                let m = mass_model.mass(radius[i], mass[i]);
                edge.apply(
                    [&mut xi, &mut yi],
                    [&mut vxi, &mut vyi],
                    radius[i],
                    m,
                    &mut impulse,
                );
                x.set(i, xi);
                y.set(i, yi);
                vx.set(i, vxi);
                vy.set(i, vyi);
            }
        }
        impulse
    });
    let mut total = WallImpulse::default();
    for part in &partial {
        total.add(part);
    }
    total
}
