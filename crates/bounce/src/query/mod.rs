//! Spatial queries over a snapshot of the discs: the discs overlapping a circle or a box,
//! the disc nearest a point, the first disc a ray enters ([`Queries`], from
//! [`crate::World::queries`]).
//!
//! A snapshot copies the centres, radii and ids and bins them once in a uniform grid
//! (O(N)); each query then looks only at the cells it can reach, so a game asking a few
//! hundred questions a frame pays for one binning. Cells are at least a disc across; in a
//! box with walls or an open world, discs wider than a cell (a Brownian particle among
//! small ones) are kept aside and tested by every query. In a periodic box the cells tile
//! the box exactly, distances are minimum images (regions up to half the box across), and a
//! ray goes on through the box's copies (in a Lees–Edwards box, the copies above and below
//! slid along x by the current offset). Results are in id order (ties to the lower id), so
//! they do not depend on the storage order or the thread count.

use crate::geometry::Geometry;
use crate::particles::{ParticleId, Particles};

mod ray;

use ray::{Walk, entry};

/// The first disc a ray enters. See [`Queries::ray_cast`] for an example.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The disc.
    pub id: ParticleId,
    /// How far along the ray, in units of the direction's length.
    pub fraction: f64,
    /// Where the ray enters it (unwrapped: in a periodic box, possibly outside the box).
    pub point: [f64; 2],
    /// The disc's outward unit normal there.
    pub normal: [f64; 2],
}

/// A snapshot of the discs binned for spatial queries. See the [module docs](self), and
/// [`crate::World::queries`] for an example.
#[derive(Clone, Debug)]
pub struct Queries {
    x: Vec<f64>,
    y: Vec<f64>,
    radius: Vec<f64>,
    id: Vec<ParticleId>,
    /// The grid's lower-left corner, cell size and cells across.
    origin: [f64; 2],
    width: [f64; 2],
    cells: [i64; 2],
    /// Each cell's discs: `items[start[c]..start[c + 1]]`, ascending.
    start: Vec<u32>,
    items: Vec<u32>,
    /// Discs wider than a cell, tested by every query.
    large: Vec<u32>,
    /// The box's size when periodic.
    period: Option<[f64; 2]>,
    /// How far along x the copy of the box above stands, in a Lees–Edwards box (else 0).
    slide: f64,
}

impl Queries {
    /// Bins the discs of `p` for `geometry`.
    pub(crate) fn new(p: &Particles, geometry: &Geometry) -> Queries {
        let n = p.len();
        let mut sorted_radii = p.radius.clone();
        sorted_radii.sort_unstable_by(f64::total_cmp);
        let typical = sorted_radii.get(n / 2).copied().unwrap_or(0.5);
        let largest = sorted_radii.last().copied().unwrap_or(0.5);
        let period = match *geometry {
            Geometry::Periodic { size, .. } => Some(size),
            _ => None,
        };
        let (lo, hi) = match geometry.bounds() {
            Some(bounds) => bounds,
            None => {
                let fold =
                    |v: &[f64], f: fn(f64, f64) -> f64, start| v.iter().copied().fold(start, f);
                let lo = [
                    fold(&p.x, f64::min, f64::INFINITY),
                    fold(&p.y, f64::min, f64::INFINITY),
                ];
                let hi = [
                    fold(&p.x, f64::max, f64::NEG_INFINITY),
                    fold(&p.y, f64::max, f64::NEG_INFINITY),
                ];
                if n == 0 {
                    ([0.0; 2], [1.0; 2])
                } else {
                    (lo, [hi[0].max(lo[0] + 1e-9), hi[1].max(lo[1] + 1e-9)])
                }
            }
        };
        let size = [hi[0] - lo[0], hi[1] - lo[1]];
        // About one disc a cell, and a cell at least a typical disc across (every disc in a
        // periodic box, whose images a large list would have to follow).
        let mut h = (size[0] * size[1] / n.max(1) as f64)
            .sqrt()
            .max(2.0 * typical);
        if period.is_some() {
            h = h.max(2.0 * largest);
        }
        let h = if h.is_finite() && h > 0.0 { h } else { 1.0 };
        let cells = size.map(|s| ((s / h).floor() as i64).clamp(1, 1 << 20));
        let width = [size[0] / cells[0] as f64, size[1] / cells[1] as f64];
        let mut out = Queries {
            x: p.x.clone(),
            y: p.y.clone(),
            radius: p.radius.clone(),
            id: p.id.clone(),
            origin: lo,
            width,
            cells,
            start: Vec::new(),
            items: Vec::new(),
            large: Vec::new(),
            period,
            slide: geometry.slide().map_or(0.0, |slide| slide.offset),
        };
        let reach = 0.5 * width[0].min(width[1]);
        let count = (cells[0] * cells[1]) as usize;
        let mut cell_of = vec![u32::MAX; n];
        let mut start = vec![0u32; count + 1];
        for (i, cell) in cell_of.iter_mut().enumerate() {
            if period.is_none() && out.radius[i] > reach {
                out.large.push(i as u32);
                continue;
            }
            let c = out.cell_index(out.cell_at([out.x[i], out.y[i]]));
            *cell = c as u32;
            start[c + 1] += 1;
        }
        for c in 0..count {
            start[c + 1] += start[c];
        }
        let mut next = start.clone();
        let mut items = vec![0u32; start[count] as usize];
        for (i, &c) in cell_of.iter().enumerate() {
            if c != u32::MAX {
                items[next[c as usize] as usize] = i as u32;
                next[c as usize] += 1;
            }
        }
        out.start = start;
        out.items = items;
        out
    }

    /// The discs in the snapshot. See [`crate::World::queries`] for an example.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// Whether the snapshot has no discs. See [`crate::World::queries`] for an example.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// The discs overlapping the circle of `radius` around `centre` (centre distance at most
    /// `radius + r`), by id.
    ///
    /// ```
    /// use bounce::{Boundary, Config, Particle, World};
    /// let mut world = World::new(Config {
    ///     boundary: Boundary::periodic([0.0, 0.0], [10.0, 10.0]),
    ///     ..Config::default()
    /// })?;
    /// let edge = world.add_particle(Particle::new([9.5, 5.0], [0.0, 0.0], 0.4))?;
    /// world.add_particle(Particle::new([5.0, 5.0], [0.0, 0.0], 0.4))?;
    /// // Across the periodic edge: x = 9.5 is 1 from x = 0.5.
    /// assert_eq!(world.queries().in_circle([0.5, 5.0], 0.7), vec![edge]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn in_circle(&self, centre: [f64; 2], radius: f64) -> Vec<ParticleId> {
        let centre = self.wrap(centre);
        let mut out = Vec::new();
        self.around(centre, [radius; 2], |i| {
            let d = self.offset(i, centre);
            let reach = radius + self.radius[i];
            if d[0] * d[0] + d[1] * d[1] <= reach * reach {
                out.push(self.id[i]);
            }
        });
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The discs overlapping the box `[min, max]` (the box's nearest point to the centre at
    /// most `r` away), by id.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// let a = world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 0.5))?;
    /// world.add_particle(Particle::new([3.0, 0.0], [0.0, 0.0], 0.5))?;
    /// // The box's corner (0.3, 0.3) is 0.42 from `a`'s centre: inside its radius.
    /// assert_eq!(world.queries().in_box([0.3, 0.3], [2.0, 2.0]), vec![a]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn in_box(&self, min: [f64; 2], max: [f64; 2]) -> Vec<ParticleId> {
        let centre = self.wrap([0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1])]);
        let half = [0.5 * (max[0] - min[0]), 0.5 * (max[1] - min[1])];
        let mut out = Vec::new();
        self.around(centre, half, |i| {
            let d = self.offset(i, centre);
            let outside = [0, 1].map(|k| (d[k].abs() - half[k]).max(0.0));
            let r = self.radius[i];
            if outside[0] * outside[0] + outside[1] * outside[1] <= r * r {
                out.push(self.id[i]);
            }
        });
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The disc whose edge is nearest `point` and that distance (`|point − centre| − r`,
    /// negative inside); ties to the lower id. `None` without discs.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// world.add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 0.5))?;
    /// let big = world.add_particle(Particle::new([4.0, 0.0], [0.0, 0.0], 2.0))?;
    /// // Nearer the small disc's centre, nearer the big one's edge.
    /// assert_eq!(world.queries().nearest([1.5, 0.0]), Some((big, 0.5)));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn nearest(&self, point: [f64; 2]) -> Option<(ParticleId, f64)> {
        let point = self.wrap(point);
        let mut best: Option<(f64, ParticleId)> = None;
        let consider = |best: &mut Option<(f64, ParticleId)>, i: usize| {
            let d = self.offset(i, point);
            let gap = (d[0] * d[0] + d[1] * d[1]).sqrt() - self.radius[i];
            let candidate = (gap, self.id[i]);
            if best.is_none_or(|b| (candidate.0, candidate.1) < (b.0, b.1)) {
                *best = Some(candidate);
            }
        };
        for &i in &self.large {
            consider(&mut best, i as usize);
        }
        let home = self.cell_at(point);
        let reach = 0.5 * self.width[0].min(self.width[1]);
        let most = self.cells[0].max(self.cells[1]);
        for ring in 0..=most + 1 {
            for cell in ring_cells(home, ring) {
                for (cell, _) in self.images_of(cell).into_iter().flatten() {
                    self.in_cell(cell, |i| consider(&mut best, i));
                }
            }
            // Every disc not yet seen is in a cell outside the rings so far.
            let unseen = self.unseen_distance(point, home, ring);
            if best.is_some_and(|b| b.0 <= unseen - reach) || unseen.is_infinite() {
                break;
            }
        }
        best.map(|(gap, id)| (id, gap))
    }

    /// The first disc the ray from `origin` along `direction` enters within
    /// `max_fraction` of the direction's length (discs containing the origin are not
    /// entered, as in Box2D); ties to the lower id. In a periodic box the ray goes on through
    /// the box's copies, for at most about four crossings of every cell.
    ///
    /// ```
    /// use bounce::{Config, Particle, World};
    /// let mut world = World::new(Config::default())?;
    /// let near = world.add_particle(Particle::new([3.0, 0.0], [0.0, 0.0], 1.0))?;
    /// world.add_particle(Particle::new([8.0, 0.0], [0.0, 0.0], 1.0))?;
    /// // From the origin along +x: the near disc's rim at x = 2, a fifth of the way.
    /// let hit = world.queries().ray_cast([0.0, 0.0], [10.0, 0.0], 1.0).unwrap();
    /// assert_eq!((hit.id, hit.fraction, hit.point), (near, 0.2, [2.0, 0.0]));
    /// // Too short a ray meets nothing.
    /// assert!(world.queries().ray_cast([0.0, 0.0], [10.0, 0.0], 0.1).is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn ray_cast(
        &self,
        origin: [f64; 2],
        direction: [f64; 2],
        max_fraction: f64,
    ) -> Option<RayHit> {
        let length2 = direction[0] * direction[0] + direction[1] * direction[1];
        if !(length2 > 0.0 && max_fraction >= 0.0) || self.is_empty() {
            return None;
        }
        let origin = self.wrap(origin);
        // (The fraction, the id, the disc and its centre's copy.)
        let mut best: Option<(f64, ParticleId, usize, [f64; 2])> = None;
        let test =
            |best: &mut Option<(f64, ParticleId, usize, [f64; 2])>, i: usize, shift: [f64; 2]| {
                let c = [self.x[i] + shift[0], self.y[i] + shift[1]];
                let Some(t) = entry(origin, direction, c, self.radius[i]) else {
                    return;
                };
                if t <= max_fraction && best.is_none_or(|b| (t, self.id[i]) < (b.0, b.1)) {
                    *best = Some((t, self.id[i], i, c));
                }
            };
        for &i in &self.large {
            test(&mut best, i as usize, [0.0; 2]);
        }
        // The cells the ray crosses, in order (a disc it enters has its centre in the
        // crossed cell that holds the entry point, or a neighbour of it).
        let mut walk = Walk::new(self, origin, direction, max_fraction);
        while let Some((cell, t_in)) = walk.next() {
            if best.is_some_and(|b| b.0 < t_in) {
                break;
            }
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let near = [cell[0] + dx, cell[1] + dy];
                    for (wrapped, shift) in self.images_of(near).into_iter().flatten() {
                        self.in_cell(wrapped, |i| test(&mut best, i, shift));
                    }
                }
            }
        }
        best.map(|(t, id, i, c)| {
            let point = [origin[0] + t * direction[0], origin[1] + t * direction[1]];
            let r = self.radius[i];
            RayHit {
                id,
                fraction: t,
                point,
                normal: [(point[0] - c[0]) / r, (point[1] - c[1]) / r],
            }
        })
    }

    /// Calls `f` with every disc whose cell may hold a disc overlapping the rectangle of
    /// half-sizes `half` around `centre` (some more than once in a small periodic box).
    fn around(&self, centre: [f64; 2], half: [f64; 2], mut f: impl FnMut(usize)) {
        self.large.iter().for_each(|&i| f(i as usize));
        let reach = 0.5 * self.width[0].min(self.width[1]);
        let lo = self.cell_at_unclamped([centre[0] - half[0] - reach, centre[1] - half[1] - reach]);
        let hi = self.cell_at_unclamped([centre[0] + half[0] + reach, centre[1] + half[1] + reach]);
        let span = |k: usize| -> (i64, i64) {
            match self.period {
                // Every column once when the range wraps all the way round.
                Some(_) if hi[k] - lo[k] + 1 >= self.cells[k] => (0, self.cells[k] - 1),
                Some(_) => (lo[k], hi[k]),
                None => (lo[k].max(0), hi[k].min(self.cells[k] - 1)),
            }
        };
        let ((mut x0, mut x1), (y0, y1)) = (span(0), span(1));
        if self.slide != 0.0 && y1 - y0 + 1 >= self.cells[1] {
            // All rows of a Lees–Edwards box: some may be wanted both slid and not, so
            // every cell (the distance decides).
            (x0, x1) = (0, self.cells[0] - 1);
        }
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                for (cell, _) in self.images_of([cx, cy]).into_iter().flatten() {
                    self.in_cell(cell, &mut f);
                }
            }
        }
    }

    /// Calls `f` with the discs of the grid cell `cell` (in range).
    fn in_cell(&self, cell: [i64; 2], mut f: impl FnMut(usize)) {
        let c = self.cell_index(cell);
        for &i in &self.items[self.start[c] as usize..self.start[c + 1] as usize] {
            f(i as usize);
        }
    }

    /// The grid cells that hold the discs of an unbounded cell index, each with the shift of
    /// that copy of the box (periodic), or the cell itself when in the grid (nothing
    /// outside it). In a Lees–Edwards box a copy above or below stands slid along x, so an
    /// unbounded cell there covers parts of two of the grid's columns.
    fn images_of(&self, cell: [i64; 2]) -> [Option<([i64; 2], [f64; 2])>; 2] {
        let Some(size) = self.period else {
            let inside = (0..2).all(|k| cell[k] >= 0 && cell[k] < self.cells[k]);
            return [inside.then_some((cell, [0.0; 2])), None];
        };
        let row = cell[1].rem_euclid(self.cells[1]);
        let up = (cell[1] - row) / self.cells[1];
        // The copy `up` boxes above stands `up δ` along x: the cell's columns in the box's
        // own coordinates.
        let slid = up as f64 * self.slide;
        let column = |c: i64| {
            let wrapped = c.rem_euclid(self.cells[0]);
            let across = (c - wrapped) / self.cells[0];
            let shift = [across as f64 * size[0] + slid, up as f64 * size[1]];
            ([wrapped, row], shift)
        };
        if slid == 0.0 {
            return [Some(column(cell[0])), None];
        }
        let left = self.origin[0] + cell[0] as f64 * self.width[0] - slid;
        let first = ((left - self.origin[0]) / self.width[0]).floor() as i64;
        [Some(column(first)), Some(column(first + 1))]
    }

    /// A disc's centre less `point` (the minimum image in a periodic box, across the top
    /// and bottom first in a Lees–Edwards box, whose copies there stand slid along x).
    fn offset(&self, i: usize, point: [f64; 2]) -> [f64; 2] {
        let mut d = [self.x[i] - point[0], self.y[i] - point[1]];
        if let Some(size) = self.period {
            let up = (d[1] / size[1]).round();
            d[1] -= size[1] * up;
            if self.slide != 0.0 {
                d[0] -= up * self.slide;
            }
            d[0] -= size[0] * (d[0] / size[0]).round();
        }
        d
    }

    /// `point` moved into the periodic box (unchanged otherwise; in a Lees–Edwards box a
    /// point moved across the top or bottom also moves back along x by the copy's slide).
    fn wrap(&self, point: [f64; 2]) -> [f64; 2] {
        let Some(size) = self.period else {
            return point;
        };
        let into = |v: f64, k: usize| {
            let v = self.origin[k] + (v - self.origin[k]).rem_euclid(size[k]);
            // (Rounding can land on the upper edge.)
            if v >= self.origin[k] + size[k] {
                self.origin[k]
            } else {
                v
            }
        };
        let y = into(point[1], 1);
        let up = ((point[1] - y) / size[1]).round();
        let x = if self.slide != 0.0 && up != 0.0 {
            point[0] - up * self.slide
        } else {
            point[0]
        };
        [into(x, 0), y]
    }

    fn cell_at_unclamped(&self, p: [f64; 2]) -> [i64; 2] {
        [0, 1].map(|k| {
            let c = ((p[k] - self.origin[k]) / self.width[k]).floor();
            c.clamp(-(1i64 << 40) as f64, (1i64 << 40) as f64) as i64
        })
    }

    fn cell_at(&self, p: [f64; 2]) -> [i64; 2] {
        let c = self.cell_at_unclamped(p);
        [
            c[0].clamp(0, self.cells[0] - 1),
            c[1].clamp(0, self.cells[1] - 1),
        ]
    }

    fn cell_index(&self, cell: [i64; 2]) -> usize {
        (cell[1] * self.cells[0] + cell[0]) as usize
    }

    /// A lower bound on the distance from `point` to a centre in a cell outside the rings
    /// `0..=ring` around `home` (infinite when there is none).
    fn unseen_distance(&self, point: [f64; 2], home: [i64; 2], ring: i64) -> f64 {
        if self.period.is_some() {
            if 2 * ring + 1 >= self.cells[0].max(self.cells[1]) {
                return f64::INFINITY;
            }
            // The point is in its home cell: a cell `ring + 1` away is `ring` cells off.
            return ring as f64 * self.width[0].min(self.width[1]);
        }
        // The grid less the rings seen: up to four rectangles of cells.
        let seen_lo = [home[0] - ring, home[1] - ring];
        let seen_hi = [home[0] + ring, home[1] + ring];
        let (g_lo, g_hi) = ([0, 0], [self.cells[0] - 1, self.cells[1] - 1]);
        let strips = [
            ([g_lo[0], g_lo[1]], [seen_lo[0] - 1, g_hi[1]]),
            ([seen_hi[0] + 1, g_lo[1]], [g_hi[0], g_hi[1]]),
            (
                [seen_lo[0].max(0), g_lo[1]],
                [seen_hi[0].min(g_hi[0]), seen_lo[1] - 1],
            ),
            (
                [seen_lo[0].max(0), seen_hi[1] + 1],
                [seen_hi[0].min(g_hi[0]), g_hi[1]],
            ),
        ];
        let mut nearest = f64::INFINITY;
        for (lo, hi) in strips {
            if lo[0] > hi[0] || lo[1] > hi[1] {
                continue;
            }
            let d = [0, 1].map(|k| {
                let a = self.origin[k] + lo[k] as f64 * self.width[k];
                let b = self.origin[k] + (hi[k] + 1) as f64 * self.width[k];
                (a - point[k]).max(point[k] - b).max(0.0)
            });
            nearest = nearest.min((d[0] * d[0] + d[1] * d[1]).sqrt());
        }
        nearest
    }
}

/// The cells at Chebyshev distance `ring` from `home`, in a fixed order.
fn ring_cells(home: [i64; 2], ring: i64) -> Vec<[i64; 2]> {
    if ring == 0 {
        return vec![home];
    }
    let mut out = Vec::with_capacity(8 * ring as usize);
    for dx in -ring..=ring {
        out.push([home[0] + dx, home[1] - ring]);
        out.push([home[0] + dx, home[1] + ring]);
    }
    for dy in -ring + 1..ring {
        out.push([home[0] - ring, home[1] + dy]);
        out.push([home[0] + ring, home[1] + dy]);
    }
    out
}
