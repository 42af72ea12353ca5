//! The world's own tests: kept candidate lists never miss a contact, loaded worlds list at
//! their reference.

use super::state::WorldState;
use super::*;
use crate::Boundary;
use crate::broadphase;
use crate::config::MassModel;
use crate::context::StepContext;
use crate::scene::{self, Gas, Speeds};

/// A fast polydisperse gas, so discs cross the skin within a few steps.
fn world(boundary: Boundary, threads: usize) -> World {
    let config = Config {
        boundary,
        gravity: [0.0, -1.0],
        coefficient_of_restitution: 0.95,
        ..Config::default()
    };
    let gas = Gas {
        count: 600,
        radius: [0.1, 1.0],
        region: Some(([5.0, 5.0], [55.0, 55.0])),
        speeds: Speeds::Uniform(6.0),
        drift: [0.0, 0.0],
        seed: 3,
    };
    let discs = scene::gas(&gas, &config).unwrap();
    world_of(config, discs, threads)
}

/// A world of `discs` stepping on `threads` threads, every stage on the workers.
fn world_of(config: Config, discs: Vec<Particle>, threads: usize) -> World {
    let mut world = World::new(config).unwrap();
    world.add_particles(discs).unwrap();
    world.set_threads(threads).unwrap();
    world.set_parallel_min_work(0);
    world
}

#[test]
fn rebuilding_every_step_changes_nothing() {
    // Kept candidate lists must never miss a contact: a run that keeps them and a run
    // that rebuilds before every step end in the same state, bit for bit.
    for boundary in [
        Boundary::walls([0.0, 0.0], [60.0, 60.0]),
        Boundary::periodic([0.0, 0.0], [60.0, 60.0]),
        Boundary::Open,
    ] {
        for threads in [1, 3] {
            let (mut kept, mut fresh) = (
                world(boundary.clone(), threads),
                world(boundary.clone(), threads),
            );
            let mut rebuilds = 0;
            for _ in 0..120 {
                kept.step(1.0 / 60.0).unwrap();
                rebuilds += kept.profile().rebuilds;
                fresh.broadphase.invalidate();
                fresh.step(1.0 / 60.0).unwrap();
                assert_eq!(fresh.profile().rebuilds, 1);
            }
            assert_eq!(kept.state_hash(), fresh.state_hash(), "{boundary:?}");
            assert!(
                (5..60).contains(&rebuilds),
                "{boundary:?}: {rebuilds} rebuilds in 120 steps"
            );
        }
    }
}

#[test]
fn a_world_loaded_between_rebuilds_lists_at_its_reference() {
    let mut straight = world(Boundary::walls([0.0, 0.0], [60.0, 60.0]), 2);
    // Step until a step keeps its list: the saved reference is then in use.
    straight.step(1.0 / 60.0).unwrap();
    while straight.profile().rebuilds > 0 {
        straight.step(1.0 / 60.0).unwrap();
    }
    let bytes = postcard::to_stdvec(&straight).unwrap();
    let mut loaded: World = postcard::from_bytes(&bytes).unwrap();
    assert!(
        loaded
            .broadphase
            .reference
            .positions(loaded.len())
            .is_some()
    );
    for _ in 0..60 {
        straight.step(1.0 / 60.0).unwrap();
        loaded.step(1.0 / 60.0).unwrap();
        assert_eq!(loaded.profile().rebuilds, straight.profile().rebuilds);
        assert_eq!(loaded.stats(), straight.stats());
    }
    assert_eq!(loaded.state_hash(), straight.state_hash());
}

#[test]
fn a_loaded_reference_of_the_wrong_length_is_refused() {
    let mut world = world(Boundary::Open, 1);
    world.step(1.0 / 60.0).unwrap();
    assert!(world.broadphase.reference.check(world.len()).is_ok());
    // A reference for one disc fewer.
    let mut shorter = world.particles.clone();
    shorter.truncate(world.len() - 1);
    let mut other = World::new(world.config.clone()).unwrap();
    other.particles = shorter;
    other.step(1.0 / 60.0).unwrap();
    let reference = other.broadphase.reference.clone();
    let state = WorldState {
        config: world.config.clone(),
        particles: world.particles.clone(),
        next_id: world.next_id,
        time: world.time,
        steps: world.steps,
        stats: world.stats,
        reference,
        obstacle_states: Vec::new(),
        obstacle_impulses: Vec::new(),
        obstacle_work: 0.0,
        friction_work: 0.0,
        thermostat_work: 0.0,
        emitter_states: Vec::new(),
        removed: 0,
        contact_log: Default::default(),
        sensors: Default::default(),
        emitted_ids: Vec::new(),
        collision_counts: Vec::new(),
    };
    let error = World::try_from(state).unwrap_err().to_string();
    assert!(
        error.contains("reference positions for 599 and 599"),
        "{error}"
    );
}

#[test]
fn later_solver_passes_meet_the_walls() {
    // A disc resting on the floor is struck from above (equal radii, e = 1, wall
    // restitution 0.5, no gravity, one substep of 0.1). By hand:
    // integration: A stays at y = 1, B falls to 2.4; pass 1: overlap 0.6, A is pushed to
    // 0.7 and held at 1.0, B to 2.7; the normal velocities swap: A -1, B 0.
    // One pass ends there. With a second: the floor bounces A to +0.5 (impulse 1.5); pass 2
    // finds the pair again (distance 1.7), pushes B to 2.85 (A is held at 1.0) and the
    // approaching pair swaps again: A 0, B +0.5.
    let run = |passes: u32| {
        let mut world = World::new(Config {
            boundary: Boundary::Walls {
                min: [-10.0, 0.0],
                max: [10.0, 10.0],
                wall_restitution: Some(0.5),
            },
            solver_iterations: passes,
            ..Config::default()
        })
        .unwrap();
        let a = world
            .add_particle(Particle::new([0.0, 1.0], [0.0, 0.0], 1.0))
            .unwrap();
        let b = world
            .add_particle(Particle::new([0.0, 2.5], [0.0, -1.0], 1.0))
            .unwrap();
        let bottom = world.step(0.1).unwrap().wall_impulse.bottom;
        let (a, b) = (world.particle(a).unwrap(), world.particle(b).unwrap());
        (
            a.position[1],
            a.velocity[1],
            b.position[1],
            b.velocity[1],
            bottom,
        )
    };
    let close = |got: (f64, f64, f64, f64, f64), want: [f64; 5]| {
        let got = [got.0, got.1, got.2, got.3, got.4];
        assert!(
            got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-12),
            "{got:?} != {want:?}"
        );
    };
    close(run(1), [1.0, -1.0, 2.7, 0.0, 0.0]);
    close(run(2), [1.0, 0.0, 2.85, 0.5, 1.5]);
}

#[test]
fn the_profile_times_each_stage_under_its_name() {
    // The obstacles' and the walls' hold are stages of their own: a world without either
    // spends nothing there, one with both spends time in each.
    let stepped = |obstacles: Vec<crate::Obstacle>, passes: u32| {
        let (config, discs) =
            scene::gas_in_walls(1000, [0.5, 0.5], 0.3, Speeds::Uniform(2.0), 7).unwrap();
        let config = Config {
            obstacles,
            solver_iterations: passes,
            ..config
        };
        let mut world = world_of(config, discs, 1);
        world.step(0.01).unwrap();
        *world.profile()
    };
    let plain = stepped(Vec::new(), 1);
    assert_eq!((plain.obstacles, plain.walls), (0.0, 0.0));
    assert!(plain.integrate > 0.0 && plain.pairs > 0.0 && plain.resolve > 0.0);
    let both = stepped(
        vec![
            crate::Obstacle::peg([30.0, 30.0], 3.0),
            crate::Obstacle::segment([5.0, 5.0], [45.0, 20.0]),
        ],
        2,
    );
    assert!(both.obstacles > 0.0 && both.walls > 0.0, "{both:?}");
    let stages = both.integrate + both.bin + both.pairs + both.resolve;
    assert_eq!(
        both.total(),
        stages + both.obstacles + both.walls + both.measure
    );
}

#[test]
fn a_sink_can_empty_the_world_and_it_keeps_stepping() {
    // Found by fuzzing: with every disc gone, a stale candidate list outlived its blocks.
    let config = Config {
        boundary: crate::Boundary::walls([0.0, 0.0], [20.0, 10.0]),
        sinks: vec![crate::Sink {
            min: [15.0, 0.0],
            max: [20.0, 10.0],
        }],
        ..Config::default()
    };
    let mut world = World::new(config).unwrap();
    for k in 0..5 {
        world
            .add_particle(Particle::new([2.0 + 2.0 * k as f64, 5.0], [10.0, 0.0], 0.4))
            .unwrap();
    }
    let mut removed = 0;
    for _ in 0..300 {
        removed += world.step(0.01).unwrap().removed;
    }
    assert_eq!((world.len(), removed), (0, 5));
    assert_eq!(world.next_id(), 5);
    // Still a world: a new disc gets the next id and steps.
    let id = world
        .add_particle(Particle::new([5.0, 5.0], [1.0, 0.0], 0.4))
        .unwrap();
    assert_eq!(id, ParticleId(5));
    world.step(0.01).unwrap();
    assert!(world.particle(id).is_some() && world.particle(ParticleId(0)).is_none());
    // The saved form keeps the gap in the ids.
    let json = serde_json::to_string(&world).unwrap();
    let back: World = serde_json::from_str(&json).unwrap();
    assert_eq!(back.state_hash(), world.state_hash());
}

/// Steps `world` 200 times; after each step, the bands detection would test for the true
/// largest displacement of the discs that do not stray find, with the strays' pairs,
/// exactly the pairs the brute-force oracle finds. Returns how many steps tested the near
/// band alone, how many both, how many had one grid level and how many had strays.
fn check_bands_every_step(world: &mut World) -> (usize, usize, usize, usize) {
    let (mut near_only, mut both, mut one_level, mut strayed) = (0, 0, 0, 0);
    for _ in 0..200 {
        world.step(1.0 / 60.0).unwrap();
        one_level += (world.broadphase.levels() == 1) as usize;
        strayed += !world.broadphase.strays().is_empty() as usize;
        let ctx = StepContext::new(&world.config, 0.0, &world.exec, None);
        let bp = &world.broadphase;
        let p = &world.particles;
        let (rx, ry) = bp.reference.positions(p.len()).unwrap();
        let min_image = ctx.geometry.min_image();
        let displacement2 = (0..p.len())
            .filter(|&i| !bp.strays().contains(i))
            .map(|i| {
                let [dx, dy] = min_image.diff(p.x[i], p.y[i], rx[i] as f64, ry[i] as f64);
                dx * dx + dy * dy
            })
            .fold(0.0, f64::max);
        let bands = bp.bands_within(displacement2);
        if bands < broadphase::BANDS {
            near_only += 1;
        } else {
            both += 1;
        }
        let mut contacts = Contacts::default();
        contacts.find(bp, bands, p, &ctx);
        let expected = world.colliding_pairs_brute_force();
        assert_eq!(
            contacts.pair_ids(p),
            expected,
            "{:?}",
            world.config.boundary
        );
    }
    (near_only, both, one_level, strayed)
}

/// A walled and a periodic `side` × `side` box.
fn boxes(side: f64) -> [Boundary; 2] {
    [
        Boundary::walls([0.0, 0.0], [side, side]),
        Boundary::periodic([0.0, 0.0], [side, side]),
    ]
}

/// `gas` in `boundary` under the default law, on two threads.
fn gas_world(boundary: &Boundary, gas: &Gas) -> World {
    let config = Config {
        boundary: boundary.clone(),
        ..Config::default()
    };
    let discs = scene::gas(gas, &config).unwrap();
    world_of(config, discs, 2)
}

#[test]
fn the_near_band_holds_every_contact_while_discs_stay_close_to_their_references() {
    // Between rebuilds, detection skips the far band while the displacements allow it; both
    // cases occur. A dense fast gas: contacts are many, so some come from the far band.
    let gas = Gas {
        count: 2000,
        radius: [0.3, 0.6],
        region: Some(([2.0, 2.0], [58.0, 58.0])),
        speeds: Speeds::Uniform(8.0),
        drift: [0.0, 0.0],
        seed: 5,
    };
    for boundary in boxes(60.0) {
        let (near_only, both, _, strayed) = check_bands_every_step(&mut gas_world(&boundary, &gas));
        assert!(near_only > 10 && both > 10, "{near_only} {both}");
        // The fastest few stray before the rest need a new list.
        assert!(strayed > 40, "{strayed} steps with strays");
    }
}

#[test]
fn merged_levels_find_every_contact() {
    // Radii 0.05 to 2.5 (six bands) about as sparse as the benchmark's polydisperse gas:
    // one grid holds them all, each pair cut and banded at its own collision distance, and
    // every step finds exactly the contacts of the oracle.
    let gas = Gas {
        count: 250,
        radius: [0.05, 2.5],
        region: Some(([3.0, 3.0], [97.0, 97.0])),
        speeds: Speeds::Uniform(6.0),
        drift: [0.0, 0.0],
        seed: 9,
    };
    for boundary in boxes(100.0) {
        let (near_only, both, one_level, _) =
            check_bands_every_step(&mut gas_world(&boundary, &gas));
        assert!(near_only > 10 && both > 10, "{near_only} {both}");
        // Collisions with large discs speed small ones up, widening the skin and the cells
        // until the levels part; most steps still share one grid.
        assert!(one_level > 100, "{one_level} of 200 steps on one level");
    }
}

#[test]
fn a_far_pair_that_closes_in_is_found() {
    // Two discs (radius 0.5, skin 0.75) head on at 1.5 each, listed in the first step 1.45
    // apart: beyond the near band (1.375), so in the far one. They touch in step 10, each
    // having moved 0.225 since, within the allowance (0.3675): no rebuild, and the far band
    // must be tested by then.
    let mut world = World::new(Config {
        boundary: Boundary::walls([0.0, 0.0], [20.0, 20.0]),
        ..Config::default()
    })
    .unwrap();
    world
        .add_particles([
            Particle::new([9.25, 10.0], [1.5, 0.0], 0.5),
            Particle::new([10.75, 10.0], [-1.5, 0.0], 0.5),
        ])
        .unwrap();
    world.step(1.0 / 60.0).unwrap();
    assert_eq!(world.broadphase.candidates()[0][1].len(), 1, "listed far");
    let mut contacts_at = None;
    for step in 2..=12 {
        let stats = *world.step(1.0 / 60.0).unwrap();
        assert_eq!(world.profile().rebuilds, 0);
        if stats.pairs > 0 && contacts_at.is_none() {
            contacts_at = Some(step);
            // The near band alone would have missed it.
            let ctx = StepContext::new(&world.config, 0.0, &world.exec, None);
            let mut contacts = Contacts::default();
            contacts.find(&world.broadphase, 1, &world.particles, &ctx);
            assert!(contacts.list().is_empty());
        }
    }
    assert_eq!(contacts_at, Some(10));
}

/// 1,200 discs (radii 0.4–0.6) packed into the lower 50 of a 40-wide box under gravity
/// (e = 0.7, 4 substeps), on 2 threads; in a periodic box on a floor segment across it.
fn settling_pile(boundary: &Boundary) -> World {
    settling_pile_of(boundary, [0.4, 0.6])
}

/// [`settling_pile`] with radii in `radius`.
fn settling_pile_of(boundary: &Boundary, radius: [f64; 2]) -> World {
    let config = Config {
        boundary: boundary.clone(),
        gravity: [0.0, -9.81],
        obstacles: match boundary {
            Boundary::Periodic { .. } => {
                vec![crate::Obstacle::segment([-1.0, -0.5], [41.0, -0.5])]
            }
            _ => Vec::new(),
        },
        coefficient_of_restitution: 0.7,
        substeps: 4,
        ..Config::default()
    };
    let gas = Gas {
        count: 1200,
        radius,
        region: Some(([0.0, 0.0], [40.0, 50.0])),
        speeds: Speeds::Uniform(1.0),
        drift: [0.0, 0.0],
        seed: 8,
    };
    let discs = scene::packed_gas(&gas, &config, &[]).unwrap();
    world_of(config, discs, 2)
}

/// Steps `fast` with the fast step and `reference` with the plain one side by side: the same
/// contacts (count, largest overlap, virial, walls' impulses) and state bits every step.
fn beside_the_plain_step(fast: &mut World, reference: &mut World, steps: usize, case: &str) {
    for step in 0..steps {
        let a = *fast.step(1.0 / 60.0).unwrap();
        let b = *crate::plain::step(reference, 1.0 / 60.0).unwrap();
        assert_eq!(
            (a.pairs, a.max_overlap, a.virial, a.wall_impulse),
            (b.pairs, b.max_overlap, b.virial, b.wall_impulse),
            "{case}, step {step}"
        );
        assert_eq!(
            fast.state_hash(),
            reference.state_hash(),
            "{case}, step {step}"
        );
    }
}

#[test]
fn presorted_candidates_give_the_plain_steps_bits() {
    // A pile (contacts dense) keeps its near candidates in canonical order instead of
    // sorting the contacts each substep, with the plain step's bits. Periodic: on a floor
    // (a segment across the box).
    for boundary in [
        Boundary::walls([0.0, 0.0], [40.0, 80.0]),
        Boundary::periodic([0.0, -1.0], [40.0, 80.0]),
    ] {
        let (mut fast, mut reference) = (settling_pile(&boundary), settling_pile(&boundary));
        beside_the_plain_step(&mut fast, &mut reference, 150, &format!("{boundary:?}"));
        assert!(fast.contacts.presorted(), "{boundary:?}");
        // The last step's detections, presorted but perhaps the first after a new list.
        assert!(fast.profile().sorted_detections < 4, "{boundary:?}");
    }
}

#[test]
fn a_new_list_after_a_lasting_one_is_presorted_at_once() {
    // A settled pile lists anew now and then, each list lasting dozens of detections: the
    // next list's candidates are presorted at its first detection, with no sorted ones
    // before (three, before the presort, when the list before did not last), and that
    // detection finds every contact in place. The plain step's bits throughout.
    let boundary = Boundary::walls([0.0, 0.0], [40.0, 80.0]);
    let (mut world, mut reference) = (settling_pile(&boundary), settling_pile(&boundary));
    // Settled: the list has lasted for many detections.
    beside_the_plain_step(&mut world, &mut reference, 300, "settling");
    let uses = world.contacts.listing_uses();
    assert!(uses > 40, "the last list lasted {uses} detections");
    world.relist();
    beside_the_plain_step(&mut world, &mut reference, 1, "relisted");
    let profile = world.profile();
    assert_eq!(profile.rebuilds, 1);
    assert_eq!(profile.sorted_detections, 0, "sorted after relisting");
    // Presorted where the discs are now; four substeps move few discs to another block.
    assert!(
        profile.out_of_place < 50,
        "{} out of place",
        profile.out_of_place
    );
    assert_eq!(
        world.contacts.presorted_generation(),
        Some(world.broadphase.generation())
    );
    beside_the_plain_step(&mut world, &mut reference, 20, "after");
}

#[test]
fn strays_change_nothing_but_how_often_lists_are_made() {
    // Strays met alone while the list is kept: the plain step's contacts every step (count,
    // largest overlap, their virial and the walls' exact sums) and state, bit for bit.
    // Equal radii (the one-limit test) and a polydisperse mix; walls, periodic and open;
    // 1 and 2 threads.
    let gases = [([0.5, 0.5], 3.0), ([0.2, 0.9], 6.0)];
    for boundary in [boxes(60.0).to_vec(), vec![Boundary::Open]].concat() {
        for (radius, speed) in gases {
            for threads in [1, 2] {
                let gas = Gas {
                    count: 1500,
                    radius,
                    region: Some(([2.0, 2.0], [58.0, 58.0])),
                    speeds: Speeds::Uniform(speed),
                    drift: [0.0, 0.0],
                    seed: 11,
                };
                let case = format!("{boundary:?} {radius:?} {threads}");
                let mut world = gas_world(&boundary, &gas);
                world.set_threads(threads).unwrap();
                let mut reference = gas_world(&boundary, &gas);
                let mut strayed = 0;
                for _ in 0..150 {
                    beside_the_plain_step(&mut world, &mut reference, 1, &case);
                    strayed += (world.profile().strays > 0) as usize;
                    // A list kept with strays is not yet worn out (a distributed run relists
                    // its parts together at 1).
                    if !world.broadphase.strays().is_empty() {
                        let worn = world.candidates_worn().unwrap();
                        assert!(worn > 0.0 && worn < 1.0, "{case}: worn {worn}");
                    }
                }
                assert!(strayed > 30, "{case}: {strayed} steps with strays");
            }
        }
    }
}

#[test]
fn a_settling_pile_gives_the_plain_steps_bits_with_strays() {
    // Contacts dense: strays keep a list only while the other discs need the near band
    // alone. The plain step's state, bit for bit.
    let boundary = Boundary::walls([0.0, 0.0], [40.0, 80.0]);
    let (mut world, mut reference) = (settling_pile(&boundary), settling_pile(&boundary));
    let mut strayed = 0;
    for _ in 0..200 {
        beside_the_plain_step(&mut world, &mut reference, 1, "pile");
        strayed += (world.profile().strays > 0) as usize;
    }
    assert!(
        world.stats().pairs > 1000,
        "{} contacts: a pile",
        world.stats().pairs
    );
    // While settling, strays kept the list in some steps (the rest on the near band).
    assert!(strayed > 10, "{strayed} steps with strays");
}

#[test]
fn equal_discs_known_to_be_equal_give_the_plain_steps_bits() {
    // With every radius equal, detection, resolution and measurement use that one number
    // instead of reading the radii (the plain step reads them all): the same state and
    // contacts, bit for bit, for every mass model (the seed's mass = radius, the area, each
    // disc's own), in walls and in a periodic box, dilute (a gas, whose solver asks for its
    // discs ahead) and dense (a pile).
    for boundary in boxes(40.0) {
        for mass_model in [MassModel::Radius, MassModel::Area, MassModel::PerParticle] {
            for (count, gravity) in [(800, [0.0, 0.0]), (1300, [0.0, -9.81])] {
                let config = Config {
                    boundary: boundary.clone(),
                    mass_model,
                    gravity,
                    coefficient_of_restitution: 0.8,
                    ..Config::default()
                };
                let gas = Gas {
                    count,
                    radius: [0.4, 0.4],
                    region: None,
                    speeds: Speeds::Uniform(4.0),
                    drift: [0.3, -0.2],
                    seed: 17,
                };
                let mut discs = scene::gas(&gas, &config).unwrap();
                for (k, disc) in discs.iter_mut().enumerate() {
                    // Masses of their own, which only the per-particle model reads.
                    disc.mass = Some(0.5 + (k % 7) as f64 * 0.25);
                }
                let case = format!("{boundary:?} {mass_model:?} {count}");
                let mut world = world_of(config.clone(), discs.clone(), 2);
                let mut reference = world_of(config, discs, 1);
                beside_the_plain_step(&mut world, &mut reference, 60, &case);
                assert!(world.broadphase.uniform_radius().is_some(), "{case}");
                assert!(world.stats().pairs > 0, "{case}");
            }
        }
    }
}

/// The seed's loop over `contacts` in their canonical order, one pair after another on the
/// current state (walls holding pushed discs); returns the collision virial.
fn resolve_one_by_one(contacts: &Contacts, p: &mut Particles, ctx: &StepContext) -> f64 {
    let min_image = ctx.geometry.min_image();
    let mut virial = crate::sum::ExactSum::new();
    for c in contacts.list() {
        let (a, b) = (c.a as usize, c.b as usize);
        let diff = min_image.diff(p.x[a], p.y[a], p.x[b], p.y[b]);
        let body = |i: usize| {
            crate::law::Body::new(
                [p.vx[i], p.vy[i]],
                p.radius[i],
                ctx.law.mass(p.radius[i], p.mass[i]),
            )
        };
        let (one, two) = (body(a), body(b));
        let out = ctx.law.resolve(diff, &one, &two);
        let impulse = [0, 1].map(|k| {
            0.5 * (one.mass * (out.v1[k] - one.velocity[k])
                - two.mass * (out.v2[k] - two.velocity[k]))
        });
        virial.add(diff[0] * impulse[0] + diff[1] * impulse[1]);
        let (mut xa, mut ya) = (p.x[a] + out.push[0], p.y[a] + out.push[1]);
        let (mut xb, mut yb) = (p.x[b] - out.push[0], p.y[b] - out.push[1]);
        ctx.geometry.hold(&mut xa, &mut ya, one.radius);
        ctx.geometry.hold(&mut xb, &mut yb, two.radius);
        (p.x[a], p.y[a], p.x[b], p.y[b]) = (xa, ya, xb, yb);
        [p.vx[a], p.vy[a]] = out.v1;
        [p.vx[b], p.vy[b]] = out.v2;
    }
    virial.value()
}

#[test]
fn the_solver_lanes_give_the_bits_of_the_seed_loop() {
    // The solver resolves four runs of contacts (whole blocks, disjoint discs) side by side,
    // two or one as they run out: the same state and virial, bit for bit, as the seed's loop
    // over the same contacts one after another. Settling piles of equal and of mixed discs
    // (dense contacts, long runs), in walls and on a floor in a periodic box, some time in,
    // resolved with each mass model (equal discs' radius, and with it the seed's mass, is
    // one number in the solver; the other models still read each disc's mass).
    for boundary in [
        Boundary::walls([0.0, 0.0], [40.0, 80.0]),
        Boundary::periodic([0.0, -2.0], [40.0, 80.0]),
    ] {
        for (equal, mass_model) in [false, true]
            .into_iter()
            .flat_map(|equal| [MassModel::Radius, MassModel::Area].map(|m| (equal, m)))
        {
            let radius = if equal { [0.5, 0.5] } else { [0.4, 0.6] };
            let mut world = settling_pile_of(&boundary, radius);
            for _ in 0..300 {
                world.step(1.0 / 60.0).unwrap();
            }
            let case = format!("{boundary:?} equal {equal} {mass_model:?}");
            let config = Config {
                mass_model,
                ..world.config.clone()
            };
            let ctx = StepContext::new(&config, 1.0 / 240.0, &world.exec, None);
            let bp = &world.broadphase;
            world
                .contacts
                .find(bp, broadphase::BANDS, &world.particles, &ctx);
            let found = world.contacts.list().len();
            assert!(
                found > 1000,
                "{case}: {found} contacts, {} in the step",
                world.stats().pairs
            );
            assert_eq!(bp.uniform_radius().is_some(), equal, "{case}");
            let mut lanes = world.particles.clone();
            let resolved = crate::resolve::resolve_all(
                &world.contacts,
                &mut lanes,
                &ctx,
                bp.uniform_radius(),
                Default::default(),
            );
            // Recording the tensor and the impacts changes nothing else, and the tensor's
            // trace is the virial.
            let mut recorded = world.particles.clone();
            let recording = crate::resolve::Recording {
                tensor: true,
                impacts: true,
            };
            let with = crate::resolve::resolve_all(
                &world.contacts,
                &mut recorded,
                &ctx,
                bp.uniform_radius(),
                recording,
            );
            let trace = with.tensor[0].value() + with.tensor[1].value();
            assert!(
                (trace - with.virial.value()).abs() <= 1e-9 * trace.abs().max(1.0),
                "{case}: trace {trace}, virial {}",
                with.virial.value()
            );
            assert_eq!(with.collided.len(), 2 * with.impacts, "{case}");
            assert_eq!(
                with.virial.value().to_bits(),
                resolved.virial.value().to_bits()
            );
            assert!(resolved.collided.is_empty() && resolved.tensor[0].value() == 0.0);
            let mut seed = world.particles.clone();
            let seed_virial = resolve_one_by_one(&world.contacts, &mut seed, &ctx);
            let bits = |p: &Particles| -> Vec<u64> {
                [&p.x, &p.y, &p.vx, &p.vy]
                    .iter()
                    .flat_map(|v| v.iter().map(|v| v.to_bits()))
                    .collect()
            };
            assert_eq!(bits(&lanes), bits(&seed), "{case}");
            assert_eq!(bits(&recorded), bits(&seed), "{case}");
            assert_eq!(
                resolved.virial.value().to_bits(),
                seed_virial.to_bits(),
                "{case}"
            );
            assert_ne!(bits(&lanes), bits(&world.particles), "{case}");
        }
    }
}
