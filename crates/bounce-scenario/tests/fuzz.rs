//! A bounded mutation fuzzer over the shipped scenarios and over checkpoint bytes: thousands
//! of cases in seconds, each must end (no hang) in a world or in an error with a message, and
//! nothing may panic. Deterministic: the same cases every run.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

use bounce_scenario::{Limits, Session, TEMPLATES, checkpoint};

/// A small deterministic generator (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Values that broke, or could break, an input path.
const EXTREMES: [&str; 16] = [
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "9000000000000000000",
    "1e300",
    "0.0",
    "1000000000",
    "\"text\"",
    "[1e308, -1e308]",
    "[]",
];

/// The shipped scenarios with their generators made small (the cases must be fast).
fn seeds() -> Vec<(&'static str, String)> {
    TEMPLATES
        .iter()
        .map(|(name, text)| {
            let small: Vec<String> = text
                .lines()
                .map(|l| {
                    let key = l.split('=').next().unwrap_or("").trim();
                    match key {
                        "count" => "count = 150".to_string(),
                        "counts" => "counts = [6, 6]".to_string(),
                        _ => l.to_string(),
                    }
                })
                .collect();
            (*name, small.join("\n"))
        })
        .collect()
}

/// One mutation of scenario text.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return text.to_string();
    }
    let k = rng.below(lines.len());
    match rng.below(6) {
        // A value replaced by an extreme one.
        0 | 1 => {
            if let Some((key, _)) = lines[k].split_once('=') {
                let value = EXTREMES[rng.below(EXTREMES.len())];
                lines[k] = format!("{key}= {value}");
            }
        }
        // A line dropped or doubled.
        2 => {
            lines.remove(k);
        }
        3 => {
            let line = lines[k].clone();
            lines.insert(k, line);
        }
        // A byte replaced by a printable character.
        4 => {
            let mut bytes = lines[k].clone().into_bytes();
            if !bytes.is_empty() {
                let at = rng.below(bytes.len());
                const CHARS: &[u8] = b" 0123456789.-+e[]=\"#abc_,";
                bytes[at] = CHARS[rng.below(CHARS.len())];
            }
            lines[k] = String::from_utf8_lossy(&bytes).into_owned();
        }
        // Two lines swapped.
        _ => {
            let j = rng.below(lines.len());
            lines.swap(k, j);
        }
    }
    lines.join("\n")
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
    for (name, text) in seeds() {
        for _ in 0..500 {
            let mut input = mutate(&text, &mut rng);
            if rng.below(3) == 0 {
                input = mutate(&input, &mut rng);
            }
            survive(name, &input, || {
                match Session::from_text_with(name, &input, &limits) {
                    Ok(mut session) => {
                        built += 1;
                        let _ = session.world.set_threads(2);
                        for _ in 0..3 {
                            if session.step().is_err() {
                                break;
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
        built > 300 && refused > 300,
        "{built} built, {refused} refused"
    );
}

/// FNV-1a 64, as the checkpoint's checksum: the fuzzer fixes it up after mutating so the
/// cases reach the decoder and the world's validation, not just the checksum.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for &b in bytes {
        hash = (hash ^ b as u64).wrapping_mul(0x0100_0000_01b3);
    }
    hash
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
    // And a world with every kind of state: a moving piston, pegs, an emitter, a sink.
    let text = r#"
[world]
min = [0.0, 0.0]
max = [20.0, 20.0]
gravity = [0.0, -1.0]
[time]
dt = 0.02
steps = 1
[[gas]]
count = 20
radius = 0.4
speed = 1.0
[[obstacle]]
segment = [[0.0, 15.0], [20.0, 15.0]]
force = [0.0, -5.0]
mass = 3.0
[[obstacle]]
pegs = { origin = [3.0, 3.0], rows = 2, columns = 4, spacing = [4.0, 4.0] }
radius = 0.5
[[emitter]]
region = { min = [1.0, 10.0], max = [19.0, 14.0] }
rate = 30.0
radius = 0.3
[[sink]]
region = { min = [0.0, 0.0], max = [20.0, 1.0] }
"#;
    let mut worlds = Session::from_text("works", text).unwrap();
    for _ in 0..40 {
        worlds.step().unwrap();
    }
    let works = checkpoint::encode(&worlds.world, None).unwrap();
    const HEADER: usize = 18 + 4 + 8 + 8 + 8;
    let mut rng = Rng(7);
    let (mut loaded, mut refused) = (0, 0);
    for case in 0..4000 {
        let mut bad = if case % 2 == 0 {
            plain.clone()
        } else {
            works.clone()
        };
        for _ in 0..1 + rng.below(4) {
            // Mutations past the header need a byte past it (a truncation may leave none).
            if bad.len() <= HEADER {
                break;
            }
            match rng.below(4) {
                0 => {
                    let at = rng.below(bad.len());
                    bad[at] = rng.next() as u8;
                }
                1 => {
                    let at = HEADER + rng.below(bad.len() - HEADER);
                    bad[at] ^= 1 << rng.below(8);
                }
                2 => {
                    let at = HEADER + rng.below(bad.len() - HEADER);
                    bad.truncate(at.max(HEADER));
                }
                _ => {
                    let at = HEADER + rng.below(bad.len() - HEADER);
                    bad.insert(at, rng.next() as u8);
                }
            }
        }
        // Most cases get a valid length and checksum, to reach the decoder.
        if case % 8 != 0 && bad.len() >= HEADER {
            let payload_len = (bad.len() - HEADER) as u64;
            let checksum = fnv1a(&bad[HEADER..]);
            bad[22..30].copy_from_slice(&payload_len.to_le_bytes());
            bad[30..38].copy_from_slice(&checksum.to_le_bytes());
        }
        let input = format!("case {case}");
        survive("decode", &input, || {
            match checkpoint::decode(&bad, "c.bin") {
                Ok(mut c) => {
                    loaded += 1;
                    for _ in 0..2 {
                        if c.world.step(0.01).is_err() {
                            break;
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
        refused > 1000 && loaded > 10,
        "{loaded} loaded, {refused} refused"
    );
}
