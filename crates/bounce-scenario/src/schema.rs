//! The scenario file's schema: every table and key a scenario may hold, with its default,
//! as serde reads it, and the [`Config`] the file describes.

use crate::observables;
use crate::obstacles::{self, ObstacleGroup, ObstacleSpec};
use bounce::law::Law;
use bounce::{
    Boundary, Config, MassModel, Particle, RestingContacts, RestitutionModel, VelocityUpdate,
};
use serde::Deserialize;
use toml::Spanned;

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
    pub(crate) fn range(self) -> [f64; 2] {
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
    pub headline: Option<HeadlineKind>,
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

    /// Where a `[[file]]` table's file is.
    pub fn file_path(&self, spec: &FileSpec) -> std::path::PathBuf {
        match &self.dir {
            Some(dir) => dir.join(&spec.path),
            None => std::path::PathBuf::from(&spec.path),
        }
    }

    /// Whether any generator sets a colour.
    pub fn has_colours(&self) -> bool {
        self.gas.iter().any(|g| g.get_ref().color.is_some())
            || self.lattice.iter().any(|g| g.get_ref().color.is_some())
            || self.block.iter().any(|g| g.get_ref().color.is_some())
            || self.disc.iter().any(|g| g.get_ref().color.is_some())
            || self.file.iter().any(|g| g.get_ref().color.is_some())
    }
}

pub(crate) fn block_spacing(block: &BlockSpec, law: &Law) -> f64 {
    // Just beyond the collision distance, so the block starts without contacts.
    block
        .spacing
        .unwrap_or(law.interaction_diameter(block.radius) * 1.001)
}

pub(crate) fn block_counts(block: &BlockSpec, law: &Law) -> [usize; 2] {
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

/// What a run's headline measures (`[output] headline`); the headline module measures it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HeadlineKind {
    /// The final speeds against 2D Maxwell–Boltzmann: the Kolmogorov–Smirnov distance.
    MaxwellBoltzmann,
    /// `Z = P A / (N kT)` against Monte Carlo (or Henderson's equation of state).
    Compressibility,
    /// The shear viscosity `−⟨P_xy⟩ / γ̇` against Enskog's (needs `pressure_tensor`).
    Viscosity,
    /// A heap's angle of repose: both flanks.
    ReposeAngle,
    /// A Galton board's heap against the binomial of independent balls.
    GaltonSpread,
    /// The discharge rate through a neck (the first sensor's entries), steady as Beverloo's
    /// law says.
    Discharge,
    /// A piston's gas heating along the hard-disc adiabat.
    Adiabat,
    /// A chamber emptying through a hole, against the effusion rate.
    Effusion,
    /// A driven granular gas's temperature against van Noije and Ernst's.
    GranularTemperature,
    /// The largest disc's diffusion coefficient (needs a GSD trajectory).
    Diffusion,
    /// Newton's cradle: the last disc's velocity after the blow.
    Cradle,
    /// How mixed two kinds of disc are.
    Mixing,
    /// A pile's packing fraction and largest overlap.
    Packing,
    /// Disc-steps per second of the physics.
    Throughput,
}
