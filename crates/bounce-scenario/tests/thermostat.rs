//! Thermostats and drives in a scenario, against theory: a white-noise-driven granular gas
//! settles at van Noije & Ernst's temperature; velocity rescaling and Andersen's bath hold
//! the bath's temperature in an elastic gas; the same bits on 1 and 2 threads, by the plain
//! step, and across a checkpoint; a bad thermostat names the field and its line.

use bounce_scenario::{Session, checkpoint};

/// 2,000 hard discs of diameter 1 at packing 0.2, periodic, event-driven (exact collisions),
/// observed every `dt`, with `extra` in `[world]`.
fn gas(world: &str, time: &str) -> String {
    let side = (2000.0 * std::f64::consts::PI * 0.25 / 0.2f64).sqrt();
    format!(
        r#"
[world]
boundary = "periodic"
min = [0.0, 0.0]
max = [{side}, {side}]
{world}

[time]
{time}

[[gas]]
count = 2000
radius = 0.5
temperature = 1.1
placement = "lattice"
zero_momentum = true
seed = 4
"#
    )
}

/// The mean of the step's temperature (kT) from step `from` to `to`.
fn mean_temperature(session: &mut Session, from: u64, to: u64) -> f64 {
    let mut sum = 0.0;
    for step in 1..=to {
        let stats = *session.step().unwrap();
        if step > from {
            let n = session.world.len() as f64;
            let m = 0.5; // mass = radius, the seed's
            let p = stats.momentum;
            let centre = (p[0] * p[0] + p[1] * p[1]) / (2.0 * m * n);
            sum += (stats.kinetic_energy - centre) / n;
        }
    }
    sum / (to - from) as f64
}

#[test]
fn a_white_noise_driven_granular_gas_settles_at_van_noije_and_ernsts_temperature() {
    let (e, rate, bath): (f64, f64, f64) = (0.9, 0.1, 1.0);
    let text = gas(
        &format!(
            "coefficient_of_restitution = {e}\nrestitution_model = \"relative_normal_velocity\"\n\
             thermostat = {{ kind = \"white_noise\", temperature = {bath}, rate = {rate}, seed = 3 }}"
        ),
        "method = \"event_driven\"\ndt = 0.05\nsteps = 1000",
    );
    let mut session = Session::from_text("driven.toml", &text).unwrap();
    // Steady state: the noise's input, 2 rate T_bath (1 − 1/N) a disc, equals the collisions'
    // loss, ζ T = (1 − e²) n σ χ √π T^{3/2} / √m (1 + 3 a₂/16), with Enskog's contact value χ
    // (Henderson's) and the Sonine coefficient of the white-noise-driven gas (van Noije &
    // Ernst, Granular Matter 1, 57 (1998)).
    let (n_discs, eta, m, sigma) = (2000.0, 0.2, 0.5f64, 1.0);
    let density = eta / (std::f64::consts::PI / 4.0);
    let chi = (1.0 - 7.0 * eta / 16.0) / (1.0 - eta).powi(2);
    let a2 = 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e)
        / (73.0 + 56.0 * 2.0 - 24.0 * 2.0 * e - 105.0 * e + 30.0 * (1.0 - e) * e * e);
    let input = 2.0 * rate * bath * (1.0 - 1.0 / n_discs);
    let loss = (1.0 - e * e) * density * sigma * chi * std::f64::consts::PI.sqrt() / m.sqrt()
        * (1.0 + 3.0 * a2 / 16.0);
    let theory = (input / loss).powf(2.0 / 3.0);
    // About 5 time units to settle (1/ζ), then 40 averaged.
    let measured = mean_temperature(&mut session, 200, 1000);
    assert!(
        (measured / theory - 1.0).abs() < 0.05,
        "T = {measured}, van Noije & Ernst: {theory}"
    );
    // Without the drive the same gas cools (Haff): the thermostat is what holds it.
    let cooling = gas(
        &format!(
            "coefficient_of_restitution = {e}\nrestitution_model = \"relative_normal_velocity\""
        ),
        "method = \"event_driven\"\ndt = 0.05\nsteps = 1000",
    );
    let mut cooling = Session::from_text("cooling.toml", &cooling).unwrap();
    assert!(mean_temperature(&mut cooling, 200, 400) < 0.5 * theory);
}

#[test]
fn rescaling_and_andersen_hold_an_elastic_gas_at_the_baths_temperature() {
    for (kind, rate) in [("rescale", 2.0), ("andersen", 0.5)] {
        let text = gas(
            &format!("thermostat = {{ kind = \"{kind}\", temperature = 2.5, rate = {rate} }}"),
            "method = \"event_driven\"\ndt = 0.05\nsteps = 600",
        );
        let mut session = Session::from_text("bath.toml", &text).unwrap();
        let measured = mean_temperature(&mut session, 300, 600);
        assert!(
            (measured / 2.5 - 1.0).abs() < 0.02,
            "{kind}: T = {measured}"
        );
        let work = session.world.stats().thermostat_work;
        assert!(work.is_finite());
    }
}

#[test]
fn a_thermostatted_run_gives_the_same_bits_on_threads_by_the_plain_step_and_after_a_resume() {
    // Time-stepped, walls, three kinds in turn.
    for kind in ["rescale", "andersen", "white_noise"] {
        let text = format!(
            r#"
[world]
boundary = "walls"
min = [0.0, 0.0]
max = [40.0, 40.0]
coefficient_of_restitution = 0.8
thermostat = {{ kind = "{kind}", temperature = 1.0, rate = 3.0, seed = 9 }}

[time]
dt = 0.01
steps = 60

[[gas]]
count = 600
radius = [0.3, 0.5]
speed = 1.0
seed = 2
"#
        );
        let run = |threads: usize, plain: bool, steps: u64| {
            let mut s = Session::from_text("t.toml", &text).unwrap();
            s.world.set_threads(threads).unwrap();
            s.world.set_parallel_min_work(0);
            for _ in 0..steps {
                if plain {
                    bounce::plain::step(&mut s.world, 0.01).unwrap();
                } else {
                    s.world.step(0.01).unwrap();
                }
            }
            s
        };
        let one = run(1, false, 60);
        assert_eq!(
            run(2, false, 60).world.state_hash(),
            one.world.state_hash(),
            "{kind}"
        );
        assert_eq!(
            run(1, true, 60).world.state_hash(),
            one.world.state_hash(),
            "{kind}"
        );
        let half = run(2, false, 30);
        let bytes = checkpoint::encode(&half.world, None).unwrap();
        let mut resumed = checkpoint::decode(&bytes, "t.ckpt").unwrap().world;
        for _ in 0..30 {
            resumed.step(0.01).unwrap();
        }
        assert_eq!(resumed.state_hash(), one.world.state_hash(), "{kind}");
        // The thermostat acted: the run differs from one without it.
        let off =
            Session::from_text("off.toml", &text.replace("thermostat", "# thermostat")).unwrap();
        let mut off = off;
        for _ in 0..60 {
            off.world.step(0.01).unwrap();
        }
        assert_ne!(off.world.state_hash(), one.world.state_hash(), "{kind}");
    }
}

#[test]
fn a_bad_thermostat_names_the_field_and_its_line() {
    let text = gas(
        "thermostat = { kind = \"rescale\", temperature = -1.0, rate = 1.0 }",
        "dt = 0.01\nsteps = 1",
    );
    let e = Session::from_text("bad.toml", &text)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.toml:6") && e.contains("temperature -1"),
        "{e}"
    );
    let text = gas(
        "thermostat = { kind = \"nose_hoover\", temperature = 1.0, rate = 1.0 }",
        "dt = 0.01\nsteps = 1",
    );
    let e = Session::from_text("bad.toml", &text)
        .unwrap_err()
        .to_string();
    assert!(e.contains("nose_hoover") && e.contains("rescale"), "{e}");
    let text = gas(
        "thermostat = { kind = \"andersen\", temperature = 1.0, rate = 0.0 }",
        "dt = 0.01\nsteps = 1",
    );
    let e = Session::from_text("bad.toml", &text)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rate 0") && e.contains("> 0"), "{e}");
}
