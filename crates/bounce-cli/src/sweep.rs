//! `bounce sweep SWEEP.toml --out WORKSPACE`: a parameter sweep as a signac workspace.
//!
//! The sweep file names a scenario (relative to the sweep file), optionally a run length
//! (`steps`) and replicas (`seeds = N`: each state point run with `--seed 0..N`), and under
//! `[parameters]` a list of values for any `--set` key. The jobs are the product of the
//! lists (keys in sorted order, the last varying fastest, then the seeds).
//!
//! Each job's state point is the nested mapping of its keys (`world.friction = 0.5` becomes
//! `{"world": {"friction": 0.5}}`, plus `"seed"` with replicas), and its id is signac 2's:
//! the MD5 of the state point as Python's `json.dumps(sp, sort_keys=True)` writes it. The
//! workspace is signac's layout: `WORKSPACE/.signac/config` and
//! `WORKSPACE/workspace/<id>/signac_statepoint.json`, so `signac.get_project(WORKSPACE)`
//! finds every job. A job's run writes its outputs into its directory; a finished one holds
//! `bounce_done`, and a rerun skips it (and says so); an interrupted one continues from its
//! `checkpoint.bin`. `WORKSPACE/summary.csv` has a row per finished job: its id, its state
//! point and its last `stats.csv` row.
//!
//! `--jobs N` runs N at once, each with its share of the cores; `--task-id K` runs job K
//! only (a Slurm array task), `--job ID` the job of that id (what `row` passes);
//! `--slurm` writes `WORKSPACE/sweep.sbatch`, a job array over every job, and
//! `WORKSPACE/workflow.toml`, the same for glotzerlab's `row`, instead of running.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};

use anyhow::{Context, Result, anyhow, bail};
use bounce_scenario::json::string as json_string;
use md5::{Digest, Md5};
use serde::Deserialize;

/// The sweep file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    /// The scenario, relative to the sweep file.
    scenario: PathBuf,
    /// Run to this step (default: the scenario's `time.steps`).
    steps: Option<u64>,
    /// Replicas of every state point, run with `--seed 0..seeds`.
    seeds: Option<u64>,
    /// `--set` keys and the values each takes.
    parameters: BTreeMap<String, Vec<toml::Value>>,
}

/// One job: its settings and its state point.
#[derive(Clone, Debug)]
pub struct Job {
    /// `(key, value)` in key order.
    pub settings: Vec<(String, toml::Value)>,
    /// The replica's seed, with `seeds`.
    pub seed: Option<u64>,
}

impl Job {
    /// The state point as JSON in Python's `json.dumps(sp, sort_keys=True)` form.
    pub fn statepoint_json(&self) -> String {
        let mut root = Tree::default();
        for (key, value) in &self.settings {
            root.insert(&key.split('.').collect::<Vec<_>>(), value.clone());
        }
        if let Some(seed) = self.seed {
            root.insert(&["seed"], toml::Value::Integer(seed as i64));
        }
        root.json()
    }

    /// signac 2's job id: the MD5 of the sorted JSON state point.
    pub fn id(&self) -> String {
        let digest = Md5::digest(self.statepoint_json().as_bytes());
        digest.iter().map(|b| format!("{b:02x}")).collect()
    }
}

/// A nested state point.
#[derive(Default)]
struct Tree(BTreeMap<String, Node>);

enum Node {
    Leaf(toml::Value),
    Branch(Tree),
}

impl Tree {
    fn insert(&mut self, path: &[&str], value: toml::Value) {
        let Some((key, rest)) = path.split_first() else {
            return;
        };
        if rest.is_empty() {
            self.0.insert(key.to_string(), Node::Leaf(value));
            return;
        }
        let node = self
            .0
            .entry(key.to_string())
            .or_insert_with(|| Node::Branch(Tree::default()));
        if let Node::Leaf(_) = node {
            *node = Node::Branch(Tree::default());
        }
        if let Node::Branch(tree) = node {
            tree.insert(rest, value);
        }
    }

    /// Python's `json.dumps(..., sort_keys=True)`: `", "` and `": "`, ASCII only.
    fn json(&self) -> String {
        let items: Vec<String> = (self.0.iter())
            .map(|(k, v)| {
                let value = match v {
                    Node::Leaf(value) => python_json(value),
                    Node::Branch(tree) => tree.json(),
                };
                format!("{}: {value}", json_string(k))
            })
            .collect();
        format!("{{{}}}", items.join(", "))
    }
}

/// A TOML value as Python's `json.dumps` writes the same value.
fn python_json(value: &toml::Value) -> String {
    match value {
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => python_float(*f),
        toml::Value::Boolean(b) => b.to_string(),
        toml::Value::String(s) => json_string(s),
        toml::Value::Array(items) => {
            let items: Vec<String> = items.iter().map(python_json).collect();
            format!("[{}]", items.join(", "))
        }
        other => json_string(&other.to_string()),
    }
}

/// Python's `repr` of a float (what `json.dumps` writes): the shortest digits that read
/// back, in fixed notation for exponents −4 to 15 (with `.0` on whole numbers), else as
/// `d.ddde±XX`.
pub fn python_float(f: f64) -> String {
    if f.is_nan() {
        return "NaN".into();
    }
    if f.is_infinite() {
        return if f > 0.0 { "Infinity" } else { "-Infinity" }.into();
    }
    if f == 0.0 {
        return if f.is_sign_negative() { "-0.0" } else { "0.0" }.into();
    }
    // Rust's `{:e}` gives the shortest round-trip digits: `d.ddde±x`.
    let e = format!("{f:e}");
    let (mantissa, exponent) = e.split_once('e').expect("an exponent");
    let exponent: i32 = exponent.parse().expect("an integer exponent");
    let negative = mantissa.starts_with('-');
    let digits: String = mantissa.chars().filter(|c| c.is_ascii_digit()).collect();
    let sign = if negative { "-" } else { "" };
    if (-4..16).contains(&exponent) {
        let point = exponent + 1; // digits before the decimal point
        let body = if point <= 0 {
            format!("0.{}{digits}", "0".repeat((-point) as usize))
        } else if point as usize >= digits.len() {
            format!("{digits}{}.0", "0".repeat(point as usize - digits.len()))
        } else {
            format!(
                "{}.{}",
                &digits[..point as usize],
                &digits[point as usize..]
            )
        };
        format!("{sign}{body}")
    } else {
        let mantissa = if digits.len() > 1 {
            format!("{}.{}", &digits[..1], &digits[1..])
        } else {
            digits
        };
        let exp_sign = if exponent < 0 { '-' } else { '+' };
        format!("{sign}{mantissa}e{exp_sign}{:02}", exponent.abs())
    }
}

/// A value as a `--set` takes it (TOML).
fn set_value(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => toml::Value::String(s.clone()).to_string(),
        other => other.to_string(),
    }
}

/// What `bounce sweep` was asked.
pub struct Request<'a> {
    pub sweep: &'a Path,
    pub out: &'a Path,
    pub jobs: usize,
    pub task_id: Option<usize>,
    /// Run the job whose id (its directory's name) this is: what `row` passes.
    pub job: Option<String>,
    pub slurm: bool,
    /// The most jobs the sweep may make (`--max-jobs`): a product of lists grows fast, and
    /// each job is a folder and a run.
    pub max_jobs: u64,
}

/// The jobs a sweep makes unless `--max-jobs` says more.
pub const DEFAULT_MAX_JOBS: u64 = 10_000;

/// The sweep's scenario and jobs.
struct Sweep {
    scenario: PathBuf,
    steps: Option<u64>,
    jobs: Vec<Job>,
}

fn read(path: &Path, max_jobs: u64) -> Result<Sweep> {
    let name = path.display();
    let text = bounce_scenario::files::read_to_string(path)
        .with_context(|| format!("{name}: cannot read the file"))?;
    let file: SweepFile = toml::from_str(&text).map_err(|e| anyhow!("{name}: {e}"))?;
    if file.parameters.is_empty() {
        bail!("{name}: [parameters] lists no key to sweep");
    }
    for (key, values) in &file.parameters {
        if values.is_empty() {
            bail!("{name}: parameters.\"{key}\" lists no value");
        }
        if key.split('.').any(str::is_empty) || key == "seed" {
            bail!("{name}: parameters.\"{key}\": not a `--set` key (like world.friction)");
        }
    }
    if file.seeds == Some(0) {
        bail!("{name}: seeds = 0: must be at least 1 (or left out)");
    }
    // The product is counted before anything is made of it.
    let count = file
        .parameters
        .values()
        .try_fold(file.seeds.unwrap_or(1), |n, values| {
            n.checked_mul(values.len() as u64)
        });
    match count {
        Some(n) if n <= max_jobs => {}
        Some(n) => bail!(
            "{name}: the sweep makes {n} jobs (the product of its lists and seeds), over the \
             limit of {max_jobs}: raise it with --max-jobs {n} to run them all"
        ),
        None => bail!("{name}: the sweep's product of lists and seeds overflows a count"),
    }
    let scenario = path.parent().unwrap_or(Path::new(".")).join(&file.scenario);
    let mut jobs = vec![Job {
        settings: Vec::new(),
        seed: None,
    }];
    for (key, values) in &file.parameters {
        jobs = jobs
            .iter()
            .flat_map(|job| {
                values.iter().map(move |v| {
                    let mut next = job.clone();
                    next.settings.push((key.clone(), v.clone()));
                    next
                })
            })
            .collect();
    }
    if let Some(seeds) = file.seeds {
        jobs = jobs
            .iter()
            .flat_map(|job| {
                (0..seeds).map(move |s| Job {
                    seed: Some(s),
                    ..job.clone()
                })
            })
            .collect();
    }
    Ok(Sweep {
        scenario,
        steps: file.steps,
        jobs,
    })
}

/// Writes `text` to `path` whole.
fn write_file(path: &Path, text: &str) -> Result<()> {
    bounce_scenario::atomic::write(path, text.as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Runs (or schedules) the sweep.
pub fn sweep(request: &Request) -> Result<()> {
    let sweep = read(request.sweep, request.max_jobs)?;
    let out = request.out;
    let workspace = out.join("workspace");
    std::fs::create_dir_all(&workspace)
        .with_context(|| format!("cannot create {}", workspace.display()))?;
    std::fs::create_dir_all(out.join(".signac"))?;
    write_file(&out.join(".signac/config"), "schema_version = 2\n")?;
    for job in &sweep.jobs {
        let dir = workspace.join(job.id());
        std::fs::create_dir_all(&dir)?;
        write_file(&dir.join("signac_statepoint.json"), &job.statepoint_json())?;
    }
    if request.slurm {
        return write_slurm(request, sweep.jobs.len());
    }
    let chosen: Vec<usize> = match (request.task_id, &request.job) {
        (Some(k), _) if k < sweep.jobs.len() => vec![k],
        (Some(k), _) => bail!(
            "--task-id {k}: the sweep has jobs 0..{} ({} in all)",
            sweep.jobs.len() - 1,
            sweep.jobs.len()
        ),
        (None, Some(id)) => {
            // `row` may pass the directory with the workspace before it.
            let id = Path::new(id)
                .file_name()
                .map_or(id.as_str(), |n| n.to_str().unwrap_or(id));
            match sweep.jobs.iter().position(|j| j.id() == id) {
                Some(k) => vec![k],
                None => bail!("--job {id}: no job of this sweep has that id"),
            }
        }
        (None, None) => (0..sweep.jobs.len()).collect(),
    };
    let (done, todo): (Vec<usize>, Vec<usize>) = chosen.into_iter().partition(|&k| {
        workspace
            .join(sweep.jobs[k].id())
            .join("bounce_done")
            .exists()
    });
    if !done.is_empty() {
        println!("{} job(s) already done, skipped", done.len());
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let at_once = request.jobs.max(1);
    let threads = (cores / at_once).max(1);
    let mut running: Vec<(usize, Child)> = Vec::new();
    let mut queue = todo.into_iter();
    let mut failed = Vec::new();
    loop {
        while running.len() < at_once {
            let Some(k) = queue.next() else { break };
            let child = start(&sweep, k, &workspace, threads)?;
            running.push((k, child));
        }
        if running.is_empty() {
            break;
        }
        let (k, mut child) = running.remove(0);
        let status = child.wait()?;
        let dir = workspace.join(sweep.jobs[k].id());
        if status.success() {
            write_file(&dir.join("bounce_done"), "")?;
            println!("job {k} ({}) done", sweep.jobs[k].id());
        } else {
            failed.push(k);
            eprintln!(
                "job {k} ({}) failed ({status}); its output is in {}",
                sweep.jobs[k].id(),
                dir.display()
            );
        }
    }
    write_summary(&sweep, &workspace, &out.join("summary.csv"))?;
    if !failed.is_empty() {
        bail!("{} job(s) failed: {failed:?}", failed.len());
    }
    Ok(())
}

/// Starts job `k`'s run in its directory: anew, or from its checkpoint when an earlier run
/// of it was interrupted.
fn start(sweep: &Sweep, k: usize, workspace: &Path, threads: usize) -> Result<Child> {
    let job = &sweep.jobs[k];
    let dir = workspace.join(job.id());
    let exe = std::env::current_exe().context("cannot find the bounce command")?;
    let mut command = Command::new(exe);
    command
        .arg("run")
        .arg(&sweep.scenario)
        .arg("--out")
        .arg(&dir)
        .args(["--quiet", "--threads", &threads.to_string()]);
    for (key, value) in &job.settings {
        command.args(["--set", &format!("{key}={}", set_value(value))]);
    }
    if let Some(seed) = job.seed {
        command.args(["--seed", &seed.to_string()]);
    }
    if let Some(steps) = sweep.steps {
        command.args(["--steps", &steps.to_string()]);
    }
    let checkpoint = dir.join("checkpoint.bin");
    if checkpoint.exists() {
        println!("job {k} ({}) resumes from its checkpoint", job.id());
        command.arg("--resume").arg(&checkpoint);
    } else {
        command.arg("--force");
    }
    stop_with_parent(&mut command);
    command
        .spawn()
        .with_context(|| format!("cannot start job {k}"))
}

/// A job's run stops (as at Ctrl-C: the step finished, every output and the checkpoint
/// written) when the sweep that started it dies, even by SIGKILL or a scheduler's cancel,
/// rather than running on unseen beside the rerun that resumes it.
#[cfg(target_os = "linux")]
fn stop_with_parent(command: &mut Command) {
    use std::os::unix::process::CommandExt;
    let parent = std::process::id() as libc::pid_t;
    // SAFETY: between fork and exec the closure only calls async-signal-safe functions
    // (prctl, getppid, raise) and allocates nothing.
    unsafe {
        command.pre_exec(move || {
            libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM);
            // The sweep may have died before prctl: then stop now.
            if libc::getppid() != parent {
                libc::raise(libc::SIGTERM);
            }
            Ok(())
        });
    }
}

#[cfg(not(target_os = "linux"))]
fn stop_with_parent(_: &mut Command) {}

/// `summary.csv`: per finished job, its id, its settings and its last `stats.csv` row.
fn write_summary(sweep: &Sweep, workspace: &Path, path: &Path) -> Result<()> {
    let mut header: Option<String> = None;
    let mut rows = Vec::new();
    for job in &sweep.jobs {
        let dir = workspace.join(job.id());
        if !dir.join("bounce_done").exists() {
            continue;
        }
        let stats = std::fs::read_to_string(dir.join("stats.csv"))
            .with_context(|| format!("{}: no stats.csv", dir.display()))?;
        let mut lines = stats.lines();
        let columns = lines.next().unwrap_or_default().to_string();
        let last = lines.last().unwrap_or_default().to_string();
        if header.is_none() {
            let keys: Vec<&str> = job.settings.iter().map(|(k, _)| k.as_str()).collect();
            let seed = if job.seed.is_some() { ",seed" } else { "" };
            header = Some(format!("job_id,{}{seed},{columns}", keys.join(",")));
        }
        let values: Vec<String> = job.settings.iter().map(|(_, v)| csv_value(v)).collect();
        let seed = job.seed.map_or_else(String::new, |s| format!(",{s}"));
        rows.push(format!("{},{}{seed},{last}", job.id(), values.join(",")));
    }
    let mut text = header.unwrap_or_else(|| "job_id".into());
    text.push('\n');
    for row in rows {
        text.push_str(&row);
        text.push('\n');
    }
    write_file(path, &text)
}

/// A setting's value in a CSV cell.
fn csv_value(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) if !s.contains([',', '"', '\n']) => s.clone(),
        toml::Value::String(s) => format!("\"{}\"", s.replace('"', "\"\"")),
        toml::Value::Float(f) => f.to_string(),
        other => other.to_string(),
    }
}

/// `sweep.sbatch`: a Slurm job array whose task K runs job K.
fn write_slurm(request: &Request, jobs: usize) -> Result<()> {
    let absolute = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    let exe = std::env::current_exe().context("cannot find the bounce command")?;
    // Each task reads the sweep again: a raised limit travels with it.
    let limit = if request.max_jobs == DEFAULT_MAX_JOBS {
        String::new()
    } else {
        format!(" --max-jobs {}", request.max_jobs)
    };
    let script = format!(
        "#!/bin/bash\n\
         # A bounce sweep as a Slurm job array: task K runs job K of {sweep}.\n\
         # Submit with `sbatch {out}/sweep.sbatch`; rerun it to finish what did not.\n\
         #SBATCH --job-name=bounce-sweep\n\
         #SBATCH --array=0-{last}\n\
         #SBATCH --ntasks=1\n\
         #SBATCH --cpus-per-task=1\n\
         #SBATCH --output={out}/slurm-%A_%a.out\n\
         \n\
         {exe} sweep {sweep} --out {out}{limit} --task-id $SLURM_ARRAY_TASK_ID\n",
        sweep = absolute(request.sweep).display(),
        out = absolute(request.out).display(),
        last = jobs - 1,
        exe = exe.display(),
    );
    let path = request.out.join("sweep.sbatch");
    write_file(&path, &script)?;
    let workflow = format!(
        "# The sweep for glotzerlab's row (https://row.readthedocs.io): `row submit` here\n\
         # submits every job whose directory lacks bounce_done.\n\
         [workspace]\n\
         path = \"workspace\"\n\
         value_file = \"signac_statepoint.json\"\n\
         \n\
         [[action]]\n\
         name = \"run\"\n\
         command = \"{exe} sweep {sweep} --out {out}{limit} --job {{directory}}\"\n\
         products = [\"bounce_done\"]\n\
         # One directory a submission: the command runs one job ({{directory}}).\n\
         group.maximum_size = 1\n\
         resources.processes.per_directory = 1\n\
         resources.walltime.per_directory = \"01:00:00\"\n",
        exe = exe.display(),
        sweep = absolute(request.sweep).display(),
        out = absolute(request.out).display(),
    );
    write_file(&request.out.join("workflow.toml"), &workflow)?;
    println!(
        "{}: a job array of {jobs} tasks (0..{}); submit it with sbatch (or `row submit` \
         with {})",
        path.display(),
        jobs - 1,
        request.out.join("workflow.toml").display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_are_written_as_python_writes_them() {
        for (f, python) in [
            (0.9, "0.9"),
            (1.0, "1.0"),
            (100.0, "100.0"),
            (0.0001, "0.0001"),
            (1e-5, "1e-05"),
            (1.5e-7, "1.5e-07"),
            (1e16, "1e+16"),
            (1.2345678901234568e17, "1.2345678901234568e+17"),
            (123456789012345.6, "123456789012345.6"),
            (-2.5, "-2.5"),
            (0.1 + 0.2, "0.30000000000000004"),
        ] {
            assert_eq!(python_float(f), python, "{f}");
        }
    }

    #[test]
    fn a_state_point_is_nested_sorted_and_hashed_as_signac_does() {
        // signac 2.4: `Project.open_job(sp).id` for this state point.
        let job = Job {
            settings: vec![
                (
                    "world.coefficient_of_restitution".into(),
                    toml::Value::Float(0.9),
                ),
                ("gas.1.count".into(), toml::Value::Integer(500)),
            ],
            seed: Some(0),
        };
        assert_eq!(
            job.statepoint_json(),
            r#"{"gas": {"1": {"count": 500}}, "seed": 0, "world": {"coefficient_of_restitution": 0.9}}"#
        );
        assert_eq!(job.id(), "baa9028b5551c2543c63489827411687");
        assert_eq!(json_string("é\"x"), r#""\u00e9\"x""#);
    }
}
