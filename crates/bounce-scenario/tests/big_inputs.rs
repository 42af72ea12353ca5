//! Big inputs: a scenario of tens of thousands of `[[disc]]` tables loads whole, ids in file
//! order, and a bad disc among them is named by its table and line.

use bounce::ParticleId;
use bounce_scenario::parse;

/// A walled box with `count` disc tables on a lattice, the `bad`th (1-based) given `radius`.
fn discs(count: usize, bad: Option<(usize, &str)>) -> String {
    let cols = 200;
    let side = 1.2 * cols as f64 + 1.0;
    let mut text = format!(
        "name = \"discs\"\n[world]\nboundary = \"walls\"\nmin = [0.0, 0.0]\nmax = [{side}, {}]\n\
         [time]\ndt = 0.01\nsteps = 1\n",
        side.max(1.2 * (count / cols + 1) as f64 + 1.0)
    );
    for k in 0..count {
        let (x, y) = (0.6 + 1.2 * (k % cols) as f64, 0.6 + 1.2 * (k / cols) as f64);
        let radius = match bad {
            Some((b, r)) if b == k + 1 => r,
            _ => "0.5",
        };
        text += &format!(
            "[[disc]]\nposition = [{x}, {y}]\nvelocity = [{}, 0.0]\nradius = {radius}\n",
            k as f64 * 1e-3
        );
    }
    text
}

#[test]
fn twenty_thousand_disc_tables_load_in_file_order() {
    let count = 20_000;
    let text = discs(count, None);
    let scenario = parse(&text, "d.toml").unwrap();
    let built = scenario.build(&text, "d.toml").unwrap();
    assert_eq!(built.world.len(), count);
    for k in [0, 1, 7_777, count - 1] {
        let p = built.world.particle(ParticleId(k as u32)).unwrap();
        assert_eq!(p.velocity[0], k as f64 * 1e-3, "disc {k}");
        assert_eq!(p.position[0], 0.6 + 1.2 * (k % 200) as f64, "disc {k}");
    }
}

#[test]
fn a_bad_disc_among_thousands_is_named_by_its_table_and_line() {
    let (count, bad) = (12_000, 10_001);
    // Each table is four lines after a header of eight, and starts with `[[disc]]`.
    let line = 8 + 4 * (bad - 1) + 1;
    // Too large for the box: found when the discs are added to the world.
    let text = discs(count, Some((bad, "1e4")));
    let scenario = parse(&text, "d.toml").unwrap();
    let Err(error) = scenario.build(&text, "d.toml") else {
        panic!("a disc too large for the box was accepted");
    };
    let message = error.to_string();
    assert!(
        message.contains(&format!("d.toml:{line}")) && message.contains("disc #10001"),
        "{message}"
    );
    assert!(message.contains("too large"), "{message}");
}
