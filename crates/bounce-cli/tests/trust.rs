//! Runs you can trust: each finding of the "runs you can trust" review, reproduced with its
//! exact input and answered.

mod common;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{Scratch, bounce, gsd_chunks, output};

/// A small walled gas with every output on.
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

[[gas]]
count = 60
radius = 0.3
speed = 3.0
seed = 5
region = { min = [15.0, 2.0], max = [40.0, 20.0] }
color = "blue"

[output]
stats_every = 5
frame_every = 20
frame_width = 200
gif = true
gsd_every = 10
color_by = "color"
"##;

fn run(s: &Scratch, scenario: &Path, out: &str, extra: &[&str]) -> (i32, String, String) {
    output(
        bounce()
            .arg("run")
            .arg(scenario)
            .arg("--out")
            .arg(s.path(out))
            .arg("--quiet")
            .args(extra),
    )
}

fn check(scenario: &Path, extra: &[&str]) -> (i32, String, String) {
    output(bounce().arg("check").arg(scenario).args(extra))
}

/// Waits for a child with a deadline; kills it and fails when it hangs.
fn wait(mut child: Child, limit: Duration, what: &str) -> std::process::Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("{what} still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Runs `bounce` with a time limit: a hang fails the test instead of stalling it.
fn bounded(args: &[&str], scenario: &Path, limit: Duration) -> (i32, String) {
    let child = bounce()
        .args(args)
        .arg(scenario)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = wait(child, limit, &format!("bounce {args:?}"));
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn checkpoint_step(path: &Path) -> u64 {
    bounce_scenario::checkpoint::load(path)
        .unwrap()
        .world
        .step_count()
}

fn last_row_step(csv: &Path) -> u64 {
    let text = std::fs::read_to_string(csv).unwrap();
    let last = text.lines().last().unwrap();
    last.split(',').next().unwrap().parse().unwrap()
}

fn temporaries(dir: &Path) -> Vec<String> {
    [dir.to_path_buf(), dir.join("frames")]
        .iter()
        .flat_map(|d| std::fs::read_dir(d).into_iter().flatten().flatten())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".bounce-tmp") || n.starts_with(".tmp"))
        .collect()
}

/// Starts a long run and sends `signal` once it has written its first frame.
fn signalled_run(s: &Scratch, scenario: &Path, out: &str, signal: &str) -> std::process::Output {
    let child = bounce()
        .arg("run")
        .arg(scenario)
        .arg("--out")
        .arg(s.path(out))
        .arg("--quiet")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let frame0 = s.path(out).join("frames/frame_0000000.png");
    let start = Instant::now();
    while !frame0.exists() && start.elapsed() < Duration::from_secs(20) {
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(200));
    kill(&child, signal);
    wait(child, Duration::from_secs(60), "the signalled run")
}

#[test]
fn sigterm_and_sighup_finish_the_step_write_everything_and_exit_128_plus_the_signal() {
    let s = Scratch::new();
    let scenario = s.scenario(
        "long.toml",
        &SMALL.replace("steps = 40", "steps = 100000000"),
    );
    for (signal, code) in [("TERM", 143), ("HUP", 129)] {
        let out_name = format!("out-{signal}");
        let out = signalled_run(&s, &scenario, &out_name, signal);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{signal}: {stderr}");
        assert!(stderr.contains("--resume"), "{stderr}");
        let dir = s.path(&out_name);
        for file in [
            "checkpoint.bin",
            "stats.csv",
            "trajectory.gsd",
            "animation.gif",
            "plots.png",
        ] {
            assert!(dir.join(file).exists(), "{signal}: {file}");
        }
        // The final step is in the checkpoint, the stats and the trajectory alike.
        let step = checkpoint_step(&dir.join("checkpoint.bin"));
        assert_eq!(last_row_step(&dir.join("stats.csv")), step, "{signal}");
        assert_eq!(gsd_steps(&dir.join("trajectory.gsd")).last(), Some(&step));
        assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
    }
}

/// Starts a run of steps of 10,000 substeps of 100,000 discs (about 3 s each) into `out`
/// and returns once it is well into its first step (step 0's frame is written before it).
fn slow_run(s: &Scratch, out: &Path) -> Child {
    let scenario = s.scenario(
        "slow.toml",
        &SMALL
            .replace("steps = 40", "steps = 1000\nsubsteps = 10000")
            .replace("max = [40.0, 20.0]", "max = [400.0, 400.0]")
            .replace("count = 60", "count = 100000")
            .replace(
                "region = { min = [15.0, 2.0], max = [40.0, 20.0] }",
                "region = { min = [15.0, 2.0], max = [400.0, 400.0] }",
            ),
    );
    let child = bounce()
        .args(["run", "--quiet", "--threads", "1", "--out"])
        .arg(out)
        .arg(&scenario)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let frame0 = out.join("frames/frame_0000000.png");
    while !frame0.exists() && start.elapsed() < Duration::from_secs(20) {
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(700));
    child
}

fn kill(child: &Child, signal: &str) {
    let sent = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(sent.success());
}

#[test]
fn sigterm_inside_a_long_step_stops_within_a_second_at_the_last_whole_step() {
    // Steps of 10,000 substeps of 100,000 discs: about 3 s each. A signal during one stops
    // the run within about a second, back at the step before, with every file whole
    // (finishing the step first took the rest of it).
    let s = Scratch::new();
    let out = s.path("out");
    let child = slow_run(&s, &out);
    let sent_at = Instant::now();
    kill(&child, "TERM");
    let done = wait(child, Duration::from_secs(60), "the signalled run");
    let took = sent_at.elapsed();
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert_eq!(done.status.code(), Some(143), "{stderr}");
    assert!(
        took < Duration::from_secs(2),
        "stopped {took:?} after the signal"
    );
    // Back at a whole step: the checkpoint, the last row and the frames agree.
    let step = checkpoint_step(&out.join("checkpoint.bin"));
    assert_eq!(last_row_step(&out.join("stats.csv")), step);
    assert!(temporaries(&out).is_empty(), "{:?}", temporaries(&out));
}

#[test]
fn a_second_signal_exits_at_once_and_leaves_no_partial_file() {
    // The first TERM starts the stop (back to the last whole step, then every output written:
    // a 100,000-disc trajectory frame, plots, an animation); the second, straight after, ends
    // the process before that is done. The files being written go; none is left half-written.
    let s = Scratch::new();
    let out = s.path("out");
    let child = slow_run(&s, &out);
    kill(&child, "TERM");
    std::thread::sleep(Duration::from_millis(30));
    let sent_at = Instant::now();
    kill(&child, "INT");
    let done = wait(child, Duration::from_secs(60), "the twice signalled run");
    let took = sent_at.elapsed();
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert_eq!(done.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("second signal"), "{stderr}");
    assert!(took < Duration::from_secs(1), "exited {took:?} after it");
    assert!(temporaries(&out).is_empty(), "{:?}", temporaries(&out));
    // The exit cut the outputs' writing short: the slowest, the plots and the animation,
    // are not both there. (How far it got before the second signal depends on the disk.)
    assert!(
        !(out.join("plots.png").exists() && out.join("animation.gif").exists()),
        "every output was written before the second signal"
    );
    // What is there is whole, at the step the run stopped at.
    if out.join("checkpoint.bin").exists() {
        let step = checkpoint_step(&out.join("checkpoint.bin"));
        if out.join("stats.csv").exists() {
            assert_eq!(last_row_step(&out.join("stats.csv")), step);
        }
        if out.join("trajectory.gsd").exists() {
            assert_eq!(gsd_steps(&out.join("trajectory.gsd")).last(), Some(&step));
        }
    }
    if out.join("plots.png").exists() {
        assert!(tiny_skia::Pixmap::load_png(out.join("plots.png")).is_ok());
    }
    let frame = out.join("frames/frame_0000000.png");
    assert!(
        tiny_skia::Pixmap::load_png(&frame).is_ok(),
        "{} is not whole",
        frame.display()
    );
}

/// The `configuration/step` of every frame of a GSD file.
fn gsd_steps(path: &Path) -> Vec<u64> {
    gsd_chunks(path)
        .into_iter()
        .filter(|c| c.name == "configuration/step")
        .map(|c| u64::from_le_bytes(c.data[..8].try_into().unwrap()))
        .collect()
}

fn frame_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn assert_same_run(a: &Path, b: &Path) {
    for file in ["stats.csv", "trajectory.gsd", "checkpoint.bin"] {
        assert!(
            std::fs::read(a.join(file)).unwrap() == std::fs::read(b.join(file)).unwrap(),
            "{file} differs from the uninterrupted run's"
        );
    }
    assert_eq!(frame_names(a), frame_names(b));
}

#[test]
fn resume_into_the_same_folder_continues_the_same_files() {
    let s = Scratch::new();
    let scenario = s.scenario("small.toml", SMALL);
    assert_eq!(run(&s, &scenario, "straight", &["--threads", "1"]).0, 0);
    // Stopped at step 17 (off every schedule), then resumed to the end with another thread
    // count.
    assert_eq!(run(&s, &scenario, "cut", &["--steps", "17"]).0, 0);
    assert_eq!(last_row_step(&s.path("cut/stats.csv")), 17);
    let checkpoint = s.path("cut/checkpoint.bin");
    let (code, _, stderr) = run(
        &s,
        &scenario,
        "cut",
        &["--resume", checkpoint.to_str().unwrap(), "--threads", "2"],
    );
    assert_eq!(code, 0, "{stderr}");
    assert_same_run(&s.path("straight"), &s.path("cut"));
    // Twice over: a resume from a checkpoint that is itself on the schedule.
    assert_eq!(run(&s, &scenario, "twice", &["--steps", "20"]).0, 0);
    let checkpoint = s.path("twice/checkpoint.bin");
    let (code, _, stderr) = run(
        &s,
        &scenario,
        "twice",
        &["--resume", checkpoint.to_str().unwrap()],
    );
    assert_eq!(code, 0, "{stderr}");
    assert_same_run(&s.path("straight"), &s.path("twice"));
}

#[test]
fn a_run_interrupted_at_any_step_and_resumed_equals_an_uninterrupted_one() {
    let s = Scratch::new();
    let text = SMALL.replace("steps = 40", "steps = 6000");
    let scenario = s.scenario("mid.toml", &text);
    assert_eq!(run(&s, &scenario, "straight", &[]).0, 0);
    let out = signalled_run(&s, &scenario, "cut", "INT");
    assert_eq!(out.status.code(), Some(130));
    let stopped = checkpoint_step(&s.path("cut/checkpoint.bin"));
    assert!(stopped < 6000, "the run finished before the signal");
    // The exact command the run printed.
    let stderr = String::from_utf8_lossy(&out.stderr);
    let command = stderr.split("continue with: ").nth(1).unwrap().trim();
    let args: Vec<&str> = command.split_whitespace().skip(1).collect();
    let (code, _, stderr) = output(bounce().args(&args).arg("--quiet"));
    assert_eq!(code, 0, "{command}: {stderr}");
    assert_same_run(&s.path("straight"), &s.path("cut"));
}

#[test]
fn an_old_output_folder_is_refused_unless_forced_and_stale_files_go() {
    let s = Scratch::new();
    let scenario = s.scenario("small.toml", SMALL);
    assert_eq!(run(&s, &scenario, "out", &[]).0, 0);
    let (code, _, stderr) = run(&s, &scenario, "out", &[]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("--force") && stderr.contains("stats.csv"),
        "{stderr}"
    );
    // A stale frame of an older run and a temporary file of a killed one.
    std::fs::write(s.path("out/frames/frame_9999999.png"), b"old").unwrap();
    std::fs::write(s.path("out/.bounce-tmp-killed"), b"half").unwrap();
    let (code, _, stderr) = run(&s, &scenario, "out", &["--force", "--steps", "25"]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(
        frame_names(&s.path("out")),
        vec![
            "frame_0000000.png",
            "frame_0000020.png",
            "frame_0000025.png"
        ]
    );
    assert!(temporaries(&s.path("out")).is_empty());
}

#[test]
fn a_checkpoint_of_another_scenario_is_refused_naming_what_differs() {
    let s = Scratch::new();
    let scenario = s.scenario("small.toml", SMALL);
    assert_eq!(run(&s, &scenario, "a", &["--steps", "5"]).0, 0);
    let other = s.scenario(
        "other.toml",
        &SMALL.replace("[world]\n", "[world]\ngravity = [0.0, -1.0]\n"),
    );
    let checkpoint = s.path("a/checkpoint.bin");
    let (code, _, stderr) = run(&s, &other, "b", &["--resume", checkpoint.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("not a checkpoint of")
            && stderr.contains("gravity: [0.0, -1.0] vs [0.0, 0.0]"),
        "{stderr}"
    );
}

#[test]
fn huge_counts_are_refused_up_front_with_the_estimate() {
    let s = Scratch::new();
    let limit = Duration::from_secs(20);
    for count in ["1000000000", "9000000000000000000"] {
        let scenario = s.scenario(
            "huge.toml",
            &SMALL.replace("count = 60", &format!("count = {count}")),
        );
        for command in ["check", "run"] {
            let (code, stderr) = bounded(&[command], &scenario, limit);
            assert_eq!(code, 1, "{command} {count}: {stderr}");
            assert!(
                stderr.contains("GiB") && stderr.contains("--memory-limit"),
                "{stderr}"
            );
        }
    }
    // Counts that overflow 64 bits.
    let lattice = s.scenario(
        "lattice.toml",
        &SMALL.replace(
            "[output]",
            "[[lattice]]\norigin = [1.0, 1.0]\nspacing = [1.0, 1.0]\ncounts = [4294967296, 4294967296]\nradius = 0.1\n\n[output]",
        ),
    );
    let (code, stderr) = bounded(&["check"], &lattice, limit);
    assert_eq!(code, 1);
    assert!(stderr.contains("overflow"), "{stderr}");
    // The limit can be lowered (and raised) from the command line.
    let small = s.scenario("small.toml", SMALL);
    let (code, _, stderr) = check(&small, &["--memory-limit", "0.00001"]);
    assert_eq!(code, 1);
    assert!(stderr.contains("over the limit"), "{stderr}");
    assert_eq!(check(&small, &["--memory-limit", "64"]).0, 0);
}

#[test]
fn inputs_that_made_placement_loop_forever_now_end() {
    let s = Scratch::new();
    let limit = Duration::from_secs(30);
    let cases = [
        (
            "scale",
            SMALL.replace(
                "max = [40.0, 20.0]",
                "max = [40.0, 20.0]\ncollision_radius_scale = 1e300",
            ),
        ),
        (
            "periodic giant",
            SMALL
                .replace("boundary = \"walls\"", "boundary = \"periodic\"")
                .replace("radius = 0.3", "radius = 1e200"),
        ),
        (
            "denormal region",
            SMALL.replace(
                "region = { min = [15.0, 2.0], max = [40.0, 20.0] }",
                "region = { min = [15.0, 0.0], max = [40.0, 1e-320] }",
            ),
        ),
    ];
    for (what, text) in cases {
        let scenario = s.scenario("case.toml", &text);
        let (code, stderr) = bounded(&["check"], &scenario, limit);
        assert_eq!(code, 1, "{what}: {stderr}");
        assert!(stderr.contains("case.toml"), "{what}: {stderr}");
    }
}

#[test]
fn an_overflowing_run_stops_naming_the_step_and_particle_and_keeps_its_outputs() {
    let s = Scratch::new();
    for (what, text) in [
        (
            "dt",
            SMALL
                .replace("dt = 0.02", "dt = 1e300")
                .replace("boundary = \"walls\"", "boundary = \"open\"")
                .replace("speed = 3.0", "speed = 1e10"),
        ),
        (
            "gravity",
            SMALL.replace("[world]\n", "[world]\ngravity = [0.0, -1e300]\n"),
        ),
    ] {
        let scenario = s.scenario("big.toml", &text);
        let out = format!("out-{what}");
        let (code, _, stderr) = run(&s, &scenario, &out, &[]);
        assert_eq!(code, 1, "{what}: {stderr}");
        assert!(
            stderr.contains("step 1: particle") && stderr.contains("non-finite"),
            "{what}: {stderr}"
        );
        let dir = s.path(&out);
        assert_eq!(checkpoint_step(&dir.join("checkpoint.bin")), 0, "{what}");
        let csv = std::fs::read_to_string(dir.join("stats.csv")).unwrap();
        assert!(
            !csv.contains("inf") && !csv.contains("NaN"),
            "{what}: {csv}"
        );
        assert!(dir.join("plots.png").exists() && dir.join("trajectory.gsd").exists());
    }
}

#[test]
fn worlds_whose_energy_overflows_are_refused_at_the_start() {
    let s = Scratch::new();
    let scenario = s.scenario("fast.toml", &SMALL.replace("speed = 3.0", "speed = 1e200"));
    let (code, _, stderr) = check(&scenario, &[]);
    assert_eq!(code, 1);
    assert!(stderr.contains("kinetic energy"), "{stderr}");
    let heavy = s.scenario(
        "heavy.toml",
        &SMALL.replace("[world]\n", "[world]\ngravity = [0.0, -1e308]\n"),
    );
    let (code, _, stderr) = run(&s, &heavy, "heavy", &[]);
    assert_eq!(code, 1);
    assert!(stderr.contains("potential energy"), "{stderr}");
}

#[test]
fn substeps_and_threads_have_upper_bounds() {
    let s = Scratch::new();
    let scenario = s.scenario(
        "subs.toml",
        &SMALL.replace("steps = 40", "steps = 40\nsubsteps = 1000000000"),
    );
    let (code, stderr) = bounded(&["check"], &scenario, Duration::from_secs(10));
    assert_eq!(code, 1);
    assert!(
        stderr.contains("substeps") && stderr.contains("10000"),
        "{stderr}"
    );
    let small = s.scenario("small.toml", SMALL);
    let (code, _, stderr) = run(&s, &small, "t", &["--threads", "100000"]);
    assert_eq!(code, 1);
    assert!(stderr.contains("--threads"), "{stderr}");
}

#[test]
fn generators_keep_clear_of_earlier_tables_and_check_reports_overlaps() {
    let s = Scratch::new();
    // The shipped brownian scenario: no small disc starts inside the big one.
    let text = bounce_scenario::template("brownian").unwrap();
    let session = bounce_scenario::Session::from_text("brownian", text).unwrap();
    let world = &session.world;
    let big = world.particle(bounce::ParticleId(0)).unwrap();
    for (_, p) in world.particles_by_id().iter().skip(1) {
        let d = (p.position[0] - big.position[0]).hypot(p.position[1] - big.position[1]);
        assert!(
            d > big.radius + p.radius,
            "a disc at {:?} is inside",
            p.position
        );
    }
    // The same tables the other way round: the disc comes after the gas, onto its discs.
    let swapped = text
        .replace("[[disc]]", "[[tmp]]")
        .replace("[[gas]]", "[[disc-later]]");
    let disc = "[[disc]]\nposition = [60.0, 60.0]\nradius = 6.0\n";
    let swapped = swapped
        .replace(
            "[[tmp]]\nposition = [60.0, 60.0]\nradius = 6.0\ncolor = \"#e8463c\"\n",
            "",
        )
        .replace("[[disc-later]]", "[[gas]]")
        .replace("[output]", &format!("{disc}\n[output]"));
    let scenario = s.scenario("swapped.toml", &swapped);
    let (code, _, stderr) = check(&scenario, &[]);
    assert_eq!(code, 1, "{swapped}");
    assert!(
        stderr.contains("gas #1 (line")
            && stderr.contains("disc #1 (line")
            && stderr.contains("overlap"),
        "{stderr}"
    );
}

#[test]
fn set_seed_and_version_steer_the_run() {
    let s = Scratch::new();
    let scenario = s.scenario("small.toml", SMALL);
    let (code, _, stderr) = run(
        &s,
        &scenario,
        "set",
        &[
            "--set",
            "world.coefficient_of_restitution=0.5",
            "--set",
            "time.steps=6",
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    let world = bounce_scenario::checkpoint::load(&s.path("set/checkpoint.bin"))
        .unwrap()
        .world;
    assert_eq!(world.step_count(), 6);
    assert_eq!(world.config().coefficient_of_restitution, 0.5);
    // Validated like the file.
    let (code, _, stderr) = check(&scenario, &["--set", "time.dt=-1"]);
    assert_eq!(code, 1);
    assert!(stderr.contains("time.dt = -1"), "{stderr}");
    // --seed reseeds the gas: another state, the same for the same seed.
    let hash = |extra: &[&str]| -> String {
        let (code, stdout, stderr) = run(
            &s,
            &scenario,
            "seeded",
            &[&["--force", "--steps", "3"], extra].concat(),
        );
        assert_eq!(code, 0, "{stderr}");
        stdout.split("state hash ").nth(1).unwrap()[..16].to_string()
    };
    let (plain, seeded, again) = (hash(&[]), hash(&["--seed", "9"]), hash(&["--seed", "9"]));
    assert_ne!(plain, seeded);
    assert_eq!(seeded, again);
    let (code, stdout, _) = output(bounce().arg("--version"));
    assert_eq!(code, 0);
    assert_eq!(stdout.trim(), concat!("bounce ", env!("CARGO_PKG_VERSION")));
}

#[test]
fn the_summary_splits_physics_from_output_time_and_counts_potential_energy() {
    let s = Scratch::new();
    let pile = s.scenario("pile.toml", bounce_scenario::template("pile").unwrap());
    let (code, stdout, stderr) = run(&s, &pile, "pile", &["--steps", "120"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("time: physics") && stdout.contains("outputs"),
        "{stdout}"
    );
    let change: f64 = stdout
        .split("kinetic + potential energy ")
        .nth(1)
        .and_then(|rest| rest.split(',').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{stdout}"));
    // Falling discs turn potential energy into kinetic; the total only loses to inelastic
    // collisions (e = 0.7), never gains a hundredfold as kinetic energy alone does.
    assert!((-1.0..=0.01).contains(&change), "{stdout}");
}

/// Read back by HOOMD's own `gsd` package (`scripts/test` installs it in a virtual
/// environment named by `BOUNCE_PYTHON`): types from the scenario, image flags that unwrap a
/// periodic trajectory, and absolute positions in an open world.
#[cfg(feature = "system-tests")]
#[test]
fn the_gsd_trajectory_keeps_types_images_and_a_fixed_origin() {
    let s = Scratch::new();
    let python = std::env::var("BOUNCE_PYTHON").unwrap_or_else(|_| "python3".into());
    // The shipped mixing scenario: two species by colour.
    let mixing = bounce_scenario::template("mixing").unwrap().replace(
        "[output]",
        "[output]\ngsd_every = 50\nframe_every = 0\ngif = false\nplots = false\n[unused]",
    );
    let mixing = mixing.replace("\n[unused]", "");
    let mixing_path = s.scenario("mixing.toml", &strip_output_keys(&mixing));
    assert_eq!(run(&s, &mixing_path, "mixing", &["--steps", "100"]).0, 0);
    // A fast periodic gas, a lone disc in the open.
    let periodic = s.scenario(
        "periodic.toml",
        "[world]\nboundary = \"periodic\"\nmin = [0.0, 0.0]\nmax = [20.0, 20.0]\n\
         [time]\ndt = 0.05\nsteps = 200\n[[gas]]\ncount = 50\nradius = 0.3\nspeed = 6.0\n\
         type = \"fast\"\n[output]\ngsd_every = 1\nplots = false\n",
    );
    assert_eq!(run(&s, &periodic, "periodic", &[]).0, 0);
    let open = s.scenario(
        "open.toml",
        "[world]\nboundary = \"open\"\n[time]\ndt = 0.1\nsteps = 20\n\
         [[disc]]\nposition = [100.0, 50.0]\nvelocity = [1.0, 0.0]\nradius = 0.5\n\
         [[disc]]\nposition = [-3.0, 0.0]\nradius = 0.5\n[output]\ngsd_every = 10\nplots = false\n",
    );
    assert_eq!(run(&s, &open, "open", &[]).0, 0);
    let script = r#"
import sys, numpy as np, gsd.hoomd
mixing, periodic, open_ = sys.argv[1:4]
with gsd.hoomd.open(mixing, "r") as t:
    f = t[-1]
    types = list(f.particles.types)
    assert types == ["red", "blue"], types
    counts = np.bincount(f.particles.typeid)
    assert len(counts) == 2 and counts.min() > 0, counts
with gsd.hoomd.open(periodic, "r") as t:
    L = t[0].configuration.box[0]
    assert list(t[0].particles.types) == ["fast"]
    first = t[0].particles.position + t[0].particles.image * L
    crossed = 0
    prev = first
    for f in t[1:]:
        unwrapped = f.particles.position + f.particles.image * L
        # Per frame (one step of 0.05 at speeds near 6) no disc moves a box width.
        assert np.abs(unwrapped - prev).max() < 2.0, np.abs(unwrapped - prev).max()
        prev = unwrapped
        crossed = max(crossed, np.abs(f.particles.image).max())
    assert crossed >= 1, crossed
with gsd.hoomd.open(open_, "r") as t:
    for f in t:
        # Absolute positions: the drifting disc's x is 100 + time, whatever the box.
        x = f.particles.position[0][0]
        assert abs(x - (100 + 0.1 * f.configuration.step)) < 1e-3, x
        assert abs(f.particles.position[1][0] + 3) < 1e-5
print("ok")
"#;
    let (code, stdout, stderr) = output(
        Command::new(python)
            .arg("-c")
            .arg(script)
            .arg(s.path("mixing/trajectory.gsd"))
            .arg(s.path("periodic/trajectory.gsd"))
            .arg(s.path("open/trajectory.gsd")),
    );
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.starts_with("ok"));
}

/// A scenario text with `gsd_every`, `frame_every`, `gif` and `plots` given once (the first
/// time each appears wins).
#[cfg(feature = "system-tests")]
fn strip_output_keys(text: &str) -> String {
    let mut seen = std::collections::HashSet::new();
    text.lines()
        .filter(|l| {
            let key = l.split('=').next().unwrap_or("").trim();
            !["gsd_every", "frame_every", "gif", "plots"].contains(&key)
                || seen.insert(key.to_string())
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn validate_quick_passes_every_check_and_draws_the_equation_of_state() {
    let s = Scratch::new();
    let (code, stdout, stderr) = output(
        bounce()
            .args(["validate", "--quick", "--out"])
            .arg(s.path("v")),
    );
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert_eq!(stdout.matches("PASS").count(), 13, "{stdout}");
    assert!(!stdout.contains("FAIL"), "{stdout}");
    assert!(stdout.contains("13 of 13 checks passed in"), "{stdout}");
    assert!(
        stdout.contains("shear viscosity at packing 0.3"),
        "{stdout}"
    );
    assert!(
        stdout.contains("exact hard discs: collision rate at packing 0.3"),
        "{stdout}"
    );
    assert!(
        stdout.contains("acceleration rolling 2.28"),
        "the rough disc rolls: {stdout}"
    );
    assert!(
        stdout.contains("largest speed: bounce 0.100000, rest 0"),
        "{stdout}"
    );
    let plot = tiny_skia::Pixmap::load_png(s.path("v/validate.png")).unwrap();
    assert_eq!((plot.width(), plot.height()), (800, 560));
}

#[test]
fn a_lattice_gas_reaches_a_dense_liquid_from_a_scenario() {
    let s = Scratch::new();
    // Packing 0.7 in a 40 × 40 periodic box: random placement cannot, the lattice can.
    let text = |placement: &str| {
        format!(
            "[world]\nboundary = \"periodic\"\nmin = [0.0, 0.0]\nmax = [40.0, 40.0]\n\
             [time]\ndt = 0.005\nsteps = 20\n[[gas]]\ncount = 1426\nradius = 0.5\n\
             temperature = 1.0\nzero_momentum = true\nplacement = \"{placement}\"\n"
        )
    };
    let random = s.scenario("random.toml", &text("random"));
    let (code, _, stderr) = check(&random, &[]);
    assert_eq!(code, 1);
    assert!(stderr.contains("could only place"), "{stderr}");
    let lattice = s.scenario("lattice.toml", &text("lattice"));
    let (code, stdout, stderr) = check(&lattice, &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("1426 particles"), "{stdout}");
    let (code, stdout, stderr) = run(&s, &lattice, "out", &[]);
    assert_eq!(code, 0, "{stderr}");
    // Zero net momentum from the start: every row's momentum is rounding.
    let csv = std::fs::read_to_string(s.path("out/stats.csv")).unwrap();
    for row in csv.lines().skip(1) {
        let cols: Vec<f64> = row.split(',').take(5).map(|v| v.parse().unwrap()).collect();
        assert!(cols[3].abs() < 1e-9 && cols[4].abs() < 1e-9, "{row}");
    }
    assert!(stdout.contains("expected pressure bias"), "{stdout}");
}

#[test]
fn a_closed_standard_output_ends_the_command_quietly() {
    // `bounce check ... | head -1`: the reader leaves before bounce writes. Found by
    // review: `println!` panicked on the broken pipe. Now the process ends as other Unix
    // tools do, on SIGPIPE, with no panic message.
    let scenario =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/gas.toml");
    for _ in 0..5 {
        let mut child = bounce()
            .arg("check")
            .arg(&scenario)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take()); // the reader is gone before the first line
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{stderr}");
        #[cfg(unix)]
        {
            use std::os::unix::process::ExitStatusExt;
            // Ended by SIGPIPE, or done before the pipe closed.
            assert!(
                out.status.signal() == Some(SIGPIPE) || out.status.success(),
                "{:?}",
                out.status
            );
        }
    }
}

/// SIGPIPE's number on Linux and the BSDs.
#[cfg(unix)]
const SIGPIPE: i32 = 13;

#[test]
fn a_second_signal_keeps_every_whole_row_and_frame_and_the_run_resumes_from_them() {
    // The third round's find: a second SIGTERM removed `stats.csv` and `trajectory.gsd` as
    // files being written, and `--resume` then began `stats.csv` at the last checkpoint's
    // step without a word. Now the second signal keeps each up to its last whole row or
    // frame, and the resumed run equals an uninterrupted one.
    let s = Scratch::new();
    let text = SMALL
        .replace("steps = 40", "steps = 300000")
        .replace("count = 60", "count = 400")
        .replace("stats_every = 5", "stats_every = 50")
        .replace(
            "frame_every = 20",
            "frame_every = 100000\ncheckpoint_every = 20000",
        )
        .replace("gsd_every = 10", "gsd_every = 1000")
        .replace("gif = true", "gif = false");
    let scenario = s.scenario("long.toml", &text);
    let (code, _, stderr) = run(&s, &scenario, "straight", &[]);
    assert_eq!(code, 0, "{stderr}");
    // The second signal must come while the first stop is still writing; on a busy machine
    // the stop may finish first, so a few tries are allowed.
    let mut landed = None;
    for attempt in 0..5 {
        let out = s.path(&format!("cut{attempt}"));
        let child = bounce()
            .args(["run", "--quiet", "--out"])
            .arg(&out)
            .arg(&scenario)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(1500));
        kill(&child, "TERM");
        kill(&child, "TERM");
        let done = wait(child, Duration::from_secs(60), "the twice signalled run");
        let stderr = String::from_utf8_lossy(&done.stderr).into_owned();
        assert_eq!(done.status.code(), Some(143), "{stderr}");
        if stderr.contains("second signal") {
            landed = Some(out);
            break;
        }
    }
    let out =
        landed.expect("in five tries, the first stop always finished before the second signal");
    assert!(temporaries(&out).is_empty(), "{:?}", temporaries(&out));
    // Every row and frame up to the last whole one, none missing.
    let stats = std::fs::read_to_string(out.join("stats.csv")).unwrap();
    let steps: Vec<u64> = (stats.lines().skip(1))
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(steps.len() > 10, "{} rows", steps.len());
    for (k, step) in steps.iter().enumerate() {
        // (The last row may be the stop's, off the schedule.)
        assert!(
            *step == 50 * k as u64 || k == steps.len() - 1,
            "row {k} is step {step}"
        );
    }
    let frames = gsd_steps(&out.join("trajectory.gsd"));
    assert!(!frames.is_empty());
    for (k, step) in frames.iter().enumerate() {
        assert!(
            *step == 1000 * k as u64 || k == frames.len() - 1,
            "frame {k} is step {step}"
        );
    }
    // The run continues from its checkpoint over those files, as if never interrupted.
    let checkpoint = out.join("checkpoint.bin");
    let folder = out.file_name().unwrap().to_str().unwrap();
    let (code, _, stderr) = run(
        &s,
        &scenario,
        folder,
        &["--resume", checkpoint.to_str().unwrap()],
    );
    assert_eq!(code, 0, "{stderr}");
    assert_same_run(&s.path("straight"), &out);
}

#[test]
fn a_resume_over_rows_that_were_lost_says_so_and_stops() {
    let s = Scratch::new();
    let scenario = s.scenario("small.toml", SMALL);
    assert_eq!(run(&s, &scenario, "cut", &["--steps", "30"]).0, 0);
    // Rows after step 10 lost (as a second signal once removed them).
    let path = s.path("cut/stats.csv");
    let stats = std::fs::read_to_string(&path).unwrap();
    let kept: Vec<&str> = stats.lines().take(4).collect();
    std::fs::write(&path, kept.join("\n") + "\n").unwrap();
    let checkpoint = s.path("cut/checkpoint.bin");
    let (code, _, stderr) = run(
        &s,
        &scenario,
        "cut",
        &["--resume", checkpoint.to_str().unwrap()],
    );
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("stats.csv")
            && stderr.contains("ends at step 10")
            && stderr.contains("through step 30"),
        "{stderr}"
    );
}
