//! Absurd inputs end in a clear error naming the field, or in a run that finishes: never in
//! an infinite clock.

use bounce_scenario::Session;

const SCENARIO: &str = r#"
[world]
min = [0.0, 0.0]
max = [10.0, 10.0]
[time]
dt = DT
steps = STEPS
[[disc]]
position = [5.0, 5.0]
velocity = [1.0, 0.0]
radius = 0.5
"#;

fn session(dt: &str, steps: &str) -> Result<Session, String> {
    let text = SCENARIO.replace("DT", dt).replace("STEPS", steps);
    Session::from_text("a.toml", &text).map_err(|e| e.to_string())
}

#[test]
fn a_time_step_that_overflows_the_clock_is_refused_naming_it() {
    for (dt, steps) in [("1e308", "100"), ("1e300", "1000000000")] {
        let Err(error) = session(dt, steps) else {
            panic!("dt {dt} for {steps} steps was accepted");
        };
        assert!(
            error.contains("a.toml:6") && error.contains(&format!("time.dt = {dt}")),
            "{error}"
        );
        assert!(error.contains("overflows the clock"), "{error}");
    }
    // Large but finite over the run: it runs, and the clock stays finite.
    let mut s = session("1e300", "10").unwrap();
    s.run_until(10, |_, _| {
        Ok::<_, bounce::StepError>(std::ops::ControlFlow::Continue(()))
    })
    .unwrap();
    assert!(s.world.time().is_finite() && s.world.time() > 9e300);
}

#[test]
fn obstacles_count_in_the_memory_limit() {
    // Three million pegs (about 1.3 GB in a run) under a 1 GiB limit: refused before the
    // world is built, the message counting them.
    let text = r#"
[world]
min = [0.0, 0.0]
max = [40000.0, 40000.0]
[time]
dt = 0.01
steps = 1
[[disc]]
position = [0.5, 0.5]
velocity = [1.0, 0.0]
radius = 0.2
[[obstacle]]
pegs = { origin = [1.0, 1.0], rows = 1500, columns = 2000, spacing = [10.0, 10.0] }
radius = 0.1
[[obstacle]]
polyline = [[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]]
closed = true
"#;
    let scenario = bounce_scenario::parse(text, "p.toml").unwrap();
    let estimate = scenario.estimate().unwrap();
    assert_eq!(estimate.obstacles, 3_000_003);
    let Err(error) = scenario.build_with(text, "p.toml", &bounce_scenario::Limits::memory_gib(1.0))
    else {
        panic!("three million pegs were built under a 1 GiB limit");
    };
    let message = error.to_string();
    assert!(
        message.contains("1 particles and 3000003 obstacles"),
        "{message}"
    );
    // Each table's count is what it makes.
    let small = text.replace("rows = 1500, columns = 2000", "rows = 3, columns = 5");
    let scenario = bounce_scenario::parse(&small, "p.toml").unwrap();
    let made: usize = scenario
        .obstacle
        .iter()
        .map(|o| o.get_ref().expand().len())
        .sum();
    assert_eq!(scenario.estimate().unwrap().obstacles, made as u64);
    assert_eq!(made, 15 + 3);
}

#[test]
fn a_collision_distance_whose_square_overflows_is_refused() {
    // Found by the fuzzer: the cradle at scale 1e308 reached an infinite overlap and a NaN
    // pressure.
    let text = SCENARIO
        .replace("DT", "0.01")
        .replace("STEPS", "5")
        .replace("[time]", "collision_radius_scale = 1e308\n[time]");
    let Err(error) = Session::from_text("a.toml", &text).map(|_| ()) else {
        panic!("scale 1e308 was accepted");
    };
    let error = error.to_string();
    assert!(
        error.contains("2 r collision_radius_scale") && error.contains("1e150"),
        "{error}"
    );
    // Open worlds too: a radius of 1e300 reaches beyond any square.
    let open = "[world]\nboundary = \"open\"\n[time]\ndt = 0.01\nsteps = 5\n\
                [[disc]]\nposition = [0.0, 0.0]\nradius = 1e300\n";
    let error = Session::from_text("b.toml", open).map(|_| ()).unwrap_err();
    assert!(error.to_string().contains("b.toml"), "{error}");
}

#[test]
fn a_trajectory_frame_beyond_32_bit_floats_is_an_error_naming_the_disc() {
    // An open world admits any finite place; HOOMD's frames hold 32-bit floats, so a disc
    // at 1e39 cannot be written, and saying so beats writing an infinity.
    let open = "[world]\nboundary = \"open\"\n[time]\ndt = 0.01\nsteps = 5\n\
                [[disc]]\nposition = [0.0, 0.0]\nradius = 1.0\n\
                [[disc]]\nposition = [1e39, 0.0]\nradius = 1.0\n";
    let session = Session::from_text("c.toml", open).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.gsd");
    let mut gsd =
        bounce_scenario::gsd::GsdWriter::create(&path, &session.types, &session.typeid).unwrap();
    let error = gsd.frame(&session.world).unwrap_err().to_string();
    assert!(
        error.contains("disc 1") && error.contains("position") && error.contains("32-bit"),
        "{error}"
    );
}
