//! Helpers shared by the integration tests.
#![allow(dead_code)]

use bounce::scene::{self, Gas, Speeds};
use bounce::{Config, World};

/// A world of `count` discs from a gas spec, with the given config.
pub fn gas_world(
    config: Config,
    count: usize,
    radius: [f64; 2],
    speeds: Speeds,
    drift: [f64; 2],
    seed: u64,
) -> World {
    let discs = scene::gas(
        &Gas {
            count,
            radius,
            region: None,
            speeds,
            drift,
            seed,
        },
        &config,
    )
    .expect("gas fits");
    let mut world = World::new(config).expect("valid config");
    world.add_particles(discs).expect("valid discs");
    world
}

/// Side of a square box holding `count` discs of mean squared radius `r2` at packing `phi`.
pub fn box_side(count: usize, r2: f64, phi: f64) -> f64 {
    (count as f64 * std::f64::consts::PI * r2 / phi).sqrt()
}

/// `|a - b| <= tol * max(|b|, 1e-300)`.
pub fn assert_rel(a: f64, b: f64, tol: f64, what: &str) {
    let rel = (a - b).abs() / b.abs().max(1e-300);
    assert!(
        rel <= tol,
        "{what}: {a} vs {b}, relative difference {rel:e} > {tol:e}"
    );
}

/// `|a - b| <= tol`.
pub fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol,
        "{what}: {a} vs {b} (tolerance {tol:e})"
    );
}

/// `count` discs of radius 0.5 at kT = 1 on a triangular lattice filling `config`'s box
/// (a gas that melts; no two discs overlap, as exact hard discs need).
pub fn lattice_gas(config: &Config, count: usize, seed: u64) -> Vec<bounce::Particle> {
    scene::packed_gas(
        &Gas {
            count,
            radius: [0.5, 0.5],
            region: None,
            speeds: Speeds::Temperature(1.0),
            drift: [0.0, 0.0],
            seed,
        },
        config,
        &[],
    )
    .expect("a lattice fits")
}

/// Uniform numbers in `[0, 1)` from a xorshift generator started at `seed` (not 0): the same
/// sequence on every machine.
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}
