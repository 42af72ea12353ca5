//! A session: a scenario turned into everything a front end needs to run it.
//!
//! The CLI, the desktop viewer, the web page (both renderers) and the tests all start here:
//! scenario text → a [`Session`] holding the world, the discs' colours, the time step and run
//! length, the colouring, the region to show (computed once, [`view_bounds`]) and the output
//! plan; [`Session::run_until`] is the run loop they share, and checkpoints are saved with the
//! same atomic write everywhere.

use std::ops::ControlFlow;
use std::path::Path;

use bounce::{StepError, StepStats, World};

use crate::{ColorBy, Limits, OutputSpec, Problem, Rgb, Scenario, ScenarioError};

/// How obstacles are drawn when their table sets no colour.
pub const OBSTACLE_GREY: Rgb = [170, 176, 190];

/// A scenario ready to run.
#[derive(Debug)]
pub struct Session {
    /// What to call the run: the scenario's `name`, else where it came from.
    pub title: String,
    /// Where the scenario came from (a file, or a built-in name), as messages name it.
    pub origin: String,
    /// The scenario text: what [`Session::reset`] rebuilds from.
    pub text: String,
    /// The parsed scenario.
    pub scenario: Scenario,
    /// The world, particles placed (ids in file order).
    pub world: World,
    /// Colour of each particle by id; `None` where the scenario sets none.
    pub colours: Vec<Option<Rgb>>,
    /// The particle types (`type`, else the colour, else `A`), in order of first appearance.
    pub types: Vec<String>,
    /// Each particle's index into `types`, by id.
    pub typeid: Vec<u32>,
    /// Each emitter's colour and type, given to the discs it adds ([`Session::note_emitted`]).
    pub emitted: Vec<(Option<Rgb>, u32)>,
    /// The time step.
    pub dt: f64,
    /// The step the scenario runs to (`time.steps`).
    pub steps: u64,
    /// How pictures colour the discs: the scenario's `output.color_by`, else its colours
    /// when it sets any, else speed.
    pub colour_by: ColorBy,
    /// The region pictures show: `output.view`, else the box, else the discs' extent at the
    /// start with a margin of two largest radii.
    pub view: ([f64; 2], [f64; 2]),
    /// What a run writes.
    pub output: OutputSpec,
}

impl Session {
    /// A session from scenario text; `origin` names it in messages.
    pub fn from_text(origin: &str, text: &str) -> Result<Session, ScenarioError> {
        Session::from_text_with(origin, text, &Limits::default())
    }

    /// A session from scenario text within `limits`; `[[file]]` paths are relative to the
    /// current folder.
    pub fn from_text_with(
        origin: &str,
        text: &str,
        limits: &Limits,
    ) -> Result<Session, ScenarioError> {
        Session::from_text_in(origin, text, limits, None)
    }

    /// A session from scenario text within `limits`, its `[[file]]` paths relative to `dir`
    /// (the scenario file's folder).
    pub fn from_text_in(
        origin: &str,
        text: &str,
        limits: &Limits,
        dir: Option<&Path>,
    ) -> Result<Session, ScenarioError> {
        let (scenario, built) = crate::build::read_and_build(text, origin, limits, dir)?;
        let colour_by = scenario
            .output
            .color_by
            .unwrap_or(if scenario.has_colours() {
                ColorBy::Color
            } else {
                ColorBy::Speed
            });
        let view = view_bounds(&built.world, scenario.output.view.map(|v| (v.min, v.max)));
        Ok(Session {
            title: scenario.name.clone().unwrap_or_else(|| origin.to_string()),
            origin: origin.to_string(),
            text: text.to_string(),
            dt: scenario.time.dt,
            steps: scenario.time.steps,
            colour_by,
            view,
            output: scenario.output.clone(),
            world: built.world,
            colours: built.colours,
            types: built.types,
            typeid: built.typeid,
            emitted: built.emitted,
            scenario,
        })
    }

    /// A session from a scenario file.
    pub fn load(path: &Path) -> Result<Session, ScenarioError> {
        let origin = path.display().to_string();
        let text = crate::files::read_to_string(path).map_err(|e| ScenarioError {
            file: origin.clone(),
            problems: vec![Problem {
                line: None,
                message: format!("cannot read the file: {e}"),
            }],
        })?;
        Session::from_text_in(&origin, &text, &Limits::default(), path.parent())
    }

    /// The colour of each obstacle, in `Config::obstacles` order: its table's `color`, else
    /// [`OBSTACLE_GREY`].
    pub fn obstacle_colours(&self) -> Vec<Rgb> {
        let mut out = vec![OBSTACLE_GREY; self.world.config().obstacles.len()];
        for group in self.scenario.obstacle_groups() {
            for k in group.range.clone() {
                if let (Some(slot), Some(c)) = (out.get_mut(k), group.colour) {
                    *slot = c;
                }
            }
        }
        out
    }

    /// The scenario's colours with the particle types that wear them, each colour once, in
    /// order of first use (the emitters' after the tables'): the key to frames coloured by
    /// `color`.
    pub fn colour_key(&self) -> Vec<(Rgb, String)> {
        let tables = self.colours.iter().zip(&self.typeid);
        let emitted = self.emitted.iter().map(|(c, t)| (c, t));
        let mut out: Vec<(Rgb, String)> = Vec::new();
        for (colour, &t) in tables.chain(emitted) {
            if let Some(c) = colour
                && !out.iter().any(|(seen, _)| seen == c)
            {
                let name = self.types.get(t as usize).cloned().unwrap_or_default();
                out.push((*c, name));
            }
        }
        out
    }

    /// The first named moving segment of the scenario and how it faces the gas (towards the
    /// box's centre), in a walled box: a piston, with its name.
    pub fn piston(&self) -> Option<(String, Piston)> {
        piston_of(&self.scenario, &self.world)
    }

    /// A session of a shipped scenario (`gas`, `pile`, ...: [`crate::TEMPLATES`]).
    pub fn builtin(name: &str) -> Result<Session, String> {
        let text = crate::template(name).ok_or_else(|| {
            let names: Vec<&str> = crate::TEMPLATES.iter().map(|(n, _)| *n).collect();
            format!(
                "no built-in scenario {name:?}; choose one of {}",
                names.join(", ")
            )
        })?;
        Session::from_text(name, text).map_err(|e| e.to_string())
    }

    /// Rebuilds the world from the scenario text: the state at step 0. The thread count is
    /// kept.
    pub fn reset(&mut self) -> Result<(), ScenarioError> {
        let threads = self.world.threads();
        let fresh = Session::from_text_in(
            &self.origin,
            &self.text,
            &Limits::default(),
            self.scenario.dir.as_deref(),
        )?;
        *self = fresh;
        // A thread pool that started once starts again.
        let _ = self.world.set_threads(threads);
        Ok(())
    }

    /// The scenario from its start again under `method` (its `time.method` set so): a
    /// world switched to the event-driven method mid-run would start with the overlaps the
    /// time-stepped one leaves, which exact hard discs cannot have. What the scenario asks
    /// that the method cannot do is the error, naming the field.
    pub fn restart_with_method(&mut self, method: bounce::Method) -> Result<(), String> {
        let set = format!("time.method={}", method.name());
        let text = crate::overrides::apply(&self.text, &[set], None)?;
        let threads = self.world.threads();
        *self = Session::from_text_in(
            &self.origin,
            &text,
            &Limits::default(),
            self.scenario.dir.as_deref(),
        )
        .map_err(|e| e.to_string())?;
        let _ = self.world.set_threads(threads);
        Ok(())
    }

    /// One step of `dt`.
    pub fn step(&mut self) -> Result<&StepStats, StepError> {
        self.world.step(self.dt)?;
        self.note_emitted();
        Ok(self.world.stats())
    }

    /// Gives the discs the emitters added in the last step their emitter's colour and type
    /// (`colours` and `typeid` are by id, and grow with the ids given).
    pub fn note_emitted(&mut self) {
        note_emitted(
            &self.world,
            &self.emitted,
            Some(&mut self.colours),
            &mut self.typeid,
        );
    }

    /// Steps until step `target`, calling `after_step` after each; it returns
    /// `ControlFlow::Break(())` to stop early (Ctrl-C, a paused viewer). Returns whether the
    /// target was reached.
    pub fn run_until<E: From<StepError>>(
        &mut self,
        target: u64,
        mut after_step: impl FnMut(&World, &StepStats) -> Result<ControlFlow<()>, E>,
    ) -> Result<bool, E> {
        while self.world.step_count() < target {
            let stats = *self.world.step(self.dt)?;
            self.note_emitted();
            if after_step(&self.world, &stats)?.is_break() && self.world.step_count() < target {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// [`Session::run_until`] that `stop` (a signal handler's flag: non-zero stops) also ends
    /// inside a long step: the first step, and any after a step that took over a second,
    /// start from a copy of the world and may stop between substeps, going back to the
    /// copy. So a run stops within about a second of the flag wherever it is, at the end of
    /// a whole step. Returns whether the target was reached.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn run_until_stopped<E: From<StepError>>(
        &mut self,
        target: u64,
        stop: &std::sync::Arc<std::sync::atomic::AtomicUsize>,
        mut after_step: impl FnMut(&World, &StepStats) -> Result<ControlFlow<()>, E>,
    ) -> Result<bool, E> {
        use std::sync::atomic::Ordering;
        let mut slow = true;
        while self.world.step_count() < target {
            if stop.load(Ordering::SeqCst) != 0 {
                return Ok(false);
            }
            let copy = slow
                .then(|| crate::checkpoint::encode(&self.world, None).ok())
                .flatten();
            self.world
                .set_interrupt(copy.as_ref().map(|_| stop.clone()));
            let started = std::time::Instant::now();
            let stepped = self.world.step(self.dt).copied();
            self.world.set_interrupt(None);
            let stats = match (stepped, copy) {
                (Err(StepError::Interrupted { .. }), Some(copy)) => {
                    let back = crate::checkpoint::decode(&copy, "the copy before the step")
                        .map_err(|_| StepError::Interrupted {
                            step: self.world.step_count() + 1,
                        })?;
                    self.adopt(back.world);
                    return Ok(false);
                }
                (stepped, _) => stepped?,
            };
            slow = started.elapsed().as_secs_f64() > 1.0;
            self.note_emitted();
            if after_step(&self.world, &stats)?.is_break() && self.world.step_count() < target {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Replaces the world with one loaded from a checkpoint, which must be of this scenario:
    /// the same configuration and as many discs. Otherwise says what differs.
    pub fn resume(&mut self, world: World, checkpoint: &str) -> Result<(), String> {
        let mut differences =
            crate::checkpoint::config_differences(self.world.config(), world.config());
        // Emitters and sinks change the count; otherwise it is the scenario's.
        let fixed_count = world.config().emitters.is_empty() && world.config().sinks.is_empty();
        if fixed_count && world.len() != self.world.len() {
            differences.push(format!(
                "particles: {} vs {}",
                self.world.len(),
                world.len()
            ));
        }
        // The clock: the scenario's steps of `dt` (summed step by step, so within rounding).
        let expected = world.step_count() as f64 * self.dt;
        if (world.time() - expected).abs() > 1e-6 * expected.max(self.dt) {
            differences.push(format!(
                "time: {expected} ({} steps of dt {}) vs {}",
                world.step_count(),
                self.dt,
                world.time()
            ));
        }
        if !differences.is_empty() {
            return Err(format!(
                "{checkpoint} is not a checkpoint of {} (scenario vs checkpoint): {}",
                self.origin,
                differences.join("; ")
            ));
        }
        self.adopt(world);
        Ok(())
    }

    /// Replaces the world with `world` unchecked (a front end's edited world, reloaded):
    /// it keeps the thread count, and the discs beyond the scenario's get their emitter's
    /// colour and type, or none. [`Session::resume`] adopts what it has checked.
    pub fn adopt(&mut self, world: World) {
        let threads = self.world.threads();
        self.world = world;
        let _ = self.world.set_threads(threads);
        // The discs emitted before the checkpoint: their emitter's colour and type.
        let scenario_discs = self.colours.len() as u32;
        for id in scenario_discs..self.world.next_id() {
            if let Some(k) = self.world.emitter_of(bounce::ParticleId(id)) {
                let (colour, kind) = self.emitted.get(k as usize).copied().unwrap_or((None, 0));
                self.colours.resize(id as usize + 1, None);
                self.typeid.resize(id as usize + 1, 0);
                self.colours[id as usize] = colour;
                self.typeid[id as usize] = kind;
            }
        }
    }
}

/// The region pictures show: `view` if given, else the box, else the discs' extent with a
/// margin of two largest radii (`[-10, 10]²` for an empty open world).
pub fn view_bounds(world: &World, view: Option<([f64; 2], [f64; 2])>) -> ([f64; 2], [f64; 2]) {
    if let Some(view) = view.or(world.config().boundary.bounds()) {
        return view;
    }
    let p = world.particles();
    if p.is_empty() {
        return ([-10.0, -10.0], [10.0, 10.0]);
    }
    let margin = 2.0 * p.radius().iter().copied().fold(0.0, f64::max);
    let lo = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min) - margin;
    let hi = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max) + margin;
    ([lo(p.x()), lo(p.y())], [hi(p.x()), hi(p.y())])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_session_holds_the_scenario_ready_to_run() {
        let mut s = Session::builtin("mixing").unwrap();
        assert_eq!(s.colour_by, ColorBy::Color);
        assert!(s.colours.iter().all(|c| c.is_some()));
        assert_eq!(s.view, s.world.config().boundary.bounds().unwrap());
        let start = s.world.state_hash();
        // Stops when asked, and reaches the target otherwise.
        let mut seen = 0;
        let reached = s
            .run_until(10, |_, _| {
                seen += 1;
                Ok::<_, StepError>(if seen == 3 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                })
            })
            .unwrap();
        assert!(!reached);
        assert_eq!(s.world.step_count(), 3);
        assert!(
            s.run_until(5, |_, _| Ok::<_, StepError>(ControlFlow::Continue(())))
                .unwrap()
        );
        assert_eq!(s.world.step_count(), 5);
        s.reset().unwrap();
        assert_eq!(s.world.state_hash(), start);
        assert!(Session::builtin("nope").unwrap_err().contains("gas"));
    }

    #[test]
    fn an_open_world_is_viewed_around_its_discs() {
        let text = "[world]\nboundary = \"open\"\n[time]\ndt = 0.1\nsteps = 1\n\
                    [[disc]]\nposition = [1.0, 2.0]\nradius = 0.5\n\
                    [[disc]]\nposition = [5.0, -2.0]\nradius = 1.0\n";
        let s = Session::from_text("open.toml", text).unwrap();
        assert_eq!(s.view, ([-1.0, -4.0], [7.0, 4.0]));
        assert_eq!(s.title, "open.toml");
    }

    #[test]
    fn resuming_needs_the_same_number_of_discs() {
        let mut s = Session::builtin("gas").unwrap();
        let other = Session::builtin("pile").unwrap().world;
        let e = s.resume(other, "c.bin").unwrap_err();
        assert!(
            e.contains("c.bin") && e.contains("particles: 2000 vs"),
            "{e}"
        );
        assert!(e.contains("gravity: [0.0, 0.0] vs [0.0, -"), "{e}");
    }

    #[test]
    fn resuming_needs_the_clock_of_the_steps_taken() {
        let mut s = Session::builtin("gas").unwrap();
        let dt = s.dt;
        s.run_until(3, |_, _| Ok::<_, StepError>(ControlFlow::Continue(())))
            .unwrap();
        let bytes = crate::checkpoint::encode(&s.world, None).unwrap();
        let good = crate::checkpoint::decode(&bytes, "c.bin").unwrap().world;
        let mut fresh = Session::builtin("gas").unwrap();
        fresh.resume(good, "c.bin").unwrap();
        assert_eq!(fresh.world.step_count(), 3);
        // The same state said to be two steps in (a step counter moved back), or far on.
        for steps in [2.0, 1e300 / dt] {
            let world = crate::checkpoint::tests::with_time(&s.world, steps * dt);
            let e = Session::builtin("gas")
                .unwrap()
                .resume(world, "c.bin")
                .unwrap_err();
            assert!(e.contains("c.bin") && e.contains("time: "), "{e}");
        }
    }
}

/// How the time step compares with the discs' speeds and sizes, and what that does to the
/// physics: the numbers `bounce check` and `bounce run` print.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeStepReport {
    /// Mean speed × dt / mean diameter: how far a typical disc moves per step, in diameters.
    pub mean_travel: f64,
    /// Fastest speed × dt / smallest radius: above 1 a fast disc can pass through a small one.
    pub max_travel: f64,
    /// The packing fraction, where the world has a box.
    pub packing: Option<f64>,
    /// The expected low bias of the pressure, in percent (negative), from the measured
    /// table in the user guide (`docs/src/concepts/time-step.md`): about
    /// `(0.2 + 9 η²) × mean_travel × 100`.
    pub pressure_bias_percent: Option<f64>,
    /// A warning with what to change, when the bias is over 1% or discs can tunnel.
    pub warning: Option<String>,
    /// The event-driven method: every collision exact, `dt` only how often the world is
    /// observed (no bias, nothing tunnels).
    pub exact: bool,
}

impl Session {
    /// The time step against the discs now (substeps and `max_travel` counted).
    pub fn time_step_report(&self) -> TimeStepReport {
        let world = &self.world;
        let config = world.config();
        let p = world.particles();
        let n = p.len().max(1) as f64;
        let speeds = p.vx().iter().zip(p.vy()).map(|(x, y)| x.hypot(*y));
        let (sum, max) = speeds.fold((0.0, 0.0f64), |(s, m), v| (s + v, m.max(v)));
        let mean_diameter = 2.0 * p.radius().iter().sum::<f64>() / n;
        let r_min = p.radius().iter().copied().fold(f64::INFINITY, f64::min);
        let h = self.dt / config.substeps as f64;
        // No discs yet (an emitter's box at its start): nothing travels.
        let mean_travel = if p.is_empty() {
            0.0
        } else {
            sum / n * h / mean_diameter
        };
        let max_travel = match config.max_travel {
            // Adaptive substeps hold every disc to this.
            Some(f) => f.min(max * h / r_min),
            None if p.is_empty() => 0.0,
            None => max * h / r_min,
        };
        let packing = config.boundary.bounds().map(|(lo, hi)| {
            let discs: f64 = p
                .radius()
                .iter()
                .map(|r| std::f64::consts::PI * r * r)
                .sum();
            discs / ((hi[0] - lo[0]) * (hi[1] - lo[1]))
        });
        // Events are exact: no time-step bias, nothing tunnels.
        let exact = config.method == bounce::Method::EventDriven;
        let bias = packing
            .filter(|_| !exact)
            .map(|eta| -(0.2 + 9.0 * eta * eta) * mean_travel * 100.0);
        let mut warnings = Vec::new();
        if let Some(b) = bias
            && b < -1.0
        {
            warnings.push(format!(
                "the pressure will be about {:.1}% low (mean travel {mean_travel:.3} diameters \
                 per step at packing {:.2}); dt = {:.3e} or {} substeps bring it under 1%",
                -b,
                packing.unwrap_or(0.0),
                self.dt / (-b),
                (config.substeps as f64 * -b).ceil()
            ));
        }
        if max_travel > 1.0 && !exact {
            warnings.push(format!(
                "the fastest disc moves {max_travel:.2} of the smallest radius per substep and \
                 can pass through small discs or walls; set time.max_travel = 0.5"
            ));
        }
        TimeStepReport {
            mean_travel,
            max_travel,
            packing,
            pressure_bias_percent: bias,
            warning: (!warnings.is_empty()).then(|| warnings.join("; ")),
            exact,
        }
    }
}

impl std::fmt::Display for TimeStepReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.exact {
            return write!(
                f,
                "time step: none (event-driven, every collision exact); observed every dt, \
                 mean speed·dt/σ = {:.4}",
                self.mean_travel
            );
        }
        write!(
            f,
            "time step: mean speed·dt/σ = {:.4}, max speed·dt/r_min = {:.3}",
            self.mean_travel, self.max_travel
        )?;
        if let Some(b) = self.pressure_bias_percent {
            write!(f, ", expected pressure bias {b:+.1}%")?;
        }
        if let Some(w) = &self.warning {
            write!(f, "\nwarning: {w}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod time_step_tests {
    use super::*;

    #[test]
    fn an_event_driven_run_has_no_time_step_to_warn_about() {
        let hard = Session::builtin("hard-discs").unwrap();
        let coarse = hard.text.replace("dt = 0.1 ", "dt = 10.0 ");
        let report = Session::from_text("coarse", &coarse)
            .unwrap()
            .time_step_report();
        assert!(report.exact && report.warning.is_none() && report.pressure_bias_percent.is_none());
        assert!(report.to_string().contains("event-driven"), "{report}");
    }

    #[test]
    fn the_report_warns_when_the_step_biases_the_pressure() {
        let gas = Session::builtin("gas").unwrap();
        let report = gas.time_step_report();
        assert!(report.mean_travel > 0.0 && report.packing.is_some());
        // Ten times the step: the warning names a dt that brings the bias under 1%.
        let coarse = gas
            .text
            .replace("dt = 0.016666666666666666", "dt = 0.16666666666666666");
        let coarse = Session::from_text("coarse", &coarse).unwrap();
        let report = coarse.time_step_report();
        let warning = report.warning.expect("a warning");
        assert!(
            warning.contains("pressure will be about") && warning.contains("dt ="),
            "{warning}"
        );
        assert!(report.pressure_bias_percent.unwrap() < -1.0);
    }
}

/// A piston: a moving segment of `length` across a box whose gas lies on one side, the
/// side `towards` points to from it (the area between it and the wall there).
#[derive(Clone, Copy, Debug)]
pub struct Piston {
    /// The segment's length: pressure is force over length.
    pub length: f64,
    /// The unit normal from the piston into the gas.
    pub towards: [f64; 2],
    /// The box's lower-left corner: the gas fills from the piston to the wall `towards`
    /// points at.
    pub min: [f64; 2],
    /// The box's upper-right corner.
    pub max: [f64; 2],
    /// The area the gas's discs cover as hard discs (`π (s r)²` each, `s` the collision
    /// radius scale): its packing fraction sets the adiabat's steepness.
    pub disc_area: f64,
}

impl Piston {
    /// The area of gas between a piston centred at `centre` and the far wall.
    pub fn gas_area(&self, centre: [f64; 2]) -> f64 {
        let [nx, ny] = self.towards;
        if nx.abs() > ny.abs() {
            let wall = if nx > 0.0 { self.max[0] } else { self.min[0] };
            (wall - centre[0]).abs() * (self.max[1] - self.min[1])
        } else {
            let wall = if ny > 0.0 { self.max[1] } else { self.min[1] };
            (wall - centre[1]).abs() * (self.max[0] - self.min[0])
        }
    }
}

/// The first named moving segment of the scenario and how it faces the gas (towards the
/// box's centre), in a walled box: a piston, with its name.
pub(crate) fn piston_of(scenario: &crate::Scenario, world: &World) -> Option<(String, Piston)> {
    let bounce::Boundary::Walls { min, max, .. } = world.config().boundary else {
        return None;
    };
    let group = scenario
        .obstacle_groups()
        .into_iter()
        .find(|g| g.moving && g.name.is_some())?;
    let bounce::Shape::Segment { a, b } = world.config().obstacles.get(group.range.start)?.shape
    else {
        return None;
    };
    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
    let normal = [-(b[1] - a[1]) / length, (b[0] - a[0]) / length];
    // Towards the centre of the box (where the gas is, for a piston at one end).
    let centre = [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0];
    let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    let side = (centre[0] - mid[0]) * normal[0] + (centre[1] - mid[1]) * normal[1];
    let towards = if side >= 0.0 {
        normal
    } else {
        [-normal[0], -normal[1]]
    };
    // The discs as hard discs: the collision distance of two is their radii's sum scaled.
    let scale = world.config().collision_radius_scale;
    let disc_area = world
        .particles()
        .radius()
        .iter()
        .map(|r| std::f64::consts::PI * (scale * r).powi(2))
        .sum();
    Some((
        group.name?,
        Piston {
            length,
            towards,
            min,
            max,
            disc_area,
        },
    ))
}

/// Gives the discs the emitters added in `world`'s last step their emitter's type in
/// `typeid` (and colour in `colours`), by id, from `emitted` (each emitter's colour and type,
/// [`Session::emitted`]): the one bookkeeping of emitted discs that the viewer, the web page
/// and Python share (the CLI's outputs do the same as they write).
pub fn note_emitted(
    world: &World,
    emitted: &[(Option<Rgb>, u32)],
    mut colours: Option<&mut Vec<Option<Rgb>>>,
    typeid: &mut Vec<u32>,
) {
    for &(id, k) in world.emitted_last_step() {
        let (colour, kind) = emitted.get(k as usize).copied().unwrap_or((None, 0));
        let id = id.0 as usize;
        if typeid.len() <= id {
            typeid.resize(id + 1, 0);
        }
        typeid[id] = kind;
        if let Some(colours) = colours.as_deref_mut() {
            if colours.len() <= id {
                colours.resize(id + 1, None);
            }
            colours[id] = colour;
        }
    }
}
