//! `bounce-bench events`: the event-driven method's speed, in collisions per second on one
//! core, and its compressibility factor, for a periodic gas of equal discs (radius 0.5,
//! kT = 1, the seed's mass = radius) started on a lattice, melted for `time`, then measured
//! over `time` more. With `--dynamo PATH` the same discs, from the same start, run in
//! DynamO's `dynarun` too (built by `scripts/build-dynamo`), one row beside bounce's.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use bounce::event::EventDriven;
use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config, Particle};

/// DynamO is a 3D code: discs are spheres with their centres and velocities in the plane
/// z = 0, in a periodic box this deep (what `dynamod` gives a box one lattice cell deep:
/// enough cells across z for its neighbour list, and no sphere meets its own image).
const DYNAMO_DEPTH: f64 = 4.000_000_1;

/// Measures each count in `counts`, beside DynamO's `dynarun` where `dynamo` is given.
pub fn run(
    counts: &[usize],
    packing: f64,
    time: f64,
    dynamo: Option<&Path>,
    machine: &str,
) -> Result<()> {
    if let Some(dynarun) = dynamo
        && !dynarun.is_file()
    {
        bail!(
            "--dynamo {}: no such file (scripts/build-dynamo builds target/dynamo/build/dynarun)",
            dynarun.display()
        );
    }
    println!("{machine}");
    println!(
        "| N | packing | engine | collisions | collisions per second | Z | memory | farthest from bounce |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for &n in counts {
        let side = (n as f64 * std::f64::consts::PI * 0.25 / packing).sqrt();
        let config = Config {
            boundary: Boundary::periodic([0.0, 0.0], [side, side]),
            ..Config::default()
        };
        let gas = Gas {
            count: n,
            radius: [0.5, 0.5],
            region: None,
            speeds: Speeds::Temperature(1.0),
            drift: [0.0, 0.0],
            seed: 1,
        };
        let discs = scene::packed_gas(&gas, &config, &[])?;
        let mut world = EventDriven::new(&config, &discs)?;
        // The start as the engine has it, for DynamO: its masses (the seed's mass = radius)
        // filled in.
        let start = dynamo.map(|_| world.particles());
        drop(discs);
        world.advance(time)?;
        let begun = Instant::now();
        let seen = world.advance(time)?;
        let spent = begun.elapsed().as_secs_f64();
        let kt = world.kinetic_energy() / n as f64;
        let z = 1.0 + seen.virial / (2.0 * time * n as f64 * kt);
        println!(
            "| {n} | {packing} | bounce | {} | {:.3e} | {z:.4} | {:.0} bytes a disc (the engine's) | |",
            seen.collisions,
            seen.collisions as f64 / spent,
            world.memory_bytes() as f64 / n as f64
        );
        if let (Some(dynarun), Some(start)) = (dynamo, start) {
            let end = world.particles();
            drop(world);
            let r = run_dynamo(dynarun, &start, side, time)?;
            // How far apart the two engines' discs end (the nearest image, a disc at a time).
            let apart = end
                .iter()
                .zip(&r.positions)
                .map(|(d, p)| {
                    let gap = [0, 1].map(|a| {
                        let g = d.position[a] - 0.5 * side - p[a];
                        g - side * (g / side).round()
                    });
                    gap[0].hypot(gap[1])
                })
                .fold(0.0, f64::max);
            println!(
                "| {n} | {packing} | DynamO | {} | {:.3e} | {:.4} | {:.0} MB peak (the process's) | {apart:.1e} |",
                r.collisions,
                r.collisions as f64 / r.seconds,
                r.z,
                r.peak_kib / 1024.0
            );
        }
    }
    Ok(())
}

/// What a DynamO run over the measured interval reported.
struct DynamoRun {
    collisions: u64,
    /// Its own timing of the run (the loading and the first scheduling left out).
    seconds: f64,
    z: f64,
    /// The peak resident memory of the process.
    peak_kib: f64,
    /// Each disc's centre at the end (in the box centred on the origin).
    positions: Vec<[f64; 2]>,
}

/// Writes `discs` (in a periodic box `side` wide) as a DynamO configuration, melts it for
/// `time` and measures over `time` more, with only DynamO's `Misc` output (timing, event
/// counts, the pressure tensor, the temperature).
fn run_dynamo(dynarun: &Path, discs: &[Particle], side: f64, time: f64) -> Result<DynamoRun> {
    let dir = std::env::temp_dir().join(format!("bounce-dynamo-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let start = dir.join("start.xml");
    std::fs::write(&start, dynamo_config(discs, side))?;
    let melted = dir.join("melted.xml");
    let output = dir.join("output.xml");
    // `-E`: no output plugins but those asked for (`Misc` in the measured run); the melt's
    // output is written too, so into the folder, not the working one.
    let run = |config: &Path, out: &Path, data: &Path, plugins: &[&str]| -> Result<()> {
        let status = Command::new(dynarun)
            .arg(config)
            .args(["-E", "-f", &time.to_string(), "-o"])
            .arg(out)
            .arg("--out-data-file")
            .arg(data)
            .args(plugins)
            .stdout(std::process::Stdio::null())
            .status()
            .with_context(|| format!("running {}", dynarun.display()))?;
        if !status.success() {
            bail!("{} failed: {status}", dynarun.display());
        }
        Ok(())
    };
    run(&start, &melted, &dir.join("melt.xml"), &[])?;
    run(&melted, &dir.join("end.xml"), &output, &["-L", "Misc"])?;
    let report = std::fs::read_to_string(&output)?;
    let positions = centres(&std::fs::read_to_string(dir.join("end.xml"))?)?;
    if positions.len() != discs.len() {
        bail!(
            "DynamO's end holds {} discs, not {}",
            positions.len(),
            discs.len()
        );
    }
    std::fs::remove_dir_all(&dir)?;
    let n = discs.len() as f64;
    let tensor = numbers_after(&report, "<Tensor>", 9)?;
    // DynamO's temperature is Σ m v² / (3N) (three dimensions); the discs' kT is Σ m v² / 2N.
    let kt = 1.5 * attribute(&report, "<Temperature", "Mean")?;
    // The plane's pressure is the tensor's in-plane mean times the box's depth.
    let pressure = 0.5 * (tensor[0] + tensor[4]) * DYNAMO_DEPTH;
    Ok(DynamoRun {
        collisions: attribute(&report, "<Duration", "TwoParticleEvents")? as u64,
        seconds: attribute(&report, "<Timing", "RuntimeSeconds")?,
        z: pressure * side * side / (n * kt),
        peak_kib: attribute(&report, "<Memusage", "MaxKiloBytes")?,
        positions,
    })
}

/// `discs` as a DynamO configuration: hard spheres of diameter 1 (the discs' collision
/// distance; radius 0.5 throughout) with the discs' mass, in a periodic box centred on the
/// origin.
fn dynamo_config(discs: &[Particle], side: f64) -> String {
    use std::fmt::Write;
    let mass = discs.first().and_then(|d| d.mass).unwrap_or(1.0);
    let mut xml = String::new();
    let _ = write!(
        xml,
        "<?xml version=\"1.0\"?>\n<DynamOconfig version=\"1.5.0\">\n<Simulation>\n\
         <Scheduler Type=\"NeighbourList\"><Sorter Type=\"BoundedPQMinMax3\"/></Scheduler>\n\
         <SimulationSize x=\"{side:?}\" y=\"{side:?}\" z=\"{DYNAMO_DEPTH:?}\"/>\n\
         <Genus><Species Mass=\"{mass:?}\" Name=\"Bulk\" Type=\"Point\"><IDRange Type=\"All\"/>\
         </Species></Genus>\n<BC Type=\"PBC\"/>\n<Topology/>\n<Interactions>\
         <Interaction Type=\"HardSphere\" Diameter=\"1\" Name=\"Bulk\">\
         <IDPairRange Type=\"All\"/></Interaction></Interactions>\n\
         <Locals/><Globals/><SystemEvents/><Dynamics Type=\"Newtonian\"/>\n</Simulation>\n\
         <Properties/>\n<ParticleData>\n"
    );
    for (k, d) in discs.iter().enumerate() {
        let [x, y] = d.position.map(|p| p - 0.5 * side);
        let [u, v] = d.velocity;
        let _ = writeln!(
            xml,
            "<Pt ID=\"{k}\"><P x=\"{x:?}\" y=\"{y:?}\" z=\"0\"/><V x=\"{u:?}\" y=\"{v:?}\" z=\"0\"/></Pt>"
        );
    }
    xml.push_str("</ParticleData>\n</DynamOconfig>\n");
    xml
}

/// The value of attribute `name` of the first element opening with `tag` in `xml`.
fn attribute(xml: &str, tag: &str, name: &str) -> Result<f64> {
    let element = xml
        .find(tag)
        .map(|at| &xml[at..])
        .and_then(|rest| rest.split('>').next())
        .with_context(|| format!("DynamO's output has no {tag}"))?;
    let key = format!(" {name}=\"");
    let value = element
        .find(&key)
        .map(|at| &element[at + key.len()..])
        .and_then(|rest| rest.split('"').next())
        .with_context(|| format!("DynamO's {tag} has no {name}"))?;
    value
        .parse()
        .with_context(|| format!("DynamO's {tag} {name} = {value:?}"))
}

/// Every particle's centre in a DynamO configuration, in the order written (DynamO writes
/// them by ID).
fn centres(xml: &str) -> Result<Vec<[f64; 2]>> {
    xml.split("<P ")
        .skip(1)
        .map(|element| {
            let element = format!("<P {}", element.split('>').next().unwrap_or(""));
            Ok([
                attribute(&element, "<P", "x")?,
                attribute(&element, "<P", "y")?,
            ])
        })
        .collect()
}

/// The first `count` numbers after `marker` in `xml`.
fn numbers_after(xml: &str, marker: &str, count: usize) -> Result<Vec<f64>> {
    let at = xml
        .find(marker)
        .with_context(|| format!("DynamO's output has no {marker}"))?;
    let numbers: Vec<f64> = xml[at + marker.len()..]
        .split_whitespace()
        .take(count)
        .map(str::parse)
        .collect::<Result<_, _>>()
        .with_context(|| format!("DynamO's {marker}"))?;
    if numbers.len() < count {
        bail!("DynamO's {marker} holds fewer than {count} numbers");
    }
    Ok(numbers)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dynamos_report_is_read_as_it_is_written() {
        let report = "<Misc>\n<Timing RuntimeSeconds=\"8.94\" EventsPerSec=\"1\"/>\n\
                      <Temperature Mean=\"0.668\" Current=\"1\"/>\n<Pressure Avg=\"0.43\">\n\
                      <Tensor>\n0.655 -0.0003 0\n-0.0003 0.656 0\n0 0 0\n</Tensor>\n\
                      <Duration Events=\"99\" TwoParticleEvents=\"994199\"/>";
        assert_eq!(
            attribute(report, "<Timing", "RuntimeSeconds").unwrap(),
            8.94
        );
        assert_eq!(
            attribute(report, "<Duration", "TwoParticleEvents").unwrap(),
            994199.0
        );
        assert_eq!(
            numbers_after(report, "<Tensor>", 9).unwrap()[4],
            0.656,
            "the tensor's yy"
        );
        let end = "<ParticleData>\n<Pt ID=\"0\">\n<P x=\"-1.5\" y=\"2.25\" z=\"0\"/>\n\
                   <V x=\"9\" y=\"9\" z=\"0\"/>\n</Pt>\n<Pt ID=\"1\"><P x=\"3\" y=\"-4\" z=\"0\"/>";
        assert_eq!(centres(end).unwrap(), vec![[-1.5, 2.25], [3.0, -4.0]]);
        let missing = attribute(report, "<Memusage", "MaxKiloBytes").unwrap_err();
        assert!(missing.to_string().contains("<Memusage"), "{missing}");
    }

    #[test]
    fn the_configuration_holds_every_disc_centred_on_the_origin() {
        let discs = [
            Particle {
                mass: Some(0.5),
                ..Particle::new([1.0, 9.0], [0.25, -1.5], 0.5)
            },
            Particle::new([5.0, 5.0], [0.0, 0.0], 0.5),
        ];
        let xml = dynamo_config(&discs, 10.0);
        assert!(xml.contains("<Species Mass=\"0.5\""), "{xml}");
        assert!(
            xml.contains("<SimulationSize x=\"10.0\" y=\"10.0\""),
            "{xml}"
        );
        assert!(
            xml.contains("<Pt ID=\"0\"><P x=\"-4.0\" y=\"4.0\" z=\"0\"/><V x=\"0.25\" y=\"-1.5\""),
            "{xml}"
        );
        assert_eq!(xml.matches("<Pt ").count(), 2);
    }
}
