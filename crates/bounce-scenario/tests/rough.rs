//! Rough discs in a scenario: the `[world]` fields, `[[obstacle]] friction`, `[[disc]]
//! angular_velocity` and `[[gas]] spin` reach the world; a bad value is an error naming the
//! field and its line; a trajectory carries the orientations and spins HOOMD-blue's way and
//! a run restarts from it with them; a checkpoint keeps them, and a resumed run equals an
//! uninterrupted one.

use bounce::ParticleId;
use bounce_scenario::{Session, checkpoint, gsd::GsdWriter};

const ROUGH: &str = r#"
[world]
boundary = "walls"
min = [0.0, 0.0]
max = [30.0, 20.0]
gravity = [0.0, -10.0]
friction = 0.4
wall_friction = 0.8
tangential_restitution = 0.2
rolling_resistance = 0.01
inertia_factor = 0.4

[time]
dt = 0.005
steps = 100
substeps = 2

[[obstacle]]
segment = [[2.0, 6.0], [20.0, 2.0]]
friction = 0.9

[[obstacle]]
peg = [24.0, 8.0]
radius = 1.0

[[disc]]
position = [10.0, 15.0]
velocity = [1.0, 0.0]
radius = 0.6
angular_velocity = 5.0

[[gas]]
count = 200
radius = [0.2, 0.4]
speed = 2.0
spin = 3.0
region = { min = [1.0, 8.0], max = [29.0, 19.0] }
"#;

#[test]
fn the_scenarios_rough_fields_reach_the_world() {
    let s = Session::from_text("rough.toml", ROUGH).unwrap();
    let c = s.world.config();
    assert_eq!(
        (
            c.friction,
            c.wall_friction,
            c.tangential_restitution,
            c.rolling_resistance,
            c.inertia_factor
        ),
        (0.4, Some(0.8), 0.2, 0.01, 0.4)
    );
    assert_eq!(c.obstacles[0].friction, Some(0.9));
    assert_eq!(c.obstacles[1].friction, None);
    assert_eq!(c.obstacle_friction(&c.obstacles[1]), 0.4);
    let spins = s.world.angular_velocities();
    assert_eq!(spins[0], 5.0);
    // The gas's spins: uniform in ±3, not all alike.
    let gas = &spins[1..];
    assert!(gas.iter().all(|w| w.abs() <= 3.0));
    let mean = gas.iter().sum::<f64>() / gas.len() as f64;
    assert!(
        mean.abs() < 0.5 && gas.iter().any(|w| w.abs() > 2.0),
        "{mean}"
    );
    // The same gas without spin: the same places and velocities.
    let plain = Session::from_text("rough.toml", &ROUGH.replace("spin = 3.0", "")).unwrap();
    for k in 1..201 {
        let (a, b) = (
            s.world.particle(ParticleId(k)).unwrap(),
            plain.world.particle(ParticleId(k)).unwrap(),
        );
        assert_eq!((a.position, a.velocity), (b.position, b.velocity));
    }
    // A smooth scenario keeps no rotation state at all.
    let smooth = ROUGH
        .replace("friction = 0.4\n", "")
        .replace("wall_friction = 0.8\n", "")
        .replace("rolling_resistance = 0.01\n", "")
        .replace("friction = 0.9\n", "")
        .replace("angular_velocity = 5.0\n", "")
        .replace("spin = 3.0\n", "");
    let s = Session::from_text("smooth.toml", &smooth).unwrap();
    assert!(!s.world.particles().turns());
    assert!(s.world.particles().angular_velocity().is_empty());
}

#[test]
fn a_bad_rough_value_is_an_error_naming_the_field_and_its_line() {
    for (from, to, field) in [
        ("friction = 0.4", "friction = -0.4", "friction"),
        (
            "wall_friction = 0.8",
            "wall_friction = inf",
            "wall_friction",
        ),
        (
            "tangential_restitution = 0.2",
            "tangential_restitution = 1.5",
            "tangential_restitution",
        ),
        (
            "rolling_resistance = 0.01",
            "rolling_resistance = -1.0",
            "rolling_resistance",
        ),
        (
            "inertia_factor = 0.4",
            "inertia_factor = 0.0",
            "inertia_factor",
        ),
        ("friction = 0.9", "friction = -2.0", "friction"),
    ] {
        let text = ROUGH.replacen(from, to, 1);
        let err = match Session::from_text("rough.toml", &text) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{to} accepted"),
        };
        // The world's fields at their own line, an obstacle's at its table's.
        let line = text.lines().position(|l| l == to).unwrap() + 1;
        let line = if field == "friction" && to.contains("-2") {
            text.lines().position(|l| l == "[[obstacle]]").unwrap() + 1
        } else {
            line
        };
        assert!(err.contains(field), "{to}: {err}");
        assert!(err.contains(&format!("rough.toml:{line}:")), "{to}: {err}");
    }
}

#[test]
fn a_trajectory_carries_the_spins_and_a_run_restarts_from_it() {
    let mut run = Session::from_text("rough.toml", ROUGH).unwrap();
    for _ in 0..40 {
        run.step().unwrap();
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.gsd");
    let mut gsd = GsdWriter::create(&path, &run.types, &run.typeid).unwrap();
    gsd.frame(&run.world).unwrap();
    gsd.finish().unwrap();
    let text = format!(
        "[world]\nboundary = \"walls\"\nmin = [0.0, 0.0]\nmax = [30.0, 20.0]\nfriction = 0.4\n\
         inertia_factor = 0.4\n[time]\ndt = 0.005\nsteps = 1\n[[file]]\npath = {:?}\n",
        path.display().to_string()
    );
    let start = Session::from_text("restart.toml", &text).unwrap();
    let (spins, turned) = (run.world.angular_velocities(), run.world.orientations());
    assert!(turned.iter().any(|&t| t > 0.1), "the discs turned");
    for (k, (a, b)) in start
        .world
        .angular_velocities()
        .iter()
        .zip(&spins)
        .enumerate()
    {
        assert!((a - b).abs() < 1e-5 * (1.0 + b.abs()), "{k}: ω {a} vs {b}");
    }
    for (k, (a, b)) in start.world.orientations().iter().zip(&turned).enumerate() {
        let gap = (a - b).abs();
        assert!(
            gap < 1e-5 || (gap - std::f64::consts::TAU).abs() < 1e-5,
            "{k}: θ {a} vs {b}"
        );
    }
}

#[test]
fn a_checkpoint_keeps_the_spins_and_a_resumed_run_equals_an_uninterrupted_one() {
    let mut whole = Session::from_text("rough.toml", ROUGH).unwrap();
    let mut first = Session::from_text("rough.toml", ROUGH).unwrap();
    for _ in 0..30 {
        whole.step().unwrap();
        first.step().unwrap();
    }
    assert!(first.world.friction_work() > 0.0);
    let bytes = checkpoint::encode(&first.world, None).unwrap();
    let mut resumed = checkpoint::decode(&bytes, "rough.ckpt").unwrap().world;
    assert_eq!(resumed.state_hash(), first.world.state_hash());
    assert_eq!(resumed.friction_work(), first.world.friction_work());
    for _ in 0..30 {
        whole.step().unwrap();
        resumed.step(0.005).unwrap();
    }
    assert_eq!(resumed.state_hash(), whole.world.state_hash());
    assert_eq!(resumed.friction_work(), whole.world.friction_work());
}

/// The `angle-of-repose` template run whole with `friction` and `rolling_resistance`: the
/// heap's angle in degrees.
fn repose(friction: f64, rolling: f64) -> Option<f64> {
    let text = bounce_scenario::template("angle-of-repose")
        .unwrap()
        .replace(
            "friction = 0.5\nwall_friction",
            &format!("friction = {friction:?}\nwall_friction"),
        )
        .replace(
            "rolling_resistance = 0.1",
            &format!("rolling_resistance = {rolling:?}"),
        );
    let mut s = Session::from_text("angle-of-repose.toml", &text).unwrap();
    assert_eq!(s.world.config().friction, friction);
    for _ in 0..s.steps {
        s.step().unwrap();
    }
    assert_eq!(s.world.len(), 1000);
    bounce_scenario::analysis::repose_angle(&s.world, 0.0, 2.0)
}

#[test]
fn a_poured_heap_stands_steeper_with_friction_and_rolling_resistance() {
    // Smooth discs flow out flat; friction holds a heap; rolling resistance a steeper one.
    let smooth = repose(0.0, 0.0).unwrap_or(0.0);
    let rough = repose(0.5, 0.0).unwrap();
    let rolling = repose(0.5, 0.1).unwrap();
    assert!(smooth < 3.0, "smooth discs: {smooth}°");
    assert!((10.0..22.0).contains(&rough), "μ = 0.5: {rough}°");
    assert!(
        rolling > rough + 4.0,
        "μ = 0.5, μ_r = 0.1: {rolling}° against {rough}°"
    );
}
