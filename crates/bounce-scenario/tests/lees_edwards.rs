//! Lees–Edwards boxes in a scenario: the template starts with the linear flow and keeps it,
//! the stats' temperature is taken relative to the flow, a GSD trajectory records each
//! frame's offset and reads back as the world it came from (g(r) through the sliding
//! images), and every misuse names its field and line.

use bounce_scenario::structure::{Rdf, Snapshot};
use bounce_scenario::trajectory::Trajectory;
use bounce_scenario::{Session, analysis, gsd};

#[test]
fn the_shear_template_starts_in_its_flow_and_keeps_its_temperature_relative_to_it() {
    let mut session = Session::builtin("shear").unwrap();
    let world = &session.world;
    let bounce::Boundary::LeesEdwards {
        shear_rate, max, ..
    } = world.config().boundary
    else {
        panic!("the template is sheared");
    };
    // `streaming = true`: each disc's x velocity less its thermal part is the flow there,
    // so the least-squares slope of v_x on y is the shear rate within the thermal noise.
    let p = world.particles();
    let n = p.len() as f64;
    let mean = |v: &[f64]| v.iter().sum::<f64>() / n;
    let (my, mv) = (mean(p.y()), mean(p.vx()));
    let cov: f64 = (p.y().iter().zip(p.vx()))
        .map(|(y, v)| (y - my) * (v - mv))
        .sum();
    let var: f64 = p.y().iter().map(|y| (y - my).powi(2)).sum();
    let slope = cov / var;
    assert!((slope - shear_rate).abs() < 0.01, "slope {slope}");
    assert!(max[1] > 50.0);
    // The temperature the stats report is the flow's own: about the gas's kT = 1, not the
    // kinetic energy of the shear flow (which adds m γ̇² L² / 24 ≈ 0.05 a disc).
    let total_mass: f64 = analysis::masses(world).iter().sum();
    let kt = analysis::temperature(world, total_mass);
    assert!((kt - 1.0).abs() < 0.1, "kT {kt}");
    assert_eq!(kt, world.peculiar_kinetic_energy() / n);
    for _ in 0..200 {
        session.step().unwrap();
    }
    let kt = analysis::temperature(&session.world, total_mass);
    assert!((kt - 1.0).abs() < 0.1, "kT after 200 steps {kt}");
}

/// The ordered pairs of `frame` per bin of `width` up to `r_max`, by brute force: each
/// pair's nearest copy among the nine around, the rows above and below slid by `slide`.
fn brute_pairs(frame: &Snapshot, slide: f64, r_max: f64, bins: usize) -> Vec<u64> {
    let [lx, ly] = frame.size;
    let width = r_max / bins as f64;
    let mut out = vec![0u64; bins];
    let p = &frame.position;
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let mut r = f64::INFINITY;
            for up in [-1.0, 0.0, 1.0] {
                for across in [-2.0, -1.0, 0.0, 1.0, 2.0] {
                    let dx = p[j][0] + across * lx + up * slide - p[i][0];
                    let dy = p[j][1] + up * ly - p[i][1];
                    r = r.min(dx.hypot(dy));
                }
            }
            if r < r_max {
                out[((r / width) as usize).min(bins - 1)] += 2;
            }
        }
    }
    out
}

#[test]
fn a_sheared_trajectory_records_each_offset_and_its_g_of_r_slides_with_the_images() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.gsd");
    let mut session = Session::builtin("shear").unwrap();
    let mut writer = gsd::GsdWriter::create(&path, &session.types, &session.typeid).unwrap();
    let mut offsets = Vec::new();
    for frame in 0..3 {
        if frame > 0 {
            for _ in 0..400 {
                session.step().unwrap();
            }
        }
        writer.frame(&session.world).unwrap();
        offsets.push(session.world.lees_edwards_offset().unwrap());
    }
    writer.finish().unwrap();
    assert!(offsets[2] != 0.0 && offsets[1] != offsets[2], "{offsets:?}");
    let mut trajectory = Trajectory::open(&path).unwrap();
    let frames = trajectory.snapshots(0, None).unwrap();
    let (r_max, bins) = (3.0, 60);
    for (frame, offset) in frames.iter().zip(&offsets) {
        assert_eq!(frame.slide, Some(*offset));
        // g(r)'s pairs through the grid and the sliding minimum image are brute force's.
        let mut rdf = Rdf::new(bins, r_max).unwrap();
        rdf.add(frame).unwrap();
        assert_eq!(rdf.pairs(), brute_pairs(frame, *offset, r_max, bins));
        // Taken as an unsheared periodic box, pairs across the top and bottom go wrong.
        if *offset != 0.0 {
            let mut unslid = Rdf::new(bins, r_max).unwrap();
            unslid
                .add(&Snapshot {
                    slide: None,
                    ..frame.clone()
                })
                .unwrap();
            assert_ne!(unslid.pairs(), rdf.pairs());
        }
    }
    // An MSD of sliding frames is refused, with the reason.
    let error = bounce_scenario::structure::msd(&frames).unwrap_err();
    assert!(error.contains("Lees–Edwards"), "{error}");
}

/// What `Session` says of a small gas with `world` in `[world]`, `gas` in its `[[gas]]`
/// and `output` in `[output]` (`""`: nothing); `[time]` holds `time` too.
fn problems_in(world: &str, time: &str, gas: &str, output: &str) -> String {
    let text = format!(
        "[world]\n{world}\nmin = [0.0, 0.0]\nmax = [20.0, 20.0]\n\n[time]\ndt = 0.01\nsteps = 10\n\
         {time}\n\n[[gas]]\ncount = 50\nradius = 0.5\ntemperature = 1.0\n{gas}\n\n[output]\n\
         {output}\n"
    );
    match Session::from_text("s.toml", &text) {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    }
}

fn problems(world: &str, gas: &str, output: &str) -> String {
    problems_in(world, "", gas, output)
}

#[test]
fn misused_shear_fields_are_named_with_their_lines() {
    let sheared = "boundary = \"lees_edwards\"\nshear_rate = 0.1";
    assert_eq!(problems(sheared, "streaming = true", ""), "");
    let cases = [
        (
            "boundary = \"lees_edwards\"",
            "",
            "",
            "world.shear_rate is required with boundary = \"lees_edwards\"",
        ),
        (
            "boundary = \"periodic\"\nshear_rate = 0.1",
            "",
            "",
            "world.shear_rate = 0.1: only with boundary = \"lees_edwards\"",
        ),
        (
            "boundary = \"periodic\"",
            "streaming = true",
            "",
            "gas #1: streaming = true needs boundary = \"lees_edwards\"",
        ),
        (
            sheared,
            "",
            "msd = true",
            "output.msd: not in a Lees–Edwards box",
        ),
        (
            "boundary = \"lees_edwards\"\nshear_rate = inf",
            "",
            "",
            "world.boundary.shear_rate = inf: must be finite",
        ),
    ];
    for (world, gas, output, want) in cases {
        let error = problems(world, gas, output);
        assert!(error.contains(want), "{world} / {gas} / {output}:\n{error}");
        assert!(error.contains("s.toml:"), "the file and line: {error}");
    }
    // The event-driven method refuses the box, naming it.
    let error = problems_in(sheared, "method = \"event_driven\"", "", "");
    assert!(error.contains("Lees–Edwards"), "{error}");
}
