//! # bounce
//!
//! A fast, faithful, deterministic 2D simulator of colliding discs.
//!
//! bounce implements one simple, widely used collision model exactly, as its default:
//! two discs collide when `distance <= (r_i + r_j) * collision_radius_scale`; a colliding
//! pair is pushed apart half each, its velocities are split into normal and tangent parts,
//! the normal parts follow the 1D elastic formula with the **radii as masses**, and each new
//! normal velocity is scaled by the coefficient of restitution. Where that model departs from
//! textbook physics, the textbook way is an option of [`Config`], never the default. The user
//! guide's page on the collision model (`docs/src/concepts/collision-model.md`) gives every
//! formula. The model comes from a short specification bounce was written to reproduce, which
//! the source calls *the seed*; its resolution is numbered in steps 1–7 (find the pair, push
//! it apart, the normal, the normal and tangent velocities, the elastic update with
//! restitution, the new velocities), and the law's documentation refers to those steps.
//!
//! What it aims for, in order:
//! 1. **Faithful**: the model's formulas term for term ([`law::resolve_pair`]), in one module
//!    that owns the collision law ([`law::Law`]).
//! 2. **Deterministic**: the same input gives the same bits, whatever the thread count.
//! 3. **Fast**: O(N) per step: candidate pairs listed with a hierarchy of uniform grids and
//!    kept for several steps (a skin), particles kept in cell order, contacts resolved in
//!    parallel blocks.
//!
//! ## A tour
//!
//! **Make a world** from a [`Config`] (every field's default is the default model's behaviour) and
//! add discs ([`Particle`]); each gets an id ([`ParticleId`]) that never changes.
//!
//! ```
//! use bounce::{Boundary, Config, ContactKind, Particle, Region, Sensor, World};
//!
//! let config = Config {
//!     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
//!     contact_events: true, // report contacts as they begin and end
//!     sensors: vec![Sensor::new("right", Region::Box { min: [6.0, 0.0], max: [10.0, 10.0] })],
//!     ..Config::default()
//! };
//! let mut world = World::new(config)?;
//! let a = world.add_particle(Particle::new([3.0, 5.0], [1.0, 0.0], 0.5))?;
//! let b = world.add_particle(Particle::new([7.0, 5.0], [-1.0, 0.0], 0.5).with_tag(42))?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! **Step it** by `dt` ([`World::step`]); each step reports its statistics ([`StepStats`]),
//! the same bits on any thread count ([`World::set_threads`]).
//!
//! ```
//! # use bounce::{Boundary, Config, ContactKind, Particle, Region, Sensor, World};
//! # let config = Config {
//! #     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
//! #     contact_events: true,
//! #     sensors: vec![Sensor::new("right", Region::Box { min: [6.0, 0.0], max: [10.0, 10.0] })],
//! #     ..Config::default()
//! # };
//! # let mut world = World::new(config)?;
//! # let a = world.add_particle(Particle::new([3.0, 5.0], [1.0, 0.0], 0.5))?;
//! # let b = world.add_particle(Particle::new([7.0, 5.0], [-1.0, 0.0], 0.5).with_tag(42))?;
//! let mut began = Vec::new();
//! for _ in 0..300 {
//!     let stats = world.step(0.01)?;
//!     // Equal discs meet head on and swap velocities: momentum (mass = radius) is kept.
//!     assert!(stats.momentum[0].abs() < 1e-12);
//!     // **Read events**: what began and ended touching in the step's substeps.
//!     let events = world.contact_events().iter();
//!     began.extend(events.filter(|e| e.kind == ContactKind::Begin).map(|e| (e.a, e.b)));
//! }
//! assert_eq!(began, vec![(a, bounce::Party::Disc(b))]);
//! // They met at t = 1.5 and went back: the sensor saw `b` leave the right half and return.
//! let right = &world.sensors()[0];
//! assert_eq!((right.entered, right.left, right.inside), (2, 1, 1));
//!
//! // **Query** a snapshot: the discs in a circle, the nearest, the first a ray enters.
//! let queries = world.queries();
//! assert_eq!(queries.in_circle([7.0, 5.0], 1.0), vec![b]);
//! let hit = queries.ray_cast([0.0, 5.0], [1.0, 0.0], 10.0).unwrap();
//! assert!(hit.id == a && (hit.point[0] - 2.5).abs() < 0.02); // `a`'s edge, near x = 2.5
//!
//! // **Remove discs**; ids are never given again, tags follow their discs.
//! assert_eq!(world.particle(b).unwrap().tag, 42);
//! world.remove_particles(&[a]);
//! assert_eq!(world.len(), 1);
//!
//! // **Save and load** with any serde format (postcard keeps every bit): the loaded world
//! // continues exactly as this one does.
//! let bytes = postcard::to_allocvec(&world)?;
//! let mut loaded: World = postcard::from_bytes(&bytes)?;
//! world.step(0.01)?;
//! loaded.step(0.01)?;
//! assert_eq!(world.state_hash(), loaded.state_hash());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Where to look next: [`Config`] for every option (walls, periodic boxes, gravity,
//! substeps, the mass and restitution models, rough discs, obstacles, emitters, sinks,
//! sensors, the event-driven [`Method`]); [`law`] for the collision law on its own;
//! [`plain`] for the reference step the fast one equals bit for bit; [`query`] for spatial
//! queries; [`scene`] for generators of gases and lattices.
//!
//! See `ARCHITECTURE.md` in the repository for the data flow of one step.

mod broadphase;
mod config;
mod contact_events;
pub use contact_events::{ContactEvent, ContactKind, ContactLog, Party, WallSide};
mod contacts;
pub use contacts::{order_block_start, order_cell_width, order_pass_reach};
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
mod thermostat;
mod world;

/// The README's Rust examples, compiled and run as doctests so they cannot rot.
#[doc = include_str!("../../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The user guide's Rust examples (`docs/src`), run as doctests like the README's.
#[cfg(doctest)]
pub mod guide {
    /// Embedding the library.
    #[doc = include_str!("../../../docs/src/tutorials/library.md")]
    pub struct Library;
    /// The collision model.
    #[doc = include_str!("../../../docs/src/concepts/collision-model.md")]
    pub struct CollisionModel;
}

pub use config::{
    Boundary, Config, ConfigError, Emitter, EmitterState, MAX_SUBSTEPS, MassModel, Method, Motion,
    Obstacle, ObstacleState, Region, RestingContacts, RestitutionModel, Sensor, Shape, Sink,
    Thermostat, ThermostatKind, VelocityUpdate,
};
pub use parallel::{DEFAULT_PARALLEL_MIN_WORK, ThreadsError};
pub use part::{DiscRecord, Tally, Travel, wrap_coordinate};
pub use particles::{Particle, ParticleError, ParticleId, Particles};
pub use stats::{StepProfile, StepStats};
pub use sum::{ExactSum, StepSums, WallImpulse, WallSums};
pub use world::{SavedWorld, SensorCount, SensorState, StepError, World, WorldError};
