//! Resting contacts (`Config::resting_contacts`): the seed's bounce of every contact leaves
//! a disc resting on the floor, a segment or a peg moving at up to `|g| h`, and a stack
//! gaining energy; `RestingContacts::Rest` gives contacts slower than the resting speed
//! restitution 0, and they rest. Impacts and worlds without gravity keep the seed's bits.

mod common;

use bounce::{
    Boundary, Config, Obstacle, Particle, RestingContacts, RestitutionModel, World, law::Law,
};

const G: f64 = 10.0;
const DT: f64 = 0.01;

/// Kinetic and potential energy under gravity `G` downwards (masses are the radii).
fn energy(world: &World) -> (f64, f64) {
    let p = world.particles();
    let (mut kinetic, mut potential) = (0.0, 0.0);
    for i in 0..p.len() {
        let (m, v) = (p.radius()[i], [p.vx()[i], p.vy()[i]]);
        kinetic += 0.5 * m * (v[0] * v[0] + v[1] * v[1]);
        potential += m * G * p.y()[i];
    }
    (kinetic, potential)
}

/// A column of `count` discs of radius 0.5 touching, the lowest resting on `support`.
fn column(support: &str, count: usize, rest: RestingContacts, passes: u32) -> World {
    let (obstacles, base) = match support {
        "floor" => (vec![], 0.0),
        "segment" => (vec![Obstacle::segment([0.0, 2.0], [10.0, 2.0])], 2.0),
        _ => (vec![Obstacle::peg([5.0, 1.0], 1.0)], 2.0),
    };
    let config = Config {
        gravity: [0.0, -G],
        boundary: Boundary::walls([0.0, 0.0], [10.0, 20.0]),
        solver_iterations: passes,
        resting_contacts: rest,
        obstacles,
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    for k in 0..count {
        let y = base + 0.5 + k as f64;
        world
            .add_particle(Particle::new([5.0, y], [0.0, 0.0], 0.5))
            .unwrap();
    }
    world
}

/// Over `steps` steps: the largest speed at a step's end, the largest kinetic energy, and
/// the largest and smallest total energy relative to the start.
fn run(world: &mut World, steps: usize) -> (f64, f64, f64, f64) {
    let (k0, p0) = energy(world);
    let e0 = k0 + p0;
    let (mut speed, mut kinetic, mut gain, mut loss) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..steps {
        world.step(DT).unwrap();
        let p = world.particles();
        for i in 0..p.len() {
            speed = speed.max(p.vx()[i].hypot(p.vy()[i]));
        }
        let (k, u) = energy(world);
        kinetic = kinetic.max(k);
        gain = gain.max((k + u - e0) / e0);
        loss = loss.min((k + u - e0) / e0);
    }
    (speed, kinetic, gain, loss)
}

#[test]
fn a_disc_resting_on_the_floor_a_segment_or_a_peg_carries_g_h_under_the_seed_and_rests_under_rest()
{
    for support in ["floor", "segment", "peg"] {
        // The seed's: pulled in by g h each step and reflected back at e g h (e = 1), the
        // disc ends every other step at |g| h: kinetic energy ½ m (g h)².
        let mut world = column(support, 1, RestingContacts::Bounce, 1);
        let (speed, kinetic, _, _) = run(&mut world, 400);
        common::assert_rel(speed, G * DT, 1e-9, support);
        common::assert_rel(kinetic, 0.5 * 0.5 * (G * DT).powi(2), 1e-9, support);
        // Resting: still at the end of every step, and where it started.
        for passes in [1, 2, 4] {
            let mut world = column(support, 1, RestingContacts::Rest, passes);
            let y = world.particles().y()[0];
            let (speed, _, gain, _) = run(&mut world, 400);
            assert_eq!(speed, 0.0, "{support}, {passes} passes");
            assert_eq!(gain, 0.0, "{support}, {passes} passes");
            assert!((world.particles().y()[0] - y).abs() < 1e-12, "{support}");
        }
    }
}

#[test]
fn a_stacked_pair_at_e_1_gains_energy_under_the_seed_and_never_under_rest() {
    // Two discs of radius 0.5 touching, the lower on the floor, e = 1 everywhere, 20,000
    // steps. The seed's bounces leave the pair with up to 2 ½ m (g h)² of kinetic energy on
    // top of the potential it started with: a gain of (g h)² / (2 g Σ y) = 0.1 % here.
    let mut seed = column("floor", 2, RestingContacts::Bounce, 1);
    let (_, _, gain, _) = run(&mut seed, 20_000);
    common::assert_rel(gain, 1e-3, 1e-6, "the seed's gain");
    // Resting, under both restitution models and 1, 2 and 4 passes, the pair never gains:
    // it only loses the little potential energy of the overlap gravity presses in
    // (g h² per substep, pushed half back).
    for model in [
        RestitutionModel::ScaleEachNormalVelocity,
        RestitutionModel::RelativeNormalVelocity,
    ] {
        for passes in [1, 2, 4] {
            let mut world = column("floor", 2, RestingContacts::Rest, passes);
            world
                .set_config(Config {
                    restitution_model: model,
                    ..world.config().clone()
                })
                .unwrap();
            let (_, kinetic, gain, loss) = run(&mut world, 20_000);
            let what = format!("{model:?}, {passes} passes");
            assert!(gain <= 1e-15, "{what}: gain {gain}");
            assert!(loss > -1e-3, "{what}: loss {loss}");
            if model == RestitutionModel::ScaleEachNormalVelocity {
                // The seed's step 6 at e = 0 stops both: the pair is still.
                assert_eq!(kinetic, 0.0, "{what}");
            } else {
                // One common velocity per pass: the floor's support reaches the top disc
                // a pass at a time, so its residual speed halves with each pass.
                assert!(
                    kinetic <= 2.0 * 0.5 * 0.5 * (G * DT).powi(2),
                    "{what}: {kinetic}"
                );
            }
        }
    }
}

#[test]
fn a_column_of_five_rests_under_the_seeds_model_with_rest() {
    // Five discs stacked on the floor at one pass: the seed's bounce pumps energy into the
    // column (it ends far from rest); resting contacts keep it still.
    let mut seed = column("floor", 5, RestingContacts::Bounce, 1);
    let (_, _, seed_gain, _) = run(&mut seed, 5_000);
    assert!(seed_gain > 0.01, "the seed's column gains {seed_gain}");
    for passes in [1, 2, 4] {
        let mut world = column("floor", 5, RestingContacts::Rest, passes);
        let (speed, _, gain, loss) = run(&mut world, 5_000);
        assert_eq!((speed, gain), (0.0, 0.0), "{passes} passes");
        assert!(loss > -5e-3, "{passes} passes: {loss}");
    }
}

#[test]
fn impacts_keep_their_restitution_and_worlds_without_gravity_keep_their_bits() {
    // A disc dropped from 2 above the floor at e = 0.8: under both options the same bits
    // through its first bounces (impacts), until it has settled far enough to rest.
    let dropped = |rest| {
        let config = Config {
            gravity: [0.0, -G],
            coefficient_of_restitution: 0.8,
            boundary: Boundary::walls([0.0, 0.0], [10.0, 20.0]),
            resting_contacts: rest,
            ..Config::default()
        };
        let mut world = World::new(config).unwrap();
        world
            .add_particle(Particle::new([5.0, 2.5], [0.0, 0.0], 0.5))
            .unwrap();
        world
    };
    let (mut seed, mut rest) = (
        dropped(RestingContacts::Bounce),
        dropped(RestingContacts::Rest),
    );
    let mut bounces = 0;
    for _ in 0..400 {
        let before = seed.particles().vy()[0];
        seed.step(DT).unwrap();
        rest.step(DT).unwrap();
        bounces += (before < 0.0 && seed.particles().vy()[0] > 0.0) as usize;
        assert_eq!(seed.state_hash(), rest.state_hash());
    }
    assert!(bounces >= 3, "{bounces} bounces");
    // Later the seed's disc keeps bouncing at about |g| h, the resting one stops.
    for _ in 0..3000 {
        seed.step(DT).unwrap();
        rest.step(DT).unwrap();
    }
    assert!(seed.stats().kinetic_energy > 0.0);
    assert_eq!(rest.stats().kinetic_energy, 0.0);
    // Without gravity no contact rests: an elastic gas keeps the seed's bits.
    let gas = |rest| {
        let config = Config {
            boundary: Boundary::walls([0.0, 0.0], [30.0, 30.0]),
            resting_contacts: rest,
            ..Config::default()
        };
        common::gas_world(
            config,
            300,
            [0.3, 0.6],
            bounce::scene::Speeds::Uniform(1.0),
            [0.0, 0.0],
            5,
        )
    };
    let (mut a, mut b) = (gas(RestingContacts::Bounce), gas(RestingContacts::Rest));
    for _ in 0..200 {
        a.step(0.02).unwrap();
        b.step(0.02).unwrap();
    }
    assert!(a.stats().collisions > 0);
    assert_eq!(a.state_hash(), b.state_hash());
    assert_eq!(Law::at_substep(b.config(), 0.02).rest_below, None);
}

#[test]
fn touching_discs_falling_together_are_held_back_by_the_seeds_model_only() {
    // Two discs touching one above the other, dropped from high up: their contact approaches
    // at 0, a resting contact. The seed's step 6 at restitution 0 sets both normal
    // velocities to 0 each substep, so they sink at |g| h (as the seed's own model slows them
    // at e < 1); the momentum-conserving model keeps their common velocity: free fall.
    let falling = |model| {
        let config = Config {
            gravity: [0.0, -G],
            boundary: Boundary::walls([0.0, 0.0], [10.0, 200.0]),
            restitution_model: model,
            resting_contacts: RestingContacts::Rest,
            ..Config::default()
        };
        let mut world = World::new(config).unwrap();
        world
            .add_particle(Particle::new([5.0, 150.0], [0.0, 0.0], 0.5))
            .unwrap();
        world
            .add_particle(Particle::new([5.0, 151.0], [0.0, 0.0], 0.5))
            .unwrap();
        for _ in 0..100 {
            world.step(DT).unwrap();
        }
        world.particles().vy().to_vec()
    };
    let held = falling(RestitutionModel::ScaleEachNormalVelocity);
    assert!(held.iter().all(|v| v.abs() <= G * DT + 1e-12), "{held:?}");
    let free = falling(RestitutionModel::RelativeNormalVelocity);
    for v in free {
        common::assert_rel(v, -G * DT * 100.0, 1e-9, "free fall");
    }
}
