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
    /// [`crate::StepStats::obstacle_work`]): with elastic collisions, the gain in kinetic energy a
    /// piston gave the gas.
    pub fn obstacle_work(&self) -> f64 {
        self.obstacle_work
    }

    /// The momentum each obstacle received during the last step (divide by `dt` for the
    /// force), in the configuration's order.
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
