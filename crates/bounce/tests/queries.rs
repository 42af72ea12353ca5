//! Spatial queries against brute force: random worlds of every boundary kind (walls with a
//! disc far larger than the rest, a periodic box, an open world, a Lees–Edwards box whose
//! images stand slid), 14,000 probes in all of circles, boxes, nearest points and rays, each
//! answer equal to testing every disc.

use bounce::{Boundary, Config, Particle, ParticleId, World};
use proptest::prelude::*;

/// Whether a kind of world is periodic (plain or sheared).
fn periodic(kind: u8) -> bool {
    kind == 1 || kind == 3
}

/// A world of `n` random discs (radii in [0.1, 0.6], one of radius 4 unless periodic); the
/// sheared one is stepped once, at rest, so its images stand 6.9 along.
fn world(kind: u8, n: usize, seed: u64) -> World {
    let boundary = match kind {
        0 => Boundary::walls([0.0, 0.0], [40.0, 30.0]),
        1 => Boundary::periodic([-10.0, 0.0], [30.0, 30.0]),
        3 => Boundary::lees_edwards([-10.0, 0.0], [30.0, 30.0], 0.1),
        _ => Boundary::Open,
    };
    let mut world = World::new(Config {
        boundary,
        ..Config::default()
    })
    .unwrap();
    let mut state = seed | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (lo, hi) = match kind {
        1 | 3 => ([-10.0, 0.0], [30.0, 30.0]),
        _ => ([0.0, 0.0], [40.0, 30.0]),
    };
    for k in 0..n {
        let r = if k == 0 && !periodic(kind) {
            4.0
        } else {
            0.1 + 0.5 * next()
        };
        let margin = if kind == 0 { r } else { 0.0 };
        let x = lo[0] + margin + (hi[0] - lo[0] - 2.0 * margin) * next();
        let y = lo[1] + margin + (hi[1] - lo[1] - 2.0 * margin) * next();
        world
            .add_particle(Particle::new([x, y], [0.0, 0.0], r))
            .unwrap();
    }
    if kind == 3 {
        // Images above at 0.1 · 30 · 2.3 = 6.9 along x.
        world.step(2.3).unwrap();
    }
    world
}

/// `a - b` as the queries measure it: the minimum image in a periodic box, across the top
/// and bottom first where the images there stand `slide` along x.
fn offset(a: [f64; 2], b: [f64; 2], period: Option<[f64; 2]>, slide: f64) -> [f64; 2] {
    let mut d = [a[0] - b[0], a[1] - b[1]];
    if let Some(size) = period {
        let up = (d[1] / size[1]).round();
        d[1] -= up * size[1];
        d[0] -= up * slide;
        d[0] -= size[0] * (d[0] / size[0]).round();
    }
    d
}

/// The entering fraction of a ray into a disc, as a textbook writes it.
fn entry(o: [f64; 2], d: [f64; 2], c: [f64; 2], r: f64) -> Option<f64> {
    let m = [o[0] - c[0], o[1] - c[1]];
    let a = d[0] * d[0] + d[1] * d[1];
    let b = m[0] * d[0] + m[1] * d[1];
    let cc = m[0] * m[0] + m[1] * m[1] - r * r;
    if cc <= 0.0 || b >= 0.0 {
        return None;
    }
    let disc = b * b - a * cc;
    (disc >= 0.0).then(|| cc / (-b + disc.sqrt()))
}

fn check(kind: u8, n: usize, seed: u64, probes: &[[f64; 5]]) -> Result<(), TestCaseError> {
    let world = world(kind, n, seed);
    let queries = world.queries();
    let discs = world.particles_by_id();
    let period = periodic(kind).then_some([40.0, 30.0]);
    let slide = world.lees_edwards_offset().unwrap_or(0.0);
    assert!(kind != 3 || (slide - 6.9).abs() < 1e-9);
    let wrap = |p: [f64; 2]| match period {
        Some(size) => {
            let up = (p[1] / size[1]).floor();
            [
                -10.0 + (p[0] - up * slide + 10.0).rem_euclid(size[0]),
                (p[1]).rem_euclid(size[1]),
            ]
        }
        None => p,
    };
    for probe in probes {
        let &[px, py, a, b, angle] = probe;
        let point = [px, py];
        // A circle of radius `a`.
        let brute: Vec<ParticleId> = (discs.iter())
            .filter(|(_, d)| {
                let v = offset(d.position, wrap(point), period, slide);
                (v[0] * v[0] + v[1] * v[1]).sqrt() <= a + d.radius
            })
            .map(|(id, _)| *id)
            .collect();
        let found = queries.in_circle(point, a);
        // (The boundary's rounding may differ by a hair: compare away from it.)
        let near_edge = discs.iter().any(|(_, d)| {
            let v = offset(d.position, wrap(point), period, slide);
            ((v[0] * v[0] + v[1] * v[1]).sqrt() - (a + d.radius)).abs() < 1e-9
        });
        if !near_edge {
            prop_assert_eq!(&found, &brute, "circle {:?} r {}", point, a);
        }
        // A box of half-sizes a and b.
        let (min, max) = ([px - a, py - b], [px + a, py + b]);
        let centre = wrap([0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1])]);
        let brute: Vec<ParticleId> = (discs.iter())
            .filter(|(_, d)| {
                let v = offset(d.position, centre, period, slide);
                let out = [(v[0].abs() - a).max(0.0), (v[1].abs() - b).max(0.0)];
                out[0] * out[0] + out[1] * out[1] <= d.radius * d.radius
            })
            .map(|(id, _)| *id)
            .collect();
        prop_assert_eq!(queries.in_box(min, max), brute, "box {:?} {:?}", min, max);
        // The nearest edge.
        let brute = (discs.iter())
            .map(|(id, d)| {
                let v = offset(d.position, wrap(point), period, slide);
                ((v[0] * v[0] + v[1] * v[1]).sqrt() - d.radius, *id)
            })
            .min_by(|x, y| x.partial_cmp(y).unwrap())
            .unwrap();
        let (id, gap) = queries.nearest(point).unwrap();
        prop_assert_eq!((gap, id), brute, "nearest {:?}", point);
        // A ray of length `4 a + 10` (up to two boxes across in a periodic one).
        let direction = [angle.cos(), angle.sin()];
        let length = 4.0 * a + 10.0;
        let origin = wrap(point);
        let shifts: Vec<[f64; 2]> = match period {
            Some(size) => (-3..=3)
                .flat_map(|i| {
                    (-3..=3)
                        .map(move |j| [i as f64 * size[0] + j as f64 * slide, j as f64 * size[1]])
                })
                .collect(),
            None => vec![[0.0, 0.0]],
        };
        let mut brute: Option<(f64, ParticleId)> = None;
        for (id, d) in &discs {
            for s in &shifts {
                let c = [d.position[0] + s[0], d.position[1] + s[1]];
                if let Some(t) = entry(origin, direction, c, d.radius)
                    && t <= length
                    && brute.is_none_or(|b| (t, *id) < b)
                {
                    brute = Some((t, *id));
                }
            }
        }
        let hit = queries.ray_cast(point, direction, length);
        prop_assert_eq!(
            hit.map(|h| (h.fraction, h.id)),
            brute,
            "ray from {:?} at {}",
            point,
            angle
        );
        if let Some(h) = hit {
            let norm = (h.normal[0] * h.normal[0] + h.normal[1] * h.normal[1]).sqrt();
            prop_assert!((norm - 1.0).abs() < 1e-9);
        }
    }
    Ok(())
}

fn probes() -> impl Strategy<Value = Vec<[f64; 5]>> {
    prop::collection::vec(
        (
            -15.0..55.0f64,
            -10.0..40.0f64,
            0.0..8.0f64,
            0.0..6.0f64,
            0.0..6.3f64,
        )
            .prop_map(|(x, y, a, b, t)| [x, y, a, b, t]),
        250,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 14, ..ProptestConfig::default() })]

    // 14 cases × 250 probes × 4 boundary kinds: 14,000 probes of each query.
    #[test]
    fn queries_equal_brute_force(n in 1usize..400, seed in any::<u64>(), probes in probes()) {
        for kind in 0..4 {
            check(kind, n, seed, &probes)?;
        }
    }
}

#[test]
fn an_empty_world_answers_nothing() {
    let world = World::new(Config::default()).unwrap();
    let queries = world.queries();
    assert!(queries.is_empty());
    assert!(queries.in_circle([0.0, 0.0], 5.0).is_empty());
    assert!(queries.nearest([0.0, 0.0]).is_none());
    assert!(queries.ray_cast([0.0, 0.0], [1.0, 0.0], 10.0).is_none());
}
