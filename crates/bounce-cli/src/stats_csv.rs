//! `stats.csv`: one row every `stats_every` steps, plus the first and the last step.
//!
//! Columns: `step,time,kinetic_energy,momentum_x,momentum_y,collisions,wall_impulse,
//! max_overlap,temperature,potential_energy,pressure,substeps,particles,contacts`.
//! `collisions` counts impacts (pairs that met approaching faster than a resting contact
//! does, `bounce::law::is_impact`), `contacts` every colliding pair found in every substep
//! (a resting contact in each). `pressure` is the step's
//! collision-virial pressure (empty in an open world, which has no area); `substeps` the
//! substeps the step took (more than `time.substeps` with `time.max_travel`); `particles` the
//! discs in the world (emitters add, sinks remove). `collisions`, `contacts`, `wall_impulse` and `max_overlap`
//! cover the steps since the previous row (the first row, at the starting step, has zeros
//! there).
//!
//! Obstacles add columns: for each `[[obstacle]]` with a `name`, the mean force on it since
//! the previous row (`force_NAME_x`, `force_NAME_y`: momentum received over time) and, when
//! it moves, where it is (`NAME_x`, `NAME_y`: its first piece's centre); with any moving
//! obstacle, `obstacle_work`, the work the moving obstacles have done on the discs since the
//! start.
//!
//! Each `[[sensor]]` adds `sensor_NAME_in` and `sensor_NAME_out` (the discs whose centre
//! entered and left its region since the previous row; a disc a sink removes inside it
//! leaves) and `sensor_NAME_count` (the discs inside now).
//!
//! `[output] pressure_tensor = true` adds `pressure_xx`, `pressure_yy` and `pressure_xy`
//! (`bounce::World::pressure_tensor`: kinetic plus collisional, at the row's step like
//! `pressure`, whose value is the mean of the first two).
//!
//! `[output] dissipation = true` adds `dissipated`: the energy (kinetic, rotational,
//! potential) the discs lost since the previous row beyond what the thermostat and moving
//! obstacles put in: inelastic collisions and friction (negative where the default model
//! gains energy).
//!
//! A thermostat (`[world] thermostat`) adds `thermostat_work`: the kinetic energy it added
//! since the previous row (negative where it took energy away).
//!
//! Rough or spinning discs (`[world] friction`, `[[disc]] angular_velocity`, `[[gas]] spin`)
//! add `rotational_energy` (`Σ ½ I ω²`), `angular_momentum` (about the origin, orbital and
//! spin) and `friction_work` (the energy friction and rolling resistance removed since the
//! start): with `e = 1`, the kinetic, rotational and potential energy and `friction_work` add
//! up to the energy at the start.
//!
//! A run that stops early (Ctrl-C, SIGTERM) writes a row for its last step too. A resumed
//! run drops the rows after its checkpoint's step, and that extra row, and continues from
//! the totals the checkpoint kept, so its file equals an uninterrupted run's byte for byte.

use std::path::Path;

use anyhow::{Context, Result};
use std::ops::Range;

use bounce::{SensorCount, Shape, StepStats, World};
use bounce_scenario::atomic::AtomicFile;
use bounce_scenario::checkpoint::RunState;

/// The header, in order.
pub const COLUMNS: [&str; 14] = [
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
    "particles",
    "contacts",
];

/// The columns a scenario adds: its obstacles' (its named groups, and whether any obstacle
/// moves) and, where discs turn, the rotation's.
#[derive(Clone, Debug, Default)]
pub struct ScenarioColumns {
    /// Name, pieces, moving.
    groups: Vec<(String, Range<usize>, bool)>,
    /// Whether to write `obstacle_work`.
    work: bool,
    /// Whether to write the rotation's columns.
    rotation: bool,
    /// The sensors' names.
    sensors: Vec<String>,
    /// Whether to write `thermostat_work`.
    thermostat: bool,
    /// Whether to write the pressure tensor.
    pressure_tensor: bool,
    /// Whether to write `dissipated`.
    dissipation: bool,
}

impl ScenarioColumns {
    /// The columns for `session`'s obstacles and discs.
    pub fn of(session: &bounce_scenario::Session) -> Self {
        let groups = session.scenario.obstacle_groups();
        ScenarioColumns {
            rotation: session.world.particles().turns(),
            sensors: (session.world.config().sensors.iter())
                .map(|s| s.name.clone())
                .collect(),
            work: groups.iter().any(|g| g.moving),
            thermostat: session.world.config().thermostat.is_some(),
            pressure_tensor: session.world.config().pressure_tensor,
            dissipation: session.output.dissipation,
            groups: groups
                .into_iter()
                .filter_map(|g| Some((g.name?, g.range, g.moving)))
                .collect(),
        }
    }

    /// The header: the fixed columns, then these.
    fn header(&self) -> Vec<String> {
        let mut out: Vec<String> = COLUMNS.iter().map(|c| c.to_string()).collect();
        for (name, _, moving) in &self.groups {
            out.push(format!("force_{name}_x"));
            out.push(format!("force_{name}_y"));
            if *moving {
                out.push(format!("{name}_x"));
                out.push(format!("{name}_y"));
            }
        }
        if self.work {
            out.push("obstacle_work".into());
        }
        if self.rotation {
            out.extend(
                ["rotational_energy", "angular_momentum", "friction_work"].map(String::from),
            );
        }
        for name in &self.sensors {
            for what in ["in", "out", "count"] {
                out.push(format!("sensor_{name}_{what}"));
            }
        }
        if self.thermostat {
            out.push("thermostat_work".into());
        }
        if self.pressure_tensor {
            out.extend(["pressure_xx", "pressure_yy", "pressure_xy"].map(String::from));
        }
        if self.dissipation {
            out.push("dissipated".into());
        }
        out
    }

    /// This row's values of these columns.
    fn values(&self, world: &World, totals: &RunState, energy: Option<f64>) -> Vec<String> {
        let mut out = Vec::new();
        let shapes = world.obstacle_shapes();
        for (_, range, moving) in &self.groups {
            let mut impulse = [0.0, 0.0];
            for k in range.clone() {
                if let Some(j) = totals.obstacle_impulse.get(k) {
                    impulse[0] += j[0];
                    impulse[1] += j[1];
                }
            }
            for j in impulse {
                out.push(if totals.elapsed > 0.0 {
                    (j / totals.elapsed).to_string()
                } else {
                    "0".into()
                });
            }
            if *moving {
                let centre = match shapes.get(range.start) {
                    Some(Shape::Segment { a, b }) => [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0],
                    Some(Shape::Peg { centre, .. }) => *centre,
                    None => [f64::NAN; 2],
                };
                out.extend(centre.map(|v| v.to_string()));
            }
        }
        if self.work {
            out.push(world.obstacle_work().to_string());
        }
        if self.rotation {
            out.push(world.rotational_energy().to_string());
            out.push(world.angular_momentum().to_string());
            out.push(world.friction_work().to_string());
        }
        for (k, count) in world.sensors().iter().enumerate().take(self.sensors.len()) {
            let [entered, left] = totals.sensor_crossings.get(k).copied().unwrap_or([0, 0]);
            out.extend([entered, left, count.inside as u64].map(|v| v.to_string()));
        }
        if self.thermostat {
            out.push(totals.thermostat_work.to_string());
        }
        if self.pressure_tensor {
            // Empty where `pressure` is: before the first step, which has no virial.
            let tensor = world
                .pressure_tensor()
                .filter(|_| world.stats().pressure.is_some());
            for k in 0..3 {
                out.push(tensor.map_or_else(String::new, |t| t[k].to_string()));
            }
        }
        if let Some(now) = energy {
            // What left the discs' energy beyond what the thermostat and moving obstacles
            // put in (0 at the first row).
            let lost = totals.row_energy.map_or(0.0, |before| {
                before + totals.thermostat_work + totals.obstacle_work - now
            });
            out.push(lost.to_string());
        }
        out
    }
}

/// Running totals since the previous row.
#[derive(Clone, Debug, Default)]
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
            row: run.clone(),
            scheduled: run,
        }
    }

    /// Adds one step of `dt` that `world` just took, whose sensors counted `sensors` (the
    /// world's own, or in a distributed run the root's for the whole world).
    pub fn add(&mut self, stats: &StepStats, world: &World, sensors: &[SensorCount], dt: f64) {
        let impulses = world.obstacle_impulses();
        for t in [&mut self.row, &mut self.scheduled] {
            t.collisions += stats.collisions as u64;
            t.contacts += stats.pairs as u64;
            t.wall_impulse += stats.wall_impulse.total();
            t.max_overlap = t.max_overlap.max(stats.max_overlap);
            t.thermostat_work += stats.thermostat_work;
            t.obstacle_work += stats.obstacle_work;
            t.elapsed += dt;
            t.obstacle_impulse.resize(impulses.len(), [0.0; 2]);
            for (sum, j) in t.obstacle_impulse.iter_mut().zip(impulses) {
                sum[0] += j[0];
                sum[1] += j[1];
            }
            t.sensor_crossings.resize(sensors.len(), [0, 0]);
            for (sum, count) in t.sensor_crossings.iter_mut().zip(sensors) {
                sum[0] += count.entered_last_step;
                sum[1] += count.left_last_step;
            }
        }
    }

    /// A row was written (`scheduled`: on the schedule, not a run's extra last row), with
    /// the discs' energy then when `dissipated` is written.
    pub fn reset(&mut self, scheduled: bool, row_energy: Option<f64>) {
        let fresh = RunState {
            row_energy,
            ..RunState::default()
        };
        if scheduled {
            self.scheduled = fresh.clone();
        }
        self.row = fresh;
    }

    /// What a checkpoint keeps.
    pub fn checkpoint(&self) -> RunState {
        self.scheduled.clone()
    }
}

/// Accumulates per-step statistics and writes rows.
pub struct StatsCsv {
    writer: csv::Writer<AtomicFile>,
    pub totals: Totals,
    total_mass: f64,
    obstacles: ScenarioColumns,
}

impl StatsCsv {
    /// Starts `stats.csv` in `dir`; `total_mass` is the sum of the discs' masses.
    pub fn create(dir: &Path, total_mass: f64, obstacles: ScenarioColumns) -> Result<Self> {
        let mut writer = csv::Writer::from_writer(AtomicFile::create(&dir.join("stats.csv"))?);
        writer.write_record(obstacles.header())?;
        Ok(StatsCsv {
            writer,
            totals: Totals::default(),
            total_mass,
            obstacles,
        })
    }

    /// Continues `stats.csv` in `dir`: keeps the header and the rows whose step passes
    /// `keep`, byte for byte, and continues from `run`'s totals. Without an earlier file,
    /// starts a new one.
    pub fn resume(
        dir: &Path,
        total_mass: f64,
        obstacles: ScenarioColumns,
        keep: impl Fn(u64) -> bool,
        through: Option<u64>,
        run: RunState,
    ) -> Result<Self> {
        let header = obstacles.header().join(",");
        let path = dir.join("stats.csv");
        let Some(file) = crate::rows::continue_rows(&path, &header, &keep, through)? else {
            let mut fresh = StatsCsv::create(dir, total_mass, obstacles)?;
            fresh.totals = Totals::resumed(run);
            return Ok(fresh);
        };
        Ok(StatsCsv {
            writer: csv::WriterBuilder::new()
                .has_headers(false)
                .from_writer(file),
            totals: Totals::resumed(run),
            total_mass,
            obstacles,
        })
    }

    /// Writes a row for the world's current state and resets the totals (`scheduled`: the
    /// row is on the schedule).
    pub fn row(&mut self, world: &World, scheduled: bool) -> Result<()> {
        let s = world.stats();
        // Emitters and sinks change the total mass.
        let config = world.config();
        if !(config.emitters.is_empty() && config.sinks.is_empty()) {
            self.total_mass = bounce_scenario::analysis::total_mass(world);
        }
        let temperature = bounce_scenario::analysis::temperature(world, self.total_mass);
        // Summed in id order, so a resumed or distributed run writes the same bits.
        let (energy, momentum) = bounce_scenario::analysis::motion_sums(world);
        // (None before the first step, which has no virial.)
        let pressure = s
            .pressure
            .and_then(|_| world.pressure(energy, momentum, s.virial));
        let t = &self.totals.row;
        let row_energy = self.row_energy(world);
        let extra = self.obstacles.values(world, t, row_energy);
        let mut record = vec![
            world.step_count().to_string(),
            world.time().to_string(),
            energy.to_string(),
            momentum[0].to_string(),
            momentum[1].to_string(),
            t.collisions.to_string(),
            t.wall_impulse.to_string(),
            t.max_overlap.to_string(),
            temperature.to_string(),
            bounce_scenario::analysis::potential_energy(world).to_string(),
            pressure.map_or_else(String::new, |p| p.to_string()),
            s.substeps.to_string(),
            world.len().to_string(),
            t.contacts.to_string(),
        ];
        record.extend(extra);
        self.writer.write_record(record)?;
        // The row is whole: a second signal keeps it.
        self.writer.flush()?;
        self.writer.get_ref().mark_whole();
        self.totals.reset(scheduled, row_energy);
        Ok(())
    }

    /// The discs' energy `dissipated` is measured from, when it is written.
    pub fn row_energy(&self, world: &World) -> Option<f64> {
        self.obstacles
            .dissipation
            .then(|| bounce_scenario::analysis::total_energy(world))
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

/// The rows read back: time, kinetic energy, momentum, potential energy, and for the moving
/// obstacle `piston` names (when given) its position and the force on it.
pub fn read_history(path: &Path, piston: Option<&str>) -> Result<Vec<crate::plots::Sample>> {
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    let header = reader
        .headers()
        .with_context(|| format!("cannot read {}", path.display()))?
        .clone();
    let column = |name: String| header.iter().position(|h| h == name);
    let piston_columns = piston.and_then(|name| {
        Some((
            column(format!("{name}_x"))?,
            column(format!("{name}_y"))?,
            column(format!("force_{name}_x"))?,
            column(format!("force_{name}_y"))?,
        ))
    });
    let mut out = Vec::new();
    for record in reader.records() {
        let record = record.with_context(|| format!("cannot read {}", path.display()))?;
        let field = |k: usize| -> f64 { record.get(k).and_then(|v| v.parse().ok()).unwrap_or(0.0) };
        out.push(crate::plots::Sample {
            time: field(1),
            energy: field(2),
            momentum: [field(3), field(4)],
            potential: field(9),
            piston: piston_columns.map(|(x, y, fx, fy)| [field(x), field(y), field(fx), field(fy)]),
        });
    }
    Ok(out)
}
