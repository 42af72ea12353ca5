//! `bounce run`: a scenario stepped headless, with every output it asks for.
//!
//! Outputs follow a schedule: a row, frame or GSD frame at step 0, at every multiple of its
//! interval, and at the last step. A run stopped early (a signal) finishes its step, writes
//! its last step everywhere and a checkpoint, and exits with 128 + the signal. A resumed run
//! (`--resume` into the same folder) first drops what came after the checkpoint's step and the
//! stopped run's extra last step, then continues the same files: the result equals an
//! uninterrupted run's, byte for byte for `stats.csv` and the GSD.

use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use bounce::{StepError, World};
use bounce_scenario::Session;
use bounce_scenario::analysis::mechanical_energy;
use bounce_scenario::checkpoint::RunState;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::checkpoint;
use crate::events_csv::EventsCsv;
use crate::observables_csv::ObservablesCsv;
use crate::plots;
use crate::render::{GifWriter, Painter, frame_files, gif_from_frames, save_png};
use crate::stats_csv::{ScenarioColumns, StatsCsv, Totals, read_history};
use bounce_scenario::gsd::GsdWriter;
use bounce_scenario::headline::{self, Headline, HeadlineKind, Rows};

/// What `bounce run` was asked to do.
pub struct RunArgs {
    pub scenario: PathBuf,
    pub out: PathBuf,
    pub steps: Option<u64>,
    pub threads: usize,
    pub resume: Option<PathBuf>,
    pub quiet: bool,
    pub force: bool,
    /// The scenario after `--set` and `--seed`, and the name to give it.
    pub text: String,
    pub origin: String,
    pub limits: bounce_scenario::Limits,
}

/// How a run ended.
pub enum Outcome {
    Finished,
    /// Stopped by this signal.
    Stopped(i32),
}

/// The files of a run in its folder: what `--force` clears.
const RUN_FILES: [&str; 10] = [
    "stats.csv",
    "summary.json",
    "animation.gif",
    "trajectory.gsd",
    "plots.png",
    "checkpoint.bin",
    "events.csv",
    "profile.csv",
    "msd.csv",
    "collisions.csv",
];

/// Runs the scenario. A signal number stored in `stop` finishes the current step, writes
/// everything and returns [`Outcome::Stopped`].
pub fn run(args: &RunArgs, stop: Arc<AtomicUsize>) -> Result<Outcome> {
    let setup = Instant::now();
    let (mut session, run_state, total) = load_session(args)?;
    prepare_out_dir(&args.out, args.resume.is_some(), args.force)?;
    // Kept to replay from, should a step overflow.
    let start_world = checkpoint::encode(&session.world, run_state.as_ref())?;
    session
        .world
        .set_threads(args.threads)
        .context("cannot start the worker threads")?;
    let start_step = session.world.step_count();

    let time_step = session.time_step_report();
    let energy_start = mechanical_energy(&session.world);
    if !energy_start.is_finite() {
        bail!(
            "{}: the potential energy in the gravity field overflows f64 at the start (gravity \
             {:?} is too strong for these positions)",
            session.origin,
            session.world.config().gravity
        );
    }
    let mut outputs = Outputs::start(&session, &args.out, total, run_state)?;
    let setup_time = setup.elapsed().as_secs_f64();

    let progress = progress_bar(total - start_step, args.quiet);
    let clock = Instant::now();
    let mut output_time = 0.0;
    let mut collisions = 0usize;
    let dt = session.dt;
    let stepped = session.run_until_stopped(total, &stop, |world, stats| -> Result<_> {
        let t = Instant::now();
        collisions += stats.collisions;
        outputs.stats.totals.add(stats, world, world.sensors(), dt);
        outputs.record(world)?;
        progress.inc(1);
        output_time += t.elapsed().as_secs_f64();
        Ok(if stop.load(Ordering::SeqCst) != 0 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        })
    });
    progress.finish_and_clear();
    let reached = match stepped {
        Ok(reached) => reached,
        Err(e) => match e.downcast::<StepError>() {
            Ok(StepError::NonFinite { step, id }) => {
                return overflowed(args, &start_world, outputs, step - 1, &id);
            }
            Ok(e) => return Err(e.into()),
            // An output failed (a value its format cannot hold, a full disk): what was written
            // is kept.
            Err(e) => return Err(outputs.salvage(&session.world, e)),
        },
    };
    let physics_time = (clock.elapsed().as_secs_f64() - output_time).max(0.0);
    let world = &session.world;
    let t = Instant::now();
    let ran = world.step_count() - start_step;
    let headline = outputs.finish(world, !reached, Some((physics_time, ran)))?;
    output_time += t.elapsed().as_secs_f64();

    let report = Report {
        title: &session.title,
        ran: world.step_count() - start_step,
        total,
        collisions,
        energy_start,
        physics_time,
        output_time,
        setup_time,
        time_step: time_step.to_string(),
        headline,
    };
    report.print(args, world);
    Ok(report.outcome(args, world, reached, &stop))
}

/// What `bounce run` says at the end of a run (one process or many).
pub(crate) struct Report<'a> {
    pub title: &'a str,
    /// Steps taken in this run.
    pub ran: u64,
    /// The step the run ends at.
    pub total: u64,
    pub collisions: usize,
    pub energy_start: f64,
    pub physics_time: f64,
    pub output_time: f64,
    pub setup_time: f64,
    pub time_step: String,
    /// What the run demonstrates, measured (`[output] headline`).
    pub headline: Option<String>,
}

impl Report<'_> {
    /// The summary: particles, steps, collisions, the energy's drift, the state hash, times.
    pub(crate) fn print(&self, args: &RunArgs, world: &World) {
        let energy_end = mechanical_energy(world);
        let what = if world.config().gravity == [0.0, 0.0] {
            "relative energy change"
        } else {
            "relative change of kinetic + potential energy"
        };
        let change = if self.energy_start != 0.0 {
            format!("{:+.3e}", energy_end / self.energy_start - 1.0)
        } else {
            "n/a (started with zero energy)".into()
        };
        println!(
            "{}: {} particles, {} steps (to step {}), {} collisions, {what} {change}, state hash {:016x}",
            self.title,
            world.len(),
            self.ran,
            world.step_count(),
            self.collisions,
            world.state_hash(),
        );
        // Event-driven runs are measured in collisions: a step is only an observation.
        let rate = if world.config().method == bounce::Method::EventDriven {
            format!(
                "{:.3e} collisions/s",
                self.collisions as f64 / self.physics_time.max(1e-9)
            )
        } else {
            format!(
                "{:.1} steps/s",
                self.ran as f64 / self.physics_time.max(1e-9)
            )
        };
        println!(
            "time: physics {:.2} s ({rate}), outputs {:.2} s, setup {:.2} s",
            self.physics_time, self.output_time, self.setup_time,
        );
        if let Some(headline) = &self.headline {
            println!("{headline}");
        }
        println!("{}", self.time_step);
        println!("outputs in {}", args.out.display());
    }

    /// Finished, or stopped by the stored signal (with how to continue).
    pub(crate) fn outcome(
        &self,
        args: &RunArgs,
        world: &World,
        reached: bool,
        stop: &AtomicUsize,
    ) -> Outcome {
        if reached {
            return Outcome::Finished;
        }
        let signal = stop.load(Ordering::SeqCst) as i32;
        eprintln!(
            "interrupted by signal {signal} at step {} of {}; continue with: bounce run {} --out {} --resume {}",
            world.step_count(),
            self.total,
            args.scenario.display(),
            args.out.display(),
            args.out.join("checkpoint.bin").display()
        );
        Outcome::Stopped(signal)
    }
}

/// The run's scenario (resumed from `--resume`'s checkpoint, with the totals it kept, when
/// given) and the step the run ends at; refused when there is nothing to do.
pub(crate) fn load_session(args: &RunArgs) -> Result<(Session, Option<RunState>, u64)> {
    let mut session = Session::from_text_in(
        &args.origin,
        &args.text,
        &args.limits,
        args.scenario.parent(),
    )?;
    let mut run_state = None;
    if let Some(path) = &args.resume {
        let loaded = checkpoint::load(path)?;
        session
            .resume(loaded.world, &path.display().to_string())
            .map_err(|e| anyhow!(e))?;
        run_state = Some(loaded.run.unwrap_or_default());
    }
    let total = args.steps.unwrap_or(session.steps);
    let start_step = session.world.step_count();
    if start_step >= total {
        bail!(
            "nothing to do: the world is at step {start_step} and the run ends at step {total} (use --steps)"
        );
    }
    Ok((session, run_state, total))
}

/// The step after `step` overflowed: the outputs up to `step`, the last finite one, are kept
/// and completed, a checkpoint of it is written (replayed from the run's start: runs are
/// deterministic), and the run fails naming the step and the particle.
fn overflowed(
    args: &RunArgs,
    start: &[u8],
    outputs: Outputs,
    step: u64,
    id: &str,
) -> Result<Outcome> {
    let loaded =
        bounce_scenario::checkpoint::decode(start, "the run's start").map_err(|e| anyhow!(e))?;
    let mut world = loaded.world;
    world.set_threads(args.threads)?;
    let mut totals = Totals::resumed(loaded.run.unwrap_or_default());
    let schedule = &outputs.schedule;
    let dt = outputs.dt;
    while world.step_count() < step {
        let stats = *world.step(dt)?;
        totals.add(&stats, &world, world.sensors(), dt);
        if schedule.on(schedule.output.stats_every, world.step_count()) {
            totals.reset(true, outputs.stats.row_energy(&world));
        }
    }
    outputs.finish_at(&world, totals.checkpoint(), None)?;
    bail!(
        "step {}: particle {id} has a non-finite position, velocity or kinetic energy: dt, gravity or speeds \
         are too large for f64. Outputs and checkpoint.bin hold the run up to step {step}.",
        step + 1
    )
}

/// Creates the folder; refuses one holding another run's files unless resuming or `force`
/// (which clears them); removes temporary files a killed run left.
pub(crate) fn prepare_out_dir(out: &Path, resume: bool, force: bool) -> Result<()> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create the output directory {}", out.display()))?;
    let frames = out.join("frames");
    for dir in [out, frames.as_path()] {
        for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            let name = entry.file_name();
            if name
                .to_str()
                .is_some_and(|n| n.starts_with(bounce_scenario::atomic::TEMP_PREFIX))
            {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
    let previous: Vec<String> = RUN_FILES
        .iter()
        .filter(|f| out.join(f).exists())
        .map(|f| f.to_string())
        .chain((!frame_files(&frames).is_empty()).then(|| "frames/".to_string()))
        .collect();
    if !previous.is_empty() && !resume {
        if !force {
            bail!(
                "{} holds another run's files ({}): use --force to replace them, --resume to \
                 continue that run, or another --out",
                out.display(),
                previous.join(", ")
            );
        }
        for f in RUN_FILES {
            let _ = std::fs::remove_file(out.join(f));
        }
        for (_, frame) in frame_files(&frames) {
            std::fs::remove_file(&frame)
                .with_context(|| format!("cannot remove {}", frame.display()))?;
        }
    }
    tempfile::NamedTempFile::new_in(out)
        .with_context(|| format!("cannot write in the output directory {}", out.display()))?;
    Ok(())
}

pub(crate) fn progress_bar(steps: u64, quiet: bool) -> ProgressBar {
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

/// When each output is due.
pub(crate) struct Schedule {
    pub total: u64,
    pub output: bounce_scenario::OutputSpec,
}

/// On the schedule of an output written every `every` steps (and at step 0).
fn on_schedule(every: u64, step: u64) -> bool {
    step == 0 || (every > 0 && step.is_multiple_of(every))
}

impl Schedule {
    /// On the schedule of an output written every `every` steps (and at step 0).
    fn on(&self, every: u64, step: u64) -> bool {
        on_schedule(every, step)
    }

    /// Due at `step`: on the schedule, or the run's last step.
    fn due(&self, every: u64, step: u64) -> bool {
        self.on(every, step) || step == self.total
    }

    /// Whether any output (or a checkpoint) is written at `step`.
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub(crate) fn any_due(&self, step: u64) -> bool {
        let o = &self.output;
        [o.stats_every, o.frame_every, o.gsd_every]
            .into_iter()
            .zip([true, o.frame_every > 0, o.gsd_every > 0])
            .any(|(every, on)| on && self.due(every, step))
            || (o.checkpoint_every > 0 && step > 0 && self.on(o.checkpoint_every, step))
    }
}

/// Whether the scenario asks for `profile.csv` or `msd.csv`.
fn wants_observables(session: &Session) -> bool {
    session.output.profile.is_some() || session.output.msd
}

/// The files a run writes, opened at the start and completed at the end.
pub(crate) struct Outputs {
    pub schedule: Schedule,
    dir: PathBuf,
    dt: f64,
    pub stats: StatsCsv,
    painter: Option<Painter>,
    /// The GIF, built as frames are painted; `None` when resumed (then redrawn from the
    /// frame files at the end).
    gif: Option<GifWriter>,
    gsd: Option<GsdWriter>,
    /// `events.csv`, with `[output] events`.
    events: Option<EventsCsv>,
    /// `profile.csv` and `msd.csv`, with `[output] profile` or `msd`.
    observables: Option<ObservablesCsv>,
    total_mass: f64,
    /// The last step each of stats, frames and GSD was written at, so a stop does not write
    /// a step twice.
    recorded: [Option<u64>; 3],
    /// Each emitter's colour and type, for the discs it adds.
    emitted: Vec<(Option<bounce_scenario::Rgb>, u32)>,
    /// The first named moving segment, when the box has walls: plots show its pressure.
    piston: Option<(String, bounce_scenario::Piston)>,
    /// What the run's headline is measured from, with `[output] headline`.
    headline: Option<HeadlineSetup>,
}

/// What a headline is measured from besides the run's files, kept from its start: the
/// scenario, its world at step 0 (built anew for a resumed run) and the discs' types.
struct HeadlineSetup {
    kind: HeadlineKind,
    scenario: bounce_scenario::Scenario,
    start: Option<World>,
    typeid: Vec<u32>,
}

impl HeadlineSetup {
    fn new(session: &Session) -> Result<Option<Self>> {
        let Some(kind) = session.output.headline else {
            return Ok(None);
        };
        // The throughput needs no start; a million discs are not built twice for it.
        let start = if kind == HeadlineKind::Throughput {
            None
        } else {
            let fresh = Session::from_text_in(
                &session.origin,
                &session.text,
                &bounce_scenario::Limits::default(),
                session.scenario.dir.as_deref(),
            )?;
            Some(fresh.world)
        };
        Ok(Some(HeadlineSetup {
            kind,
            scenario: session.scenario.clone(),
            start,
            typeid: session.typeid.clone(),
        }))
    }

    /// Measures the headline on the run's files in `dir` and its last world.
    fn measure(
        &self,
        world: &World,
        dir: &Path,
        timing: Option<(f64, u64)>,
    ) -> Result<Headline, String> {
        let stats = std::fs::read_to_string(dir.join("stats.csv")).map_err(|e| e.to_string())?;
        let rows = Rows::parse(&stats);
        let gsd = dir.join("trajectory.gsd");
        let frames = if matches!(self.kind, HeadlineKind::Diffusion | HeadlineKind::Mixing)
            && gsd.exists()
        {
            bounce_scenario::trajectory::Trajectory::open(&gsd)?.snapshots(0, None)?
        } else {
            Vec::new()
        };
        let run = headline::Run {
            scenario: &self.scenario,
            start: self.start.as_ref().unwrap_or(world),
            end: world,
            typeid: &self.typeid,
            rows: &rows,
            frames: &frames,
            physics_seconds: timing.map(|t| t.0),
            steps_run: timing.map_or(0, |t| t.1),
        };
        headline::measure(self.kind, &run)
    }
}

impl Outputs {
    /// The outputs of a run to step `total` in `dir`: continued from a checkpoint's totals
    /// (`run`), or created with the starting step written.
    pub(crate) fn start(
        session: &Session,
        dir: &Path,
        total: u64,
        run: Option<RunState>,
    ) -> Result<Self> {
        let schedule = Schedule {
            total,
            output: session.output.clone(),
        };
        Ok(match run {
            Some(run) => Outputs::resume(session, dir, schedule, run)?,
            None => {
                let mut outputs = Outputs::create(session, dir, schedule)?;
                outputs.record(&session.world)?;
                outputs
            }
        })
    }

    fn create(session: &Session, dir: &Path, schedule: Schedule) -> Result<Self> {
        let world = &session.world;
        let total_mass = bounce_scenario::analysis::total_mass(world);
        let gsd = if schedule.output.gsd_every > 0 {
            Some(GsdWriter::create(
                &dir.join("trajectory.gsd"),
                &session.types,
                &session.typeid,
            )?)
        } else {
            None
        };
        let mut outputs = Self::open(
            session,
            dir,
            schedule,
            StatsCsv::create(dir, total_mass, ScenarioColumns::of(session))?,
            gsd,
            total_mass,
        )?;
        if outputs.schedule.output.events {
            outputs.events = Some(EventsCsv::create(dir, session)?);
        }
        if wants_observables(session) {
            outputs.observables = Some(ObservablesCsv::create(dir, session)?);
        }
        outputs.gif = match (&outputs.painter, outputs.schedule.output.gif) {
            (Some(p), true) => Some(GifWriter::create(&dir.join("animation.gif"), p.size())?),
            _ => None,
        };
        Ok(outputs)
    }

    /// Continues the outputs in `dir` from the world's step (a checkpoint's).
    fn resume(session: &Session, dir: &Path, schedule: Schedule, run: RunState) -> Result<Self> {
        let world = &session.world;
        let k = world.step_count();
        let total_mass = bounce_scenario::analysis::total_mass(world);
        // Everything before the checkpoint's step, and at it only what the schedule has
        // there (not the extra last step of a stopped run).
        let keep = |every: u64| move |step: u64| step < k || (step == k && on_schedule(every, k));
        // The last step on the schedule up to the checkpoint's: the files must reach it.
        let through = |every: u64| Some(if every > 0 { k - k % every } else { 0 });
        let spec = &schedule.output;
        let observables = if wants_observables(session) {
            let origin = run.origin.clone();
            Some(ObservablesCsv::resume(
                dir,
                session,
                &keep(spec.stats_every),
                through(spec.stats_every),
                origin,
            )?)
        } else {
            None
        };
        let stats = StatsCsv::resume(
            dir,
            total_mass,
            ScenarioColumns::of(session),
            keep(spec.stats_every),
            through(spec.stats_every),
            run,
        )?;
        let gsd = if spec.gsd_every > 0 {
            Some(GsdWriter::resume(
                &dir.join("trajectory.gsd"),
                &session.types,
                &session.typeid,
                keep(spec.gsd_every),
            )?)
        } else {
            None
        };
        if let (Some(gsd), Some(through)) = (&gsd, through(spec.gsd_every))
            && gsd.last_step().is_some_and(|last| last < through)
        {
            bail!(
                "{}: its frames end at step {}, but the checkpoint's run wrote frames through \
                 step {through}: they are gone (cut short after the checkpoint was saved), and \
                 continuing would leave a hole; resume into a folder holding the run's whole \
                 files, or start the run anew",
                dir.join("trajectory.gsd").display(),
                gsd.last_step().unwrap_or(0)
            );
        }
        let keep_frame = keep(spec.frame_every);
        for (step, frame) in frame_files(&dir.join("frames")) {
            if !keep_frame(step) {
                std::fs::remove_file(&frame)
                    .with_context(|| format!("cannot remove {}", frame.display()))?;
            }
        }
        let mut outputs = Self::open(session, dir, schedule, stats, gsd, total_mass)?;
        if outputs.schedule.output.events {
            outputs.events = Some(EventsCsv::resume(dir, session, k)?);
        }
        outputs.observables = observables;
        outputs.recorded = [Some(k); 3];
        Ok(outputs)
    }

    fn open(
        session: &Session,
        dir: &Path,
        schedule: Schedule,
        stats: StatsCsv,
        gsd: Option<GsdWriter>,
        total_mass: f64,
    ) -> Result<Self> {
        let world = &session.world;
        let spec = &schedule.output;
        let painter = (spec.frame_every > 0).then(|| {
            Painter::new(
                world,
                session.view,
                spec.frame_width,
                session.colour_by,
                session.colours.clone(),
            )
            .with_obstacle_colours(session.obstacle_colours())
            .with_key(session.colour_key())
        });
        if painter.is_some() {
            std::fs::create_dir_all(dir.join("frames"))
                .with_context(|| format!("cannot create {}", dir.join("frames").display()))?;
        }
        Ok(Outputs {
            total_mass,
            schedule,
            dir: dir.to_path_buf(),
            dt: session.dt,
            stats,
            painter,
            gif: None,
            gsd,
            events: None,
            observables: None,
            recorded: [None; 3],
            emitted: session.emitted.clone(),
            piston: session.piston(),
            headline: HeadlineSetup::new(session)?,
        })
    }

    /// Writes what is due at the world's current step; with `last`, everything (the last
    /// step of a stopped run).
    fn write(&mut self, world: &World, last: bool) -> Result<()> {
        // Discs the emitters added take their emitter's colour and type.
        for &(id, k) in world.emitted_last_step() {
            let (colour, kind) = self.emitted.get(k as usize).copied().unwrap_or((None, 0));
            if let Some(painter) = &mut self.painter {
                painter.set_colour(id.0 as usize, colour);
            }
            if let Some(gsd) = &mut self.gsd {
                gsd.set_type(id.0 as usize, kind);
            }
        }
        if let Some(events) = &mut self.events {
            events.step(world, self.dt)?;
        }
        let step = world.step_count();
        let spec = self.schedule.output.clone();
        let mut due = |output: usize, every: u64| {
            let due =
                self.recorded[output] != Some(step) && (last || self.schedule.due(every, step));
            if due {
                self.recorded[output] = Some(step);
            }
            due
        };
        let (stats_due, frame_due, gsd_due) = (
            due(0, spec.stats_every),
            due(1, spec.frame_every),
            due(2, spec.gsd_every),
        );
        if stats_due {
            let scheduled = self.schedule.on(spec.stats_every, step);
            self.stats.row(world, scheduled)?;
            if let Some(observables) = &mut self.observables {
                observables.row(world)?;
            }
        }
        if let Some(painter) = &self.painter
            && frame_due
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
            && gsd_due
        {
            gsd.frame(world)?;
        }
        if self.schedule.on(spec.checkpoint_every, step) && spec.checkpoint_every > 0 && step > 0 {
            checkpoint::save(
                world,
                Some(&self.run_state()),
                &self.dir.join("checkpoint.bin"),
            )?;
        }
        Ok(())
    }

    /// A distributed run's step `step` (ending at `end`, in `substeps`): its contact events,
    /// from the whole world's log that rank 0 keeps.
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub(crate) fn contact_events(
        &mut self,
        step: u64,
        end: f64,
        substeps: u32,
        events: &[bounce::ContactEvent],
    ) -> Result<()> {
        match &mut self.events {
            Some(file) => file.write(step, end, self.dt, substeps, events),
            None => Ok(()),
        }
    }

    /// What a checkpoint keeps of the run: the totals as the schedule has them, and the
    /// origin `msd.csv` measures from.
    fn run_state(&self) -> RunState {
        RunState {
            origin: self.observables.as_ref().and_then(ObservablesCsv::origin),
            ..self.stats.totals.checkpoint()
        }
    }

    /// Writes what is due at the world's current step.
    pub(crate) fn record(&mut self, world: &World) -> Result<()> {
        self.write(world, false)
    }

    /// Completes every file at `world`'s step after an output failed there (a value its format
    /// cannot hold, a full disk), so that no failure loses the run: each output stays
    /// readable up to the last step it was written for, with a checkpoint of this state.
    /// Returns `error`, saying what was kept.
    pub(crate) fn salvage(self, world: &World, error: anyhow::Error) -> anyhow::Error {
        let step = world.step_count();
        let totals = self.run_state();
        match self.finish_at(world, totals, None) {
            Ok(_) => anyhow!(
                "{error:#}\nThe outputs hold the run up to the last step each was written for, \
                 and checkpoint.bin its state at step {step}."
            ),
            Err(also) => anyhow!("{error:#}\nThe outputs could not be completed either: {also:#}"),
        }
    }

    /// Completes every file; `stopped`: the run ends before its last step, which is then
    /// written everywhere. `timing`, the physics' seconds and the steps it took, goes into
    /// a throughput headline. Returns the headline's line for the summary, with
    /// `[output] headline`.
    pub(crate) fn finish(
        mut self,
        world: &World,
        stopped: bool,
        timing: Option<(f64, u64)>,
    ) -> Result<Option<String>> {
        // The checkpoint keeps the totals as the schedule has them, before the extra row.
        let totals = self.run_state();
        if stopped {
            self.write(world, true)?;
        }
        self.finish_at(world, totals, timing)
    }

    /// Writes the checkpoint of `world` with `totals` and completes the files; measures the
    /// headline (into `summary.json`, and `plots.png`).
    fn finish_at(
        self,
        world: &World,
        totals: RunState,
        timing: Option<(f64, u64)>,
    ) -> Result<Option<String>> {
        checkpoint::save(world, Some(&totals), &self.dir.join("checkpoint.bin"))?;
        if let Some(counts) = world.collision_counts() {
            write_collisions(world, &counts, &self.dir.join("collisions.csv"))?;
        }
        self.stats.finish()?;
        if let Some(events) = self.events {
            events.finish()?;
        }
        if let Some(observables) = self.observables {
            observables.finish()?;
        }
        if let Some(gsd) = self.gsd {
            gsd.finish()?;
        }
        let headline = self
            .headline
            .as_ref()
            .map(|setup| setup.measure(world, &self.dir, timing));
        if let Some(Ok(headline)) = &headline {
            bounce_scenario::atomic::write(
                &self.dir.join("summary.json"),
                headline.to_json().as_bytes(),
            )
            .with_context(|| format!("cannot write {}", self.dir.join("summary.json").display()))?;
        }
        // A resumed run's GIF and plots are drawn from the whole run's files.
        if let Some(gif) = self.gif {
            gif.finish()?;
        } else if let Some(painter) = &self.painter
            && self.schedule.output.gif
        {
            let frames = frame_files(&self.dir.join("frames"));
            gif_from_frames(&frames, painter.size(), &self.dir.join("animation.gif"))?;
        }
        if self.schedule.output.plots {
            let history = read_history(
                &self.dir.join("stats.csv"),
                self.piston.as_ref().map(|(name, _)| name.as_str()),
            )?;
            plots::draw(
                &history,
                world,
                self.total_mass,
                self.piston.as_ref().map(|(_, p)| p),
                headline.as_ref().and_then(|h| h.as_ref().ok()),
                &self.dir.join("plots.png"),
            )?;
        }
        Ok(headline.map(|h| match h {
            Ok(h) => format!("headline: {}", h.summary()),
            Err(e) => format!("headline: not measured: {e}"),
        }))
    }
}

/// `collisions.csv`: each disc present at the end, in id order, with its radius and its
/// collisions with other discs over the whole run.
fn write_collisions(world: &World, counts: &[u64], path: &Path) -> Result<()> {
    use std::fmt::Write as _;
    let mut text = String::from("id,radius,collisions\n");
    for (id, index) in world.in_id_order() {
        let radius = world.particles().radius()[index];
        let _ = writeln!(text, "{},{radius},{}", id.0, counts[id.0 as usize]);
    }
    bounce_scenario::atomic::write(path, text.as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))
}
