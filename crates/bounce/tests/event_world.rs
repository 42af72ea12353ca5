//! `Method::EventDriven` through `World`: hand-computed collision times and velocities under
//! gravity (two discs, a disc and the floor, a peg, a segment's face and its end), the
//! refusals and the stall message, the TC model, determinism and resume, and the
//! time-stepped method converging to the event-driven pressure as dt falls.

mod common;

use bounce::event::EventError;
use bounce::{
    Boundary, Config, Method, Obstacle, Particle, ParticleId, RestitutionModel, StepError, World,
};

const G: f64 = 10.0;

fn events(config: Config) -> Config {
    Config {
        method: Method::EventDriven,
        ..config
    }
}

fn falling(boundary: Boundary, e: f64) -> Config {
    events(Config {
        gravity: [0.0, -G],
        coefficient_of_restitution: e,
        boundary,
        ..Config::default()
    })
}

fn world_with(config: Config, discs: &[Particle]) -> World {
    let mut world = World::new(config).unwrap();
    for d in discs {
        world.add_particle(*d).unwrap();
    }
    world
}

fn close(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-12 * b.abs().max(1.0),
        "{what}: {a} vs {b}"
    );
}

/// Steps `world` to just before `t` and across it: the step across has one bounce or
/// collision, the one before none; returns the state just after `t`.
fn across(world: &mut World, t: f64) -> f64 {
    let before = t - 1e-7;
    world.step(before).unwrap();
    let quiet = *world.stats();
    assert_eq!(quiet.collisions, 0);
    assert_eq!(quiet.wall_impulse.bottom, 0.0);
    world.step(2e-7).unwrap();
    t + 1e-7
}

#[test]
fn a_disc_dropped_on_the_floor_bounces_when_and_as_the_hand_calculation_says() {
    // Radius 0.5 at height 5.5 over the floor at 0, e = 0.8: the centre falls 5 to 0.5,
    // so it lands at t = √(2·5/10) = 1 at 10, and leaves at 8.
    let config = falling(Boundary::walls([0.0, 0.0], [10.0, 10.0]), 0.8);
    let mut world = world_with(config, &[Particle::new([5.0, 5.5], [0.0, 0.0], 0.5)]);
    let t = across(&mut world, 1.0);
    let d = world.particle(ParticleId(0)).unwrap();
    // 1e-7 after leaving at 8 upward: v = 8 − 10·1e-7, y = 0.5 + 8e-7 − 5e-14.
    close(d.velocity[1], 8.0 - G * (t - 1.0), "velocity");
    close(d.position[1], 0.5 + 8.0 * 1e-7 - 0.5 * G * 1e-14, "height");
    // The floor took m |Δv| = 0.5 · 18 (the seed's mass = radius).
    close(world.stats().wall_impulse.bottom, 9.0, "impulse");
}

#[test]
fn two_falling_discs_meet_as_if_gravity_were_not_there() {
    // Both fall alike, so their relative motion is a straight line: centres 10 apart
    // closing at 4 meet at t = 2, radii 1 (masses 1), e = 1: they swap their horizontal
    // velocities, and each falls at g t.
    let config = falling(Boundary::Open, 1.0);
    let discs = [
        Particle::new([0.0, 0.0], [2.0, 0.0], 1.0),
        Particle::new([10.0, 0.0], [-2.0, 0.0], 1.0),
    ];
    let mut world = world_with(config, &discs);
    let t = across(&mut world, 2.0);
    assert_eq!(world.stats().collisions, 1);
    let (a, b) = (
        world.particle(ParticleId(0)).unwrap(),
        world.particle(ParticleId(1)).unwrap(),
    );
    close(a.velocity[0], -2.0, "a's vx");
    close(b.velocity[0], 2.0, "b's vx");
    close(a.velocity[1], -G * t, "a's vy");
    close(a.position[0], 4.0 - 2.0 * (t - 2.0), "a's x");
    close(a.position[1], -0.5 * G * t * t, "a's y");
}

#[test]
fn a_disc_dropped_on_a_peg_and_on_a_segment_end_leaves_as_the_hand_calculation_says() {
    // A peg of radius 1 at the origin; radius 0.5 dropped from (0, 6.5): contact at a
    // centre distance of 1.5, after falling 5: t = 1, v = −10, reversed and scaled by 0.5.
    let mut peg = falling(Boundary::Open, 0.5);
    peg.obstacles = vec![Obstacle::peg([0.0, 0.0], 1.0)];
    let mut world = world_with(peg, &[Particle::new([0.0, 6.5], [0.0, 0.0], 0.5)]);
    let t = across(&mut world, 1.0);
    let d = world.particle(ParticleId(0)).unwrap();
    close(d.velocity[1], 5.0 - G * (t - 1.0), "off the peg");
    close(
        world.obstacle_impulses()[0][1],
        -0.5 * 15.0,
        "the peg's impulse",
    );

    // A segment from (−5, 0) to (0, 0); radius 0.5 dropped at x = 0.3 from y = 5.4: it
    // meets the end (0, 0) when its centre is 0.5 from it, at y = 0.4 (0.3² + 0.4² = 0.5²),
    // after falling 5: t = 1, v = (0, −10), normal n = (0.6, 0.8), e = 1: v − 2 (v·n) n.
    let mut segment = falling(Boundary::Open, 1.0);
    segment.obstacles = vec![Obstacle::segment([-5.0, 0.0], [0.0, 0.0])];
    let mut world = world_with(segment, &[Particle::new([0.3, 5.4], [0.0, 0.0], 0.5)]);
    let t = across(&mut world, 1.0);
    let d = world.particle(ParticleId(0)).unwrap();
    let (vx, vy) = (2.0 * 8.0 * 0.6, -10.0 + 2.0 * 8.0 * 0.8);
    close(d.velocity[0], vx, "vx off the end");
    close(d.velocity[1], vy - G * (t - 1.0), "vy off the end");
    close(d.position[0], 0.3 + vx * 1e-7, "x off the end");

    // The same segment's face: dropped at x = −2 from 5.5, it lands on the face at t = 1.
    let mut face = falling(Boundary::Open, 1.0);
    face.obstacles = vec![Obstacle::segment([-5.0, 0.0], [0.0, 0.0])];
    let mut world = world_with(face, &[Particle::new([-2.0, 5.5], [0.0, 0.0], 0.5)]);
    let t = across(&mut world, 1.0);
    let d = world.particle(ParticleId(0)).unwrap();
    close(d.velocity[1], 10.0 - G * (t - 1.0), "off the face");
    assert_eq!(d.velocity[0], 0.0);
}

#[test]
fn what_the_method_cannot_do_is_refused_naming_the_field() {
    for config in [
        Config {
            substeps: 4,
            ..events(Config::default())
        },
        Config {
            max_travel: Some(0.5),
            ..events(Config::default())
        },
        Config {
            friction: 0.5,
            ..events(Config::default())
        },
    ] {
        let error = World::new(config).unwrap_err();
        assert_eq!(error.field, "method");
        assert!(error.expected.contains("cannot be combined"), "{error}");
    }
    // Overlapping discs are named by their ids.
    let mut world = world_with(
        events(Config::default()),
        &[
            Particle::new([0.0, 0.0], [0.0, 0.0], 1.0),
            Particle::new([1.0, 0.0], [0.0, 0.0], 1.0),
        ],
    );
    let error = world.step(0.1).unwrap_err();
    assert_eq!(error, StepError::EventDriven(EventError::Overlap(0, 1)));
}

#[test]
fn a_run_that_cannot_advance_stops_naming_the_discs_and_the_time() {
    // e = 0 on the floor under gravity: the disc lands at t = 1 and then meets the floor
    // again and again at that instant.
    let config = falling(Boundary::walls([0.0, 0.0], [10.0, 10.0]), 0.0);
    let mut world = world_with(
        config,
        &[
            Particle::new([2.0, 8.0], [0.0, 0.0], 0.5),
            Particle::new([5.0, 5.5], [0.0, 0.0], 0.5),
        ],
    );
    match world.step(2.0) {
        Err(StepError::EventDriven(EventError::Stalled { time, discs })) => {
            assert!((time - 1.0).abs() < 1e-9, "{time}");
            assert!(discs.contains(&1), "{discs:?}");
            let message = StepError::EventDriven(EventError::Stalled { time, discs }).to_string();
            assert!(message.contains("contact_duration"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

/// `count` discs of radius 0.5 at kT = 1 on a lattice in `config`'s box.
fn gas(config: Config, count: usize, seed: u64) -> World {
    let discs = common::lattice_gas(&config, count, seed);
    world_with(config, &discs)
}

fn periodic(count: usize, packing: f64) -> Config {
    let side = (count as f64 * std::f64::consts::PI * 0.25 / packing).sqrt();
    Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        ..Config::default()
    }
}

#[test]
fn the_tc_model_lets_an_inelastic_pile_settle_that_otherwise_collapses() {
    // 400 discs at e = 0.5 dropped into a box under gravity: without the TC model the
    // settling pile collapses (infinitely many collisions in a finite time) and the run
    // stops with a clear error; with t_c = 1e-3 it runs on, and its motion dies down.
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [20.0, 60.0]),
        gravity: [0.0, -G],
        coefficient_of_restitution: 0.5,
        restitution_model: RestitutionModel::RelativeNormalVelocity,
        ..events(Config::default())
    };
    let mut stalls = gas(config.clone(), 400, 1);
    let stalled = (0..200).find_map(|_| stalls.step(0.05).err());
    assert!(
        matches!(
            stalled,
            Some(StepError::EventDriven(EventError::Stalled { .. }))
        ),
        "{stalled:?}"
    );
    let mut settles = gas(
        Config {
            contact_duration: 1e-3,
            ..config
        },
        400,
        1,
    );
    // Kinetic and potential energy (the seed's mass = radius), and the kinetic alone.
    let energy = |w: &World| {
        let p = w.particles();
        (0..p.len()).fold([0.0, 0.0], |[all, kinetic], i| {
            let k = 0.5 * p.radius()[i] * (p.vx()[i].powi(2) + p.vy()[i].powi(2));
            [all + k + p.radius()[i] * G * p.y()[i], kinetic + k]
        })
    };
    let [start, _] = energy(&settles);
    // 3.5 time units: fallen and settling. (A pile at rest is no place for events: its
    // collisions per unit time grow as its gaps close, TC or not; see
    // the guide's `docs/src/concepts/hard-discs.md`.)
    for _ in 0..70 {
        settles.step(0.05).unwrap();
    }
    let [end, kinetic] = energy(&settles);
    assert!(end < start, "{end} vs {start}");
    assert!(kinetic < 0.01 * start, "{kinetic} of {start}");
}

#[test]
fn a_rerun_and_a_resume_give_the_same_bits() {
    let config = Config {
        method: Method::EventDriven,
        ..periodic(500, 0.4)
    };
    let mut first = gas(config.clone(), 500, 7);
    let mut second = gas(config, 500, 7);
    for _ in 0..20 {
        first.step(0.05).unwrap();
        second.step(0.05).unwrap();
    }
    assert_eq!(first.state_hash(), second.state_hash());
    let saved = postcard::to_allocvec(&first).unwrap();
    let mut resumed: World = postcard::from_bytes(&saved).unwrap();
    assert_eq!(first.state_hash(), resumed.state_hash(), "loaded");
    for _ in 0..20 {
        first.step(0.05).unwrap();
        resumed.step(0.05).unwrap();
    }
    assert_eq!(first.state_hash(), resumed.state_hash());
    assert!(first.stats().collisions > 0);
}

#[test]
fn the_time_stepped_pressure_converges_to_the_event_driven_one_as_dt_falls() {
    // 1,000 discs at packing 0.5 from the same start: the event-driven pressure is exact;
    // the time-stepped one is low by about (0.2 + 9 η²) × (mean speed dt / σ) and its error
    // must shrink as dt does.
    let pressure = |method: Method, dt: f64| {
        let mut world = gas(
            Config {
                method,
                ..periodic(1000, 0.5)
            },
            1000,
            5,
        );
        let steps = (5.0 / dt).round() as usize;
        for _ in 0..steps {
            world.step(dt).unwrap();
        }
        let (mut sum, mut n) = (0.0, 0.0);
        for _ in 0..(20.0 / dt).round() as usize {
            sum += world.step(dt).unwrap().pressure.unwrap();
            n += 1.0;
        }
        sum / n
    };
    let exact = pressure(Method::EventDriven, 0.05);
    let errors: Vec<f64> = [0.01, 0.0025, 0.000_625]
        .into_iter()
        .map(|dt| (pressure(Method::TimeStepped, dt) / exact - 1.0).abs())
        .collect();
    assert!(
        errors[0] > errors[1] && errors[1] > errors[2] && errors[2] < 0.015,
        "relative errors {errors:?} against the event-driven {exact}"
    );
}
