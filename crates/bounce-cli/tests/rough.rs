//! `bounce run` with rough discs: `stats.csv`'s rotation columns balance the energy, the GSD
//! trajectory holds HOOMD-blue's rotation chunks, and a smooth run has neither.

mod common;

use common::{Scratch, bounce, gsd_chunks, output};

/// Elastic rough discs in a box without gravity (e = 1, so only friction removes energy).
const ROUGH: &str = r#"
[world]
boundary = "walls"
min = [0.0, 0.0]
max = [30.0, 30.0]
friction = 0.3
rolling_resistance = 0.02

[time]
dt = 0.01
steps = 200

[[gas]]
count = 300
radius = 0.5
speed = 3.0
spin = 4.0

[output]
stats_every = 20
gsd_every = 100
plots = false
"#;

/// `bounce run` of `text` into `out` in `s`: its `stats.csv`.
fn run(s: &Scratch, text: &str) -> String {
    let scenario = s.scenario("scenario.toml", text);
    let (code, _, err) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(s.path("out")),
    );
    assert_eq!(code, 0, "{err}");
    std::fs::read_to_string(s.path("out/stats.csv")).unwrap()
}

/// The rows of a `stats.csv`, each column by name.
fn rows(text: &str) -> Vec<std::collections::HashMap<String, f64>> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .map(|(h, v)| (h.to_string(), v.parse().unwrap_or(f64::NAN)))
                .collect()
        })
        .collect()
}

#[test]
fn stats_balance_the_energy_and_the_trajectory_holds_the_rotation() {
    let s = Scratch::new();
    let text = run(&s, ROUGH);
    assert!(
        text.lines()
            .next()
            .unwrap()
            .ends_with(",rotational_energy,angular_momentum,friction_work"),
        "{}",
        text.lines().next().unwrap()
    );
    let rows = rows(&text);
    let total = |r: &std::collections::HashMap<String, f64>| {
        r["kinetic_energy"] + r["rotational_energy"] + r["friction_work"]
    };
    let start = total(&rows[0]);
    assert_eq!(rows[0]["friction_work"], 0.0);
    let last = rows.last().unwrap();
    assert!(last["friction_work"] > 0.01 * start, "friction did work");
    for r in &rows {
        assert!(
            ((total(r) - start) / start).abs() < 1e-9,
            "step {}: {} vs {start}",
            r["step"],
            total(r)
        );
    }

    // Frames at steps 0, 100 and 200, each with the rotation chunks: I = k m r² = ½ 0.5
    // 0.25 for every disc, unit orientation quaternions, angmom = 2 q (0, 0, 0, I ω).
    let chunks = gsd_chunks(&s.path("out/trajectory.gsd"));
    let f32s = |data: &[u8]| -> Vec<f32> {
        data.chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    };
    for frame in 0..3 {
        let of = |name: &str| {
            f32s(
                &chunks
                    .iter()
                    .find(|c| c.frame == frame && c.name == name)
                    .unwrap_or_else(|| panic!("frame {frame} has no {name}"))
                    .data,
            )
        };
        let (inertia, q, p) = (
            of("particles/moment_inertia"),
            of("particles/orientation"),
            of("particles/angmom"),
        );
        assert_eq!((inertia.len(), q.len(), p.len()), (900, 1200, 1200));
        for k in 0..300 {
            assert_eq!(&inertia[3 * k..3 * k + 3], &[0.0, 0.0, 0.0625]);
            let q = &q[4 * k..4 * k + 4];
            assert!((q[0] * q[0] + q[3] * q[3] - 1.0).abs() < 1e-6 && q[1] == 0.0 && q[2] == 0.0);
            // The body angular momentum back: (cos(θ/2) p_z − sin(θ/2) p_s) / 2 = I ω, |ω| <= 4
            // at the start.
            let l = (q[0] * p[4 * k + 3] - q[3] * p[4 * k]) / 2.0;
            if frame == 0 {
                assert!(l.abs() <= 0.0625 * 4.0 + 1e-6, "{l}");
            }
        }
    }
}

#[test]
fn a_smooth_run_has_no_rotation_columns_or_chunks() {
    let s = Scratch::new();
    let smooth = ROUGH
        .replace("friction = 0.3\n", "")
        .replace("rolling_resistance = 0.02\n", "")
        .replace("spin = 4.0\n", "");
    let text = run(&s, &smooth);
    assert!(!text.lines().next().unwrap().contains("rotational_energy"));
    let chunks = gsd_chunks(&s.path("out/trajectory.gsd"));
    assert!(chunks.iter().all(|c| !c.name.contains("angmom")));
}
