//! `cargo bench -p bounce`: milliseconds per step of the gas scene (radius 0.5, packing
//! fraction 0.3, walls, e = 1, velocities uniform in [-2, 2]², dt = 1/60) on one thread.

use bounce::World;
use bounce::scene::Bench;

fn main() {
    divan::main();
}

/// The benchmark gas of `count` discs, settled for a few steps.
fn gas(count: usize) -> World {
    let (config, discs) = Bench::Gas.build(count).expect("gas fits");
    let mut world = World::new(config).expect("valid config");
    world.add_particles(discs).expect("valid discs");
    for _ in 0..5 {
        world.step(Bench::DT).expect("valid dt");
    }
    world
}

#[divan::bench(args = [10_000, 100_000, 1_000_000], sample_count = 20, sample_size = 1)]
fn step_one_thread(bencher: divan::Bencher, count: usize) {
    let mut world = gas(count);
    bencher.bench_local(|| {
        world.step(Bench::DT).expect("valid dt");
    });
}
