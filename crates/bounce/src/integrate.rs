//! Time integration: semi-implicit (symplectic) Euler with uniform gravity, then the boundary.
//!
//! `v += g h; x += v h` for each disc, and the boundary applied right after it moves, in one
//! pass over memory. The same pass measures how far each disc now is from its broadphase
//! reference position, so checking the candidate list costs no extra pass. It runs over
//! fixed chunks so the wall-impulse sums do not depend on the thread count.

use crate::boundary::{Edge, WallImpulse};
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
/// `reference`.
pub(crate) fn integrate(
    p: &mut Particles,
    config: &Config,
    h: f64,
    reference: &Reference,
    exec: &Executor,
) -> Moved {
    let [gx, gy] = config.gravity;
    let edge = Edge::of(config);
    let periodicity = Periodicity::of(config);
    let mass_model = config.mass_model;
    let n = p.len();
    let reference = reference.positions(n);
    let (radius, mass) = (&p.radius, &p.mass);
    let x = SharedSlice::new(&mut p.x);
    let y = SharedSlice::new(&mut p.y);
    let vx = SharedSlice::new(&mut p.vx);
    let vy = SharedSlice::new(&mut p.vy);
    let partial = exec.map_index(0..n.div_ceil(CHUNK), |chunk| {
        let mut impulse = WallImpulse::default();
        let mut max_displacement2 = 0.0f64;
        let mut max_speed2 = 0.0f64;
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
                max_speed2 = max_speed2.max(vxi * vxi + vyi * vyi);
                if let Some((rx, ry)) = reference {
                    let [dx, dy] = periodicity.diff(xi, yi, rx[i] as f64, ry[i] as f64);
                    max_displacement2 = max_displacement2.max(dx * dx + dy * dy);
                }
            }
        }
        (impulse, max_displacement2, max_speed2)
    });
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
