//! Per-stage time of the benchmark scenes, for profiling one change at a time:
//! `cargo run --release --example profile [COUNT] [THREADS] [STEPS] [gas|pile|poly|fast] [SETTLED]`.
//!
//! `pile` is the gas's discs under gravity (e = 0.7, 4 substeps). With `SETTLED`, a file of
//! little-endian `f64` triples (x, y, radius), such as the benchmark harness's settled pile
//! (`target/bench/cache/pile-settled-100k.f64`), the discs start there at rest and the first
//! 30 steps are not timed; else the first 4, as in the harness (the first step sorts the
//! discs from the order they were made in, a one-off several rebuilds long). Prints the mean, median and 99th percentile ms per step (rebuilds
//! included) and the mean per stage, and the most discs past the allowance that a substep
//! met alone instead of listing anew (strays). `MIN_WORK=N` in the environment sets the smallest work
//! that runs on the pool (`World::set_parallel_min_work`); `RELIST=1` lists the candidates
//! anew every step (`World::relist`), so the rebuild's own cost can be timed over many.
//! `TENSOR=1` measures the pressure tensor and `COUNTS=1` counts each disc's collisions.

use bounce::scene::Bench;
use bounce::{Particle, StepProfile, World};

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
    let settled = args.next();
    let scene = match kind.as_str() {
        "pile" => Bench::Pile,
        "poly" => Bench::Poly,
        "fast" => Bench::Fast,
        _ => Bench::Gas,
    };
    let (mut config, mut discs) = scene.build(count)?;
    // What a run may record besides the state: the pressure tensor and each disc's collisions.
    config.pressure_tensor = std::env::var_os("TENSOR").is_some();
    config.collision_counts = std::env::var_os("COUNTS").is_some();
    let mut warm_up = 4;
    if scene == Bench::Pile
        && let Some(path) = settled
    {
        let bytes = std::fs::read(&path)?;
        let f = |k: usize| f64::from_le_bytes(bytes[8 * k..8 * k + 8].try_into().unwrap());
        discs = (0..bytes.len() / 24)
            .map(|i| Particle::new([f(3 * i), f(3 * i + 1)], [0.0, 0.0], f(3 * i + 2)))
            .collect();
        warm_up = 30;
    }
    let mut world = World::new(config)?;
    world
        .add_particles(discs)
        .map_err(|(i, e)| format!("{i}: {e}"))?;
    world.set_threads(threads)?;
    if let Some(work) = std::env::var("MIN_WORK").ok().and_then(|v| v.parse().ok()) {
        world.set_parallel_min_work(work);
    }
    for _ in 0..warm_up {
        world.step(Bench::DT)?;
    }
    let mut sum = StepProfile::default();
    let mut totals = Vec::new();
    let mut pairs = 0;
    let mut rebuilds = 0;
    let mut strays = 0;
    let mut rebuild_ms = Vec::new();
    let mut rebuild_times = Vec::new();
    let relist = std::env::var_os("RELIST").is_some();
    for _ in 0..steps {
        if relist {
            world.relist();
        }
        let clock = std::time::Instant::now();
        pairs += world.step(Bench::DT)?.pairs;
        totals.push(clock.elapsed().as_secs_f64());
        let p = world.profile();
        rebuilds += p.rebuilds;
        strays = strays.max(p.strays);
        if p.rebuilds > 0 {
            rebuild_ms.push(format!("{:.1}", p.bin * 1e3));
            rebuild_times.push(p.bin * 1e3);
        }
        sum.integrate += p.integrate;
        sum.bin += p.bin;
        sum.pairs += p.pairs;
        sum.resolve += p.resolve;
        sum.obstacles += p.obstacles;
        sum.walls += p.walls;
        sum.measure += p.measure;
    }
    let ms = |s: f64| s * 1e3 / steps as f64;
    let mean = totals.iter().sum::<f64>() / steps as f64;
    totals.sort_by(f64::total_cmp);
    let quantile = |q: f64| totals[((steps - 1) as f64 * q).round() as usize] * 1e3;
    println!(
        "{kind} {} discs, {threads} threads, {} contacts per step, {rebuilds} rebuilds in {steps} steps (at most {strays} strays kept), state {:016x}",
        world.len(),
        pairs / steps,
        world.state_hash()
    );
    println!(
        "ms/step: mean {:.3} median {:.3} p99 {:.3}; stages (mean): integrate {:.3} bin {:.3} pairs {:.3} resolve {:.3} obstacles {:.3} walls {:.3} measure {:.3}",
        mean * 1e3,
        quantile(0.5),
        quantile(0.99),
        ms(sum.integrate),
        ms(sum.bin),
        ms(sum.pairs),
        ms(sum.resolve),
        ms(sum.obstacles),
        ms(sum.walls),
        ms(sum.measure),
    );
    println!("rebuild ms: {}", rebuild_ms.join(" "));
    if relist {
        let mut times = rebuild_times;
        times.sort_by(f64::total_cmp);
        if let (Some(min), Some(median)) = (times.first(), times.get(times.len() / 2)) {
            println!("rebuild ms: min {min:.3} median {median:.3}");
        }
    }
    Ok(())
}
