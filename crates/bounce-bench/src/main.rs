//! `bounce-bench`: the same scenes, from the same initial state, in bounce, rapier2d and
//! Box2D v3 (through `boxdd`), side by side in one run.
//!
//! `cargo run --release -p bounce-bench -- [--quick] [--out DIR] [--scenes a,b]` prints
//! Markdown tables and writes `DIR/bench.csv` and `DIR/bench.png` (ns per particle-step
//! against N). Every figure leads with the **mean** over all timed steps (at least 200; the
//! steps that rebuild bounce's candidate list included), with the 99th percentile and the
//! median beside it. Each engine and scene runs in a child process of its own, so the peak
//! resident memory it reports is that run's. The machine is read from the system.
//! `bounce-bench events [--counts N,N] [--packing η] [--time T] [--dynamo PATH]` measures the
//! event-driven method instead, in collisions per second, beside DynamO's (`events.rs`).

mod engines;
mod events;
mod scenes;

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};

use crate::engines::Engine;
use crate::scenes::SceneKind;

/// Steps timed per run (after the warm-up).
const STEPS: usize = 200;
/// Steps timed per run with `--quick`.
const QUICK_STEPS: usize = 10;
/// Warm-up steps: a settled pile re-settles in each engine's own way first.
const WARM_UP: usize = 4;
const PILE_WARM_UP: usize = 30;

#[derive(Parser)]
#[command(about = "bounce against rapier2d and Box2D v3 on the same scenes")]
struct Cli {
    #[command(subcommand)]
    command: Option<Cmd>,
    /// Fewer measured steps (a quick look, not for the record).
    #[arg(long)]
    quick: bool,
    /// Where bench.csv, bench.png and the settled piles go.
    #[arg(long, default_value = "target/bench")]
    out: PathBuf,
    /// Only these scenes (see `SceneKind::ALL`: gas-10k ... fast-gas-1m).
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
    /// Only bounce (no peers).
    #[arg(long)]
    bounce_only: bool,
}

#[derive(Subcommand)]
enum Cmd {
    /// Draws bench.png again from a saved bench.csv.
    Plot { csv: PathBuf, png: PathBuf },
    /// The event-driven method: collisions per second and Z for periodic gases.
    Events {
        /// Disc counts, ascending.
        #[arg(long, value_delimiter = ',', default_value = "100000,1000000")]
        counts: Vec<usize>,
        #[arg(long, default_value_t = 0.5)]
        packing: f64,
        /// Time units to melt, then to measure.
        #[arg(long, default_value_t = 1.0)]
        time: f64,
        /// DynamO's `dynarun` (see `scripts/build-dynamo`): the same discs in it, side by side.
        #[arg(long)]
        dynamo: Option<PathBuf>,
    },
    /// Runs one engine on one scene and prints one result line (used by the parent).
    One {
        engine: String,
        scene: String,
        #[arg(long)]
        quick: bool,
        #[arg(long)]
        cache: PathBuf,
    },
}

/// One measured run.
#[derive(Clone, Debug, Default)]
struct Row {
    scene: String,
    n: usize,
    engine: String,
    /// Mean ms per step over every timed step (`None` when skipped or failed).
    mean_ms: Option<f64>,
    p99_ms: Option<f64>,
    median_ms: Option<f64>,
    peak_mb: f64,
    /// bounce's mean ms per stage (integrate, bin, pairs, resolve, measure), the share of
    /// steps with a rebuild and the contacts per disc and substep.
    stages: Option<([f64; 5], f64, f64)>,
    note: String,
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Some(Cmd::One {
            engine,
            scene,
            quick,
            cache,
        }) => return one(&engine, &scene, quick, &cache),
        Some(Cmd::Plot { csv, png }) => return plot(&read_csv(&csv)?, &png),
        Some(Cmd::Events {
            counts,
            packing,
            time,
            dynamo,
        }) => {
            let machine = Machine::read().line();
            return events::run(&counts, packing, time, dynamo.as_deref(), &machine);
        }
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
    let machine = Machine::read();
    eprintln!("{}", machine.line());
    let cache = cli.out.join("cache");
    let exe = std::env::current_exe()?;
    let mut rows = Vec::new();
    for scene in &scenes {
        scene.settle(&cache)?;
        for engine in Engine::ALL {
            if !engine.is_bounce() && (cli.bounce_only || !scene.peers) {
                continue;
            }
            eprintln!("running {} on {} ...", engine.name(), scene.name());
            let mut cmd = Command::new(&exe);
            cmd.args(["one", engine.name(), &scene.name(), "--cache"]);
            cmd.arg(&cache);
            if cli.quick {
                cmd.arg("--quick");
            }
            let out = cmd.output().context("cannot run a benchmark child")?;
            let mut row = Row {
                scene: scene.name(),
                n: scene.count(),
                engine: engine.name().to_string(),
                peak_mb: f64::NAN,
                ..Row::default()
            };
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
                row.note = format!("failed: {reason}");
            } else {
                parse_child(String::from_utf8_lossy(&out.stdout).trim(), &mut row)?;
            }
            rows.push(row);
        }
    }
    println!("{}\n", machine.line());
    print_table(&rows, &scenes);
    print_stages(&rows, &machine);
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

/// The child: build the scene, warm up, time steps, report one line of `key=value` fields.
fn one(engine: &str, scene: &str, quick: bool, cache: &Path) -> Result<()> {
    let engine = Engine::parse(engine)?;
    let scene = SceneKind::parse(scene)?;
    let setup = scene.build(cache)?;
    let count = setup.discs.len();
    // The engine consumes the setup, so the resident figure is the engine's.
    let mut sim = engine.create(setup)?;
    // One trial step decides whether the peer is too slow to measure at this size.
    let trial = sim.step_timed();
    if trial > 2.0 {
        println!("skipped\tpeak={:.1}\tnote=a step took over 2 s", peak_mb());
        return Ok(());
    }
    let warm_up = if scene.is_pile() {
        PILE_WARM_UP
    } else {
        WARM_UP
    };
    for _ in 0..warm_up {
        sim.step_timed();
    }
    let steps = if quick { QUICK_STEPS } else { STEPS };
    let mut times = Vec::with_capacity(steps);
    let mut stages = [0.0; 5];
    let mut rebuilding_steps = 0;
    let mut contacts = 0;
    for _ in 0..steps {
        times.push(sim.step_timed());
        if let Some((s, rebuilds, pairs)) = sim.stages() {
            for (total, t) in stages.iter_mut().zip(s) {
                *total += t;
            }
            rebuilding_steps += (rebuilds > 0) as usize;
            contacts += pairs;
        }
    }
    let substeps = scene.substeps() as f64;
    let mean = times.iter().sum::<f64>() / steps as f64;
    times.sort_by(f64::total_cmp);
    let quantile = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize];
    let stages = match sim.stages() {
        Some(_) => format!(
            "\tstages={}\trebuild_share={}\tcontacts={}",
            stages
                .iter()
                .map(|t| format!("{:.6}", t / steps as f64 * 1e3))
                .collect::<Vec<_>>()
                .join(","),
            rebuilding_steps as f64 / steps as f64,
            contacts as f64 / (steps as f64 * substeps * count as f64)
        ),
        None => String::new(),
    };
    println!(
        "ok\tmean={:.6}\tp99={:.6}\tmedian={:.6}\tpeak={:.1}{stages}\tnote={}; {} discs, resident after the run {:.0} MB",
        mean * 1e3,
        quantile(0.99) * 1e3,
        quantile(0.5) * 1e3,
        peak_mb(),
        sim.note(),
        count,
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

/// Fills `row` from a child's line.
fn parse_child(line: &str, row: &mut Row) -> Result<()> {
    let mut fields = line.split('\t');
    let status = fields.next().unwrap_or_default();
    if status != "ok" && status != "skipped" {
        bail!("unexpected child output {line:?}");
    }
    for field in fields {
        let (key, value) = field.split_once('=').context("a field without =")?;
        let number = || value.parse::<f64>().context("a number");
        match key {
            "mean" => row.mean_ms = Some(number()?),
            "p99" => row.p99_ms = Some(number()?),
            "median" => row.median_ms = Some(number()?),
            "peak" => row.peak_mb = number()?,
            "stages" => {
                let v: Vec<f64> = value.split(',').map(str::parse).collect::<Result<_, _>>()?;
                let stages = <[f64; 5]>::try_from(v).map_err(|_| anyhow::anyhow!("5 stages"))?;
                row.stages = Some((stages, 0.0, 0.0));
            }
            "rebuild_share" => {
                if let Some((_, share, _)) = row.stages.as_mut() {
                    *share = number()?;
                }
            }
            "contacts" => {
                if let Some((_, _, contacts)) = row.stages.as_mut() {
                    *contacts = number()?;
                }
            }
            "note" => {
                row.note = if status == "skipped" {
                    format!("skipped: {value}")
                } else {
                    value.to_string()
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// The machine, read from the system.
struct Machine {
    cpu: String,
    cpus: usize,
    memory_gib: f64,
    /// Memory bandwidth of a streaming copy on every CPU, GB/s (read + write bytes).
    copy_gbs: f64,
}

impl Machine {
    fn read() -> Machine {
        let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let cpu = cpuinfo
            .lines()
            .find(|l| l.starts_with("model name"))
            .and_then(|l| l.split_once(':'))
            .map_or("unknown CPU".into(), |(_, v)| v.trim().to_string());
        let memory_gib = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|m| {
                m.lines()
                    .find(|l| l.starts_with("MemTotal:"))
                    .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
            })
            .map_or(f64::NAN, |kb| kb / (1024.0 * 1024.0));
        Machine {
            cpu,
            cpus: std::thread::available_parallelism().map_or(1, |n| n.get()),
            memory_gib,
            copy_gbs: copy_bandwidth(),
        }
    }

    fn line(&self) -> String {
        format!(
            "Machine: {}, {} CPUs, {:.0} GiB; streaming copy {:.1} GB/s (all CPUs, read + write)",
            self.cpu, self.cpus, self.memory_gib, self.copy_gbs
        )
    }
}

/// GB/s moved (read + written) by copying 256 MiB on every CPU at once, best of five:
/// the bandwidth the 2-thread stages can use.
fn copy_bandwidth() -> f64 {
    let n = 32 << 20; // f64s
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let source: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut target = vec![0.0f64; n];
    let part = n.div_ceil(threads);
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = std::time::Instant::now();
        std::thread::scope(|s| {
            for (to, from) in target.chunks_mut(part).zip(source.chunks(part)) {
                s.spawn(move || to.copy_from_slice(from));
            }
        });
        best = best.min(t.elapsed().as_secs_f64());
        std::hint::black_box(&target);
    }
    (2 * n * 8) as f64 / best / 1e9
}

fn print_table(rows: &[Row], scenes: &[SceneKind]) {
    println!(
        "| scene | N | engine | mean ms/step | p99 ms | median ms | ns per particle-step (mean) | time vs bounce 2 threads (means) | peak MB | notes |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let ms = |v: Option<f64>| v.map_or("–".into(), |v| format!("{v:.2}"));
    for scene in scenes {
        let of_scene: Vec<&Row> = rows.iter().filter(|r| r.scene == scene.name()).collect();
        let reference = of_scene
            .iter()
            .find(|r| r.engine == Engine::Bounce2.name())
            .and_then(|r| r.mean_ms);
        for r in of_scene {
            let (per_particle, ratio) = match r.mean_ms {
                Some(mean) => (
                    format!("{:.1}", mean * 1e6 / r.n as f64),
                    reference.map_or("–".into(), |b| format!("{:.1}x", mean / b)),
                ),
                None => ("–".into(), "–".into()),
            };
            println!(
                "| {} | {} | {} | {} | {} | {} | {per_particle} | {ratio} | {:.0} | {} |",
                r.scene,
                r.n,
                r.engine,
                ms(r.mean_ms),
                ms(r.p99_ms),
                ms(r.median_ms),
                r.peak_mb,
                r.note
            );
        }
    }
}

/// Bytes each stage must move per disc and substep at least (f64 state of 8 arrays, f32
/// reference positions, 8-byte candidate pairs, 24-byte contacts), given candidates and
/// contacts per disc and the share of substeps that rebuild.
fn stage_bytes(candidates: f64, contacts: f64, rebuild_share: f64) -> [f64; 5] {
    [
        // integrate: read and write x, y, vx, vy; read the f32 reference positions.
        64.0 + 8.0,
        // bin: a rebuild reads x, y, radius, writes cell keys, permutes every array (60
        // bytes per disc read and written), writes the reference and the candidates.
        rebuild_share * (24.0 + 8.0 + 120.0 + 8.0 + 8.0 * candidates),
        // pairs: read the candidates and both discs' x, y; write the contacts.
        8.0 * candidates + 16.0 + 24.0 * contacts,
        // resolve: per contact read and write both discs' x, y, vx, vy; read radii.
        contacts * (2.0 * 64.0 + 16.0),
        // measure: read vx, vy, radius (and mass).
        32.0,
    ]
}

/// Where bounce's time goes (2 threads), each stage beside the time its memory traffic needs
/// at the measured copy bandwidth.
fn print_stages(rows: &[Row], machine: &Machine) {
    let bounce: Vec<&Row> = rows
        .iter()
        .filter(|r| r.engine == Engine::Bounce2.name() && r.stages.is_some())
        .filter(|r| r.scene == "gas-1m" || r.scene.starts_with("pile-settled"))
        .collect();
    if bounce.is_empty() {
        return;
    }
    println!(
        "\nWhere the time goes (bounce, 2 threads; mean ms per step). Floor: the stage's least \
         memory traffic (`stage_bytes`) at the copy bandwidth above, {:.1} GB/s, with the \
         contacts per disc measured and the candidates per disc counted at a rebuild (1.5 in \
         the gas, 4.5 in the settled pile).\n",
        machine.copy_gbs
    );
    println!("| scene | stage | ms | floor ms | ratio |");
    println!("|---|---|---|---|---|");
    for r in bounce {
        let (stages, share, contacts) = r.stages.expect("filtered");
        let scene = SceneKind::parse(&r.scene).expect("a known scene");
        let substeps = scene.substeps() as f64;
        let candidates = if scene.is_pile() { 4.5 } else { 1.5 };
        let bytes = stage_bytes(candidates, contacts, share / substeps);
        let names = [
            "integrate",
            "bin (upkeep and rebuilds)",
            "pairs",
            "resolve",
            "measure",
        ];
        for k in 0..5 {
            // Every stage but the measurement runs once per substep.
            let runs = if k == 4 { 1.0 } else { substeps };
            let floor = bytes[k] * r.n as f64 * runs / (machine.copy_gbs * 1e9) * 1e3;
            println!(
                "| {} | {} | {:.2} | {:.2} | {} |",
                r.scene,
                names[k],
                stages[k],
                floor,
                if floor > 0.0 {
                    format!("{:.1}x", stages[k] / floor)
                } else {
                    "–".into()
                }
            );
        }
    }
}

/// Rows from a `bench.csv` written by [`write_csv`].
fn read_csv(path: &Path) -> Result<Vec<Row>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let number =
        |v: &str| -> Result<Option<f64>> { Ok(if v.is_empty() { None } else { Some(v.parse()?) }) };
    text.lines()
        .skip(1)
        .enumerate()
        .map(|(k, line)| {
            let f: Vec<&str> = line.split(',').collect();
            let [scene, n, engine, mean, p99, median, peak] = f[..] else {
                bail!("{}: line {}: expected 7 fields", path.display(), k + 2);
            };
            Ok(Row {
                scene: scene.to_string(),
                n: n.parse()?,
                engine: engine.to_string(),
                mean_ms: number(mean)?,
                p99_ms: number(p99)?,
                median_ms: number(median)?,
                peak_mb: number(peak)?.unwrap_or(f64::NAN),
                ..Row::default()
            })
        })
        .collect()
}

fn write_csv(rows: &[Row], path: &Path) -> Result<()> {
    let mut text = String::from("scene,n,engine,mean_ms,p99_ms,median_ms,peak_mb\n");
    let v = |x: Option<f64>| x.map_or(String::new(), |v| v.to_string());
    for r in rows {
        text.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            r.scene,
            r.n,
            r.engine,
            v(r.mean_ms),
            v(r.p99_ms),
            v(r.median_ms),
            r.peak_mb
        ));
    }
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// ns per particle-step against N for the gas scenes, one line per engine (log-log).
fn plot(rows: &[Row], path: &Path) -> Result<()> {
    use plotters::prelude::*;
    let font = std::fs::read("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
        .context("plots need fonts-dejavu-core")?;
    let font: &'static [u8] = Box::leak(font.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, font)
        .map_err(|_| anyhow::anyhow!("cannot load the font"))?;
    let gas: Vec<&Row> = rows
        .iter()
        .filter(|r| r.scene.starts_with("gas-"))
        .collect();
    let ns = |r: &Row| r.mean_ms.map(|ms| ms * 1e6 / r.n as f64);
    let mean_ns = |r: &Row| r.median_ms.map(|ms| ms * 1e6 / r.n as f64);
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
                "gas: ns per particle-step, mean (solid) and median (dashed)",
                ("sans-serif", 22),
            )
            .margin(16)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((5_000f64..20_000_000f64).log_scale(), (lo..hi).log_scale())
            .map_err(|e| anyhow::anyhow!("{e:?}"))?;
        chart
            .configure_mesh()
            .x_desc("discs N")
            .y_desc("ns per particle-step")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow::anyhow!("{e:?}"))?;
        let colours = [BLUE, CYAN, RED, MAGENTA, GREEN, BLACK];
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
