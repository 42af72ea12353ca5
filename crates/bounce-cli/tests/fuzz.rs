//! The project fuzzes itself, end to end: generated scenario files (the shipped templates
//! mutated, and the schema's fields set to extreme values) and forged checkpoints (fields
//! overwritten with extreme values under a valid checksum) each run through a whole
//! `bounce run` with every output on, and must
//! - exit with 0 or 1 (never a panic's 101, an abort or another signal), an exit of 1 with an
//!   `error:` message and no backtrace;
//! - end within a time bound;
//! - leave no NaN or infinity in any output (`stats.csv`, the GSD trajectory) and no
//!   temporary file;
//! - stay within the memory limit it was given (the children's peak resident size).
//!
//! A few hundred cases run in the tests; `BOUNCE_FUZZ_CASES=N` runs N of each kind (the long
//! runs before an issue is resolved), and the counts are printed.

mod common;

#[path = "../../bounce-scenario/tests/support/fuzzgen.rs"]
mod fuzzgen;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{Scratch, bounce, gsd_chunks};
use fuzzgen::{EVERY_KIND, Rng, cases, forge, scenario_case, seeds};

/// Steps each case runs (from its start, or past the checkpoint it resumes).
const STEPS: u64 = 4;
/// The memory limit given to each run, in GiB.
const MEMORY_GIB: f64 = 0.25;
/// The longest a case may take.
const TIME_LIMIT: Duration = Duration::from_secs(60);

/// What the cases did.
#[derive(Default)]
struct Tally {
    exits: BTreeMap<i32, usize>,
    slowest: (Duration, String),
}

impl Tally {
    fn report(&self, what: &str) {
        eprintln!(
            "{what}: {} cases, exits {:?}, slowest {:.2} s ({})",
            self.exits.values().sum::<usize>(),
            self.exits,
            self.slowest.0.as_secs_f64(),
            self.slowest.1
        );
    }
}

/// Runs one case's command and checks the process and its outputs; `input` says what was
/// run when it fails.
fn run_case(command: &mut Command, out: &Path, input: &str, tally: &mut Tally, label: &str) {
    let _ = std::fs::remove_dir_all(out);
    let start = Instant::now();
    let mut child = command
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > TIME_LIMIT {
            let _ = child.kill();
            panic!("still running after {TIME_LIMIT:?}:\n{input}");
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let took = start.elapsed();
    let done = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&done.stderr);
    let code = done.status.code().unwrap_or_else(|| {
        panic!("ended by {:?}: {stderr}\n{input}", done.status);
    });
    assert!(code == 0 || code == 1, "exit {code}: {stderr}\n{input}");
    assert!(
        !stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"),
        "a panic: {stderr}\n{input}"
    );
    if code == 1 {
        assert!(
            stderr.contains("error:"),
            "exit 1 without a message: {stderr}\n{input}"
        );
    }
    check_outputs(out, input);
    *tally.exits.entry(code).or_default() += 1;
    if took > tally.slowest.0 {
        tally.slowest = (took, label.to_string());
    }
}

/// No NaN or infinity in `stats.csv` or the trajectory, no temporary left.
fn check_outputs(out: &Path, input: &str) {
    let Ok(entries) = std::fs::read_dir(out) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with(".bounce-tmp"), "{name} left:\n{input}");
        let path = entry.path();
        if name == "stats.csv" {
            let text = std::fs::read_to_string(&path).unwrap();
            for (k, line) in text.lines().enumerate().skip(1) {
                for value in line.split(',').filter(|v| !v.is_empty()) {
                    let finite = value.parse::<f64>().is_ok_and(f64::is_finite);
                    assert!(finite, "stats.csv row {k}: {value}:\n{line}\n{input}");
                }
            }
        } else if name.ends_with(".gsd") {
            for chunk in gsd_chunks(&path) {
                let finite = match chunk.kind {
                    9 => chunk
                        .data
                        .chunks(4)
                        .all(|b| f32::from_le_bytes(b.try_into().unwrap()).is_finite()),
                    10 => chunk
                        .data
                        .chunks(8)
                        .all(|b| f64::from_le_bytes(b.try_into().unwrap()).is_finite()),
                    _ => true,
                };
                assert!(
                    finite,
                    "{name}: {} of frame {}:\n{input}",
                    chunk.name, chunk.frame
                );
            }
        }
    }
}

/// The largest resident size of any child so far, in bytes.
fn children_peak_bytes() -> u64 {
    // SAFETY: getrusage only writes the struct it is given.
    let usage = unsafe {
        let mut usage = std::mem::zeroed::<libc::rusage>();
        assert_eq!(libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage), 0);
        usage
    };
    usage.ru_maxrss as u64 * 1024
}

fn assert_within_memory() {
    // The limit is on what the world holds; the process adds its code, buffers and the frame.
    let peak = children_peak_bytes();
    let allowed = (MEMORY_GIB * 1.5 * (1u64 << 30) as f64) as u64;
    assert!(
        peak < allowed,
        "a run peaked at {peak} bytes, over {allowed}"
    );
}

/// `bounce run` into `out` until step `steps`.
fn args(out: &Path, steps: u64) -> Vec<String> {
    [
        "run",
        "--quiet",
        "--threads",
        "2",
        "--steps",
        &steps.to_string(),
        "--memory-limit",
        &MEMORY_GIB.to_string(),
        "--out",
        &out.display().to_string(),
    ]
    .map(String::from)
    .to_vec()
}

#[test]
fn generated_scenarios_end_cleanly_with_finite_outputs() {
    let s = Scratch::new();
    let mut rng = Rng(45);
    let mut tally = Tally::default();
    let seeds = seeds();
    let total = cases(200);
    for case in 0..total {
        let (name, text) = &seeds[case % seeds.len()];
        let input = scenario_case(text, &mut rng);
        let scenario = s.scenario("case.toml", &input);
        let out = s.path("out");
        let label = format!("scenario case {case} from {name}");
        run_case(
            bounce().args(args(&out, STEPS)).arg(&scenario),
            &out,
            &format!("{label}:\n{input}"),
            &mut tally,
            &label,
        );
    }
    tally.report("scenario fuzz");
    assert_within_memory();
    // Both ends are reached: runs that finish and inputs refused.
    assert!(tally.exits.get(&0).is_some_and(|&n| n > total / 10));
    assert!(tally.exits.get(&1).is_some_and(|&n| n > total / 10));
}

#[test]
fn forged_checkpoints_end_cleanly_with_finite_outputs() {
    let s = Scratch::new();
    let scenario = s.scenario("every.toml", EVERY_KIND);
    let base = s.path("base");
    let status = bounce()
        .args(args(&base, 20))
        .arg(&scenario)
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let valid = std::fs::read(base.join("checkpoint.bin")).unwrap();
    let mut rng = Rng(4545);
    let mut tally = Tally::default();
    let total = cases(100);
    for case in 0..total {
        let forged = forge(&valid, case as u64, &mut rng);
        let path = s.path("forged.bin");
        std::fs::write(&path, &forged).unwrap();
        let out = s.path("out");
        let label = format!("checkpoint case {case}");
        run_case(
            bounce()
                .args(args(&out, 20 + STEPS))
                .arg("--resume")
                .arg(&path)
                .arg(&scenario),
            &out,
            &label,
            &mut tally,
            &label,
        );
    }
    tally.report("checkpoint fuzz");
    assert_within_memory();
    assert!(tally.exits.get(&1).is_some_and(|&n| n > total / 4));
    assert!(tally.exits.get(&0).is_some_and(|&n| n > 0));
}
