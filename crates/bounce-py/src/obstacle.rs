//! `bounce.Obstacle`: segments and pegs, fixed or moving, and the `polyline` and `rectangle`
//! helpers that make lists of segments; the Rust [`bounce::Obstacle`] inside.

use bounce::{Motion, Obstacle as RustObstacle, Shape};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// An obstacle discs collide with: a segment or a peg (a fixed disc), fixed, moving at a
/// prescribed ``velocity``, or driven by a constant ``force`` with a ``mass`` (a piston).
///
/// Make one with :meth:`Obstacle.segment` or :meth:`Obstacle.peg`; :func:`polyline` and
/// :func:`rectangle` make lists of segments. ``restitution=None`` uses the world's
/// coefficient of restitution, ``friction=None`` the world's friction. Pass them as ``Config(obstacles=[...])`` or to
/// :meth:`World.add_obstacles`.
#[pyclass(module = "bounce", name = "Obstacle", frozen)]
#[derive(Clone)]
pub struct Obstacle {
    pub(crate) inner: RustObstacle,
}

/// The motion the keywords ask for.
fn motion(
    velocity: Option<(f64, f64)>,
    force: Option<(f64, f64)>,
    mass: Option<f64>,
) -> PyResult<Motion> {
    let pair = |p: (f64, f64)| [p.0, p.1];
    match (force, mass) {
        (Some(force), Some(mass)) => Ok(Motion::Driven {
            force: pair(force),
            mass,
            velocity: velocity.map_or([0.0, 0.0], pair),
        }),
        (None, None) => Ok(velocity.map_or(Motion::Fixed, |v| Motion::Velocity(pair(v)))),
        _ => Err(PyTypeError::new_err(
            "force and mass go together (a driven obstacle)",
        )),
    }
}

/// `obstacle`, checked like the Rust `Config` checks it.
fn checked(obstacle: RustObstacle) -> PyResult<Obstacle> {
    let config = bounce::Config {
        obstacles: vec![obstacle],
        ..bounce::Config::default()
    };
    config
        .validate()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(Obstacle { inner: obstacle })
}

fn with(
    obstacles: Vec<RustObstacle>,
    [restitution, friction]: [Option<f64>; 2],
    velocity: Option<(f64, f64)>,
) -> PyResult<Vec<Obstacle>> {
    let motion = motion(velocity, None, None)?;
    obstacles
        .into_iter()
        .map(|mut o| {
            o.restitution = restitution;
            o.friction = friction;
            o.motion = motion;
            checked(o)
        })
        .collect()
}

#[pymethods]
impl Obstacle {
    /// The segment from ``a`` to ``b``.
    #[staticmethod]
    #[pyo3(signature = (a, b, *, restitution = None, velocity = None, force = None, mass = None, friction = None))]
    #[allow(clippy::too_many_arguments)]
    fn segment(
        a: (f64, f64),
        b: (f64, f64),
        restitution: Option<f64>,
        velocity: Option<(f64, f64)>,
        force: Option<(f64, f64)>,
        mass: Option<f64>,
        friction: Option<f64>,
    ) -> PyResult<Obstacle> {
        checked(RustObstacle {
            shape: Shape::Segment {
                a: [a.0, a.1],
                b: [b.0, b.1],
            },
            restitution,
            motion: motion(velocity, force, mass)?,
            friction,
        })
    }

    /// A peg: a fixed (or moving) disc of ``radius`` at ``centre``.
    #[staticmethod]
    #[pyo3(signature = (centre, radius, *, restitution = None, velocity = None, force = None, mass = None, friction = None))]
    #[allow(clippy::too_many_arguments)]
    fn peg(
        centre: (f64, f64),
        radius: f64,
        restitution: Option<f64>,
        velocity: Option<(f64, f64)>,
        force: Option<(f64, f64)>,
        mass: Option<f64>,
        friction: Option<f64>,
    ) -> PyResult<Obstacle> {
        checked(RustObstacle {
            shape: Shape::Peg {
                centre: [centre.0, centre.1],
                radius,
            },
            restitution,
            motion: motion(velocity, force, mass)?,
            friction,
        })
    }

    /// ``"segment"`` or ``"peg"``.
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner.shape {
            Shape::Segment { .. } => "segment",
            Shape::Peg { .. } => "peg",
        }
    }

    /// A segment's ends ``((x0, y0), (x1, y1))``, or ``None`` for a peg.
    #[getter]
    fn ends(&self) -> Option<((f64, f64), (f64, f64))> {
        match self.inner.shape {
            Shape::Segment { a, b } => Some(((a[0], a[1]), (b[0], b[1]))),
            Shape::Peg { .. } => None,
        }
    }

    /// A peg's centre, or ``None`` for a segment.
    #[getter]
    fn centre(&self) -> Option<(f64, f64)> {
        match self.inner.shape {
            Shape::Peg { centre, .. } => Some((centre[0], centre[1])),
            Shape::Segment { .. } => None,
        }
    }

    /// A peg's radius, or ``None`` for a segment.
    #[getter]
    fn radius(&self) -> Option<f64> {
        match self.inner.shape {
            Shape::Peg { radius, .. } => Some(radius),
            Shape::Segment { .. } => None,
        }
    }

    /// Its restitution (``None``: the world's).
    #[getter]
    fn restitution(&self) -> Option<f64> {
        self.inner.restitution
    }

    /// Its friction coefficient (``None``: the world's).
    #[getter]
    fn friction(&self) -> Option<f64> {
        self.inner.friction
    }

    fn __eq__(&self, other: &Obstacle) -> bool {
        self.inner == other.inner
    }

    fn __repr__(&self) -> String {
        let mut extra = match self.inner.restitution {
            Some(e) => format!(", restitution={e}"),
            None => String::new(),
        };
        if let Some(mu) = self.inner.friction {
            extra += &format!(", friction={mu}");
        }
        let motion = match self.inner.motion {
            Motion::Fixed => String::new(),
            Motion::Velocity(v) => format!(", velocity=({}, {})", v[0], v[1]),
            Motion::Driven {
                force,
                mass,
                velocity,
            } => format!(
                ", velocity=({}, {}), force=({}, {}), mass={mass}",
                velocity[0], velocity[1], force[0], force[1]
            ),
        };
        match self.inner.shape {
            Shape::Segment { a, b } => format!(
                "Obstacle.segment(({}, {}), ({}, {}){extra}{motion})",
                a[0], a[1], b[0], b[1]
            ),
            Shape::Peg { centre, radius } => format!(
                "Obstacle.peg(({}, {}), {radius}{extra}{motion})",
                centre[0], centre[1]
            ),
        }
    }
}

/// The segments joining consecutive ``points`` (and the last back to the first when
/// ``closed``).
#[pyfunction]
#[pyo3(signature = (points, closed = false, *, restitution = None, velocity = None, friction = None))]
pub fn polyline(
    points: Vec<(f64, f64)>,
    closed: bool,
    restitution: Option<f64>,
    velocity: Option<(f64, f64)>,
    friction: Option<f64>,
) -> PyResult<Vec<Obstacle>> {
    if points.len() < 2 {
        return Err(PyValueError::new_err(format!(
            "polyline needs at least 2 points ({} given)",
            points.len()
        )));
    }
    let points: Vec<[f64; 2]> = points.iter().map(|p| [p.0, p.1]).collect();
    with(
        RustObstacle::polyline(&points, closed),
        [restitution, friction],
        velocity,
    )
}

/// The four sides of a box of ``size`` centred at ``centre``, rotated by ``angle`` radians.
#[pyfunction]
#[pyo3(signature = (centre, size, angle = 0.0, *, restitution = None, velocity = None, friction = None))]
pub fn rectangle(
    centre: (f64, f64),
    size: (f64, f64),
    angle: f64,
    restitution: Option<f64>,
    velocity: Option<(f64, f64)>,
    friction: Option<f64>,
) -> PyResult<Vec<Obstacle>> {
    with(
        RustObstacle::rectangle([centre.0, centre.1], [size.0, size.1], angle),
        [restitution, friction],
        velocity,
    )
}
