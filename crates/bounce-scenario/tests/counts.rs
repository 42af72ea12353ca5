//! What `collisions` and `contacts` count: collisions are impacts (a pair meeting faster
//! than gravity's pull over a few substeps), contacts every pair found in every substep. A
//! touching Newton's cradle has five collisions and thousands of contacts; a settled pile
//! almost no collisions; a gas about as many of one as of the other.

use bounce_scenario::{Session, template};

/// Collisions and contacts over the whole run and over its last `tail` steps.
fn counts(text: &str, tail: u64) -> ([usize; 2], [usize; 2]) {
    let mut s = Session::from_text("t", text).unwrap();
    let (mut all, mut last) = ([0; 2], [0; 2]);
    let steps = s.steps;
    for k in 0..steps {
        let stats = s.step().unwrap();
        let step = [stats.collisions, stats.pairs];
        for i in 0..2 {
            all[i] += step[i];
            if k + tail >= steps {
                last[i] += step[i];
            }
        }
    }
    (all, last)
}

#[test]
fn a_touching_cradle_has_one_collision_per_blow_and_many_contacts() {
    // The template's row touching (spacing exactly two radii): the striker hits the first,
    // the blow passes down four touching pairs, the last flies off: five impacts. The
    // resting pairs are found in every step until the blow parts them.
    let text = template("newtons-cradle").unwrap().replace("2.002", "2.0");
    let ([collisions, contacts], _) = counts(&text, 0);
    assert_eq!(collisions, 5);
    assert!(contacts > 1000, "{contacts}");
}

#[test]
fn a_settled_pile_has_contacts_not_collisions_and_a_gas_has_both_alike() {
    let (_, [collisions, contacts]) = counts(template("pile").unwrap(), 200);
    assert!(contacts > 1_000_000, "{contacts}");
    assert!(
        (collisions as f64) < 0.01 * contacts as f64,
        "{collisions} of {contacts}"
    );
    // In a gas nearly every pair found is approaching: an impact.
    let ([collisions, contacts], _) = counts(template("gas").unwrap(), 0);
    assert!(
        collisions as f64 > 0.99 * contacts as f64 && collisions <= contacts,
        "{collisions} of {contacts}"
    );
}
