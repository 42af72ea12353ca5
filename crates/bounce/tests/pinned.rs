//! The pinned state hashes of the benchmark scenes (`scene::Bench`), at a test's size, on 1
//! and 2 threads.
//!
//! A refactor keeps these bits. A change that moves one changes the physics: make it on
//! purpose, and say why in the change. (The shipped templates are pinned in
//! `crates/bounce-scenario/tests/pinned.rs`.)

use bounce::World;
use bounce::scene::Bench;

/// `(scene, discs, steps, state hash)`.
const SCENES: [(Bench, usize, usize, u64); 4] = [
    (Bench::Gas, 20_000, 100, 0x9892_e0c8_a288_8b33),
    (Bench::Pile, 20_000, 100, 0x7f04_2a16_3485_955a),
    (Bench::Poly, 20_000, 100, 0xfcf2_a1a0_7ac9_0527),
    (Bench::Fast, 20_000, 100, 0x227d_c7c9_0811_41d3),
];

fn hash_after(scene: Bench, count: usize, steps: usize, threads: usize) -> u64 {
    let (config, discs) = scene.build(count).unwrap();
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world.set_threads(threads).unwrap();
    // Every parallel path runs.
    world.set_parallel_min_work(0);
    for _ in 0..steps {
        world.step(Bench::DT).unwrap();
    }
    world.state_hash()
}

#[test]
fn every_benchmark_scene_keeps_its_bits_on_one_and_two_threads() {
    let mut wrong = Vec::new();
    for (scene, count, steps, pinned) in SCENES {
        for threads in [1, 2] {
            let hash = hash_after(scene, count, steps, threads);
            if hash != pinned {
                wrong.push(format!("{scene:?} on {threads} threads: {hash:#018x}"));
            }
        }
    }
    assert!(wrong.is_empty(), "hashes moved:\n{}", wrong.join("\n"));
}
