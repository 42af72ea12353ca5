//! The fuzzer's generator, shared by the library's fuzz test (in process, many cases) and the
//! CLI's (whole `bounce run`s, checking exits and output files): scenario files mutated from
//! the shipped templates and from the schema's fields with extreme values, and checkpoints
//! forged field by field with a valid checksum. Deterministic: a seed gives the same cases.
#![allow(dead_code)]

/// A small deterministic generator (SplitMix64).
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Values that broke, or could break, an input path.
pub const EXTREMES: [&str; 24] = [
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "5e-324",
    "1e-300",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "9000000000000000000",
    "1e300",
    "1e20",
    "4.3e9",
    "0.0",
    "-0.0",
    "1000000000",
    "\"text\"",
    "[1e308, -1e308]",
    "[1e20, 1e20]",
    "[0.0, 0.0]",
    "[]",
    "{ min = [0.0, 0.0], max = [1e300, 1e-300] }",
];

/// The schema's fields, by table, that a mutation may add or overwrite.
pub const FIELDS: [(&str, &[&str]); 8] = [
    (
        "[world]",
        &[
            "min",
            "max",
            "wall_restitution",
            "gravity",
            "collision_radius_scale",
            "coefficient_of_restitution",
            "solver_iterations",
        ],
    ),
    ("[time]", &["dt", "steps", "substeps", "max_travel"]),
    (
        "[[gas]]",
        &[
            "count",
            "radius",
            "speed",
            "temperature",
            "uniform",
            "drift",
            "region",
        ],
    ),
    ("[[disc]]", &["position", "velocity", "radius", "mass"]),
    (
        "[[obstacle]]",
        &["radius", "segment", "peg", "force", "mass", "velocity"],
    ),
    (
        "[[emitter]]",
        &["rate", "radius", "velocity", "spread", "limit", "region"],
    ),
    ("[[sink]]", &["region"]),
    (
        "[output]",
        &[
            "stats_every",
            "frame_every",
            "frame_width",
            "gsd_every",
            "view",
        ],
    ),
];

/// The shipped scenarios with their generators made small (the cases must be fast).
pub fn seeds() -> Vec<(&'static str, String)> {
    bounce_scenario::TEMPLATES
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
pub fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return text.to_string();
    }
    let k = rng.below(lines.len());
    match rng.below(8) {
        // A value replaced by an extreme one.
        0 | 1 => {
            if let Some((key, _)) = lines[k].split_once('=') {
                lines[k] = format!("{key}= {}", rng.pick(&EXTREMES));
            }
        }
        // A field of the schema set to an extreme value in its table (added if absent, the
        // table added if the file has none).
        2 | 3 => {
            let (table, keys) = rng.pick(&FIELDS);
            let key = rng.pick(keys);
            let line = format!("{key} = {}", rng.pick(&EXTREMES));
            match lines.iter().position(|l| l.trim() == *table) {
                Some(at) => {
                    let end = lines[at + 1..]
                        .iter()
                        .position(|l| l.trim_start().starts_with('['))
                        .map_or(lines.len(), |e| at + 1 + e);
                    match lines[at + 1..end]
                        .iter()
                        .position(|l| l.split('=').next().unwrap_or("").trim() == *key)
                    {
                        Some(i) => lines[at + 1 + i] = line,
                        None => lines.insert(at + 1, line),
                    }
                }
                None => {
                    lines.push(table.to_string());
                    lines.push(line);
                }
            }
        }
        // A line dropped or doubled.
        4 => {
            lines.remove(k);
        }
        5 => {
            let line = lines[k].clone();
            lines.insert(k, line);
        }
        // A byte replaced by a printable character.
        6 => {
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

/// A scenario case: one or two mutations of a seed.
pub fn scenario_case(text: &str, rng: &mut Rng) -> String {
    let mut input = mutate(text, rng);
    if rng.below(3) == 0 {
        input = mutate(&input, rng);
    }
    input
}

/// A scenario with every kind of state (a moving piston, pegs, an emitter, a sink), for
/// checkpoints to forge.
pub const EVERY_KIND: &str = r#"
name = "every kind"
[world]
min = [0.0, 0.0]
max = [20.0, 20.0]
gravity = [0.0, -1.0]
[time]
dt = 0.02
steps = 40
[[gas]]
count = 20
radius = 0.4
speed = 1.0
[[obstacle]]
name = "piston"
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
[output]
stats_every = 1
frame_every = 0
gsd_every = 1
plots = false
"#;

/// The checkpoint header's length: the bytes before the payload.
pub const HEADER: usize = 18 + 4 + 8 + 8 + 8;

/// The little-endian words a forged field may hold: f64s from zero to the largest, NaN and
/// the infinities, and integers that are counts or ids gone wrong.
fn extreme_word(rng: &mut Rng) -> [u8; 8] {
    const F64S: [f64; 12] = [
        0.0,
        -0.0,
        -1.0,
        5e-324,
        1e-300,
        1e6,
        1e300,
        f64::MAX,
        -5.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    const U64S: [u64; 5] = [0, 1, u64::MAX, 1 << 40, 1 << 32];
    if rng.below(2) == 0 {
        rng.pick(&F64S).to_le_bytes()
    } else {
        rng.pick(&U64S).to_le_bytes()
    }
}

/// A checkpoint forged from `valid`: one to four edits (a field overwritten with an extreme
/// value, a byte changed, bytes cut or inserted), then, in seven cases of eight, the length
/// and checksum recomputed so the forgery reaches the decoder and the validation.
pub fn forge(valid: &[u8], case: u64, rng: &mut Rng) -> Vec<u8> {
    let mut bad = valid.to_vec();
    for _ in 0..1 + rng.below(4) {
        // Edits past the header need a byte past it (a cut may leave none).
        if bad.len() <= HEADER + 8 {
            break;
        }
        let at = HEADER + rng.below(bad.len() - HEADER - 8);
        match rng.below(6) {
            // A field: the payload is little-endian words, mostly f64s on 8-byte steps.
            0..=2 => {
                let aligned = HEADER + (at - HEADER) / 8 * 8;
                let at = if rng.below(2) == 0 { aligned } else { at };
                bad[at..at + 8].copy_from_slice(&extreme_word(rng));
            }
            3 => bad[at] ^= 1 << rng.below(8),
            4 => bad.truncate(at),
            _ => bad.insert(at, rng.next() as u8),
        }
    }
    if !case.is_multiple_of(8) && bad.len() >= HEADER {
        reseal(&mut bad);
    }
    bad
}

/// FNV-1a 64, the checkpoint's checksum.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for &b in bytes {
        hash = (hash ^ b as u64).wrapping_mul(0x0100_0000_01b3);
    }
    hash
}

/// Writes a valid length and checksum for the payload as it is.
pub fn reseal(bytes: &mut [u8]) {
    let payload_len = (bytes.len() - HEADER) as u64;
    let checksum = fnv1a(&bytes[HEADER..]);
    bytes[22..30].copy_from_slice(&payload_len.to_le_bytes());
    bytes[30..38].copy_from_slice(&checksum.to_le_bytes());
}

/// How many cases a fuzz test runs: `BOUNCE_FUZZ_CASES` (for the long runs before an issue
/// is resolved), or `default`.
pub fn cases(default: usize) -> usize {
    std::env::var("BOUNCE_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}
