//! `bounce`: run scenarios headless, start new ones from templates, check files.

mod checkpoint;
mod gsd;
mod plots;
mod render;
mod run;
mod stats_csv;

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};

/// bounce: a fast, faithful, deterministic 2D disc collision simulator.
#[derive(Parser)]
#[command(version, about)]
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
        /// Output directory (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Run until this step (overrides the scenario's time.steps).
        #[arg(long)]
        steps: Option<u64>,
        /// Worker threads (results are identical for every count); default: all cores.
        #[arg(long)]
        threads: Option<usize>,
        /// Continue from a checkpoint written by an earlier run of the same scenario.
        #[arg(long)]
        resume: Option<PathBuf>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Write a commented scenario to start from (gas, pile, newtons-cradle, brownian,
    /// mixing, million).
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
    /// Validate a scenario file and report every problem with its line.
    Check {
        /// The scenario file (TOML).
        scenario: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
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
            quiet,
        } => {
            let threads = threads
                .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
            if threads == 0 {
                bail!("--threads must be at least 1");
            }
            let interrupted = Arc::new(AtomicBool::new(false));
            let flag = interrupted.clone();
            ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst))
                .context("cannot install the Ctrl-C handler")?;
            let args = run::RunArgs {
                scenario,
                out,
                steps,
                threads,
                resume,
                quiet,
            };
            Ok(match run::run(&args, interrupted)? {
                run::Outcome::Finished => ExitCode::SUCCESS,
                run::Outcome::Interrupted => ExitCode::from(130),
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
        Command::Check { scenario } => {
            let session = bounce_scenario::Session::load(&scenario)?;
            println!(
                "{}: ok: {} particles, {} steps of dt {}, {:?} boundary",
                session.origin,
                session.world.len(),
                session.steps,
                session.dt,
                session.scenario.world.boundary
            );
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
