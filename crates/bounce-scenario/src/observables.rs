//! Observables of a world's state, written beside `stats.csv` at each of its rows: profiles
//! binned along an axis (`profile.csv`), and the displacements from an origin state (the
//! mean-square displacement and the velocity autocorrelation, `msd.csv`).
//!
//! Every sum runs in id order, so the values are the same bits whatever the storage order,
//! the thread count or a resume.

use bounce::{Boundary, World};
use serde::{Deserialize, Serialize};

/// The axis a profile bins along.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// Bins across x.
    X,
    /// Bins across y.
    Y,
}

/// A profile along an axis: one entry per bin, from the box's low edge up.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Profile {
    /// Each bin's centre on the axis.
    pub centre: Vec<f64>,
    /// The discs whose centre is in the bin.
    pub count: Vec<u64>,
    /// Discs per area: the count over the bin's area.
    pub density: Vec<f64>,
    /// The mass-weighted mean velocity, `Σ m v / Σ m` (0 in an empty bin).
    pub velocity: Vec<[f64; 2]>,
    /// The temperature in the bin's own frame, `Σ ½ m |v − u|² / (count − 1)` (2D kT; the
    /// bin's mean velocity takes one disc's worth of the motion, so this is unbiased even
    /// for a few discs a bin; 0 with fewer than two).
    pub temperature: Vec<f64>,
}

/// The most bins a profile has: each is a row of `profile.csv` at every stats row.
pub const MAX_PROFILE_BINS: usize = 100_000;

/// The profile of `world` along `axis` in `bins` equal bins across its box (a disc on the
/// top edge goes into the last bin). Refused in an open world, which has no box.
///
/// ```
/// use bounce::{Boundary, Config, Particle, World};
/// use bounce_scenario::observables::{Axis, profile};
/// let config = Config { boundary: Boundary::walls([0.0, 0.0], [10.0, 4.0]), ..Config::default() };
/// let mut world = World::new(config).unwrap();
/// world.add_particle(Particle::new([2.0, 2.0], [1.0, 0.0], 0.5)).unwrap();
/// world.add_particle(Particle::new([3.0, 2.0], [3.0, 0.0], 0.5)).unwrap();
/// let p = profile(&world, Axis::X, 2).unwrap();
/// assert_eq!((p.count, p.centre), (vec![2, 0], vec![2.5, 7.5]));
/// assert_eq!(p.velocity[0], [2.0, 0.0]); // equal masses
/// // ½ m |v − u|² summed, over count − 1: ½ · 0.5 · (1 + 1) / 1 (mass = radius).
/// assert_eq!(p.temperature[0], 0.5);
/// ```
pub fn profile(world: &World, axis: Axis, bins: usize) -> Result<Profile, String> {
    let Some((min, max)) = world.config().boundary.bounds() else {
        return Err("a profile needs a box (walls or periodic), not an open world".into());
    };
    if !(1..=MAX_PROFILE_BINS).contains(&bins) {
        return Err(format!(
            "bins = {bins}: a profile has 1 to {MAX_PROFILE_BINS} bins"
        ));
    }
    let a = match axis {
        Axis::X => 0,
        Axis::Y => 1,
    };
    let (lo, hi) = (min[a], max[a]);
    let width = (hi - lo) / bins as f64;
    let across = max[1 - a] - min[1 - a];
    let p = world.particles();
    let model = world.config().mass_model;
    let mass = |i: usize| model.mass(p.radius()[i], p.per_particle_mass()[i]);
    let position = |i: usize| [p.x()[i], p.y()[i]][a];
    let bin_of = |i: usize| (((position(i) - lo) / width).floor().max(0.0) as usize).min(bins - 1);
    let order = world.in_id_order();
    let mut out = Profile {
        centre: (0..bins).map(|k| lo + (k as f64 + 0.5) * width).collect(),
        count: vec![0; bins],
        density: vec![0.0; bins],
        velocity: vec![[0.0; 2]; bins],
        temperature: vec![0.0; bins],
    };
    let mut weight = vec![0.0; bins];
    let mut momentum = vec![[0.0; 2]; bins];
    for &(_, i) in &order {
        let (k, m) = (bin_of(i), mass(i));
        out.count[k] += 1;
        weight[k] += m;
        momentum[k][0] += m * p.vx()[i];
        momentum[k][1] += m * p.vy()[i];
    }
    for k in 0..bins {
        out.density[k] = out.count[k] as f64 / (width * across);
        if weight[k] > 0.0 {
            out.velocity[k] = [momentum[k][0] / weight[k], momentum[k][1] / weight[k]];
        }
    }
    let mut energy = vec![0.0; bins];
    for &(_, i) in &order {
        let k = bin_of(i);
        let u = out.velocity[k];
        energy[k] += 0.5 * mass(i) * ((p.vx()[i] - u[0]).powi(2) + (p.vy()[i] - u[1]).powi(2));
    }
    for ((t, &count), e) in out.temperature.iter_mut().zip(&out.count).zip(&energy) {
        if count > 1 {
            *t = e / (count - 1) as f64;
        }
    }
    Ok(out)
}

/// The discs' unwrapped positions and velocities at an origin, by id: what the MSD and the
/// velocity autocorrelation are measured from (saved in checkpoints, so a resumed run keeps
/// its origin).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Origin {
    /// The discs' ids, ascending.
    pub ids: Vec<u32>,
    /// Each disc's unwrapped position and velocity, `[x, y, vx, vy]`.
    pub state: Vec<[f64; 4]>,
}

/// A disc's centre with its periodic box crossings undone.
fn unwrapped(world: &World, i: usize) -> [f64; 2] {
    let p = world.particles();
    let [x, y] = [p.x()[i], p.y()[i]];
    match world.config().boundary {
        Boundary::Periodic { min, max } => {
            let image = p.image()[i];
            [
                x + image[0] as f64 * (max[0] - min[0]),
                y + image[1] as f64 * (max[1] - min[1]),
            ]
        }
        _ => [x, y],
    }
}

impl Origin {
    /// The world's state now.
    pub fn of(world: &World) -> Origin {
        let p = world.particles();
        let mut origin = Origin::default();
        for (id, i) in world.in_id_order() {
            let [x, y] = unwrapped(world, i);
            origin.ids.push(id.0);
            origin.state.push([x, y, p.vx()[i], p.vy()[i]]);
        }
        origin
    }

    /// The mean-square displacement `⟨|r(t) − r(0)|²⟩` and the velocity autocorrelation
    /// `⟨v(t)·v(0)⟩` over the discs both at the origin and in `world` now (emitted discs
    /// are not, removed ones no longer); `None` when there are none.
    pub fn msd_vacf(&self, world: &World) -> Option<(f64, f64)> {
        let p = world.particles();
        let (mut n, mut msd, mut vacf) = (0usize, 0.0, 0.0);
        let mut at = 0;
        for (id, i) in world.in_id_order() {
            while at < self.ids.len() && self.ids[at] < id.0 {
                at += 1;
            }
            if at == self.ids.len() || self.ids[at] != id.0 {
                continue;
            }
            let [x0, y0, vx0, vy0] = self.state[at];
            let [x, y] = unwrapped(world, i);
            msd += (x - x0).powi(2) + (y - y0).powi(2);
            vacf += p.vx()[i] * vx0 + p.vy()[i] * vy0;
            n += 1;
        }
        (n > 0).then(|| (msd / n as f64, vacf / n as f64))
    }
}
