//! The browser version in real headless Chromium: the page built by `scripts/build-web`,
//! served on 127.0.0.1, driven by `web/e2e.mjs` (playwright-core). Checks the canvas shows
//! discs, play/pause and step behave, and the state hash after 100 steps equals a native run.
//!
//! Needs Chromium, node with playwright-core and the built page: `scripts/test` installs them
//! and runs this with `--features system-tests`.
#![cfg(feature = "system-tests")]

use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A static server for web/dist that stops when dropped.
struct Server {
    child: Child,
    url: String,
}

impl Server {
    fn start() -> Self {
        let dist = root().join("web/dist");
        assert!(
            dist.join("index.html").exists() && dist.join("pkg/bounce_web_bg.wasm").exists(),
            "web/dist is not built: run scripts/build-web (scripts/test does)"
        );
        let port = TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let child = Command::new("python3")
            .args([
                "-m",
                "http.server",
                "--bind",
                "127.0.0.1",
                &port.to_string(),
                "-d",
            ])
            .arg(&dist)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("python3 serves the page");
        let deadline = Instant::now() + Duration::from_secs(20);
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(Instant::now() < deadline, "the static server did not start");
            std::thread::sleep(Duration::from_millis(100));
        }
        Server {
            child,
            url: format!("http://127.0.0.1:{port}"),
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The status a native run of the built-in scenario `name` has after `steps` steps.
fn native_status(name: &str, steps: u64) -> String {
    let mut session = bounce_scenario::Session::builtin(name).unwrap();
    for _ in 0..steps {
        session.step().unwrap();
    }
    let world = &session.world;
    format!(
        "step {steps} hash {:016x} particles {}",
        world.state_hash(),
        world.len()
    )
}

fn drive(server: &Server, mode: &str, screenshot: &Path) -> serde_json::Value {
    let web = root().join("web");
    assert!(
        web.join("node_modules/playwright-core").exists(),
        "playwright-core is not installed: run npm install in web/ (scripts/test does)"
    );
    let out = Command::new("node")
        .current_dir(&web)
        .arg("e2e.mjs")
        .arg(&server.url)
        .arg(screenshot)
        .arg(mode)
        .output()
        .expect("node runs the browser driver");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "e2e.mjs failed: {stdout} {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = stdout.lines().last().unwrap_or_default();
    serde_json::from_str(line).unwrap_or_else(|e| panic!("not JSON ({e}): {stdout}"))
}

fn check_run(result: &serde_json::Value) {
    assert!(result.get("error").is_none(), "{result}");
    assert_eq!(
        result["errors"].as_array().map(Vec::len),
        Some(0),
        "page errors: {result}"
    );
    let steps: Vec<u64> = result["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let [running, paused_a, paused_b, stepped, resumed] = steps[..] else {
        panic!("{result}")
    };
    assert!(running > 5, "frames advance the simulation: {result}");
    assert_eq!(paused_a, paused_b, "paused means no steps: {result}");
    assert_eq!(stepped, paused_b + 1, "step advances exactly one: {result}");
    assert!(resumed > stepped + 2, "play resumes: {result}");
    let native = native_status("gas", 100);
    let browser = result["hash_100"].as_str().unwrap();
    assert!(
        browser.starts_with(&native),
        "browser {browser:?} vs native {native:?}"
    );
    // The event-driven method (exact hard discs) too.
    let native = native_status("hard-discs", 20);
    let browser = result["hard_20"].as_str().unwrap_or_default();
    assert!(
        browser.starts_with(&native),
        "hard discs: browser {browser:?} vs native {native:?}"
    );
    // Obstacles (a funnel, 375 pegs, bins) too.
    if let Some(browser) = result["galton_300"].as_str() {
        let native = native_status("galton-board", 300);
        assert!(
            browser.starts_with(&native),
            "galton board: browser {browser:?} vs native {native:?}"
        );
    }
    // Rough discs (friction, rolling resistance, spin) too.
    if let Some(browser) = result["repose_2500"].as_str() {
        let native = native_status("angle-of-repose", 2500);
        assert!(
            browser.starts_with(&native),
            "angle of repose: browser {browser:?} vs native {native:?}"
        );
    }
}

/// Counts pixels in a rectangle that differ from the canvas background, and their colours.
fn disc_pixels(png: &Path, x: std::ops::Range<u32>, y: std::ops::Range<u32>) -> (usize, usize) {
    let (differing, colours) = disc_colours(png, x, y);
    (differing, colours.len())
}

/// The pixels in a rectangle that differ from the canvas background, and their colours.
fn disc_colours(
    png: &Path,
    x: std::ops::Range<u32>,
    y: std::ops::Range<u32>,
) -> (usize, std::collections::HashSet<[u8; 3]>) {
    let image = tiny_skia::Pixmap::load_png(png).unwrap();
    let mut colours = std::collections::HashSet::new();
    let mut differing = 0;
    for yy in y.step_by(2) {
        for xx in x.clone().step_by(2) {
            let c = image.pixel(xx, yy).unwrap();
            let rgb = [c.red(), c.green(), c.blue()];
            if rgb != [17, 20, 26] {
                differing += 1;
                colours.insert(rgb);
            }
        }
    }
    (differing, colours)
}

#[test]
fn the_page_runs_the_viewer_on_webgl_with_native_bits() {
    let server = Server::start();
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("webgl.png");
    let result = drive(&server, "webgl", &shot);
    check_run(&result);
    // The panel's method buttons, clicked: the gas restarts as exact hard discs, and back.
    let status = |key: &str| result[key].as_str().unwrap_or_default().to_string();
    let particles = |s: &str| {
        s.split(" particles ")
            .nth(1)
            .map(|t| t.split(' ').next().unwrap().to_string())
    };
    assert!(status("exact").ends_with("method event_driven"), "{result}");
    assert!(
        status("stepped_again").ends_with("method time_stepped"),
        "{result}"
    );
    assert_eq!(
        particles(&status("exact")),
        particles(&status("resumed")),
        "{result}"
    );
    // The simulation canvas sits between the panels: discs on the dark background.
    let (differing, colours) = disc_pixels(&shot, 330..950, 90..700);
    assert!(
        differing > 5_000 && colours > 5,
        "canvas shows {differing} disc pixels in {colours} colours"
    );
}

#[test]
fn without_webgl_the_page_falls_back_to_a_2d_canvas_with_the_same_bits() {
    let server = Server::start();
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("fallback.png");
    let result = drive(&server, "fallback", &shot);
    check_run(&result);
    assert!(result["galton_300"].is_string(), "{result}");
    assert!(result["repose_2500"].is_string(), "{result}");
    // The discs the spout has poured by step 300 each carry an orientation to draw.
    assert!(result["repose_turned"].as_u64().unwrap() > 10, "{result}");
    // The effusion scenario's sink (kind 1), which the page outlines.
    assert_eq!(
        result["effusion_regions"],
        serde_json::json!([1, 70, 0, 80, 40]),
        "{result}"
    );
    // The hourglass's sensor (kind 2), outlined, and its counts as a native run has them.
    assert_eq!(
        result["hourglass_regions"],
        serde_json::json!([2, 4, 4, 36, 38]),
        "{result}"
    );
    let mut hourglass = bounce_scenario::Session::builtin("hourglass").unwrap();
    for _ in 0..600 {
        hourglass.step().unwrap();
    }
    let count = &hourglass.world.sensors()[0];
    assert!(count.entered > 0, "grains came through by step 600");
    assert_eq!(
        result["hourglass_sensed"].as_str(),
        Some(
            format!(
                "lower_bulb: {} inside · {} in · {} out",
                count.inside, count.entered, count.left
            )
            .as_str()
        ),
        "{result}"
    );
    // The impacts it flashes: the contacts that began in the step, as natively.
    let mut gas = bounce_scenario::Session::builtin("gas").unwrap();
    let mut config = gas.world.config().clone();
    config.contact_events = true;
    gas.world.set_config(config).unwrap();
    for _ in 0..20 {
        gas.step().unwrap();
    }
    let begun = (gas.world.contact_events().iter())
        .filter(|e| e.kind == bounce::ContactKind::Begin)
        .count();
    assert!(begun > 0);
    assert_eq!(
        result["gas_flashes"].as_u64(),
        Some(begun as u64),
        "{result}"
    );
    assert_eq!(result["flashing"], serde_json::json!(true), "{result}");
    // Where the shear template's sliding copies stand after 50 steps, as natively; none in
    // walls.
    let mut shear = bounce_scenario::Session::builtin("shear").unwrap();
    for _ in 0..50 {
        shear.step().unwrap();
    }
    let offset = shear.world.lees_edwards_offset().unwrap();
    let (min, max) = shear.world.config().boundary.bounds().unwrap();
    let along = |shift: f64| min[0] + shift.rem_euclid(max[0] - min[0]);
    let marks = [along(offset), max[1], along(-offset), min[1]];
    assert!(offset.abs() > 1.0, "the copies have slid: {offset}");
    let page: Vec<f64> = serde_json::from_value(result["shear_marks"].clone()).unwrap();
    assert_eq!(page, marks, "{result}");
    assert_eq!(result["gas_marks"], serde_json::json!([]), "{result}");
    let (differing, _) = disc_pixels(&shot, 20..880, 60..600);
    assert!(differing > 5_000, "2D canvas shows {differing} disc pixels");
}

#[test]
fn the_fallback_opens_the_scenario_of_the_address_in_its_colours() {
    let server = Server::start();
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("mixing.png");
    let result = drive(&server, "fallback-scenario", &shot);
    assert!(result.get("error").is_none(), "{result}");
    let status = result["status"].as_str().unwrap();
    assert!(status.ends_with("scenario mixing"), "{status}");
    // mixing.toml paints one species red and the other blue.
    let (differing, colours) = disc_colours(&shot, 20..880, 60..600);
    let reddish = colours.iter().filter(|c| c[0] > 150 && c[2] < 100).count();
    let bluish = colours.iter().filter(|c| c[2] > 150 && c[0] < 100).count();
    assert!(
        differing > 5_000 && reddish > 0 && bluish > 0,
        "{differing} disc pixels, {reddish} red and {bluish} blue shades"
    );
}
