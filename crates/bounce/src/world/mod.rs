//! The world: configuration, particles, what the step keeps between steps, and the API
//! around them (the step's script of stages is in `step`). Inputs are
//! validated at the edges (`new`, `add_particle`, `set_config`, loading a checkpoint), so the
//! step itself cannot fail for any state reachable through this API.

use std::sync::atomic::AtomicUsize;
use std::sync::{Arc, OnceLock};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::broadphase::Broadphase;
use crate::config::{Config, ConfigError};
use crate::config::{EmitterState, ObstacleState};
use crate::contact_events::{ContactEvent, ContactLog};
use crate::contacts::Contacts;
use crate::geometry::Geometry;
use crate::law::Law;
use crate::obstacles::{Obstacles, Trail};
use crate::parallel::{Executor, ThreadsError};
use crate::part::{Tally, Travel};
use crate::particles::{Particle, ParticleError, ParticleId, Particles};
use crate::stats::{Measured, StepProfile, StepStats, measure};
use crate::sum::StepSums;

mod access;
mod emitters;
mod events;
mod obstacles;
mod part;
mod pressure;
mod report;
mod rotation;
mod sensors;

mod state;
mod step;
mod work;

pub use sensors::{SensorCount, SensorState};
pub use state::SavedWorld;
#[cfg(test)]
mod tests;

use access::IndexMap;
use obstacles::initial_states;
use state::{WorldState, serialize_reference};
pub(crate) use step::{Substepped, substep_end};

/// A 2D world of discs. See the [crate docs](crate) for an example.
///
/// `World` serializes with serde (configuration, particles in storage order, time, step
/// count); a world loaded from that data continues bit-identically. Loading validates
/// everything, like [`World::new`] and [`World::add_particle`] do.
#[derive(Debug, Serialize, Deserialize)]
#[serde(try_from = "WorldState")]
pub struct World {
    pub(crate) config: Config,
    pub(crate) particles: Particles,
    next_id: u32,
    time: f64,
    steps: u64,
    pub(crate) stats: StepStats,
    #[serde(skip)]
    profile: StepProfile,
    /// What the last measurement found: the fastest disc and the smallest radius choose
    /// adaptive substeps. Derived from the state, so recomputed on loading.
    #[serde(skip)]
    measured: Measured,
    /// Saved as its reference positions: when the candidate list is rebuilt decides the
    /// storage order, and so the last bits of the energy and impulse sums.
    #[serde(rename = "reference", serialize_with = "serialize_reference")]
    pub(crate) broadphase: Broadphase,
    /// Where each obstacle of the configuration is and how fast it moves (moving ones).
    pub(crate) obstacle_states: Vec<ObstacleState>,
    /// The momentum each obstacle received in the last step.
    obstacle_impulses: Vec<[f64; 2]>,
    /// The work moving obstacles have done on the discs since the start.
    obstacle_work: f64,
    /// The energy friction and rolling resistance have removed since the start.
    friction_work: f64,
    /// The kinetic energy the thermostat has added since the start.
    thermostat_work: f64,
    /// The obstacles binned for the step; `None` until the next step builds them.
    #[serde(skip)]
    pub(crate) obstacles: Option<Obstacles>,
    /// The largest disc radius the obstacles' grid covers.
    #[serde(skip)]
    obstacle_radius: f64,
    /// Where the discs were last on the right side of every segment (with obstacles).
    #[serde(skip)]
    trail: Trail,
    #[serde(skip)]
    contacts: Contacts,
    #[serde(skip)]
    exec: Executor,
    /// How far each emitter has got.
    emitter_states: Vec<EmitterState>,
    /// How many discs have been removed (sinks, `remove_particles`): ids run to
    /// `next_id = len + removed`, with gaps where removed ones were.
    removed: u32,
    /// The last substep's contacts and the last step's contact events (with
    /// [`Config::contact_events`]).
    pub(crate) contact_log: ContactLog,
    /// Each sensor's discs and counts.
    sensors: sensors::SensorState,
    /// Which emitter gave which ids: `[first id, count, emitter]`, ascending (runs of
    /// consecutive ids from one emitter are merged).
    emitted_ids: Vec<[u32; 3]>,
    /// Each id's collisions with other discs so far, with [`Config::collision_counts`].
    collision_counts: Vec<u64>,
    /// The discs the emitters added in the last step, with their emitter.
    #[serde(skip)]
    emitted_last_step: Vec<(ParticleId, u32)>,
    /// Where each id is stored, built on demand after each step.
    #[serde(skip)]
    index_of: OnceLock<IndexMap>,
    /// Which events the step's sums count (`None`: all; see `part`).
    #[serde(skip)]
    tally: Option<Tally>,
    /// The contact order's grid is sized for discs up to this radius at least (the whole
    /// world's largest, in a part of it; see `part`).
    #[serde(skip)]
    order_radius: f64,
    /// The exact sums of the last step.
    #[serde(skip)]
    sums: StepSums,
    /// A bound on how far discs have moved since the world was made.
    #[serde(skip)]
    travel: Travel,
    /// A flag another thread (a signal handler) sets non-zero to stop a step between two of
    /// its substeps (see [`World::set_interrupt`]).
    #[serde(skip)]
    interrupt: Option<Arc<AtomicUsize>>,
}

/// Why a step was refused.
///
/// ```
/// use bounce::{Config, StepError, World};
/// let error = World::new(Config::default())?.step(-1.0).unwrap_err();
/// assert_eq!(error, StepError::InvalidTimeStep(-1.0));
/// assert_eq!(error.to_string(), "time step dt = -1 must be finite and > 0");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Error)]
pub enum StepError {
    /// The time step is not a finite number `> 0`.
    #[error("time step dt = {0} must be finite and > 0")]
    InvalidTimeStep(f64),
    /// With `max_travel`, the fastest disc would need more substeps than
    /// [`crate::MAX_SUBSTEPS`] in a step of `dt`: the step is refused rather than let discs
    /// tunnel.
    #[error(
        "dt {dt} needs more than {} substeps to keep the fastest disc within max_travel \
         {max_travel} of the smallest radius per substep: lower dt or raise max_travel",
        crate::MAX_SUBSTEPS
    )]
    TooManySubsteps {
        /// The time step.
        dt: f64,
        /// The configured `max_travel`.
        max_travel: f64,
    },
    /// The interrupt flag ([`World::set_interrupt`]) was set during a step of several
    /// substeps: the step stopped between two of them, and the world is left there, part of
    /// the way through the step. Restore it from a copy taken before the step. (Under the
    /// event-driven method the flag is read between events, and the world is left as it
    /// was before the step.)
    #[error("step {step} was interrupted between two of its substeps")]
    Interrupted {
        /// The step that was interrupted.
        step: u64,
    },
    /// The clock would pass what `f64` holds: the time after the step is not finite.
    #[error("time {time} + dt {dt} overflows the clock (dt is too large for the run)")]
    ClockOverflow {
        /// The time before the step.
        time: f64,
        /// The time step.
        dt: f64,
    },
    /// The event-driven method could not start or go on (discs overlap, or the run
    /// stalled); its discs are named by their ids.
    #[error(transparent)]
    EventDriven(#[from] crate::event::EventError),
    /// A position or velocity overflowed (became infinite or NaN) during the step: the time
    /// step, gravity or speeds are too large for `f64`. The world's state is no longer
    /// usable; reload a checkpoint.
    #[error(
        "step {step}: particle {id} has a non-finite position, velocity or kinetic energy (dt, \
         gravity or speeds too large for f64)"
    )]
    NonFinite {
        /// The step that overflowed.
        step: u64,
        /// The first particle (by id) with a non-finite value, when one is.
        id: String,
    },
}

/// Why a configuration or loaded state was refused. See [`World::set_config`] for an example.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum WorldError {
    /// The configuration is invalid.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A particle does not fit the configuration.
    #[error("disc {}: {error}", id.0)]
    Particle {
        /// The particle's id.
        id: ParticleId,
        /// What is wrong with it.
        error: ParticleError,
    },
    /// Loaded data is inconsistent (array lengths, duplicate ids).
    #[error("inconsistent world data: {0}")]
    Inconsistent(String),
}

impl World {
    /// An empty world; fails if the configuration is invalid.
    ///
    /// ```
    /// use bounce::{Config, World};
    /// assert!(World::new(Config::default()).is_ok());
    /// let bad = Config { collision_radius_scale: -1.0, ..Config::default() };
    /// assert_eq!(World::new(bad).unwrap_err().field, "collision_radius_scale");
    /// ```
    pub fn new(config: Config) -> Result<World, ConfigError> {
        config.validate()?;
        let (obstacle_states, obstacle_count) = (initial_states(&config), config.obstacles.len());
        let emitter_count = config.emitters.len();
        let sensors = sensors::SensorState::new(&config.sensors);
        let mut particles = Particles::default();
        if config.is_rough() {
            particles.start_turning();
        }
        Ok(World {
            config,
            particles,
            next_id: 0,
            time: 0.0,
            steps: 0,
            stats: StepStats::default(),
            profile: StepProfile::default(),
            measured: Measured::default(),
            broadphase: Broadphase::default(),
            obstacle_states,
            obstacle_impulses: vec![[0.0; 2]; obstacle_count],
            obstacle_work: 0.0,
            friction_work: 0.0,
            thermostat_work: 0.0,
            obstacles: None,
            trail: Trail::default(),
            obstacle_radius: 0.0,
            emitter_states: vec![EmitterState::default(); emitter_count],
            removed: 0,
            contact_log: ContactLog::default(),
            sensors,
            emitted_ids: Vec::new(),
            collision_counts: Vec::new(),
            emitted_last_step: Vec::new(),
            contacts: Contacts::default(),
            exec: Executor::default(),
            index_of: OnceLock::new(),
            tally: None,
            order_radius: 0.0,
            sums: StepSums::default(),
            travel: Travel::default(),
            interrupt: None,
        })
    }

    /// The configuration. See [`World::set_config`] for an example.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Replaces the configuration. Fails, leaving the world unchanged, if the configuration is
    /// invalid or a particle does not fit it (outside a new box, too large for it).
    ///
    /// ```
    /// use bounce::{Boundary, Config, Obstacle, Particle, World, WorldError};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([5.0, 5.0], [0.0, 0.0], 1.0))?;
    /// let walls = |side| Config { boundary: Boundary::walls([0.0, 0.0], [side, side]), ..Config::default() };
    /// world.set_config(walls(10.0))?;
    /// // A box the disc is outside of is refused; the world keeps its configuration.
    /// assert!(matches!(world.set_config(walls(3.0)), Err(WorldError::Particle { .. })));
    /// assert_eq!(world.config(), &walls(10.0));
    /// world.add_obstacles([Obstacle::peg([2.0, 2.0], 0.5)])?;
    /// assert_eq!(world.config().obstacles.len(), 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_config(&mut self, config: Config) -> Result<(), WorldError> {
        config.validate()?;
        let (geometry, law) = (Geometry::new(&config), Law::new(&config));
        let p = &self.particles;
        for i in 0..p.len() {
            geometry
                .admit([p.x[i], p.y[i]], p.radius[i], &law)
                .map_err(|error| WorldError::Particle { id: p.id[i], error })?;
        }
        if config.obstacles != self.config.obstacles {
            // Obstacles that stay where they were in the list keep their motion; new or
            // changed ones start at their configured place.
            let fresh = initial_states(&config);
            let old = &self.config.obstacles;
            self.obstacle_states = (0..config.obstacles.len())
                .map(|k| match old.get(k) {
                    Some(o) if *o == config.obstacles[k] => self.obstacle_states[k],
                    _ => fresh[k],
                })
                .collect();
            self.obstacle_impulses = vec![[0.0; 2]; config.obstacles.len()];
        }
        if config.emitters != self.config.emitters {
            // Emitters that stay keep their counts; new or changed ones start afresh.
            let old = &self.config.emitters;
            self.emitter_states = (0..config.emitters.len())
                .map(|k| match old.get(k) {
                    Some(e) if *e == config.emitters[k] => self.emitter_states[k],
                    _ => EmitterState::default(),
                })
                .collect();
        }
        if config.is_rough() {
            self.particles.start_turning();
        }
        self.sensors.fit(&config.sensors);
        self.config = config;
        self.obstacles = None;
        self.broadphase.invalidate();
        self.refresh_stats();
        Ok(())
    }

    /// Adds obstacles after the existing ones (which keep their motion). Fails, leaving the
    /// world unchanged, if one is invalid. See [`World::set_config`] for an example.
    pub fn add_obstacles(
        &mut self,
        obstacles: impl IntoIterator<Item = crate::Obstacle>,
    ) -> Result<(), WorldError> {
        let mut config = self.config.clone();
        config.obstacles.extend(obstacles);
        self.set_config(config)
    }

    /// Adds a disc and returns its id. Fails, leaving the world unchanged, on a non-finite
    /// position or velocity, a radius or mass that is not finite and positive, or a centre
    /// outside the box. See the [crate docs](crate) for an example.
    pub fn add_particle(&mut self, particle: Particle) -> Result<ParticleId, ParticleError> {
        self.add_particles([particle])
            .map(|ids| ids[0])
            .map_err(|(_, e)| e)
    }

    /// Adds discs all or nothing: on the first invalid one, returns its index in the input
    /// and the error, and the world is unchanged.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default()).unwrap();
    /// let (ok, bad) = (Particle::new([0.0, 0.0], [0.0, 0.0], 1.0), Particle::new([f64::NAN, 0.0], [0.0, 0.0], 1.0));
    /// assert_eq!(world.add_particles([ok, bad]).unwrap_err().0, 1);
    /// assert!(world.is_empty());
    /// assert_eq!(world.add_particles([ok, ok]).unwrap().len(), 2);
    /// ```
    pub fn add_particles(
        &mut self,
        particles: impl IntoIterator<Item = Particle>,
    ) -> Result<Vec<ParticleId>, (usize, ParticleError)> {
        let start = self.particles.len();
        let mut ids = Vec::new();
        for (k, particle) in particles.into_iter().enumerate() {
            let checked = particle.validate(&self.config).and_then(|()| {
                u32::try_from(start + k)
                    .ok()
                    .filter(|&id| id < u32::MAX)
                    .ok_or(ParticleError::TooMany)
            });
            if let Err(e) = checked {
                self.particles.truncate(start);
                return Err((k, e));
            }
            let id = ParticleId(self.next_id + k as u32);
            self.particles.push(id, &particle);
            ids.push(id);
        }
        self.next_id += ids.len() as u32;
        self.index_of = OnceLock::new();
        // The obstacles' grid covers discs up to the radius it was built for.
        if self.particles.radius[start..]
            .iter()
            .any(|&r| r > self.obstacle_radius)
        {
            self.obstacles = None;
        }
        self.broadphase.invalidate();
        self.refresh_stats();
        Ok(ids)
    }

    /// A flag that, once another thread (a signal handler) sets it non-zero, stops a step of
    /// several substeps between two of them with [`StepError::Interrupted`], leaving the
    /// world part of the way through the step: a front end that sets it keeps a copy of the
    /// world from before the step to go back to. `None` (the default): steps always finish.
    ///
    /// ```
    /// use std::sync::{Arc, atomic::AtomicUsize};
    /// use bounce::{Config, Particle, StepError, World};
    /// let mut world = World::new(Config { substeps: 4, ..Config::default() })?;
    /// world.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 0.5))?;
    /// world.set_interrupt(Some(Arc::new(AtomicUsize::new(2)))); // a signal came
    /// assert_eq!(world.step(0.1).unwrap_err(), StepError::Interrupted { step: 1 });
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_interrupt(&mut self, flag: Option<Arc<AtomicUsize>>) {
        self.interrupt = flag;
    }

    /// Runs `threads` worker threads for the step (1 = on the calling thread, the default).
    /// Results are bit-identical for every thread count (see [`World::state_hash`]).
    ///
    /// ```
    /// use bounce::{Config, World};
    /// let mut world = World::new(Config::default())?;
    /// world.set_threads(2)?;
    /// world.set_parallel_min_work(0); // every stage on the workers, however small
    /// assert_eq!(world.threads(), 2);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_threads(&mut self, threads: usize) -> Result<(), ThreadsError> {
        let min_work = self.exec.min_work;
        self.exec = Executor::new(threads)?;
        self.exec.min_work = min_work;
        Ok(())
    }

    /// Work below `min_work` units (about one per disc, a few per contact) runs on the
    /// calling thread even with worker threads: waking them costs more than small work saves.
    /// The default is [`DEFAULT_PARALLEL_MIN_WORK`](crate::DEFAULT_PARALLEL_MIN_WORK); 0
    /// runs every stage on the workers. Results never depend on it. See
    /// [`World::set_threads`] for an example.
    pub fn set_parallel_min_work(&mut self, min_work: usize) {
        self.exec.min_work = min_work;
    }

    /// The number of worker threads the step uses. See [`World::set_threads`] for an example.
    pub fn threads(&self) -> usize {
        self.exec.threads()
    }

    /// Advances the world by `dt`, in `config.substeps` substeps (more with
    /// `config.max_travel`), and returns what it measured. See [`World::stats`] for an
    /// example.
    pub fn step(&mut self, dt: f64) -> Result<&StepStats, StepError> {
        let substeps = self.substeps_for(dt);
        self.step_with_substeps(dt, substeps)
    }

    /// [`World::step`] in exactly `substeps` substeps (at least 1, at most
    /// [`crate::MAX_SUBSTEPS`]): for a part of a distributed world, whose substeps the whole
    /// world's fastest disc decides (see [`World::substeps_for_extremes`], which has an
    /// example).
    pub fn step_with_substeps(&mut self, dt: f64, substeps: u32) -> Result<&StepStats, StepError> {
        let installer = self.exec.installer(self.particles.len());
        if self.config.method == crate::Method::EventDriven {
            // One thread: events happen one after the other.
            self.step_events(dt)?;
        } else {
            installer.install(|| self.step_in_pool(dt, substeps))?;
        }
        Ok(&self.stats)
    }

    /// The substeps a step of `dt` takes: `config.substeps`, or with `config.max_travel` as
    /// many as keep the fastest disc (gravity included) within `max_travel` of the smallest
    /// radius per substep (more than [`crate::MAX_SUBSTEPS`] is refused by the step).
    pub(crate) fn substeps_for(&self, dt: f64) -> u32 {
        self.substeps_for_extremes(dt, self.measured.max_speed2, self.measured.min_radius)
    }

    /// The substeps a step of `dt` takes when the fastest disc's squared speed is
    /// `max_speed2` and the smallest radius `min_radius` (what [`World::step`] measures over
    /// its own discs; a distributed run gives the whole world's). More than
    /// [`crate::MAX_SUBSTEPS`] means too many: [`World::step_with_substeps`] refuses it.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config { max_travel: Some(0.5), ..Config::default() })?;
    /// // Speed 8 for 0.25 with at most half of radius 0.5 per substep: 8 substeps.
    /// assert_eq!(world.substeps_for_extremes(0.25, 64.0, 0.5), 8);
    /// world.add_particle(Particle::new([0.0, 0.0], [8.0, 0.0], 0.5))?;
    /// assert_eq!(world.step_with_substeps(0.25, 8)?.substeps, 8);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn substeps_for_extremes(&self, dt: f64, max_speed2: f64, min_radius: f64) -> u32 {
        let fixed = self.config.substeps;
        let Some(fraction) = self.config.max_travel else {
            return fixed;
        };
        let [gx, gy] = self.config.gravity;
        let v_max = max_speed2.sqrt() + (gx * gx + gy * gy).sqrt() * dt;
        let needed = (v_max * dt / (fraction * min_radius)).ceil();
        if needed > crate::MAX_SUBSTEPS as f64 {
            // More than a step may take (or infinitely many): the step refuses it.
            crate::MAX_SUBSTEPS + 1
        } else if needed > fixed as f64 {
            needed as u32
        } else {
            fixed
        }
    }

    /// The contacts that began and ended in the last step's substeps, substep by substep,
    /// each substep's in the order of the parties' ids (see [`ContactEvent`]); empty unless
    /// [`Config::contact_events`] is on.
    ///
    /// ```
    /// use bounce::{Config, ContactKind, Party, Particle, World};
    /// let config = Config { contact_events: true, ..Config::default() };
    /// let mut world = World::new(config).unwrap();
    /// let a = world.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 1.0)).unwrap();
    /// let b = world.add_particle(Particle::new([2.5, 0.0], [0.0, 0.0], 1.0)).unwrap();
    /// let mut begins: Vec<bounce::ContactEvent> = Vec::new();
    /// for _ in 0..100 {
    ///     world.step(0.01).unwrap();
    ///     let events = world.contact_events().iter();
    ///     begins.extend(events.filter(|e| e.kind == ContactKind::Begin));
    /// }
    /// // Equal masses at e = 1: the first stops, the second leaves at 1, an impulse of 1.
    /// assert_eq!(begins.len(), 1);
    /// assert_eq!((begins[0].a, begins[0].b), (a, Party::Disc(b)));
    /// assert!((begins[0].normal_impulse - 1.0).abs() < 1e-12);
    /// ```
    pub fn contact_events(&self) -> &[ContactEvent] {
        self.contact_log.events()
    }

    /// The lowest id with a non-finite position, velocity or kinetic energy, or `?` when
    /// there is none (then only a sum overflowed).
    fn first_non_finite(&self) -> String {
        let p = &self.particles;
        let law = Law::new(&self.config);
        (0..p.len())
            .filter(|&i| {
                let m = law.mass(p.radius[i], p.mass[i]);
                let energy = 0.5 * m * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i]);
                ![p.x[i], p.y[i], energy].iter().all(|v| v.is_finite())
            })
            .map(|i| p.id[i].0)
            .min()
            .map_or_else(|| "?".into(), |id| id.to_string())
    }

    /// The total mass and the sum of the radii, summed in id order: the same bits whatever
    /// the storage order, so a loaded world measures its pressure as the original does.
    fn totals_by_id(&self) -> (f64, f64) {
        let p = &self.particles;
        let law = Law::new(&self.config);
        let (mut mass, mut radius) = (0.0, 0.0);
        for (_, i) in self.in_id_order() {
            mass += law.mass(p.radius[i], p.mass[i]);
            radius += p.radius[i];
        }
        (mass, radius)
    }

    /// Measures the discs again: what the next step's substeps and the pressure need.
    fn remeasure(&mut self) {
        self.measured = measure(
            &self.particles,
            self.config.mass_model,
            self.broadphase.uniform_radius(),
            &self.exec,
            self.config.max_travel.is_some(),
        );
        (self.measured.total_mass, self.measured.radius_sum) = self.totals_by_id();
    }

    fn refresh_stats(&mut self) {
        self.remeasure();
        (self.stats.kinetic_energy, self.stats.momentum) =
            (self.measured.kinetic_energy, self.measured.momentum);
    }
}
