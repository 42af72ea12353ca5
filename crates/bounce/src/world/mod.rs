//! The world: configuration, particles, what the step keeps between steps, and the API
//! around them (the step's script of stages is in `step`). Inputs are
//! validated at the edges (`new`, `add_particle`, `set_config`, loading a checkpoint), so the
//! step itself cannot fail for any state reachable through this API.

use std::sync::OnceLock;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::broadphase::{self, Broadphase};
use crate::config::{Config, ConfigError};
use crate::contacts::Contacts;
use crate::context::StepContext;
use crate::geometry::Geometry;
use crate::law::Law;
use crate::obstacles::{ObstacleState, Obstacles, Shape, Trail};
use crate::parallel::{Executor, ThreadsError};
use crate::part::{DiscRecord, Tally, Travel};
use crate::particles::{Particle, ParticleError, ParticleId, Particles};
use crate::sources::{self, EmitterState};
use crate::stats::{Measured, StepProfile, StepStats, measure};
use crate::sum::StepSums;

mod state;
mod step;
#[cfg(test)]
mod tests;

use state::{WorldState, serialize_reference};
pub(crate) use step::Substepped;

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
    /// Which emitter gave which ids: `[first id, count, emitter]`, ascending (runs of
    /// consecutive ids from one emitter are merged).
    emitted_ids: Vec<[u32; 3]>,
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
}

/// Why a step was refused.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum StepError {
    /// The time step is not a finite number `> 0`.
    #[error("time step dt = {0} must be finite and > 0")]
    InvalidTimeStep(f64),
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

/// Why a configuration or loaded state was refused.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum WorldError {
    /// The configuration is invalid.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A particle does not fit the configuration.
    #[error("particle {id:?}: {error}")]
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
    pub fn new(config: Config) -> Result<World, ConfigError> {
        config.validate()?;
        let (obstacle_states, obstacle_count) = (initial_states(&config), config.obstacles.len());
        let emitter_count = config.emitters.len();
        Ok(World {
            config,
            particles: Particles::default(),
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
            obstacles: None,
            trail: Trail::default(),
            obstacle_radius: 0.0,
            emitter_states: vec![EmitterState::default(); emitter_count],
            removed: 0,
            emitted_ids: Vec::new(),
            emitted_last_step: Vec::new(),
            contacts: Contacts::default(),
            exec: Executor::default(),
            index_of: OnceLock::new(),
            tally: None,
            order_radius: 0.0,
            sums: StepSums::default(),
            travel: Travel::default(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Replaces the configuration. Fails, leaving the world unchanged, if the configuration is
    /// invalid or a particle does not fit it (outside a new box, too large for it).
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
        self.config = config;
        self.obstacles = None;
        self.broadphase.invalidate();
        self.refresh_stats();
        Ok(())
    }

    /// Adds obstacles after the existing ones (which keep their motion). Fails, leaving the
    /// world unchanged, if one is invalid.
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
    /// outside the box.
    pub fn add_particle(&mut self, particle: Particle) -> Result<ParticleId, ParticleError> {
        self.add_particles([particle])
            .map(|ids| ids[0])
            .map_err(|(_, e)| e)
    }

    /// Adds discs all or nothing: on the first invalid one, returns its index in the input
    /// and the error, and the world is unchanged.
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

    /// Runs `threads` worker threads for the step (1 = on the calling thread, the default).
    /// Results are bit-identical for every thread count.
    pub fn set_threads(&mut self, threads: usize) -> Result<(), ThreadsError> {
        let min_work = self.exec.min_work;
        self.exec = Executor::new(threads)?;
        self.exec.min_work = min_work;
        Ok(())
    }

    /// Work below `min_work` units (about one per disc, a few per contact) runs on the
    /// calling thread even with worker threads: waking them costs more than small work saves.
    /// The default is [`DEFAULT_PARALLEL_MIN_WORK`](crate::DEFAULT_PARALLEL_MIN_WORK); 0
    /// runs every stage on the workers. Results never depend on it.
    pub fn set_parallel_min_work(&mut self, min_work: usize) {
        self.exec.min_work = min_work;
    }

    /// The number of worker threads the step uses.
    pub fn threads(&self) -> usize {
        self.exec.threads()
    }

    /// Advances the world by `dt`, in `config.substeps` substeps (more with
    /// `config.max_travel`), and returns what it measured.
    pub fn step(&mut self, dt: f64) -> Result<&StepStats, StepError> {
        let substeps = self.substeps_for(dt);
        self.step_with_substeps(dt, substeps)
    }

    /// [`World::step`] in exactly `substeps` substeps (at least 1, at most
    /// [`crate::MAX_SUBSTEPS`]): for a part of a distributed world, whose substeps the whole
    /// world's fastest disc decides (see [`World::substeps_for_extremes`]).
    pub fn step_with_substeps(&mut self, dt: f64, substeps: u32) -> Result<&StepStats, StepError> {
        let installer = self.exec.installer(self.particles.len());
        installer.install(|| self.step_in_pool(dt, substeps))?;
        Ok(&self.stats)
    }

    /// The emitters' discs for a step of `dt`, added before it; returns how many.
    pub(crate) fn emit(&mut self, dt: f64) -> usize {
        self.emitted_last_step.clear();
        if self.config.emitters.is_empty() {
            return 0;
        }
        let law = Law::new(&self.config);
        // The obstacles' grid covers the emitters' discs too (see `prepare_obstacles`).
        self.prepare_obstacles();
        let mut added = 0;
        for k in 0..self.config.emitters.len() {
            let emitter = self.config.emitters[k];
            let (config, obstacles) = (&self.config, self.obstacles.as_ref());
            let blocked = |disc: &Particle| {
                disc.validate(config).is_err()
                    || obstacles.is_some_and(|o| o.blocks(disc.position, disc.radius, &law))
            };
            let discs = sources::emit(
                &emitter,
                &mut self.emitter_states[k],
                dt,
                &self.particles,
                &law,
                blocked,
            );
            if discs.is_empty() {
                continue;
            }
            let ids = self
                .add_particles(discs)
                .expect("emitted discs are validated by `blocked`");
            added += ids.len();
            let (first, count) = (ids[0].0, ids.len() as u32);
            match self.emitted_ids.last_mut() {
                Some(run) if run[2] == k as u32 && run[0] + run[1] == first => run[1] += count,
                _ => self.emitted_ids.push([first, count, k as u32]),
            }
            self.emitted_last_step
                .extend(ids.into_iter().map(|id| (id, k as u32)));
        }
        added
    }

    /// Removes the discs inside a sink; returns how many.
    fn drain_sinks(&mut self) -> usize {
        let sinks = &self.config.sinks;
        let p = &self.particles;
        let inside: Vec<bool> = (0..p.len())
            .map(|i| sinks.iter().any(|s| s.contains([p.x[i], p.y[i]])))
            .collect();
        let gone = self.particles.retain(|i| !inside[i]);
        if gone > 0 {
            self.after_removal(gone);
        }
        gone
    }

    /// Removes the discs with these ids (unknown ids are skipped); returns how many went.
    /// Their ids are never given again.
    pub fn remove_particles(&mut self, ids: &[ParticleId]) -> usize {
        let mut doomed = vec![false; self.particles.len()];
        for &id in ids {
            if let Some(i) = self.index_of(id) {
                doomed[i] = true;
            }
        }
        let gone = self.particles.retain(|i| !doomed[i]);
        if gone > 0 {
            self.after_removal(gone);
            self.refresh_stats();
        }
        gone
    }

    fn after_removal(&mut self, gone: usize) {
        self.removed += gone as u32;
        self.index_of = OnceLock::new();
        self.broadphase.invalidate();
        (self.measured.total_mass, self.measured.radius_sum) = self.totals_by_id();
    }

    /// The discs the emitters added at the start of the last step, each with the index of
    /// its emitter in `Config::emitters`.
    pub fn emitted_last_step(&self) -> &[(ParticleId, u32)] {
        &self.emitted_last_step
    }

    /// The emitter (its index in `Config::emitters`) that added disc `id`, if one did.
    pub fn emitter_of(&self, id: ParticleId) -> Option<u32> {
        let k = self.emitted_ids.partition_point(|run| run[0] <= id.0);
        let run = self.emitted_ids.get(k.checked_sub(1)?)?;
        (id.0 < run[0] + run[1]).then_some(run[2])
    }

    /// How far each emitter has got.
    pub fn emitter_states(&self) -> &[EmitterState] {
        &self.emitter_states
    }

    /// The next id a disc will get: one more than every id given so far.
    pub fn next_id(&self) -> u32 {
        self.next_id
    }

    /// Builds the obstacles' grid when the configuration or the discs changed.
    fn prepare_obstacles(&mut self) {
        if self.obstacles.is_none() {
            // The discs there are and those the emitters will add.
            let emitted = self.config.emitters.iter().map(|e| e.radius[1]);
            let max_radius = self
                .particles
                .radius
                .iter()
                .copied()
                .chain(emitted)
                .fold(0.0, f64::max);
            self.obstacle_radius = max_radius;
            self.obstacles = Some(Obstacles::new(
                &self.config,
                &self.obstacle_states,
                max_radius,
            ));
        }
    }

    /// The obstacles where they are now (moving ones moved), in the configuration's order.
    pub fn obstacle_shapes(&self) -> Vec<Shape> {
        self.config
            .obstacles
            .iter()
            .zip(&self.obstacle_states)
            .map(|(o, s)| o.shifted(s.offset))
            .collect()
    }

    /// Where each obstacle is (its offset from the configured shape) and how fast it moves.
    pub fn obstacle_states(&self) -> &[ObstacleState] {
        &self.obstacle_states
    }

    /// The work the moving obstacles have done on the discs since the start (the sum of
    /// [`StepStats::obstacle_work`]): with elastic collisions, the gain in kinetic energy a
    /// piston gave the gas.
    pub fn obstacle_work(&self) -> f64 {
        self.obstacle_work
    }

    /// The momentum each obstacle received during the last step (divide by `dt` for the
    /// force), in the configuration's order.
    pub fn obstacle_impulses(&self) -> &[[f64; 2]] {
        &self.obstacle_impulses
    }

    /// The substeps a step of `dt` takes: `config.substeps`, or with `config.max_travel` as
    /// many as keep the fastest disc (gravity included) within `max_travel` of the smallest
    /// radius per substep, at most [`crate::MAX_SUBSTEPS`].
    pub(crate) fn substeps_for(&self, dt: f64) -> u32 {
        self.substeps_for_extremes(dt, self.measured.max_speed2, self.measured.min_radius)
    }

    /// The substeps a step of `dt` takes when the fastest disc's squared speed is
    /// `max_speed2` and the smallest radius `min_radius` (what [`World::step`] measures over
    /// its own discs; a distributed run gives the whole world's).
    pub fn substeps_for_extremes(&self, dt: f64, max_speed2: f64, min_radius: f64) -> u32 {
        let fixed = self.config.substeps;
        let Some(fraction) = self.config.max_travel else {
            return fixed;
        };
        let [gx, gy] = self.config.gravity;
        let v_max = max_speed2.sqrt() + (gx * gx + gy * gy).sqrt() * dt;
        let needed = (v_max * dt / (fraction * min_radius)).ceil();
        if needed.is_finite() && needed > fixed as f64 {
            needed.min(crate::MAX_SUBSTEPS as f64) as u32
        } else {
            fixed
        }
    }

    /// What the last step measured (energy and momentum are kept current when particles are
    /// added or the configuration changes).
    pub fn stats(&self) -> &StepStats {
        &self.stats
    }

    /// Where the last step spent its time, stage by stage.
    pub fn profile(&self) -> &StepProfile {
        &self.profile
    }

    /// Simulated time: the sum of the `dt`s stepped.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Number of steps taken.
    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// `true` when the world holds no particles.
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// The particle arrays, in storage order (which changes every step; ids do not).
    pub fn particles(&self) -> &Particles {
        &self.particles
    }

    /// The storage index of particle `id` now.
    pub fn index_of(&self, id: ParticleId) -> Option<usize> {
        self.index_map().get(id)
    }

    fn index_map(&self) -> &IndexMap {
        self.index_of
            .get_or_init(|| IndexMap::new(&self.particles.id, self.next_id))
    }

    /// Every disc as `(id, storage index)`, in id order (ids have gaps where a sink or
    /// `remove_particles` took discs).
    pub fn in_id_order(&self) -> Vec<(ParticleId, usize)> {
        self.index_map().in_order()
    }

    /// Particle `id` as it is now.
    pub fn particle(&self, id: ParticleId) -> Option<Particle> {
        let mut p = self.particles.get(self.index_of(id)?)?;
        if self.config.mass_model != crate::MassModel::PerParticle {
            p.mass = Some(self.config.mass_model.mass(p.radius, 0.0));
        }
        Some(p)
    }

    /// Every particle in id order.
    pub fn particles_by_id(&self) -> Vec<(ParticleId, Particle)> {
        let mut ids: Vec<ParticleId> = self.particles.id.clone();
        ids.sort_unstable();
        ids.into_iter()
            .filter_map(|id| Some((id, self.particle(id)?)))
            .collect()
    }

    /// Sets the velocity of particle `id` (for interactive tools). Fails on an unknown id or a
    /// non-finite velocity.
    pub fn set_velocity(
        &mut self,
        id: ParticleId,
        velocity: [f64; 2],
    ) -> Result<(), ParticleError> {
        if !velocity.iter().all(|v| v.is_finite()) {
            return Err(ParticleError::NonFiniteVelocity(velocity));
        }
        let i = self.index_of(id).ok_or(ParticleError::UnknownId(id))?;
        self.particles.vx[i] = velocity[0];
        self.particles.vy[i] = velocity[1];
        self.refresh_stats();
        Ok(())
    }

    /// Moves every disc, `positions[k]` for id `k`, all or nothing: on the first position
    /// the boundary does not admit (or not finite), returns its index and the error, and the
    /// world is unchanged. Velocities and periodic image counts are kept.
    pub fn set_positions(&mut self, positions: &[[f64; 2]]) -> Result<(), (usize, ParticleError)> {
        self.set_each(positions, |particle, position| particle.position = position)?;
        self.broadphase.invalidate();
        Ok(())
    }

    /// Sets every disc's velocity, `velocities[k]` for id `k`, all or nothing: on the first
    /// invalid one returns its index and the error, and the world is unchanged.
    pub fn set_velocities(
        &mut self,
        velocities: &[[f64; 2]],
    ) -> Result<(), (usize, ParticleError)> {
        self.set_each(velocities, |particle, velocity| {
            particle.velocity = velocity
        })
    }

    /// Validates `values` (one per id, in id order) applied by `apply`, then writes them.
    fn set_each(
        &mut self,
        values: &[[f64; 2]],
        apply: impl Fn(&mut Particle, [f64; 2]),
    ) -> Result<(), (usize, ParticleError)> {
        if values.len() != self.particles.len() {
            return Err((
                values.len().min(self.particles.len()),
                ParticleError::WrongCount {
                    expected: self.particles.len(),
                    given: values.len(),
                },
            ));
        }
        let mut updated = Vec::with_capacity(values.len());
        for (k, (&value, (_, i))) in values.iter().zip(self.in_id_order()).enumerate() {
            let mut particle = self.particles.get(i).expect("an index from index_of");
            apply(&mut particle, value);
            particle.validate(&self.config).map_err(|e| (k, e))?;
            updated.push((i, particle));
        }
        let p = &mut self.particles;
        for (i, particle) in updated {
            [p.x[i], p.y[i]] = particle.position;
            [p.vx[i], p.vy[i]] = particle.velocity;
        }
        self.refresh_stats();
        Ok(())
    }

    /// Adds `delta_v` to the velocity of every particle whose centre lies within `radius` of
    /// `centre` (for interactive tools: a push). Returns how many were pushed; non-finite
    /// arguments push nothing.
    pub fn push_region(&mut self, centre: [f64; 2], radius: f64, delta_v: [f64; 2]) -> usize {
        let finite = centre.iter().chain(&delta_v).all(|v| v.is_finite()) && radius.is_finite();
        if !finite || radius < 0.0 {
            return 0;
        }
        let p = &mut self.particles;
        let mut pushed = 0;
        for i in 0..p.len() {
            let (dx, dy) = (p.x[i] - centre[0], p.y[i] - centre[1]);
            if dx * dx + dy * dy <= radius * radius {
                p.vx[i] += delta_v[0];
                p.vy[i] += delta_v[1];
                pushed += 1;
            }
        }
        self.refresh_stats();
        pushed
    }

    /// The particle whose disc contains `point` (the nearest centre if several overlap it).
    pub fn particle_at(&self, point: [f64; 2]) -> Option<ParticleId> {
        let p = &self.particles;
        (0..p.len())
            .filter_map(|i| {
                let d2 = (p.x[i] - point[0]).powi(2) + (p.y[i] - point[1]).powi(2);
                (d2 <= p.radius[i] * p.radius[i]).then_some((d2, p.id[i]))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, id)| id)
    }

    /// The pairs within the collision distance right now, as sorted id pairs, found the way a
    /// step finds them (grids, then the law's test). A query: neither the state nor the
    /// storage order changes.
    pub fn colliding_pairs(&self) -> Vec<(ParticleId, ParticleId)> {
        let ctx = StepContext::new(&self.config, 0.0, &self.exec, None);
        let p = &self.particles;
        let mut broadphase = Broadphase::default();
        // Any margin gives a superset of the colliding pairs; the law's test decides.
        let r_min = p.radius.iter().copied().fold(f64::INFINITY, f64::min);
        let margin = 0.25 * ctx.law.interaction_diameter(r_min);
        broadphase.list_in_place([&p.x, &p.y, &p.radius], &ctx, margin);
        let mut contacts = Contacts::default();
        contacts.find(&broadphase, broadphase::BANDS, p, &ctx);
        contacts.pair_ids(p)
    }

    /// The same pairs as [`World::colliding_pairs`] by testing all N(N-1)/2 pairs: the
    /// reference the grid is tested against. O(N²): for tests and small worlds.
    pub fn colliding_pairs_brute_force(&self) -> Vec<(ParticleId, ParticleId)> {
        let ctx = StepContext::new(&self.config, 0.0, &self.exec, None);
        broadphase::brute_force_pairs(&self.particles, &ctx)
    }

    /// A 64-bit FNV-1a hash of the state (ids, positions, velocities, radii, in id order,
    /// bit for bit) and the step count: equal hashes mean identical runs, on any platform.
    pub fn state_hash(&self) -> u64 {
        let mut hash = 0xcbf2_9ce4_8422_2325u64;
        let mut eat = |bytes: [u8; 8]| {
            for b in bytes {
                hash = (hash ^ b as u64).wrapping_mul(0x0100_0000_01b3);
            }
        };
        eat(self.steps.to_le_bytes());
        let p = &self.particles;
        for (id, i) in self.in_id_order() {
            eat((id.0 as u64).to_le_bytes());
            for v in [p.x[i], p.y[i], p.vx[i], p.vy[i], p.radius[i]] {
                eat(v.to_bits().to_le_bytes());
            }
        }
        hash
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

    /// The pressure `(K + W) / A` of [`StepStats::pressure`] for a kinetic energy, momentum
    /// and virial `W` (the discs' total mass and mean radius are the world's, summed in id
    /// order). `None` in an open world.
    pub fn pressure(&self, kinetic_energy: f64, momentum: [f64; 2], virial: f64) -> Option<f64> {
        let m = &self.measured;
        let mean_radius = m.radius_sum / self.particles.len().max(1) as f64;
        Geometry::new(&self.config).area(mean_radius).map(|area| {
            let [px, py] = momentum;
            let drift = if m.total_mass > 0.0 {
                (px * px + py * py) / (2.0 * m.total_mass)
            } else {
                0.0
            };
            (kinetic_energy - drift + virial) / area
        })
    }

    /// Counts only the events in `tally`'s region in the step's sums (`None`: all): for a
    /// part of a distributed world, see [`Tally`].
    pub fn set_tally(&mut self, tally: Option<Tally>) {
        self.tally = tally;
    }

    /// Sizes the contact order's grid for discs up to `radius` (or this world's largest, if
    /// larger): a part of a distributed world gives the whole world's largest radius, so
    /// that its contacts fall in the same order.
    pub fn set_order_radius(&mut self, radius: f64) {
        self.order_radius = radius;
    }

    /// How much of the candidate list's life the discs have used (the farthest disc's
    /// distance from where the list was made over the distance that forces a new list, not
    /// counting the few met alone, the strays, or their count over their cap if that is
    /// more): at 1 the next substep lists again. `None` while no list is kept.
    pub fn candidates_worn(&self) -> Option<f64> {
        let bp = &self.broadphase;
        let allowance = bp.reference.allowance();
        (bp.reference.positions(self.particles.len()).is_some() && allowance > 0.0)
            .then(|| bp.worn())
    }

    /// Lists the candidates afresh at the next step, however little the discs moved: the
    /// parts of a distributed world list together (their steps wait for the slowest part,
    /// and listing costs several plain steps), not each on its own schedule. Results do not
    /// change: which pairs collide never depends on when lists are made.
    pub fn relist(&mut self) {
        self.broadphase.invalidate();
    }

    /// Bounds on how far any disc has moved, from what the broadphase measures anyway (see
    /// [`Travel`]): a distributed run decides from it when its discs must change hands.
    pub fn travel(&self) -> Travel {
        self.travel
    }

    /// The exact sums of the last step (see [`StepSums`]).
    pub fn step_sums(&self) -> &StepSums {
        &self.sums
    }

    /// Takes `other`'s clock, last statistics, obstacles, sources and id counter.
    pub(crate) fn adopt_clock(&mut self, other: &World) {
        self.next_id = other.next_id;
        self.time = other.time;
        self.steps = other.steps;
        self.stats = other.stats;
        self.obstacle_states = other.obstacle_states.clone();
        self.obstacle_impulses = other.obstacle_impulses.clone();
        self.obstacle_work = other.obstacle_work;
        self.emitter_states = other.emitter_states.clone();
        self.removed = other.removed;
        self.emitted_ids = other.emitted_ids.clone();
    }

    pub(crate) fn reset_travel(&mut self) {
        self.travel = Travel::default();
    }

    /// Keeps the discs `keep` accepts, by storage index.
    pub(crate) fn keep_discs(&mut self, keep: &mut impl FnMut(usize) -> bool) {
        let kept: Vec<bool> = (0..self.particles.len()).map(keep).collect();
        self.particles.retain(|i| kept[i]);
    }

    /// Appends a disc with its id and image counts (checked by the caller).
    pub(crate) fn push_record(&mut self, r: &DiscRecord) {
        let p = &mut self.particles;
        p.id.push(r.id);
        p.x.push(r.position[0]);
        p.y.push(r.position[1]);
        p.vx.push(r.velocity[0]);
        p.vy.push(r.velocity[1]);
        p.radius.push(r.radius);
        p.mass.push(r.mass);
        p.image.push(r.image);
    }

    /// After discs were pushed: ids, broadphase and measurements brought up to date (the
    /// last statistics' energy and momentum kept as adopted).
    pub(crate) fn after_records(&mut self) {
        self.index_of = OnceLock::new();
        self.obstacles = None;
        self.broadphase.invalidate();
        let stats = self.stats;
        self.remeasure();
        self.stats = stats;
        // Ids run to `next_id` with gaps: the removed ones and, in a part, the others'.
        self.removed = self.next_id - self.particles.len() as u32;
    }

    /// Writes positions and velocities at storage indices `at`.
    pub(crate) fn write_motion(&mut self, at: &[usize], states: &[(ParticleId, [f64; 4])]) {
        let p = &mut self.particles;
        for (&i, (_, [x, y, vx, vy])) in at.iter().zip(states) {
            (p.x[i], p.y[i], p.vx[i], p.vy[i]) = (*x, *y, *vx, *vy);
        }
    }

    pub(crate) fn set_stats(&mut self, stats: StepStats) {
        self.stats = stats;
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

/// Every obstacle at its configured place with its starting velocity.
fn initial_states(config: &Config) -> Vec<ObstacleState> {
    config
        .obstacles
        .iter()
        .map(|o| ObstacleState {
            offset: [0.0, 0.0],
            velocity: o.initial_velocity(),
        })
        .collect()
}

/// Where each id is stored: a table by id while ids are dense, else the sorted pairs (ids
/// removed by sinks leave gaps; a table by id would grow with every id ever given).
#[derive(Debug)]
enum IndexMap {
    Dense(Vec<u32>),
    Sparse(Vec<(ParticleId, u32)>),
}

impl IndexMap {
    fn new(ids: &[ParticleId], next_id: u32) -> IndexMap {
        if next_id as usize <= 2 * ids.len() + 1024 {
            let mut map = vec![u32::MAX; next_id as usize];
            for (i, id) in ids.iter().enumerate() {
                map[id.0 as usize] = i as u32;
            }
            IndexMap::Dense(map)
        } else {
            let mut pairs: Vec<(ParticleId, u32)> = ids
                .iter()
                .enumerate()
                .map(|(i, &id)| (id, i as u32))
                .collect();
            pairs.sort_unstable();
            IndexMap::Sparse(pairs)
        }
    }

    fn get(&self, id: ParticleId) -> Option<usize> {
        match self {
            IndexMap::Dense(map) => map
                .get(id.0 as usize)
                .filter(|&&i| i != u32::MAX)
                .map(|&i| i as usize),
            IndexMap::Sparse(pairs) => pairs
                .binary_search_by_key(&id, |&(id, _)| id)
                .ok()
                .map(|k| pairs[k].1 as usize),
        }
    }

    fn in_order(&self) -> Vec<(ParticleId, usize)> {
        match self {
            IndexMap::Dense(map) => map
                .iter()
                .enumerate()
                .filter(|&(_, &i)| i != u32::MAX)
                .map(|(id, &i)| (ParticleId(id as u32), i as usize))
                .collect(),
            IndexMap::Sparse(pairs) => pairs.iter().map(|&(id, i)| (id, i as usize)).collect(),
        }
    }
}
