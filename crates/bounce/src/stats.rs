//! What a step reports: energy, momentum, collisions, wall impulses, overlap.

use serde::{Deserialize, Serialize};

use crate::config::MassModel;
use crate::geometry::WallImpulse;
use crate::parallel::{CHUNK, Executor};
use crate::particles::Particles;

/// Measurements of the last [`crate::World::step`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepStats {
    /// Total kinetic energy `Σ ½ m v²` after the step, with the active mass model.
    pub kinetic_energy: f64,
    /// Total linear momentum `Σ m v` after the step, with the active mass model.
    pub momentum: [f64; 2],
    /// Colliding pairs found (distance <= collision distance), summed over the substeps.
    pub pairs: usize,
    /// Momentum delivered to each wall during the step, summed over the substeps.
    pub wall_impulse: WallImpulse,
    /// Largest `collision_distance - distance` among the pairs found in any substep, or 0.
    pub max_overlap: f64,
}

/// Wall-clock seconds spent in each stage of the last step, summed over its substeps.
/// All zero on `wasm32`, which has no clock in `std`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepProfile {
    /// Integration and boundary.
    pub integrate: f64,
    /// Broadphase upkeep: checking the candidate list and, when discs have moved too far,
    /// rebuilding it (levels, grids, counting sort, reordering into cell order, listing).
    pub bin: f64,
    /// Testing the candidates and sorting the contacts into canonical order.
    pub pairs: f64,
    /// Pair resolution.
    pub resolve: f64,
    /// Energy and momentum sums.
    pub measure: f64,
    /// How many substeps rebuilt the candidate list.
    pub rebuilds: usize,
}

impl StepProfile {
    /// Total over the stages.
    pub fn total(&self) -> f64 {
        self.integrate + self.bin + self.pairs + self.resolve + self.measure
    }
}

/// A stopwatch that reads nothing where `std` has no clock.
pub(crate) struct Stopwatch {
    #[cfg(not(target_arch = "wasm32"))]
    last: std::time::Instant,
}

impl Stopwatch {
    pub(crate) fn start() -> Self {
        Stopwatch {
            #[cfg(not(target_arch = "wasm32"))]
            last: std::time::Instant::now(),
        }
    }

    /// Seconds since the last lap (or the start).
    pub(crate) fn lap(&mut self) -> f64 {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let now = std::time::Instant::now();
            let dt = (now - self.last).as_secs_f64();
            self.last = now;
            dt
        }
        #[cfg(target_arch = "wasm32")]
        0.0
    }
}

/// Kinetic energy and momentum of all discs, summed in fixed chunks (thread-count independent).
pub(crate) fn energy_and_momentum(
    p: &Particles,
    mass_model: MassModel,
    exec: &Executor,
) -> (f64, [f64; 2]) {
    let n = p.len();
    let partial = exec.map_index(n, 0..n.div_ceil(CHUNK), |chunk| {
        let (mut e, mut px, mut py) = (0.0, 0.0, 0.0);
        for i in chunk * CHUNK..((chunk + 1) * CHUNK).min(n) {
            let m = mass_model.mass(p.radius[i], p.mass[i]);
            let (vx, vy) = (p.vx[i], p.vy[i]);
            e += 0.5 * m * (vx * vx + vy * vy);
            px += m * vx;
            py += m * vy;
        }
        (e, px, py)
    });
    partial
        .iter()
        .fold((0.0, [0.0, 0.0]), |(e, [px, py]), &(de, dx, dy)| {
            (e + de, [px + dx, py + dy])
        })
}
