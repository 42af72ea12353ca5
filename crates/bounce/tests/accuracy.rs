//! Accuracy under control: tunnelling, walls that hold, and the pressure from the collision
//! virial checked against the walls and against hard-disc theory.

use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config, Particle, RestitutionModel, VelocityUpdate, World};

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

/// A pile: discs rain into a 30 × 40 box under gravity with restitution 0.7 and 4 substeps,
/// with the momentum-conserving restitution model and `passes` solver passes.
fn relative_pile(passes: u32, threads: usize) -> World {
    pile(
        Config {
            restitution_model: RestitutionModel::RelativeNormalVelocity,
            solver_iterations: passes,
            ..Config::default()
        },
        threads,
    )
}

/// The pile of `relative_pile` under `model`'s restitution model, velocity update and passes.
fn pile(model: Config, threads: usize) -> World {
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [30.0, 40.0]),
        gravity: [0.0, -9.81],
        coefficient_of_restitution: 0.7,
        substeps: 4,
        ..model
    };
    let discs = scene::gas(
        &Gas {
            count: 600,
            radius: [0.3, 0.6],
            region: Some(([0.0, 10.0], [30.0, 40.0])),
            speeds: Speeds::Uniform(0.5),
            drift: [0.0, 0.0],
            seed: 8,
        },
        &config,
    )
    .unwrap();
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world.set_threads(threads).unwrap();
    world.set_parallel_min_work(0);
    world
}

/// The largest overlap and the mean kinetic energy over the last 100 of 400 steps.
fn settled(world: &mut World) -> (f64, f64) {
    let (mut worst, mut energy) = (0.0f64, 0.0);
    for step in 0..400 {
        let stats = world.step(1.0 / 60.0).unwrap();
        if step >= 300 {
            worst = worst.max(stats.max_overlap);
            energy += stats.kinetic_energy / 100.0;
        }
    }
    (worst, energy)
}

#[test]
fn more_solver_passes_keep_a_pile_from_compressing() {
    // Found by review: with the momentum-conserving model one pass per substep cannot take
    // the shared downward velocity out of a stack, and overlaps reach twice the smallest
    // radius. More passes, each ending with the walls, hand it down within the substep.
    let (one, one_energy) = settled(&mut relative_pile(1, 1));
    let (eight, eight_energy) = settled(&mut relative_pile(8, 1));
    let (sixteen, sixteen_energy) = settled(&mut relative_pile(16, 1));
    assert!(
        eight < one / 3.0 && sixteen < one / 10.0,
        "largest overlap: 1 pass {one}, 8 passes {eight}, 16 passes {sixteen}"
    );
    assert!(
        eight_energy < one_energy / 3.0 && sixteen_energy < one_energy / 8.0,
        "kinetic energy: 1 pass {one_energy}, 8 passes {eight_energy}, 16 {sixteen_energy}"
    );
    // Still the same bits for every thread count.
    let (mut a, mut b) = (relative_pile(4, 1), relative_pile(4, 3));
    for _ in 0..60 {
        a.step(1.0 / 60.0).unwrap();
        b.step(1.0 / 60.0).unwrap();
    }
    assert_eq!(a.state_hash(), b.state_hash());
}

#[test]
fn with_enough_passes_the_momentum_conserving_pile_settles_as_well_as_the_seeds() {
    // Issue 12: under the standard model (Newton's restitution on the relative normal
    // velocity, approaching pairs only) the pile's kinetic-energy floor and largest overlap
    // are no worse than the seed model's single pass. Each block's contacts go lowest first
    // when there are several passes under gravity, so a pass carries the floor's support
    // up a whole block.
    let (seed_overlap, seed_energy) = settled(&mut pile(Config::default(), 2));
    let standard = Config {
        restitution_model: RestitutionModel::RelativeNormalVelocity,
        velocity_update: VelocityUpdate::ApproachingOnly,
        solver_iterations: 64,
        ..Config::default()
    };
    let (overlap, energy) = settled(&mut pile(standard, 2));
    assert!(
        overlap <= seed_overlap && energy <= seed_energy,
        "64 passes: overlap {overlap}, kinetic energy {energy}; the seed's single pass: \
         {seed_overlap}, {seed_energy}"
    );
}

#[test]
fn a_lattice_start_reaches_packing_0_7_without_overlaps_and_zero_momentum() {
    let side = 40.0;
    let count = (0.7 * side * side / (std::f64::consts::PI * 0.25)) as usize;
    for boundary in [
        Boundary::periodic([0.0, 0.0], [side, side]),
        Boundary::walls([0.0, 0.0], [side, side]),
    ] {
        let config = Config {
            boundary: boundary.clone(),
            ..Config::default()
        };
        let gas = Gas {
            count,
            radius: [0.5, 0.5],
            region: None,
            speeds: Speeds::Temperature(1.0),
            drift: [0.0, 0.0],
            seed: 5,
        };
        // Random placement cannot get there.
        assert!(scene::gas(&gas, &config).is_err());
        let mut discs = scene::packed_gas(&gas, &config, &[]).unwrap();
        assert_eq!(discs.len(), count);
        let packing = count as f64 * std::f64::consts::PI * 0.25 / (side * side);
        assert!(packing >= 0.699, "{packing}");
        // Thermal velocities leave a net momentum of about sqrt(N); zero_momentum removes it.
        let momentum = |d: &[Particle]| {
            d.iter().fold([0.0, 0.0], |p, q| {
                [p[0] + 0.5 * q.velocity[0], p[1] + 0.5 * q.velocity[1]]
            })
        };
        assert!(momentum(&discs)[0].abs() + momentum(&discs)[1].abs() > 1.0);
        scene::zero_momentum(&mut discs, &config, [0.0, 0.0]);
        let p = momentum(&discs);
        assert!(p[0].abs() < 1e-9 && p[1].abs() < 1e-9, "{p:?}");
        let mut world = World::new(config).unwrap();
        world.add_particles(discs).unwrap();
        assert!(
            world.colliding_pairs().is_empty(),
            "{boundary:?}: overlaps at the start"
        );
        // It melts: the lattice order goes (discs leave their sites), stably.
        let start: Vec<[f64; 2]> = world
            .particles_by_id()
            .iter()
            .map(|(_, p)| p.position)
            .collect();
        for _ in 0..300 {
            world.step(0.01).unwrap();
        }
        let moved = world
            .particles_by_id()
            .iter()
            .zip(&start)
            .filter(|((_, p), s)| (p.position[0] - s[0]).hypot(p.position[1] - s[1]) > 0.3)
            .count();
        assert!(
            moved > count / 2,
            "{boundary:?}: {moved} of {count} left their sites"
        );
    }
}
