//! What is wrong with a scenario: one [`Problem`] per finding, with its line, gathered into
//! a [`ScenarioError`]; and the semantic checks that find them once the file is read.

use bounce::law::Law;

use crate::lines::{LineIndex, line_at, line_of_key};
use crate::schema::{BoundaryKind, Scenario, block_counts};
use crate::{observables, parse_colour};

/// One problem in a scenario file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// What is wrong, naming the field and value.
    pub message: String,
}

/// Every problem found in one file.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.render())]
pub struct ScenarioError {
    /// The file, as given.
    pub file: String,
    /// The problems, in file order.
    pub problems: Vec<Problem>,
}

impl ScenarioError {
    fn render(&self) -> String {
        let mut out = String::new();
        for (k, p) in self.problems.iter().enumerate() {
            if k > 0 {
                out.push('\n');
            }
            match p.line {
                Some(line) => out.push_str(&format!("{}:{}: {}", self.file, line, p.message)),
                None => out.push_str(&format!("{}: {}", self.file, p.message)),
            }
        }
        out
    }
}

impl Scenario {
    /// For a config problem of an obstacle, emitter or sink (`WHAT K: ...`, K its index in
    /// the config's list): the table's index, its kind and its line.
    fn table_of(
        &self,
        e: &bounce::ConfigError,
        source: &str,
    ) -> Option<(usize, &'static str, Option<usize>)> {
        let k: usize = e
            .value
            .split_once(": ")?
            .0
            .split(' ')
            .nth(1)?
            .parse()
            .ok()?;
        let (table, what, span) = match e.field {
            "obstacles" => {
                let groups = self.obstacle_groups();
                let t = groups.iter().position(|g| g.range.contains(&k))?;
                (t, "obstacle", self.obstacle[t].span())
            }
            "emitters" => (k, "emitter", self.emitter.get(k)?.span()),
            "sinks" => (k, "sink", self.sink.get(k)?.span()),
            "sensors" => (k, "sensor", self.sensor.get(k)?.span()),
            _ => return None,
        };
        Some((table, what, Some(line_at(source, span.start))))
    }

    /// Every problem that can be found without placing particles.
    pub(crate) fn problems(&self, source: &str) -> Vec<Problem> {
        let lines = LineIndex::new(source);
        let mut out = Vec::new();
        let mut at = |line: Option<usize>, message: String| out.push(Problem { line, message });

        let w = &self.world;
        if w.boundary != BoundaryKind::Open {
            for (key, v) in [("min", w.min), ("max", w.max)] {
                if v.is_none() {
                    at(
                        line_of_key(source, "world", "boundary"),
                        format!("world.{key} is required with boundary = {:?}", w.boundary),
                    );
                }
            }
        }
        let sheared = w.boundary == BoundaryKind::LeesEdwards;
        if sheared && w.shear_rate.is_none() {
            at(
                line_of_key(source, "world", "boundary"),
                "world.shear_rate is required with boundary = \"lees_edwards\"".into(),
            );
        }
        if !sheared && let Some(rate) = w.shear_rate {
            at(
                line_of_key(source, "world", "shear_rate"),
                format!(
                    "world.shear_rate = {rate}: only with boundary = \"lees_edwards\" (this is \
                     {:?})",
                    w.boundary
                ),
            );
        }
        if sheared && self.output.dissipation {
            at(
                line_of_key(source, "output", "dissipation"),
                "output.dissipation: not in a Lees–Edwards box yet (its sliding images do work \
                 on the discs that the balance does not count)"
                    .into(),
            );
        }
        if sheared && self.output.msd {
            at(
                line_of_key(source, "output", "msd"),
                "output.msd: not in a Lees–Edwards box yet (its images slide, so image counts \
                 do not unwrap the positions)"
                    .into(),
            );
        }
        for (k, g) in self.gas.iter().enumerate() {
            if g.get_ref().streaming && !sheared {
                at(
                    Some(lines.at(g.span().start)),
                    format!(
                        "gas #{}: streaming = true needs boundary = \"lees_edwards\" (the flow \
                         it adds is the sheared box's)",
                        k + 1
                    ),
                );
            }
        }
        for (k, o) in self.obstacle.iter().enumerate() {
            let line = Some(lines.at(o.span().start));
            for message in o.get_ref().problems() {
                at(line, format!("obstacle #{}: {message}", k + 1));
            }
        }
        for (k, sensor) in self.sensor.iter().enumerate() {
            let name = &sensor.get_ref().name;
            let plain = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
            if name.is_empty() || !name.chars().all(plain) {
                at(
                    Some(lines.at(sensor.span().start)),
                    format!(
                        "sensor #{}: name {name:?} must be letters, digits, `_` or `-` (it names \
                         stats.csv columns)",
                        k + 1
                    ),
                );
            }
        }
        for (k, e) in self.emitter.iter().enumerate() {
            let line = Some(lines.at(e.span().start));
            colour_problem(
                &e.get_ref().color,
                line,
                &format!("emitter #{}", k + 1),
                &mut at,
            );
        }
        for e in self.config().problems() {
            if let Some((table, what, line)) = self.table_of(&e, source) {
                // `WHAT K: VALUE`, K the index in the config's list: name the table.
                let value = e.value.split_once(": ").map_or(&*e.value, |(_, v)| v);
                at(
                    line,
                    format!("{what} #{}: {value}: {}", table + 1, e.expected),
                );
                continue;
            }
            if e.field == "contact_event_threshold" {
                at(
                    line_of_key(source, "output", "events_threshold"),
                    format!("output.events_threshold = {}: {}", e.value, e.expected),
                );
                continue;
            }
            let key = e.field.split('.').next_back().unwrap_or(e.field);
            let key = if key == "boundary" { "max" } else { key };
            let line = line_of_key(source, "world", key)
                .or_else(|| line_of_key(source, "time", key))
                .or_else(|| line_of_key(source, "world", "boundary"));
            at(
                line,
                format!("world.{} = {}: {}", e.field, e.value, e.expected),
            );
        }
        if self.output.dissipation && !(self.emitter.is_empty() && self.sink.is_empty()) {
            at(
                line_of_key(source, "output", "dissipation"),
                "output.dissipation: not with [[emitter]] or [[sink]] tables, whose discs bring \
                 and take energy"
                    .into(),
            );
        }
        if let Some(profile) = self.output.profile {
            if w.boundary == BoundaryKind::Open {
                at(
                    line_of_key(source, "output", "profile"),
                    "output.profile: a profile needs a box (walls or periodic), not an open \
                     world"
                        .into(),
                );
            } else if !(1..=observables::MAX_PROFILE_BINS).contains(&profile.bins) {
                at(
                    line_of_key(source, "output", "profile"),
                    format!(
                        "output.profile.bins = {}: must be in 1..={}",
                        profile.bins,
                        observables::MAX_PROFILE_BINS
                    ),
                );
            }
        }
        if !(self.time.dt.is_finite() && self.time.dt > 0.0) {
            at(
                line_of_key(source, "time", "dt"),
                format!("time.dt = {} must be finite and > 0", self.time.dt),
            );
        } else if !(self.time.dt * self.time.steps as f64 * 2.0).is_finite() {
            // (Twice: room for the clock's rounding and a run continued as long again.)
            at(
                line_of_key(source, "time", "dt"),
                format!(
                    "time.dt = {:?} for {} steps overflows the clock (the run's time must be \
                     finite)",
                    self.time.dt, self.time.steps
                ),
            );
        }
        for (k, g) in self.gas.iter().enumerate() {
            let line = Some(lines.at(g.span().start));
            let gas = g.get_ref();
            let set = [gas.speed, gas.temperature, gas.uniform]
                .iter()
                .filter(|v| v.is_some())
                .count();
            if set != 1 {
                at(
                    line,
                    format!(
                        "gas #{}: give exactly one of speed, temperature, uniform ({set} given)",
                        k + 1
                    ),
                );
            }
            let [lo, hi] = gas.radius.range();
            if !(lo.is_finite() && lo > 0.0 && hi.is_finite() && hi >= lo) {
                at(
                    line,
                    format!(
                        "gas #{}: radius = {}: must be finite, > 0, with min <= max",
                        k + 1,
                        gas.radius
                    ),
                );
            }
            colour_problem(&gas.color, line, &format!("gas #{}", k + 1), &mut at);
        }
        for (k, l) in self.lattice.iter().enumerate() {
            let line = Some(lines.at(l.span().start));
            let lat = l.get_ref();
            if !(lat.radius.is_finite() && lat.radius > 0.0) {
                at(
                    line,
                    format!(
                        "lattice #{}: radius {} must be finite and > 0",
                        k + 1,
                        lat.radius
                    ),
                );
            }
            colour_problem(&lat.color, line, &format!("lattice #{}", k + 1), &mut at);
        }
        for (k, b) in self.block.iter().enumerate() {
            let line = Some(lines.at(b.span().start));
            let block = b.get_ref();
            if !(block.radius.is_finite() && block.radius > 0.0) {
                at(
                    line,
                    format!(
                        "block #{}: radius {} must be finite and > 0",
                        k + 1,
                        block.radius
                    ),
                );
            } else if block_counts(block, &Law::new(&self.config())).contains(&0) {
                at(
                    line,
                    format!(
                        "block #{}: {:?}..{:?} holds no disc of radius {}",
                        k + 1,
                        block.min,
                        block.max,
                        block.radius
                    ),
                );
            }
            colour_problem(&block.color, line, &format!("block #{}", k + 1), &mut at);
        }
        for (k, d) in self.disc.iter().enumerate() {
            let line = Some(lines.at(d.span().start));
            colour_problem(
                &d.get_ref().color,
                line,
                &format!("disc #{}", k + 1),
                &mut at,
            );
        }
        let count = self.particle_count();
        if count.is_none() {
            at(
                None,
                "the scenario asks for more particles than 2^64 (a count overflows)".into(),
            );
        } else if count == Some(0) && self.emitter.is_empty() && self.file.is_empty() {
            at(
                None,
                "the scenario has no particles: add [[gas]], [[lattice]], [[block]], [[disc]], [[file]] \
                 or [[emitter]]"
                    .into(),
            );
        }
        let o = &self.output;
        if o.frame_width < 16 || o.frame_width > 8192 {
            at(
                line_of_key(source, "output", "frame_width"),
                format!(
                    "output.frame_width = {} must be in 16..=8192",
                    o.frame_width
                ),
            );
        }
        if o.gif && o.frame_every == 0 {
            at(
                line_of_key(source, "output", "gif"),
                "output.gif needs output.frame_every > 0".into(),
            );
        }
        out.sort_by_key(|p| p.line.unwrap_or(usize::MAX));
        out
    }
}

pub(crate) fn colour_problem(
    colour: &Option<String>,
    line: Option<usize>,
    what: &str,
    at: &mut impl FnMut(Option<usize>, String),
) {
    if let Some(c) = colour
        && let Err(e) = parse_colour(c)
    {
        at(line, format!("{what}: {e}"));
    }
}
