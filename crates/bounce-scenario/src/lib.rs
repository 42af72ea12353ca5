//! Scenario files: what a bounce run simulates and writes, as TOML.
//!
//! [`load`] parses a file and validates everything it can, collecting *every* problem with
//! its line instead of stopping at the first; [`Scenario::build`] then places the particles
//! and returns a ready [`bounce::World`] and the discs' colours. [`Session`] wraps that into
//! what every front end runs (the CLI, the desktop viewer, the web page): world, colours,
//! time step, view and output plan, the run loop and checkpoints.
//!
//! The format, with every default, is documented in the user guide
//! (`docs/src/reference/scenario.md`) and by `bounce new gas`.

use std::path::Path;

use bounce::law::Law;
use bounce::scene::{self, Gas, Lattice, Speeds};
use bounce::{
    Boundary, Config, MassModel, Particle, RestingContacts, RestitutionModel, VelocityUpdate, World,
};
use serde::Deserialize;
use toml::Spanned;

pub mod analysis;
#[cfg(not(target_arch = "wasm32"))]
pub mod atomic;
pub mod checkpoint;
mod colour;
mod diagnose;
pub mod files;
pub mod observables;
pub mod obstacles;
pub use obstacles::{ObstacleGroup, ObstacleSpec};
#[cfg(not(target_arch = "wasm32"))]
pub mod gsd;
pub mod headline;
pub mod json;
pub mod palette;
mod session;
#[cfg(not(target_arch = "wasm32"))]
pub mod start;
pub mod structure;
pub mod support;
#[cfg(not(target_arch = "wasm32"))]
pub mod trajectory;
pub use colour::{Rgb, parse_colour, ramp, spin_ramp};
pub use session::{OBSTACLE_GREY, Piston, Session, TimeStepReport, note_emitted, view_bounds};
pub mod overrides;

/// The shipped scenarios, by name: `bounce new NAME` writes them out.
pub const TEMPLATES: [(&str, &str); 14] = [
    ("gas", include_str!("../../../scenarios/gas.toml")),
    ("pile", include_str!("../../../scenarios/pile.toml")),
    (
        "newtons-cradle",
        include_str!("../../../scenarios/newtons-cradle.toml"),
    ),
    ("brownian", include_str!("../../../scenarios/brownian.toml")),
    ("mixing", include_str!("../../../scenarios/mixing.toml")),
    ("million", include_str!("../../../scenarios/million.toml")),
    (
        "galton-board",
        include_str!("../../../scenarios/galton-board.toml"),
    ),
    (
        "hourglass",
        include_str!("../../../scenarios/hourglass.toml"),
    ),
    (
        "angle-of-repose",
        include_str!("../../../scenarios/angle-of-repose.toml"),
    ),
    ("piston", include_str!("../../../scenarios/piston.toml")),
    ("effusion", include_str!("../../../scenarios/effusion.toml")),
    (
        "hard-discs",
        include_str!("../../../scenarios/hard-discs.toml"),
    ),
    (
        "driven-granular",
        include_str!("../../../scenarios/driven-granular.toml"),
    ),
    ("shear", include_str!("../../../scenarios/shear.toml")),
];

/// A parsed scenario file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// A title for the run.
    #[serde(default)]
    pub name: Option<String>,
    /// One line on what it shows.
    #[serde(default)]
    pub description: Option<String>,
    /// The world: boundary, the collision model's parameters, model options.
    pub world: WorldSpec,
    /// Time step and run length.
    pub time: TimeSpec,
    /// Random gases.
    #[serde(default)]
    pub gas: Vec<Spanned<GasSpec>>,
    /// Lattices of equal discs.
    #[serde(default)]
    pub lattice: Vec<Spanned<LatticeSpec>>,
    /// Rectangles filled with discs moving together.
    #[serde(default)]
    pub block: Vec<Spanned<BlockSpec>>,
    /// Single discs.
    #[serde(default)]
    pub disc: Vec<Spanned<DiscSpec>>,
    /// Discs from a file: a GSD frame or a CSV table.
    #[serde(default)]
    pub file: Vec<Spanned<FileSpec>>,
    /// The folder `[[file]]` paths are relative to (the scenario file's; `None`: the current
    /// folder).
    #[serde(skip)]
    pub dir: Option<std::path::PathBuf>,
    /// Segments, polylines, boxes and pegs, fixed or moving.
    #[serde(default)]
    pub obstacle: Vec<Spanned<ObstacleSpec>>,
    /// Regions that add discs during the run.
    #[serde(default)]
    pub emitter: Vec<Spanned<EmitterSpec>>,
    /// Regions that remove the discs entering them.
    #[serde(default)]
    pub sink: Vec<Spanned<SinkSpec>>,
    /// Regions that count the discs entering and leaving them.
    #[serde(default)]
    pub sensor: Vec<Spanned<SensorSpec>>,
    /// What to write.
    #[serde(default)]
    pub output: OutputSpec,
}

/// `[world]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSpec {
    /// `walls` (default), `periodic`, `lees_edwards` (a sheared periodic box) or `open`.
    #[serde(default = "default_boundary")]
    pub boundary: BoundaryKind,
    /// The shear rate `γ̇` of a `lees_edwards` box (required there, refused elsewhere).
    #[serde(default)]
    pub shear_rate: Option<f64>,
    /// Lower-left corner of the box (required unless open).
    #[serde(default)]
    pub min: Option<[f64; 2]>,
    /// Upper-right corner of the box (required unless open).
    #[serde(default)]
    pub max: Option<[f64; 2]>,
    /// Wall restitution; defaults to the coefficient of restitution.
    #[serde(default)]
    pub wall_restitution: Option<f64>,
    /// Gravity, default `[0, 0]`.
    #[serde(default)]
    pub gravity: [f64; 2],
    /// Collide when the centres are at most `(r_i + r_j)` times this apart; default 1.
    #[serde(default = "one")]
    pub collision_radius_scale: f64,
    /// The coefficient of restitution, default 1.
    #[serde(default = "one")]
    pub coefficient_of_restitution: f64,
    /// Default `radius` (mass = radius).
    #[serde(default = "default_mass_model")]
    pub mass_model: MassModel,
    /// Default `scale_each_normal_velocity` (restitution on each normal velocity).
    #[serde(default = "default_restitution_model")]
    pub restitution_model: RestitutionModel,
    /// Default `all_detected` (every pair found colliding).
    #[serde(default = "default_velocity_update")]
    pub velocity_update: VelocityUpdate,
    /// Default `bounce`; `rest` makes contacts slower than 4 substeps of
    /// gravity's pull perfectly inelastic.
    #[serde(default = "default_resting_contacts")]
    pub resting_contacts: RestingContacts,
    /// Passes of detection and resolution per substep, default 1 (a single pass).
    #[serde(default = "one_u32")]
    pub solver_iterations: u32,
    /// Coulomb friction of disc–disc contacts, default 0 (smooth discs); with
    /// any friction or rolling resistance the discs are rough and rotate.
    #[serde(default)]
    pub friction: f64,
    /// Friction at the walls; default `friction`.
    #[serde(default)]
    pub wall_friction: Option<f64>,
    /// Walton's tangential restitution in `[-1, 1]`, default 0 (slip removed).
    #[serde(default)]
    pub tangential_restitution: f64,
    /// Rolling resistance, default 0.
    #[serde(default)]
    pub rolling_resistance: f64,
    /// `k` in the moment of inertia `k m r²`, default 0.5 (a solid disc).
    #[serde(default = "half")]
    pub inertia_factor: f64,
    /// A heat bath or drive at the end of every step:
    /// `{ kind = "rescale" | "andersen" | "white_noise", temperature, rate, seed }`;
    /// default none.
    #[serde(default)]
    pub thermostat: Option<bounce::Thermostat>,
}

/// The kind of boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryKind {
    /// Reflecting walls around `[min, max]`.
    Walls,
    /// A periodic box `[min, max)`.
    Periodic,
    /// A periodic box `[min, max)` under simple shear: its images above and below slide at
    /// `±shear_rate` times its height (`bounce::Boundary::LeesEdwards`).
    LeesEdwards,
    /// No boundary.
    Open,
}

/// `[time]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    /// Time step, > 0.
    pub dt: f64,
    /// Steps to run (the CLI's `--steps` overrides it).
    pub steps: u64,
    /// Substeps per step, default 1.
    #[serde(default = "one_u32")]
    pub substeps: u32,
    /// Adaptive substeps: the farthest a disc may move in one substep, as a fraction of the
    /// smallest radius (default: none, fixed substeps).
    #[serde(default)]
    pub max_travel: Option<f64>,
    /// `time_stepped` (default, step by step) or `event_driven` (exact hard discs: `dt`
    /// is then how often the world is observed).
    #[serde(default)]
    pub method: bounce::Method,
    /// The TC model's `t_c` for the event-driven method: a disc's collision within it of
    /// its last one is elastic (default 0, off).
    #[serde(default)]
    pub contact_duration: f64,
}

/// A radius or a range of radii.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(
    untagged,
    expecting = "expected a radius: a number, or a range [min, max]"
)]
pub enum RadiusSpec {
    /// One radius.
    One(f64),
    /// Uniform in `[min, max]`.
    Range([f64; 2]),
}

/// As the file writes it: `0.5`, or `[0.4, 0.6]`.
impl std::fmt::Display for RadiusSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RadiusSpec::One(r) => write!(f, "{r}"),
            RadiusSpec::Range([lo, hi]) => write!(f, "[{lo}, {hi}]"),
        }
    }
}

impl RadiusSpec {
    fn range(self) -> [f64; 2] {
        match self {
            RadiusSpec::One(r) => [r, r],
            RadiusSpec::Range(r) => r,
        }
    }
}

/// A region `{ min = [x, y], max = [x, y] }`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// Lower-left corner.
    pub min: [f64; 2],
    /// Upper-right corner.
    pub max: [f64; 2],
}

/// `[[gas]]`: a random gas. Give exactly one of `speed`, `temperature`, `uniform`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GasSpec {
    /// Number of discs.
    pub count: usize,
    /// Radius or `[min, max]`.
    pub radius: RadiusSpec,
    /// Every disc at this speed in a random direction.
    #[serde(default)]
    pub speed: Option<f64>,
    /// Thermal velocities at this kT.
    #[serde(default)]
    pub temperature: Option<f64>,
    /// Components uniform in `[-a, a]`.
    #[serde(default)]
    pub uniform: Option<f64>,
    /// Common velocity added to all.
    #[serde(default)]
    pub drift: [f64; 2],
    /// Random seed, default 0.
    #[serde(default)]
    pub seed: u64,
    /// Where centres go; default the whole box.
    #[serde(default)]
    pub region: Option<RegionSpec>,
    /// `random` (default: uniform, no overlaps, up to packings near 0.5) or `lattice` (a
    /// triangular lattice filling the region: dense liquids up to packing 0.9 once melted).
    #[serde(default)]
    pub placement: Placement,
    /// Add the Lees–Edwards box's streaming velocity, `shear_rate (y − centre)` along x, to
    /// each disc: the sheared flow from the start (otherwise the sliding images drive it
    /// in, by viscosity, slowly); default false, only with `boundary = "lees_edwards"`.
    #[serde(default)]
    pub streaming: bool,
    /// Remove the net momentum the random velocities leave (then add `drift`); default false.
    #[serde(default)]
    pub zero_momentum: bool,
    /// Angular velocities uniform in `[-spin, spin]`; default 0 (no spin).
    #[serde(default)]
    pub spin: f64,
    /// Colour of these discs (`#rrggbb` or a name).
    #[serde(default)]
    pub color: Option<String>,
    /// The particle type these discs get in the GSD trajectory (`particles/types`);
    /// default: the colour's name, or `A` without one.
    #[serde(default, rename = "type")]
    pub kind: Option<String>,
    /// The discs' tag (`Particle::tag`: the user's own number, carried to every output);
    /// default 0.
    #[serde(default)]
    pub tag: u64,
}

/// How a `[[gas]]` places its discs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Placement {
    /// Uniformly at random without overlaps.
    #[default]
    Random,
    /// On a triangular lattice filling the region.
    Lattice,
}

/// `[[lattice]]`: a grid of equal discs.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    /// Centre of the first disc.
    pub origin: [f64; 2],
    /// Distance between centres along x and y.
    pub spacing: [f64; 2],
    /// Discs along x and y.
    pub counts: [usize; 2],
    /// Radius.
    pub radius: f64,
    /// Common velocity, default 0.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Colour.
    #[serde(default)]
    pub color: Option<String>,
    /// The particle type these discs get in the GSD trajectory (`particles/types`);
    /// default: the colour's name, or `A` without one.
    #[serde(default, rename = "type")]
    pub kind: Option<String>,
    /// The discs' tag (`Particle::tag`: the user's own number, carried to every output);
    /// default 0.
    #[serde(default)]
    pub tag: u64,
}

/// `[[block]]`: a rectangle filled with touching-free discs moving together.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlockSpec {
    /// Lower-left corner of the rectangle.
    pub min: [f64; 2],
    /// Upper-right corner.
    pub max: [f64; 2],
    /// Radius of every disc.
    pub radius: f64,
    /// Centre spacing; default just over the collision distance of two of these discs.
    #[serde(default)]
    pub spacing: Option<f64>,
    /// Common velocity.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Colour.
    #[serde(default)]
    pub color: Option<String>,
    /// The particle type these discs get in the GSD trajectory (`particles/types`);
    /// default: the colour's name, or `A` without one.
    #[serde(default, rename = "type")]
    pub kind: Option<String>,
    /// The discs' tag (`Particle::tag`: the user's own number, carried to every output);
    /// default 0.
    #[serde(default)]
    pub tag: u64,
}

/// `[[disc]]`: one disc.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiscSpec {
    /// Centre.
    pub position: [f64; 2],
    /// Velocity, default 0.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Radius.
    pub radius: f64,
    /// Mass (used with `mass_model = "per_particle"`).
    #[serde(default)]
    pub mass: Option<f64>,
    /// Angular velocity (counter-clockwise, radians per time unit), default 0.
    #[serde(default)]
    pub angular_velocity: f64,
    /// Colour.
    #[serde(default)]
    pub color: Option<String>,
    /// The particle type these discs get in the GSD trajectory (`particles/types`);
    /// default: the colour's name, or `A` without one.
    #[serde(default, rename = "type")]
    pub kind: Option<String>,
    /// The discs' tag (`Particle::tag`: the user's own number, carried to every output);
    /// default 0.
    #[serde(default)]
    pub tag: u64,
}

/// Discs read from a file ([`start`]), in file order, with their types.
#[derive(Clone, Debug, Default)]
pub struct FileDiscs {
    /// The discs (a `mass` only where the file gives one).
    pub discs: Vec<Particle>,
    /// Each disc's index into `types`.
    pub typeid: Vec<u32>,
    /// The type names the file uses.
    pub types: Vec<String>,
}

/// `[[file]]`: the discs of a file, as [`start`] reads them: a frame of a GSD trajectory
/// (positions, velocities, diameters, masses, types; the box must have the world's size) or
/// a CSV table with the columns `x, y, radius` and optionally `vx, vy, mass, type`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileSpec {
    /// The file, relative to the scenario file's folder; `.csv` is a table, anything else a
    /// GSD trajectory.
    pub path: String,
    /// The GSD frame (negative counts from the end); default -1, the last.
    #[serde(default = "last_frame")]
    pub frame: i64,
    /// Colour of these discs.
    #[serde(default)]
    pub color: Option<String>,
    /// One particle type for every disc; default the file's own types (GSD
    /// `particles/types`, a CSV `type` column), else `A`.
    #[serde(default, rename = "type")]
    pub kind: Option<String>,
}

fn last_frame() -> i64 {
    -1
}

/// `[[emitter]]`: discs added during the run in a region, at a rate.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmitterSpec {
    /// Where the new discs' centres go.
    pub region: RegionSpec,
    /// Discs per unit time.
    pub rate: f64,
    /// Radius or `[min, max]`.
    pub radius: RadiusSpec,
    /// Mean velocity, default 0.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Each velocity component gets a uniform part in `[-spread, spread]`; default 0.
    #[serde(default)]
    pub spread: f64,
    /// Random seed, default 0.
    #[serde(default)]
    pub seed: u64,
    /// Stop after this many discs; default never.
    #[serde(default)]
    pub limit: Option<u64>,
    /// Colour of these discs.
    #[serde(default)]
    pub color: Option<String>,
    /// Their particle type in the GSD trajectory (default: the colour's name, or `A`).
    #[serde(default, rename = "type")]
    pub kind: Option<String>,
}

/// `[[sink]]`: discs whose centre enters the region are removed at the end of a step.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SinkSpec {
    /// The region.
    pub region: RegionSpec,
}

/// `[[sensor]]`: counts the discs whose centre enters and leaves `region` (`stats.csv`'s
/// `sensor_NAME_in`, `sensor_NAME_out`, `sensor_NAME_count`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// Its name, unique among the sensors (letters, digits, `_` and `-`).
    pub name: String,
    /// A box `{ min, max }` or a circle `{ centre, radius }`.
    #[serde(deserialize_with = "sensor_region")]
    pub region: bounce::Region,
}

/// A sensor region's keys as written, before they are known to make a box or a circle.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RegionFields {
    min: Option<[f64; 2]>,
    max: Option<[f64; 2]>,
    centre: Option<[f64; 2]>,
    radius: Option<f64>,
}

/// A sensor's region from its keys: a box or a circle, nothing in between.
fn sensor_region<'de, D: serde::Deserializer<'de>>(d: D) -> Result<bounce::Region, D::Error> {
    let r = RegionFields::deserialize(d)?;
    match (r.min, r.max, r.centre, r.radius) {
        (Some(min), Some(max), None, None) => Ok(bounce::Region::Box { min, max }),
        (None, None, Some(centre), Some(radius)) => Ok(bounce::Region::Circle { centre, radius }),
        _ => Err(serde::de::Error::custom(
            "a sensor's region is a box { min = [x, y], max = [x, y] } or a circle \
             { centre = [x, y], radius = r }",
        )),
    }
}

/// How frames colour the discs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ColorBy {
    /// By speed, slow blue to fast yellow.
    Speed,
    /// By radius.
    Radius,
    /// The colours the scenario sets (grey where none).
    Color,
    /// By angular velocity: clockwise blue, still grey, counter-clockwise red.
    Spin,
}

/// `[output]`: all intervals are in steps; 0 turns an output off.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSpec {
    /// A `stats.csv` row every this many steps (default 10).
    pub stats_every: u64,
    /// A PNG frame every this many steps (default 0: none).
    pub frame_every: u64,
    /// Frame width in pixels (height follows the box's aspect); default 800.
    pub frame_width: u32,
    /// Also write `animation.gif` from the frames; default false.
    pub gif: bool,
    /// A GSD trajectory frame every this many steps (default 0: none).
    pub gsd_every: u64,
    /// A checkpoint every this many steps besides the one at the end (default 0).
    pub checkpoint_every: u64,
    /// Frame colouring; default `color` when the scenario sets colours, else `speed`.
    pub color_by: Option<ColorBy>,
    /// Write `plots.png` at the end; default true.
    pub plots: bool,
    /// The region frames show; default the box (or, in an open world, the particles' extent
    /// at the start).
    pub view: Option<RegionSpec>,
    /// Record contact events and write every step's to `events.csv`; default false.
    pub events: bool,
    /// The smallest normal impulse a contact's `begin` (and so its `end`) is written with;
    /// default 0, every contact.
    pub events_threshold: f64,
    /// Profiles binned along an axis, written to `profile.csv` at every `stats.csv` row:
    /// `{ axis = "x" | "y", bins = N }`; default none.
    pub profile: Option<ProfileSpec>,
    /// The mean-square displacement and the velocity autocorrelation from the run's start,
    /// written to `msd.csv` at every `stats.csv` row; default false.
    pub msd: bool,
    /// The pressure tensor in `stats.csv` (`pressure_xx`, `pressure_yy`, `pressure_xy`);
    /// default false.
    pub pressure_tensor: bool,
    /// Count each disc's collisions with other discs: `collisions.csv` at the run's end
    /// (`id,radius,collisions`) and `log/particles/bounce/collisions` in each GSD frame;
    /// default false.
    pub collision_counts: bool,
    /// The energy dissipated since the previous row in `stats.csv` (`dissipated`); default
    /// false. Not with emitters or sinks, whose discs bring and take energy.
    pub dissipation: bool,
    /// What the run demonstrates, measured at its end into the summary, `summary.json` and
    /// `plots.png` ([`headline::HeadlineKind`]); default none.
    pub headline: Option<headline::HeadlineKind>,
}

/// `[output] profile`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileSpec {
    /// The axis the bins cut.
    pub axis: observables::Axis,
    /// How many bins across the box (at least 1).
    pub bins: usize,
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            stats_every: 10,
            frame_every: 0,
            frame_width: 800,
            gif: false,
            gsd_every: 0,
            checkpoint_every: 0,
            color_by: None,
            plots: true,
            view: None,
            events: false,
            events_threshold: 0.0,
            profile: None,
            msd: false,
            pressure_tensor: false,
            collision_counts: false,
            dissipation: false,
            headline: None,
        }
    }
}

fn default_boundary() -> BoundaryKind {
    BoundaryKind::Walls
}
fn one() -> f64 {
    1.0
}
fn half() -> f64 {
    0.5
}
fn one_u32() -> u32 {
    1
}
fn default_mass_model() -> MassModel {
    MassModel::Radius
}
fn default_restitution_model() -> RestitutionModel {
    RestitutionModel::ScaleEachNormalVelocity
}
fn default_velocity_update() -> VelocityUpdate {
    VelocityUpdate::AllDetected
}
fn default_resting_contacts() -> RestingContacts {
    RestingContacts::Bounce
}

/// One problem in a scenario file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// What is wrong, naming the field and value.
    pub message: String,
}

/// Every problem found in one file.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.render())]
pub struct ScenarioError {
    /// The file, as given.
    pub file: String,
    /// The problems, in file order.
    pub problems: Vec<Problem>,
}

impl ScenarioError {
    fn render(&self) -> String {
        let mut out = String::new();
        for (k, p) in self.problems.iter().enumerate() {
            if k > 0 {
                out.push('\n');
            }
            match p.line {
                Some(line) => out.push_str(&format!("{}:{}: {}", self.file, line, p.message)),
                None => out.push_str(&format!("{}: {}", self.file, p.message)),
            }
        }
        out
    }
}

/// Memory a run needs per disc, with room to spare: the hot arrays and the candidate lists
/// (about 95 bytes per disc measured at 10^6), the generator's and the outputs' copies.
pub const BYTES_PER_PARTICLE: u64 = 256;

/// Memory a run needs per obstacle, with room to spare: the configuration's and the step's
/// copies, the grid's lists and the scenario's groups (about 445 bytes per peg measured for a
/// run of 10^6 pegs).
pub const BYTES_PER_OBSTACLE: u64 = 512;

/// What a scenario needs, estimated before it is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Estimate {
    /// Discs.
    pub particles: u64,
    /// Obstacles (each segment of a polyline or box, each peg of a lattice).
    pub obstacles: u64,
    /// Bytes of memory, about.
    pub bytes: u64,
}

/// The resources a scenario may use; a larger one is refused before anything is allocated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Bytes of memory. Default: half the machine's memory (4 GiB where it cannot be read).
    pub memory_bytes: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            memory_bytes: machine_memory().map_or(4 << 30, |m| m / 2),
        }
    }
}

impl Limits {
    /// A limit of `gib` GiB of memory.
    pub fn memory_gib(gib: f64) -> Limits {
        Limits {
            memory_bytes: (gib * (1u64 << 30) as f64) as u64,
        }
    }

    /// Refuses an estimate over the limit, saying both.
    pub fn check(&self, estimate: &Estimate) -> Result<(), String> {
        if estimate.bytes > self.memory_bytes {
            return Err(format!(
                "{} particles and {} obstacles need about {:.1} GiB, over the limit of {:.1} \
                 GiB (half the machine's memory by default; raise it with --memory-limit GIB)",
                estimate.particles,
                estimate.obstacles,
                estimate.bytes as f64 / (1u64 << 30) as f64,
                self.memory_bytes as f64 / (1u64 << 30) as f64
            ));
        }
        Ok(())
    }
}

/// The machine's memory in bytes, from `/proc/meminfo` (Linux).
fn machine_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// A scenario turned into a world.
pub struct Built {
    /// The world, particles added.
    pub world: World,
    /// Colour of each particle, indexed by id; `None` where the scenario sets none.
    pub colours: Vec<Option<Rgb>>,
    /// The particle types, in order of first appearance.
    pub types: Vec<String>,
    /// Each particle's index into `types`, by id.
    pub typeid: Vec<u32>,
    /// Each emitter's colour and index into `types`, for the discs it adds.
    pub emitted: Vec<(Option<Rgb>, u32)>,
}

/// Reads and validates a scenario file.
pub fn load(path: &Path) -> Result<Scenario, ScenarioError> {
    let file = path.display().to_string();
    let source = files::read_to_string(path).map_err(|e| ScenarioError {
        file: file.clone(),
        problems: vec![Problem {
            line: None,
            message: format!("cannot read the file: {e}"),
        }],
    })?;
    parse(&source, &file)
}

/// Parses and validates scenario text; `file` names it in messages. Every problem reading
/// can find is listed, in line order: type errors past the first, and the semantic problems
/// of the rest (the placement of the discs adds its own: [`Session::from_text_in`]).
pub fn parse(source: &str, file: &str) -> Result<Scenario, ScenarioError> {
    let examined = diagnose::examine(source);
    match examined.scenario {
        Some(scenario) if examined.problems.is_empty() => Ok(scenario),
        _ => Err(ScenarioError {
            file: file.to_string(),
            problems: examined.problems,
        }),
    }
}

/// Reads scenario text and places its discs, listing every problem of both: where the reading
/// found problems, the tables they are on are left out of the placement, so that the other
/// tables' problems (a disc outside the box, overlapping tables) are listed beside them.
pub(crate) fn read_and_build(
    source: &str,
    file: &str,
    limits: &Limits,
    dir: Option<&Path>,
) -> Result<(Scenario, Built), ScenarioError> {
    let examined = diagnose::examine(source);
    let fail = |problems| ScenarioError {
        file: file.to_string(),
        problems,
    };
    let Some(mut scenario) = examined.scenario else {
        return Err(fail(examined.problems));
    };
    scenario.dir = dir.map(Path::to_path_buf);
    if examined.problems.is_empty() {
        let built = scenario.build_with(source, file, limits)?;
        return Ok((scenario, built));
    }
    let skip: Vec<usize> = examined.problems.iter().filter_map(|p| p.line).collect();
    let mut problems = examined.problems;
    if let Err(e) = scenario.build_skipping(source, file, limits, Some(&skip)) {
        problems.extend(e.problems);
        diagnose::sort(&mut problems);
    }
    Err(fail(problems))
}

/// The 1-based line of byte offset `at`.
fn line_at(source: &str, at: usize) -> usize {
    source[..at.min(source.len())].matches('\n').count() + 1
}

/// Where each line of a source starts, for the lines of many offsets: [`line_at`] counts the
/// newlines before each one, which for a table per disc made a file of `N` discs take
/// `O(N²)`.
struct LineIndex(Vec<usize>);

impl LineIndex {
    fn new(source: &str) -> LineIndex {
        LineIndex(
            source
                .bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(k, _)| k)
                .collect(),
        )
    }

    /// The 1-based line of byte offset `at`, as [`line_at`] gives it.
    fn at(&self, at: usize) -> usize {
        self.0.partition_point(|&newline| newline < at) + 1
    }
}

/// `table.key` for a `key = value` line (1-based), for messages that only know the line.
fn field_at(source: &str, line: usize) -> Option<String> {
    let mut table = String::new();
    for (n, text) in source.lines().enumerate() {
        let t = text.trim();
        if t.starts_with('[') {
            table = t.trim_matches(|c| c == '[' || c == ']').trim().to_string();
        }
        if n + 1 == line {
            let key = t.split('=').next()?.trim();
            if key.is_empty() || key.starts_with('[') || !t.contains('=') {
                return None;
            }
            return Some(if table.is_empty() {
                key.to_string()
            } else {
                format!("{table}.{key}")
            });
        }
    }
    None
}

/// The line of `key = ...` inside `[table]`, for messages about plain fields.
fn line_of_key(source: &str, table: &str, key: &str) -> Option<usize> {
    let mut current = String::new();
    for (n, line) in source.lines().enumerate() {
        let t = line.trim();
        if t.starts_with('[') {
            current = t.trim_matches(|c| c == '[' || c == ']').trim().to_string();
        } else if current == table
            && t.strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        {
            return Some(n + 1);
        }
    }
    None
}

/// Gives every disc of a table the table's tag.
fn tag(discs: &mut [Particle], tag: u64) {
    for disc in discs {
        disc.tag = tag;
    }
}

impl Scenario {
    /// The world configuration the scenario describes (not yet validated).
    pub fn config(&self) -> Config {
        let w = &self.world;
        let (min, max) = (w.min.unwrap_or([0.0, 0.0]), w.max.unwrap_or([0.0, 0.0]));
        Config {
            collision_radius_scale: w.collision_radius_scale,
            coefficient_of_restitution: w.coefficient_of_restitution,
            gravity: w.gravity,
            substeps: self.time.substeps,
            solver_iterations: w.solver_iterations,
            max_travel: self.time.max_travel,
            method: self.time.method,
            contact_duration: self.time.contact_duration,
            contact_events: self.output.events,
            contact_event_threshold: self.output.events_threshold,
            pressure_tensor: self.output.pressure_tensor,
            collision_counts: self.output.collision_counts,
            boundary: match w.boundary {
                BoundaryKind::Walls => Boundary::Walls {
                    min,
                    max,
                    wall_restitution: w.wall_restitution,
                },
                BoundaryKind::Periodic => Boundary::Periodic { min, max },
                BoundaryKind::LeesEdwards => Boundary::LeesEdwards {
                    min,
                    max,
                    shear_rate: w.shear_rate.unwrap_or(0.0),
                },
                BoundaryKind::Open => Boundary::Open,
            },
            mass_model: w.mass_model,
            restitution_model: w.restitution_model,
            velocity_update: w.velocity_update,
            resting_contacts: w.resting_contacts,
            friction: w.friction,
            wall_friction: w.wall_friction,
            tangential_restitution: w.tangential_restitution,
            rolling_resistance: w.rolling_resistance,
            inertia_factor: w.inertia_factor,
            thermostat: w.thermostat,
            obstacles: self
                .obstacle
                .iter()
                .flat_map(|o| o.get_ref().expand())
                .collect(),
            emitters: self
                .emitter
                .iter()
                .map(|e| {
                    let e = e.get_ref();
                    bounce::Emitter {
                        min: e.region.min,
                        max: e.region.max,
                        rate: e.rate,
                        radius: e.radius.range(),
                        velocity: e.velocity,
                        spread: e.spread,
                        seed: e.seed,
                        limit: e.limit,
                    }
                })
                .collect(),
            sinks: self
                .sink
                .iter()
                .map(|s| bounce::Sink {
                    min: s.get_ref().region.min,
                    max: s.get_ref().region.max,
                })
                .collect(),
            sensors: self
                .sensor
                .iter()
                .map(|s| bounce::Sensor::new(s.get_ref().name.clone(), s.get_ref().region))
                .collect(),
        }
    }

    /// The `[[obstacle]]` tables' groups: names, colours and where their pieces are in
    /// `Config::obstacles`.
    pub fn obstacle_groups(&self) -> Vec<ObstacleGroup> {
        let specs: Vec<ObstacleSpec> = self.obstacle.iter().map(|o| o.get_ref().clone()).collect();
        obstacles::groups(&specs)
    }

    /// Total particles the scenario asks for; `None` when the count overflows 64 bits.
    pub fn particle_count(&self) -> Option<u64> {
        let law = Law::new(&self.config());
        let product = |[x, y]: [usize; 2]| (x as u64).checked_mul(y as u64);
        let mut total = self.disc.len() as u64;
        for f in &self.file {
            // A file that cannot be read counts nothing here; building it says why.
            total = total.checked_add(self.file_count(f.get_ref()).unwrap_or(0))?;
        }
        for n in self
            .gas
            .iter()
            .map(|g| Some(g.get_ref().count as u64))
            .chain(self.lattice.iter().map(|l| product(l.get_ref().counts)))
            .chain(
                self.block
                    .iter()
                    .map(|b| product(block_counts(b.get_ref(), &law))),
            )
        {
            total = total.checked_add(n?)?;
        }
        Some(total)
    }

    /// Where a `[[file]]` table's file is.
    pub fn file_path(&self, spec: &FileSpec) -> std::path::PathBuf {
        match &self.dir {
            Some(dir) => dir.join(&spec.path),
            None => std::path::PathBuf::from(&spec.path),
        }
    }

    /// The discs of a `[[file]]` table, placed in the world's box.
    #[cfg(not(target_arch = "wasm32"))]
    fn read_file(&self, spec: &FileSpec, config: &bounce::Config) -> Result<FileDiscs, String> {
        start::read_for(&self.file_path(spec), spec.frame, &config.boundary)
    }

    #[cfg(target_arch = "wasm32")]
    fn read_file(&self, spec: &FileSpec, _: &bounce::Config) -> Result<FileDiscs, String> {
        Err(format!(
            "{}: the web page cannot read files; paste the discs as [[disc]] tables",
            spec.path
        ))
    }

    #[cfg(not(target_arch = "wasm32"))]
    fn file_count(&self, spec: &FileSpec) -> Option<u64> {
        start::count(&self.file_path(spec), spec.frame)
    }

    #[cfg(target_arch = "wasm32")]
    fn file_count(&self, _: &FileSpec) -> Option<u64> {
        None
    }

    /// What running the scenario needs, estimated before placing a disc.
    pub fn estimate(&self) -> Option<Estimate> {
        let particles = self.particle_count()?;
        let obstacles = self
            .obstacle
            .iter()
            .map(|o| o.get_ref().count())
            .fold(0u64, u64::saturating_add);
        Some(Estimate {
            particles,
            obstacles,
            bytes: particles
                .saturating_mul(BYTES_PER_PARTICLE)
                .saturating_add(obstacles.saturating_mul(BYTES_PER_OBSTACLE)),
        })
    }

    /// Whether any generator sets a colour.
    pub fn has_colours(&self) -> bool {
        self.gas.iter().any(|g| g.get_ref().color.is_some())
            || self.lattice.iter().any(|g| g.get_ref().color.is_some())
            || self.block.iter().any(|g| g.get_ref().color.is_some())
            || self.disc.iter().any(|g| g.get_ref().color.is_some())
            || self.file.iter().any(|g| g.get_ref().color.is_some())
    }

    /// For a config problem of an obstacle, emitter or sink (`WHAT K: ...`, K its index in
    /// the config's list): the table's index, its kind and its line.
    fn table_of(
        &self,
        e: &bounce::ConfigError,
        source: &str,
    ) -> Option<(usize, &'static str, Option<usize>)> {
        let k: usize = e
            .value
            .split_once(": ")?
            .0
            .split(' ')
            .nth(1)?
            .parse()
            .ok()?;
        let (table, what, span) = match e.field {
            "obstacles" => {
                let groups = self.obstacle_groups();
                let t = groups.iter().position(|g| g.range.contains(&k))?;
                (t, "obstacle", self.obstacle[t].span())
            }
            "emitters" => (k, "emitter", self.emitter.get(k)?.span()),
            "sinks" => (k, "sink", self.sink.get(k)?.span()),
            "sensors" => (k, "sensor", self.sensor.get(k)?.span()),
            _ => return None,
        };
        Some((table, what, Some(line_at(source, span.start))))
    }

    /// Every problem that can be found without placing particles.
    fn problems(&self, source: &str) -> Vec<Problem> {
        let lines = LineIndex::new(source);
        let mut out = Vec::new();
        let mut at = |line: Option<usize>, message: String| out.push(Problem { line, message });

        let w = &self.world;
        if w.boundary != BoundaryKind::Open {
            for (key, v) in [("min", w.min), ("max", w.max)] {
                if v.is_none() {
                    at(
                        line_of_key(source, "world", "boundary"),
                        format!("world.{key} is required with boundary = {:?}", w.boundary),
                    );
                }
            }
        }
        let sheared = w.boundary == BoundaryKind::LeesEdwards;
        if sheared && w.shear_rate.is_none() {
            at(
                line_of_key(source, "world", "boundary"),
                "world.shear_rate is required with boundary = \"lees_edwards\"".into(),
            );
        }
        if !sheared && let Some(rate) = w.shear_rate {
            at(
                line_of_key(source, "world", "shear_rate"),
                format!(
                    "world.shear_rate = {rate}: only with boundary = \"lees_edwards\" (this is \
                     {:?})",
                    w.boundary
                ),
            );
        }
        if sheared && self.output.dissipation {
            at(
                line_of_key(source, "output", "dissipation"),
                "output.dissipation: not in a Lees–Edwards box yet (its sliding images do work \
                 on the discs that the balance does not count)"
                    .into(),
            );
        }
        if sheared && self.output.msd {
            at(
                line_of_key(source, "output", "msd"),
                "output.msd: not in a Lees–Edwards box yet (its images slide, so image counts \
                 do not unwrap the positions)"
                    .into(),
            );
        }
        for (k, g) in self.gas.iter().enumerate() {
            if g.get_ref().streaming && !sheared {
                at(
                    Some(lines.at(g.span().start)),
                    format!(
                        "gas #{}: streaming = true needs boundary = \"lees_edwards\" (the flow \
                         it adds is the sheared box's)",
                        k + 1
                    ),
                );
            }
        }
        for (k, o) in self.obstacle.iter().enumerate() {
            let line = Some(lines.at(o.span().start));
            for message in o.get_ref().problems() {
                at(line, format!("obstacle #{}: {message}", k + 1));
            }
        }
        for (k, sensor) in self.sensor.iter().enumerate() {
            let name = &sensor.get_ref().name;
            let plain = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
            if name.is_empty() || !name.chars().all(plain) {
                at(
                    Some(lines.at(sensor.span().start)),
                    format!(
                        "sensor #{}: name {name:?} must be letters, digits, `_` or `-` (it names \
                         stats.csv columns)",
                        k + 1
                    ),
                );
            }
        }
        for (k, e) in self.emitter.iter().enumerate() {
            let line = Some(lines.at(e.span().start));
            colour_problem(
                &e.get_ref().color,
                line,
                &format!("emitter #{}", k + 1),
                &mut at,
            );
        }
        for e in self.config().problems() {
            if let Some((table, what, line)) = self.table_of(&e, source) {
                // `WHAT K: VALUE`, K the index in the config's list: name the table.
                let value = e.value.split_once(": ").map_or(&*e.value, |(_, v)| v);
                at(
                    line,
                    format!("{what} #{}: {value}: {}", table + 1, e.expected),
                );
                continue;
            }
            if e.field == "contact_event_threshold" {
                at(
                    line_of_key(source, "output", "events_threshold"),
                    format!("output.events_threshold = {}: {}", e.value, e.expected),
                );
                continue;
            }
            let key = e.field.split('.').next_back().unwrap_or(e.field);
            let key = if key == "boundary" { "max" } else { key };
            let line = line_of_key(source, "world", key)
                .or_else(|| line_of_key(source, "time", key))
                .or_else(|| line_of_key(source, "world", "boundary"));
            at(
                line,
                format!("world.{} = {}: {}", e.field, e.value, e.expected),
            );
        }
        if self.output.dissipation && !(self.emitter.is_empty() && self.sink.is_empty()) {
            at(
                line_of_key(source, "output", "dissipation"),
                "output.dissipation: not with [[emitter]] or [[sink]] tables, whose discs bring \
                 and take energy"
                    .into(),
            );
        }
        if let Some(profile) = self.output.profile {
            if w.boundary == BoundaryKind::Open {
                at(
                    line_of_key(source, "output", "profile"),
                    "output.profile: a profile needs a box (walls or periodic), not an open \
                     world"
                        .into(),
                );
            } else if !(1..=observables::MAX_PROFILE_BINS).contains(&profile.bins) {
                at(
                    line_of_key(source, "output", "profile"),
                    format!(
                        "output.profile.bins = {}: must be in 1..={}",
                        profile.bins,
                        observables::MAX_PROFILE_BINS
                    ),
                );
            }
        }
        if !(self.time.dt.is_finite() && self.time.dt > 0.0) {
            at(
                line_of_key(source, "time", "dt"),
                format!("time.dt = {} must be finite and > 0", self.time.dt),
            );
        } else if !(self.time.dt * self.time.steps as f64 * 2.0).is_finite() {
            // (Twice: room for the clock's rounding and a run continued as long again.)
            at(
                line_of_key(source, "time", "dt"),
                format!(
                    "time.dt = {:?} for {} steps overflows the clock (the run's time must be \
                     finite)",
                    self.time.dt, self.time.steps
                ),
            );
        }
        for (k, g) in self.gas.iter().enumerate() {
            let line = Some(lines.at(g.span().start));
            let gas = g.get_ref();
            let set = [gas.speed, gas.temperature, gas.uniform]
                .iter()
                .filter(|v| v.is_some())
                .count();
            if set != 1 {
                at(
                    line,
                    format!(
                        "gas #{}: give exactly one of speed, temperature, uniform ({set} given)",
                        k + 1
                    ),
                );
            }
            let [lo, hi] = gas.radius.range();
            if !(lo.is_finite() && lo > 0.0 && hi.is_finite() && hi >= lo) {
                at(
                    line,
                    format!(
                        "gas #{}: radius = {}: must be finite, > 0, with min <= max",
                        k + 1,
                        gas.radius
                    ),
                );
            }
            colour_problem(&gas.color, line, &format!("gas #{}", k + 1), &mut at);
        }
        for (k, l) in self.lattice.iter().enumerate() {
            let line = Some(lines.at(l.span().start));
            let lat = l.get_ref();
            if !(lat.radius.is_finite() && lat.radius > 0.0) {
                at(
                    line,
                    format!(
                        "lattice #{}: radius {} must be finite and > 0",
                        k + 1,
                        lat.radius
                    ),
                );
            }
            colour_problem(&lat.color, line, &format!("lattice #{}", k + 1), &mut at);
        }
        for (k, b) in self.block.iter().enumerate() {
            let line = Some(lines.at(b.span().start));
            let block = b.get_ref();
            if !(block.radius.is_finite() && block.radius > 0.0) {
                at(
                    line,
                    format!(
                        "block #{}: radius {} must be finite and > 0",
                        k + 1,
                        block.radius
                    ),
                );
            } else if block_counts(block, &Law::new(&self.config())).contains(&0) {
                at(
                    line,
                    format!(
                        "block #{}: {:?}..{:?} holds no disc of radius {}",
                        k + 1,
                        block.min,
                        block.max,
                        block.radius
                    ),
                );
            }
            colour_problem(&block.color, line, &format!("block #{}", k + 1), &mut at);
        }
        for (k, d) in self.disc.iter().enumerate() {
            let line = Some(lines.at(d.span().start));
            colour_problem(
                &d.get_ref().color,
                line,
                &format!("disc #{}", k + 1),
                &mut at,
            );
        }
        let count = self.particle_count();
        if count.is_none() {
            at(
                None,
                "the scenario asks for more particles than 2^64 (a count overflows)".into(),
            );
        } else if count == Some(0) && self.emitter.is_empty() && self.file.is_empty() {
            at(
                None,
                "the scenario has no particles: add [[gas]], [[lattice]], [[block]], [[disc]], [[file]] \
                 or [[emitter]]"
                    .into(),
            );
        }
        let o = &self.output;
        if o.frame_width < 16 || o.frame_width > 8192 {
            at(
                line_of_key(source, "output", "frame_width"),
                format!(
                    "output.frame_width = {} must be in 16..=8192",
                    o.frame_width
                ),
            );
        }
        if o.gif && o.frame_every == 0 {
            at(
                line_of_key(source, "output", "gif"),
                "output.gif needs output.frame_every > 0".into(),
            );
        }
        out.sort_by_key(|p| p.line.unwrap_or(usize::MAX));
        out
    }

    /// Places the particles and returns the world, within the default [`Limits`]. `file` and
    /// `source` name problems.
    pub fn build(&self, source: &str, file: &str) -> Result<Built, ScenarioError> {
        self.build_with(source, file, &Limits::default())
    }

    /// Places the particles and returns the world; refuses up front, with the estimate, a
    /// scenario that needs more than `limits` allow.
    pub fn build_with(
        &self,
        source: &str,
        file: &str,
        limits: &Limits,
    ) -> Result<Built, ScenarioError> {
        self.build_skipping(source, file, limits, None)
    }

    /// [`Scenario::build_with`], listing every problem of the placement rather than the
    /// first: each table a generator cannot place, each invalid disc (the first few of a
    /// table), each pair of overlapping tables. With `skip` (the lines of problems a reading
    /// already reported) the particle tables starting on those lines are left out, and a
    /// configuration the world refuses (reported too) is replaced by its sound part, so the
    /// other tables are still checked.
    fn build_skipping(
        &self,
        source: &str,
        file: &str,
        limits: &Limits,
        skip: Option<&[usize]>,
    ) -> Result<Built, ScenarioError> {
        let checking = skip.is_some();
        let skip = skip.unwrap_or_default();
        let fail = |line: Option<usize>, message: String| ScenarioError {
            file: file.to_string(),
            problems: vec![Problem { line, message }],
        };
        let mut problems: Vec<Problem> = Vec::new();
        let lines = LineIndex::new(source);
        let estimate = self
            .estimate()
            .ok_or_else(|| fail(None, "the particle count overflows".into()))?;
        limits.check(&estimate).map_err(|m| fail(None, m))?;
        let mut world = match World::new(self.config()) {
            Ok(world) => world,
            Err(_) if checking => {
                World::new(placement_config(&self.config())).map_err(|_| ScenarioError {
                    file: file.to_string(),
                    problems: Vec::new(),
                })?
            }
            Err(e) => return Err(fail(None, e.to_string())),
        };
        let config = world.config().clone();
        let mut colours = Vec::new();
        // Every disc so far, so later generators keep clear of earlier tables' discs.
        let mut placed: Vec<Particle> = Vec::new();
        // Which table made which ids: (first id, what, line).
        let mut tables: Vec<(usize, String, usize)> = Vec::new();
        let mut types: Vec<String> = Vec::new();
        let mut typeid: Vec<u32> = Vec::new();
        // `own_types`: a file's own type for each disc (names and each disc's index).
        let mut add = |discs: Vec<Particle>,
                       (colour, kind): (&Option<String>, &Option<String>),
                       line: usize,
                       what: String,
                       placed: &mut Vec<Particle>,
                       own_types: Option<(&[String], &[u32])>| {
            let rgb = colour
                .as_deref()
                .map(|c| parse_colour(c).expect("checked in problems"));
            let n = discs.len();
            let mut type_of = |name: String| match types.iter().position(|t| *t == name) {
                Some(t) => t as u32,
                None => {
                    types.push(name);
                    types.len() as u32 - 1
                }
            };
            match (own_types, kind) {
                (Some((names, ids)), None) => {
                    let map: Vec<u32> = names.iter().map(|n| type_of(n.clone())).collect();
                    typeid.extend(ids.iter().map(|&t| map[t as usize]));
                }
                _ => {
                    let name = kind
                        .clone()
                        .or_else(|| colour.clone())
                        .unwrap_or_else(|| "A".into());
                    let t = type_of(name);
                    typeid.extend(std::iter::repeat_n(t, n));
                }
            }
            tables.push((placed.len(), what, line));
            placed.extend_from_slice(&discs);
            colours.extend(std::iter::repeat_n(rgb, n));
            Ok::<(), ScenarioError>(())
        };
        // Particles get their ids in the order their tables appear in the file.
        let mut entries: Vec<(usize, Entry)> = Vec::new();
        entries.extend(
            self.gas
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::Gas(k))),
        );
        entries.extend(
            self.lattice
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::Lattice(k))),
        );
        entries.extend(
            self.block
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::Block(k))),
        );
        entries.extend(
            self.disc
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::Disc(k))),
        );
        entries.extend(
            self.file
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::File(k))),
        );
        entries.sort_by_key(|&(start, _)| start);
        let mut left_out = false;
        for (start, entry) in entries {
            let line = lines.at(start);
            if skip.contains(&line) {
                left_out = true;
                continue;
            }
            match entry {
                Entry::Gas(k) => {
                    let spec = self.gas[k].get_ref();
                    let speeds = match (spec.speed, spec.temperature, spec.uniform) {
                        (Some(v), _, _) => Speeds::Fixed(v),
                        (_, Some(t), _) => Speeds::Temperature(t),
                        (_, _, Some(a)) => Speeds::Uniform(a),
                        _ => Speeds::Fixed(0.0),
                    };
                    let gas = Gas {
                        count: spec.count,
                        radius: spec.radius.range(),
                        region: spec.region.map(|r| (r.min, r.max)),
                        speeds,
                        drift: spec.drift,
                        seed: spec.seed,
                    };
                    let placement = match spec.placement {
                        Placement::Random => scene::gas_among(&gas, &config, &placed),
                        Placement::Lattice => scene::packed_gas(&gas, &config, &placed),
                    };
                    let mut discs = match placement {
                        Ok(discs) => discs,
                        Err(e) => {
                            problems.push(Problem {
                                line: Some(line),
                                message: format!("gas #{}: {e}", k + 1),
                            });
                            continue;
                        }
                    };
                    if spec.zero_momentum {
                        scene::zero_momentum(&mut discs, &config, spec.drift);
                    }
                    if spec.streaming {
                        for d in &mut discs {
                            let flow = config.boundary.streaming_velocity(d.position[1]);
                            d.velocity[0] += flow.unwrap_or(0.0);
                        }
                    }
                    if spec.spin != 0.0 {
                        scene::spin(&mut discs, spec.spin, spec.seed);
                    }
                    tag(&mut discs, spec.tag);
                    add(
                        discs,
                        (&spec.color, &spec.kind),
                        line,
                        format!("gas #{}", k + 1),
                        &mut placed,
                        None,
                    )?;
                }
                Entry::Lattice(k) => {
                    let spec = self.lattice[k].get_ref();
                    let mut discs = scene::lattice(&Lattice {
                        origin: spec.origin,
                        spacing: spec.spacing,
                        counts: spec.counts,
                        radius: spec.radius,
                        velocity: spec.velocity,
                    });
                    tag(&mut discs, spec.tag);
                    add(
                        discs,
                        (&spec.color, &spec.kind),
                        line,
                        format!("lattice #{}", k + 1),
                        &mut placed,
                        None,
                    )?;
                }
                Entry::Block(k) => {
                    let spec = self.block[k].get_ref();
                    let law = Law::new(&config);
                    let spacing = block_spacing(spec, &law);
                    let mut discs = scene::lattice(&Lattice {
                        origin: [spec.min[0] + spec.radius, spec.min[1] + spec.radius],
                        spacing: [spacing, spacing],
                        counts: block_counts(spec, &law),
                        radius: spec.radius,
                        velocity: spec.velocity,
                    });
                    tag(&mut discs, spec.tag);
                    add(
                        discs,
                        (&spec.color, &spec.kind),
                        line,
                        format!("block #{}", k + 1),
                        &mut placed,
                        None,
                    )?;
                }
                Entry::File(k) => {
                    let spec = self.file[k].get_ref();
                    let read = match self.read_file(spec, &config) {
                        Ok(read) => read,
                        Err(e) => {
                            problems.push(Problem {
                                line: Some(line),
                                message: format!("file #{}: {e}", k + 1),
                            });
                            continue;
                        }
                    };
                    add(
                        read.discs,
                        (&spec.color, &spec.kind),
                        line,
                        format!("file #{} ({})", k + 1, spec.path),
                        &mut placed,
                        Some((&read.types, &read.typeid)),
                    )?;
                }
                Entry::Disc(k) => {
                    let spec = self.disc[k].get_ref();
                    let disc = Particle {
                        mass: spec.mass,
                        angular_velocity: spec.angular_velocity,
                        tag: spec.tag,
                        ..Particle::new(spec.position, spec.velocity, spec.radius)
                    };
                    add(
                        vec![disc],
                        (&spec.color, &spec.kind),
                        line,
                        format!("disc #{}", k + 1),
                        &mut placed,
                        None,
                    )?;
                }
            }
        }
        // Into the world at once (one at a time, each addition re-measured the world: a
        // table per disc took `O(N²)`); an invalid disc is named by its table, and left out
        // so that the rest are checked too.
        add_valid(&mut world, placed, &mut tables, &mut problems);
        // With tables or discs left out, ids are not the ones a run would give: not named.
        let ids = !left_out && problems.is_empty();
        problems.extend(overlapping(&world, &tables, ids));
        if !problems.is_empty() {
            return Err(ScenarioError {
                file: file.to_string(),
                problems,
            });
        }
        let emitted = self
            .emitter
            .iter()
            .map(|e| {
                let e = e.get_ref();
                let name = e
                    .kind
                    .clone()
                    .or_else(|| e.color.clone())
                    .unwrap_or_else(|| "A".into());
                let t = match types.iter().position(|t| *t == name) {
                    Some(t) => t,
                    None => {
                        types.push(name);
                        types.len() - 1
                    }
                };
                let rgb = e.color.as_deref().and_then(|c| parse_colour(c).ok());
                (rgb, t as u32)
            })
            .collect();
        Ok(Built {
            world,
            colours,
            types,
            typeid,
            emitted,
        })
    }
}

/// What of `config` the placement can check discs against when the whole is refused (a
/// problem already reported): its box, collision distance, mass model and obstacles where
/// those are sound, the rest at their defaults.
fn placement_config(config: &Config) -> Config {
    let geometry = Config {
        boundary: config.boundary.clone(),
        collision_radius_scale: config.collision_radius_scale,
        mass_model: config.mass_model,
        obstacles: config.obstacles.clone(),
        ..Config::default()
    };
    if geometry.validate().is_ok() {
        geometry
    } else {
        Config {
            boundary: config.boundary.clone(),
            ..Config::default()
        }
    }
}

/// The invalid discs a table may report before the rest are counted.
const INVALID_PER_TABLE: usize = 3;

/// Adds `placed` to `world`, leaving out and reporting each invalid disc (the first few of a
/// table, then their count); `tables` (each table's first index, name and line) is moved to
/// the discs kept.
fn add_valid(
    world: &mut World,
    placed: Vec<Particle>,
    tables: &mut [(usize, String, usize)],
    problems: &mut Vec<Problem>,
) {
    let total = placed.len();
    let table_of =
        |i: usize, tables: &[(usize, String, usize)]| tables.partition_point(|t| t.0 <= i) - 1;
    let mut invalid: Vec<usize> = Vec::new();
    let mut per_table = vec![0usize; tables.len()];
    let mut from = 0;
    while from < total {
        // All or nothing: on the first invalid disc the world is unchanged, so add the valid
        // ones before it and go on after it.
        let Err((k, e)) = world.add_particles(placed[from..].iter().copied()) else {
            break;
        };
        let i = from + k;
        world
            .add_particles(placed[from..i].iter().copied())
            .expect("the discs before the first invalid one are valid");
        let t = table_of(i, tables);
        per_table[t] += 1;
        let (start, what, line) = &tables[t];
        if per_table[t] <= INVALID_PER_TABLE {
            let n = tables.get(t + 1).map_or(total, |next| next.0) - start;
            problems.push(Problem {
                line: Some(*line),
                message: format!("{what}: particle {} of {n}: {e}", i - start + 1),
            });
        }
        invalid.push(i);
        from = i + 1;
    }
    for (t, &count) in per_table.iter().enumerate() {
        if count > INVALID_PER_TABLE {
            let (_, what, line) = &tables[t];
            problems.push(Problem {
                line: Some(*line),
                message: format!(
                    "{what}: {} more invalid particles",
                    count - INVALID_PER_TABLE
                ),
            });
        }
    }
    // The tables' first indices among the discs kept.
    for table in tables.iter_mut() {
        table.0 -= invalid.partition_point(|&i| i < table.0);
    }
}

/// Discs that start overlapping (closer than their collision distance, not just touching),
/// named by their tables: at most one problem per pair of tables.
fn overlapping(world: &World, tables: &[(usize, String, usize)], ids: bool) -> Vec<Problem> {
    let law = Law::new(world.config());
    let table_of = |id: u32| {
        let k = tables.partition_point(|t| t.0 <= id as usize) - 1;
        &tables[k]
    };
    let mut seen = std::collections::BTreeSet::new();
    let mut out = Vec::new();
    for (a, b) in world.colliding_pairs() {
        let (pa, pb) = (
            world.particle(a).expect("listed"),
            world.particle(b).expect("listed"),
        );
        let (dx, dy) = (
            pa.position[0] - pb.position[0],
            pa.position[1] - pb.position[1],
        );
        let gap = law.collision_distance(pa.radius, pb.radius) - (dx * dx + dy * dy).sqrt();
        // Only real overlaps (a lattice of touching discs is fine); the minimum image of a
        // periodic box is left to the grid, which found the pair.
        if gap <= 1e-9 * law.collision_distance(pa.radius, pb.radius) {
            continue;
        }
        let (ta, tb) = (table_of(a.0), table_of(b.0));
        // A file holds the overlaps of the run that wrote it; the first step resolves them.
        if ta.0 == tb.0 && ta.1.starts_with("file") {
            continue;
        }
        if !seen.insert((ta.0, tb.0)) {
            continue;
        }
        // ", discs 3 and 7": which two, where the ids are the ones a run would give.
        let which = if ids {
            format!(" (discs {} and {})", a.0, b.0)
        } else {
            String::new()
        };
        let message = if ta.0 == tb.0 {
            format!(
                "{}: two of its discs{which} overlap by {gap:.3} (spacing below the collision \
                 distance)",
                ta.1
            )
        } else {
            format!(
                "{} (line {}) and {} (line {}) overlap{which} by {gap:.3}; move one or let a \
                 [[gas]] come later (generators keep clear of earlier tables)",
                ta.1, ta.2, tb.1, tb.2
            )
        };
        out.push(Problem {
            line: Some(tb.2),
            message,
        });
        if out.len() >= 10 {
            break;
        }
    }
    out
}

/// A particle table, for building in file order.
#[derive(Clone, Copy)]
enum Entry {
    Gas(usize),
    Lattice(usize),
    Block(usize),
    Disc(usize),
    File(usize),
}

fn block_spacing(block: &BlockSpec, law: &Law) -> f64 {
    // Just beyond the collision distance, so the block starts without contacts.
    block
        .spacing
        .unwrap_or(law.interaction_diameter(block.radius) * 1.001)
}

fn block_counts(block: &BlockSpec, law: &Law) -> [usize; 2] {
    let spacing = block_spacing(block, law);
    [0, 1].map(|a| {
        let room = block.max[a] - block.min[a] - 2.0 * block.radius;
        if room.is_finite() && room >= 0.0 && spacing > 0.0 {
            (room / spacing).floor().min(1e7) as usize + 1
        } else {
            0
        }
    })
}

fn colour_problem(
    colour: &Option<String>,
    line: Option<usize>,
    what: &str,
    at: &mut impl FnMut(Option<usize>, String),
) {
    if let Some(c) = colour
        && let Err(e) = parse_colour(c)
    {
        at(line, format!("{what}: {e}"));
    }
}

/// The text of a shipped template.
pub fn template(name: &str) -> Option<&'static str> {
    TEMPLATES.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}
