//! The world's pressure and pressure tensor: the kinetic part from the discs' motion in the
//! centre-of-mass frame (less the streaming velocity in a Lees–Edwards box), the collisional
//! part from the last step's virial, over the area the centres move in.

use crate::geometry::Geometry;
use crate::law::Law;

use super::World;

impl World {
    /// The pressure `(K + W) / A` of [`crate::StepStats::pressure`] for a kinetic energy,
    /// momentum and virial `W` (the discs' total mass and mean radius are the world's, summed
    /// in id order). `None` in an open world.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::periodic([0.0, 0.0], [10.0, 10.0]),
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([2.0, 2.0], [1.0, 0.0], 0.5))?;
    /// world.add_particle(Particle::new([7.0, 7.0], [-1.0, 0.0], 0.5))?;
    /// // No collisions (W = 0): P A = N kT = the kinetic energy, ½ · 0.5 · 1 · 2.
    /// let p = world.pressure(0.5, [0.0, 0.0], 0.0).unwrap();
    /// assert!((p - 0.5 / 100.0).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// In a Lees–Edwards box the kinetic part is the motion relative to the streaming
    /// velocity, [`World::peculiar_kinetic_energy`] (the arguments' kinetic energy and
    /// momentum, which include the shear flow, are not used).
    pub fn pressure(&self, kinetic_energy: f64, momentum: [f64; 2], virial: f64) -> Option<f64> {
        let m = &self.measured;
        let area = self.pressure_area()?;
        let kinetic = if self.config.boundary.is_sheared() {
            self.peculiar_kinetic_energy()
        } else {
            let [px, py] = momentum;
            let drift = if m.total_mass > 0.0 {
                (px * px + py * py) / (2.0 * m.total_mass)
            } else {
                0.0
            };
            kinetic_energy - drift
        };
        Some((kinetic + virial) / area)
    }

    /// The area the pressure is taken over: the area the discs' centres move in, a periodic
    /// box's, or between walls the box less the discs' mean radius at each wall. `None` in an
    /// open world.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([5.0, 5.0], [0.0, 0.0], 0.5))?;
    /// assert_eq!(world.pressure_area(), Some(9.0 * 9.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn pressure_area(&self) -> Option<f64> {
        let mean_radius = self.measured.radius_sum / self.particles.len().max(1) as f64;
        Geometry::new(&self.config).area(mean_radius)
    }

    /// The pressure tensor `[P_xx, P_yy, P_xy]` now, with [`crate::Config::pressure_tensor`]
    /// (`None` without it, or in an open world): `P_ab = (Σ m u_a u_b + W_ab) / A`, `u` each
    /// disc's velocity in the centre-of-mass frame (summed in id order), `W_ab` the last
    /// step's [`crate::StepStats::virial_tensor`] and `A` the area of
    /// [`crate::StepStats::pressure`]. Its mean diagonal `(P_xx + P_yy) / 2` is the pressure.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let config = Config {
    ///     boundary: Boundary::periodic([0.0, 0.0], [10.0, 10.0]),
    ///     pressure_tensor: true,
    ///     ..Config::default()
    /// };
    /// let mut world = World::new(config).unwrap();
    /// world.add_particle(Particle::new([2.0, 5.0], [1.0, 0.0], 0.5)).unwrap();
    /// world.add_particle(Particle::new([8.0, 5.0], [-1.0, 0.0], 0.5)).unwrap();
    /// world.step(0.01).unwrap();
    /// // Two discs moving along x, no collision yet: only P_xx.
    /// let [xx, yy, xy] = world.pressure_tensor().unwrap();
    /// assert!(xx > 0.0 && yy == 0.0 && xy == 0.0);
    /// ```
    pub fn pressure_tensor(&self) -> Option<[f64; 3]> {
        if !self.config.pressure_tensor {
            return None;
        }
        let area = self.pressure_area()?;
        let mut kinetic = [0.0; 3];
        for (mass, u) in self.peculiar_velocities() {
            kinetic[0] += mass * u[0] * u[0];
            kinetic[1] += mass * u[1] * u[1];
            kinetic[2] += mass * u[0] * u[1];
        }
        let w = self.stats.virial_tensor;
        Some([0, 1, 2].map(|k| (kinetic[k] + w[k]) / area))
    }

    /// The kinetic energy of the discs' motion relative to the centre of mass and, in a
    /// Lees–Edwards box, to the streaming velocity
    /// ([`crate::Boundary::streaming_velocity`]): `N kT` in two dimensions, summed in id
    /// order.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::lees_edwards([0.0, 0.0], [10.0, 10.0], 0.2),
    ///     ..Config::default()
    /// })?;
    /// // Each disc moves with the flow at its height (0.2 · (y − 5)), plus 1 along y.
    /// world.add_particle(Particle::new([2.0, 2.0], [-0.6, 1.0], 0.5))?;
    /// world.add_particle(Particle::new([7.0, 8.0], [0.6, -1.0], 0.5))?;
    /// // Relative to the flow and the (resting) centre of mass: ½ m 1² each, m = 0.5.
    /// assert!((world.peculiar_kinetic_energy() - 0.5).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn peculiar_kinetic_energy(&self) -> f64 {
        let velocities = self.peculiar_velocities();
        (velocities.iter())
            .map(|(mass, u)| 0.5 * mass * (u[0] * u[0] + u[1] * u[1]))
            .sum()
    }

    /// Each disc's mass and velocity relative to the centre of mass and the streaming
    /// velocity (in a Lees–Edwards box), in id order.
    fn peculiar_velocities(&self) -> Vec<(f64, [f64; 2])> {
        let (p, law) = (&self.particles, Law::new(&self.config));
        let boundary = &self.config.boundary;
        let order = self.in_id_order();
        let velocity = |i: usize| match boundary.streaming_velocity(p.y[i]) {
            Some(u) => [p.vx[i] - u, p.vy[i]],
            None => [p.vx[i], p.vy[i]],
        };
        let (mut total, mut momentum) = (0.0, [0.0; 2]);
        for &(_, i) in &order {
            let mass = law.mass(p.radius[i], p.mass[i]);
            let v = velocity(i);
            total += mass;
            momentum[0] += mass * v[0];
            momentum[1] += mass * v[1];
        }
        let centre = if total > 0.0 {
            [momentum[0] / total, momentum[1] / total]
        } else {
            [0.0; 2]
        };
        (order.iter())
            .map(|&(_, i)| {
                let v = velocity(i);
                let mass = law.mass(p.radius[i], p.mass[i]);
                (mass, [v[0] - centre[0], v[1] - centre[1]])
            })
            .collect()
    }
}
