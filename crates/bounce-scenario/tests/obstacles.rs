//! Obstacles in shipped scenarios: the hourglass holds its sand, the Galton board's bins fill
//! as a bell curve, a slow piston's work is the gas's gain in energy, and runs with obstacles
//! are deterministic across threads and resumes.

use bounce::{ParticleId, Shape};
use bounce_scenario::Session;
use bounce_scenario::analysis::{hard_disc_adiabat, henderson_z};

fn session(name: &str) -> Session {
    Session::builtin(name).unwrap()
}

/// Whether `p` is inside the polygon `outline` (even-odd rule).
fn inside(outline: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut inside = false;
    for k in 0..outline.len() {
        let (a, b) = (outline[k], outline[(k + 1) % outline.len()]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

#[test]
fn the_hourglass_holds_its_sand_for_a_hundred_thousand_steps() {
    // The glass is one polyline open at the top (the box's top wall closes it). Gravity is
    // turned over every 8,000 steps, so the sand runs through the neck again and again; at
    // every check each grain is inside the glass, and the sand did move between the bulbs.
    let mut s = session("hourglass");
    let Shape::Segment { a: first, .. } = s.world.obstacle_shapes()[0] else {
        panic!("a polyline is segments");
    };
    let mut outline: Vec<[f64; 2]> = vec![first];
    for shape in s.world.obstacle_shapes() {
        let Shape::Segment { b, .. } = shape else {
            panic!("a polyline is segments")
        };
        outline.push(b);
    }
    // Close it across the top, above the box (the top wall holds the sand in).
    let (left, right) = (outline[0], *outline.last().unwrap());
    outline.push([right[0], 200.0]);
    outline.push([left[0], 200.0]);
    let n = s.world.len();
    let mut lower_counts = Vec::new();
    for step in 1..=100_000u64 {
        s.world.step(s.dt).unwrap();
        if step % 8_000 == 0 {
            let mut config = s.world.config().clone();
            config.gravity[1] = -config.gravity[1];
            s.world.set_config(config).unwrap();
        }
        if step % 1_000 == 0 {
            let p = s.world.particles();
            let outside: Vec<usize> = (0..n)
                .filter(|&i| !inside(&outline, [p.x()[i], p.y()[i]]))
                .collect();
            assert!(
                outside.is_empty(),
                "step {step}: {} grains outside the glass, e.g. at ({}, {})",
                outside.len(),
                p.x()[outside[0]],
                p.y()[outside[0]]
            );
        }
        if step % 8_000 == 7_999 {
            let p = s.world.particles();
            lower_counts.push((0..n).filter(|&i| p.y()[i] < 40.0).count());
        }
    }
    // Just before each turn the sand has run into the bulb gravity points to.
    for (k, &lower) in lower_counts.iter().enumerate() {
        let expected_lower = k % 2 == 0;
        let moved = if expected_lower { lower } else { n - lower };
        assert!(
            moved > n * 9 / 10,
            "turn {k}: only {moved} of {n} grains ran through: {lower_counts:?}"
        );
    }
}

/// The bin (0..20, 3 wide) of each ball of a finished Galton board run.
fn galton_bins(seed: u64, threads: usize) -> (Vec<usize>, u64) {
    let text = bounce_scenario::overrides::apply(
        bounce_scenario::template("galton-board").unwrap(),
        &[],
        Some(seed),
    )
    .unwrap();
    let mut s = Session::from_text("galton-board", &text).unwrap();
    s.world.set_threads(threads).unwrap();
    for _ in 0..s.steps {
        s.world.step(s.dt).unwrap();
    }
    let mut bins = vec![0usize; 20];
    for id in 0..s.world.len() as u32 {
        let p = s.world.particle(ParticleId(id)).unwrap().position;
        assert!(p[1] < 26.0, "ball {id} has not reached the bins: {p:?}");
        bins[((p[0] / 3.0) as usize).min(19)] += 1;
    }
    (bins, s.world.state_hash())
}

#[test]
fn the_galton_board_fills_its_bins_as_a_bell_curve() {
    // 4 boards of 500 balls. Stated test: (1) symmetric: the mean bin is within 3 standard
    // errors of the centre (10, the board's axis is the boundary between bins 9 and 10, so
    // bin centres are k + 0.5); (2) bell-shaped: a chi-square test of the counts against the
    // normal with the sample's mean and standard deviation (bins with fewer than 5 expected
    // merged into the tails) does not reject at the 0.1 % level; (3) one peak: the counts
    // rise to the mode and fall after it, allowing dips of a few balls.
    let mut counts = vec![0usize; 20];
    for seed in 1..=4 {
        let (bins, _) = galton_bins(seed, 2);
        for (c, b) in counts.iter_mut().zip(bins) {
            *c += b;
        }
    }
    let n: usize = counts.iter().sum();
    let centre = |k: usize| k as f64 + 0.5;
    let mean = counts
        .iter()
        .enumerate()
        .map(|(k, &c)| centre(k) * c as f64)
        .sum::<f64>()
        / n as f64;
    let var = counts
        .iter()
        .enumerate()
        .map(|(k, &c)| (centre(k) - mean).powi(2) * c as f64)
        .sum::<f64>()
        / (n - 1) as f64;
    let sd = var.sqrt();
    let standard_error = sd / (n as f64).sqrt();
    assert!(
        (mean - 10.0).abs() < 3.0 * standard_error,
        "mean bin {mean} (sd {sd}, n {n}) off centre: {counts:?}"
    );
    // Expected counts from the fitted normal, bins of width 1 (the last ones open-ended).
    let phi = |x: f64| 0.5 * (1.0 + libm::erf((x - mean) / (sd * std::f64::consts::SQRT_2)));
    let expected: Vec<f64> = (0..20)
        .map(|k| {
            let lo = if k == 0 { 0.0 } else { phi(k as f64) };
            let hi = if k == 19 { 1.0 } else { phi(k as f64 + 1.0) };
            n as f64 * (hi - lo)
        })
        .collect();
    // Merge tails until every class expects at least 5.
    let mut classes: Vec<(f64, f64)> = Vec::new();
    let (mut e_acc, mut o_acc) = (0.0, 0.0);
    for k in 0..20 {
        e_acc += expected[k];
        o_acc += counts[k] as f64;
        if e_acc >= 5.0 {
            classes.push((o_acc, e_acc));
            (e_acc, o_acc) = (0.0, 0.0);
        }
    }
    if let Some(last) = classes.last_mut() {
        last.0 += o_acc;
        last.1 += e_acc;
    }
    let chi2: f64 = classes.iter().map(|(o, e)| (o - e).powi(2) / e).sum();
    let df = classes.len() - 3;
    // The 0.1 % critical values of chi-square for 1..=20 degrees of freedom.
    const CRITICAL: [f64; 20] = [
        10.83, 13.82, 16.27, 18.47, 20.52, 22.46, 24.32, 26.12, 27.88, 29.59, 31.26, 32.91, 34.53,
        36.12, 37.70, 39.25, 40.79, 42.31, 43.82, 45.31,
    ];
    assert!(
        chi2 < CRITICAL[df - 1],
        "chi-square {chi2} with {df} degrees of freedom against the fitted normal \
         (mean {mean}, sd {sd}): {counts:?}"
    );
    eprintln!("bins {counts:?}: mean {mean:.3}, sd {sd:.3}, chi-square {chi2:.2} ({df} df)");
    // (4) What the board shows is not the binomial of independent balls: 15 rows, each a
    // step of half the peg spacing (1.2) left or right, spread them by 1.2 √15 = 4.65 units,
    // 1.55 bins of 3. The balls fall as a crowd and knock each other sideways: the heap is
    // about 2.6 times as wide (the template says so).
    let binomial = 1.2 * 15f64.sqrt() / 3.0;
    let ratio = sd / binomial;
    assert!(
        (2.0..3.2).contains(&ratio),
        "spread {sd:.2} bins, {ratio:.2} times the binomial's {binomial:.2}"
    );
    let mode = (0..20).max_by_key(|&k| counts[k]).unwrap();
    let slack = n / 100;
    for k in 1..=mode {
        assert!(
            counts[k] + slack >= counts[k - 1],
            "no single peak: {counts:?}"
        );
    }
    for k in mode + 1..20 {
        assert!(
            counts[k] <= counts[k - 1] + slack,
            "no single peak: {counts:?}"
        );
    }
}

#[test]
fn obstacles_give_the_same_bits_on_any_thread_count() {
    assert_eq!(galton_bins(7, 1).1, galton_bins(7, 3).1);
}

#[test]
fn a_slow_piston_does_work_equal_to_the_gain_in_kinetic_energy() {
    // The shipped piston (e = 1 everywhere): over 12,000 steps it moves 12 units into the
    // gas. Every collision with it is elastic in its frame, so the work it does, summed over
    // its collisions, is the gas's gain in kinetic energy; the rest of the dynamics
    // conserves energy at e = 1.
    let mut s = session("piston");
    let before = s.world.stats().kinetic_energy;
    let mut impulse = [0.0, 0.0];
    for _ in 0..12_000 {
        s.world.step(s.dt).unwrap();
        let j = s.world.obstacle_impulses()[0];
        impulse = [impulse[0] + j[0], impulse[1] + j[1]];
    }
    let gain = s.world.stats().kinetic_energy - before;
    let work = s.world.obstacle_work();
    assert!(
        gain > 0.2 * before,
        "the gas barely heated: {before} -> +{gain}"
    );
    assert!(
        (work - gain).abs() < 0.01 * gain,
        "work {work} vs kinetic energy gained {gain}"
    );
    // The gas pushed on the piston (the force on it points up), and the piston moved as
    // prescribed.
    assert!(impulse[1] > 0.0, "impulse on the piston {impulse:?}");
    let Shape::Segment { a, .. } = s.world.obstacle_shapes()[0] else {
        panic!("the piston is a segment");
    };
    assert!(
        (a[1] - (50.0 - 0.05 * 0.02 * 12_000.0)).abs() < 1e-9,
        "{a:?}"
    );
}

#[test]
fn a_resumed_run_with_a_moving_piston_continues_bit_for_bit() {
    let mut straight = session("piston");
    let mut first = session("piston");
    for _ in 0..300 {
        straight.world.step(straight.dt).unwrap();
    }
    for _ in 0..150 {
        first.world.step(first.dt).unwrap();
    }
    let bytes = bounce_scenario::checkpoint::encode(&first.world, None).unwrap();
    let mut resumed = session("piston");
    let loaded = bounce_scenario::checkpoint::decode(&bytes, "c").unwrap();
    resumed.resume(loaded.world, "c").unwrap();
    for _ in 0..150 {
        resumed.world.step(resumed.dt).unwrap();
    }
    assert_eq!(resumed.world.state_hash(), straight.world.state_hash());
    assert_eq!(
        resumed.world.obstacle_shapes(),
        straight.world.obstacle_shapes()
    );
    assert_eq!(
        resumed.world.obstacle_work(),
        straight.world.obstacle_work()
    );
}

#[test]
fn obstacle_tables_with_problems_are_refused_with_their_lines() {
    let text = r#"
[world]
min = [0.0, 0.0]
max = [10.0, 10.0]
[time]
dt = 0.01
steps = 10
[[obstacle]]
segment = [[1.0, 1.0], [2.0, 2.0]]
peg = [5.0, 5.0]
radius = 1.0
[[obstacle]]
peg = [5.0, 5.0]
[[obstacle]]
box = { centre = [5.0, 5.0], size = [2.0, 2.0] }
force = [0.0, -1.0]
mass = 2.0
[[obstacle]]
segment = [[3.0, 3.0], [3.0, 3.0]]
[[obstacle]]
peg = [1.0, 1.0]
radius = -2.0
restitution = 1.5
[[obstacle]]
pegs = { origin = [2.0, 2.0], rows = 3, columns = 0, spacing = [1.0, 1.0] }
radius = 0.1
"#;
    let error = Session::from_text("bad.toml", text)
        .unwrap_err()
        .to_string();
    for expected in [
        "bad.toml:8: obstacle #1: give exactly one of segment, polyline, box, peg, pegs (2 given)",
        "bad.toml:12: obstacle #2: a peg needs `radius`",
        "bad.toml:14: obstacle #3: a driven obstacle (`force`) is one segment or one peg",
        "bad.toml:18: obstacle #4: segment [3.0, 3.0] to [3.0, 3.0]: the ends must differ",
        "bad.toml:20: obstacle #5: peg.radius -2: must be finite and > 0",
        "bad.toml:24: obstacle #6: pegs: 3 rows of 0 is no peg (rows and columns must be >= 1)",
    ] {
        assert!(
            error.contains(expected),
            "missing {expected:?} in:\n{error}"
        );
    }
}

#[test]
fn a_piston_under_a_weight_comes_to_rest_where_the_gas_holds_it() {
    // A driven piston of mass 20 pushed down by a force of 40 on an elastic gas: it sinks
    // until the gas's pressure carries it, then the mean force of the gas on it equals the
    // weight (its mean acceleration is zero) and it stays inside the box.
    let text = r#"
[world]
min = [0.0, 0.0]
max = [30.0, 60.0]
[time]
dt = 0.01
steps = 1
substeps = 2
[[gas]]
count = 300
radius = 0.5
temperature = 2.0
seed = 9
region = { min = [0.0, 0.0], max = [30.0, 39.0] }
[[obstacle]]
segment = [[0.0, 40.0], [30.0, 40.0]]
force = [0.0, -40.0]
mass = 20.0
name = "piston"
"#;
    let mut s = Session::from_text("weight.toml", text).unwrap();
    // Settle, then average the gas's push over a long window.
    for _ in 0..4_000 {
        s.world.step(s.dt).unwrap();
    }
    let (mut impulse, mut time, mut heights) = (0.0, 0.0, Vec::new());
    for _ in 0..8_000 {
        s.world.step(s.dt).unwrap();
        impulse += s.world.obstacle_impulses()[0][1];
        time += s.dt;
        let Shape::Segment { a, .. } = s.world.obstacle_shapes()[0] else {
            panic!("a segment")
        };
        heights.push(a[1]);
    }
    let force = impulse / time;
    assert!(
        (force - 40.0).abs() < 0.05 * 40.0,
        "the gas pushes with {force} against a weight of 40"
    );
    let (lo, hi) = heights
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &y| {
            (l.min(y), h.max(y))
        });
    assert!(
        lo > 1.0 && hi < 60.0,
        "the piston stayed between {lo} and {hi}"
    );
}

#[test]
fn the_piston_heats_its_gas_along_the_hard_disc_adiabat() {
    // The shipped piston compresses 400 discs (radius 0.5) from packing 0.16 to 0.31. Slow
    // and elastic, the compression is adiabatic: d ln T = −Z(η) d ln A with the hard-disc
    // Z (Henderson's). The ideal gas's T A = constant would say the temperature doubles; the
    // dense gas heats well beyond that.
    let mut s = session("piston");
    let count = s.world.len() as f64;
    let disc_area = count * std::f64::consts::PI * 0.25;
    let gas_area = |s: &Session| {
        let Shape::Segment { a, .. } = s.world.obstacle_shapes()[0] else {
            panic!("the piston is a segment");
        };
        40.0 * a[1]
    };
    let (a0, t0) = (gas_area(&s), s.world.stats().kinetic_energy / count);
    for _ in 0..25_000 {
        s.world.step(s.dt).unwrap();
    }
    let (a1, t1) = (gas_area(&s), s.world.stats().kinetic_energy / count);
    // The adiabat's pressure ratio is Z1 T1 A0 / (Z0 T0 A1): its temperature ratio follows.
    let z = |a: f64| henderson_z(disc_area / a);
    let adiabat = hard_disc_adiabat(a0, 1.0, disc_area, a1) * (z(a0) / z(a1)) * (a1 / a0);
    let measured = t1 / t0;
    eprintln!("piston: A {a0} -> {a1}, T x{measured:.4}, hard-disc adiabat x{adiabat:.4}");
    assert!(
        (measured / adiabat - 1.0).abs() < 0.03,
        "T rose {measured:.3}x from A = {a0} to {a1}; the hard-disc adiabat says {adiabat:.3}x"
    );
    assert!(
        measured > 1.4 * (a0 / a1),
        "T rose {measured:.3}x, near the ideal gas's {:.3}x",
        a0 / a1
    );
}
