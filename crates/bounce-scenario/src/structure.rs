//! The structure of frames of discs: the radial distribution function g(r), the global
//! bond-orientational order |ψ6| and the mean-square displacement, as `bounce analyze` and
//! Python's `bounce.rdf`, `psi6` and `msd` compute them, each to freud's convention (the
//! tests compare them with freud on the same frames).
//!
//! - **g(r)**: pairs binned by distance up to `r_max` (the minimum image in a periodic box),
//!   accumulated over frames. In a periodic box the normalisation is freud's `exact` one: the
//!   ordered pairs of a bin over `N · (N/A) · π(r₂² − r₁²)` per frame. Between walls, or in an
//!   open world, the pairs are divided by those an ideal gas would have in the same
//!   rectangle: for centres uniform in an `a × b` rectangle (the box less a mean diameter each
//!   way, where centres can be; an open world's the frame's bounding box of centres), the
//!   ordered pairs at distance r are `N(N−1) · 2πr γ(r) dr / (ab)²`, with the rectangle's
//!   isotropic set covariance `γ(r) = ab − 2r(a+b)/π + r²/π` (r ≤ min(a, b)), so g → 1 far
//!   from contact without the walls' deficit.
//! - **|ψ6|**: each disc's `ψ6(i) = (1/n) Σ_j exp(6iφ_ij)` over its 6 nearest neighbours
//!   (`φ_ij` the angle of the bond to j from the x axis), the global order the modulus of the
//!   mean over discs (freud's `Hexatic(k=6)` with `num_neighbors = 6`).
//! - **MSD**: over every time origin (freud's `MSD` in `window` mode), from unwrapped
//!   positions (position + image × box in a periodic box): the mean over discs and origins of
//!   `|r(t + lag) − r(t)|²`, for every lag of the frames, which must be evenly spaced and hold
//!   the same discs in the same order.
//!
//! Neighbours are found through a cell grid, so a frame costs O(N) for a fixed `r_max`.

/// How a frame's box ends: what sets the minimum image and g(r)'s normalisation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edges {
    /// Periodic in both directions (every HOOMD-blue box).
    Periodic,
    /// Walls at the box's edges.
    Walls,
    /// An open world: the box only holds the discs.
    Open,
}

impl Edges {
    /// The edges `bounce analyze --boundary` and Python's `boundary=` name: `periodic`,
    /// `walls` or `open`.
    pub fn from_name(name: &str) -> Option<Edges> {
        [Edges::Periodic, Edges::Walls, Edges::Open]
            .into_iter()
            .find(|e| e.name() == name)
    }

    /// The name `bounce analyze --boundary` takes.
    pub fn name(self) -> &'static str {
        match self {
            Edges::Periodic => "periodic",
            Edges::Walls => "walls",
            Edges::Open => "open",
        }
    }
}

/// One frame: positions relative to the box centre (HOOMD's convention).
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// The step the frame was taken at.
    pub step: u64,
    /// The simulated time it was taken at, where the file records it (bounce's do).
    pub time: Option<f64>,
    /// The box's size.
    pub size: [f64; 2],
    /// How the box ends.
    pub edges: Edges,
    /// Each disc's centre, relative to the box centre.
    pub position: Vec<[f64; 2]>,
    /// Each disc's periodic box crossings (zero outside a periodic box).
    pub image: Vec<[i32; 2]>,
    /// In a Lees–Edwards box, how far along x the images above stand in this frame (the
    /// images below stand at minus it): distances take the sliding minimum image. `None`
    /// in any other box.
    pub slide: Option<f64>,
    /// Each disc's diameter.
    pub diameter: Vec<f64>,
}

impl Snapshot {
    /// The world's discs now, in id order, as a frame of its GSD trajectory holds them:
    /// positions relative to the box centre (an open world's box: the centres' bounding box
    /// around the origin), no periodic images.
    pub fn of(world: &bounce::World) -> Snapshot {
        let by_id = world.particles_by_id();
        let (centre, size, edges) = match world.config().boundary {
            bounce::Boundary::Periodic { min, max }
            | bounce::Boundary::LeesEdwards { min, max, .. } => (min, max, Edges::Periodic),
            bounce::Boundary::Walls { min, max, .. } => (min, max, Edges::Walls),
            bounce::Boundary::Open => ([0.0; 2], [0.0; 2], Edges::Open),
        };
        let (centre, size) = if edges == Edges::Open {
            let reach = by_id.iter().fold(0.0f64, |m, (_, p)| {
                m.max(p.position[0].abs()).max(p.position[1].abs())
            });
            ([0.0; 2], [2.0 * reach.max(0.5); 2])
        } else {
            let (min, max) = (centre, size);
            (
                [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0],
                [max[0] - min[0], max[1] - min[1]],
            )
        };
        Snapshot {
            step: world.step_count(),
            time: Some(world.time()),
            slide: world.lees_edwards_offset(),
            size,
            edges,
            position: (by_id.iter())
                .map(|(_, p)| [p.position[0] - centre[0], p.position[1] - centre[1]])
                .collect(),
            image: vec![[0, 0]; by_id.len()],
            diameter: by_id.iter().map(|(_, p)| 2.0 * p.radius).collect(),
        }
    }

    /// The mean diameter (1 without discs).
    pub fn mean_diameter(&self) -> f64 {
        if self.diameter.is_empty() {
            1.0
        } else {
            self.diameter.iter().sum::<f64>() / self.diameter.len() as f64
        }
    }

    /// The largest `r_max` g(r) takes in this frame: half the box's smaller side in a
    /// periodic box (the minimum image), else the smaller side of the rectangle the centres
    /// fill (where the set covariance holds). Unbounded for a frame of fewer than two discs,
    /// which has no pairs.
    pub fn largest_r_max(&self) -> f64 {
        if self.position.len() < 2 {
            return f64::INFINITY;
        }
        let [a, b] = self.centre_rectangle();
        match self.edges {
            Edges::Periodic => a.min(b) / 2.0,
            Edges::Walls | Edges::Open => a.min(b),
        }
    }

    /// The rectangle the centres fill: the box, less a mean diameter between walls; the
    /// centres' bounding box in an open world.
    fn centre_rectangle(&self) -> [f64; 2] {
        match self.edges {
            Edges::Periodic => self.size,
            Edges::Walls => {
                let d = self.mean_diameter();
                [(self.size[0] - d).max(0.0), (self.size[1] - d).max(0.0)]
            }
            Edges::Open => {
                let (lo, hi) = bounding_box(&self.position);
                [hi[0] - lo[0], hi[1] - lo[1]]
            }
        }
    }

    /// The vector from disc `i` to disc `j` (the minimum image in a periodic box: across
    /// the top and bottom first, which in a Lees–Edwards box also slides x).
    fn bond(&self, i: usize, j: usize) -> [f64; 2] {
        let (p, q) = (self.position[i], self.position[j]);
        let mut d = [q[0] - p[0], q[1] - p[1]];
        if self.edges == Edges::Periodic {
            let [lx, ly] = self.size;
            let up = (d[1] / ly).round();
            d[1] -= ly * up;
            if let Some(slide) = self.slide {
                d[0] -= up * slide;
            }
            d[0] -= lx * (d[0] / lx).round();
        }
        d
    }

    /// `p` brought into a Lees–Edwards box across its top or bottom (x slid with it), so a
    /// cell grid sees each disc where its image in the box is; `p` itself otherwise.
    fn in_box(&self, p: [f64; 2]) -> [f64; 2] {
        match (self.edges, self.slide) {
            (Edges::Periodic, Some(slide)) => {
                let up = (p[1] / self.size[1]).round();
                [p[0] - up * slide, p[1] - up * self.size[1]]
            }
            _ => p,
        }
    }
}

fn bounding_box(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    points.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    )
}

/// The discs of a frame binned in square-ish cells at least `reach` wide.
struct Cells {
    origin: [f64; 2],
    extent: [f64; 2],
    count: [usize; 2],
    periodic: bool,
    /// A Lees–Edwards frame: the rows across the top and bottom are slid, so a disc's
    /// neighbours there may be in any column.
    sheared: bool,
    /// `first[c]..first[c + 1]` indexes `members` for cell `c`.
    first: Vec<usize>,
    members: Vec<usize>,
}

impl Cells {
    fn new(frame: &Snapshot, reach: f64) -> Cells {
        let periodic = frame.edges == Edges::Periodic;
        let (origin, extent) = if periodic {
            ([-frame.size[0] / 2.0, -frame.size[1] / 2.0], frame.size)
        } else {
            let (lo, hi) = bounding_box(&frame.position);
            (lo, [(hi[0] - lo[0]).max(0.0), (hi[1] - lo[1]).max(0.0)])
        };
        // At most about 4 cells a disc, so sparse frames do not allocate a huge grid.
        let most = (4 * frame.position.len()).max(1) as f64;
        let mut count = [0usize; 2];
        for k in 0..2 {
            let across = (extent[k] / reach.max(f64::MIN_POSITIVE)).floor();
            count[k] = across.clamp(1.0, most.sqrt().max(1.0)) as usize;
        }
        let mut cells = Cells {
            origin,
            extent,
            count,
            periodic,
            sheared: periodic && frame.slide.is_some(),
            first: Vec::new(),
            members: Vec::new(),
        };
        let of: Vec<usize> = frame
            .position
            .iter()
            .map(|&p| {
                let [cx, cy] = cells.cell(frame.in_box(p));
                cy * count[0] + cx
            })
            .collect();
        let mut first = vec![0usize; count[0] * count[1] + 1];
        for &c in &of {
            first[c + 1] += 1;
        }
        for c in 1..first.len() {
            first[c] += first[c - 1];
        }
        let mut fill = first.clone();
        let mut members = vec![0usize; of.len()];
        for (i, &c) in of.iter().enumerate() {
            members[fill[c]] = i;
            fill[c] += 1;
        }
        cells.first = first;
        cells.members = members;
        cells
    }

    fn cell(&self, p: [f64; 2]) -> [usize; 2] {
        let mut at = [0usize; 2];
        for k in 0..2 {
            let mut u = (p[k] - self.origin[k]) / self.extent[k].max(f64::MIN_POSITIVE);
            if self.periodic {
                u = u.rem_euclid(1.0);
            }
            at[k] = ((u * self.count[k] as f64).floor().max(0.0) as usize).min(self.count[k] - 1);
        }
        at
    }

    /// Every disc in the cells within `reach` of `p`, each once.
    fn visit(&self, p: [f64; 2], reach: f64, mut f: impl FnMut(usize)) {
        let centre = self.cell(p);
        let mut ranges = [(0i64, 0i64); 2];
        for k in 0..2 {
            let width = self.extent[k] / self.count[k] as f64;
            let rings = if width > 0.0 {
                (reach / width).ceil() as i64
            } else {
                self.count[k] as i64
            };
            let n = self.count[k] as i64;
            let c = centre[k] as i64;
            ranges[k] = if self.periodic {
                // Wrapped: at most every cell once.
                let span = (2 * rings + 1).min(n);
                (c - rings, c - rings + span - 1)
            } else {
                ((c - rings).max(0), (c + rings).min(n - 1))
            };
        }
        for cy in ranges[1].0..=ranges[1].1 {
            let y = cy.rem_euclid(self.count[1] as i64) as usize;
            // (Rows that wrap all the way round are wanted slid and not: every cell.)
            let whole = ranges[1].1 - ranges[1].0 + 1 >= self.count[1] as i64;
            let across = self.sheared && (whole || cy < 0 || cy >= self.count[1] as i64);
            let columns = match across {
                true => (0, self.count[0] as i64 - 1),
                false => ranges[0],
            };
            for cx in columns.0..=columns.1 {
                let x = cx.rem_euclid(self.count[0] as i64) as usize;
                let c = y * self.count[0] + x;
                for &j in &self.members[self.first[c]..self.first[c + 1]] {
                    f(j);
                }
            }
        }
    }
}

/// g(r) accumulated over frames: [`Rdf::add`] each, then [`Rdf::g`].
#[derive(Clone, Debug)]
pub struct Rdf {
    r_max: f64,
    /// Ordered pairs per bin.
    pairs: Vec<u64>,
    /// The pairs an ideal gas would have per bin, summed over frames.
    ideal: Vec<f64>,
}

impl Rdf {
    /// `bins` bins of equal width from 0 to `r_max`.
    pub fn new(bins: usize, r_max: f64) -> Result<Rdf, String> {
        if bins == 0 {
            return Err("the number of bins must be at least 1".into());
        }
        if !(r_max.is_finite() && r_max > 0.0) {
            return Err(format!("r_max = {r_max}: must be a finite number > 0"));
        }
        Ok(Rdf {
            r_max,
            pairs: vec![0; bins],
            ideal: vec![0.0; bins],
        })
    }

    /// The bins' edges `k · r_max / bins`.
    fn edge(&self, k: usize) -> f64 {
        self.r_max * k as f64 / self.pairs.len() as f64
    }

    /// Adds a frame's pairs. Refuses an `r_max` beyond [`Snapshot::largest_r_max`]. A frame
    /// of fewer than two discs adds nothing (it has no pairs, and an ideal gas of one has
    /// none either).
    pub fn add(&mut self, frame: &Snapshot) -> Result<(), String> {
        if frame.position.len() < 2 {
            return Ok(());
        }
        let largest = frame.largest_r_max();
        if self.r_max > largest {
            return Err(format!(
                "r_max = {} is beyond {largest} in the frame at step {} ({} box {} × {}: {})",
                self.r_max,
                frame.step,
                frame.edges.name(),
                frame.size[0],
                frame.size[1],
                match frame.edges {
                    Edges::Periodic => "half its smaller side, for the minimum image",
                    _ => "the smaller side of the rectangle the centres fill",
                }
            ));
        }
        let n = frame.position.len();
        let cells = Cells::new(frame, self.r_max);
        let bins = self.pairs.len();
        let width = self.r_max / bins as f64;
        for i in 0..n {
            cells.visit(frame.in_box(frame.position[i]), self.r_max, |j| {
                if j <= i {
                    return;
                }
                let [dx, dy] = frame.bond(i, j);
                let r = dx.hypot(dy);
                if r < self.r_max {
                    let k = ((r / width) as usize).min(bins - 1);
                    self.pairs[k] += 2;
                }
            });
        }
        let n = n as f64;
        let [a, b] = frame.centre_rectangle();
        for k in 0..bins {
            let (r1, r2) = (self.edge(k), self.edge(k + 1));
            self.ideal[k] += match frame.edges {
                Edges::Periodic => n * n / (a * b) * std::f64::consts::PI * (r2 * r2 - r1 * r1),
                Edges::Walls | Edges::Open => {
                    // ∫ 2πr γ(r) dr, γ the rectangle's isotropic set covariance.
                    let f = |r: f64| {
                        std::f64::consts::PI * a * b * r * r - 4.0 / 3.0 * (a + b) * r.powi(3)
                            + r.powi(4) / 2.0
                    };
                    n * (n - 1.0) * (f(r2) - f(r1)) / (a * b).powi(2)
                }
            };
        }
        Ok(())
    }

    /// The ordered pairs counted in each bin, over the frames added (each pair twice).
    pub fn pairs(&self) -> &[u64] {
        &self.pairs
    }

    /// The bins' centres and g there (0 where no frame could hold a pair).
    pub fn g(&self) -> (Vec<f64>, Vec<f64>) {
        let bins = self.pairs.len();
        let r = (0..bins)
            .map(|k| (self.edge(k) + self.edge(k + 1)) / 2.0)
            .collect();
        let g = self
            .pairs
            .iter()
            .zip(&self.ideal)
            .map(|(&p, &ideal)| if ideal > 0.0 { p as f64 / ideal } else { 0.0 })
            .collect();
        (r, g)
    }
}

/// g(r) over `frames` (bin centres and g): up to `r_max` (`None`: 5 mean diameters of the
/// first frame, or as far as every frame allows), in bins `bin` wide (`None`: 0.01 mean
/// diameters; the last bin ends at `r_max`, so it may be narrower by rounding).
pub fn rdf(
    frames: &[Snapshot],
    r_max: Option<f64>,
    bin: Option<f64>,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let Some(first) = frames.first() else {
        return Err("no frames".into());
    };
    let d = first.mean_diameter();
    let r_max = r_max.unwrap_or_else(|| {
        let largest = frames
            .iter()
            .map(Snapshot::largest_r_max)
            .fold(f64::INFINITY, f64::min);
        (5.0 * d).min(largest)
    });
    let bin = bin.unwrap_or(0.01 * d);
    if !(bin.is_finite() && bin > 0.0) {
        return Err(format!("bin = {bin}: must be a finite width > 0"));
    }
    let bins = (r_max / bin).round().max(1.0);
    if bins > 1e7 {
        return Err(format!(
            "r_max = {r_max} in bins of {bin}: more than 10⁷ bins"
        ));
    }
    let mut rdf = Rdf::new(bins as usize, r_max)?;
    for f in frames {
        rdf.add(f)?;
    }
    Ok(rdf.g())
}

/// The global bond-orientational order |ψ6| of a frame (0 for fewer than two discs).
///
/// ```
/// use bounce::{Boundary, Config, Particle, World};
/// use bounce_scenario::structure::{Snapshot, psi6};
/// // A triangular lattice of spacing 1 filling a periodic box: perfect six-fold order.
/// let (columns, rows, h) = (12, 12, 3f64.sqrt() / 2.0);
/// let config = Config {
///     boundary: Boundary::periodic([0.0, 0.0], [columns as f64, rows as f64 * h]),
///     ..Config::default()
/// };
/// let mut world = World::new(config).unwrap();
/// for j in 0..rows {
///     for i in 0..columns {
///         let x = i as f64 + 0.5 * (j % 2) as f64 + 0.25;
///         world.add_particle(Particle::new([x, j as f64 * h + 0.25], [0.0; 2], 0.4)).unwrap();
///     }
/// }
/// assert!((psi6(&Snapshot::of(&world)) - 1.0).abs() < 1e-9);
/// ```
pub fn psi6(frame: &Snapshot) -> f64 {
    let n = frame.position.len();
    if n < 2 {
        return 0.0;
    }
    let wanted = 6.min(n - 1);
    let [a, b] = frame.size;
    // A reach that holds about 20 discs on average; doubled for a disc that finds fewer than
    // six, up to the whole box.
    let spacing = (a * b / n as f64).sqrt();
    let reach = 2.5 * spacing;
    let cells = Cells::new(frame, reach);
    let whole = a.hypot(b);
    let (mut sum_re, mut sum_im) = (0.0, 0.0);
    let mut near: Vec<(f64, usize)> = Vec::new();
    for i in 0..n {
        let mut r = reach;
        loop {
            near.clear();
            cells.visit(frame.in_box(frame.position[i]), r, |j| {
                if j != i {
                    let [dx, dy] = frame.bond(i, j);
                    let d2 = dx * dx + dy * dy;
                    if d2 <= r * r || r >= whole {
                        near.push((d2, j));
                    }
                }
            });
            if near.len() >= wanted || r >= whole {
                break;
            }
            r = (2.0 * r).min(whole);
        }
        near.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let (mut re, mut im) = (0.0, 0.0);
        for &(_, j) in &near[..wanted] {
            let [dx, dy] = frame.bond(i, j);
            let phi = 6.0 * dy.atan2(dx);
            re += phi.cos();
            im += phi.sin();
        }
        sum_re += re / wanted as f64;
        sum_im += im / wanted as f64;
    }
    (sum_re / n as f64).hypot(sum_im / n as f64)
}

/// The mean-square displacement at every lag of `frames` (lag 0 first), over every time
/// origin. The frames must hold the same discs in the same order and be evenly spaced in
/// steps; returns the lags in steps and the MSD.
pub fn msd(frames: &[Snapshot]) -> Result<(Vec<u64>, Vec<f64>), String> {
    let Some(first) = frames.first() else {
        return Err("no frames".into());
    };
    if frames.iter().any(|f| f.slide.is_some()) {
        return Err(
            "a Lees–Edwards box's images slide, so image counts do not unwrap its positions: \
             no MSD from its frames yet"
                .into(),
        );
    }
    let n = first.position.len();
    if n == 0 {
        return Err(format!("frame at step {} holds no discs", first.step));
    }
    let spacing = frames.get(1).map_or(0, |f| f.step.wrapping_sub(first.step));
    for (k, f) in frames.iter().enumerate() {
        if f.position.len() != n {
            return Err(format!(
                "the MSD needs the same discs in every frame: the frame at step {} holds {}, \
                 the first {n}",
                f.step,
                f.position.len()
            ));
        }
        let expected = (k as u64)
            .checked_mul(spacing)
            .and_then(|d| first.step.checked_add(d));
        if expected != Some(f.step) {
            return Err(format!(
                "the MSD needs evenly spaced frames: frame {k} is at step {}, frame 1 at {}",
                f.step,
                first.step.wrapping_add(spacing)
            ));
        }
    }
    let unwrapped: Vec<Vec<[f64; 2]>> = frames
        .iter()
        .map(|f| {
            f.position
                .iter()
                .zip(&f.image)
                .map(|(p, i)| {
                    if f.edges == Edges::Periodic {
                        [
                            p[0] + i[0] as f64 * f.size[0],
                            p[1] + i[1] as f64 * f.size[1],
                        ]
                    } else {
                        *p
                    }
                })
                .collect()
        })
        .collect();
    let count = frames.len();
    let mut lags = Vec::with_capacity(count);
    let mut values = Vec::with_capacity(count);
    for lag in 0..count {
        let mut sum = 0.0;
        for origin in 0..count - lag {
            let (a, b) = (&unwrapped[origin], &unwrapped[origin + lag]);
            for (p, q) in a.iter().zip(b) {
                sum += (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
            }
        }
        lags.push(lag as u64 * spacing);
        values.push(sum / ((count - lag) * n) as f64);
    }
    Ok((lags, values))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(edges: Edges, size: [f64; 2], position: Vec<[f64; 2]>) -> Snapshot {
        let n = position.len();
        Snapshot {
            step: 0,
            time: None,
            size,
            edges,
            position,
            slide: None,
            image: vec![[0, 0]; n],
            diameter: vec![1.0; n],
        }
    }

    /// A triangular lattice of `columns × rows` with spacing 1, filling a periodic box.
    fn triangular(columns: usize, rows: usize) -> Snapshot {
        let h = 3f64.sqrt() / 2.0;
        let size = [columns as f64, rows as f64 * h];
        let mut p = Vec::new();
        for j in 0..rows {
            for i in 0..columns {
                let x = i as f64 + if j % 2 == 1 { 0.5 } else { 0.0 } - size[0] / 2.0;
                p.push([x, j as f64 * h - size[1] / 2.0]);
            }
        }
        frame(Edges::Periodic, size, p)
    }

    #[test]
    fn a_perfect_triangular_lattice_has_psi6_one_and_its_shells_at_1_and_root_3() {
        let lattice = triangular(20, 20);
        assert!((psi6(&lattice) - 1.0).abs() < 1e-12);
        let mut rdf = Rdf::new(190, 1.9).unwrap();
        rdf.add(&lattice).unwrap();
        let (r, g) = rdf.g();
        let peaks: Vec<f64> = r
            .iter()
            .zip(&g)
            .filter(|(_, g)| **g > 0.0)
            .map(|(r, _)| *r)
            .collect();
        // The first shell at 1 (6 neighbours), the second at √3; nothing else below 1.9.
        assert!(
            peaks
                .iter()
                .all(|r| (r - 1.0).abs() < 0.01 || (r - 3f64.sqrt()).abs() < 0.01),
            "{peaks:?}"
        );
        // Six neighbours at distance 1 (rounding puts some a hair below 1): 6 N ordered
        // pairs in the two bins about 1, and 6 N more about √3.
        assert_eq!(rdf.pairs[99] + rdf.pairs[100], 6 * 400);
        assert_eq!(rdf.pairs[173], 6 * 400);
    }

    #[test]
    fn the_pair_counts_equal_brute_force_with_the_minimum_image() {
        // A pseudo-random frame: every pair counted once, through the cells or not.
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for edges in [Edges::Periodic, Edges::Walls, Edges::Open] {
            let size = [13.0, 9.0];
            let p: Vec<[f64; 2]> = (0..300)
                .map(|_| [(next() - 0.5) * size[0], (next() - 0.5) * size[1]])
                .collect();
            let f = frame(edges, size, p);
            let r_max = 3.7;
            let mut rdf = Rdf::new(37, r_max).unwrap();
            rdf.add(&f).unwrap();
            let mut brute = vec![0u64; 37];
            for i in 0..f.position.len() {
                for j in i + 1..f.position.len() {
                    let [dx, dy] = f.bond(i, j);
                    let r = dx.hypot(dy);
                    if r < r_max {
                        brute[((r / 0.1) as usize).min(36)] += 2;
                    }
                }
            }
            assert_eq!(rdf.pairs, brute, "{edges:?}");
        }
    }

    #[test]
    fn an_ideal_gas_between_walls_has_g_near_one_without_the_walls_deficit() {
        let mut state = 99u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        // Centres uniform in the box less a diameter (where a wall lets them be).
        let size = [31.0, 21.0];
        let mut rdf = Rdf::new(10, 10.0).unwrap();
        for _ in 0..20 {
            let p: Vec<[f64; 2]> = (0..2000)
                .map(|_| {
                    [
                        (next() - 0.5) * (size[0] - 1.0),
                        (next() - 0.5) * (size[1] - 1.0),
                    ]
                })
                .collect();
            rdf.add(&frame(Edges::Walls, size, p)).unwrap();
        }
        let (_, g) = rdf.g();
        for (k, g) in g.iter().enumerate().skip(1) {
            assert!((g - 1.0).abs() < 0.01, "bin {k}: g = {g}");
        }
        // A box's own normalisation (πr² per disc) would fall short by the walls' deficit.
        assert!(rdf.r_max <= size[1] - 1.0);
    }

    #[test]
    fn msd_of_discs_moving_steadily_grows_as_the_lag_squared_through_the_images() {
        // Every disc moves 0.9 a frame along x in a periodic box of 5: wrapped, with images.
        let frames: Vec<Snapshot> = (0..10)
            .map(|k| {
                let x = -2.0 + 0.9 * k as f64;
                let image = (x / 5.0 + 0.5).floor() as i32;
                let mut f = frame(
                    Edges::Periodic,
                    [5.0, 5.0],
                    vec![[x - 5.0 * image as f64, 0.0]],
                );
                f.image = vec![[image, 0]];
                f.step = 10 * k as u64;
                f
            })
            .collect();
        assert!(frames.iter().any(|f| f.image[0][0] != 0));
        let (lags, msd) = msd(&frames).unwrap();
        assert_eq!(lags, (0..10).map(|k| 10 * k).collect::<Vec<u64>>());
        for (k, m) in msd.iter().enumerate() {
            assert!((m - (0.9 * k as f64).powi(2)).abs() < 1e-12, "lag {k}: {m}");
        }
        let mut uneven = frames.clone();
        uneven[3].step = 31;
        assert!(super::msd(&uneven).unwrap_err().contains("evenly spaced"));
    }

    #[test]
    fn frames_of_fewer_than_two_discs_add_nothing_and_spoil_nothing() {
        let mut rdf = Rdf::new(10, 2.0).unwrap();
        let pair = frame(
            Edges::Open,
            [10.0, 10.0],
            vec![[0.0, 0.0], [2.5, 0.0], [0.0, 3.0]],
        );
        rdf.add(&pair).unwrap();
        let (_, before) = rdf.g();
        for lonely in [vec![], vec![[1.0, 1.0]]] {
            let f = frame(Edges::Open, [10.0, 10.0], lonely);
            assert_eq!(f.largest_r_max(), f64::INFINITY);
            rdf.add(&f).unwrap();
        }
        assert_eq!(rdf.g().1, before);
        assert!(before.iter().all(|g| g.is_finite()));
        assert_eq!(psi6(&frame(Edges::Open, [1.0, 1.0], vec![[0.0, 0.0]])), 0.0);
    }

    #[test]
    fn an_r_max_beyond_half_a_periodic_box_is_refused_with_the_box() {
        let mut rdf = Rdf::new(10, 3.0).unwrap();
        let e = rdf.add(&triangular(4, 4)).unwrap_err();
        assert!(
            e.contains("r_max = 3") && e.contains("minimum image"),
            "{e}"
        );
        assert!(Rdf::new(0, 1.0).is_err() && Rdf::new(5, f64::NAN).is_err());
    }
}
