//! Discs from a file: a frame of a GSD trajectory or a CSV table, for a scenario's `[[file]]`
//! tables and the Python package's `World.add_file`.
//!
//! - **GSD** (HOOMD-blue's `hoomd` schema, as bounce, HOOMD and the `gsd` package write it):
//!   `particles/position`, `velocity`, `diameter`, `mass`, `typeid` and `types`, and
//!   `configuration/box`, of one frame; with `particles/orientation`, `angmom` and
//!   `moment_inertia` (rotation about z), each disc's orientation and angular velocity. As in HOOMD's `create_state_from_gsd`, a chunk a frame
//!   lacks is taken from frame 0, and one frame 0 lacks from the schema's default (velocity 0,
//!   diameter 1, mass 1, type 0 of `["A"]`). Positions are relative to the box centre: they
//!   are placed around the world's box centre (the origin in an open world), and the file's
//!   box must have the world's size (a triclinic box is refused).
//! - **CSV**: a header naming the columns, in any order: `x`, `y` and `radius` required,
//!   `vx`, `vy`, `angular_velocity` (default 0), `mass` and `type` optional; one disc a row.
//!
//! Both are read in one pass, O(N): a million discs in about a second. Every value is checked
//! (finite numbers, a radius and mass > 0); the world then admits the discs as it does any
//! scenario's, so a file and a table fail alike, naming the file and the disc.

use std::path::Path;

use bounce::{Boundary, Particle};

pub use crate::FileDiscs;
use crate::gsd::{RawEntry, find, floats, read_at, read_layout};

/// Where the world's box is: its centre and size (`None` in an open world).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// The box centre discs are placed around (the origin in an open world).
    pub centre: [f64; 2],
    /// The box's size, which a GSD file's box must match (`None`: an open world, any box).
    pub size: Option<[f64; 2]>,
}

/// Reads the discs of `path`: a GSD file's frame `frame` (negative counts from the end: -1 is
/// the last) or a CSV table (by the extension `.csv`). Errors name the file and what is wrong.
pub fn read(path: &Path, frame: i64, world: Frame) -> Result<FileDiscs, String> {
    let name = path.display().to_string();
    let is_csv = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let read = if is_csv {
        read_csv(path)
    } else {
        read_gsd(path, frame, world)
    };
    read.map_err(|e| format!("{name}: {e}"))
}

/// [`read`] for a world of `boundary`: discs placed around its box centre (the origin in an
/// open world), the file's box checked against it, and, in a periodic box, a centre that
/// 32-bit rounding put on the far edge moved to the near one.
pub fn read_for(path: &Path, frame: i64, boundary: &Boundary) -> Result<FileDiscs, String> {
    let placing = match boundary.bounds() {
        Some((min, max)) => Frame {
            centre: [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0],
            size: Some([max[0] - min[0], max[1] - min[1]]),
        },
        None => Frame {
            centre: [0.0, 0.0],
            size: None,
        },
    };
    let mut read = read(path, frame, placing)?;
    if let Boundary::Periodic { min, max } = *boundary {
        for disc in &mut read.discs {
            for k in 0..2 {
                let x = &mut disc.position[k];
                if x.is_finite() && !(*x >= min[k] && *x < max[k]) {
                    *x = min[k] + (*x - min[k]).rem_euclid(max[k] - min[k]);
                    if *x >= max[k] {
                        *x = min[k];
                    }
                }
            }
        }
    }
    Ok(read)
}

/// How many discs `path` holds, without reading them all (GSD: the frame's `particles/N`;
/// CSV: its rows), for the memory estimate. `None` when the file cannot be read (the build
/// then names the problem).
pub fn count(path: &Path, frame: i64) -> Option<u64> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
    {
        use std::io::BufRead;
        let file = std::io::BufReader::new(crate::files::open(path).ok()?);
        let rows = file.split(b'\n').filter(|l| l.is_ok()).count() as u64;
        return Some(rows.saturating_sub(1));
    }
    let mut file = crate::files::open(path).ok()?;
    let (names, entries) = read_layout(&mut file).ok()?;
    let chosen = choose_frame(&entries, frame).ok()?;
    let chunk = find(&names, &entries, "particles/N", chosen)?;
    let bytes = read_at(&mut file, chunk.location, 4).ok()?;
    Some(u32::from_le_bytes(bytes.try_into().ok()?) as u64)
}

/// The frame index `frame` names (negative: from the end).
pub(crate) fn choose_frame(entries: &[RawEntry], frame: i64) -> Result<u64, String> {
    let frames = entries.iter().map(|e| e.frame + 1).max().unwrap_or(0);
    let chosen = if frame < 0 {
        frames as i64 + frame
    } else {
        frame
    };
    if frames == 0 {
        return Err("the file holds no frame".into());
    }
    if !(0..frames as i64).contains(&chosen) {
        return Err(format!(
            "frame = {frame}: the file holds frames 0..{} (or -{frames}..-1 from the end)",
            frames - 1
        ));
    }
    Ok(chosen as u64)
}

fn read_gsd(path: &Path, frame: i64, world: Frame) -> Result<FileDiscs, String> {
    let mut file = crate::files::open(path).map_err(|e| format!("cannot read it: {e}"))?;
    let (names, entries) = read_layout(&mut file).map_err(|e| format!("not a GSD 2 file: {e}"))?;
    let at = choose_frame(&entries, frame)?;
    let chunk = |name: &str| find(&names, &entries, name, at);
    let n = match chunk("particles/N") {
        Some(c) => {
            let bytes = read_at(&mut file, c.location, 4).map_err(|e| e.to_string())?;
            u32::from_le_bytes(bytes.try_into().expect("4")) as u64
        }
        None => 0,
    };
    if n == 0 {
        return Err(format!(
            "frame {at} holds no particles (particles/N is 0 or absent)"
        ));
    }
    let position = match chunk("particles/position") {
        Some(c) => floats(&mut file, c, "particles/position", n, 2)?,
        None => return Err(format!("frame {at} has no particles/position")),
    };
    let mut optional = |name: &str, m: u32, default: f64| match chunk(name) {
        Some(c) => floats(&mut file, c, name, n, m),
        None => Ok(vec![default; n as usize * m as usize]),
    };
    let velocity = optional("particles/velocity", 2, 0.0)?;
    let diameter = optional("particles/diameter", 1, 1.0)?;
    // Without a mass chunk the discs take the mass model's own (not the schema's 1).
    let mass = match chunk("particles/mass") {
        Some(c) => Some(floats(&mut file, c, "particles/mass", n, 1)?),
        None => None,
    };
    // Rotation about z, as HOOMD-blue writes it (see `gsd`): the orientation quaternion
    // (cos θ/2, 0, 0, sin θ/2) and the angular momentum's conjugate quaternion p, whose body
    // angular momentum is (cos(θ/2) p_z − sin(θ/2) p_s) / 2, over the moment of inertia's z.
    let quaternion = match chunk("particles/orientation") {
        Some(c) => Some(floats(&mut file, c, "particles/orientation", n, 4)?),
        None => None,
    };
    let spin = match (chunk("particles/angmom"), chunk("particles/moment_inertia")) {
        (Some(p), Some(i)) => {
            let p = floats(&mut file, p, "particles/angmom", n, 4)?;
            let inertia = floats(&mut file, i, "particles/moment_inertia", n, 3)?;
            Some((p, inertia))
        }
        _ => None,
    };
    let turn = |k: usize| -> (f64, f64) {
        let q = quaternion.as_ref().map_or([1.0, 0.0, 0.0, 0.0], |q| {
            [q[4 * k], q[4 * k + 1], q[4 * k + 2], q[4 * k + 3]]
        });
        let theta = (2.0 * libm::atan2(q[3], q[0])).rem_euclid(std::f64::consts::TAU);
        let omega = spin.as_ref().map_or(0.0, |(p, inertia)| {
            let (c, s) = (libm::cos(theta / 2.0), libm::sin(theta / 2.0));
            let l = (c * p[4 * k + 3] - s * p[4 * k]) / 2.0;
            let i = inertia[3 * k + 2];
            if i > 0.0 { l / i } else { 0.0 }
        });
        (theta, omega)
    };
    let bx = match chunk("configuration/box") {
        Some(c) => floats(&mut file, c, "configuration/box", 6, 1)?,
        None => vec![1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
    };
    if let Some(size) = world.size {
        let (lx, ly) = (bx[0], bx[1]);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * a.abs().max(b.abs());
        if !(close(lx, size[0]) && close(ly, size[1])) {
            return Err(format!(
                "its box is {lx} × {ly}, the world's is {} × {}: positions are relative to \
                 the box centre, so the sizes must agree",
                size[0], size[1]
            ));
        }
    }
    if bx.len() >= 4 && bx[3] != 0.0 {
        return Err(format!(
            "its box is triclinic (tilt xy = {}); bounce's boxes are rectangles",
            bx[3]
        ));
    }
    let typeid = match chunk("particles/typeid") {
        Some(c) if c.kind == 3 && c.n == n => {
            let bytes = read_at(&mut file, c.location, n * 4).map_err(|e| e.to_string())?;
            bytes
                .chunks_exact(4)
                .map(|b| u32::from_le_bytes(b.try_into().expect("4")))
                .collect()
        }
        Some(_) => return Err("particles/typeid is not N uint32 values".into()),
        None => vec![0; n as usize],
    };
    let types = match chunk("particles/types") {
        Some(c) if c.kind == 5 || c.kind == 1 => {
            let bytes = read_at(&mut file, c.location, c.n.saturating_mul(c.m as u64))
                .map_err(|e| e.to_string())?;
            bytes
                .chunks_exact(c.m.max(1) as usize)
                .map(|row| {
                    let end = row.iter().position(|&b| b == 0).unwrap_or(row.len());
                    String::from_utf8_lossy(&row[..end]).into_owned()
                })
                .collect()
        }
        Some(_) => return Err("particles/types is not rows of characters".into()),
        None => vec!["A".to_string()],
    };
    if let Some((k, t)) = typeid
        .iter()
        .enumerate()
        .find(|(_, t)| **t as usize >= types.len())
    {
        return Err(format!(
            "particle {k}: typeid {t} names no type ({} types)",
            types.len()
        ));
    }
    let discs = (0..n as usize)
        .map(|k| {
            let (orientation, angular_velocity) = turn(k);
            Particle {
                position: [
                    world.centre[0] + position[2 * k],
                    world.centre[1] + position[2 * k + 1],
                ],
                velocity: [velocity[2 * k], velocity[2 * k + 1]],
                radius: diameter[k] / 2.0,
                mass: mass.as_ref().map(|m| m[k]),
                angular_velocity,
                orientation,
                tag: 0,
            }
        })
        .collect();
    Ok(FileDiscs {
        discs,
        typeid,
        types,
    })
}

/// The CSV columns bounce reads.
const CSV_COLUMNS: [&str; 8] = [
    "x",
    "y",
    "vx",
    "vy",
    "radius",
    "mass",
    "type",
    "angular_velocity",
];

fn read_csv(path: &Path) -> Result<FileDiscs, String> {
    let file = crate::files::open(path).map_err(|e| format!("cannot read it: {e}"))?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(std::io::BufReader::new(file));
    let header = reader.headers().map_err(|e| e.to_string())?.clone();
    let mut column = [None; CSV_COLUMNS.len()];
    for (k, name) in header.iter().enumerate() {
        match CSV_COLUMNS.iter().position(|c| *c == name) {
            Some(c) if column[c].is_some() => return Err(format!("column {name} appears twice")),
            Some(c) => column[c] = Some(k),
            None => {
                return Err(format!(
                    "line 1: unknown column {name:?}; the columns are {}",
                    CSV_COLUMNS.join(", ")
                ));
            }
        }
    }
    for required in ["x", "y", "radius"] {
        let c = CSV_COLUMNS
            .iter()
            .position(|c| *c == required)
            .expect("listed");
        if column[c].is_none() {
            return Err(format!(
                "line 1: no column {required} (the header needs x, y and radius)"
            ));
        }
    }
    let mut out = FileDiscs::default();
    let mut record = csv::StringRecord::new();
    let mut line = 1;
    while reader.read_record(&mut record).map_err(|e| e.to_string())? {
        line += 1;
        let number = |c: usize, default: Option<f64>| -> Result<f64, String> {
            let text = column[c].and_then(|k| record.get(k)).unwrap_or("");
            match (text.parse::<f64>(), default) {
                (Ok(v), _) => Ok(v),
                (Err(_), Some(d)) if text.is_empty() => Ok(d),
                _ => Err(format!(
                    "line {line}: {} = {text:?} is not a number",
                    CSV_COLUMNS[c]
                )),
            }
        };
        let disc = Particle {
            position: [number(0, None)?, number(1, None)?],
            velocity: [number(2, Some(0.0))?, number(3, Some(0.0))?],
            radius: number(4, None)?,
            mass: match column[5].and_then(|k| record.get(k)) {
                None | Some("") => None,
                Some(_) => Some(number(5, None)?),
            },
            angular_velocity: number(7, Some(0.0))?,
            orientation: 0.0,
            tag: 0,
        };
        disc.validate_values()
            .map_err(|e| format!("line {line}: {e}"))?;
        let kind = match column[6] {
            Some(k) => record.get(k).unwrap_or("").to_string(),
            None => "A".to_string(),
        };
        let t = match out.types.iter().position(|t| *t == kind) {
            Some(t) => t,
            None => {
                out.types.push(kind);
                out.types.len() - 1
            }
        };
        out.discs.push(disc);
        out.typeid.push(t as u32);
    }
    if out.discs.is_empty() {
        return Err("the table has no rows".into());
    }
    Ok(out)
}
