//! `bounce view` tested as a person would: the real window under Xvfb (Mesa's software
//! OpenGL), a screenshot, and the pixels checked against where the discs are.
//!
//! Needs Xvfb and Mesa: `scripts/test` installs them and runs this with
//! `--features system-tests` (and the viewer, a default feature).
#![cfg(all(feature = "system-tests", feature = "view"))]

use std::path::Path;
use std::process::Command;

use assert_cmd::cargo::cargo_bin;

const BACKGROUND: [u8; 3] = [17, 20, 26];

const SCENARIO: &str = r##"
[world]
boundary = "walls"
min = [0.0, 0.0]
max = [100.0, 60.0]
[time]
dt = 0.016666666666666666
steps = 100000
[[gas]]
count = 300
radius = 1.2
speed = 12.0
seed = 4
color = "#ff8800"
[output]
color_by = "color"
"##;

/// Runs the viewer headless for `frames` frames; returns the screenshot and the sidecar text.
fn shoot(dir: &Path, scenario: &Path, frames: u32, name: &str) -> (tiny_skia::Pixmap, String) {
    let png = dir.join(name);
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(cargo_bin("bounce"))
        .arg("view")
        .arg(scenario)
        .arg("--headless-frames")
        .arg(frames.to_string())
        .arg("--screenshot")
        .arg(&png)
        .output()
        .expect("xvfb-run is installed by scripts/test");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "bounce view failed: {stderr}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("frames/s"));
    let side = std::fs::read_to_string(png.with_extension("txt")).unwrap();
    (tiny_skia::Pixmap::load_png(&png).unwrap(), side)
}

fn rgb(p: &tiny_skia::Pixmap, x: f64, y: f64) -> [u8; 3] {
    let c = p.pixel(x as u32, y as u32).unwrap();
    [c.red(), c.green(), c.blue()]
}

fn canvas(side: &str) -> [f64; 4] {
    let line = side.lines().find(|l| l.starts_with("canvas")).unwrap();
    let v: Vec<f64> = line
        .split_whitespace()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    [v[0], v[1], v[2], v[3]]
}

fn discs(side: &str) -> Vec<[f64; 3]> {
    side.lines()
        .filter(|l| l.starts_with("disc"))
        .map(|l| {
            let v: Vec<f64> = l
                .split_whitespace()
                .skip(1)
                .map(|s| s.parse().unwrap())
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

#[test]
fn the_window_shows_discs_where_the_particles_are_and_panels_around_them() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("gas.toml");
    std::fs::write(&scenario, SCENARIO).unwrap();
    let (first, side) = shoot(dir.path(), &scenario, 5, "first.png");
    assert_eq!((first.width(), first.height()), (1280, 800));

    // Discs: the pixel at each disc's centre has the scenario's colour.
    let first_discs = discs(&side);
    assert_eq!(first_discs.len(), 300);
    let orange = first_discs
        .iter()
        .filter(|d| rgb(&first, d[0], d[1]) == [255, 136, 0])
        .count();
    assert!(
        orange >= 290,
        "only {orange} of 300 disc centres are orange"
    );
    assert!(
        first_discs.iter().all(|d| d[2] > 3.0),
        "radius 1.2 is several pixels"
    );

    // Canvas background between discs, and panels on both sides of it.
    let [x0, y0, x1, y1] = canvas(&side);
    assert!(
        x0 > 100.0 && x1 < 1180.0 && y0 < 50.0 && y1 > 700.0,
        "canvas {x0} {y0} {x1} {y1}"
    );
    let empty = (0..200)
        .map(|k| (x0 + 5.0 + k as f64 * (x1 - x0 - 10.0) / 200.0, y0 + 4.0))
        .filter(|&(x, y)| rgb(&first, x, y) == BACKGROUND)
        .count();
    assert!(
        empty > 150,
        "the canvas top edge should be mostly background: {empty}"
    );
    for (name, range) in [
        ("left panel", 0.0..x0 - 2.0),
        ("right panel", x1 + 2.0..1279.0),
    ] {
        let mut colours = std::collections::HashSet::new();
        let mut differing = 0;
        for y in (0..800).step_by(4) {
            for x in (range.start as u32..range.end as u32).step_by(4) {
                let c = rgb(&first, x as f64, y as f64);
                colours.insert(c);
                differing += (c != BACKGROUND) as usize;
            }
        }
        assert!(
            colours.len() > 10,
            "{name}: only {} colours (text and widgets expected)",
            colours.len()
        );
        assert!(
            differing > 1000,
            "{name}: {differing} pixels differ from the canvas background"
        );
    }

    // More frames later, the discs have moved.
    let (later, side_later) = shoot(dir.path(), &scenario, 60, "later.png");
    let moved = first_discs
        .iter()
        .zip(discs(&side_later))
        .filter(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]) > 2.0)
        .count();
    assert!(moved > 250, "only {moved} discs moved");
    let mut changed = 0;
    for y in (y0 as u32..y1 as u32).step_by(3) {
        for x in (x0 as u32..x1 as u32).step_by(3) {
            changed +=
                (rgb(&first, x as f64, y as f64) != rgb(&later, x as f64, y as f64)) as usize;
        }
    }
    assert!(changed > 500, "the canvas barely changed: {changed} pixels");
}

#[test]
fn without_a_display_the_viewer_says_why_and_fails() {
    let out = Command::new(cargo_bin("bounce"))
        .args(["view", "--headless-frames", "2", "--screenshot"])
        .arg(std::env::temp_dir().join("never.png"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("cannot open a window"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_bad_scenario_is_reported_before_any_window_opens() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("bad.toml");
    std::fs::write(&scenario, "[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n[time]\ndt = -1.0\nsteps = 5\n[[disc]]\nposition = [5.0, 5.0]\nradius = 1.0\n").unwrap();
    let out = Command::new(cargo_bin("bounce"))
        .arg("view")
        .arg(&scenario)
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("bad.toml:5") && stderr.contains("time.dt"),
        "{stderr}"
    );
}
