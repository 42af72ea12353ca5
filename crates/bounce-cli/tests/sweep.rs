//! `bounce sweep`: a 2 × 2 sweep as a signac workspace, a rerun that runs nothing, an
//! interrupted job resumed from its checkpoint, one job by `--task-id`, a Slurm array over
//! every job, and bad sweep files named.

mod common;

use std::path::{Path, PathBuf};

use common::{Scratch, bounce, output};

/// A 2 × 2 sweep of the gas template (300 or 600 discs, e = 0.9 or 1), 60 steps, no
/// pictures.
fn sweep_file(s: &Scratch) -> PathBuf {
    let scenario = s.path("gas.toml");
    let (code, _, stderr) = output(bounce().args(["new", "gas", "--out"]).arg(&scenario));
    assert_eq!(code, 0, "{stderr}");
    let text = std::fs::read_to_string(&scenario)
        .unwrap()
        .replace("frame_every = 30", "frame_every = 0")
        .replace("gif = true", "gif = false")
        .replace("plots = true", "plots = false");
    std::fs::write(&scenario, text).unwrap();
    s.scenario(
        "sweep.toml",
        r#"
scenario = "gas.toml"
steps = 60
[parameters]
"world.coefficient_of_restitution" = [0.9, 1.0]
"gas.1.count" = [300, 600]
"#,
    )
}

fn sweep(file: &Path, out: &Path, extra: &[&str]) -> (i32, String, String) {
    output(
        bounce()
            .arg("sweep")
            .arg(file)
            .arg("--out")
            .arg(out)
            .args(extra),
    )
}

fn jobs(out: &Path) -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(out.join("workspace"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dirs.sort();
    dirs
}

#[test]
fn a_sweep_runs_every_job_once_into_a_signac_workspace() {
    let s = Scratch::new();
    let file = sweep_file(&s);
    let out = s.path("ws");
    let (code, stdout, stderr) = sweep(&file, &out, &["--jobs", "2"]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(stdout.matches(") done").count(), 4, "{stdout}");
    assert_eq!(
        std::fs::read_to_string(out.join(".signac/config")).unwrap(),
        "schema_version = 2\n"
    );
    let dirs = jobs(&out);
    assert_eq!(dirs.len(), 4);
    let mut points: Vec<String> = dirs
        .iter()
        .map(|d| std::fs::read_to_string(d.join("signac_statepoint.json")).unwrap())
        .collect();
    points.sort();
    assert_eq!(
        points[0],
        r#"{"gas": {"1": {"count": 300}}, "world": {"coefficient_of_restitution": 0.9}}"#
    );
    for d in &dirs {
        assert!(d.join("bounce_done").exists() && d.join("stats.csv").exists());
    }
    // The summary: a row per job, its settings and its last stats row (60 steps).
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut lines = summary.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("job_id,gas.1.count,world.coefficient_of_restitution,step,"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4);
    assert!(rows.iter().all(|r| r[3] == "60"));
    assert_eq!(
        rows.iter().map(|r| (r[1], r[2])).collect::<Vec<_>>(),
        [("300", "0.9"), ("300", "1"), ("600", "0.9"), ("600", "1")]
    );
    // A rerun runs nothing, and says so.
    let before = std::fs::metadata(dirs[0].join("stats.csv"))
        .unwrap()
        .modified()
        .unwrap();
    let (code, stdout, _) = sweep(&file, &out, &[]);
    assert_eq!(code, 0);
    assert!(
        stdout.contains("4 job(s) already done, skipped"),
        "{stdout}"
    );
    assert!(!stdout.contains(") done"), "{stdout}");
    let after = std::fs::metadata(dirs[0].join("stats.csv"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(before, after);
}

#[test]
fn an_interrupted_job_continues_from_its_checkpoint_as_if_never_stopped() {
    let s = Scratch::new();
    let file = sweep_file(&s);
    let whole = s.path("whole");
    assert_eq!(sweep(&file, &whole, &["--task-id", "0"]).0, 0);
    // The same job stopped at step 25: its directory has a checkpoint, no `bounce_done`.
    let cut = s.path("cut");
    let (code, stdout, stderr) = sweep(&file, &cut, &["--slurm"]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let job = jobs(&whole)
        .into_iter()
        .find(|d| d.join("bounce_done").exists())
        .unwrap();
    let id = job.file_name().unwrap();
    let dir = cut.join("workspace").join(id);
    let settings = [
        "--set",
        "world.coefficient_of_restitution=0.9",
        "--set",
        "gas.1.count=300",
    ];
    let (code, _, stderr) = output(
        bounce()
            .arg("run")
            .arg(s.path("gas.toml"))
            .args(settings)
            .args(["--steps", "25", "-q", "--force", "--out"])
            .arg(&dir),
    );
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = sweep(&file, &cut, &["--task-id", "0"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("resumes from its checkpoint"), "{stdout}");
    assert_eq!(
        std::fs::read(dir.join("stats.csv")).unwrap(),
        std::fs::read(job.join("stats.csv")).unwrap()
    );
}

#[test]
fn a_task_id_runs_its_job_alone_and_a_slurm_array_covers_every_job() {
    let s = Scratch::new();
    let file = sweep_file(&s);
    let out = s.path("ws");
    let (code, stdout, stderr) = sweep(&file, &out, &["--slurm"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("a job array of 4 tasks"), "{stdout}");
    let script = std::fs::read_to_string(out.join("sweep.sbatch")).unwrap();
    assert!(script.contains("#SBATCH --array=0-3"), "{script}");
    assert!(
        script.contains("--task-id $SLURM_ARRAY_TASK_ID"),
        "{script}"
    );
    assert!(
        jobs(&out).iter().all(|d| !d.join("stats.csv").exists()),
        "ran"
    );
    // The same for row: a workflow over the signac workspace whose action runs one job.
    let workflow: toml::Table = std::fs::read_to_string(out.join("workflow.toml"))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(
        workflow["workspace"]["value_file"].as_str(),
        Some("signac_statepoint.json")
    );
    let action = &workflow["action"][0];
    assert!(
        action["command"]
            .as_str()
            .unwrap()
            .ends_with("--job {directory}")
    );
    assert_eq!(action["products"][0].as_str(), Some("bounce_done"));
    assert_eq!(action["group"]["maximum_size"].as_integer(), Some(1));
    // What row runs: `--job <directory>` runs that job alone.
    let last = jobs(&out).pop().unwrap();
    let id = last.file_name().unwrap().to_str().unwrap().to_string();
    let (code, stdout, stderr) = sweep(&file, &out, &["--job", &format!("workspace/{id}")]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains(&format!("({id}) done")), "{stdout}");
    assert!(last.join("bounce_done").exists());
    std::fs::remove_file(last.join("bounce_done")).unwrap();
    let (code, _, stderr) = sweep(&file, &out, &["--job", "0123"]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("--job 0123: no job of this sweep has that id"),
        "{stderr}"
    );
    // Task 2 runs job 2 (the product's order: counts 600 then e 0.9) and nothing else.
    let (code, stdout, stderr) = sweep(&file, &out, &["--task-id", "2"]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(stdout.matches(") done").count(), 1, "{stdout}");
    let done: Vec<PathBuf> = jobs(&out)
        .into_iter()
        .filter(|d| d.join("bounce_done").exists())
        .collect();
    assert_eq!(done.len(), 1);
    let point = std::fs::read_to_string(done[0].join("signac_statepoint.json")).unwrap();
    assert!(
        point.contains(r#""count": 600"#) && point.contains("0.9"),
        "{point}"
    );
}

#[test]
fn bad_sweeps_are_named() {
    let s = Scratch::new();
    let file = sweep_file(&s);
    let out = s.path("ws");
    let (code, _, stderr) = sweep(&file, &out, &["--task-id", "9"]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("--task-id 9: the sweep has jobs 0..3"),
        "{stderr}"
    );
    for (text, message) in [
        (
            "scenario = \"gas.toml\"\n[parameters]\n",
            "lists no key to sweep",
        ),
        (
            "scenario = \"gas.toml\"\n[parameters]\n\"world.friction\" = []\n",
            "parameters.\"world.friction\" lists no value",
        ),
        ("[parameters]\n\"a\" = [1]\n", "missing field `scenario`"),
        (
            "scenario = \"gas.toml\"\nseeds = 0\n[parameters]\n\"a.b\" = [1]\n",
            "seeds = 0",
        ),
    ] {
        let bad = s.scenario("bad.toml", text);
        let (code, _, stderr) = sweep(&bad, &s.path("bad"), &[]);
        assert_eq!(code, 1, "{text}");
        assert!(
            stderr.contains("bad.toml") && stderr.contains(message),
            "{stderr}"
        );
    }
    // A job whose run fails is named, and the sweep exits with an error.
    let failing = s.scenario(
        "failing.toml",
        "scenario = \"gas.toml\"\nsteps = 5\n[parameters]\n\"world.coefficient_of_restitution\" = [2.0]\n",
    );
    let (code, _, stderr) = sweep(&failing, &s.path("failing"), &[]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("job 0") && stderr.contains("failed"),
        "{stderr}"
    );
}

/// glotzerlab's row itself (installed by scripts/test as `BOUNCE_ROW`) submits the sweep's
/// workflow.toml: on a machine without a scheduler it runs each job at once, one directory a
/// submission, and afterwards has nothing left to submit.
#[cfg(feature = "system-tests")]
#[test]
fn row_runs_the_workflow_to_the_end() {
    let row = std::env::var("BOUNCE_ROW").unwrap_or_else(|_| "row".into());
    let s = Scratch::new();
    let file = sweep_file(&s);
    let out = s.path("ws");
    let (code, _, stderr) = sweep(&file, &out, &["--slurm"]);
    assert_eq!(code, 0, "{stderr}");
    let run = |args: &[&str]| {
        let done = std::process::Command::new(&row)
            .args(args)
            .current_dir(&out)
            .output()
            .unwrap_or_else(|e| panic!("{row}: {e} (scripts/test installs row)"));
        let text = String::from_utf8_lossy(&done.stdout).to_string()
            + &String::from_utf8_lossy(&done.stderr);
        assert!(done.status.success(), "row {args:?}: {text}");
        text
    };
    let before = run(&["show", "status"]);
    assert!(
        before.contains("run            0         0        4"),
        "{before}"
    );
    let submitted = run(&["submit", "--yes"]);
    assert_eq!(submitted.matches(") done").count(), 4, "{submitted}");
    assert!(jobs(&out).iter().all(|d| d.join("bounce_done").exists()));
    let after = run(&["show", "status"]);
    assert!(
        after.contains("run            4         0        0"),
        "{after}"
    );
    // What row left is a finished sweep: the command line runs nothing more.
    let (code, stdout, stderr) = sweep(&file, &out, &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("4 job(s) already done"), "{stdout}");
}

/// A sweep killed outright (SIGKILL, as a scheduler's cancel can) takes its running job down
/// with it, checkpointed; the rerun resumes that job and ends with the bytes of a run never
/// stopped.
#[cfg(target_os = "linux")]
#[test]
fn a_killed_sweep_stops_its_job_and_the_rerun_resumes_it() {
    use std::time::{Duration, Instant};
    let s = Scratch::new();
    let file = sweep_file(&s);
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("steps = 60", "steps = 30000")
        .replace("\"gas.1.count\" = [300, 600]", "\"gas.1.count\" = [2000]");
    std::fs::write(&file, text).unwrap();
    let whole = s.path("whole");
    assert_eq!(sweep(&file, &whole, &["--task-id", "0"]).0, 0);
    let job = jobs(&whole)
        .into_iter()
        .find(|d| d.join("bounce_done").exists())
        .unwrap();
    let id = job.file_name().unwrap().to_owned();
    let cut = s.path("cut");
    let mut killed = bounce()
        .arg("sweep")
        .arg(&file)
        .arg("--out")
        .arg(&cut)
        .args(["--jobs", "1"])
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let dir = cut.join("workspace").join(&id);
    let deadline = Instant::now() + Duration::from_secs(60);
    // Running: its outputs are being written (as temporaries, renamed when whole).
    // The sweep writes the state point first (through a temporary too), so only a
    // temporary beside the finished state point is the run's.
    let writing = || {
        dir.join("signac_statepoint.json").exists()
            && std::fs::read_dir(&dir).is_ok_and(|entries| {
                entries
                    .flatten()
                    .any(|e| e.file_name().to_string_lossy().starts_with(".bounce-tmp-"))
            })
    };
    while !writing() {
        assert!(Instant::now() < deadline, "job 0 did not start");
        std::thread::sleep(Duration::from_millis(5));
    }
    killed.kill().unwrap(); // SIGKILL: the sweep cannot pass anything on
    killed.wait().unwrap();
    // The job's run got SIGTERM from the kernel as its parent died, and checkpointed.
    while !dir.join("checkpoint.bin").exists() {
        assert!(Instant::now() < deadline, "the orphaned job did not stop");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(500));
    assert!(!dir.join("bounce_done").exists());
    let rows = |d: &Path| {
        std::fs::read_to_string(d.join("stats.csv"))
            .unwrap()
            .lines()
            .count()
    };
    assert!(rows(&dir) < rows(&job), "the kill came after the job's end");
    let (code, stdout, stderr) = sweep(&file, &cut, &["--jobs", "1"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("resumes from its checkpoint"), "{stdout}");
    assert_eq!(stdout.matches(") done").count(), 2, "{stdout}");
    assert_eq!(
        std::fs::read(dir.join("stats.csv")).unwrap(),
        std::fs::read(job.join("stats.csv")).unwrap()
    );
}
