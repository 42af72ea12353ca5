//! Resolution: the law's pair resolution applied to every contact, in the canonical order.
//!
//! Pairs are resolved one after another on the current state (Gauss–Seidel style, as the
//! seed's loop does): a disc pushed by one pair is seen at its new place by the next. The
//! order is the canonical order of `contacts`; the pieces of one colour touch disjoint discs,
//! so they run in parallel and still give the serial result bit for bit.

use crate::contacts::Contacts;
use crate::context::StepContext;
use crate::law::Body;
use crate::parallel::{SharedSlice, prefetch};
use crate::particles::Particles;

/// How many contacts ahead the solver asks for the discs' cache lines.
const PREFETCH_AHEAD: usize = 8;

/// Resolves every contact found by the last `Contacts::find`, colour by colour, and keeps
/// walls holding: a disc a push left beyond a wall is put back against it. Returns the
/// collision virial of the substep, `Σ r_ij · Δp_ij` over the resolved pairs (`r_ij` the
/// centre difference, `Δp_ij` the pair's impulse, the antisymmetric part of the two momentum
/// changes: exact when the model conserves momentum), summed in canonical order.
pub(crate) fn resolve_all(contacts: &Contacts, p: &mut Particles, ctx: &StepContext) -> f64 {
    let law = &ctx.law;
    let min_image = ctx.geometry.min_image();
    let radius = &p.radius;
    let mass = &p.mass;
    let x = SharedSlice::new(&mut p.x);
    let y = SharedSlice::new(&mut p.y);
    let vx = SharedSlice::new(&mut p.vx);
    let vy = SharedSlice::new(&mut p.vy);
    let geometry = ctx.geometry;
    let mut virial = 0.0;
    for phase in &contacts.phases {
        // A contact costs a few cache misses: count it as a few discs' work.
        let pieces = &contacts.pieces[phase.clone()];
        let work = 4 * (pieces.last().map_or(0, |p| p.end) - pieces.first().map_or(0, |p| p.start));
        let partial = ctx.exec.map_index(work, phase.clone(), |piece| {
            let list = &contacts.list[contacts.pieces[piece].clone()];
            let mut virial = 0.0;
            for (k, contact) in list.iter().enumerate() {
                // Contacts touch scattered discs: start loading a later contact's discs now.
                if let Some(ahead) = list.get(k + PREFETCH_AHEAD) {
                    for i in [ahead.a as usize, ahead.b as usize] {
                        prefetch(x.address(i));
                        prefetch(y.address(i));
                        prefetch(vx.address(i));
                        prefetch(vy.address(i));
                        prefetch(radius.as_ptr().wrapping_add(i));
                    }
                }
                let (a, b) = (contact.a as usize, contact.b as usize);
                // SAFETY: the contacts of one piece touch discs in its blocks' cells and their
                // one-cell ring; pieces of one colour hold whole blocks of that colour, which
                // are two cells apart (see `contacts`), so no other thread touches `a` or `b`
                // now. Indices come from the current storage, so they are in bounds.
                unsafe {
                    let diff = min_image.diff(x.get(a), y.get(a), x.get(b), y.get(b));
                    let body = |i: usize| Body {
                        velocity: [vx.get(i), vy.get(i)],
                        radius: radius[i],
                        mass: law.mass(radius[i], mass[i]),
                    };
                    let (body_a, body_b) = (body(a), body(b));
                    let out = law.resolve(diff, &body_a, &body_b);
                    // The pair's impulse: half the difference of the momentum changes.
                    let impulse = [0, 1].map(|k| {
                        0.5 * (body_a.mass * (out.v1[k] - body_a.velocity[k])
                            - body_b.mass * (out.v2[k] - body_b.velocity[k]))
                    });
                    virial += diff[0] * impulse[0] + diff[1] * impulse[1];
                    let (mut xa, mut ya) = (x.get(a) + out.push[0], y.get(a) + out.push[1]);
                    let (mut xb, mut yb) = (x.get(b) - out.push[0], y.get(b) - out.push[1]);
                    geometry.hold(&mut xa, &mut ya, body_a.radius);
                    geometry.hold(&mut xb, &mut yb, body_b.radius);
                    x.set(a, xa);
                    y.set(a, ya);
                    x.set(b, xb);
                    y.set(b, yb);
                    vx.set(a, out.v1[0]);
                    vy.set(a, out.v1[1]);
                    vx.set(b, out.v2[0]);
                    vy.set(b, out.v2[1]);
                }
            }
            virial
        });
        virial += partial.iter().sum::<f64>();
    }
    virial
}
