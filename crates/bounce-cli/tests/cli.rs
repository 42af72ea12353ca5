//! The `bounce` command, driven as a user would.

mod common;

use std::path::Path;
use std::process::Command;

use common::{Scratch, bounce, output};

/// Three resting discs at known places, and a small gas for moving data.
const SMALL: &str = r##"
name = "small"
[world]
boundary = "walls"
min = [0.0, 0.0]
max = [40.0, 20.0]

[time]
dt = 0.02
steps = 40

[[disc]]
position = [10.0, 10.0]
radius = 2.0
color = "red"
tag = 42

[[disc]]
position = [30.0, 5.0]
radius = 1.5
color = "#00ff00"

[[gas]]
count = 60
radius = 0.3
speed = 1.0
seed = 5
region = { min = [15.0, 12.0], max = [40.0, 20.0] }
color = "blue"
tag = 18446744073709551615

[output]
stats_every = 5
frame_every = 20
frame_width = 400
gif = true
gsd_every = 10
color_by = "color"
"##;

fn run_small(s: &Scratch, out: &str, extra: &[&str]) -> (i32, String, String) {
    let scenario = s.scenario("small.toml", SMALL);
    output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(s.path(out))
            .arg("--quiet")
            .args(extra),
    )
}

#[test]
fn run_writes_every_output() {
    let s = Scratch::new();
    let (code, stdout, stderr) = run_small(&s, "out", &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("62 particles"), "{stdout}");
    assert!(stdout.contains("40 steps"), "{stdout}");
    assert!(stdout.contains("relative energy change"), "{stdout}");
    let out = s.path("out");
    for file in [
        "stats.csv",
        "checkpoint.bin",
        "plots.png",
        "animation.gif",
        "trajectory.gsd",
    ] {
        assert!(out.join(file).metadata().unwrap().len() > 0, "{file}");
    }
    let frames: Vec<_> = std::fs::read_dir(out.join("frames")).unwrap().collect();
    assert_eq!(frames.len(), 3, "frames at steps 0, 20, 40");
    // No temporary files left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn stats_csv_has_the_documented_columns_and_rows() {
    let s = Scratch::new();
    assert_eq!(run_small(&s, "out", &[]).0, 0);
    let text = std::fs::read_to_string(s.path("out/stats.csv")).unwrap();
    let mut lines = text.lines();
    assert!(lines.next().unwrap().starts_with(
        "step,time,kinetic_energy,momentum_x,momentum_y,collisions,wall_impulse,max_overlap"
    ));
    // The first row has no step behind it: its pressure is empty.
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            l.split(',')
                .map(|v| {
                    if v.is_empty() {
                        f64::NAN
                    } else {
                        v.parse().unwrap()
                    }
                })
                .collect()
        })
        .collect();
    assert!(rows[0][10].is_nan() && rows.iter().skip(1).all(|r| r[10] > 0.0 && r[11] == 1.0));
    let steps: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(steps, [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0]);
    assert!((rows[8][1] - 0.8).abs() < 1e-12, "time = steps * dt");
    // Elastic: the energy column stays put.
    for r in &rows {
        assert!((r[2] - rows[0][2]).abs() < 1e-9 * rows[0][2]);
    }
    assert!(
        rows.iter().map(|r| r[5]).sum::<f64>() > 0.0,
        "some collisions"
    );
    assert!(
        text.lines()
            .next()
            .unwrap()
            .ends_with(",particles,contacts")
    );
    // Every collision is a contact; in this gas nearly every contact a collision.
    assert!(rows.iter().all(|r| r[13] >= r[5]));
    assert!(
        rows.iter().map(|r| r[6]).sum::<f64>() > 0.0,
        "some wall impulse"
    );
    // `particles`: the 62 discs throughout.
    assert!(rows.iter().all(|r| r[12] == 62.0));
}

/// Writes template `name`, runs it for `steps` steps with the arguments `extra` as well,
/// and returns the run's stdout, stats.csv's header and its last row.
fn run_template(
    s: &Scratch,
    name: &str,
    steps: &str,
    extra: &[&str],
) -> (String, Vec<String>, Vec<f64>) {
    let scenario = s.path(&format!("{name}.toml"));
    let (code, _, stderr) = output(bounce().args(["new", name, "--out"]).arg(&scenario));
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .args(["--steps", steps])
            .args(extra)
            .arg("--out")
            .arg(s.path("out")),
    );
    assert_eq!(code, 0, "{stderr}");
    let text = std::fs::read_to_string(s.path("out/stats.csv")).unwrap();
    let header = text
        .lines()
        .next()
        .unwrap()
        .split(',')
        .map(String::from)
        .collect();
    let last = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap_or(f64::NAN))
        .collect();
    (stdout, header, last)
}

#[test]
fn an_event_driven_run_reports_collisions_per_second_and_the_exact_pressure() {
    let s = Scratch::new();
    let (stdout, header, last) = run_template(&s, "hard-discs", "100", &[]);
    let at = |name: &str| header.iter().position(|h| h == name).unwrap();
    assert!(stdout.contains("collisions/s"), "{stdout}");
    assert!(
        stdout.contains("event-driven, every collision exact"),
        "{stdout}"
    );
    // Z = P A / (N kT) near Monte Carlo's 4.106 (one row of 1 time unit: within 5 %).
    let area = 56.049_912_163_979_28f64.powi(2);
    let z = last[at("pressure")] * area / (2000.0 * last[at("temperature")]);
    assert!((z / 4.1062 - 1.0).abs() < 0.05, "Z = {z}");
    assert!(last[at("collisions")] > 1000.0);
    assert!(s.path("out/trajectory.gsd").exists() && s.path("out/animation.gif").exists());
}

#[test]
fn events_csv_is_the_same_on_any_thread_count_and_continues_on_resume() {
    let s = Scratch::new();
    let scenario = s.path("gas.toml");
    let (code, _, stderr) = output(bounce().args(["new", "gas", "--out"]).arg(&scenario));
    assert_eq!(code, 0, "{stderr}");
    let run = |out: &str, extra: &[&str]| {
        let (code, _, stderr) = output(
            bounce()
                .arg("run")
                .arg(&scenario)
                .args(["--set", "output.events=true", "--quiet", "--out"])
                .arg(s.path(out))
                .args(extra),
        );
        assert_eq!(code, 0, "{stderr}");
        std::fs::read(s.path(out).join("events.csv")).unwrap()
    };
    // The template's 2,000-disc gas.
    let one = run("one", &["--steps", "40", "--threads", "1"]);
    for threads in ["2", "3"] {
        let other = run(threads, &["--steps", "40", "--threads", threads]);
        assert!(one == other, "events.csv differs on {threads} threads");
    }
    run("resumed", &["--steps", "15", "--threads", "2"]);
    let checkpoint = s.path("resumed/checkpoint.bin");
    let resumed = run(
        "resumed",
        &["--steps", "40", "--resume", checkpoint.to_str().unwrap()],
    );
    assert!(one == resumed, "a resumed events.csv differs");
    let text = String::from_utf8(one).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("step,time,kind,a,b,x,y,nx,ny,normal_impulse,tangent_impulse,approach_speed")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.len() > 1000, "{} rows", rows.len());
    let walls = rows.iter().filter(|r| r[4].starts_with("wall:")).count();
    let begins = rows.iter().filter(|r| r[2] == "begin").count();
    let ends = rows.iter().filter(|r| r[2] == "end").count();
    assert!(walls > 0 && begins > 0 && ends > 0);
    // Steps ascend; every begin's normal impulse is finite and >= 0.
    let steps: Vec<u64> = rows.iter().map(|r| r[0].parse().unwrap()).collect();
    assert!(steps.windows(2).all(|w| w[0] <= w[1]) && steps[steps.len() - 1] == 40);
    for r in rows.iter().filter(|r| r[2] == "begin") {
        let j: f64 = r[9].parse().unwrap();
        assert!(j.is_finite() && j >= 0.0, "{r:?}");
    }
}

#[test]
fn sensors_count_what_enters_and_leaves_between_rows() {
    let s = Scratch::new();
    // Discs rain into a sink on the floor; one sensor covers the sink, one a circle above.
    let scenario = s.scenario(
        "rain.toml",
        r#"
[world]
min = [0.0, 0.0]
max = [20.0, 30.0]
gravity = [0.0, -9.81]
[time]
dt = 0.01
steps = 300
[[emitter]]
region = { min = [2.0, 25.0], max = [18.0, 29.0] }
rate = 50
radius = 0.3
[[sink]]
region = { min = [0.0, 0.0], max = [20.0, 2.0] }
[[sensor]]
name = "floor"
region = { min = [0.0, 0.0], max = [20.0, 2.0] }
[[sensor]]
name = "middle"
region = { centre = [10.0, 15.0], radius = 5.0 }
[output]
stats_every = 25
plots = false
"#,
    );
    let (code, _, stderr) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .args(["--quiet", "--out"])
            .arg(s.path("out")),
    );
    assert_eq!(code, 0, "{stderr}");
    let text = std::fs::read_to_string(s.path("out/stats.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<u64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap_or(0)).collect())
        .collect();
    let sum = |name: &str| rows.iter().map(|r| r[at(name)]).sum::<u64>();
    // Every disc that reached the floor was removed there: in and out alike, none left.
    let last = rows.last().unwrap();
    assert!(sum("sensor_floor_in") > 10);
    assert_eq!(sum("sensor_floor_in"), sum("sensor_floor_out"));
    assert_eq!(last[at("sensor_floor_count")], 0);
    // The circle holds what came in and did not leave.
    let held = sum("sensor_middle_in") - sum("sensor_middle_out");
    assert_eq!(held, last[at("sensor_middle_count")]);
    assert!(sum("sensor_middle_out") > 0);
}

#[test]
fn a_piston_run_reports_its_force_position_and_work() {
    let s = Scratch::new();
    let (_, header, last) = run_template(&s, "piston", "2000", &["--quiet"]);
    let at = |name: &str| header.iter().position(|h| h == name).unwrap();
    let text = std::fs::read_to_string(s.path("out/stats.csv")).unwrap();
    // 2000 steps of 0.02 at 0.05 down from y = 50.
    assert!((last[at("piston_y")] - 48.0).abs() < 1e-9);
    assert!(
        last[at("force_piston_y")] > 0.0,
        "the gas pushes the piston up"
    );
    // The work done equals the gain in kinetic energy (elastic everywhere).
    let first: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap_or(f64::NAN))
        .collect();
    let gain = last[at("kinetic_energy")] - first[at("kinetic_energy")];
    let work = last[at("obstacle_work")];
    assert!(
        gain > 0.0 && (work - gain).abs() < 0.01 * gain,
        "work {work}, gain {gain}"
    );
    assert!(s.path("out/plots.png").exists());
}

#[test]
fn png_frames_have_the_right_size_and_discs_where_the_particles_are() {
    let s = Scratch::new();
    assert_eq!(run_small(&s, "out", &[]).0, 0);
    let png = tiny_skia::Pixmap::load_png(s.path("out/frames/frame_0000000.png")).unwrap();
    // 40 x 20 box at 400 pixels wide: 10 pixels per unit.
    assert_eq!((png.width(), png.height()), (400, 200));
    let at = |x: f64, y: f64| {
        let px = png
            .pixel((x * 10.0) as u32, ((20.0 - y) * 10.0) as u32)
            .unwrap();
        [px.red(), px.green(), px.blue()]
    };
    assert_eq!(at(10.0, 10.0), [220, 50, 47], "the red disc at (10, 10)");
    assert_eq!(at(30.0, 5.0), [0, 255, 0], "the green disc at (30, 5)");
    assert_eq!(
        at(5.0, 3.0),
        [17, 20, 26],
        "background where there is no disc"
    );
    assert_eq!(
        at(13.0, 10.0),
        [17, 20, 26],
        "just outside the red disc (radius 2)"
    );
}

/// Read back by HOOMD's own `gsd` package: needs Python with `gsd`, which `scripts/test`
/// installs into a virtual environment and names in `BOUNCE_PYTHON`.
#[cfg(feature = "system-tests")]
#[test]
fn gsd_trajectory_reads_back_with_the_gsd_package() {
    let s = Scratch::new();
    assert_eq!(run_small(&s, "out", &[]).0, 0);
    let script = r#"
import sys, numpy as np, gsd.hoomd
with gsd.hoomd.open(sys.argv[1], "r") as t:
    assert len(t) == 5, len(t)
    f = t[0]
    assert f.configuration.step == 0
    assert f.configuration.dimensions == 2
    assert np.allclose(f.configuration.box[:2], [40, 20])
    assert f.particles.N == 62
    assert f.particles.position.shape == (62, 3)
    assert f.particles.velocity.shape == (62, 3)
    assert f.particles.diameter.shape == (62,)
    # Particle 0 is the red disc at (10, 10), stored relative to the box centre (20, 10).
    assert np.allclose(f.particles.position[0], [-10, 0, 0]), f.particles.position[0]
    assert np.isclose(f.particles.diameter[0], 4.0)
    assert np.isclose(f.particles.diameter[1], 3.0)
    assert t[4].configuration.step == 40
    energies = [fr.log["kinetic_energy"][0] for fr in t]
    assert np.allclose(energies, energies[0]), energies
    # The tables' tags, by id: 42, none (0), and the gas's 2^64 - 1.
    tags = t[4].log["particles/tag"]
    assert tags.dtype == np.uint64 and list(tags[:3]) == [42, 0, 2**64 - 1], tags[:3]
    print("ok", energies[0])
"#;
    let (code, stdout, stderr) = output(
        Command::new(std::env::var("BOUNCE_PYTHON").unwrap_or_else(|_| "python3".into()))
            .arg("-c")
            .arg(script)
            .arg(s.path("out/trajectory.gsd")),
    );
    assert_eq!(
        code, 0,
        "python gsd check failed (scripts/test installs gsd): {stdout}{stderr}"
    );
    assert!(stdout.starts_with("ok"));
}

#[test]
fn resume_is_bit_identical_to_an_uninterrupted_run() {
    let s = Scratch::new();
    assert_eq!(run_small(&s, "straight", &["--threads", "1"]).0, 0);
    assert_eq!(
        run_small(&s, "first", &["--steps", "17", "--threads", "2"]).0,
        0
    );
    let checkpoint = s.path("first/checkpoint.bin");
    let (code, _, stderr) = run_small(&s, "second", &["--resume", checkpoint.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let a = std::fs::read(s.path("straight/checkpoint.bin")).unwrap();
    let b = std::fs::read(s.path("second/checkpoint.bin")).unwrap();
    assert_eq!(a, b, "checkpoints differ");
}

#[test]
fn ctrl_c_finishes_the_step_and_writes_a_checkpoint() {
    let s = Scratch::new();
    let scenario = s.scenario(
        "long.toml",
        &SMALL.replace("steps = 40", "steps = 100000000"),
    );
    let child = bounce()
        .arg("run")
        .arg(&scenario)
        .arg("--out")
        .arg(s.path("out"))
        .arg("--quiet")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the run has started writing, then interrupt it.
    let frame0 = s.path("out/frames/frame_0000000.png");
    for _ in 0..200 {
        if frame0.exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    let status = Command::new("kill")
        .arg("-INT")
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("interrupted by signal 2 at step"),
        "{stderr}"
    );
    assert!(stderr.contains("--resume"), "{stderr}");
    // Everything is complete: the GSD file opens, the CSV ends with a full row.
    for file in [
        "checkpoint.bin",
        "stats.csv",
        "trajectory.gsd",
        "animation.gif",
        "plots.png",
    ] {
        assert!(s.path("out").join(file).exists(), "{file}");
    }
    let csv = std::fs::read_to_string(s.path("out/stats.csv")).unwrap();
    let columns = csv.lines().next().unwrap().split(',').count();
    assert!(csv.ends_with('\n') && csv.lines().last().unwrap().split(',').count() == columns);
}

#[test]
fn new_writes_templates_that_check_cleanly() {
    let s = Scratch::new();
    for name in [
        "gas",
        "pile",
        "newtons-cradle",
        "brownian",
        "mixing",
        "galton-board",
        "hourglass",
        "piston",
        "effusion",
        "angle-of-repose",
        "hard-discs",
        "driven-granular",
        "shear",
    ] {
        let file = s.path(&format!("{name}.toml"));
        let (code, _, stderr) = output(bounce().args(["new", name, "--out"]).arg(&file));
        assert_eq!(code, 0, "{stderr}");
        let (code, stdout, stderr) = output(bounce().arg("check").arg(&file));
        assert_eq!(code, 0, "{name}: {stderr}");
        assert!(stdout.contains("ok"), "{stdout}");
    }
    // Refuses to overwrite, and names unknown templates.
    let (code, _, stderr) = output(
        bounce()
            .args(["new", "gas", "--out"])
            .arg(s.path("gas.toml")),
    );
    assert_ne!(code, 0);
    assert!(stderr.contains("--force"), "{stderr}");
    let (code, _, stderr) = output(bounce().args(["new", "volcano"]));
    assert_ne!(code, 0);
    assert!(
        stderr.contains("volcano") && stderr.contains("newtons-cradle"),
        "{stderr}"
    );
}

#[test]
fn shipped_scenarios_all_check() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    for name in [
        "gas",
        "pile",
        "newtons-cradle",
        "brownian",
        "mixing",
        "million",
    ] {
        let (code, stdout, stderr) =
            output(bounce().arg("check").arg(root.join(format!("{name}.toml"))));
        assert_eq!(code, 0, "{name}: {stderr}");
        assert!(stdout.contains("ok"), "{stdout}");
    }
}

/// A minimal valid scenario with `body` spliced in.
fn minimal(extra_world: &str, time: &str, particles: &str) -> String {
    format!(
        "[world]\nboundary = \"walls\"\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n{extra_world}\n[time]\n{time}\n{particles}\n"
    )
}

const ONE_DISC: &str = "[[disc]]\nposition = [5.0, 5.0]\nradius = 1.0\n";

/// Bad scenario → (message fragments that must appear).
fn bad_cases() -> Vec<(&'static str, String, Vec<&'static str>)> {
    vec![
        (
            "unknown field",
            minimal("colour_scale = 3", "dt = 0.1\nsteps = 5", ONE_DISC),
            vec![":5:", "colour_scale"],
        ),
        (
            "wrong type",
            minimal("", "dt = \"fast\"\nsteps = 5", ONE_DISC),
            vec![":7:", "dt"],
        ),
        (
            "negative radius",
            minimal(
                "",
                "dt = 0.1\nsteps = 5",
                "[[disc]]\nposition = [5.0, 5.0]\nradius = -1.0\n",
            ),
            vec![":9:", "radius -1"],
        ),
        (
            "zero radius",
            minimal(
                "",
                "dt = 0.1\nsteps = 5",
                "[[gas]]\ncount = 3\nradius = 0.0\nspeed = 1.0\n",
            ),
            vec![":9:", "radius"],
        ),
        (
            "NaN",
            minimal(
                "coefficient_of_restitution = nan",
                "dt = 0.1\nsteps = 5",
                ONE_DISC,
            ),
            vec![":5:", "coefficient_of_restitution", "NaN"],
        ),
        (
            "cannot place",
            minimal(
                "",
                "dt = 0.1\nsteps = 5",
                "[[gas]]\ncount = 500\nradius = 0.5\nspeed = 1.0\n",
            ),
            vec![":9:", "could only place", "of 500"],
        ),
        (
            "outside the walls",
            minimal(
                "",
                "dt = 0.1\nsteps = 5",
                "[[disc]]\nposition = [15.0, 5.0]\nradius = 1.0\n",
            ),
            vec![":9:", "outside the box", "15"],
        ),
        (
            "dt <= 0",
            minimal("", "dt = 0.0\nsteps = 5", ONE_DISC),
            vec![":7:", "time.dt = 0"],
        ),
        (
            "negative dt",
            minimal("", "dt = -1.0\nsteps = 5", ONE_DISC),
            vec![":7:", "time.dt = -1"],
        ),
        (
            "bad colour",
            minimal(
                "",
                "dt = 0.1\nsteps = 5",
                "[[disc]]\nposition = [5.0, 5.0]\nradius = 1.0\ncolor = \"mauve\"\n",
            ),
            vec![":9:", "mauve"],
        ),
        (
            "restitution out of range",
            minimal(
                "coefficient_of_restitution = 1.5",
                "dt = 0.1\nsteps = 5",
                ONE_DISC,
            ),
            vec![":5:", "1.5", "[0, 1]"],
        ),
        (
            "two speeds",
            minimal(
                "",
                "dt = 0.1\nsteps = 5",
                "[[gas]]\ncount = 3\nradius = 0.2\nspeed = 1.0\ntemperature = 2.0\n",
            ),
            vec![":9:", "exactly one of speed"],
        ),
        (
            "no particles",
            minimal("", "dt = 0.1\nsteps = 5", ""),
            vec!["no particles"],
        ),
        (
            "missing time",
            "[world]\nboundary = \"open\"\n[[disc]]\nposition = [0.0, 0.0]\nradius = 1.0\n"
                .to_string(),
            vec!["time"],
        ),
        (
            "negative events threshold",
            minimal("", "dt = 0.1\nsteps = 5", ONE_DISC)
                + "[output]\nevents = true\nevents_threshold = -2.0\n",
            vec![":15:", "output.events_threshold = -2", ">= 0"],
        ),
        (
            "sensor region neither box nor circle",
            minimal("", "dt = 0.1\nsteps = 5", ONE_DISC)
                + "[[sensor]]\nname = \"gate\"\nregion = { centre = [1.0, 1.0] }\n",
            vec![":15:", "a box { min", "or a circle"],
        ),
        (
            "sensor name with a space",
            minimal("", "dt = 0.1\nsteps = 5", ONE_DISC)
                + "[[sensor]]\nname = \"a b\"\nregion = { min = [0.0, 0.0], max = [1.0, 1.0] }\n",
            vec![":13:", "sensor #1: name \"a b\""],
        ),
        (
            "box inverted",
            "[world]\nmin = [0.0, 0.0]\nmax = [-10.0, 10.0]\n[time]\ndt = 0.1\nsteps = 5\n"
                .to_string()
                + ONE_DISC,
            vec![":3:", "min must be below max"],
        ),
    ]
}

#[test]
fn bad_scenarios_name_file_line_and_field() {
    let s = Scratch::new();
    for (what, text, fragments) in bad_cases() {
        let file = s.scenario("bad.toml", &text);
        for command in ["check", "run"] {
            let mut cmd = bounce();
            cmd.arg(command).arg(&file).env("RUST_BACKTRACE", "1");
            if command == "run" {
                cmd.arg("--out").arg(s.path("out")).arg("--quiet");
            }
            let (code, _, stderr) = output(&mut cmd);
            let stderr = stderr.replace(&*s.path("out").to_string_lossy(), "OUT");
            assert_eq!(code, 1, "{what} ({command}): exit {code}, {stderr}");
            assert!(
                stderr.contains("bad.toml"),
                "{what} ({command}) names the file: {stderr}"
            );
            for f in &fragments {
                assert!(
                    stderr.contains(f),
                    "{what} ({command}): {f:?} missing in {stderr}"
                );
            }
            assert!(
                !stderr.contains("panicked") && !stderr.contains("backtrace"),
                "{what}: {stderr}"
            );
        }
    }
}

#[test]
fn check_reports_every_problem() {
    let s = Scratch::new();
    let text = "[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\ncollision_radius_scale = -2.0\n[time]\ndt = 0.0\nsteps = 5\n[[disc]]\nposition = [5.0, 5.0]\nradius = 1.0\ncolor = \"nope\"\n";
    let file = s.scenario("many.toml", text);
    let (code, _, stderr) = output(bounce().arg("check").arg(&file));
    assert_eq!(code, 1);
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 3, "{stderr}");
    assert!(
        lines[0].contains("many.toml:4:") && lines[0].contains("collision_radius_scale"),
        "{stderr}"
    );
    assert!(
        lines[1].contains("many.toml:6:") && lines[1].contains("dt"),
        "{stderr}"
    );
    assert!(
        lines[2].contains("many.toml:8:") && lines[2].contains("nope"),
        "{stderr}"
    );
}

#[test]
fn bad_runs_fail_cleanly() {
    let s = Scratch::new();
    let scenario = s.scenario("small.toml", SMALL);
    // Output directory that is a file.
    std::fs::write(s.path("afile"), "x").unwrap();
    let (code, _, stderr) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(s.path("afile")),
    );
    assert_eq!(code, 1);
    assert!(
        stderr.contains("output directory") && stderr.contains("afile"),
        "{stderr}"
    );
    // A missing scenario file.
    let (code, _, stderr) = output(bounce().arg("run").arg(s.path("missing.toml")));
    assert_eq!(code, 1);
    assert!(
        stderr.contains("missing.toml") && stderr.contains("cannot read"),
        "{stderr}"
    );
    // A checkpoint that is not one.
    std::fs::write(s.path("junk.bin"), "not a checkpoint").unwrap();
    let (code, _, stderr) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(s.path("o"))
            .arg("--resume")
            .arg(s.path("junk.bin")),
    );
    assert_eq!(code, 1);
    assert!(
        stderr.contains("junk.bin") && stderr.contains("not a bounce checkpoint"),
        "{stderr}"
    );
    // A truncated real checkpoint.
    assert_eq!(run_small(&s, "good", &[]).0, 0);
    let bytes = std::fs::read(s.path("good/checkpoint.bin")).unwrap();
    std::fs::write(s.path("cut.bin"), &bytes[..bytes.len() / 2]).unwrap();
    let (code, _, stderr) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(s.path("o"))
            .arg("--resume")
            .arg(s.path("cut.bin")),
    );
    assert_eq!(code, 1);
    assert!(
        stderr.contains("cut.bin") && stderr.contains("corrupt"),
        "{stderr}"
    );
    // Zero threads.
    let (code, _, stderr) = output(bounce().arg("run").arg(&scenario).arg("--threads").arg("0"));
    assert_eq!(code, 1);
    assert!(stderr.contains("--threads"), "{stderr}");
}

#[test]
fn a_thermostat_adds_its_column_balances_the_energy_and_resumes_byte_for_byte() {
    let s = Scratch::new();
    let scenario = s.path("gas.toml");
    let (code, _, stderr) = output(bounce().args(["new", "gas", "--out"]).arg(&scenario));
    assert_eq!(code, 0, "{stderr}");
    let run = |out: &str, extra: &[&str]| {
        let (code, _, stderr) = output(
            bounce()
                .arg("run")
                .arg(&scenario)
                .args([
                    "--set",
                    "world.thermostat={ kind = \"white_noise\", temperature = 1.0, rate = 0.5, seed = 2 }",
                    "--set",
                    "output.frame_every=0",
                    "--set",
                    "output.gif=false",
                    "--quiet",
                    "--out",
                ])
                .arg(s.path(out))
                .args(extra),
        );
        assert_eq!(code, 0, "{stderr}");
        std::fs::read_to_string(s.path(out).join("stats.csv")).unwrap()
    };
    let one = run("one", &["--steps", "60", "--threads", "1"]);
    assert!(one == run("two", &["--steps", "60", "--threads", "2"]));
    run("resumed", &["--steps", "25"]);
    let checkpoint = s.path("resumed/checkpoint.bin");
    let resumed = run(
        "resumed",
        &["--steps", "60", "--resume", checkpoint.to_str().unwrap()],
    );
    assert!(one == resumed, "a resumed stats.csv differs");
    // An elastic gas between elastic walls: the kinetic energy changes by exactly what the
    // thermostat added, row by row.
    let mut lines = one.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header.last(), Some(&"thermostat_work"));
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    for pair in rows.windows(2) {
        let gained = pair[1][at("kinetic_energy")] - pair[0][at("kinetic_energy")];
        let added = pair[1][at("thermostat_work")];
        assert!(
            added > 0.0 && (gained - added).abs() < 1e-9 * added,
            "{gained} vs {added}"
        );
    }
}

#[test]
fn the_pressure_tensor_columns_have_the_pressure_as_their_mean_diagonal() {
    let s = Scratch::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    for scenario in ["hard-discs.toml", "gas.toml"] {
        let out = s.path(scenario);
        let (code, _, stderr) = output(
            bounce()
                .arg("run")
                .arg(root.join(scenario))
                .args([
                    "--steps",
                    "100",
                    "--quiet",
                    "--set",
                    "output.pressure_tensor=true",
                ])
                .args(["--set", "output.frame_every=0", "--set", "output.gif=false"])
                .args(["--set", "output.gsd_every=0", "--out"])
                .arg(&out),
        );
        assert_eq!(code, 0, "{stderr}");
        let text = std::fs::read_to_string(out.join("stats.csv")).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows[0][at("pressure_xx")], ""); // no virial before the first step
        for row in &rows[1..] {
            let value = |name: &str| row[at(name)].parse::<f64>().unwrap();
            let trace = (value("pressure_xx") + value("pressure_yy")) / 2.0;
            assert!(
                (trace / value("pressure") - 1.0).abs() < 1e-12,
                "{scenario}: {row:?}"
            );
            assert!(
                value("pressure_xy").abs() < 0.2 * value("pressure"),
                "{scenario}"
            );
        }
    }
}
