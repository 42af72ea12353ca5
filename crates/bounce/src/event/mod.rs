//! Exact hard discs: event-driven dynamics beside the time-stepped step. Discs fly freely
//! between collisions (straight lines, or parabolas under gravity), and each collision is
//! resolved at the exact moment the centres come to the collision distance
//! `(r_i + r_j) * collision_radius_scale`, with the seed's velocity update (the law's
//! [`resolve_pair`](crate::law::resolve_pair); the discs touch, so there is no push). No time step: no overlap, no
//! pressure bias.
//!
//! **Algorithm.** Each disc keeps its state at its own last event (`time`); a cell grid
//! (`grid`) with cells at least the largest collision distance wide tells which discs and
//! obstacles it can meet, and a disc crossing a cell side is an event too. Each disc has
//! one slot in the calendar (`calendar`): its earliest predicted event. When an event
//! changes a disc's velocity its count rises, so an event another disc predicted with it
//! is stale and is predicted anew when it comes up; this is enough, because anything the
//! changed disc will now meet first is in its own slot. A crossing changes no velocity and
//! no count. Ties fall to the lower disc, so a run is deterministic.
//!
//! **Inelastic collapse.** With restitution below 1, a dense group can collide infinitely
//! often in a finite time. The TC model (Luding & McNamara 1998) is the remedy:
//! [`Config::contact_duration`] `t_c`, and a disc's collision within `t_c` of its last one
//! is elastic. A run that still cannot advance (many events without the clock moving)
//! stops with [`EventError::Stalled`], naming the discs and the time.

mod calendar;
mod error;
mod grid;
mod predict;
mod resolve;
mod schedule;

use std::sync::atomic::{AtomicUsize, Ordering};

use crate::config::{Boundary, Config, Shape};
use crate::geometry::{Geometry, MinImage, wrap};
use crate::law::{Law, reach_of};
use crate::particles::Particle;
use calendar::Calendar;
use grid::Grid;

pub use error::{EventError, MAX_EVENTS_PER_DISC};

/// What the events over an interval added up to. See [`EventDriven`] for an example.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Observed {
    /// Collisions of two discs resolved.
    pub collisions: u64,
    /// `Σ r_ij · Δp_ij` over them (the pair's impulse on the disc `r_ij` points from): the
    /// collision virial is half of it over the interval.
    pub virial: f64,
    /// `Σ [r_x J_x, r_y J_y, ½ (r_x J_y + r_y J_x)]` over them: the virial tensor's terms.
    pub virial_tensor: [f64; 3],
    /// The momentum the walls took (`Σ m |Δv|`), left, right, bottom, top.
    pub wall_impulse: [f64; 4],
    /// The momentum each obstacle took.
    pub obstacle_impulses: Vec<[f64; 2]>,
    /// The two discs (the caller's numbers) of each collision in turn, with
    /// [`Config::collision_counts`] (empty otherwise).
    pub collided: Vec<u32>,
}

/// One disc's flight as the engine reads it in prediction: one cache line.
#[derive(Clone, Copy, Debug, Default)]
#[repr(align(64))]
struct State {
    /// Centre and velocity at `time`.
    x: [f64; 2],
    v: [f64; 2],
    time: f64,
    radius: f64,
    mass: f64,
    /// Events that changed its velocity.
    count: u32,
    /// 0 for a disc listed in its cell; for a large one (kept off the lists), how many
    /// cells its reach spans.
    span: u32,
}

/// What a disc's slot holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// Nothing to come.
    None,
    /// Meets disc `partner` (whose count was `partner_count`).
    Pair,
    /// Crosses side `side` of its cell (0 +x, 1 −x, 2 +y, 3 −y).
    Cross,
    /// Meets the wall on side `side`.
    Wall,
    /// Meets obstacle `partner`.
    Obstacle,
}

#[derive(Clone, Copy, Debug)]
struct Next {
    kind: Kind,
    side: u8,
    partner: u32,
    partner_count: u32,
}

const NOTHING: Next = Next {
    kind: Kind::None,
    side: 0,
    partner: 0,
    partner_count: 0,
};

/// Events at one time, at most, before a run is called stalled: far more than any real
/// gas has in a relative 1e-12 of its clock.
const STALL_EVENTS: u32 = 1_000_000;

/// A world of hard discs advanced event by event (see the module docs). Most runs use it
/// through [`crate::World`] with [`crate::Method::EventDriven`].
///
/// ```
/// use bounce::event::EventDriven;
/// use bounce::{Boundary, Config, Method, Particle};
/// let config = Config {
///     boundary: Boundary::periodic([0.0, 0.0], [10.0, 10.0]),
///     method: Method::EventDriven,
///     ..Config::default()
/// };
/// // Head-on at closing speed 2 across a gap of 2: they meet at t = 1 exactly and swap.
/// let discs = [Particle::new([2.0, 5.0], [1.0, 0.0], 1.0), Particle::new([6.0, 5.0], [-1.0, 0.0], 1.0)];
/// let mut engine = EventDriven::new(&config, &discs)?;
/// let seen = engine.advance(1.5)?;
/// assert_eq!((seen.collisions, engine.time()), (1, 1.5));
/// assert_eq!(engine.state(0), ([2.5, 5.0], [-1.0, 0.0]));
/// assert_eq!(engine.particles()[1].position, [5.5, 5.0]);
/// assert_eq!(engine.wrapped(0), ([2.5, 5.0], [0, 0]));
/// assert_eq!((engine.kinetic_energy(), engine.area()), (1.0, 100.0));
/// assert!(engine.memory_bytes() > 0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct EventDriven {
    law: Law,
    /// The law within `contact_duration` of a disc's last collision (the TC model).
    elastic: Law,
    contact_duration: f64,
    /// Whether collisions are listed by disc ([`Observed::collided`]).
    count_collisions: bool,
    gravity: [f64; 2],
    /// The box (`size` 0 in an open world).
    min: [f64; 2],
    size: [f64; 2],
    periodic: bool,
    /// The walls' restitution; `None` without walls.
    walls: Option<f64>,
    min_image: MinImage,
    shapes: Vec<Shape>,
    /// Each obstacle's restitution.
    obstacle_restitution: Vec<f64>,
    /// Each disc's flight, in the engine's order (by cell, for locality).
    d: Vec<State>,
    /// The large discs (see `new`), ascending.
    large: Vec<u32>,
    /// The caller's number of each disc, and the disc of each caller's number.
    order: Vec<u32>,
    slot: Vec<u32>,
    /// When it last collided (the TC model).
    last: Vec<f64>,
    /// The box widths it has been moved back by (periodic).
    image: Vec<[i32; 2]>,
    next: Vec<Next>,
    grid: Grid,
    calendar: Calendar,
    now: f64,
    observed: Observed,
    /// Where the last progress of the clock was, and the events since.
    mark: f64,
    stuck: u32,
}

impl EventDriven {
    /// The discs `discs` (numbered in order) under `config`; no pair may overlap. Refuses
    /// what [`Config::event_driven_unsupported`] names.
    /// See [`EventDriven`] for an example.
    pub fn new(config: &Config, discs: &[Particle]) -> Result<EventDriven, EventError> {
        if let Some(what) = config.event_driven_unsupported() {
            return Err(EventError::Unsupported(what));
        }
        let law = Law::new(config);
        let elastic = Law::new(&Config {
            coefficient_of_restitution: 1.0,
            ..config.clone()
        });
        for (k, d) in discs.iter().enumerate() {
            d.validate_values()
                .map_err(|e| EventError::Disc(k, e.to_string()))?;
        }
        let (min, size, periodic, walls) = match config.boundary {
            // (A sheared box was refused above.)
            Boundary::Periodic { min, max } | Boundary::LeesEdwards { min, max, .. } => {
                (min, sub(max, min), true, None)
            }
            Boundary::Walls { min, max, .. } => {
                (min, sub(max, min), false, Some(config.wall_restitution()))
            }
            Boundary::Open => ([0.0; 2], [0.0; 2], false, None),
        };
        // Cells as wide as the largest collision distance of the ordinary discs; discs over
        // 4 times the median interaction diameter are large: kept off the cell lists, each
        // looks through the cells its reach spans, and every disc looks at them all.
        let diameters: Vec<f64> = discs
            .iter()
            .map(|d| law.interaction_diameter(d.radius))
            .collect();
        let large_above = {
            let mut sorted = diameters.clone();
            sorted.sort_unstable_by(f64::total_cmp);
            4.0 * sorted.get(sorted.len() / 2).copied().unwrap_or(0.0)
        };
        let is_large = |d: f64| large_above > 0.0 && d > large_above;
        let reach = diameters
            .iter()
            .copied()
            .filter(|&d| !is_large(d))
            .fold(0.0, f64::max);
        let small_radius = discs
            .iter()
            .map(|d| d.radius)
            .filter(|&r| !is_large(law.interaction_diameter(r)))
            .fold(0.0, f64::max);
        // The grid: over the box, or over where the discs are in an open world.
        let (grid_min, grid_size) = if config.boundary == Boundary::Open {
            let lo = discs.iter().fold([f64::INFINITY; 2], |m, d| {
                [m[0].min(d.position[0]), m[1].min(d.position[1])]
            });
            let hi = discs.iter().fold([f64::NEG_INFINITY; 2], |m, d| {
                [m[0].max(d.position[0]), m[1].max(d.position[1])]
            });
            if discs.is_empty() {
                ([0.0; 2], [1.0; 2])
            } else {
                (lo, [(hi[0] - lo[0]).max(reach), (hi[1] - lo[1]).max(reach)])
            }
        } else {
            (min, size)
        };
        let grid = Grid::new(
            grid_min,
            grid_size,
            reach.max(f64::MIN_POSITIVE),
            discs.len(),
            periodic,
        );
        if periodic && (grid.dims[0] < 3 || grid.dims[1] < 3) {
            return Err(EventError::Unsupported(
                "needs a periodic box at least three collision distances across",
            ));
        }
        let shapes: Vec<Shape> = config.obstacles.iter().map(|o| o.shape).collect();
        let n = discs.len();
        let mut world = EventDriven {
            law,
            elastic,
            contact_duration: config.contact_duration,
            count_collisions: config.collision_counts,
            gravity: config.gravity,
            min,
            size,
            periodic,
            walls,
            min_image: Geometry::new(config).min_image(),
            obstacle_restitution: config
                .obstacles
                .iter()
                .map(|o| o.restitution.unwrap_or(config.coefficient_of_restitution))
                .collect(),
            d: Vec::with_capacity(n),
            order: Vec::with_capacity(n),
            large: Vec::new(),
            slot: vec![0; n],
            last: vec![f64::NEG_INFINITY; n],
            image: vec![[0; 2]; n],
            next: vec![NOTHING; n],
            grid,
            calendar: Calendar::new(n),
            now: 0.0,
            observed: Observed {
                obstacle_impulses: vec![[0.0; 2]; shapes.len()],
                ..Observed::default()
            },
            shapes,
            mark: 0.0,
            stuck: 0,
        };
        let max_radius = discs.iter().map(|d| d.radius).fold(0.0, f64::max);
        let law = world.law;
        world
            .grid
            .bin_obstacles(&world.shapes, |s| reach_of(s, max_radius, &law));
        // Wrapped, checked, and put in the order of their cells (row by row, then by
        // number): neighbours near in memory.
        let mut placed = Vec::with_capacity(n);
        for (k, d) in discs.iter().enumerate() {
            let mut p = d.position;
            let mut image = [0; 2];
            if periodic {
                for a in 0..2 {
                    image[a] = wrap(&mut p[a], min[a], size[a]);
                }
            }
            // Round-off past a wall (a disc the last interval ended on its way to it) is
            // no fault: it meets the wall at once.
            let slack = |a: usize| 1e-9 * (size[a] + d.radius);
            if walls.is_some()
                && (0..2).any(|a| {
                    p[a] - d.radius < min[a] - slack(a)
                        || p[a] + d.radius > min[a] + size[a] + slack(a)
                })
            {
                return Err(EventError::Disc(k, "reaches beyond the walls".into()));
            }
            let cell = world.grid.cell_of(p);
            placed.push((cell[1], cell[0], k as u32, p, image));
        }
        placed.sort_unstable_by_key(|&(y, x, k, ..)| (y, x, k));
        for (i, &(y, x, k, p, image)) in placed.iter().enumerate() {
            let d = &discs[k as usize];
            let span = if is_large(law.interaction_diameter(d.radius)) {
                let width = world.grid.width();
                let sigma = law.collision_distance(d.radius, small_radius);
                (sigma / width[0].min(width[1])).ceil().max(1.0) as u32
            } else {
                0
            };
            world.d.push(State {
                x: p,
                v: d.velocity,
                time: 0.0,
                radius: d.radius,
                mass: law.mass(
                    d.radius,
                    d.mass.unwrap_or(std::f64::consts::PI * d.radius * d.radius),
                ),
                count: 0,
                span,
            });
            world.order.push(k);
            world.slot[k as usize] = i as u32;
            world.image[i] = image;
            if span == 0 {
                world.grid.insert(i, [x, y]);
            } else {
                world.grid.place(i, [x, y]);
                world.large.push(i as u32);
            }
        }
        for i in 0..n {
            let mut overlap = None;
            world.for_each_near(i, |j| {
                if j > i && overlap.is_none() {
                    let d = world.min_image.diff(
                        world.d[i].x[0],
                        world.d[i].x[1],
                        world.d[j].x[0],
                        world.d[j].x[1],
                    );
                    let reach = world
                        .law
                        .collision_distance(world.d[i].radius, world.d[j].radius);
                    // Round-off at a contact the last interval ended on is no overlap.
                    if d[0] * d[0] + d[1] * d[1] < reach * reach * (1.0 - 1e-9) {
                        overlap = Some(j);
                    }
                }
            });
            if let Some(j) = overlap {
                let (a, b) = (world.order[i] as usize, world.order[j] as usize);
                return Err(EventError::Overlap(a.min(b), a.max(b)));
            }
        }
        for i in 0..n {
            world.predict(i);
        }
        Ok(world)
    }

    /// The time the world has been advanced to.
    /// See [`EventDriven`] for an example.
    pub fn time(&self) -> f64 {
        self.now
    }

    /// Processes every event up to `now + dt` and brings every disc there; what the events
    /// added up to. Stops with [`EventError::Stalled`] where the clock cannot move.
    /// See [`EventDriven`] for an example.
    pub fn advance(&mut self, dt: f64) -> Result<Observed, EventError> {
        self.advance_within(dt, u64::MAX, None)
    }

    /// [`EventDriven::advance`] that gives up with [`EventError::TooManyEvents`] past
    /// `budget` events, and with [`EventError::Interrupted`] when `interrupt` is set
    /// non-zero (read every 65,536 events). Either leaves the world part of the way. See
    /// [`EventDriven`] for an example.
    pub fn advance_within(
        &mut self,
        dt: f64,
        budget: u64,
        interrupt: Option<&AtomicUsize>,
    ) -> Result<Observed, EventError> {
        let end = self.now + dt;
        self.observed = Observed {
            obstacle_impulses: vec![[0.0; 2]; self.shapes.len()],
            ..Observed::default()
        };
        let mut events = 0u64;
        while let Some((i, t)) = self.calendar.first() {
            if t > end {
                break;
            }
            events += 1;
            if events & 0xffff == 0 {
                if events > budget {
                    return Err(EventError::TooManyEvents { events, time: t });
                }
                if interrupt.is_some_and(|flag| flag.load(Ordering::Relaxed) != 0) {
                    return Err(EventError::Interrupted { time: t });
                }
            }
            self.now = t;
            self.watch_progress(i)?;
            let next = self.next[i];
            match next.kind {
                Kind::Pair => {
                    let j = next.partner as usize;
                    if self.d[j].count == next.partner_count {
                        self.collide(i, j);
                    } else {
                        // Stale: `j` changed course since; what `i` meets now.
                        self.bring(i);
                        self.predict(i);
                    }
                }
                Kind::Cross => self.cross(i, next.side),
                Kind::Wall => self.bounce(i, next.side),
                Kind::Obstacle => self.meet(i, next.partner as usize),
                Kind::None => unreachable!("an empty slot is at infinity"),
            }
        }
        self.now = end;
        for i in 0..self.d.len() {
            self.bring(i);
        }
        Ok(std::mem::take(&mut self.observed))
    }

    /// Every disc now, in the order given (positions wrapped into a periodic box).
    /// See [`EventDriven`] for an example.
    pub fn particles(&self) -> Vec<Particle> {
        (0..self.d.len())
            .map(|k| {
                let (p, _) = self.wrapped(k);
                let i = self.slot[k] as usize;
                Particle {
                    mass: Some(self.d[i].mass),
                    ..Particle::new(p, self.velocity(i, self.now), self.d[i].radius)
                }
            })
            .collect()
    }

    /// Disc `k`'s (in the order given) centre and velocity now.
    /// See [`EventDriven`] for an example.
    pub fn state(&self, k: usize) -> ([f64; 2], [f64; 2]) {
        let i = self.slot[k] as usize;
        (self.at(i, self.now), self.velocity(i, self.now))
    }

    /// Disc `k`'s (in the order given) centre now, wrapped into a periodic box, and the box
    /// widths it has been moved back by since the start (`[0, 0]` without a periodic box).
    /// See [`EventDriven`] for an example.
    pub fn wrapped(&self, k: usize) -> ([f64; 2], [i32; 2]) {
        let i = self.slot[k] as usize;
        let mut p = self.at(i, self.now);
        let mut image = self.image[i];
        if self.periodic {
            for a in 0..2 {
                image[a] += wrap(&mut p[a], self.min[a], self.size[a]);
            }
        }
        (p, image)
    }

    /// `Σ ½ m v²`, summed in the order given.
    /// See [`EventDriven`] for an example.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.d.len())
            .map(|k| {
                let i = self.slot[k] as usize;
                let v = self.velocity(i, self.now);
                0.5 * self.d[i].mass * (v[0] * v[0] + v[1] * v[1])
            })
            .sum()
    }

    /// The bytes the engine holds for its discs, cells and calendar (what a disc costs:
    /// this over the count).
    /// See [`EventDriven`] for an example.
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        let n = self.d.capacity();
        n * (size_of::<State>() + 2 * size_of::<u32>() + size_of::<f64>() + size_of::<[i32; 2]>())
            + self.next.capacity() * size_of::<Next>()
            + self.grid.memory_bytes()
            + self.calendar.memory_bytes()
    }

    /// The box's area (0 in an open world).
    /// See [`EventDriven`] for an example.
    pub fn area(&self) -> f64 {
        self.size[0] * self.size[1]
    }

    /// Disc `i`'s centre at time `t` on its current flight (not wrapped).
    #[inline]
    pub(super) fn at(&self, i: usize, t: f64) -> [f64; 2] {
        let dt = t - self.d[i].time;
        let [gx, gy] = self.gravity;
        [
            self.d[i].x[0] + (self.d[i].v[0] + 0.5 * gx * dt) * dt,
            self.d[i].x[1] + (self.d[i].v[1] + 0.5 * gy * dt) * dt,
        ]
    }

    /// Disc `i`'s velocity at time `t` on its current flight.
    #[inline]
    pub(super) fn velocity(&self, i: usize, t: f64) -> [f64; 2] {
        let dt = t - self.d[i].time;
        [
            self.d[i].v[0] + self.gravity[0] * dt,
            self.d[i].v[1] + self.gravity[1] * dt,
        ]
    }

    /// Brings disc `i`'s state to now.
    #[inline]
    pub(super) fn bring(&mut self, i: usize) {
        if self.d[i].time != self.now {
            (self.d[i].x, self.d[i].v) = (self.at(i, self.now), self.velocity(i, self.now));
            self.d[i].time = self.now;
        }
    }

    /// Counts an event at `i` and stops a run whose clock has not moved (relatively) over
    /// [`STALL_EVENTS`] of them.
    fn watch_progress(&mut self, i: usize) -> Result<(), EventError> {
        if self.now > self.mark {
            self.mark = self.now + self.now.abs() * 1e-12;
            self.stuck = 0;
            return Ok(());
        }
        self.stuck += 1;
        if self.stuck < STALL_EVENTS {
            return Ok(());
        }
        // Name the discs of the next few events.
        let mut discs = vec![i];
        let mut calendar = self.calendar.clone();
        for _ in 0..64 {
            let Some((k, _)) = calendar.first() else {
                break;
            };
            if !discs.contains(&k) {
                discs.push(k);
            }
            calendar.set(k, f64::INFINITY);
        }
        let mut discs: Vec<usize> = discs.into_iter().map(|k| self.order[k] as usize).collect();
        discs.sort_unstable();
        discs.truncate(16);
        Err(EventError::Stalled {
            time: self.now,
            discs,
        })
    }
}

fn sub(p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
    [p[0] - q[0], p[1] - q[1]]
}
