//! Starting from a file: a `[[file]]` table reads a CSV table or a GSD frame, places the
//! discs as a `[[disc]]` table would, and refuses a bad file naming the file, the line or
//! particle, and the field.

use std::path::Path;

use bounce::{Boundary, ParticleId};
use bounce_scenario::{Limits, Session, gsd::GsdWriter};

/// A scenario in `dir` with a `[[file]]` table for `file` (and `extra` in it).
fn scenario(boundary: &str, file: &str, extra: &str) -> String {
    format!(
        "[world]\n{boundary}\nmass_model = \"per_particle\"\n[time]\ndt = 0.01\nsteps = 5\n\
         [[file]]\npath = \"{file}\"\n{extra}\n"
    )
}

const WALLS: &str = "boundary = \"walls\"\nmin = [0.0, 0.0]\nmax = [20.0, 10.0]";

fn session_in(dir: &Path, text: &str) -> Result<Session, String> {
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    // Paths are relative to the scenario file, not the current folder.
    Session::load(&path).map_err(|e| e.to_string())
}

#[test]
fn a_csv_table_gives_each_disc_its_row_with_types_and_masses() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("start.csv"),
        "type,x,y,radius,vx,vy,mass\nbig,5,5,1.5,1,-2,7\nsmall,10,5,0.5,0,0,\nbig, 15 ,5,1.5,,,3\n",
    )
    .unwrap();
    let s = session_in(dir.path(), &scenario(WALLS, "start.csv", "")).unwrap();
    assert_eq!(s.world.len(), 3);
    let p = |k: u32| s.world.particle(ParticleId(k)).unwrap();
    assert_eq!(p(0).position, [5.0, 5.0]);
    assert_eq!(p(0).velocity, [1.0, -2.0]);
    assert_eq!(p(0).radius, 1.5);
    assert_eq!(p(0).mass, Some(7.0));
    // An empty mass takes the model's default (π r²), empty velocities 0.
    assert_eq!(p(1).mass, Some(std::f64::consts::PI * 0.25));
    assert_eq!(p(2).velocity, [0.0, 0.0]);
    assert_eq!(p(2).position, [15.0, 5.0]);
    assert_eq!(s.types, ["big", "small"]);
    assert_eq!(s.typeid, [0, 1, 0]);
    // A `type` field names every disc's type.
    let s = session_in(
        dir.path(),
        &scenario(WALLS, "start.csv", "type = \"grain\""),
    )
    .unwrap();
    assert_eq!(s.types, ["grain"]);
}

#[test]
fn a_csv_table_can_give_each_disc_its_spin() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("spin.csv"),
        "x,y,radius,angular_velocity\n5,5,1,2.5\n10,5,1,\n",
    )
    .unwrap();
    let s = session_in(dir.path(), &scenario(WALLS, "spin.csv", "")).unwrap();
    assert_eq!(s.world.angular_velocities(), [2.5, 0.0]);
    assert!(s.world.particles().turns());
    std::fs::write(
        dir.path().join("bad.csv"),
        "x,y,radius,angular_velocity\n5,5,1,fast\n",
    )
    .unwrap();
    let error = session_in(dir.path(), &scenario(WALLS, "bad.csv", "")).unwrap_err();
    assert!(
        error.contains("line 2: angular_velocity = \"fast\""),
        "{error}"
    );
}

#[test]
fn a_bad_csv_is_refused_naming_the_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    for (csv, expect) in [
        ("x,y,radius,spin\n1,1,0.5,2\n", "unknown column \"spin\""),
        ("x,radius\n1,0.5\n", "no column y"),
        (
            "x,y,radius\n1,1,0.5\n2,abc,0.5\n",
            "line 3: y = \"abc\" is not a number",
        ),
        ("x,y,radius\n1,1,0.5\n3,3,-1\n", "line 3: radius -1"),
        ("x,y,radius\n1,1,nan\n", "line 2: radius NaN"),
        ("x,y,radius\n", "no rows"),
        // Outside the walls: the world's own admission, named by the table and disc.
        ("x,y,radius\n1,1,0.5\n30,1,0.5\n", "particle 2 of 2"),
    ] {
        std::fs::write(dir.path().join("bad.csv"), csv).unwrap();
        let error = session_in(dir.path(), &scenario(WALLS, "bad.csv", "")).unwrap_err();
        assert!(
            error.contains("bad.csv") && error.contains(expect) && error.contains("s.toml:9"),
            "{csv:?}: {error}"
        );
    }
    let error = session_in(dir.path(), &scenario(WALLS, "missing.csv", "")).unwrap_err();
    assert!(error.contains("missing.csv: cannot read it"), "{error}");
}

#[test]
fn a_gsd_frame_restarts_a_run_where_its_trajectory_was() {
    // A periodic gas run a few steps with a trajectory; a new scenario starts from its frames.
    let dir = tempfile::tempdir().unwrap();
    let periodic = "boundary = \"periodic\"\nmin = [-3.0, 2.0]\nmax = [37.0, 22.0]";
    let gas = format!(
        "[world]\n{periodic}\n[time]\ndt = 0.01\nsteps = 5\n\
         [[disc]]\nposition = [10.0, 10.0]\nradius = 1.0\ntype = \"tracer\"\n\
         [[gas]]\ncount = 300\nradius = 0.3\nspeed = 2.0\ntype = \"gas\"\n"
    );
    let mut run = Session::from_text("gas.toml", &gas).unwrap();
    let path = dir.path().join("t.gsd");
    let mut gsd = GsdWriter::create(&path, &run.types, &run.typeid).unwrap();
    gsd.frame(&run.world).unwrap();
    let first: Vec<[f64; 2]> = (0..301)
        .map(|k| run.world.particle(ParticleId(k)).unwrap().position)
        .collect();
    for _ in 0..5 {
        run.step().unwrap();
    }
    gsd.frame(&run.world).unwrap();
    gsd.finish().unwrap();

    let start = session_in(dir.path(), &scenario(periodic, "t.gsd", "")).unwrap();
    assert_eq!(start.world.len(), 301);
    assert_eq!(start.types, ["tracer", "gas"]);
    assert_eq!(start.typeid[0], 0);
    assert_eq!(start.typeid[300], 1);
    assert!(matches!(
        start.world.config().boundary,
        Boundary::Periodic { .. }
    ));
    // The last frame by default: each disc where the run left it, to 32-bit precision.
    for k in 0..301 {
        let (a, b) = (
            start.world.particle(ParticleId(k)).unwrap(),
            run.world.particle(ParticleId(k)).unwrap(),
        );
        for axis in 0..2 {
            let gap = (a.position[axis] - b.position[axis]).abs();
            // (Or across the periodic box, where the rounding fell on the far edge.)
            assert!(
                gap < 1e-5 || (gap - [40.0, 20.0][axis]).abs() < 1e-5,
                "{k}: {gap}"
            );
            assert!((a.velocity[axis] - b.velocity[axis]).abs() < 1e-5);
        }
        assert!((a.radius - b.radius).abs() < 1e-7);
    }
    // Frame 0 is the start.
    let start = session_in(dir.path(), &scenario(periodic, "t.gsd", "frame = 0")).unwrap();
    for k in [0, 150, 300] {
        let p = start.world.particle(ParticleId(k)).unwrap().position;
        assert!((p[0] - first[k as usize][0]).abs() < 1e-5, "{k}");
    }
    // A frame it does not hold, and a box of another size, are refused naming them.
    let error = session_in(dir.path(), &scenario(periodic, "t.gsd", "frame = 2")).unwrap_err();
    assert!(
        error.contains("t.gsd: frame = 2: the file holds frames 0..1"),
        "{error}"
    );
    let other = "boundary = \"periodic\"\nmin = [0.0, 0.0]\nmax = [30.0, 20.0]";
    let error = session_in(dir.path(), &scenario(other, "t.gsd", "")).unwrap_err();
    assert!(
        error.contains("its box is 40 × 20, the world's is 30 × 20"),
        "{error}"
    );
    let error = session_in(dir.path(), &scenario(periodic, "s.toml", "")).unwrap_err();
    assert!(error.contains("s.toml: not a GSD 2 file"), "{error}");
}

#[test]
fn file_discs_count_in_the_memory_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("x,y,radius\n");
    for k in 0..1000 {
        csv += &format!(
            "{},{},0.1\n",
            0.5 + (k % 30) as f64 * 0.5,
            0.5 + (k / 30) as f64 * 0.25
        );
    }
    std::fs::write(dir.path().join("many.csv"), csv).unwrap();
    let mut scenario_ = bounce_scenario::parse(&scenario(WALLS, "many.csv", ""), "s").unwrap();
    scenario_.dir = Some(dir.path().to_path_buf());
    assert_eq!(scenario_.particle_count(), Some(1000));
    let text = scenario(WALLS, "many.csv", "");
    let tiny = Limits { memory_bytes: 1000 };
    let error = Session::from_text_in("s", &text, &tiny, Some(dir.path()))
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(error.contains("1000 particles"), "{error}");
}
