//! `bounce analyze` against theory: the hard-disc fluid's contact value (Henderson), g → 1
//! far from contact, |ψ6| of a crystal and a fluid, g(r) between walls and in a sheared
//! (Lees–Edwards) box; and bad input.

mod common;

use std::path::Path;

use common::{Scratch, bounce, output};

/// Runs `bounce` with `args`, requiring success; returns standard output.
fn run(args: &[&str]) -> String {
    let (code, out, err) = output(bounce().args(args));
    assert_eq!(code, 0, "{out}{err}");
    out
}

/// The rows of a two-column CSV written by `bounce analyze`.
fn columns(path: &Path) -> Vec<(f64, f64)> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let (a, b) = l.split_once(',').unwrap();
            (a.parse().unwrap(), b.parse().unwrap())
        })
        .collect()
}

/// The shipped hard-discs scenario (2,000 exact hard discs) at packing `eta`.
fn hard_discs(scratch: &Scratch, name: &str, eta: f64, steps: u32) -> std::path::PathBuf {
    let side = (2000.0 * std::f64::consts::PI * 0.25 / eta).sqrt();
    let max = format!("world.max=[{side},{side}]");
    template(
        scratch,
        "hard-discs",
        name,
        &[&max, &format!("time.steps={steps}")],
    )
}

/// The shipped scenario `template` run into `name` with each of `sets` and no pictures;
/// returns its trajectory.
fn template(scratch: &Scratch, template: &str, name: &str, sets: &[&str]) -> std::path::PathBuf {
    let out = scratch.path(name);
    let root =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenarios/{template}.toml"));
    let mut args = vec![
        "run",
        root.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "-q",
    ];
    let quiet = ["output.gif=false", "output.frame_every=0"];
    for set in sets.iter().chain(&quiet) {
        args.extend(["--set", set]);
    }
    run(&args);
    out.join("trajectory.gsd")
}

#[test]
fn the_hard_disc_fluid_touches_at_hendersons_contact_value_and_forgets_beyond_three_diameters() {
    let scratch = Scratch::new();
    let gsd = hard_discs(&scratch, "fluid", 0.3, 2000);
    let out = scratch.path("analysis");
    let said = run(&[
        "analyze",
        gsd.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--first",
        "20",
    ]);
    assert!(
        said.contains("181 frames from frame 20 (periodic box"),
        "{said}"
    );
    let g = columns(&out.join("rdf.csv"));
    assert_eq!(g.len(), 500); // bins of 0.01 diameters up to 5
    // No pair overlaps: g is 0 inside contact.
    assert!(g.iter().filter(|(r, _)| *r < 0.995).all(|(_, g)| *g == 0.0));
    // The contact value: a line through the bins within 0.1 diameters of contact, at r = 1.
    let near: Vec<&(f64, f64)> = g.iter().filter(|(r, _)| *r > 1.0 && *r < 1.1).collect();
    let n = near.len() as f64;
    let (mr, mg) = (
        near.iter().map(|p| p.0).sum::<f64>() / n,
        near.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = near.iter().map(|p| (p.0 - mr) * (p.1 - mg)).sum::<f64>()
        / near.iter().map(|p| (p.0 - mr).powi(2)).sum::<f64>();
    let contact = mg + slope * (1.0 - mr);
    let eta: f64 = 0.3;
    let henderson = (1.0 - 7.0 * eta / 16.0) / (1.0 - eta).powi(2);
    assert!(
        (contact / henderson - 1.0).abs() < 0.03,
        "g(σ) = {contact}, Henderson {henderson}"
    );
    // Beyond three diameters g is 1 (means over quarter-diameter windows).
    for window in g
        .iter()
        .filter(|(r, _)| *r > 3.0)
        .collect::<Vec<_>>()
        .chunks(25)
    {
        let mean = window.iter().map(|p| p.1).sum::<f64>() / window.len() as f64;
        assert!(
            (mean - 1.0).abs() < 0.02,
            "g = {mean} near r = {}",
            window[0].0
        );
    }
    // The fluid has no bond order.
    let order = columns(&out.join("psi6.csv"));
    assert!(order.iter().all(|(_, p)| *p < 0.1), "{order:?}");
    // Diffusing discs: the MSD grows with the lag, given in steps and in time (the frames
    // record their times: dt = 0.1 a step here).
    let text = std::fs::read_to_string(out.join("msd.csv")).unwrap();
    assert!(text.starts_with("lag,time,msd\n"), "{text}");
    let msd: Vec<[f64; 3]> = text
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    assert_eq!(msd[0], [0.0, 0.0, 0.0]);
    assert!(msd.windows(2).all(|w| w[1][2] > w[0][2]));
    assert!(
        msd[1..]
            .iter()
            .all(|[lag, time, _]| (time / lag - 0.1).abs() < 1e-9),
        "{msd:?}"
    );
    for png in ["rdf.png", "psi6.png", "msd.png"] {
        assert!(
            std::fs::metadata(out.join(png)).unwrap().len() > 5_000,
            "{png}"
        );
    }
}

#[test]
fn a_gently_sheared_fluid_keeps_its_contact_value_through_the_sliding_images() {
    // The shear template (packing 0.3, γ̇ σ √(m/kT) = 0.07): the structure is the fluid's,
    // pairs across the top and bottom found at the frame's offset.
    let scratch = Scratch::new();
    let sets = [
        "time.steps=12000",
        "output.gsd_every=100",
        "output.plots=false",
    ];
    let gsd = template(&scratch, "shear", "shear", &sets);
    let analysis = scratch.path("analysis");
    let (code, said, err) = output(bounce().args([
        "analyze",
        gsd.to_str().unwrap(),
        "--out",
        analysis.to_str().unwrap(),
        "--first",
        "20",
    ]));
    assert_eq!(code, 0, "{said}{err}");
    assert!(
        said.contains("101 frames from frame 20 (Lees–Edwards box"),
        "{said}"
    );
    // No MSD from sliding images, and the reason given.
    assert!(
        err.contains("no msd.csv") && err.contains("Lees–Edwards"),
        "{err}"
    );
    assert!(!analysis.join("msd.csv").exists());
    let g = columns(&analysis.join("rdf.csv"));
    let near: Vec<&(f64, f64)> = g.iter().filter(|(r, _)| *r > 1.0 && *r < 1.1).collect();
    let contact = near.iter().map(|p| p.1).sum::<f64>() / near.len() as f64;
    let eta: f64 = 0.3;
    let henderson = (1.0 - 7.0 * eta / 16.0) / (1.0 - eta).powi(2);
    // (The mean over the first tenth of a diameter sits a little under the contact value.)
    assert!(
        (contact / henderson - 0.95).abs() < 0.05,
        "g near contact {contact}, Henderson {henderson}"
    );
    let far: Vec<f64> = g.iter().filter(|(r, _)| *r > 3.0).map(|p| p.1).collect();
    let mean = far.iter().sum::<f64>() / far.len() as f64;
    assert!((mean - 1.0).abs() < 0.02, "g beyond 3 diameters {mean}");
}

#[test]
fn a_hard_disc_crystal_at_packing_0_8_keeps_its_bond_order() {
    let scratch = Scratch::new();
    let gsd = hard_discs(&scratch, "crystal", 0.8, 200);
    let out = scratch.path("analysis");
    run(&[
        "analyze",
        gsd.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let order = columns(&out.join("psi6.csv"));
    assert_eq!(order.len(), 21);
    assert!(order.iter().all(|(_, p)| *p > 0.9), "{order:?}");
}

#[test]
fn a_dilute_gas_between_walls_has_g_of_one_without_the_walls_deficit() {
    // 1,000 discs in 90 × 90 (packing 0.1): pairs far apart are uncorrelated, so g = 1 once
    // the pairs the walls forbid are accounted for (without the correction, g would fall to
    // about 0.8 at r = 15).
    let scratch = Scratch::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/gas.toml");
    let out = scratch.path("gas");
    run(&[
        "run",
        root.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "-q",
        "--set",
        "gas.1.count=1000",
        "--set",
        "output.gif=false",
        "--set",
        "output.frame_every=0",
        "--set",
        "output.gsd_every=20",
    ]);
    let analysis = scratch.path("analysis");
    let said = run(&[
        "analyze",
        out.join("trajectory.gsd").to_str().unwrap(),
        "--out",
        analysis.to_str().unwrap(),
        "--first",
        "10",
        "--r-max",
        "20",
        "--bin",
        "0.5",
    ]);
    assert!(said.contains("(walls box"), "{said}");
    let g = columns(&analysis.join("rdf.csv"));
    let far: Vec<f64> = g.iter().filter(|(r, _)| *r > 3.0).map(|p| p.1).collect();
    let mean = far.iter().sum::<f64>() / far.len() as f64;
    assert!(
        (mean - 1.0).abs() < 0.02,
        "mean g beyond 3 diameters: {mean}"
    );
    assert!(far.iter().all(|g| (g - 1.0).abs() < 0.05), "{far:?}");
}

#[test]
fn bad_input_names_the_problem_and_writes_nothing() {
    let scratch = Scratch::new();
    let gsd = hard_discs(&scratch, "small", 0.3, 20);
    let out = scratch.path("analysis");
    let not_gsd = scratch.scenario("notes.gsd", "not a trajectory");
    for (args, message) in [
        (
            vec!["analyze", not_gsd.to_str().unwrap()],
            "not a GSD 2 file",
        ),
        (
            vec!["analyze", gsd.to_str().unwrap(), "--first", "7"],
            "first frame 7: the file holds frames 0..2",
        ),
        (
            vec!["analyze", gsd.to_str().unwrap(), "--r-max", "50"],
            "half its smaller side",
        ),
        (
            vec!["analyze", gsd.to_str().unwrap(), "--bin", "-1"],
            "--bin -1: must be a number of mean diameters > 0",
        ),
        (
            vec!["analyze", gsd.to_str().unwrap(), "--boundary", "round"],
            "invalid value 'round'",
        ),
    ] {
        let (code, _, err) = output(bounce().args(&args).args(["--out", out.to_str().unwrap()]));
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(err.contains(message), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}
