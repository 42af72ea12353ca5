//! Image counts in a periodic box: unwrapped positions are the paths discs really travelled.

use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config, Particle, World};

fn unwrapped(world: &World, size: f64) -> Vec<[f64; 2]> {
    let p = world.particles();
    let mut out: Vec<(u32, [f64; 2])> = (0..p.len())
        .map(|i| {
            let [ix, iy] = p.image()[i];
            (
                p.ids()[i].0,
                [p.x()[i] + ix as f64 * size, p.y()[i] + iy as f64 * size],
            )
        })
        .collect();
    out.sort_by_key(|&(id, _)| id);
    out.into_iter().map(|(_, x)| x).collect()
}

#[test]
fn a_lone_disc_counts_every_crossing() {
    let mut world = World::new(Config {
        boundary: Boundary::periodic([0.0, 0.0], [10.0, 10.0]),
        ..Config::default()
    })
    .unwrap();
    world
        .add_particle(Particle::new([5.0, 5.0], [3.0, -7.0], 0.5))
        .unwrap();
    for _ in 0..100 {
        world.step(0.1).unwrap();
    }
    // 30 to the right, 70 down: images (3, -7), and the unwrapped path is the straight line.
    assert_eq!(world.particles().image()[0], [3, -7]);
    let [x, y] = unwrapped(&world, 10.0)[0];
    assert!(
        (x - 35.0).abs() < 1e-9 && (y + 65.0).abs() < 1e-9,
        "{x} {y}"
    );
}

#[test]
fn the_unwrapped_centre_of_a_gas_drifts_with_its_momentum() {
    // Equal discs: pushes move pairs symmetrically and collisions conserve momentum, so the
    // centre of the unwrapped positions moves at P / M, however often discs wrap.
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [40.0, 40.0]),
        ..Config::default()
    };
    let discs = scene::gas(
        &Gas {
            count: 400,
            radius: [0.5, 0.5],
            region: None,
            speeds: Speeds::Fixed(4.0),
            drift: [1.5, -0.5],
            seed: 2,
        },
        &config,
    )
    .unwrap();
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world.set_threads(2).unwrap();
    world.set_parallel_min_work(0);
    let centre = |w: &World| {
        let u = unwrapped(w, 40.0);
        let n = u.len() as f64;
        let s = u.iter().fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
        [s[0] / n, s[1] / n]
    };
    let start = centre(&world);
    let p = world.stats().momentum;
    let mass = 400.0 * 0.5; // the seed's mass model: mass = radius
    let (dt, steps) = (0.05, 600);
    for _ in 0..steps {
        world.step(dt).unwrap();
    }
    let end = centre(&world);
    let t = dt * steps as f64;
    let wrapped: i32 = world
        .particles()
        .image()
        .iter()
        .map(|i| i[0].abs() + i[1].abs())
        .sum();
    assert!(wrapped > 100, "discs wrapped {wrapped} times");
    for axis in 0..2 {
        let expected = start[axis] + p[axis] / mass * t;
        assert!(
            (end[axis] - expected).abs() < 1e-6,
            "axis {axis}: {} vs {expected}",
            end[axis]
        );
    }
}
