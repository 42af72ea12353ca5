//! What a run demonstrates, measured: each template names its headline (`[output] headline`)
//! and this module computes it from the run's `stats.csv` rows and its first and last
//! states, with its uncertainty and the theory or reference it is held against. The run's
//! summary prints it, `summary.json` records it and `plots.png` draws it; the tests hold
//! every template's claim with it.
//!
//! Noisy quantities (the pressure, the viscosity, a driven gas's temperature) are averaged
//! over the second half of the run, the first left to settle, with the standard error of the
//! means of ten blocks: samples a few collision times apart are correlated, blocks of many
//! rows are not.

use crate::analysis::{self, henderson_z};
use crate::json::string as json_string;
use crate::structure::Snapshot;
use crate::{ObstacleSpec, Scenario};
use bounce::World;

pub use crate::schema::HeadlineKind;

/// A measured headline.
#[derive(Clone, Debug, PartialEq)]
pub struct Headline {
    /// What was measured.
    pub kind: HeadlineKind,
    /// Its name and symbol, as the summary says it: "shear viscosity η".
    pub quantity: String,
    /// The measured value.
    pub value: f64,
    /// One standard error, where the measurement has one.
    pub error: Option<f64>,
    /// The value theory or a reference gives, with its name.
    pub reference: Option<(f64, String)>,
    /// One line more: what else was measured, or how to read it.
    pub detail: String,
    /// The quantity over the run (or across the box) for `plots.png`: points, the x axis's
    /// name, and the reference's points on the same axis.
    pub series: Series,
}

/// What `plots.png` draws of a headline.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// The x axis's name ("time", "x").
    pub x: &'static str,
    /// The y axis's name.
    pub y: &'static str,
    /// The measured points.
    pub points: Vec<(f64, f64)>,
    /// The reference's points (a line), if any.
    pub reference: Vec<(f64, f64)>,
}

/// The columns of a run's `stats.csv`.
#[derive(Clone, Debug, Default)]
pub struct Rows {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
}

impl Rows {
    /// The rows of `stats.csv` text (an empty cell reads as NaN).
    pub fn parse(text: &str) -> Rows {
        let mut lines = text.lines();
        let names: Vec<String> = lines
            .next()
            .unwrap_or("")
            .split(',')
            .map(str::to_string)
            .collect();
        let mut columns = vec![Vec::new(); names.len()];
        for line in lines {
            for (column, cell) in columns.iter_mut().zip(line.split(',')) {
                column.push(cell.parse().unwrap_or(f64::NAN));
            }
        }
        Rows { names, columns }
    }

    /// A column by name.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let k = self.names.iter().position(|n| n == name)?;
        Some(&self.columns[k])
    }

    /// The column names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    fn need(&self, name: &str) -> Result<&[f64], String> {
        self.column(name)
            .ok_or_else(|| format!("stats.csv has no `{name}` column"))
    }
}

/// What a headline is measured from.
pub struct Run<'a> {
    /// The scenario.
    pub scenario: &'a Scenario,
    /// The world as the scenario builds it (step 0).
    pub start: &'a World,
    /// The world at the run's end.
    pub end: &'a World,
    /// Each disc's type by id (the scenario's types).
    pub typeid: &'a [u32],
    /// The run's `stats.csv`.
    pub rows: &'a Rows,
    /// The run's GSD frames, where it wrote some.
    pub frames: &'a [Snapshot],
    /// The physics' wall time, for [`HeadlineKind::Throughput`].
    pub physics_seconds: Option<f64>,
    /// Steps this run took, for [`HeadlineKind::Throughput`].
    pub steps_run: u64,
}

/// Monte Carlo's Z for hard discs (Kolafa & Rottner, Mol. Phys. 104, 3435 (2006), and the
/// tables the event-driven tests use), at packings 0.1 to 0.6.
const MONTE_CARLO_Z: [(f64, f64); 6] = [
    (0.1, 1.2361),
    (0.2, 1.5702),
    (0.3, 2.0631),
    (0.4, 2.8292),
    (0.5, 4.1062),
    (0.6, 6.4537),
];

/// Measures `kind` on `run`; an error says what the run lacks for it.
pub fn measure(kind: HeadlineKind, run: &Run) -> Result<Headline, String> {
    let h = match kind {
        HeadlineKind::MaxwellBoltzmann => maxwell_boltzmann(run),
        HeadlineKind::Compressibility => compressibility(run),
        HeadlineKind::Viscosity => viscosity(run),
        HeadlineKind::ReposeAngle => repose(run),
        HeadlineKind::GaltonSpread => galton(run),
        HeadlineKind::Discharge => discharge(run),
        HeadlineKind::Adiabat => adiabat(run),
        HeadlineKind::Effusion => effusion(run),
        HeadlineKind::GranularTemperature => granular_temperature(run),
        HeadlineKind::Diffusion => diffusion(run),
        HeadlineKind::Cradle => cradle(run),
        HeadlineKind::Mixing => mixing(run),
        HeadlineKind::Packing => packing(run),
        HeadlineKind::Throughput => throughput(run),
    }?;
    Ok(Headline { kind, ..h })
}

impl Headline {
    fn new(quantity: impl Into<String>, value: f64) -> Headline {
        Headline {
            kind: HeadlineKind::Throughput,
            quantity: quantity.into(),
            value,
            error: None,
            reference: None,
            detail: String::new(),
            series: Series::default(),
        }
    }

    /// The summary's line: the value with its error, the reference beside it and the ratio.
    pub fn summary(&self) -> String {
        let mut out = format!("{} = {}", self.quantity, number(self.value));
        if let Some(e) = self.error {
            out.push_str(&format!(" ± {}", number(e)));
        }
        if let Some((r, name)) = &self.reference {
            out.push_str(&format!(" ({name}: {}", number(*r)));
            if *r != 0.0 {
                out.push_str(&format!(", ratio {:.3}", self.value / r));
            }
            out.push(')');
        }
        if !self.detail.is_empty() {
            out.push_str("; ");
            out.push_str(&self.detail);
        }
        out
    }

    /// `summary.json`: the headline as a flat JSON object.
    pub fn to_json(&self) -> String {
        let kind = format!("{:?}", self.kind);
        let field = |v: Option<f64>| match v {
            Some(v) if v.is_finite() => format!("{v}"),
            _ => "null".into(),
        };
        format!(
            "{{\n  \"headline\": {},\n  \"quantity\": {},\n  \"value\": {},\n  \"error\": {},\n  \
             \"reference\": {},\n  \"reference_name\": {},\n  \"detail\": {},\n  \"summary\": {}\n}}\n",
            json_string(&snake(&kind)),
            json_string(&self.quantity),
            field(Some(self.value)),
            field(self.error),
            field(self.reference.as_ref().map(|r| r.0)),
            self.reference
                .as_ref()
                .map_or("null".into(), |r| json_string(&r.1)),
            json_string(&self.detail),
            json_string(&self.summary()),
        )
    }
}

/// `MaxwellBoltzmann` as `maxwell_boltzmann`.
fn snake(name: &str) -> String {
    let mut out = String::new();
    for (k, c) in name.chars().enumerate() {
        if c.is_uppercase() && k > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_lowercase());
    }
    out
}

/// A number with four significant digits.
fn number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e6).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}

/// The mean of `values` and its standard error from `blocks` block means.
pub fn block_mean(values: &[f64], blocks: usize) -> Option<(f64, f64)> {
    let values: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let blocks = blocks.min(values.len());
    if blocks < 2 {
        return values.first().map(|&v| (v, f64::NAN));
    }
    let size = values.len() / blocks;
    let means: Vec<f64> = (0..blocks)
        .map(|b| values[b * size..(b + 1) * size].iter().sum::<f64>() / size as f64)
        .collect();
    let mean = means.iter().sum::<f64>() / blocks as f64;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (blocks - 1) as f64;
    Some((mean, (var / blocks as f64).sqrt()))
}

/// The rows of the second half of the run: from the row whose time is half the last's.
fn second_half(rows: &Rows) -> Result<usize, String> {
    let time = rows.need("time")?;
    let end = *time.last().ok_or("stats.csv has no rows")?;
    Ok(time.partition_point(|&t| t < end / 2.0))
}

/// `values` as `blocks` block means over the whole run, against time: what the plot draws
/// of a noisy quantity.
fn block_series(time: &[f64], values: &[f64], blocks: usize) -> Vec<(f64, f64)> {
    let n = values.len().min(time.len());
    let size = (n / blocks).max(1);
    (0..n / size)
        .filter_map(|b| {
            let (from, to) = (b * size, (b + 1) * size);
            let v: Vec<f64> = values[from..to]
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .collect();
            (!v.is_empty()).then(|| {
                let t = (time[from] + time[to - 1]) / 2.0;
                (t, v.iter().sum::<f64>() / v.len() as f64)
            })
        })
        .collect()
}

/// A horizontal line over the points' time span.
fn level(points: &[(f64, f64)], value: f64) -> Vec<(f64, f64)> {
    match (points.first(), points.last()) {
        (Some(a), Some(b)) => vec![(a.0, value), (b.0, value)],
        _ => Vec::new(),
    }
}

/// A noisy per-row quantity averaged over the second half, with its block series.
fn averaged(
    run: &Run,
    quantity: &str,
    per_row: Vec<f64>,
    reference: Option<(f64, String)>,
) -> Result<Headline, String> {
    let from = second_half(run.rows)?;
    let (value, error) = block_mean(&per_row[from.min(per_row.len())..], 10)
        .ok_or("no rows in the run's second half")?;
    let time = run.rows.need("time")?;
    let points = block_series(time, &per_row, 20);
    let series = Series {
        x: "time",
        y: "block mean",
        reference: reference
            .as_ref()
            .map_or(Vec::new(), |(r, _)| level(&points, *r)),
        points,
    };
    Ok(Headline {
        error: error.is_finite().then_some(error),
        reference,
        series,
        detail: "mean over the run's second half, ± the standard error of ten blocks".into(),
        ..Headline::new(quantity, value)
    })
}

/// The discs' packing fraction in the box: their collision discs' area (`π (s r)²`) over the
/// box's.
fn packing_fraction(world: &World) -> Option<f64> {
    let (min, max) = world.config().boundary.bounds()?;
    let s = world.config().collision_radius_scale;
    let area: f64 = world
        .particles()
        .radius()
        .iter()
        .map(|r| std::f64::consts::PI * (s * r).powi(2))
        .sum();
    Some(area / ((max[0] - min[0]) * (max[1] - min[1])))
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0.0), |(s, n), v| (s + v, n + 1.0));
    if n > 0.0 { sum / n } else { f64::NAN }
}

/// The Kolmogorov–Smirnov distance of `world`'s speeds (relative to the flow in a sheared
/// box) to 2D Maxwell–Boltzmann at their temperature, the mix of the discs' masses' Rayleigh
/// curves; with the 1 % critical value `1.63 / √N` and the temperature. `None` without two
/// moving discs.
pub fn maxwell_boltzmann_distance(world: &World) -> Option<(f64, f64, f64)> {
    let total_mass = analysis::total_mass(world);
    let kt = analysis::temperature(world, total_mass);
    let masses = analysis::masses(world);
    let boundary = &world.config().boundary;
    let p = world.particles();
    let mut speeds: Vec<f64> = (0..p.len())
        .map(|i| {
            let flow = boundary.streaming_velocity(p.y()[i]).unwrap_or(0.0);
            (p.vx()[i] - flow).hypot(p.vy()[i])
        })
        .collect();
    if speeds.len() < 2 || kt <= 0.0 {
        return None;
    }
    speeds.sort_by(f64::total_cmp);
    let sample: Vec<f64> = masses
        .iter()
        .step_by((masses.len() / 500).max(1))
        .copied()
        .collect();
    let cdf = |v: f64| {
        mean(
            sample
                .iter()
                .map(|&m| bounce::scene::maxwell_boltzmann_cdf(v, kt, m)),
        )
    };
    let n = speeds.len() as f64;
    let distance = speeds
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            let f = cdf(v);
            (f - k as f64 / n).abs().max(((k + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max);
    Some((distance, 1.63 / n.sqrt(), kt))
}

fn maxwell_boltzmann(run: &Run) -> Result<Headline, String> {
    let (distance, critical, kt) = maxwell_boltzmann_distance(run.end)
        .ok_or("a Maxwell–Boltzmann fit needs two moving discs")?;
    Ok(Headline {
        reference: Some((critical, "1% critical value".into())),
        detail: if distance < critical {
            format!(
                "the speeds follow 2D Maxwell–Boltzmann at kT = {}",
                number(kt)
            )
        } else {
            format!("not yet Maxwell–Boltzmann at kT = {}", number(kt))
        },
        ..Headline::new(
            "Kolmogorov–Smirnov distance to 2D Maxwell–Boltzmann",
            distance,
        )
    })
}

/// Z of each row: `P A / (N kT)`.
fn z_per_row(run: &Run) -> Result<Vec<f64>, String> {
    let area = run
        .end
        .pressure_area()
        .ok_or("Z needs a box (walls or periodic)")?;
    let (p, t, n) = (
        run.rows.need("pressure")?,
        run.rows.need("temperature")?,
        run.rows.need("particles")?,
    );
    Ok((0..p.len()).map(|k| p[k] * area / (n[k] * t[k])).collect())
}

fn compressibility(run: &Run) -> Result<Headline, String> {
    let eta = packing_fraction(run.end).ok_or("Z needs a box")?;
    let reference = match MONTE_CARLO_Z.iter().find(|(at, _)| (at - eta).abs() < 2e-3) {
        Some(&(_, z)) => (z, "Monte Carlo".to_string()),
        None => (
            henderson_z(eta),
            "Henderson's equation of state".to_string(),
        ),
    };
    let mut h = averaged(run, "Z = P A / (N kT)", z_per_row(run)?, Some(reference))?;
    h.detail = format!("packing {eta:.3}; {}", h.detail);
    Ok(h)
}

/// Enskog's shear viscosity of hard discs of mass `m` and diameter `sigma` at packing `phi`
/// and temperature `kt`: `η0 (1/χ + 2φ + (1 + 8/π) φ² χ)` with `η0 = √(m kT / π) / (2σ)`
/// (Gass 1971) and Henderson's contact value `χ = (1 − 7φ/16) / (1 − φ)²`.
pub fn enskog_viscosity(phi: f64, kt: f64, m: f64, sigma: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let chi = (1.0 - 7.0 * phi / 16.0) / (1.0 - phi).powi(2);
    let eta0 = (m * kt / pi).sqrt() / (2.0 * sigma);
    eta0 * (1.0 / chi + 2.0 * phi + (1.0 + 8.0 / pi) * phi * phi * chi)
}

fn viscosity(run: &Run) -> Result<Headline, String> {
    let bounce::Boundary::LeesEdwards { shear_rate, .. } = run.end.config().boundary else {
        return Err("the viscosity needs a Lees–Edwards box".into());
    };
    let xy = run
        .rows
        .column("pressure_xy")
        .ok_or("the viscosity needs `output.pressure_tensor = true`")?;
    let per_row: Vec<f64> = xy.iter().map(|p| -p / shear_rate).collect();
    let from = second_half(run.rows)?;
    let kt = mean(run.rows.need("temperature")?[from..].iter().copied());
    let phi = packing_fraction(run.end).ok_or("needs a box")?;
    let p = run.end.particles();
    let m = mean(analysis::masses(run.end).into_iter());
    let sigma = 2.0 * run.end.config().collision_radius_scale * mean(p.radius().iter().copied());
    let enskog = enskog_viscosity(phi, kt, m, sigma);
    let mut h = averaged(
        run,
        "shear viscosity η = −⟨P_xy⟩ / γ̇",
        per_row,
        Some((enskog, "Enskog".into())),
    )?;
    h.detail = format!("packing {phi:.3}, kT {}; {}", number(kt), h.detail);
    Ok(h)
}

fn repose(run: &Run) -> Result<Headline, String> {
    let world = run.end;
    let floor = world
        .config()
        .boundary
        .bounds()
        .map_or(0.0, |(min, _)| min[1]);
    let column = 2.0 * mean(world.particles().radius().iter().copied()) * 2.0;
    let (left, right) = analysis::repose_flanks(world, floor, column).ok_or("no heap found")?;
    let flanks: Vec<f64> = [left, right].into_iter().flatten().collect();
    if flanks.is_empty() {
        return Err("the heap has no flank of three columns".into());
    }
    let angle = flanks.iter().sum::<f64>() / flanks.len() as f64;
    let show = |f: Option<f64>| f.map_or("none".into(), |a| format!("{a:.1}°"));
    Ok(Headline {
        detail: format!("left flank {}, right flank {}", show(left), show(right)),
        series: Series {
            x: "x",
            y: "height of the heap",
            points: analysis::heap_surface(world, floor, column),
            reference: Vec::new(),
        },
        ..Headline::new("angle of repose (degrees)", angle)
    })
}

/// The first `pegs` table: its rows, spacing and first row's height.
fn pegs(scenario: &Scenario) -> Option<(usize, [f64; 2], f64)> {
    scenario.obstacle.iter().find_map(|o| {
        let o: &ObstacleSpec = o.get_ref();
        o.pegs.map(|p| (p.rows, p.spacing, p.origin[1]))
    })
}

fn galton(run: &Run) -> Result<Headline, String> {
    let (rows, [dx, _], lowest) =
        pegs(run.scenario).ok_or("a Galton board needs a `pegs` table")?;
    let p = run.end.particles();
    let xs: Vec<f64> = (0..p.len())
        .filter(|&i| p.y()[i] < lowest - dx)
        .map(|i| p.x()[i])
        .collect();
    if xs.len() < 10 {
        return Err(format!(
            "only {} balls have come through the pegs",
            xs.len()
        ));
    }
    let m = mean(xs.iter().copied());
    let spread = (xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (xs.len() - 1) as f64).sqrt();
    // Each row moves a ball half a spacing left or right: a binomial of `rows` steps.
    let binomial = 0.5 * dx * (rows as f64).sqrt();
    // The heap against the binomial's bell, in bins a spacing wide.
    let (lo, hi) = run
        .end
        .config()
        .boundary
        .bounds()
        .map_or((m - 30.0, m + 30.0), |(a, b)| (a[0], b[0]));
    let bins = ((hi - lo) / dx).ceil().max(1.0) as usize;
    let mut counts = vec![0.0; bins];
    for x in &xs {
        counts[(((x - lo) / dx) as usize).min(bins - 1)] += 1.0;
    }
    let points = counts
        .iter()
        .enumerate()
        .map(|(k, &c)| (lo + (k as f64 + 0.5) * dx, c))
        .collect();
    let n = xs.len() as f64;
    let bell = (0..=200)
        .map(|k| {
            let x = lo + (hi - lo) * k as f64 / 200.0;
            let z = (x - m) / binomial;
            (
                x,
                n * dx * (-0.5 * z * z).exp() / (binomial * (2.0 * std::f64::consts::PI).sqrt()),
            )
        })
        .collect();
    Ok(Headline {
        reference: Some((binomial, "the binomial of independent balls".into())),
        detail: format!(
            "{} balls in the bins: they collide, so the heap is wider",
            xs.len()
        ),
        series: Series {
            x: "x",
            y: "balls in a bin",
            points,
            reference: bell,
        },
        ..Headline::new("spread of the heap σ", spread)
    })
}

/// The least-squares slope of `points` and its standard error.
fn slope(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    if n < 3.0 {
        return None;
    }
    let (mx, my) = (
        mean(points.iter().map(|p| p.0)),
        mean(points.iter().map(|p| p.1)),
    );
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let b = sxy / sxx;
    let residual: f64 = points
        .iter()
        .map(|p| (p.1 - my - b * (p.0 - mx)).powi(2))
        .sum();
    Some((b, (residual / (n - 2.0) / sxx).sqrt()))
}

fn discharge(run: &Run) -> Result<Headline, String> {
    let name = run
        .rows
        .names()
        .iter()
        .find_map(|n| {
            n.strip_prefix("sensor_")
                .and_then(|n| n.strip_suffix("_in"))
        })
        .ok_or("the discharge needs a `[[sensor]]` under the neck")?
        .to_string();
    let entries = run.rows.need(&format!("sensor_{name}_in"))?;
    let time = run.rows.need("time")?;
    let mut total = 0.0;
    let passed: Vec<(f64, f64)> = time
        .iter()
        .zip(entries)
        .map(|(&t, &n)| {
            total += n;
            (t, total)
        })
        .collect();
    // The steady part: from a fifth to four fifths of everything that passed.
    let steady: Vec<(f64, f64)> = passed
        .iter()
        .copied()
        .filter(|&(_, n)| n >= 0.2 * total && n <= 0.8 * total)
        .collect();
    let (rate, error) = slope(&steady).ok_or("too few grains passed the neck to fit a rate")?;
    // Beverloo: the rate does not depend on how full the glass is. The two halves agree.
    let half = steady.len() / 2;
    let first = slope(&steady[..half]).map(|s| s.0);
    let second = slope(&steady[half..]).map(|s| s.0);
    let detail = match (first, second) {
        (Some(a), Some(b)) if (b / a - 1.0).abs() < 0.15 => format!(
            "{total} grains through `{name}`; {} a unit time in the first half, {} in the \
             second: steady while the glass empties, as Beverloo's law says of grains",
            number(a),
            number(b)
        ),
        (Some(a), Some(b)) => format!(
            "{total} grains through `{name}`; {} a unit time in the first half, {} in the \
             second: slowing as the level falls, as a liquid does (Torricelli), not steady as \
             Beverloo's law says of grains (rough grains are: examples/python/beverloo.py)",
            number(a),
            number(b)
        ),
        _ => format!("{total} grains through `{name}`"),
    };
    let line = match (steady.first(), steady.last()) {
        (Some(a), Some(b)) => {
            let my = mean(steady.iter().map(|p| p.1));
            let mx = mean(steady.iter().map(|p| p.0));
            vec![(a.0, my + rate * (a.0 - mx)), (b.0, my + rate * (b.0 - mx))]
        }
        _ => Vec::new(),
    };
    Ok(Headline {
        error: Some(error),
        detail,
        series: Series {
            x: "time",
            y: "grains through",
            points: passed,
            reference: line,
        },
        ..Headline::new(
            format!("discharge rate through `{name}` (grains a unit time)"),
            rate,
        )
    })
}

/// The temperature a piston's gas reaches along the hard-disc adiabat from `t0` at area `a0`
/// to area `a`.
fn adiabat_temperature(t0: f64, a0: f64, a: f64, disc_area: f64) -> f64 {
    // P A / Z is N kT: the adiabat's pressure gives the temperature.
    let p = analysis::hard_disc_adiabat(a0, 1.0, disc_area, a);
    t0 * (p * a * henderson_z(disc_area / a0)) / (a0 * henderson_z(disc_area / a))
}

fn adiabat(run: &Run) -> Result<Headline, String> {
    let session_piston = crate::session::piston_of(run.scenario, run.start)
        .ok_or("the adiabat needs a named moving segment (a piston) in walls")?;
    let (name, piston) = session_piston;
    let (t, y, x) = (
        run.rows.need("temperature")?,
        run.rows.need(&format!("{name}_y"))?,
        run.rows.need(&format!("{name}_x"))?,
    );
    let time = run.rows.need("time")?;
    let (t0, a0) = (t[0], piston.gas_area([x[0], y[0]]));
    let k = t.len() - 1;
    let (t1, a1) = (t[k], piston.gas_area([x[k], y[k]]));
    let theory = adiabat_temperature(t0, a0, a1, piston.disc_area);
    let points = time.iter().zip(t).map(|(&s, &v)| (s, v / t0)).collect();
    let reference = time
        .iter()
        .zip(x.iter().zip(y))
        .map(|(&s, (&px, &py))| {
            (
                s,
                adiabat_temperature(1.0, a0, piston.gas_area([px, py]), piston.disc_area),
            )
        })
        .collect();
    Ok(Headline {
        reference: Some((theory / t0, "the hard-disc adiabat".into())),
        detail: format!(
            "compressed from area {} to {} (an ideal gas, T A constant: {:.3}x)",
            number(a0),
            number(a1),
            a0 / a1
        ),
        series: Series {
            x: "time",
            y: "T / T_start",
            points,
            reference,
        },
        ..Headline::new("heating T_end / T_start", t1 / t0)
    })
}

/// A hole in a straight wall: the wall's x and the hole's width, from two vertical segments
/// on one line with a gap between them.
fn hole(world: &World) -> Option<(f64, f64)> {
    let mut verticals: Vec<(f64, f64, f64)> = world
        .obstacle_shapes()
        .iter()
        .filter_map(|s| match *s {
            bounce::Shape::Segment { a, b } if a[0] == b[0] => {
                Some((a[0], a[1].min(b[1]), a[1].max(b[1])))
            }
            _ => None,
        })
        .collect();
    verticals.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1)));
    verticals
        .windows(2)
        .find(|w| w[0].0 == w[1].0 && w[1].1 > w[0].2)
        .map(|w| (w[0].0, w[1].1 - w[0].2))
}

fn effusion(run: &Run) -> Result<Headline, String> {
    let (wall, width) = hole(run.start)
        .ok_or("effusion needs a wall with a hole (two segments on one vertical line)")?;
    let (min, max) = run
        .start
        .config()
        .boundary
        .bounds()
        .ok_or("effusion needs a box")?;
    let left = |world: &World| world.particles().x().iter().filter(|&&x| x < wall).count() as f64;
    let (n0, n1) = (left(run.start), left(run.end));
    let area = (wall - min[0]) * (max[1] - min[1]);
    let kt = analysis::temperature(run.start, analysis::total_mass(run.start));
    let m = mean(analysis::masses(run.start).into_iter());
    // 2D: the mean speed is √(π kT / 2m), and a hole of width w lets out n v̄ w / π a unit time.
    let v_mean = (std::f64::consts::PI * kt / (2.0 * m)).sqrt();
    let t = run.end.time() - run.start.time();
    let p = 1.0 - (-v_mean * width * t / (std::f64::consts::PI * area)).exp();
    let lost = n0 - n1;
    Ok(Headline {
        error: Some((n0 * p * (1.0 - p)).sqrt()),
        reference: Some((
            n0 * p,
            "the draining formula N0 (1 − exp(−v̄ w t / (π A)))".into(),
        )),
        detail: format!(
            "{n0} discs started in the chamber; a hole {} wide, {} time units",
            number(width),
            number(t)
        ),
        ..Headline::new("discs that left the chamber", lost)
    })
}

/// van Noije & Ernst's temperature of a white-noise-driven gas of hard discs (Granular
/// Matter 1, 57 (1998)): the noise's input `2 rate T_bath (1 − 1/N)` a disc equals the
/// collisions' loss `(1 − e²) n σ χ √π T^{3/2} / √m (1 + 3 a₂/16)`.
pub fn van_noije_ernst(
    e: f64,
    rate: f64,
    bath: f64,
    n: usize,
    eta: f64,
    m: f64,
    sigma: f64,
) -> f64 {
    let density = eta / (std::f64::consts::PI * sigma * sigma / 4.0);
    let chi = (1.0 - 7.0 * eta / 16.0) / (1.0 - eta).powi(2);
    let a2 = 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e)
        / (73.0 + 56.0 * 2.0 - 24.0 * 2.0 * e - 105.0 * e + 30.0 * (1.0 - e) * e * e);
    let input = 2.0 * rate * bath * (1.0 - 1.0 / n as f64);
    let loss = (1.0 - e * e) * density * sigma * chi * std::f64::consts::PI.sqrt() / m.sqrt()
        * (1.0 + 3.0 * a2 / 16.0);
    (input / loss).powf(2.0 / 3.0)
}

fn granular_temperature(run: &Run) -> Result<Headline, String> {
    let config = run.end.config();
    let thermostat = config
        .thermostat
        .filter(|t| t.kind == bounce::ThermostatKind::WhiteNoise)
        .ok_or("a driven granular gas needs a white-noise thermostat")?;
    let eta = packing_fraction(run.end).ok_or("needs a box")?;
    let m = mean(analysis::masses(run.end).into_iter());
    let sigma =
        2.0 * config.collision_radius_scale * mean(run.end.particles().radius().iter().copied());
    let theory = van_noije_ernst(
        config.coefficient_of_restitution,
        thermostat.rate,
        thermostat.temperature,
        run.end.len(),
        eta,
        m,
        sigma,
    );
    let t = run.rows.need("temperature")?.to_vec();
    averaged(
        run,
        "temperature kT",
        t,
        Some((theory, "van Noije & Ernst".into())),
    )
}

/// The largest disc's unwrapped centre in each frame.
fn track(frames: &[Snapshot]) -> Option<Vec<[f64; 2]>> {
    let first = frames.first()?;
    let id = (0..first.diameter.len())
        .max_by(|&a, &b| first.diameter[a].total_cmp(&first.diameter[b]))?;
    frames
        .iter()
        .map(|f| {
            let p = f.position.get(id)?;
            let i = f.image.get(id)?;
            Some([
                p[0] + i[0] as f64 * f.size[0],
                p[1] + i[1] as f64 * f.size[1],
            ])
        })
        .collect()
}

fn diffusion(run: &Run) -> Result<Headline, String> {
    let track = track(run.frames).filter(|t| t.len() >= 5).ok_or(
        "the diffusion coefficient needs a GSD trajectory of five frames or more (`output.gsd_every`)",
    )?;
    let dt = run.scenario.time.dt;
    let step = |k: usize| run.frames[k].step as f64 * dt;
    let interval = step(1) - step(0);
    // The mean-square displacement over every origin, up to half the run.
    let lags = track.len() / 2;
    let msd: Vec<(f64, f64)> = (1..=lags)
        .map(|lag| {
            let d = mean((0..track.len() - lag).map(|o| {
                let (a, b) = (track[o], track[o + lag]);
                (b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)
            }));
            (lag as f64 * interval, d)
        })
        .collect();
    // Diffusive at long lags: MSD = 4 D t, fitted through the origin over the second half;
    // the log–log slope there says whether it is (1: a random walk; 2: still ballistic).
    let tail = &msd[msd.len() / 2..];
    let d = tail.iter().map(|p| p.0 * p.1).sum::<f64>()
        / tail.iter().map(|p| p.0 * p.0).sum::<f64>()
        / 4.0;
    let logs: Vec<(f64, f64)> = tail
        .iter()
        .filter(|p| p.1 > 0.0)
        .map(|p| (p.0.ln(), p.1.ln()))
        .collect();
    let alpha = slope(&logs).map_or(f64::NAN, |s| s.0);
    let regime = if (alpha - 1.0).abs() < 0.25 {
        "a random walk"
    } else {
        "not yet a random walk: run longer"
    };
    let reference = msd.iter().map(|&(t, _)| (t, 4.0 * d * t)).collect();
    Ok(Headline {
        detail: format!(
            "MSD ∝ t^{alpha:.2} at long lags over {} frames: {regime}",
            track.len()
        ),
        series: Series {
            x: "lag (time)",
            y: "mean-square displacement",
            points: msd,
            reference,
        },
        ..Headline::new("the largest disc's diffusion coefficient D", d)
    })
}

fn cradle(run: &Run) -> Result<Headline, String> {
    let speed = |world: &World| {
        let p = world.particles();
        (0..p.len())
            .map(|i| p.vx()[i].hypot(p.vy()[i]))
            .fold(0.0, f64::max)
    };
    let v0 = speed(run.start);
    if v0 == 0.0 {
        return Err("nothing moves at the start".into());
    }
    // The discs in the order they stand in, left to right.
    let mut discs = run.end.particles_by_id();
    discs.sort_by(|a, b| a.1.position[0].total_cmp(&b.1.position[0]));
    let (last, rest) = discs.split_last().ok_or("no discs")?;
    let others = rest
        .iter()
        .map(|(_, d)| d.velocity[0].hypot(d.velocity[1]))
        .fold(0.0, f64::max);
    Ok(Headline {
        reference: Some((1.0, "an ideal cradle".into())),
        detail: format!(
            "the others move at most {} of the blow's speed",
            number(others / v0)
        ),
        ..Headline::new(
            "the last disc's velocity over the blow's",
            last.1.velocity[0] / v0,
        )
    })
}

/// How far two kinds of disc are from mixed: `1 − |x̄_A − x̄_B| / (L / 2)`, 0 for two halves,
/// 1 for one mixture.
fn mixing_index(xs: impl Iterator<Item = (u32, f64)>, width: f64) -> f64 {
    let (mut sum, mut count) = ([0.0; 2], [0.0; 2]);
    for (t, x) in xs {
        let k = (t != 0) as usize;
        sum[k] += x;
        count[k] += 1.0;
    }
    1.0 - ((sum[0] / count[0] - sum[1] / count[1]).abs() / (width / 2.0)).min(1.0)
}

fn mixing(run: &Run) -> Result<Headline, String> {
    let (min, max) = run
        .end
        .config()
        .boundary
        .bounds()
        .ok_or("mixing needs a box")?;
    let width = max[0] - min[0];
    if !run.typeid.iter().any(|&t| t != 0) {
        return Err("mixing needs two types of disc".into());
    }
    let of = |world: &World| {
        mixing_index(
            world
                .particles_by_id()
                .into_iter()
                .map(|(id, d)| (run.typeid[id.0 as usize], d.position[0])),
            width,
        )
    };
    let dt = run.scenario.time.dt;
    let points: Vec<(f64, f64)> = run
        .frames
        .iter()
        .map(|f| {
            let xs = f
                .position
                .iter()
                .enumerate()
                .map(|(i, p)| (run.typeid.get(i).copied().unwrap_or(0), p[0]));
            (f.step as f64 * dt, mixing_index(xs, width))
        })
        .collect();
    Ok(Headline {
        reference: Some((1.0, "fully mixed".into())),
        detail: format!("{} at the start (two halves: 0)", number(of(run.start))),
        series: Series {
            x: "time",
            y: "mixing index",
            reference: level(&points, 1.0),
            points,
        },
        ..Headline::new("mixing index 1 − |x̄_A − x̄_B| / (L/2)", of(run.end))
    })
}

fn packing(run: &Run) -> Result<Headline, String> {
    let world = run.end;
    let (min, max) = world
        .config()
        .boundary
        .bounds()
        .ok_or("packing needs a box")?;
    let p = world.particles();
    let mut tops: Vec<f64> = (0..p.len()).map(|i| p.y()[i] + p.radius()[i]).collect();
    tops.sort_by(f64::total_cmp);
    let height = tops[(tops.len() * 19) / 20] - min[1];
    // The bulk: the pile's middle half, away from the floor and the surface.
    let (lo, hi) = (min[1] + 0.25 * height, min[1] + 0.75 * height);
    let area: f64 = (0..p.len())
        .filter(|&i| (lo..hi).contains(&p.y()[i]))
        .map(|i| std::f64::consts::PI * p.radius()[i].powi(2))
        .sum();
    let phi = area / ((max[0] - min[0]) * (hi - lo));
    let overlap = run
        .rows
        .need("max_overlap")?
        .last()
        .copied()
        .unwrap_or(f64::NAN);
    let r = mean(p.radius().iter().copied());
    Ok(Headline {
        detail: format!(
            "the largest overlap in the last rows is {} ({:.1}% of the mean radius)",
            number(overlap),
            100.0 * overlap / r
        ),
        ..Headline::new("packing fraction of the settled pile", phi)
    })
}

fn throughput(run: &Run) -> Result<Headline, String> {
    let seconds = run
        .physics_seconds
        .filter(|s| *s > 0.0)
        .ok_or("no timing")?;
    let rate = run.end.len() as f64 * run.steps_run as f64 / seconds;
    Ok(Headline {
        detail: format!(
            "{} discs, {} steps in {:.2} s of physics on {} threads",
            run.end.len(),
            run.steps_run,
            seconds,
            run.end.threads()
        ),
        ..Headline::new("disc-steps per second", rate)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_four_significant_digits() {
        assert_eq!(number(0.0), "0");
        assert_eq!(number(0.34667), "0.3467");
        assert_eq!(number(4.1062), "4.106");
        assert_eq!(number(1234.5), "1234");
        assert_eq!(number(4.8e7), "4.800e7");
    }

    #[test]
    fn block_means_give_the_mean_and_its_error() {
        let values: Vec<f64> = (0..100)
            .map(|k| if k % 2 == 0 { 1.0 } else { 3.0 })
            .collect();
        let (mean, error) = block_mean(&values, 10).unwrap();
        assert_eq!(mean, 2.0);
        assert_eq!(error, 0.0); // every block holds five of each
    }

    #[test]
    fn the_summary_says_the_value_its_error_and_the_reference() {
        let h = Headline {
            error: Some(0.02),
            reference: Some((0.35, "Enskog".into())),
            ..Headline::new("η", 0.385)
        };
        assert_eq!(
            h.summary(),
            "η = 0.3850 ± 0.02000 (Enskog: 0.3500, ratio 1.100)"
        );
        assert!(h.to_json().contains("\"reference\": 0.35"));
    }

    #[test]
    fn enskog_and_van_noije_ernst_as_the_tests_use_them() {
        // The validate check's numbers: packing 0.3, kT 1, m 0.5, σ 1.
        let pi = std::f64::consts::PI;
        let chi = (1.0 - 7.0 * 0.3 / 16.0) / 0.49;
        let by_hand = (0.5 / pi).sqrt() / 2.0 * (1.0 / chi + 0.6 + (1.0 + 8.0 / pi) * 0.09 * chi);
        assert!((enskog_viscosity(0.3, 1.0, 0.5, 1.0) - by_hand).abs() < 1e-15);
        // The driven granular template's theory: 1.104 (its comment says 1.10).
        let t = van_noije_ernst(0.9, 0.1, 1.0, 2000, 0.2, 0.5, 1.0);
        assert!((t - 1.104).abs() < 0.001, "{t}");
    }

    #[test]
    fn two_halves_are_unmixed_and_one_mixture_is_mixed() {
        let halves = (0..100).map(|k| ((k >= 50) as u32, if k < 50 { 25.0 } else { 75.0 }));
        assert_eq!(mixing_index(halves, 100.0), 0.0);
        let mixed = (0..100).map(|k| ((k % 2) as u32, 50.0));
        assert_eq!(mixing_index(mixed, 100.0), 1.0);
    }
}
