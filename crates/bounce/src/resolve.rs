//! Resolution: the law's pair resolution applied to every contact, in the canonical order.
//!
//! Pairs are resolved one after another on the current state (Gauss–Seidel style, as the
//! seed's loop does): a disc pushed by one pair is seen at its new place by the next. The
//! order is the canonical order of `contacts`; the pieces of one colour touch disjoint discs,
//! so they run in parallel and still give the serial result bit for bit.
//!
//! With more than one solver pass, walls are contacts too: after each pass's pairs,
//! [`resolve_walls`] bounces every disc that touches a wall and moves into it. Without it
//! only integration meets the walls, once per substep, and the floor can hold up a stack
//! only by the bounce of its bottom row: in a momentum-conserving model the whole pile then
//! sinks at a steady speed that the pushes undo (measured: mean vy ≈ -0.6 in the settled
//! shipped pile under `relative_normal_velocity`, a kinetic energy near 150).

use crate::contacts::Contacts;
use crate::context::StepContext;
use crate::geometry::{Geometry, bounce};
use crate::law::Body;
use crate::parallel::{CHUNK, SharedSlice, prefetch};
use crate::particles::Particles;
use crate::sum::{ExactSum, WallSums};

/// How many contacts ahead the solver asks for the discs' cache lines.
const PREFETCH_AHEAD: usize = 8;

/// Resolves every contact found by the last `Contacts::find`, colour by colour, and keeps
/// walls holding: a disc a push left beyond a wall is put back against it. Returns the
/// collision virial of the substep, `Σ r_ij · Δp_ij` over the resolved pairs (`r_ij` the
/// centre difference, `Δp_ij` the pair's impulse, the antisymmetric part of the two momentum
/// changes: exact when the model conserves momentum), summed exactly (so in no particular
/// order), over the contacts the step's tally counts (by the lower-id disc's place).
pub(crate) fn resolve_all(contacts: &Contacts, p: &mut Particles, ctx: &StepContext) -> ExactSum {
    let tally = ctx.tally;
    let law = &ctx.law;
    let min_image = ctx.geometry.min_image();
    let radius = &p.radius;
    let mass = &p.mass;
    let x = SharedSlice::new(&mut p.x);
    let y = SharedSlice::new(&mut p.y);
    let vx = SharedSlice::new(&mut p.vx);
    let vy = SharedSlice::new(&mut p.vy);
    let geometry = ctx.geometry;
    let mut virial = ExactSum::new();
    for phase in &contacts.phases {
        // A contact costs a few cache misses: count it as a few discs' work.
        let pieces = &contacts.pieces[phase.clone()];
        let work = 4 * (pieces.last().map_or(0, |p| p.end) - pieces.first().map_or(0, |p| p.start));
        let partial = ctx.exec.map_index(work, phase.clone(), |piece| {
            let list = &contacts.list[contacts.pieces[piece].clone()];
            let mut virial = ExactSum::new();
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
                    if tally.is_none_or(|t| t.counts(x.get(a), y.get(a))) {
                        virial.add(diff[0] * impulse[0] + diff[1] * impulse[1]);
                    }
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
        for piece in &partial {
            virial.merge(piece);
        }
    }
    virial
}

/// Walls as contacts of a solver pass: every disc touching a wall (its centre at most its
/// radius from it, as [`Geometry::hold`] leaves pushed discs) and moving into it leaves with
/// its normal velocity reversed and scaled by the walls' restitution, like a reflection in
/// integration. Returns the momentum given to each wall by the discs the tally counts.
pub(crate) fn resolve_walls(p: &mut Particles, ctx: &StepContext) -> WallSums {
    let Geometry::Walls {
        min,
        max,
        restitution: e,
    } = ctx.geometry
    else {
        return WallSums::default();
    };
    let law = &ctx.law;
    let tally = ctx.tally;
    let (x, y, radius, mass) = (&p.x, &p.y, &p.radius, &p.mass);
    let mut chunks: Vec<(usize, &mut [f64], &mut [f64])> =
        p.vx.chunks_mut(CHUNK)
            .zip(p.vy.chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, (vx, vy))| (c * CHUNK, vx, vy))
            .collect();
    // One axis: the impulse on the low and the high wall.
    let touch = |position: f64, v: &mut f64, r: f64, m: f64, lo: f64, hi: f64| {
        if position <= lo + r && *v < 0.0 {
            [bounce(v, e, m), 0.0]
        } else if position >= hi - r && *v > 0.0 {
            [0.0, bounce(v, e, m)]
        } else {
            [0.0; 2]
        }
    };
    let partial = ctx
        .exec
        .map_mut(p.x.len(), &mut chunks, |_, (base, vx, vy)| {
            let mut impulse = WallSums::default();
            for (k, (vx, vy)) in vx.iter_mut().zip(vy.iter_mut()).enumerate() {
                let i = *base + k;
                let r = radius[i];
                let m = law.mass(r, mass[i]);
                let [left, right] = touch(x[i], vx, r, m, min[0], max[0]);
                let [bottom, top] = touch(y[i], vy, r, m, min[1], max[1]);
                if tally.is_none_or(|t| t.counts(x[i], y[i])) {
                    impulse.add([left, right, bottom, top]);
                }
            }
            impulse
        });
    let mut total = WallSums::default();
    for impulse in &partial {
        total.merge(impulse);
    }
    total
}
