//! A bounded mutation fuzzer over the shipped scenarios and over checkpoint bytes, in
//! process: thousands of cases in seconds, each must end (no hang) in a world or in an error
//! with a message, nothing may panic, and a world that steps keeps its statistics finite.
//! Deterministic: the same cases every run. `BOUNCE_FUZZ_CASES` sets the number of cases per
//! seed scenario (scenarios) and in all (checkpoints). The CLI's `tests/fuzz.rs` runs the same
//! generator through whole `bounce run`s.

#[path = "support/fuzzgen.rs"]
mod fuzzgen;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

use bounce_scenario::{Limits, Session, checkpoint};
use fuzzgen::{EVERY_KIND, Rng, cases, forge, scenario_case, seeds};

/// A step's statistics are all finite (what stats.csv is written from).
fn assert_finite(stats: &bounce::StepStats, input: &str) {
    let text = format!("{stats:?}");
    assert!(
        !text.contains("NaN") && !text.contains("inf"),
        "non-finite statistics {text} on:\n{input}"
    );
}

/// Runs `case`, failing on a panic (with `input`) or when it takes too long.
fn survive(what: &str, input: &str, case: impl FnOnce()) {
    let start = Instant::now();
    if catch_unwind(AssertUnwindSafe(case)).is_err() {
        panic!("{what} panicked on:\n{input}");
    }
    let took = start.elapsed();
    assert!(
        took < Duration::from_secs(10),
        "{what} took {took:?} on:\n{input}"
    );
}

#[test]
fn mutated_scenarios_never_panic_or_hang() {
    // Quiet the default hook: a caught panic still fails the test, with its input.
    let limits = Limits {
        memory_bytes: 64 << 20,
    };
    let mut rng = Rng(2026);
    let (mut built, mut refused) = (0, 0);
    let per_seed = cases(500);
    for (name, text) in seeds() {
        for _ in 0..per_seed {
            let input = scenario_case(&text, &mut rng);
            survive(name, &input, || {
                match Session::from_text_with(name, &input, &limits) {
                    Ok(mut session) => {
                        built += 1;
                        let _ = session.world.set_threads(2);
                        for _ in 0..3 {
                            match session.step() {
                                Ok(stats) => assert_finite(stats, &input),
                                Err(_) => break,
                            }
                        }
                    }
                    Err(e) => {
                        refused += 1;
                        let message = e.to_string();
                        assert!(
                            !message.trim().is_empty() && message.contains(name),
                            "a refusal without a message naming the file: {message:?}\n{input}"
                        );
                    }
                }
            });
        }
    }
    eprintln!("scenario fuzz: {built} built and stepped, {refused} refused");
    // Both paths are exercised.
    assert!(
        built > per_seed / 2 && refused > per_seed / 2,
        "{built} built, {refused} refused"
    );
}

#[test]
fn mutated_checkpoints_never_panic_or_allocate_wildly() {
    let mut session = Session::builtin("mixing").unwrap();
    for _ in 0..5 {
        session.step().unwrap();
    }
    // Fewer discs, so each case is quick.
    let text = session.text.replace("count = 1500", "count = 40");
    let mut session = Session::from_text("mixing", &text).unwrap();
    for _ in 0..3 {
        session.step().unwrap();
    }
    let plain = checkpoint::encode(&session.world, None).unwrap();
    // And a world with every kind of state.
    let mut worlds = Session::from_text("works", EVERY_KIND).unwrap();
    for _ in 0..40 {
        worlds.step().unwrap();
    }
    let works = checkpoint::encode(&worlds.world, None).unwrap();
    let mut rng = Rng(7);
    let (mut loaded, mut refused) = (0, 0);
    let total = cases(4000);
    for case in 0..total {
        let valid = if case % 2 == 0 { &plain } else { &works };
        let bad = forge(valid, case as u64, &mut rng);
        let input = format!("case {case}");
        survive("decode", &input, || {
            match checkpoint::decode(&bad, "c.bin") {
                Ok(mut c) => {
                    loaded += 1;
                    for _ in 0..2 {
                        match c.world.step(0.01) {
                            Ok(stats) => assert_finite(stats, &input),
                            Err(_) => break,
                        }
                    }
                }
                Err(e) => {
                    refused += 1;
                    assert!(e.starts_with("c.bin"), "{e}");
                }
            }
        });
    }
    eprintln!("checkpoint fuzz: {loaded} loaded and stepped, {refused} refused");
    assert!(
        refused > total / 4 && loaded > total / 400,
        "{loaded} loaded, {refused} refused"
    );
}
