//! A step under [`Method::EventDriven`](crate::Method::EventDriven): the discs handed to the
//! event engine ([`crate::event`]) as they are, every event up to `t + dt` processed, and
//! the discs and the step's sums taken back. The engine is built anew from the state each
//! step, so a step is a function of the state alone: a run resumed from a checkpoint
//! continues bit for bit.

use crate::event::{EventDriven, EventError, MAX_EVENTS_PER_DISC};
use crate::integrate::turned;
use crate::particles::Particle;
use crate::world::step::Substepped;

use super::{StepError, World};

impl World {
    /// The event-driven step's body.
    pub(super) fn step_events(&mut self, dt: f64) -> Result<(), StepError> {
        self.check_time_step(dt)?;
        let mut done = Substepped::new(1, 0, self.config.obstacles.len());
        let p = &self.particles;
        let discs: Vec<Particle> = (0..p.len())
            .map(|i| Particle {
                mass: Some(p.mass[i]),
                ..Particle::new([p.x[i], p.y[i]], [p.vx[i], p.vy[i]], p.radius[i])
            })
            .collect();
        let name = |e: EventError| self.name_discs(e);
        let mut engine = EventDriven::new(&self.config, &discs).map_err(name)?;
        let budget = MAX_EVENTS_PER_DISC.saturating_mul(discs.len().max(100) as u64);
        let seen = match engine.advance_within(dt, budget, self.interrupt.as_deref()) {
            Ok(seen) => seen,
            Err(EventError::Interrupted { .. }) => {
                return Err(StepError::Interrupted {
                    step: self.steps + 1,
                });
            }
            Err(e) => return Err(self.name_discs(e)),
        };
        let p = &mut self.particles;
        for i in 0..p.len() {
            let ((position, image), (_, velocity)) = (engine.wrapped(i), engine.state(i));
            [p.x[i], p.y[i]] = position;
            [p.vx[i], p.vy[i]] = velocity;
            p.image[i] = [0, 1].map(|a| p.image[i][a].wrapping_add(image[a]));
            done.finite &= position.iter().chain(&velocity).all(|v| v.is_finite());
        }
        if p.turning {
            for (theta, &omega) in p.theta.iter_mut().zip(&p.omega) {
                *theta = turned(*theta, omega, dt);
            }
        }
        done.stats.collisions = seen.collisions as usize;
        done.collided = seen.collided.iter().map(|&k| p.id[k as usize].0).collect();
        done.sums.virial.add(seen.virial);
        if self.config.pressure_tensor {
            for (sum, term) in done.tensor.iter_mut().zip(seen.virial_tensor) {
                sum.add(term);
            }
        }
        done.sums.walls.add(seen.wall_impulse);
        done.met.impulses = seen.obstacle_impulses;
        self.broadphase.invalidate();
        self.finish_step(dt, done)
    }

    /// `error` with its discs named by their ids (the engine numbers them in storage
    /// order).
    fn name_discs(&self, error: EventError) -> StepError {
        let id = |k: usize| self.particles.id[k].0 as usize;
        StepError::EventDriven(match error {
            EventError::Disc(k, what) => EventError::Disc(id(k), what),
            EventError::Overlap(a, b) => {
                let (a, b) = (id(a), id(b));
                EventError::Overlap(a.min(b), a.max(b))
            }
            EventError::Stalled { time, discs } => EventError::Stalled {
                time: self.time + time,
                discs: discs.into_iter().map(id).collect(),
            },
            EventError::TooManyEvents { events, time } => EventError::TooManyEvents {
                events,
                time: self.time + time,
            },
            unsupported => unsupported,
        })
    }
}
