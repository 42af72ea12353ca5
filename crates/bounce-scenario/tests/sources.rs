//! Emitters and sinks through scenarios: discs come and go deterministically (any thread
//! count, across a resume in the middle of emission), ids are never reused, and the
//! emitted discs take their emitter's colour and type.

use std::ops::ControlFlow;

use bounce::{ParticleId, StepError};
use bounce_scenario::Session;

const FLOW: &str = r##"
[world]
min = [0.0, 0.0]
max = [60.0, 30.0]
gravity = [0.0, -1.0]
coefficient_of_restitution = 0.9

[time]
dt = 0.02
steps = 600
substeps = 2

[[gas]]
count = 50
radius = 0.4
speed = 1.0
seed = 3
region = { min = [20.0, 5.0], max = [40.0, 25.0] }

[[emitter]]
region = { min = [1.0, 10.0], max = [3.0, 28.0] }
rate = 40.0
radius = [0.3, 0.5]
velocity = [10.0, 0.0]
spread = 0.5
seed = 7
color = "#ff0000"
type = "fresh"

[[obstacle]]
pegs = { origin = [15.0, 4.0], rows = 6, columns = 8, spacing = [4.0, 4.0] }
radius = 0.5

[[sink]]
region = { min = [55.0, 0.0], max = [60.0, 30.0] }
"##;

fn flow(threads: usize) -> Session {
    let mut s = Session::from_text("flow.toml", FLOW).unwrap();
    s.world.set_threads(threads).unwrap();
    s
}

#[test]
fn discs_come_and_go_with_the_same_bits_on_any_thread_count() {
    let (mut a, mut b) = (flow(1), flow(3));
    let mut max_id_seen = 0;
    let (mut emitted, mut removed) = (0, 0);
    for _ in 0..600 {
        let sa = *a.step().unwrap();
        b.step().unwrap();
        emitted += sa.emitted;
        removed += sa.removed;
        // A new disc always has an id above every id given before.
        for &(id, _) in a.world.emitted_last_step() {
            assert!(id.0 >= max_id_seen, "id {} reused", id.0);
            max_id_seen = id.0 + 1;
        }
    }
    assert_eq!(a.world.state_hash(), b.world.state_hash());
    // 12 time units at 40 per unit: 480 due (a few attempts may land on a disc and wait).
    assert!((400..=480).contains(&emitted), "emitted {emitted}");
    assert!(removed >= 5, "the sink removed {removed}");
    assert_eq!(a.world.len(), 50 + emitted - removed);
    assert_eq!(a.world.next_id() as usize, 50 + emitted);
    // Emitted discs are the emitter's colour and type; the gas keeps its own.
    let fresh = a.types.iter().position(|t| t == "fresh").unwrap() as u32;
    let last = ParticleId(a.world.next_id() - 1);
    assert_eq!(a.world.emitter_of(last), Some(0));
    assert_eq!(a.colours[last.0 as usize], Some([255, 0, 0]));
    assert_eq!(a.typeid[last.0 as usize], fresh);
    assert_eq!(a.world.emitter_of(ParticleId(0)), None);
    // No disc inside a peg or a sink.
    let p = a.world.particles();
    for i in 0..p.len() {
        assert!(p.x()[i] < 55.0 + 0.5, "a disc in the sink at {}", p.x()[i]);
    }
}

#[test]
fn a_resume_in_the_middle_of_emission_continues_bit_for_bit() {
    let mut straight = flow(2);
    for _ in 0..400 {
        straight.step().unwrap();
    }
    let mut first = flow(2);
    for _ in 0..200 {
        first.step().unwrap();
    }
    let bytes = bounce_scenario::checkpoint::encode(&first.world, None).unwrap();
    let mut resumed = flow(1);
    let loaded = bounce_scenario::checkpoint::decode(&bytes, "c").unwrap();
    resumed.resume(loaded.world, "c").unwrap();
    // The discs emitted before the checkpoint got their colours back.
    assert_eq!(resumed.colours, first.colours);
    for _ in 0..200 {
        resumed.step().unwrap();
    }
    assert_eq!(resumed.world.state_hash(), straight.world.state_hash());
    assert_eq!(
        resumed.world.emitter_states(),
        straight.world.emitter_states()
    );
    assert_eq!(resumed.colours, straight.colours);
    assert_eq!(resumed.typeid, straight.typeid);
}

#[test]
fn emitter_and_sink_tables_with_problems_are_refused_with_their_lines() {
    let text = r#"
[world]
min = [0.0, 0.0]
max = [10.0, 10.0]
[time]
dt = 0.01
steps = 10
[[emitter]]
region = { min = [1.0, 1.0], max = [0.0, 2.0] }
rate = 1.0
radius = 0.5
[[emitter]]
region = { min = [1.0, 1.0], max = [2.0, 2.0] }
rate = -3.0
radius = 0.5
[[sink]]
region = { min = [5.0, 5.0], max = [5.0, 6.0] }
[[emitter]]
region = { min = [8.0, 8.0], max = [12.0, 9.0] }
rate = 1.0
radius = 0.5
"#;
    let error = Session::from_text("bad.toml", text)
        .unwrap_err()
        .to_string();
    for expected in [
        "bad.toml:8: emitter #1: min [1.0, 1.0], max [0.0, 2.0]: the region must be finite with min below max",
        "bad.toml:12: emitter #2: rate -3: must be finite and >= 0",
        "bad.toml:16: sink #1: min [5.0, 5.0], max [5.0, 6.0]: the region must be finite",
        "bad.toml:18: emitter #3: min [8.0, 8.0], max [12.0, 9.0]: the region must lie inside the box",
    ] {
        assert!(
            error.contains(expected),
            "missing {expected:?} in:\n{error}"
        );
    }
}

#[test]
fn the_effusion_template_leaks_at_kinetic_theorys_rate_over_twelve_seeds() {
    // Kinetic theory: through a hole of width w in 2D, n v̄ w / π discs leave per unit time,
    // v̄ = √(π kT / 2m) the mean speed. With the left chamber's count N draining as
    // dN/dt = −(N / A) v̄ w / π, it loses N0 (1 − exp(−v̄ w t / (π A))) in a time t.
    // The measure: the discs left of the wall (x < 40) after 6,000 steps (t = 120), against
    // the 600 at the start, mean and standard error over 12 seeds of the gas.
    let text = bounce_scenario::template("effusion").unwrap();
    let (n0, area, w, m, kt, t) = (600.0, 40.0 * 40.0, 2.0, 0.4, 1.0, 120.0);
    let mean_speed = (std::f64::consts::PI * kt / (2.0 * m)).sqrt();
    let theory = n0 * (1.0 - (-mean_speed * w * t / (std::f64::consts::PI * area)).exp());
    let losses: Vec<f64> = (1..=12)
        .map(|seed| {
            let text = text.replace("seed = 5", &format!("seed = {seed}"));
            let mut s = Session::from_text("effusion", &text).unwrap();
            s.run_until(6000, |_, _| Ok::<_, StepError>(ControlFlow::Continue(())))
                .unwrap();
            let left = s
                .world
                .particles()
                .x()
                .iter()
                .filter(|&&x| x < 40.0)
                .count();
            n0 - left as f64
        })
        .collect();
    let k = losses.len() as f64;
    let mean = losses.iter().sum::<f64>() / k;
    let sd = (losses.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
    let error = sd / k.sqrt();
    eprintln!("effusion: lost {mean:.1} ± {error:.1} (sd {sd:.1}) of 600, theory {theory:.1}");
    // Within three standard errors and 10 % of the theory (the hole's edges and the discs'
    // size make the real hole a little narrower than w).
    assert!(
        (mean - theory).abs() < (3.0 * error).max(0.1 * theory),
        "lost {mean} ± {error} against {theory}: {losses:?}"
    );
}
