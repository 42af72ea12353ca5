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

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

use crate::law::Law;
use crate::particles::{Particle, Particles};

/// Attempts per disc due before a step gives up on it.
const ATTEMPTS_PER_DISC: u64 = 8;

/// Adds discs in a rectangle at a rate.
///
/// ```
/// use bounce::{Boundary, Config, Emitter, World};
/// let config = Config {
///     boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
///     emitters: vec![Emitter {
///         rate: 50.0,
///         velocity: [3.0, 0.0],
///         ..Emitter::new([1.0, 1.0], [3.0, 19.0], 0.3)
///     }],
///     ..Config::default()
/// };
/// let mut world = World::new(config)?;
/// for _ in 0..100 {
///     world.step(0.01)?;
/// }
/// assert_eq!(world.len(), 50); // one second at 50 per second
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Emitter {
    /// Lower-left corner of the region centres go in.
    pub min: [f64; 2],
    /// Upper-right corner.
    pub max: [f64; 2],
    /// Discs per unit time, `>= 0`.
    pub rate: f64,
    /// Radii uniform in `[radius[0], radius[1]]`.
    pub radius: [f64; 2],
    /// The mean velocity.
    pub velocity: [f64; 2],
    /// Each velocity component gets a uniform random part in `[-spread, spread]`.
    pub spread: f64,
    /// The seed of the emitter's random numbers.
    pub seed: u64,
    /// Stop after this many discs (`None`: never).
    pub limit: Option<u64>,
}

impl Emitter {
    /// Discs of `radius` at rest in `[min, max]`, none yet (rate 0; set the rate).
    pub fn new(min: [f64; 2], max: [f64; 2], radius: f64) -> Emitter {
        Emitter {
            min,
            max,
            rate: 0.0,
            radius: [radius, radius],
            velocity: [0.0, 0.0],
            spread: 0.0,
            seed: 0,
            limit: None,
        }
    }

    /// What is wrong with it: `(value, expected)`.
    pub(crate) fn problem(&self) -> Option<(String, &'static str)> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let [r0, r1] = self.radius;
        if let Some(problem) = region_problem(self.min, self.max) {
            Some(problem)
        } else if !(self.rate.is_finite() && self.rate >= 0.0) {
            Some((format!("rate {}", self.rate), "must be finite and >= 0"))
        } else if !(r0.is_finite() && r0 > 0.0 && r1.is_finite() && r1 >= r0) {
            Some((
                format!("radius {:?}", self.radius),
                "must be finite, > 0, with min <= max",
            ))
        } else if !(finite(&self.velocity) && self.spread.is_finite() && self.spread >= 0.0) {
            Some((
                format!("velocity {:?}, spread {}", self.velocity, self.spread),
                "must be finite (spread >= 0)",
            ))
        } else {
            None
        }
    }

    /// The disc of attempt `attempt` (a pure function of the seed and the attempt).
    fn disc(&self, attempt: u64) -> Particle {
        // A different stream per attempt: the seed mixed with the attempt number.
        let mut rng = Pcg64Mcg::seed_from_u64(splitmix(self.seed ^ splitmix(attempt)));
        let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
        let [r0, r1] = self.radius;
        let r = uniform(r0, r1);
        let position = [
            uniform(self.min[0], self.max[0]),
            uniform(self.min[1], self.max[1]),
        ];
        let velocity = [
            self.velocity[0] + uniform(-self.spread, self.spread),
            self.velocity[1] + uniform(-self.spread, self.spread),
        ];
        Particle::new(position, velocity, r)
    }
}

/// SplitMix64's finaliser: a well-mixed 64-bit hash.
fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Removes discs whose centre enters a rectangle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sink {
    /// Lower-left corner.
    pub min: [f64; 2],
    /// Upper-right corner.
    pub max: [f64; 2],
}

impl Sink {
    /// Whether `p` is inside.
    #[inline]
    pub fn contains(&self, p: [f64; 2]) -> bool {
        p[0] >= self.min[0] && p[0] <= self.max[0] && p[1] >= self.min[1] && p[1] <= self.max[1]
    }

    pub(crate) fn problem(&self) -> Option<(String, &'static str)> {
        region_problem(self.min, self.max)
    }
}

/// What is wrong with the rectangle `[min, max]` of an emitter or a sink, if anything.
fn region_problem(min: [f64; 2], max: [f64; 2]) -> Option<(String, &'static str)> {
    let ok = min.iter().chain(&max).all(|v| v.is_finite()) && min[0] < max[0] && min[1] < max[1];
    (!ok).then(|| {
        (
            format!("min {min:?}, max {max:?}"),
            "the region must be finite with min below max",
        )
    })
}

/// How far an emitter has got: part of the world's saved state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EmitterState {
    /// Discs it has added.
    pub emitted: u64,
    /// Attempts it has made (placed or not): the next attempt's number.
    pub attempts: u64,
    /// Discs due and not yet placed (fractional).
    pub due: f64,
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
    let wanted = (state.due.floor() as u64).min(left);
    if wanted == 0 {
        return Vec::new();
    }
    // The discs that could touch a new one: centres within reach of the region.
    let r_max = p.radius().iter().copied().fold(emitter.radius[1], f64::max);
    let reach = law.collision_distance(emitter.radius[1], r_max);
    let near: Vec<([f64; 2], f64)> = (0..p.len())
        .filter(|&i| {
            let (x, y) = (p.x()[i], p.y()[i]);
            x >= emitter.min[0] - reach
                && x <= emitter.max[0] + reach
                && y >= emitter.min[1] - reach
                && y <= emitter.max[1] + reach
        })
        .map(|i| ([p.x()[i], p.y()[i]], p.radius()[i]))
        .collect();
    let mut placed: Vec<Particle> = Vec::new();
    let mut budget = wanted * ATTEMPTS_PER_DISC;
    while (placed.len() as u64) < wanted && budget > 0 {
        budget -= 1;
        let disc = emitter.disc(state.attempts);
        state.attempts += 1;
        let touches = |(q, r): ([f64; 2], f64)| {
            let d = [disc.position[0] - q[0], disc.position[1] - q[1]];
            law.is_colliding(d, disc.radius, r)
        };
        let clear = near.iter().all(|&q| !touches(q))
            && placed.iter().all(|o| !touches((o.position, o.radius)))
            && !blocked(&disc);
        if clear {
            placed.push(disc);
        }
    }
    state.emitted += placed.len() as u64;
    state.due -= placed.len() as f64;
    placed
}
