//! `bounce analyze TRAJECTORY.gsd --out DIR`: the structure of a trajectory's frames
//! (`bounce_scenario::structure`) written as `rdf.csv` (`r,g`), `psi6.csv` (`step,psi6`) and
//! `msd.csv` (`lag,time,msd`: the lag in steps and, where the file records its frames' times, in time), each with a PNG beside it. Every file is written
//! whole or not at all.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, anyhow, bail};
use bounce_scenario::atomic::AtomicFile;
use bounce_scenario::structure::{Edges, msd, psi6, rdf};
use bounce_scenario::trajectory::Trajectory;

/// What `bounce analyze` was asked.
pub struct Request<'a> {
    /// The GSD trajectory.
    pub trajectory: &'a Path,
    /// Where the files go (created if missing).
    pub out: &'a Path,
    /// The first frame used (negative: from the end).
    pub first: i64,
    /// g(r)'s reach, in mean diameters (`None`: 5, or as far as the box allows).
    pub r_max: Option<f64>,
    /// g(r)'s bin width, in mean diameters.
    pub bin: f64,
    /// The box's edges, overriding what the file records.
    pub edges: Option<Edges>,
}

/// Reads the frames, computes and writes; prints what it wrote.
pub fn analyze(request: &Request) -> Result<()> {
    let mut trajectory = Trajectory::open(request.trajectory).map_err(|e| anyhow!(e))?;
    if !(request.bin.is_finite() && request.bin > 0.0) {
        bail!(
            "--bin {}: must be a number of mean diameters > 0",
            request.bin
        );
    }
    let snapshots = trajectory
        .snapshots(request.first, request.edges)
        .map_err(|e| anyhow!(e))?;
    let edges = snapshots[0].edges;
    let first = trajectory.len() as usize - snapshots.len();
    let d = snapshots[0].mean_diameter();
    let r_max = match request.r_max {
        Some(r) if r.is_finite() && r > 0.0 => Some(r * d),
        Some(r) => bail!("--r-max {r}: must be a number of mean diameters > 0"),
        None => None,
    };
    let (r, g) = rdf(&snapshots, r_max, Some(request.bin * d)).map_err(|e| {
        anyhow!(
            "{}: {e}; choose a smaller --r-max (in mean diameters of {d})",
            request.trajectory.display()
        )
    })?;
    std::fs::create_dir_all(request.out)
        .with_context(|| format!("cannot create {}", request.out.display()))?;
    let rdf_rows: Vec<(f64, f64)> = r.into_iter().zip(g).collect();
    write_csv(&request.out.join("rdf.csv"), "r,g", &rdf_rows)?;
    crate::plots::curve(
        &request.out.join("rdf.png"),
        &format!("g(r), {} frames ({})", snapshots.len(), edges.name()),
        ("r", "g(r)"),
        &rdf_rows,
        false,
        Some(1.0),
    )?;
    let order: Vec<(f64, f64)> = snapshots.iter().map(|s| (s.step as f64, psi6(s))).collect();
    write_csv(&request.out.join("psi6.csv"), "step,psi6", &order)?;
    crate::plots::curve(
        &request.out.join("psi6.png"),
        "global bond order |ψ6|",
        ("step", "|ψ6|"),
        &order,
        false,
        None,
    )?;
    let mut written = vec!["rdf.csv", "psi6.csv"];
    match msd(&snapshots) {
        Ok((lags, values)) => {
            // The lag in time too, where the frames record their times (bounce's do): the
            // time per step from the first and last frames.
            let per_step = match (snapshots.first(), snapshots.last()) {
                (Some(a), Some(b)) if b.step > a.step => b
                    .time
                    .zip(a.time)
                    .map(|(tb, ta)| (tb - ta) / (b.step - a.step) as f64),
                _ => None,
            };
            let text: String = lags
                .iter()
                .zip(&values)
                .map(|(&lag, msd)| match per_step {
                    Some(dt) => format!("{lag},{},{msd}\n", lag as f64 * dt),
                    None => format!("{lag},,{msd}\n"),
                })
                .collect();
            let path = request.out.join("msd.csv");
            bounce_scenario::atomic::write(&path, format!("lag,time,msd\n{text}").as_bytes())
                .with_context(|| format!("cannot write {}", path.display()))?;
            let (x, scale) = match per_step {
                Some(dt) => ("lag (time)", dt),
                None => ("lag (steps)", 1.0),
            };
            let rows: Vec<(f64, f64)> =
                lags.iter().map(|&l| l as f64 * scale).zip(values).collect();
            crate::plots::curve(
                &request.out.join("msd.png"),
                "mean-square displacement",
                (x, "MSD"),
                &rows,
                true,
                None,
            )?;
            written.push("msd.csv");
        }
        Err(e) => eprintln!("bounce analyze: no msd.csv: {e}"),
    }
    println!(
        "{}: {} frames from frame {first} ({} box, mean diameter {d:.6}): {} and their PNGs \
         in {}",
        request.trajectory.display(),
        snapshots.len(),
        match snapshots.first().and_then(|f| f.slide) {
            Some(_) => "Lees–Edwards",
            None => edges.name(),
        },
        written.join(", "),
        request.out.display()
    );
    Ok(())
}

/// Writes `header` and one `x,y` row per point, at full precision.
fn write_csv(path: &Path, header: &str, rows: &[(f64, f64)]) -> Result<()> {
    let mut file =
        AtomicFile::create(path).with_context(|| format!("cannot write {}", path.display()))?;
    let w = &mut file;
    writeln!(w, "{header}")?;
    for (x, y) in rows {
        writeln!(w, "{x},{y}")?;
    }
    file.commit()
        .with_context(|| format!("cannot write {}", path.display()))
}
