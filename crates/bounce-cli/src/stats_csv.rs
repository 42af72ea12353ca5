//! `stats.csv`: one row every `stats_every` steps, plus the first and the last step.
//!
//! Columns: `step,time,kinetic_energy,momentum_x,momentum_y,collisions,wall_impulse,
//! max_overlap,temperature,potential_energy,pressure,substeps`. `pressure` is the step's
//! collision-virial pressure (empty in an open world, which has no area); `substeps` the
//! substeps the step took (more than `time.substeps` with `time.max_travel`). `collisions`, `wall_impulse` and `max_overlap`
//! cover the steps since the previous row (the first row, at the starting step, has zeros
//! there).
//!
//! A run that stops early (Ctrl-C, SIGTERM) writes a row for its last step too. A resumed
//! run drops the rows after its checkpoint's step, and that extra row, and continues from
//! the totals the checkpoint kept, so its file equals an uninterrupted run's byte for byte.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
use bounce::{StepStats, World};
use bounce_scenario::atomic::AtomicFile;
use bounce_scenario::checkpoint::RunState;

/// The header, in order.
pub const COLUMNS: [&str; 12] = [
    "step",
    "time",
    "kinetic_energy",
    "momentum_x",
    "momentum_y",
    "collisions",
    "wall_impulse",
    "max_overlap",
    "temperature",
    "potential_energy",
    "pressure",
    "substeps",
];

/// Running totals since the previous row.
#[derive(Clone, Copy, Debug, Default)]
pub struct Totals {
    /// Since the previous row of any kind: what the next row reports.
    row: RunState,
    /// Since the previous row on the schedule: what a checkpoint keeps, since a resumed run
    /// drops an off-schedule row.
    scheduled: RunState,
}

impl Totals {
    /// Continues from a checkpoint's totals.
    pub fn resumed(run: RunState) -> Self {
        Totals {
            row: run,
            scheduled: run,
        }
    }

    /// Adds one step.
    pub fn add(&mut self, stats: &StepStats) {
        for t in [&mut self.row, &mut self.scheduled] {
            t.collisions += stats.pairs as u64;
            t.wall_impulse += stats.wall_impulse.total();
            t.max_overlap = t.max_overlap.max(stats.max_overlap);
        }
    }

    /// A row was written (`scheduled`: on the schedule, not a run's extra last row).
    pub fn reset(&mut self, scheduled: bool) {
        self.row = RunState::default();
        if scheduled {
            self.scheduled = RunState::default();
        }
    }

    /// What a checkpoint keeps.
    pub fn checkpoint(&self) -> RunState {
        self.scheduled
    }
}

/// Accumulates per-step statistics and writes rows.
pub struct StatsCsv {
    writer: csv::Writer<AtomicFile>,
    pub totals: Totals,
    total_mass: f64,
}

impl StatsCsv {
    /// Starts `stats.csv` in `dir`; `total_mass` is the sum of the discs' masses.
    pub fn create(dir: &Path, total_mass: f64) -> Result<Self> {
        let mut writer = csv::Writer::from_writer(AtomicFile::create(&dir.join("stats.csv"))?);
        writer.write_record(COLUMNS)?;
        Ok(StatsCsv {
            writer,
            totals: Totals::default(),
            total_mass,
        })
    }

    /// Continues `stats.csv` in `dir`: keeps the header and the rows whose step passes
    /// `keep`, byte for byte, and continues from `run`'s totals. Without an earlier file,
    /// starts a new one.
    pub fn resume(
        dir: &Path,
        total_mass: f64,
        keep: impl Fn(u64) -> bool,
        run: RunState,
    ) -> Result<Self> {
        let path = dir.join("stats.csv");
        let Ok(old) = std::fs::read_to_string(&path) else {
            let mut fresh = StatsCsv::create(dir, total_mass)?;
            fresh.totals = Totals::resumed(run);
            return Ok(fresh);
        };
        let mut lines = old.lines();
        if lines.next() != Some(COLUMNS.join(",").as_str()) {
            bail!(
                "{}: not the stats.csv of this bounce (its header differs); resume into the \
                 run's own folder or use a new one",
                path.display()
            );
        }
        let mut file = AtomicFile::create(&path)?;
        writeln!(file, "{}", COLUMNS.join(","))?;
        for line in lines {
            let step: u64 = line
                .split(',')
                .next()
                .and_then(|s| s.parse().ok())
                .with_context(|| format!("{}: a row without a step: {line:?}", path.display()))?;
            if keep(step) {
                writeln!(file, "{line}")?;
            }
        }
        Ok(StatsCsv {
            writer: csv::WriterBuilder::new()
                .has_headers(false)
                .from_writer(file),
            totals: Totals::resumed(run),
            total_mass,
        })
    }

    /// Writes a row for the world's current state and resets the totals (`scheduled`: the
    /// row is on the schedule).
    pub fn row(&mut self, world: &World, scheduled: bool) -> Result<()> {
        let s = world.stats();
        let temperature = bounce_scenario::analysis::temperature(world, self.total_mass);
        let t = self.totals.row;
        self.writer.write_record([
            world.step_count().to_string(),
            world.time().to_string(),
            s.kinetic_energy.to_string(),
            s.momentum[0].to_string(),
            s.momentum[1].to_string(),
            t.collisions.to_string(),
            t.wall_impulse.to_string(),
            t.max_overlap.to_string(),
            temperature.to_string(),
            bounce_scenario::analysis::potential_energy(world).to_string(),
            s.pressure.map_or_else(String::new, |p| p.to_string()),
            s.substeps.to_string(),
        ])?;
        self.totals.reset(scheduled);
        Ok(())
    }

    /// Flushes and renames the file into place.
    pub fn finish(self) -> Result<()> {
        let file = self
            .writer
            .into_inner()
            .map_err(|e| e.into_error())
            .context("cannot write stats.csv")?;
        Ok(file.commit()?)
    }
}

/// One row read back: `(time, kinetic energy, momentum, potential energy)`.
pub fn read_history(path: &Path) -> Result<Vec<crate::plots::Sample>> {
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut out = Vec::new();
    for record in reader.records() {
        let record = record.with_context(|| format!("cannot read {}", path.display()))?;
        let field = |k: usize| -> f64 { record.get(k).and_then(|v| v.parse().ok()).unwrap_or(0.0) };
        out.push(crate::plots::Sample {
            time: field(1),
            energy: field(2),
            momentum: [field(3), field(4)],
            potential: field(9),
        });
    }
    Ok(out)
}
