//! The benchmark scenes, built once from bounce's generators so every engine starts from the
//! same discs, created in spatial order (the peers' best case).

use std::path::Path;

use anyhow::{Context, Result, bail};
use bounce::scene::{self, Bench, Gas, Speeds};
use bounce::{Boundary, Config, Obstacle, Particle, World};

/// What a scene is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// Radius 0.5 at packing 0.3, speeds uniform in [-2, 2]², e = 1.
    Gas,
    /// The gas's start under gravity, e = 0.7, 4 substeps, settled before timing.
    SettledPile,
    /// The settled pile's start with friction 0.5 everywhere (bounce's rough discs).
    SettledFrictionPile,
    /// Radius 0.5 at packing 0.7 (a melting lattice), e = 1.
    Dense,
    /// Radii uniform in [0.05, 5] at packing 0.3, e = 1.
    Poly,
    /// The gas with speeds uniform in [-40, 40]²: speed × dt ≈ the radius.
    Fast,
    /// The gas among 10,000 pegs of radius 0.5 on a square lattice over the box (bounce
    /// only: the peers' scenes have no obstacles).
    Pegs,
}

/// A named scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneKind {
    pub kind: Kind,
    pub n: usize,
    /// Whether the peers run it (they cannot at millions of discs: a step takes seconds or
    /// Box2D asserts).
    pub peers: bool,
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
    /// Obstacles (bounce only).
    pub obstacles: Vec<Obstacle>,
    /// Coulomb friction of every contact (0: bounce's smooth discs, the seed's).
    pub friction: f64,
}

const fn scene(kind: Kind, n: usize, peers: bool) -> SceneKind {
    SceneKind { kind, n, peers }
}

impl SceneKind {
    pub const ALL: [SceneKind; 14] = [
        scene(Kind::Gas, 10_000, true),
        scene(Kind::Gas, 100_000, true),
        scene(Kind::Gas, 1_000_000, true),
        scene(Kind::Gas, 4_000_000, false),
        scene(Kind::Gas, 10_000_000, false),
        scene(Kind::SettledPile, 100_000, true),
        scene(Kind::SettledPile, 1_000_000, false),
        scene(Kind::SettledFrictionPile, 100_000, true),
        scene(Kind::Dense, 100_000, true),
        scene(Kind::Poly, 100_000, true),
        scene(Kind::Poly, 1_000_000, false),
        scene(Kind::Fast, 100_000, true),
        scene(Kind::Fast, 1_000_000, false),
        scene(Kind::Pegs, 100_000, false),
    ];

    pub fn name(&self) -> String {
        let kind = match self.kind {
            Kind::Gas => "gas",
            Kind::SettledPile => "pile-settled",
            Kind::SettledFrictionPile => "pile-settled-friction",
            Kind::Dense => "dense-0.7",
            Kind::Poly => "poly-0.05-5",
            Kind::Fast => "fast-gas",
            Kind::Pegs => "pegs-10k-gas",
        };
        let n = match self.n {
            n if n >= 1_000_000 => format!("{}m", n / 1_000_000),
            n => format!("{}k", n / 1000),
        };
        format!("{kind}-{n}")
    }

    pub fn parse(name: &str) -> Result<Self> {
        match Self::ALL.iter().find(|s| s.name() == name) {
            Some(s) => Ok(*s),
            None => bail!(
                "unknown scene {name:?}; scenes: {}",
                Self::ALL.map(|s| s.name()).join(", ")
            ),
        }
    }

    pub fn count(&self) -> usize {
        self.n
    }

    /// Substeps per step.
    pub fn substeps(&self) -> u32 {
        self.physics().2
    }

    /// The scene's physics, without discs.
    fn physics(&self) -> ([f64; 2], f64, u32) {
        let scene = match self.kind {
            Kind::SettledPile | Kind::SettledFrictionPile => Bench::Pile,
            _ => Bench::Gas,
        };
        scene.physics()
    }

    /// The initial state, in spatial order. A settled pile comes from `cache` (made by
    /// [`SceneKind::settle`] first).
    pub fn build(&self, cache: &Path) -> Result<Setup> {
        let n = self.n;
        let (gravity, restitution, substeps) = self.physics();
        let (config, mut discs) = match self.kind {
            Kind::Gas | Kind::SettledPile | Kind::SettledFrictionPile | Kind::Pegs => {
                Bench::Gas.build(n)?
            }
            Kind::Fast => Bench::Fast.build(n)?,
            Kind::Poly => Bench::Poly.build(n)?,
            Kind::Dense => {
                let side = (n as f64 * std::f64::consts::PI * 0.25 / 0.7).sqrt();
                let config = Config {
                    boundary: Boundary::walls([0.0, 0.0], [side, side]),
                    ..Config::default()
                };
                let gas = Gas {
                    count: n,
                    radius: [0.5, 0.5],
                    region: None,
                    speeds: Speeds::Uniform(2.0),
                    drift: [0.0, 0.0],
                    seed: 1,
                };
                let discs = scene::packed_gas(&gas, &config, &[])?;
                (config, discs)
            }
        };
        if self.is_pile() {
            discs = read_settled(&self.cache_file(cache), n)?;
        }
        let mut obstacles = Vec::new();
        if self.kind == Kind::Pegs {
            // 100 × 100 pegs, the gas placed clear of them.
            let (min, max) = config.boundary.bounds().context("walls")?;
            let step = [(max[0] - min[0]) / 100.0, (max[1] - min[1]) / 100.0];
            for i in 0..100 {
                for j in 0..100 {
                    let centre = [
                        min[0] + (i as f64 + 0.5) * step[0],
                        min[1] + (j as f64 + 0.5) * step[1],
                    ];
                    obstacles.push(Obstacle::peg(centre, 0.5));
                }
            }
            let with_pegs = Config {
                obstacles: obstacles.clone(),
                ..config.clone()
            };
            let gas = Gas {
                count: n,
                radius: [0.5, 0.5],
                region: None,
                speeds: Speeds::Uniform(2.0),
                drift: [0.0, 0.0],
                seed: 1,
            };
            discs = scene::gas(&gas, &with_pegs)?;
        }
        spatial_order(&mut discs);
        let (min, max) = config.boundary.bounds().context("walls")?;
        Ok(Setup {
            discs,
            min,
            max,
            gravity,
            restitution,
            dt: Bench::DT,
            substeps,
            obstacles,
            friction: if self.kind == Kind::SettledFrictionPile {
                0.5
            } else {
                0.0
            },
        })
    }

    /// Whether it starts from a settled pile.
    pub fn is_pile(&self) -> bool {
        matches!(self.kind, Kind::SettledPile | Kind::SettledFrictionPile)
    }

    /// The settled pile's file: the same one with and without friction.
    fn cache_file(&self, cache: &Path) -> std::path::PathBuf {
        let pile = SceneKind {
            kind: Kind::SettledPile,
            ..*self
        };
        let name = if self.is_pile() {
            pile.name()
        } else {
            self.name()
        };
        cache.join(format!("{name}.f64"))
    }

    /// Settles a pile with bounce (2 threads) and stores the positions and radii in `cache`
    /// (reused when present); every engine then starts from those discs at rest. The pile
    /// starts as a lattice at packing 0.8 in the bottom of the gas's box (raining the gas
    /// down would take thousands of steps at a million discs) and settles for 300 steps
    /// under gravity, e = 0.7, 4 substeps.
    pub fn settle(&self, cache: &Path) -> Result<()> {
        if !self.is_pile() || self.cache_file(cache).exists() {
            return Ok(());
        }
        let (config, _) = Bench::Pile.build(self.n)?;
        let (_, max) = config.boundary.bounds().context("walls")?;
        let height = self.n as f64 * std::f64::consts::PI * 0.25 / (0.8 * max[0]);
        let gas = Gas {
            count: self.n,
            radius: [0.5, 0.5],
            region: Some(([0.0, 0.0], [max[0], height])),
            speeds: Speeds::Fixed(0.0),
            drift: [0.0, 0.0],
            seed: 1,
        };
        let discs = scene::packed_gas(&gas, &config, &[])?;
        let mut world = World::new(config)?;
        world
            .add_particles(discs)
            .map_err(|(i, e)| anyhow::anyhow!("disc {i}: {e}"))?;
        world.set_threads(2)?;
        eprintln!("settling pile-settled-{} ...", self.n);
        for _ in 0..300 {
            world.step(Bench::DT)?;
        }
        eprintln!(
            "settled the pile of {} for 300 steps: kinetic energy {:.3e}, largest overlap {:.3}",
            self.n,
            world.stats().kinetic_energy,
            world.stats().max_overlap
        );
        let mut bytes = Vec::with_capacity(self.n * 24);
        for (_, p) in world.particles_by_id() {
            for v in [p.position[0], p.position[1], p.radius] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        std::fs::create_dir_all(cache)?;
        std::fs::write(self.cache_file(cache), bytes)?;
        Ok(())
    }
}

/// The settled discs (at rest) stored by [`SceneKind::settle`].
fn read_settled(path: &Path, n: usize) -> Result<Vec<Particle>> {
    let bytes = std::fs::read(path)
        .with_context(|| format!("cannot read {} (settle first)", path.display()))?;
    if bytes.len() != n * 24 {
        bail!("{}: {} bytes for {n} discs", path.display(), bytes.len());
    }
    let f = |k: usize| f64::from_le_bytes(bytes[8 * k..8 * k + 8].try_into().expect("8"));
    Ok((0..n)
        .map(|i| Particle::new([f(3 * i), f(3 * i + 1)], [0.0, 0.0], f(3 * i + 2)))
        .collect())
}

/// Sorts discs along a Z-order curve over cells about a diameter wide: bodies created in
/// spatial order make the peers 1.1–1.4x faster than random order (bounce reorders its
/// storage itself).
fn spatial_order(discs: &mut [Particle]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut r_max = 0.0f64;
    for d in discs.iter() {
        for k in 0..2 {
            lo[k] = lo[k].min(d.position[k]);
            hi[k] = hi[k].max(d.position[k]);
        }
        r_max = r_max.max(d.radius);
    }
    let cell = (2.0 * r_max).max(1e-9);
    let spread = |v: u64| {
        // Interleave the low 32 bits with zeros.
        let mut v = v & 0xFFFF_FFFF;
        v = (v | (v << 16)) & 0x0000_FFFF_0000_FFFF;
        v = (v | (v << 8)) & 0x00FF_00FF_00FF_00FF;
        v = (v | (v << 4)) & 0x0F0F_0F0F_0F0F_0F0F;
        v = (v | (v << 2)) & 0x3333_3333_3333_3333;
        (v | (v << 1)) & 0x5555_5555_5555_5555
    };
    let key = |d: &Particle| {
        let cx = ((d.position[0] - lo[0]) / cell) as u64;
        let cy = ((d.position[1] - lo[1]) / cell) as u64;
        spread(cx) | (spread(cy) << 1)
    };
    discs.sort_by_cached_key(key);
}
