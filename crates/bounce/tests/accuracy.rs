//! Accuracy under control: tunnelling, walls that hold, and the pressure from the collision
//! virial checked against the walls and against hard-disc theory.

use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config, Particle, RestitutionModel, World};

/// Two discs of radius 0.5 closing at 30 per unit time: each moves 3 diameters per step of
/// 0.1 (found by review: they passed through each other with 0 collisions).
fn head_on(max_travel: Option<f64>) -> World {
    let mut world = World::new(Config {
        max_travel,
        ..Config::default()
    })
    .unwrap();
    world
        .add_particles([
            Particle::new([0.0, 0.0], [15.0, 0.0], 0.5),
            Particle::new([10.25, 0.0], [-15.0, 0.0], 0.5),
        ])
        .unwrap();
    world
}

#[test]
fn fast_discs_tunnel_at_a_fixed_step_and_collide_with_max_travel() {
    let mut fixed = head_on(None);
    let mut pairs = 0;
    for _ in 0..6 {
        pairs += fixed.step(0.1).unwrap().pairs;
    }
    assert_eq!(pairs, 0, "the finding: they pass through each other");
    let by_id = fixed.particles_by_id();
    assert!(by_id[0].1.position[0] > by_id[1].1.position[0]);

    let mut adaptive = head_on(Some(0.5));
    let mut pairs = 0;
    let mut substeps = 0;
    for _ in 0..6 {
        let stats = adaptive.step(0.1).unwrap();
        pairs += stats.pairs;
        substeps = substeps.max(stats.substeps);
    }
    // 1.5 per step over 0.25 per substep: 6 substeps.
    assert_eq!(substeps, 6);
    assert!(pairs > 0);
    let by_id = adaptive.particles_by_id();
    // Equal discs exchanged their velocities and turned back.
    assert_eq!(by_id[0].1.velocity, [-15.0, 0.0]);
    assert_eq!(by_id[1].1.velocity, [15.0, 0.0]);
    assert!(by_id[0].1.position[0] < by_id[1].1.position[0]);
}

#[test]
fn adaptive_substeps_are_the_same_bits_for_any_thread_count() {
    let run = |threads| {
        let mut world = gas_world(0.3, 4.0, 11, Some(0.25));
        world.set_threads(threads).unwrap();
        world.set_parallel_min_work(0);
        for _ in 0..40 {
            world.step(0.05).unwrap();
        }
        (world.state_hash(), world.stats().substeps)
    };
    let one = run(1);
    assert!(one.1 > 1, "adaptive substeps were used");
    assert_eq!(run(3), one);
}

#[test]
fn walls_hold_a_hard_pressed_pile() {
    // Found by review: gravity -200, e = 0, one substep left 81 discs below the floor.
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [40.0, 60.0]),
        gravity: [0.0, -200.0],
        coefficient_of_restitution: 0.0,
        ..Config::default()
    };
    let discs = scene::gas(
        &Gas {
            count: 1500,
            radius: [0.3, 0.6],
            region: None,
            speeds: Speeds::Uniform(1.0),
            drift: [0.0, 0.0],
            seed: 4,
        },
        &config,
    )
    .unwrap();
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    for step in 0..400 {
        world.step(1.0 / 60.0).unwrap();
        for (id, p) in world.particles_by_id() {
            let [x, y] = p.position;
            let r = p.radius;
            assert!(
                x >= r && x <= 40.0 - r && y >= r && y <= 60.0 - r,
                "step {step}: disc {id:?} at {:?} (radius {r}) is outside the walls",
                p.position
            );
        }
    }
}

/// A walled gas of equal discs (radius 0.5) at `packing`, speeds uniform in [-v, v]².
fn gas_world(packing: f64, v: f64, seed: u64, max_travel: Option<f64>) -> World {
    let (mut config, discs) =
        scene::gas_in_walls(2000, [0.5, 0.5], packing, Speeds::Uniform(v), seed).unwrap();
    config.max_travel = max_travel;
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world
}

/// Time averages over `steps` steps after `settle`: (virial pressure, wall pressure, kT / area
/// per disc, i.e. the ideal-gas pressure).
fn pressures(world: &mut World, dt: f64, settle: usize, steps: usize) -> (f64, f64, f64) {
    for _ in 0..settle {
        world.step(dt).unwrap();
    }
    let (min, max) = world.config().boundary.bounds().unwrap();
    let (w, h) = (max[0] - min[0], max[1] - min[1]);
    // The centres of these discs (radius 0.5) move in a box one diameter smaller.
    let area = (w - 1.0) * (h - 1.0);
    let (mut virial, mut impulse, mut ideal) = (0.0, 0.0, 0.0);
    for _ in 0..steps {
        let stats = *world.step(dt).unwrap();
        virial += stats.pressure.unwrap();
        impulse += stats.wall_impulse.total();
        ideal += stats.kinetic_energy / area;
    }
    let n = steps as f64;
    (virial / n, impulse / (n * dt * 2.0 * (w + h)), ideal / n)
}

#[test]
fn the_virial_pressure_matches_the_walls_and_hard_disc_theory() {
    // Packing 0.3, small steps (mean speed × dt / σ ≈ 0.004): the collision virial must give
    // the pressure the walls feel.
    let mut world = gas_world(0.3, 1.0, 1, None);
    let (virial, walls, ideal) = pressures(&mut world, 0.005, 600, 3000);
    let z = virial / ideal;
    assert!(
        (virial / walls - 1.0).abs() < 0.01,
        "virial {virial} vs walls {walls}"
    );
    // Henderson's equation of state for hard discs, Z = (1 + η²/8) / (1 − η)², within 1% of
    // Monte Carlo at this density, at the packing the centres' area gives.
    let (min, max) = world.config().boundary.bounds().unwrap();
    let area = (max[0] - min[0] - 1.0) * (max[1] - min[1] - 1.0);
    let eta = 2000.0 * std::f64::consts::PI * 0.25 / area;
    let henderson = (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta));
    assert!(
        (z / henderson - 1.0).abs() < 0.03,
        "Z = {z}, theory {henderson}"
    );
}

#[test]
fn a_dilute_gas_has_the_ideal_pressure() {
    // Packing 0.01: Z = 1 + 2η + ... = 1.02.
    let mut world = gas_world(0.01, 1.0, 2, None);
    let (virial, _, ideal) = pressures(&mut world, 0.02, 200, 1500);
    let z = virial / ideal;
    assert!((1.0..1.05).contains(&z), "Z = {z}");
}

#[test]
fn pressure_is_measured_in_a_periodic_box_too_and_open_worlds_have_none() {
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [60.0, 60.0]),
        restitution_model: RestitutionModel::RelativeNormalVelocity,
        ..Config::default()
    };
    let discs = scene::gas(
        &Gas {
            count: 1000,
            radius: [0.5, 0.5],
            region: None,
            speeds: Speeds::Fixed(1.0),
            drift: [0.0, 0.0],
            seed: 3,
        },
        &config,
    )
    .unwrap();
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    let mut z = 0.0;
    for _ in 0..200 {
        world.step(0.01).unwrap();
    }
    for _ in 0..1000 {
        let stats = *world.step(0.01).unwrap();
        z += stats.pressure.unwrap() * 3600.0 / stats.kinetic_energy;
    }
    let z = z / 1000.0;
    // η = 1000 π 0.25 / 3600 = 0.218: Henderson gives Z = 1.653.
    let eta = 1000.0 * std::f64::consts::PI * 0.25 / 3600.0;
    let henderson = (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta));
    assert!(
        (z / henderson - 1.0).abs() < 0.03,
        "Z = {z}, theory {henderson}"
    );
    let mut open = World::new(Config::default()).unwrap();
    open.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 0.5))
        .unwrap();
    assert_eq!(open.step(0.1).unwrap().pressure, None);
}
