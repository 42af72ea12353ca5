//! The step context: what every stage of one step reads, decoded from the configuration
//! once per step instead of once per stage.

use crate::config::Config;
use crate::geometry::Geometry;
use crate::law::Law;
use crate::parallel::Executor;
use crate::part::Tally;

/// The substep length, the collision law, the geometry and where work runs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StepContext<'a> {
    /// The substep: `dt / substeps`.
    pub h: f64,
    /// Uniform acceleration.
    pub gravity: [f64; 2],
    /// When discs collide and what that does.
    pub law: Law,
    /// The edge of the world.
    pub geometry: Geometry,
    /// With more than one solver pass under gravity: the gravity vector, by which each
    /// order block's contacts are resolved lowest first (see `contacts`). `None` keeps the
    /// seed's single pass in id order.
    pub stack_order: Option<[f64; 2]>,
    /// Serial or a thread pool; results never depend on it.
    pub exec: &'a Executor,
    /// Which events the step's sums count: all (`None`), or in a part of a distributed
    /// world those in its region (see `part`).
    pub tally: Option<Tally>,
    /// The contact order's grid is sized for discs up to this radius at least (see
    /// `World::set_order_radius`; 0 sizes it for the discs here).
    pub order_radius: f64,
    /// The approach speed below which a contact rests (`law::resting_speed`).
    pub resting_speed: f64,
}

impl<'a> StepContext<'a> {
    /// The context of a step of substep `h` under `config`.
    pub(crate) fn new(config: &Config, h: f64, exec: &'a Executor, tally: Option<Tally>) -> Self {
        StepContext {
            h,
            gravity: config.gravity,
            law: Law::at_substep(config, h),
            geometry: Geometry::new(config),
            stack_order: (config.solver_iterations > 1 && config.gravity != [0.0, 0.0])
                .then_some(config.gravity),
            exec,
            tally,
            order_radius: 0.0,
            resting_speed: crate::law::resting_speed(config.gravity, h),
        }
    }
}
