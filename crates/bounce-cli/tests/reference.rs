//! The user guide's reference pages against the code they describe: every scenario key and
//! its allowed values against the file format's own parser, every output column against the
//! files a run writes, every command and flag against `--help`, and the compatibility table
//! against the refusals the code makes. A key, column, flag or refusal added or removed
//! without its page fails here.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use common::{Scratch, bounce, output};

fn page(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../docs/src/reference")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The cells of a Markdown table row (`| a | b \| c |` gives `a`, `b | c`).
fn cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|').trim_end_matches('|');
    let mut out = vec![String::new()];
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                out.last_mut().unwrap().push('|');
                chars.next();
            }
            '|' => out.push(String::new()),
            c => out.last_mut().unwrap().push(c),
        }
    }
    out.into_iter().map(|c| c.trim().to_string()).collect()
}

/// Each heading's tables: heading text → rows (header and separator left out).
fn tables(text: &str) -> BTreeMap<String, Vec<Vec<String>>> {
    let mut out: BTreeMap<String, Vec<Vec<String>>> = BTreeMap::new();
    let mut heading = String::new();
    let mut in_table = false;
    for line in text.lines() {
        if let Some(h) = line.strip_prefix('#') {
            heading = h.trim_start_matches('#').trim().to_string();
            in_table = false;
        } else if line.starts_with('|') {
            if !in_table {
                in_table = true; // the header row
                continue;
            }
            if line.starts_with("|---") {
                continue;
            }
            out.entry(heading.clone()).or_default().push(cells(line));
        } else {
            in_table = false;
        }
    }
    out
}

/// The names in backticks in a cell: "`force_NAME_x`, `force_NAME_y`" gives both.
fn code_spans(cell: &str) -> Vec<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The names serde lists after "expected" in an unknown-field or unknown-variant error.
fn expected_names(message: &str) -> BTreeSet<String> {
    let (_, after) = message
        .split_once("expected")
        .unwrap_or_else(|| panic!("no list of names in: {message}"));
    let list = after.lines().next().unwrap_or("");
    code_spans(list).into_iter().collect()
}

/// What the scenario parser says of `probe`.
fn parse_error(probe: &str) -> String {
    match toml::from_str::<bounce_scenario::Scenario>(probe) {
        Ok(_) => panic!("the probe parsed: {probe}"),
        Err(e) => e.to_string(),
    }
}

/// Each section of the scenario page, and the TOML that puts `KEY = VALUE` in its table.
const SCENARIO_SECTIONS: [(&str, &str); 18] = [
    ("Top level", "KEY = VALUE\n"),
    ("`[world]`", "[world]\nKEY = VALUE\n"),
    (
        "`world.thermostat`",
        "[world]\nthermostat = { KEY = VALUE }\n",
    ),
    ("`[time]`", "[time]\nKEY = VALUE\n"),
    ("`[[gas]]`", "[[gas]]\nKEY = VALUE\n"),
    ("`region`", "[[gas]]\nregion = { KEY = VALUE }\n"),
    ("`[[lattice]]`", "[[lattice]]\nKEY = VALUE\n"),
    ("`[[block]]`", "[[block]]\nKEY = VALUE\n"),
    ("`[[disc]]`", "[[disc]]\nKEY = VALUE\n"),
    ("`[[file]]`", "[[file]]\nKEY = VALUE\n"),
    ("`[[obstacle]]`", "[[obstacle]]\nKEY = VALUE\n"),
    ("`box`", "[[obstacle]]\nbox = { KEY = VALUE }\n"),
    ("`pegs`", "[[obstacle]]\npegs = { KEY = VALUE }\n"),
    ("`[[emitter]]`", "[[emitter]]\nKEY = VALUE\n"),
    ("`[[sink]]`", "[[sink]]\nKEY = VALUE\n"),
    ("`[[sensor]]`", "[[sensor]]\nKEY = VALUE\n"),
    ("`sensor.region`", "[[sensor]]\nregion = { KEY = VALUE }\n"),
    ("`[output]`", "[output]\nKEY = VALUE\n"),
];

#[test]
fn the_scenario_page_lists_every_key_of_every_table_and_every_allowed_value() {
    let text = page("scenario.md");
    let mut sections = tables(&text);
    sections.remove("A whole file");
    let mut probes: BTreeMap<&str, &str> = SCENARIO_SECTIONS.into_iter().collect();
    probes.insert("`output.profile`", "[output]\nprofile = { KEY = VALUE }\n");
    let documented: BTreeSet<&str> = sections.keys().map(String::as_str).collect();
    let probed: BTreeSet<&str> = probes.keys().copied().collect();
    assert_eq!(
        documented, probed,
        "the page's sections against the tables this test knows"
    );
    let mut values_checked = 0;
    for (section, rows) in &sections {
        let probe = probes[section.as_str()];
        let keys: BTreeSet<String> = rows
            .iter()
            .map(|r| r[0].trim_matches('`').to_string())
            .collect();
        let unknown = probe.replace("KEY", "zzz_unknown").replace("VALUE", "1");
        let format = expected_names(&parse_error(&unknown));
        assert_eq!(
            keys, format,
            "{section}: the page's keys against the format's"
        );
        // Keys whose values are a list of names: the page's list against the format's.
        for row in rows {
            let allowed: BTreeSet<String> = code_spans(&row[1])
                .into_iter()
                .filter(|v| v.starts_with('"'))
                .map(|v| v.trim_matches('"').to_string())
                .collect();
            if allowed.is_empty() || !row[1].contains("\\|") && !row[1].contains('|') {
                continue;
            }
            let key = row[0].trim_matches('`');
            let bad = probe
                .replace("KEY", key)
                .replace("VALUE", "\"zzz_unknown\"");
            let format = expected_names(&parse_error(&bad));
            assert_eq!(
                allowed, format,
                "{section} {key}: the page's values against the format's"
            );
            values_checked += 1;
        }
    }
    assert!(
        values_checked >= 9,
        "only {values_checked} keys with named values were checked"
    );
}

/// A run with every output switch on, into `scratch/run`.
fn run_everything(scratch: &Scratch) -> PathBuf {
    let scenario = scratch.scenario(
        "everything.toml",
        r#"
[world]
min = [0.0, 0.0]
max = [20.0, 20.0]
friction = 0.3
thermostat = { kind = "rescale", temperature = 1.0, rate = 1.0 }

[time]
dt = 0.01
steps = 20

[[gas]]
count = 60
radius = 0.4
temperature = 1.0
region = { min = [0.0, 0.0], max = [20.0, 15.0] }
tag = 3

[[obstacle]]
segment = [[2.0, 17.0], [18.0, 17.0]]
velocity = [0.0, -0.1]
name = "piston"

[[sensor]]
name = "left"
region = { min = [0.0, 0.0], max = [10.0, 20.0] }

[output]
stats_every = 5
gsd_every = 10
frame_every = 0
plots = false
events = true
profile = { axis = "y", bins = 4 }
msd = true
pressure_tensor = true
collision_counts = true
dissipation = true
headline = "maxwell_boltzmann"
"#,
    );
    let out = scratch.path("run");
    let (code, _, err) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(&out)
            .arg("-q"),
    );
    assert_eq!(code, 0, "{err}");
    out
}

fn header(path: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect()
}

/// The columns a table documents, with `NAME` filled in from `names`.
fn documented_columns(rows: &[Vec<String>], names: &[&str]) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for row in rows {
        for column in code_spans(&row[0]) {
            if column.contains("NAME") {
                out.extend(names.iter().map(|n| column.replace("NAME", n)));
            } else {
                out.insert(column);
            }
        }
    }
    out
}

#[test]
fn the_outputs_page_lists_every_column_a_run_writes() {
    let text = page("outputs.md");
    let sections = tables(&text);
    let scratch = Scratch::new();
    let out = run_everything(&scratch);
    // Each documented CSV against the run's header; NAME is the obstacle's or sensor's.
    let stats = &sections["`stats.csv`"];
    let mut documented = BTreeSet::new();
    for row in stats {
        let names: &[&str] = if row[0].contains("sensor_NAME") {
            &["left"]
        } else {
            &["piston"]
        };
        documented.extend(documented_columns(std::slice::from_ref(row), names));
    }
    assert_eq!(documented, header(&out.join("stats.csv")), "stats.csv");
    for (section, file) in [
        ("`events.csv`", "events.csv"),
        ("`profile.csv`", "profile.csv"),
        ("`msd.csv`", "msd.csv"),
        ("`collisions.csv`", "collisions.csv"),
    ] {
        let documented = documented_columns(&sections[section], &[]);
        assert_eq!(documented, header(&out.join(file)), "{file}");
    }
    // Every file the page's first table names (frames and GIF apart, which this run turns
    // off) is there, and nothing else is.
    let mut listed = BTreeSet::new();
    for row in &sections["Output files"] {
        for name in code_spans(&row[0]) {
            listed.insert(name);
        }
    }
    let written: BTreeSet<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    for name in &written {
        assert!(
            listed.contains(name),
            "{name} is written but not on the page"
        );
    }
    for name in &listed {
        let off = name.starts_with("frames/") || name == "animation.gif" || name == "plots.png";
        assert!(
            off || written.contains(name),
            "{name} is on the page but this run wrote none"
        );
    }
    // summary.json's keys, against the page's.
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let keys: BTreeSet<String> = json
        .lines()
        .filter_map(|l| {
            l.trim()
                .strip_prefix('"')?
                .split_once("\":")
                .map(|(k, _)| k.to_string())
        })
        .collect();
    let documented: BTreeSet<String> = sections["`summary.json`"]
        .iter()
        .filter_map(|r| code_spans(&r[0]).into_iter().next())
        .collect();
    assert!(
        documented.is_superset(&keys) && keys.len() >= 8,
        "summary.json's keys {keys:?} against {documented:?}"
    );
    // What `bounce analyze` writes, against its files.
    let analysis = scratch.path("analysis");
    let (code, _, err) = output(
        bounce()
            .arg("analyze")
            .arg(out.join("trajectory.gsd"))
            .arg("--out")
            .arg(&analysis),
    );
    assert_eq!(code, 0, "{err}");
    for row in &sections["What `bounce analyze` writes"] {
        let csv = code_spans(&row[0])
            .into_iter()
            .find(|f| f.ends_with(".csv"))
            .unwrap();
        let columns: BTreeSet<String> = code_spans(&row[1]).into_iter().collect();
        assert_eq!(columns, header(&analysis.join(&csv)), "{csv}");
    }
}

/// The long flags `--help` lists for `args`, without --help and --version. Clap writes an
/// option's line as `      --out <OUT>  ...` or `  -q, --quiet  ...`.
fn help_flags(args: &[&str]) -> BTreeSet<String> {
    let (code, help, err) = output(bounce().args(args).arg("--help"));
    assert_eq!(code, 0, "{err}");
    // Option lines are indented a few spaces; a wrapped description's lines many more.
    let indent = |l: &str| l.len() - l.trim_start().len();
    help.lines()
        .filter(|l| indent(l) <= 10)
        .map(str::trim_start)
        .filter(|l| l.starts_with('-'))
        .filter_map(|l| l.split_whitespace().take(2).find(|w| w.starts_with("--")))
        .map(|w| w.trim_end_matches(',').to_string())
        .filter(|f| f != "--help" && f != "--version")
        .collect()
}

#[test]
fn the_command_page_lists_every_command_and_flag_that_help_does() {
    let text = page("cli.md");
    let sections = tables(&text);
    // The commands, against the top-level help's list.
    let (code, help, _) = output(bounce().arg("--help"));
    assert_eq!(code, 0);
    let commands: BTreeSet<String> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        // A command's line is indented two spaces; its wrapped description's lines more.
        .filter(|l| !l[2..].starts_with(' '))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect();
    let listed: BTreeSet<String> = sections["The `bounce` command"]
        .iter()
        .map(|row| {
            code_spans(&row[0])[0]
                .trim_start_matches("bounce ")
                .to_string()
        })
        .collect();
    assert_eq!(
        listed, commands,
        "the page's commands against `bounce --help`"
    );
    for command in &commands {
        let section = format!("`bounce {command}`");
        let rows = sections.get(&section).map(Vec::as_slice).unwrap_or(&[]);
        let documented: BTreeSet<String> = rows
            .iter()
            .map(|row| {
                code_spans(&row[0])[0]
                    .split(' ')
                    .next()
                    .unwrap()
                    .to_string()
            })
            .collect();
        assert_eq!(
            documented,
            help_flags(&[command]),
            "{section}'s flags against its --help"
        );
    }
}

/// What one row of the compatibility table adds to the base scenario: keys for `[world]`,
/// `[time]` and `[output]`, and whole tables after them.
struct Option_ {
    world: &'static str,
    time: &'static str,
    output: &'static str,
    tables: &'static str,
}

const fn opt(
    world: &'static str,
    time: &'static str,
    output: &'static str,
    tables: &'static str,
) -> Option_ {
    Option_ {
        world,
        time,
        output,
        tables,
    }
}

fn compatibility_rows() -> BTreeMap<&'static str, Option_> {
    BTreeMap::from([
        ("`time.substeps = 4`", opt("", "substeps = 4", "", "")),
        ("`time.max_travel`", opt("", "max_travel = 0.5", "", "")),
        (
            "`world.solver_iterations = 4`",
            opt("solver_iterations = 4", "", "", ""),
        ),
        (
            "`world.resting_contacts = \"rest\"`",
            opt(
                "resting_contacts = \"rest\"\ngravity = [0.0, -1.0]",
                "",
                "",
                "",
            ),
        ),
        ("`world.gravity`", opt("gravity = [0.0, -1.0]", "", "", "")),
        (
            "`world.friction` (rough discs)",
            opt("friction = 0.5", "", "", ""),
        ),
        (
            "`world.thermostat`",
            opt(
                "thermostat = { kind = \"rescale\", temperature = 1.0, rate = 1.0 }",
                "",
                "",
                "",
            ),
        ),
        (
            "a fixed `[[obstacle]]`",
            opt(
                "",
                "",
                "",
                "[[obstacle]]\npeg = [15.0, 15.0]\nradius = 0.5\n",
            ),
        ),
        (
            "a moving `[[obstacle]]`",
            opt(
                "",
                "",
                "",
                "[[obstacle]]\nsegment = [[12.0, 12.0], [18.0, 12.0]]\nvelocity = [0.0, 0.1]\n",
            ),
        ),
        (
            "`[[emitter]]`",
            opt(
                "",
                "",
                "",
                "[[emitter]]\nregion = { min = [12.0, 14.0], max = [18.0, 18.0] }\nrate = 1.0\nradius = 0.3\n",
            ),
        ),
        (
            "`[[sink]]`",
            opt(
                "",
                "",
                "",
                "[[sink]]\nregion = { min = [12.0, 2.0], max = [18.0, 6.0] }\n",
            ),
        ),
        (
            "`[[sensor]]`",
            opt(
                "",
                "",
                "",
                "[[sensor]]\nname = \"s\"\nregion = { min = [12.0, 2.0], max = [18.0, 6.0] }\n",
            ),
        ),
        ("`output.events`", opt("", "", "events = true", "")),
        (
            "`output.pressure_tensor`",
            opt("", "", "pressure_tensor = true", ""),
        ),
        (
            "`output.collision_counts`",
            opt("", "", "collision_counts = true", ""),
        ),
        (
            "`output.profile`",
            opt("", "", "profile = { axis = \"y\", bins = 4 }", ""),
        ),
        ("`output.msd`", opt("", "", "msd = true", "")),
        (
            "`output.dissipation`",
            opt("", "", "dissipation = true", ""),
        ),
        (
            "`time.method = \"event_driven\"`",
            opt("", "method = \"event_driven\"", "", ""),
        ),
    ])
}

/// The base scenario as one column has it, with `option` added.
fn compatibility_scenario(column: &str, option: &Option_) -> String {
    let (boundary, method) = match column {
        "event-driven" => ("boundary = \"walls\"", "method = \"event_driven\""),
        "periodic" => ("boundary = \"periodic\"", ""),
        "Lees–Edwards" => ("boundary = \"lees_edwards\"\nshear_rate = 0.1", ""),
        "open" => ("boundary = \"open\"", ""),
        "MPI" => ("boundary = \"walls\"", ""),
        other => panic!("a column this test does not know: {other}"),
    };
    let bounds = if column == "open" {
        ""
    } else {
        "min = [0.0, 0.0]\nmax = [20.0, 20.0]"
    };
    // A method the option itself sets is not set twice.
    let method = if option.time.contains("method") {
        ""
    } else {
        method
    };
    format!(
        "[world]\n{boundary}\n{bounds}\n{}\n\n[time]\ndt = 0.01\nsteps = 5\n{method}\n{}\n\n\
         [[gas]]\ncount = 20\nradius = 0.4\ntemperature = 1.0\n\
         region = {{ min = [1.0, 1.0], max = [10.0, 10.0] }}\n\n{}\n[output]\n{}\n",
        option.world, option.time, option.tables, option.output
    )
}

#[test]
fn the_compatibility_table_says_what_the_code_refuses() {
    let text = page("compatibility.md");
    let (header, rows) = {
        let line = text.lines().find(|l| l.starts_with("| option |")).unwrap();
        let table = &tables(&text)["Options × method, boundary and MPI"];
        (cells(line), table.clone())
    };
    let known = compatibility_rows();
    let documented: BTreeSet<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(
        documented,
        known.keys().copied().collect(),
        "the table's rows against this test's"
    );
    let (mut checked, mut wrong) = (0, Vec::new());
    for row in &rows {
        let option = &known[row[0].as_str()];
        for (column, cell) in header.iter().zip(row).skip(1) {
            let expect_runs = match cell.as_str() {
                "✓" => true,
                "✗" => false,
                "–" => continue,
                other => panic!("{}, {column}: a cell of ✓, ✗ or –, not {other}", row[0]),
            };
            let text = compatibility_scenario(column, option);
            let refusal = match bounce_scenario::Session::from_text("compat.toml", &text) {
                Err(e) => Some(e.to_string()),
                Ok(session) if column == "MPI" => {
                    bounce_scenario::support::across_ranks_unsupported(session.world.config())
                        .map(str::to_string)
                }
                Ok(_) => None,
            };
            if refusal.is_none() != expect_runs {
                wrong.push(format!(
                    "{} / {column}: the page says {cell}, the code {refusal:?}",
                    row[0]
                ));
            }
            checked += 1;
        }
    }
    assert!(
        wrong.is_empty(),
        "cells the code contradicts:\n{}",
        wrong.join("\n")
    );
    assert!(checked >= 90, "only {checked} cells were checked");
}
