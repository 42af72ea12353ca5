//! The collision model's options ([`crate::Config`]'s `mass_model`, `restitution_model`,
//! `velocity_update`, `resting_contacts`): each default is the default model's way, each other value
//! the physically standard one, chosen explicitly.

use serde::{Deserialize, Serialize};

/// The mass of each disc.
///
/// ```
/// use bounce::MassModel;
/// let (r, own) = (2.0, 7.0);
/// assert_eq!(MassModel::Radius.mass(r, own), 2.0); // the default
/// assert_eq!(MassModel::Area.mass(r, own), std::f64::consts::PI * 4.0);
/// assert_eq!(MassModel::PerParticle.mass(r, own), 7.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MassModel {
    /// The default: mass = radius. Cheap and what the default model's formulas say, but a disc of
    /// twice the radius has four times the area and only twice the mass.
    Radius,
    /// Mass = π r² (uniform areal density 1): what a 2D disc of one material weighs. Choose it
    /// for mixtures of sizes where heavy large discs matter (Brownian motion, segregation).
    Area,
    /// Each particle's own [`crate::Particle::mass`] (defaulting to π r² when not given).
    PerParticle,
}

impl MassModel {
    /// The mass of a disc of `radius` whose per-particle mass is `per_particle`. See
    /// [`MassModel`] for an example.
    #[inline]
    pub fn mass(self, radius: f64, per_particle: f64) -> f64 {
        match self {
            MassModel::Radius => radius,
            MassModel::Area => std::f64::consts::PI * radius * radius,
            MassModel::PerParticle => per_particle,
        }
    }
}

/// How the coefficient of restitution `e` enters the collision.
///
/// ```
/// use bounce::{Config, Particle, RestitutionModel, World};
/// // A disc at 2 hits an equal one at rest, e = 0.5.
/// let after = |model| -> Result<[f64; 2], Box<dyn std::error::Error>> {
///     let mut world = World::new(Config {
///         coefficient_of_restitution: 0.5,
///         restitution_model: model,
///         ..Config::default()
///     })?;
///     world.add_particle(Particle::new([0.0, 0.0], [2.0, 0.0], 1.0))?;
///     world.add_particle(Particle::new([2.0, 0.0], [0.0, 0.0], 1.0))?;
///     world.step(0.001)?;
///     let v: Vec<f64> = world.particles_by_id().iter().map(|(_, p)| p.velocity[0]).collect();
///     Ok([v[0], v[1]])
/// };
/// // The default: the elastic exchange (0, 2), each scaled by e; momentum 2 becomes 1.
/// assert_eq!(after(RestitutionModel::ScaleEachNormalVelocity)?, [0.0, 1.0]);
/// // Newton's: relative speed reversed and halved, momentum kept.
/// assert_eq!(after(RestitutionModel::RelativeNormalVelocity)?, [0.5, 1.5]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RestitutionModel {
    /// The default: compute both elastic normal velocities, then multiply each by `e`.
    /// For `e < 1` this does not conserve momentum (a resting pair hit by a moving one loses
    /// momentum to nowhere), and pairs keep losing speed while in contact.
    ScaleEachNormalVelocity,
    /// The standard Newton restitution law: the relative normal velocity is reversed and scaled
    /// by `e`, the centre-of-mass velocity is kept. Conserves momentum for every `e`;
    /// identical to the default at `e = 1` up to rounding.
    RelativeNormalVelocity,
}

/// Which detected pairs get their velocities changed.
///
/// ```
/// use bounce::{Config, Particle, VelocityUpdate, World};
/// // Two overlapping discs already moving apart.
/// let after = |update| -> Result<f64, Box<dyn std::error::Error>> {
///     let mut world = World::new(Config { velocity_update: update, ..Config::default() })?;
///     world.add_particle(Particle::new([0.0, 0.0], [-1.0, 0.0], 1.0))?;
///     world.add_particle(Particle::new([1.5, 0.0], [1.0, 0.0], 1.0))?;
///     world.step(0.001)?;
///     Ok(world.particles_by_id()[0].1.velocity[0])
/// };
/// // The default exchanges their normal velocities anyway: the first now moves right.
/// assert_eq!(after(VelocityUpdate::AllDetected)?, 1.0);
/// // Approaching pairs only: it keeps moving away.
/// assert_eq!(after(VelocityUpdate::ApproachingOnly)?, -1.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VelocityUpdate {
    /// The default: every pair within the collision distance gets steps 4–7, even one whose
    /// discs already move apart. Such a pair exchanges its normal velocities back, so two discs
    /// still overlapping after a bounce can stick together for a few steps.
    AllDetected,
    /// Only pairs whose relative normal velocity brings them closer. The usual choice in
    /// impulse-based engines: separating pairs only get the overlap push.
    ApproachingOnly,
}

/// What a **resting contact** does: a contact whose normal speed (towards or away from the
/// other side) is at most the resting speed, 4 substeps of gravity's pull
/// ([`crate::law::resting_speed`], the speed that also tells a step's `contacts` from its
/// `collisions`). Without gravity no contact rests, and both choices are the same.
///
/// ```
/// use bounce::{Boundary, Config, Particle, RestingContacts, World};
/// // A disc at rest on the floor: the default keeps it hopping at |g| h; `Rest` holds it still.
/// let fastest = |contacts| -> Result<f64, Box<dyn std::error::Error>> {
///     let mut world = World::new(Config {
///         boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
///         gravity: [0.0, -10.0],
///         resting_contacts: contacts,
///         ..Config::default()
///     })?;
///     world.add_particle(Particle::new([5.0, 1.0], [0.0, 0.0], 1.0))?;
///     let mut fastest: f64 = 0.0;
///     for _ in 0..200 {
///         world.step(0.01)?;
///         fastest = fastest.max(world.particles_by_id()[0].1.velocity[1].abs());
///     }
///     Ok(fastest)
/// };
/// assert_eq!(fastest(RestingContacts::Rest)?, 0.0);
/// assert!((fastest(RestingContacts::Bounce)? - 0.1).abs() < 1e-12); // |g| h = 10 · 0.01
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RestingContacts {
    /// The default: every contact gets its restitution, however slow. Gravity pulls a disc
    /// resting on the floor, a segment or a peg in by `|g| h` each substep, and the
    /// reflection sends it back up at `e |g| h`: at the end of a step it moves at up to
    /// `|g| h` (kinetic energy up to `½ m (g h)²`), and in a stack the exchange of normal
    /// velocities passes that speed up and down (a stacked pair at `e = 1` gains up to a few
    /// tenths of a percent of its energy over a run).
    Bounce,
    /// A resting contact is perfectly inelastic along its normal: a disc on a wall or an
    /// obstacle leaves with the obstacle's normal velocity (it stops against a fixed one),
    /// and a pair leaves with one common normal velocity, the pair's momentum kept (whatever
    /// [`RestitutionModel`]). Faster contacts, impacts, keep the restitution. A disc resting
    /// on the floor, a segment or a peg is then at rest at the end of every substep, and
    /// resting contacts never add energy. Tangential velocities are kept, as always.
    Rest,
}
