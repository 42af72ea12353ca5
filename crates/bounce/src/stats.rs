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
    /// The collision virial of the step, `W = (1/2) Σ r_ij · Δp_ij / dt` over the pairs
    /// resolved in all its substeps (`r_ij = p_i - p_j`, `Δp_ij` the impulse on `i`): the
    /// interaction part of the 2D virial equation `P A = N kT + W`. Energy units.
    pub virial: f64,
    /// The pressure `(K + W) / A` where `K` is the kinetic energy in the centre-of-mass
    /// frame (`N kT` in 2D) and `A` the area the centres move in: the periodic box's area,
    /// or between walls `(width − d)(height − d)` with `d` the mean diameter (walls stop a
    /// centre one radius short; exact for equal discs). `None` in an open world, which has no
    /// area. Force per length in 2D (M T⁻²); in a walled box it matches the walls' impulse per
    /// time and length.
    pub pressure: Option<f64>,
    /// The substeps the step took: `Config::substeps`, or more when `Config::max_travel`
    /// asked for them.
    pub substeps: u32,
    /// Work done on the discs by moving obstacles during the step, `Σ J · u` over their
    /// collisions (`J` the disc's impulse, `u` the obstacle's velocity): what a piston puts
    /// into the gas.
    pub obstacle_work: f64,
    /// Discs the emitters added at the start of the step.
    pub emitted: usize,
    /// Discs the sinks removed at the end of the step.
    pub removed: usize,
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
    /// The most discs past the list's allowance in a substep that kept the list (met
    /// alone: `broadphase::strays`).
    pub strays: usize,
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

/// What one pass over the discs measures: the sums of the step's statistics and what the
/// next step needs to choose its substeps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Measured {
    pub kinetic_energy: f64,
    pub momentum: [f64; 2],
    /// The total mass (set by the world, in id order, when discs or the config change).
    pub total_mass: f64,
    /// The largest squared speed (only measured for adaptive substeps).
    pub max_speed2: f64,
    /// The smallest radius (infinite without discs; only for adaptive substeps).
    pub min_radius: f64,
    /// The sum of the radii (set by the world like the total mass).
    pub radius_sum: f64,
}

/// Kinetic energy and momentum of all discs, and with `extremes` the
/// largest speed and the smallest radius (what adaptive substeps need; the minimum and
/// maximum cost as much as the rest of the pass, so only then), summed in fixed chunks
/// (thread-count independent).
///
/// The total mass and the radius sum change only when discs or the configuration do: the
/// world sums them in id order then (`World::totals_by_id`), not here.
pub(crate) fn measure(
    p: &Particles,
    mass_model: MassModel,
    exec: &Executor,
    extremes: bool,
) -> Measured {
    if extremes {
        measure_pass::<true>(p, mass_model, exec)
    } else {
        measure_pass::<false>(p, mass_model, exec)
    }
}

fn measure_pass<const EXTREMES: bool>(
    p: &Particles,
    mass_model: MassModel,
    exec: &Executor,
) -> Measured {
    let n = p.len();
    let partial = exec.map_index(n, 0..n.div_ceil(CHUNK), |chunk| {
        // Scalars, not a struct, so the accumulators stay in registers.
        let (mut e, mut px, mut py) = (0.0, 0.0, 0.0);
        let (mut max_speed2, mut min_radius) = (0.0f64, f64::INFINITY);
        for i in chunk * CHUNK..((chunk + 1) * CHUNK).min(n) {
            let m = mass_model.mass(p.radius[i], p.mass[i]);
            let (vx, vy) = (p.vx[i], p.vy[i]);
            let v2 = vx * vx + vy * vy;
            e += 0.5 * m * v2;
            px += m * vx;
            py += m * vy;
            if EXTREMES {
                max_speed2 = max_speed2.max(v2);
                min_radius = min_radius.min(p.radius[i]);
            }
        }
        Measured {
            kinetic_energy: e,
            momentum: [px, py],
            max_speed2,
            min_radius,
            ..Measured::default()
        }
    });
    partial.iter().fold(
        Measured {
            min_radius: f64::INFINITY,
            ..Measured::default()
        },
        |a, b| Measured {
            kinetic_energy: a.kinetic_energy + b.kinetic_energy,
            momentum: [a.momentum[0] + b.momentum[0], a.momentum[1] + b.momentum[1]],
            total_mass: 0.0,
            max_speed2: a.max_speed2.max(b.max_speed2),
            min_radius: a.min_radius.min(b.min_radius),
            radius_sum: 0.0,
        },
    )
}
