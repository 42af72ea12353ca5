//! Sensors: a crossing counts one in and one out, a sensor over a sink counts the
//! removals, circles and boxes, the counts survive a save and load, and bad sensors are
//! refused by name.

use bounce::{Boundary, Config, Emitter, Particle, Region, Sensor, Sink, World};

#[test]
fn a_disc_crossing_a_circle_once_counts_one_in_and_one_out() {
    let ring = Sensor::new(
        "ring",
        Region::Circle {
            centre: [5.0, 0.0],
            radius: 1.0,
        },
    );
    let config = Config {
        sensors: vec![ring],
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    world
        .add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 0.1))
        .unwrap();
    // A second disc passes beside it and never enters.
    world
        .add_particle(Particle::new([0.0, 1.5], [1.0, 0.0], 0.1))
        .unwrap();
    let mut inside_steps = 0;
    for _ in 0..100 {
        world.step(0.1).unwrap();
        inside_steps += world.sensors()[0].inside;
    }
    let count = &world.sensors()[0];
    assert_eq!((count.entered, count.left, count.inside), (1, 1, 0));
    // In for x in [4, 6]: about 2 time units, 20 steps of 0.1.
    assert!((19..=21).contains(&inside_steps), "{inside_steps}");
}

#[test]
fn a_sensor_over_a_sink_counts_every_removal() {
    let drain = [[0.0, 0.0], [10.0, 2.0]];
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [10.0, 20.0]),
        gravity: [0.0, -9.81],
        emitters: vec![Emitter {
            rate: 40.0,
            seed: 3,
            ..Emitter::new([1.0, 15.0], [9.0, 19.0], 0.2)
        }],
        sinks: vec![Sink {
            min: drain[0],
            max: drain[1],
        }],
        // The same region: discs are removed in the step they enter it.
        sensors: vec![Sensor::new(
            "drain",
            Region::Box {
                min: drain[0],
                max: drain[1],
            },
        )],
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    let (mut removed, mut stepwise) = (0u64, 0u64);
    for _ in 0..400 {
        let stats = world.step(0.01).unwrap();
        removed += stats.removed as u64;
        stepwise += world.sensors()[0].left_last_step;
    }
    let count = &world.sensors()[0];
    assert!(removed > 50, "{removed} removed");
    assert_eq!(count.left, removed);
    assert_eq!(count.entered, removed);
    assert_eq!(stepwise, removed);
    assert_eq!(count.inside, 0);
}

#[test]
fn counts_continue_after_a_save_and_load() {
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [20.0, 20.0]),
        sensors: vec![Sensor::new(
            "middle",
            Region::Box {
                min: [5.0, 5.0],
                max: [15.0, 15.0],
            },
        )],
        ..Config::default()
    };
    let mut a = World::new(config).unwrap();
    for k in 0..40 {
        let (x, y) = ((k % 8) as f64 * 2.5 + 0.5, (k / 8) as f64 * 4.0 + 0.5);
        let v = [(k as f64 * 0.7).sin(), (k as f64 * 1.3).cos()];
        a.add_particle(Particle::new([x, y], v, 0.3)).unwrap();
    }
    for _ in 0..50 {
        a.step(0.1).unwrap();
    }
    let mut b: World = postcard::from_bytes(&postcard::to_allocvec(&a).unwrap()).unwrap();
    for _ in 0..50 {
        a.step(0.1).unwrap();
        b.step(0.1).unwrap();
        assert_eq!(a.sensors(), b.sensors());
    }
    let count = &a.sensors()[0];
    assert!(count.entered > 5 && count.left > 5);
    // Every disc in it came in (or started there and was counted entering at step 1).
    assert_eq!(count.entered - count.left, count.inside as u64);
}

#[test]
fn bad_sensors_are_refused_by_name() {
    let unit = Region::Circle {
        centre: [0.0, 0.0],
        radius: 1.0,
    };
    let twice = Config {
        sensors: vec![Sensor::new("a", unit), Sensor::new("a", unit)],
        ..Config::default()
    };
    let e = twice.validate().unwrap_err();
    assert_eq!(e.field, "sensors");
    assert!(e.to_string().contains("sensor 1: name \"a\""), "{e}");
    let flat = Config {
        sensors: vec![Sensor::new(
            "flat",
            Region::Box {
                min: [0.0, 0.0],
                max: [1.0, 0.0],
            },
        )],
        ..Config::default()
    };
    assert!(
        flat.validate()
            .unwrap_err()
            .to_string()
            .contains("min below max")
    );
}
