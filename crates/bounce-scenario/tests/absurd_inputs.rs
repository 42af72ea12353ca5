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
