//! Regression tests for what the third hostile round found (issue 60), each named for its
//! find: damaged GSD files, FIFOs and devices, a spin whose energy overflows, a box too small
//! for a pressure, and sweeps whose product of lists runs away. Each is refused with a
//! message naming it, quickly, with no panic; and an output that cannot hold a value keeps
//! the run written so far.

mod common;

use std::path::Path;
use std::time::{Duration, Instant};

use common::{Scratch, bounce, output};

const SMALL: &str = "[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n[time]\ndt = 0.01\nsteps = 4\n\
                     [[gas]]\ncount = 20\nradius = 0.3\nspeed = 1.0\n[output]\ngsd_every = 2\n\
                     plots = false\n";

/// Runs `command`, killing it past `seconds` (a FIFO would block it forever): (exit code,
/// stderr), or a failure naming the hang.
fn output_within(command: &mut std::process::Command, seconds: u64) -> (i32, String) {
    use std::io::Read;
    let mut child = command
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(seconds);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            return (status.code().unwrap_or(-1), err);
        }
        if Instant::now() > deadline {
            child.kill().unwrap();
            panic!("still running after {seconds} s: it waits on the FIFO");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// A GSD trajectory of a small run, its bytes, and where its index starts and ends.
fn trajectory(s: &Scratch) -> (Vec<u8>, usize, usize) {
    let scenario = s.scenario("small.toml", SMALL);
    let (code, _, err) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(s.path("run"))
            .arg("-q"),
    );
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(s.path("run/trajectory.gsd")).unwrap();
    let word = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) as usize;
    // GSD 2.0's header: magic, index location, index entries allocated.
    let (index, allocated) = (word(8), word(16));
    (bytes, index, index + 32 * allocated)
}

/// Runs `bounce analyze` on `bytes` written as a file; (exit code, stderr).
fn analyze(s: &Scratch, bytes: &[u8]) -> (i32, String) {
    let path = s.path("damaged.gsd");
    std::fs::write(&path, bytes).unwrap();
    let (code, _, err) = output(
        bounce()
            .arg("analyze")
            .arg(&path)
            .arg("--out")
            .arg(s.path("a")),
    );
    assert!(!err.contains("panicked"), "{err}");
    (code, err)
}

#[test]
fn a_gsd_index_entry_holding_no_values_is_refused_not_a_panic() {
    let s = Scratch::new();
    let (mut bytes, from, to) = trajectory(&s);
    // Every entry's N (bytes 8..16 of its 32) set to 0.
    for entry in (from..to).step_by(32) {
        if bytes[entry..entry + 32].iter().any(|&b| b != 0) {
            bytes[entry + 8..entry + 16].copy_from_slice(&0u64.to_le_bytes());
        }
    }
    let (code, err) = analyze(&s, &bytes);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("holds no value") || err.contains("no particles"),
        "{err}"
    );
}

#[test]
fn a_gsd_index_naming_frame_a_billion_is_damaged_not_a_billion_frames() {
    let s = Scratch::new();
    let (mut bytes, from, _) = trajectory(&s);
    // The first entry's frame (bytes 0..8) set to 10⁹.
    bytes[from..from + 8].copy_from_slice(&1_000_000_000u64.to_le_bytes());
    let start = Instant::now();
    let (code, err) = analyze(&s, &bytes);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("damaged"), "{err}");
    assert!(start.elapsed() < Duration::from_secs(10));
}

#[cfg(unix)]
#[test]
fn a_fifo_named_as_a_file_of_discs_is_refused_at_once() {
    let s = Scratch::new();
    let fifo = s.path("discs.csv");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let scenario = s.scenario(
        "f.toml",
        "[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n[time]\ndt = 0.01\nsteps = 4\n\
         [[file]]\npath = \"discs.csv\"\n",
    );
    let start = Instant::now();
    let (code, err) = output_within(bounce().arg("check").arg(&scenario), 20);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("not a regular file"), "{err}");
    assert!(start.elapsed() < Duration::from_secs(10));
    // A FIFO as the scenario itself too.
    let (code, err) = output_within(bounce().arg("check").arg(&fifo), 20);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("not a regular file"), "{err}");
}

#[cfg(unix)]
#[test]
fn a_device_is_never_replaced_by_an_output() {
    let null = Path::new("/dev/null");
    let (code, _, err) = output(bounce().args(["new", "gas", "--force", "--out"]).arg(null));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("not a regular file"), "{err}");
    use std::os::unix::fs::FileTypeExt;
    assert!(
        std::fs::metadata(null)
            .unwrap()
            .file_type()
            .is_char_device()
    );
}

#[test]
fn a_spin_whose_energy_overflows_is_refused_at_the_start() {
    let s = Scratch::new();
    let scenario = s.scenario(
        "spin.toml",
        "[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n[time]\ndt = 0.01\nsteps = 4\n\
         [[disc]]\nposition = [5.0, 5.0]\nradius = 0.5\nangular_velocity = 1e160\n",
    );
    let (code, _, err) = output(bounce().arg("check").arg(&scenario));
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("rotational energy") && err.contains("disc #1"),
        "{err}"
    );
}

#[test]
fn a_box_too_small_for_a_pressure_is_refused() {
    let s = Scratch::new();
    let scenario = s.scenario(
        "tiny.toml",
        "[world]\nboundary = \"periodic\"\nmin = [0.0, 0.0]\nmax = [1e-300, 1e-300]\n\
         [time]\ndt = 0.01\nsteps = 4\n[[disc]]\nposition = [0.0, 0.0]\nradius = 1e-301\n",
    );
    let (code, _, err) = output(bounce().arg("check").arg(&scenario));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("area"), "{err}");
}

#[test]
fn a_sweep_whose_product_runs_away_is_refused_with_its_count() {
    let s = Scratch::new();
    s.scenario("gas.toml", SMALL);
    for (body, count) in [
        ("seeds = 9223372036854775807\n", "9223372036854775807"),
        ("seeds = 1000000000\n", "1000000000"),
    ] {
        let sweep = s.scenario(
            "sweep.toml",
            &format!("scenario = \"gas.toml\"\n{body}[parameters]\n\"world.friction\" = [0.0]\n"),
        );
        let start = Instant::now();
        let (code, _, err) = output(
            bounce()
                .arg("sweep")
                .arg(&sweep)
                .arg("--out")
                .arg(s.path("ws")),
        );
        assert_eq!(code, 1, "{err}");
        assert!(err.contains(count) && err.contains("--max-jobs"), "{err}");
        assert!(start.elapsed() < Duration::from_secs(10));
        assert!(!s.path("ws").exists(), "no workspace made");
    }
    // 8 keys of 10 values: 10⁸ jobs.
    let keys: String = (0..8)
        .map(|k| format!("\"gas.{k}x\" = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]\n"))
        .collect();
    let sweep = s.scenario(
        "sweep.toml",
        &format!("scenario = \"gas.toml\"\n[parameters]\n{keys}"),
    );
    let (code, _, err) = output(
        bounce()
            .arg("sweep")
            .arg(&sweep)
            .arg("--out")
            .arg(s.path("ws")),
    );
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("100000000 jobs"), "{err}");
    // A raised limit runs a large-ish sweep's check (the product only; --slurm writes no runs).
    let sweep = s.scenario(
        "sweep.toml",
        "scenario = \"gas.toml\"\nseeds = 12000\n[parameters]\n\"world.friction\" = [0.0]\n",
    );
    let (code, _, err) = output(
        bounce()
            .arg("sweep")
            .arg(&sweep)
            .arg("--out")
            .arg(s.path("ws"))
            .args(["--slurm", "--max-jobs", "12000"]),
    );
    assert_eq!(code, 0, "{err}");
    let script = std::fs::read_to_string(s.path("ws/sweep.sbatch")).unwrap();
    assert!(script.contains("--max-jobs 12000"), "{script}");
}

#[test]
fn an_output_that_cannot_hold_a_value_keeps_the_run_written_so_far() {
    // Two discs falling under a gravity of 1e37: at step 583 the open world's box no longer
    // fits a GSD frame's 32-bit floats. Every file keeps what it held before.
    let s = Scratch::new();
    let scenario = s.scenario(
        "fall.toml",
        "[world]\nboundary = \"open\"\ngravity = [0.0, -1e37]\n[time]\ndt = 0.01\n\
         steps = 1000\n[[disc]]\nposition = [0.0, 0.0]\nradius = 0.5\n[[disc]]\n\
         position = [3.0, 0.0]\nradius = 0.5\n[output]\nstats_every = 1\ngsd_every = 1\n\
         plots = false\n",
    );
    let (code, _, err) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(s.path("run"))
            .arg("-q"),
    );
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("beyond the 32-bit floats") && err.contains("its state at step 583"),
        "{err}"
    );
    let stats = std::fs::read_to_string(s.path("run/stats.csv")).unwrap();
    let last = stats.lines().last().unwrap();
    assert_eq!(stats.lines().count(), 1 + 584, "{last}");
    assert!(last.starts_with("583,"), "{last}");
    let gsd = bounce_scenario::trajectory::Trajectory::open(&s.path("run/trajectory.gsd")).unwrap();
    assert_eq!(gsd.len(), 583, "frames 0 to 582");
    let checkpoint = std::fs::read(s.path("run/checkpoint.bin")).unwrap();
    let loaded = bounce_scenario::checkpoint::decode(&checkpoint, "checkpoint.bin").unwrap();
    assert_eq!(loaded.world.step_count(), 583);
}

#[test]
fn check_finds_what_a_run_would_refuse_at_its_first_step() {
    // Three of the files `check` passed and `run` refused at step 0: each is now a problem
    // of the file, named with its line, in both.
    let s = Scratch::new();
    for (name, text, line, says) in [
        (
            "energy.toml",
            "[world]\nboundary = \"open\"\ngravity = [0.0, -1e300]\n[time]\ndt = 0.01\n\
             steps = 4\n[[disc]]\nposition = [0.0, 1e300]\nradius = 0.5\n",
            ":3: world.gravity",
            "overflows f64",
        ),
        (
            "frame.toml",
            "[world]\nboundary = \"open\"\n[time]\ndt = 0.01\nsteps = 4\n[[disc]]\n\
             position = [0.0, 1e39]\nradius = 0.5\n[output]\ngsd_every = 1\n",
            ":10: output.gsd_every",
            "32-bit floats",
        ),
        (
            "substeps.toml",
            "[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n[time]\ndt = 0.01\nsteps = 4\n\
             max_travel = 0.01\n[[disc]]\nposition = [5.0, 5.0]\nradius = 0.5\n\
             velocity = [1e7, 0.0]\n",
            ":7: time.max_travel",
            "more than 10000 substeps",
        ),
    ] {
        let scenario = s.scenario(name, text);
        let (code, _, err) = output(bounce().arg("check").arg(&scenario));
        assert_eq!(code, 1, "{name}: {err}");
        assert!(err.contains(line) && err.contains(says), "{name}: {err}");
        let (code, _, err) = output(
            bounce()
                .arg("run")
                .arg(&scenario)
                .arg("--out")
                .arg(s.path(name))
                .arg("-q"),
        );
        assert_eq!(code, 1, "{name}: {err}");
        assert!(err.contains(line), "{name}: {err}");
    }
}
