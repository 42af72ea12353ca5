//! Resolution: the law's pair resolution applied to every contact, in the canonical order.
//!
//! Pairs are resolved one after another on the current state (Gauss–Seidel style, as the
//! seed's loop does): a disc pushed by one pair is seen at its new place by the next. The
//! order is the wave order of `contacts` (the canonical order's bits in one sweep); the pieces
//! of one phase touch disjoint discs, so they run in parallel and still give the serial
//! result bit for bit.
//!
//! With more than one solver pass, walls are contacts too: after each pass's pairs,
//! [`resolve_walls`] bounces every disc that touches a wall and moves into it. Without it
//! only integration meets the walls, once per substep, and the floor can hold up a stack
//! only by the bounce of its bottom row: in a momentum-conserving model the whole pile then
//! sinks at a steady speed that the pushes undo (measured: mean vy ≈ -0.6 in the settled
//! shipped pile under `relative_normal_velocity`, a kinetic energy near 150).

use std::ops::Range;

use crate::config::MassModel;
use crate::contacts::{Contact, Contacts};
use crate::context::StepContext;
use crate::geometry::Geometry;
use crate::geometry::MinImage;
use crate::lanes::{F64x2, F64x4, Lanes};
use crate::law::rough::rub_pair;
use crate::law::{
    Body, Law, Resolution, Rough, hold, is_impact, resolve_lanes, rub_walls, touch_walls,
};
use crate::parallel::{CHUNK, SharedSlice, prefetch};
use crate::part::Tally;
use crate::particles::Particles;
use crate::sum::{ExactSum, WallSums};

/// What resolving the contacts of a substep adds up.
#[derive(Clone, Debug)]
pub(crate) struct Resolved {
    /// The collision virial `Σ r_ij · Δp_ij`, summed exactly (so in no particular order).
    pub virial: ExactSum,
    /// The pairs that met as impacts ([`is_impact`]), not resting contacts.
    pub impacts: usize,
    /// The energy friction and rolling resistance removed (rough discs), summed exactly.
    pub friction: ExactSum,
}

impl Resolved {
    pub(crate) fn new() -> Self {
        Resolved {
            virial: ExactSum::new(),
            impacts: 0,
            friction: ExactSum::new(),
        }
    }

    fn merge(&mut self, other: &Resolved) {
        self.virial.merge(&other.virial);
        self.impacts += other.impacts;
        self.friction.merge(&other.friction);
    }
}

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
        (true, true, true) => resolve_pieces::<true, true, true>(contacts, p, ctx, walls, r),
        (true, false, true) => resolve_pieces::<true, false, true>(contacts, p, ctx, walls, r),
        (true, true, false) => resolve_pieces::<true, true, false>(contacts, p, ctx, walls, r),
        (true, false, false) => resolve_pieces::<true, false, false>(contacts, p, ctx, walls, r),
        (false, true, true) => resolve_pieces::<false, true, true>(contacts, p, ctx, walls, r),
        (false, false, true) => resolve_pieces::<false, false, true>(contacts, p, ctx, walls, r),
        (false, true, false) => resolve_pieces::<false, true, false>(contacts, p, ctx, walls, r),
        (false, false, false) => resolve_pieces::<false, false, false>(contacts, p, ctx, walls, r),
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
) -> Resolved {
    let tally = ctx.tally;
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
    unsafe fn resolve<L: Lanes, const ROUGH: bool>(
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
            // The pair's impulse: half the difference of the momentum changes.
            let half = L::splat(0.5);
            // (Written out, not `[0, 1].map`: the compiler left that closure out of line.)
            let impulse_along = |k: usize| half * (ma * (v1[k] - va[k]) - mb * (v2[k] - vb[k]));
            let impulse = [impulse_along(0), impulse_along(1)];
            let term = diff[0] * impulse[0] + diff[1] * impulse[1];
            // The lanes' terms (zero where the tally does not count the pair) added together.
            let (xa_at, ya_at) = (lane_values(xa), lane_values(ya));
            let mut terms = lane_values(term);
            let approach = lane_values(out.approach);
            for k in 0..L::LANES {
                if tally.is_some_and(|t| !t.counts(xa_at[k], ya_at[k])) {
                    terms[k] = 0.0;
                    rubbed[k] = 0.0;
                } else {
                    sums.impacts += is_impact(approach[k], *resting_speed) as usize;
                }
            }
            sums.virial.add_all(&terms[..L::LANES]);
            if ROUGH {
                sums.friction.add_all(&rubbed[..L::LANES]);
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
            if discs.spin.is_some() {
                resolve::<L, true>(pair, discs, sums)
            } else {
                resolve::<L, false>(pair, discs, sums)
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
            // The pair's impulse: the antisymmetric part of the two momentum changes.
            let impulse = [0, 1].map(|k| {
                0.5 * (one.mass * (out.v1[k] - one.velocity[k])
                    - two.mass * (out.v2[k] - two.velocity[k]))
            });
            sums.virial.add(diff[0] * impulse[0] + diff[1] * impulse[1]);
            sums.impacts += is_impact(out.approach, resting_speed) as usize;
            if rubs {
                sums.friction.add(out.friction_work);
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
}

/// The lanes of `v` as an array of up to four.
#[inline(always)]
fn lane_values<L: Lanes>(v: L) -> [f64; 4] {
    let mut out = [0.0; 4];
    v.each(|k, v| out[k] = v);
    out
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
    let e = law.restitution_of(e);
    let tally = ctx.tally;
    let rubbing = law.rough.filter(|rough| rough.rubs_walls());
    let (x, y, radius, mass) = (&p.x, &p.y, &p.radius, &p.mass);
    // (The angular velocities' chunks are empty for smooth discs.)
    let mut omega_chunks: Vec<&mut [f64]> = p.omega.chunks_mut(CHUNK).collect();
    omega_chunks.resize_with(p.vx.len().div_ceil(CHUNK), || &mut []);
    type Chunk<'a> = (usize, &'a mut [f64], &'a mut [f64], &'a mut [f64]);
    let mut chunks: Vec<Chunk> =
        p.vx.chunks_mut(CHUNK)
            .zip(p.vy.chunks_mut(CHUNK))
            .zip(omega_chunks)
            .enumerate()
            .map(|(c, ((vx, vy), omega))| (c * CHUNK, vx, vy, omega))
            .collect();
    // One axis: the impulse on the low and the high wall.
    let partial = ctx
        .exec
        .map_mut(p.x.len(), &mut chunks, |_, (base, vx, vy, omega)| {
            let mut impulse = WallSums::default();
            for (k, (vx, vy)) in vx.iter_mut().zip(vy.iter_mut()).enumerate() {
                let i = *base + k;
                let r = radius[i];
                let m = law.mass(r, mass[i]);
                let [left, right] = touch_walls(x[i], vx, r, m, min[0], max[0], e);
                let [bottom, top] = touch_walls(y[i], vy, r, m, min[1], max[1], e);
                let hits = [left, right, bottom, top];
                let counted = tally.is_none_or(|t| t.counts(x[i], y[i]));
                if counted {
                    impulse.add(hits);
                }
                if let Some(rough) = &rubbing
                    && hits != [0.0; 4]
                {
                    let mut velocity = [*vx, *vy];
                    let work = rub_walls(hits, &mut velocity, &mut omega[k], r, m, rough);
                    [*vx, *vy] = velocity;
                    if counted {
                        impulse.friction.add(work);
                    }
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
