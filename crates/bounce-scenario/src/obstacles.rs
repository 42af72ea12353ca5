//! `[[obstacle]]` tables: segments, polylines, boxes, pegs and peg lattices, fixed or moving,
//! expanded into the core's [`bounce::Obstacle`]s. Each table is one *group*: its pieces
//! share a name (whose force `stats.csv` reports), a colour and a motion.

use std::ops::Range;

use bounce::{Motion, Obstacle};
use serde::Deserialize;

use crate::{Rgb, parse_colour};

/// `[[obstacle]]`: give exactly one of `segment`, `polyline`, `box`, `peg`, `pegs`.
///
/// ```toml
/// [[obstacle]]
/// polyline = [[0.0, 40.0], [38.0, 22.0]]   # a funnel side
/// restitution = 0.5
/// name = "funnel"
/// ```
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// A segment `[[x0, y0], [x1, y1]]`.
    #[serde(default)]
    pub segment: Option<[[f64; 2]; 2]>,
    /// Segments joining consecutive points `[[x, y], ...]` (at least two).
    #[serde(default)]
    pub polyline: Option<Vec<[f64; 2]>>,
    /// Join the polyline's last point back to its first; default false.
    #[serde(default)]
    pub closed: bool,
    /// A box built from four segments.
    #[serde(default, rename = "box")]
    pub rectangle: Option<BoxSpec>,
    /// A peg's centre `[x, y]` (with `radius`).
    #[serde(default)]
    pub peg: Option<[f64; 2]>,
    /// A staggered lattice of pegs (with `radius`): a Galton board.
    #[serde(default)]
    pub pegs: Option<PegsSpec>,
    /// The pegs' radius.
    #[serde(default)]
    pub radius: Option<f64>,
    /// Restitution of discs hitting it; default the world's coefficient of restitution.
    #[serde(default)]
    pub restitution: Option<f64>,
    /// Friction of discs against it; default the world's `friction`.
    #[serde(default)]
    pub friction: Option<f64>,
    /// Moves at this constant velocity (a piston driven at a prescribed speed), or starts
    /// at it when `force` is given.
    #[serde(default)]
    pub velocity: Option<[f64; 2]>,
    /// Moves as a body of `mass` under this constant force and the discs' impulses.
    #[serde(default)]
    pub force: Option<[f64; 2]>,
    /// The mass of a driven obstacle (with `force`).
    #[serde(default)]
    pub mass: Option<f64>,
    /// A name: `stats.csv` then reports the force on this group (`force_NAME_x`,
    /// `force_NAME_y`), and for a moving one its position (`NAME_x`, `NAME_y`).
    #[serde(default)]
    pub name: Option<String>,
    /// Colour in frames and the viewer (`#rrggbb` or a name); default grey.
    #[serde(default)]
    pub color: Option<String>,
}

/// `box = { centre = [x, y], size = [w, h], angle = 0 }` (angle in degrees).
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Centre.
    pub centre: [f64; 2],
    /// Width and height.
    pub size: [f64; 2],
    /// Rotation, counter-clockwise in degrees; default 0.
    #[serde(default)]
    pub angle: f64,
}

/// `pegs = { origin = [x, y], rows = 10, columns = 20, spacing = [dx, dy] }`: row `k` at
/// `y = origin.y + k dy`, its pegs at `x = origin.x + j dx`, odd rows shifted by `dx / 2`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PegsSpec {
    /// The first peg of the first row.
    pub origin: [f64; 2],
    /// Rows.
    pub rows: usize,
    /// Pegs per row.
    pub columns: usize,
    /// Spacing along a row and between rows.
    pub spacing: [f64; 2],
}

/// Pegs one `[[obstacle]]` may create.
const MAX_PEGS: usize = 10_000_000;

/// One `[[obstacle]]` table after expansion: where its pieces are in the world's list.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleGroup {
    /// The table's name, if any.
    pub name: Option<String>,
    /// Its pieces in `Config::obstacles`.
    pub range: Range<usize>,
    /// Its colour, if set.
    pub colour: Option<Rgb>,
    /// Whether it moves.
    pub moving: bool,
}

impl ObstacleSpec {
    /// What is wrong with the table, one message each (the core validates the numbers).
    pub(crate) fn problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        let shapes = [
            self.segment.is_some(),
            self.polyline.is_some(),
            self.rectangle.is_some(),
            self.peg.is_some(),
            self.pegs.is_some(),
        ]
        .iter()
        .filter(|&&s| s)
        .count();
        if shapes != 1 {
            out.push(format!(
                "give exactly one of segment, polyline, box, peg, pegs ({shapes} given)"
            ));
        }
        let needs_radius = self.peg.is_some() || self.pegs.is_some();
        if needs_radius != self.radius.is_some() {
            out.push(if needs_radius {
                "a peg needs `radius`".to_string()
            } else {
                "`radius` is only for peg and pegs".to_string()
            });
        }
        if let Some(points) = &self.polyline
            && points.len() < 2
        {
            out.push(format!(
                "polyline needs at least 2 points ({} given)",
                points.len()
            ));
        }
        if let Some(pegs) = &self.pegs
            && (pegs.rows == 0 || pegs.columns == 0)
        {
            // An empty group has no place: its stats.csv columns would be NaN.
            out.push(format!(
                "pegs: {} rows of {} is no peg (rows and columns must be >= 1)",
                pegs.rows, pegs.columns
            ));
        }
        if let Some(pegs) = &self.pegs
            && pegs.rows.saturating_mul(pegs.columns) > MAX_PEGS
        {
            out.push(format!(
                "pegs: {} rows of {} is more than {MAX_PEGS} pegs",
                pegs.rows, pegs.columns
            ));
        }
        if self.force.is_some() != self.mass.is_some() {
            out.push("`force` and `mass` go together (a driven obstacle)".to_string());
        }
        if self.force.is_some() && !(self.segment.is_some() || self.peg.is_some()) {
            out.push(
                "a driven obstacle (`force`) is one segment or one peg: the pieces of a \
                 polyline, box or lattice would each move alone"
                    .to_string(),
            );
        }
        if let Some(c) = &self.color
            && let Err(e) = parse_colour(c)
        {
            out.push(format!("color: {e}"));
        }
        if let Some(name) = &self.name
            && (name.is_empty()
                || !name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-'))
        {
            out.push(format!(
                "name {name:?} must be letters, digits, `_` or `-` (it names stats.csv columns)"
            ));
        }
        out
    }

    /// How many obstacles the table makes, counted without making them.
    pub fn count(&self) -> u64 {
        if self.segment.is_some() || self.peg.is_some() {
            1
        } else if let Some(points) = &self.polyline {
            let segments = points.len().saturating_sub(1) as u64;
            segments + u64::from(self.closed && points.len() > 2)
        } else if self.rectangle.is_some() {
            4
        } else if let Some(pegs) = &self.pegs {
            (pegs.rows as u64).saturating_mul(pegs.columns as u64)
        } else {
            0
        }
    }

    /// The obstacles this table makes (empty when the table has problems).
    pub fn expand(&self) -> Vec<Obstacle> {
        if !self.problems().is_empty() {
            return Vec::new();
        }
        let radius = self.radius.unwrap_or(0.0);
        let mut out = if let Some([a, b]) = self.segment {
            vec![Obstacle::segment(a, b)]
        } else if let Some(points) = &self.polyline {
            Obstacle::polyline(points, self.closed)
        } else if let Some(b) = self.rectangle {
            Obstacle::rectangle(b.centre, b.size, b.angle.to_radians())
        } else if let Some(centre) = self.peg {
            vec![Obstacle::peg(centre, radius)]
        } else if let Some(p) = self.pegs {
            let mut pegs = Vec::with_capacity(p.rows * p.columns);
            for k in 0..p.rows {
                let shift = if k % 2 == 1 { 0.5 * p.spacing[0] } else { 0.0 };
                for j in 0..p.columns {
                    pegs.push(Obstacle::peg(
                        [
                            p.origin[0] + j as f64 * p.spacing[0] + shift,
                            p.origin[1] + k as f64 * p.spacing[1],
                        ],
                        radius,
                    ));
                }
            }
            pegs
        } else {
            Vec::new()
        };
        let motion = match (self.force, self.mass) {
            (Some(force), Some(mass)) => Motion::Driven {
                force,
                mass,
                velocity: self.velocity.unwrap_or([0.0, 0.0]),
            },
            _ => self.velocity.map_or(Motion::Fixed, Motion::Velocity),
        };
        for o in &mut out {
            o.restitution = self.restitution;
            o.friction = self.friction;
            o.motion = motion;
        }
        out
    }
}

/// The groups of `specs` laid out one after another, as `expand` fills `Config::obstacles`.
pub(crate) fn groups(specs: &[ObstacleSpec]) -> Vec<ObstacleGroup> {
    let mut start = 0;
    specs
        .iter()
        .map(|spec| {
            let count = spec.expand().len();
            let group = ObstacleGroup {
                name: spec.name.clone(),
                range: start..start + count,
                colour: spec.color.as_deref().and_then(|c| parse_colour(c).ok()),
                moving: spec.velocity.is_some() || spec.force.is_some(),
            };
            start += count;
            group
        })
        .collect()
}
