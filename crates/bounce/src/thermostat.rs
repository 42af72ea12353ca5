//! Thermostats and drives ([`crate::Config::thermostat`]): the discs' velocities changed at
//! the end of a step, after its collisions, by velocity rescaling, Andersen's bath
//! collisions or white-noise kicks (see [`crate::ThermostatKind`] for each law).
//!
//! Everything here is a function of the state, the step number and the discs' ids: each
//! disc's random numbers come from its own stream, seeded by `(seed, step, id)`, and the
//! sums over discs (the centre-of-mass velocity, the temperature, the mean kick) are exact
//! ([`ExactSum`]), so the result is the same bits whatever the thread count or storage order,
//! and across a resume. Rotation is left alone.

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

use crate::config::{Boundary, MassModel, Thermostat, ThermostatKind};
use crate::particles::Particles;
use crate::sources::splitmix;
use crate::sum::ExactSum;

/// Applies `thermostat` at the end of step `step` (counted from 1) of `dt`; returns the
/// kinetic energy it added (negative when it took some away).
///
/// In a Lees–Edwards box the temperature is that of the motion relative to the streaming
/// velocity ([`Boundary::streaming_velocity`]): rescaling scales it, and Andersen's bath
/// draws it, about the disc's streaming velocity.
pub(crate) fn apply(
    thermostat: &Thermostat,
    (model, boundary): (MassModel, &Boundary),
    p: &mut Particles,
    step: u64,
    dt: f64,
) -> f64 {
    let n = p.len();
    if n == 0 {
        return 0.0;
    }
    let mass: Vec<f64> = (0..n).map(|i| model.mass(p.radius[i], p.mass[i])).collect();
    let before: Vec<[f64; 2]> = (0..n).map(|i| [p.vx[i], p.vy[i]]).collect();
    let coupling = (thermostat.rate * dt).min(1.0);
    let t = thermostat.temperature;
    // The streaming velocity of each disc, in a Lees–Edwards box (none in any other).
    let streams: Vec<Option<f64>> = (p.y.iter())
        .map(|&y| boundary.streaming_velocity(y))
        .collect();
    let streaming = |i: usize| streams[i];
    match thermostat.kind {
        ThermostatKind::Rescale => {
            let relative: Vec<[f64; 2]> = (before.iter().zip(&streams))
                .map(|(v, u)| u.map_or(*v, |u| [v[0] - u, v[1]]))
                .collect();
            let centre = centre_of_mass_velocity(&mass, &relative);
            let mut peculiar = ExactSum::new();
            for (m, v) in mass.iter().zip(&relative) {
                peculiar.add(0.5 * m * ((v[0] - centre[0]).powi(2) + (v[1] - centre[1]).powi(2)));
            }
            let now = peculiar.value() / n as f64;
            if now > 0.0 {
                let scale = (1.0 + coupling * (t / now - 1.0)).sqrt();
                for (i, v) in relative.iter().enumerate() {
                    p.vx[i] = centre[0] + scale * (v[0] - centre[0]);
                    p.vy[i] = centre[1] + scale * (v[1] - centre[1]);
                    if let Some(u) = streaming(i) {
                        p.vx[i] += u;
                    }
                }
            }
        }
        ThermostatKind::Andersen => {
            for (i, m) in mass.iter().enumerate() {
                let mut draw = Draws::new(thermostat.seed, step, p.id[i].0);
                if draw.uniform() < coupling {
                    let [a, b] = draw.normals();
                    let spread = (t / m).sqrt();
                    (p.vx[i], p.vy[i]) = (spread * a, spread * b);
                    if let Some(u) = streaming(i) {
                        p.vx[i] += u;
                    }
                }
            }
        }
        ThermostatKind::WhiteNoise => {
            let kicks: Vec<[f64; 2]> = (0..n)
                .map(|i| {
                    let [a, b] = Draws::new(thermostat.seed, step, p.id[i].0).normals();
                    let spread = (2.0 * thermostat.rate * t * dt / mass[i]).sqrt();
                    [spread * a, spread * b]
                })
                .collect();
            // Less the kicks' mass-weighted mean, so momentum is kept.
            let mean = centre_of_mass_velocity(&mass, &kicks);
            for (i, k) in kicks.iter().enumerate() {
                p.vx[i] += k[0] - mean[0];
                p.vy[i] += k[1] - mean[1];
            }
        }
    }
    let mut added = ExactSum::new();
    for i in 0..n {
        let (v, w) = (before[i], [p.vx[i], p.vy[i]]);
        added.add(0.5 * mass[i] * (w[0] * w[0] + w[1] * w[1] - v[0] * v[0] - v[1] * v[1]));
    }
    added.value()
}

/// `Σ m v / Σ m`, summed exactly.
fn centre_of_mass_velocity(mass: &[f64], velocity: &[[f64; 2]]) -> [f64; 2] {
    let (mut total, mut px, mut py) = (ExactSum::new(), ExactSum::new(), ExactSum::new());
    for (&m, v) in mass.iter().zip(velocity) {
        total.add(m);
        px.add(m * v[0]);
        py.add(m * v[1]);
    }
    let total = total.value();
    [px.value() / total, py.value() / total]
}

/// One disc's random numbers in one step: a stream of its own, from `(seed, step, id)`.
struct Draws(Pcg64Mcg);

impl Draws {
    fn new(seed: u64, step: u64, id: u32) -> Self {
        Draws(Pcg64Mcg::seed_from_u64(splitmix(
            seed ^ splitmix(step ^ splitmix(id as u64)),
        )))
    }

    /// Uniform in `[0, 1)`.
    fn uniform(&mut self) -> f64 {
        self.0.random::<f64>()
    }

    /// Two independent standard normals (Box–Muller, with `libm` for the same bits on every
    /// platform).
    fn normals(&mut self) -> [f64; 2] {
        let u = 1.0 - self.uniform(); // (0, 1]: the logarithm stays finite
        let angle = std::f64::consts::TAU * self.uniform();
        let r = libm::sqrt(-2.0 * libm::log(u));
        [r * libm::cos(angle), r * libm::sin(angle)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::{Particle, ParticleId};

    fn gas(n: usize) -> Particles {
        let mut p = Particles::default();
        for i in 0..n {
            let v = [(i as f64 * 0.37).sin() * 2.0, (i as f64 * 0.91).cos()];
            p.push(
                ParticleId(i as u32),
                &Particle::new([3.0 * i as f64, 0.0], v, 0.5 + 0.1 * (i % 3) as f64),
            );
        }
        p
    }

    fn temperature(p: &Particles, model: MassModel) -> f64 {
        let n = p.len();
        let mass: Vec<f64> = (0..n).map(|i| model.mass(p.radius[i], p.mass[i])).collect();
        let v: Vec<[f64; 2]> = (0..n).map(|i| [p.vx[i], p.vy[i]]).collect();
        let c = centre_of_mass_velocity(&mass, &v);
        (0..n)
            .map(|i| 0.5 * mass[i] * ((v[i][0] - c[0]).powi(2) + (v[i][1] - c[1]).powi(2)))
            .sum::<f64>()
            / n as f64
    }

    #[test]
    fn rescaling_relaxes_the_temperature_by_the_coupling_and_keeps_momentum() {
        let model = MassModel::Area;
        let mut p = gas(50);
        let bath = Thermostat::new(ThermostatKind::Rescale, 3.0, 10.0);
        let t0 = temperature(&p, model);
        let added = apply(&bath, (model, &Boundary::Open), &mut p, 1, 0.02);
        // T += 0.2 (3 − T).
        let t1 = temperature(&p, model);
        assert!((t1 - (t0 + 0.2 * (3.0 - t0))).abs() < 1e-12 * t1);
        assert!((added - 50.0 * (t1 - t0)).abs() < 1e-9);
        // rate · dt >= 1: exactly the bath's temperature.
        apply(&bath, (model, &Boundary::Open), &mut p, 2, 0.5);
        assert!((temperature(&p, model) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn white_noise_keeps_momentum_and_adds_its_energy_on_average() {
        let model = MassModel::Radius;
        let (n, steps, dt) = (4000, 100, 0.01);
        let bath = Thermostat::new(ThermostatKind::WhiteNoise, 1.5, 2.0);
        let mut p = gas(n);
        let momentum = |p: &Particles| -> [f64; 2] {
            let mut m = [0.0; 2];
            for i in 0..p.len() {
                m[0] += p.radius[i] * p.vx[i];
                m[1] += p.radius[i] * p.vy[i];
            }
            m
        };
        let start = momentum(&p);
        let mut added = 0.0;
        for step in 1..=steps {
            added += apply(&bath, (model, &Boundary::Open), &mut p, step, dt);
        }
        let end = momentum(&p);
        assert!((end[0] - start[0]).abs() < 1e-10 && (end[1] - start[1]).abs() < 1e-10);
        // 2 rate T (1 − 1/N) a disc per unit time. Each disc's gain is a χ² of two degrees
        // of freedom (a relative spread of 1): over 4,000 discs, 1.6 %.
        let expected = 2.0 * 2.0 * 1.5 * (1.0 - 1.0 / n as f64) * n as f64 * steps as f64 * dt;
        assert!(
            (added / expected - 1.0).abs() < 0.05,
            "{added} vs {expected}"
        );
    }

    #[test]
    fn andersen_draws_the_baths_maxwell_boltzmann_at_its_rate() {
        let model = MassModel::Area;
        let mut p = gas(2000);
        let bath = Thermostat::new(ThermostatKind::Andersen, 0.7, 25.0);
        let before: Vec<f64> = p.vx.clone();
        apply(&bath, (model, &Boundary::Open), &mut p, 1, 0.01);
        // About a quarter of the discs drawn anew.
        let changed = (0..2000).filter(|&i| p.vx[i] != before[i]).count();
        assert!((changed as f64 / 2000.0 - 0.25).abs() < 0.04, "{changed}");
        // Every disc drawn: its temperature is the bath's.
        let all = Thermostat::new(ThermostatKind::Andersen, 0.7, 1e3);
        apply(&all, (model, &Boundary::Open), &mut p, 2, 0.01);
        assert!((temperature(&p, model) / 0.7 - 1.0).abs() < 0.06);
    }

    #[test]
    fn the_draws_follow_the_disc_not_its_place_in_storage() {
        let model = MassModel::Radius;
        let bath = Thermostat::new(ThermostatKind::WhiteNoise, 1.0, 1.0);
        let mut forward = gas(20);
        let mut backward = Particles::default();
        for i in (0..20).rev() {
            backward.push(ParticleId(i as u32), &forward.get(i).unwrap());
        }
        apply(&bath, (model, &Boundary::Open), &mut forward, 7, 0.1);
        apply(&bath, (model, &Boundary::Open), &mut backward, 7, 0.1);
        for i in 0..20 {
            let j = 19 - i;
            assert_eq!(forward.vx[i].to_bits(), backward.vx[j].to_bits());
            assert_eq!(forward.vy[i].to_bits(), backward.vy[j].to_bits());
        }
    }
}
