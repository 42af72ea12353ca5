//! Per-stage time of the benchmark scenes:
//! `cargo run --release --example profile [COUNT] [THREADS] [STEPS] [gas|pile|poly]`.

use bounce::scene::{self, Speeds};
use bounce::{StepProfile, World};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let count: usize = args
        .next()
        .map(|a| a.parse())
        .transpose()?
        .unwrap_or(1_000_000);
    let threads: usize = args.next().map(|a| a.parse()).transpose()?.unwrap_or(1);
    let steps: usize = args.next().map(|a| a.parse()).transpose()?.unwrap_or(20);
    let kind = args.next().unwrap_or_else(|| "gas".into());
    let radius = if kind == "poly" {
        [0.1, 2.5]
    } else {
        [0.5, 0.5]
    };
    let (mut config, discs) = scene::gas_in_walls(count, radius, 0.3, Speeds::Uniform(2.0), 1)?;
    if kind == "pile" {
        config.gravity = [0.0, -9.81];
        config.coefficient_of_restitution = 0.7;
        config.substeps = 4;
    }
    let mut world = World::new(config)?;
    world
        .add_particles(discs)
        .map_err(|(i, e)| format!("{i}: {e}"))?;
    world.set_threads(threads)?;
    let mut sum = StepProfile::default();
    let mut totals = Vec::new();
    let mut pairs = 0;
    let mut rebuilds = 0;
    let mut rebuild_ms = Vec::new();
    for _ in 0..steps {
        pairs += world.step(1.0 / 60.0)?.pairs;
        let p = world.profile();
        totals.push(p.total());
        rebuilds += p.rebuilds;
        if p.rebuilds > 0 {
            rebuild_ms.push(format!("{:.1}", p.bin * 1e3));
        }
        sum.integrate += p.integrate;
        sum.bin += p.bin;
        sum.pairs += p.pairs;
        sum.resolve += p.resolve;
        sum.measure += p.measure;
    }
    let ms = |s: f64| s * 1e3 / steps as f64;
    totals.sort_by(f64::total_cmp);
    println!(
        "{kind} {count} discs, {threads} threads, {} colliding pairs per step, {rebuilds} rebuilds in {steps} steps, median {:.2} ms/step; mean ms/step: integrate {:.2} bin {:.2} pairs {:.2} resolve {:.2} measure {:.2} total {:.2}",
        pairs / steps,
        totals[steps / 2] * 1e3,
        ms(sum.integrate),
        ms(sum.bin),
        ms(sum.pairs),
        ms(sum.resolve),
        ms(sum.measure),
        ms(sum.total())
    );
    println!("rebuild ms: {}", rebuild_ms.join(" "));
    Ok(())
}
