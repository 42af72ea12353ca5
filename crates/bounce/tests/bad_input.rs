//! Bad input gets a typed error naming the value, and the world is unchanged.

use bounce::{
    Boundary, Config, ConfigError, Particle, ParticleError, StepError, World, WorldError,
};

fn walled() -> World {
    World::new(Config {
        boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
        ..Config::default()
    })
    .unwrap()
}

fn refused(world: &mut World, p: Particle) -> ParticleError {
    let before = world.state_hash();
    let n = world.len();
    let err = world.add_particle(p).unwrap_err();
    assert_eq!(world.len(), n);
    assert_eq!(world.state_hash(), before);
    err
}

#[test]
fn non_finite_position_or_velocity() {
    let mut w = walled();
    let e = refused(&mut w, Particle::new([f64::NAN, 1.0], [0.0, 0.0], 0.5));
    assert!(matches!(e, ParticleError::NonFinitePosition(_)));
    assert!(e.to_string().contains("NaN"), "{e}");
    let e = refused(&mut w, Particle::new([1.0, 1.0], [f64::INFINITY, 0.0], 0.5));
    assert!(matches!(e, ParticleError::NonFiniteVelocity([v, _]) if v == f64::INFINITY));
}

#[test]
fn bad_radius_and_mass() {
    let mut w = walled();
    for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = refused(&mut w, Particle::new([1.0, 1.0], [0.0, 0.0], r));
        assert!(matches!(e, ParticleError::InvalidRadius(_)), "{r}: {e}");
        assert!(e.to_string().contains(&r.to_string()));
    }
    let p = Particle {
        mass: Some(-2.0),
        ..Particle::new([1.0, 1.0], [0.0, 0.0], 0.5)
    };
    assert_eq!(refused(&mut w, p), ParticleError::InvalidMass(-2.0));
}

#[test]
fn centre_outside_the_walls_or_too_large() {
    let mut w = walled();
    let e = refused(&mut w, Particle::new([11.0, 5.0], [0.0, 0.0], 0.5));
    assert!(matches!(
        e,
        ParticleError::OutsideBox {
            position: [11.0, 5.0],
            ..
        }
    ));
    assert!(e.to_string().contains("11"), "{e}");
    let e = refused(&mut w, Particle::new([5.0, 5.0], [0.0, 0.0], 6.0));
    assert!(matches!(e, ParticleError::TooLarge { radius: 6.0, .. }));
    let mut periodic = World::new(Config {
        boundary: Boundary::periodic([0.0, 0.0], [10.0, 10.0]),
        ..Config::default()
    })
    .unwrap();
    // Half-open: max is the same place as min.
    assert!(matches!(
        refused(&mut periodic, Particle::new([10.0, 5.0], [0.0, 0.0], 0.5)),
        ParticleError::OutsideBox { .. }
    ));
    assert!(matches!(
        refused(&mut periodic, Particle::new([5.0, 5.0], [0.0, 0.0], 3.0)),
        ParticleError::TooLarge { .. }
    ));
}

#[test]
fn batch_add_is_all_or_nothing() {
    let mut w = walled();
    let good = Particle::new([1.0, 1.0], [0.0, 0.0], 0.5);
    let bad = Particle::new([1.0, 1.0], [0.0, 0.0], -0.5);
    let (index, error) = w.add_particles([good, good, bad]).unwrap_err();
    assert_eq!((index, error), (2, ParticleError::InvalidRadius(-0.5)));
    assert_eq!(w.len(), 0);
    // Ids continue from where they were.
    assert_eq!(w.add_particle(good).unwrap().0, 0);
}

#[test]
fn invalid_config_names_the_field() {
    let cases: [(Config, &str); 6] = [
        (
            Config {
                collision_radius_scale: 0.0,
                ..Config::default()
            },
            "collision_radius_scale",
        ),
        (
            Config {
                collision_radius_scale: f64::NAN,
                ..Config::default()
            },
            "collision_radius_scale",
        ),
        (
            Config {
                coefficient_of_restitution: 1.5,
                ..Config::default()
            },
            "coefficient_of_restitution",
        ),
        (
            Config {
                gravity: [0.0, f64::INFINITY],
                ..Config::default()
            },
            "gravity",
        ),
        (
            Config {
                substeps: 0,
                ..Config::default()
            },
            "substeps",
        ),
        (
            Config {
                boundary: Boundary::walls([0.0, 0.0], [-1.0, 5.0]),
                ..Config::default()
            },
            "boundary",
        ),
    ];
    for (config, field) in cases {
        let err: ConfigError = World::new(config).unwrap_err();
        assert_eq!(err.field, field);
        assert!(err.to_string().contains(field), "{err}");
    }
    let wall_e = Config {
        boundary: Boundary::Walls {
            min: [0.0; 2],
            max: [1.0; 2],
            wall_restitution: Some(-0.1),
        },
        ..Config::default()
    };
    assert_eq!(
        wall_e.validate().unwrap_err().field,
        "boundary.wall_restitution"
    );
}

#[test]
fn set_config_refuses_a_box_the_particles_do_not_fit() {
    let mut w = walled();
    w.add_particle(Particle::new([8.0, 8.0], [0.0, 0.0], 0.5))
        .unwrap();
    let smaller = Config {
        boundary: Boundary::walls([0.0, 0.0], [5.0, 5.0]),
        ..Config::default()
    };
    let err = w.set_config(smaller).unwrap_err();
    assert!(matches!(
        err,
        WorldError::Particle {
            error: ParticleError::OutsideBox { .. },
            ..
        }
    ));
    assert_eq!(
        w.config().boundary,
        Boundary::walls([0.0, 0.0], [10.0, 10.0])
    );
}

#[test]
fn bad_time_steps() {
    let mut w = walled();
    w.add_particle(Particle::new([1.0, 1.0], [1.0, 0.0], 0.5))
        .unwrap();
    for dt in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let err = w.step(dt).unwrap_err();
        assert!(matches!(err, StepError::InvalidTimeStep(_)));
        assert!(err.to_string().contains("dt"));
    }
    assert_eq!(w.step_count(), 0);
    // A finite dt that the clock cannot hold: refused before the step, nothing moved.
    w.step(1e308).unwrap();
    let before = w.state_hash();
    let err = w.step(1e308).unwrap_err();
    assert!(matches!(err, StepError::ClockOverflow { .. }), "{err}");
    assert!(err.to_string().contains("overflows the clock"), "{err}");
    assert_eq!((w.step_count(), w.state_hash()), (1, before));
    assert!(w.time().is_finite());
}

#[test]
fn extreme_but_valid_states_never_produce_nan() {
    // Many discs stacked on one point, huge speeds, tiny and huge radii together.
    let mut w = walled();
    for i in 0..200 {
        let v = if i % 2 == 0 { 1e12 } else { -1e12 };
        w.add_particle(Particle::new(
            [5.0, 5.0],
            [v, v * 0.5],
            if i % 7 == 0 { 4.9 } else { 1e-6 },
        ))
        .unwrap();
    }
    for _ in 0..50 {
        w.step(1e-3).unwrap();
    }
    let p = w.particles();
    assert!(
        p.x()
            .iter()
            .chain(p.y())
            .chain(p.vx())
            .chain(p.vy())
            .all(|v| v.is_finite())
    );
    assert!(w.stats().kinetic_energy.is_finite());
}

#[test]
fn a_checkpoint_with_bad_values_is_refused() {
    let mut w = walled();
    w.add_particle(Particle::new([1.0, 1.0], [1.0, 0.0], 0.5))
        .unwrap();
    let bytes = postcard::to_stdvec(&w).unwrap();
    // Flip the radius (the last f64 before the mass array) to a negative number by finding
    // the encoded 0.5 and replacing it with -0.5.
    let half = 0.5f64.to_le_bytes();
    let at = bytes
        .windows(8)
        .position(|win| win == half)
        .expect("radius in the bytes");
    let mut bad = bytes.clone();
    bad[at..at + 8].copy_from_slice(&(-0.5f64).to_le_bytes());
    let err = postcard::from_bytes::<World>(&bad).unwrap_err();
    assert!(!err.to_string().is_empty());
}

#[test]
fn interactive_edits_validate_and_count() {
    let mut w = walled();
    let a = w
        .add_particle(Particle::new([2.0, 2.0], [0.0, 0.0], 0.5))
        .unwrap();
    w.add_particle(Particle::new([8.0, 8.0], [0.0, 0.0], 0.5))
        .unwrap();
    assert_eq!(w.particle_at([2.3, 2.0]), Some(a));
    assert_eq!(w.particle_at([5.0, 5.0]), None);
    assert_eq!(w.push_region([2.0, 2.0], 1.0, [1.0, 0.0]), 1);
    assert_eq!(w.particle(a).unwrap().velocity, [1.0, 0.0]);
    assert_eq!(w.push_region([2.0, 2.0], f64::NAN, [1.0, 0.0]), 0);
    assert!(matches!(
        w.set_velocity(a, [f64::NAN, 0.0]),
        Err(ParticleError::NonFiniteVelocity(_))
    ));
    assert!(matches!(
        w.set_velocity(bounce::ParticleId(99), [0.0, 0.0]),
        Err(ParticleError::UnknownId(_))
    ));
    // Energy reflects the edits at once: ½ · 0.5 · 1².
    assert_eq!(w.stats().kinetic_energy, 0.25);
}

#[test]
fn a_checkpoint_claiming_four_billion_ids_is_refused_before_allocating() {
    // Found by review: next_id = 2^32 - 1 in a 6 KB checkpoint made loading allocate 16.8 GB.
    let mut w = walled();
    w.add_particle(Particle::new([1.0, 1.0], [1.0, 0.0], 0.5))
        .unwrap();
    let mut state = serde_json::to_value(&w).unwrap();
    state["next_id"] = serde_json::json!(u32::MAX);
    let err = serde_json::from_value::<World>(state.clone())
        .unwrap_err()
        .to_string();
    assert!(err.contains("next_id 4294967295"), "{err}");
    // A repeated id is refused too.
    state["next_id"] = serde_json::json!(1);
    let ids = state["particles"]["id"].clone();
    state["particles"]["id"] = serde_json::json!([ids[0], ids[0]]);
    assert!(serde_json::from_value::<World>(state).is_err());
}

#[test]
fn a_step_that_overflows_names_the_step_and_the_particle() {
    let mut w = World::new(Config::default()).unwrap();
    w.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 0.5))
        .unwrap();
    w.add_particle(Particle::new([5.0, 0.0], [1e10, 0.0], 0.5))
        .unwrap();
    match w.step(1e300) {
        Err(bounce::StepError::NonFinite { step, id }) => assert_eq!((step, id.as_str()), (1, "1")),
        other => panic!("{other:?}"),
    }
    // Discs whose kinetic energy already overflows never get in.
    let too_fast = w.add_particle(Particle::new([9.0, 0.0], [1e200, 0.0], 0.5));
    assert!(matches!(
        too_fast,
        Err(ParticleError::EnergyOverflow { .. })
    ));
}

#[test]
fn a_step_needing_more_substeps_than_the_cap_is_refused_naming_dt_and_max_travel() {
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [1e9, 1e9]),
        max_travel: Some(0.01),
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    world
        .add_particle(Particle::new([5e8, 5e8], [1e6, 0.0], 0.5))
        .unwrap();
    let before = world.state_hash();
    // 1e6 × 0.01 / (0.01 × 0.5) = 2e6 substeps.
    let err = world.step(0.01).unwrap_err();
    assert!(matches!(err, StepError::TooManySubsteps { .. }), "{err}");
    let message = err.to_string();
    assert!(
        message.contains("dt 0.01") && message.contains("max_travel 0.01"),
        "{message}"
    );
    assert_eq!((world.step_count(), world.state_hash()), (0, before));
    assert!(bounce::plain::step(&mut world, 0.01).is_err());
    // Within the cap it steps: 1e3 × 0.01 / 0.005 = 2,000 substeps.
    world
        .set_velocity(bounce::ParticleId(0), [1e3, 0.0])
        .unwrap();
    assert_eq!(world.step(0.01).unwrap().substeps, 2000);
}

#[test]
fn an_emitter_at_an_absurd_rate_fills_its_region_and_no_more() {
    // 1e20 discs a second: a step places what the region holds (discs at least a collision
    // distance apart) and carries no more than a step's worth, every step ending.
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
        emitters: vec![bounce::Emitter {
            rate: 1e20,
            ..bounce::Emitter::new([2.0, 2.0], [8.0, 8.0], 0.5)
        }],
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    for _ in 0..3 {
        world.step(0.01).unwrap();
    }
    // At most the region grown by half a collision distance over each disc's share.
    let bound = (7.0 * 7.0 / (std::f64::consts::FRAC_PI_4 * 1.0)) as usize + 1;
    assert!(
        world.len() > 10 && world.len() <= bound,
        "{} discs",
        world.len()
    );
    assert!(world.colliding_pairs().is_empty(), "placed discs overlap");
}
