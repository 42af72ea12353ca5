//! `bounce view`: the simulation live in a window, with controls, plots and the mouse.
//!
//! The window is eframe/egui on the glow (OpenGL) backend, which runs on Mesa's software
//! renderer where there is no GPU. Discs are rasterised on the CPU into one texture per frame
//! (`canvas`), which keeps 100,000 discs well above 30 frames per second.
//!
//! For tests and CI, [`Options::headless`] renders a fixed number of frames in the real window
//! (under Xvfb), saves a screenshot with a sidecar file locating the canvas and the discs, and
//! closes.

mod app;
pub mod canvas;

pub use app::{Tool, ViewerApp};

use std::path::{Path, PathBuf};
#[cfg(not(target_arch = "wasm32"))]
use std::sync::{Arc, Mutex};

use bounce::World;
use eframe::egui;

/// The scenario shown without one: two streams of discs colliding in a box, coloured, moving
/// from the first frame.
pub const DEMO: &str = include_str!("demo.toml");

/// What `bounce view` was asked to do.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// A scenario file; `None` opens the built-in demo.
    pub scenario: Option<PathBuf>,
    /// Render this many frames, save a screenshot, close.
    pub headless: Option<Headless>,
}

/// A scripted run for tests.
#[derive(Clone, Debug)]
pub struct Headless {
    /// Frames to render before the screenshot.
    pub frames: u32,
    /// PNG to write; `FILE.txt` beside it locates the canvas and the discs.
    pub screenshot: PathBuf,
}

/// Opens the window and runs until it is closed. Errors say why (no display, bad scenario,
/// a screenshot that could not be written).
#[cfg(not(target_arch = "wasm32"))]
pub fn run(options: Options) -> Result<(), String> {
    let scenario = match &options.scenario {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| format!("{}: cannot read the file: {e}", path.display()))?;
            Some((path.display().to_string(), text))
        }
        None => None,
    };
    let result = Arc::new(Mutex::new(Ok(())));
    let headless = options.headless.clone().map(|h| (h, result.clone()));
    // Build the app first, so a bad scenario is reported before any window opens.
    let app = app::ViewerApp::new(scenario, headless)?;
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1280.0, 800.0])
            .with_title("bounce"),
        ..Default::default()
    };
    eframe::run_native("bounce", native, Box::new(|_cc| Ok(Box::new(app)))).map_err(|e| {
        format!("cannot open a window: {e} (is DISPLAY set? headless machines can use xvfb-run)")
    })?;
    let outcome = result
        .lock()
        .map_err(|_| "viewer state poisoned".to_string())?
        .clone();
    if options.headless.is_some()
        && !options
            .headless
            .as_ref()
            .is_some_and(|h| h.screenshot.exists())
    {
        outcome.clone()?;
        return Err("the window closed before the screenshot was taken".into());
    }
    outcome
}

/// Writes the screenshot as PNG and, beside it, `FILE.txt`: the canvas rectangle and up to
/// 1,000 discs (centre and radius), all in screenshot pixels.
#[allow(clippy::too_many_arguments)]
fn save_screenshot(
    image: &egui::ColorImage,
    path: &Path,
    canvas: egui::Rect,
    pixels_per_point: f32,
    world: &World,
    view: Option<&canvas::View>,
    raster: (usize, usize),
) -> Result<(), String> {
    let [w, h] = image.size;
    let rgba: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
    let pixmap = tiny_skia::IntSize::from_wh(w as u32, h as u32)
        .and_then(|size| tiny_skia::Pixmap::from_vec(rgba, size))
        .ok_or("empty screenshot")?;
    pixmap
        .save_png(path)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let ppp = pixels_per_point as f64;
    let (x0, y0) = (canvas.min.x as f64 * ppp, canvas.min.y as f64 * ppp);
    let mut text = format!(
        "canvas {x0} {y0} {} {}\n",
        canvas.max.x as f64 * ppp,
        canvas.max.y as f64 * ppp
    );
    if let Some(view) = view {
        let p = world.particles();
        for i in 0..p.len().min(1000) {
            let [px, py] = view.to_pixel([p.x()[i], p.y()[i]], raster.0, raster.1);
            text.push_str(&format!(
                "disc {} {} {}\n",
                x0 + px,
                y0 + py,
                p.radius()[i] * view.scale
            ));
        }
    }
    let side = path.with_extension("txt");
    std::fs::write(&side, text).map_err(|e| format!("cannot write {}: {e}", side.display()))
}
