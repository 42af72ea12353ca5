//! The pressure tensor ([`Config::pressure_tensor`]): a head-on collision's virial by hand,
//! the same bits as without it, its trace the pressure, and an equilibrium gas isotropic.

use bounce::scene::{self, Gas, Speeds};
use bounce::{Boundary, Config, Method, Particle, World};

fn pair(pressure_tensor: bool) -> World {
    let config = Config {
        boundary: Boundary::periodic([-10.0, -10.0], [10.0, 10.0]),
        pressure_tensor,
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    // After one step of 0.5 they touch at x = 0 and 2, approaching at 1 each.
    world
        .add_particle(Particle::new([-0.5, 0.0], [1.0, 0.0], 1.0))
        .unwrap();
    world
        .add_particle(Particle::new([2.5, 0.0], [-1.0, 0.0], 1.0))
        .unwrap();
    world
}

#[test]
fn a_head_on_collision_has_the_hand_computed_virial_tensor() {
    let mut world = pair(true);
    let stats = *world.step(0.5).unwrap();
    // r = x_a − x_b = (−2, 0); the seed's exchange at e = 1 (masses = radii = 1) swaps the
    // velocities: J on a = ½ (1 (−1 − 1) − 1 (1 + 1)) = −2 along x. W_xx = r_x J_x / dt = 8.
    assert_eq!(stats.collisions, 1);
    assert_eq!(stats.virial_tensor, [8.0, 0.0, 0.0]);
    assert_eq!(stats.virial, 4.0);
    // P = (Σ m u u + W) / A, A the periodic box's 400: the discs move along x only.
    let [xx, yy, xy] = world.pressure_tensor().unwrap();
    assert_eq!([xx, yy, xy], [(1.0 + 1.0 + 8.0) / 400.0, 0.0, 0.0]);
    // Measuring changes nothing; without the switch there is no tensor.
    let mut plain = pair(false);
    plain.step(0.5).unwrap();
    assert_eq!(plain.state_hash(), world.state_hash());
    assert_eq!(plain.stats().virial_tensor, [0.0; 3]);
    assert!(plain.pressure_tensor().is_none());
}

fn gas(method: Method) -> World {
    let side = (2000.0 * std::f64::consts::PI * 0.25 / 0.4f64).sqrt();
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        pressure_tensor: true,
        method,
        ..Config::default()
    };
    let discs = scene::packed_gas(
        &Gas {
            count: 2000,
            radius: [0.5, 0.5],
            region: None,
            speeds: Speeds::Temperature(1.0),
            drift: [0.0, 0.0],
            seed: 7,
        },
        &config,
        &[],
    )
    .unwrap();
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world
}

#[test]
fn the_trace_is_the_pressure_and_an_equilibrium_gas_is_isotropic() {
    for (method, dt) in [(Method::EventDriven, 0.1), (Method::TimeStepped, 0.002)] {
        let mut world = gas(method);
        let (mut sum, mut samples) = ([0.0; 3], 0.0);
        for step in 0..400 {
            let stats = *world.step(dt).unwrap();
            let tensor = world.pressure_tensor().unwrap();
            let pressure = stats.pressure.unwrap();
            let trace = (tensor[0] + tensor[1]) / 2.0;
            assert!(
                (trace / pressure - 1.0).abs() < 1e-12,
                "{method:?}: {trace} vs {pressure}"
            );
            if step >= 100 {
                for k in 0..3 {
                    sum[k] += tensor[k];
                }
                samples += 1.0;
            }
        }
        let [xx, yy, xy] = sum.map(|v| v / samples);
        let mean = (xx + yy) / 2.0;
        assert!((xx / yy - 1.0).abs() < 0.02, "{method:?}: {xx} vs {yy}");
        assert!(xy.abs() < 0.01 * mean, "{method:?}: P_xy = {xy}");
    }
}
