//! The world's side of distributed runs (see `part`): records of discs, a part of the
//! world, discs leaving and arriving, ghost states written from their owners, the sensors'
//! discs a part sees and the state the root keeps.

use std::sync::OnceLock;

use crate::part::{DiscRecord, Tally, Travel};
use crate::particles::ParticleId;
use crate::stats::StepStats;
use crate::sum::StepSums;

use super::{SensorState, World, WorldError};
use crate::contact_events::ContactLog;

impl World {
    /// The record of the disc at storage index `i`.
    /// See [`World::part`] for an example.
    pub fn record(&self, i: usize) -> DiscRecord {
        let p = self.particles();
        DiscRecord {
            id: p.ids()[i],
            position: [p.x()[i], p.y()[i]],
            velocity: [p.vx()[i], p.vy()[i]],
            radius: p.radius()[i],
            mass: p.per_particle_mass()[i],
            image: p.image()[i],
            angular_velocity: p.angular_velocity().get(i).copied().unwrap_or(0.0),
            orientation: p.orientation().get(i).copied().unwrap_or(0.0),
            tag: p.tag_of(i),
        }
    }

    /// A world of these discs (ids kept, stored in the order given) with this one's
    /// configuration, clock, last statistics, obstacles, sources and id counter: a part of
    /// this world, or (given every disc) the whole of a distributed one. Its candidates are
    /// listed at its first step; it runs on one thread until told otherwise.
    ///
    /// ```
    /// use bounce::{Boundary, Config, ExactSum, Particle, Tally, World};
    /// let config = Config {
    ///     boundary: Boundary::periodic([0.0, 0.0], [20.0, 20.0]),
    ///     ..Config::default()
    /// };
    /// let mut whole = World::new(config)?;
    /// for k in 0..100 {
    ///     let (i, j, f) = ((k % 10) as f64, (k / 10) as f64, k as f64);
    ///     let v = [(0.7 * f).sin(), (1.3 * f).cos()];
    ///     whole.add_particle(Particle::new([1.0 + 2.0 * i, 1.0 + 2.0 * j], v, 0.9))?;
    /// }
    /// let records: Vec<_> = (0..whole.len()).map(|i| whole.record(i)).collect();
    /// // Two parts holding every disc, each counting the events in its half of the box.
    /// let mut parts = Vec::new();
    /// for x in [[0.0, 10.0], [10.0, 20.0]] {
    ///     let mut part = whole.part(&records)?;
    ///     let all = [f64::NEG_INFINITY, f64::INFINITY];
    ///     part.set_tally(Some(Tally::new(x, all, [Some((0.0, 20.0)), None])));
    ///     parts.push(part);
    /// }
    /// let mut total = 0;
    /// for _ in 0..20 {
    ///     whole.step(0.05)?;
    ///     let (mut virial, mut collisions) = (ExactSum::new(), 0);
    ///     for part in &mut parts {
    ///         part.step(0.05)?;
    ///         virial.merge(&part.step_sums().virial);
    ///         collisions += part.stats().collisions;
    ///     }
    ///     // Between them the parts count every event once: the whole's sums, to the bit.
    ///     assert_eq!(collisions, whole.stats().collisions);
    ///     total += collisions;
    ///     assert_eq!(virial.value().to_bits(), whole.step_sums().virial.value().to_bits());
    /// }
    /// assert!(total > 10, "{total} collisions");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn part(&self, records: &[DiscRecord]) -> Result<World, WorldError> {
        let mut part = World::new(self.config().clone())?;
        part.adopt_clock(self);
        if self.particles.turning {
            part.particles.start_turning();
        }
        part.regroup(|_| true, records)?;
        Ok(part)
    }

    /// Keeps the discs `keep` accepts (by storage index) and adds `arriving` (ids not held
    /// here): a part's discs changing hands. All or nothing: an arriving disc that is held
    /// already, repeated, beyond the world's ids, or has non-finite values or a radius
    /// `<= 0` changes nothing and is the error. The candidates are listed again at the next
    /// step, and [`World::travel`] counts from here.
    ///
    /// ```
    /// use bounce::{Config, Particle, ParticleId, World};
    /// let mut world = World::new(Config::default())?;
    /// for x in [0.0, 4.0, 8.0] {
    ///     world.add_particle(Particle::new([x, 0.0], [1.0, 0.0], 0.5))?;
    /// }
    /// let last = world.record(world.index_of(ParticleId(2)).unwrap());
    /// // A part holding discs 0 and 1; disc 1 leaves and disc 2 arrives.
    /// let mut part = world.part(&[world.record(0), world.record(1)])?;
    /// let leaving = part.index_of(ParticleId(1)).unwrap();
    /// part.regroup(|i| i != leaving, &[last])?;
    /// let ids: Vec<u32> = part.in_id_order().iter().map(|(id, _)| id.0).collect();
    /// assert_eq!(ids, [0, 2]);
    /// // A ghost's state written from its owner: position, velocity, spin.
    /// part.overwrite(&[(ParticleId(2), [9.0, 1.0, -1.0, 0.0, 0.0])])?;
    /// assert_eq!(part.particle(ParticleId(2)).unwrap().position, [9.0, 1.0]);
    /// assert!(part.overwrite(&[(ParticleId(1), [0.0; 5])]).is_err()); // not held here
    /// // How far the discs have moved bounds when they must change hands again.
    /// part.relist();
    /// part.step(0.5)?;
    /// assert!(part.travel().since_start >= 0.5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn regroup(
        &mut self,
        mut keep: impl FnMut(usize) -> bool,
        arriving: &[DiscRecord],
    ) -> Result<(), WorldError> {
        // One bit per id: the discs here, then the arriving ones.
        let mut seen = vec![0u64; (self.next_id() as usize).div_ceil(64)];
        let bit = |id: ParticleId| ((id.0 / 64) as usize, 1u64 << (id.0 % 64));
        for &id in self.particles().ids() {
            let (word, b) = bit(id);
            seen[word] |= b;
        }
        for r in arriving {
            // States come from a running world: a disc an overlap push left a hair
            // outside a periodic box is wrapped at the next integration, so only the values
            // themselves are checked, not the box.
            let values = [
                r.position,
                r.velocity,
                [r.radius, r.mass],
                [r.angular_velocity, r.orientation],
            ];
            if !(values.iter().flatten().all(|v| v.is_finite()) && r.radius > 0.0) {
                return Err(WorldError::Inconsistent(format!(
                    "disc {}: non-finite values or a radius <= 0 in {r:?}",
                    r.id.0
                )));
            }
            if r.id.0 >= self.next_id() {
                return Err(WorldError::Inconsistent(format!(
                    "disc {} is beyond the world's ids (next id {})",
                    r.id.0,
                    self.next_id()
                )));
            }
            let (word, b) = bit(r.id);
            if seen[word] & b != 0 {
                return Err(WorldError::Inconsistent(format!(
                    "disc {} is here already or arrives twice",
                    r.id.0
                )));
            }
            seen[word] |= b;
        }
        self.keep_discs(&mut keep);
        for r in arriving {
            self.push_record(r);
        }
        self.after_records();
        self.reset_travel();
        Ok(())
    }

    /// Sets the position, velocity and angular velocity `[x, y, vx, vy, ω]` of each disc
    /// named (a part's ghosts, from their owners; their image counts and orientations are
    /// left as they are, and ω where discs do not turn). Every id must be here; otherwise
    /// nothing changes.
    /// See [`World::part`] and [`World::regroup`] for examples.
    pub fn overwrite(&mut self, states: &[(ParticleId, [f64; 5])]) -> Result<(), WorldError> {
        let mut at = Vec::with_capacity(states.len());
        for (id, _) in states {
            let i = self.index_of(*id).ok_or_else(|| {
                WorldError::Inconsistent(format!("disc {} is not in this world", id.0))
            })?;
            at.push(i);
        }
        self.write_motion(&at, states);
        Ok(())
    }

    /// Reports `stats` as the last step's: a distributed run's whole world, assembled from
    /// its parts, reports the step's statistics merged from theirs.
    /// See [`World::part`] and [`World::regroup`] for examples.
    pub fn set_reported_stats(&mut self, stats: StepStats) {
        self.set_stats(stats);
    }

    /// Reports `friction_work` as the energy friction has removed since the start: a
    /// distributed run's whole world reports the sum of the merged steps' (each part's own
    /// counts only its share).
    /// See [`World::part`] and [`World::regroup`] for examples.
    pub fn set_reported_friction_work(&mut self, friction_work: f64) {
        self.friction_work = friction_work;
    }
}

impl World {
    /// Counts only the events in `tally`'s region in the step's sums (`None`: all): for a
    /// part of a distributed world, see [`Tally`].
    /// See [`World::part`] for an example.
    pub fn set_tally(&mut self, tally: Option<Tally>) {
        self.tally = tally;
    }

    /// In a part with a tally and contact events on: the contacts its last step saw that
    /// the tally counts (by the place of their disc `a`), each with its substep, for the
    /// whole world's [`ContactLog::record_step`]. Taken once.
    /// See [`ContactLog::record_step`] for an example.
    pub fn take_contact_sightings(&mut self) -> Vec<(u32, crate::ContactEvent)> {
        self.contact_log.take_sightings()
    }

    /// Each sensor's discs now that this world counts (its tally's, in a part; all
    /// otherwise), ids ascending: what a part tells the root for the whole world's
    /// [`SensorState`].
    /// See [`SensorState::observe_sets`] for an example.
    pub fn sensed(&self) -> Vec<Vec<ParticleId>> {
        let p = &self.particles;
        let tally = self.tally;
        self.config
            .sensors
            .iter()
            .map(|sensor| {
                let mut ids: Vec<ParticleId> = (0..p.len())
                    .filter(|&i| {
                        let at = [p.x[i], p.y[i]];
                        sensor.region.contains(at) && tally.is_none_or(|t| t.counts(at[0], at[1]))
                    })
                    .map(|i| p.id[i])
                    .collect();
                ids.sort_unstable();
                ids
            })
            .collect()
    }

    /// Every sensor's discs and counts.
    /// See [`crate::SensorState::counts`] for an example.
    pub fn sensor_state(&self) -> &SensorState {
        &self.sensors
    }

    /// Replaces the sensors' state: a distributed run's whole world takes the one its root
    /// keeps, so its counts, outputs and checkpoints are one process's. Refused (naming the
    /// problem) when it does not fit this world's sensors and ids.
    /// See [`SensorState::observe_sets`] for an example.
    pub fn set_sensor_state(&mut self, state: SensorState) -> Result<(), WorldError> {
        if let Some(problem) = state.problem(&self.config.sensors, self.next_id) {
            return Err(WorldError::Inconsistent(format!("sensors: {problem}")));
        }
        self.sensors = state;
        Ok(())
    }

    /// The contact log (the last substep's contacts and the last step's events).
    /// See [`ContactLog::record_step`] for an example.
    pub fn contact_log(&self) -> &ContactLog {
        &self.contact_log
    }

    /// Replaces the contact log: a distributed run's whole world takes the log its root
    /// keeps, so its events, outputs and checkpoints are one process's.
    /// See [`ContactLog::record_step`] for an example.
    pub fn set_contact_log(&mut self, log: ContactLog) {
        self.contact_log = log;
    }

    /// Sizes the contact order's grid for discs up to `radius` (or this world's largest, if
    /// larger): a part of a distributed world gives the whole world's largest radius, so
    /// that its contacts fall in the same order.
    /// See [`World::part`] for an example.
    pub fn set_order_radius(&mut self, radius: f64) {
        self.order_radius = radius;
    }

    /// How much of the candidate list's life the discs have used (the farthest disc's
    /// distance from where the list was made over the distance that forces a new list, not
    /// counting the few met alone, the strays, or their count over their cap if that is
    /// more): at 1 the next substep lists again. `None` while no list is kept.
    /// See [`World::regroup`] for an example.
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
    /// See [`World::regroup`] for an example.
    pub fn relist(&mut self) {
        self.broadphase.invalidate();
    }

    /// Bounds on how far any disc has moved, from what the broadphase measures anyway (see
    /// [`Travel`]): a distributed run decides from it when its discs must change hands.
    /// See [`World::regroup`] for an example.
    pub fn travel(&self) -> Travel {
        self.travel
    }

    /// The exact sums of the last step (see [`StepSums`]).
    /// See [`World::part`] for an example.
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
        self.friction_work = other.friction_work;
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
        if p.turning {
            p.omega.push(r.angular_velocity);
            p.theta.push(r.orientation);
        }
        p.push_tag(r.tag);
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

    /// Writes positions, velocities and (where discs turn) angular velocities at storage
    /// indices `at`.
    pub(crate) fn write_motion(&mut self, at: &[usize], states: &[(ParticleId, [f64; 5])]) {
        let p = &mut self.particles;
        for (&i, (_, [x, y, vx, vy, w])) in at.iter().zip(states) {
            (p.x[i], p.y[i], p.vx[i], p.vy[i]) = (*x, *y, *vx, *vy);
            if p.turning {
                p.omega[i] = *w;
            }
        }
    }

    pub(crate) fn set_stats(&mut self, stats: StepStats) {
        self.stats = stats;
    }
}
