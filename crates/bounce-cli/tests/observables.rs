//! `profile.csv` and `msd.csv` against theory: a gas in gravity has the barometric density
//! profile at its own temperature; a dilute gas's displacements are ballistic at short
//! times and diffusive later; both files are the same bytes on 1 and 2 threads and after a
//! resume.

mod common;

use common::{Scratch, bounce, output};

/// 1,000 small discs (packing 0.005: nearly an ideal gas), exact (event-driven), with
/// `world` and `output` lines added.
fn scenario(world: &str, output: &str) -> String {
    format!(
        r#"
name = "observables"
[world]
min = [0.0, 0.0]
max = [40.0, 40.0]
{world}

[time]
method = "event_driven"
dt = 0.1
steps = 3000

[[gas]]
count = 1000
radius = 0.05
temperature = 1.0
seed = 3

[output]
plots = false
{output}
"#
    )
}

fn run(s: &Scratch, text: &str, out: &str, extra: &[&str]) {
    let file = s.scenario(&format!("{out}.toml"), text);
    let (code, _, stderr) = output(
        bounce()
            .arg("run")
            .arg(&file)
            .args(["-q", "--out"])
            .arg(s.path(out))
            .args(extra),
    );
    assert_eq!(code, 0, "{stderr}");
}

/// The rows of a CSV file as numbers (an empty field as NaN), and its header.
fn table(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    (header, rows)
}

#[test]
fn a_gas_in_gravity_has_the_barometric_profile_at_its_own_temperature() {
    let s = Scratch::new();
    let text = scenario(
        "boundary = \"walls\"\ngravity = [0.0, -2.0]",
        "stats_every = 50\nprofile = { axis = \"y\", bins = 20 }",
    );
    run(&s, &text, "out", &[]);
    let (header, rows) = table(&s.path("out/profile.csv"));
    assert_eq!(
        header.join(","),
        "step,time,bin,centre,count,density,vx,vy,temperature"
    );
    // Each row's counts add up to the discs.
    let first: f64 = rows.iter().filter(|r| r[0] == 0.0).map(|r| r[4]).sum();
    assert_eq!(first, 1000.0);
    // After 100 time units of settling, the mean density and temperature in each bin.
    let (mut n, mut t, mut y) = (vec![0.0; 20], vec![0.0; 20], vec![0.0; 20]);
    let late: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] >= 1000.0).collect();
    for r in &late {
        let k = r[2] as usize;
        (n[k], t[k], y[k]) = (n[k] + r[5], t[k] + r[8], r[3]);
    }
    let samples = late.len() as f64 / 20.0;
    let kt = t.iter().zip(&n).map(|(t, n)| t * n).sum::<f64>() / n.iter().sum::<f64>() / samples;
    // The least-squares slope of ln n against height: −m g / kT (mass = radius = 0.05).
    let ln: Vec<f64> = n.iter().map(|n| (n / samples).ln()).collect();
    let (my, ml) = (y.iter().sum::<f64>() / 20.0, ln.iter().sum::<f64>() / 20.0);
    let slope = y
        .iter()
        .zip(&ln)
        .map(|(y, l)| (y - my) * (l - ml))
        .sum::<f64>()
        / y.iter().map(|y| (y - my).powi(2)).sum::<f64>();
    let theory = -0.05 * 2.0 / kt;
    assert!(
        (slope / theory - 1.0).abs() < 0.04,
        "slope {slope}, barometric {theory} (kT = {kt})"
    );
    // At rest on average, and the same temperature at every height (within the noise).
    for r in &late {
        assert!(r[8] >= 0.0 && r[6].is_finite() && r[7].is_finite());
    }
    for (k, t) in t.iter().enumerate() {
        assert!(
            (t / samples / kt - 1.0).abs() < 0.1,
            "bin {k}: {}",
            t / samples
        );
    }
}

#[test]
fn a_dilute_gas_moves_ballistically_then_diffuses() {
    let s = Scratch::new();
    let text = scenario("boundary = \"periodic\"", "stats_every = 1\nmsd = true")
        .replace("dt = 0.1\nsteps = 3000", "dt = 0.02\nsteps = 2000");
    run(&s, &text, "out", &[]);
    let (header, rows) = table(&s.path("out/msd.csv"));
    assert_eq!(header.join(","), "step,time,msd,vacf");
    let v2 = rows[0][3];
    assert_eq!(rows[0][2], 0.0);
    // ⟨v²⟩ = 2 kT / m at the start.
    assert!((v2 / (2.0 * 1.0 / 0.05) - 1.0).abs() < 0.05, "{v2}");
    // Ballistic over a fiftieth of a collision time: ⟨v²⟩ t².
    let t = rows[1][1];
    assert!(
        (rows[1][2] / (v2 * t * t) - 1.0).abs() < 0.01,
        "{:?}",
        rows[1]
    );
    // Diffusive after many collisions (about one a time unit): the MSD grows as t.
    let at = |time: f64| rows.iter().find(|r| (r[1] - time).abs() < 1e-9).unwrap()[2];
    let exponent = (at(40.0) / at(20.0)).ln() / 2f64.ln();
    assert!((exponent - 1.0).abs() < 0.1, "MSD ∝ t^{exponent}");
    // The velocities forget their start.
    assert!(rows.last().unwrap()[3].abs() < 0.2 * v2);
}

#[test]
fn the_observables_are_the_same_bytes_on_threads_and_after_a_resume() {
    let s = Scratch::new();
    let text = scenario(
        "boundary = \"periodic\"\ncoefficient_of_restitution = 0.9\nrestitution_model = \"relative_normal_velocity\"\nthermostat = { kind = \"andersen\", temperature = 1.0, rate = 0.2 }",
        "stats_every = 10\nprofile = { axis = \"x\", bins = 8 }\nmsd = true\ncollision_counts = true",
    )
    .replace("method = \"event_driven\"\ndt = 0.1", "dt = 0.01");
    same_bytes_on_threads_and_after_a_resume(
        &s,
        &text,
        (300, 120),
        &["profile.csv", "msd.csv", "collisions.csv"],
    );
}

/// Runs `text` for `steps` on 1 and 2 threads and to `cut` and resumed from there to `steps`:
/// each of `files` is the same bytes in all three.
fn same_bytes_on_threads_and_after_a_resume(
    s: &Scratch,
    text: &str,
    (steps, cut): (u32, u32),
    files: &[&str],
) {
    let (steps, cut) = (steps.to_string(), cut.to_string());
    run(s, text, "one", &["--steps", &steps, "--threads", "1"]);
    run(s, text, "two", &["--steps", &steps, "--threads", "2"]);
    run(s, text, "resumed", &["--steps", &cut]);
    let checkpoint = s.path("resumed/checkpoint.bin");
    let resume = ["--steps", &steps, "--resume", checkpoint.to_str().unwrap()];
    run(s, text, "resumed", &resume);
    for file in files {
        let one = std::fs::read(s.path("one").join(file)).unwrap();
        assert!(
            one == std::fs::read(s.path("two").join(file)).unwrap(),
            "{file}: threads"
        );
        assert!(
            one == std::fs::read(s.path("resumed").join(file)).unwrap(),
            "{file}: resume"
        );
        assert!(one.len() > 1000, "{file}");
    }
}

#[test]
fn a_sheared_run_is_the_same_bytes_on_threads_and_after_a_resume() {
    // The shear template (Lees–Edwards, thermostatted, pressure tensor and profile).
    let s = Scratch::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shear.toml");
    let text = std::fs::read_to_string(root)
        .unwrap()
        .replace("gif = true", "gif = false")
        .replace("frame_every = 500", "frame_every = 0\ngsd_every = 50")
        .replace("plots = true", "plots = false");
    same_bytes_on_threads_and_after_a_resume(
        &s,
        &text,
        (600, 250),
        &["stats.csv", "profile.csv", "trajectory.gsd"],
    );
}

#[test]
fn a_profile_of_an_open_world_is_refused_with_its_line() {
    let s = Scratch::new();
    let text = scenario(
        "boundary = \"open\"",
        "profile = { axis = \"y\", bins = 5 }",
    );
    let file = s.scenario("open.toml", &text);
    let (code, _, stderr) = output(bounce().arg("check").arg(&file));
    assert_eq!(code, 1);
    assert!(
        stderr.contains("open.toml:21") && stderr.contains("needs a box"),
        "{stderr}"
    );
}

#[test]
fn a_resume_refuses_a_file_of_another_run_naming_it() {
    let s = Scratch::new();
    let text = scenario(
        "boundary = \"periodic\"",
        "stats_every = 10\nprofile = { axis = \"y\", bins = 4 }",
    );
    run(&s, &text, "out", &["--steps", "20"]);
    let profile = s.path("out/profile.csv");
    let old = std::fs::read_to_string(&profile).unwrap();
    std::fs::write(&profile, old.replacen("temperature", "temp", 1)).unwrap();
    let file = s.path("out.toml");
    let checkpoint = s.path("out/checkpoint.bin");
    let (code, _, stderr) = output(
        bounce()
            .arg("run")
            .arg(&file)
            .args(["-q", "--steps", "40", "--out"])
            .arg(s.path("out"))
            .arg("--resume")
            .arg(&checkpoint),
    );
    assert_eq!(code, 1);
    assert!(
        stderr.contains("profile.csv: not the profile.csv of this bounce (its header differs)"),
        "{stderr}"
    );
    // The file is left as it was.
    assert!(
        std::fs::read_to_string(&profile)
            .unwrap()
            .contains(",temp\n")
    );
}

/// A shipped template run for `steps` with `output.dissipation` and `extra` settings; its
/// stats.csv as a header and rows.
fn dissipation_run(
    s: &Scratch,
    template: &str,
    out: &str,
    extra: &[&str],
) -> (Vec<String>, Vec<Vec<f64>>) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let (code, _, stderr) = output(
        bounce()
            .arg("run")
            .arg(root.join(format!("{template}.toml")))
            .args(["-q", "--set", "output.dissipation=true"])
            .args(["--set", "output.frame_every=0", "--set", "output.gif=false"])
            .args(["--set", "output.plots=false", "--set", "output.gsd_every=0"])
            .args(extra)
            .arg("--out")
            .arg(s.path(out)),
    );
    assert_eq!(code, 0, "{stderr}");
    table(&s.path(out).join("stats.csv"))
}

#[test]
fn the_dissipated_energy_balances_the_work_put_in_and_matches_the_collisional_loss() {
    let s = Scratch::new();
    let column = |header: &[String], name: &str| header.iter().position(|h| h == name).unwrap();
    // Elastic discs: a piston doing work, and white-noise kicks, both accounted for.
    for (template, extra) in [
        ("piston", vec!["--steps", "300"]),
        (
            "gas",
            vec![
                "--steps",
                "300",
                "--set",
                "world.thermostat={ kind = \"white_noise\", temperature = 1.0, rate = 0.5 }",
            ],
        ),
    ] {
        let (header, rows) = dissipation_run(&s, template, template, &extra);
        let (lost, energy) = (
            column(&header, "dissipated"),
            column(&header, "kinetic_energy"),
        );
        assert_eq!(rows[0][lost], 0.0);
        for r in &rows {
            assert!(r[lost].abs() < 1e-9 * r[energy], "{template}: {r:?}");
        }
    }
    // The driven granular gas: in the steady state the collisions take out what the kicks
    // put in, at the rate kinetic theory gives at the measured temperature,
    // (1 − e²) n σ χ √π T^{3/2} / √m (1 + 3a₂/16) a disc (Enskog; van Noije & Ernst's a₂).
    let (header, rows) = dissipation_run(&s, "driven-granular", "driven", &[]);
    let late: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] > 200.0).collect();
    let span = late.len() as f64 * 10.0 * 0.05 * 2000.0; // rows of 10 steps of 0.05, a disc
    let sum = |name: &str| late.iter().map(|r| r[column(&header, name)]).sum::<f64>();
    let (lost, put_in) = (sum("dissipated") / span, sum("thermostat_work") / span);
    assert!((lost / put_in - 1.0).abs() < 0.02, "{lost} vs {put_in}");
    let t = sum("temperature") / late.len() as f64;
    let (e, eta, m): (f64, f64, f64) = (0.9, 0.2, 0.5);
    let n = eta / (std::f64::consts::PI / 4.0);
    let chi = (1.0 - 7.0 * eta / 16.0) / (1.0 - eta).powi(2);
    let a2 = 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e)
        / (73.0 + 112.0 - 48.0 * e - 105.0 * e + 30.0 * (1.0 - e) * e * e);
    let theory = (1.0 - e * e) * n * chi * std::f64::consts::PI.sqrt() * t.powf(1.5) / m.sqrt()
        * (1.0 + 3.0 * a2 / 16.0);
    assert!(
        (lost / theory - 1.0).abs() < 0.06,
        "{lost} vs Enskog's {theory} at kT = {t}"
    );
    // Resumed, the column continues byte for byte.
    let settings = ["--set", "world.coefficient_of_restitution=0.8"];
    dissipation_run(
        &s,
        "gas",
        "whole",
        &[&settings[..], &["--steps", "60"]].concat(),
    );
    dissipation_run(
        &s,
        "gas",
        "cut",
        &[&settings[..], &["--steps", "25"]].concat(),
    );
    let checkpoint = s.path("cut/checkpoint.bin");
    let resume = ["--steps", "60", "--resume", checkpoint.to_str().unwrap()];
    dissipation_run(&s, "gas", "cut", &[&settings[..], &resume[..]].concat());
    assert_eq!(
        std::fs::read(s.path("whole/stats.csv")).unwrap(),
        std::fs::read(s.path("cut/stats.csv")).unwrap()
    );
    // Not with emitters or sinks, whose discs bring and take energy.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let (code, _, stderr) = output(
        bounce()
            .arg("check")
            .arg(root.join("effusion.toml"))
            .args(["--set", "output.dissipation=true"]),
    );
    assert_eq!(code, 1);
    // Named by the override that set it.
    assert!(
        stderr.contains("--set output.dissipation=true: not with [[emitter]] or [[sink]]"),
        "{stderr}"
    );
}

#[test]
fn collision_counts_add_up_to_twice_the_collisions_in_the_csv_and_the_gsd() {
    let s = Scratch::new();
    let text = scenario(
        "boundary = \"periodic\"",
        "stats_every = 10\ngsd_every = 100\ncollision_counts = true",
    )
    .replace("radius = 0.05", "radius = 0.4");
    run(&s, &text, "counts", &["--steps", "500"]);
    let (header, rows) = table(&s.path("counts/stats.csv"));
    let column = header.iter().position(|h| h == "collisions").unwrap();
    // Rows after the first count the collisions since the row before.
    let collisions: f64 = rows[1..].iter().map(|r| r[column]).sum();
    let (header, discs) = table(&s.path("counts/collisions.csv"));
    assert_eq!(header, ["id", "radius", "collisions"]);
    assert_eq!(discs.len(), 1000);
    let counted: f64 = discs.iter().map(|r| r[2]).sum();
    assert!(collisions > 1000.0, "{collisions}");
    assert_eq!(counted, 2.0 * collisions);
    // The GSD's last frame holds the same counts, in id order.
    let chunks = common::gsd_chunks(&s.path("counts/trajectory.gsd"));
    let last = chunks
        .iter()
        .rfind(|c| c.name == "log/particles/bounce/collisions")
        .unwrap();
    assert_eq!(last.frame, 5);
    let in_gsd: Vec<f64> = last
        .data
        .chunks(8)
        .map(|b| u64::from_le_bytes(b.try_into().unwrap()) as f64)
        .collect();
    assert_eq!(in_gsd, discs.iter().map(|r| r[2]).collect::<Vec<_>>());
}
