//! Lees–Edwards boundaries: the sliding images by hand (a disc through the top and the
//! bottom, a pair across them resolved with the image's velocity), the fast step equal to
//! the plain one on any thread count and across a save, the pinned periodic bits untouched,
//! and a sheared gas's linear velocity profile at the imposed rate.

mod common;

use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config, Particle, Thermostat, ThermostatKind, World, plain};

fn sheared(size: f64, shear_rate: f64) -> Config {
    Config {
        boundary: Boundary::lees_edwards([0.0, 0.0], [size, size], shear_rate),
        ..Config::default()
    }
}

#[test]
fn a_disc_through_the_bottom_comes_back_at_the_top_moved_on_by_the_offset() {
    // Box 10 × 10 at shear rate 0.1: the images above move at +1, those below at −1.
    let mut world = World::new(sheared(10.0, 0.1)).unwrap();
    let id = world
        .add_particle(Particle::new([9.8, 0.2], [0.5, -1.0], 0.5))
        .unwrap();
    world.step(0.5).unwrap();
    // At t = 0.5 the offset is 0.5. The disc reached (10.05, −0.3): the box below stands
    // 0.5 to the left, so it re-enters at (10.05 + 0.5, 9.7) → wrapped to x = 0.55, its x
    // velocity 0.5 + 1.
    let disc = world.particle(id).unwrap();
    common::assert_close(disc.position[0], 0.55, 1e-12, "x");
    common::assert_close(disc.position[1], 9.7, 1e-12, "y");
    assert_eq!(disc.velocity, [1.5, -1.0]);
    assert_eq!(world.lees_edwards_offset(), Some(0.5));
    // The offset stays within half a width: at t = 7.5, 7.5 − 10.
    for _ in 0..14 {
        world.step(0.5).unwrap();
    }
    common::assert_close(world.lees_edwards_offset().unwrap(), -2.5, 1e-12, "offset");
}

/// Two discs of radius 0.5 across the top and bottom of a sheared box, touching after one
/// step of 0.5; `top_first` gives the top disc the lower id.
fn seam_pair(top_first: bool) -> (World, [bounce::ParticleId; 2]) {
    let mut world = World::new(sheared(10.0, 0.1)).unwrap();
    let top = Particle::new([5.0, 9.6], [0.0, 0.0], 0.5);
    let bottom = Particle::new([4.2, 0.3], [0.0, 0.0], 0.5);
    let ids = if top_first {
        let t = world.add_particle(top).unwrap();
        [t, world.add_particle(bottom).unwrap()]
    } else {
        let b = world.add_particle(bottom).unwrap();
        [world.add_particle(top).unwrap(), b]
    };
    (world, ids)
}

#[test]
fn a_pair_across_the_top_meets_the_image_with_its_sliding_velocity() {
    for top_first in [true, false] {
        let (mut world, [top, bottom]) = seam_pair(top_first);
        let stats = *world.step(0.5).unwrap();
        assert_eq!(stats.collisions, 1, "top first: {top_first}");
        // At t = 0.5 the box above stands 0.5 along x and moves at +1: the bottom disc's
        // image is at (4.7, 10.3), moving at (1, 0); the top disc rests at (5, 9.6).
        let r: [f64; 2] = [5.0 - 4.7, 9.6 - 10.3];
        let d = (r[0] * r[0] + r[1] * r[1]).sqrt();
        let n = [r[0] / d, r[1] / d];
        let half_overlap = 0.5 * (1.0 - d);
        // The seed's law at e = 1 with equal masses swaps the normal velocities: the top disc
        // takes the image's normal part (1, 0)·n; the image keeps its tangential part.
        let vn = n[0];
        let want_top = [vn * n[0], vn * n[1]];
        let image_after = [1.0 - vn * n[0], -vn * n[1]];
        let t = world.particle(top).unwrap();
        let b = world.particle(bottom).unwrap();
        let close = |got: [f64; 2], want: [f64; 2], what: &str| {
            for k in 0..2 {
                common::assert_close(got[k], want[k], 1e-12, what);
            }
        };
        close(t.velocity, want_top, "the top disc's velocity");
        // Back in the box's own frame, the image's velocity less the images' speed.
        close(
            b.velocity,
            [image_after[0] - 1.0, image_after[1]],
            "the bottom disc's",
        );
        close(
            t.position,
            [5.0 + half_overlap * n[0], 9.6 + half_overlap * n[1]],
            "the top disc's push",
        );
        close(
            b.position,
            [4.2 - half_overlap * n[0], 0.3 - half_overlap * n[1]],
            "the bottom disc's push",
        );
        // The plain step resolves it the same way, to the bit.
        let (mut reference, _) = seam_pair(top_first);
        plain::step(&mut reference, 0.5).unwrap();
        assert_eq!(reference.state_hash(), world.state_hash());
    }
}

/// A polydisperse gas (radii 0.3 to 1.6: several broadphase levels) in a sheared box with
/// the streaming profile, thermostatted.
fn gas(config: Config, count: usize, seed: u64) -> World {
    let rate = match config.boundary {
        Boundary::LeesEdwards { shear_rate, .. } => shear_rate,
        _ => 0.0,
    };
    let mut discs = scene::gas(
        &Gas {
            count,
            radius: [0.3, 1.6],
            region: None,
            speeds: Speeds::Temperature(1.0),
            drift: [0.0, 0.0],
            seed,
        },
        &config,
    )
    .unwrap();
    let (_, max) = config.boundary.bounds().unwrap();
    for d in &mut discs {
        d.velocity[0] += rate * (d.position[1] - 0.5 * max[1]);
    }
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world
}

#[test]
fn the_fast_step_keeps_the_plain_steps_bits_in_a_sheared_box() {
    let thermostat = Some(Thermostat::new(ThermostatKind::Rescale, 1.0, 2.0));
    let variants = [
        sheared(40.0, 0.3),
        Config {
            substeps: 2,
            solver_iterations: 2,
            pressure_tensor: true,
            thermostat,
            ..sheared(40.0, -0.7)
        },
        // A box too low for three cells: one cell, every pair tested.
        Config {
            boundary: Boundary::lees_edwards([-3.0, 2.0], [60.0, 8.5], 0.5),
            ..Config::default()
        },
    ];
    for (k, config) in variants.into_iter().enumerate() {
        let count = if k == 2 { 60 } else { 300 };
        let mut reference = gas(config.clone(), count, 11 + k as u64);
        let mut fast = [1, 2].map(|threads| {
            let mut w = gas(config.clone(), count, 11 + k as u64);
            w.set_threads(threads).unwrap();
            w
        });
        let mut collisions = 0;
        for step in 0..150 {
            plain::step(&mut reference, 0.05).unwrap();
            for w in &mut fast {
                collisions += w.step(0.05).unwrap().collisions;
            }
            for (t, w) in fast.iter().enumerate() {
                assert_eq!(
                    w.state_hash(),
                    reference.state_hash(),
                    "variant {k}, {} thread(s), step {step}",
                    t + 1
                );
            }
        }
        assert!(
            collisions > 100,
            "variant {k}: only {collisions} collisions"
        );
    }
}

#[test]
fn a_saved_sheared_world_goes_on_with_the_same_bits() {
    // Saved at several steps, so some saves fall while a candidate list is kept (the loaded
    // world lists its candidates anew where its copies stood then).
    let config = sheared(40.0, 0.3);
    for saved_at in [37, 38, 39, 40] {
        let mut world = gas(config.clone(), 300, 5);
        for _ in 0..saved_at {
            world.step(0.05).unwrap();
        }
        let bytes = postcard::to_stdvec(&world).unwrap();
        let mut resumed: World = postcard::from_bytes(&bytes).unwrap();
        for _ in 0..40 {
            world.step(0.05).unwrap();
            resumed.step(0.05).unwrap();
        }
        assert_eq!(
            resumed.state_hash(),
            world.state_hash(),
            "saved at {saved_at}"
        );
        assert_eq!(resumed.lees_edwards_offset(), world.lees_edwards_offset());
    }
}

/// `count` discs of radius 0.5 at packing `phi` from a melting lattice, in a square
/// Lees–Edwards box sheared at `shear_rate`, started in the flow and held at kT = 1 by a
/// rescaling thermostat; with the pressure tensor when asked.
fn held_in_shear(count: usize, phi: f64, shear_rate: f64, pressure_tensor: bool) -> World {
    let side = common::box_side(count, 0.25, phi);
    let config = Config {
        thermostat: Some(Thermostat::new(ThermostatKind::Rescale, 1.0, 1.0)),
        pressure_tensor,
        ..sheared(side, shear_rate)
    };
    let mut discs = common::lattice_gas(&config, count, 3);
    for d in &mut discs {
        d.velocity[0] += shear_rate * (d.position[1] - 0.5 * side);
    }
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world
}

#[test]
fn a_sheared_gas_keeps_the_linear_velocity_profile_at_the_shear_rate() {
    // 600 discs of radius 0.5 at packing 0.3 (side 38.8) sheared at γ̇ = 0.2: the images
    // slide at 7.8, against thermal speeds of about 1.4; a rescaling thermostat takes the
    // viscous heat away. The flow's own fluctuations (momentum in long waves, which decay
    // only by viscosity, in tens of time units) are what limit the measurement: least
    // squares of v_x on y over every disc, every 10 steps for 200 time units.
    let shear_rate = 0.2;
    let mut world = held_in_shear(600, 0.3, shear_rate, false);
    for _ in 0..1000 {
        world.step(0.02).unwrap();
    }
    let (mut syy, mut sy, mut svy, mut sv, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for _ in 0..1000 {
        for _ in 0..10 {
            world.step(0.02).unwrap();
        }
        let p = world.particles();
        for (&y, &vx) in p.y().iter().zip(p.vx()) {
            (syy, sy, svy, sv, n) = (syy + y * y, sy + y, svy + y * vx, sv + vx, n + 1.0);
        }
    }
    let slope = (svy / n - (sy / n) * (sv / n)) / (syy / n - (sy / n).powi(2));
    common::assert_rel(slope, shear_rate, 0.02, "the profile's slope");
    // The thermostat holds the temperature of the motion relative to the flow.
    let kt = world.peculiar_kinetic_energy() / world.len() as f64;
    common::assert_rel(kt, 1.0, 0.1, "kT relative to the flow");
}

#[test]
fn the_shear_viscosity_from_the_pressure_tensor_is_enskogs_at_packing_0_3() {
    // 1,000 discs of radius 0.5 (mass 0.5, the seed's mass = radius) at packing 0.3,
    // sheared at γ̇ = 0.1 (γ̇ σ √(m/kT) = 0.07: linear response) and held at kT = 1:
    // η = −⟨P_xy⟩ / γ̇ over 400 time units after 10, against Enskog's for hard discs (Gass
    // 1971; García-Rojo, Luding & Brey 2006): η = η0 (1/χ + 2φ + (1 + 8/π) φ² χ), with
    // η0 = √(m kT / π) / (2σ) and Henderson's contact value χ = (1 − 7φ/16) / (1 − φ)².
    let (phi, rate, dt) = (0.3, 0.1, 0.01);
    let mut world = held_in_shear(1000, phi, rate, true);
    for _ in 0..1000 {
        world.step(dt).unwrap();
    }
    let (mut xy, mut kt, mut samples) = (0.0, 0.0, 0.0);
    for _ in 0..40_000 {
        let stats = *world.step(dt).unwrap();
        let [pxx, pyy, pxy] = world.pressure_tensor().unwrap();
        // The tensor's trace is the pressure column, flow taken out of both.
        common::assert_rel(0.5 * (pxx + pyy), stats.pressure.unwrap(), 1e-9, "trace");
        xy += pxy;
        kt += world.peculiar_kinetic_energy() / world.len() as f64;
        samples += 1.0;
    }
    let (eta, kt) = (-xy / samples / rate, kt / samples);
    let chi = (1.0 - 7.0 * phi / 16.0) / (1.0f64 - phi).powi(2);
    let eta0 = (0.5 * kt / std::f64::consts::PI).sqrt() / 2.0;
    let enskog =
        eta0 * (1.0 / chi + 2.0 * phi + (1.0 + 8.0 / std::f64::consts::PI) * phi * phi * chi);
    common::assert_rel(eta, enskog, 0.1, "the shear viscosity against Enskog's");
}
