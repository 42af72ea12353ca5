//! Particles by id: the lookup from ids to storage, reading and setting discs, and the
//! queries a front end makes (the disc under the mouse, the colliding pairs).

use crate::broadphase::{self, Broadphase};
use crate::contacts::Contacts;
use crate::context::StepContext;
use crate::particles::{Particle, ParticleError, ParticleId};

use super::World;

impl World {
    /// Where a Lees–Edwards box's images above stand along x now: `shear_rate · height ·
    /// time`, brought into `[-width / 2, width / 2)` (the images below stand at minus it);
    /// `None` in any other boundary.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::lees_edwards([0.0, 0.0], [10.0, 10.0], 0.1),
    ///     ..Config::default()
    /// })?;
    /// let id = world.add_particle(Particle::new([5.0, 9.9], [0.0, 1.0], 0.5))?;
    /// world.step(0.5)?; // the images above move at 0.1 · 10 = 1: offset 0.5
    /// assert_eq!(world.lees_edwards_offset(), Some(0.5));
    /// // Out through the top, in at the bottom moved back by the offset, 1 slower along x.
    /// let disc = world.particle(id).unwrap();
    /// assert!((disc.position[0] - 4.5).abs() < 1e-12 && (disc.position[1] - 0.4).abs() < 1e-12);
    /// assert_eq!(disc.velocity, [-1.0, 1.0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn lees_edwards_offset(&self) -> Option<f64> {
        crate::geometry::Geometry::new(&self.config)
            .at_time(self.time)
            .slide()
            .map(|slide| slide.offset)
    }
    /// The storage index of particle `id` now: where its values sit in
    /// [`World::particles`]' arrays until the next step may reorder them.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// let id = world.add_particle(Particle::new([3.0, 4.0], [0.0, 0.0], 0.5))?;
    /// let i = world.index_of(id).unwrap();
    /// assert_eq!(world.particles().x()[i], 3.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn index_of(&self, id: ParticleId) -> Option<usize> {
        self.index_map().get(id)
    }

    pub(super) fn index_map(&self) -> &IndexMap {
        self.index_of
            .get_or_init(|| IndexMap::new(&self.particles.id, self.next_id))
    }

    /// Every disc as `(id, storage index)`, in id order (ids have gaps where a sink or
    /// `remove_particles` took discs).
    ///
    /// ```
    /// use bounce::{Config, Particle, ParticleId, World};
    /// let mut world = World::new(Config::default())?;
    /// for x in [0.0, 5.0, 10.0] {
    ///     world.add_particle(Particle::new([x, 0.0], [0.0, 0.0], 0.5))?;
    /// }
    /// world.remove_particles(&[ParticleId(1)]);
    /// let ids: Vec<u32> = world.in_id_order().iter().map(|(id, _)| id.0).collect();
    /// assert_eq!(ids, [0, 2]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn in_id_order(&self) -> Vec<(ParticleId, usize)> {
        self.index_map().in_order()
    }

    /// Each disc's collisions with other discs so far, with
    /// [`crate::Config::collision_counts`] (`None` when it is off): the count of id `k` at
    /// index `k`, one entry for every id given (removed discs keep theirs). A collision is an
    /// impact, as [`crate::StepStats::collisions`] counts them, and counts once for each of
    /// its two discs, so the counts add up to twice the collisions.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    ///
    /// let config = Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [20.0, 10.0]),
    ///     collision_counts: true,
    ///     ..Config::default()
    /// };
    /// let mut world = World::new(config).unwrap();
    /// world.add_particle(Particle::new([5.0, 5.0], [1.0, 0.0], 1.0)).unwrap();
    /// world.add_particle(Particle::new([9.0, 5.0], [-1.0, 0.0], 1.0)).unwrap();
    /// world.add_particle(Particle::new([15.0, 5.0], [0.0, 0.0], 1.0)).unwrap();
    /// for _ in 0..200 {
    ///     world.step(0.01).unwrap();
    /// }
    /// // Discs 0 and 1 met head-on at t = 1 and parted; disc 2 was left alone.
    /// assert_eq!(world.collision_counts().unwrap(), vec![1, 1, 0]);
    /// ```
    pub fn collision_counts(&self) -> Option<Vec<u64>> {
        self.config.collision_counts.then(|| {
            let mut counts = self.collision_counts.clone();
            counts.resize(self.next_id as usize, 0);
            counts
        })
    }

    /// Particle `id` as it is now (`None` for an id never given or removed).
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// let id = world.add_particle(Particle::new([0.0, 0.0], [2.0, 0.0], 0.5))?;
    /// world.step(0.5)?;
    /// assert_eq!(world.particle(id).unwrap().position, [1.0, 0.0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn particle(&self, id: ParticleId) -> Option<Particle> {
        let mut p = self.particles.get(self.index_of(id)?)?;
        if self.config.mass_model != crate::MassModel::PerParticle {
            p.mass = Some(self.config.mass_model.mass(p.radius, 0.0));
        }
        Some(p)
    }

    /// Every particle in id order.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 0.5))?;
    /// world.add_particle(Particle::new([5.0, 0.0], [0.0, 0.0], 1.5))?;
    /// let radii: Vec<f64> = world.particles_by_id().iter().map(|(_, p)| p.radius).collect();
    /// assert_eq!(radii, [0.5, 1.5]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn particles_by_id(&self) -> Vec<(ParticleId, Particle)> {
        let mut ids: Vec<ParticleId> = self.particles.id.clone();
        ids.sort_unstable();
        ids.into_iter()
            .filter_map(|id| Some((id, self.particle(id)?)))
            .collect()
    }

    /// Sets the tag of particle `id` ([`crate::Particle::tag`]); fails on an unknown id.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// let id = world.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 0.5).with_tag(7))?;
    /// world.step(0.1)?;
    /// assert_eq!(world.particle(id).unwrap().tag, 7);
    /// world.set_tag(id, 9)?;
    /// assert_eq!(world.particle(id).unwrap().tag, 9);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_tag(&mut self, id: ParticleId, tag: u64) -> Result<(), ParticleError> {
        let i = self.index_of(id).ok_or(ParticleError::UnknownId(id))?;
        self.particles.set_tag(i, tag);
        Ok(())
    }

    /// Sets the velocity of particle `id` (for interactive tools). Fails on an unknown id or a
    /// non-finite velocity.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// let id = world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 0.5))?;
    /// world.set_velocity(id, [0.0, 3.0])?;
    /// world.step(1.0)?;
    /// assert_eq!(world.particle(id).unwrap().position, [0.0, 3.0]);
    /// assert!(world.set_velocity(id, [f64::NAN, 0.0]).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_velocity(
        &mut self,
        id: ParticleId,
        velocity: [f64; 2],
    ) -> Result<(), ParticleError> {
        if !velocity.iter().all(|v| v.is_finite()) {
            return Err(ParticleError::NonFiniteVelocity(velocity));
        }
        let i = self.index_of(id).ok_or(ParticleError::UnknownId(id))?;
        self.particles.vx[i] = velocity[0];
        self.particles.vy[i] = velocity[1];
        self.refresh_stats();
        Ok(())
    }

    /// Moves every disc, `positions[k]` for id `k`, all or nothing: on the first position
    /// the boundary does not admit (or not finite), returns its index and the error, and the
    /// world is unchanged. Velocities and periodic image counts are kept.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
    ///     ..Config::default()
    /// })?;
    /// world.add_particle(Particle::new([1.0, 1.0], [0.0, 0.0], 0.5))?;
    /// world.add_particle(Particle::new([3.0, 1.0], [0.0, 0.0], 0.5))?;
    /// world.set_positions(&[[5.0, 5.0], [7.0, 5.0]]).unwrap();
    /// // The second is outside the box: refused by its index, nothing moved.
    /// assert_eq!(world.set_positions(&[[2.0, 2.0], [20.0, 5.0]]).unwrap_err().0, 1);
    /// assert_eq!(world.particles_by_id()[0].1.position, [5.0, 5.0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_positions(&mut self, positions: &[[f64; 2]]) -> Result<(), (usize, ParticleError)> {
        self.set_each(positions, |particle, position| particle.position = position)?;
        self.broadphase.invalidate();
        Ok(())
    }

    /// Sets every disc's velocity, `velocities[k]` for id `k`, all or nothing: on the first
    /// invalid one returns its index and the error, and the world is unchanged.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 0.5))?;
    /// world.add_particle(Particle::new([5.0, 0.0], [0.0, 0.0], 0.5))?;
    /// world.set_velocities(&[[1.0, 0.0], [0.0, -1.0]]).unwrap();
    /// assert_eq!(world.particles_by_id()[1].1.velocity, [0.0, -1.0]);
    /// assert_eq!(world.set_velocities(&[[0.0, 0.0], [f64::INFINITY, 0.0]]).unwrap_err().0, 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_velocities(
        &mut self,
        velocities: &[[f64; 2]],
    ) -> Result<(), (usize, ParticleError)> {
        self.set_each(velocities, |particle, velocity| {
            particle.velocity = velocity
        })
    }

    /// Validates `values` (one per id, in id order) applied by `apply`, then writes them.
    pub(super) fn set_each(
        &mut self,
        values: &[[f64; 2]],
        apply: impl Fn(&mut Particle, [f64; 2]),
    ) -> Result<(), (usize, ParticleError)> {
        if values.len() != self.particles.len() {
            return Err((
                values.len().min(self.particles.len()),
                ParticleError::WrongCount {
                    expected: self.particles.len(),
                    given: values.len(),
                },
            ));
        }
        let mut updated = Vec::with_capacity(values.len());
        for (k, (&value, (_, i))) in values.iter().zip(self.in_id_order()).enumerate() {
            let mut particle = self.particles.get(i).expect("an index from index_of");
            apply(&mut particle, value);
            particle.validate(&self.config).map_err(|e| (k, e))?;
            updated.push((i, particle));
        }
        let p = &mut self.particles;
        for (i, particle) in updated {
            [p.x[i], p.y[i]] = particle.position;
            [p.vx[i], p.vy[i]] = particle.velocity;
        }
        self.refresh_stats();
        Ok(())
    }

    /// Adds `delta_v` to the velocity of every particle whose centre lies within `radius` of
    /// `centre` (for interactive tools: a push). Returns how many were pushed; non-finite
    /// arguments push nothing.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// let near = world.add_particle(Particle::new([1.0, 0.0], [0.0, 0.0], 0.5))?;
    /// let far = world.add_particle(Particle::new([9.0, 0.0], [0.0, 0.0], 0.5))?;
    /// assert_eq!(world.push_region([0.0, 0.0], 2.0, [0.0, 4.0]), 1);
    /// assert_eq!(world.particle(near).unwrap().velocity, [0.0, 4.0]);
    /// assert_eq!(world.particle(far).unwrap().velocity, [0.0, 0.0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn push_region(&mut self, centre: [f64; 2], radius: f64, delta_v: [f64; 2]) -> usize {
        let finite = centre.iter().chain(&delta_v).all(|v| v.is_finite()) && radius.is_finite();
        if !finite || radius < 0.0 {
            return 0;
        }
        let p = &mut self.particles;
        let mut pushed = 0;
        for i in 0..p.len() {
            let (dx, dy) = (p.x[i] - centre[0], p.y[i] - centre[1]);
            if dx * dx + dy * dy <= radius * radius {
                p.vx[i] += delta_v[0];
                p.vy[i] += delta_v[1];
                pushed += 1;
            }
        }
        self.refresh_stats();
        pushed
    }

    /// A snapshot of the discs binned for spatial queries: the discs overlapping a circle or
    /// a box, the nearest disc to a point, the first disc a ray enters. Building it bins
    /// every disc once (O(N)); each query then costs what is near it. It does not follow
    /// the world: ask again after a step.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
    ///     ..Config::default()
    /// })?;
    /// let a = world.add_particle(Particle::new([2.0, 5.0], [0.0, 0.0], 0.5))?;
    /// let b = world.add_particle(Particle::new([8.0, 5.0], [0.0, 0.0], 0.5))?;
    /// let queries = world.queries();
    /// assert_eq!(queries.in_circle([3.0, 5.0], 1.0), vec![a]);
    /// assert_eq!(queries.nearest([9.0, 9.0]).unwrap().0, b);
    /// let hit = queries.ray_cast([0.0, 5.0], [1.0, 0.0], 100.0).unwrap();
    /// assert_eq!((hit.id, hit.point, hit.normal), (a, [1.5, 5.0], [-1.0, 0.0]));
    /// assert_eq!((queries.len(), queries.is_empty()), (2, false));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn queries(&self) -> crate::query::Queries {
        crate::query::Queries::new(
            &self.particles,
            &crate::geometry::Geometry::new(&self.config).at_time(self.time),
        )
    }

    /// The particle whose disc contains `point` (the nearest centre if several overlap it).
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// let id = world.add_particle(Particle::new([2.0, 2.0], [0.0, 0.0], 1.0))?;
    /// assert_eq!(world.particle_at([2.5, 2.5]), Some(id));
    /// assert_eq!(world.particle_at([5.0, 5.0]), None);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn particle_at(&self, point: [f64; 2]) -> Option<ParticleId> {
        let p = &self.particles;
        (0..p.len())
            .filter_map(|i| {
                let d2 = (p.x[i] - point[0]).powi(2) + (p.y[i] - point[1]).powi(2);
                (d2 <= p.radius[i] * p.radius[i]).then_some((d2, p.id[i]))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, id)| id)
    }

    /// The pairs within the collision distance right now, as sorted id pairs, found the way a
    /// step finds them (grids, then the law's test). A query: neither the state nor the
    /// storage order changes.
    ///
    /// ```
    /// use bounce::{Config, Particle, ParticleId, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 1.0))?;
    /// world.add_particle(Particle::new([1.5, 0.0], [0.0, 0.0], 1.0))?; // overlapping
    /// world.add_particle(Particle::new([9.0, 0.0], [0.0, 0.0], 1.0))?;
    /// assert_eq!(world.colliding_pairs(), [(ParticleId(0), ParticleId(1))]);
    /// assert_eq!(world.colliding_pairs(), world.colliding_pairs_brute_force());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn colliding_pairs(&self) -> Vec<(ParticleId, ParticleId)> {
        let mut ctx = StepContext::new(&self.config, 0.0, &self.exec, None);
        ctx.geometry = ctx.geometry.at_time(self.time);
        let p = &self.particles;
        let mut broadphase = Broadphase::default();
        // Any margin gives a superset of the colliding pairs; the law's test decides.
        let r_min = p.radius.iter().copied().fold(f64::INFINITY, f64::min);
        let margin = 0.25 * ctx.law.interaction_diameter(r_min);
        broadphase.list_in_place([&p.x, &p.y, &p.radius], &ctx, margin);
        let mut contacts = Contacts::default();
        contacts.find(&broadphase, broadphase::BANDS, p, &ctx);
        contacts.pair_ids(p)
    }

    /// The same pairs as [`World::colliding_pairs`] by testing all N(N-1)/2 pairs: the
    /// reference the grid is tested against. O(N²): for tests and small worlds.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 1.0))?;
    /// world.add_particle(Particle::new([2.0, 0.0], [0.0, 0.0], 1.0))?; // touching counts
    /// assert_eq!(world.colliding_pairs_brute_force().len(), 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn colliding_pairs_brute_force(&self) -> Vec<(ParticleId, ParticleId)> {
        let mut ctx = StepContext::new(&self.config, 0.0, &self.exec, None);
        ctx.geometry = ctx.geometry.at_time(self.time);
        broadphase::brute_force_pairs(&self.particles, &ctx)
    }
}

/// Where each id is stored: a table by id while ids are dense, else the sorted pairs (ids
/// removed by sinks leave gaps; a table by id would grow with every id ever given).
#[derive(Debug)]
pub(super) enum IndexMap {
    Dense(Vec<u32>),
    Sparse(Vec<(ParticleId, u32)>),
}

impl IndexMap {
    fn new(ids: &[ParticleId], next_id: u32) -> IndexMap {
        if next_id as usize <= 2 * ids.len() + 1024 {
            let mut map = vec![u32::MAX; next_id as usize];
            for (i, id) in ids.iter().enumerate() {
                map[id.0 as usize] = i as u32;
            }
            IndexMap::Dense(map)
        } else {
            let mut pairs: Vec<(ParticleId, u32)> = ids
                .iter()
                .enumerate()
                .map(|(i, &id)| (id, i as u32))
                .collect();
            pairs.sort_unstable();
            IndexMap::Sparse(pairs)
        }
    }

    fn get(&self, id: ParticleId) -> Option<usize> {
        match self {
            IndexMap::Dense(map) => map
                .get(id.0 as usize)
                .filter(|&&i| i != u32::MAX)
                .map(|&i| i as usize),
            IndexMap::Sparse(pairs) => pairs
                .binary_search_by_key(&id, |&(id, _)| id)
                .ok()
                .map(|k| pairs[k].1 as usize),
        }
    }

    fn in_order(&self) -> Vec<(ParticleId, usize)> {
        match self {
            IndexMap::Dense(map) => map
                .iter()
                .enumerate()
                .filter(|&(_, &i)| i != u32::MAX)
                .map(|(id, &i)| (ParticleId(id as u32), i as usize))
                .collect(),
            IndexMap::Sparse(pairs) => pairs.iter().map(|&(id, i)| (id, i as usize)).collect(),
        }
    }
}
