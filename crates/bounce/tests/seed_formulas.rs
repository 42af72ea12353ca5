//! The seed's formulas on cases worked out by hand.

mod common;

use bounce::law::{Body, Law, resolve_pair};
use bounce::{Boundary, Config, MassModel, Particle, RestitutionModel, VelocityUpdate, World};
use common::assert_close;

fn seed_params(e: f64) -> Law {
    Law {
        collision_radius_scale: 1.0,
        restitution: e,
        restitution_model: RestitutionModel::ScaleEachNormalVelocity,
        velocity_update: VelocityUpdate::AllDetected,
        mass_model: MassModel::Radius,
        rest_below: None,
        rough: None,
    }
}

/// The seed's detection rule with `collision_radius_scale` = `scale`.
fn is_colliding(diff: [f64; 2], r1: f64, r2: f64, scale: f64) -> bool {
    Law {
        collision_radius_scale: scale,
        ..seed_params(1.0)
    }
    .is_colliding(diff, r1, r2)
}

/// A body under the seed's mass model (mass = radius).
fn body(velocity: [f64; 2], radius: f64) -> Body {
    Body::new(velocity, radius, radius)
}

fn close2(a: [f64; 2], b: [f64; 2], what: &str) {
    assert_close(a[0], b[0], 1e-12, what);
    assert_close(a[1], b[1], 1e-12, what);
}

#[test]
fn head_on_equal_radii_exchange_normal_velocities() {
    let out = resolve_pair(
        [-2.0, 0.0],
        &body([3.0, 0.0], 1.0),
        &body([-1.0, 0.0], 1.0),
        &seed_params(1.0),
    );
    assert_eq!(out.v1, [-1.0, 0.0]);
    assert_eq!(out.v2, [3.0, 0.0]);
    assert_eq!(out.push, [0.0, 0.0], "touching exactly: no overlap");
}

#[test]
fn radii_one_and_three_by_hand() {
    // p1 = (0, 0), r1 = 1, v1 = (2, 0); p2 = (3.9, 0), r2 = 3, v2 = (-1, 0).
    // diff = p1 - p2 = (-3.9, 0), distance 3.9, collision distance 4: overlap 0.1.
    // n = (-1, 0), t = (0, -1).  v1n = -2, v2n = 1, tangents 0.
    // v1n' = (-2 (1 - 3) + 2·3·1) / 4 = (4 + 6) / 4 = 2.5   -> v1 = 2.5 n = (-2.5, 0)
    // v2n' = (1 (3 - 1) + 2·1·(-2)) / 4 = (2 - 4) / 4 = -0.5 -> v2 = -0.5 n = (0.5, 0)
    // Momentum with mass = radius: 1·2 + 3·(-1) = -1 before, 1·(-2.5) + 3·0.5 = -1 after.
    // Each disc moves half the overlap: p1 -> (-0.05, 0), p2 -> (3.95, 0).
    let out = resolve_pair(
        [-3.9, 0.0],
        &body([2.0, 0.0], 1.0),
        &body([-1.0, 0.0], 3.0),
        &seed_params(1.0),
    );
    close2(out.v1, [-2.5, 0.0], "v1");
    close2(out.v2, [0.5, 0.0], "v2");
    close2(out.push, [-0.05, 0.0], "push");
}

#[test]
fn radii_one_and_three_through_a_world_step() {
    // The same pair inside a world: the step first moves the discs by v dt (dt = 0.01),
    // p1 = (0.02, 0), p2 = (3.89, 0): distance 3.87, overlap 0.13, half is 0.065.
    let mut world = World::new(Config::default()).unwrap();
    let a = world
        .add_particle(Particle::new([0.0, 0.0], [2.0, 0.0], 1.0))
        .unwrap();
    let b = world
        .add_particle(Particle::new([3.9, 0.0], [-1.0, 0.0], 3.0))
        .unwrap();
    let stats = *world.step(0.01).unwrap();
    assert_eq!(stats.pairs, 1);
    assert_close(stats.max_overlap, 0.13, 1e-12, "overlap");
    let (pa, pb) = (world.particle(a).unwrap(), world.particle(b).unwrap());
    close2(pa.position, [0.02 - 0.065, 0.0], "p1");
    close2(pb.position, [3.89 + 0.065, 0.0], "p2");
    close2(pa.velocity, [-2.5, 0.0], "v1");
    close2(pb.velocity, [0.5, 0.0], "v2");
    close2(stats.momentum, [-1.0, 0.0], "momentum, mass = radius");
    assert_close(
        stats.kinetic_energy,
        3.5,
        1e-12,
        "energy: ½(1·4 + 3·1) = ½(1·6.25 + 3·0.25)",
    );
}

#[test]
fn oblique_collision_keeps_tangential_components() {
    // 3-4-5 triangle: diff = (-3, -4), distance 5 = r1 + r2 (touching).
    // n = (-0.6, -0.8), t = (0.8, -0.6). v1 = (1, 0): v1n = -0.6, v1t = 0.8; v2 = 0.
    // Equal masses: normal parts exchange: v1 = 0.8 t = (0.64, -0.48), v2 = -0.6 n = (0.36, 0.48).
    let out = resolve_pair(
        [-3.0, -4.0],
        &body([1.0, 0.0], 2.5),
        &body([0.0, 0.0], 2.5),
        &seed_params(1.0),
    );
    close2(out.v1, [0.64, -0.48], "v1");
    close2(out.v2, [0.36, 0.48], "v2");
    let t = [0.8, -0.6];
    let dot = |v: [f64; 2]| v[0] * t[0] + v[1] * t[1];
    assert_close(dot(out.v1), 0.8, 1e-12, "v1 tangent unchanged");
    assert_close(dot(out.v2), 0.0, 1e-12, "v2 tangent unchanged");
}

#[test]
fn restitution_scales_each_new_normal_velocity() {
    // Head on, equal radii: elastic result (−1, +1) along n = (−1, 0), each times e = 0.5.
    let out = resolve_pair(
        [-2.0, 0.0],
        &body([1.0, 0.0], 1.0),
        &body([-1.0, 0.0], 1.0),
        &seed_params(0.5),
    );
    close2(out.v1, [-0.5, 0.0], "v1");
    close2(out.v2, [0.5, 0.0], "v2");

    // Moving disc hits a resting one: elastic gives (0, 1), scaled (0, 0.5). Momentum
    // falls from 1 to 0.5: the seed's rule does not conserve it.
    let seed = resolve_pair(
        [-2.0, 0.0],
        &body([1.0, 0.0], 1.0),
        &body([0.0, 0.0], 1.0),
        &seed_params(0.5),
    );
    close2(seed.v1, [0.0, 0.0], "seed v1");
    close2(seed.v2, [0.5, 0.0], "seed v2");

    // The momentum-conserving option: v1' = (1 − 0.5)/2 = 0.25, v2' = (1 + 0.5)/2 = 0.75.
    let newton = Law {
        restitution_model: RestitutionModel::RelativeNormalVelocity,
        ..seed_params(0.5)
    };
    let out = resolve_pair(
        [-2.0, 0.0],
        &body([1.0, 0.0], 1.0),
        &body([0.0, 0.0], 1.0),
        &newton,
    );
    close2(out.v1, [0.25, 0.0], "newton v1");
    close2(out.v2, [0.75, 0.0], "newton v2");
}

#[test]
fn collision_radius_scale_widens_detection() {
    assert!(is_colliding([2.3, 0.0], 1.0, 1.0, 1.2));
    assert!(!is_colliding([2.5, 0.0], 1.0, 1.0, 1.2));
    assert!(!is_colliding([2.3, 0.0], 1.0, 1.0, 1.0));
    // And through the world's grid.
    for (distance, expected) in [(2.3, 1), (2.5, 0)] {
        let config = Config {
            collision_radius_scale: 1.2,
            ..Config::default()
        };
        let mut world = World::new(config).unwrap();
        world
            .add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 1.0))
            .unwrap();
        world
            .add_particle(Particle::new([distance, 0.0], [0.0, 0.0], 1.0))
            .unwrap();
        assert_eq!(
            world.colliding_pairs().len(),
            expected,
            "distance {distance}"
        );
    }
}

#[test]
fn overlap_moves_each_disc_by_half() {
    // Distance 1.5, collision distance 2: overlap 0.5, each moves 0.25 along the normal,
    // whatever the radii (the seed splits the push equally, not by mass).
    let out = resolve_pair(
        [-1.5, 0.0],
        &body([0.0, 0.0], 1.0),
        &body([0.0, 0.0], 1.0),
        &seed_params(1.0),
    );
    close2(out.push, [-0.25, 0.0], "push");
    let out = resolve_pair(
        [0.0, 3.0],
        &body([0.0, 0.0], 1.0),
        &body([0.0, 0.0], 3.0),
        &seed_params(1.0),
    );
    close2(out.push, [0.0, 0.5], "push, unequal radii");
}

#[test]
fn coincident_centres_use_the_fixed_normal() {
    let out = resolve_pair(
        [0.0, 0.0],
        &body([0.0, 1.0], 1.0),
        &body([0.0, -1.0], 1.0),
        &seed_params(1.0),
    );
    close2(out.push, [1.0, 0.0], "pushed apart along +x by half of 2");
    assert!(out.v1.iter().chain(&out.v2).all(|v| v.is_finite()));
    // The same through a world step: positions and velocities stay finite.
    let mut world = World::new(Config::default()).unwrap();
    let a = world
        .add_particle(Particle::new([1.0, 1.0], [0.0, 0.0], 0.5))
        .unwrap();
    let b = world
        .add_particle(Particle::new([1.0, 1.0], [0.0, 0.0], 0.5))
        .unwrap();
    world.step(0.1).unwrap();
    let (pa, pb) = (world.particle(a).unwrap(), world.particle(b).unwrap());
    assert_eq!(pa.position[0] - pb.position[0], 1.0);
    assert!(
        pa.position
            .iter()
            .chain(&pb.position)
            .all(|v| v.is_finite())
    );
}

#[test]
fn seed_updates_separating_pairs_and_the_option_does_not() {
    // Overlapping but already separating: v1n − v2n > 0.
    let (a, b) = (body([-1.0, 0.0], 1.0), body([1.0, 0.0], 1.0));
    let seed = resolve_pair([-1.5, 0.0], &a, &b, &seed_params(1.0));
    close2(seed.v1, [1.0, 0.0], "seed swaps them back together");
    let approaching = Law {
        velocity_update: VelocityUpdate::ApproachingOnly,
        ..seed_params(1.0)
    };
    let out = resolve_pair([-1.5, 0.0], &a, &b, &approaching);
    assert_eq!((out.v1, out.v2), (a.velocity, b.velocity));
    close2(out.push, [-0.25, 0.0], "the overlap is still resolved");
}

#[test]
fn area_mass_model_weighs_large_discs_more() {
    // Radii 1 and 2 head on with mass = π r²: m1 = π, m2 = 4π.
    // v1 = 1, v2 = 0 along x; n = (-1, 0): v1n = -1, v2n = 0.
    // v1n' = (-1 (π - 4π)) / 5π = 3/5 -> v1 = (-0.6, 0); v2n' = 2π(-1)/5π = -0.4 -> v2 = (0.4, 0).
    let mut world = World::new(Config {
        mass_model: MassModel::Area,
        ..Config::default()
    })
    .unwrap();
    let a = world
        .add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 1.0))
        .unwrap();
    let b = world
        .add_particle(Particle::new([3.0, 0.0], [0.0, 0.0], 2.0))
        .unwrap();
    world.step(1e-9).unwrap();
    close2(world.particle(a).unwrap().velocity, [-0.6, 0.0], "v1");
    close2(world.particle(b).unwrap().velocity, [0.4, 0.0], "v2");
}

#[test]
fn walls_reflect_with_wall_restitution_and_report_impulse() {
    let config = Config {
        boundary: Boundary::Walls {
            min: [0.0, 0.0],
            max: [10.0, 10.0],
            wall_restitution: Some(0.5),
        },
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    let id = world
        .add_particle(Particle::new([0.6, 5.0], [-2.0, 0.0], 0.5))
        .unwrap();
    let stats = *world.step(0.1).unwrap();
    let p = world.particle(id).unwrap();
    assert_eq!(p.position, [0.5, 5.0]);
    assert_eq!(p.velocity, [1.0, 0.0]);
    // Mass = radius = 0.5; |Δv| = 3.
    assert_eq!(stats.wall_impulse.left, 1.5);
    assert_eq!(stats.wall_impulse.total(), 1.5);
}
