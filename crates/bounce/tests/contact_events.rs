//! Contact events against hand calculations (a pair head on, a wall, a peg), the same list
//! on any thread count and after a resume, the threshold, and no change to the physics.

use bounce::scene::Bench;
use bounce::{
    Boundary, Config, ContactEvent, ContactKind, Obstacle, Particle, ParticleId, Party, WallSide,
    World,
};

const DT: f64 = 0.01;

fn with_events(config: Config) -> Config {
    Config {
        contact_events: true,
        ..config
    }
}

/// Every event of `steps` steps, with the step it came in.
fn run(world: &mut World, steps: u64) -> Vec<(u64, ContactEvent)> {
    let mut out = Vec::new();
    for _ in 0..steps {
        world.step(DT).unwrap();
        let step = world.step_count();
        out.extend(world.contact_events().iter().map(|e| (step, *e)));
    }
    out
}

#[test]
fn two_discs_head_on_begin_once_with_the_hand_impulse_and_end_once() {
    // r = 1 each, the seed's model (mass = radius = 1), e = 1; the second at rest.
    let mut world = World::new(with_events(Config::default())).unwrap();
    let a = world
        .add_particle(Particle::new([0.0, 0.0], [1.0, 0.0], 1.0))
        .unwrap();
    let b = world
        .add_particle(Particle::new([2.5, 0.0], [0.0, 0.0], 1.0))
        .unwrap();
    // The step at which the distance first reaches 2, by the integration's arithmetic.
    let (mut x, mut first) = (0.0f64, 0u64);
    for k in 1.. {
        x += 1.0 * DT;
        if 2.5 - x <= 2.0 {
            first = k;
            break;
        }
    }
    let events = run(&mut world, 100);
    let begins: Vec<_> = events
        .iter()
        .filter(|(_, e)| e.kind == ContactKind::Begin)
        .collect();
    let ends: Vec<_> = events
        .iter()
        .filter(|(_, e)| e.kind == ContactKind::End)
        .collect();
    assert_eq!(begins.len(), 1, "{events:?}");
    assert_eq!(ends.len(), 1, "{events:?}");
    let (step, begin) = begins[0];
    assert_eq!(*step, first);
    assert_eq!((begin.a, begin.b), (a, Party::Disc(b)));
    // Equal masses swap: the first stops, the second takes 1; the impulse is 1.
    assert!((begin.normal_impulse - 1.0).abs() < 1e-12, "{begin:?}");
    assert!(begin.tangent_impulse.abs() < 1e-15);
    assert!((begin.approach_speed - 1.0).abs() < 1e-15);
    assert_eq!(begin.normal, [1.0, 0.0]);
    // Halfway between the centres (equal radii), where they were when resolved.
    assert!((begin.point[0] - (x + 0.5 * (2.5 - x))).abs() < 1e-12);
    assert_eq!(begin.point[1], 0.0);
    // They separate in the next step: the end, with the contact's last place.
    let (end_step, end) = ends[0];
    assert_eq!(*end_step, first + 1);
    assert_eq!((end.a, end.b, end.point), (a, Party::Disc(b), begin.point));
    assert_eq!(end.normal_impulse, 0.0);
}

#[test]
fn a_disc_striking_a_wall_begins_once_with_twice_its_momentum() {
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
        ..with_events(Config::default())
    };
    let mut world = World::new(config).unwrap();
    // Mass = radius = 0.5, speed 2 into the left wall: at e = 1 the wall gives 2 m v = 2.
    let id = world
        .add_particle(Particle::new([3.0, 4.0], [-2.0, 0.0], 0.5))
        .unwrap();
    let events = run(&mut world, 1200);
    let begins: Vec<_> = (events.iter())
        .filter(|(_, e)| e.kind == ContactKind::Begin)
        .map(|(_, e)| e)
        .collect();
    let first = begins[0];
    assert_eq!((first.a, first.b), (id, Party::Wall(WallSide::Left)));
    assert!((first.normal_impulse - 2.0).abs() < 1e-12, "{first:?}");
    assert_eq!(first.normal, [-1.0, 0.0]);
    assert_eq!(first.point, [0.0, 4.0]);
    assert!((first.approach_speed - 2.0).abs() < 1e-15);
    // Across the box and back: the right wall next, each wall once per visit, each begin
    // followed by its end.
    let sides: Vec<Party> = begins.iter().map(|e| e.b).collect();
    assert_eq!(
        sides[..3],
        [
            Party::Wall(WallSide::Left),
            Party::Wall(WallSide::Right),
            Party::Wall(WallSide::Left)
        ]
    );
    let kinds: Vec<ContactKind> = events.iter().map(|(_, e)| e.kind).collect();
    for pair in kinds.chunks(2) {
        assert_eq!(
            pair,
            [ContactKind::Begin, ContactKind::End][..pair.len()].to_vec()
        );
    }
}

#[test]
fn a_disc_striking_a_peg_begins_once_with_twice_its_momentum() {
    let config = Config {
        obstacles: vec![Obstacle::peg([5.0, 0.0], 1.0)],
        ..with_events(Config::default())
    };
    let mut world = World::new(config).unwrap();
    // Radius 1 (mass 1), speed 3 head on into a fixed peg at e = 1: 2 m v = 6.
    let id = world
        .add_particle(Particle::new([0.0, 0.0], [3.0, 0.0], 1.0))
        .unwrap();
    let events = run(&mut world, 200);
    let begins: Vec<_> = (events.iter())
        .filter(|(_, e)| e.kind == ContactKind::Begin)
        .collect();
    assert_eq!(begins.len(), 1, "{events:?}");
    let (_, hit) = begins[0];
    assert_eq!((hit.a, hit.b), (id, Party::Obstacle(0)));
    assert!((hit.normal_impulse - 6.0).abs() < 1e-12, "{hit:?}");
    assert_eq!(hit.normal, [1.0, 0.0]);
    assert_eq!(hit.point, [4.0, 0.0]);
    assert!((hit.approach_speed - 3.0).abs() < 1e-15);
    assert_eq!(events.len(), 2, "one begin, one end");
}

const PEG: [f64; 2] = [12.0, 8.0];

/// The pile (gravity, e = 0.7, 4 substeps) with a peg and rough discs: every kind of party.
fn pile(threads: usize, events: bool) -> World {
    pile_over(threads, events, 0.0)
}

/// [`pile`] reporting contacts that begin with a normal impulse of at least `threshold`.
fn pile_over(threads: usize, events: bool, threshold: f64) -> World {
    let (config, discs) = Bench::Pile.build(600).unwrap();
    let config = Config {
        friction: 0.3,
        solver_iterations: 2,
        contact_events: events,
        contact_event_threshold: threshold,
        obstacles: vec![Obstacle::peg(PEG, 2.0)],
        ..config
    };
    let mut world = World::new(config).unwrap();
    world.set_threads(threads).unwrap();
    world.set_parallel_min_work(1);
    for disc in discs {
        let d = [disc.position[0] - PEG[0], disc.position[1] - PEG[1]];
        if (d[0] * d[0] + d[1] * d[1]).sqrt() > 2.0 + disc.radius {
            world.add_particle(disc).unwrap();
        }
    }
    world
}

#[test]
fn events_are_the_same_on_any_thread_count_and_leave_the_physics_alone() {
    let mut quiet = pile(1, false);
    let mut one = pile(1, true);
    let mut reference = Vec::new();
    for _ in 0..120 {
        quiet.step(Bench::DT).unwrap();
        one.step(Bench::DT).unwrap();
        reference.push(one.contact_events().to_vec());
    }
    assert_eq!(
        quiet.state_hash(),
        one.state_hash(),
        "events change nothing"
    );
    assert!(quiet.contact_events().is_empty());
    let all: Vec<&ContactEvent> = reference.iter().flatten().collect();
    let walls = all.iter().filter(|e| matches!(e.b, Party::Wall(_))).count();
    let pegs = all
        .iter()
        .filter(|e| matches!(e.b, Party::Obstacle(0)))
        .count();
    let pairs = all.iter().filter(|e| matches!(e.b, Party::Disc(_))).count();
    assert!(
        walls > 0 && pegs > 0 && pairs > 100,
        "{walls} {pegs} {pairs}"
    );
    // Rough discs rub: some pairs report a tangential impulse.
    assert!(all.iter().any(|e| e.tangent_impulse.abs() > 1e-6));
    for threads in [2, 3] {
        let mut world = pile(threads, true);
        for (k, expected) in reference.iter().enumerate() {
            world.step(Bench::DT).unwrap();
            assert_eq!(
                world.contact_events(),
                &expected[..],
                "step {k}, {threads} threads"
            );
        }
    }
    // Each substep's events in the order of their parties.
    for step in &reference {
        for w in step.windows(2) {
            assert!((w[0].substep, w[0].a, w[0].b) < (w[1].substep, w[1].a, w[1].b));
        }
    }
}

#[test]
fn a_loaded_world_reports_what_the_original_does() {
    let mut original = pile(2, true);
    for _ in 0..40 {
        original.step(Bench::DT).unwrap();
    }
    assert!(original.contacts_now() > 0, "saved mid-contact");
    let bytes = postcard::to_allocvec(&original).unwrap();
    let mut loaded: World = postcard::from_bytes(&bytes).unwrap();
    for k in 0..30 {
        original.step(Bench::DT).unwrap();
        loaded.step(Bench::DT).unwrap();
        assert_eq!(
            loaded.contact_events(),
            original.contact_events(),
            "step {k}"
        );
    }
}

#[test]
fn the_threshold_keeps_hard_impacts_and_their_ends_only() {
    let mut all = pile(1, true);
    let mut hard = pile_over(1, true, 2.0);
    let (mut every, mut kept) = (Vec::new(), Vec::new());
    for _ in 0..60 {
        all.step(Bench::DT).unwrap();
        hard.step(Bench::DT).unwrap();
        every.extend_from_slice(all.contact_events());
        kept.extend_from_slice(hard.contact_events());
    }
    let strong = |e: &&ContactEvent| e.kind == ContactKind::Begin && e.normal_impulse >= 2.0;
    let begins: Vec<_> = kept
        .iter()
        .filter(|e| e.kind == ContactKind::Begin)
        .collect();
    assert_eq!(begins, every.iter().filter(strong).collect::<Vec<_>>());
    let every_begin = every
        .iter()
        .filter(|e| e.kind == ContactKind::Begin)
        .count();
    assert!(
        !begins.is_empty() && begins.len() < every_begin / 2,
        "{} of {every_begin}",
        begins.len()
    );
    // Every end belongs to a kept begin.
    let ends = kept.iter().filter(|e| e.kind == ContactKind::End);
    for end in ends {
        assert!(
            begins.iter().any(|b| (b.a, b.b) == (end.a, end.b)),
            "{end:?}"
        );
    }
}

#[test]
fn the_configuration_checks_the_threshold_and_the_method() {
    let bad = Config {
        contact_event_threshold: -1.0,
        ..Config::default()
    };
    assert_eq!(bad.validate().unwrap_err().field, "contact_event_threshold");
    let exact = Config {
        contact_events: true,
        method: bounce::Method::EventDriven,
        ..Config::default()
    };
    let err = exact.validate().unwrap_err();
    assert_eq!(err.field, "method");
    assert!(err.to_string().contains("contact events"), "{err}");
    // A removed disc's contacts end.
    let mut world = World::new(with_events(Config::default())).unwrap();
    let a = world
        .add_particle(Particle::new([0.0, 0.0], [0.0, 0.0], 1.0))
        .unwrap();
    world
        .add_particle(Particle::new([1.5, 0.0], [0.0, 0.0], 1.0))
        .unwrap();
    world.step(DT).unwrap();
    assert_eq!(world.contact_events().len(), 1);
    assert_eq!(world.remove_particles(&[ParticleId(1)]), 1);
    world.step(DT).unwrap();
    let end = world.contact_events()[0];
    assert_eq!((end.kind, end.a), (ContactKind::End, a));
}
