//! A world's saved form: what a checkpoint holds, and the validation of every invariant on
//! the way back in, before anything is allocated by a value read from the data.

use serde::{Deserialize, Serialize};

use super::{World, WorldError};
use crate::broadphase::{Broadphase, Reference};
use crate::config::Config;
use crate::config::EmitterState;
use crate::config::ObstacleState;
use crate::contact_events::ContactLog;
use crate::geometry::Geometry;
use crate::law::Law;
use crate::particles::{Particle, Particles};
use crate::stats::StepStats;

/// A world as saved, not yet checked: decode saved data into this, then `World::try_from`
/// it, whose error names what is wrong (the disc and the field). Deserializing a [`World`]
/// directly checks the same, but formats such as postcard drop the message of a custom
/// error.
///
/// ```
/// use bounce::{Config, Particle, SavedWorld, World};
/// let mut world = World::new(Config::default())?;
/// world.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 0.5))?;
/// world.step(0.1)?;
/// let bytes = postcard::to_stdvec(&world)?;
/// let saved: SavedWorld = postcard::from_bytes(&bytes)?;
/// let loaded = World::try_from(saved)?;
/// assert_eq!(loaded.state_hash(), world.state_hash());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Deserialize)]
#[serde(transparent)]
pub struct SavedWorld(WorldState);

impl TryFrom<SavedWorld> for World {
    type Error = WorldError;

    fn try_from(saved: SavedWorld) -> Result<World, WorldError> {
        World::try_from(saved.0)
    }
}

/// The serialized form of a [`World`], validated on the way in.
#[derive(Deserialize)]
pub(super) struct WorldState {
    pub(super) config: Config,
    pub(super) particles: Particles,
    pub(super) next_id: u32,
    pub(super) time: f64,
    pub(super) steps: u64,
    pub(super) stats: StepStats,
    pub(super) reference: Reference,
    pub(super) obstacle_states: Vec<ObstacleState>,
    pub(super) obstacle_impulses: Vec<[f64; 2]>,
    pub(super) obstacle_work: f64,
    pub(super) friction_work: f64,
    pub(super) thermostat_work: f64,
    pub(super) emitter_states: Vec<EmitterState>,
    pub(super) removed: u32,
    pub(super) contact_log: ContactLog,
    pub(super) sensors: super::sensors::SensorState,
    pub(super) emitted_ids: Vec<[u32; 3]>,
    pub(super) collision_counts: Vec<u64>,
}

pub(super) fn serialize_reference<S: serde::Serializer>(
    broadphase: &Broadphase,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    broadphase.reference.serialize(serializer)
}

impl TryFrom<WorldState> for World {
    type Error = WorldError;

    fn try_from(state: WorldState) -> Result<World, WorldError> {
        let mut world = World::new(state.config)?;
        let (geometry, law) = (Geometry::new(&world.config), Law::new(&world.config));
        let p = &state.particles;
        let n = p.len();
        let lengths = [
            p.x.len(),
            p.y.len(),
            p.vx.len(),
            p.vy.len(),
            p.radius.len(),
            p.mass.len(),
            p.image.len(),
        ];
        if lengths.iter().any(|&l| l != n) {
            return Err(WorldError::Inconsistent(format!(
                "{n} ids but array lengths {lengths:?}"
            )));
        }
        let turning = if p.turning { n } else { 0 };
        if p.omega.len() != turning || p.theta.len() != turning {
            return Err(WorldError::Inconsistent(format!(
                "{n} ids but {} angular velocities and {} orientations",
                p.omega.len(),
                p.theta.len()
            )));
        }
        if !(p.tag.is_empty() || p.tag.len() == n) {
            return Err(WorldError::Inconsistent(format!(
                "{n} ids but {} tags",
                p.tag.len()
            )));
        }
        // Ids are given in order and never again: `next_id` is the discs kept plus those
        // removed, and the ids are distinct and below it. Checked by sorting the ids (no
        // table sized by a number read from the data).
        if state.next_id as u64 != n as u64 + state.removed as u64 {
            return Err(WorldError::Inconsistent(format!(
                "next_id {} does not follow the {n} particle ids and {} removed",
                state.next_id, state.removed
            )));
        }
        let mut ids: Vec<u32> = p.id.iter().map(|id| id.0).collect();
        ids.sort_unstable();
        if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
            return Err(WorldError::Inconsistent(format!("id {} is repeated", w[0])));
        }
        if let Some(&last) = ids.last()
            && last >= state.next_id
        {
            return Err(WorldError::Inconsistent(format!(
                "id {last} is not below next_id {}",
                state.next_id
            )));
        }
        // Centres in a walled box stay inside it (the walls hold a disc a radius inside);
        // in a periodic box a push may leave one a little past the edge until the next
        // integration wraps it: at most the largest collision distance.
        let max_radius = p.radius.iter().fold(0.0f64, |m, &r| m.max(r));
        let slack = if geometry.is_periodic() {
            law.interaction_diameter(max_radius)
        } else {
            0.0
        };
        for i in 0..n {
            let id = p.id[i];
            let particle = Particle {
                position: [p.x[i], p.y[i]],
                velocity: [p.vx[i], p.vy[i]],
                radius: p.radius[i],
                mass: Some(p.mass[i]),
                angular_velocity: p.omega.get(i).copied().unwrap_or(0.0),
                orientation: p.theta.get(i).copied().unwrap_or(0.0),
                tag: p.tag_of(i),
            };
            particle
                .validate_values()
                .and_then(|()| geometry.fits_size(particle.radius, &law))
                .and_then(|()| geometry.holds(particle.position, slack))
                .and_then(|()| particle.check_energy(&law, world.config.inertia_factor))
                .map_err(|error| WorldError::Particle { id, error })?;
        }
        // Every step advances the clock by a finite `dt > 0`.
        if !(state.time.is_finite() && state.time >= 0.0 && (state.time > 0.0) == (state.steps > 0))
        {
            return Err(WorldError::Inconsistent(format!(
                "time {} after {} steps (a step advances the time by dt > 0)",
                state.time, state.steps
            )));
        }
        if let Some(field) = state.stats.first_non_finite() {
            return Err(WorldError::Inconsistent(format!(
                "the last step's {field} is not finite"
            )));
        }
        state.reference.check(n).map_err(WorldError::Inconsistent)?;
        let obstacles = world.config.obstacles.len();
        if state.obstacle_states.len() != obstacles || state.obstacle_impulses.len() != obstacles {
            return Err(WorldError::Inconsistent(format!(
                "{obstacles} obstacles but {} states and {} impulses",
                state.obstacle_states.len(),
                state.obstacle_impulses.len()
            )));
        }
        let finite = |v: &[f64; 2]| v.iter().all(|x| x.is_finite());
        if let Some(k) = state
            .obstacle_states
            .iter()
            .position(|s| !(finite(&s.offset) && finite(&s.velocity)))
        {
            return Err(WorldError::Inconsistent(format!(
                "obstacle {k}: offset or velocity is not finite"
            )));
        }
        if let Some(k) = state.obstacle_impulses.iter().position(|j| !finite(j)) {
            return Err(WorldError::Inconsistent(format!(
                "obstacle {k}: impulse {:?} is not finite",
                state.obstacle_impulses[k]
            )));
        }
        world.obstacle_states = state.obstacle_states;
        world.obstacle_impulses = state.obstacle_impulses;
        if !state.obstacle_work.is_finite() {
            return Err(WorldError::Inconsistent(format!(
                "obstacle work {} is not finite",
                state.obstacle_work
            )));
        }
        world.obstacle_work = state.obstacle_work;
        if !state.friction_work.is_finite() {
            return Err(WorldError::Inconsistent(format!(
                "friction work {} is not finite",
                state.friction_work
            )));
        }
        world.friction_work = state.friction_work;
        if !state.thermostat_work.is_finite() {
            return Err(WorldError::Inconsistent(format!(
                "thermostat work {} is not finite",
                state.thermostat_work
            )));
        }
        world.thermostat_work = state.thermostat_work;
        if state.emitter_states.len() != world.config.emitters.len() {
            return Err(WorldError::Inconsistent(format!(
                "{} emitters but {} emitter states",
                world.config.emitters.len(),
                state.emitter_states.len()
            )));
        }
        if let Some(k) = state
            .emitter_states
            .iter()
            .position(|s| !(s.due.is_finite() && s.due >= 0.0 && s.emitted <= s.attempts))
        {
            let s = &state.emitter_states[k];
            return Err(WorldError::Inconsistent(format!(
                "emitter {k}: {} due, {} emitted in {} attempts (due must be finite and >= 0, \
                 emitted at most the attempts)",
                s.due, s.emitted, s.attempts
            )));
        }
        world.emitter_states = state.emitter_states;
        world.removed = state.removed;
        let mut end = 0u64;
        for run in &state.emitted_ids {
            let run_end = run[0] as u64 + run[1] as u64;
            if (run[0] as u64) < end
                || run_end > state.next_id as u64
                || run[2] as usize >= world.config.emitters.len()
            {
                return Err(WorldError::Inconsistent(format!(
                    "emitted ids {run:?} overlap, pass next_id {} or name no emitter",
                    state.next_id
                )));
            }
            end = run_end;
        }
        world.emitted_ids = state.emitted_ids;
        if state.collision_counts.len() > state.next_id as usize {
            return Err(WorldError::Inconsistent(format!(
                "{} collision counts for {} ids",
                state.collision_counts.len(),
                state.next_id
            )));
        }
        world.collision_counts = state.collision_counts;
        if let Some(problem) = state.contact_log.problem(state.next_id) {
            return Err(WorldError::Inconsistent(format!("contact_log: {problem}")));
        }
        world.contact_log = state.contact_log;
        if let Some(problem) = state.sensors.problem(&world.config.sensors, state.next_id) {
            return Err(WorldError::Inconsistent(format!("sensors: {problem}")));
        }
        world.sensors = state.sensors;
        world.broadphase.reference = state.reference;
        world.particles = state.particles;
        if world.config.is_rough() {
            world.particles.start_turning();
        }
        world.next_id = state.next_id;
        world.time = state.time;
        world.steps = state.steps;
        world.remeasure();
        world.stats = state.stats;
        Ok(world)
    }
}
