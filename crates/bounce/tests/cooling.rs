//! Several solver passes, correct: a later pass acts only on pairs still approaching, so a
//! pair collides once however many passes there are, and a freely cooling granular gas
//! loses the energy kinetic theory says its collisions take (Haff's law), at 1, 2 and 4
//! passes.

mod common;

use bounce::scene::Speeds;
use bounce::{Boundary, Config, Particle, RestitutionModel, World};
use common::{assert_rel, box_side, gas_world};

/// Two equal discs met head on, stepped until long after: the steps in which they were
/// found colliding, and their velocities at the end.
fn head_on(passes: u32) -> (usize, [f64; 2]) {
    let mut world = World::new(Config {
        boundary: Boundary::walls([0.0, 0.0], [100.0, 20.0]),
        solver_iterations: passes,
        ..Config::default()
    })
    .unwrap();
    world
        .add_particle(Particle::new([40.0, 10.0], [1.0, 0.0], 1.0))
        .unwrap();
    world
        .add_particle(Particle::new([60.0, 10.0], [-1.0, 0.0], 1.0))
        .unwrap();
    let mut colliding_steps = 0;
    for _ in 0..2000 {
        if world.step(0.01).unwrap().pairs > 0 {
            colliding_steps += 1;
        }
    }
    let p = world.particles();
    (colliding_steps, [p.vx()[0], p.vx()[1]])
}

#[test]
fn a_head_on_pair_collides_once_at_any_number_of_passes() {
    for passes in [1, 2, 4] {
        let (colliding, v) = head_on(passes);
        assert_eq!(
            colliding, 1,
            "{passes} passes: collided in {colliding} steps"
        );
        // They swapped velocities (equal masses, e = 1) and fly apart.
        assert_eq!(v, [-1.0, 1.0], "{passes} passes");
    }
}

/// A freely cooling gas of equal discs at packing 0.1 in a periodic box, restitution `e`
/// under the momentum-conserving model: the temperature (per disc, `E / N` in 2D) and the
/// collisions counted since the start, at each of `samples` times.
fn cooling(passes: u32, e: f64, count: usize, samples: &[f64], dt: f64) -> Vec<(f64, f64, f64)> {
    let side = box_side(count, 0.25, 0.1);
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        coefficient_of_restitution: e,
        restitution_model: RestitutionModel::RelativeNormalVelocity,
        solver_iterations: passes,
        ..Config::default()
    };
    let mut world = gas_world(
        config,
        count,
        [0.5, 0.5],
        Speeds::Temperature(1.0),
        [0.0, 0.0],
        7,
    );
    // At rest as a whole: the temperature is the kinetic energy per disc.
    let mut collisions = 0usize;
    let mut out = Vec::new();
    let mut t = 0.0;
    for &until in samples {
        while t < until - dt / 2.0 {
            collisions += world.step(dt).unwrap().pairs;
            t += dt;
        }
        let temperature = world.stats().kinetic_energy / count as f64;
        out.push((t, temperature, collisions as f64));
    }
    out
}

#[test]
fn a_cooling_gas_follows_haffs_law_at_one_two_and_four_passes() {
    // Haff: each collision of equal discs takes (1 − e²) T on average from a Maxwellian
    // gas (the relative normal velocity of colliding pairs has <(g·n)²> = 4 T / m), so
    // dT/dt = −(1 − e²) ω T / 2 with the collision frequency per disc ω ∝ √T:
    //   T(t) = T0 / (1 + t / t0)²,  1 / t0 = (1 − e²) ω0 / 4,
    // and the collisions counted by then, C(t) = (2 N / (1 − e²)) ln(1 + t / t0), give ω0
    // from the whole run: ω0 = 4 / ((1 − e²) t) (exp((1 − e²) C / (2 N)) − 1).
    // Extra resolutions of separated pairs take energy no collision is counted for: the
    // gas then cools faster than its collisions say.
    let (e, count, dt) = (0.95, 4000, 0.005);
    // Until the temperature is down to about 0.4: later, the homogeneous cooling state's
    // velocity correlations (the onset of clustering) take the gas slowly off the law
    // (1.5 % by T = 0.34 in this box).
    let samples = [0.0, 7.5, 15.0, 22.5, 30.0];
    let loss = 1.0 - e * e;
    for passes in [1, 2, 4] {
        let run = cooling(passes, e, count, &samples, dt);
        let (t_end, _, c_end) = *run.last().unwrap();
        let omega0 = 4.0 / (loss * t_end) * ((loss * c_end / (2.0 * count as f64)).exp() - 1.0);
        let inverse_t0 = loss * omega0 / 4.0;
        // The generator's temperature, up to sampling.
        let start = run[0].1;
        assert_rel(
            start,
            1.0,
            0.03,
            &format!("{passes} passes: the start's temperature"),
        );
        for &(t, temperature, collisions) in &run {
            let haff = start / (1.0 + t * inverse_t0).powi(2);
            assert_rel(
                temperature,
                haff,
                0.02,
                &format!("{passes} passes: T({t}) against Haff's law"),
            );
            // The energy balance itself: T = T0 exp(−(1 − e²) C / N).
            let balance = start * (-loss * collisions / count as f64).exp();
            assert_rel(
                temperature,
                balance,
                0.02,
                &format!("{passes} passes: T({t}) against its collisions"),
            );
        }
        // The gas cooled well into the law (to under half its temperature).
        assert!(
            run.last().unwrap().1 < 0.5 * start,
            "{passes} passes: {run:?}"
        );
    }
}
