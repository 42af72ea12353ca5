//! Sensors in the world: which discs each sensor holds, and how many entered and left.
//!
//! At the end of every step, after the emitters and the substeps and before the sinks, each
//! sensor's discs (those whose centre is in its region) are compared with the last step's:
//! the new ones *entered*, the missing ones *left*. Discs a sink then removes leave at once,
//! so a sensor over a sink counts every removal, even of a disc that entered in the same
//! step. The sets are kept by id, so they are the same on any thread count and storage
//! order, and they are saved with the world.

use serde::{Deserialize, Serialize};

use crate::config::Sensor;
use crate::particles::{ParticleId, Particles};

/// One sensor's counts ([`crate::World::sensors`]).
///
/// ```
/// use bounce::{Config, Particle, Region, Sensor, World};
/// let gate = Region::Box { min: [4.0, -1.0], max: [6.0, 1.0] };
/// let mut world = World::new(Config {
///     sensors: vec![Sensor::new("gate", gate)],
///     ..Config::default()
/// })?;
/// world.add_particle(Particle::new([0.0, 0.0], [10.0, 0.0], 0.5))?;
/// for _ in 0..100 {
///     world.step(0.01)?; // through the gate and out the other side
/// }
/// let count = &world.sensors()[0];
/// assert_eq!((count.entered, count.left, count.inside), (1, 1, 0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SensorCount {
    /// The discs whose centre entered the region since the world was made.
    pub entered: u64,
    /// The discs whose centre left (or that were removed inside) since the world was made.
    pub left: u64,
    /// The discs inside now.
    pub inside: usize,
    /// Of `entered`, those of the last step.
    pub entered_last_step: u64,
    /// Of `left`, those of the last step.
    pub left_last_step: u64,
}

/// Every sensor's discs and counts ([`crate::World::sensor_state`]): what a distributed
/// run's root keeps for the whole world, fed with the discs each part sees
/// ([`SensorState::observe_sets`]). See there for an example.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct SensorState {
    counts: Vec<SensorCount>,
    /// Each sensor's discs, ascending.
    holds: Vec<Vec<ParticleId>>,
}

impl SensorState {
    /// Nothing held yet, for `sensors`.
    pub(crate) fn new(sensors: &[Sensor]) -> SensorState {
        let mut out = SensorState::default();
        out.fit(sensors);
        out
    }

    /// The counts, one per sensor of the configuration (what [`crate::World::sensors`]
    /// gives).
    ///
    /// ```
    /// use bounce::{Config, Particle, Region, Sensor, World};
    /// let mut world = World::new(Config {
    ///     sensors: vec![Sensor::new("all", Region::Circle { centre: [0.0, 0.0], radius: 9.0 })],
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([1.0, 0.0], [0.0, 0.0], 0.5))?;
    /// world.step(0.1)?;
    /// assert_eq!(world.sensor_state().counts(), world.sensors());
    /// assert_eq!(world.sensors()[0].inside, 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn counts(&self) -> &[SensorCount] {
        &self.counts
    }

    /// Fits the state to `sensors` (a changed configuration starts each sensor anew; the
    /// same one keeps its state).
    pub(crate) fn fit(&mut self, sensors: &[Sensor]) {
        if self.counts.len() != sensors.len() {
            self.counts = vec![SensorCount::default(); sensors.len()];
            self.holds = vec![Vec::new(); sensors.len()];
        }
    }

    /// The end of a step: each sensor's discs now, against the last step's.
    pub(crate) fn observe(&mut self, sensors: &[Sensor], p: &Particles) {
        let now = sensors
            .iter()
            .map(|sensor| {
                (0..p.len())
                    .filter(|&i| sensor.region.contains([p.x[i], p.y[i]]))
                    .map(|i| p.id[i])
                    .collect()
            })
            .collect();
        self.observe_sets(sensors, now);
    }

    /// The end of a step, from each sensor's discs now (`now[k]` for sensor `k`, in any
    /// order; a sensor without a set holds none): those new to a sensor entered it, those
    /// it no longer holds left.
    ///
    /// ```
    /// use bounce::{Config, ParticleId, Region, Sensor, World};
    /// let sensors = vec![Sensor::new("a", Region::Circle { centre: [0.0, 0.0], radius: 1.0 })];
    /// let world = World::new(Config { sensors: sensors.clone(), ..Config::default() })?;
    /// let mut state = world.sensor_state().clone();
    /// state.observe_sets(&sensors, vec![vec![ParticleId(3), ParticleId(1)]]);
    /// state.observe_sets(&sensors, vec![vec![ParticleId(1), ParticleId(5)]]);
    /// let count = &state.counts()[0];
    /// assert_eq!((count.entered, count.left, count.inside), (3, 1, 2));
    /// assert_eq!((count.entered_last_step, count.left_last_step), (1, 1));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn observe_sets(&mut self, sensors: &[Sensor], now: Vec<Vec<ParticleId>>) {
        self.fit(sensors);
        let sets = self.counts.iter_mut().zip(&mut self.holds);
        let now = now.into_iter().chain(std::iter::repeat_with(Vec::new));
        for ((count, held), mut now) in sets.zip(now) {
            now.sort_unstable();
            let stayed = now
                .iter()
                .filter(|id| held.binary_search(id).is_ok())
                .count();
            count.entered_last_step = (now.len() - stayed) as u64;
            count.left_last_step = (held.len() - stayed) as u64;
            count.entered += count.entered_last_step;
            count.left += count.left_last_step;
            count.inside = now.len();
            *held = now;
        }
    }

    /// Discs were removed: those a sensor held left it.
    pub(crate) fn removed(&mut self, p: &Particles) {
        if self.holds.iter().all(Vec::is_empty) {
            return;
        }
        let mut present = p.id.clone();
        present.sort_unstable();
        for (count, held) in self.counts.iter_mut().zip(&mut self.holds) {
            let before = held.len();
            held.retain(|id| present.binary_search(id).is_ok());
            let gone = (before - held.len()) as u64;
            count.left_last_step += gone;
            count.left += gone;
            count.inside = held.len();
        }
    }

    /// What is wrong with a loaded state for `sensors` and ids below `next_id`, if anything.
    pub(crate) fn problem(&self, sensors: &[Sensor], next_id: u32) -> Option<String> {
        if self.counts.len() != self.holds.len() || self.counts.len() != sensors.len() {
            return Some(format!(
                "{} counts and {} sets for {} sensors",
                self.counts.len(),
                self.holds.len(),
                sensors.len()
            ));
        }
        for (k, (count, held)) in self.counts.iter().zip(&self.holds).enumerate() {
            let ascending = held.windows(2).all(|w| w[0] < w[1]);
            let known = held.last().is_none_or(|id| id.0 < next_id);
            if !(ascending && known && count.inside == held.len()) {
                return Some(format!("sensor {k}: its discs are not a set of known ids"));
            }
        }
        None
    }
}
