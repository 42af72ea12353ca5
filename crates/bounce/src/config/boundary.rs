//! The edge of the world: [`Boundary`] (open, walls, a periodic box, a sheared periodic box)
//! as the configuration describes it, and what a Lees–Edwards box cannot be combined with.
//! The stages' form of it is `crate::geometry`.

use serde::{Deserialize, Serialize};

use super::Config;

/// The edge of the world.
///
/// ```
/// use bounce::{Boundary, Config, Particle, World};
/// let mut world = World::new(Config {
///     boundary: Boundary::periodic([0.0, 0.0], [10.0, 10.0]),
///     ..Config::default()
/// })?;
/// let id = world.add_particle(Particle::new([9.5, 5.0], [1.0, 0.0], 0.5))?;
/// world.step(1.0)?; // out through the right edge, in through the left
/// assert_eq!(world.particle(id).unwrap().position, [0.5, 5.0]);
/// assert_eq!(Boundary::walls([0.0, 0.0], [4.0, 3.0]).bounds(), Some(([0.0, 0.0], [4.0, 3.0])));
/// assert_eq!(Boundary::Open.bounds(), None);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Boundary {
    /// No boundary: particles fly freely. The grid follows the particles.
    Open,
    /// An axis-aligned box whose four walls reflect discs. A disc touches a wall when its
    /// centre is within its (unscaled) radius of it; its centre is then put back at that distance
    /// and its normal velocity, if moving into the wall, is reversed and scaled by the wall
    /// restitution. The momentum change is reported per wall in [`crate::StepStats`].
    Walls {
        /// Lower-left corner.
        min: [f64; 2],
        /// Upper-right corner.
        max: [f64; 2],
        /// Restitution of the walls, in `[0, 1]`. `None` (the default) uses the
        /// coefficient of restitution.
        #[serde(default)]
        wall_restitution: Option<f64>,
    },
    /// A periodic box: a disc leaving one side re-enters on the other, and distances use the
    /// minimum image. Discs must satisfy `2 r * collision_radius_scale <= width / 2` (and
    /// height), so that only one image of a neighbour can be within reach.
    Periodic {
        /// Lower-left corner.
        min: [f64; 2],
        /// Upper-right corner.
        max: [f64; 2],
    },
    /// A periodic box under simple shear (Lees–Edwards): the images above slide along x at
    /// `+shear_rate * height`, those below at `-shear_rate * height`, so the images stand
    /// at the offset `δ(t) = shear_rate * height * t` (modulo the width). A disc leaving
    /// through the top re-enters at the bottom moved back by `δ` along x, its x velocity
    /// less `shear_rate * height`; distances use the sliding minimum image, and a pair
    /// across the top and bottom is resolved by the seed's law with the partner's
    /// velocity seen from the first disc's image. The streaming velocity is
    /// `shear_rate * (y - centre)` along x. Discs obey the periodic box's size rule.
    LeesEdwards {
        /// Lower-left corner.
        min: [f64; 2],
        /// Upper-right corner.
        max: [f64; 2],
        /// The shear rate `γ̇ = du_x/dy` (per unit time); negative shears the other way.
        shear_rate: f64,
    },
}

impl Boundary {
    /// Walls around the box `[min, max]` with the wall restitution equal to the coefficient of
    /// restitution. See [`Boundary`] for an example.
    pub fn walls(min: [f64; 2], max: [f64; 2]) -> Self {
        Boundary::Walls {
            min,
            max,
            wall_restitution: None,
        }
    }

    /// A periodic box `[min, max)`. See [`Boundary`] for an example.
    pub fn periodic(min: [f64; 2], max: [f64; 2]) -> Self {
        Boundary::Periodic { min, max }
    }

    /// A sheared periodic box `[min, max)` (Lees–Edwards) at `shear_rate`. See
    /// [`crate::World::lees_edwards_offset`] for an example.
    pub fn lees_edwards(min: [f64; 2], max: [f64; 2], shear_rate: f64) -> Self {
        Boundary::LeesEdwards {
            min,
            max,
            shear_rate,
        }
    }

    /// The box of a walled or periodic world; `None` when open. See [`Boundary`] for an
    /// example.
    pub fn bounds(&self) -> Option<([f64; 2], [f64; 2])> {
        match *self {
            Boundary::Open => None,
            Boundary::Walls { min, max, .. }
            | Boundary::Periodic { min, max }
            | Boundary::LeesEdwards { min, max, .. } => Some((min, max)),
        }
    }

    /// The streaming velocity along x at height `y`: `shear_rate * (y - centre)` in a
    /// Lees–Edwards box (`centre` the middle of its height), `None` in any other.
    ///
    /// ```
    /// use bounce::Boundary;
    /// let sheared = Boundary::lees_edwards([0.0, 0.0], [10.0, 20.0], 0.5);
    /// assert_eq!(sheared.streaming_velocity(15.0), Some(2.5));
    /// assert_eq!(Boundary::periodic([0.0, 0.0], [10.0, 20.0]).streaming_velocity(15.0), None);
    /// ```
    pub fn streaming_velocity(&self, y: f64) -> Option<f64> {
        match *self {
            Boundary::LeesEdwards {
                min,
                max,
                shear_rate,
            } => Some(shear_rate * (y - 0.5 * (min[1] + max[1]))),
            _ => None,
        }
    }

    /// Whether this is a sheared (Lees–Edwards) box. See [`Boundary::is_periodic`] for an
    /// example.
    pub fn is_sheared(&self) -> bool {
        matches!(self, Boundary::LeesEdwards { .. })
    }

    /// Whether positions wrap (a periodic box, sheared or not).
    ///
    /// ```
    /// use bounce::Boundary;
    /// let sheared = Boundary::lees_edwards([0.0, 0.0], [10.0, 10.0], 0.1);
    /// assert!(sheared.is_periodic() && sheared.is_sheared());
    /// let plain = Boundary::periodic([0.0, 0.0], [10.0, 10.0]);
    /// assert!(plain.is_periodic() && !plain.is_sheared());
    /// assert!(!Boundary::walls([0.0, 0.0], [10.0, 10.0]).is_periodic());
    /// ```
    pub fn is_periodic(&self) -> bool {
        matches!(
            self,
            Boundary::Periodic { .. } | Boundary::LeesEdwards { .. }
        )
    }
}

impl Config {
    /// What is wrong with a Lees–Edwards boundary here, if anything: its shear rate must be
    /// finite, and obstacles cannot be sheared with the box (a segment or peg near the top
    /// would have to meet the discs across it at the sliding offset).
    pub(crate) fn lees_edwards_problem(&self) -> Option<(String, &'static str)> {
        let Boundary::LeesEdwards { shear_rate, .. } = self.boundary else {
            return None;
        };
        if !shear_rate.is_finite() {
            return Some((shear_rate.to_string(), "must be finite"));
        }
        if !self.obstacles.is_empty() {
            return Some((
                format!("{shear_rate} with {} obstacles", self.obstacles.len()),
                "a Lees–Edwards box cannot hold obstacles",
            ));
        }
        None
    }
}
