//! What a world reports: the last step's statistics and profile, the clock, the discs, the
//! sensors' counts and the contacts now, and the state hash that says two runs are the same.

use crate::particles::Particles;
use crate::stats::{StepProfile, StepStats};

use super::{SensorCount, World};

impl World {
    /// Each sensor's counts, in the order of [`crate::Config::sensors`]: the discs inside now, and
    /// those that entered and left, in the last step and since the world was made. See
    /// [`SensorCount`] for an example.
    pub fn sensors(&self) -> &[SensorCount] {
        self.sensors.counts()
    }

    /// How many contacts the last substep had (a pair, a disc and a wall, a disc and an
    /// obstacle), as contact events follow them; 0 unless [`crate::Config::contact_events`] is on.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let config = Config { contact_events: true, ..Config::default() };
    /// let mut world = World::new(config)?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 1.0))?;
    /// world.add_particle(Particle::new([1.5, 0.0], [0.0, 0.0], 1.0))?; // overlapping
    /// world.step(0.01)?;
    /// assert_eq!(world.contacts_now(), 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn contacts_now(&self) -> usize {
        self.contact_log.touching()
    }

    /// What the last step measured (energy and momentum are kept current when particles are
    /// added or the configuration changes).
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// assert!(world.is_empty());
    /// world.add_particle(Particle::new([0.0, 0.0], [2.0, 0.0], 0.5))?;
    /// assert_eq!(world.stats().kinetic_energy, 1.0); // ½ · 0.5 · 2², mass = radius
    /// for _ in 0..3 {
    ///     world.step(0.25)?;
    /// }
    /// assert_eq!((world.time(), world.step_count(), world.len()), (0.75, 3, 1));
    /// assert_eq!(world.particles().x()[0], 1.5);
    /// assert_eq!(world.stats().momentum, [1.0, 0.0]);
    /// assert!(world.profile().integrate >= 0.0); // seconds in each stage
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn stats(&self) -> &StepStats {
        &self.stats
    }

    /// Where the last step spent its time, stage by stage. See [`World::stats`] for an
    /// example.
    pub fn profile(&self) -> &StepProfile {
        &self.profile
    }

    /// Simulated time: the sum of the `dt`s stepped. See [`World::stats`] for an example.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Number of steps taken. See [`World::stats`] for an example.
    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// Number of particles. See [`World::stats`] for an example.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// `true` when the world holds no particles. See [`World::stats`] for an example.
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// The particle arrays, in storage order (which changes every step; ids do not). See
    /// [`Particles`] for an example.
    pub fn particles(&self) -> &Particles {
        &self.particles
    }

    /// A 64-bit FNV-1a hash of the state (ids, positions, velocities, radii, and where discs
    /// turn their angular velocities and orientations, in id order, bit for bit) and the
    /// step count: equal hashes mean identical runs, on any platform.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let run = |threads| -> Result<u64, Box<dyn std::error::Error>> {
    ///     let mut world = World::new(Config::default())?;
    ///     world.set_threads(threads)?;
    ///     for k in 0..20 {
    ///         world.add_particle(Particle::new([k as f64 * 1.9, 0.0], [(k % 3) as f64, 0.0], 1.0))?;
    ///     }
    ///     for _ in 0..50 {
    ///         world.step(0.1)?;
    ///     }
    ///     Ok(world.state_hash())
    /// };
    /// assert_eq!(run(1)?, run(2)?); // the same bits on any thread count
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn state_hash(&self) -> u64 {
        let mut hash = 0xcbf2_9ce4_8422_2325u64;
        let mut eat = |bytes: [u8; 8]| {
            for b in bytes {
                hash = (hash ^ b as u64).wrapping_mul(0x0100_0000_01b3);
            }
        };
        eat(self.steps.to_le_bytes());
        let p = &self.particles;
        for (id, i) in self.in_id_order() {
            eat((id.0 as u64).to_le_bytes());
            for v in [p.x[i], p.y[i], p.vx[i], p.vy[i], p.radius[i]] {
                eat(v.to_bits().to_le_bytes());
            }
            if p.turning {
                for v in [p.omega[i], p.theta[i]] {
                    eat(v.to_bits().to_le_bytes());
                }
            }
        }
        hash
    }
}
