//! Emitters and sinks as the configuration describes them, and an emitter's saved state.
//! What they do during a step is `sources`.

use serde::{Deserialize, Serialize};

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
    /// Discs of `radius` at rest in `[min, max]`, none yet (rate 0; set the rate). See
    /// [`Emitter`] for an example.
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
}

/// Removes discs whose centre enters a rectangle.
///
/// ```
/// use bounce::{Config, Particle, Sink, World};
/// let drain = Sink { min: [4.0, -1.0], max: [6.0, 1.0] };
/// assert!(drain.contains([5.0, 0.0]) && !drain.contains([7.0, 0.0]));
/// let mut world = World::new(Config { sinks: vec![drain], ..Config::default() })?;
/// world.add_particle(Particle::new([0.0, 0.0], [10.0, 0.0], 0.5))?;
/// for _ in 0..50 {
///     world.step(0.01)?;
/// }
/// assert_eq!(world.len(), 0); // taken when its centre crossed x = 4
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sink {
    /// Lower-left corner.
    pub min: [f64; 2],
    /// Upper-right corner.
    pub max: [f64; 2],
}

impl Sink {
    /// Whether `p` is inside. See [`Sink`] for an example.
    #[inline]
    pub fn contains(&self, p: [f64; 2]) -> bool {
        p[0] >= self.min[0] && p[0] <= self.max[0] && p[1] >= self.min[1] && p[1] <= self.max[1]
    }

    pub(crate) fn problem(&self) -> Option<(String, &'static str)> {
        region_problem(self.min, self.max)
    }
}

/// What is wrong with the rectangle `[min, max]` of an emitter, a sink or a sensor, if
/// anything.
pub(super) fn region_problem(min: [f64; 2], max: [f64; 2]) -> Option<(String, &'static str)> {
    let ok = min.iter().chain(&max).all(|v| v.is_finite()) && min[0] < max[0] && min[1] < max[1];
    (!ok).then(|| {
        (
            format!("min {min:?}, max {max:?}"),
            "the region must be finite with min below max",
        )
    })
}

/// How far an emitter has got: part of the world's saved state. See
/// [`crate::World::emitter_states`] for an example.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EmitterState {
    /// Discs it has added.
    pub emitted: u64,
    /// Attempts it has made (placed or not): the next attempt's number.
    pub attempts: u64,
    /// Discs due and not yet placed (fractional).
    pub due: f64,
}
