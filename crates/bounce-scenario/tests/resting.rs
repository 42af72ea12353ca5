//! `resting_contacts = "rest"` in a scenario: the shipped pile settles stiller than under
//! the seed's bounce of every contact, with smaller overlaps, and the field is read from the
//! file and checked.

use bounce_scenario::{Session, template};

/// The pile template run whole with `resting_contacts` = `mode`: the kinetic energy and the
/// largest overlap, each the mean over the last 100 steps.
fn settled(mode: &str) -> (f64, f64) {
    let text = template("pile").unwrap().replace(
        "coefficient_of_restitution = 0.7",
        &format!("coefficient_of_restitution = 0.7\nresting_contacts = \"{mode}\""),
    );
    let mut s = Session::from_text("pile", &text).unwrap();
    let rest = s.world.config().resting_contacts;
    assert_eq!(format!("{rest:?}").to_lowercase(), mode);
    let (mut kinetic, mut overlap) = (0.0, 0.0);
    let steps = s.steps;
    for k in 0..steps {
        let stats = s.step().unwrap();
        if k + 100 >= steps {
            kinetic += stats.kinetic_energy / 100.0;
            overlap += stats.max_overlap / 100.0;
        }
    }
    (kinetic, overlap)
}

#[test]
fn the_pile_settles_stiller_when_resting_contacts_rest() {
    let (seed_kinetic, seed_overlap) = settled("bounce");
    let (kinetic, overlap) = settled("rest");
    assert!(
        kinetic < 0.25 * seed_kinetic,
        "kinetic energy {kinetic} against the seed's {seed_kinetic}"
    );
    assert!(
        overlap < 0.75 * seed_overlap,
        "largest overlap {overlap} against the seed's {seed_overlap}"
    );
}

#[test]
fn a_misspelt_mode_is_an_error_naming_the_field() {
    let text = template("pile")
        .unwrap()
        .replace("[time]", "resting_contacts = \"still\"\n\n[time]");
    let err = match Session::from_text("pile.toml", &text) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted"),
    };
    assert!(
        err.contains("resting_contacts") || err.contains("still"),
        "{err}"
    );
    assert!(err.contains("bounce") && err.contains("rest"), "{err}");
}
