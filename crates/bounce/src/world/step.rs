//! The fast step as a script of stages, each stage's policy inside the stage, and the end
//! of the step that the fast and the plain step share.
//!
//! One step: emit; then `substeps` times: move the obstacles → integrate (walls and the
//! displacement check) → send back the discs that crossed a segment → keep or rebuild the
//! candidate list → `solver_iterations` times: detect the colliding pairs, resolve them in
//! canonical order, meet the obstacles, hold the walls; then sinks and measure. The profile
//! times each stage under its own name (`StepProfile`).

use crate::broadphase::{self, Broadphase, Moved};
use crate::config::Config;
use crate::config::ObstacleState;
use crate::contact_events::ContactLog;
use crate::contacts::Contacts;
use crate::context::StepContext;
use crate::integrate::{integrate, turn};

use crate::obstacles::{self, Met, Obstacles, Trail, resolve_obstacles, take_impacts};
use crate::part::Travel;
use crate::particles::Particles;
use crate::resolve::{Recording, resolve_all, resolve_in_order, resolve_walls, solver_order};
use crate::stats::{Measured, StepProfile, StepStats, Stopwatch, measure};
use crate::sum::{ExactSum, StepSums};

use super::{StepError, World};

impl World {
    /// The step's body, on one of the pool's threads when the world is large enough to use
    /// them (see `Executor::installer`).
    pub(super) fn step_in_pool(&mut self, dt: f64, substeps: u32) -> Result<(), StepError> {
        self.check_time_step(dt)?;
        let substeps = self.check_substeps(dt, substeps)?;
        let emitted = self.emit(dt);
        self.prepare_obstacles();
        let mut done = Substepped::new(substeps, emitted, self.config.obstacles.len());
        let interrupt = self.interrupt.clone();
        let step = self.steps + 1;
        let start = self.time;
        let mut stages = Stages::new(self, dt / substeps as f64);
        for substep in 0..substeps {
            let end = substep_end(start, dt, substeps, substep);
            stages.ctx.geometry = stages.ctx.geometry.at_time(end);
            if substep > 0
                && interrupt
                    .as_ref()
                    .is_some_and(|flag| flag.load(std::sync::atomic::Ordering::Relaxed) != 0)
            {
                return Err(StepError::Interrupted { step });
            }
            stages.move_obstacles(&mut done);
            let moved = stages.integrate(&mut done);
            stages.send_back_crossings(&mut done);
            let Some(rebuilt) = stages.update_candidates(&moved, &mut done) else {
                break;
            };
            for pass in 0..stages.config.solver_iterations {
                stages.detect(pass, rebuilt, &moved, &mut done);
                stages.resolve_pairs(pass, &mut done);
                stages.meet_obstacles(&mut done);
                stages.hold_walls(&mut done);
            }
            if let Some(log) = stages.log.as_deref_mut() {
                log.end_substep(substep, stages.config.contact_event_threshold);
            }
        }
        self.finish_step(dt, done)
    }

    /// Refuses a `dt` that is not finite and `> 0`, or that would take the clock past
    /// `f64`: a step never starts that cannot end.
    pub(crate) fn check_time_step(&self, dt: f64) -> Result<(), StepError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(StepError::InvalidTimeStep(dt));
        }
        if !(self.time + dt).is_finite() {
            return Err(StepError::ClockOverflow {
                time: self.time,
                dt,
            });
        }
        Ok(())
    }

    /// The substeps a step takes, at least one; more than [`crate::MAX_SUBSTEPS`] (only
    /// `max_travel` asks for that) is refused, naming `dt` and `max_travel`.
    pub(crate) fn check_substeps(&self, dt: f64, substeps: u32) -> Result<u32, StepError> {
        if substeps > crate::MAX_SUBSTEPS {
            return Err(StepError::TooManySubsteps {
                dt,
                max_travel: self.config.max_travel.unwrap_or(f64::NAN),
            });
        }
        Ok(substeps.max(1))
    }

    /// The end of every step, fast, plain or event-driven, after its substeps: the
    /// thermostat, the sensors and sinks, the measurement, the clock, and the check that
    /// nothing overflowed.
    pub(crate) fn finish_step(&mut self, dt: f64, done: Substepped) -> Result<(), StepError> {
        let Substepped {
            mut stats,
            mut sums,
            tensor,
            met,
            mut profile,
            mut clock,
            finite,
            mut reordered,
            collided,
        } = done;
        if self.config.collision_counts {
            // By id, so the counts follow the discs through every reordering.
            self.collision_counts.resize(self.next_id as usize, 0);
            for id in collided {
                self.collision_counts[id as usize] += 1;
            }
        }
        if let Some(thermostat) = self.config.thermostat.as_ref().filter(|_| finite) {
            stats.thermostat_work = crate::thermostat::apply(
                thermostat,
                (self.config.mass_model, &self.config.boundary),
                &mut self.particles,
                self.steps + 1,
                dt,
            );
        }
        if !self.config.sensors.is_empty() {
            self.sensors.observe(&self.config.sensors, &self.particles);
        }
        if !self.config.sinks.is_empty() && finite {
            stats.removed = self.drain_sinks();
            reordered |= stats.removed > 0;
            if stats.removed > 0 {
                self.sensors.removed(&self.particles);
            }
        }
        let measured = Measured {
            total_mass: self.measured.total_mass,
            radius_sum: self.measured.radius_sum,
            ..measure(
                &self.particles,
                self.config.mass_model,
                self.broadphase.uniform_radius(),
                &self.exec,
                self.config.max_travel.is_some(),
            )
        };
        (stats.kinetic_energy, stats.momentum) = (measured.kinetic_energy, measured.momentum);
        // The 2D virial equation: P A = N kT + (1/2) <Σ r_ij · F_ij>, the forces being the
        // impulses over the step.
        stats.virial = 0.5 * sums.virial.value() / dt;
        stats.virial_tensor = tensor.each_ref().map(|sum| sum.value() / dt);
        stats.wall_impulse = sums.walls.impulse();
        sums.friction.merge(&met.friction);
        stats.friction_work = sums.friction_work();
        self.friction_work += stats.friction_work;
        self.thermostat_work += stats.thermostat_work;
        self.sums = sums;
        self.measured = measured;
        stats.pressure = self.pressure(measured.kinetic_energy, measured.momentum, stats.virial);
        profile.measure += clock.lap();
        stats.obstacle_work = met.work;
        self.stats = stats;
        self.obstacle_impulses = met.impulses;
        self.obstacle_work += stats.obstacle_work;
        self.profile = profile;
        self.time += dt;
        self.steps += 1;
        if reordered {
            self.index_of = std::sync::OnceLock::new();
        }
        let momentum_finite = stats.momentum.iter().all(|v| v.is_finite());
        if !(finite && stats.kinetic_energy.is_finite() && momentum_finite) {
            self.broadphase.invalidate();
            return Err(StepError::NonFinite {
                step: self.steps,
                id: self.first_non_finite(),
            });
        }
        Ok(())
    }
}

/// When substep `k` of `substeps` of a step of `dt` from `start` ends (the last one at the
/// step's own end, `start + dt`): where a Lees–Edwards box's images stand for it.
pub(crate) fn substep_end(start: f64, dt: f64, substeps: u32, k: u32) -> f64 {
    if k + 1 == substeps {
        start + dt
    } else {
        start + f64::from(k + 1) * (dt / f64::from(substeps))
    }
}

/// What a step's substeps leave for [`World::finish_step`].
pub(crate) struct Substepped {
    pub stats: StepStats,
    pub sums: StepSums,
    /// `Σ [r_x J_x, r_y J_y, ½ (r_x J_y + r_y J_x)]` over the resolved pairs, with
    /// [`Config::pressure_tensor`] (empty otherwise).
    pub tensor: [ExactSum; 3],
    pub met: Met,
    pub profile: StepProfile,
    pub clock: Stopwatch,
    /// No position overflowed.
    pub finite: bool,
    /// The discs' storage order changed.
    pub reordered: bool,
    /// The ids of the two discs of each impact, with [`Config::collision_counts`] (empty
    /// otherwise).
    pub collided: Vec<u32>,
}

impl Substepped {
    /// A step of `substeps` that emitted `emitted` discs first, with `obstacles` obstacles.
    pub(crate) fn new(substeps: u32, emitted: usize, obstacles: usize) -> Self {
        Substepped {
            stats: StepStats {
                substeps,
                emitted,
                ..StepStats::default()
            },
            sums: StepSums::default(),
            tensor: Default::default(),
            met: Met::new(obstacles),
            profile: StepProfile::default(),
            clock: Stopwatch::start(),
            finite: true,
            reordered: false,
            collided: Vec::new(),
        }
    }
}

/// The world's parts a substep's stages work on, borrowed apart from the configuration the
/// step's context reads.
struct Stages<'w> {
    ctx: StepContext<'w>,
    config: &'w Config,
    particles: &'w mut Particles,
    broadphase: &'w mut Broadphase,
    contacts: &'w mut Contacts,
    obstacles: &'w mut Obstacles,
    obstacle_states: &'w mut Vec<ObstacleState>,
    trail: &'w mut Trail,
    travel: &'w mut Travel,
    /// Segments can be crossed: discs are followed from where they were last on the right
    /// side. Pegs have an inside, and need no trail.
    follow: bool,
    /// The last step's contacts per disc and substep (saved with the world, so a loaded one
    /// decides as the original does).
    contacts_per_disc: f64,
    /// Where the substeps' contacts are reported, when the configuration asks for events.
    log: Option<&'w mut ContactLog>,
}

impl<'w> Stages<'w> {
    fn new(world: &'w mut World, h: f64) -> Self {
        let last = &world.stats;
        let contacts_per_disc =
            last.pairs as f64 / (last.substeps.max(1) as f64 * world.particles.len().max(1) as f64);
        let World {
            config,
            particles,
            broadphase,
            contacts,
            obstacles,
            obstacle_states,
            trail,
            travel,
            exec,
            tally,
            order_radius,
            contact_log,
            ..
        } = world;
        let log = config.contact_events.then(|| {
            contact_log.start_step(*tally);
            contact_log
        });
        let obstacles = obstacles.as_mut().expect("prepared");
        let mut ctx = StepContext::new(config, h, exec, *tally);
        ctx.order_radius = *order_radius;
        Stages {
            ctx,
            config,
            particles,
            broadphase,
            contacts,
            follow: obstacles.needs_trail(),
            obstacles,
            obstacle_states,
            trail,
            travel,
            contacts_per_disc,
            log,
        }
    }

    /// Moving obstacles advance to the substep's end and are placed in their grid; with
    /// segments, the discs' places are noted first.
    fn move_obstacles(&mut self, done: &mut Substepped) {
        if self.obstacles.is_empty() {
            return;
        }
        obstacles::advance(self.config, self.obstacle_states, self.ctx.h);
        self.obstacles.place(self.config, self.obstacle_states);
        if self.follow {
            self.trail.mark(self.particles);
        }
        done.profile.obstacles += done.clock.lap();
    }

    /// Gravity, drift and the walls, with how far each disc got from its reference.
    fn integrate(&mut self, done: &mut Substepped) -> Moved {
        if let Some(log) = self.log.as_deref_mut() {
            log.before_walls(self.particles, &self.ctx.geometry);
        }
        let bp = &self.broadphase;
        let mut moved = integrate(self.particles, &self.ctx, &bp.reference, bp.radius_bound());
        if self.particles.turning {
            turn(self.particles, self.ctx.h, self.ctx.exec);
        }
        // A disc sent back across a segment returns to where it was, which for a stray of
        // the last substep is past the allowance: with segments, no strays are kept.
        moved.too_many_strays |= self.follow && !moved.strays.is_empty();
        if let Some(log) = self.log.as_deref_mut() {
            let [gx, gy] = self.ctx.gravity;
            let fall = [gx * self.ctx.h, gy * self.ctx.h];
            log.see_walls(self.particles, &self.ctx.geometry, &self.ctx.law, fall);
        }
        done.sums.walls.merge(&moved.impulse);
        done.profile.integrate += done.clock.lap();
        moved
    }

    /// Discs that flew through a segment in this substep go back.
    fn send_back_crossings(&mut self, done: &mut Substepped) {
        if self.follow {
            self.meet(true, done);
        }
    }

    /// Keeps the candidate list or rebuilds it (reordering the discs); `Some(rebuilt)`, or
    /// `None` when a position overflowed (the step ends).
    fn update_candidates(&mut self, moved: &Moved, done: &mut Substepped) -> Option<bool> {
        let bp = &mut *self.broadphase;
        let rebuilt = bp.update(self.particles, &self.ctx, moved, self.contacts_per_disc);
        done.reordered |= rebuilt;
        self.travel
            .note(moved.max_displacement2, moved.max_stride, rebuilt);
        if rebuilt && self.follow {
            self.trail.mark(self.particles);
        }
        done.profile.rebuilds += rebuilt as usize;
        done.profile.strays = done.profile.strays.max(bp.strays().len());
        done.profile.bin += done.clock.lap();
        if rebuilt && bp.overflowed() {
            // An infinite position (NaN ones come with NaN velocities, caught at the end).
            done.finite = false;
            return None;
        }
        Some(rebuilt)
    }

    /// The colliding pairs among the candidates, in canonical order; the first pass's are
    /// the step's count. Later passes see the velocities and places the earlier ones left
    /// (the candidates still hold every pair that can collide).
    fn detect(&mut self, pass: u32, rebuilt: bool, moved: &Moved, done: &mut Substepped) {
        let bp = &*self.broadphase;
        // The first pass after integration knows how far discs are from their references;
        // later ones (after pushes) and segment crossings test all.
        let bands = if pass == 0 && !self.follow {
            // A rebuild took the current positions as the reference; strays are met alone.
            bp.bands_within(if rebuilt {
                0.0
            } else {
                bp.kept2(moved.max_kept2, &self.ctx)
            })
        } else {
            broadphase::BANDS
        };
        let found = self.contacts.find(bp, bands, self.particles, &self.ctx);
        done.profile.sorted_detections += found.sorted as usize;
        done.profile.out_of_place += found.out_of_place;
        if pass == 0 {
            let found = match self.ctx.tally {
                None => found,
                Some(tally) => self.contacts.tallied(self.particles, &self.ctx, tally),
            };
            done.stats.pairs += found.pairs;
            done.stats.max_overlap = done.stats.max_overlap.max(found.max_overlap);
        }
        done.profile.pairs += done.clock.lap();
    }

    /// The law of this pass on each contact, in canonical order.
    fn resolve_pairs(&mut self, pass: u32, done: &mut Substepped) {
        let uniform = self.broadphase.uniform_radius();
        let ctx = StepContext {
            law: self.ctx.law.for_pass(pass),
            ..self.ctx
        };
        let recording = Recording {
            tensor: self.config.pressure_tensor,
            impacts: self.config.collision_counts && pass == 0,
        };
        // In a Lees–Edwards box a contact across the top and bottom meets its partner's
        // sliding image, whose velocity the side-by-side kernel does not carry: the contacts
        // are resolved one at a time in the canonical order, as the plain step does (the
        // colouring still holds: the blocks a disc meets across the edge are slid along x,
        // still one of each colour).
        let sheared = ctx.geometry.slide().is_some();
        let order = |contacts: &Contacts| match sheared {
            true => (contacts.list().iter())
                .map(|c| (c.a as usize, c.b as usize))
                .collect(),
            false => solver_order(contacts),
        };
        let resolved = match self.log.as_deref_mut() {
            None if !sheared => {
                resolve_all(self.contacts, self.particles, &ctx, uniform, recording)
            }
            // One contact at a time, each reported (the same bits: `solver_order`).
            mut log => resolve_in_order(
                self.particles,
                order(self.contacts),
                &ctx.law,
                &ctx.geometry,
                (ctx.resting_speed, ctx.tally),
                recording,
                |p, pair| {
                    if let Some(log) = log.as_deref_mut() {
                        log.see_pair(p, pair);
                    }
                },
            ),
        };
        for (sum, part) in done.tensor.iter_mut().zip(&resolved.tensor) {
            sum.merge(part);
        }
        done.collided.extend_from_slice(&resolved.collided);
        done.sums.virial.merge(&resolved.virial);
        done.sums.friction.merge(&resolved.friction);
        if pass == 0 {
            done.stats.collisions += resolved.impacts;
        }
        done.profile.resolve += done.clock.lap();
    }

    /// Discs touching an obstacle are pushed out and bounce; moving obstacles take their
    /// impulses.
    fn meet_obstacles(&mut self, done: &mut Substepped) {
        if !self.obstacles.is_empty() {
            self.meet(self.follow, done);
        }
    }

    /// One obstacle pass (`follow`: along the trail), its impacts reported when asked.
    fn meet(&mut self, follow: bool, done: &mut Substepped) {
        let trail = follow.then_some(&mut *self.trail);
        let (p, ctx) = (&mut *self.particles, &self.ctx);
        match self.log.as_deref_mut() {
            None => obstacles::meet(
                p,
                trail,
                self.obstacles,
                self.obstacle_states,
                self.config,
                ctx,
                &mut done.met,
            ),
            Some(log) => {
                let impacts =
                    resolve_obstacles(p, trail, self.obstacles, self.obstacle_states, ctx, true);
                let states = &*self.obstacle_states;
                let shapes = self.obstacles.shapes();
                log.see_obstacles(p, &impacts, shapes, |k| states[k].velocity);
                take_impacts(impacts, self.config, self.obstacle_states, &mut done.met);
            }
        }
        done.profile.obstacles += done.clock.lap();
    }

    /// With several solver passes, the pushes may carry discs past a wall: they are held
    /// (integration holds them in the first).
    fn hold_walls(&mut self, done: &mut Substepped) {
        if self.config.solver_iterations > 1 {
            if let Some(log) = self.log.as_deref_mut() {
                log.before_walls(self.particles, &self.ctx.geometry);
            }
            done.sums
                .walls
                .merge(&resolve_walls(self.particles, &self.ctx));
            if let Some(log) = self.log.as_deref_mut() {
                log.see_walls(self.particles, &self.ctx.geometry, &self.ctx.law, [0.0; 2]);
            }
            done.profile.walls += done.clock.lap();
        }
    }
}
