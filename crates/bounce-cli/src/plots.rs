//! `plots.png`: energy and momentum over time, and the final speed histogram against the
//! 2D Maxwell–Boltzmann distribution at the measured temperature.

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use bounce::World;
use plotters::prelude::*;

/// Where TrueType fonts are looked for (Debian's fonts-dejavu-core first).
const FONTS: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// One sample of the run's history.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// Simulated time.
    pub time: f64,
    /// Kinetic energy.
    pub energy: f64,
    /// Momentum components.
    pub momentum: [f64; 2],
}

fn register_font() -> Result<()> {
    let bytes = FONTS
        .iter()
        .find_map(|p| std::fs::read(p).ok())
        .ok_or_else(|| {
            anyhow!("no TrueType font found for plots.png (install fonts-dejavu-core)")
        })?;
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
        .map_err(|_| anyhow!("cannot load the font for plots.png"))
}

/// Draws `plots.png` into `path` (atomically).
pub fn draw(history: &[Sample], world: &World, total_mass: f64, path: &Path) -> Result<()> {
    register_font()?;
    let (w, h) = (1400u32, 560u32);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (left, right) = root.split_horizontally(w / 2);
        let (top, bottom) = left.split_vertically(h / 2);
        series(&top, "kinetic energy", history, |s| s.energy, &BLUE)?;
        series(
            &bottom,
            "|momentum|",
            history,
            |s| s.momentum[0].hypot(s.momentum[1]),
            &RED,
        )?;
        histogram(&right, world, total_mass)?;
        root.present().map_err(plot_err)?;
    }
    let image = tiny_skia::IntSize::from_wh(w, h)
        .and_then(|size| {
            let rgba: Vec<u8> = rgb
                .chunks(3)
                .flat_map(|c| [c[0], c[1], c[2], 255])
                .collect();
            tiny_skia::Pixmap::from_vec(rgba, size)
        })
        .ok_or_else(|| anyhow!("cannot build the plot image"))?;
    crate::render::save_png(&image, path).context("cannot write plots.png")
}

fn plot_err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("cannot draw plots.png: {e:?}")
}

fn series<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    label: &str,
    history: &[Sample],
    value: impl Fn(&Sample) -> f64,
    colour: &RGBColor,
) -> Result<()> {
    let t_end = history.last().map_or(1.0, |s| s.time).max(1e-12);
    let t_start = history.first().map_or(0.0, |s| s.time);
    let values: Vec<f64> = history.iter().map(&value).collect();
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let pad = ((hi - lo) * 0.1).max(hi.abs() * 1e-6).max(1e-12);
    let (lo, hi) = if lo.is_finite() {
        (lo - pad, hi + pad)
    } else {
        (0.0, 1.0)
    };
    let mut chart = ChartBuilder::on(area)
        .caption(format!("{label} over time"), ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(32)
        .y_label_area_size(70)
        .build_cartesian_2d(t_start..t_end.max(t_start + 1e-12), lo..hi)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("time")
        .y_desc(label)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(plot_err)?;
    chart
        .draw_series(LineSeries::new(
            history.iter().map(|s| (s.time, value(s))),
            colour.stroke_width(2),
        ))
        .map_err(plot_err)?;
    Ok(())
}

fn histogram<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    world: &World,
    total_mass: f64,
) -> Result<()> {
    let h = bounce_scenario::analysis::speed_histogram(world, 40, total_mass);
    let (kt, width, density) = (h.kt, h.width, h.density);
    let v_max = width * density.len() as f64;
    let curve_points: Vec<(f64, f64)> = h.curve.iter().map(|&[v, d]| (v, d)).collect();
    let top = density
        .iter()
        .copied()
        .chain(curve_points.iter().map(|&(_, y)| y))
        .fold(0.0, f64::max)
        .max(1e-12)
        * 1.1;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!(
                "speed distribution at step {} (kT = {kt:.4})",
                world.step_count()
            ),
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
        .label_style(("sans-serif", 13))
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
    chart
        .draw_series(LineSeries::new(curve_points, RED.stroke_width(3)))
        .map_err(plot_err)?
        .label("2D Maxwell–Boltzmann")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], RED.stroke_width(3)));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(plot_err)?;
    Ok(())
}
