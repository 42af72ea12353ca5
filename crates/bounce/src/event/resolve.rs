//! What each event does: a crossing moves a disc to the next cell, a wall or an obstacle
//! turns its normal velocity back (scaled by the restitution), and two discs get the law's
//! velocity update at contact, with the TC model's elastic law within the contact duration.

use crate::law::{Body, Law, nearest, resolve_pair, virial_terms};

use super::{EventDriven, sub};

impl EventDriven {
    /// The law a collision of discs whose last collisions were at `last` takes at now: the
    /// elastic one within the contact duration (the TC model).
    pub(super) fn law_for(&self, last: f64) -> &Law {
        if self.now - last < self.contact_duration {
            &self.elastic
        } else {
            &self.law
        }
    }

    /// Disc `i` crosses side `side` of its cell now: into the next cell (wrapping, with its
    /// centre, across a periodic box). Its velocity is the same, so its count too.
    pub(super) fn cross(&mut self, i: usize, side: u8) {
        self.bring(i);
        let (cell, shift) = self.grid.beyond(self.grid.cell[i], side);
        if shift != 0 {
            let axis = (side / 2) as usize;
            self.d[i].x[axis] += shift as f64 * self.size[axis];
            self.image[i][axis] -= shift;
        }
        if self.d[i].span == 0 {
            self.grid.remove(i);
            self.grid.insert(i, cell);
        } else {
            self.grid.place(i, cell);
        }
        self.predict(i);
    }

    /// Disc `i` meets wall `side` now: put exactly at it (round-off), its normal velocity
    /// reversed and scaled by the walls' restitution, the momentum recorded.
    pub(super) fn bounce(&mut self, i: usize, side: u8) {
        self.bring(i);
        let axis = (side / 2) as usize;
        let r = self.d[i].radius;
        self.d[i].x[axis] = if side % 2 == 1 {
            self.min[axis] + r
        } else {
            self.min[axis] + self.size[axis] - r
        };
        let elastic = self.now - self.last[i] < self.contact_duration;
        let e = if elastic {
            1.0
        } else {
            self.walls.expect("walls")
        };
        let v = self.d[i].v[axis];
        let after = -e * v;
        // The wall's side in `Observed` order: left, right, bottom, top.
        let wall = 2 * axis + side.is_multiple_of(2) as usize;
        self.observed.wall_impulse[wall] += self.d[i].mass * (after - v).abs();
        self.d[i].v[axis] = after;
        self.d[i].count = self.d[i].count.wrapping_add(1);
        self.last[i] = self.now;
        self.predict(i);
    }

    /// Disc `i` meets obstacle `k` now: the obstacle's rule (the law's `collide`) at contact.
    pub(super) fn meet(&mut self, i: usize, k: usize) {
        self.bring(i);
        let e = if self.now - self.last[i] < self.contact_duration {
            1.0
        } else {
            self.obstacle_restitution[k]
        };
        // The obstacle's rule (see `law::obstacle`) at contact, where there is no overlap
        // to push out: the normal velocity, if it moves in, reversed and scaled.
        let (q, _) = nearest(&self.shapes[k], self.d[i].x);
        let d = sub(self.d[i].x, q);
        let distance = d[0].hypot(d[1]);
        if distance > 0.0 {
            let n = [d[0] / distance, d[1] / distance];
            let vn = self.d[i].v[0] * n[0] + self.d[i].v[1] * n[1];
            if vn < 0.0 {
                let dv = -(1.0 + self.law.restitution_of(e).at(-vn)) * vn;
                self.d[i].v[0] += dv * n[0];
                self.d[i].v[1] += dv * n[1];
                let impulse = &mut self.observed.obstacle_impulses[k];
                impulse[0] -= self.d[i].mass * dv * n[0];
                impulse[1] -= self.d[i].mass * dv * n[1];
            }
        }
        self.d[i].count = self.d[i].count.wrapping_add(1);
        self.last[i] = self.now;
        self.predict(i);
    }

    /// Discs `a` and `b` meet now: the law's velocity update at contact.
    pub(super) fn collide(&mut self, a: usize, b: usize) {
        self.bring(a);
        self.bring(b);
        let diff = self.min_image.diff(
            self.d[a].x[0],
            self.d[a].x[1],
            self.d[b].x[0],
            self.d[b].x[1],
        );
        let body = |i: usize| Body::new(self.d[i].v, self.d[i].radius, self.d[i].mass);
        let (one, two) = (body(a), body(b));
        let law = self.law_for(self.last[a].max(self.last[b]));
        let out = resolve_pair(diff, &one, &two, law);
        let (virial, terms) = virial_terms(diff, out.impulse(&one, &two));
        self.observed.virial += virial;
        for (sum, term) in self.observed.virial_tensor.iter_mut().zip(terms) {
            *sum += term;
        }
        self.observed.collisions += 1;
        if self.count_collisions {
            let ids = [self.order[a], self.order[b]];
            self.observed.collided.extend(ids);
        }
        (self.d[a].v, self.d[b].v) = (out.v1, out.v2);
        for i in [a, b] {
            self.d[i].count = self.d[i].count.wrapping_add(1);
            self.last[i] = self.now;
        }
        self.predict(a);
        self.predict(b);
    }
}
