//! The benchmark scenes, built once from bounce's generators so every engine starts from the
//! same discs.

use anyhow::{Result, bail};
use bounce::Particle;
use bounce::scene::{self, Speeds};

/// A named scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SceneKind {
    Gas(usize),
    Pile(usize),
    Poly(usize),
}

/// What every engine gets.
pub struct Setup {
    pub discs: Vec<Particle>,
    pub min: [f64; 2],
    pub max: [f64; 2],
    pub gravity: [f64; 2],
    pub restitution: f64,
    pub dt: f64,
    pub substeps: u32,
}

impl SceneKind {
    pub const ALL: [SceneKind; 5] = [
        SceneKind::Gas(10_000),
        SceneKind::Gas(100_000),
        SceneKind::Gas(1_000_000),
        SceneKind::Pile(100_000),
        SceneKind::Poly(100_000),
    ];

    pub fn name(&self) -> &'static str {
        match self {
            SceneKind::Gas(10_000) => "gas-10k",
            SceneKind::Gas(100_000) => "gas-100k",
            SceneKind::Gas(_) => "gas-1m",
            SceneKind::Pile(_) => "pile-100k",
            SceneKind::Poly(_) => "poly-100k",
        }
    }

    pub fn parse(name: &str) -> Result<Self> {
        match Self::ALL.iter().find(|s| s.name() == name) {
            Some(s) => Ok(*s),
            None => bail!("unknown scene {name:?}"),
        }
    }

    pub fn count(&self) -> usize {
        match *self {
            SceneKind::Gas(n) | SceneKind::Pile(n) | SceneKind::Poly(n) => n,
        }
    }

    /// The initial state: walls around a square box at packing fraction 0.3.
    pub fn build(&self) -> Setup {
        let n = self.count();
        let (radius, gravity, restitution, substeps) = match self {
            SceneKind::Gas(_) => ([0.5, 0.5], [0.0, 0.0], 1.0, 1),
            SceneKind::Pile(_) => ([0.5, 0.5], [0.0, -9.81], 0.7, 4),
            SceneKind::Poly(_) => ([0.1, 2.5], [0.0, 0.0], 1.0, 1),
        };
        let (config, discs) = scene::gas_in_walls(n, radius, 0.3, Speeds::Uniform(2.0), 1)
            .expect("the benchmark gas fits");
        let (min, max) = config.boundary.bounds().expect("walls");
        Setup {
            discs,
            min,
            max,
            gravity,
            restitution,
            dt: 1.0 / 60.0,
            substeps,
        }
    }
}
