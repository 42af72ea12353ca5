//! `bounce-bench`: the same scenes, from the same initial state, in bounce, rapier2d and
//! Box2D v3 (through `boxdd`), side by side in one run.
//!
//! `cargo run --release -p bounce-bench -- [--quick] [--out DIR]` prints a Markdown table
//! (median and mean ms per step, particle-steps per second, ratio to bounce, peak memory) and writes
//! `DIR/bench.csv` and `DIR/bench.png` (ns per particle-step against N). Each engine and scene
//! runs in a child process of its own, so the peak resident memory it reports is that run's.

mod engines;
mod scenes;

use std::path::PathBuf;
use std::process::Command;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};

use crate::engines::Engine;
use crate::scenes::SceneKind;

#[derive(Parser)]
#[command(about = "bounce against rapier2d and Box2D v3 on the same scenes")]
struct Cli {
    #[command(subcommand)]
    command: Option<Cmd>,
    /// Fewer measured steps (a quick look, not for the record).
    #[arg(long)]
    quick: bool,
    /// Where bench.csv and bench.png go.
    #[arg(long, default_value = "target/bench")]
    out: PathBuf,
    /// Only these scenes (gas-10k, gas-100k, gas-1m, pile-100k, poly-100k).
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
}

#[derive(Subcommand)]
enum Cmd {
    /// Draws bench.png again from a saved bench.csv.
    Plot { csv: PathBuf, png: PathBuf },
    /// Runs one engine on one scene and prints one result line (used by the parent).
    One {
        engine: String,
        scene: String,
        #[arg(long)]
        quick: bool,
    },
}

/// One measured run.
#[derive(Clone, Debug)]
struct Row {
    scene: String,
    n: usize,
    engine: String,
    /// `None` when skipped (a step took over 2 s).
    median_ms: Option<f64>,
    /// Mean over the same steps: bounce rebuilds its candidate list every few steps, so the
    /// median alone would hide that cost.
    mean_ms: Option<f64>,
    peak_mb: f64,
    note: String,
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Some(Cmd::One {
            engine,
            scene,
            quick,
        }) => return one(&engine, &scene, quick),
        Some(Cmd::Plot { csv, png }) => return plot(&read_csv(&csv)?, &png),
        None => {}
    }
    let scenes: Vec<SceneKind> = if cli.scenes.is_empty() {
        SceneKind::ALL.to_vec()
    } else {
        cli.scenes
            .iter()
            .map(|s| SceneKind::parse(s))
            .collect::<Result<_>>()?
    };
    let exe = std::env::current_exe()?;
    let mut rows = Vec::new();
    for scene in &scenes {
        for engine in Engine::ALL {
            eprintln!("running {} on {} ...", engine.name(), scene.name());
            let mut cmd = Command::new(&exe);
            cmd.args(["one", engine.name(), scene.name()]);
            if cli.quick {
                cmd.arg("--quick");
            }
            let out = cmd.output().context("cannot run a benchmark child")?;
            if !out.status.success() {
                // A peer that aborts (Box2D asserts past 65,535 bodies per solver block) is
                // reported, not fatal: the other engines still run.
                let stderr = String::from_utf8_lossy(&out.stderr);
                let reason = stderr
                    .lines()
                    .find(|l| !l.trim().is_empty() && !l.starts_with("running"))
                    .unwrap_or("no message")
                    .trim()
                    .to_string();
                eprintln!("{} on {} failed: {reason}", engine.name(), scene.name());
                rows.push(Row {
                    scene: scene.name().to_string(),
                    n: scene.count(),
                    engine: engine.name().to_string(),
                    median_ms: None,
                    mean_ms: None,
                    peak_mb: f64::NAN,
                    note: format!("failed: {reason}"),
                });
                continue;
            }
            let line = String::from_utf8_lossy(&out.stdout);
            rows.push(parse_row(line.trim(), scene, engine)?);
        }
    }
    print_table(&rows, &scenes);
    std::fs::create_dir_all(&cli.out)?;
    write_csv(&rows, &cli.out.join("bench.csv"))?;
    plot(&rows, &cli.out.join("bench.png"))?;
    eprintln!(
        "wrote {} and {}",
        cli.out.join("bench.csv").display(),
        cli.out.join("bench.png").display()
    );
    Ok(())
}

/// The child: build the scene, warm up, time steps, report.
fn one(engine: &str, scene: &str, quick: bool) -> Result<()> {
    let engine = Engine::parse(engine)?;
    let scene = SceneKind::parse(scene)?;
    let setup = scene.build();
    let count = setup.discs.len();
    // The engine consumes the setup, so the resident figure is the engine's.
    let mut sim = engine.create(setup)?;
    // One trial step decides whether the peer is too slow to measure at this size.
    let trial = sim.step_timed();
    if trial > 2.0 {
        println!("skipped {:.1} a step took over 2 s", peak_mb());
        return Ok(());
    }
    for _ in 0..3 {
        sim.step_timed();
    }
    let steps = match (quick, count) {
        (true, _) => 5,
        (false, n) if n >= 1_000_000 => 20,
        (false, n) if n >= 100_000 => 40,
        _ => 200,
    };
    let mut times: Vec<f64> = (0..steps).map(|_| sim.step_timed()).collect();
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    times.sort_by(f64::total_cmp);
    println!(
        "ok {:.6} {:.6} {:.1} {}; resident after the run {:.0} MB",
        times[times.len() / 2] * 1e3,
        mean * 1e3,
        peak_mb(),
        sim.note(),
        resident_mb()
    );
    Ok(())
}

/// Peak resident set size of this process, in MB (Linux `VmHWM`): setup included.
fn peak_mb() -> f64 {
    status_mb("VmHWM:")
}

/// Resident set size now, in MB (Linux `VmRSS`).
fn resident_mb() -> f64 {
    status_mb("VmRSS:")
}

fn status_mb(field: &str) -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with(field))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn parse_row(line: &str, scene: &SceneKind, engine: Engine) -> Result<Row> {
    let mut parts = line.splitn(4, ' ');
    let status = parts.next().unwrap_or_default();
    let (median_ms, mean_ms, peak_mb, note) = match status {
        "ok" => {
            let mut parts = line.splitn(5, ' ').skip(1);
            let ms: f64 = parts.next().context("median")?.parse()?;
            let mean: f64 = parts.next().context("mean")?.parse()?;
            let mb: f64 = parts.next().context("memory")?.parse()?;
            (
                Some(ms),
                Some(mean),
                mb,
                parts.next().unwrap_or("").to_string(),
            )
        }
        "skipped" => {
            let mb: f64 = parts.next().context("memory")?.parse()?;
            let rest = [parts.next().unwrap_or(""), parts.next().unwrap_or("")].join(" ");
            (None, None, mb, format!("skipped: {}", rest.trim()))
        }
        other => bail!("unexpected child output {other:?}"),
    };
    Ok(Row {
        scene: scene.name().to_string(),
        n: scene.count(),
        engine: engine.name().to_string(),
        median_ms,
        mean_ms,
        peak_mb,
        note,
    })
}

fn print_table(rows: &[Row], scenes: &[SceneKind]) {
    println!(
        "| scene | N | engine | median ms/step | mean ms/step | particle-steps/s | time vs bounce (2 threads) | peak MB | notes |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for scene in scenes {
        let of_scene: Vec<&Row> = rows.iter().filter(|r| r.scene == scene.name()).collect();
        let reference = of_scene
            .iter()
            .find(|r| r.engine == Engine::Bounce2.name())
            .and_then(|r| r.median_ms);
        for r in of_scene {
            let (ms, rate, ratio) = match r.median_ms {
                Some(ms) => (
                    format!("{ms:.2}"),
                    format!("{:.2e}", r.n as f64 / (ms / 1e3)),
                    reference.map_or("–".into(), |b| format!("{:.1}x", ms / b)),
                ),
                None => ("–".into(), "–".into(), "–".into()),
            };
            let mean = r.mean_ms.map_or("–".into(), |m| format!("{m:.2}"));
            println!(
                "| {} | {} | {} | {ms} | {mean} | {rate} | {ratio} | {:.0} | {} |",
                r.scene, r.n, r.engine, r.peak_mb, r.note
            );
        }
    }
}

/// Rows from a `bench.csv` written by [`write_csv`].
fn read_csv(path: &std::path::Path) -> Result<Vec<Row>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let number =
        |v: &str| -> Result<Option<f64>> { Ok(if v.is_empty() { None } else { Some(v.parse()?) }) };
    text.lines()
        .skip(1)
        .enumerate()
        .map(|(k, line)| {
            let f: Vec<&str> = line.split(',').collect();
            let [scene, n, engine, median, mean, peak] = f[..] else {
                bail!("{}: line {}: expected 6 fields", path.display(), k + 2);
            };
            Ok(Row {
                scene: scene.to_string(),
                n: n.parse()?,
                engine: engine.to_string(),
                median_ms: number(median)?,
                mean_ms: number(mean)?,
                peak_mb: number(peak)?.unwrap_or(f64::NAN),
                note: String::new(),
            })
        })
        .collect()
}

fn write_csv(rows: &[Row], path: &std::path::Path) -> Result<()> {
    let mut text = String::from("scene,n,engine,median_ms,mean_ms,peak_mb\n");
    for r in rows {
        let ms = r.median_ms.map_or(String::new(), |v| v.to_string());
        let mean = r.mean_ms.map_or(String::new(), |v| v.to_string());
        text.push_str(&format!(
            "{},{},{},{ms},{mean},{}\n",
            r.scene, r.n, r.engine, r.peak_mb
        ));
    }
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// ns per particle-step against N for the gas scenes, one line per engine (log-log).
fn plot(rows: &[Row], path: &std::path::Path) -> Result<()> {
    use plotters::prelude::*;
    let font = std::fs::read("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
        .context("plots need fonts-dejavu-core")?;
    let font: &'static [u8] = Box::leak(font.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, font)
        .map_err(|_| anyhow::anyhow!("cannot load the font"))?;
    let gas: Vec<&Row> = rows.iter().filter(|r| r.scene.starts_with("gas")).collect();
    let ns = |r: &Row| r.median_ms.map(|ms| ms * 1e6 / r.n as f64);
    let mean_ns = |r: &Row| r.mean_ms.map(|ms| ms * 1e6 / r.n as f64);
    let hi = gas
        .iter()
        .flat_map(|r| [ns(r), mean_ns(r)])
        .flatten()
        .fold(1.0, f64::max)
        * 2.0;
    let lo = gas
        .iter()
        .filter_map(|r| ns(r))
        .fold(f64::INFINITY, f64::min)
        .min(1.0)
        / 2.0;
    let (w, h) = (900u32, 600u32);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e:?}"))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "gas: ns per particle-step, median (solid) and mean (dashed)",
                ("sans-serif", 22),
            )
            .margin(16)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((5_000f64..2_000_000f64).log_scale(), (lo..hi).log_scale())
            .map_err(|e| anyhow::anyhow!("{e:?}"))?;
        chart
            .configure_mesh()
            .x_desc("discs N")
            .y_desc("ns per particle-step")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow::anyhow!("{e:?}"))?;
        let colours = [BLUE, CYAN, RED, GREEN, MAGENTA];
        for (k, engine) in Engine::ALL.iter().enumerate() {
            let points: Vec<(f64, f64)> = gas
                .iter()
                .filter(|r| r.engine == engine.name())
                .filter_map(|r| Some((r.n as f64, ns(r)?)))
                .collect();
            let colour = colours[k % colours.len()];
            chart
                .draw_series(LineSeries::new(points.clone(), colour.stroke_width(3)))
                .map_err(|e| anyhow::anyhow!("{e:?}"))?
                .label(engine.name())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(3))
                });
            chart
                .draw_series(
                    points
                        .into_iter()
                        .map(|p| Circle::new(p, 5, colour.filled())),
                )
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            let means: Vec<(f64, f64)> = gas
                .iter()
                .filter(|r| r.engine == engine.name())
                .filter_map(|r| Some((r.n as f64, mean_ns(r)?)))
                .collect();
            chart
                .draw_series(DashedLineSeries::new(means, 8, 6, colour.stroke_width(2)))
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
            .draw()
            .map_err(|e| anyhow::anyhow!("{e:?}"))?;
        root.present().map_err(|e| anyhow::anyhow!("{e:?}"))?;
    }
    let rgba: Vec<u8> = rgb
        .chunks(3)
        .flat_map(|c| [c[0], c[1], c[2], 255])
        .collect();
    let pixmap = tiny_skia::IntSize::from_wh(w, h)
        .and_then(|s| tiny_skia::Pixmap::from_vec(rgba, s))
        .context("plot image")?;
    pixmap
        .save_png(path)
        .with_context(|| format!("cannot write {}", path.display()))
}
