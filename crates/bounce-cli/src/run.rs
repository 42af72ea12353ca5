//! `bounce run`: a scenario stepped headless, with every output it asks for.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use std::ops::ControlFlow;

use anyhow::{Context, Result, anyhow, bail};
use bounce::World;
use bounce_scenario::Session;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::checkpoint;
use crate::gsd::GsdWriter;
use crate::plots::{self, Sample};
use crate::render::{GifWriter, Painter, save_png};
use crate::stats_csv::StatsCsv;

/// What `bounce run` was asked to do.
pub struct RunArgs {
    pub scenario: PathBuf,
    pub out: PathBuf,
    pub steps: Option<u64>,
    pub threads: usize,
    pub resume: Option<PathBuf>,
    pub quiet: bool,
}

/// How a run ended.
pub enum Outcome {
    Finished,
    Interrupted,
}

/// Runs the scenario. Ctrl-C finishes the current step, writes everything and returns
/// [`Outcome::Interrupted`].
pub fn run(args: &RunArgs, interrupted: Arc<AtomicBool>) -> Result<Outcome> {
    let mut session = Session::load(&args.scenario)?;
    prepare_out_dir(&args.out)?;
    if let Some(path) = &args.resume {
        let world = checkpoint::load(path)?;
        session
            .resume(world, &path.display().to_string())
            .map_err(|e| anyhow!(e))?;
    }
    session
        .world
        .set_threads(args.threads)
        .context("cannot start the worker threads")?;
    let total = args.steps.unwrap_or(session.steps);

    let mut outputs = Outputs::create(&session, &args.out)?;
    let world = &session.world;
    let start_step = world.step_count();
    if start_step >= total {
        bail!(
            "nothing to do: the world is at step {start_step} and the run ends at step {total} (use --steps)"
        );
    }
    let energy_start = world.stats().kinetic_energy;
    outputs.record(world, true)?;

    let progress = progress_bar(total - start_step, args.quiet);
    let clock = Instant::now();
    let mut collisions = 0usize;
    let reached = session.run_until(total, |world, stats| -> Result<_> {
        collisions += stats.pairs;
        outputs.stats.accumulate(stats);
        outputs.record(world, world.step_count() == total)?;
        progress.inc(1);
        Ok(if interrupted.load(Ordering::SeqCst) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        })
    })?;
    let outcome = if reached {
        Outcome::Finished
    } else {
        Outcome::Interrupted
    };
    let world = &session.world;
    progress.finish_and_clear();
    let wall = clock.elapsed().as_secs_f64();
    let ran = world.step_count() - start_step;
    outputs.finish(world)?;

    let energy_end = world.stats().kinetic_energy;
    let change = if energy_start != 0.0 {
        format!("{:+.3e}", energy_end / energy_start - 1.0)
    } else {
        "n/a (started at rest)".into()
    };
    println!(
        "{}: {} particles, {ran} steps (to step {}) in {wall:.2} s, {:.1} steps/s, {collisions} collisions, relative energy change {change}, state hash {:016x}",
        session.title,
        world.len(),
        world.step_count(),
        ran as f64 / wall.max(1e-9),
        world.state_hash(),
    );
    println!("outputs in {}", args.out.display());
    if let Outcome::Interrupted = outcome {
        eprintln!(
            "interrupted at step {} of {total}; continue with: bounce run {} --out {} --resume {}",
            world.step_count(),
            args.scenario.display(),
            args.out.display(),
            args.out.join("checkpoint.bin").display()
        );
    }
    Ok(outcome)
}

fn prepare_out_dir(out: &Path) -> Result<()> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create the output directory {}", out.display()))?;
    tempfile::NamedTempFile::new_in(out)
        .with_context(|| format!("cannot write in the output directory {}", out.display()))?;
    Ok(())
}

fn progress_bar(steps: u64, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(steps), ProgressDrawTarget::hidden());
    }
    let bar = ProgressBar::new(steps);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} step {pos}/{len}  {per_sec}  ETA {eta}")
            .expect("valid template"),
    );
    bar
}

/// The files a run writes, opened at the start and completed at the end.
struct Outputs {
    spec: bounce_scenario::OutputSpec,
    dir: PathBuf,
    stats: StatsCsv,
    painter: Option<Painter>,
    gif: Option<GifWriter>,
    gsd: Option<GsdWriter>,
    history: Vec<Sample>,
    total_mass: f64,
}

impl Outputs {
    fn create(session: &Session, dir: &Path) -> Result<Self> {
        let (spec, world) = (session.output.clone(), &session.world);
        let total_mass: f64 = bounce_scenario::analysis::masses(world).iter().sum();
        let painter = (spec.frame_every > 0).then(|| {
            Painter::new(
                world,
                session.view,
                spec.frame_width,
                session.colour_by,
                session.colours.clone(),
            )
        });
        if painter.is_some() {
            std::fs::create_dir_all(dir.join("frames"))
                .with_context(|| format!("cannot create {}", dir.join("frames").display()))?;
        }
        let gif = match (&painter, spec.gif) {
            (Some(p), true) => Some(GifWriter::create(&dir.join("animation.gif"), p.size())?),
            _ => None,
        };
        let gsd = if spec.gsd_every > 0 {
            Some(GsdWriter::create(&dir.join("trajectory.gsd"))?)
        } else {
            None
        };
        Ok(Outputs {
            stats: StatsCsv::create(dir, total_mass)?,
            spec,
            dir: dir.to_path_buf(),
            painter,
            gif,
            gsd,
            history: Vec::new(),
            total_mass,
        })
    }

    /// Writes what is due at the world's current step (`force`: the first or last step).
    fn record(&mut self, world: &World, force: bool) -> Result<()> {
        let step = world.step_count();
        let due = |every: u64| every > 0 && step.is_multiple_of(every);
        if due(self.spec.stats_every) || force {
            self.stats.row(world)?;
            let s = world.stats();
            self.history.push(Sample {
                time: world.time(),
                energy: s.kinetic_energy,
                momentum: s.momentum,
            });
        }
        if let Some(painter) = &self.painter
            && (due(self.spec.frame_every) || force)
        {
            let pixmap = painter.paint(world);
            save_png(
                &pixmap,
                &self.dir.join("frames").join(format!("frame_{step:07}.png")),
            )?;
            if let Some(gif) = &mut self.gif {
                gif.add(&pixmap)?;
            }
        }
        if let Some(gsd) = &mut self.gsd
            && (due(self.spec.gsd_every) || force)
        {
            gsd.frame(world)?;
        }
        if due(self.spec.checkpoint_every) && !force {
            checkpoint::save(world, &self.dir.join("checkpoint.bin"))?;
        }
        Ok(())
    }

    fn finish(self, world: &World) -> Result<()> {
        checkpoint::save(world, &self.dir.join("checkpoint.bin"))?;
        self.stats.finish()?;
        if let Some(gif) = self.gif {
            gif.finish()?;
        }
        if let Some(gsd) = self.gsd {
            gsd.finish()?;
        }
        if self.spec.plots {
            plots::draw(
                &self.history,
                world,
                self.total_mass,
                &self.dir.join("plots.png"),
            )?;
        }
        Ok(())
    }
}
