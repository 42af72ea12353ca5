//! Obstacles as the configuration describes them: a shape, a restitution, a friction and a motion, and
//! a moving obstacle's saved state. What a disc does at an obstacle is the law's
//! (`law::obstacle`); the step's form of the obstacles is `obstacles`.

use serde::{Deserialize, Serialize};

/// The shape of an obstacle.
///
/// ```
/// use bounce::{Motion, Obstacle, Shape};
/// let board = Obstacle::peg([5.0, 5.0], 1.0).with_restitution(0.5).with_friction(0.2);
/// assert_eq!(board.shape, Shape::Peg { centre: [5.0, 5.0], radius: 1.0 });
/// assert_eq!((board.restitution, board.friction), (Some(0.5), Some(0.2)));
/// // A closed triangle is three segments; a box four, here turned a quarter turn.
/// assert_eq!(Obstacle::polyline(&[[0.0, 0.0], [4.0, 0.0], [0.0, 3.0]], true).len(), 3);
/// let sides = Obstacle::rectangle([0.0, 0.0], [4.0, 2.0], std::f64::consts::FRAC_PI_2);
/// assert_eq!(sides.len(), 4);
/// // A piston: a segment moving up; `shifted` is where it is after moving by an offset.
/// let piston = Obstacle::segment([0.0, 0.0], [10.0, 0.0]).moving(Motion::Velocity([0.0, 1.0]));
/// assert_eq!(piston.motion, Motion::Velocity([0.0, 1.0]));
/// assert_eq!(piston.shifted([0.0, 2.0]), Shape::Segment { a: [0.0, 2.0], b: [10.0, 2.0] });
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// The segment from `a` to `b` (a wall at any angle; polylines and boxes are made of
    /// segments).
    Segment {
        /// One end.
        a: [f64; 2],
        /// The other end.
        b: [f64; 2],
    },
    /// A fixed disc (a peg).
    Peg {
        /// Centre.
        centre: [f64; 2],
        /// Radius, `> 0`.
        radius: f64,
    },
}

/// How an obstacle moves. See [`Shape`] and [`crate::World::obstacle_states`] for examples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Motion {
    /// It does not move (the default).
    #[default]
    Fixed,
    /// At a prescribed constant velocity.
    Velocity([f64; 2]),
    /// A body of `mass` under a constant external `force`, starting at `velocity`, moved by
    /// the discs' impulses too (a piston under a weight).
    Driven {
        /// The external force.
        force: [f64; 2],
        /// The obstacle's mass, `> 0`.
        mass: f64,
        /// Its velocity at the start.
        velocity: [f64; 2],
    },
}

/// An obstacle: a shape, its restitution and friction, and how it moves.
///
/// ```
/// use bounce::{Boundary, Config, Obstacle, Particle, World};
/// // A floor at 45 degrees: a disc falling straight down leaves sideways.
/// let config = Config {
///     obstacles: vec![Obstacle::segment([-10.0, 10.0], [10.0, -10.0])],
///     ..Config::default()
/// };
/// let mut world = World::new(config)?;
/// world.add_particle(Particle::new([2.0, 3.0], [0.0, -4.0], 0.5))?;
/// for _ in 0..200 {
///     world.step(0.01)?;
/// }
/// let v = world.particle(bounce::ParticleId(0)).unwrap().velocity;
/// assert!(v[0] > 3.9 && v[1].abs() < 1e-9, "{v:?}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Obstacle {
    /// Where it is (at time 0, for a moving one).
    pub shape: Shape,
    /// Restitution of discs hitting it, in `[0, 1]`. `None` (the default) uses the world's
    /// coefficient of restitution.
    pub restitution: Option<f64>,
    /// Fixed (the default) or moving.
    pub motion: Motion,
    /// Coulomb friction coefficient of discs against it, `>= 0` (see
    /// [`crate::Config::friction`]). `None` (the default) uses the world's friction.
    #[serde(default)]
    pub friction: Option<f64>,
}

impl Obstacle {
    /// A fixed segment from `a` to `b`. See [`Shape`] for an example.
    pub fn segment(a: [f64; 2], b: [f64; 2]) -> Obstacle {
        Obstacle::from(Shape::Segment { a, b })
    }

    /// A fixed peg. See [`Shape`] for an example.
    pub fn peg(centre: [f64; 2], radius: f64) -> Obstacle {
        Obstacle::from(Shape::Peg { centre, radius })
    }

    /// The segments joining consecutive `points` (closed: back to the first as well). See [`Shape`]
    /// for an example.
    pub fn polyline(points: &[[f64; 2]], closed: bool) -> Vec<Obstacle> {
        let mut out: Vec<Obstacle> = points
            .windows(2)
            .map(|w| Obstacle::segment(w[0], w[1]))
            .collect();
        if closed && points.len() > 2 {
            out.push(Obstacle::segment(points[points.len() - 1], points[0]));
        }
        out
    }

    /// The four sides of a box of `size` centred at `centre`, rotated by `angle` radians
    /// (counter-clockwise). See [`Shape`] for an example.
    pub fn rectangle(centre: [f64; 2], size: [f64; 2], angle: f64) -> Vec<Obstacle> {
        let (s, c) = (libm::sin(angle), libm::cos(angle));
        let [hx, hy] = [size[0] / 2.0, size[1] / 2.0];
        let corner = |x: f64, y: f64| [centre[0] + c * x - s * y, centre[1] + s * x + c * y];
        let corners = [
            corner(-hx, -hy),
            corner(hx, -hy),
            corner(hx, hy),
            corner(-hx, hy),
        ];
        Obstacle::polyline(&corners, true)
    }

    /// This obstacle with its own restitution. See [`Shape`] for an example.
    pub fn with_restitution(self, restitution: f64) -> Obstacle {
        Obstacle {
            restitution: Some(restitution),
            ..self
        }
    }

    /// This obstacle with its own friction coefficient. See [`Shape`] for an example.
    pub fn with_friction(self, friction: f64) -> Obstacle {
        Obstacle {
            friction: Some(friction),
            ..self
        }
    }

    /// This obstacle moving as `motion` says. See [`Shape`] for an example.
    pub fn moving(self, motion: Motion) -> Obstacle {
        Obstacle { motion, ..self }
    }

    /// The shape moved by `offset`. See [`Shape`] for an example.
    pub fn shifted(&self, offset: [f64; 2]) -> Shape {
        let add = |p: [f64; 2]| [p[0] + offset[0], p[1] + offset[1]];
        match self.shape {
            Shape::Segment { a, b } => Shape::Segment {
                a: add(a),
                b: add(b),
            },
            Shape::Peg { centre, radius } => Shape::Peg {
                centre: add(centre),
                radius,
            },
        }
    }

    /// What is wrong with it, if anything: `(field, value, expected)`.
    pub(crate) fn problem(&self) -> Option<(&'static str, String, &'static str)> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        match self.shape {
            Shape::Segment { a, b } => {
                if !finite(&[a[0], a[1], b[0], b[1]]) {
                    return Some(("segment", format!("{a:?} to {b:?}"), "ends must be finite"));
                }
                if a == b {
                    return Some(("segment", format!("{a:?} to {b:?}"), "the ends must differ"));
                }
            }
            Shape::Peg { centre, radius } => {
                if !finite(&centre) {
                    return Some(("peg.centre", format!("{centre:?}"), "must be finite"));
                }
                if !(radius.is_finite() && radius > 0.0) {
                    return Some(("peg.radius", radius.to_string(), "must be finite and > 0"));
                }
            }
        }
        if let Some(e) = self.restitution
            && !(0.0..=1.0).contains(&e)
        {
            return Some(("restitution", e.to_string(), "must be in [0, 1]"));
        }
        if let Some(mu) = self.friction
            && !(mu.is_finite() && mu >= 0.0)
        {
            return Some(("friction", mu.to_string(), "must be finite and >= 0"));
        }
        match self.motion {
            Motion::Fixed => None,
            Motion::Velocity(v) if !finite(&v) => {
                Some(("velocity", format!("{v:?}"), "must be finite"))
            }
            Motion::Driven {
                force,
                mass,
                velocity,
            } => {
                if !(finite(&force) && finite(&velocity)) {
                    Some((
                        "force",
                        format!("force {force:?}, velocity {velocity:?}"),
                        "must be finite",
                    ))
                } else if !(mass.is_finite() && mass > 0.0) {
                    Some(("mass", mass.to_string(), "must be finite and > 0"))
                } else {
                    None
                }
            }
            Motion::Velocity(_) => None,
        }
    }

    /// The velocity at the start.
    pub(crate) fn initial_velocity(&self) -> [f64; 2] {
        match self.motion {
            Motion::Fixed => [0.0, 0.0],
            Motion::Velocity(v) => v,
            Motion::Driven { velocity, .. } => velocity,
        }
    }
}

impl From<Shape> for Obstacle {
    fn from(shape: Shape) -> Obstacle {
        Obstacle {
            shape,
            restitution: None,
            motion: Motion::Fixed,
            friction: None,
        }
    }
}

/// Where a moving obstacle is and how fast it goes: its offset from the configured shape
/// and its velocity. Part of the world's saved state. See
/// [`crate::World::obstacle_states`] for an example.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ObstacleState {
    /// Displacement from the configured shape.
    pub offset: [f64; 2],
    /// Current velocity.
    pub velocity: [f64; 2],
}
