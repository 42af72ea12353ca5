//! World configuration: the collision model's parameters, the boundary, and the model options.
//!
//! Every default is the default collision model's behaviour (the user guide's
//! `docs/src/concepts/collision-model.md` explains it and where it comes from). Where that
//! model is physically questionable (mass = radius, restitution applied to each new normal velocity, velocity update for pairs
//! that already separate) the physically standard choice is an explicit option here, never the
//! default. [`Config::validate`] checks everything once; the step itself never re-checks.

use serde::{Deserialize, Serialize};
use thiserror::Error;

mod boundary;
mod method;
mod models;
mod obstacle;
mod sensor;
mod sources;
mod thermostat;

pub use boundary::Boundary;
pub use method::Method;
pub use models::{MassModel, RestingContacts, RestitutionModel, VelocityUpdate};

pub use obstacle::{Motion, Obstacle, ObstacleState, Shape};
pub use sensor::{Region, Sensor};
pub use sources::{Emitter, EmitterState, Sink};
pub use thermostat::{Thermostat, ThermostatKind};

/// Simulation parameters. Build with [`Config::default`] and change what you need.
///
/// ```
/// use bounce::{Boundary, Config};
/// let config = Config {
///     coefficient_of_restitution: 0.9,
///     boundary: Boundary::walls([0.0, 0.0], [100.0, 50.0]),
///     ..Config::default()
/// };
/// assert!(config.validate().is_ok());
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    /// Two discs collide when their centre distance is at most
    /// `(r_i + r_j) * collision_radius_scale`. Default `1.0` (discs touch exactly). Values
    /// above 1 make particles react before they touch, for responsiveness. Must be finite and `> 0`.
    pub collision_radius_scale: f64,
    /// The coefficient of restitution `e`, applied as [`Config::restitution_model`] says.
    /// Default `1.0` (elastic). Must be finite and in `[0, 1]`.
    pub coefficient_of_restitution: f64,
    /// Uniform acceleration in length/time², applied every substep. Default `[0, 0]`: no
    /// gravity, since a gas is the common first experiment.
    pub gravity: [f64; 2],
    /// Substeps per [`crate::World::step`]: each runs integrate → boundary → detect → resolve
    /// with `dt / substeps`. Default `1`: one move and resolution a step; raise it for stacks and
    /// piles where overlaps must stay small. Must be `>= 1`.
    /// At most [`MAX_SUBSTEPS`].
    pub substeps: u32,
    /// Passes of detection and resolution per substep. Default `1`, a single pass.
    /// A later pass changes the velocities only of pairs still approaching, whatever
    /// [`VelocityUpdate`] says (see [`crate::law::Law::for_pass`]): a pair collides once,
    /// however many passes. With more than one, each pass ends with the walls as contacts (a disc touching a wall and
    /// moving into it bounces with the wall restitution), so a stack (a pile under gravity)
    /// passes its shared velocity down to the floor within a substep: a pile under the
    /// momentum-conserving model stops compressing. Under gravity the contacts of each
    /// order block are then resolved lowest first, so one pass carries the floor's support
    /// up a block; with 64 passes the momentum-conserving pile rests as still as the default model's.
    /// At most 100.
    pub solver_iterations: u32,
    /// Adaptive substeps: the farthest a disc may travel in one substep, as a fraction of the
    /// smallest radius. `None` (the default) keeps `substeps` fixed. With `Some(f)`, each step
    /// takes `max(substeps, ceil(v_max dt / (f r_min)))` substeps (a step that would need
    /// more than [`MAX_SUBSTEPS`] is refused with [`crate::StepError::TooManySubsteps`]),
    /// chosen from the fastest disc at the start of the step and gravity:
    /// fast discs cannot tunnel through discs or walls, and the time-step bias stays bounded.
    /// Deterministic: the count depends on the state only. Must be finite and `> 0`.
    pub max_travel: Option<f64>,
    /// What happens at the edge of the world. Default [`Boundary::Open`]: a
    /// world needs no box, and an open world invents no length scale. Use [`Boundary::walls`] for a container.
    pub boundary: Boundary,
    /// The mass each disc has in the collision formula, kinetic energy and momentum. Default
    /// [`MassModel::Radius`]: the radii stand in for the masses.
    pub mass_model: MassModel,
    /// How the coefficient of restitution is applied. Default
    /// [`RestitutionModel::ScaleEachNormalVelocity`]: each new normal velocity is scaled.
    pub restitution_model: RestitutionModel,
    /// Which detected pairs get the velocity update. Default [`VelocityUpdate::AllDetected`]:
    /// every pair found colliding.
    pub velocity_update: VelocityUpdate,
    /// What a contact slower than the resting speed does (see [`RestingContacts`]). Default
    /// [`RestingContacts::Bounce`]: every contact is resolved with its
    /// restitution, however slow.
    pub resting_contacts: RestingContacts,
    /// Coulomb's friction coefficient `μ` of disc–disc contacts, finite and `>= 0`. Default
    /// `0`: smooth discs, whose tangential velocities a collision keeps. With any
    /// friction (here, at the walls or at an obstacle) or rolling resistance the discs are
    /// **rough**: each has an angular velocity and an orientation, and a contact's tangential
    /// impulse, after the normal update, removes (or reverses) the slip of the
    /// touching surfaces up to `μ` times the normal impulse (see [`crate::law::rough`]).
    pub friction: f64,
    /// The walls' friction coefficient, finite and `>= 0`. `None` (the default) uses
    /// [`Config::friction`].
    pub wall_friction: Option<f64>,
    /// Walton's tangential restitution `β` in `[-1, 1]`: a contact that sticks leaves with
    /// its slip velocity `-β` times what it was. Default `0` (the slip is removed: rolling
    /// contact); `1` reverses it (perfectly rough, elastic), `-1` leaves it (smooth).
    pub tangential_restitution: f64,
    /// Rolling resistance `μ_r`, finite and `>= 0`: at each contact a couple brakes the
    /// relative rotation of the two sides by at most `μ_r |J_n| r_eff` of angular impulse
    /// (`J_n` the normal impulse, `r_eff` the reduced lever arm; see
    /// [`crate::law::rough`]). Default `0`.
    pub rolling_resistance: f64,
    /// `k` in each disc's moment of inertia `I = k m r²` (`m` its mass under
    /// [`Config::mass_model`]), in `(0, 1]`. Default `0.5`, a solid disc (a ring is 1).
    pub inertia_factor: f64,
    /// How a step advances the world (see [`Method`]). Default [`Method::TimeStepped`]:
    /// step by step.
    pub method: Method,
    /// The TC model's duration `t_c` under [`Method::EventDriven`] (Luding & McNamara
    /// 1998): a disc's collision (with a disc, a wall or an obstacle) within `t_c` of its
    /// last one is elastic, so a dense inelastic group cannot collapse into infinitely many
    /// collisions in a finite time. Default `0`, off: every collision has its restitution.
    /// Finite and `>= 0`; the time-stepped method has no use for it.
    pub contact_duration: f64,
    /// Record contact events: each step, the contacts that began and ended in each of its
    /// substeps ([`crate::World::contact_events`], [`crate::ContactEvent`]). Default
    /// `false`: nothing is recorded and the step does no work for it.
    pub contact_events: bool,
    /// The smallest normal impulse a contact's `begin` event reports (and so its `end`):
    /// contacts that begin more gently are followed but not reported, as a game that plays
    /// a sound only for hard impacts wants. Default `0`, every contact. Finite and `>= 0`.
    pub contact_event_threshold: f64,
    /// Segments and pegs the discs collide with, fixed or moving (see [`Obstacle`]).
    /// Default none. Their impulses are reported by [`crate::World::obstacle_impulses`].
    pub obstacles: Vec<Obstacle>,
    /// Regions that add discs at a rate during the run (see [`Emitter`]). Default none.
    pub emitters: Vec<Emitter>,
    /// Regions that remove the discs entering them (see [`Sink`]). Default none.
    pub sinks: Vec<Sink>,
    /// Regions that count the discs entering and leaving them (see [`Sensor`]). Default
    /// none.
    pub sensors: Vec<Sensor>,
    /// Measure the collision virial tensor each step ([`crate::StepStats::virial_tensor`],
    /// [`crate::World::pressure_tensor`]). Default `false`. When on, the time-stepped solver
    /// takes the contacts one at a time (the same bits, as with contact events), which is
    /// slower.
    pub pressure_tensor: bool,
    /// Count each disc's collisions with other discs ([`crate::World::collision_counts`]):
    /// impacts, as [`crate::StepStats::collisions`] counts them. Default `false`. When on,
    /// the time-stepped solver takes the contacts one at a time (the same bits, as with
    /// contact events), which is slower.
    pub collision_counts: bool,
    /// A heat bath or a random drive acting at the end of every step (see [`Thermostat`]).
    /// Default `None`: the discs' energy changes only by collisions, walls and obstacles.
    pub thermostat: Option<Thermostat>,
}

/// The most substeps a step may have ([`Config::substeps`]). See [`ConfigError`] for an
/// example.
pub const MAX_SUBSTEPS: u32 = 10_000;

impl Default for Config {
    fn default() -> Self {
        Config {
            collision_radius_scale: 1.0,
            coefficient_of_restitution: 1.0,
            gravity: [0.0, 0.0],
            substeps: 1,
            solver_iterations: 1,
            max_travel: None,
            boundary: Boundary::Open,
            mass_model: MassModel::Radius,
            restitution_model: RestitutionModel::ScaleEachNormalVelocity,
            velocity_update: VelocityUpdate::AllDetected,
            resting_contacts: RestingContacts::Bounce,
            friction: 0.0,
            wall_friction: None,
            tangential_restitution: 0.0,
            rolling_resistance: 0.0,
            inertia_factor: 0.5,
            method: Method::TimeStepped,
            contact_duration: 0.0,
            contact_events: false,
            contact_event_threshold: 0.0,
            obstacles: Vec::new(),
            emitters: Vec::new(),
            sinks: Vec::new(),
            sensors: Vec::new(),
            pressure_tensor: false,
            collision_counts: false,
            thermostat: None,
        }
    }
}

/// A configuration value out of its allowed range.
///
/// ```
/// use bounce::Config;
/// let config = Config { coefficient_of_restitution: 1.5, substeps: 0, ..Config::default() };
/// let error = config.validate().unwrap_err();
/// assert_eq!(error.field, "coefficient_of_restitution");
/// assert_eq!(config.problems().len(), 2); // every problem, not only the first
/// assert!(error.to_string().starts_with("invalid config: `coefficient_of_restitution` = 1.5"));
/// ```
#[derive(Clone, Debug, PartialEq, Error)]
#[error("invalid config: `{field}` = {value}: {expected}")]
pub struct ConfigError {
    /// The field's name as in [`Config`] (`boundary.max` for nested fields).
    pub field: &'static str,
    /// The offending value, formatted.
    pub value: String,
    /// What the field must be.
    pub expected: &'static str,
}

impl Config {
    /// Checks every field; the first problem is returned, naming the field and its value.
    /// See [`ConfigError`] for an example.
    pub fn validate(&self) -> Result<(), ConfigError> {
        match self.problems().into_iter().next() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Every invalid field, in declaration order. See [`ConfigError`] for an example.
    pub fn problems(&self) -> Vec<ConfigError> {
        let mut out = Vec::new();
        let mut err = |field, value: String, expected| {
            out.push(ConfigError {
                field,
                value,
                expected,
            })
        };
        let s = self.collision_radius_scale;
        if !(s.is_finite() && s > 0.0) {
            err(
                "collision_radius_scale",
                s.to_string(),
                "must be finite and > 0",
            );
        }
        let e = self.coefficient_of_restitution;
        if !(0.0..=1.0).contains(&e) {
            err(
                "coefficient_of_restitution",
                e.to_string(),
                "must be in [0, 1]",
            );
        }
        if !self.gravity.iter().all(|g| g.is_finite()) {
            err("gravity", format!("{:?}", self.gravity), "must be finite");
        }
        if !(1..=MAX_SUBSTEPS).contains(&self.substeps) {
            err(
                "substeps",
                self.substeps.to_string(),
                "must be in 1..=10000 (more makes one step take minutes and ignore Ctrl-C)",
            );
        }
        if !(1..=100).contains(&self.solver_iterations) {
            err(
                "solver_iterations",
                self.solver_iterations.to_string(),
                "must be in 1..=100",
            );
        }
        if let Some(f) = self.max_travel
            && !(f.is_finite() && f > 0.0)
        {
            err("max_travel", f.to_string(), "must be finite and > 0");
        }
        if let Some((min, max)) = self.boundary.bounds() {
            if !min.iter().chain(&max).all(|v| v.is_finite()) {
                err(
                    "boundary",
                    format!("min {min:?}, max {max:?}"),
                    "corners must be finite",
                );
            } else if !(min[0] < max[0] && min[1] < max[1]) {
                err(
                    "boundary",
                    format!("min {min:?}, max {max:?}"),
                    "min must be below max on both axes",
                );
            } else if !((max[0] - min[0]) * (max[1] - min[1])).is_normal() {
                // The pressure divides by the area: it must be a finite, non-vanishing number.
                err(
                    "boundary",
                    format!("min {min:?}, max {max:?}"),
                    "the box's area must be a finite number of at least 1e-308",
                );
            }
        }
        if let Boundary::Walls {
            wall_restitution: Some(w),
            ..
        } = self.boundary
            && !(0.0..=1.0).contains(&w)
        {
            err(
                "boundary.wall_restitution",
                w.to_string(),
                "must be in [0, 1]",
            );
        }
        if let Some((value, expected)) = self.lees_edwards_problem() {
            err("boundary.shear_rate", value, expected);
        }
        let coefficient = |v: f64| v.is_finite() && v >= 0.0;
        if !coefficient(self.friction) {
            err(
                "friction",
                self.friction.to_string(),
                "must be finite and >= 0",
            );
        }
        if let Some(w) = self.wall_friction
            && !coefficient(w)
        {
            err("wall_friction", w.to_string(), "must be finite and >= 0");
        }
        let beta = self.tangential_restitution;
        if !(-1.0..=1.0).contains(&beta) {
            err(
                "tangential_restitution",
                beta.to_string(),
                "must be in [-1, 1]",
            );
        }
        if !coefficient(self.rolling_resistance) {
            err(
                "rolling_resistance",
                self.rolling_resistance.to_string(),
                "must be finite and >= 0",
            );
        }
        let k = self.inertia_factor;
        if !(k > 0.0 && k <= 1.0) {
            err(
                "inertia_factor",
                k.to_string(),
                "must be in (0, 1] (a solid disc is 0.5, a ring 1)",
            );
        }
        if !coefficient(self.contact_duration) {
            err(
                "contact_duration",
                self.contact_duration.to_string(),
                "must be finite and >= 0",
            );
        }
        if !coefficient(self.contact_event_threshold) {
            err(
                "contact_event_threshold",
                self.contact_event_threshold.to_string(),
                "must be finite and >= 0",
            );
        }
        if self.method == Method::EventDriven
            && let Some(what) = self.event_driven_unsupported()
        {
            err("method", "\"event_driven\"".into(), what);
        }
        for (k, obstacle) in self.obstacles.iter().enumerate() {
            if let Some((field, value, expected)) = obstacle.problem() {
                err(
                    "obstacles",
                    format!("obstacle {k}: {field} {value}"),
                    expected,
                );
            }
        }
        for (k, emitter) in self.emitters.iter().enumerate() {
            if let Some((value, expected)) = emitter.problem() {
                err("emitters", format!("emitter {k}: {value}"), expected);
            } else if let Some((min, max)) = self.boundary.bounds()
                && !(emitter.min[0] >= min[0]
                    && emitter.min[1] >= min[1]
                    && emitter.max[0] <= max[0]
                    && emitter.max[1] <= max[1])
            {
                err(
                    "emitters",
                    format!("emitter {k}: min {:?}, max {:?}", emitter.min, emitter.max),
                    "the region must lie inside the box",
                );
            }
        }
        for (k, sink) in self.sinks.iter().enumerate() {
            if let Some((value, expected)) = sink.problem() {
                err("sinks", format!("sink {k}: {value}"), expected);
            }
        }
        for (k, sensor) in self.sensors.iter().enumerate() {
            if let Some((value, expected)) = sensor.region.problem() {
                err("sensors", format!("sensor {k}: {value}"), expected);
            }
            let repeated = self.sensors[..k].iter().any(|s| s.name == sensor.name);
            if sensor.name.is_empty() || repeated {
                err(
                    "sensors",
                    format!("sensor {k}: name {:?}", sensor.name),
                    "each sensor needs a name of its own",
                );
            }
        }
        if let Some((value, expected)) = self.thermostat.as_ref().and_then(|t| t.problem()) {
            err("thermostat", value, expected);
        }
        out
    }

    /// The friction coefficient the walls use.
    ///
    /// ```
    /// use bounce::{Config, Obstacle};
    /// let config = Config { friction: 0.4, wall_friction: Some(0.1), ..Config::default() };
    /// assert_eq!(config.wall_friction(), 0.1);
    /// let (plain, sticky) = (Obstacle::peg([0.0, 0.0], 1.0), Obstacle::peg([5.0, 0.0], 1.0).with_friction(0.9));
    /// assert_eq!((config.obstacle_friction(&plain), config.obstacle_friction(&sticky)), (0.4, 0.9));
    /// assert!(config.is_rough() && !Config::default().is_rough());
    /// ```
    pub fn wall_friction(&self) -> f64 {
        self.wall_friction.unwrap_or(self.friction)
    }

    /// The friction coefficient of obstacle `obstacle` (its own, else the discs'). See
    /// [`Config::wall_friction`] for an example.
    pub fn obstacle_friction(&self, obstacle: &Obstacle) -> f64 {
        obstacle.friction.unwrap_or(self.friction)
    }

    /// Whether the discs are rough: some contact (a pair, a wall of the box, an obstacle)
    /// has friction, or there is rolling resistance. Rough discs carry an angular velocity
    /// and an orientation; smooth ones (the default) have neither, and their
    /// step is the smooth one to the bit. See [`Config::wall_friction`] for an example.
    pub fn is_rough(&self) -> bool {
        let walls = matches!(self.boundary, Boundary::Walls { .. });
        self.friction > 0.0
            || (walls && self.wall_friction() > 0.0)
            || self.rolling_resistance > 0.0
            || self
                .obstacles
                .iter()
                .any(|o| self.obstacle_friction(o) > 0.0)
    }

    /// The restitution the walls use: the walls' own, else the coefficient of restitution.
    ///
    /// ```
    /// use bounce::{Boundary, Config};
    /// let config = Config { coefficient_of_restitution: 0.8, ..Config::default() };
    /// assert_eq!(config.wall_restitution(), 0.8);
    /// let walls = Boundary::Walls { min: [0.0, 0.0], max: [1.0, 1.0], wall_restitution: Some(1.0) };
    /// assert_eq!(Config { boundary: walls, ..config }.wall_restitution(), 1.0);
    /// ```
    pub fn wall_restitution(&self) -> f64 {
        match self.boundary {
            Boundary::Walls {
                wall_restitution: Some(w),
                ..
            } => w,
            _ => self.coefficient_of_restitution,
        }
    }
}
