//! Reading the particles: the struct-of-arrays slices in storage order, one particle by
//! its index, and whether the discs carry rotation.

use super::{Particle, ParticleId, Particles};

impl Particles {
    /// Number of particles.
    ///
    /// See [`Particles`] for an example.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// `true` when there are no particles.
    ///
    /// See [`Particles`] for an example.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Stable ids, in storage order.
    ///
    /// See [`Particles`] for an example.
    pub fn ids(&self) -> &[ParticleId] {
        &self.id
    }

    /// Centre x coordinates.
    ///
    /// See [`Particles`] for an example.
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// Centre y coordinates.
    ///
    /// See [`Particles`] for an example.
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// Velocity x components.
    ///
    /// See [`Particles`] for an example.
    pub fn vx(&self) -> &[f64] {
        &self.vx
    }

    /// Velocity y components.
    ///
    /// See [`Particles`] for an example.
    pub fn vy(&self) -> &[f64] {
        &self.vy
    }

    /// Radii.
    ///
    /// See [`Particles`] for an example.
    pub fn radius(&self) -> &[f64] {
        &self.radius
    }

    /// Per-particle masses (π r² where none was given); see [`crate::MassModel::PerParticle`].
    ///
    /// See [`Particles`] for an example.
    pub fn per_particle_mass(&self) -> &[f64] {
        &self.mass
    }

    /// Periodic image counts `[ix, iy]`: the unwrapped position (the path a disc really
    /// travelled, for diffusion) is `position + image × box size`. Zero outside a periodic box.
    ///
    /// See [`Particles`] for an example.
    pub fn image(&self) -> &[[i32; 2]] {
        &self.image
    }

    /// Angular velocities (counter-clockwise), or empty when no disc turns (see
    /// [`Particles::turns`]).
    ///
    /// See [`Particles`] for an example.
    pub fn angular_velocity(&self) -> &[f64] {
        &self.omega
    }

    /// Orientations in `[0, 2π)`, or empty when no disc turns.
    ///
    /// See [`Particles`] for an example.
    pub fn orientation(&self) -> &[f64] {
        &self.theta
    }

    /// The discs' tags ([`Particle::tag`]), or empty while every tag is 0.
    ///
    /// See [`Particles`] for an example.
    pub fn tag(&self) -> &[u64] {
        &self.tag
    }

    /// Disc `i`'s tag.
    ///
    /// See [`Particles`] for an example.
    pub fn tag_of(&self, i: usize) -> u64 {
        self.tag.get(i).copied().unwrap_or(0)
    }

    /// Whether the discs carry rotation state: some disc was given an angular velocity or
    /// an orientation, or the configuration is rough. Smooth discs that never turned have
    /// none, and their step never reads it.
    ///
    /// See [`Particles`] for an example.
    pub fn turns(&self) -> bool {
        self.turning
    }

    /// The particle at storage index `i`.
    ///
    /// See [`Particles`] for an example.
    pub fn get(&self, i: usize) -> Option<Particle> {
        (i < self.len()).then(|| Particle {
            position: [self.x[i], self.y[i]],
            velocity: [self.vx[i], self.vy[i]],
            radius: self.radius[i],
            mass: Some(self.mass[i]),
            angular_velocity: self.omega.get(i).copied().unwrap_or(0.0),
            orientation: self.theta.get(i).copied().unwrap_or(0.0),
            tag: self.tag_of(i),
        })
    }
}
