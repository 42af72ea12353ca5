//! The viewer application: its state and what one frame does; each panel and input in its
//! own module.

use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use bounce::{Method, World};
use bounce_scenario::{ColorBy, Rgb, Session};
use eframe::egui::{self, TextureHandle};
use web_time::Instant;

use crate::canvas::{Palette, Raster, View};
use crate::{DEMO, Headless};

mod controls;
mod headless;
mod keys;
mod panels;
mod pointer;
#[cfg(test)]
mod tests;

/// Samples kept for the energy and momentum plot.
const HISTORY: usize = 600;

/// The running simulation and the view on it.
pub struct ViewerApp {
    /// The scenario running: world, colours, dt, view; what `r` resets to.
    session: Session,
    running: bool,
    steps_per_frame: u32,
    colour_by: ColorBy,
    palette: Palette,
    /// Each obstacle's colour.
    obstacle_colours: Vec<Rgb>,
    /// What the left mouse button makes.
    tool: Tool,
    /// Where a segment being drawn starts.
    segment_start: Option<[f64; 2]>,
    view: Option<View>,
    raster: Raster,
    texture: Option<TextureHandle>,
    history: VecDeque<[f64; 4]>,
    last_step_ms: f64,
    last_pairs: usize,
    frame_times: VecDeque<f64>,
    last_frame: Option<Instant>,
    spawn_radius: f64,
    drag_start: Option<[f64; 2]>,
    fling: Option<bounce::ParticleId>,
    last_spawn: Option<[f64; 2]>,
    path: String,
    message: String,
    show_help: bool,
    /// Show the structure: |ψ6| and the profiles along y.
    show_structure: bool,
    headless: Option<HeadlessState>,
    /// Screen rectangles of the play/pause and step buttons (for browser tests).
    /// Where the play, step and the two method buttons were last drawn (for tests).
    buttons: [egui::Rect; 4],
}

/// What the left mouse button makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Discs: a click spawns one, a drag lays a moving trail.
    Discs,
    /// A segment obstacle from where a drag starts to where it ends.
    Segment,
    /// A peg (a fixed disc of the spawn radius) where the click is.
    Peg,
}

/// Progress of a `--headless-frames` run.
struct HeadlessState {
    spec: Headless,
    frames: u32,
    started: Instant,
    requested: bool,
    shot: Arc<Mutex<Option<Arc<egui::ColorImage>>>>,
    canvas: egui::Rect,
    pixels_per_point: f32,
    result: Outcome,
}

/// Where a headless run leaves its result for [`crate::run`].
pub type Outcome = Arc<Mutex<Result<(), String>>>;

/// A session of scenario text named by its path: `[[file]]` tables are read beside it.
fn open_session(name: &str, text: &str) -> Result<Session, bounce_scenario::ScenarioError> {
    let dir = std::path::Path::new(name).parent();
    Session::from_text_in(name, text, &bounce_scenario::Limits::default(), dir)
}

impl ViewerApp {
    /// The app for a scenario (or the built-in demo).
    pub fn new(
        scenario: Option<(String, String)>,
        headless: Option<(Headless, Outcome)>,
    ) -> Result<Self, String> {
        let (name, text) = scenario.unwrap_or_else(|| ("built-in demo".into(), DEMO.into()));
        let session = open_session(&name, &text).map_err(|e| e.to_string())?;
        let colour_by = session.colour_by;
        let palette = Palette::for_world(&session.world, colour_by, session.colours.clone());
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let mut app = ViewerApp {
            session,
            running: true,
            steps_per_frame: 1,
            colour_by,
            palette,
            obstacle_colours: Vec::new(),
            tool: Tool::Discs,
            segment_start: None,
            view: None,
            raster: Raster::new(1, 1),
            texture: None,
            history: VecDeque::new(),
            last_step_ms: 0.0,
            last_pairs: 0,
            frame_times: VecDeque::new(),
            last_frame: None,
            spawn_radius: 0.5,
            drag_start: None,
            fling: None,
            last_spawn: None,
            path: String::new(),
            message: String::new(),
            show_help: false,
            show_structure: false,
            buttons: [egui::Rect::NOTHING; 4],
            headless: headless.map(|(spec, result)| HeadlessState {
                spec,
                frames: 0,
                started: Instant::now(),
                requested: false,
                shot: Arc::new(Mutex::new(None)),
                canvas: egui::Rect::NOTHING,
                pixels_per_point: 1.0,
                result,
            }),
        };
        app.session
            .world
            .set_threads(threads)
            .map_err(|e| e.to_string())?;
        app.spawn_radius = app.typical_radius();
        app.obstacle_colours = app.session.obstacle_colours();
        Ok(app)
    }

    fn typical_radius(&self) -> f64 {
        let r = self.session.world.particles().radius();
        if r.is_empty() {
            0.5
        } else {
            r.iter().sum::<f64>() / r.len() as f64
        }
    }

    /// Replaces the simulation with a scenario text.
    fn open(&mut self, name: String, text: String) {
        match open_session(&name, &text) {
            Ok(session) => {
                let threads = self.session.world.threads();
                self.session = session;
                let _ = self.session.world.set_threads(threads);
                self.colour_by = self.session.colour_by;
                self.after_reload();
                self.message = format!("opened {}", self.session.origin);
            }
            Err(e) => self.message = e.to_string(),
        }
    }

    fn after_reload(&mut self) {
        self.palette = Palette::for_world(
            &self.session.world,
            self.colour_by,
            self.session.colours.clone(),
        );
        self.view = None;
        self.history.clear();
        self.spawn_radius = self.typical_radius();
        self.obstacle_colours = self.session.obstacle_colours();
    }

    /// The scene from its start under `method` (see `Session::restart_with_method`).
    fn switch_method(&mut self, method: Method) {
        self.message = match self.session.restart_with_method(method) {
            Ok(()) => format!("restarted {:?}", method),
            Err(e) => e,
        };
        self.colour_by = self.session.colour_by;
        self.after_reload();
    }

    fn reset(&mut self) {
        self.message = match self.session.reset() {
            Ok(()) => "reset".into(),
            Err(e) => e.to_string(),
        };
        self.colour_by = self.session.colour_by;
        self.after_reload();
    }

    fn step(&mut self) {
        let start = Instant::now();
        let mut pairs = 0;
        for _ in 0..self.steps_per_frame {
            match self.session.step() {
                Ok(stats) => {
                    pairs += stats.pairs;
                    // Discs an emitter added take its colour.
                    if stats.emitted > 0 {
                        self.palette.colours.clone_from(&self.session.colours);
                    }
                }
                Err(e) => {
                    self.message = e.to_string();
                    self.running = false;
                    break;
                }
            }
        }
        self.last_step_ms = start.elapsed().as_secs_f64() * 1e3 / self.steps_per_frame as f64;
        self.last_pairs = pairs / self.steps_per_frame as usize;
        self.record();
    }

    fn record(&mut self) {
        let s = self.session.world.stats();
        self.history.push_back([
            self.session.world.time(),
            s.kinetic_energy,
            s.momentum[0],
            s.momentum[1],
        ]);
        while self.history.len() > HISTORY {
            self.history.pop_front();
        }
    }

    fn save_checkpoint(&mut self) {
        let path = self.path_or("checkpoint.bin");
        self.message = match save_checkpoint(&self.session.world, &path) {
            Ok(()) => format!("saved {}", path.display()),
            Err(e) => format!("cannot save {}: {e}", path.display()),
        };
    }

    fn load_checkpoint(&mut self) {
        let path = self.path_or("checkpoint.bin");
        match bounce_scenario::checkpoint::load(&path) {
            Ok(bounce_scenario::checkpoint::Checkpoint { world, .. }) => {
                // Unchecked against the scenario: the saved world may have been edited
                // here (discs and pegs added with the mouse).
                self.session.adopt(world);
                self.after_reload();
                self.message = format!("loaded {}", path.display());
            }
            Err(e) => self.message = e,
        }
    }

    fn open_path(&mut self) {
        let path = self.path_or("scenario.toml");
        match std::fs::read_to_string(&path) {
            Ok(text) => self.open(path.display().to_string(), text),
            Err(e) => self.message = format!("cannot read {}: {e}", path.display()),
        }
    }

    fn path_or(&self, default: &str) -> PathBuf {
        PathBuf::from(if self.path.trim().is_empty() {
            default
        } else {
            self.path.trim()
        })
    }

    /// A scenario file dropped on the window. (In the browser the page reads dropped files
    /// and calls [`ViewerApp::open_text`], since reading a file there is asynchronous.)
    #[cfg(not(target_arch = "wasm32"))]
    fn dropped(&mut self, ctx: &egui::Context) {
        let files = ctx.input(|i| i.raw.dropped_files.clone());
        for file in files {
            let name = file.path().display().to_string();
            match file
                .bytes()
                .and_then(|b| String::from_utf8(b).map_err(|e| e.to_string()))
            {
                Ok(text) => self.open(name, text),
                Err(e) => self.message = format!("cannot read {name}: {e}"),
            }
        }
    }

    #[cfg(target_arch = "wasm32")]
    fn dropped(&mut self, _ctx: &egui::Context) {}

    /// Opens scenario text (e.g. a file dropped on the page).
    pub fn open_text(&mut self, name: &str, text: &str) -> Result<(), String> {
        let session = Session::from_text(name, text).map_err(|e| e.to_string())?;
        let threads = self.session.world.threads();
        self.session = session;
        let _ = self.session.world.set_threads(threads);
        self.colour_by = self.session.colour_by;
        self.after_reload();
        self.message = format!("opened {name}");
        Ok(())
    }
}

impl eframe::App for ViewerApp {
    #[cfg(target_arch = "wasm32")]
    fn as_any_mut(&mut self) -> Option<&mut dyn std::any::Any> {
        Some(&mut *self)
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        let now = Instant::now();
        if let Some(last) = self.last_frame {
            self.frame_times.push_back((now - last).as_secs_f64());
            while self.frame_times.len() > 60 {
                self.frame_times.pop_front();
            }
        }
        self.last_frame = Some(now);
        self.keyboard(&ctx);
        self.dropped(&ctx);
        if self.running {
            self.step();
        }
        egui::Panel::left("controls")
            .resizable(false)
            .default_size(270.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.controls(ui));
            });
        egui::Panel::right("stats")
            .resizable(false)
            .default_size(300.0)
            .show(ui, |ui| self.panels(ui));
        egui::CentralPanel::default().show(ui, |ui| self.canvas(ui));
        self.help(&ctx);
        self.headless_frame(&ctx);
        if self.running {
            ctx.request_repaint();
        }
    }
}

/// Writes a checkpoint whole or not at all, as the CLI does.
#[cfg(not(target_arch = "wasm32"))]
fn save_checkpoint(world: &World, path: &std::path::Path) -> Result<(), String> {
    bounce_scenario::checkpoint::save(world, None, path)
}

/// The browser has no files to write.
#[cfg(target_arch = "wasm32")]
fn save_checkpoint(_world: &World, _path: &std::path::Path) -> Result<(), String> {
    Err("no file system in the browser".into())
}
