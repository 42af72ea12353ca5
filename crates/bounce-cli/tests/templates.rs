//! Every template shows its point, and its claims hold: each shipped scenario is run (some
//! shortened) and its headline, from `summary.json`, is held to what the template's comment
//! says, within the stated uncertainty.

mod common;

use common::{Scratch, bounce, output};

/// A template's headline after a run of it with `sets` (frames off): value, error, reference.
fn headline(name: &str, sets: &[&str]) -> (f64, Option<f64>, Option<f64>, String) {
    let s = Scratch::new();
    let scenario = s.path(&format!("{name}.toml"));
    let (code, _, err) = output(bounce().args(["new", name, "--out"]).arg(&scenario));
    assert_eq!(code, 0, "{err}");
    let mut command = bounce();
    command
        .arg("run")
        .arg(&scenario)
        .arg("--out")
        .arg(s.path("out"))
        .arg("-q");
    for set in [
        "output.frame_every=0",
        "output.gif=false",
        "output.plots=false",
    ]
    .iter()
    .chain(sets)
    {
        command.args(["--set", set]);
    }
    let (code, stdout, err) = output(&mut command);
    assert_eq!(code, 0, "{name}: {err}");
    assert!(
        stdout.contains("headline: ") && !stdout.contains("not measured"),
        "{name}: {stdout}"
    );
    let json = std::fs::read_to_string(s.path("out/summary.json")).unwrap();
    let number = |key: &str| -> Option<f64> {
        let line = json
            .lines()
            .find(|l| l.trim().starts_with(&format!("\"{key}\":")))?;
        line.split_once(':')?
            .1
            .trim()
            .trim_end_matches(',')
            .parse()
            .ok()
    };
    let detail = json
        .lines()
        .find(|l| l.contains("\"detail\""))
        .unwrap_or("")
        .to_string();
    (
        number("value").unwrap(),
        number("error"),
        number("reference"),
        detail,
    )
}

#[test]
fn the_gas_relaxes_to_maxwell_boltzmann() {
    let (distance, _, critical, _) = headline("gas", &[]);
    assert!(distance < critical.unwrap(), "KS {distance}");
}

#[test]
fn hard_discs_give_monte_carlos_equation_of_state() {
    // The template: Z at Monte Carlo's 4.106 (exact hard discs).
    let (z, error, reference, _) = headline("hard-discs", &[]);
    assert_eq!(reference, Some(4.1062));
    let error = error.unwrap();
    assert!(error < 0.1, "± {error}");
    assert!((z - 4.1062).abs() < 3.0 * error + 0.01, "Z = {z} ± {error}");
}

#[test]
fn the_sheared_gas_has_a_viscosity_about_a_tenth_above_enskogs() {
    // The template: about 1.1 times Enskog's 0.35 (1.10 ± 0.02 over seven seeds), ± 0.02 a run.
    let (eta, error, enskog, _) = headline("shear", &[]);
    let enskog = enskog.unwrap();
    assert!((enskog - 0.347).abs() < 0.002, "Enskog {enskog}");
    let error = error.unwrap();
    assert!(error > 0.005 && error < 0.05, "± {error}");
    assert!(
        (eta / enskog - 1.10).abs() < 3.0 * error / enskog + 0.02,
        "η = {eta} ± {error}"
    );
}

#[test]
fn the_galton_heap_is_about_two_and_a_half_binomials_wide() {
    // The template: the heap about 2.6 times as wide as the binomial's 1.55 bins.
    let (spread, _, binomial, _) = headline("galton-board", &[]);
    let binomial = binomial.unwrap();
    assert!((binomial - 0.5 * 2.4 * 15f64.sqrt()).abs() < 1e-12);
    assert!(
        (2.3..2.9).contains(&(spread / binomial)),
        "{spread} / {binomial}"
    );
}

#[test]
fn the_hourglass_empties_slowing_as_a_liquid() {
    // The template: about 90 grains a unit time, then 60, all 500 through within the run.
    let (rate, _, _, detail) = headline("hourglass", &[]);
    assert!((50.0..110.0).contains(&rate), "{rate}");
    assert!(
        detail.contains("500 grains") && detail.contains("slowing"),
        "{detail}"
    );
}

#[test]
fn the_piston_heats_its_gas_along_the_hard_disc_adiabat() {
    // The template: 3.34x where the adiabat says 3.25x.
    let (heating, _, adiabat, _) = headline("piston", &[]);
    assert!((heating - 3.34).abs() < 0.05, "{heating}");
    assert!((adiabat.unwrap() - 3.25).abs() < 0.01, "{adiabat:?}");
}

#[test]
fn the_chamber_drains_at_the_effusion_rate() {
    // The template: one run about 60 ± 7 against the formula's about 55.
    let (lost, error, formula, _) = headline("effusion", &[]);
    let (error, formula) = (error.unwrap(), formula.unwrap());
    assert!((formula - 54.9).abs() < 1.0, "{formula}");
    assert!(
        (lost - formula).abs() < 2.5 * error,
        "{lost} ± {error} against {formula}"
    );
}

#[test]
fn the_driven_granular_gas_settles_near_van_noije_and_ernsts_temperature() {
    // The template: about 1.13 against the theory's 1.10.
    let (t, error, theory, _) = headline("driven-granular", &[]);
    assert!((theory.unwrap() - 1.104).abs() < 0.001);
    assert!((t - 1.13).abs() < 0.03 && error.unwrap() < 0.02, "{t}");
}

#[test]
fn the_heap_stands_at_about_twenty_four_degrees() {
    let (angle, _, _, _) = headline("angle-of-repose", &[]);
    assert!((20.0..28.0).contains(&angle), "{angle}");
}

#[test]
fn the_brownian_disc_is_still_nearly_ballistic() {
    // The template: the MSD's exponent still about 1.7–2 over the run.
    let (d, _, _, detail) = headline("brownian", &[]);
    assert!(d > 0.0);
    let exponent: f64 = detail.split("t^").nth(1).unwrap()[..4].parse().unwrap();
    assert!((1.5..2.2).contains(&exponent), "{detail}");
}

#[test]
fn the_cradle_passes_the_blow_to_the_last_disc() {
    let (ratio, _, _, detail) = headline("newtons-cradle", &[]);
    assert!((ratio - 1.0).abs() < 1e-9, "{ratio}");
    assert!(detail.contains("at most 0 "), "{detail}");
}

#[test]
fn the_two_gases_begin_to_mix() {
    let (index, _, _, detail) = headline("mixing", &[]);
    assert!(index > 0.0 && index < 1.0, "{index}");
    assert!(detail.contains("0 at the start"), "{detail}");
}

#[test]
fn the_pile_settles_densely() {
    let (packing, _, _, _) = headline("pile", &[]);
    assert!((0.78..0.9).contains(&packing), "{packing}");
}

#[test]
fn the_million_reports_its_throughput() {
    let (rate, _, _, _) = headline("million", &["time.steps=2"]);
    assert!(rate > 0.0);
}
