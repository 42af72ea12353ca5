//! Derived quantities the outputs report.

use bounce::World;

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

/// `kT` from the kinetic energy in the centre-of-mass frame: in 2D each disc carries `kT`.
/// `total_mass` is the sum of [`masses`].
pub fn temperature(world: &World, total_mass: f64) -> f64 {
    let n = world.len();
    if n == 0 || total_mass <= 0.0 {
        return 0.0;
    }
    let s = world.stats();
    let drift_energy = (s.momentum[0].powi(2) + s.momentum[1].powi(2)) / (2.0 * total_mass);
    ((s.kinetic_energy - drift_energy) / n as f64).max(0.0)
}
