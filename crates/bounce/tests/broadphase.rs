//! The grid finds exactly the pairs that testing all pairs finds.

mod common;

use bounce::{Boundary, Config, Particle, World};
use proptest::prelude::*;

/// Radii spread log-uniformly over `[0.1, 5]`, positions anywhere in the box (overlaps allowed).
fn discs(count: usize, size: f64, max_radius: f64) -> impl Strategy<Value = Vec<Particle>> {
    proptest::collection::vec(
        (0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64, -1.0..1.0f64),
        1..count,
    )
    .prop_map(move |raw| {
        raw.into_iter()
            .map(|(u, v, w, vel)| {
                let r = 0.1 * (max_radius / 0.1).powf(w * w * w);
                Particle::new([u * size, v * size], [vel, -vel], r)
            })
            .collect()
    })
}

fn boundary(kind: u8, size: f64) -> Boundary {
    match kind {
        0 => Boundary::walls([0.0, 0.0], [size, size]),
        1 => Boundary::periodic([0.0, 0.0], [size, size]),
        // Sheared: after each step of 0.5 the images above stand another 0.185 sides on.
        2 => Boundary::lees_edwards([0.0, 0.0], [size, size], 0.37),
        _ => Boundary::Open,
    }
}

fn check(world: &mut World) -> Result<(), TestCaseError> {
    let brute = world.colliding_pairs_brute_force();
    let grid = world.colliding_pairs();
    if grid != brute {
        for pair in brute.iter().filter(|p| !grid.contains(p)) {
            let (a, b) = (
                world.particle(pair.0).unwrap(),
                world.particle(pair.1).unwrap(),
            );
            eprintln!("MISSED {pair:?}: {a:?} {b:?} config {:?}", world.config());
        }
    }
    prop_assert_eq!(grid, brute);
    Ok(())
}

/// The grid against the oracle for `particles` in a box of `size` (kind as [`boundary`]),
/// now and after each of three steps. Positions are kept inside the box, and a disc the
/// periodic box refuses (too large for the minimum image) is left out.
fn check_stepping(
    kind: u8,
    size: f64,
    scale: f64,
    particles: Vec<Particle>,
) -> Result<(), TestCaseError> {
    let config = Config {
        collision_radius_scale: scale,
        boundary: boundary(kind, size),
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    for p in particles {
        let position = p.position.map(|v| v.min(size - 1e-9));
        let _ = world.add_particle(Particle { position, ..p });
    }
    check(&mut world)?;
    // And again after the state has moved on.
    for _ in 0..3 {
        world.step(0.5).unwrap();
        check(&mut world)?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn grid_matches_brute_force(
        kind in 0u8..4,
        scale in 0.5..2.0f64,
        particles in discs(400, 60.0, 5.0),
    ) {
        check_stepping(kind, 60.0, scale, particles)?;
    }

    #[test]
    fn grid_matches_brute_force_when_levels_share_a_grid(
        kind in 0u8..3,
        scale in 0.5..2.0f64,
        particles in discs(200, 200.0, 5.0),
    ) {
        // Sparse discs of six bands in a box: fewer than one per cell of the largest, so
        // the levels share one grid, each pair cut at its own collision distance.
        check_stepping(kind, 200.0, scale, particles)?;
    }

    #[test]
    fn grid_matches_brute_force_with_one_giant(
        kind in 0u8..4,
        particles in discs(600, 40.0, 0.3),
    ) {
        // Brownian-like: many small discs and one large one (four levels apart).
        let size = 40.0;
        let config = Config { boundary: boundary(kind, size), ..Config::default() };
        let mut world = World::new(config).unwrap();
        world.add_particle(Particle::new([20.0, 20.0], [0.3, 0.1], 5.0)).unwrap();
        for p in particles {
            let p = Particle { position: [p.position[0].min(size - 1e-9), p.position[1].min(size - 1e-9)], ..p };
            world.add_particle(p).unwrap();
        }
        check(&mut world)?;
        world.step(0.5).unwrap();
        check(&mut world)?;
    }
}

#[test]
fn open_world_with_a_far_outlier_still_finds_every_pair() {
    let mut world = World::new(Config::default()).unwrap();
    for i in 0..50 {
        let x = (i % 10) as f64 * 0.9;
        let y = (i / 10) as f64 * 0.9;
        world
            .add_particle(Particle::new([x, y], [0.0, 0.0], 0.5))
            .unwrap();
    }
    // Two touching discs very far away: they fall into the grid's edge cell.
    world
        .add_particle(Particle::new([1e9, 1e9], [0.0, 0.0], 0.5))
        .unwrap();
    world
        .add_particle(Particle::new([1e9 + 0.5, 1e9], [0.0, 0.0], 0.5))
        .unwrap();
    let grid = world.colliding_pairs();
    assert_eq!(grid, world.colliding_pairs_brute_force());
    assert!(grid.len() > 50);
}
