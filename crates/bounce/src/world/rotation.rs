//! The discs' rotation as a front end reads and sets it: angular velocities and orientations
//! by id, the rotational energy, the angular momentum and the work of friction (see
//! `law::rough`). Smooth discs that never turned keep no rotation state: their angular
//! velocities read as zeros and cost nothing.

use crate::law::Law;
use crate::particles::ParticleError;

use super::World;

impl World {
    /// Every disc's angular velocity (counter-clockwise, radians per time unit), in id order;
    /// zeros for discs that never turned.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 1.0))?;
    /// world.add_particle(Particle::new([5.0, 0.0], [0.0, 0.0], 1.0))?;
    /// world.set_angular_velocities(&[2.0, 0.0]).unwrap();
    /// assert_eq!(world.angular_velocities(), [2.0, 0.0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn angular_velocities(&self) -> Vec<f64> {
        self.by_id(&self.particles.omega)
    }

    /// Every disc's orientation (radians, in `[0, 2π]`), in id order.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 1.0))?;
    /// world.add_particle(Particle::new([5.0, 0.0], [0.0, 0.0], 1.0))?;
    /// world.set_angular_velocities(&[2.0, 0.0]).unwrap();
    /// world.step(0.25)?; // a spinning disc turns: θ += ω dt
    /// assert_eq!(world.orientations(), [0.5, 0.0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn orientations(&self) -> Vec<f64> {
        self.by_id(&self.particles.theta)
    }

    /// A rotation array in id order (zeros while it is not kept).
    fn by_id(&self, values: &[f64]) -> Vec<f64> {
        self.in_id_order()
            .into_iter()
            .map(|(_, i)| values.get(i).copied().unwrap_or(0.0))
            .collect()
    }

    /// Sets every disc's angular velocity, `omega[k]` for id `k`, all or nothing: on the
    /// wrong count or the first value that is not finite, returns its index and the error
    /// and the world is unchanged. Smooth discs start keeping rotation state (a spinning disc
    /// turns; only rough ones change their spin).
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 1.0))?;
    /// assert_eq!(world.set_angular_velocities(&[f64::NAN]).unwrap_err().0, 0);
    /// assert!(world.set_angular_velocities(&[1.0, 2.0]).is_err()); // one disc, two values
    /// world.set_angular_velocities(&[1.0]).unwrap();
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_angular_velocities(&mut self, omega: &[f64]) -> Result<(), (usize, ParticleError)> {
        let n = self.particles.len();
        if omega.len() != n {
            return Err((
                omega.len().min(n),
                ParticleError::WrongCount {
                    expected: n,
                    given: omega.len(),
                },
            ));
        }
        if let Some(k) = omega.iter().position(|w| !w.is_finite()) {
            return Err((k, ParticleError::NonFiniteRotation(omega[k], 0.0)));
        }
        if omega.iter().all(|&w| w == 0.0) && !self.particles.turning {
            return Ok(());
        }
        self.particles.start_turning();
        for (&w, (_, i)) in omega.iter().zip(self.in_id_order()) {
            self.particles.omega[i] = w;
        }
        Ok(())
    }

    /// The energy friction and rolling resistance have removed since the start (the sum of
    /// [`crate::StepStats::friction_work`]): with `e = 1`, the kinetic, rotational and
    /// potential energy lost.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// // A disc sliding along a rough floor: friction starts it rolling and takes energy.
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [50.0, 10.0]),
    ///     gravity: [0.0, -10.0],
    ///     friction: 0.5,
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([5.0, 1.0], [4.0, 0.0], 1.0))?;
    /// for _ in 0..100 {
    ///     world.step(0.01)?;
    /// }
    /// assert!(world.friction_work() > 0.0);
    /// assert!(world.angular_velocities()[0] < 0.0); // rolling clockwise, to the right
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn friction_work(&self) -> f64 {
        self.friction_work
    }

    /// The rotational energy `Σ ½ I ω²` (`I = k m r²`), summed in id order; 0 for discs
    /// that never turned.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 2.0))?;
    /// world.set_angular_velocities(&[3.0]).unwrap();
    /// // I = ½ m r² (a uniform disc), m = r = 2 under the seed's mass model: ½ · 4 · 9.
    /// assert!((world.rotational_energy() - 18.0).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn rotational_energy(&self) -> f64 {
        let p = &self.particles;
        if !p.turning {
            return 0.0;
        }
        let inertia = self.inertia();
        self.in_id_order()
            .into_iter()
            .map(|(_, i)| 0.5 * inertia(i) * p.omega[i] * p.omega[i])
            .sum()
    }

    /// The angular momentum about the origin, `Σ m (x v_y − y v_x) + I ω` (orbital and
    /// spin), summed in id order, from the stored centres (wrapped into a periodic box, where
    /// the orbital part is not conserved).
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// // Mass 1 at (0, 2) moving at (3, 0): m (x v_y − y v_x) = −6.
    /// world.add_particle(Particle::new([0.0, 2.0], [3.0, 0.0], 1.0))?;
    /// assert_eq!(world.angular_momentum(), -6.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn angular_momentum(&self) -> f64 {
        let p = &self.particles;
        let law = Law::new(&self.config);
        let inertia = self.inertia();
        self.in_id_order()
            .into_iter()
            .map(|(_, i)| {
                let m = law.mass(p.radius[i], p.mass[i]);
                let orbital = m * (p.x[i] * p.vy[i] - p.y[i] * p.vx[i]);
                orbital + p.omega.get(i).map_or(0.0, |w| inertia(i) * w)
            })
            .sum()
    }

    /// Each disc's moment of inertia `k m r²`, by storage index.
    fn inertia(&self) -> impl Fn(usize) -> f64 + '_ {
        let (p, law) = (&self.particles, Law::new(&self.config));
        let k = self.config.inertia_factor;
        move |i| k * law.mass(p.radius[i], p.mass[i]) * p.radius[i] * p.radius[i]
    }
}
