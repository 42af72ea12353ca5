//! A GSD trajectory writer (HOOMD-blue's format, read by OVITO, freud and the `gsd` Python
//! package), from the published file layer specification, version 2.0.
//!
//! Layout: a 256-byte header; data chunks appended frame after frame; at the end, the name
//! list (NUL-terminated names, padded to 64-byte blocks) and the index (32-byte entries
//! sorted by frame, then name id, ended by an all-zero entry), and the header rewritten to
//! point at them. The file is written under a temporary name and renamed when complete.
//!
//! Each frame holds the `hoomd` schema chunks `configuration/{step,dimensions,box}` and
//! `particles/{N,position,velocity,diameter,mass,image,typeid,types}` with particles in id
//! order, and `log/kinetic_energy`; in frame 0, `log/bounce/boundary` (a `uint8`: 0 an open
//! world, 1 walls, 2 a periodic box, 3 a Lees–Edwards box: how `bounce analyze` reads the
//! box), and in a Lees–Edwards box `log/bounce/lees_edwards_offset` in every frame (a
//! `float64`: where the copy above stands along x); where any disc has
//! a tag (`Particle::tag`), `log/particles/tag` (`uint64`, id order); with collision counts
//! (`bounce::Config::collision_counts`), `log/particles/bounce/collisions` (`uint64`, id
//! order: each disc's collisions so far). Where discs turn (rough or spinning), also
//! `particles/{moment_inertia,orientation,angmom}` as HOOMD-blue writes rotation about z:
//! the moment of inertia `(0, 0, I)`, the orientation quaternion `(cos θ/2, 0, 0, sin θ/2)`
//! and the angular momentum's conjugate quaternion `2 q ⊗ (0, 0, 0, I ω)`
//! `= (−2 sin(θ/2) I ω, 0, 0, 2 cos(θ/2) I ω)`, so OVITO and freud show the orientations.
//!
//! - Positions are relative to the box centre (HOOMD's convention). In an open world the
//!   centre is the origin, fixed for the whole file, so positions are absolute; the box is
//!   the smallest one centred on the origin that holds every disc of the frame.
//! - `particles/image` counts the periodic box crossings: the unwrapped position is
//!   `position + image × box` (zero outside a periodic box).
//! - `particles/types` are the scenario's types (a table's `type`, else its colour, else
//!   `A`); `typeid` gives each disc's.

use std::io::{self, Seek, SeekFrom, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};

use bounce::{Boundary, World};

use crate::atomic::AtomicFile;

type Result<T> = io::Result<T>;

/// Checks that `values` survive HOOMD's 32-bit floats: a value beyond ±3.4e38 would be
/// written as an infinity.
fn fits_f32(step: u64, what: &str, field: &str, values: &[f64]) -> Result<()> {
    match values.iter().find(|v| !(**v as f32).is_finite()) {
        None => Ok(()),
        Some(v) => Err(invalid(format!(
            "step {step}: {what}: {field} {values:?} holds {v:e}, beyond the 32-bit floats of \
             a GSD frame (|x| <= 3.4e38)"
        ))),
    }
}

/// An error naming what was wrong.
fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message)
}

const MAGIC: u64 = 0x65DF_65DF_65DF_65DF;
const HEADER_SIZE: u64 = 256;
const NAME_BLOCK: usize = 64;

const fn version(major: u32, minor: u32) -> u32 {
    (major << 16) | minor
}

/// The GSD element types this writer uses.
#[derive(Clone, Copy)]
enum Type {
    U8 = 1,
    U32 = 3,
    U64 = 4,
    I8 = 5,
    I32 = 7,
    F32 = 9,
    F64 = 10,
}

impl Type {
    fn from_u8(v: u8) -> Option<Type> {
        Some(match v {
            1 => Type::U8,
            3 => Type::U32,
            4 => Type::U64,
            5 => Type::I8,
            7 => Type::I32,
            9 => Type::F32,
            10 => Type::F64,
            _ => return None,
        })
    }

    /// Bytes per element.
    fn size(self) -> u64 {
        match self {
            Type::U8 | Type::I8 => 1,
            Type::U32 | Type::I32 | Type::F32 => 4,
            Type::U64 | Type::F64 => 8,
        }
    }
}

/// An index entry as read from a file.
pub(crate) struct RawEntry {
    pub frame: u64,
    pub n: u64,
    pub location: u64,
    pub m: u32,
    pub id: u16,
    pub kind: u8,
}

/// `len` bytes at `at` (bounded: a GSD chunk of this writer is one array of one frame).
pub(crate) fn read_at(file: &mut std::fs::File, at: u64, len: u64) -> Result<Vec<u8>> {
    use std::io::Read;
    let size = file.metadata()?.len();
    if at.checked_add(len).is_none_or(|end| end > size) {
        return Err(invalid("a chunk runs past the end of the file".into()));
    }
    file.seek(SeekFrom::Start(at))?;
    let mut bytes = vec![0u8; len as usize];
    file.read_exact(&mut bytes)?;
    Ok(bytes)
}

/// The name list and the index entries of a GSD file written by [`GsdWriter`].
pub(crate) fn read_layout(file: &mut std::fs::File) -> Result<(Vec<String>, Vec<RawEntry>)> {
    let header = read_at(file, 0, HEADER_SIZE)?;
    let word = |at: usize| u64::from_le_bytes(header[at..at + 8].try_into().expect("8"));
    if word(0) != MAGIC {
        return Err(invalid("no GSD header".into()));
    }
    let (index_location, allocated) = (word(8), word(16));
    let (names_location, name_blocks) = (word(24), word(32));
    let names_bytes = read_at(
        file,
        names_location,
        name_blocks.saturating_mul(NAME_BLOCK as u64),
    )?;
    let names: Vec<String> = names_bytes
        .split(|&b| b == 0)
        .take_while(|n| !n.is_empty())
        .map(|n| String::from_utf8_lossy(n).into_owned())
        .collect();
    let index = read_at(file, index_location, allocated.saturating_mul(32))?;
    let mut entries = Vec::new();
    for e in index.chunks_exact(32) {
        let u64_at = |at: usize| u64::from_le_bytes(e[at..at + 8].try_into().expect("8"));
        let location = u64_at(16);
        if location == 0 {
            break;
        }
        entries.push(RawEntry {
            frame: u64_at(0),
            n: u64_at(8),
            location,
            m: u32::from_le_bytes(e[24..28].try_into().expect("4")),
            id: u16::from_le_bytes(e[28..30].try_into().expect("2")),
            kind: e[30],
        });
    }
    Ok((names, entries))
}

struct IndexEntry {
    frame: u64,
    n: u64,
    location: u64,
    m: u32,
    id: u16,
    kind: Type,
}

/// The chunks written so far: their names and index entries. Shared with the file's closing
/// (a second signal keeps the whole frames: [`crate::atomic::exit_now`]).
#[derive(Default)]
struct Layout {
    names: Vec<String>,
    index: Vec<IndexEntry>,
}

impl Layout {
    /// The name list and the index of the chunks before byte `end` (the whole frames of a
    /// file cut there), to append at `end`, and the header that points at them.
    fn closing(&self, end: u64) -> (Vec<u8>, Vec<u8>) {
        // Name list: NUL-terminated names, then at least one NUL (the end marker), padded to
        // whole 64-byte blocks.
        let mut names: Vec<u8> = Vec::new();
        for name in &self.names {
            names.extend_from_slice(name.as_bytes());
            names.push(0);
        }
        names.push(0);
        names.resize(names.len().div_ceil(NAME_BLOCK) * NAME_BLOCK, 0);
        let namelist_location = end;

        // Index: sorted by (frame, id); room for more entries than frames (readers check
        // frame < allocated entries) and an all-zero end marker.
        let mut index: Vec<&IndexEntry> = self.index.iter().filter(|e| e.location < end).collect();
        index.sort_by_key(|e| (e.frame, e.id));
        let frames = index.last().map_or(0, |e| e.frame + 1);
        let allocated = (index.len() + 1)
            .max(frames as usize + 1)
            .next_power_of_two();
        let index_location = end + names.len() as u64;
        let mut tail = names;
        for e in index {
            tail.extend_from_slice(&e.frame.to_le_bytes());
            tail.extend_from_slice(&e.n.to_le_bytes());
            tail.extend_from_slice(&(e.location as i64).to_le_bytes());
            tail.extend_from_slice(&e.m.to_le_bytes());
            tail.extend_from_slice(&e.id.to_le_bytes());
            tail.push(e.kind as u8);
            tail.push(0); // flags
        }
        let names_len = (index_location - namelist_location) as usize;
        tail.resize(names_len + allocated * 32, 0);

        let mut header = Vec::with_capacity(HEADER_SIZE as usize);
        header.extend_from_slice(&MAGIC.to_le_bytes());
        header.extend_from_slice(&index_location.to_le_bytes());
        header.extend_from_slice(&(allocated as u64).to_le_bytes());
        header.extend_from_slice(&namelist_location.to_le_bytes());
        header.extend_from_slice(&((names_len / NAME_BLOCK) as u64).to_le_bytes());
        header.extend_from_slice(&version(1, 4).to_le_bytes()); // hoomd schema version
        header.extend_from_slice(&version(2, 0).to_le_bytes()); // file layer version
        let mut text = |s: &str, len: usize| {
            let mut field = s.as_bytes()[..s.len().min(len - 1)].to_vec();
            field.resize(len, 0);
            header.extend_from_slice(&field);
        };
        text(concat!("bounce ", env!("CARGO_PKG_VERSION")), 64);
        text("hoomd", 64);
        header.resize(HEADER_SIZE as usize, 0);
        (tail, header)
    }
}

/// Writes a trajectory frame by frame; [`GsdWriter::finish`] completes the file. A second
/// signal keeps its whole frames.
pub struct GsdWriter {
    file: AtomicFile,
    offset: u64,
    layout: Arc<Mutex<Layout>>,
    frame: u64,
    /// The step of the last frame written (or kept by a resume).
    last_step: Option<u64>,
    /// `particles/types` as NUL-padded rows, and its row width.
    types: (Vec<u8>, u32),
    /// Each particle's type, by id (0 beyond).
    typeid: Vec<u32>,
}

impl GsdWriter {
    /// Starts `path` for particles of `types` (names), `typeid` giving each id's.
    pub fn create(path: &Path, types: &[String], typeid: &[u32]) -> Result<Self> {
        let mut file = AtomicFile::create(path)?;
        // Placeholder header, rewritten by `finish`.
        file.write_all(&[0u8; HEADER_SIZE as usize])?;
        file.mark_whole();
        let layout = Arc::new(Mutex::new(Layout::default()));
        let shared = layout.clone();
        file.set_closing(Box::new(move |end| {
            let layout = shared.lock().unwrap_or_else(|p| p.into_inner());
            layout.closing(end)
        }));
        let width = types.iter().map(|t| t.len()).max().unwrap_or(1) + 1;
        let mut rows = Vec::with_capacity(width * types.len().max(1));
        for t in types {
            rows.extend_from_slice(t.as_bytes());
            rows.resize(rows.len() + width - t.len(), 0);
        }
        if types.is_empty() {
            rows.extend_from_slice(b"A\0");
        }
        Ok(GsdWriter {
            file,
            offset: HEADER_SIZE,
            layout,
            last_step: None,
            frame: 0,
            types: (rows, width as u32),
            typeid: typeid.to_vec(),
        })
    }

    /// Continues the trajectory at `path`: keeps the frames whose step passes `keep` (a
    /// leading run of them), chunk for chunk, so the file continues as if never interrupted.
    /// Without an earlier file, starts a new one.
    pub fn resume(
        path: &Path,
        types: &[String],
        typeid: &[u32],
        keep: impl Fn(u64) -> bool,
    ) -> Result<Self> {
        let mut writer = GsdWriter::create(path, types, typeid)?;
        let Ok(mut old) = std::fs::File::open(path) else {
            return Ok(writer);
        };
        let name = path.display().to_string();
        let (names, entries) = read_layout(&mut old)
            .map_err(|e| invalid(format!("{name}: not a GSD file of bounce: {e}")))?;
        // The step of each frame, from its `configuration/step` chunk.
        let step_id = names.iter().position(|n| n == "configuration/step");
        let mut frames_kept = 0u64;
        for e in &entries {
            if Some(e.id as usize) == step_id {
                let step =
                    u64::from_le_bytes(read_at(&mut old, e.location, 8)?.try_into().expect("8"));
                if e.frame == frames_kept && keep(step) {
                    frames_kept += 1;
                    writer.last_step = Some(step);
                }
            }
        }
        let mut by_location: Vec<&RawEntry> =
            entries.iter().filter(|e| e.frame < frames_kept).collect();
        by_location.sort_by_key(|e| e.location);
        for e in by_location {
            let kind = Type::from_u8(e.kind)
                .ok_or_else(|| invalid(format!("{name}: unknown GSD type {}", e.kind)))?;
            let len = e.n.saturating_mul(e.m as u64).saturating_mul(kind.size());
            let bytes = read_at(&mut old, e.location, len)?;
            let chunk_name = names
                .get(e.id as usize)
                .ok_or_else(|| invalid(format!("{name}: a chunk without a name")))?
                .clone();
            writer.frame = e.frame;
            writer.chunk(&chunk_name, kind, e.n, e.m, &bytes)?;
        }
        writer.frame = frames_kept;
        writer.file.mark_whole();
        Ok(writer)
    }

    fn chunk(&mut self, name: &str, kind: Type, n: u64, m: u32, bytes: &[u8]) -> Result<()> {
        {
            // (Released before the file is written: the file's closing takes this lock
            // inside the file's own.)
            let mut layout = self.layout.lock().unwrap_or_else(|p| p.into_inner());
            let id = match layout.names.iter().position(|n| n == name) {
                Some(i) => i as u16,
                None => {
                    layout.names.push(name.to_string());
                    (layout.names.len() - 1) as u16
                }
            };
            layout.index.push(IndexEntry {
                frame: self.frame,
                n,
                location: self.offset,
                m,
                id,
                kind,
            });
        }
        self.file.write_all(bytes)?;
        self.offset += bytes.len() as u64;
        Ok(())
    }

    /// The step of the last frame written, or kept by [`GsdWriter::resume`].
    pub fn last_step(&self) -> Option<u64> {
        self.last_step
    }

    /// Gives disc `id` (a disc an emitter added) the type `typeid`.
    pub fn set_type(&mut self, id: usize, typeid: u32) {
        if self.typeid.len() <= id {
            self.typeid.resize(id + 1, 0);
        }
        self.typeid[id] = typeid;
    }

    /// Appends the world's current state as one frame.
    pub fn frame(&mut self, world: &World) -> Result<()> {
        let by_id = world.particles_by_id();
        fits(world, &by_id)?;
        let (centre, size) = box_of(world);
        let n = by_id.len();
        let f32s = |values: &mut dyn Iterator<Item = f64>| -> Vec<u8> {
            values.flat_map(|v| (v as f32).to_le_bytes()).collect()
        };
        let model = world.config().mass_model;

        self.chunk(
            "configuration/step",
            Type::U64,
            1,
            1,
            &world.step_count().to_le_bytes(),
        )?;
        self.chunk("configuration/dimensions", Type::U8, 1, 1, &[2])?;
        let bx = [size[0], size[1], 1.0, 0.0, 0.0, 0.0];
        self.chunk(
            "configuration/box",
            Type::F32,
            6,
            1,
            &f32s(&mut bx.into_iter()),
        )?;
        self.chunk("particles/N", Type::U32, 1, 1, &(n as u32).to_le_bytes())?;
        let pos = f32s(
            &mut by_id
                .iter()
                .flat_map(|(_, p)| [p.position[0] - centre[0], p.position[1] - centre[1], 0.0]),
        );
        self.chunk("particles/position", Type::F32, n as u64, 3, &pos)?;
        let vel = f32s(
            &mut by_id
                .iter()
                .flat_map(|(_, p)| [p.velocity[0], p.velocity[1], 0.0]),
        );
        self.chunk("particles/velocity", Type::F32, n as u64, 3, &vel)?;
        let diameter = f32s(&mut by_id.iter().map(|(_, p)| 2.0 * p.radius));
        self.chunk("particles/diameter", Type::F32, n as u64, 1, &diameter)?;
        let mass = f32s(
            &mut by_id
                .iter()
                .map(|(_, p)| model.mass(p.radius, p.mass.unwrap_or(0.0))),
        );
        self.chunk("particles/mass", Type::F32, n as u64, 1, &mass)?;
        let image = images_by_id(world);
        self.chunk("particles/image", Type::I32, n as u64, 3, &image)?;
        let typeid: Vec<u8> = by_id
            .iter()
            .flat_map(|(id, _)| {
                self.typeid
                    .get(id.0 as usize)
                    .copied()
                    .unwrap_or(0)
                    .to_le_bytes()
            })
            .collect();
        self.chunk("particles/typeid", Type::U32, n as u64, 1, &typeid)?;
        let (rows, width) = self.types.clone();
        let count = rows.len() as u64 / width as u64;
        self.chunk("particles/types", Type::I8, count, width, &rows)?;
        if world.particles().turns() {
            self.rotation(world, &by_id)?;
        }
        if !world.particles().tag().is_empty() {
            let tags: Vec<u8> = by_id
                .iter()
                .flat_map(|(_, p)| p.tag.to_le_bytes())
                .collect();
            self.chunk("log/particles/tag", Type::U64, n as u64, 1, &tags)?;
        }
        if let Some(counts) = world.collision_counts() {
            let counts: Vec<u8> = by_id
                .iter()
                .flat_map(|(id, _)| counts[id.0 as usize].to_le_bytes())
                .collect();
            self.chunk(COLLISIONS_CHUNK, Type::U64, n as u64, 1, &counts)?;
        }
        let (energy, _) = crate::analysis::motion_sums(world);
        self.chunk("log/kinetic_energy", Type::F64, 1, 1, &energy.to_le_bytes())?;
        let time = world.time();
        self.chunk(TIME_CHUNK, Type::F64, 1, 1, &time.to_le_bytes())?;
        if let Some(offset) = world.lees_edwards_offset() {
            let chunk = SLIDE_CHUNK;
            self.chunk(chunk, Type::F64, 1, 1, &offset.to_le_bytes())?;
        }
        if self.frame == 0 {
            // How the box ends, for `bounce analyze` (HOOMD's boxes are all periodic).
            let edges: u8 = match world.config().boundary {
                Boundary::Open => 0,
                Boundary::Walls { .. } => 1,
                Boundary::Periodic { .. } => 2,
                Boundary::LeesEdwards { .. } => 3,
            };
            self.chunk(BOUNDARY_CHUNK, Type::U8, 1, 1, &[edges])?;
        }
        self.frame += 1;
        self.last_step = Some(world.step_count());
        self.file.mark_whole();
        Ok(())
    }

    /// The rotation chunks of a frame (see the module docs), particles in id order.
    fn rotation(
        &mut self,
        world: &World,
        by_id: &[(bounce::ParticleId, bounce::Particle)],
    ) -> Result<()> {
        let (model, k) = (world.config().mass_model, world.config().inertia_factor);
        let n = by_id.len() as u64;
        let inertia: Vec<f64> = by_id
            .iter()
            .map(|(_, p)| k * model.mass(p.radius, p.mass.unwrap_or(0.0)) * p.radius * p.radius)
            .collect();
        let f32s = |values: &mut dyn Iterator<Item = f64>| -> Vec<u8> {
            values.flat_map(|v| (v as f32).to_le_bytes()).collect()
        };
        let moment = f32s(&mut inertia.iter().flat_map(|&i| [0.0, 0.0, i]));
        self.chunk("particles/moment_inertia", Type::F32, n, 3, &moment)?;
        let half = |p: &bounce::Particle| {
            (
                libm::cos(p.orientation / 2.0),
                libm::sin(p.orientation / 2.0),
            )
        };
        let orientation = f32s(&mut by_id.iter().flat_map(|(_, p)| {
            let (c, s) = half(p);
            [c, 0.0, 0.0, s]
        }));
        self.chunk("particles/orientation", Type::F32, n, 4, &orientation)?;
        let angmom = f32s(&mut by_id.iter().zip(&inertia).flat_map(|((_, p), &i)| {
            let ((c, s), l) = (half(p), i * p.angular_velocity);
            [-2.0 * s * l, 0.0, 0.0, 2.0 * c * l]
        }));
        self.chunk("particles/angmom", Type::F32, n, 4, &angmom)
    }

    /// Writes the name list, the index and the header, and renames the file into place.
    pub fn finish(mut self) -> Result<()> {
        let (tail, head) = self
            .layout
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .closing(self.offset);
        self.file.write_all(&tail)?;
        self.file.commit_with_head(&head)
    }
}

/// The chunk naming the box's edges (see the module docs).
pub const BOUNDARY_CHUNK: &str = "log/bounce/boundary";

/// The chunk holding a Lees–Edwards box's offset in each frame (`float64`: how far along x
/// the images above stand).
pub const SLIDE_CHUNK: &str = "log/bounce/lees_edwards_offset";

/// The chunk holding a frame's simulated time (float64), in bounce's files.
pub const TIME_CHUNK: &str = "log/bounce/time";

/// Each disc's collisions so far (`bounce::World::collision_counts`), `uint64`, id order.
pub const COLLISIONS_CHUNK: &str = "log/particles/bounce/collisions";

/// Whether the world's current state fits a GSD frame's 32-bit floats (positions from the
/// box's centre, velocities, sizes, masses, rotation, the box), naming the first value that
/// does not: checked before a frame is written, and at a scenario's start.
pub fn fits_frame(world: &World) -> Result<()> {
    fits(world, &world.particles_by_id())
}

/// [`fits_frame`] with the discs in id order already at hand.
fn fits(world: &World, by_id: &[(bounce::ParticleId, bounce::Particle)]) -> Result<()> {
    let (centre, size) = box_of(world);
    let model = world.config().mass_model;
    let step = world.step_count();
    for (id, p) in by_id {
        let what = format!("disc {}", id.0);
        let centred = [p.position[0] - centre[0], p.position[1] - centre[1]];
        fits_f32(step, &what, "position (from the box's centre)", &centred)?;
        fits_f32(step, &what, "velocity", &p.velocity)?;
        let mass = model.mass(p.radius, p.mass.unwrap_or(0.0));
        fits_f32(step, &what, "diameter and mass", &[2.0 * p.radius, mass])?;
        let inertia = world.config().inertia_factor * mass * p.radius * p.radius;
        let angmom = 2.0 * inertia * p.angular_velocity;
        fits_f32(
            step,
            &what,
            "moment of inertia and angular momentum",
            &[inertia, angmom],
        )?;
    }
    fits_f32(step, "the box", "size", &size)
}

/// Centre and size of the box HOOMD should see: the walls or periodic box; for an open
/// world, centred on the origin (fixed, so positions are absolute) and just holding every
/// disc.
fn box_of(world: &World) -> ([f64; 2], [f64; 2]) {
    match world.config().boundary {
        Boundary::Walls { min, max, .. }
        | Boundary::Periodic { min, max }
        | Boundary::LeesEdwards { min, max, .. } => (
            [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0],
            [max[0] - min[0], max[1] - min[1]],
        ),
        Boundary::Open => {
            let p = world.particles();
            let r = p.radius().iter().copied().fold(0.0, f64::max);
            let reach = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs())) + r;
            ([0.0, 0.0], [2.0 * reach(p.x()), 2.0 * reach(p.y())])
        }
    }
}

/// The image counts as GSD's `int32[N][3]`, in id order.
fn images_by_id(world: &World) -> Vec<u8> {
    let p = world.particles();
    let mut by_id: Vec<(u32, [i32; 2])> = p
        .ids()
        .iter()
        .zip(p.image())
        .map(|(id, &image)| (id.0, image))
        .collect();
    by_id.sort_unstable_by_key(|&(id, _)| id);
    by_id
        .iter()
        .flat_map(|&(_, [ix, iy])| [ix, iy, 0])
        .flat_map(i32::to_le_bytes)
        .collect()
}

/// The entry of chunk `name` in frame `frame`, else in frame 0 (the schema's rule).
pub(crate) fn find<'a>(
    names: &[String],
    entries: &'a [RawEntry],
    name: &str,
    frame: u64,
) -> Option<&'a RawEntry> {
    let id = names.iter().position(|n| n == name)? as u16;
    let in_frame = |f: u64| entries.iter().find(|e| e.id == id && e.frame == f);
    in_frame(frame).or_else(|| in_frame(0))
}

/// A chunk's values as `f64`, `m` per row, checking its shape.
pub(crate) fn floats(
    file: &mut std::fs::File,
    chunk: &RawEntry,
    name: &str,
    n: u64,
    m: u32,
) -> std::result::Result<Vec<f64>, String> {
    if chunk.n != n || chunk.m < m {
        return Err(format!(
            "{name} is {} × {}, expected {n} × {m} (particles/N = {n})",
            chunk.n, chunk.m
        ));
    }
    let width = match chunk.kind {
        9 => 4,
        10 => 8,
        k => {
            return Err(format!(
                "{name} has GSD type {k}; expected float32 or float64"
            ));
        }
    };
    let bytes = read_at(
        file,
        chunk.location,
        n.saturating_mul(chunk.m as u64).saturating_mul(width),
    )
    .map_err(|e| format!("{name}: {e}"))?;
    let row = chunk.m as usize * width as usize;
    let mut out = Vec::with_capacity(n as usize * m as usize);
    for r in bytes.chunks_exact(row) {
        for k in 0..m as usize {
            let at = k * width as usize;
            out.push(if width == 4 {
                f32::from_le_bytes(r[at..at + 4].try_into().expect("4")) as f64
            } else {
                f64::from_le_bytes(r[at..at + 8].try_into().expect("8"))
            });
        }
    }
    Ok(out)
}
