//! A gas of equal discs in a walled box: prints energy and collision counts as it relaxes.
//!
//! `cargo run --release --example gas [COUNT] [STEPS]` (defaults: 10,000 discs, 600 steps).

use bounce::World;
use bounce::scene::{self, Speeds};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let count: usize = args
        .next()
        .map(|a| a.parse())
        .transpose()?
        .unwrap_or(10_000);
    let steps: u64 = args.next().map(|a| a.parse()).transpose()?.unwrap_or(600);
    let threads: usize = std::thread::available_parallelism().map_or(1, |n| n.get());

    // Radius 0.5 at packing fraction 0.3, all at speed 1 in random directions.
    let (config, discs) = scene::gas_in_walls(count, [0.5, 0.5], 0.3, Speeds::Fixed(1.0), 1)?;
    let side = config.boundary.bounds().map_or(0.0, |(_, max)| max[0]);
    let mut world = World::new(config)?;
    world
        .add_particles(discs)
        .map_err(|(i, e)| format!("disc {i}: {e}"))?;
    world.set_threads(threads)?;
    let e0 = world.stats().kinetic_energy;
    println!("{count} discs in a {side:.1} x {side:.1} box, {threads} threads");
    println!(
        "{:>6} {:>14} {:>12} {:>10}",
        "step", "energy", "collisions", "overlap"
    );
    let start = std::time::Instant::now();
    for step in 1..=steps {
        let stats = world.step(1.0 / 60.0)?;
        if step % (steps / 10).max(1) == 0 {
            println!(
                "{step:>6} {:>14.6} {:>12} {:>10.2e}",
                stats.kinetic_energy, stats.pairs, stats.max_overlap
            );
        }
    }
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "{steps} steps in {elapsed:.2} s ({:.2} ms/step); energy change {:+.3e} (relative)",
        elapsed * 1e3 / steps as f64,
        world.stats().kinetic_energy / e0 - 1.0
    );
    Ok(())
}
