//! Conservation laws the seed model must keep at e = 1.

mod common;

use bounce::scene::Speeds;
use bounce::{Boundary, Config};
use common::{assert_rel, box_side, gas_world};

#[test]
fn periodic_elastic_seed_model_conserves_momentum_and_energy() {
    // 1,000 discs, radii 0.3..0.7 (so mass = radius differs between discs), packing 0.3,
    // a net drift so the total momentum is not zero, 10,000 steps.
    let side = box_side(1000, 0.25 + 0.04 / 3.0, 0.3);
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        ..Config::default()
    };
    let mut world = gas_world(
        config,
        1000,
        [0.3, 0.7],
        Speeds::Uniform(2.0),
        [0.4, -0.3],
        7,
    );
    let e0 = world.stats().kinetic_energy;
    let p0 = world.stats().momentum;
    let mut collisions = 0;
    for _ in 0..10_000 {
        collisions += world.step(1.0 / 60.0).unwrap().pairs;
    }
    let stats = world.stats();
    assert!(
        collisions > 100_000,
        "the gas must actually collide: {collisions}"
    );
    assert_rel(stats.kinetic_energy, e0, 1e-9, "kinetic energy");
    let p0_norm = p0[0].hypot(p0[1]);
    let dp = (stats.momentum[0] - p0[0]).hypot(stats.momentum[1] - p0[1]);
    assert!(
        dp / p0_norm <= 1e-9,
        "momentum {:?} vs {p0:?}: relative change {:e}",
        stats.momentum,
        dp / p0_norm
    );
}

#[test]
fn restitution_below_one_loses_energy_with_the_seed_rule() {
    let side = box_side(500, 0.25, 0.3);
    let config = Config {
        coefficient_of_restitution: 0.8,
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        ..Config::default()
    };
    let mut world = gas_world(config, 500, [0.5, 0.5], Speeds::Fixed(1.0), [0.0, 0.0], 3);
    let e0 = world.stats().kinetic_energy;
    for _ in 0..600 {
        world.step(1.0 / 60.0).unwrap();
    }
    assert!(world.stats().kinetic_energy < 0.5 * e0);
}

#[test]
fn momentum_conserving_option_keeps_momentum_when_inelastic() {
    let side = box_side(500, 0.25 + 0.04 / 3.0, 0.3);
    let config = Config {
        coefficient_of_restitution: 0.5,
        restitution_model: bounce::RestitutionModel::RelativeNormalVelocity,
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        ..Config::default()
    };
    let mut world = gas_world(config, 500, [0.3, 0.7], Speeds::Uniform(1.0), [1.0, 0.5], 5);
    let p0 = world.stats().momentum;
    let e0 = world.stats().kinetic_energy;
    for _ in 0..1000 {
        world.step(1.0 / 60.0).unwrap();
    }
    let p = world.stats().momentum;
    assert_rel(p[0], p0[0], 1e-9, "momentum x");
    assert_rel(p[1], p0[1], 1e-9, "momentum y");
    assert!(
        world.stats().kinetic_energy < 0.9 * e0,
        "and it still dissipates"
    );
}

#[test]
fn walls_keep_energy_at_e_one() {
    let side = box_side(2000, 0.25, 0.3);
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [side, side]),
        ..Config::default()
    };
    let mut world = gas_world(config, 2000, [0.5, 0.5], Speeds::Fixed(2.0), [0.0, 0.0], 11);
    let e0 = world.stats().kinetic_energy;
    let mut impulse = 0.0;
    for _ in 0..600 {
        impulse += world.step(1.0 / 60.0).unwrap().wall_impulse.total();
    }
    assert_rel(world.stats().kinetic_energy, e0, 1e-9, "kinetic energy");
    // Pressure from the wall impulse against the ideal-gas-like estimate: same order.
    let kt = e0 / 2000.0;
    let pressure = impulse / (600.0 / 60.0) / (4.0 * side);
    let ideal = 2000.0 * kt / (side * side);
    assert!(
        pressure > ideal && pressure < 3.0 * ideal,
        "pressure {pressure} vs n kT {ideal}"
    );
}
