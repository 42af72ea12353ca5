//! The benchmark scenes: a walled square box at a packing with a gas in it, one definition
//! for the harness (`bounce-bench`), the profiler, the divan bench and the pinned hashes.

use super::{Gas, SceneError, Speeds, gas, invalid};
use crate::config::{Boundary, Config};
use crate::particles::Particle;

/// A square walled box sized so `count` discs with radii uniform in `radius` fill
/// `packing` of its area, and a gas in it: the benchmark scenes' setup. See [`Bench`] for an
/// example.
pub fn gas_in_walls(
    count: usize,
    radius: [f64; 2],
    packing: f64,
    speeds: Speeds,
    seed: u64,
) -> Result<(Config, Vec<Particle>), SceneError> {
    if !(packing > 0.0 && packing < 1.0) {
        return Err(invalid("packing", packing.to_string(), "in (0, 1)"));
    }
    // Mean r² of a radius uniform in [a, b] is (a² + ab + b²) / 3.
    let [a, b] = radius;
    let mean_r2 = (a * a + a * b + b * b) / 3.0;
    let side = (count as f64 * std::f64::consts::PI * mean_r2 / packing).sqrt();
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [side, side]),
        ..Config::default()
    };
    let discs = gas(
        &Gas {
            count,
            radius,
            region: None,
            speeds,
            drift: [0.0, 0.0],
            seed,
        },
        &config,
    )?;
    Ok((config, discs))
}

/// The benchmark scenes, one definition for the harness (`bounce-bench`), the profiler
/// (`examples/profile.rs`), the divan bench and the pinned hashes: a walled square box, discs
/// at packing 0.3, dt = 1/60.
///
/// ```
/// use bounce::scene::Bench;
/// use bounce::World;
/// let (config, discs) = Bench::Pile.build(1000)?;
/// assert_eq!((config.gravity, config.coefficient_of_restitution, config.substeps), ([0.0, -9.81], 0.7, 4));
/// assert_eq!(Bench::Pile.physics(), ([0.0, -9.81], 0.7, 4));
/// let mut world = World::new(config)?;
/// world.add_particles(discs).unwrap();
/// world.step(Bench::DT)?;
/// assert_eq!((world.len(), Bench::ALL.len()), (1000, 4));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bench {
    /// Radius 0.5, velocity components uniform in [-2, 2], e = 1, one substep.
    Gas,
    /// The gas's start under gravity (0, -9.81), e = 0.7, 4 substeps.
    Pile,
    /// Radii uniform in [0.05, 5], otherwise the gas.
    Poly,
    /// The gas with components uniform in [-40, 40]: a step moves a disc about its radius.
    Fast,
}

impl Bench {
    /// Every scene. See [`Bench`] for an example.
    pub const ALL: [Bench; 4] = [Bench::Gas, Bench::Pile, Bench::Poly, Bench::Fast];

    /// The time step every scene runs at. See [`Bench`] for an example.
    pub const DT: f64 = 1.0 / 60.0;

    /// The configuration and the discs (in creation order) of `count` discs. See [`Bench`]
    /// for an example.
    pub fn build(self, count: usize) -> Result<(Config, Vec<Particle>), SceneError> {
        let (radius, speed) = match self {
            Bench::Poly => ([0.05, 5.0], 2.0),
            Bench::Fast => ([0.5, 0.5], 40.0),
            Bench::Gas | Bench::Pile => ([0.5, 0.5], 2.0),
        };
        let (config, discs) = gas_in_walls(count, radius, 0.3, Speeds::Uniform(speed), 1)?;
        let (gravity, coefficient_of_restitution, substeps) = self.physics();
        let config = Config {
            gravity,
            coefficient_of_restitution,
            substeps,
            ..config
        };
        Ok((config, discs))
    }

    /// The scene's gravity, restitution and substeps per step. See [`Bench`] for an example.
    pub fn physics(self) -> ([f64; 2], f64, u32) {
        match self {
            Bench::Pile => ([0.0, -9.81], 0.7, 4),
            Bench::Gas | Bench::Poly | Bench::Fast => ([0.0, 0.0], 1.0, 1),
        }
    }
}
