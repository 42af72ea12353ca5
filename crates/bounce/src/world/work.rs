//! The work done on the discs from outside their collisions, which the energy balance needs
//! besides the discs' own energy: over an interval, the energy dissipated is the energy
//! before, less the energy after, plus the work the thermostat
//! ([`World::thermostat_work`]) and the moving obstacles ([`World::obstacle_work`]) did.

use super::World;

impl World {
    /// The kinetic energy the thermostat has added since the start (the sum of
    /// [`crate::StepStats::thermostat_work`]; negative where it took more away than it
    /// gave). 0 without a thermostat.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, Thermostat, ThermostatKind, World};
    ///
    /// let config = Config {
    ///     boundary: Boundary::periodic([0.0, 0.0], [20.0, 20.0]),
    ///     thermostat: Some(Thermostat::new(ThermostatKind::Rescale, 2.0, 1.0)),
    ///     ..Config::default()
    /// };
    /// let mut world = World::new(config).unwrap();
    /// world.add_particle(Particle::new([5.0, 5.0], [1.0, 0.0], 1.0)).unwrap();
    /// world.add_particle(Particle::new([15.0, 15.0], [-1.0, 0.0], 1.0)).unwrap();
    /// let before = world.stats().kinetic_energy;
    /// world.step(0.1).unwrap();
    /// // No collision: the bath alone changed the energy (heating the discs towards kT = 2).
    /// let gained = world.stats().kinetic_energy - before;
    /// assert!(gained > 0.0);
    /// assert!((world.thermostat_work() - gained).abs() < 1e-12);
    /// ```
    pub fn thermostat_work(&self) -> f64 {
        self.thermostat_work
    }
}
