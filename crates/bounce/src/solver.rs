//! Applies the seed's pair resolution to every detected pair, in the canonical order.
//!
//! Pairs are resolved one after another on the current state (Gauss–Seidel style, as the
//! seed's loop does): a disc pushed by one pair is seen at its new place by the next. The
//! order is the broadphase's canonical order; blocks within one phase touch disjoint discs,
//! so a phase runs in parallel and still gives the serial result bit for bit.

use crate::broadphase::{Broadphase, Periodicity};
use crate::collision::{Body, ResolveParams, resolve_pair};
use crate::config::Config;
use crate::parallel::{Executor, SharedSlice};
use crate::particles::Particles;

/// Resolves every pair found by the last `find_pairs`, phase by phase.
pub(crate) fn resolve_all(
    broadphase: &Broadphase,
    p: &mut Particles,
    config: &Config,
    exec: &Executor,
) {
    let params = ResolveParams {
        collision_radius_scale: config.collision_radius_scale,
        restitution: config.coefficient_of_restitution,
        restitution_model: config.restitution_model,
        velocity_update: config.velocity_update,
    };
    let periodicity = Periodicity::of(config);
    let mass_model = config.mass_model;
    let radius = &p.radius;
    let mass = &p.mass;
    let x = SharedSlice::new(&mut p.x);
    let y = SharedSlice::new(&mut p.y);
    let vx = SharedSlice::new(&mut p.vx);
    let vy = SharedSlice::new(&mut p.vy);
    for phase in &broadphase.phases {
        exec.for_each_index(phase.clone(), |block| {
            for &[a, b] in &broadphase.pairs[block] {
                let (a, b) = (a as usize, b as usize);
                // SAFETY: the pairs of one block touch discs in the block's cells and their
                // one-cell ring; blocks of one phase are two cells apart (see `broadphase`),
                // so no other thread touches `a` or `b` now. Indices come from the current
                // storage, so they are in bounds.
                unsafe {
                    let diff = periodicity.diff(x.get(a), y.get(a), x.get(b), y.get(b));
                    let body = |i: usize| Body {
                        velocity: [vx.get(i), vy.get(i)],
                        radius: radius[i],
                        mass: mass_model.mass(radius[i], mass[i]),
                    };
                    let out = resolve_pair(diff, &body(a), &body(b), &params);
                    x.set(a, x.get(a) + out.push[0]);
                    y.set(a, y.get(a) + out.push[1]);
                    x.set(b, x.get(b) - out.push[0]);
                    y.set(b, y.get(b) - out.push[1]);
                    vx.set(a, out.v1[0]);
                    vy.set(a, out.v1[1]);
                    vx.set(b, out.v2[0]);
                    vy.set(b, out.v2[1]);
                }
            }
        });
    }
}
