//! The pinned state hashes: every shipped template after 200 steps, on 1 and 2 threads.
//!
//! A refactor keeps these bits. A change that moves one changes the physics: make it on
//! purpose, and say why in the change. (The benchmark scenes are pinned beside the core's
//! tests, in `crates/bounce/tests/pinned.rs`.)

use bounce_scenario::Session;

/// `(template, state hash after 200 steps)`.
const TEMPLATES: [(&str, u64); 12] = [
    ("gas", 0xfdc4_568d_6ad9_5664),
    ("pile", 0xc60b_c57a_5279_98e3),
    ("galton-board", 0x2bd2_e9c4_9649_5597),
    ("mixing", 0x0247_e866_964d_9480),
    ("hourglass", 0xb72f_ad7d_d680_6ac2),
    ("effusion", 0x9a90_83e2_7f01_da5f),
    ("newtons-cradle", 0x03f5_e426_854e_f4b8),
    ("piston", 0xb684_0245_0e20_5ce5),
    ("angle-of-repose", 0xd5d8_e402_b960_a77e),
    ("hard-discs", 0xcf9f_e852_1ac6_86d2),
    ("driven-granular", 0xd561_eedd_c9c3_8411),
    ("shear", 0x00b5_1639_5809_7a16),
];

fn hash_after(name: &str, threads: usize, steps: usize) -> u64 {
    let mut session = Session::builtin(name).unwrap();
    session.world.set_threads(threads).unwrap();
    // Every parallel path runs, however small the world.
    session.world.set_parallel_min_work(0);
    for _ in 0..steps {
        session.step().unwrap();
    }
    session.world.state_hash()
}

/// The plain step (`bounce::plain`) gives every template its pinned bits too.
#[test]
fn the_plain_step_gives_every_template_its_pinned_bits() {
    for (name, pinned) in TEMPLATES {
        let mut session = Session::builtin(name).unwrap();
        for _ in 0..200 {
            bounce::plain::step(&mut session.world, session.dt).unwrap();
        }
        assert_eq!(session.world.state_hash(), pinned, "{name}");
    }
}

#[test]
fn every_template_keeps_its_bits_on_one_and_two_threads() {
    let mut wrong = Vec::new();
    for (name, pinned) in TEMPLATES {
        for threads in [1, 2] {
            let hash = hash_after(name, threads, 200);
            if hash != pinned {
                wrong.push(format!("{name} on {threads} threads: {hash:#018x}"));
            }
        }
    }
    assert!(wrong.is_empty(), "hashes moved:\n{}", wrong.join("\n"));
}

/// A driven obstacle takes the momentum of every disc that hits it, and the discs' storage
/// order changes whenever the candidates are listed anew: the piston's state must not
/// depend on when that happens.
#[test]
fn the_piston_keeps_its_bits_whenever_the_candidates_are_listed() {
    // The template's piston, driven by a force instead of at a set speed.
    let text = bounce_scenario::template("piston").unwrap().replace(
        "velocity = [0.0, -0.05]",
        "force = [0.0, -400.0]\nmass = 4.0",
    );
    assert!(text.contains("mass = 4.0"));
    let mut default = Session::from_text("driven.toml", &text).unwrap();
    let mut relisted = Session::from_text("driven.toml", &text).unwrap();
    let mut moved = 0.0f64;
    for step in 0..300 {
        relisted.world.relist();
        let a = default.step().unwrap().pairs;
        let b = relisted.step().unwrap().pairs;
        assert_eq!(a, b, "step {step}");
        assert_eq!(
            default.world.obstacle_states(),
            relisted.world.obstacle_states(),
            "step {step}"
        );
        assert_eq!(
            default.world.obstacle_impulses(),
            relisted.world.obstacle_impulses(),
            "step {step}"
        );
        assert_eq!(
            default.world.obstacle_work().to_bits(),
            relisted.world.obstacle_work().to_bits(),
            "step {step}"
        );
        assert_eq!(
            default.world.state_hash(),
            relisted.world.state_hash(),
            "step {step}"
        );
        let impulses = default.world.obstacle_impulses();
        moved = moved.max(
            impulses
                .iter()
                .map(|j| j[0].abs() + j[1].abs())
                .fold(0.0, f64::max),
        );
    }
    // The gas pushed on the piston (the test compares something that happened).
    assert!(moved > 0.0);
}

/// The rough discs' physics, pinned where it acts: the `angle-of-repose` template after its
/// first discs have landed and rolled (2,500 steps), on 1 and 2 threads and the plain step.
#[test]
fn the_rough_heap_keeps_its_bits() {
    const PINNED: u64 = 0xf77f_0061_2be0_a995;
    for threads in [1, 2] {
        assert_eq!(
            hash_after("angle-of-repose", threads, 2500),
            PINNED,
            "{threads} threads"
        );
    }
    let mut session = Session::builtin("angle-of-repose").unwrap();
    for _ in 0..2500 {
        bounce::plain::step(&mut session.world, session.dt).unwrap();
    }
    assert!(session.world.friction_work() > 0.0);
    assert_eq!(session.world.state_hash(), PINNED, "the plain step");
}
