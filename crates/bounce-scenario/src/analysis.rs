//! Quantities the CLI's plots and the viewer's panels both show: masses, temperature, the
//! speed histogram against the 2D Maxwell–Boltzmann distribution, the hard-disc equation of
//! state and adiabat the pressure is compared with, and a heap's angle of repose.

use bounce::World;
use bounce::scene::maxwell_boltzmann_pdf;

/// The masses of all discs under the world's mass model, in storage order.
pub fn masses(world: &World) -> Vec<f64> {
    let p = world.particles();
    let model = world.config().mass_model;
    p.radius()
        .iter()
        .zip(p.per_particle_mass())
        .map(|(&r, &m)| model.mass(r, m))
        .collect()
}

/// The total mass, summed in id order: the same bits whatever the storage order (a resumed
/// run's storage order differs from the original's, its temperatures must not).
pub fn total_mass(world: &World) -> f64 {
    let p = world.particles();
    let m = masses(world);
    let mut by_id: Vec<(u32, f64)> = p.ids().iter().map(|id| id.0).zip(m).collect();
    by_id.sort_unstable_by_key(|&(id, _)| id);
    by_id.iter().map(|&(_, m)| m).sum()
}

/// The discs' energy: kinetic, rotational and potential, each summed in id order. What
/// `stats.csv`'s `dissipated` balances (with the thermostat's and the obstacles' work).
pub fn total_energy(world: &World) -> f64 {
    let (kinetic, _) = motion_sums(world);
    kinetic + world.rotational_energy() + potential_energy(world)
}

/// The discs' kinetic plus potential energy, summed in id order (the potential is zero
/// without gravity): what a run's summary compares from start to end, and what must be
/// finite at the start.
pub fn mechanical_energy(world: &World) -> f64 {
    motion_sums(world).0 + potential_energy(world)
}

/// The potential energy in the uniform gravity field, `−Σ m g·x` (zero at the origin), with
/// the world's mass model, summed in id order. Zero without gravity.
pub fn potential_energy(world: &World) -> f64 {
    let g = world.config().gravity;
    if g == [0.0, 0.0] {
        return 0.0;
    }
    let p = world.particles();
    let m = masses(world);
    world
        .in_id_order()
        .iter()
        .map(|&(_, i)| -m[i] * (g[0] * p.x()[i] + g[1] * p.y()[i]))
        .sum()
}

/// The kinetic energy `Σ ½ m v²` and momentum `Σ m v` with the world's mass model, summed in
/// id order: what files report, the same bits whatever the storage order (a resumed run's,
/// or a distributed run's whole assembled from its ranks). The world's own
/// [`bounce::StepStats`] sums in storage order, which is faster.
pub fn motion_sums(world: &World) -> (f64, [f64; 2]) {
    let p = world.particles();
    let m = masses(world);
    let (mut energy, mut momentum) = (0.0, [0.0, 0.0]);
    for (_, i) in world.in_id_order() {
        let (vx, vy) = (p.vx()[i], p.vy()[i]);
        energy += 0.5 * m[i] * (vx * vx + vy * vy);
        momentum[0] += m[i] * vx;
        momentum[1] += m[i] * vy;
    }
    (energy, momentum)
}

/// `kT` from the kinetic energy in the centre-of-mass frame (relative to the shear flow in a
/// Lees–Edwards box): in 2D each disc carries `kT`.
/// `total_mass` is the sum of [`masses`] (kept by callers, since masses do not change).
pub fn temperature(world: &World, total_mass: f64) -> f64 {
    let n = world.len();
    if n == 0 || total_mass <= 0.0 {
        return 0.0;
    }
    if world.config().boundary.is_sheared() {
        // Relative to the shear flow, not only the drift.
        return (world.peculiar_kinetic_energy() / n as f64).max(0.0);
    }
    let (energy, momentum) = motion_sums(world);
    let drift_energy = (momentum[0].powi(2) + momentum[1].powi(2)) / (2.0 * total_mass);
    ((energy - drift_energy) / n as f64).max(0.0)
}

/// The speed distribution now, and what theory expects at the measured temperature.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedHistogram {
    /// Bin width; bin `k` covers `[k width, (k + 1) width)`.
    pub width: f64,
    /// Probability density in each bin (integrates to 1).
    pub density: Vec<f64>,
    /// The measured temperature `kT`.
    pub kt: f64,
    /// `(speed, density)` points of the 2D Maxwell–Boltzmann distribution at `kt`: the mix
    /// of the Rayleigh curves of the masses present (a sample of up to 2,000 discs).
    pub curve: Vec<[f64; 2]>,
}

/// Histogram of the discs' speeds in `bins` bins, with the theoretical curve. In a sheared
/// (Lees–Edwards) box the speeds are *peculiar*, relative to the shear flow at each disc's
/// height, as the temperature is: lab-frame speeds there mix the flow into the spread and
/// follow no Maxwell–Boltzmann curve.
pub fn speed_histogram(world: &World, bins: usize, total_mass: f64) -> SpeedHistogram {
    let p = world.particles();
    let bins = bins.max(1);
    let boundary = &world.config().boundary;
    let speeds: Vec<f64> = p
        .vx()
        .iter()
        .zip(p.vy())
        .zip(p.y())
        .map(|((vx, vy), &y)| (vx - boundary.streaming_velocity(y).unwrap_or(0.0)).hypot(*vy))
        .collect();
    let v_max = speeds.iter().copied().fold(0.0, f64::max).max(1e-12) * 1.05;
    let width = v_max / bins as f64;
    let mut counts = vec![0usize; bins];
    for &v in &speeds {
        counts[((v / width) as usize).min(bins - 1)] += 1;
    }
    let n = speeds.len().max(1) as f64;
    let density = counts.iter().map(|&c| c as f64 / (n * width)).collect();
    let kt = temperature(world, total_mass);
    let all = masses(world);
    let mut sample: Vec<f64> = all
        .iter()
        .step_by((all.len() / 2000).max(1))
        .copied()
        .collect();
    // The mix weighs each distinct mass by how often it is drawn: one curve a mass, not a
    // disc, so a monodisperse gas costs one Rayleigh curve.
    sample.sort_unstable_by(f64::total_cmp);
    let mut kinds: Vec<(f64, f64)> = Vec::new();
    for &m in &sample {
        match kinds.last_mut() {
            Some((last, count)) if *last == m => *count += 1.0,
            _ => kinds.push((m, 1.0)),
        }
    }
    let curve = (0..=200)
        .map(|k| {
            let v = v_max * k as f64 / 200.0;
            let density = if kt > 0.0 && !sample.is_empty() {
                kinds
                    .iter()
                    .map(|&(m, count)| count * maxwell_boltzmann_pdf(v, kt, m))
                    .sum::<f64>()
                    / sample.len() as f64
            } else {
                0.0
            };
            [v, density]
        })
        .collect();
    SpeedHistogram {
        width,
        density,
        kt,
        curve,
    }
}

/// Henderson's equation of state for hard discs at packing fraction `eta`,
/// `Z = P A / (N kT) = (1 + η²/8) / (1 − η)²` (D. Henderson, Mol. Phys. 30, 971 (1975);
/// within about 1% of Monte Carlo to η = 0.6).
pub fn henderson_z(eta: f64) -> f64 {
    (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta))
}

/// The pressure at area `a` of hard discs covering `disc_area` in all, compressed (or let
/// expand) slowly and without heat from area `a0` at pressure `p0`: the hard-disc adiabat.
/// The work on the gas is its energy's gain, `N dT = −P dA` in 2D, and `P = Z(η) N kT / A`
/// with `η = disc_area / A`, so `d ln T = −Z(η) d ln A`: an ideal gas (`Z = 1`) keeps
/// `T A` and `P A²` constant, a dense one heats faster. `NaN` where `η >= 1`.
pub fn hard_disc_adiabat(a0: f64, p0: f64, disc_area: f64, a: f64) -> f64 {
    let z = |area: f64| {
        let eta = disc_area / area;
        if eta < 1.0 {
            henderson_z(eta)
        } else {
            f64::NAN
        }
    };
    // ln(T / T0) = −∫ Z d ln A, by Simpson's rule over ln A.
    const STEPS: usize = 256;
    let (l0, l1) = (a0.ln(), a.ln());
    let h = (l1 - l0) / STEPS as f64;
    let integral = (0..=STEPS)
        .map(|k| {
            let weight = match k {
                0 | STEPS => 1.0,
                k if k % 2 == 1 => 4.0,
                _ => 2.0,
            };
            weight * z((l0 + k as f64 * h).exp())
        })
        .sum::<f64>()
        * h
        / 3.0;
    p0 * (z(a) / z(a0)) * (-integral).exp() * (a0 / a)
}

/// The angle of repose of a heap on the floor, in degrees: the mean of its two flanks'
/// slopes ([`repose_flanks`]). `None` without a flank of three columns.
pub fn repose_angle(world: &World, floor: f64, column: f64) -> Option<f64> {
    match repose_flanks(world, floor, column)? {
        (Some(a), Some(b)) => Some((a + b) / 2.0),
        (a, b) => a.or(b),
    }
}

/// A heap's surface: the highest disc top `y + r` above `floor` in each column of `column`
/// width, as `(column centre, top)` (empty columns left out).
pub fn heap_surface(world: &World, floor: f64, column: f64) -> Vec<(f64, f64)> {
    let (left, tops) = column_tops(world, floor, column);
    tops.iter()
        .enumerate()
        .filter_map(|(k, t)| t.map(|t| (left + (k as f64 + 0.5) * column, t)))
        .collect()
}

/// The leftmost centre and each column's highest top above `floor`.
fn column_tops(world: &World, floor: f64, column: f64) -> (f64, Vec<Option<f64>>) {
    let p = world.particles();
    let left = p.x().iter().copied().fold(f64::INFINITY, f64::min);
    let mut tops: Vec<Option<f64>> = Vec::new();
    for i in 0..p.len() {
        let k = ((p.x()[i] - left) / column) as usize;
        if tops.len() <= k {
            tops.resize(k + 1, None);
        }
        let top = p.y()[i] + p.radius()[i] - floor;
        tops[k] = Some(tops[k].map_or(top, |t: f64| t.max(top)));
    }
    (left, tops)
}

/// The angles of a heap's left and right flanks, in degrees. The surface is
/// [`heap_surface`]'s; each flank is the straight line fitted (least squares) to the surface
/// from the peak outwards while it is between 20 % and 80 % of the peak's height above
/// `floor` (`None` for a flank of fewer than three columns). `None` without discs.
pub fn repose_flanks(world: &World, floor: f64, column: f64) -> Option<(Option<f64>, Option<f64>)> {
    let (_, tops) = column_tops(world, floor, column);
    let (peak, height) = tops
        .iter()
        .enumerate()
        .filter_map(|(k, t)| t.map(|t| (k, t)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let flank = |columns: &mut dyn Iterator<Item = usize>| -> Option<f64> {
        let points: Vec<(f64, f64)> = columns
            .filter_map(|k| tops[k].map(|t| ((k as f64 + 0.5) * column, t)))
            .filter(|&(_, t)| t >= 0.2 * height && t <= 0.8 * height)
            .collect();
        if points.len() < 3 {
            return None;
        }
        let n = points.len() as f64;
        let (mx, my) = points
            .iter()
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
        let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
            (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
        });
        Some((sxy / sxx).abs().atan().to_degrees())
    };
    Some((
        flank(&mut (0..peak).rev()),
        flank(&mut (peak + 1..tops.len())),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use bounce::{Config, Particle};

    #[test]
    fn the_hard_disc_adiabat_is_the_ideal_one_when_dilute_and_steeper_when_dense() {
        // Dilute: P A² constant.
        let p = hard_disc_adiabat(100.0, 2.0, 1e-9, 50.0);
        assert!((p / (2.0 * 4.0) - 1.0).abs() < 1e-9, "{p}");
        // Dense: d ln P / d ln A = d ln Z / d ln A − Z − 1 at every area.
        let (a0, p0, discs) = (100.0, 1.0, 30.0);
        for a in [90.0, 70.0, 50.0] {
            let ln_p = |a: f64| hard_disc_adiabat(a0, p0, discs, a).ln();
            let ln_z = |a: f64| henderson_z(discs / a).ln();
            let d = 1e-4 * a;
            let slope = (ln_p(a + d) - ln_p(a - d)) / ((a + d).ln() - (a - d).ln());
            let z_slope = (ln_z(a + d) - ln_z(a - d)) / ((a + d).ln() - (a - d).ln());
            let expected = z_slope - henderson_z(discs / a) - 1.0;
            assert!(
                (slope - expected).abs() < 1e-6,
                "{a}: {slope} vs {expected}"
            );
        }
        // Compressing from packing 0.16 to 0.30 heats far more than the ideal gas would.
        let p = hard_disc_adiabat(100.0, 1.0, 16.0, 16.0 / 0.3);
        assert!(p > 1.5 * (100.0f64 * 0.3 / 16.0).powi(2), "{p}");
        assert!(hard_disc_adiabat(100.0, 1.0, 16.0, 15.0).is_nan());
    }

    #[test]
    fn histogram_integrates_to_one_and_temperature_ignores_drift() {
        let mut world = World::new(Config::default()).unwrap();
        // Two discs of mass 1 (radius 1, seed model) moving together: all drift, kT = 0.
        world
            .add_particle(Particle::new([0.0, 0.0], [2.0, 0.0], 1.0))
            .unwrap();
        world
            .add_particle(Particle::new([5.0, 0.0], [2.0, 0.0], 1.0))
            .unwrap();
        assert_eq!(temperature(&world, 2.0), 0.0);
        let h = speed_histogram(&world, 10, 2.0);
        let total: f64 = h.density.iter().map(|d| d * h.width).sum();
        assert!((total - 1.0).abs() < 1e-12);
        // Opposite velocities: no drift, kT = KE / N = (½·4 + ½·4) / 2 = 2.
        world
            .set_velocity(bounce::ParticleId(1), [-2.0, 0.0])
            .unwrap();
        assert!((temperature(&world, 2.0) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn the_curve_mixes_the_rayleigh_curves_of_the_masses_present() {
        let mut world = World::new(Config::default()).unwrap();
        // Masses 1, 1 and 2 (the seed's model: mass = radius), no drift.
        for (x, v, r) in [(0.0, 1.0, 1.0), (5.0, -1.0, 1.0), (10.0, 0.0, 2.0)] {
            world
                .add_particle(Particle::new([x, 0.0], [0.0, v], r))
                .unwrap();
        }
        let h = speed_histogram(&world, 10, 4.0);
        // kT = (½·1 + ½·1 + 0) / 3.
        assert!((h.kt - 1.0 / 3.0).abs() < 1e-15);
        for &[v, density] in &h.curve {
            let rayleigh = |m: f64| m * v / h.kt * (-m * v * v / (2.0 * h.kt)).exp();
            let by_hand = (2.0 * rayleigh(1.0) + rayleigh(2.0)) / 3.0;
            assert!(
                (density - by_hand).abs() < 1e-14,
                "{v}: {density} vs {by_hand}"
            );
        }
    }

    #[test]
    fn in_a_sheared_box_the_speeds_are_relative_to_the_flow() {
        use bounce::Boundary;
        let world = |shear_rate: f64| {
            let mut world = World::new(Config {
                boundary: Boundary::LeesEdwards {
                    min: [0.0, 0.0],
                    max: [10.0, 10.0],
                    shear_rate,
                },
                ..Config::default()
            })
            .unwrap();
            // Discs riding the flow, u_x = 0.5 (y − 5), and one more moving across it at 1.
            for y in [1.0, 3.0, 7.0, 9.0] {
                let v = [0.5 * (y - 5.0), 0.0];
                world.add_particle(Particle::new([5.0, y], v, 0.2)).unwrap();
            }
            world
                .add_particle(Particle::new([2.0, 5.0], [0.0, 1.0], 0.2))
                .unwrap();
            world
        };
        let h = speed_histogram(&world(0.5), 4, 1.0);
        // Relative to the flow: four at rest, one at 1 (the top of the range, 1.05).
        assert_eq!(
            h.density
                .iter()
                .map(|d| d * h.width * 5.0)
                .map(f64::round)
                .collect::<Vec<_>>(),
            [4.0, 0.0, 0.0, 1.0]
        );
        // The same discs in a box at rest: their lab-frame speeds, up to 2.
        let h = speed_histogram(&world(0.0), 4, 1.0);
        assert!(h.width * 4.0 > 2.0);
    }
}
