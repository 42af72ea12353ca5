//! `bounce check` lists every problem of a file in one run, in line order: type errors past
//! the first, semantic problems past a table's first, the placement's problems beside the
//! reading's, a `--set` typo named by its override with the nearest key, and values echoed as
//! they were written.

mod common;

use common::{Scratch, bounce, output};

/// `bounce check` on `text`: (exit code, the problem lines of standard error).
fn check(text: &str, sets: &[&str]) -> (i32, Vec<String>) {
    let s = Scratch::new();
    let file = s.scenario("many.toml", text);
    let mut command = bounce();
    command.arg("check").arg(&file);
    for set in sets {
        command.arg("--set").arg(set);
    }
    let (code, _, stderr) = output(&mut command);
    assert!(!stderr.contains("panicked"), "{stderr}");
    (code, stderr.lines().map(str::to_string).collect())
}

/// The line numbers the problems name, in order (`many.toml:12: ...`).
fn lines_named(problems: &[String]) -> Vec<usize> {
    problems
        .iter()
        .filter_map(|p| {
            p.split_once("many.toml:")?
                .1
                .split(':')
                .next()?
                .parse()
                .ok()
        })
        .collect()
}

#[test]
fn a_bad_gas_hides_neither_a_bad_restitution_nor_a_disc_outside_the_box() {
    let text = "\
[world]
min = [0.0, 0.0]
max = [10.0, 10.0]
coefficient_of_restitution = 1.5

[time]
dt = 0.01
steps = 5

[[gas]]
count = 10
radius = -0.5
speed = 1.0

[[disc]]
position = [50.0, 5.0]
radius = 0.5
";
    let (code, problems) = check(text, &[]);
    assert_eq!(code, 1);
    assert_eq!(lines_named(&problems), vec![4, 10, 15], "{problems:#?}");
    assert!(
        problems[0].contains("coefficient_of_restitution"),
        "{problems:#?}"
    );
    // The radius as written: a number, not a range made of it.
    assert!(problems[1].contains("radius = -0.5:"), "{problems:#?}");
    assert!(problems[2].contains("disc #1"), "{problems:#?}");
}

#[test]
fn an_overlapping_pair_is_listed_beside_another_discs_bad_radius() {
    let text = "\
[world]
min = [0.0, 0.0]
max = [10.0, 10.0]

[time]
dt = 0.01
steps = 5

[[disc]]
position = [2.0, 2.0]
radius = -1.0

[[disc]]
position = [5.0, 5.0]
radius = 1.0

[[disc]]
position = [5.5, 5.0]
radius = 1.0
";
    let (code, problems) = check(text, &[]);
    assert_eq!(code, 1);
    assert_eq!(lines_named(&problems), vec![9, 17], "{problems:#?}");
    assert!(problems[0].contains("disc #1"), "{problems:#?}");
    assert!(
        problems[1].contains("overlap") && problems[1].contains("disc #2"),
        "{problems:#?}"
    );
    // With disc #1 left out, the ids are not a run's: the message names tables, not ids.
    assert!(!problems[1].contains("discs 0 and 1"), "{problems:#?}");
}

#[test]
fn every_disc_outside_the_box_is_listed() {
    let mut text = String::from(
        "[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n[time]\ndt = 0.01\nsteps = 5\n",
    );
    for x in [20.0, 5.0, -3.0] {
        text.push_str(&format!("[[disc]]\nposition = [{x}, 5.0]\nradius = 0.5\n"));
    }
    let (code, problems) = check(&text, &[]);
    assert_eq!(code, 1);
    assert_eq!(lines_named(&problems), vec![7, 13], "{problems:#?}");
}

#[test]
fn three_type_errors_come_in_one_run_in_line_order() {
    let text = "\
[world]
min = [0.0, 0.0]
max = [10.0, 10.0]

[time]
dt = 0.01
steps = 5

[[gas]]
count = 10
radius = \"big\"
speed = 1.0
seed = -4

[output]
stats_every = 10
frame_every = 5
gif = \"yes\"
plots = true
view = { min = [0.0, 0.0], max = [10.0, 10.0] }
events = false
events_threshold = 0.0
color_by = 3
";
    let (code, problems) = check(text, &[]);
    assert_eq!(code, 1);
    assert_eq!(
        lines_named(&problems),
        vec![11, 13, 18, 23],
        "{problems:#?}"
    );
    assert!(problems[0].contains("radius"), "{problems:#?}");
    assert!(problems[3].contains("color_by"), "{problems:#?}");
}

#[test]
fn a_typo_in_a_set_names_the_set_and_the_nearest_key() {
    let text = "[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n[time]\ndt = 0.01\nsteps = 5\n\
                [[disc]]\nposition = [5.0, 5.0]\nradius = 0.5\n";
    let (code, problems) = check(text, &["world.gravty=1"]);
    assert_eq!(code, 1);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let p = &problems[0];
    assert!(p.contains("--set world.gravty=1:"), "{p}");
    assert!(p.contains("did you mean `gravity`?"), "{p}");
    assert!(
        !p.contains("many.toml (with --set/--seed):3"),
        "a line of the file named: {p}"
    );
    // The same typo in the file names its line and the key.
    let text = text.replace(
        "max = [10.0, 10.0]\n",
        "max = [10.0, 10.0]\ngravty = [0.0, -1.0]\n",
    );
    let (_, problems) = check(&text, &[]);
    assert!(
        problems[0].contains("many.toml:4:") && problems[0].contains("`gravity`?"),
        "{problems:#?}"
    );
    // A bad value set from the command line is named by its override too.
    let (_, problems) = check(
        &text.replace("gravty", "gravity"),
        &["world.coefficient_of_restitution=1.5"],
    );
    assert!(
        problems[0].starts_with(
            "error: many.toml (with --set/--seed): --set world.coefficient_of_restitution=1.5:"
        ) || problems[0].contains("--set world.coefficient_of_restitution=1.5:"),
        "{problems:#?}"
    );
}
