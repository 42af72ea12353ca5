//! The fast step against the plain one (`bounce::plain`): random worlds under every boundary,
//! mass, restitution, velocity-update and resting-contact option, smooth and rough discs
//! (friction at pairs, walls and obstacles, tangential restitution, rolling resistance,
//! spin), polydisperse radii, obstacles fixed, moving and driven, emitters and sinks, several
//! solver passes and adaptive substeps, a Lees–Edwards box, stepped with both for 50 steps on
//! 1 and 2 threads, must keep the same bits. Every world runs with no recording switch on (the
//! fast step's side-by-side kernel) and again with those drawn (contact events, the pressure
//! tensor, collision counts: one contact at a time); the plain step resolves its pairs with
//! its own loop, so neither of the fast step's solvers is compared with itself.

use bounce::scene::{self, Gas, Speeds};
use bounce::{
    Boundary, Config, Emitter, MassModel, Motion, Obstacle, RestingContacts, RestitutionModel,
    Sink, VelocityUpdate, World, plain,
};
use proptest::prelude::*;

/// A world's recipe, drawn by proptest.
#[derive(Clone, Debug)]
struct Recipe {
    boundary: u8,
    mass_model: u8,
    restitution_model: bool,
    approaching_only: bool,
    rest: bool,
    restitution: f64,
    scale: f64,
    radius: [f64; 2],
    count: usize,
    speed: f64,
    gravity: bool,
    wall_restitution: f64,
    substeps: u32,
    solver_iterations: u32,
    max_travel: Option<f64>,
    obstacles: u8,
    sources: bool,
    seed: u64,
    /// Which recording switches are on: contact events (1), the pressure tensor (2),
    /// collision counts (4).
    recording: u8,
    /// 0–1 smooth; 2 friction at pairs and walls; 3 friction everywhere, rolling
    /// resistance and spin.
    rough: u8,
    friction: f64,
    tangential_restitution: f64,
    rolling_resistance: f64,
}

fn recipe() -> impl Strategy<Value = Recipe> {
    (
        (
            0u8..4,
            0u8..3,
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
            0.5f64..=1.0,
        ),
        (
            0.9f64..1.3,
            0.2f64..0.6,
            1.0f64..4.0,
            20usize..160,
            0.5f64..8.0,
        ),
        (any::<bool>(), 0.5f64..=1.0, 1u32..4, 1u32..4),
        (
            prop::option::of(0.2f64..1.0),
            0u8..16,
            any::<bool>(),
            any::<u64>(),
        ),
        (0u8..4, 0.0f64..1.0, -1.0f64..=1.0, 0.0f64..0.3, 0u8..8),
    )
        .prop_map(
            |(
                (boundary, mass_model, restitution_model, approaching_only, rest, restitution),
                (scale, r_min, ratio, count, speed),
                (gravity, wall_restitution, substeps, solver_iterations),
                (max_travel, obstacles, sources, seed),
                (rough, friction, tangential_restitution, rolling_resistance, recording),
            )| Recipe {
                recording,
                rough,
                friction,
                tangential_restitution,
                rolling_resistance,
                boundary,
                mass_model,
                restitution_model,
                approaching_only,
                rest,
                restitution,
                scale,
                radius: [r_min, r_min * ratio],
                // At most 15 % of the region covered by the largest discs' reach.
                count: count.min(
                    (0.15 * 38.0 * 38.0 / (std::f64::consts::PI * (r_min * ratio * scale).powi(2)))
                        as usize
                        + 2,
                ),
                speed,
                gravity,
                wall_restitution,
                substeps,
                solver_iterations,
                max_travel,
                // A Lees–Edwards box holds no obstacles.
                obstacles: if boundary == 3 { 0 } else { obstacles },
                sources,
                seed,
            },
        )
}

const SIDE: f64 = 40.0;

fn config(r: &Recipe) -> Config {
    let (min, max) = ([0.0, 0.0], [SIDE, SIDE]);
    let boundary = match r.boundary {
        0 => Boundary::Walls {
            min,
            max,
            wall_restitution: Some(r.wall_restitution),
        },
        1 => Boundary::periodic(min, max),
        2 => Boundary::Open,
        _ => Boundary::lees_edwards(min, max, 0.4),
    };
    let mut obstacles = Vec::new();
    // One bit per kind: a fixed segment, a peg, a segment at a set speed, a driven piston.
    if r.obstacles & 1 != 0 {
        let segment = Obstacle::segment([5.0, 12.0], [30.0, 8.0]).with_restitution(0.8);
        obstacles.push(if r.rough == 3 {
            segment.with_friction(0.9)
        } else {
            segment
        });
    }
    if r.obstacles & 2 != 0 {
        obstacles.push(Obstacle::peg([20.0, 25.0], 2.0));
    }
    if r.obstacles & 4 != 0 {
        obstacles.push(
            Obstacle::segment([8.0, 32.0], [22.0, 36.0]).moving(Motion::Velocity([0.3, -0.2])),
        );
    }
    if r.obstacles & 8 != 0 {
        obstacles.push(
            Obstacle::segment([2.0, 38.0], [38.0, 38.0]).moving(Motion::Driven {
                force: [0.0, -20.0],
                mass: 2.0,
                velocity: [0.0, 0.0],
            }),
        );
    }
    let (emitters, sinks) = if r.sources {
        let emitter = Emitter {
            rate: 30.0,
            velocity: [3.0, 1.0],
            spread: 0.5,
            seed: r.seed ^ 1,
            ..Emitter::new([1.0, 20.0], [4.0, 30.0], r.radius[0])
        };
        let sink = Sink {
            min: [34.0, 0.0],
            max: [40.0, 14.0],
        };
        (vec![emitter], vec![sink])
    } else {
        (Vec::new(), Vec::new())
    };
    Config {
        collision_radius_scale: r.scale,
        coefficient_of_restitution: r.restitution,
        gravity: if r.gravity { [0.3, -6.0] } else { [0.0, 0.0] },
        substeps: r.substeps,
        solver_iterations: r.solver_iterations,
        max_travel: r.max_travel,
        boundary,
        mass_model: match r.mass_model {
            0 => MassModel::Radius,
            1 => MassModel::Area,
            _ => MassModel::PerParticle,
        },
        restitution_model: if r.restitution_model {
            RestitutionModel::RelativeNormalVelocity
        } else {
            RestitutionModel::ScaleEachNormalVelocity
        },
        velocity_update: if r.approaching_only {
            VelocityUpdate::ApproachingOnly
        } else {
            VelocityUpdate::AllDetected
        },
        resting_contacts: if r.rest {
            RestingContacts::Rest
        } else {
            RestingContacts::Bounce
        },
        friction: if r.rough >= 2 { r.friction } else { 0.0 },
        wall_friction: (r.rough == 3).then_some(0.3),
        tangential_restitution: r.tangential_restitution,
        rolling_resistance: if r.rough == 3 {
            r.rolling_resistance
        } else {
            0.0
        },
        inertia_factor: if r.rough == 3 { 0.4 } else { 0.5 },
        // The plain step is the time-stepped method's reference.
        method: bounce::Method::TimeStepped,
        contact_duration: 0.0,
        // Reporting contacts resolves them one at a time: the same bits.
        contact_events: r.recording & 1 != 0,
        contact_event_threshold: 0.0,
        obstacles,
        emitters,
        sinks,
        // Sensors count; they change nothing.
        sensors: vec![bounce::Sensor::new(
            "half",
            bounce::Region::Circle {
                centre: [20.0, 15.0],
                radius: 10.0,
            },
        )],
        // Measuring the virial tensor takes the contacts one at a time: the same bits.
        pressure_tensor: r.recording & 2 != 0,
        // So does counting each disc's collisions.
        collision_counts: r.recording & 4 != 0,
        // A thermostat of each kind, or none, by the seed's next bits.
        thermostat: [
            None,
            Some(bounce::ThermostatKind::Rescale),
            Some(bounce::ThermostatKind::Andersen),
            Some(bounce::ThermostatKind::WhiteNoise),
        ][(r.seed >> 1) as usize % 4]
            .map(|kind| bounce::Thermostat {
                seed: r.seed,
                ..bounce::Thermostat::new(kind, 0.8, 3.0)
            }),
    }
}

fn world(r: &Recipe, threads: usize) -> World {
    let config = config(r);
    let mut discs = scene::gas(
        &Gas {
            count: r.count,
            radius: r.radius,
            region: Some(([1.0, 1.0], [SIDE - 1.0, SIDE - 1.0])),
            speeds: Speeds::Uniform(r.speed),
            drift: [0.0, 0.0],
            seed: r.seed,
        },
        &config,
    )
    .expect("the gas fits");
    for (k, d) in discs.iter_mut().enumerate() {
        // Per-particle masses unlike the radii.
        d.mass = Some(0.5 + (k % 7) as f64 * 0.3);
    }
    if r.rough == 3 {
        scene::spin(&mut discs, 4.0, r.seed);
    }
    let mut world = World::new(config).expect("valid config");
    world.add_particles(discs).expect("valid discs");
    world.set_threads(threads).unwrap();
    world.set_parallel_min_work(0);
    world
}

/// Steps the fast and the plain world side by side and compares what must be equal.
fn same_bits(r: &Recipe, threads: usize, steps: usize) -> Result<(), TestCaseError> {
    let (mut fast, mut reference) = (world(r, threads), world(r, 1));
    for step in 0..steps {
        let dt = 0.02;
        let a = *fast.step(dt).expect("the fast step");
        let b = *plain::step(&mut reference, dt).expect("the plain step");
        let at = format!("step {step}, {threads} threads");
        prop_assert_eq!(fast.state_hash(), reference.state_hash(), "state, {}", at);
        prop_assert_eq!(
            (a.pairs, a.collisions, a.substeps, a.emitted, a.removed),
            (b.pairs, b.collisions, b.substeps, b.emitted, b.removed),
            "counts, {}",
            at
        );
        prop_assert_eq!(
            a.max_overlap.to_bits(),
            b.max_overlap.to_bits(),
            "overlap, {}",
            at
        );
        prop_assert_eq!(a.virial.to_bits(), b.virial.to_bits(), "virial, {}", at);
        prop_assert_eq!(
            a.virial_tensor.map(f64::to_bits),
            b.virial_tensor.map(f64::to_bits),
            "virial tensor, {}",
            at
        );
        prop_assert_eq!(
            a.thermostat_work.to_bits(),
            b.thermostat_work.to_bits(),
            "thermostat, {}",
            at
        );
        prop_assert_eq!(a.wall_impulse, b.wall_impulse, "walls, {}", at);
        prop_assert_eq!(
            fast.collision_counts(),
            reference.collision_counts(),
            "collision counts, {}",
            at
        );
        prop_assert_eq!(
            fast.obstacle_states(),
            reference.obstacle_states(),
            "obstacles, {}",
            at
        );
        prop_assert_eq!(
            fast.obstacle_impulses(),
            reference.obstacle_impulses(),
            "{}",
            at
        );
        prop_assert_eq!(
            fast.obstacle_work().to_bits(),
            reference.obstacle_work().to_bits()
        );
        prop_assert_eq!(
            (a.friction_work.to_bits(), fast.friction_work().to_bits()),
            (
                b.friction_work.to_bits(),
                reference.friction_work().to_bits()
            ),
            "friction work, {}",
            at
        );
        // Summed in storage order, which the plain step never changes.
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * x.abs().max(1.0);
        prop_assert!(close(a.kinetic_energy, b.kinetic_energy), "energy, {}", at);
    }
    Ok(())
}

/// 48 worlds, the same ones on every run (CI stays reproducible); `PROPTEST_RNG_SEED` (and
/// `PROPTEST_CASES`) draw others. Random seeds found the two bugs fixed in the obstacles'
/// pass: a long path crossing a segment listed at neither end, and a disc sent back across
/// a segment meeting what was near its old place.
fn cases() -> ProptestConfig {
    let mut config = ProptestConfig {
        cases: 48,
        ..ProptestConfig::default()
    };
    if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
        config.rng_seed = proptest::test_runner::RngSeed::Fixed(0x006f_756e_6365);
    }
    config
}

proptest! {
    #![proptest_config(cases())]

    #[test]
    fn the_fast_step_keeps_the_plain_steps_bits(r in recipe()) {
        // With no recording switch: the side-by-side kernel (but in a Lees–Edwards box).
        let bare = Recipe { recording: 0, ..r.clone() };
        same_bits(&bare, 1, 50)?;
        same_bits(&bare, 2, 50)?;
        if r.recording != 0 {
            // One contact at a time, as recording needs.
            same_bits(&r, 1, 50)?;
            same_bits(&r, 2, 50)?;
        }
    }
}

/// The benchmark scenes at a test's size: a gas and a pile, thousands of contacts a
/// substep, the fast step's dense paths (presort, several bands) included; and the pile of
/// rough discs.
#[test]
fn the_benchmark_scenes_keep_the_plain_steps_bits() {
    for (scene, friction) in [
        (scene::Bench::Gas, 0.0),
        (scene::Bench::Pile, 0.0),
        (scene::Bench::Poly, 0.0),
        (scene::Bench::Pile, 0.5),
    ] {
        let (mut config, discs) = scene.build(4000).unwrap();
        config.friction = friction;
        let mut fast = World::new(config.clone()).unwrap();
        fast.add_particles(discs.clone()).unwrap();
        fast.set_threads(2).unwrap();
        fast.set_parallel_min_work(0);
        let mut reference = World::new(config).unwrap();
        reference.add_particles(discs).unwrap();
        for step in 0..60 {
            fast.step(scene::Bench::DT).unwrap();
            plain::step(&mut reference, scene::Bench::DT).unwrap();
            assert_eq!(
                fast.state_hash(),
                reference.state_hash(),
                "{scene:?}, friction {friction}, step {step}"
            );
        }
    }
}
