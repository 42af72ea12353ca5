//! `bounce validate`: short reference simulations, measured against theory, each with a
//! stated tolerance and a pass or a fail, so a teacher or a reviewer can see what the
//! simulator gets right before trusting it.
//!
//! The checks (the default model unless said):
//! 1. Speeds relax to the 2D Maxwell–Boltzmann (Rayleigh) distribution: Kolmogorov–Smirnov
//!    distance under the 1% critical value `1.63 / √N`.
//! 2. Energy and momentum are conserved at e = 1 in a periodic box (relative change < 1e-9).
//! 3. The equation of state: Z = P A / (N kT) from the collision virial at packings 0.1, 0.3
//!    and 0.5, against Henderson's equation for hard discs, Z = (1 + η²/8) / (1 − η)²
//!    (D. Henderson, Mol. Phys. 30, 971 (1975); within about 1% of Monte Carlo to η = 0.6),
//!    within 2.5% at mean speed × dt / σ ≈ 0.002.
//! 4. Equipartition in a binary mixture (radii 0.3 and 0.6, masses by area): the mean
//!    kinetic energy per disc of the two species agrees within 5%.
//! 5. The model options do what their documentation says, on a two-disc collision worked
//!    by hand: the default restitution loses momentum at e < 1, the relative-velocity one keeps
//!    it; `approaching_only` leaves a separating pair's velocities alone.
//! 6. Resting contacts: a disc resting on the floor (g = 10, dt = 0.01) moves at up to
//!    `|g| dt` under the default bounce and is still under `resting_contacts = "rest"`.
//! 7. Rough discs: a disc on a 20° incline rolls without slipping at `(2/3) g sin θ`
//!    (friction 0.5) and slides at `g (sin θ − μ cos θ)` (friction 0.05), within 1%.
//! 8. Exact hard discs (the event-driven method): Z at packings 0.3 and 0.5 against Monte
//!    Carlo (2.0631, 4.1062; Kolafa & Rottner, Mol. Phys. 104, 3435 (2006)) within 1%, and
//!    the collision rate at 0.3 against Enskog's `2 n σ g(σ) √(π kT / m)` with Henderson's
//!    contact value `g(σ) = (1 − 7η/16) / (1 − η)²`, within 2%.
//! 9. Shear (a Lees–Edwards box, 1,000 discs at packing 0.3, γ̇ = 0.1, held at kT = 1): the
//!    shear viscosity `−⟨P_xy⟩ / γ̇` against Enskog's for hard discs,
//!    `η0 (1/χ + 2φ + (1 + 8/π) φ² χ)` with `η0 = √(m kT / π) / (2σ)` (Gass 1971), within
//!    15% (10% over the full run's 400 time units).
//!
//! It writes `validate.png` (Z against packing with Henderson's curve) and states its runtime.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use bounce::law::{Body, Law, resolve_pair};
use bounce::scene::{self, Gas, Speeds};
use bounce::{
    Boundary, Config, MassModel, Particle, RestingContacts, RestitutionModel, VelocityUpdate, World,
};
use bounce_scenario::headline::{enskog_viscosity, maxwell_boltzmann_distance};
use plotters::prelude::*;

/// How big the reference runs are.
#[derive(Clone, Copy)]
struct Size {
    discs: usize,
    /// Time units run for each measurement.
    time: f64,
}

/// One line of the report.
struct Check {
    name: String,
    measured: String,
    expected: String,
    pass: bool,
}

use bounce_scenario::analysis::henderson_z as henderson;

/// A periodic box of `discs` equal discs (radius 0.5) at `packing`, on a melted lattice.
fn periodic_gas(discs: usize, packing: f64, speeds: Speeds, config: Config) -> Result<World> {
    let side = (discs as f64 * std::f64::consts::PI * 0.25 / packing).sqrt();
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        ..config
    };
    let gas = Gas {
        count: discs,
        radius: [0.5, 0.5],
        region: None,
        speeds,
        drift: [0.0, 0.0],
        seed: 1,
    };
    let mut placed = scene::packed_gas(&gas, &config, &[])?;
    scene::zero_momentum(&mut placed, &config, [0.0, 0.0]);
    let mut world = World::new(config)?;
    world
        .add_particles(placed)
        .map_err(|(i, e)| anyhow::anyhow!("disc {i}: {e}"))?;
    world.set_threads(std::thread::available_parallelism().map_or(1, |n| n.get()))?;
    Ok(world)
}

fn maxwell_boltzmann(size: Size) -> Result<Check> {
    let mut world = periodic_gas(size.discs, 0.3, Speeds::Fixed(1.0), Config::default())?;
    let dt = 0.01;
    for _ in 0..(size.time / dt) as usize {
        world.step(dt)?;
    }
    let (d, critical, _) =
        maxwell_boltzmann_distance(&world).context("the gas has no moving discs")?;
    let n = world.len();
    Ok(Check {
        name: "speeds relax to 2D Maxwell–Boltzmann (all start at speed 1)".into(),
        measured: format!("KS distance {d:.4}"),
        expected: format!("< {critical:.4} (1% level, N = {n})"),
        pass: d < critical,
    })
}

fn conservation(size: Size) -> Result<Check> {
    let mut world = periodic_gas(size.discs, 0.3, Speeds::Uniform(1.0), Config::default())?;
    let (e0, p0) = (world.stats().kinetic_energy, world.stats().momentum);
    let dt = 0.01;
    for _ in 0..(size.time / dt) as usize {
        world.step(dt)?;
    }
    let s = world.stats();
    let de = (s.kinetic_energy / e0 - 1.0).abs();
    let scale = (2.0 * e0 * 0.5 * world.len() as f64).sqrt();
    let dp = ((s.momentum[0] - p0[0]).abs() + (s.momentum[1] - p0[1]).abs()) / scale;
    Ok(Check {
        name: "energy and momentum conserved (e = 1, periodic, packing 0.3)".into(),
        measured: format!("relative ΔE {de:.1e}, Δp {dp:.1e}"),
        expected: "< 1e-9 each".into(),
        pass: de < 1e-9 && dp < 1e-9,
    })
}

/// Z at `packing` with a small step.
fn compressibility(size: Size, packing: f64) -> Result<f64> {
    let mut world = periodic_gas(size.discs, packing, Speeds::Fixed(1.0), Config::default())?;
    let dt = 0.0025;
    for _ in 0..(size.time / 2.0 / dt) as usize {
        world.step(dt)?;
    }
    let (mut pa, mut ke) = (0.0, 0.0);
    let (min, max) = world.config().boundary.bounds().expect("a box");
    let area = (max[0] - min[0]) * (max[1] - min[1]);
    for _ in 0..(size.time / dt) as usize {
        let s = world.step(dt)?;
        pa += s.pressure.unwrap_or(0.0) * area;
        ke += s.kinetic_energy;
    }
    Ok(pa / ke)
}

fn equipartition(size: Size) -> Result<Check> {
    let half = size.discs / 2;
    // Packing 0.25.
    let side = (half as f64 * std::f64::consts::PI * (0.36 + 0.09) / 0.25).sqrt();
    let config = Config {
        boundary: Boundary::periodic([0.0, 0.0], [side, side]),
        mass_model: MassModel::Area,
        ..Config::default()
    };
    let mut discs = Vec::new();
    for (radius, seed) in [(0.6, 3), (0.3, 4)] {
        let gas = Gas {
            count: half,
            radius: [radius, radius],
            region: None,
            // Both species start at the same speed: the heavy ones with 4 times the energy.
            speeds: Speeds::Fixed(1.0),
            drift: [0.0, 0.0],
            seed,
        };
        discs.extend(scene::gas_among(&gas, &config, &discs)?);
    }
    let mut world = World::new(config)?;
    world
        .add_particles(discs)
        .map_err(|(i, e)| anyhow::anyhow!("disc {i}: {e}"))?;
    let dt = 0.01;
    for _ in 0..(size.time / dt) as usize {
        world.step(dt)?;
    }
    let (mut big, mut small) = (0.0, 0.0);
    let samples = (size.time * 10.0) as usize;
    for _ in 0..samples {
        for _ in 0..10 {
            world.step(dt)?;
        }
        let p = world.particles();
        for i in 0..p.len() {
            let r = p.radius()[i];
            let e = 0.5 * std::f64::consts::PI * r * r * (p.vx()[i].powi(2) + p.vy()[i].powi(2));
            if r > 0.45 {
                big += e;
            } else {
                small += e;
            }
        }
    }
    let ratio = big / small;
    Ok(Check {
        name: "equipartition in a binary mixture (radii 0.6 and 0.3, mass = area)".into(),
        measured: format!("<E> large / <E> small = {ratio:.3} (started at 4)"),
        expected: "1 ± 0.05".into(),
        pass: (ratio - 1.0).abs() < 0.05,
    })
}

fn model_options() -> Check {
    let seed = Law::new(&Config {
        coefficient_of_restitution: 0.5,
        ..Config::default()
    });
    let newton = Law {
        restitution_model: RestitutionModel::RelativeNormalVelocity,
        ..seed
    };
    let moving = Body::new([1.0, 0.0], 1.0, 1.0);
    let resting = Body {
        velocity: [0.0, 0.0],
        ..moving
    };
    let momentum = |law: &Law| {
        let out = resolve_pair([-2.0, 0.0], &moving, &resting, law);
        out.v1[0] + out.v2[0]
    };
    let (p_seed, p_newton) = (momentum(&seed), momentum(&newton));
    let approaching = Law {
        velocity_update: VelocityUpdate::ApproachingOnly,
        ..Law::new(&Config::default())
    };
    let apart = Body {
        velocity: [-1.0, 0.0],
        ..moving
    };
    let other = Body {
        velocity: [1.0, 0.0],
        ..moving
    };
    let left_alone = resolve_pair([-1.5, 0.0], &apart, &other, &approaching).v1 == apart.velocity;
    Check {
        name: "model options (two equal discs, e = 0.5, one at rest)".into(),
        measured: format!(
            "momentum after: each normal velocity scaled {p_seed}, relative {p_newton}; separating pair left alone: {left_alone}"
        ),
        expected: "scaled 0.5 (the default loses momentum), relative 1, true".into(),
        pass: p_seed == 0.5 && p_newton == 1.0 && left_alone,
    }
}

/// A disc of radius 0.5 resting on the floor for 100 steps under each `resting_contacts`:
/// its largest speed at a step's end.
fn resting_contacts() -> Result<Check> {
    let (g, dt) = (10.0, 0.01);
    let speed = |rest| -> Result<f64> {
        let config = Config {
            gravity: [0.0, -g],
            boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
            resting_contacts: rest,
            ..Config::default()
        };
        let mut world = World::new(config)?;
        world.add_particle(Particle::new([5.0, 0.5], [0.0, 0.0], 0.5))?;
        let mut top = 0.0f64;
        for _ in 0..100 {
            world.step(dt)?;
            top = top.max(world.particles().vy()[0].abs());
        }
        Ok(top)
    };
    let (bounce, rest) = (
        speed(RestingContacts::Bounce)?,
        speed(RestingContacts::Rest)?,
    );
    Ok(Check {
        name: "resting contacts (a disc on the floor, g = 10, dt = 0.01)".into(),
        measured: format!("largest speed: bounce {bounce:.6}, rest {rest}"),
        expected: "bounce |g| dt = 0.1 (the default), rest 0".into(),
        pass: (bounce - g * dt).abs() < 1e-12 && rest == 0.0,
    })
}

/// A rough disc (radius 0.5) released on a 20° incline under gravity 10 for 1.5 time units:
/// its acceleration along the slope against rolling, `(2/3) g sin θ` (friction 0.5), and
/// sliding, `g (sin θ − μ cos θ)` (friction 0.05 < tan θ / 3).
fn rough_incline() -> Result<Check> {
    let (g, angle) = (10.0, 20f64.to_radians());
    let (c, s) = (angle.cos(), angle.sin());
    let acceleration = |friction: f64| -> Result<f64> {
        let slope = bounce::Obstacle::segment([-40.0 * c, 40.0 * s], [40.0 * c, -40.0 * s]);
        let config = Config {
            gravity: [0.0, -g],
            friction,
            substeps: 4,
            obstacles: vec![slope],
            ..Config::default()
        };
        let start = [-20.0 * c + 0.5 * s, 20.0 * s + 0.5 * c];
        let mut world = World::new(config)?;
        world.add_particle(Particle::new(start, [0.0, 0.0], 0.5))?;
        let (dt, steps) = (0.001, 1500);
        for _ in 0..steps {
            world.step(dt)?;
        }
        let p = world.particles();
        let travelled = (p.x()[0] - start[0]) * c - (p.y()[0] - start[1]) * s;
        let t = dt * steps as f64;
        Ok(2.0 * travelled / (t * t))
    };
    let (rolling, sliding) = (acceleration(0.5)?, acceleration(0.05)?);
    let (roll, slide) = (2.0 / 3.0 * g * s, g * (s - 0.05 * c));
    Ok(Check {
        name: "rough discs (a disc down a 20° incline, g = 10)".into(),
        measured: format!("acceleration rolling {rolling:.4}, sliding {sliding:.4}"),
        expected: format!("(2/3) g sin θ = {roll:.4}, g (sin θ − μ cos θ) = {slide:.4}, ± 1%"),
        pass: (rolling / roll - 1.0).abs() < 0.01 && (sliding / slide - 1.0).abs() < 0.01,
    })
}

/// Runs every check, prints the report and writes `validate.png` into `out`. Returns whether
/// all passed.
/// The event-driven method's equation of state at packings 0.3 and 0.5, and its collision
/// rate at 0.3 against Enskog's.
fn hard_discs(size: Size) -> Result<Vec<Check>> {
    let mut checks = Vec::new();
    for (packing, monte_carlo) in [(0.3, 2.0631), (0.5, 4.1062)] {
        let config = Config {
            method: bounce::Method::EventDriven,
            ..Config::default()
        };
        let mut world = periodic_gas(size.discs, packing, Speeds::Temperature(1.0), config)?;
        let dt = 0.5;
        for _ in 0..(size.time / 4.0 / dt) as usize {
            world.step(dt)?;
        }
        let (min, max) = world.config().boundary.bounds().expect("a box");
        let area = (max[0] - min[0]) * (max[1] - min[1]);
        let (mut pa, mut ke, mut collisions, mut time) = (0.0, 0.0, 0usize, 0.0);
        for _ in 0..(size.time / dt) as usize {
            let s = world.step(dt)?;
            pa += s.pressure.unwrap_or(0.0) * area;
            ke += s.kinetic_energy;
            collisions += s.collisions;
            time += dt;
        }
        let z = pa / ke;
        checks.push(Check {
            name: format!("exact hard discs: equation of state at packing {packing}"),
            measured: format!("Z = {z:.4}"),
            expected: format!("Monte Carlo {monte_carlo} ± 1%"),
            pass: (z / monte_carlo - 1.0).abs() < 0.01,
        });
        if packing == 0.3 {
            // kT = KE / N in 2D; the seed's mass = radius = 0.5; σ = 1.
            let n = size.discs as f64;
            let kt = ke / (n * (size.time / dt).floor());
            let density = n / area;
            let g = (1.0 - 7.0 * packing / 16.0) / (1.0 - packing).powi(2);
            let enskog = 2.0 * density * g * (std::f64::consts::PI * kt / 0.5).sqrt();
            let rate = 2.0 * collisions as f64 / (n * time);
            checks.push(Check {
                name: "exact hard discs: collision rate at packing 0.3".into(),
                measured: format!("{rate:.4} per disc per time"),
                expected: format!("Enskog (Henderson's g(σ)) {enskog:.4} ± 2%"),
                pass: (rate / enskog - 1.0).abs() < 0.02,
            });
        }
    }
    Ok(checks)
}

/// The shear viscosity of a sheared gas (Lees–Edwards) against Enskog's.
fn shear_viscosity(quick: bool) -> Result<Check> {
    let (phi, rate, dt, time) = (0.3, 0.1, 0.01, if quick { 150.0 } else { 400.0 });
    let config = Config {
        thermostat: Some(bounce::Thermostat::new(
            bounce::ThermostatKind::Rescale,
            1.0,
            1.0,
        )),
        pressure_tensor: true,
        ..Config::default()
    };
    let mut world = periodic_gas(1000, phi, Speeds::Temperature(1.0), config)?;
    // The same box, sheared, the discs in its flow.
    let (min, max) = world.config().boundary.bounds().expect("a box");
    world.set_config(Config {
        boundary: Boundary::lees_edwards(min, max, rate),
        ..world.config().clone()
    })?;
    let flow: Vec<[f64; 2]> = world
        .particles_by_id()
        .iter()
        .map(|(_, d)| {
            [
                d.velocity[0] + rate * (d.position[1] - 0.5 * (min[1] + max[1])),
                d.velocity[1],
            ]
        })
        .collect();
    world
        .set_velocities(&flow)
        .map_err(|(i, e)| anyhow::anyhow!("disc {i}: {e}"))?;
    for _ in 0..(10.0 / dt) as usize {
        world.step(dt)?;
    }
    let (mut xy, mut kt, mut samples) = (0.0, 0.0, 0.0);
    for _ in 0..(time / dt) as usize {
        world.step(dt)?;
        xy += world.pressure_tensor().expect("asked for")[2];
        kt += world.peculiar_kinetic_energy() / world.len() as f64;
        samples += 1.0;
    }
    let (eta, kt) = (-xy / samples / rate, kt / samples);
    // Mass = radius = 0.5, diameter 1.
    let enskog = enskog_viscosity(phi, kt, 0.5, 1.0);
    let tolerance = if quick { 0.15 } else { 0.10 };
    Ok(Check {
        name: "shear viscosity at packing 0.3 (Lees–Edwards, γ̇ = 0.1)".into(),
        measured: format!("η = {eta:.4}"),
        expected: format!("Enskog {enskog:.4} ± {:.0}%", tolerance * 100.0),
        pass: (eta / enskog - 1.0).abs() < tolerance,
    })
}

pub fn validate(quick: bool, out: &Path) -> Result<bool> {
    let start = Instant::now();
    let size = if quick {
        Size {
            discs: 2000,
            time: 40.0,
        }
    } else {
        Size {
            discs: 10000,
            time: 100.0,
        }
    };
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut checks = vec![maxwell_boltzmann(size)?, conservation(size)?];
    let mut points = Vec::new();
    for packing in [0.1, 0.3, 0.5] {
        let z = compressibility(size, packing)?;
        let theory = henderson(packing);
        points.push((packing, z));
        checks.push(Check {
            name: format!("equation of state at packing {packing} (virial, periodic)"),
            measured: format!("Z = {z:.3}"),
            expected: format!("Henderson {theory:.3} ± 2.5%"),
            pass: (z / theory - 1.0).abs() < 0.025,
        });
    }
    checks.push(equipartition(size)?);
    checks.push(model_options());
    checks.push(resting_contacts()?);
    checks.push(rough_incline()?);
    checks.extend(hard_discs(size)?);
    checks.push(shear_viscosity(quick)?);
    for c in &checks {
        println!(
            "{}  {}: {} (expected {})",
            if c.pass { "PASS" } else { "FAIL" },
            c.name,
            c.measured,
            c.expected
        );
    }
    let plot = out.join("validate.png");
    draw(&points, &plot)?;
    let passed = checks.iter().filter(|c| c.pass).count();
    println!(
        "{passed} of {} checks passed in {:.1} s ({} discs per run{}); plot: {}",
        checks.len(),
        start.elapsed().as_secs_f64(),
        size.discs,
        if quick { ", --quick" } else { "" },
        plot.display()
    );
    Ok(passed == checks.len())
}

/// Z against packing, with Henderson's curve.
fn draw(points: &[(f64, f64)], path: &Path) -> Result<()> {
    crate::plots::register_font()?;
    let (w, h) = (800u32, 560u32);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(crate::plots::plot_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption("hard-disc equation of state", ("sans-serif", 20))
            .margin(16)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..0.6, 0.0..7.0)
            .map_err(crate::plots::plot_err)?;
        chart
            .configure_mesh()
            .x_desc("packing fraction η")
            .y_desc("Z = PA / NkT")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(crate::plots::plot_err)?;
        chart
            .draw_series(LineSeries::new(
                (0..=60).map(|k| {
                    let eta = k as f64 / 100.0;
                    (eta, henderson(eta))
                }),
                RED.stroke_width(2),
            ))
            .map_err(crate::plots::plot_err)?
            .label("Henderson (1975)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], RED.stroke_width(2)));
        chart
            .draw_series(
                points
                    .iter()
                    .map(|&(eta, z)| Circle::new((eta, z), 6, BLUE.filled())),
            )
            .map_err(crate::plots::plot_err)?
            .label("bounce (collision virial)")
            .legend(|(x, y)| Circle::new((x + 7, y), 5, BLUE.filled()));
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(crate::plots::plot_err)?;
        root.present().map_err(crate::plots::plot_err)?;
    }
    crate::plots::save_rgb(&rgb, w, h, path)
}
