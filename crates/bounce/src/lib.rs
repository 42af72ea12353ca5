//! # bounce
//!
//! A fast, faithful, deterministic 2D simulator of colliding discs.
//!
//! bounce implements the collision model of its seed document exactly, as its default:
//! two discs collide when `distance <= (r_i + r_j) * collision_radius_scale`; a colliding
//! pair is pushed apart half each, its velocities are split into normal and tangent parts,
//! the normal parts follow the 1D elastic formula with the **radii as masses**, and each new
//! normal velocity is scaled by the coefficient of restitution. Where that model departs from
//! textbook physics, the textbook way is an option of [`Config`], never the default.
//!
//! What it aims for, in order:
//! 1. **Faithful**: the seed's formulas term for term ([`law::resolve_pair`]), in one module
//!    that owns the collision law ([`law::Law`]).
//! 2. **Deterministic**: the same input gives the same bits, whatever the thread count.
//! 3. **Fast**: O(N) per step: candidate pairs listed with a hierarchy of uniform grids and
//!    kept for several steps (a skin), particles kept in cell order, contacts resolved in
//!    parallel blocks.
//!
//! ```
//! use bounce::{Boundary, Config, Particle, World};
//!
//! let config = Config {
//!     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
//!     ..Config::default()
//! };
//! let mut world = World::new(config)?;
//! world.add_particle(Particle::new([3.0, 5.0], [1.0, 0.0], 0.5))?;
//! world.add_particle(Particle::new([7.0, 5.0], [-1.0, 0.0], 0.5))?;
//! for _ in 0..200 {
//!     world.step(0.01)?;
//! }
//! // Equal discs met head on and swapped velocities: momentum (mass = radius) is conserved.
//! let p = world.stats().momentum;
//! assert!(p[0].abs() < 1e-12 && p[1].abs() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! See `ARCHITECTURE.md` in the repository for the data flow of one step.

mod broadphase;
mod config;
mod contact_events;
pub use contact_events::{ContactEvent, ContactKind, Party, WallSide};
mod contacts;
pub use contacts::{order_block_start, order_cell_width};
mod context;
pub mod event;
mod geometry;
mod integrate;
mod lanes;
pub mod law;
mod obstacles;
mod parallel;
mod part;
mod particles;
pub mod plain;
pub mod query;
mod resolve;
pub mod scene;
mod sources;
mod stats;
mod sum;
mod world;

pub use config::{
    Boundary, Config, ConfigError, Emitter, EmitterState, MAX_SUBSTEPS, MassModel, Method, Motion,
    Obstacle, ObstacleState, Region, RestingContacts, RestitutionModel, Sensor, Shape, Sink,
    VelocityUpdate,
};
pub use geometry::WallImpulse;
pub use parallel::{DEFAULT_PARALLEL_MIN_WORK, ThreadsError};
pub use part::{DiscRecord, Tally, Travel, wrap_coordinate};
pub use particles::{Particle, ParticleError, ParticleId, Particles};
pub use stats::{StepProfile, StepStats};
pub use sum::{ExactSum, StepSums, WallSums};
pub use world::{SavedWorld, SensorCount, StepError, World, WorldError};
