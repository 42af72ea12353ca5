//! Rough discs (`law::rough`): the tangential impulse and the rolling couple against hand-worked
//! impulse equations, a disc rolling and sliding down an incline against Newton, the
//! conservation laws, homogeneous cooling against kinetic theory, and the same bits on any
//! thread count.

mod common;

use bounce::law::{Body, Law, resolve_pair};
use bounce::{
    Boundary, Config, Obstacle, Particle, ParticleId, RestitutionModel, VelocityUpdate, World,
};
use common::assert_close;

/// Two equal discs (radius 1, the seed's mass 1, I = ½) meeting head on along x, touching,
/// with spin: worked by hand in the comments.
fn oblique_pair(friction: f64) -> bounce::law::Resolution {
    let law = Law::new(&Config {
        friction,
        ..Config::default()
    });
    let a = Body {
        angular_velocity: 1.0,
        ..Body::new([2.0, 1.0], 1.0, 1.0)
    };
    let b = Body {
        angular_velocity: 2.0,
        ..Body::new([-1.0, 0.0], 1.0, 1.0)
    };
    // diff = p1 - p2 = (-2, 0): n = (-1, 0), t = (0, -1). The seed's normal update (e = 1,
    // equal masses) exchanges the normal velocities: v1 = (-1, 1), v2 = (2, 0), and
    // J_n = ½ (1·3 − 1·(−3)) = 3.
    resolve_pair([-2.0, 0.0], &a, &b, &law)
}

#[test]
fn an_oblique_pair_with_spin_sticks_or_slips_as_the_impulse_equations_say() {
    // Slip g = v1·t − l1 ω1 − (v2·t + l2 ω2) = −1 − 1 − (0 + 2) = −4 (lever arms 1);
    // w = 1/m1 + 1/m2 + l1²/I1 + l2²/I2 = 6; sticking (β = 0): J_t = 4/6 = 2/3, within
    // μ J_n for μ >= 2/9.
    let stick = oblique_pair(0.5);
    let close = |a: [f64; 2], b: [f64; 2], what: &str| {
        assert_close(a[0], b[0], 1e-12, what);
        assert_close(a[1], b[1], 1e-12, what);
    };
    // v1 = (−1, 1) + (2/3)(0, −1), v2 = (2, 0) − (2/3)(0, −1); ω_i −= l J_t / I = 4/3.
    close(stick.v1, [-1.0, 1.0 / 3.0], "v1, stick");
    close(stick.v2, [2.0, 2.0 / 3.0], "v2, stick");
    assert_close(stick.w1, -1.0 / 3.0, 1e-12, "w1, stick");
    assert_close(stick.w2, 2.0 / 3.0, 1e-12, "w2, stick");
    // Rolling contact after: no slip. The energy removed, −J (g + g′)/2 = 4/3.
    assert_close(
        -stick.v1[1] - stick.w1 - (-stick.v2[1] + stick.w2),
        0.0,
        1e-12,
        "slip after",
    );
    assert_close(stick.friction_work, 4.0 / 3.0, 1e-12, "work, stick");
    // μ = 0.1: Coulomb's limit μ J_n = 0.3 holds the impulse; the discs still slip.
    let slip = oblique_pair(0.1);
    close(slip.v1, [-1.0, 0.7], "v1, slip");
    close(slip.v2, [2.0, 0.3], "v2, slip");
    assert_close(slip.w1, 1.0 - 0.6, 1e-12, "w1, slip");
    assert_close(slip.w2, 2.0 - 0.6, 1e-12, "w2, slip");
    // Angular momentum about the origin (disc 1 there, disc 2 at (2, 0)) before and after:
    // 0.5·1 + (2·0 + 0.5·2) = 1.5.
    for out in [stick, slip] {
        let l = 0.5 * out.w1 + (2.0 * out.v2[1] + 0.5 * out.w2);
        assert_close(l, 1.5, 1e-12, "angular momentum");
    }
}

/// A disc of radius 0.5 (the seed's mass 0.5, I = k m r² = 1/16) at `x`, 0.01 above the
/// floor of a box, falling at 2 with `vx` and spin 3, one step of 0.01 without gravity.
fn drop_on_floor(friction: f64, tangential_restitution: f64) -> (Particle, f64) {
    let config = Config {
        boundary: Boundary::walls([-10.0, 0.0], [10.0, 10.0]),
        friction,
        tangential_restitution,
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    world
        .add_particle(Particle {
            angular_velocity: 3.0,
            ..Particle::new([0.0, 0.51], [1.0, -2.0], 0.5)
        })
        .unwrap();
    let stats = *world.step(0.01).unwrap();
    (world.particle(ParticleId(0)).unwrap(), stats.friction_work)
}

#[test]
fn a_spinning_disc_dropped_on_a_floor_leaves_as_the_impulse_equations_say() {
    // The floor reflects vy = −2 to 2 (e = 1): J_n = m·4 = 2. Normal n = (0, 1), tangent
    // t = (−1, 0), lever r = 0.5: slip g = v·t − r ω = −1 − 1.5 = −2.5; w = 1/m + r²/I =
    // 2 + 4 = 6.
    // Sticking (β = 0): J_t = 2.5/6 = 5/12 (within μ J_n for μ >= 5/24): vx = 1 − J_t/m =
    // 1/6, ω = 3 − r J_t/I = −1/3: rolling (vx = −r ω).
    let (disc, work) = drop_on_floor(0.5, 0.0);
    assert_close(disc.velocity[0], 1.0 / 6.0, 1e-12, "vx, stick");
    assert_close(disc.velocity[1], 2.0, 1e-12, "vy, stick");
    assert_close(disc.angular_velocity, -1.0 / 3.0, 1e-12, "ω, stick");
    // −J (g + g′)/2 with g′ = 0: 25/24.
    assert_close(work, 2.5 * 2.5 / 12.0, 1e-12, "work, stick");
    // β = 1 reverses the slip: twice the impulse, no energy lost.
    let (disc, work) = drop_on_floor(0.5, 1.0);
    assert_close(
        disc.velocity[0],
        1.0 - 2.0 * (5.0 / 12.0) / 0.5,
        1e-12,
        "vx, β = 1",
    );
    assert_close(
        disc.angular_velocity,
        3.0 - 0.5 * (5.0 / 6.0) * 16.0,
        1e-12,
        "ω, β = 1",
    );
    assert!(work.abs() < 1e-12, "{work}");
    // μ = 0.1: J_t = μ J_n = 0.2: vx = 1 − 0.4, ω = 3 − 0.5·0.2·16 = 1.4.
    let (disc, _) = drop_on_floor(0.1, 0.0);
    assert_close(disc.velocity[0], 0.6, 1e-12, "vx, slip");
    assert_close(disc.angular_velocity, 1.4, 1e-12, "ω, slip");
    // Smooth (the default): the seed's reflection, the spin kept.
    let (disc, work) = drop_on_floor(0.0, 0.0);
    assert_eq!(
        (disc.velocity, disc.angular_velocity, work),
        ([1.0, 2.0], 3.0, 0.0)
    );
}

/// A disc of radius 0.5 released at rest on a segment inclined at 20° (gravity −10), run
/// for 1.5 time units: its acceleration along the slope, from the distance travelled, and
/// its rotational over translational kinetic energy at the end.
fn incline(friction: f64) -> (f64, f64) {
    let angle = 20f64.to_radians();
    let (c, s) = (angle.cos(), angle.sin());
    // The slope from (−40, 0) up to the left; the disc touches it at its middle.
    let (a, b) = ([-40.0 * c, 40.0 * s], [40.0 * c, -40.0 * s]);
    let config = Config {
        gravity: [0.0, -10.0],
        friction,
        substeps: 4,
        obstacles: vec![Obstacle::segment(a, b)],
        ..Config::default()
    };
    let normal = [s, c];
    let start = [-20.0 * c + 0.5 * normal[0], 20.0 * s + 0.5 * normal[1]];
    let mut world = World::new(config).unwrap();
    world
        .add_particle(Particle::new(start, [0.0, 0.0], 0.5))
        .unwrap();
    let (dt, steps) = (0.001, 1500);
    for _ in 0..steps {
        world.step(dt).unwrap();
    }
    let disc = world.particle(ParticleId(0)).unwrap();
    let down = [c, -s];
    let travelled =
        (disc.position[0] - start[0]) * down[0] + (disc.position[1] - start[1]) * down[1];
    let t = dt * steps as f64;
    let v2 = disc.velocity[0].powi(2) + disc.velocity[1].powi(2);
    let rotational = 0.5 * (0.5 * 0.5 * 0.25) * disc.angular_velocity.powi(2);
    (2.0 * travelled / (t * t), rotational / (0.5 * 0.5 * v2))
}

#[test]
fn a_disc_rolls_down_an_incline_without_slipping_or_slides_as_newton_says() {
    let (g, angle) = (10.0, 20f64.to_radians());
    // μ = 0.5 > tan θ / 3: rolling, a = g sin θ / (1 + k) = (2/3) g sin θ, and the rotational
    // energy is k = ½ of the translational.
    let (a, ratio) = incline(0.5);
    common::assert_rel(a, 2.0 / 3.0 * g * angle.sin(), 0.01, "rolling acceleration");
    common::assert_rel(ratio, 0.5, 0.01, "rotational / translational energy");
    // μ = 0.05 < tan θ / 3: sliding, a = g (sin θ − μ cos θ).
    let (a, _) = incline(0.05);
    common::assert_rel(
        a,
        g * (angle.sin() - 0.05 * angle.cos()),
        0.01,
        "sliding acceleration",
    );
}

/// A dilute gas of rough discs in a periodic box: radius 0.5, packing 0.05, speeds uniform
/// in ±1, spins uniform in ±2.
fn rough_gas(config: Config, count: usize) -> World {
    let side = common::box_side(count, 0.25, 0.05);
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        ..config
    };
    let mut discs = bounce::scene::gas(
        &bounce::scene::Gas {
            count,
            radius: [0.5, 0.5],
            region: None,
            speeds: bounce::scene::Speeds::Uniform(1.0),
            drift: [0.0, 0.0],
            seed: 7,
        },
        &config,
    )
    .unwrap();
    bounce::scene::spin(&mut discs, 2.0, 7);
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world
}

fn total_energy(world: &World) -> f64 {
    world.stats().kinetic_energy + world.rotational_energy()
}

#[test]
fn elastic_rough_discs_conserve_energy_and_smooth_tangents_change_nothing() {
    // β = 1 with e = 1 and a friction never reached: every contact reverses its slip, and
    // translational plus rotational energy is kept, to rounding.
    let elastic = Config {
        friction: 1e6,
        tangential_restitution: 1.0,
        ..Config::default()
    };
    let mut world = rough_gas(elastic, 400);
    let start = total_energy(&world);
    let mut collisions = 0;
    for _ in 0..1000 {
        collisions += world.step(0.05).unwrap().collisions;
    }
    assert!(collisions > 500, "{collisions} collisions");
    let end = total_energy(&world);
    assert!(
        ((end - start) / start).abs() < 1e-12,
        "energy {start} -> {end}"
    );
    assert!(world.friction_work().abs() < 1e-12 * start);
    // Energy moved between translation and rotation all the same.
    let rotational_start = rough_gas(Config::default(), 400).rotational_energy();
    assert!((world.rotational_energy() - rotational_start).abs() > 0.01 * start);

    // β = −1 leaves every slip as it was: with friction the gas moves exactly as smooth
    // discs do, and the spins stay.
    let smooth = rough_gas(Config::default(), 400);
    let unchanged = Config {
        friction: 0.5,
        tangential_restitution: -1.0,
        ..Config::default()
    };
    let (mut smooth, mut rough) = (smooth, rough_gas(unchanged, 400));
    let spins = rough.angular_velocities();
    for _ in 0..200 {
        smooth.step(0.02).unwrap();
        rough.step(0.02).unwrap();
    }
    assert_eq!(smooth.stats().kinetic_energy, rough.stats().kinetic_energy);
    assert_eq!(
        smooth
            .particles_by_id()
            .iter()
            .map(|p| p.1.position)
            .collect::<Vec<_>>(),
        rough
            .particles_by_id()
            .iter()
            .map(|p| p.1.position)
            .collect::<Vec<_>>()
    );
    assert_eq!(rough.angular_velocities(), spins);
    assert_eq!(rough.friction_work(), 0.0);
}

#[test]
fn a_rough_pair_keeps_its_momentum_and_its_angular_momentum() {
    // Random pairs, overlapping or touching, every restitution at e = 1 (momentum kept by
    // the normal update), stick and slip: the tangential impulse and the rolling couple keep
    // the momentum and the angular momentum about the origin (taken at the places the push
    // leaves), to rounding.
    let mut next = common::uniform(0x2545_f491_4f6c_dd1d);
    for case in 0..2000 {
        let law = Law::new(&Config {
            friction: 2.0 * next(),
            tangential_restitution: 2.0 * next() - 1.0,
            rolling_resistance: 0.5 * next(),
            inertia_factor: 0.2 + 0.8 * next(),
            collision_radius_scale: 1.0 + 0.2 * next(),
            restitution_model: RestitutionModel::RelativeNormalVelocity,
            velocity_update: VelocityUpdate::ApproachingOnly,
            ..Config::default()
        });
        let body = |next: &mut dyn FnMut() -> f64| Body {
            angular_velocity: 6.0 * next() - 3.0,
            ..Body::new(
                [4.0 * next() - 2.0, 4.0 * next() - 2.0],
                0.2 + next(),
                0.5 + next(),
            )
        };
        let (a, b) = (body(&mut next), body(&mut next));
        let reach = law.collision_distance(a.radius, b.radius);
        let angle = std::f64::consts::TAU * next();
        let d = reach * (0.8 + 0.2 * next());
        let p1 = [3.0 * next(), 3.0 * next()];
        let p2 = [p1[0] - d * angle.cos(), p1[1] - d * angle.sin()];
        let out = resolve_pair([p1[0] - p2[0], p1[1] - p2[1]], &a, &b, &law);
        let (q1, q2) = (
            [p1[0] + out.push[0], p1[1] + out.push[1]],
            [p2[0] - out.push[0], p2[1] - out.push[1]],
        );
        let inertia = |body: &Body| law.rough.unwrap().inertia(body.mass, body.radius);
        let angular = |p: [f64; 2], v: [f64; 2], w: f64, body: &Body| {
            body.mass * (p[0] * v[1] - p[1] * v[0]) + inertia(body) * w
        };
        let before = angular(q1, a.velocity, a.angular_velocity, &a)
            + angular(q2, b.velocity, b.angular_velocity, &b);
        let after = angular(q1, out.v1, out.w1, &a) + angular(q2, out.v2, out.w2, &b);
        assert!(
            (after - before).abs() < 1e-12 * (1.0 + before.abs()),
            "case {case}: {before} -> {after}"
        );
        for k in 0..2 {
            let p = a.mass * a.velocity[k] + b.mass * b.velocity[k];
            let q = a.mass * out.v1[k] + b.mass * out.v2[k];
            assert!((p - q).abs() < 1e-12, "case {case}: momentum {p} -> {q}");
        }
        assert!(
            out.friction_work >= -1e-12,
            "case {case}: {}",
            out.friction_work
        );
    }
}

#[test]
fn rough_discs_give_the_same_bits_on_any_thread_count() {
    let (config, discs) = bounce::scene::Bench::Pile.build(6000).unwrap();
    let config = Config {
        friction: 0.5,
        rolling_resistance: 0.05,
        ..config
    };
    let hashes: Vec<u64> = [1, 2, 3]
        .iter()
        .map(|&threads| {
            let mut world = World::new(config.clone()).unwrap();
            world.add_particles(discs.clone()).unwrap();
            world.set_threads(threads).unwrap();
            world.set_parallel_min_work(0);
            for _ in 0..60 {
                world.step(bounce::scene::Bench::DT).unwrap();
            }
            assert!(world.friction_work() > 0.0);
            world.state_hash()
        })
        .collect();
    assert!(hashes.iter().all(|&h| h == hashes[0]), "{hashes:x?}");
}

/// The ratio `R = T_rot / T_tr` a homogeneously cooling gas of rough discs reaches in the
/// two-temperature (Maxwellian) kinetic theory of Huthmann and Zippelius (PRE 56, R6275,
/// 1997) and Luding, Huthmann, McNamara and Zippelius (PRE 58, 3416, 1998), worked out for
/// discs (one rotational degree of freedom, one tangential direction). With `q` the inertia
/// factor, normal restitution `e` and tangential `β`, `η = q (1 + β) / (2 (1 + q))`; averaged
/// over Maxwellian collisions, a collision changes the translational energy by
/// `2 (−A T_tr + B T_rot)` and the rotational by `2 (B T_tr − C T_rot)`, with
/// `A = (1 − e²)/2 + η (1 − η)`, `B = η² / q`, `C = (η / q)(1 − η / q)`. As `E_tr = N T_tr`
/// (two degrees of freedom) and `E_rot = N T_rot / 2` (one), both temperatures decay at one
/// rate when `B R² + (2C − A) R − 2B = 0`.
fn cooling_ratio(e: f64, beta: f64, q: f64) -> f64 {
    let eta = q * (1.0 + beta) / (2.0 * (1.0 + q));
    let a = (1.0 - e * e) / 2.0 + eta * (1.0 - eta);
    let b = eta * eta / q;
    let c = eta / q * (1.0 - eta / q);
    ((a - 2.0 * c) + ((a - 2.0 * c).powi(2) + 8.0 * b * b).sqrt()) / (2.0 * b)
}

#[test]
fn homogeneous_cooling_reaches_the_kinetic_theorys_temperature_ratio() {
    // Elastic rough discs are at equipartition (R = 1); smooth ones never spin up.
    assert!((cooling_ratio(1.0, 1.0, 0.5) - 1.0).abs() < 1e-15);
    // 20,000 discs at packing 0.05 (dilute: Boltzmann's kinetic theory), spins started at
    // R = 0.5; a friction never reached (constant β), the standard normal restitution. R over
    // the second half of 8,000 steps (about 8 to 15 collisions per disc), against theory.
    for (e, beta) in [(1.0, 0.5), (1.0, 0.8), (0.95, 0.0)] {
        let config = Config {
            coefficient_of_restitution: e,
            restitution_model: RestitutionModel::RelativeNormalVelocity,
            velocity_update: VelocityUpdate::ApproachingOnly,
            friction: 1e6,
            tangential_restitution: beta,
            ..Config::default()
        };
        let mut world = rough_gas(config, 20_000);
        let (mut ratio, mut samples) = (0.0, 0);
        let mut collisions = 0;
        for step in 0..8000 {
            collisions += world.step(0.02).unwrap().collisions;
            if step >= 4000 && step % 10 == 0 {
                ratio += 2.0 * world.rotational_energy() / world.stats().kinetic_energy;
                samples += 1;
            }
        }
        assert!(collisions > 20_000 * 6 / 2, "{collisions} collisions");
        let measured = ratio / samples as f64;
        common::assert_rel(measured, cooling_ratio(e, beta, 0.5), 0.03, "T_rot / T_tr");
    }
}
