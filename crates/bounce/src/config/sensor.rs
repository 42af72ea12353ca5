//! Sensors as the configuration describes them: named regions that count the discs whose
//! centres enter and leave them (the counting is `world::sensors`).

use serde::{Deserialize, Serialize};

/// Where a sensor looks. See [`Region::contains`] for an example.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Region {
    /// The rectangle `[min, max]` (edges included).
    Box {
        /// Lower-left corner.
        min: [f64; 2],
        /// Upper-right corner.
        max: [f64; 2],
    },
    /// The disc of `radius` around `centre` (edge included).
    Circle {
        /// Centre.
        centre: [f64; 2],
        /// Radius, `> 0`.
        radius: f64,
    },
}

impl Region {
    /// Whether the point `p` is inside (edges included).
    ///
    /// ```
    /// use bounce::Region;
    /// let ring = Region::Circle { centre: [0.0, 0.0], radius: 1.0 };
    /// assert!(ring.contains([0.6, 0.8]) && !ring.contains([0.8, 0.8]));
    /// ```
    #[inline]
    pub fn contains(&self, p: [f64; 2]) -> bool {
        match *self {
            Region::Box { min, max } => {
                p[0] >= min[0] && p[0] <= max[0] && p[1] >= min[1] && p[1] <= max[1]
            }
            Region::Circle { centre, radius } => {
                let d = [p[0] - centre[0], p[1] - centre[1]];
                d[0] * d[0] + d[1] * d[1] <= radius * radius
            }
        }
    }

    /// What is wrong with it, if anything: the value and what it must be.
    pub(crate) fn problem(&self) -> Option<(String, &'static str)> {
        match *self {
            Region::Box { min, max } => super::sources::region_problem(min, max),
            Region::Circle { centre, radius } => {
                let ok = centre.iter().all(|v| v.is_finite()) && radius.is_finite() && radius > 0.0;
                (!ok).then(|| {
                    (
                        format!("centre {centre:?}, radius {radius}"),
                        "a circle must be finite with a radius > 0",
                    )
                })
            }
        }
    }
}

/// A region that counts the discs whose centres enter and leave it, step by step
/// ([`crate::World::sensors`]). It does nothing to them.
///
/// ```
/// use bounce::{Config, Particle, Region, Sensor, World};
/// let gate = Sensor::new("gate", Region::Box { min: [4.0, -1.0], max: [6.0, 1.0] });
/// let mut world = World::new(Config { sensors: vec![gate], ..Config::default() })?;
/// world.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 0.1))?;
/// for _ in 0..100 {
///     world.step(0.1)?;
/// }
/// // The disc flew through once: in at x = 4, out past x = 6.
/// let count = &world.sensors()[0];
/// assert_eq!((count.entered, count.left, count.inside), (1, 1, 0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sensor {
    /// Its name (in `stats.csv`'s columns and Python's counts), unique among the sensors.
    pub name: String,
    /// Where it looks.
    pub region: Region,
}

impl Sensor {
    /// A sensor called `name` over `region`. See [`Sensor`] for an example.
    pub fn new(name: impl Into<String>, region: Region) -> Sensor {
        Sensor {
            name: name.into(),
            region,
        }
    }
}
