//! `mpirun -np R bounce run`: the same bits as one process for R = 1..4, checkpoints that
//! resume with any R, domains cut by count, and failures that end the whole job.
//!
//! Needs Open MPI's `mpirun` (`scripts/test` installs it and turns on the feature `mpi`).
//! Every `mpirun` runs under `timeout`, so a hang fails the test instead of stalling it.
#![cfg(feature = "mpi")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BOUNCE: &str = env!("CARGO_BIN_EXE_bounce");

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

/// Outputs that are compared: no pictures (their time is the same with any R, their
/// drawing is tested elsewhere).
const QUIET_OUTPUTS: [&str; 6] = [
    "--set",
    "output.frame_every=0",
    "--set",
    "output.gif=false",
    "--set",
    "output.plots=false",
];

/// `bounce run` (with `ranks`, under `mpirun`) into `out`, with extra arguments.
fn run(ranks: Option<usize>, scenario: &str, out: &Path, extra: &[&str]) -> Output {
    let mut command = match ranks {
        Some(r) => {
            let mut c = Command::new("timeout");
            c.args(["300", "mpirun", "-np", &r.to_string(), BOUNCE]);
            c
        }
        None => Command::new(BOUNCE),
    };
    command
        .arg("run")
        .arg(scenarios().join(scenario))
        .arg("--out")
        .arg(out)
        .args(["-q", "--threads", "1"])
        .args(QUIET_OUTPUTS)
        .args(extra)
        // Open MPI refuses root without these, and more ranks than cores without the last.
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .output()
        .expect("bounce runs")
}

fn ok(output: Output, what: &str) -> String {
    let text = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{what} failed: {}\n{text}",
        String::from_utf8_lossy(&output.stderr)
    );
    text
}

/// The state hash `bounce run` prints.
fn hash(stdout: &str) -> String {
    let at = stdout.find("state hash ").expect("a state hash") + "state hash ".len();
    stdout[at..at + 16].to_string()
}

/// The `mpi:` line's discs owned per rank and ghosts per rank.
fn shares(stdout: &str) -> (Vec<u64>, Vec<u64>) {
    let list = |key: &str| -> Vec<u64> {
        let at = stdout.find(key).expect(key) + key.len();
        let end = stdout[at..].find(']').unwrap() + at;
        stdout[at..end]
            .split(',')
            .map(|v| v.trim().parse().unwrap())
            .collect()
    };
    (list("owned per rank ["), list("ghosts ["))
}

fn same_files(a: &Path, b: &Path, what: &str) {
    for file in ["stats.csv", "trajectory.gsd"] {
        let (x, y) = (
            std::fs::read(a.join(file)).unwrap(),
            std::fs::read(b.join(file)).unwrap(),
        );
        assert!(x == y, "{what}: {file} differs from one process's");
    }
}

/// One process, then R = 1..4 ranks: the same `stats.csv`, GSD and state hash; returns the
/// 4-rank run's shares.
fn same_bits_for_1_to_4_ranks(scenario: &str, extra: &[&str], what: &str) -> (Vec<u64>, Vec<u64>) {
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one");
    let reference = hash(&ok(run(None, scenario, &one, extra), what));
    let mut last = None;
    for ranks in 1..=4 {
        let out = dir.path().join(format!("r{ranks}"));
        let stdout = ok(run(Some(ranks), scenario, &out, extra), what);
        assert_eq!(
            hash(&stdout),
            reference,
            "{what}: state hash with {ranks} ranks"
        );
        same_files(&one, &out, &format!("{what}, {ranks} ranks"));
        last = Some(shares(&stdout));
    }
    last.unwrap()
}

/// A pile of 4,000 discs 300 high with one substep: domains with real ghost layers.
const TALL_PILE: [&str; 5] = [
    "time.steps=300",
    "time.substeps=1",
    "gas.count=4000",
    "world.max=[80.0, 300.0]",
    "gas.region={ min = [0.0, 20.0], max = [80.0, 300.0] }",
];

/// `--set VALUE` for each value.
fn sets(values: &[&'static str]) -> Vec<&'static str> {
    values.iter().flat_map(|v| ["--set", v]).collect()
}

/// Every rank holds ghosts, and none holds every disc: real layers, not copies.
fn assert_holds_layers(owned: &[u64], ghosts: &[u64], total: u64) {
    for (o, g) in owned.iter().zip(ghosts) {
        assert!(
            *g > 0 && o + g < total,
            "owned {owned:?}, ghosts {ghosts:?}"
        );
    }
}

#[test]
fn a_gas_in_walls_gives_the_same_bits_on_any_number_of_ranks() {
    // 6,000 discs of radii 0.3-0.9 in a 200 x 200 box: domains of 100 x 100 (4 ranks) with ghost layers
    // narrower than them, so discs really are owned, copied and handed over.
    let (owned, ghosts) = same_bits_for_1_to_4_ranks(
        "gas.toml",
        &sets(&[
            "time.steps=150",
            "gas.count=6000",
            "world.max=[200.0, 200.0]",
            "gas.radius=[0.3, 0.9]",
            "output.stats_every=5",
            "output.gsd_every=25",
        ]),
        "gas in walls",
    );
    assert_eq!(owned.iter().sum::<u64>(), 6000);
    assert_holds_layers(&owned, &ghosts, 6000);
}

#[test]
fn a_periodic_gas_gives_the_same_bits_on_any_number_of_ranks() {
    // Ghosts across the periodic edges: the first and last rows and columns are neighbours.
    let (owned, ghosts) = same_bits_for_1_to_4_ranks(
        "gas.toml",
        &sets(&[
            "world.boundary=periodic",
            "time.steps=150",
            "gas.count=6000",
            "world.max=[200.0, 200.0]",
            "gas.radius=[0.3, 0.9]",
            "output.gsd_every=25",
        ]),
        "periodic gas",
    );
    assert_eq!(owned.iter().sum::<u64>(), 6000);
    assert_holds_layers(&owned, &ghosts, 6000);
}

#[test]
fn a_sheared_gas_gives_the_same_bits_on_any_number_of_ranks() {
    // A Lees–Edwards box, cut in rows: ghosts across the top and bottom come from the whole
    // width, slid by the offset; discs through the top come back slid at the bottom.
    let (owned, ghosts) = same_bits_for_1_to_4_ranks(
        "gas.toml",
        &sets(&[
            "world.boundary=\"lees_edwards\"",
            "world.shear_rate=0.05",
            "time.steps=150",
            "gas.count=6000",
            "world.max=[200.0, 200.0]",
            "gas.radius=[0.3, 0.9]",
            "gas.streaming=true",
            "output.gsd_every=25",
        ]),
        "sheared gas",
    );
    assert_eq!(owned.iter().sum::<u64>(), 6000);
    assert_holds_layers(&owned, &ghosts, 6000);
}

#[test]
fn a_settling_pile_gives_the_same_bits_on_any_number_of_ranks() {
    // The shipped pile (4 substeps: every rank's ghost layer spans the box) and a tall one
    // with one substep whose domains have real ghost layers, through the fall and the
    // settling; and with three solver passes (contacts lowest first, walls as contacts).
    same_bits_for_1_to_4_ranks("pile.toml", &sets(&["time.steps=300"]), "pile");
    let (owned, ghosts) = same_bits_for_1_to_4_ranks("pile.toml", &sets(&TALL_PILE), "tall pile");
    assert_holds_layers(&owned, &ghosts, 4000);
    same_bits_for_1_to_4_ranks(
        "pile.toml",
        &sets(&[
            "time.steps=120",
            "world.solver_iterations=3",
            "world.restitution_model=relative_normal_velocity",
        ]),
        "pile with three passes",
    );
}

#[test]
fn rough_discs_give_the_same_bits_on_any_number_of_ranks() {
    // A tall pile of rough discs (friction at the discs and the walls, rolling resistance)
    // with real ghost layers, and a spinning periodic gas: the ghosts' spins, the records'
    // orientations and the friction work cross the ranks.
    let rough = [
        "world.friction=0.5",
        "world.rolling_resistance=0.05",
        "output.gsd_every=50",
    ];
    let (owned, ghosts) = same_bits_for_1_to_4_ranks(
        "pile.toml",
        &sets(&[&TALL_PILE[..], &rough].concat()),
        "rough pile",
    );
    assert_holds_layers(&owned, &ghosts, 4000);
    same_bits_for_1_to_4_ranks(
        "gas.toml",
        &sets(&[
            "world.boundary=periodic",
            "time.steps=100",
            "gas.count=3000",
            "world.max=[150.0, 150.0]",
            "gas.spin=5.0",
            "world.friction=0.3",
            "world.tangential_restitution=0.5",
            "output.gsd_every=25",
        ]),
        "rough periodic gas",
    );
}

#[test]
fn an_open_world_and_adaptive_substeps_give_the_same_bits() {
    same_bits_for_1_to_4_ranks(
        "gas.toml",
        &sets(&[
            "world.boundary=open",
            "time.steps=150",
            "gas.region={ min = [0.0, 0.0], max = [150.0, 150.0] }",
            "time.max_travel=0.02",
        ]),
        "open world with max_travel",
    );
}

#[test]
fn checkpoints_resume_with_any_number_of_ranks_or_none() {
    // Rough spinning discs: the checkpoint carries their spins, orientations and the
    // friction work.
    let extra = sets(&[
        "time.steps=200",
        "gas.count=6000",
        "world.max=[200.0, 200.0]",
        "output.gsd_every=20",
        "world.friction=0.3",
        "gas.spin=2.0",
    ]);
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one");
    ok(run(None, "gas.toml", &one, &extra), "one process");
    // (first part's ranks, steps, second part's ranks)
    for (first, steps, second) in [
        (Some(2), "90", Some(3)),
        (Some(4), "110", None),
        (None, "70", Some(2)),
    ] {
        let out = dir.path().join(format!("{first:?}-{second:?}"));
        let mut part = extra.to_vec();
        part.extend(["--steps", steps]);
        ok(run(first, "gas.toml", &out, &part), "first part");
        let checkpoint = out.join("checkpoint.bin");
        let mut rest = extra.to_vec();
        rest.extend(["--resume", checkpoint.to_str().unwrap()]);
        ok(run(second, "gas.toml", &out, &rest), "resumed part");
        same_files(&one, &out, &format!("{first:?} ranks then {second:?}"));
    }
}

#[test]
fn domains_are_cut_by_count_where_the_discs_are() {
    // All 6,000 discs start in the bottom fifth of the box: domains of equal size would
    // give them all to the bottom row (ranks 0 and 1).
    let dir = tempfile::tempdir().unwrap();
    let stdout = ok(
        run(
            Some(4),
            "gas.toml",
            &dir.path().join("out"),
            &sets(&[
                "time.steps=20",
                "gas.count=6000",
                "world.max=[200.0, 200.0]",
                "gas.region={ min = [0.0, 0.0], max = [200.0, 40.0] }",
                "gas.radius=0.3",
            ]),
        ),
        "bottom-heavy gas",
    );
    let (owned, _) = shares(&stdout);
    for &n in &owned {
        assert!(
            (1350..=1650).contains(&n),
            "each rank owns about 1,500: {owned:?}"
        );
    }
}

#[test]
fn a_bad_scenario_is_reported_once_and_every_rank_exits() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(
        Some(3),
        "gas.toml",
        &dir.path().join("out"),
        &sets(&["world.coefficient_of_restitution=-1"]),
    );
    assert!(!out.status.success());
    assert_ne!(out.status.code(), Some(124), "not a hang (timeout)");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        stderr.matches("coefficient_of_restitution").count(),
        1,
        "{stderr}"
    );
}

#[test]
fn events_csv_is_one_processs_on_any_number_of_ranks_and_after_a_resume() {
    // The 6,000-disc gas of the walls test: pairs across the domains' edges, discs handed
    // over, walls on every side.
    let dir = tempfile::tempdir().unwrap();
    let settings = [
        "time.steps=60",
        "gas.count=6000",
        "world.max=[200.0, 200.0]",
        "gas.radius=[0.3, 0.9]",
        "output.events=true",
    ];
    let events = |ranks: Option<usize>, out: &str, extra: &[&str]| {
        let mut args = sets(&settings);
        args.extend_from_slice(extra);
        ok(run(ranks, "gas.toml", &dir.path().join(out), &args), out);
        std::fs::read(dir.path().join(out).join("events.csv")).unwrap()
    };
    let one = events(None, "one", &[]);
    assert!(one.len() > 100_000, "{} bytes of events", one.len());
    for r in 1..=3 {
        let name = format!("ranks{r}");
        assert!(
            events(Some(r), &name, &[]) == one,
            "{r} ranks: events.csv differs"
        );
    }
    // Stopped at step 25 on three ranks, resumed on two.
    events(Some(3), "resumed", &["--steps", "25"]);
    let checkpoint = dir.path().join("resumed/checkpoint.bin");
    let resumed = events(
        Some(2),
        "resumed",
        &["--resume", checkpoint.to_str().unwrap()],
    );
    assert!(resumed == one, "a resumed events.csv differs");
}

#[test]
fn a_panic_on_one_rank_aborts_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let mut command = Command::new("timeout");
    command
        .args(["120", "mpirun", "-np", "3", BOUNCE, "run"])
        .arg(scenarios().join("gas.toml"))
        .arg("--out")
        .arg(dir.path().join("out"))
        .args(["-q", "--set", "time.steps=400"])
        .env("BOUNCE_MPI_PANIC_AT", "1:5")
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1");
    let out = command.output().unwrap();
    assert!(!out.status.success());
    assert_ne!(out.status.code(), Some(124), "not a hang (timeout)");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("rank 1 panicked"), "{stderr}");
    // Nothing half-written: no stats.csv (it is renamed into place only at the end).
    assert!(!dir.path().join("out/stats.csv").exists());
}

#[test]
fn a_signal_stops_every_rank_with_its_outputs_and_a_checkpoint_that_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let extra = sets(&[
        "gas.count=20000",
        "world.max=[300.0, 300.0]",
        "time.steps=1000000",
        "output.gsd_every=20",
    ]);
    let child = Command::new("mpirun")
        .args(["-np", "2", BOUNCE, "run"])
        .arg(scenarios().join("gas.toml"))
        .arg("--out")
        .arg(&out)
        .args(["-q", "--threads", "1"])
        .args(QUIET_OUTPUTS)
        .args(&extra)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .stderr(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Once the run has started writing (its output folder has files), and a moment more.
    let started = std::time::Instant::now();
    while std::fs::read_dir(&out).map_or(true, |mut d| d.next().is_none())
        && started.elapsed().as_secs() < 120
    {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    std::thread::sleep(std::time::Duration::from_secs(2));
    // SIGTERM to mpirun, which forwards it to the ranks.
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    let at = stderr
        .find("interrupted by signal 15 at step ")
        .unwrap_or_else(|| panic!("a stop message: {stderr}"))
        + "interrupted by signal 15 at step ".len();
    let stopped: u64 = stderr[at..].split(' ').next().unwrap().parse().unwrap();
    assert!(stopped > 0);
    // Resumed on 3 ranks to 30 steps past the stop: one process's run to there, byte for
    // byte.
    let target = (stopped + 30).to_string();
    let checkpoint = out.join("checkpoint.bin");
    let mut rest = extra.clone();
    rest.extend(["--steps", &target, "--resume", checkpoint.to_str().unwrap()]);
    ok(run(Some(3), "gas.toml", &out, &rest), "resumed");
    let one = dir.path().join("one");
    let mut whole = extra.clone();
    whole.extend(["--steps", &target]);
    ok(run(None, "gas.toml", &one, &whole), "one process");
    same_files(&one, &out, "stopped by a signal and resumed");
}

#[test]
fn what_ranks_cannot_share_yet_is_refused_with_its_name() {
    let dir = tempfile::tempdir().unwrap();
    for (sets, name) in [
        (
            &["world.thermostat={ kind = \"rescale\", temperature = 1.0, rate = 1.0 }"][..],
            "world.thermostat",
        ),
        (&["time.method=\"event_driven\""][..], "time.method"),
    ] {
        let args: Vec<&str> = sets.iter().flat_map(|set| ["--set", set]).collect();
        let out = run(Some(2), "gas.toml", &dir.path().join("out"), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name} ran under mpirun");
        assert!(
            stderr.contains(name) && stderr.contains("not supported across MPI ranks"),
            "{stderr}"
        );
    }
}

#[test]
fn profiles_and_displacements_are_the_same_bytes_on_any_number_of_ranks_and_after_a_resume() {
    // The periodic Brownian scene: discs cross the box, so the MSD unwraps their images.
    let dir = tempfile::tempdir().unwrap();
    let extra = [
        "--set",
        "output.msd=true",
        "--set",
        "output.profile={ axis = \"y\", bins = 4 }",
        "--set",
        "output.stats_every=20",
        "--steps",
        "100",
    ];
    let files =
        |out: &Path| ["profile.csv", "msd.csv"].map(|f| std::fs::read(out.join(f)).unwrap());
    let one = dir.path().join("one");
    ok(run(None, "brownian.toml", &one, &extra), "one process");
    let reference = files(&one);
    assert!(reference[1].len() > 100);
    for ranks in [2, 3] {
        let out = dir.path().join(format!("r{ranks}"));
        ok(run(Some(ranks), "brownian.toml", &out, &extra), "ranks");
        assert!(
            files(&out) == reference,
            "{ranks} ranks: profile.csv or msd.csv differs"
        );
    }
    // Stopped at step 40 on three ranks, resumed on two: the origin travels in the checkpoint.
    let resumed = dir.path().join("resumed");
    let mut first = extra.to_vec();
    let last = first.len() - 1;
    first[last] = "40";
    ok(
        run(Some(3), "brownian.toml", &resumed, &first),
        "first part",
    );
    let checkpoint = resumed.join("checkpoint.bin");
    let mut rest = extra.to_vec();
    rest.extend(["--resume", checkpoint.to_str().unwrap()]);
    ok(
        run(Some(2), "brownian.toml", &resumed, &rest),
        "resumed part",
    );
    assert!(
        files(&resumed) == reference,
        "a resumed profile.csv or msd.csv differs"
    );
}

#[test]
fn sensors_count_as_one_process_on_any_number_of_ranks_and_after_a_resume() {
    // The 6,000-disc gas with a box across the domains' edges and a circle: discs cross
    // them and the domains (handed over between ranks) all the while.
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("sensed.toml");
    let text = std::fs::read_to_string(scenarios().join("gas.toml")).unwrap()
        + "\n[[sensor]]\nname = \"middle\"\nregion = { min = [60.0, 60.0], max = [140.0, 140.0] }\n\
           \n[[sensor]]\nname = \"hole\"\nregion = { centre = [100.0, 30.0], radius = 25.0 }\n";
    std::fs::write(&scenario, text).unwrap();
    let scenario = scenario.to_str().unwrap().to_string();
    let settings = [
        "time.steps=120",
        "gas.count=6000",
        "world.max=[200.0, 200.0]",
        "gas.radius=[0.3, 0.9]",
        "gas.speed=10.0",
        "output.stats_every=5",
    ];
    let stats = |ranks: Option<usize>, out: &str, extra: &[&str]| {
        let mut args = sets(&settings);
        args.extend_from_slice(extra);
        ok(run(ranks, &scenario, &dir.path().join(out), &args), out);
        std::fs::read_to_string(dir.path().join(out).join("stats.csv")).unwrap()
    };
    let one = stats(None, "one", &[]);
    // The counts move: discs entered and left both sensors.
    let header: Vec<&str> = one.lines().next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for name in [
        "sensor_middle_in",
        "sensor_middle_out",
        "sensor_hole_in",
        "sensor_hole_out",
    ] {
        let k = column(name);
        let total: u64 = one
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(k).unwrap().parse::<u64>().unwrap())
            .sum();
        assert!(total > 50, "{name}: {total}");
    }
    for r in 2..=3 {
        assert!(
            stats(Some(r), &format!("r{r}"), &[]) == one,
            "{r} ranks: stats.csv differs"
        );
    }
    // Stopped at step 40 on three ranks, resumed on two: the sensors' discs travel in the
    // checkpoint.
    stats(Some(3), "resumed", &["--steps", "40"]);
    let checkpoint = dir.path().join("resumed/checkpoint.bin");
    let resumed = stats(
        Some(2),
        "resumed",
        &["--resume", checkpoint.to_str().unwrap()],
    );
    assert!(resumed == one, "a resumed stats.csv differs");
}
