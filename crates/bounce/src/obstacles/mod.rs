//! Obstacles in the step: segments and pegs that discs collide with, fixed or moving (a
//! piston). What a disc does at one is the law's (`law::obstacle`: the seed's rule with an
//! immovable partner); this module finds which obstacles a disc meets and keeps the books.
//!
//! Fixed obstacles are binned once in a uniform grid whose cells list every obstacle within
//! reach of any point inside them, so a disc looks at one cell: a board of 10,000 pegs costs
//! what the discs near pegs cost. Moving obstacles (a few pistons) are tested against every
//! disc. Each disc is resolved alone against the obstacles near it, in obstacle order, so the
//! pass runs in parallel chunks and gives the same bits on any thread count; each obstacle's
//! impulses are summed exactly.
//!
//! A disc whose centre crossed a segment since its trail mark (it moved fast, or was pushed)
//! goes back to the side it came from ([`uncross`]): the segments listed at either end of
//! its path, or every fixed one for a path longer than the grid vouches for.
//! `Config::max_travel` bounds the travel per substep (`max_travel = 1` or less keeps every
//! disc from tunnelling through another).

use crate::config::{Config, Motion, ObstacleState, Shape};
use crate::context::StepContext;
use crate::geometry::MinImage;
use crate::law::{Disc, Law, collide, nearest, reach_of, touches};
use crate::parallel::{CHUNK, SharedSlice};
use crate::particles::Particles;

mod impacts;
pub(crate) use impacts::{Approach, Impact, Impacts, Met, meet, take_impacts};

/// The obstacles in the form the step uses: the current shapes, the restitutions and
/// frictions, and the
/// grid over the fixed ones. Built by the world when the configuration or the largest disc
/// changes.
#[derive(Debug, Default)]
pub(crate) struct Obstacles {
    shapes: Vec<Shape>,
    /// Each one's restitution and friction coefficient.
    surface: Vec<[f64; 2]>,
    /// Indices of the moving obstacles, tested against every disc.
    moving: Vec<u32>,
    /// Indices of the fixed ones, ascending: what a path longer than `cross_reach` may cross.
    fixed: Vec<u32>,
    /// The longest path from a disc's trail mark to its place whose crossed segments the
    /// grid is sure to list at one end: twice a segment's reach for the grid's largest disc
    /// (a crossed segment is within half the path of one end).
    cross_reach: f64,
    /// Whether any obstacle is a segment (which a disc could cross: pegs have an inside).
    has_segments: bool,
    grid: Grid,
}

/// A uniform grid over the fixed obstacles: `items[start[c]..start[c + 1]]` are the
/// obstacles (ascending) within reach of some point of cell `c` for a disc of radius up to
/// `Obstacles::built_for`.
#[derive(Debug, Default)]
struct Grid {
    origin: [f64; 2],
    inv_cell: f64,
    dims: [usize; 2],
    start: Vec<u32>,
    items: Vec<u32>,
}

/// At most this many grid cells.
const MAX_CELLS: f64 = 4e6;

impl Obstacles {
    /// Each obstacle's shape where it is now, by index.
    pub(crate) fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// The obstacles of `config` with the moving ones at `states`, binned for discs of radius
    /// up to `max_radius`.
    pub(crate) fn new(config: &Config, states: &[ObstacleState], max_radius: f64) -> Obstacles {
        let law = Law::new(config);
        let list = &config.obstacles;
        let shapes: Vec<Shape> = list
            .iter()
            .zip(states)
            .map(|(o, s)| o.shifted(s.offset))
            .collect();
        let surface = list
            .iter()
            .map(|o| {
                let e = o.restitution.unwrap_or(config.coefficient_of_restitution);
                [e, config.obstacle_friction(o)]
            })
            .collect();
        let moving = (0..list.len() as u32)
            .filter(|&k| list[k as usize].motion != Motion::Fixed)
            .collect();
        let fixed: Vec<u32> = (0..list.len() as u32)
            .filter(|&k| list[k as usize].motion == Motion::Fixed)
            .collect();
        let grid = Grid::new(&shapes, &fixed, &law, max_radius);
        let has_segments = shapes.iter().any(|s| matches!(s, Shape::Segment { .. }));
        Obstacles {
            has_segments,
            shapes,
            surface,
            moving,
            fixed,
            cross_reach: 2.0 * law.reach(max_radius),
            grid,
        }
    }

    /// Whether there are none.
    pub(crate) fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// Whether discs must be followed ([`Trail`]) so none crosses a segment.
    pub(crate) fn needs_trail(&self) -> bool {
        self.has_segments
    }

    /// Whether a disc of radius `r` (at most the radius the grid was built for) at `p`
    /// collides with any obstacle: what placement avoids.
    pub(crate) fn blocks(&self, p: [f64; 2], r: f64, law: &Law) -> bool {
        let near = self.grid.near(p[0], p[1]);
        near.iter()
            .chain(&self.moving)
            .any(|&k| touches(&self.shapes[k as usize], p, r, law))
    }

    /// Moves the moving obstacles to `states` (after `advance`).
    pub(crate) fn place(&mut self, config: &Config, states: &[ObstacleState]) {
        for &k in &self.moving {
            let k = k as usize;
            self.shapes[k] = config.obstacles[k].shifted(states[k].offset);
        }
    }
}

impl Grid {
    fn new(shapes: &[Shape], fixed: &[u32], law: &Law, max_radius: f64) -> Grid {
        if fixed.is_empty() {
            return Grid::default();
        }
        // Each obstacle's reach for the largest disc, and the box of all of them.
        let reach = |s: &Shape| reach_of(s, max_radius, law);
        let bounds = |s: &Shape| -> [[f64; 2]; 2] {
            let d = reach(s);
            match *s {
                Shape::Segment { a, b } => [
                    [a[0].min(b[0]) - d, a[1].min(b[1]) - d],
                    [a[0].max(b[0]) + d, a[1].max(b[1]) + d],
                ],
                Shape::Peg { centre, .. } => [
                    [centre[0] - d, centre[1] - d],
                    [centre[0] + d, centre[1] + d],
                ],
            }
        };
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut widest = 0.0f64;
        for &k in fixed {
            let [l, h] = bounds(&shapes[k as usize]);
            for a in 0..2 {
                lo[a] = lo[a].min(l[a]);
                hi[a] = hi[a].max(h[a]);
            }
            widest = widest.max(2.0 * reach(&shapes[k as usize]));
        }
        let size = [hi[0] - lo[0], hi[1] - lo[1]];
        // Cells one largest reach across: a cell lists what comes within reach of any
        // of its points, so smaller cells list fewer obstacles a disc then does not touch
        // (finer cells than this measured no faster: the table outgrows the cache).
        // No more than about MAX_CELLS of them, however long and thin the obstacles' box
        // (one segment far longer than the world would otherwise ask for a row of cells
        // along all of it).
        let cell = (widest / 2.0)
            .max((size[0] * size[1] / MAX_CELLS).sqrt())
            .max(size[0].max(size[1]) / MAX_CELLS)
            .max(f64::MIN_POSITIVE);
        let dims = [0, 1].map(|a| ((size[a] / cell).floor() as usize + 1).max(1));
        let inv_cell = 1.0 / cell;
        let cells = dims[0] * dims[1];
        // Each obstacle into the cells of its box that come within its reach.
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        let half_diagonal = cell * std::f64::consts::FRAC_1_SQRT_2;
        for &k in fixed {
            let shape = &shapes[k as usize];
            let [l, h] = bounds(shape);
            let c0 = [0, 1].map(|a| (((l[a] - lo[a]) * inv_cell) as usize).min(dims[a] - 1));
            let c1 = [0, 1].map(|a| (((h[a] - lo[a]) * inv_cell) as usize).min(dims[a] - 1));
            for cy in c0[1]..=c1[1] {
                for cx in c0[0]..=c1[0] {
                    let centre = [
                        lo[0] + (cx as f64 + 0.5) * cell,
                        lo[1] + (cy as f64 + 0.5) * cell,
                    ];
                    let distance = nearest(shape, centre).1.sqrt();
                    if distance <= reach(shape) + half_diagonal {
                        pairs.push(((cy * dims[0] + cx) as u32, k));
                    }
                }
            }
        }
        pairs.sort_unstable();
        let mut start = vec![0u32; cells + 1];
        for &(c, _) in &pairs {
            start[c as usize + 1] += 1;
        }
        for c in 0..cells {
            start[c + 1] += start[c];
        }
        Grid {
            origin: lo,
            inv_cell,
            dims,
            start,
            items: pairs.into_iter().map(|(_, k)| k).collect(),
        }
    }

    /// The fixed obstacles near `(x, y)`.
    #[inline]
    fn near(&self, x: f64, y: f64) -> &[u32] {
        if self.items.is_empty() {
            return &[];
        }
        let fx = (x - self.origin[0]) * self.inv_cell;
        let fy = (y - self.origin[1]) * self.inv_cell;
        // Outside the grid (or NaN): nothing is within reach.
        if !(fx >= 0.0 && fy >= 0.0 && fx < self.dims[0] as f64 && fy < self.dims[1] as f64) {
            return &[];
        }
        let c = fy as usize * self.dims[0] + fx as usize;
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }
}

/// Where each disc was when it was last known to be on the right side of every segment, in
/// storage order: the start of a path that must not cross one.
#[derive(Debug, Default)]
pub(crate) struct Trail {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl Trail {
    /// Every disc where it is now.
    pub(crate) fn mark(&mut self, p: &Particles) {
        self.x.clone_from(&p.x);
        self.y.clone_from(&p.y);
    }
}

/// Every disc against the obstacles near it (and the moving ones), in parallel chunks of
/// storage order; `states[k]` says how fast obstacle `k` moves.
///
/// First, a disc whose centre crossed a segment since `trail` (moving fast, or pushed by
/// its neighbours) is put back on the side it came from, touching the segment; then each
/// obstacle in reach pushes it out and bounces it ([`collide`]). Pushed discs are kept inside
/// the walls, and `trail` becomes the new positions. With `approaches`, each impact's
/// approach is kept too (for contact events).
pub(crate) fn resolve_obstacles(
    p: &mut Particles,
    trail: Option<&mut Trail>,
    obstacles: &Obstacles,
    states: &[ObstacleState],
    ctx: &StepContext,
    approaches: bool,
) -> Impacts {
    let (law, exec, geometry) = (&ctx.law, ctx.exec, ctx.geometry);
    let min_image = geometry.min_image();
    let velocities: Vec<[f64; 2]> = states.iter().map(|s| s.velocity).collect();
    let radius = &p.radius;
    let mass = &p.mass;
    let n = p.x.len();
    // (Empty for smooth discs.)
    let omega = SharedSlice::new(&mut p.omega);
    let turning = p.turning;
    let omega = &omega;
    // Without a trail (no segments), the chunks of the trail are empty.
    let (tx, ty) = match trail {
        Some(t) => {
            debug_assert_eq!(t.x.len(), n, "the trail is marked for these discs");
            (&mut t.x[..], &mut t.y[..])
        }
        None => (&mut [][..], &mut [][..]),
    };
    let mut chunks: Vec<_> =
        p.x.chunks_mut(CHUNK)
            .zip(p.y.chunks_mut(CHUNK))
            .zip(p.vx.chunks_mut(CHUNK).zip(p.vy.chunks_mut(CHUNK)))
            .enumerate()
            .map(|(c, ((x, y), (vx, vy)))| (c * CHUNK, x, y, vx, vy))
            .collect();
    let mut trail_chunks: Vec<(&mut [f64], &mut [f64])> =
        tx.chunks_mut(CHUNK).zip(ty.chunks_mut(CHUNK)).collect();
    trail_chunks.resize_with(chunks.len(), || (&mut [][..], &mut [][..]));
    let mut work: Vec<_> = chunks.iter_mut().zip(trail_chunks).collect();
    let partial = exec.map_mut(n, &mut work, |_, ((base, x, y, vx, vy), (x0, y0))| {
        let mut out = Impacts::default();
        let followed = !x0.is_empty();
        for k in 0..x.len() {
            let i = *base + k;
            let near = obstacles.grid.near(x[k], y[k]);
            let from = if followed {
                path_start(&min_image, [x0[k], y0[k]], [x[k], y[k]])
            } else {
                [x[k], y[k]]
            };
            let near_from = if from == [x[k], y[k]] {
                &[][..]
            } else {
                obstacles.grid.near(from[0], from[1])
            };
            // A path longer than the grid vouches for may cross a segment listed at neither
            // end (see `cross_reach`).
            let path = [x[k] - from[0], y[k] - from[1]];
            let long = path[0] * path[0] + path[1] * path[1]
                > obstacles.cross_reach * obstacles.cross_reach;
            if near.is_empty() && near_from.is_empty() && obstacles.moving.is_empty() && !long {
                if followed {
                    (x0[k], y0[k]) = (x[k], y[k]);
                }
                continue;
            }
            let spin = if turning {
                // SAFETY: disc `i` is this chunk's alone, and in bounds where discs turn.
                unsafe { omega.get(i) }
            } else {
                0.0
            };
            let mut disc = Disc {
                position: [x[k], y[k]],
                velocity: [vx[k], vy[k]],
                radius: radius[i],
                mass: law.mass(radius[i], mass[i]),
                omega: spin,
            };
            let start = disc;
            if followed {
                // The segments the path may cross, in obstacle order (fixed ascending, then
                // moving): those listed at either end, or every fixed one for a long path.
                let mut meet = |o: u32| {
                    let shape = &obstacles.shapes[o as usize];
                    uncross(shape, from, &mut disc.position, law.reach(disc.radius));
                };
                if long {
                    obstacles.fixed.iter().for_each(|&o| meet(o));
                } else {
                    in_order(near_from, near, &mut meet);
                }
                obstacles.moving.iter().for_each(|&o| meet(o));
            }
            // Sent back across a segment, the disc meets what is near where it is now.
            let near = if disc.position == start.position {
                near
            } else {
                obstacles.grid.near(disc.position[0], disc.position[1])
            };
            for &o in near.iter().chain(&obstacles.moving) {
                let u = velocities[o as usize];
                let (position, before) = (disc.position, disc.velocity);
                let shape = &obstacles.shapes[o as usize];
                let surface = obstacles.surface[o as usize];
                let (j, rubbed) = collide(shape, u, surface, law, &mut disc);
                if j != [0.0, 0.0] {
                    if rubbed != 0.0 {
                        out.friction.add(rubbed);
                    }
                    out.list.push(Impact {
                        obstacle: o,
                        disc: i as u32,
                        momentum: j,
                    });
                    if approaches {
                        out.approaches.push(Approach {
                            position,
                            velocity: before,
                        });
                    }
                    // The work of the obstacle on the disc: the disc's impulse along `u`.
                    let dv = [disc.velocity[0] - before[0], disc.velocity[1] - before[1]];
                    out.work.add(disc.mass * (dv[0] * u[0] + dv[1] * u[1]));
                }
            }
            if disc != start {
                let [mut px, mut py] = disc.position;
                geometry.hold(&mut px, &mut py, disc.radius);
                (x[k], y[k], vx[k], vy[k]) = (px, py, disc.velocity[0], disc.velocity[1]);
                if turning {
                    // SAFETY: as above.
                    unsafe { omega.set(i, disc.omega) };
                }
            }
            if followed {
                (x0[k], y0[k]) = (x[k], y[k]);
            }
        }
        out
    });
    let mut total = Impacts::default();
    for part in partial {
        total.list.extend(part.list);
        total.approaches.extend(part.approaches);
        total.work.merge(&part.work);
        total.friction.merge(&part.friction);
    }
    total
}

/// Each index of two ascending lists once, ascending.
fn in_order(a: &[u32], b: &[u32], mut f: impl FnMut(u32)) {
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        let next = match (a.get(i), b.get(j)) {
            (Some(&u), Some(&v)) if u == v => {
                (i, j) = (i + 1, j + 1);
                u
            }
            (Some(&u), Some(&v)) if u < v => {
                i += 1;
                u
            }
            (Some(&u), None) => {
                i += 1;
                u
            }
            (_, Some(&v)) => {
                j += 1;
                v
            }
            (None, None) => unreachable!("the loop's condition"),
        };
        f(next);
    }
}

/// Where a disc's path to `position` starts, for a disc last marked at `mark`: the mark
/// itself, or in a periodic box its image nearest `position` (a disc that wrapped across the
/// box's edge did not travel across the box).
#[inline]
pub(crate) fn path_start(min_image: &MinImage, mark: [f64; 2], position: [f64; 2]) -> [f64; 2] {
    if !min_image.is_periodic() {
        return mark;
    }
    let d = min_image.diff(position[0], position[1], mark[0], mark[1]);
    [position[0] - d[0], position[1] - d[1]]
}

/// If the centre's path from `from` to `position` crosses `shape` (a segment), puts the
/// centre back on `from`'s side, `reach` from the crossing point along the segment's normal.
#[inline]
pub(crate) fn uncross(shape: &Shape, from: [f64; 2], position: &mut [f64; 2], reach: f64) {
    let Shape::Segment { a, b } = *shape else {
        return;
    };
    let ab = [b[0] - a[0], b[1] - a[1]];
    let side = |p: [f64; 2]| ab[0] * (p[1] - a[1]) - ab[1] * (p[0] - a[0]);
    let (s0, s1) = (side(from), side(*position));
    if !((s0 > 0.0 && s1 < 0.0) || (s0 < 0.0 && s1 > 0.0)) {
        return;
    }
    // Where the path meets the segment's line, and whether that is on the segment.
    let f = s0 / (s0 - s1);
    let c = [
        from[0] + f * (position[0] - from[0]),
        from[1] + f * (position[1] - from[1]),
    ];
    let l2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = ((c[0] - a[0]) * ab[0] + (c[1] - a[1]) * ab[1]) / l2;
    if !(0.0..=1.0).contains(&t) {
        return;
    }
    // The unit normal pointing to `from`'s side (the left normal when s0 > 0).
    let l = l2.sqrt();
    let sign = if s0 > 0.0 { 1.0 } else { -1.0 };
    let normal = [-ab[1] / l * sign, ab[0] / l * sign];
    *position = [c[0] + normal[0] * reach, c[1] + normal[1] * reach];
}

/// Advances the moving obstacles by one substep `h`: a prescribed velocity moves them, a
/// driven one is accelerated by its force first (semi-implicit Euler, like the discs). In a
/// walled box the walls stop them: a moving obstacle that would cross one stays against it,
/// its velocity into the wall set to zero (a piston stops at the bottom of its cylinder).
pub(crate) fn advance(config: &Config, states: &mut [ObstacleState], h: f64) {
    let walls = match config.boundary {
        crate::Boundary::Walls { min, max, .. } => Some((min, max)),
        _ => None,
    };
    for (o, s) in config.obstacles.iter().zip(states.iter_mut()) {
        match o.motion {
            Motion::Fixed => continue,
            Motion::Velocity(v) => s.velocity = v,
            Motion::Driven { force, mass, .. } => {
                s.velocity[0] += force[0] / mass * h;
                s.velocity[1] += force[1] / mass * h;
            }
        }
        s.offset[0] += s.velocity[0] * h;
        s.offset[1] += s.velocity[1] * h;
        let Some((min, max)) = walls else {
            continue;
        };
        let [lo, hi] = extent(&o.shifted(s.offset));
        for axis in 0..2 {
            // Only a shape that fits between the walls can be held by them.
            if hi[axis] - lo[axis] > max[axis] - min[axis] {
                continue;
            }
            if lo[axis] < min[axis] {
                s.offset[axis] += min[axis] - lo[axis];
                s.velocity[axis] = s.velocity[axis].max(0.0);
            } else if hi[axis] > max[axis] {
                s.offset[axis] -= hi[axis] - max[axis];
                s.velocity[axis] = s.velocity[axis].min(0.0);
            }
        }
    }
}

/// The box a shape occupies.
fn extent(shape: &Shape) -> [[f64; 2]; 2] {
    match *shape {
        Shape::Segment { a, b } => [
            [a[0].min(b[0]), a[1].min(b[1])],
            [a[0].max(b[0]), a[1].max(b[1])],
        ],
        Shape::Peg { centre, radius } => [
            [centre[0] - radius, centre[1] - radius],
            [centre[0] + radius, centre[1] + radius],
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Obstacle;

    #[test]
    fn the_grid_stays_small_however_far_the_obstacles_reach() {
        // A segment 2e20 long and a peg 1e20 away: the grid's cells grow, not their number.
        let config = Config {
            obstacles: vec![
                Obstacle::segment([-1e20, 5.0], [1e20, 7.0]),
                Obstacle::peg([1e20, 1e20], 1.0),
                Obstacle::peg([3.0, 3.0], 1.0),
            ],
            ..Config::default()
        };
        let law = Law::new(&config);
        let obstacles = Obstacles::new(&config, &[ObstacleState::default(); 3], 0.5);
        let grid = &obstacles.grid;
        assert!(
            grid.dims[0] * grid.dims[1] <= 3 * MAX_CELLS as usize,
            "{:?}",
            grid.dims
        );
        // Still every obstacle a disc touches.
        assert!(obstacles.blocks([3.0, 4.2], 0.5, &law));
        assert!(obstacles.blocks([0.0, 6.2], 0.5, &law));
        assert!(!obstacles.blocks([0.0, 9.0], 0.5, &law));
    }

    #[test]
    fn the_grid_lists_every_obstacle_within_reach() {
        // Random pegs and segments; every disc position that touches an obstacle finds it
        // in its cell.
        let config = Config {
            collision_radius_scale: 1.3,
            ..Config::default()
        };
        let law = Law::new(&config);
        let mut state = 99u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut shapes = Vec::new();
        for k in 0..300 {
            let p = [next() * 50.0, next() * 50.0];
            shapes.push(if k % 3 == 0 {
                Shape::Segment {
                    a: p,
                    b: [p[0] + next() * 20.0 - 10.0, p[1] + next() * 20.0 - 10.0],
                }
            } else {
                Shape::Peg {
                    centre: p,
                    radius: 0.1 + next(),
                }
            });
        }
        let fixed: Vec<u32> = (0..shapes.len() as u32).collect();
        let r_max = 0.7;
        let grid = Grid::new(&shapes, &fixed, &law, r_max);
        for _ in 0..20000 {
            let p = [next() * 70.0 - 10.0, next() * 70.0 - 10.0];
            let r = next() * r_max;
            let near = grid.near(p[0], p[1]);
            for (k, s) in shapes.iter().enumerate() {
                if touches(s, p, r, &law) {
                    assert!(near.contains(&(k as u32)), "obstacle {k} missed at {p:?}");
                }
            }
        }
    }

    #[test]
    fn generated_gases_keep_clear_of_obstacles() {
        // A peg in the middle and a diagonal wall: neither generator puts a disc on them.
        use crate::scene::{self, Gas, Speeds};
        let config = Config {
            boundary: crate::Boundary::walls([0.0, 0.0], [40.0, 40.0]),
            obstacles: vec![
                Obstacle::peg([20.0, 20.0], 5.0),
                Obstacle::segment([0.0, 0.0], [40.0, 30.0]),
            ],
            ..Config::default()
        };
        let law = Law::new(&config);
        let gas = Gas {
            count: 300,
            radius: [0.4, 0.6],
            region: None,
            speeds: Speeds::Fixed(1.0),
            drift: [0.0, 0.0],
            seed: 4,
        };
        for discs in [
            scene::gas(&gas, &config).unwrap(),
            scene::packed_gas(&gas, &config, &[]).unwrap(),
        ] {
            assert_eq!(discs.len(), 300);
            for d in &discs {
                for o in &config.obstacles {
                    assert!(
                        !touches(&o.shape, d.position, d.radius, &law),
                        "a disc at {:?} touches {o:?}",
                        d.position
                    );
                }
            }
        }
    }

    #[test]
    fn walls_stop_a_moving_obstacle() {
        // A piston driven down hard in an empty 10 × 10 box stops on the floor; one moving
        // sideways at a prescribed speed stops at the right wall.
        let config = Config {
            boundary: crate::Boundary::walls([0.0, 0.0], [10.0, 10.0]),
            obstacles: vec![
                Obstacle::segment([0.0, 5.0], [10.0, 5.0]).moving(Motion::Driven {
                    force: [0.0, -100.0],
                    mass: 1.0,
                    velocity: [0.0, 0.0],
                }),
                Obstacle::peg([2.0, 2.0], 1.0).moving(Motion::Velocity([3.0, 0.0])),
            ],
            ..Config::default()
        };
        let mut states = vec![ObstacleState::default(); 2];
        for _ in 0..1000 {
            advance(&config, &mut states, 0.01);
        }
        assert_eq!(states[0].offset[1], -5.0);
        assert_eq!(states[0].velocity[1], 0.0);
        assert_eq!(states[1].offset[0], 7.0);
        assert_eq!(states[1].velocity[0], 0.0);
    }
}
