//! The plain step: the seed's algorithm as a newcomer would write it, beside the fast one.
//!
//! [`step`] advances a [`World`] by `dt` exactly as [`World::step`] does, bit for bit, with
//! none of the fast step's machinery: no candidate lists, skins, strays or bands, no presort,
//! no lanes, no threads, no unsafe code. Each substep integrates every disc, finds every
//! colliding pair through a plain grid, sorts the pairs into the canonical order and resolves
//! them one after the other through the law, then meets the walls and the obstacles. It shares
//! with the fast step only the rules themselves (the law, the geometry's walls and wrap, the
//! obstacles' `collide` and `uncross`, the canonical order's key) and what surrounds the
//! substeps (emitters, sinks, measurement). Its pairs are resolved by its own loop, not by
//! either of the fast step's solvers (the side-by-side kernel, or one contact at a time for
//! contact reports, the pressure tensor, the collision counts and a Lees–Edwards box), so
//! both are held to it.
//!
//! It is the reference: a property test (`tests/plain_step.rs`) steps random worlds with
//! both and requires the same state bits, so a change to a kernel that moves one bit fails
//! there. A new law is easiest written here first. It is slow (one thread, a hash grid), and
//! it steps whole worlds only (not the parts of a distributed run).
//!
//! What the two steps keep apart is the storage order: the fast step reorders the discs when
//! it lists candidates, this one never does. No state depends on that order; only the last
//! bits of the measured kinetic energy and momentum (summed in storage order) may differ.

use std::collections::HashMap;

use crate::Motion;
use crate::Shape;
use crate::config::Config;
use crate::config::ObstacleState;
use crate::contacts::{OrderGrid, ordered_bits};
use crate::geometry::{Geometry, wrap};
use crate::integrate::turned;
use crate::law::{Body, is_impact, virial_terms};
use crate::law::{Disc, Law, Rough, collide, reflect, resting_speed, rub_walls, touch_walls};
use crate::obstacles::{self, Impact, Impacts, Met, uncross};
use crate::particles::Particles;
use crate::resolve::Resolved;
use crate::stats::{StepProfile, StepStats, Stopwatch};
use crate::sum::{ExactSum, StepSums, WallSums};
use crate::world::{StepError, Substepped, World, substep_end};

/// Advances `world` by `dt` as [`World::step`] does (the same substeps, the same bits of
/// the state), the plain way. It reports no contact events ([`World::contact_events`] is
/// empty after it). The world's fast-step lists are forgotten (the next
/// [`World::step`] lists anew).
///
/// ```
/// use bounce::{Config, Particle, World, plain};
/// let mut fast = World::new(Config::default()).unwrap();
/// fast.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 1.0)).unwrap();
/// fast.add_particle(Particle::new([2.5, 0.0], [-1.0, 0.0], 1.0)).unwrap();
/// let mut reference = World::new(Config::default()).unwrap();
/// reference.add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 1.0)).unwrap();
/// reference.add_particle(Particle::new([2.5, 0.0], [-1.0, 0.0], 1.0)).unwrap();
/// for _ in 0..60 {
///     fast.step(0.01).unwrap();
///     plain::step(&mut reference, 0.01).unwrap();
/// }
/// assert_eq!(fast.state_hash(), reference.state_hash());
/// ```
pub fn step(world: &mut World, dt: f64) -> Result<&StepStats, StepError> {
    if world.config.method == crate::Method::EventDriven {
        // Events have no time step to write plainly: the engine is its own reference.
        return world.step(dt);
    }
    world.check_time_step(dt)?;
    let substeps = world.check_substeps(dt, world.substeps_for(dt))?;
    let emitted = world.emit(dt);
    world.broadphase.invalidate();
    // Contact events are the fast step's to report: a plain step reports none.
    world.contact_log.start_step(None);
    let config = world.config.clone();
    let h = dt / substeps as f64;
    let mut rules = Rules::new(&config, h);
    let start = world.time();
    let mut stats = StepStats {
        substeps,
        emitted,
        ..StepStats::default()
    };
    let mut sums = StepSums::default();
    let mut tensor: [ExactSum; 3] = Default::default();
    let mut collided = Vec::new();
    let mut met = Met::new(config.obstacles.len());
    let mut finite = true;
    let has_obstacles = !config.obstacles.is_empty();
    let has_segments = config
        .obstacles
        .iter()
        .any(|o| matches!(o.shape, Shape::Segment { .. }));
    let p = &mut world.particles;
    let states = &mut world.obstacle_states;
    for substep in 0..substeps {
        let end = substep_end(start, dt, substeps, substep);
        rules.geometry = rules.geometry.at_time(end);
        if has_obstacles {
            obstacles::advance(&config, states, h);
        }
        let shapes: Vec<Shape> = (config.obstacles.iter().zip(states.iter()))
            .map(|(o, s)| o.shifted(s.offset))
            .collect();
        // With segments, each disc is followed from where it was on the right side.
        let mut trail: Option<Vec<[f64; 2]>> =
            has_segments.then(|| (0..p.len()).map(|i| [p.x[i], p.y[i]]).collect());
        sums.walls.merge(&integrate(p, &rules, h));
        if p.x.iter().chain(&p.y).any(|v| v.is_infinite()) {
            finite = false;
            break;
        }
        if has_segments {
            // Discs that flew through a segment in this substep go back.
            let impacts = meet_obstacles(p, trail.as_deref_mut(), &shapes, states, &rules);
            obstacles::take_impacts(impacts, &config, states, &mut met);
        }
        for pass in 0..config.solver_iterations {
            let (contacts, max_overlap) = find_contacts(p, &rules);
            if pass == 0 {
                stats.pairs += contacts.len();
                stats.max_overlap = stats.max_overlap.max(max_overlap);
            }
            let resolved = resolve_one_after_another(
                p,
                &contacts,
                &rules.law.for_pass(pass),
                &rules.geometry,
                rules.resting_speed,
                (config.pressure_tensor, config.collision_counts && pass == 0),
            );
            for (sum, part) in tensor.iter_mut().zip(&resolved.tensor) {
                sum.merge(part);
            }
            collided.extend_from_slice(&resolved.collided);
            sums.virial.merge(&resolved.virial);
            sums.friction.merge(&resolved.friction);
            if pass == 0 {
                stats.collisions += resolved.impacts;
            }
            if has_obstacles {
                let impacts = meet_obstacles(p, trail.as_deref_mut(), &shapes, states, &rules);
                obstacles::take_impacts(impacts, &config, states, &mut met);
            }
            if config.solver_iterations > 1 {
                sums.walls.merge(&walls_as_contacts(p, &rules));
            }
        }
    }
    if let Some(grid) = world.obstacles.as_mut() {
        grid.place(&config, &world.obstacle_states);
    }
    let done = Substepped {
        stats,
        sums,
        tensor,
        met,
        profile: StepProfile::default(),
        clock: Stopwatch::start(),
        finite,
        reordered: false,
        collided,
    };
    world.finish_step(dt, done)?;
    Ok(&world.stats)
}

/// What a substep's stages read: the law, the geometry and the order of resolution.
struct Rules {
    law: Law,
    geometry: Geometry,
    gravity: [f64; 2],
    /// With several passes under gravity, each block's contacts go lowest first.
    stack_order: Option<[f64; 2]>,
    /// Each obstacle's restitution and friction.
    surface: Vec<[f64; 2]>,
    /// The order a disc meets the obstacles in: the fixed ones, then the moving ones.
    obstacle_order: Vec<usize>,
    /// The approach speed below which a contact rests.
    resting_speed: f64,
}

impl Rules {
    fn new(config: &Config, h: f64) -> Rules {
        let moving: Vec<bool> = config
            .obstacles
            .iter()
            .map(|o| o.motion != Motion::Fixed)
            .collect();
        let obstacle_order = (0..moving.len())
            .filter(|&k| !moving[k])
            .chain((0..moving.len()).filter(|&k| moving[k]))
            .collect();
        Rules {
            law: Law::at_substep(config, h),
            geometry: Geometry::new(config),
            gravity: config.gravity,
            stack_order: (config.solver_iterations > 1 && config.gravity != [0.0, 0.0])
                .then_some(config.gravity),
            surface: (config.obstacles.iter())
                .map(|o| {
                    let e = o.restitution.unwrap_or(config.coefficient_of_restitution);
                    [e, config.obstacle_friction(o)]
                })
                .collect(),
            obstacle_order,
            resting_speed: resting_speed(config.gravity, h),
        }
    }

    fn mass(&self, p: &Particles, i: usize) -> f64 {
        self.law.mass(p.radius[i], p.mass[i])
    }
}

/// Semi-implicit Euler, `v += g h; x += v h`, then the boundary for each disc: walls reflect
/// it (rough ones rub it; returns the impulses they took), a periodic box wraps it; then a
/// disc that turns turns.
fn integrate(p: &mut Particles, rules: &Rules, h: f64) -> WallSums {
    let [gx, gy] = rules.gravity;
    let mut impulse = WallSums::default();
    let rubbing = rules.law.rough.filter(|rough| rough.rubs_walls());
    for i in 0..p.len() {
        p.vx[i] += gx * h;
        p.vy[i] += gy * h;
        p.x[i] += p.vx[i] * h;
        p.y[i] += p.vy[i] * h;
        match rules.geometry {
            Geometry::Open => {}
            Geometry::Walls {
                min,
                max,
                restitution: e,
            } => {
                let (r, m, e) = (p.radius[i], rules.mass(p, i), rules.law.restitution_of(e));
                let (left, right) = reflect(&mut p.x[i], &mut p.vx[i], r, min[0], max[0], e, m);
                let (bottom, top) = reflect(&mut p.y[i], &mut p.vy[i], r, min[1], max[1], e, m);
                rub(p, i, [left, right, bottom, top], m, rubbing, &mut impulse);
            }
            Geometry::Periodic {
                min,
                size,
                slide: Some(slide),
                ..
            } => {
                let crossed = slide.wrap([&mut p.x[i], &mut p.y[i], &mut p.vx[i]], min, size);
                p.image[i][0] = p.image[i][0].wrapping_add(crossed[0]);
                p.image[i][1] = p.image[i][1].wrapping_add(crossed[1]);
            }
            Geometry::Periodic { min, size, .. } => {
                p.image[i][0] = p.image[i][0].wrapping_add(wrap(&mut p.x[i], min[0], size[0]));
                p.image[i][1] = p.image[i][1].wrapping_add(wrap(&mut p.y[i], min[1], size[1]));
            }
        }
        if p.turning {
            p.theta[i] = turned(p.theta[i], p.omega[i], h);
        }
    }
    impulse
}

/// A colliding pair: storage indices, the lower id's first, and its place in the
/// canonical order.
struct Contact {
    /// (order block, height against gravity when stacking, lower id, higher id).
    order: (u64, u64, u64),
    a: usize,
    b: usize,
}

/// Every colliding pair, in the canonical order, and the largest overlap.
fn find_contacts(p: &Particles, rules: &Rules) -> (Vec<Contact>, f64) {
    let n = p.len();
    let max_radius = p.radius.iter().copied().fold(0.0, f64::max);
    let order = OrderGrid::new(&rules.geometry, &rules.law, max_radius);
    let min_image = rules.geometry.min_image();
    let mut contacts = Vec::new();
    let mut max_overlap = 0.0f64;
    for_each_near_pair(p, rules, max_radius, |i, j| {
        let diff = min_image.diff(p.x[i], p.y[i], p.x[j], p.y[j]);
        let Some(overlap) = rules.law.overlap(diff, p.radius[i], p.radius[j]) else {
            return;
        };
        max_overlap = max_overlap.max(overlap);
        let (a, b) = if p.id[i] < p.id[j] { (i, j) } else { (j, i) };
        let height = match rules.stack_order {
            None => 0,
            Some(g) => {
                let d = min_image.diff(p.x[a], p.y[a], p.x[b], p.y[b]);
                let mid = [p.x[a] - 0.5 * d[0], p.y[a] - 0.5 * d[1]];
                ordered_bits(-(g[0] * mid[0] + g[1] * mid[1]))
            }
        };
        let ids = (u64::from(p.id[a].0) << 32) | u64::from(p.id[b].0);
        contacts.push(Contact {
            order: (order.key(p.x[a], p.y[a]), height, ids),
            a,
            b,
        });
    });
    debug_assert!(contacts.len() <= n * n);
    contacts.sort_by_key(|c| c.order);
    (contacts, max_overlap)
}

/// Calls `f(i, j)` (storage indices, `i < j`) for every pair of discs that may collide: those
/// in the same or neighbouring cells of a grid of cells at least the largest collision
/// distance wide (wrapping in a periodic box; every pair when the box is too small for three
/// cells across).
fn for_each_near_pair(
    p: &Particles,
    rules: &Rules,
    max_radius: f64,
    mut f: impl FnMut(usize, usize),
) {
    let n = p.len();
    let reach = rules.law.interaction_diameter(max_radius);
    let (origin, cells) = match rules.geometry {
        Geometry::Periodic { min, size, .. } => {
            let across = size.map(|s| (s / reach).floor());
            if !(across[0] >= 3.0 && across[1] >= 3.0 && reach > 0.0) {
                for i in 0..n {
                    for j in i + 1..n {
                        f(i, j);
                    }
                }
                return;
            }
            (min, Some(across.map(|c| c.min(1e9) as i64)))
        }
        Geometry::Walls { min, .. } => (min, None),
        Geometry::Open => ([0.0, 0.0], None),
    };
    let width = match (cells, rules.geometry) {
        (Some(c), Geometry::Periodic { size, .. }) => {
            [size[0] / c[0] as f64, size[1] / c[1] as f64]
        }
        _ => [reach.max(f64::MIN_POSITIVE); 2],
    };
    let cell_of = |i: usize| -> [i64; 2] {
        // In a Lees–Edwards box a centre pushed past the top or bottom goes in the cell of
        // its image in the box.
        let [x, y] = rules.geometry.slid_into_box([p.x[i], p.y[i]]);
        let raw = [
            ((x - origin[0]) / width[0]).floor() as i64,
            ((y - origin[1]) / width[1]).floor() as i64,
        ];
        match cells {
            Some(c) => [raw[0].rem_euclid(c[0]), raw[1].rem_euclid(c[1])],
            None => raw,
        }
    };
    let mut grid: HashMap<[i64; 2], Vec<usize>> = HashMap::new();
    for i in 0..n {
        grid.entry(cell_of(i)).or_default().push(i);
    }
    for i in 0..n {
        let [cx, cy] = cell_of(i);
        let mut near = Vec::with_capacity(9);
        for dy in -1..=1i64 {
            for dx in -1..=1i64 {
                let mut cell = [cx.saturating_add(dx), cy.saturating_add(dy)];
                if let Some(c) = cells {
                    cell = [cell[0].rem_euclid(c[0]), cell[1].rem_euclid(c[1])];
                }
                if !near.contains(&cell) {
                    near.push(cell);
                }
            }
        }
        // Across the top or bottom of a Lees–Edwards box the row slides: all of it.
        if let (Some(c), Some(_)) = (cells, rules.geometry.slide()) {
            for row in [cy - 1, cy + 1]
                .into_iter()
                .filter(|row| !(0..c[1]).contains(row))
            {
                for column in 0..c[0] {
                    let cell = [column, row.rem_euclid(c[1])];
                    if !near.contains(&cell) {
                        near.push(cell);
                    }
                }
            }
        }
        for cell in near {
            for &j in grid.get(&cell).map(Vec::as_slice).unwrap_or(&[]) {
                if j > i {
                    f(i, j);
                }
            }
        }
    }
}

/// Records disc `i`'s wall `hits` (of mass `m`) in `impulse`, and rough walls' friction on it.
fn rub(
    p: &mut Particles,
    i: usize,
    hits: [f64; 4],
    m: f64,
    rubbing: Option<Rough>,
    impulse: &mut WallSums,
) {
    impulse.add(hits);
    if let Some(rough) = &rubbing
        && hits != [0.0; 4]
    {
        let mut v = [p.vx[i], p.vy[i]];
        let work = rub_walls(hits, &mut v, &mut p.omega[i], p.radius[i], m, rough);
        impulse.friction.add(work);
        [p.vx[i], p.vy[i]] = v;
    }
}

/// The walls as contacts: each disc touching a wall and moving into it bounces.
fn walls_as_contacts(p: &mut Particles, rules: &Rules) -> WallSums {
    let mut impulse = WallSums::default();
    let Geometry::Walls {
        min,
        max,
        restitution: e,
    } = rules.geometry
    else {
        return impulse;
    };
    let e = rules.law.restitution_of(e);
    let rubbing = rules.law.rough.filter(|rough| rough.rubs_walls());
    for i in 0..p.len() {
        let (r, m) = (p.radius[i], rules.mass(p, i));
        let [left, right] = touch_walls(p.x[i], &mut p.vx[i], r, m, min[0], max[0], e);
        let [bottom, top] = touch_walls(p.y[i], &mut p.vy[i], r, m, min[1], max[1], e);
        rub(p, i, [left, right, bottom, top], m, rubbing, &mut impulse);
    }
    impulse
}

/// Each disc alone against every obstacle: first put back on its side of any segment its
/// centre crossed since `trail`, then pushed out and bounced by each obstacle it touches
/// (the fixed ones, then the moving ones, in the frame of each), then held inside the walls.
/// `trail` becomes the new positions.
fn meet_obstacles(
    p: &mut Particles,
    mut trail: Option<&mut [[f64; 2]]>,
    shapes: &[Shape],
    states: &[ObstacleState],
    rules: &Rules,
) -> Impacts {
    let mut impacts = Impacts::default();
    let law = &rules.law;
    let min_image = rules.geometry.min_image();
    for i in 0..p.len() {
        let start = Disc {
            position: [p.x[i], p.y[i]],
            velocity: [p.vx[i], p.vy[i]],
            radius: p.radius[i],
            mass: rules.mass(p, i),
            omega: p.omega.get(i).copied().unwrap_or(0.0),
        };
        let mut disc = start;
        if let Some(trail) = trail.as_deref() {
            let from = obstacles::path_start(&min_image, trail[i], disc.position);
            for &k in &rules.obstacle_order {
                uncross(&shapes[k], from, &mut disc.position, law.reach(disc.radius));
            }
        }
        for &k in &rules.obstacle_order {
            let u = states[k].velocity;
            let before = disc.velocity;
            let (j, rubbed) = collide(&shapes[k], u, rules.surface[k], law, &mut disc);
            if j != [0.0, 0.0] {
                if rubbed != 0.0 {
                    impacts.friction.add(rubbed);
                }
                impacts.list.push(Impact {
                    obstacle: k as u32,
                    disc: i as u32,
                    momentum: j,
                });
                let dv = [disc.velocity[0] - before[0], disc.velocity[1] - before[1]];
                impacts.work.add(disc.mass * (dv[0] * u[0] + dv[1] * u[1]));
            }
        }
        if disc != start {
            let [mut x, mut y] = disc.position;
            rules.geometry.hold(&mut x, &mut y, disc.radius);
            (p.x[i], p.y[i], p.vx[i], p.vy[i]) = (x, y, disc.velocity[0], disc.velocity[1]);
            if p.turning {
                p.omega[i] = disc.omega;
            }
        }
        if let Some(trail) = trail.as_deref_mut() {
            trail[i] = [p.x[i], p.y[i]];
        }
    }
    impacts
}

/// The seed's steps 1–7 for each contact in the canonical order, one after the other on the
/// current state (a disc pushed by one pair is seen at its new place by the next), walls held
/// after each push. Returns the collision virial, the impacts and the friction work, and with
/// `(tensor, impacts)` the virial tensor's terms and the discs of each impact.
fn resolve_one_after_another(
    p: &mut Particles,
    contacts: &[Contact],
    law: &Law,
    geometry: &Geometry,
    resting_speed: f64,
    (tensor, impacts): (bool, bool),
) -> Resolved {
    let min_image = geometry.min_image();
    let rubs = law.rough.is_some_and(|rough| rough.rubs_pairs());
    let mut resolved = Resolved::new();
    for &Contact { a, b, .. } in contacts {
        let body = |i: usize| Body {
            velocity: [p.vx[i], p.vy[i]],
            radius: p.radius[i],
            mass: law.mass(p.radius[i], p.mass[i]),
            angular_velocity: p.omega.get(i).copied().unwrap_or(0.0),
        };
        let before = [body(a), body(b)];
        let diff = min_image.diff(p.x[a], p.y[a], p.x[b], p.y[b]);
        let image_velocity = min_image.image_velocity(p.y[a], p.y[b]);
        let out = law.resolve_seen(diff, &before[0], &before[1], image_velocity);
        // The virial takes the pair's impulse (the law's: half of a's momentum change less
        // half of b's).
        let (virial, terms) = virial_terms(diff, out.impulse(&before[0], &before[1]));
        resolved.virial.add(virial);
        if tensor {
            for (sum, term) in resolved.tensor.iter_mut().zip(terms) {
                sum.add(term);
            }
        }
        if is_impact(out.approach, resting_speed) {
            resolved.impacts += 1;
            if impacts {
                resolved.collided.extend([p.id[a].0, p.id[b].0]);
            }
        }
        if rubs {
            resolved.friction.add(out.friction_work);
        }
        // Half the overlap each way, then back inside the walls.
        for (i, sign) in [(a, 1.0), (b, -1.0)] {
            p.x[i] += sign * out.push[0];
            p.y[i] += sign * out.push[1];
            let (mut x, mut y) = (p.x[i], p.y[i]);
            geometry.hold(&mut x, &mut y, p.radius[i]);
            (p.x[i], p.y[i]) = (x, y);
        }
        [p.vx[a], p.vy[a]] = out.v1;
        [p.vx[b], p.vy[b]] = out.v2;
        if rubs {
            (p.omega[a], p.omega[b]) = (out.w1, out.w2);
        }
    }
    resolved
}
