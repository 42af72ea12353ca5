//! `plots.png`: energy and momentum over time, and the final speed histogram, with the 2D
//! Maxwell–Boltzmann distribution at the measured temperature where it applies (no gravity:
//! a pile in a gravity field is not a gas in equilibrium; in a sheared box, the speeds
//! relative to the flow).
//!
//! Axis ranges are made finite and non-empty whatever the data (a run that overflowed stops
//! before its data is written, but huge finite values must still draw), and tick labels use
//! a short scientific form so they never run into each other.

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use bounce::World;
use bounce_scenario::Piston;
use bounce_scenario::analysis::hard_disc_adiabat;
use bounce_scenario::headline::Headline;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// One sample of the run's history.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// Simulated time.
    pub time: f64,
    /// Kinetic energy.
    pub energy: f64,
    /// Momentum components.
    pub momentum: [f64; 2],
    /// Potential energy in the gravity field.
    pub potential: f64,
    /// A piston's centre and the mean force on it since the previous row, when the run has
    /// one.
    pub piston: Option<[f64; 4]>,
}

pub(crate) fn register_font() -> Result<()> {
    let bytes = crate::font::bytes().ok_or_else(|| {
        anyhow!("no TrueType font found for plots.png (install fonts-dejavu-core)")
    })?;
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
        .map_err(|_| anyhow!("cannot load the font for plots.png"))
}

/// Draws `plots.png` into `path` (atomically).
pub fn draw(
    history: &[Sample],
    world: &World,
    total_mass: f64,
    piston: Option<&Piston>,
    headline: Option<&Headline>,
    path: &Path,
) -> Result<()> {
    register_font()?;
    // A headline adds a strip below: its value and reference, and its series against theory.
    let strip = match headline {
        Some(h) if !h.series.points.is_empty() => 300,
        Some(_) => 50,
        None => 0,
    };
    let (w, h) = (1400u32, 560u32 + strip);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (root, below) = root.split_vertically(560);
        if let Some(headline) = headline {
            headline_strip(&below, headline)?;
        }
        let (left, right) = root.split_horizontally(w / 2);
        let (top, bottom) = left.split_vertically(280);
        let gravity = world.config().gravity != [0.0, 0.0];
        if gravity {
            series(
                &top,
                "energy",
                history,
                &[
                    ("kinetic", &|s: &Sample| s.energy, &BLUE),
                    (
                        "kinetic + potential",
                        &|s: &Sample| s.energy + s.potential,
                        &BLACK,
                    ),
                ],
            )?;
        } else {
            series(
                &top,
                "kinetic energy",
                history,
                &[("kinetic", &|s: &Sample| s.energy, &BLUE)],
            )?;
        }
        match piston {
            // A piston run: its pressure against the gas's area (instead of the momentum).
            Some(piston) => pressure_area(&bottom, history, piston)?,
            None => series(
                &bottom,
                "|momentum|",
                history,
                &[(
                    "|momentum|",
                    &|s: &Sample| s.momentum[0].hypot(s.momentum[1]),
                    &RED,
                )],
            )?,
        }
        histogram(&right, world, total_mass, !gravity)?;
        root.present().map_err(plot_err)?;
    }
    save_rgb(&rgb, w, h, path)
}

/// Saves an RGB buffer of `w` × `h` pixels as a PNG (atomically).
pub(crate) fn save_rgb(rgb: &[u8], w: u32, h: u32, path: &Path) -> Result<()> {
    let image = tiny_skia::IntSize::from_wh(w, h)
        .and_then(|size| {
            let rgba: Vec<u8> = rgb
                .chunks(3)
                .flat_map(|c| [c[0], c[1], c[2], 255])
                .collect();
            tiny_skia::Pixmap::from_vec(rgba, size)
        })
        .ok_or_else(|| anyhow!("cannot build the plot image"))?;
    crate::render::save_png(&image, path)
        .with_context(|| format!("cannot write {}", path.display()))
}

pub(crate) fn plot_err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("cannot draw plots.png: {e:?}")
}

/// A finite, non-empty axis range around the finite values of `values`, padded by a tenth.
fn axis_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return (0.0, 1.0);
    }
    // Halved first so that the span of values near ±f64::MAX stays finite.
    let (half_lo, half_hi) = (lo / 2.0, hi / 2.0);
    let half_pad = ((half_hi - half_lo) * 0.1)
        .max(half_hi.abs().max(half_lo.abs()) * 1e-6)
        .max(1e-300);
    let (lo, hi) = (2.0 * (half_lo - half_pad), 2.0 * (half_hi + half_pad));
    if lo.is_finite() && hi.is_finite() && lo < hi {
        (lo, hi)
    } else {
        (-f64::MAX / 2.0, f64::MAX / 2.0)
    }
}

/// A tick label: plain for ordinary magnitudes, scientific otherwise, and always short.
fn tick(v: &f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-3..1e5).contains(&a) {
        format!("{v:.4}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        format!("{v:.2e}")
    }
}

type Line<'a> = (&'a str, &'a dyn Fn(&Sample) -> f64, &'a RGBColor);

/// The chart's legend, boxed, in the top right.
fn legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    size: u32,
) -> Result<()> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", size))
        .draw()
        .map_err(plot_err)
}

/// A captioned chart over `x` and `y` with its mesh and labelled axes drawn.
fn xy_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    caption: &str,
    (x, x_desc): (std::ops::Range<f64>, &str),
    (y, y_desc): (std::ops::Range<f64>, &str),
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(84)
        .build_cartesian_2d(x, y)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style(("sans-serif", 13))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(plot_err)?;
    Ok(chart)
}

/// The pressure on a piston (the force into it over its length, mean over each row's
/// steps) against the area the gas has, with the hard-disc adiabat through the first
/// measured points (`analysis::hard_disc_adiabat`: `d ln T = −Z(η) d ln A` with Henderson's
/// `Z`; the ideal gas's `P A²` constant holds only where the gas is dilute).
fn pressure_area<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    history: &[Sample],
    piston: &Piston,
) -> Result<()> {
    let [nx, ny] = piston.towards;
    let points: Vec<(f64, f64)> = history
        .iter()
        .skip(1)
        .filter_map(|s| s.piston)
        .map(|[x, y, fx, fy]| {
            // The gas pushes the piston against the normal.
            let pressure = -(fx * nx + fy * ny) / piston.length;
            (piston.gas_area([x, y]), pressure)
        })
        .filter(|(a, p)| a.is_finite() && p.is_finite() && *a > 0.0)
        .collect();
    let (a_lo, a_hi) = axis_range(points.iter().map(|p| p.0));
    let (p_lo, p_hi) = axis_range(points.iter().map(|p| p.1));
    let mut chart = xy_chart(
        area,
        "pressure on the piston against area",
        (a_lo..a_hi, "area"),
        (p_lo..p_hi, "pressure"),
    )?;
    chart
        .draw_series(
            points
                .iter()
                .map(|&(a, p)| Circle::new((a, p.clamp(p_lo, p_hi)), 2, BLUE.filled())),
        )
        .map_err(plot_err)?
        .label("measured (mean per row)")
        .legend(|(x, y)| Circle::new((x + 7, y), 3, BLUE.filled()));
    // The adiabat through the mean of the first few points.
    let first: Vec<&(f64, f64)> = points.iter().take(5).collect();
    if !first.is_empty() {
        let a0 = first.iter().map(|p| p.0).sum::<f64>() / first.len() as f64;
        let p0 = first.iter().map(|p| p.1).sum::<f64>() / first.len() as f64;
        let curve = (0..=100).filter_map(|k| {
            let a = a_lo + (a_hi - a_lo) * k as f64 / 100.0;
            let p = hard_disc_adiabat(a0, p0, piston.disc_area, a);
            p.is_finite().then_some((a, p.clamp(p_lo, p_hi)))
        });
        chart
            .draw_series(LineSeries::new(curve, BLACK.stroke_width(2)))
            .map_err(plot_err)?
            .label("hard-disc adiabat (Henderson's Z)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], BLACK.stroke_width(2)));
    }
    legend(&mut chart, 13)?;
    Ok(())
}

fn series<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    label: &str,
    history: &[Sample],
    lines: &[Line],
) -> Result<()> {
    // The run's time span exactly; padded only when it is a single instant.
    let (t_start, t_end) = match (history.first(), history.last()) {
        (Some(a), Some(b)) if a.time < b.time && (b.time - a.time).is_finite() => (a.time, b.time),
        _ => axis_range(history.iter().map(|s| s.time)),
    };
    let (lo, hi) = axis_range(
        lines
            .iter()
            .flat_map(|(_, value, _)| history.iter().map(value)),
    );
    let mut chart = xy_chart(
        area,
        &format!("{label} over time"),
        (t_start..t_end, "time"),
        (lo..hi, label),
    )?;
    let columns = area.dim_in_pixel().0 as usize;
    for &(name, value, colour) in lines {
        let points: Vec<(f64, f64)> = history
            .iter()
            .map(|s| (s.time, value(s).clamp(lo, hi)))
            .filter(|(t, v)| t.is_finite() && v.is_finite())
            .collect();
        // Thick lines are drawn segment by segment, and steep short segments then break up;
        // a line with more than a point every few pixels is drawn one pixel wide, unbroken.
        let width = if points.len() * 4 > columns { 1 } else { 2 };
        chart
            .draw_series(LineSeries::new(
                envelope(&points, t_start, t_end, columns),
                colour.stroke_width(width),
            ))
            .map_err(plot_err)?
            .label(name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 14, y)], colour.stroke_width(2))
            });
    }
    if lines.len() > 1 {
        legend(&mut chart, 13)?;
    }
    Ok(())
}

/// The headline: its summary as the caption, and its series (the measured points) against
/// its reference (a line) where it has one.
fn headline_strip<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    headline: &Headline,
) -> Result<()> {
    let caption = headline.summary();
    let series = &headline.series;
    if series.points.is_empty() {
        area.draw(&Text::new(
            caption,
            (16, 16),
            ("sans-serif", 16).into_font().color(&BLACK),
        ))
        .map_err(plot_err)?;
        return Ok(());
    }
    let all = || series.points.iter().chain(&series.reference);
    let (x_lo, x_hi) = axis_range(all().map(|p| p.0));
    let (y_lo, y_hi) = axis_range(all().map(|p| p.1).chain([0.0]));
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 15))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(84)
        .build_cartesian_2d(x_lo..x_hi, y_lo..y_hi)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(series.x)
        .y_desc(series.y)
        .x_labels(8)
        .y_labels(5)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style(("sans-serif", 13))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(plot_err)?;
    chart
        .draw_series(
            series
                .points
                .iter()
                .map(|&(x, y)| Circle::new((x, y.clamp(y_lo, y_hi)), 3, BLUE.filled())),
        )
        .map_err(plot_err)?
        .label("measured")
        .legend(|(x, y)| Circle::new((x + 7, y), 3, BLUE.filled()));
    if !series.reference.is_empty() {
        let name = headline
            .reference
            .as_ref()
            .map_or("theory".to_string(), |r| r.1.clone());
        chart
            .draw_series(LineSeries::new(
                series
                    .reference
                    .iter()
                    .map(|&(x, y)| (x, y.clamp(y_lo, y_hi))),
                RED.stroke_width(2),
            ))
            .map_err(plot_err)?
            .label(name)
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], RED.stroke_width(2)));
    }
    legend(&mut chart, 13)?;
    Ok(())
}

/// `points` (in time order) thinned to what `columns` pixel columns show: in each column
/// its first point, its lowest and highest and its last, in time order: the same picture
/// from at most four points a column, whatever the row count.
fn envelope(points: &[(f64, f64)], t0: f64, t1: f64, columns: usize) -> Vec<(f64, f64)> {
    if points.len() <= 2 * columns.max(1) || t1 <= t0 {
        return points.to_vec();
    }
    let column = |t: f64| (((t - t0) / (t1 - t0)) * columns as f64).floor() as i64;
    let mut out = Vec::with_capacity(4 * columns);
    for group in points.chunk_by(|a, b| column(a.0) == column(b.0)) {
        let low = group
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.1.total_cmp(&b.1.1))
            .unwrap();
        let high = group
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.1.total_cmp(&b.1.1))
            .unwrap();
        let mut picked = [0, low.0, high.0, group.len() - 1];
        picked.sort_unstable();
        let mut last = None;
        for k in picked {
            if last != Some(k) {
                out.push(group[k]);
                last = Some(k);
            }
        }
    }
    out
}

fn histogram<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    world: &World,
    total_mass: f64,
    with_theory: bool,
) -> Result<()> {
    let h = bounce_scenario::analysis::speed_histogram(world, 40, total_mass);
    let (kt, width, density) = (h.kt, h.width, h.density);
    let v_max = width * density.len() as f64;
    let (_, v_max) = axis_range([0.0, v_max].into_iter());
    let curve_points: Vec<(f64, f64)> = if with_theory {
        h.curve.iter().map(|&[v, d]| (v, d)).collect()
    } else {
        Vec::new()
    };
    let top = density
        .iter()
        .copied()
        .chain(curve_points.iter().map(|&(_, y)| y))
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    let (_, top) = axis_range([0.0, top].into_iter());
    let what = if world.config().boundary.is_sheared() {
        "speeds relative to the shear flow"
    } else {
        "speed distribution"
    };
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{what} at step {} (kT = {kt:.4})", world.step_count()),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(32)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..v_max, 0.0..top)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("speed")
        .y_desc("probability density")
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style(("sans-serif", 13))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(plot_err)?;
    chart
        .draw_series(density.iter().enumerate().map(|(k, &d)| {
            let x0 = k as f64 * width;
            Rectangle::new(
                [(x0, 0.0), (x0 + width, d)],
                RGBColor(120, 160, 220).filled(),
            )
        }))
        .map_err(plot_err)?
        .label("simulation")
        .legend(|(x, y)| {
            Rectangle::new(
                [(x, y - 5), (x + 14, y + 5)],
                RGBColor(120, 160, 220).filled(),
            )
        });
    if with_theory {
        chart
            .draw_series(LineSeries::new(curve_points, RED.stroke_width(3)))
            .map_err(plot_err)?
            .label("2D Maxwell–Boltzmann")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], RED.stroke_width(3)));
    }
    legend(&mut chart, 14)?;
    Ok(())
}

/// One curve through `points`, drawn into `path` (a PNG, atomically): `bounce analyze`'s
/// g(r), |ψ6| and MSD. With `log`, both axes are logarithmic (points not above 0 left out);
/// `level` draws a dashed horizontal line (g = 1).
pub fn curve(
    path: &Path,
    caption: &str,
    (x_desc, y_desc): (&str, &str),
    points: &[(f64, f64)],
    log: bool,
    level: Option<f64>,
) -> Result<()> {
    register_font()?;
    let points: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && (!log || (*x > 0.0 && *y > 0.0)))
        .collect();
    let (w, h) = (800u32, 520u32);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut x = axis_range(points.iter().map(|p| p.0));
        let mut y = axis_range(points.iter().map(|p| p.1).chain(level));
        let line =
            |chart_points: Vec<(f64, f64)>| LineSeries::new(chart_points, BLUE.stroke_width(2));
        if log {
            let positive = |(lo, hi): (f64, f64), values: &mut dyn Iterator<Item = f64>| {
                let lo = values
                    .fold(f64::INFINITY, f64::min)
                    .min(hi)
                    .max(lo.max(f64::MIN_POSITIVE));
                (lo / 1.5, hi * 1.5)
            };
            x = positive(x, &mut points.iter().map(|p| p.0));
            y = positive(y, &mut points.iter().map(|p| p.1));
            let mut chart = ChartBuilder::on(&root)
                .caption(caption, ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(84)
                .build_cartesian_2d((x.0..x.1).log_scale(), (y.0..y.1).log_scale())
                .map_err(plot_err)?;
            // Few labels on log axes: their ticks bunch at each decade's end.
            chart
                .configure_mesh()
                .x_desc(x_desc)
                .y_desc(y_desc)
                .x_labels(5)
                .y_labels(5)
                .x_label_formatter(&tick)
                .y_label_formatter(&tick)
                .label_style(("sans-serif", 13))
                .light_line_style(TRANSPARENT)
                .draw()
                .map_err(plot_err)?;
            chart.draw_series(line(points)).map_err(plot_err)?;
        } else {
            let mut chart = xy_chart(&root, caption, (x.0..x.1, x_desc), (y.0..y.1, y_desc))?;
            if let Some(level) = level {
                chart
                    .draw_series(DashedLineSeries::new(
                        [(x.0, level), (x.1, level)],
                        6,
                        4,
                        BLACK.stroke_width(1),
                    ))
                    .map_err(plot_err)?;
            }
            chart.draw_series(line(points)).map_err(plot_err)?;
        }
        root.present().map_err(plot_err)?;
    }
    save_rgb(&rgb, w, h, path)
}

#[cfg(test)]
mod tests {
    use super::envelope;

    #[test]
    fn the_envelope_keeps_each_columns_extremes_and_order() {
        // 10,000 points over 100 columns: a sawtooth whose extremes are known.
        let points: Vec<(f64, f64)> = (0..10_000)
            .map(|k| (k as f64 / 10_000.0, ((k % 37) as f64) - 18.0))
            .collect();
        let thin = envelope(&points, 0.0, 1.0, 100);
        assert!(thin.len() <= 400, "{} points", thin.len());
        assert!(thin.windows(2).all(|w| w[0].0 <= w[1].0), "in time order");
        let (lo, hi) = thin.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
            (lo.min(p.1), hi.max(p.1))
        });
        assert_eq!((lo, hi), (-18.0, 18.0));
        // Few points are drawn as they are.
        assert_eq!(
            envelope(&points[..50], 0.0, 1.0, 100),
            points[..50].to_vec()
        );
    }
}
