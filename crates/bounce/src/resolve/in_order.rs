//! One contact at a time, in a given order: what contact reports and a Lees–Edwards box
//! need, and the order (`solver_order`) in which it gives the fast solver's bits.

use crate::contacts::Contacts;
use crate::geometry::Geometry;
use crate::law::{Body, Law, Resolution, is_impact, virial_terms};
use crate::part::Tally;
use crate::particles::Particles;

use super::{Recording, Resolved};

/// A pair as [`resolve_in_order`] met it.
pub(crate) struct PairResolved {
    /// Storage indices, the lower id's first.
    pub a: usize,
    pub b: usize,
    /// `x_a - x_b` (the minimum image) when it was resolved.
    pub diff: [f64; 2],
    /// Disc `a`'s centre when it was resolved.
    pub at: [f64; 2],
    /// The two discs going in.
    pub before: [Body; 2],
    /// The law's resolution.
    pub out: Resolution,
}

/// The contacts of the last `Contacts::find` (storage indices) in an order that, resolved
/// one at a time, gives the solver's bits: its phases, pieces, colour rows and quarters in
/// turn (the quarters of a colour row touch disjoint discs, so their interleaving is free).
pub(crate) fn solver_order(contacts: &Contacts) -> Vec<(usize, usize)> {
    let list = contacts.list();
    let mut order = Vec::with_capacity(list.len());
    for phase in contacts.phases() {
        for piece in phase.clone() {
            for colour_rows in &contacts.pieces()[piece] {
                for s in colour_rows.clone() {
                    for quarter in contacts.quarters(s).into_iter().flatten() {
                        order.extend(list[quarter].iter().map(|c| (c.a as usize, c.b as usize)));
                    }
                }
            }
        }
    }
    order
}

/// The seed's steps 1–7 for each pair (storage indices, the lower id's first) in order, on
/// the current state (a disc pushed by one pair is seen at its new place by the next), with
/// rough discs' friction; walls hold after each push. `each` sees every pair as resolved.
/// Returns the collision virial, the impacts and the friction work of the pairs `tally`
/// counts (by the lower-id disc's place), as [`resolve_all`] does: the fast step's solver when
/// it reports contacts, measures the pressure tensor or counts collisions, and in a
/// Lees–Edwards box (the plain step resolves with its own loop, so this one is held to it).
pub(crate) fn resolve_in_order(
    p: &mut Particles,
    pairs: impl IntoIterator<Item = (usize, usize)>,
    law: &Law,
    geometry: &Geometry,
    (resting_speed, tally): (f64, Option<Tally>),
    recording: Recording,
    mut each: impl FnMut(&Particles, &PairResolved),
) -> Resolved {
    let min_image = geometry.min_image();
    let mut sums = Resolved::new();
    let rubs = law.rough.is_some_and(|rough| rough.rubs_pairs());
    for (a, b) in pairs {
        let diff = min_image.diff(p.x[a], p.y[a], p.x[b], p.y[b]);
        let body = |i: usize| Body {
            velocity: [p.vx[i], p.vy[i]],
            radius: p.radius[i],
            mass: law.mass(p.radius[i], p.mass[i]),
            angular_velocity: p.omega.get(i).copied().unwrap_or(0.0),
        };
        let (one, two) = (body(a), body(b));
        // Across a Lees–Edwards box's top or bottom, `b` is seen from `a`'s side.
        let out = law.resolve_seen(diff, &one, &two, min_image.image_velocity(p.y[a], p.y[b]));
        let at = [p.x[a], p.y[a]];
        if tally.is_none_or(|t| t.counts(at[0], at[1])) {
            let (term, tensor) = virial_terms(diff, out.impulse(&one, &two));
            sums.virial.add(term);
            let impact = is_impact(out.approach, resting_speed);
            sums.impacts += impact as usize;
            if rubs {
                sums.friction.add(out.friction_work);
            }
            if recording.tensor {
                for (sum, term) in sums.tensor.iter_mut().zip(tensor) {
                    sum.add(term);
                }
            }
            if recording.impacts && impact {
                sums.collided.extend([p.id[a].0, p.id[b].0]);
            }
        }
        p.x[a] += out.push[0];
        p.y[a] += out.push[1];
        p.x[b] -= out.push[0];
        p.y[b] -= out.push[1];
        for i in [a, b] {
            let (mut x, mut y) = (p.x[i], p.y[i]);
            geometry.hold(&mut x, &mut y, p.radius[i]);
            (p.x[i], p.y[i]) = (x, y);
        }
        [p.vx[a], p.vy[a]] = out.v1;
        [p.vx[b], p.vy[b]] = out.v2;
        if rubs {
            (p.omega[a], p.omega[b]) = (out.w1, out.w2);
        }
        let before = [one, two];
        each(
            p,
            &PairResolved {
                a,
                b,
                diff,
                at,
                before,
                out,
            },
        );
    }
    sums
}
