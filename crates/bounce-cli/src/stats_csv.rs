//! `stats.csv`: one row every `stats_every` steps.
//!
//! Columns: `step,time,kinetic_energy,momentum_x,momentum_y,collisions,wall_impulse,
//! max_overlap,temperature`. `collisions`, `wall_impulse` and `max_overlap` cover the steps
//! since the previous row (the first row, at the starting step, has zeros there).

use std::path::Path;

use anyhow::{Context, Result};
use bounce::{StepStats, World};

use bounce_scenario::atomic::AtomicFile;

/// The header, in order.
pub const COLUMNS: [&str; 9] = [
    "step",
    "time",
    "kinetic_energy",
    "momentum_x",
    "momentum_y",
    "collisions",
    "wall_impulse",
    "max_overlap",
    "temperature",
];

/// Accumulates per-step statistics and writes rows.
pub struct StatsCsv {
    writer: csv::Writer<AtomicFile>,
    collisions: usize,
    wall_impulse: f64,
    max_overlap: f64,
    total_mass: f64,
}

impl StatsCsv {
    /// Starts `stats.csv` in `dir`; `total_mass` is the sum of the discs' masses.
    pub fn create(dir: &Path, total_mass: f64) -> Result<Self> {
        let mut writer = csv::Writer::from_writer(AtomicFile::create(&dir.join("stats.csv"))?);
        writer.write_record(COLUMNS)?;
        Ok(StatsCsv {
            writer,
            collisions: 0,
            wall_impulse: 0.0,
            max_overlap: 0.0,
            total_mass,
        })
    }

    /// Adds one step's statistics to the running totals.
    pub fn accumulate(&mut self, stats: &StepStats) {
        self.collisions += stats.pairs;
        self.wall_impulse += stats.wall_impulse.total();
        self.max_overlap = self.max_overlap.max(stats.max_overlap);
    }

    /// Writes a row for the world's current state and resets the totals.
    pub fn row(&mut self, world: &World) -> Result<()> {
        let s = world.stats();
        let temperature = bounce_scenario::analysis::temperature(world, self.total_mass);
        self.writer.write_record([
            world.step_count().to_string(),
            world.time().to_string(),
            s.kinetic_energy.to_string(),
            s.momentum[0].to_string(),
            s.momentum[1].to_string(),
            self.collisions.to_string(),
            self.wall_impulse.to_string(),
            self.max_overlap.to_string(),
            temperature.to_string(),
        ])?;
        self.collisions = 0;
        self.wall_impulse = 0.0;
        self.max_overlap = 0.0;
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
