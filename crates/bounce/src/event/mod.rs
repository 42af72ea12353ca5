//! Exact hard discs: event-driven dynamics beside the time-stepped step, the first part of
//! it. Discs fly freely between collisions, and each collision is resolved at the exact
//! moment the centres come to the collision distance `(r_i + r_j) * collision_radius_scale`,
//! with the seed's velocity update (the law's [`resolve_pair`]; the discs touch, so there is
//! no push). No time step: no overlap, no pressure bias.
//!
//! **Algorithm.** Each disc keeps its state at its own last event (`time`); a cell grid with
//! cells at least the largest collision distance wide tells which discs can meet, and a disc
//! crossing a cell side is an event too. One calendar (a binary heap) holds every predicted
//! event with the event counts of its discs when it was predicted; a disc's count rises with
//! each of its events, so an event whose disc has moved on since is stale and skipped when it
//! comes up (lazy invalidation). Ties are broken by the discs' ids, so a run is
//! deterministic.
//!
//! **So far:** a periodic box or walls (a disc meets a wall when its centre is its radius
//! from it, and leaves with its normal velocity reversed and scaled by the walls'
//! restitution), without gravity or obstacles ([`EventDriven::new`] refuses the rest). The
//! scenario's `method`, the front ends and the rest of the physics follow.

mod predict;

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use thiserror::Error;

use crate::config::{Boundary, Config};
use crate::geometry::{Geometry, MinImage};
use crate::law::{Body, Law, resolve_pair};
use crate::particles::Particle;
use predict::{contact_time, exit_time};

/// Why an event-driven world was refused.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum EventError {
    /// The configuration asks for what the event-driven engine does not do yet.
    #[error("the event-driven engine does not support {0} yet")]
    Unsupported(&'static str),
    /// A disc is invalid or overlaps another.
    #[error("disc {0}: {1}")]
    Disc(usize, String),
}

/// A predicted event: a collision of discs `a < b`, or disc `a` crossing the side `side` of
/// its cell or meeting that wall (0 +x, 1 −x, 2 +y, 3 −y), with the discs' event counts
/// when it was predicted.
#[derive(Clone, Copy, Debug)]
struct Event {
    time: f64,
    a: u32,
    b: u32,
    side: u8,
    counts: [u64; 2],
}

/// `b` of a crossing.
const CROSSING: u32 = u32::MAX;
/// `b` of a wall.
const WALL: u32 = u32::MAX - 1;

impl Event {
    fn key(&self) -> (f64, u32, u32, u8) {
        (self.time, self.a, self.b, self.side)
    }
}

impl PartialEq for Event {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Event {}

impl PartialOrd for Event {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Event {
    /// Earliest first (reversed, for `BinaryHeap`'s largest-first), then by ids.
    fn cmp(&self, other: &Self) -> Ordering {
        let (a, b) = (self.key(), other.key());
        b.0.total_cmp(&a.0)
            .then(b.1.cmp(&a.1))
            .then(b.2.cmp(&a.2))
            .then(b.3.cmp(&a.3))
    }
}

/// What the events over an interval added up to.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Observed {
    /// Collisions resolved.
    pub collisions: u64,
    /// `Σ r_ij · Δp_ij` over them (the pair's impulse on the disc `r_ij` points from): the
    /// collision virial is half of it over the interval.
    pub virial: f64,
    /// The momentum the walls took (`Σ m |Δv|`), left, right, bottom, top.
    pub wall_impulse: [f64; 4],
}

/// A world of hard discs advanced event by event (see the module docs).
#[derive(Clone, Debug)]
pub struct EventDriven {
    law: Law,
    size: [f64; 2],
    min: [f64; 2],
    /// The walls' restitution; `None` in a periodic box.
    walls: Option<f64>,
    /// Centre differences: the minimum image in a periodic box.
    min_image: MinImage,
    /// Per disc, at its own `time`: centre, velocity; radius, mass.
    x: Vec<[f64; 2]>,
    v: Vec<[f64; 2]>,
    radius: Vec<f64>,
    mass: Vec<f64>,
    time: Vec<f64>,
    count: Vec<u64>,
    cell: Vec<[usize; 2]>,
    cells: Vec<Vec<u32>>,
    dims: [usize; 2],
    width: [f64; 2],
    calendar: BinaryHeap<Event>,
    now: f64,
}

impl EventDriven {
    /// The discs `discs` (ids in order) under `config`: a periodic box without gravity or
    /// obstacles; discs must not overlap.
    pub fn new(config: &Config, discs: &[Particle]) -> Result<EventDriven, EventError> {
        let (min, max, walls) = match config.boundary {
            Boundary::Periodic { min, max } => (min, max, None),
            Boundary::Walls { min, max, .. } => (min, max, Some(config.wall_restitution())),
            Boundary::Open => return Err(EventError::Unsupported("an open world")),
        };
        if config.gravity != [0.0, 0.0] {
            return Err(EventError::Unsupported("gravity"));
        }
        if !config.obstacles.is_empty() || !config.emitters.is_empty() || !config.sinks.is_empty() {
            return Err(EventError::Unsupported("obstacles, emitters or sinks"));
        }
        let law = Law::new(config);
        let size = [max[0] - min[0], max[1] - min[1]];
        let reach = discs
            .iter()
            .map(|d| law.interaction_diameter(d.radius))
            .fold(0.0, f64::max);
        let dims = size.map(|s| ((s / reach).floor() as usize).min(1 << 12));
        if dims[0] < 3 || dims[1] < 3 {
            return Err(EventError::Unsupported(
                "a box under three collision distances across",
            ));
        }
        let width = [size[0] / dims[0] as f64, size[1] / dims[1] as f64];
        let mut world = EventDriven {
            law,
            size,
            min,
            walls,
            min_image: Geometry::new(config).min_image(),
            x: Vec::new(),
            v: Vec::new(),
            radius: Vec::new(),
            mass: Vec::new(),
            time: vec![0.0; discs.len()],
            count: vec![0; discs.len()],
            cell: Vec::new(),
            cells: vec![Vec::new(); dims[0] * dims[1]],
            dims,
            width,
            calendar: BinaryHeap::new(),
            now: 0.0,
        };
        for (k, d) in discs.iter().enumerate() {
            d.validate_values()
                .map_err(|e| EventError::Disc(k, e.to_string()))?;
            let p = world.wrap(d.position);
            if world.walls.is_some()
                && (0..2).any(|a| p[a] - d.radius < min[a] || p[a] + d.radius > max[a])
            {
                return Err(EventError::Disc(k, "reaches beyond the walls".into()));
            }
            let cell = [0, 1].map(|a| (((p[a] - min[a]) / width[a]) as usize).min(dims[a] - 1));
            world.x.push(p);
            world.v.push(d.velocity);
            world.radius.push(d.radius);
            world.mass.push(law.mass(
                d.radius,
                d.mass.unwrap_or(std::f64::consts::PI * d.radius * d.radius),
            ));
            world.cell.push(cell);
            world.cells[cell[1] * dims[0] + cell[0]].push(k as u32);
        }
        for i in 0..discs.len() {
            for j in world.neighbours(i) {
                let d = world.image(world.x[i], world.x[j as usize]);
                let reach = world.reach(i, j as usize);
                if (i as u32) < j && d[0] * d[0] + d[1] * d[1] < reach * reach {
                    return Err(EventError::Disc(i, format!("overlaps disc {j}")));
                }
            }
        }
        for i in 0..discs.len() {
            world.predict(i, None);
        }
        Ok(world)
    }

    /// The time the world has been advanced to.
    pub fn time(&self) -> f64 {
        self.now
    }

    /// Processes every event up to `now + dt` and brings every disc there.
    pub fn advance(&mut self, dt: f64) -> Observed {
        let end = self.now + dt;
        let mut observed = Observed::default();
        while let Some(&event) = self.calendar.peek() {
            if event.time > end {
                break;
            }
            self.calendar.pop();
            let (a, b) = (event.a as usize, event.b);
            let pair = b < WALL;
            if self.count[a] != event.counts[0]
                || (pair && self.count[b as usize] != event.counts[1])
            {
                continue;
            }
            if b == CROSSING {
                self.cross(a, event.side, event.time);
            } else if b == WALL {
                self.bounce(a, event.side, event.time, &mut observed);
            } else {
                self.collide(a, b as usize, event.time, &mut observed);
            }
        }
        for i in 0..self.x.len() {
            self.x[i] = self.at(i, end);
            self.time[i] = end;
        }
        self.now = end;
        observed
    }

    /// Every disc now, in id order (positions wrapped into the box).
    pub fn particles(&self) -> Vec<Particle> {
        (0..self.x.len())
            .map(|i| {
                let p = self.wrap(self.at(i, self.now));
                Particle {
                    mass: Some(self.mass[i]),
                    ..Particle::new(p, self.v[i], self.radius[i])
                }
            })
            .collect()
    }

    /// `Σ ½ m v²`.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.v.len())
            .map(|i| 0.5 * self.mass[i] * (self.v[i][0].powi(2) + self.v[i][1].powi(2)))
            .sum()
    }

    /// The box's area.
    pub fn area(&self) -> f64 {
        self.size[0] * self.size[1]
    }

    /// `p` wrapped into a periodic box (as it is between walls).
    fn wrap(&self, p: [f64; 2]) -> [f64; 2] {
        if self.walls.is_some() {
            return p;
        }
        [0, 1].map(|a| self.min[a] + (p[a] - self.min[a]).rem_euclid(self.size[a]))
    }

    /// Disc `i`'s centre at time `t` (not wrapped).
    fn at(&self, i: usize, t: f64) -> [f64; 2] {
        let dt = t - self.time[i];
        [
            self.x[i][0] + self.v[i][0] * dt,
            self.x[i][1] + self.v[i][1] * dt,
        ]
    }

    fn reach(&self, i: usize, j: usize) -> f64 {
        self.law.collision_distance(self.radius[i], self.radius[j])
    }

    /// `p - q`, the minimum image in a periodic box (a disc's centre stays within a cell of
    /// the box, so one correction per axis finds it).
    fn image(&self, p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
        self.min_image.diff(p[0], p[1], q[0], q[1])
    }

    /// The discs in the 3 × 3 cells around disc `i`'s, `i` left out.
    fn neighbours(&self, i: usize) -> Vec<u32> {
        let [cx, cy] = self.cell[i];
        let [nx, ny] = self.dims;
        let mut out = Vec::new();
        let walled = self.walls.is_some();
        for dy in [ny - 1, 0, 1] {
            for dx in [nx - 1, 0, 1] {
                // Between walls the grid does not wrap: no cell beyond an edge.
                let beyond =
                    |c: usize, d: usize, n: usize| (d == n - 1 && c == 0) || (d == 1 && c + 1 == n);
                if walled && (beyond(cx, dx, nx) || beyond(cy, dy, ny)) {
                    continue;
                }
                let cell = ((cy + dy) % ny) * nx + (cx + dx) % nx;
                out.extend(self.cells[cell].iter().filter(|&&j| j as usize != i));
            }
        }
        out
    }

    /// Predicts disc `i`'s events from its state now: a collision with each neighbour
    /// (`except` left out: the one it just met) and its next crossing.
    fn predict(&mut self, i: usize, except: Option<usize>) {
        let t = self.time[i];
        for j in self.neighbours(i) {
            let j = j as usize;
            if Some(j) == except {
                continue;
            }
            let dr = self.image(self.x[i], self.at(j, t));
            let dv = [self.v[i][0] - self.v[j][0], self.v[i][1] - self.v[j][1]];
            if let Some(dt) = contact_time(dr, dv, self.reach(i, j)) {
                let (a, b) = if i < j { (i, j) } else { (j, i) };
                self.calendar.push(Event {
                    time: t + dt,
                    a: a as u32,
                    b: b as u32,
                    side: 0,
                    counts: [self.count[a], self.count[b]],
                });
            }
        }
        if self.walls.is_some() {
            // The wall it moves to along each axis: where its centre is its radius from it.
            for a in 0..2 {
                let (x, v, r) = (self.x[i][a], self.v[i][a], self.radius[i]);
                let (lo, hi) = (self.min[a] + r, self.min[a] + self.size[a] - r);
                let (dt, side) = if v > 0.0 {
                    ((hi - x) / v, 2 * a as u8)
                } else if v < 0.0 {
                    ((lo - x) / v, 2 * a as u8 + 1)
                } else {
                    continue;
                };
                self.calendar.push(Event {
                    time: t + dt.max(0.0),
                    a: i as u32,
                    b: WALL,
                    side,
                    counts: [self.count[i], 0],
                });
            }
        }
        let mut next = (f64::INFINITY, 0u8);
        for a in 0..2 {
            let lo = self.min[a] + self.cell[i][a] as f64 * self.width[a];
            let leave = exit_time(self.x[i][a], self.v[i][a], lo, lo + self.width[a]);
            let side = 2 * a as u8 + (self.v[i][a] < 0.0) as u8;
            if leave < next.0 {
                next = (leave, side);
            }
        }
        if next.0.is_finite() {
            self.calendar.push(Event {
                time: t + next.0,
                a: i as u32,
                b: CROSSING,
                side: next.1,
                counts: [self.count[i], 0],
            });
        }
    }

    /// Disc `i` crosses side `side` of its cell at `t`: into the next cell (wrapping, with
    /// its centre, across the box).
    fn cross(&mut self, i: usize, side: u8, t: f64) {
        self.x[i] = self.at(i, t);
        self.time[i] = t;
        self.count[i] += 1;
        let old = self.cell[i];
        let (axis, down) = ((side / 2) as usize, side % 2 == 1);
        let n = self.dims[axis];
        let mut cell = old;
        if down {
            cell[axis] = (old[axis] + n - 1) % n;
            if old[axis] == 0 {
                self.x[i][axis] += self.size[axis];
            }
        } else {
            cell[axis] = (old[axis] + 1) % n;
            if cell[axis] == 0 {
                self.x[i][axis] -= self.size[axis];
            }
        }
        let from = &mut self.cells[old[1] * self.dims[0] + old[0]];
        let k = from.iter().position(|&j| j as usize == i).expect("listed");
        from.swap_remove(k);
        self.cells[cell[1] * self.dims[0] + cell[0]].push(i as u32);
        self.cell[i] = cell;
        self.predict(i, None);
    }

    /// Disc `i` meets wall `side` at `t`: its normal velocity reversed and scaled by the
    /// walls' restitution, the momentum recorded.
    fn bounce(&mut self, i: usize, side: u8, t: f64, observed: &mut Observed) {
        self.x[i] = self.at(i, t);
        self.time[i] = t;
        self.count[i] += 1;
        let axis = (side / 2) as usize;
        let e = self.walls.expect("walls");
        let v = self.v[i][axis];
        let after = -e * v;
        // The wall's side in `Observed` order: left, right, bottom, top.
        let wall = 2 * axis + side.is_multiple_of(2) as usize;
        observed.wall_impulse[wall] += self.mass[i] * (after - v).abs();
        self.v[i][axis] = after;
        self.predict(i, None);
    }

    /// Discs `a` and `b` meet at `t`: the law's velocity update at contact.
    fn collide(&mut self, a: usize, b: usize, t: f64, observed: &mut Observed) {
        for i in [a, b] {
            self.x[i] = self.at(i, t);
            self.time[i] = t;
            self.count[i] += 1;
        }
        let diff = self.image(self.x[a], self.x[b]);
        let body = |i: usize| Body::new(self.v[i], self.radius[i], self.mass[i]);
        let (one, two) = (body(a), body(b));
        let out = resolve_pair(diff, &one, &two, &self.law);
        let impulse = [0, 1].map(|k| {
            0.5 * (one.mass * (out.v1[k] - one.velocity[k])
                - two.mass * (out.v2[k] - two.velocity[k]))
        });
        observed.virial += diff[0] * impulse[0] + diff[1] * impulse[1];
        observed.collisions += 1;
        (self.v[a], self.v[b]) = (out.v1, out.v2);
        self.predict(a, Some(b));
        self.predict(b, Some(a));
    }
}
