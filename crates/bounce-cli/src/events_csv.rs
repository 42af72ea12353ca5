//! `events.csv` (`[output] events = true`): every contact event of every step
//! ([`bounce::World::contact_events`]), one row each, in the world's order (substep by
//! substep, each by the parties' ids).
//!
//! Columns: `step,time,kind,a,b,x,y,nx,ny,normal_impulse,tangent_impulse,approach_speed`.
//! `time` is the end of the event's substep; `kind` is `begin` or `end`; `a` a disc id; `b`
//! a disc id, `wall:left|right|bottom|top`, or `obstacle:NAME` (the `[[obstacle]]`'s name)
//! or `obstacle:INDEX` (the obstacle's index among the expanded pieces, for unnamed ones);
//! `x,y` the contact point and `nx,ny` the unit normal from `a` towards `b`; the impulses are
//! what `b` gave `a` (the normal one positive when they push apart) and `approach_speed` how
//! fast `a` moved towards `b` (both 0 for `end`).
//!
//! Numbers are written in Rust's shortest round-trip form (`1e-17` rather than 17 zeros).
//!
//! Written through a temporary file and renamed into place at the end, like every output; a
//! resumed run keeps the rows up to its checkpoint's step and continues, so its file equals
//! an uninterrupted run's byte for byte.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};
use bounce::{ContactEvent, Party, World};
use bounce_scenario::Session;
use bounce_scenario::atomic::AtomicFile;

const HEADER: &str = "step,time,kind,a,b,x,y,nx,ny,normal_impulse,tangent_impulse,approach_speed";

/// The open `events.csv`.
pub struct EventsCsv {
    file: AtomicFile,
    /// Each obstacle's name in the file (`NAME` or its index).
    obstacles: Vec<String>,
    /// The last step written, so a step is never written twice.
    written: Option<u64>,
}

impl EventsCsv {
    /// Starts `events.csv` in `dir`.
    pub fn create(dir: &Path, session: &Session) -> Result<Self> {
        let mut file = AtomicFile::create(&dir.join("events.csv"))?;
        writeln!(file, "{HEADER}")?;
        Ok(EventsCsv {
            file,
            obstacles: obstacle_names(session),
            written: None,
        })
    }

    /// Continues `events.csv` in `dir` after step `k`: the rows of steps up to `k` kept byte
    /// for byte (a new file without an earlier one).
    pub fn resume(dir: &Path, session: &Session, k: u64) -> Result<Self> {
        let keep = |step: u64| step <= k;
        let Some(file) = crate::rows::continue_rows(&dir.join("events.csv"), HEADER, &keep, None)?
        else {
            return EventsCsv::create(dir, session);
        };
        Ok(EventsCsv {
            file,
            obstacles: obstacle_names(session),
            written: Some(k),
        })
    }

    /// The last step's events, once per step.
    pub fn step(&mut self, world: &World, dt: f64) -> Result<()> {
        let (step, end) = (world.step_count(), world.time());
        let substeps = world.stats().substeps;
        self.write(step, end, dt, substeps, world.contact_events())
    }

    /// The `events` of step `step` of `dt` in `substeps`, ending at time `end`, once per
    /// step.
    pub fn write(
        &mut self,
        step: u64,
        end: f64,
        dt: f64,
        substeps: u32,
        events: &[ContactEvent],
    ) -> Result<()> {
        if self.written == Some(step) || step == 0 {
            return Ok(());
        }
        self.written = Some(step);
        for event in events {
            self.row(step, event.time(end, dt, substeps), event)?;
        }
        // The step's rows are whole: a second signal keeps them.
        self.file.mark_whole();
        Ok(())
    }

    fn row(&mut self, step: u64, time: f64, e: &ContactEvent) -> Result<()> {
        let b = match e.b {
            Party::Disc(id) => id.0.to_string(),
            Party::Wall(side) => format!("wall:{}", side.name()),
            Party::Obstacle(k) => {
                let name = self.obstacles.get(k as usize);
                format!(
                    "obstacle:{}",
                    name.cloned().unwrap_or_else(|| k.to_string())
                )
            }
        };
        write!(self.file, "{step},{time:?},{},{},{b}", e.kind.name(), e.a.0)?;
        for v in e.numbers() {
            write!(self.file, ",{v:?}")?;
        }
        writeln!(self.file)?;
        Ok(())
    }

    /// Flushes and renames the file into place.
    pub fn finish(self) -> Result<()> {
        self.file.commit().context("cannot write events.csv")
    }
}

/// Each expanded obstacle's name in `events.csv`: its `[[obstacle]]`'s name, or its index.
fn obstacle_names(session: &Session) -> Vec<String> {
    let count = session.world.config().obstacles.len();
    let mut names: Vec<String> = (0..count).map(|k| k.to_string()).collect();
    for group in session.scenario.obstacle_groups() {
        if let Some(name) = group.name {
            for k in group.range {
                names[k] = name.clone();
            }
        }
    }
    names
}
