//! Emitters and sinks: discs entering and leaving the world during a run.
//!
//! An [`Emitter`] adds discs in a rectangle at a rate (discs per unit time), radii uniform in
//! a range, velocities a mean plus a uniform spread per component. Each *attempt* to place a
//! disc draws its numbers from a generator seeded by the emitter's seed and the attempt's
//! number, so the discs depend on the state alone: the same on any thread count and after
//! a checkpoint (which keeps the counts, [`EmitterState`]). An attempt whose disc would
//! touch another disc or an obstacle is dropped; a step makes at most a few attempts per
//! disc due and carries what it could not place to the next step (at most one step's worth).
//!
//! A [`Sink`] removes every disc whose centre is inside its rectangle at the end of a step.
//! Ids are never reused: a new disc takes the next id after every id ever given.

use std::collections::HashMap;

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

use crate::config::{Emitter, EmitterState};
use crate::law::Law;
use crate::particles::{Particle, Particles};

/// Attempts per disc due before a step gives up on it.
const ATTEMPTS_PER_DISC: u64 = 8;

/// The disc of attempt `attempt` (a pure function of the seed and the attempt).
fn disc(emitter: &Emitter, attempt: u64) -> Particle {
    // A different stream per attempt: the seed mixed with the attempt number.
    let mut rng = Pcg64Mcg::seed_from_u64(splitmix(emitter.seed ^ splitmix(attempt)));
    let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
    let [r0, r1] = emitter.radius;
    let r = uniform(r0, r1);
    let position = [
        uniform(emitter.min[0], emitter.max[0]),
        uniform(emitter.min[1], emitter.max[1]),
    ];
    let velocity = [
        emitter.velocity[0] + uniform(-emitter.spread, emitter.spread),
        emitter.velocity[1] + uniform(-emitter.spread, emitter.spread),
    ];
    Particle::new(position, velocity, r)
}

/// SplitMix64's finaliser: a well-mixed 64-bit hash.
pub(crate) fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The discs `emitter` adds in a step of `dt`, clear of `p` (and of each other and of what
/// `blocked` refuses), advancing its `state`.
pub(crate) fn emit(
    emitter: &Emitter,
    state: &mut EmitterState,
    dt: f64,
    p: &Particles,
    law: &Law,
    blocked: impl Fn(&Particle) -> bool,
) -> Vec<Particle> {
    let left = emitter
        .limit
        .map_or(u64::MAX, |l| l.saturating_sub(state.emitted));
    // What could not be placed is carried, but never more than one step's worth.
    let per_step = emitter.rate * dt;
    state.due = (state.due + per_step).min(per_step.max(1.0) + 1.0);
    // And never more than the region can hold: centres at least a collision distance `d`
    // apart each own a disc of diameter `d`, inside the region grown by `d / 2` on each side.
    let d = law.collision_distance(emitter.radius[0], emitter.radius[0]);
    let [w, h] = [
        emitter.max[0] - emitter.min[0],
        emitter.max[1] - emitter.min[1],
    ];
    let capacity = ((w + d) * (h + d) / (std::f64::consts::FRAC_PI_4 * d * d)).floor() + 1.0;
    let wanted = (state.due.floor().min(capacity) as u64).min(left);
    if wanted == 0 {
        return Vec::new();
    }
    // The discs that could touch a new one: centres within reach of the region, in cells a
    // reach wide (a new disc meets only the 3×3 cells around it).
    let r_max = p.radius().iter().copied().fold(emitter.radius[1], f64::max);
    let reach = law.collision_distance(emitter.radius[1], r_max);
    let cell_of = |q: [f64; 2]| [(q[0] / reach).floor() as i64, (q[1] / reach).floor() as i64];
    let mut near: HashMap<[i64; 2], Vec<([f64; 2], f64)>> = HashMap::new();
    for i in 0..p.len() {
        let (x, y) = (p.x()[i], p.y()[i]);
        if x >= emitter.min[0] - reach
            && x <= emitter.max[0] + reach
            && y >= emitter.min[1] - reach
            && y <= emitter.max[1] + reach
        {
            near.entry(cell_of([x, y]))
                .or_default()
                .push(([x, y], p.radius()[i]));
        }
    }
    let mut placed: Vec<Particle> = Vec::new();
    let mut budget = wanted * ATTEMPTS_PER_DISC;
    while (placed.len() as u64) < wanted && budget > 0 {
        budget -= 1;
        let disc = disc(emitter, state.attempts);
        state.attempts += 1;
        let touches = |&(q, r): &([f64; 2], f64)| {
            let d = [disc.position[0] - q[0], disc.position[1] - q[1]];
            law.is_colliding(d, disc.radius, r)
        };
        let [cx, cy] = cell_of(disc.position);
        let clear = (-1..=1).all(|dy| {
            (-1..=1).all(|dx| {
                let cell = [cx.saturating_add(dx), cy.saturating_add(dy)];
                near.get(&cell).is_none_or(|list| !list.iter().any(touches))
            })
        }) && !blocked(&disc);
        if clear {
            near.entry(cell_of(disc.position))
                .or_default()
                .push((disc.position, disc.radius));
            placed.push(disc);
        }
    }
    state.emitted += placed.len() as u64;
    state.due -= placed.len() as f64;
    placed
}
