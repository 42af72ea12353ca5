//! The world's obstacles: the step's form of them built from the configuration, and what
//! a front end reads of them (shapes where they are now, states, impulses, work).

use crate::config::{Config, ObstacleState, Shape};
use crate::obstacles::Obstacles;

use super::World;

impl World {
    /// Builds the obstacles' grid when the configuration or the discs changed.
    pub(super) fn prepare_obstacles(&mut self) {
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
    ///
    /// ```
    /// use bounce::{Boundary, Config, Motion, Obstacle, Particle, World};
    /// // A segment moving up at 1 a time unit, a disc at rest above it.
    /// let piston = Obstacle::segment([0.0, 1.0], [20.0, 1.0]).moving(Motion::Velocity([0.0, 1.0]));
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
    ///     obstacles: vec![piston],
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([10.0, 3.0], [0.0, 0.0], 0.5))?;
    /// world.step(0.5)?;
    /// assert_eq!(world.obstacle_shapes()[0], bounce::Shape::Segment { a: [0.0, 1.5], b: [20.0, 1.5] });
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn obstacle_shapes(&self) -> Vec<Shape> {
        self.config
            .obstacles
            .iter()
            .zip(&self.obstacle_states)
            .map(|(o, s)| o.shifted(s.offset))
            .collect()
    }

    /// Where each obstacle is (its offset from the configured shape) and how fast it moves.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Motion, Obstacle, Particle, World};
    /// // A segment moving up at 1 a time unit, a disc at rest above it.
    /// let piston = Obstacle::segment([0.0, 1.0], [20.0, 1.0]).moving(Motion::Velocity([0.0, 1.0]));
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
    ///     obstacles: vec![piston],
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([10.0, 3.0], [0.0, 0.0], 0.5))?;
    /// world.step(0.5)?;
    /// let state = world.obstacle_states()[0];
    /// assert_eq!((state.offset, state.velocity), ([0.0, 0.5], [0.0, 1.0]));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn obstacle_states(&self) -> &[ObstacleState] {
        &self.obstacle_states
    }

    /// The work the moving obstacles have done on the discs since the start (the sum of
    /// [`crate::StepStats::obstacle_work`]): with elastic collisions, the gain in kinetic energy a
    /// piston gave the gas.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Motion, Obstacle, Particle, World};
    /// // A segment moving up at 1 a time unit, a disc at rest above it.
    /// let piston = Obstacle::segment([0.0, 1.0], [20.0, 1.0]).moving(Motion::Velocity([0.0, 1.0]));
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
    ///     obstacles: vec![piston],
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([10.0, 3.0], [0.0, 0.0], 0.5))?;
    /// for _ in 0..300 {
    ///     world.step(0.01)?;
    /// }
    /// // The piston met the disc and threw it up: the work it did is the energy gained.
    /// assert!(world.obstacle_work() > 0.0);
    /// assert!((world.obstacle_work() - world.stats().kinetic_energy).abs() < 1e-9);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn obstacle_work(&self) -> f64 {
        self.obstacle_work
    }

    /// The momentum each obstacle received during the last step (divide by `dt` for the
    /// force), in the configuration's order.
    ///
    /// ```
    /// use bounce::{Config, Obstacle, Particle, World};
    /// // A disc (mass 1) falling onto a fixed peg at speed 2 bounces straight back.
    /// let mut world = World::new(Config {
    ///     obstacles: vec![Obstacle::peg([0.0, 0.0], 1.0)],
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([0.0, 2.01], [0.0, -2.0], 1.0))?;
    /// world.step(0.01)?;
    /// let [jx, jy] = world.obstacle_impulses()[0];
    /// assert!(jx.abs() < 1e-12 && (jy + 4.0).abs() < 1e-9); // the peg took −2 m v
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn obstacle_impulses(&self) -> &[[f64; 2]] {
        &self.obstacle_impulses
    }
}

/// Every obstacle at its configured place with its starting velocity.
pub(super) fn initial_states(config: &Config) -> Vec<ObstacleState> {
    config
        .obstacles
        .iter()
        .map(|o| ObstacleState {
            offset: [0.0, 0.0],
            velocity: o.initial_velocity(),
        })
        .collect()
}
