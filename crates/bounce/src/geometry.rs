//! The geometry of the world: its boundary, and everything that depends on it.
//!
//! [`Geometry`] is built once from [`Config::boundary`] and answers every question the other
//! stages have about the edge of the world:
//! - **admission**: may a disc of this radius sit here ([`Geometry::admit`])?
//! - **distances**: `p1 - p2`, as the minimum image in a periodic box ([`MinImage`]), the
//!   images above and below slid along x in a Lees–Edwards box ([`Slide`]);
//! - **the edge**: walls reflect a disc and record the impulse, a periodic box wraps it
//!   ([`reflect`], [`wrap`], applied per disc by `integrate`; [`Slide::wrap`] in a sheared
//!   box);
//! - **grids**: the region the broadphase grids cover and whether they wrap
//!   ([`Geometry::grid_extent`]), and the origin and period of the contact order grid
//!   ([`Geometry::order_axis`]).
//!
//! Adding a boundary kind means a [`crate::Boundary`] variant and its answers here.

use crate::config::{Boundary, Config};
use crate::law::{Law, MAX_INTERACTION_DIAMETER, hold};
use crate::particles::{Particle, ParticleError};

/// The boundary in the form the stages use, with the derived quantities precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Geometry {
    /// No edge.
    Open,
    /// Reflecting walls around `[min, max]`.
    Walls {
        min: [f64; 2],
        max: [f64; 2],
        /// The walls' restitution.
        restitution: f64,
    },
    /// A periodic box `[min, min + size)`; a Lees–Edwards box when its images slide.
    Periodic {
        min: [f64; 2],
        max: [f64; 2],
        size: [f64; 2],
        slide: Option<Slide>,
    },
}

/// The sliding images of a Lees–Edwards box at one moment: the box above stands `offset`
/// along x and moves at `speed` (`γ̇ L_y`); the box below, the opposite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Slide {
    /// `γ̇ L_y`.
    pub speed: f64,
    /// `δ = γ̇ L_y t`, brought into `[-L_x / 2, L_x / 2)`.
    pub offset: f64,
    /// The time `t` the offset is for.
    pub time: f64,
}

impl Slide {
    /// How far the copies across the top and bottom have slid past each other since time
    /// `since` (never negative).
    pub(crate) fn drift_since(&self, since: f64) -> f64 {
        (self.speed * (self.time - since)).abs()
    }

    /// The offset at time `t` in a box `width` wide: `speed t` modulo the width, centred.
    pub(crate) fn offset_at(speed: f64, t: f64, width: f64) -> f64 {
        let d = (speed * t).rem_euclid(width);
        if d >= 0.5 * width { d - width } else { d }
    }

    /// Brings a disc back into the box `[min, min + size)`: through the top or bottom it
    /// re-enters the other side moved back by the offset, its x velocity less the images'
    /// speed (per box crossed); then x wraps. Returns the boxes crossed along each axis.
    #[inline(always)]
    pub(crate) fn wrap(
        &self,
        [x, y, vx]: [&mut f64; 3],
        min: [f64; 2],
        size: [f64; 2],
    ) -> [i32; 2] {
        let up = wrap(y, min[1], size[1]);
        if up != 0 {
            *x -= up as f64 * self.offset;
            *vx -= up as f64 * self.speed;
        }
        [wrap(x, min[0], size[0]), up]
    }
}

/// How a grid covers the world along both axes: from `origin`, `width` wide, wrapping or not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Extent {
    pub origin: [f64; 2],
    pub width: [f64; 2],
    pub wrap: bool,
}

/// One axis of the contact order grid: where cells start, and the period when it wraps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OrderAxisFrame {
    pub origin: f64,
    pub period: Option<f64>,
}

impl Geometry {
    pub(crate) fn new(config: &Config) -> Self {
        match config.boundary {
            Boundary::Open => Geometry::Open,
            Boundary::Walls { min, max, .. } => Geometry::Walls {
                min,
                max,
                restitution: config.wall_restitution(),
            },
            Boundary::Periodic { min, max } => Geometry::Periodic {
                min,
                max,
                size: [max[0] - min[0], max[1] - min[1]],
                slide: None,
            },
            Boundary::LeesEdwards {
                min,
                max,
                shear_rate,
            } => Geometry::Periodic {
                min,
                max,
                size: [max[0] - min[0], max[1] - min[1]],
                slide: Some(Slide {
                    speed: shear_rate * (max[1] - min[1]),
                    offset: 0.0,
                    time: 0.0,
                }),
            },
        }
    }

    /// This geometry at time `t`: a Lees–Edwards box's images at their offset then.
    pub(crate) fn at_time(mut self, t: f64) -> Geometry {
        if let Geometry::Periodic {
            size,
            slide: Some(slide),
            ..
        } = &mut self
        {
            slide.offset = Slide::offset_at(slide.speed, t, size[0]);
            slide.time = t;
        }
        self
    }

    /// Where a centre pushed past a Lees–Edwards box's top or bottom has its image in the box
    /// (x slid with it, so grids see it among its neighbours); unchanged in any other
    /// geometry.
    pub(crate) fn slid_into_box(&self, [mut x, mut y]: [f64; 2]) -> [f64; 2] {
        if let Geometry::Periodic {
            min,
            size,
            slide: Some(slide),
            ..
        } = *self
        {
            slide.wrap([&mut x, &mut y, &mut 0.0], min, size);
        }
        [x, y]
    }

    /// The sliding images, in a Lees–Edwards box.
    pub(crate) fn slide(&self) -> Option<Slide> {
        match *self {
            Geometry::Periodic { slide, .. } => slide,
            _ => None,
        }
    }

    /// The box, when there is one.
    pub(crate) fn bounds(&self) -> Option<([f64; 2], [f64; 2])> {
        match *self {
            Geometry::Open => None,
            Geometry::Walls { min, max, .. } | Geometry::Periodic { min, max, .. } => {
                Some((min, max))
            }
        }
    }

    /// The period along `axis`, in a periodic box.
    pub(crate) fn period(&self, axis: usize) -> Option<f64> {
        match *self {
            Geometry::Periodic { size, .. } => Some(size[axis]),
            _ => None,
        }
    }

    /// Whether positions wrap.
    pub(crate) fn is_periodic(&self) -> bool {
        matches!(self, Geometry::Periodic { .. })
    }

    /// The minimum-image difference for this geometry.
    #[inline]
    pub(crate) fn min_image(&self) -> MinImage {
        match *self {
            Geometry::Periodic { size, slide, .. } => MinImage {
                size: Some(size),
                slide: slide.map_or([0.0; 2], |s| [s.offset, s.speed]),
            },
            _ => MinImage {
                size: None,
                slide: [0.0; 2],
            },
        }
    }

    /// Checks that a disc of radius `r` may be placed at `position`: inside the box, and
    /// small enough for it.
    pub(crate) fn admit(&self, position: [f64; 2], r: f64, law: &Law) -> Result<(), ParticleError> {
        let [x, y] = position;
        let outside = match *self {
            Geometry::Open => false,
            // A periodic box is half-open: `max` is the same place as `min`.
            Geometry::Periodic { min, max, .. } => {
                !(x >= min[0] && x < max[0] && y >= min[1] && y < max[1])
            }
            Geometry::Walls { min, max, .. } => {
                !(x >= min[0] && x <= max[0] && y >= min[1] && y <= max[1])
            }
        };
        if outside {
            let (min, max) = self.bounds().expect("a box");
            return Err(ParticleError::OutsideBox { position, min, max });
        }
        self.fits_size(r, law)
    }

    /// Checks that a saved centre is where a step can leave one: inside a walled box (the
    /// walls hold a disc a radius inside them), within `slack` of a periodic box (a push may
    /// leave a disc past the edge until the next integration wraps it).
    pub(crate) fn holds(&self, position: [f64; 2], slack: f64) -> Result<(), ParticleError> {
        let Some((min, max)) = self.bounds() else {
            return Ok(());
        };
        let slack = if self.is_periodic() { slack } else { 0.0 };
        let inside = (0..2).all(|k| position[k] >= min[k] - slack && position[k] <= max[k] + slack);
        if inside {
            Ok(())
        } else {
            Err(ParticleError::OutsideBox { position, min, max })
        }
    }

    /// Checks that a disc of radius `r` fits the box (walls: its diameter fits between them;
    /// periodic: its interaction diameter is at most half a side, so only one image of a
    /// neighbour is within reach).
    pub(crate) fn fits_size(&self, r: f64, law: &Law) -> Result<(), ParticleError> {
        let reach = law.interaction_diameter(r);
        if reach.is_nan() || reach > MAX_INTERACTION_DIAMETER {
            return Err(ParticleError::ReachTooLarge { radius: r, reach });
        }
        let Some((min, max)) = self.bounds() else {
            return Ok(());
        };
        let size = [max[0] - min[0], max[1] - min[1]];
        let smaller_side = size[0].min(size[1]);
        match self {
            Geometry::Walls { .. } if 2.0 * r > smaller_side => Err(ParticleError::TooLarge {
                radius: r,
                size,
                rule: "the diameter must fit between the walls",
            }),
            Geometry::Periodic { .. } if law.interaction_diameter(r) > smaller_side / 2.0 => {
                Err(ParticleError::TooLarge {
                    radius: r,
                    size,
                    rule: "2 r collision_radius_scale must be <= half of each side (minimum image)",
                })
            }
            _ => Ok(()),
        }
    }

    /// Keeps walls holding after a push: a centre closer to a wall than its radius `r` is
    /// put back at that distance (velocities are left to the next integration, which
    /// reflects a disc still moving outwards). Nothing happens in other geometries.
    #[inline(always)]
    pub(crate) fn hold(&self, x: &mut f64, y: &mut f64, r: f64) {
        if let Geometry::Walls { min, max, .. } = *self {
            *x = hold(*x, r, min[0], max[0]);
            *y = hold(*y, r, min[1], max[1]);
        }
    }

    /// The area the centres of discs of mean radius `r` move in: a periodic box's area,
    /// the box less a radius at each wall; `None` in an open world.
    pub(crate) fn area(&self, r: f64) -> Option<f64> {
        match *self {
            Geometry::Open => None,
            Geometry::Periodic { size, .. } => Some(size[0] * size[1]),
            Geometry::Walls { min, max, .. } => {
                Some((max[0] - min[0] - 2.0 * r) * (max[1] - min[1] - 2.0 * r))
            }
        }
    }

    /// The region a broadphase grid covers and whether it wraps; `None` in an open world,
    /// where the grid follows the discs.
    pub(crate) fn grid_extent(&self) -> Option<Extent> {
        match *self {
            Geometry::Open => None,
            Geometry::Walls { min, max, .. } => Some(Extent {
                origin: min,
                width: [max[0] - min[0], max[1] - min[1]],
                wrap: false,
            }),
            Geometry::Periodic { min, max, .. } => Some(Extent {
                origin: min,
                width: [max[0] - min[0], max[1] - min[1]],
                wrap: true,
            }),
        }
    }

    /// Where the contact order grid's cells start along `axis`, and its period in a
    /// periodic box. Fixed by the configuration alone, so the order never depends on where
    /// the discs happen to be.
    pub(crate) fn order_axis(&self, axis: usize) -> OrderAxisFrame {
        match *self {
            Geometry::Periodic { min, max, .. } => OrderAxisFrame {
                origin: min[axis],
                period: Some(max[axis] - min[axis]),
            },
            Geometry::Walls { min, .. } => OrderAxisFrame {
                origin: min[axis],
                period: None,
            },
            Geometry::Open => OrderAxisFrame {
                origin: 0.0,
                period: None,
            },
        }
    }
}

/// Admission is the geometry's: a particle is checked against the box it would enter.
impl Particle {
    /// Checks this particle against a (valid) config: finite values, and a place and size
    /// the boundary admits.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle};
    /// let config = Config { boundary: Boundary::walls([0.0, 0.0], [4.0, 4.0]), ..Config::default() };
    /// assert!(Particle::new([2.0, 2.0], [0.0, 0.0], 1.0).validate(&config).is_ok());
    /// assert!(Particle::new([5.0, 2.0], [0.0, 0.0], 1.0).validate(&config).is_err()); // outside
    /// assert!(Particle::new([2.0, 2.0], [0.0, 0.0], 3.0).validate(&config).is_err()); // too large
    /// ```
    pub fn validate(&self, config: &Config) -> Result<(), ParticleError> {
        self.validate_values()?;
        let law = Law::new(config);
        self.check_energy(&law, config.inertia_factor)?;
        Geometry::new(config).admit(self.position, self.radius, &law)
    }

    /// Checks that the kinetic energy under the law's mass model is finite, and the energy of
    /// its spin, `½ I ω²` with `I = inertia_factor m r²`.
    pub(crate) fn check_energy(&self, law: &Law, inertia_factor: f64) -> Result<(), ParticleError> {
        let mass = law.mass(
            self.radius,
            self.mass
                .unwrap_or(std::f64::consts::PI * self.radius * self.radius),
        );
        let [vx, vy] = self.velocity;
        if !(0.5 * mass * (vx * vx + vy * vy)).is_finite() {
            return Err(ParticleError::EnergyOverflow {
                velocity: self.velocity,
                mass,
            });
        }
        let inertia = inertia_factor * mass * self.radius * self.radius;
        let w = self.angular_velocity;
        if w != 0.0 && !(0.5 * inertia * w * w).is_finite() {
            return Err(ParticleError::SpinEnergyOverflow {
                angular_velocity: w,
                inertia,
            });
        }
        Ok(())
    }
}

/// `p1 - p2`, as the minimum image when the box is periodic, with the images above and below
/// slid along x in a Lees–Edwards box.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MinImage {
    /// The box's size, when periodic.
    size: Option<[f64; 2]>,
    /// The offset of the images above and their speed (zero unless sheared).
    slide: [f64; 2],
}

impl MinImage {
    /// The minimum image of an unsheared periodic box of `size`.
    #[cfg(test)]
    pub(crate) fn periodic(size: [f64; 2]) -> Self {
        MinImage {
            size: Some(size),
            slide: [0.0; 2],
        }
    }

    /// Whether positions wrap.
    #[inline]
    pub(crate) fn is_periodic(&self) -> bool {
        self.size.is_some()
    }

    /// `p1 - p2`, as the minimum image in a periodic box: across the top or bottom first
    /// (which slides x by the offset in a Lees–Edwards box, kept within half a width), then
    /// across the sides. Positions may sit slightly outside the box after an overlap push;
    /// one correction per axis still finds the nearest image.
    #[inline]
    pub(crate) fn diff(&self, x1: f64, y1: f64, x2: f64, y2: f64) -> [f64; 2] {
        let (mut dx, mut dy) = (x1 - x2, y1 - y2);
        if let Some([lx, ly]) = self.size {
            let [offset, _] = self.slide;
            if dy > 0.5 * ly {
                dy -= ly;
                dx -= offset;
            } else if dy < -0.5 * ly {
                dy += ly;
                dx += offset;
            }
            if dx > 0.5 * lx {
                dx -= lx;
            } else if dx < -0.5 * lx {
                dx += lx;
            }
        }
        [dx, dy]
    }

    /// What to add to the x velocity of the disc at height `y2` to see it from the disc at
    /// `y1` (as [`MinImage::diff`] places it): the images' speed when the nearest image of
    /// the second is across the top or bottom of a Lees–Edwards box, else 0.
    #[inline]
    pub(crate) fn image_velocity(&self, y1: f64, y2: f64) -> f64 {
        let (Some([_, ly]), [_, speed]) = (self.size, self.slide) else {
            return 0.0;
        };
        let dy = y1 - y2;
        if dy > 0.5 * ly {
            speed
        } else if dy < -0.5 * ly {
            -speed
        } else {
            0.0
        }
    }
}

/// One axis of the periodic box: back into `[lo, lo + size)`. Returns the box widths the
/// disc was moved back by (its change of image: +1 when it left through the high side).
#[inline]
pub(crate) fn wrap(x: &mut f64, lo: f64, size: f64) -> i32 {
    let mut crossed = 0i32;
    if *x < lo {
        *x += size;
        crossed = -1;
    } else if *x >= lo + size {
        *x -= size;
        crossed = 1;
    }
    // A disc faster than a box width per substep: reduce fully.
    if !(*x >= lo && *x < lo + size) {
        let widths = ((*x - lo) / size).floor();
        *x = lo + (*x - lo).rem_euclid(size);
        if *x >= lo + size {
            *x = lo;
        }
        // Image counts wrap past ±2³¹ box widths (only a disc crossing the box billions of
        // times reaches that), the same in every build.
        crossed = crossed.wrapping_add(widths.clamp(i32::MIN as f64, i32::MAX as f64) as i32);
    }
    crossed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapping_lands_in_the_half_open_box() {
        for (x0, want, crossed) in [
            (-0.5, 9.5, -1),
            (10.0, 0.0, 1),
            (10.5, 0.5, 1),
            (35.0, 5.0, 3),
            (-25.0, 5.0, -3),
            (4.0, 4.0, 0),
        ] {
            let mut x = x0;
            assert_eq!(wrap(&mut x, 0.0, 10.0), crossed, "from {x0}");
            assert_eq!(x, want, "from {x0}");
        }
        let mut tiny = -1e-17;
        wrap(&mut tiny, 0.0, 10.0);
        assert!((0.0..10.0).contains(&tiny));
        // Far past i32's box widths: the count saturates without overflowing.
        let mut far = 1e300;
        wrap(&mut far, 0.0, 10.0);
        assert!((0.0..10.0).contains(&far));
    }

    #[test]
    fn minimum_image_picks_the_nearest_copy() {
        let p = MinImage::periodic([10.0, 10.0]);
        assert_eq!(p.diff(9.5, 0.5, 0.5, 9.5), [-1.0, 1.0]);
        assert_eq!(p.diff(3.0, 3.0, 1.0, 1.0), [2.0, 2.0]);
        // Pushed slightly outside the box.
        assert_eq!(p.diff(10.25, 5.0, 0.25, 5.0), [0.0, 0.0]);
    }

    #[test]
    fn admission_follows_the_box() {
        let law = Law::new(&Config::default());
        let walls = Geometry::new(&Config {
            boundary: Boundary::walls([0.0, 0.0], [10.0, 4.0]),
            ..Config::default()
        });
        assert!(walls.admit([10.0, 4.0], 1.0, &law).is_ok());
        assert!(walls.admit([10.1, 4.0], 1.0, &law).is_err());
        assert!(walls.admit([5.0, 2.0], 2.1, &law).is_err());
        let periodic = Geometry::new(&Config {
            boundary: Boundary::periodic([0.0, 0.0], [10.0, 4.0]),
            ..Config::default()
        });
        // Half-open, and the interaction diameter at most half a side.
        assert!(periodic.admit([10.0, 2.0], 0.5, &law).is_err());
        assert!(periodic.admit([5.0, 2.0], 1.0, &law).is_ok());
        assert!(periodic.admit([5.0, 2.0], 1.01, &law).is_err());
        assert!(Geometry::Open.admit([1e300, -1e300], 1e100, &law).is_ok());
        // A collision distance whose square overflows is refused in any world.
        assert!(matches!(
            Geometry::Open.admit([0.0, 0.0], 1e300, &law),
            Err(ParticleError::ReachTooLarge { .. })
        ));
    }
}
