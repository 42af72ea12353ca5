//! Contact events: which contacts began and which ended in each substep, with the parties,
//! the contact point, the normal, the impulses and the approach speed, for a front end to
//! read after the step ([`crate::World::contact_events`]), as Box2D v3 reports them.
//!
//! A contact is *detected* in a substep when the law finds the pair colliding (any solver
//! pass), or when a wall or an obstacle acts on the disc (its bounce or push changes the
//! disc's velocity). A contact detected in a substep and not in the one before *begins*; one
//! detected in the one before and not in this one *ends*. The contacts of the last substep
//! are part of the world's saved state, so a loaded world reports what the original does.
//!
//! Each substep's events come in the order of their parties' ids (the lower-id disc, then
//! the other party: a disc, a wall, an obstacle), which no thread count, storage order or
//! rank count changes. The stages report what they saw ([`ContactLog::see`]); nothing here
//! runs unless the configuration asks for events.

use serde::{Deserialize, Serialize};

use crate::config::Shape;
use crate::geometry::Geometry;
use crate::law::{COINCIDENT_NORMAL, Law, nearest};
use crate::obstacles::Impacts;
use crate::part::Tally;
use crate::particles::{ParticleId, Particles};
use crate::resolve::PairResolved;

/// Whether a contact began or ended. See [`ContactEvent`] for an example.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactKind {
    /// Detected in this substep, not in the one before.
    Begin,
    /// Detected in the substep before, not in this one.
    End,
}

impl ContactKind {
    /// `"begin"` or `"end"`. See [`ContactEvent`] for an example.
    pub fn name(self) -> &'static str {
        match self {
            ContactKind::Begin => "begin",
            ContactKind::End => "end",
        }
    }
}

/// One of the box's four walls. See [`ContactEvent`] for an example.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WallSide {
    /// `x = min[0]`.
    Left,
    /// `x = max[0]`.
    Right,
    /// `y = min[1]`.
    Bottom,
    /// `y = max[1]`.
    Top,
}

impl WallSide {
    /// Left, right, bottom, top.
    ///
    /// ```
    /// use bounce::WallSide;
    /// assert_eq!(WallSide::ALL.map(|w| w.name()), ["left", "right", "bottom", "top"]);
    /// ```
    pub const ALL: [WallSide; 4] = [
        WallSide::Left,
        WallSide::Right,
        WallSide::Bottom,
        WallSide::Top,
    ];

    /// `"left"`, `"right"`, `"bottom"` or `"top"`. See [`ContactEvent`] for an example.
    pub fn name(self) -> &'static str {
        match self {
            WallSide::Left => "left",
            WallSide::Right => "right",
            WallSide::Bottom => "bottom",
            WallSide::Top => "top",
        }
    }

    /// The wall's unit normal out of the box (from a disc into the wall). See
    /// [`ContactEvent`] for an example.
    pub fn outward(self) -> [f64; 2] {
        match self {
            WallSide::Left => [-1.0, 0.0],
            WallSide::Right => [1.0, 0.0],
            WallSide::Bottom => [0.0, -1.0],
            WallSide::Top => [0.0, 1.0],
        }
    }
}

/// The second party of a contact; the first is always a disc. See [`ContactEvent`] for an
/// example.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Party {
    /// Another disc, of a higher id than the first.
    Disc(ParticleId),
    /// A wall of the box.
    Wall(WallSide),
    /// An obstacle, by its index in [`crate::Config::obstacles`].
    Obstacle(u32),
}

/// A contact that began or ended in a substep ([`crate::World::contact_events`]).
///
/// The normal points from the disc `a` towards `b` (into the wall, into the obstacle). The
/// impulses are what `b` gave `a` over the substep: `normal_impulse` along `-normal` (so
/// positive when they push apart), `tangent_impulse` along `[-normal[1], normal[0]]` (non-zero
/// only for rough discs, up to rounding). For a pair the impulse is the antisymmetric part of
/// the two momentum changes, `(m_a Δv_a − m_b Δv_b) / 2`, which is the impulse itself when the
/// model conserves momentum. `approach_speed` is how fast `a` moved towards `b` along the
/// normal before (negative when they were separating). An `end` event carries the point
/// and normal of the contact's last substep and no impulse or speed.
///
/// ```
/// use bounce::{Boundary, Config, ContactKind, Party, Particle, WallSide, World};
/// let mut world = World::new(Config {
///     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
///     contact_events: true,
///     ..Config::default()
/// })?;
/// // Mass 1 at speed 2 into the right wall: the wall gives it an impulse of 4.
/// world.add_particle(Particle::new([8.5, 5.0], [2.0, 0.0], 1.0))?;
/// world.step(0.5)?;
/// let e = world.contact_events()[0];
/// assert_eq!((e.kind, e.b), (ContactKind::Begin, Party::Wall(WallSide::Right)));
/// assert_eq!((e.kind.name(), e.b, WallSide::Right.name()), ("begin", e.b, "right"));
/// assert_eq!((e.point, e.normal), ([10.0, 5.0], WallSide::Right.outward()));
/// assert_eq!((e.normal_impulse, e.approach_speed), (4.0, 2.0));
/// assert_eq!(e.numbers(), [10.0, 5.0, 1.0, 0.0, 4.0, 0.0, 2.0]);
/// assert_eq!(e.time(world.time(), 0.5, 1), 0.5); // its substep ended with the step
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactEvent {
    /// Began or ended.
    pub kind: ContactKind,
    /// The substep of the step it happened in, from 0.
    pub substep: u32,
    /// The disc (the lower id of a pair).
    pub a: ParticleId,
    /// What it touched.
    pub b: Party,
    /// Where they touch: on the line between the centres, at `r_a / (r_a + r_b)` of the way
    /// from `a` (for a pair); the nearest point of the wall or the obstacle.
    pub point: [f64; 2],
    /// The unit normal from `a` towards `b`.
    pub normal: [f64; 2],
    /// The impulse along `-normal` (0 for `end`).
    pub normal_impulse: f64,
    /// The impulse along the tangent `[-normal[1], normal[0]]` (0 for `end`).
    pub tangent_impulse: f64,
    /// How fast `a` approached `b` along the normal before (0 for `end`).
    pub approach_speed: f64,
}

impl ContactEvent {
    /// When its substep ended, in a step of `dt` in `substeps` that ended at `step_end`
    /// (`World::time()` after the step). See [`ContactEvent`] for an example.
    pub fn time(&self, step_end: f64, dt: f64, substeps: u32) -> f64 {
        let substeps = substeps.max(1);
        let left = substeps.saturating_sub(1 + self.substep) as f64;
        step_end - dt * left / substeps as f64
    }

    /// Its numbers in `events.csv`'s order: the point (x, y), the normal (x, y), the normal
    /// and tangential impulses and the approach speed. See [`ContactEvent`] for an example.
    pub fn numbers(&self) -> [f64; 7] {
        [
            self.point[0],
            self.point[1],
            self.normal[0],
            self.normal[1],
            self.normal_impulse,
            self.tangent_impulse,
            self.approach_speed,
        ]
    }
}

/// A contact of the last substep, as the next one needs it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Touch {
    a: ParticleId,
    b: Party,
    point: [f64; 2],
    normal: [f64; 2],
    /// Its `begin` was reported (over the threshold), so its `end` will be.
    reported: bool,
}

/// The contacts of the last substep, and the events of the last step: what turns the
/// contacts seen in each substep into `begin` and `end` events. Every [`crate::World`] keeps
/// one; a distributed run keeps the whole world's on one rank, fed with the parts' sightings
/// ([`crate::World::take_contact_sightings`], [`ContactLog::record_step`]). See
/// [`ContactLog::record_step`] for an example.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct ContactLog {
    /// The last substep's contacts, by `(a, b)`.
    touching: Vec<Touch>,
    /// The last step's events.
    #[serde(skip)]
    events: Vec<ContactEvent>,
    /// What the stages saw in this substep (`kind` unused until the substep ends).
    #[serde(skip)]
    seen: Vec<ContactEvent>,
    /// The discs' velocities before a stage that walls act in, in storage order.
    #[serde(skip)]
    before: Vec<[f64; 2]>,
    /// In a part of a distributed world: the contacts this part counts (by the place of
    /// their disc `a`), each with its substep, not yet compared with anything.
    #[serde(skip)]
    tally: Option<Tally>,
    #[serde(skip)]
    sightings: Vec<(u32, ContactEvent)>,
}

impl ContactLog {
    /// An empty log. See [`ContactLog::record_step`] for an example.
    pub fn new() -> ContactLog {
        ContactLog::default()
    }

    /// The last step's events, substep by substep, each substep's by `(a, b)`. See
    /// [`ContactLog::record_step`] for an example.
    pub fn events(&self) -> &[ContactEvent] {
        &self.events
    }

    /// A step of `substeps` from the contacts its parts saw (each with its substep; in any
    /// order of the parts, each part's own order kept): the events, exactly as one world's
    /// log gives them.
    ///
    /// ```
    /// use bounce::{ContactEvent, ContactKind, ContactLog, Party, ParticleId};
    /// let seen = ContactEvent {
    ///     kind: ContactKind::Begin,
    ///     substep: 0,
    ///     a: ParticleId(3),
    ///     b: Party::Disc(ParticleId(8)),
    ///     point: [1.0, 2.0],
    ///     normal: [1.0, 0.0],
    ///     normal_impulse: 0.5,
    ///     tangent_impulse: 0.0,
    ///     approach_speed: 1.0,
    /// };
    /// let mut log = ContactLog::new();
    /// log.record_step(vec![(0, seen)], 1, 0.0); // seen: it begins
    /// assert_eq!(log.events()[0].kind, ContactKind::Begin);
    /// log.record_step(Vec::new(), 1, 0.0); // not seen: it ends
    /// assert_eq!((log.events()[0].kind, log.events()[0].point), (ContactKind::End, [1.0, 2.0]));
    /// ```
    pub fn record_step(
        &mut self,
        mut sightings: Vec<(u32, ContactEvent)>,
        substeps: u32,
        threshold: f64,
    ) {
        self.start_step(None);
        sightings.sort_by_key(|(substep, s)| (*substep, s.a, s.b));
        let mut rest = &sightings[..];
        for substep in 0..substeps {
            let n = rest.iter().take_while(|(k, _)| *k == substep).count();
            self.seen.extend(rest[..n].iter().map(|(_, s)| *s));
            rest = &rest[n..];
            self.end_substep(substep, threshold);
        }
    }

    /// The contacts this part saw in its last step, for [`ContactLog::record_step`].
    pub(crate) fn take_sightings(&mut self) -> Vec<(u32, ContactEvent)> {
        std::mem::take(&mut self.sightings)
    }

    /// The contacts of the last substep.
    pub(crate) fn touching(&self) -> usize {
        self.touching.len()
    }

    /// What is wrong with a loaded log, if anything: contacts out of order or repeated, an
    /// id not below `next_id`, a point or normal not finite.
    pub(crate) fn problem(&self, next_id: u32) -> Option<String> {
        for (k, t) in self.touching.iter().enumerate() {
            let ids_ok =
                t.a.0 < next_id && !matches!(t.b, Party::Disc(b) if b.0 >= next_id || b <= t.a);
            if !ids_ok {
                return Some(format!(
                    "contact {k} ({:?}, {:?}) names an unknown disc",
                    t.a, t.b
                ));
            }
            if !t.point.iter().chain(&t.normal).all(|v| v.is_finite()) {
                return Some(format!("contact {k}: point or normal not finite"));
            }
            if k > 0 && (self.touching[k - 1].a, self.touching[k - 1].b) >= (t.a, t.b) {
                return Some(format!("contact {k} out of order"));
            }
        }
        None
    }

    /// A step begins: the last one's events are forgotten. With `tally` (a part of a
    /// distributed world) the substeps' contacts are kept as sightings instead.
    pub(crate) fn start_step(&mut self, tally: Option<Tally>) {
        self.events.clear();
        self.seen.clear();
        self.sightings.clear();
        self.tally = tally;
    }

    /// A substep ends: what was seen is compared with the substep before, the contacts that
    /// began (with a normal impulse of at least `threshold`) and those that ended (whose
    /// begin was reported) become events.
    pub(crate) fn end_substep(&mut self, substep: u32, threshold: f64) {
        if self.tally.is_some() {
            let seen = std::mem::take(&mut self.seen);
            self.sightings
                .extend(seen.into_iter().map(|s| (substep, s)));
            return;
        }
        let mut seen = std::mem::take(&mut self.seen);
        seen.sort_by_key(|s| (s.a, s.b));
        // One contact seen several times (a pair in several passes, a wall at the
        // integration and as a contact): the impulses add, the first sight's geometry and
        // approach stay.
        let mut now: Vec<ContactEvent> = Vec::with_capacity(seen.len());
        for s in seen {
            match now.last_mut() {
                Some(last) if (last.a, last.b) == (s.a, s.b) => {
                    last.normal_impulse += s.normal_impulse;
                    last.tangent_impulse += s.tangent_impulse;
                }
                _ => now.push(s),
            }
        }
        let before = std::mem::take(&mut self.touching);
        let mut touching = Vec::with_capacity(now.len());
        let (mut old, mut new) = (before.iter().peekable(), now.iter().peekable());
        loop {
            let order = match (old.peek(), new.peek()) {
                (None, None) => break,
                (Some(_), None) => std::cmp::Ordering::Less,
                (None, Some(_)) => std::cmp::Ordering::Greater,
                (Some(o), Some(n)) => (o.a, o.b).cmp(&(n.a, n.b)),
            };
            match order {
                std::cmp::Ordering::Less => {
                    let o = old.next().expect("peeked");
                    if o.reported {
                        self.events.push(ContactEvent {
                            kind: ContactKind::End,
                            substep,
                            a: o.a,
                            b: o.b,
                            point: o.point,
                            normal: o.normal,
                            normal_impulse: 0.0,
                            tangent_impulse: 0.0,
                            approach_speed: 0.0,
                        });
                    }
                }
                std::cmp::Ordering::Greater => {
                    let n = new.next().expect("peeked");
                    let reported = n.normal_impulse >= threshold;
                    if reported {
                        self.events.push(ContactEvent { substep, ..*n });
                    }
                    touching.push(Touch::of(n, reported));
                }
                std::cmp::Ordering::Equal => {
                    let o = old.next().expect("peeked");
                    let n = new.next().expect("peeked");
                    touching.push(Touch::of(n, o.reported));
                }
            }
        }
        self.touching = touching;
    }

    /// A pair the solver resolved.
    pub(crate) fn see_pair(&mut self, p: &Particles, pair: &PairResolved) {
        let PairResolved {
            a,
            b,
            diff,
            at,
            before,
            out,
        } = pair;
        // The law's difference is `x_a - x_b`: the normal towards `b` is its opposite.
        let d = (diff[0] * diff[0] + diff[1] * diff[1]).sqrt();
        let normal = if d > 0.0 {
            [-diff[0] / d, -diff[1] / d]
        } else {
            [-COINCIDENT_NORMAL[0], -COINCIDENT_NORMAL[1]]
        };
        let [one, two] = before;
        let impulse = out.impulse(one, two);
        if self.tally.is_some_and(|t| !t.counts(at[0], at[1])) {
            return;
        }
        let share = one.radius / (one.radius + two.radius);
        let relative = [0, 1].map(|k| one.velocity[k] - two.velocity[k]);
        self.see(
            p.id[*a],
            Party::Disc(p.id[*b]),
            [at[0] - diff[0] * share, at[1] - diff[1] * share],
            normal,
            impulse,
            dot(relative, normal),
        );
    }

    /// Notes the discs' velocities before a stage that the walls act in (walls only).
    pub(crate) fn before_walls(&mut self, p: &Particles, geometry: &Geometry) {
        if matches!(geometry, Geometry::Walls { .. }) {
            self.before.clear();
            self.before
                .extend(p.vx.iter().zip(&p.vy).map(|(&vx, &vy)| [vx, vy]));
        }
    }

    /// The walls that acted on a disc since [`ContactLog::before_walls`]: those the disc
    /// touches (its centre within its radius) whose normal velocity changed from what
    /// the stage's free flight gave (`gravity_h`, `g h` for the integration, zero
    /// otherwise). A disc in a corner gets each wall's normal impulse and no tangential one.
    pub(crate) fn see_walls(
        &mut self,
        p: &Particles,
        geometry: &Geometry,
        law: &Law,
        gravity_h: [f64; 2],
    ) {
        let Geometry::Walls { min, max, .. } = *geometry else {
            return;
        };
        for i in 0..p.len() {
            let [vx0, vy0] = self.before[i];
            // The stage's own arithmetic for the free flight, so an untouched disc matches.
            let free = [vx0 + gravity_h[0], vy0 + gravity_h[1]];
            let now = [p.vx[i], p.vy[i]];
            if now == free {
                continue;
            }
            let (x, y, r) = (p.x[i], p.y[i], p.radius[i]);
            if self.tally.is_some_and(|t| !t.counts(x, y)) {
                continue;
            }
            let touches = [
                x <= min[0] + r,
                x >= max[0] - r,
                y <= min[1] + r,
                y >= max[1] - r,
            ];
            let hit = |side: usize| touches[side] && now[side / 2] != free[side / 2];
            let m = law.mass(r, p.mass[i]);
            for (k, side) in WallSide::ALL.into_iter().enumerate() {
                if !hit(k) {
                    continue;
                }
                let axis = k / 2;
                let across = 1 - axis;
                let cornered = hit(2 * across) || hit(2 * across + 1);
                let mut impulse = [0.0; 2];
                impulse[axis] = m * (now[axis] - free[axis]);
                if !cornered {
                    impulse[across] = m * (now[across] - free[across]);
                }
                let normal = side.outward();
                let mut point = [x, y];
                point[axis] = if k % 2 == 0 { min[axis] } else { max[axis] };
                self.see(
                    p.id[i],
                    Party::Wall(side),
                    point,
                    normal,
                    impulse,
                    dot(free, normal),
                );
            }
        }
    }

    /// The obstacles' impacts of an obstacle pass (`shapes` the obstacles in the step's
    /// form, `velocities` how fast each moves).
    pub(crate) fn see_obstacles(
        &mut self,
        p: &Particles,
        impacts: &Impacts,
        shapes: &[Shape],
        velocities: impl Fn(usize) -> [f64; 2],
    ) {
        for (hit, approach) in impacts.list.iter().zip(&impacts.approaches) {
            let o = hit.obstacle as usize;
            let (mut q, _) = nearest(&shapes[o], approach.position);
            let toward = [q[0] - approach.position[0], q[1] - approach.position[1]];
            let d = (toward[0] * toward[0] + toward[1] * toward[1]).sqrt();
            let j = hit.momentum;
            let jd = (j[0] * j[0] + j[1] * j[1]).sqrt();
            // On the obstacle itself the normal is the way the disc was pushed back.
            let normal = if d > 0.0 {
                [toward[0] / d, toward[1] / d]
            } else {
                [j[0] / jd, j[1] / jd]
            };
            if let Shape::Peg { radius, .. } = shapes[o] {
                // The peg's edge, not its centre.
                q = [q[0] - normal[0] * radius, q[1] - normal[1] * radius];
            }
            let u = velocities(o);
            let relative = [approach.velocity[0] - u[0], approach.velocity[1] - u[1]];
            self.see(
                p.id[hit.disc as usize],
                Party::Obstacle(hit.obstacle),
                q,
                normal,
                [-j[0], -j[1]],
                dot(relative, normal),
            );
        }
    }

    /// A contact of this substep: `impulse` is what `a` received.
    fn see(
        &mut self,
        a: ParticleId,
        b: Party,
        point: [f64; 2],
        normal: [f64; 2],
        impulse: [f64; 2],
        approach_speed: f64,
    ) {
        let tangent = [-normal[1], normal[0]];
        self.seen.push(ContactEvent {
            kind: ContactKind::Begin,
            substep: 0,
            a,
            b,
            point,
            normal,
            normal_impulse: -dot(impulse, normal),
            tangent_impulse: dot(impulse, tangent),
            approach_speed,
        });
    }
}

impl Touch {
    fn of(event: &ContactEvent, reported: bool) -> Touch {
        Touch {
            a: event.a,
            b: event.b,
            point: event.point,
            normal: event.normal,
            reported,
        }
    }
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
