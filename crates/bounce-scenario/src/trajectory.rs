//! A GSD trajectory read frame by frame, for analysis (`bounce analyze`, Python's
//! `bounce.rdf`, `psi6` and `msd`): each frame's step, box, positions, periodic images and
//! diameters, in the file's particle order.
//!
//! The box's edges are what bounce wrote in frame 0's `log/bounce/boundary` (0 an open
//! world, 1 walls, 2 a periodic box, 3 a Lees–Edwards box, whose offset each frame records
//! in `log/bounce/lees_edwards_offset`); a file without it (HOOMD-blue's, or bounce's
//! before it was written) is periodic, as every HOOMD box is. A caller may say otherwise.

use std::path::Path;

use crate::gsd::{
    BOUNDARY_CHUNK, RawEntry, SLIDE_CHUNK, TIME_CHUNK, find, floats, read_at, read_layout,
};
use crate::structure::{Edges, Snapshot};

/// An open GSD file and its index.
pub struct Trajectory {
    file: std::fs::File,
    names: Vec<String>,
    entries: Vec<RawEntry>,
    frames: u64,
    edges: Edges,
    /// The file's box is a Lees–Edwards one.
    sheared: bool,
    name: String,
}

impl Trajectory {
    /// Opens `path`; errors name the file and what is wrong with it.
    pub fn open(path: &Path) -> Result<Trajectory, String> {
        let name = path.display().to_string();
        let mut file =
            crate::files::open(path).map_err(|e| format!("{name}: cannot read it: {e}"))?;
        let (names, entries) =
            read_layout(&mut file).map_err(|e| format!("{name}: not a GSD 2 file: {e}"))?;
        let frames = entries.iter().map(|e| e.frame + 1).max().unwrap_or(0);
        if frames == 0 {
            return Err(format!("{name}: the file holds no frame"));
        }
        // Frames are numbered without gaps: an index naming frame 10⁹ in a small file is
        // damaged, not a billion frames to read.
        let mut numbers: Vec<u64> = entries.iter().map(|e| e.frame).collect();
        numbers.sort_unstable();
        numbers.dedup();
        if numbers.len() as u64 != frames {
            return Err(format!(
                "{name}: its index names frame {} but holds chunks of {} frames: the file is \
                 damaged",
                frames - 1,
                numbers.len()
            ));
        }
        let mut trajectory = Trajectory {
            file,
            names,
            entries,
            frames,
            edges: Edges::Periodic,
            sheared: false,
            name,
        };
        if let Some(c) = find(&trajectory.names, &trajectory.entries, BOUNDARY_CHUNK, 0) {
            let (location, kind) = (c.location, c.kind);
            let byte = read_at(&mut trajectory.file, location, 1)
                .map_err(|e| format!("{}: {BOUNDARY_CHUNK}: {e}", trajectory.name))?;
            trajectory.edges = match (kind, byte[0]) {
                (1, 0) => Edges::Open,
                (1, 1) => Edges::Walls,
                (1, 2) => Edges::Periodic,
                (1, 3) => {
                    trajectory.sheared = true;
                    Edges::Periodic
                }
                (_, v) => {
                    return Err(format!(
                        "{}: {BOUNDARY_CHUNK} is {v} (type {kind}); expected a uint8 0 \
                         (open), 1 (walls), 2 (periodic) or 3 (Lees–Edwards)",
                        trajectory.name
                    ));
                }
            };
        }
        Ok(trajectory)
    }

    /// How many frames the file holds.
    pub fn len(&self) -> u64 {
        self.frames
    }

    /// Whether the file holds no frame (never: [`Trajectory::open`] refuses such a file).
    pub fn is_empty(&self) -> bool {
        self.frames == 0
    }

    /// The box's edges the file records (periodic where it records none).
    pub fn edges(&self) -> Edges {
        self.edges
    }

    /// The frames from `first` (negative: counted from the end, -1 the last) to the last,
    /// their box's edges `edges` (`None`: what the file records).
    pub fn snapshots(&mut self, first: i64, edges: Option<Edges>) -> Result<Vec<Snapshot>, String> {
        let frames = self.frames as i64;
        let from = if first < 0 { frames + first } else { first };
        if !(0..frames).contains(&from) {
            return Err(format!(
                "{}: first frame {first}: the file holds frames 0..{} (or -{frames}..-1 from \
                 the end)",
                self.name,
                frames - 1
            ));
        }
        let edges = edges.unwrap_or(self.edges);
        (from as u64..self.frames)
            .map(|k| self.snapshot(k, edges))
            .collect()
    }

    /// Frame `frame` (0-based), its box's edges taken as `edges`.
    pub fn snapshot(&mut self, frame: u64, edges: Edges) -> Result<Snapshot, String> {
        self.read(frame, edges)
            .map_err(|e| format!("{}: frame {frame}: {e}", self.name))
    }

    fn read(&mut self, frame: u64, edges: Edges) -> Result<Snapshot, String> {
        if frame >= self.frames {
            return Err(format!("the file holds frames 0..{}", self.frames - 1));
        }
        let file = &mut self.file;
        let (names, entries) = (&self.names, &self.entries);
        let chunk = |name: &str| find(names, entries, name, frame);
        let whole = |file: &mut std::fs::File, c: &RawEntry, size: u64| {
            read_at(
                file,
                c.location,
                c.n.saturating_mul(c.m as u64).saturating_mul(size),
            )
            .map_err(|e| e.to_string())
        };
        // A chunk of no values (an index entry with N = 0) has no first value to read.
        let first = |bytes: Vec<u8>, size: usize, name: &str| -> Result<Vec<u8>, String> {
            if bytes.len() < size {
                return Err(format!("{name} holds no value"));
            }
            Ok(bytes[..size].to_vec())
        };
        let step = match chunk("configuration/step") {
            Some(c) if c.kind == 4 => {
                let bytes = first(whole(file, c, 8)?, 8, "configuration/step")?;
                u64::from_le_bytes(bytes.try_into().expect("8"))
            }
            _ => 0,
        };
        let n = match chunk("particles/N") {
            Some(c) if c.kind == 3 => {
                let bytes = first(whole(file, c, 4)?, 4, "particles/N")?;
                u32::from_le_bytes(bytes.try_into().expect("4")) as u64
            }
            _ => 0,
        };
        let size = match chunk("configuration/box") {
            Some(c) => {
                let b = floats(file, c, "configuration/box", 6, 1)?;
                [b[0], b[1]]
            }
            None => [1.0, 1.0],
        };
        if !(size[0] > 0.0 && size[1] > 0.0) {
            return Err(format!("the box is {} × {}", size[0], size[1]));
        }
        let (position, diameter) = if n == 0 {
            (Vec::new(), Vec::new())
        } else {
            let xyz = match chunk("particles/position") {
                Some(c) => floats(file, c, "particles/position", n, 2)?,
                None => return Err("no particles/position".into()),
            };
            let diameter = match chunk("particles/diameter") {
                Some(c) => floats(file, c, "particles/diameter", n, 1)?,
                None => vec![1.0; n as usize],
            };
            let position: Vec<[f64; 2]> = xyz.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
            (position, diameter)
        };
        let image = match chunk("particles/image") {
            Some(c) if c.kind == 7 && c.n == n && c.m >= 2 => whole(file, c, 4)?
                .chunks_exact(4 * c.m as usize)
                .map(|row| {
                    let at =
                        |k: usize| i32::from_le_bytes(row[4 * k..4 * k + 4].try_into().expect("4"));
                    [at(0), at(1)]
                })
                .collect(),
            Some(c) => {
                return Err(format!(
                    "particles/image is {} × {} of GSD type {}; expected int32 {n} × 3",
                    c.n, c.m, c.kind
                ));
            }
            None => vec![[0, 0]; n as usize],
        };
        if let Some(bad) = position
            .iter()
            .position(|p| !p.iter().all(|v| v.is_finite()))
        {
            return Err(format!("particle {bad}'s position is not finite"));
        }
        // A Lees–Edwards frame's offset (read as periodic, the box slides).
        let slide = match (self.sheared && edges == Edges::Periodic, chunk(SLIDE_CHUNK)) {
            (true, Some(c)) => Some(floats(&mut self.file, c, SLIDE_CHUNK, 1, 1)?[0]),
            (true, None) => return Err(format!("no {SLIDE_CHUNK} in a Lees–Edwards file")),
            (false, _) => None,
        };
        let time = match chunk(TIME_CHUNK) {
            Some(c) => {
                Some(floats(&mut self.file, c, TIME_CHUNK, 1, 1)?[0]).filter(|t| t.is_finite())
            }
            None => None,
        };
        Ok(Snapshot {
            step,
            time,
            size,
            edges,
            position,
            slide,
            image,
            diameter,
        })
    }
}
