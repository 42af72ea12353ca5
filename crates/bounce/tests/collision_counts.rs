//! Per-disc collision counts (`Config::collision_counts`): each species of an exact hard-disc
//! mixture collides as often as Enskog's theory says; the counts add up to twice the
//! collisions, change no bit of the motion, follow the discs through reordering, threads,
//! a save and load, and removal.

mod common;

use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config, Method, ParticleId, World};
use std::f64::consts::PI;

/// The 2D Enskog collision frequency of a disc of species `i` (radius `radius[i]`, mass =
/// radius, the seed's model) in a mixture with number densities `density`, at `kt`:
/// `ν_i = Σ_j n_j g_ij σ_ij √(2π kT / μ_ij)`, with `σ_ij = r_i + r_j` the contact distance,
/// `μ_ij` the reduced mass and `g_ij` the contact values of Jenkins & Mancini (1987) for
/// discs, `1/(1−η) + (9/16) η/(1−η)² · d_i d_j M1 / (d_ij M2)` (`d` diameters, `d_ij` their
/// mean, `M_k` the k-th moment of the diameters): Henderson's for one species.
fn enskog_frequency(i: usize, radius: [f64; 2], density: [f64; 2], kt: f64) -> f64 {
    let packing: f64 = (0..2)
        .map(|k| density[k] * PI * radius[k] * radius[k])
        .sum();
    let n: f64 = density.iter().sum();
    let d = radius.map(|r| 2.0 * r);
    let moment = |k: i32| (0..2).map(|j| density[j] / n * d[j].powi(k)).sum::<f64>();
    (0..2)
        .map(|j| {
            let d_ij = 0.5 * (d[i] + d[j]);
            let g = 1.0 / (1.0 - packing)
                + 9.0 / 16.0 * packing / (1.0 - packing).powi(2) * d[i] * d[j] * moment(1)
                    / (d_ij * moment(2));
            let mu = radius[i] * radius[j] / (radius[i] + radius[j]);
            density[j] * g * d_ij * (2.0 * PI * kt / mu).sqrt()
        })
        .sum()
}

#[test]
fn each_species_of_a_hard_disc_mixture_collides_as_often_as_enskog_says() {
    // 1,000 discs of radius 0.6 and 1,000 of 0.3 at packing 0.15, exact hard discs.
    let radius = [0.6, 0.3];
    let packing = 0.15;
    let side = (1000.0 * PI * (0.36 + 0.09) / packing).sqrt();
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        method: Method::EventDriven,
        collision_counts: true,
        ..Config::default()
    };
    let mut discs = Vec::new();
    for (r, seed) in radius.iter().zip([5, 6]) {
        let gas = Gas {
            count: 1000,
            radius: [*r, *r],
            region: None,
            speeds: Speeds::Temperature(1.0),
            drift: [0.0, 0.0],
            seed,
        };
        discs.extend(scene::gas_among(&gas, &config, &discs).unwrap());
    }
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    for _ in 0..40 {
        world.step(0.5).unwrap();
    }
    let start = world.collision_counts().unwrap();
    let (span, mut collisions, mut energy) = (150.0, 0usize, 0.0);
    for _ in 0..300 {
        world.step(span / 300.0).unwrap();
        collisions += world.stats().collisions;
        energy += world.stats().kinetic_energy / 300.0;
    }
    let end = world.collision_counts().unwrap();
    let counted: u64 = end.iter().zip(&start).map(|(a, b)| a - b).sum();
    assert_eq!(
        counted,
        2 * collisions as u64,
        "each collision counts for both discs"
    );
    // Elastic, momentum zero: kT is the mean kinetic energy a disc.
    let kt = energy / 2000.0;
    let density = [1000.0 / (side * side); 2];
    for (i, &r) in radius.iter().enumerate() {
        let (mut sum, mut discs) = (0u64, 0);
        for (id, particle) in world.particles_by_id() {
            if particle.radius == r {
                sum += end[id.0 as usize] - start[id.0 as usize];
                discs += 1;
            }
        }
        let measured = sum as f64 / (discs as f64 * span);
        let theory = enskog_frequency(i, radius, density, kt);
        assert!(
            (measured / theory - 1.0).abs() < 0.02,
            "radius {r}: {measured} collisions per disc per time against Enskog's {theory}"
        );
    }
}

fn walled_gas(counting: bool, threads: usize) -> World {
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [40.0, 40.0]),
        coefficient_of_restitution: 0.95,
        substeps: 2,
        collision_counts: counting,
        ..Config::default()
    };
    let discs = common::lattice_gas(&config, 600, 11);
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world.set_threads(threads).unwrap();
    world.set_parallel_min_work(0);
    world
}

#[test]
fn the_counts_add_up_change_nothing_and_follow_the_discs() {
    let mut plain = walled_gas(false, 1);
    let mut counted = [walled_gas(true, 1), walled_gas(true, 2)];
    let mut previous = vec![0u64; 600];
    for step in 0..300 {
        plain.step(0.02).unwrap();
        for world in &mut counted {
            world.step(0.02).unwrap();
            // The same bits as without counting, on any thread count.
            assert_eq!(world.state_hash(), plain.state_hash(), "step {step}");
        }
        let counts = counted[0].collision_counts().unwrap();
        assert_eq!(Some(&counts), counted[1].collision_counts().as_ref());
        let added: u64 = counts.iter().zip(&previous).map(|(a, b)| a - b).sum();
        assert_eq!(
            added,
            2 * counted[0].stats().collisions as u64,
            "step {step}"
        );
        previous = counts;
    }
    assert!(plain.collision_counts().is_none());
    assert!(previous.iter().sum::<u64>() > 1000, "the gas collided");
    // Saved and loaded, the counts go on as if never saved.
    let bytes = postcard::to_stdvec(&counted[0]).unwrap();
    let mut loaded: World = postcard::from_bytes(&bytes).unwrap();
    for _ in 0..50 {
        loaded.step(0.02).unwrap();
        counted[0].step(0.02).unwrap();
    }
    assert_eq!(loaded.collision_counts(), counted[0].collision_counts());
    // A removed disc keeps its count under its id; the others are unchanged.
    let before = loaded.collision_counts().unwrap();
    loaded.remove_particles(&[ParticleId(7)]);
    assert_eq!(loaded.collision_counts().unwrap(), before);
}
