//! Collisions per second of the event-driven engine for a periodic hard-disc gas, and its
//! compressibility factor Z = P A / (N kT) from the collision virial:
//! `cargo run --release -p bounce --example events -- N PACKING TIME` (the gas melts for
//! TIME first, then is measured over TIME).

use std::time::Instant;

use bounce::event::EventDriven;
use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(100_000, |a| a.parse().expect("N"));
    let packing: f64 = args.get(2).map_or(0.5, |a| a.parse().expect("PACKING"));
    let time: f64 = args.get(3).map_or(2.0, |a| a.parse().expect("TIME"));
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
    let discs = scene::packed_gas(&gas, &config, &[]).expect("a gas");
    let start = Instant::now();
    let mut world = EventDriven::new(&config, &discs).expect("a world");
    let built = start.elapsed().as_secs_f64();
    world.advance(time).expect("melts");
    let start = Instant::now();
    let seen = world.advance(time).expect("runs");
    let spent = start.elapsed().as_secs_f64();
    let kt = world.kinetic_energy() / n as f64;
    let z = 1.0 + seen.virial / (2.0 * time * n as f64 * kt);
    println!(
        "N {n} packing {packing}: built in {built:.3} s; {} collisions in {spent:.3} s: \
         {:.3e} per second; Z = {z:.4}",
        seen.collisions,
        seen.collisions as f64 / spent
    );
}
