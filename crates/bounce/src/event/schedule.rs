//! What a disc meets next: from its state at an event, its earliest crossing of a cell
//! side, wall, collision with a disc near it and contact with an obstacle near it, into its
//! slot in the calendar.

use crate::config::Shape;
use crate::law::reach_of;

use super::predict::{contact_time, fall_to, point_contact, rise_to};
use super::{EventDriven, Kind, NOTHING, Next, sub};

impl EventDriven {
    /// Calls `f` with every disc `i` may meet before it leaves its cell (`i` itself
    /// included): an ordinary disc, the discs listed in the 3 × 3 cells around it; a large
    /// one, those in the cells its reach spans; both, every large disc.
    #[inline]
    pub(super) fn for_each_near(&self, i: usize, mut f: impl FnMut(usize)) {
        let cell = self.grid.cell[i];
        match self.d[i].span {
            0 => self.grid.for_each_near(cell, &mut f),
            span => self.grid.for_each_within(cell, span, &mut f),
        }
        for &j in &self.large {
            f(j as usize);
        }
    }

    /// Predicts disc `i`'s next event from its state now (its `time` is now) and puts it in
    /// its slot: its crossing, a wall, a disc near, an obstacle near, whichever first.
    pub(super) fn predict(&mut self, i: usize) {
        let t = self.now;
        let (x, v, g, r) = (self.d[i].x, self.d[i].v, self.gravity, self.d[i].radius);
        let mut best = (f64::INFINITY, NOTHING);
        let cell = self.grid.cell[i];
        for a in 0..2 {
            let (lo, hi) = self.grid.sides(cell, a);
            let event = |side: u8| Next {
                kind: Kind::Cross,
                side: 2 * a as u8 + side,
                ..NOTHING
            };
            if lo.is_finite() {
                offer(&mut best, fall_to(x[a] - lo, v[a], g[a]), event(1));
            }
            if hi.is_finite() {
                offer(&mut best, rise_to(x[a] - hi, v[a], g[a]), event(0));
            }
        }
        if self.walls.is_some() {
            for a in 0..2 {
                let (lo, hi) = (self.min[a] + r, self.min[a] + self.size[a] - r);
                let event = |side: u8| Next {
                    kind: Kind::Wall,
                    side: 2 * a as u8 + side,
                    ..NOTHING
                };
                offer(&mut best, fall_to(x[a] - lo, v[a], g[a]), event(1));
                offer(&mut best, rise_to(x[a] - hi, v[a], g[a]), event(0));
            }
        }
        let grid = &self.grid;
        self.for_each_near(i, |j| {
            if j == i {
                return;
            }
            // Relative motion is linear: gravity pulls both alike.
            let dt = t - self.d[j].time;
            let xj = [
                self.d[j].x[0] + (self.d[j].v[0] + 0.5 * g[0] * dt) * dt,
                self.d[j].x[1] + (self.d[j].v[1] + 0.5 * g[1] * dt) * dt,
            ];
            let vj = [self.d[j].v[0] + g[0] * dt, self.d[j].v[1] + g[1] * dt];
            let dr = self.min_image.diff(x[0], x[1], xj[0], xj[1]);
            let dv = [v[0] - vj[0], v[1] - vj[1]];
            let sigma = self.law.collision_distance(r, self.d[j].radius);
            offer(
                &mut best,
                contact_time(dr, dv, sigma),
                Next {
                    kind: Kind::Pair,
                    side: 0,
                    partner: j as u32,
                    partner_count: self.d[j].count,
                },
            );
        });
        for &k in grid.obstacles_near(cell) {
            let dt = self.obstacle_time(i, &self.shapes[k as usize], best.0);
            offer(
                &mut best,
                dt,
                Next {
                    kind: Kind::Obstacle,
                    partner: k,
                    ..NOTHING
                },
            );
        }
        self.next[i] = best.1;
        self.calendar.set(i, t + best.0);
    }

    /// When disc `i` (at its state now) first meets `shape` within `horizon`: a peg as a
    /// point at the sum of the reaches, a segment on either face (where its foot is on the
    /// segment) or at an end.
    pub(super) fn obstacle_time(&self, i: usize, shape: &Shape, horizon: f64) -> Option<f64> {
        let (x, v, g) = (self.d[i].x, self.d[i].v, self.gravity);
        let sigma = reach_of(shape, self.d[i].radius, &self.law);
        match *shape {
            Shape::Peg { centre, .. } => point_contact(sub(x, centre), v, g, sigma, horizon),
            Shape::Segment { a, b } => {
                let ab = sub(b, a);
                let length = ab[0].hypot(ab[1]);
                let n = [-ab[1] / length, ab[0] / length];
                let dot = |p: [f64; 2], q: [f64; 2]| p[0] * q[0] + p[1] * q[1];
                // The signed distance from the line moves on a parabola.
                let (s, sv, sg) = (dot(sub(x, a), n), dot(v, n), dot(g, n));
                // The face on the disc's side only: a disc beyond an end, within σ of the
                // line, meets that end first.
                let face = if s >= 0.0 {
                    fall_to(s - sigma, sv, sg)
                } else {
                    rise_to(s + sigma, sv, sg)
                };
                let face = face
                    .into_iter()
                    .filter(|&dt| {
                        let foot = dot(sub(self.at_offset(i, dt), a), ab) / (length * length);
                        (0.0..=1.0).contains(&foot)
                    })
                    .fold(f64::INFINITY, f64::min);
                let horizon = horizon.min(face);
                let end = [a, b]
                    .into_iter()
                    .filter_map(|p| point_contact(sub(x, p), v, g, sigma, horizon))
                    .fold(f64::INFINITY, f64::min);
                let first = face.min(end);
                first.is_finite().then_some(first)
            }
        }
    }

    /// Disc `i`'s centre `dt` after its `time`.
    pub(super) fn at_offset(&self, i: usize, dt: f64) -> [f64; 2] {
        self.at(i, self.d[i].time + dt)
    }
}

/// Keeps `next` at `dt` in `best` if it comes first.
#[inline]
fn offer(best: &mut (f64, Next), dt: Option<f64>, next: Next) {
    if let Some(dt) = dt
        && dt < best.0
    {
        *best = (dt, next);
    }
}
