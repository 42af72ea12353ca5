//! The world's emitters and sinks: discs added at a rate and removed where they enter, and
//! what a front end asks of them (which emitter made a disc, the next id).

use std::sync::OnceLock;

use crate::config::EmitterState;
use crate::law::Law;
use crate::particles::{Particle, ParticleId};
use crate::sources;

use super::World;

impl World {
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
    pub(super) fn drain_sinks(&mut self) -> usize {
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
    ///
    /// ```
    /// use bounce::{Config, Particle, ParticleId, World};
    /// let mut world = World::new(Config::default())?;
    /// for x in [0.0, 5.0] {
    ///     world.add_particle(Particle::new([x, 0.0], [0.0, 0.0], 0.5))?;
    /// }
    /// assert_eq!(world.remove_particles(&[ParticleId(0), ParticleId(9)]), 1);
    /// assert_eq!(world.len(), 1);
    /// let next = world.add_particle(Particle::new([9.0, 0.0], [0.0, 0.0], 0.5))?;
    /// assert_eq!(next, ParticleId(2)); // id 0 is not given again
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
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

    pub(super) fn after_removal(&mut self, gone: usize) {
        self.removed += gone as u32;
        self.index_of = OnceLock::new();
        self.broadphase.invalidate();
        (self.measured.total_mass, self.measured.radius_sum) = self.totals_by_id();
    }

    /// The discs the emitters added at the start of the last step, each with the index of
    /// its emitter in `Config::emitters`.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Emitter, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
    ///     emitters: vec![Emitter {
    ///         rate: 100.0,
    ///         limit: Some(5),
    ///         ..Emitter::new([1.0, 1.0], [19.0, 19.0], 0.5)
    ///     }],
    ///     ..Config::default()
    /// })?;
    /// world.step(0.1)?;
    /// // The 5 discs the emitter was limited to, all from emitter 0.
    /// assert_eq!(world.emitted_last_step().len(), 5);
    /// assert!(world.emitted_last_step().iter().all(|&(_, k)| k == 0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn emitted_last_step(&self) -> &[(ParticleId, u32)] {
        &self.emitted_last_step
    }

    /// The emitter (its index in `Config::emitters`) that added disc `id`, if one did.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Emitter, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
    ///     emitters: vec![Emitter {
    ///         rate: 100.0,
    ///         limit: Some(5),
    ///         ..Emitter::new([1.0, 1.0], [19.0, 19.0], 0.5)
    ///     }],
    ///     ..Config::default()
    /// })?;
    /// world.step(0.1)?;
    /// let (id, _) = world.emitted_last_step()[0];
    /// assert_eq!(world.emitter_of(id), Some(0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn emitter_of(&self, id: ParticleId) -> Option<u32> {
        let k = self.emitted_ids.partition_point(|run| run[0] <= id.0);
        let run = self.emitted_ids.get(k.checked_sub(1)?)?;
        (id.0 < run[0] + run[1]).then_some(run[2])
    }

    /// How far each emitter has got.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Emitter, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
    ///     emitters: vec![Emitter {
    ///         rate: 100.0,
    ///         limit: Some(5),
    ///         ..Emitter::new([1.0, 1.0], [19.0, 19.0], 0.5)
    ///     }],
    ///     ..Config::default()
    /// })?;
    /// world.step(0.1)?;
    /// assert_eq!(world.emitter_states()[0].emitted, 5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn emitter_states(&self) -> &[EmitterState] {
        &self.emitter_states
    }

    /// The next id a disc will get: one more than every id given so far.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// assert_eq!(world.next_id(), 0);
    /// let id = world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 0.5))?;
    /// assert_eq!((id.0, world.next_id()), (0, 1));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn next_id(&self) -> u32 {
        self.next_id
    }
}
