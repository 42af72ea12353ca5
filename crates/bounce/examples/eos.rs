//! The time-step bias of the pressure: the compressibility factor Z = P A / (N kT) of a
//! hard-disc gas in a periodic box (the seed's model, equal discs of radius 0.5, started on a
//! lattice and melted), against mean speed × dt / σ, next to Henderson's equation of state
//! (within about 1% of Monte Carlo up to packing 0.6).
//! `cargo run --release --example eos [DISCS]`.

use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config, World};

/// Z at `packing` with steps of `dt`; speeds start at 1 (mean speed of the relaxed gas
/// sqrt(π/4) ≈ 0.886).
fn z(packing: f64, discs: usize, dt: f64) -> f64 {
    let side = (discs as f64 * std::f64::consts::PI * 0.25 / packing).sqrt();
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        ..Config::default()
    };
    let gas = Gas {
        count: discs,
        radius: [0.5, 0.5],
        region: None,
        speeds: Speeds::Fixed(1.0),
        drift: [0.0, 0.0],
        seed: 1,
    };
    let mut placed = scene::packed_gas(&gas, &config, &[]).unwrap();
    scene::zero_momentum(&mut placed, &config, [0.0, 0.0]);
    let mut world = World::new(config).unwrap();
    world.add_particles(placed).unwrap();
    world.set_threads(2).unwrap();
    let (settle, run) = ((10.0 / dt) as usize, (20.0 / dt) as usize);
    for _ in 0..settle {
        world.step(dt).unwrap();
    }
    let (mut p, mut ke) = (0.0, 0.0);
    for _ in 0..run {
        let s = world.step(dt).unwrap();
        p += s.pressure.unwrap();
        ke += s.kinetic_energy;
    }
    p * side * side / ke
}

fn main() {
    let discs: usize = std::env::args().nth(1).map_or(2000, |a| a.parse().unwrap());
    let v_bar = (std::f64::consts::PI / 4.0).sqrt();
    println!("| packing | v̄·dt/σ | Z | Henderson | bias |");
    println!("|---|---|---|---|---|");
    for packing in [0.1, 0.3, 0.5] {
        let henderson = (1.0 + packing * packing / 8.0) / ((1.0 - packing) * (1.0 - packing));
        for dt in [0.0025, 0.0075, 0.034, 0.05] {
            let z = z(packing, discs, dt);
            println!(
                "| {packing} | {:.4} | {z:.3} | {henderson:.3} | {:+.1}% |",
                v_bar * dt,
                (z / henderson - 1.0) * 100.0
            );
        }
    }
}
