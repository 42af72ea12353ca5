//! `bounce`: run scenarios headless, start new ones from templates, check files.

mod analyze;
mod checkpoint;
#[cfg(feature = "mpi")]
mod distributed;
mod events_csv;
mod font;
mod observables_csv;
mod overlay;
mod plots;
mod render;
mod rows;
mod run;
mod stats_csv;
mod sweep;
mod validate;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::{Context, Result, anyhow, bail};
use clap::{Parser, Subcommand};

/// bounce: a fast, faithful, deterministic 2D disc collision simulator.
#[derive(Parser)]
#[command(name = "bounce", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario headless and write statistics, frames, a trajectory and plots.
    Run {
        /// The scenario file (TOML).
        scenario: PathBuf,
        /// Output directory (created if missing; refused if it holds another run's files,
        /// unless --force or --resume).
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Run until this step (overrides the scenario's time.steps).
        #[arg(long)]
        steps: Option<u64>,
        /// Worker threads, 1 to 256 (results are identical for every count); default: all
        /// cores.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..=MAX_THREADS))]
        threads: Option<u16>,
        /// Continue from a checkpoint of the same scenario; into the run's own folder the
        /// outputs are continued (later rows and frames dropped first).
        #[arg(long)]
        resume: Option<PathBuf>,
        /// Replace the files of a previous run in the output directory.
        #[arg(long, conflicts_with = "resume")]
        force: bool,
        #[command(flatten)]
        steer: Steer,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Write a commented scenario to start from (gas, pile, newtons-cradle, brownian,
    /// mixing, million, galton-board, hourglass, piston, effusion, angle-of-repose,
    /// hard-discs, driven-granular, shear).
    New {
        /// The template's name.
        template: String,
        /// Where to write it (default: standard output).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Overwrite an existing file.
        #[arg(long)]
        force: bool,
    },
    /// Watch and play with a scenario in a window (the built-in demo without one).
    View {
        /// The scenario file (TOML).
        scenario: Option<PathBuf>,
        /// Render this many frames, save a screenshot and close (for tests and CI).
        #[arg(long, requires = "screenshot")]
        headless_frames: Option<u32>,
        /// Where the headless screenshot goes (PNG; a .txt beside it locates the discs).
        #[arg(long, requires = "headless_frames")]
        screenshot: Option<PathBuf>,
    },
    /// Run short reference simulations and compare them with theory (Maxwell–Boltzmann,
    /// conservation, the hard-disc equation of state, equipartition, the model options).
    Validate {
        /// Smaller and shorter runs: under a minute.
        #[arg(long)]
        quick: bool,
        /// Where the plot goes.
        #[arg(long, default_value = "validate")]
        out: PathBuf,
    },
    /// The structure of a GSD trajectory: g(r) (rdf.csv), the global bond order |ψ6| per
    /// frame (psi6.csv) and the mean-square displacement (msd.csv), each with a PNG.
    Analyze {
        /// The GSD trajectory (bounce's, HOOMD-blue's or any `hoomd` schema file).
        trajectory: PathBuf,
        /// Output directory (created if missing; its rdf, psi6 and msd files are replaced).
        #[arg(long, default_value = "analysis")]
        out: PathBuf,
        /// The first frame used (negative counts from the end: -10 is the last ten).
        #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
        first: i64,
        /// g(r) up to this distance, in mean diameters (default 5, or as far as the box
        /// allows).
        #[arg(long, allow_negative_numbers = true)]
        r_max: Option<f64>,
        /// g(r)'s bin width, in mean diameters.
        #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
        bin: f64,
        /// How the box ends, where the file does not say or says wrong (bounce's files
        /// record it; HOOMD-blue's boxes are periodic).
        #[arg(long, value_parser = ["periodic", "walls", "open"])]
        boundary: Option<String>,
    },
    /// Run a parameter sweep into a signac workspace: every combination of the sweep
    /// file's `[parameters]` lists (and `seeds` replicas), one `bounce run` per job, a
    /// summary.csv; or write a Slurm job array for it.
    Sweep {
        /// The sweep file (TOML): `scenario`, optional `steps` and `seeds`, `[parameters]`.
        sweep: PathBuf,
        /// The workspace (signac's layout; created if missing, finished jobs kept).
        #[arg(long, default_value = "sweep")]
        out: PathBuf,
        /// Jobs run at once (each gets its share of the cores).
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=256))]
        jobs: u16,
        /// Run job K only (a Slurm array task).
        #[arg(long, value_name = "K", conflicts_with_all = ["slurm", "job"])]
        task_id: Option<usize>,
        /// Run the job of this id (its directory's name) only: what row's workflow passes.
        #[arg(long, value_name = "ID", conflicts_with = "slurm")]
        job: Option<String>,
        /// Write WORKSPACE/sweep.sbatch (a Slurm job array over every job) and
        /// WORKSPACE/workflow.toml (the same for glotzerlab's row) instead of running.
        #[arg(long)]
        slurm: bool,
        /// The most jobs the sweep may make; a larger product of lists is refused with its
        /// count.
        #[arg(long, value_name = "N", default_value_t = sweep::DEFAULT_MAX_JOBS)]
        max_jobs: u64,
    },
    /// Validate a scenario file and report every problem with its line.
    Check {
        /// The scenario file (TOML).
        scenario: PathBuf,
        #[command(flatten)]
        steer: Steer,
    },
}

/// Changes to the scenario from the command line, and the resources it may use.
#[derive(clap::Args)]
struct Steer {
    /// Override a scenario field, validated like the file's own value:
    /// `--set world.coefficient_of_restitution=0.9 --set time.dt=0.001 --set gas.2.count=500`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Reseed every [[gas]] generator: table k gets seed N + k.
    #[arg(long)]
    seed: Option<u64>,
    /// Refuse scenarios estimated to need more memory than this, in GiB (default: half the
    /// machine's memory).
    #[arg(long, value_name = "GIB")]
    memory_limit: Option<f64>,
}

/// The most worker threads `--threads` accepts.
const MAX_THREADS: i64 = 256;

impl Steer {
    /// The scenario's text with the overrides applied, its name, and the limits.
    fn apply(&self, scenario: &Path) -> Result<(String, String, bounce_scenario::Limits)> {
        let origin = scenario.display().to_string();
        let text = bounce_scenario::files::read_to_string(scenario)
            .with_context(|| format!("{origin}: cannot read the file"))?;
        let text = bounce_scenario::overrides::apply(&text, &self.sets, self.seed)
            .map_err(|e| anyhow!("{origin}: {e}"))?;
        let origin = if self.sets.is_empty() && self.seed.is_none() {
            origin
        } else {
            format!("{origin} (with --set/--seed)")
        };
        let limits = match self.memory_limit {
            Some(gib) if gib.is_finite() && gib > 0.0 => bounce_scenario::Limits::memory_gib(gib),
            Some(gib) => bail!("--memory-limit {gib}: must be a number of GiB > 0"),
            None => bounce_scenario::Limits::default(),
        };
        Ok((text, origin, limits))
    }
}

/// Stores the number of the first SIGINT, SIGTERM or SIGHUP received: the run stops at its
/// last whole step (within a second, even inside a long step), writes everything and exits
/// with 128 + that number. With `second_exits`, a second signal, for a user who will not
/// wait, exits at once: files growing row by row or frame by frame keep what was whole,
/// the others being written are removed, those already complete stay, none is left
/// half-written (`bounce_scenario::atomic::exit_now`). (Not under `mpirun`, which forwards one signal to its ranks
/// more than once: there the first is the stop, and repeats change nothing.)
fn stop_on_signals(second_exits: bool) -> Result<Arc<AtomicUsize>> {
    let stop = Arc::new(AtomicUsize::new(0));
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])
            .context("cannot handle signals")?;
        let first = stop.clone();
        std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                for signal in signals.forever() {
                    if first.load(Ordering::SeqCst) == 0 {
                        first.store(signal as usize, Ordering::SeqCst);
                    } else if second_exits {
                        eprintln!(
                            "bounce: second signal ({signal}): exiting now; the rows and frames \
                             already whole are kept, the files being written removed"
                        );
                        bounce_scenario::atomic::exit_now(128 + signal);
                    }
                }
            })
            .context("cannot start the signal thread")?;
    }
    Ok(stop)
}

fn main() -> ExitCode {
    // Like other Unix tools, end quietly when the reader of standard output goes away
    // (`bounce check ... | head -1`): Rust starts with SIGPIPE ignored, so the next write
    // would fail and `println!` panic. Output files are written atomically, so a run ended
    // this way leaves none half-written.
    #[cfg(unix)]
    // SAFETY: sets a signal's default disposition at start-up, before any other thread.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Bad arguments exit with 1, like every other bad input (help and --version with 0).
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    match dispatch(cli) {
        Ok(code) => code,
        Err(e) => {
            // Scenario errors already carry file:line on each line.
            for line in format!("{e:#}").lines() {
                eprintln!("error: {line}");
            }
            ExitCode::FAILURE
        }
    }
}

fn dispatch(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::Run {
            scenario,
            out,
            steps,
            threads,
            resume,
            force,
            steer,
            quiet,
        } => {
            #[cfg(feature = "mpi")]
            let distributed = distributed::launched();
            #[cfg(not(feature = "mpi"))]
            let distributed = false;
            let threads = threads.map_or_else(
                || {
                    #[cfg(feature = "mpi")]
                    if distributed {
                        return distributed::default_threads();
                    }
                    std::thread::available_parallelism().map_or(1, |n| n.get())
                },
                usize::from,
            );
            let stop = stop_on_signals(!distributed)?;
            let (text, origin, limits) = steer.apply(&scenario)?;
            let args = run::RunArgs {
                scenario,
                out,
                steps,
                threads,
                resume,
                quiet,
                force,
                text,
                origin,
                limits,
            };
            #[cfg(feature = "mpi")]
            if distributed {
                return Ok(distributed::main(&args, stop));
            }
            let _ = distributed;
            Ok(match run::run(&args, stop)? {
                run::Outcome::Finished => ExitCode::SUCCESS,
                run::Outcome::Stopped(signal) => ExitCode::from((128 + signal.clamp(0, 127)) as u8),
            })
        }
        Command::New {
            template,
            out,
            force,
        } => {
            let Some(text) = bounce_scenario::template(&template) else {
                let names: Vec<&str> = bounce_scenario::TEMPLATES.iter().map(|(n, _)| *n).collect();
                bail!(
                    "no template named {template:?}; choose one of {}",
                    names.join(", ")
                );
            };
            match out {
                None => print!("{text}"),
                Some(path) => {
                    if path.exists() && !force {
                        bail!("{} exists; use --force to overwrite it", path.display());
                    }
                    bounce_scenario::atomic::write(&path, text.as_bytes())?;
                    eprintln!(
                        "wrote {} (run it: bounce run {})",
                        path.display(),
                        path.display()
                    );
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::View {
            scenario,
            headless_frames,
            screenshot,
        } => {
            view(scenario, headless_frames.zip(screenshot))?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Validate { quick, out } => Ok(if validate::validate(quick, &out)? {
            ExitCode::SUCCESS
        } else {
            ExitCode::FAILURE
        }),
        Command::Analyze {
            trajectory,
            out,
            first,
            r_max,
            bin,
            boundary,
        } => {
            // (clap has checked the name.)
            let edges = boundary.and_then(|b| bounce_scenario::structure::Edges::from_name(&b));
            analyze::analyze(&analyze::Request {
                trajectory: &trajectory,
                out: &out,
                first,
                r_max,
                bin,
                edges,
            })?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Sweep {
            sweep,
            out,
            jobs,
            task_id,
            job,
            slurm,
            max_jobs,
        } => {
            sweep::sweep(&sweep::Request {
                sweep: &sweep,
                out: &out,
                jobs: jobs as usize,
                task_id,
                job,
                slurm,
                max_jobs,
            })?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Check { scenario, steer } => {
            let (text, origin, limits) = steer.apply(&scenario)?;
            let session =
                bounce_scenario::Session::from_text_in(&origin, &text, &limits, scenario.parent())?;
            let boundary = match session.world.config().boundary {
                bounce::Boundary::Open => "an open world".to_string(),
                bounce::Boundary::Walls { .. } => "walls".into(),
                bounce::Boundary::Periodic { .. } => "a periodic box".into(),
                bounce::Boundary::LeesEdwards { shear_rate, .. } => {
                    format!("a Lees–Edwards box sheared at {shear_rate}")
                }
            };
            println!(
                "{}: ok: {} particles, {} steps of dt {}, {boundary}",
                session.origin,
                session.world.len(),
                session.steps,
                session.dt,
            );
            println!("{}", session.time_step_report());
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// `bounce view`: the window, when this bounce was built with the viewer.
#[cfg(feature = "view")]
fn view(scenario: Option<PathBuf>, headless: Option<(u32, PathBuf)>) -> Result<()> {
    let headless =
        headless.map(|(frames, screenshot)| bounce_viewer::Headless { frames, screenshot });
    bounce_viewer::run(bounce_viewer::Options { scenario, headless })
        .map_err(|e| anyhow::anyhow!(e))
}

/// `bounce view` in a build without the viewer (`--no-default-features`, for clusters).
#[cfg(not(feature = "view"))]
fn view(_scenario: Option<PathBuf>, _headless: Option<(u32, PathBuf)>) -> Result<()> {
    bail!(
        "this bounce was built without the viewer (cargo feature `view`); \
         install it with: cargo install --path crates/bounce-cli"
    )
}
