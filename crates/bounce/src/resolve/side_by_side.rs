//! The fast solver: a colour row's quarters (disjoint discs) side by side, one per lane, with
//! the bits of one contact at a time; the pieces of a phase in parallel.

use std::ops::Range;

use crate::config::MassModel;
use crate::contacts::{Contact, Contacts};
use crate::context::StepContext;
use crate::geometry::Geometry;
use crate::geometry::MinImage;
use crate::lanes::{F64x2, F64x4, Lanes};
use crate::law::rough::rub_pair;
use crate::law::{Law, Rough, hold, is_impact, pair_impulse, resolve_lanes, virial_terms};
use crate::parallel::{SharedSlice, prefetch};
use crate::part::Tally;
use crate::particles::Particles;

use super::{Recording, Resolved};

/// How many contacts ahead the solver asks for the discs' cache lines.
const PREFETCH_AHEAD: usize = 8;

/// Resolves every contact found by the last `Contacts::find`, colour by colour, and keeps
/// walls holding: a disc a push left beyond a wall is put back against it. Returns the
/// collision virial of the substep, `Σ r_ij · Δp_ij` over the resolved pairs (`r_ij` the
/// centre difference, `Δp_ij` the pair's impulse, the antisymmetric part of the two momentum
/// changes: exact when the model conserves momentum), summed exactly (so in no particular
/// order), and the impacts among them, over the contacts the step's tally counts (by the
/// lower-id disc's place).
/// `uniform_radius` is every disc's radius when all are equal (as the broadphase knows).
pub(crate) fn resolve_all(
    contacts: &Contacts,
    p: &mut Particles,
    ctx: &StepContext,
    uniform_radius: Option<f64>,
    recording: Recording,
) -> Resolved {
    // What the unsafe writes below rely on, checked once: the contacts index this storage
    // (their pieces' disjointness is `Contacts`' own invariant).
    assert_eq!(
        contacts.found_for(),
        p.len(),
        "contacts found for other particles"
    );
    // One loop per common case, so the boundary and the mass model are decided once, not
    // per contact.
    let walls = match ctx.geometry {
        Geometry::Walls { min, max, .. } => Some((min, max)),
        _ => None,
    };
    // Dense contacts (a pile) share their discs' cache lines; scattered ones (a gas) wait
    // for memory unless their discs are asked for ahead.
    let scattered = contacts.list().len() < p.len() / 4;
    let radius_is_mass = ctx.law.mass_model == MassModel::Radius;
    // Equal discs' radius is one number: not a fifth cache line per scattered disc, and for
    // dense contacts (which find theirs in cache) no lanes to gather and no sums of radii
    // or masses per contact.
    // (Unread unless `UNIFORM`.)
    let r = uniform_radius.unwrap_or(f64::NAN);
    match (scattered, radius_is_mass, uniform_radius.is_some()) {
        (true, true, true) => {
            resolve_pieces::<true, true, true>(contacts, p, ctx, walls, r, recording)
        }
        (true, false, true) => {
            resolve_pieces::<true, false, true>(contacts, p, ctx, walls, r, recording)
        }
        (true, true, false) => {
            resolve_pieces::<true, true, false>(contacts, p, ctx, walls, r, recording)
        }
        (true, false, false) => {
            resolve_pieces::<true, false, false>(contacts, p, ctx, walls, r, recording)
        }
        (false, true, true) => {
            resolve_pieces::<false, true, true>(contacts, p, ctx, walls, r, recording)
        }
        (false, false, true) => {
            resolve_pieces::<false, false, true>(contacts, p, ctx, walls, r, recording)
        }
        (false, true, false) => {
            resolve_pieces::<false, true, false>(contacts, p, ctx, walls, r, recording)
        }
        (false, false, false) => {
            resolve_pieces::<false, false, false>(contacts, p, ctx, walls, r, recording)
        }
    }
}

/// [`resolve_all`] with whether to prefetch (`PREFETCH`), whether the mass is the radius
/// (`RADIUS_MASS`, the seed's model) and whether every disc has radius `uniform_radius`
/// (`UNIFORM`) fixed, and the walls' corners if any.
///
/// Each colour row of a piece (one colour of one block row) is cut at block boundaries into four
/// quarters, which touch disjoint discs (see `contacts`): their contacts go through the law
/// two at a time, one per lane ([`F64x2`]), two such pairs side by side, with the bits of
/// one at a time.
fn resolve_pieces<const PREFETCH: bool, const RADIUS_MASS: bool, const UNIFORM: bool>(
    contacts: &Contacts,
    p: &mut Particles,
    ctx: &StepContext,
    walls: Option<([f64; 2], [f64; 2])>,
    uniform_radius: f64,
    recording: Recording,
) -> Resolved {
    let tally = ctx.tally;
    let ids = &p.id;
    let law = &ctx.law;
    let min_image = ctx.geometry.min_image();
    let radius = &p.radius;
    let mass = &p.mass;
    let x = SharedSlice::new(&mut p.x);
    let y = SharedSlice::new(&mut p.y);
    let vx = SharedSlice::new(&mut p.vx);
    let vy = SharedSlice::new(&mut p.vy);
    // Rough pairs turn their discs too.
    let omega = SharedSlice::new(&mut p.omega);
    let spin = law.rough.filter(|rough| rough.rubs_pairs());
    let radius_of = |i: usize| {
        if UNIFORM { uniform_radius } else { radius[i] }
    };
    let mass_of = |i: usize| {
        if RADIUS_MASS {
            radius_of(i)
        } else {
            law.mass(radius_of(i), mass[i])
        }
    };
    let prefetch_discs = |contact: &Contact| {
        for i in [contact.a as usize, contact.b as usize] {
            prefetch(x.address(i));
            prefetch(y.address(i));
            prefetch(vx.address(i));
            prefetch(vy.address(i));
            if !UNIFORM {
                prefetch(radius.as_ptr().wrapping_add(i));
            }
        }
    };
    // The contacts `pair(lane)` (storage indices, lower id first), one per lane; adds the
    // lanes' virial and impacts (those the tally counts) to `sums`.
    //
    // SAFETY (for callers): the lanes' contacts touch disjoint discs, and no other thread
    // touches them meanwhile: the contacts of one block touch discs in its cells and their
    // one-cell ring, and the pieces of one phase hold blocks rows that are that far apart
    // (see `Contacts::split`). Indices come from the current storage, so they are in bounds.
    #[inline(always)]
    unsafe fn resolve<L: Lanes, const ROUGH: bool, const RECORD: bool>(
        pair: impl Fn(usize) -> (usize, usize),
        discs: &Discs<'_, impl Fn(usize) -> f64, impl Fn(usize) -> f64>,
        sums: &mut Resolved,
    ) {
        let Discs {
            x,
            y,
            vx,
            vy,
            radius_of,
            mass_of,
            law,
            min_image,
            walls,
            tally,
            resting_speed,
            omega,
            spin,
            ids,
            recording,
        } = discs;
        // The lanes' indices read once: the disc stores below go through raw pointers, which
        // the compiler cannot tell apart from the contact list, so it would read them anew
        // after each.
        let (mut first, mut second) = ([0usize; 4], [0usize; 4]);
        for lane in 0..L::LANES {
            (first[lane], second[lane]) = pair(lane);
        }
        let (a, b) = (|k: usize| first[k], |k: usize| second[k]);
        // SAFETY: as the caller promises.
        unsafe {
            let (xa, ya) = (L::gather(|k| x.get(a(k))), L::gather(|k| y.get(a(k))));
            let (xb, yb) = (L::gather(|k| x.get(b(k))), L::gather(|k| y.get(b(k))));
            let diff = if min_image.is_periodic() {
                // The minimum image lane by lane (it branches on each difference).
                let (ax, ay, bx, by) = (
                    lane_values(xa),
                    lane_values(ya),
                    lane_values(xb),
                    lane_values(yb),
                );
                let image = |k: usize| min_image.diff(ax[k], ay[k], bx[k], by[k]);
                [L::gather(|k| image(k)[0]), L::gather(|k| image(k)[1])]
            } else {
                [xa - xb, ya - yb]
            };
            let va = [L::gather(|k| vx.get(a(k))), L::gather(|k| vy.get(a(k)))];
            let vb = [L::gather(|k| vx.get(b(k))), L::gather(|k| vy.get(b(k)))];
            let (ra, rb) = (
                L::gather(|k| radius_of(a(k))),
                L::gather(|k| radius_of(b(k))),
            );
            let (ma, mb) = (L::gather(|k| mass_of(a(k))), L::gather(|k| mass_of(b(k))));
            let out = resolve_lanes(diff, [va, vb], [ra, rb], [ma, mb], law);
            // Rough discs: the tangential impulse and the rolling couple.
            // (`ROUGH` says `spin` is `Some`: smooth discs' code has no trace of it.)
            let (v1, v2, mut rubbed) = match spin.as_ref().filter(|_| ROUGH) {
                None => (out.v1, out.v2, [0.0; 4]),
                Some(rough) => {
                    let (wa, wb) = (
                        L::gather(|k| omega.get(a(k))),
                        L::gather(|k| omega.get(b(k))),
                    );
                    let scale = law.collision_radius_scale;
                    let velocity = [out.v1, out.v2];
                    let rubbed = rub_pair(
                        out.normal,
                        [va, vb],
                        velocity,
                        [wa, wb],
                        [ra, rb],
                        [ma, mb],
                        scale,
                        rough,
                    );
                    rubbed.omega1.each(|k, v| omega.set(a(k), v));
                    rubbed.omega2.each(|k, v| omega.set(b(k), v));
                    (rubbed.v1, rubbed.v2, lane_values(rubbed.work))
                }
            };
            let impulse = pair_impulse([va, vb], [v1, v2], [ma, mb]);
            let (term, tensor) = virial_terms(diff, impulse);
            // The lanes' terms (zero where the tally does not count the pair) added together.
            let (xa_at, ya_at) = (lane_values(xa), lane_values(ya));
            let mut terms = lane_values(term);
            let mut tensor = tensor.map(lane_values);
            let approach = lane_values(out.approach);
            for k in 0..L::LANES {
                if tally.is_some_and(|t| !t.counts(xa_at[k], ya_at[k])) {
                    terms[k] = 0.0;
                    rubbed[k] = 0.0;
                    if RECORD {
                        tensor.iter_mut().for_each(|t| t[k] = 0.0);
                    }
                } else {
                    let impact = is_impact(approach[k], *resting_speed);
                    sums.impacts += impact as usize;
                    if RECORD && recording.impacts && impact {
                        sums.collided.extend([ids[a(k)].0, ids[b(k)].0]);
                    }
                }
            }
            sums.virial.add_all(&terms[..L::LANES]);
            if ROUGH {
                sums.friction.add_all(&rubbed[..L::LANES]);
            }
            if RECORD && recording.tensor {
                for (sum, terms) in sums.tensor.iter_mut().zip(&tensor) {
                    sum.add_all(&terms[..L::LANES]);
                }
            }
            let (mut xa, mut ya) = (xa + out.push[0], ya + out.push[1]);
            let (mut xb, mut yb) = (xb - out.push[0], yb - out.push[1]);
            if let Some((min, max)) = *walls {
                (xa, ya) = (hold(xa, ra, min[0], max[0]), hold(ya, ra, min[1], max[1]));
                (xb, yb) = (hold(xb, rb, min[0], max[0]), hold(yb, rb, min[1], max[1]));
            }
            xa.each(|k, v| x.set(a(k), v));
            ya.each(|k, v| y.set(a(k), v));
            xb.each(|k, v| x.set(b(k), v));
            yb.each(|k, v| y.set(b(k), v));
            v1[0].each(|k, v| vx.set(a(k), v));
            v1[1].each(|k, v| vy.set(a(k), v));
            v2[0].each(|k, v| vx.set(b(k), v));
            v2[1].each(|k, v| vy.set(b(k), v));
        }
    }
    let discs = Discs {
        x: &x,
        y: &y,
        vx: &vx,
        vy: &vy,
        radius_of,
        mass_of,
        law,
        min_image,
        walls,
        tally,
        resting_speed: ctx.resting_speed,
        omega: &omega,
        spin,
        ids,
        recording,
    };
    let mut sums = Resolved::new();
    let list = contacts.list();
    // The `k`th contacts of runs that touch disjoint discs, one per lane.
    //
    // SAFETY (for callers): the runs touch disjoint discs, as for `resolve`; there are at
    // least `L::LANES` of them, each a range of `list` longer than `k`.
    #[inline(always)]
    unsafe fn side_by_side<L: Lanes>(
        list: &[Contact],
        runs: &[Range<usize>],
        k: usize,
        discs: &Discs<'_, impl Fn(usize) -> f64, impl Fn(usize) -> f64>,
        sums: &mut Resolved,
    ) {
        let pair = |lane: usize| {
            debug_assert!(lane < runs.len() && runs[lane].start + k < runs[lane].end);
            debug_assert!(runs[lane].end <= list.len());
            // SAFETY: as the caller promises (the lanes' runs exist and hold contact `k`).
            let contact = unsafe { list.get_unchecked(runs.get_unchecked(lane).start + k) };
            (contact.a as usize, contact.b as usize)
        };
        // SAFETY: as the caller promises.
        unsafe {
            match (discs.spin.is_some(), discs.recording.any()) {
                (true, false) => resolve::<L, true, false>(pair, discs, sums),
                (false, false) => resolve::<L, false, false>(pair, discs, sums),
                (true, true) => resolve::<L, true, true>(pair, discs, sums),
                (false, true) => resolve::<L, false, true>(pair, discs, sums),
            }
        };
    }
    let prefetch_ahead = |runs: &[Range<usize>], k: usize| {
        if PREFETCH {
            // Contacts touch scattered discs: start loading later ones' discs now.
            for run in runs {
                if let Some(ahead) = list.get(run.start + k + PREFETCH_AHEAD / runs.len()) {
                    prefetch_discs(ahead);
                }
            }
        }
    };
    // One colour row: its four quarters (whole blocks, so disjoint discs) side by side, one
    // per lane, each in its own order; as quarters run out, the rest two at a time and the
    // last alone.
    let colour_row = |s: usize, sums: &mut Resolved| {
        // (An array, not a `Vec`: a gas's colour rows hold a contact or two, and an allocation
        // per colour row cost more than resolving them.)
        let [[q0, q1], [q2, q3]] = contacts.quarters(s);
        let mut runs = [q0, q1, q2, q3];
        loop {
            // The runs with contacts left first, in their order.
            runs.sort_by_key(|run| run.is_empty());
            let live = runs.iter().take_while(|run| !run.is_empty()).count();
            let lanes = match live {
                0 => break,
                1 => 1,
                2 | 3 => 2,
                _ => 4,
            };
            let runs = &mut runs[..lanes];
            let steps = runs.iter().map(|run| run.len()).min().unwrap_or(0);
            for k in 0..steps {
                prefetch_ahead(runs, k);
                // SAFETY: one contact of each of `lanes` quarters (`k` below every live
                // run's length, ranges of the list): disjoint discs.
                unsafe {
                    match lanes {
                        4 => side_by_side::<F64x4>(list, runs, k, &discs, sums),
                        2 => side_by_side::<F64x2>(list, runs, k, &discs, sums),
                        _ => side_by_side::<f64>(list, runs, k, &discs, sums),
                    }
                }
            }
            for run in runs {
                run.start += steps;
            }
        }
    };
    for phase in contacts.phases() {
        // A contact costs a few cache misses: count it as a few discs' work.
        let work = 4 * phase
            .clone()
            .map(|p| contacts.piece_contacts(p))
            .sum::<usize>();
        let partial = ctx.exec.map_index(work, phase.clone(), |piece| {
            let mut sums = Resolved::new();
            for colour_rows in &contacts.pieces()[piece] {
                for s in colour_rows.clone() {
                    colour_row(s, &mut sums);
                }
            }
            sums
        });
        for piece in &partial {
            sums.merge(piece);
        }
    }
    sums
}

/// What resolving a contact reads besides the contact.
struct Discs<'a, R, M> {
    x: &'a SharedSlice<'a, f64>,
    y: &'a SharedSlice<'a, f64>,
    vx: &'a SharedSlice<'a, f64>,
    vy: &'a SharedSlice<'a, f64>,
    radius_of: R,
    mass_of: M,
    law: &'a Law,
    min_image: MinImage,
    walls: Option<([f64; 2], [f64; 2])>,
    tally: Option<Tally>,
    /// The approach speed above which a contact is an impact.
    resting_speed: f64,
    /// The angular velocities (empty for smooth discs).
    omega: &'a SharedSlice<'a, f64>,
    /// Rough pairs' coefficients, when pairs rub.
    spin: Option<Rough>,
    /// The discs' ids (read only when recording impacts).
    ids: &'a [crate::ParticleId],
    recording: Recording,
}

/// The lanes of `v` as an array of up to four.
#[inline(always)]
fn lane_values<L: Lanes>(v: L) -> [f64; 4] {
    let mut out = [0.0; 4];
    v.each(|k, v| out[k] = v);
    out
}
