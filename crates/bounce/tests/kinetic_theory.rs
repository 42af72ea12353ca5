//! A gas of equal discs relaxes to the 2D Maxwell–Boltzmann (Rayleigh) speed distribution.

mod common;

use bounce::scene::{Speeds, maxwell_boltzmann_cdf, temperature};
use bounce::{Boundary, Config, World};
use common::{box_side, gas_world};

/// Kolmogorov–Smirnov statistic of the speeds against the Rayleigh distribution at the
/// temperature the speeds themselves give.
fn ks_statistic(world: &World) -> f64 {
    let p = world.particles();
    let mut speeds: Vec<f64> = p
        .vx()
        .iter()
        .zip(p.vy())
        .map(|(vx, vy)| vx.hypot(*vy))
        .collect();
    speeds.sort_by(f64::total_cmp);
    let n = speeds.len() as f64;
    let kt = temperature(world.stats().kinetic_energy, speeds.len());
    let m = 0.5; // mass = radius
    speeds
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let f = maxwell_boltzmann_cdf(v, kt, m);
            (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn equal_speeds_relax_to_maxwell_boltzmann() {
    let count = 2000;
    let side = box_side(count, 0.25, 0.2);
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        ..Config::default()
    };
    let mut world = gas_world(
        config,
        count,
        [0.5, 0.5],
        Speeds::Fixed(1.0),
        [0.0, 0.0],
        42,
    );
    // Critical value of the one-sample KS test at the 1% level: 1.628 / sqrt(n).
    let critical = 1.628 / (count as f64).sqrt();
    let d0 = ks_statistic(&world);
    assert!(
        d0 > 5.0 * critical,
        "all speeds equal is far from Rayleigh: D = {d0}"
    );

    // Mean free time ~ 1 / (n σ v) ≈ 4 time units; run ~25 of them.
    let mut collisions = 0;
    for _ in 0..6000 {
        collisions += world.step(1.0 / 60.0).unwrap().pairs;
    }
    assert!(
        collisions > 10 * count,
        "each disc collides many times: {collisions}"
    );
    let d = ks_statistic(&world);
    assert!(
        d < critical,
        "KS statistic {d} >= critical {critical} at the 1% level"
    );
}
