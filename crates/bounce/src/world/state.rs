//! A world's saved form: what a checkpoint holds, and the validation of every invariant on
//! the way back in, before anything is allocated by a value read from the data.

use serde::{Deserialize, Serialize};

use super::{World, WorldError};
use crate::broadphase::{Broadphase, Reference};
use crate::config::Config;
use crate::config::EmitterState;
use crate::config::ObstacleState;
use crate::geometry::Geometry;
use crate::law::Law;
use crate::particles::{Particle, Particles};
use crate::stats::StepStats;

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
    pub(super) emitter_states: Vec<EmitterState>,
    pub(super) removed: u32,
    pub(super) emitted_ids: Vec<[u32; 3]>,
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
        for i in 0..n {
            let id = p.id[i];
            // Positions may sit slightly outside the walls after an overlap push, so a loaded
            // state is checked for finite values and sizes, not for the box.
            let particle = Particle {
                position: [p.x[i], p.y[i]],
                velocity: [p.vx[i], p.vy[i]],
                radius: p.radius[i],
                mass: Some(p.mass[i]),
            };
            particle
                .validate_values()
                .and_then(|()| geometry.fits_size(particle.radius, &law))
                .map_err(|error| WorldError::Particle { id, error })?;
        }
        if !(state.time.is_finite()) {
            return Err(WorldError::Inconsistent(format!(
                "time {} is not finite",
                state.time
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
        if !state
            .obstacle_states
            .iter()
            .all(|s| finite(&s.offset) && finite(&s.velocity))
        {
            return Err(WorldError::Inconsistent(
                "an obstacle's offset or velocity is not finite".into(),
            ));
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
        if state.emitter_states.len() != world.config.emitters.len() {
            return Err(WorldError::Inconsistent(format!(
                "{} emitters but {} emitter states",
                world.config.emitters.len(),
                state.emitter_states.len()
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
        world.broadphase.reference = state.reference;
        world.particles = state.particles;
        world.next_id = state.next_id;
        world.time = state.time;
        world.steps = state.steps;
        world.remeasure();
        world.stats = state.stats;
        Ok(world)
    }
}
