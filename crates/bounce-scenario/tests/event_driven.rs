//! The event-driven method from a scenario file: the `hard-discs` template's pressure
//! column gives the hard-disc equation of state, a misspelt method is an error naming the
//! field, what the method cannot do is refused naming the field, and a run resumed from its
//! checkpoint continues bit for bit.

use bounce_scenario::{Session, checkpoint};

/// The template's Z = P A / (N kT) over rows after the lattice has melted, against Monte
/// Carlo's 4.1062 at packing 0.5.
#[test]
fn the_hard_discs_template_gives_the_monte_carlo_equation_of_state() {
    let mut session = Session::builtin("hard-discs").unwrap();
    let area = {
        let (min, max) = session.world.config().boundary.bounds().unwrap();
        (max[0] - min[0]) * (max[1] - min[1])
    };
    let (mut z, mut rows) = (0.0, 0.0);
    for step in 0..600 {
        let stats = *session.step().unwrap();
        if step >= 50 {
            let kt = stats.kinetic_energy / 2000.0;
            z += stats.pressure.unwrap() * area / (2000.0 * kt);
            rows += 1.0;
        }
    }
    let z = z / rows;
    assert!((z / 4.1062 - 1.0).abs() < 0.005, "Z = {z}");
}

#[test]
fn a_misspelt_method_and_an_unsupported_combination_name_the_field() {
    let text = bounce_scenario::template("hard-discs").unwrap();
    let error = Session::from_text("typo.toml", &text.replace("\"event_driven\"", "\"events\""))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("method") && error.contains("events"),
        "{error}"
    );
    let error = Session::from_text(
        "substeps.toml",
        &text.replace("dt = 0.1 ", "substeps = 4\ndt = 0.1 "),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("method") && error.contains("substeps"),
        "{error}"
    );
}

#[test]
fn a_resumed_event_driven_run_continues_bit_for_bit() {
    let mut whole = Session::builtin("hard-discs").unwrap();
    let mut half = Session::builtin("hard-discs").unwrap();
    for _ in 0..20 {
        whole.step().unwrap();
        half.step().unwrap();
    }
    let bytes = checkpoint::encode(&half.world, None).unwrap();
    let mut resumed = Session::builtin("hard-discs").unwrap();
    resumed.world = checkpoint::decode(&bytes, "checkpoint.bin").unwrap().world;
    for _ in 0..20 {
        whole.step().unwrap();
        resumed.step().unwrap();
    }
    assert_eq!(whole.world.state_hash(), resumed.world.state_hash());
}
