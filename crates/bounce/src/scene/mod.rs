//! Ready-made sets of discs that the examples, tests, benchmarks, CLI and viewer share:
//! a random gas placed without overlap, and a lattice. Deterministic from a seed, on every
//! platform: the transcendental functions come from the pure-Rust `libm`, not the system's
//! (whose last bits differ between glibc and WebAssembly).

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::config::Config;
use crate::config::ObstacleState;
use crate::geometry::Geometry;
use crate::law::Law;
use crate::obstacles::Obstacles;
use crate::particles::Particle;

mod bench;

pub use bench::{Bench, gas_in_walls};

/// How a generator sets velocities. See [`Gas`] for an example.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Speeds {
    /// Every disc at this speed, in a uniformly random direction.
    Fixed(f64),
    /// Each component uniform in `[-a, a]`.
    Uniform(f64),
    /// Thermal: each component normal with variance `kT / m` (2D Maxwell–Boltzmann at
    /// temperature `kT`, with the mass model's masses).
    Temperature(f64),
}

/// A random gas: `count` discs with radii uniform in `radius`, centres uniform in the region
/// with no two discs within the collision distance, velocities from `speeds` plus `drift`.
///
/// ```
/// use bounce::scene::{self, Gas, Speeds};
/// use bounce::{Boundary, Config, World};
/// let config = Config {
///     boundary: Boundary::periodic([0.0, 0.0], [40.0, 40.0]),
///     ..Config::default()
/// };
/// let spec = Gas {
///     count: 300,
///     radius: [0.5, 0.5],
///     region: None, // the whole box
///     speeds: Speeds::Temperature(1.0),
///     drift: [0.0, 0.0],
///     seed: 7,
/// };
/// let mut discs = scene::gas(&spec, &config)?;
/// assert_eq!(discs, scene::gas(&spec, &config)?); // the same seed, the same discs
/// // A second species placed clear of the first.
/// let small = Gas { count: 100, radius: [0.2, 0.2], seed: 8, ..spec.clone() };
/// discs.extend(scene::gas_among(&small, &config, &discs)?);
/// scene::zero_momentum(&mut discs, &config, [0.0, 0.0]);
/// scene::spin(&mut discs, 0.5, 9); // ω uniform in ±0.5
/// // A dense liquid's start: a lattice at packing 0.7 (random placement stalls near 0.5).
/// let dense = Gas { count: 1426, ..spec.clone() };
/// assert_eq!(scene::packed_gas(&dense, &config, &[])?.len(), 1426);
/// let too_many = Gas { count: scene::MAX_GAS_COUNT as usize + 1, ..spec };
/// assert!(scene::gas(&too_many, &config).is_err());
/// let mut world = World::new(config)?;
/// world.add_particles(discs).unwrap();
/// assert!(world.colliding_pairs().is_empty() && world.stats().momentum[0].abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Gas {
    /// Number of discs.
    pub count: usize,
    /// Smallest and largest radius (equal for one size).
    pub radius: [f64; 2],
    /// Where centres go; `None` means the whole box of the boundary (required when open).
    pub region: Option<([f64; 2], [f64; 2])>,
    /// Velocity distribution.
    pub speeds: Speeds,
    /// Common velocity added to every disc.
    pub drift: [f64; 2],
    /// Random seed: the same seed gives the same discs.
    pub seed: u64,
}

/// A rectangular lattice of equal discs with one common velocity.
///
/// ```
/// use bounce::scene::{Lattice, lattice};
/// let discs = lattice(&Lattice {
///     origin: [1.0, 1.0],
///     spacing: [2.0, 3.0],
///     counts: [4, 2],
///     radius: 0.5,
///     velocity: [1.0, 0.0],
/// });
/// assert_eq!(discs.len(), 8);
/// assert_eq!((discs[0].position, discs[7].position), ([1.0, 1.0], [7.0, 4.0])); // row by row
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lattice {
    /// Centre of the first disc.
    pub origin: [f64; 2],
    /// Distance between neighbouring centres along x and y.
    pub spacing: [f64; 2],
    /// Discs along x and y.
    pub counts: [usize; 2],
    /// Radius of every disc.
    pub radius: f64,
    /// Velocity of every disc.
    pub velocity: [f64; 2],
}

/// Why a generator could not produce its discs.
///
/// ```
/// use bounce::scene::{self, Gas, SceneError, Speeds};
/// use bounce::{Boundary, Config};
/// let config = Config { boundary: Boundary::walls([0.0, 0.0], [5.0, 5.0]), ..Config::default() };
/// let crowd = Gas {
///     count: 1000,
///     radius: [0.5, 0.5],
///     region: None,
///     speeds: Speeds::Fixed(1.0),
///     drift: [0.0, 0.0],
///     seed: 1,
/// };
/// assert!(matches!(scene::gas(&crowd, &config), Err(SceneError::CannotPlace { .. })));
/// // `packed_gas` starts discs on a lattice instead: dense packings random placement
/// // cannot reach (here 40 discs, packing 0.31, in a box twice the size).
/// let roomy = Config { boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]), ..config };
/// assert_eq!(scene::packed_gas(&Gas { count: 40, ..crowd }, &roomy, &[])?.len(), 40);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Error)]
pub enum SceneError {
    /// Random placement ran out of attempts.
    #[error(
        "could only place {placed} of {requested} discs without overlap: use fewer or smaller discs, or a larger region"
    )]
    CannotPlace {
        /// Discs placed before giving up.
        placed: usize,
        /// Discs asked for.
        requested: usize,
    },
    /// A parameter is out of range.
    #[error("invalid `{field}` = {value}: {expected}")]
    Invalid {
        /// The parameter.
        field: &'static str,
        /// Its value.
        value: String,
        /// What it must be.
        expected: &'static str,
    },
}

/// Attempts per disc before random placement gives up.
const ATTEMPTS: usize = 2000;

fn invalid(field: &'static str, value: String, expected: &'static str) -> SceneError {
    SceneError::Invalid {
        field,
        value,
        expected,
    }
}

/// Places a random gas for `config`. Fails if the spec is invalid or the discs do not fit.
/// See [`Gas`] for an example.
pub fn gas(spec: &Gas, config: &Config) -> Result<Vec<Particle>, SceneError> {
    gas_among(spec, config, &[])
}

/// The most discs one generator places: a larger `count` is refused as a [`SceneError`].
/// See [`Gas`] for an example.
pub const MAX_GAS_COUNT: u64 = 1 << 40;

/// A rectangle: lower-left and upper-right corners.
type Region = ([f64; 2], [f64; 2]);

/// Checks a gas spec (count, radii, speeds, region) and returns the geometry and the region
/// its centres go in: the spec's, else the box.
fn checked_region(spec: &Gas, config: &Config) -> Result<(Geometry, Region), SceneError> {
    let [r_lo, r_hi] = spec.radius;
    if spec.count as u64 > MAX_GAS_COUNT {
        return Err(invalid(
            "count",
            spec.count.to_string(),
            "at most 2^40 discs per generator",
        ));
    }
    if !(r_lo.is_finite() && r_lo > 0.0 && r_hi.is_finite() && r_hi >= r_lo) {
        return Err(invalid(
            "radius",
            format!("{:?}", spec.radius),
            "finite, > 0, min <= max",
        ));
    }
    let speed_ok = match spec.speeds {
        Speeds::Fixed(v) | Speeds::Uniform(v) | Speeds::Temperature(v) => v.is_finite() && v >= 0.0,
    };
    if !speed_ok || !spec.drift.iter().all(|v| v.is_finite()) {
        return Err(invalid(
            "speeds",
            format!("{:?}, drift {:?}", spec.speeds, spec.drift),
            "finite and >= 0",
        ));
    }
    let geometry = Geometry::new(config);
    let (min, max) = spec
        .region
        .or(geometry.bounds())
        .ok_or_else(|| invalid("region", "none".into(), "required in an open world"))?;
    if !(min.iter().chain(&max).all(|v| v.is_finite()) && min[0] < max[0] && min[1] < max[1]) {
        return Err(invalid(
            "region",
            format!("{min:?}..{max:?}"),
            "finite with min < max",
        ));
    }
    Ok((geometry, (min, max)))
}

/// Places a random gas for `config` whose discs keep clear of `existing` ones (placed by
/// earlier generators) and of each other. Fails if the spec is invalid or the discs do not fit.
///
/// The work per attempt is bounded by the discs placed so far, whatever the radii, the
/// collision_radius_scale or the region's size. See [`Gas`] for an example.
pub fn gas_among(
    spec: &Gas,
    config: &Config,
    existing: &[Particle],
) -> Result<Vec<Particle>, SceneError> {
    let (geometry, (min, max)) = checked_region(spec, config)?;
    let [r_lo, r_hi] = spec.radius;
    let periodic = geometry.is_periodic();
    let law = Law::new(config);
    let mut rng = Pcg64Mcg::seed_from_u64(spec.seed);

    // Largest first: big discs are hardest to fit late.
    let mut radii: Vec<f64> = (0..spec.count)
        .map(|_| r_lo + (r_hi - r_lo) * rng.random::<f64>())
        .collect();
    radii.sort_by(|a, b| b.total_cmp(a));

    // A placement grid with cells no smaller than the largest interaction diameter.
    let size = [max[0] - min[0], max[1] - min[1]];
    let reach = law.interaction_diameter(r_hi);
    let n = [0, 1].map(|a| ((size[a] / reach).floor() as usize).clamp(1, 4096));
    // Cell lists as linked lists through two flat arrays (a head per cell, a next per disc):
    // a million discs cost 8 MB here, not a Vec per cell.
    const NONE: u32 = u32::MAX;
    let mut head = vec![NONE; n[0] * n[1]];
    let mut next: Vec<u32> = Vec::with_capacity(spec.count + existing.len());
    let cell_of = |p: [f64; 2]| -> [usize; 2] {
        [0, 1].map(|a| (((p[a] - min[a]) / size[a] * n[a] as f64) as usize).min(n[a] - 1))
    };
    let min_image = geometry.min_image();
    // Every disc to keep clear of, earlier generators' first: (centre, radius).
    let mut all: Vec<([f64; 2], f64)> = Vec::with_capacity(spec.count + existing.len());
    for q in existing {
        let cell = cell_of(q.position);
        let cell = cell[1] * n[0] + cell[0];
        next.push(head[cell]);
        head[cell] = all.len() as u32;
        all.push((q.position, q.radius));
    }
    // Obstacles keep discs off them too (at their starting places).
    let obstacles = obstacle_grid(config, r_hi);
    // Partners reach at most this far.
    let r_far = existing.iter().map(|q| q.radius).fold(r_hi, f64::max);
    let mut placed: Vec<Particle> = Vec::with_capacity(spec.count);
    for &r in &radii {
        // Centres keep a radius from walls (and from an open region's edge).
        let margin = if periodic { 0.0 } else { r };
        if 2.0 * margin >= size[0] || 2.0 * margin >= size[1] {
            return Err(SceneError::CannotPlace {
                placed: placed.len(),
                requested: spec.count,
            });
        }
        let mut found = None;
        'attempt: for _ in 0..ATTEMPTS {
            let pos =
                [0, 1].map(|a| min[a] + margin + (size[a] - 2.0 * margin) * rng.random::<f64>());
            let pos = [0, 1].map(|a| if pos[a] >= max[a] { min[a] } else { pos[a] });
            let c = cell_of(pos);
            if obstacles.as_ref().is_some_and(|o| o.blocks(pos, r, &law)) {
                continue 'attempt;
            }
            let clear = |q: &([f64; 2], f64)| {
                let diff = min_image.diff(pos[0], pos[1], q.0[0], q.0[1]);
                !law.is_colliding(diff, r, q.1)
            };
            // Large discs reach further than one cell of the placement grid (at most the
            // whole grid).
            let pair_reach = law.collision_distance(r, r_far);
            let span = [0, 1].map(|a| {
                let cells = (pair_reach / size[a] * n[a] as f64).ceil();
                (cells.min(n[a] as f64) as isize).max(1)
            });
            let window = (2 * span[0] + 1) as usize * (2 * span[1] + 1) as usize;
            if window > all.len() {
                // Fewer discs than cells to visit: test them all.
                if all.iter().all(clear) {
                    found = Some((pos, c));
                    break;
                }
                continue 'attempt;
            }
            for dy in -span[1]..=span[1] {
                for dx in -span[0]..=span[0] {
                    let (cx, cy) = (c[0] as isize + dx, c[1] as isize + dy);
                    let (cx, cy) = if periodic {
                        (cx.rem_euclid(n[0] as isize), cy.rem_euclid(n[1] as isize))
                    } else if cx < 0 || cy < 0 || cx >= n[0] as isize || cy >= n[1] as isize {
                        continue;
                    } else {
                        (cx, cy)
                    };
                    let mut j = head[cy as usize * n[0] + cx as usize];
                    while j != NONE {
                        let q = &all[j as usize];
                        j = next[j as usize];
                        if !clear(q) {
                            continue 'attempt;
                        }
                    }
                }
            }
            found = Some((pos, c));
            break;
        }
        let Some((pos, c)) = found else {
            return Err(SceneError::CannotPlace {
                placed: placed.len(),
                requested: spec.count,
            });
        };
        let cell = c[1] * n[0] + c[0];
        next.push(head[cell]);
        head[cell] = all.len() as u32;
        all.push((pos, r));
        placed.push(Particle::new(pos, [0.0, 0.0], r));
    }

    set_velocities(&mut placed, spec, config, &mut rng);
    Ok(placed)
}

/// The obstacles of `config` at their starting places, binned for discs up to `r_max`, or
/// `None` without obstacles.
fn obstacle_grid(config: &Config, r_max: f64) -> Option<Obstacles> {
    (!config.obstacles.is_empty()).then(|| {
        let states = vec![ObstacleState::default(); config.obstacles.len()];
        Obstacles::new(config, &states, r_max)
    })
}

/// Draws every disc's velocity from `spec.speeds`, plus the drift.
fn set_velocities(placed: &mut [Particle], spec: &Gas, config: &Config, rng: &mut Pcg64Mcg) {
    for p in placed {
        let v = match spec.speeds {
            Speeds::Fixed(speed) => {
                let angle = std::f64::consts::TAU * rng.random::<f64>();
                [speed * libm::cos(angle), speed * libm::sin(angle)]
            }
            Speeds::Uniform(a) => [0, 1].map(|_| a * (2.0 * rng.random::<f64>() - 1.0)),
            Speeds::Temperature(kt) => {
                let m = config
                    .mass_model
                    .mass(p.radius, std::f64::consts::PI * p.radius * p.radius);
                let sigma = (kt / m).sqrt();
                let [a, b] = standard_normal_pair(rng);
                [sigma * a, sigma * b]
            }
        };
        p.velocity = [v[0] + spec.drift[0], v[1] + spec.drift[1]];
    }
}

/// A dense gas: the discs start on a triangular lattice filling the region evenly (sites
/// drawn at random when there are more than discs), keeping clear of `existing` discs, with
/// velocities as [`gas`] gives them. Reaches packings random placement cannot (0.7 and
/// beyond, up to the lattice's 0.9); run it a while to melt the lattice into a liquid. See
/// [`Gas`] for an example.
pub fn packed_gas(
    spec: &Gas,
    config: &Config,
    existing: &[Particle],
) -> Result<Vec<Particle>, SceneError> {
    let (geometry, (min, max)) = checked_region(spec, config)?;
    let law = Law::new(config);
    let periodic = geometry.is_periodic();
    let [r_lo, r_hi] = spec.radius;
    let margin = if periodic { 0.0 } else { r_hi };
    let size = [
        max[0] - min[0] - 2.0 * margin,
        max[1] - min[1] - 2.0 * margin,
    ];
    let cannot = |placed| SceneError::CannotPlace {
        placed,
        requested: spec.count,
    };
    if spec.count == 0 {
        return Ok(Vec::new());
    }
    if !(size[0] > 0.0 && size[1] > 0.0) {
        return Err(cannot(0));
    }
    // Obstacles take lattice sites: with them, try lattices with room to spare.
    let obstacles = obstacle_grid(config, r_hi);
    let headroom: &[f64] = if obstacles.is_some() {
        &[1.0, 1.25, 1.5, 2.0, 3.0]
    } else {
        &[1.0]
    };
    let min_image = geometry.min_image();
    let mut placed = Vec::with_capacity(spec.count);
    let mut rng = Pcg64Mcg::seed_from_u64(spec.seed);
    for (attempt, &extra) in headroom.iter().enumerate() {
        // Rows √3/2 of the column spacing apart fill a triangular lattice; an even number of
        // rows keeps the stagger continuous across a periodic box.
        let count = (spec.count as f64 * extra).ceil();
        let mut nx = (count * size[0] / size[1] * 3f64.sqrt() / 2.0)
            .sqrt()
            .ceil()
            .max(1.0);
        let mut ny = (count / nx).ceil().max(1.0);
        if periodic && ny % 2.0 == 1.0 && ny > 1.0 {
            ny += 1.0;
            nx = (count / ny).ceil().max(1.0);
        }
        if nx * ny > 4.0 * count + 64.0 || !(nx * ny).is_finite() {
            return Err(cannot(0));
        }
        let (nx, ny) = (nx as usize, ny as usize);
        let spacing = [size[0] / nx as f64, size[1] / ny as f64];
        let nearest =
            spacing[0].min((0.25 * spacing[0] * spacing[0] + spacing[1] * spacing[1]).sqrt());
        if nearest <= law.interaction_diameter(r_hi) {
            if attempt > 0 {
                break;
            }
            return Err(SceneError::Invalid {
                field: "count",
                value: spec.count.to_string(),
                expected: "few enough for a lattice of discs this size to fit the region",
            });
        }
        rng = Pcg64Mcg::seed_from_u64(spec.seed);
        let mut sites: Vec<usize> = (0..nx * ny).collect();
        // Fisher–Yates: which sites get a disc.
        for k in (1..sites.len()).rev() {
            let j = (rng.random::<f64>() * (k + 1) as f64) as usize;
            sites.swap(k, j.min(k));
        }
        placed.clear();
        for &site in &sites {
            if placed.len() == spec.count {
                break;
            }
            let (i, j) = (site % nx, site / nx);
            let stagger = if j % 2 == 1 { 0.5 } else { 0.0 };
            let position = [
                min[0] + margin + (i as f64 + 0.25 + stagger) * spacing[0],
                min[1] + margin + (j as f64 + 0.5) * spacing[1],
            ];
            let r = r_lo + (r_hi - r_lo) * rng.random::<f64>();
            // Sites on an obstacle stay empty.
            let clear = !obstacles
                .as_ref()
                .is_some_and(|o| o.blocks(position, r, &law))
                && existing.iter().all(|q| {
                    let [dx, dy] =
                        min_image.diff(position[0], position[1], q.position[0], q.position[1]);
                    !law.is_colliding([dx, dy], r, q.radius)
                });
            if clear {
                placed.push(Particle::new(position, [0.0, 0.0], r));
            }
        }
        if placed.len() == spec.count {
            break;
        }
    }
    if placed.len() < spec.count {
        return Err(cannot(placed.len()));
    }
    // Storage in lattice order (neighbours near each other), velocities drawn after.
    placed.sort_by(|a, b| {
        (a.position[1], a.position[0])
            .partial_cmp(&(b.position[1], b.position[0]))
            .expect("finite")
    });
    set_velocities(&mut placed, spec, config, &mut rng);
    Ok(placed)
}

/// Removes the net momentum of `discs` (under `config`'s mass model), then adds `drift` to
/// every velocity: a generator's `temperature = kT` otherwise leaves a net momentum of about
/// √N thermal momenta. See [`Gas`] for an example.
pub fn zero_momentum(discs: &mut [Particle], config: &Config, drift: [f64; 2]) {
    let mass = |p: &Particle| {
        config.mass_model.mass(
            p.radius,
            p.mass.unwrap_or(std::f64::consts::PI * p.radius * p.radius),
        )
    };
    let (mut total, mut momentum) = (0.0, [0.0, 0.0]);
    for p in discs.iter() {
        let m = mass(p);
        total += m;
        momentum[0] += m * (p.velocity[0] - drift[0]);
        momentum[1] += m * (p.velocity[1] - drift[1]);
    }
    if total > 0.0 {
        for p in discs.iter_mut() {
            p.velocity[0] -= momentum[0] / total;
            p.velocity[1] -= momentum[1] / total;
        }
    }
}

/// Gives every disc an angular velocity uniform in `[-spin, spin]`, drawn from `seed` apart
/// from the draws that placed the discs (a gas with and without spin has the same places and
/// velocities). See [`Gas`] for an example.
pub fn spin(discs: &mut [Particle], spin: f64, seed: u64) {
    let mut rng = Pcg64Mcg::seed_from_u64(seed ^ 0x5350_494e_5350_494e);
    for p in discs {
        p.angular_velocity = spin * (2.0 * rng.random::<f64>() - 1.0);
    }
}

/// Two independent standard normal numbers (Box–Muller).
fn standard_normal_pair(rng: &mut Pcg64Mcg) -> [f64; 2] {
    // 1 - u is in (0, 1], so the logarithm is finite.
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    let radius = (-2.0 * libm::log(u1)).sqrt();
    let angle = std::f64::consts::TAU * u2;
    [radius * libm::cos(angle), radius * libm::sin(angle)]
}

/// The discs of a lattice, row by row. See [`Lattice`] for an example.
pub fn lattice(spec: &Lattice) -> Vec<Particle> {
    let mut out = Vec::with_capacity(spec.counts[0] * spec.counts[1]);
    for j in 0..spec.counts[1] {
        for i in 0..spec.counts[0] {
            let pos = [
                spec.origin[0] + i as f64 * spec.spacing[0],
                spec.origin[1] + j as f64 * spec.spacing[1],
            ];
            out.push(Particle::new(pos, spec.velocity, spec.radius));
        }
    }
    out
}

/// The 2D Maxwell–Boltzmann speed distribution (a Rayleigh distribution): the probability
/// that a disc of mass `m` at temperature `kt` has speed at most `v`.
///
/// ```
/// use bounce::scene::{maxwell_boltzmann_cdf, maxwell_boltzmann_pdf, temperature};
/// // The most probable speed is √(kT/m), where the cdf is 1 − e^(−1/2).
/// assert!((maxwell_boltzmann_cdf(1.0, 2.0, 2.0) - (1.0 - (-0.5f64).exp())).abs() < 1e-15);
/// assert_eq!(maxwell_boltzmann_pdf(0.0, 2.0, 2.0), 0.0);
/// assert_eq!(temperature(50.0, 100), 0.5); // ½ m v² = kT a disc in 2D
/// ```
pub fn maxwell_boltzmann_cdf(v: f64, kt: f64, m: f64) -> f64 {
    1.0 - (-m * v * v / (2.0 * kt)).exp()
}

/// Its density: `m v / kT · exp(-m v² / 2kT)`. See [`maxwell_boltzmann_cdf`] for an example.
pub fn maxwell_boltzmann_pdf(v: f64, kt: f64, m: f64) -> f64 {
    m * v / kt * (-m * v * v / (2.0 * kt)).exp()
}

/// The temperature `kT` of `count` discs from their total kinetic energy (in the frame where
/// the total momentum is zero): in 2D, equipartition gives `<½ m v²> = kT` per disc. See
/// [`maxwell_boltzmann_cdf`] for an example.
pub fn temperature(kinetic_energy: f64, count: usize) -> f64 {
    kinetic_energy / count.max(1) as f64
}
