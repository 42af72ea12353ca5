//! The resources a scenario may use, estimated from the file before anything is built.

use crate::schema::{FileSpec, Scenario, block_counts};
#[cfg(not(target_arch = "wasm32"))]
use crate::start;
use bounce::law::Law;

/// Memory a run needs per disc, with room to spare: the hot arrays and the candidate lists
/// (about 95 bytes per disc measured at 10^6), the generator's and the outputs' copies.
pub const BYTES_PER_PARTICLE: u64 = 256;

/// Memory a run needs per obstacle, with room to spare: the configuration's and the step's
/// copies, the grid's lists and the scenario's groups (about 445 bytes per peg measured for a
/// run of 10^6 pegs).
pub const BYTES_PER_OBSTACLE: u64 = 512;

/// What a scenario needs, estimated before it is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Estimate {
    /// Discs.
    pub particles: u64,
    /// Obstacles (each segment of a polyline or box, each peg of a lattice).
    pub obstacles: u64,
    /// Bytes of memory, about.
    pub bytes: u64,
}

/// The resources a scenario may use; a larger one is refused before anything is allocated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Bytes of memory. Default: half the machine's memory (4 GiB where it cannot be read).
    pub memory_bytes: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            memory_bytes: machine_memory().map_or(4 << 30, |m| m / 2),
        }
    }
}

impl Limits {
    /// A limit of `gib` GiB of memory.
    pub fn memory_gib(gib: f64) -> Limits {
        Limits {
            memory_bytes: (gib * (1u64 << 30) as f64) as u64,
        }
    }

    /// Refuses an estimate over the limit, saying both.
    pub fn check(&self, estimate: &Estimate) -> Result<(), String> {
        if estimate.bytes > self.memory_bytes {
            return Err(format!(
                "{} particles and {} obstacles need about {:.1} GiB, over the limit of {:.1} \
                 GiB (half the machine's memory by default; raise it with --memory-limit GIB)",
                estimate.particles,
                estimate.obstacles,
                estimate.bytes as f64 / (1u64 << 30) as f64,
                self.memory_bytes as f64 / (1u64 << 30) as f64
            ));
        }
        Ok(())
    }
}

/// The machine's memory in bytes, from `/proc/meminfo` (Linux).
fn machine_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

impl Scenario {
    /// Total particles the scenario asks for; `None` when the count overflows 64 bits.
    pub fn particle_count(&self) -> Option<u64> {
        let law = Law::new(&self.config());
        let product = |[x, y]: [usize; 2]| (x as u64).checked_mul(y as u64);
        let mut total = self.disc.len() as u64;
        for f in &self.file {
            // A file that cannot be read counts nothing here; building it says why.
            total = total.checked_add(self.file_count(f.get_ref()).unwrap_or(0))?;
        }
        for n in self
            .gas
            .iter()
            .map(|g| Some(g.get_ref().count as u64))
            .chain(self.lattice.iter().map(|l| product(l.get_ref().counts)))
            .chain(
                self.block
                    .iter()
                    .map(|b| product(block_counts(b.get_ref(), &law))),
            )
        {
            total = total.checked_add(n?)?;
        }
        Some(total)
    }

    #[cfg(not(target_arch = "wasm32"))]
    fn file_count(&self, spec: &FileSpec) -> Option<u64> {
        start::count(&self.file_path(spec), spec.frame)
    }

    #[cfg(target_arch = "wasm32")]
    fn file_count(&self, _: &FileSpec) -> Option<u64> {
        None
    }

    /// What running the scenario needs, estimated before placing a disc.
    pub fn estimate(&self) -> Option<Estimate> {
        let particles = self.particle_count()?;
        let obstacles = self
            .obstacle
            .iter()
            .map(|o| o.get_ref().count())
            .fold(0u64, u64::saturating_add);
        Some(Estimate {
            particles,
            obstacles,
            bytes: particles
                .saturating_mul(BYTES_PER_PARTICLE)
                .saturating_add(obstacles.saturating_mul(BYTES_PER_OBSTACLE)),
        })
    }
}
