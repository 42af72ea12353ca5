//! `bounce-bench events`: the event-driven method's speed, in collisions per second on one
//! core, and its compressibility factor, for a periodic gas of equal discs (radius 0.5,
//! kT = 1, the seed's mass = radius) started on a lattice, melted for `time`, then measured
//! over `time` more. No peer yet: see BENCHMARKS.md.

use std::time::Instant;

use anyhow::Result;
use bounce::event::EventDriven;
use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config};

/// Measures each count in `counts`.
pub fn run(counts: &[usize], packing: f64, time: f64, machine: &str) -> Result<()> {
    println!("{machine}");
    println!("| N | packing | collisions | collisions per second | Z | engine bytes a disc |");
    println!("|---|---|---|---|---|---|");
    for &n in counts {
        let side = (n as f64 * std::f64::consts::PI * 0.25 / packing).sqrt();
        let config = Config {
            boundary: Boundary::periodic([0.0, 0.0], [side, side]),
            ..Config::default()
        };
        let gas = Gas {
            count: n,
            radius: [0.5, 0.5],
            region: None,
            speeds: Speeds::Temperature(1.0),
            drift: [0.0, 0.0],
            seed: 1,
        };
        let discs = scene::packed_gas(&gas, &config, &[])?;
        let mut world = EventDriven::new(&config, &discs)?;
        drop(discs);
        world.advance(time)?;
        let start = Instant::now();
        let seen = world.advance(time)?;
        let spent = start.elapsed().as_secs_f64();
        let kt = world.kinetic_energy() / n as f64;
        let z = 1.0 + seen.virial / (2.0 * time * n as f64 * kt);
        println!(
            "| {n} | {packing} | {} | {:.3e} | {z:.4} | {:.0} |",
            seen.collisions,
            seen.collisions as f64 / spent,
            world.memory_bytes() as f64 / n as f64
        );
    }
    Ok(())
}
