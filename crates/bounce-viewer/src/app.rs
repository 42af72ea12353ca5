//! The viewer application: state, controls, mouse and keyboard, panels.

use std::collections::VecDeque;
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use bounce::{
    MassModel, Method, Obstacle, Particle, RestingContacts, RestitutionModel, VelocityUpdate, World,
};
use bounce_scenario::{ColorBy, Rgb, Session};
use eframe::egui::{self, Color32, PointerButton, Sense, TextureHandle, TextureOptions};
use egui_plot::{Bar, BarChart, Legend, Line, Plot, PlotPoints};
use web_time::Instant;

use crate::canvas::{Palette, Raster, View};
use crate::{DEMO, Headless};

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

    fn controls(&mut self, ui: &mut egui::Ui) {
        ui.heading("bounce");
        ui.label(&self.session.title);
        ui.horizontal(|ui| {
            let play = ui.button(if self.running { "pause" } else { "play" });
            if play.clicked() {
                self.running = !self.running;
            }
            let step = ui.button("step");
            if step.clicked() {
                self.step();
            }
            (self.buttons[0], self.buttons[1]) = (play.rect, step.rect);
            if ui.button("reset").clicked() {
                self.reset();
            }
        });
        egui::ComboBox::from_label("built-in")
            .selected_text("open…")
            .show_ui(ui, |ui| {
                for (name, text) in bounce_scenario::TEMPLATES {
                    // A million discs is for the command line, not an interactive frame rate.
                    if name != "million" && ui.selectable_label(false, name).clicked() {
                        self.open(name.to_string(), text.to_string());
                    }
                }
            });
        ui.add(slider(&mut self.steps_per_frame, 1..=20).text("steps / frame"));
        ui.separator();
        ui.label("collision model");
        let mut config = self.session.world.config().clone();
        let before = config.clone();
        ui.add(
            slider(&mut config.collision_radius_scale, 0.5..=2.0).text("collision_radius_scale"),
        );
        ui.add(slider(&mut config.coefficient_of_restitution, 0.0..=1.0).text("restitution"));
        ui.add(slider(&mut config.gravity[0], -20.0..=20.0).text("gravity x"));
        ui.add(slider(&mut config.gravity[1], -20.0..=20.0).text("gravity y"));
        ui.add(
            slider(&mut self.session.dt, 0.0005..=0.05)
                .logarithmic(true)
                .text("dt"),
        );
        // The method restarts the scene: exact hard discs cannot start from the overlaps
        // the time-stepped loop leaves.
        let mut method = config.method;
        ui.horizontal(|ui| {
            ui.label("method");
            let stepped = ui.radio_value(&mut method, Method::TimeStepped, "time-stepped");
            let exact = ui.radio_value(&mut method, Method::EventDriven, "event-driven (exact)");
            (self.buttons[2], self.buttons[3]) = (stepped.rect, exact.rect);
        });
        if method != config.method {
            self.switch_method(method);
            return;
        }
        ui.add(slider(&mut config.substeps, 1..=16).text("substeps"));
        ui.add(slider(&mut config.solver_iterations, 1..=16).text("solver passes"));
        let mut adaptive = config.max_travel.is_some();
        ui.checkbox(&mut adaptive, "adaptive substeps (no tunnelling)");
        if adaptive {
            let mut travel = config.max_travel.unwrap_or(0.5);
            ui.add(
                slider(&mut travel, 0.05..=2.0)
                    .logarithmic(true)
                    .text("max travel / r_min"),
            );
            config.max_travel = Some(travel);
        } else {
            config.max_travel = None;
        }
        ui.label("model options");
        egui::ComboBox::from_label("mass")
            .selected_text(format!("{:?}", config.mass_model))
            .show_ui(ui, |ui| {
                ui.selectable_value(
                    &mut config.mass_model,
                    MassModel::Radius,
                    "mass = radius (default)",
                );
                ui.selectable_value(&mut config.mass_model, MassModel::Area, "area");
                ui.selectable_value(
                    &mut config.mass_model,
                    MassModel::PerParticle,
                    "per particle",
                );
            });
        let mut newton = config.restitution_model == RestitutionModel::RelativeNormalVelocity;
        ui.checkbox(&mut newton, "momentum-conserving restitution");
        config.restitution_model = if newton {
            RestitutionModel::RelativeNormalVelocity
        } else {
            RestitutionModel::ScaleEachNormalVelocity
        };
        let mut approaching = config.velocity_update == VelocityUpdate::ApproachingOnly;
        ui.checkbox(&mut approaching, "update approaching pairs only");
        config.velocity_update = if approaching {
            VelocityUpdate::ApproachingOnly
        } else {
            VelocityUpdate::AllDetected
        };
        let mut rest = config.resting_contacts == RestingContacts::Rest;
        ui.checkbox(&mut rest, "resting contacts rest (no g·h jitter)");
        config.resting_contacts = if rest {
            RestingContacts::Rest
        } else {
            RestingContacts::Bounce
        };
        ui.checkbox(&mut config.contact_events, "flash impacts (contact events)");
        ui.label("rough discs (friction turns them)");
        ui.add(slider(&mut config.friction, 0.0..=1.0).text("friction"));
        ui.add(
            slider(&mut config.tangential_restitution, -1.0..=1.0).text("tangential restitution"),
        );
        ui.add(slider(&mut config.rolling_resistance, 0.0..=0.5).text("rolling resistance"));
        if config != before
            && let Err(e) = self.session.world.set_config(config)
        {
            self.message = e.to_string();
        }
        ui.separator();
        ui.label("colour by");
        let old = self.colour_by;
        ui.horizontal(|ui| {
            ui.radio_value(&mut self.colour_by, ColorBy::Speed, "speed");
            ui.radio_value(&mut self.colour_by, ColorBy::Radius, "radius");
            ui.radio_value(&mut self.colour_by, ColorBy::Color, "scenario");
            ui.radio_value(&mut self.colour_by, ColorBy::Spin, "spin");
        });
        if old != self.colour_by {
            self.palette = Palette::for_world(
                &self.session.world,
                self.colour_by,
                self.session.colours.clone(),
            );
        }
        ui.add(
            slider(&mut self.spawn_radius, 0.05..=5.0)
                .logarithmic(true)
                .text("spawn radius"),
        );
        ui.horizontal(|ui| {
            ui.label("left button:");
            ui.radio_value(&mut self.tool, Tool::Discs, "discs");
            ui.radio_value(&mut self.tool, Tool::Segment, "segment");
            ui.radio_value(&mut self.tool, Tool::Peg, "peg");
        });
        ui.separator();
        ui.label("file (scenario or checkpoint)");
        ui.text_edit_singleline(&mut self.path);
        ui.horizontal(|ui| {
            if ui.button("open scenario").clicked() {
                self.open_path();
            }
        });
        ui.horizontal(|ui| {
            if ui.button("save checkpoint").clicked() {
                self.save_checkpoint();
            }
            if ui.button("load checkpoint").clicked() {
                self.load_checkpoint();
            }
        });
        if !self.message.is_empty() {
            ui.separator();
            ui.label(&self.message);
        }
        ui.separator();
        ui.small("space: pause · . : step · r: reset · h: help");
    }

    fn panels(&mut self, ui: &mut egui::Ui) {
        let fps = self.fps();
        egui::Grid::new("numbers").num_columns(2).show(ui, |ui| {
            ui.label("frames / s");
            ui.label(format!("{fps:.1}"));
            ui.end_row();
            ui.label("step time");
            ui.label(format!("{:.2} ms", self.last_step_ms));
            ui.end_row();
            ui.label("particles");
            ui.label(self.session.world.len().to_string());
            ui.end_row();
            ui.label("colliding pairs / step");
            ui.label(self.last_pairs.to_string());
            ui.end_row();
            ui.label("step");
            ui.label(self.session.world.step_count().to_string());
            ui.end_row();
            ui.label("time");
            ui.label(format!("{:.3}", self.session.world.time()));
            ui.end_row();
            let stats = self.session.world.stats();
            ui.label("pressure");
            ui.label(
                stats
                    .pressure
                    .map_or("– (open)".into(), |p| format!("{p:.4}")),
            );
            ui.end_row();
            ui.label("substeps");
            ui.label(stats.substeps.to_string());
            ui.end_row();
            ui.label("state hash");
            ui.monospace(format!("{:016x}", self.session.world.state_hash()));
            ui.end_row();
            let world = &self.session.world;
            if let (bounce::Boundary::LeesEdwards { shear_rate, .. }, Some(offset)) =
                (&world.config().boundary, world.lees_edwards_offset())
            {
                ui.label("shear (Lees–Edwards)");
                ui.label(format!("γ̇ = {shear_rate} · images at {offset:+.3}"));
                ui.end_row();
            }
            if world.config().contact_events {
                ui.label("contacts begun / step");
                let begun = (world.contact_events().iter())
                    .filter(|e| e.kind == bounce::ContactKind::Begin)
                    .count();
                ui.label(begun.to_string());
                ui.end_row();
            }
            for (sensor, count) in world.config().sensors.iter().zip(world.sensors()) {
                ui.label(format!("sensor {}", sensor.name));
                ui.label(format!(
                    "{} inside · {} in · {} out",
                    count.inside, count.entered, count.left
                ));
                ui.end_row();
            }
        });
        ui.separator();
        ui.label("kinetic energy and |momentum|");
        let energy: PlotPoints = self.history.iter().map(|h| [h[0], h[1]]).collect();
        let momentum: PlotPoints = self
            .history
            .iter()
            .map(|h| [h[0], h[2].hypot(h[3])])
            .collect();
        Plot::new("energy")
            .height(150.0)
            .legend(Legend::default())
            .allow_scroll(false)
            .show(ui, |plot| {
                plot.line(Line::new("kinetic energy", energy));
                plot.line(Line::new("|momentum|", momentum));
            });
        ui.separator();
        ui.checkbox(
            &mut self.show_structure,
            "structure: |ψ6| and profiles along y",
        );
        if self.show_structure {
            self.structure(ui);
        }
        ui.separator();
        // Speeds under gravity are no single Maxwell–Boltzmann distribution: the curve
        // would mislead there, so only the histogram is drawn. In a sheared box the speeds
        // are relative to the flow (`analysis::speed_histogram`), which the curve fits.
        let config = self.session.world.config();
        let no_curve = config.gravity != [0.0, 0.0];
        if no_curve {
            ui.label("speeds (no Maxwell–Boltzmann curve under gravity)");
        } else if config.boundary.is_sheared() {
            ui.label("speeds relative to the shear flow vs 2D Maxwell–Boltzmann");
        } else {
            ui.label("speeds vs 2D Maxwell–Boltzmann");
        }
        let (bars, curve) = self.speed_histogram();
        Plot::new("speeds")
            .height(170.0)
            .legend(Legend::default())
            .allow_scroll(false)
            .show(ui, |plot| {
                plot.bar_chart(
                    BarChart::new("simulation", bars).color(Color32::from_rgb(120, 160, 220)),
                );
                if !no_curve {
                    plot.line(Line::new("Maxwell–Boltzmann", curve).color(Color32::RED));
                }
            });
    }

    /// The bond order and, in a box, the density and temperature profiles along y (each
    /// scaled by its mean, so both read against 1).
    fn structure(&self, ui: &mut egui::Ui) {
        let (order, profile) = structure_of(&self.session.world);
        ui.label(format!("global bond order |ψ6| = {order:.3}"));
        let Some(p) = profile else {
            ui.label("profiles need a box (walls or periodic)");
            return;
        };
        let relative = |values: &[f64]| -> PlotPoints<'static> {
            let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
            let scale = if mean > 0.0 { 1.0 / mean } else { 0.0 };
            (p.centre.iter().zip(values))
                .map(|(&y, &v)| [y, v * scale])
                .collect()
        };
        Plot::new("profiles")
            .height(150.0)
            .legend(Legend::default())
            .allow_scroll(false)
            .show(ui, |plot| {
                plot.line(Line::new("density / mean", relative(&p.density)));
                plot.line(Line::new("temperature / mean", relative(&p.temperature)));
            });
    }

    fn speed_histogram(&self) -> (Vec<Bar>, PlotPoints<'static>) {
        let total_mass = bounce_scenario::analysis::total_mass(&self.session.world);
        let h = bounce_scenario::analysis::speed_histogram(&self.session.world, 30, total_mass);
        let bars = h
            .density
            .iter()
            .enumerate()
            .map(|(k, &d)| Bar::new((k as f64 + 0.5) * h.width, d).width(h.width))
            .collect();
        (bars, PlotPoints::from(h.curve))
    }

    /// The picture and its mouse handling.
    fn canvas(&mut self, ui: &mut egui::Ui) {
        let size = ui.available_size();
        let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point();
        let (w, h) = (
            ((rect.width() * ppp).round() as usize).max(1),
            ((rect.height() * ppp).round() as usize).max(1),
        );
        if self.raster.width != w || self.raster.height != h {
            self.raster = Raster::new(w, h);
        }
        let view = *self
            .view
            .get_or_insert_with(|| View::fit(self.session.view.0, self.session.view.1, w, h));
        self.handle_mouse(ui, &response, rect, ppp, w, h);
        let view = self.view.unwrap_or(view);
        self.raster.draw(
            &self.session.world,
            &view,
            &self.palette,
            &self.obstacle_colours,
        );
        let image = egui::ColorImage::from_rgba_unmultiplied([w, h], &self.raster.pixels);
        match &mut self.texture {
            Some(t) => t.set(image, TextureOptions::NEAREST),
            None => {
                self.texture = Some(ui.ctx().load_texture(
                    "bounce",
                    image,
                    TextureOptions::NEAREST,
                ));
            }
        }
        if let Some(t) = &self.texture {
            ui.painter().image(
                t.id(),
                rect,
                egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                Color32::WHITE,
            );
        }
        // A segment being drawn: from its start to the cursor.
        if let (Some(start), Some(pos)) = (self.segment_start, response.hover_pos()) {
            let [x, y] = view.to_pixel(start, w, h);
            let from = egui::pos2(rect.min.x + x as f32 / ppp, rect.min.y + y as f32 / ppp);
            ui.painter().line_segment(
                [from, pos],
                egui::Stroke::new(2.0, Color32::from_rgb(170, 176, 190)),
            );
        }
        if let Some(state) = &mut self.headless {
            state.canvas = rect;
            state.pixels_per_point = ppp;
        }
    }

    fn handle_mouse(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        rect: egui::Rect,
        ppp: f32,
        w: usize,
        h: usize,
    ) {
        let Some(view) = self.view.as_mut() else {
            return;
        };
        let to_px = |pos: egui::Pos2| {
            [
                ((pos.x - rect.min.x) * ppp) as f64,
                ((pos.y - rect.min.y) * ppp) as f64,
            ]
        };
        // Scroll zooms about the cursor.
        if let Some(pos) = response.hover_pos() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                view.zoom_at(to_px(pos), (scroll as f64 / 200.0).exp(), w, h);
            }
        }
        // Middle drag pans.
        if response.dragged_by(PointerButton::Middle) {
            let d = response.drag_delta() * ppp;
            view.centre[0] -= d.x as f64 / view.scale;
            view.centre[1] += d.y as f64 / view.scale;
        }
        let view = *view;
        let Some(pos) = response.interact_pointer_pos() else {
            if !response.dragged() {
                self.drag_start = None;
                self.fling = None;
                self.last_spawn = None;
            }
            return;
        };
        let world_pos = view.to_world(to_px(pos), w, h);
        match self.tool {
            Tool::Discs => {}
            Tool::Peg => {
                if response.clicked_by(PointerButton::Primary) {
                    self.add_obstacle(Obstacle::peg(world_pos, self.spawn_radius));
                }
            }
            Tool::Segment => {
                if response.drag_started_by(PointerButton::Primary) {
                    self.segment_start = Some(world_pos);
                }
                if response.drag_stopped_by(PointerButton::Primary)
                    && let Some(start) = self.segment_start.take()
                    && start != world_pos
                {
                    self.add_obstacle(Obstacle::segment(start, world_pos));
                }
            }
        }
        // Left: click spawns one disc; dragging lays a trail moving with the drag.
        if self.tool != Tool::Discs {
            // The left button draws obstacles.
        } else if response.clicked_by(PointerButton::Primary) {
            self.spawn(world_pos, [0.0, 0.0]);
        } else if response.dragged_by(PointerButton::Primary) {
            let far_enough = self.last_spawn.is_none_or(|last| {
                (last[0] - world_pos[0]).hypot(last[1] - world_pos[1]) >= 2.2 * self.spawn_radius
            });
            if far_enough {
                let d = response.drag_delta() * ppp;
                let v = [
                    d.x as f64 / view.scale / self.session.dt.max(1e-9) * 0.1,
                    -d.y as f64 / view.scale / self.session.dt.max(1e-9) * 0.1,
                ];
                self.spawn(world_pos, v);
                self.last_spawn = Some(world_pos);
            }
        }
        // Right drag: fling the disc under the press, or push everything around the cursor.
        if response.drag_started_by(PointerButton::Secondary) {
            self.drag_start = Some(world_pos);
            self.fling = self.session.world.particle_at(world_pos);
        }
        if response.dragged_by(PointerButton::Secondary) && self.fling.is_none() {
            let d = response.drag_delta() * ppp;
            let dv = [
                d.x as f64 / view.scale * 2.0,
                -d.y as f64 / view.scale * 2.0,
            ];
            let reach = 40.0 / view.scale;
            self.session.world.push_region(world_pos, reach, dv);
        }
        if response.drag_stopped_by(PointerButton::Secondary) {
            if let (Some(id), Some(start)) = (self.fling, self.drag_start) {
                let v = [
                    (world_pos[0] - start[0]) * 3.0,
                    (world_pos[1] - start[1]) * 3.0,
                ];
                if let Err(e) = self.session.world.set_velocity(id, v) {
                    self.message = e.to_string();
                }
            }
            self.fling = None;
            self.drag_start = None;
        }
    }

    /// Adds an obstacle drawn with the mouse (grey).
    pub fn add_obstacle(&mut self, obstacle: Obstacle) {
        match self.session.world.add_obstacles([obstacle]) {
            Ok(()) => self.obstacle_colours.push(bounce_scenario::OBSTACLE_GREY),
            Err(e) => self.message = format!("cannot add that obstacle: {e}"),
        }
    }

    /// The obstacles in the world now.
    pub fn obstacle_count(&self) -> usize {
        self.session.world.config().obstacles.len()
    }

    fn spawn(&mut self, at: [f64; 2], velocity: [f64; 2]) {
        let r = self.spawn_radius;
        match self
            .session
            .world
            .add_particle(Particle::new(at, velocity, r))
        {
            Ok(_) => self.session.colours.push(Some([240, 240, 240])),
            Err(e) => self.message = format!("cannot place a disc there: {e}"),
        }
        self.palette.colours = self.session.colours.clone();
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

    /// `step N hash H particles P running B fps F` for tests and the page.
    pub fn status(&self) -> String {
        format!(
            "step {} hash {:016x} particles {} running {} fps {:.1} method {}",
            self.session.world.step_count(),
            self.session.world.state_hash(),
            self.session.world.len(),
            self.running,
            self.fps(),
            match self.session.world.config().method {
                Method::TimeStepped => "time_stepped",
                Method::EventDriven => "event_driven",
            }
        )
    }

    /// Frames per second over the last 60 frames.
    fn fps(&self) -> f64 {
        if self.frame_times.len() > 1 {
            let total: f64 = self.frame_times.iter().sum();
            self.frame_times.len() as f64 / total.max(1e-9)
        } else {
            0.0
        }
    }

    /// Opens a built-in scenario by name.
    pub fn open_builtin(&mut self, name: &str) -> Result<(), String> {
        let text =
            bounce_scenario::template(name).ok_or(format!("no built-in scenario {name:?}"))?;
        self.open_text(name, text)
    }

    /// Pauses and steps until step `target` (for tests comparing with a native run).
    pub fn run_to(&mut self, target: u64) {
        self.running = false;
        let per_frame = self.steps_per_frame;
        self.steps_per_frame = 1;
        let _ = self.session.run_until(target, |_, _| {
            Ok::<_, bounce::StepError>(ControlFlow::Continue(()))
        });
        self.steps_per_frame = per_frame;
        self.record();
    }

    /// `play X Y step X Y time_stepped X Y event_driven X Y`: centres of the play/pause and
    /// step buttons and of the two method buttons in points (CSS pixels in the browser), for
    /// tests that click them.
    pub fn button_centres(&self) -> String {
        let [play, step, stepped, exact] = self.buttons.map(|r| r.center());
        format!(
            "play {} {} step {} {} time_stepped {} {} event_driven {} {}",
            play.x, play.y, step.x, step.y, stepped.x, stepped.y, exact.x, exact.y
        )
    }

    /// Play (true) or pause.
    pub fn set_running(&mut self, running: bool) {
        self.running = running;
    }

    fn keyboard(&mut self, ctx: &egui::Context) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let (space, dot, r, help) = ctx.input(|i| {
            (
                i.key_pressed(egui::Key::Space),
                i.key_pressed(egui::Key::Period),
                i.key_pressed(egui::Key::R),
                i.key_pressed(egui::Key::H) || i.key_pressed(egui::Key::Questionmark),
            )
        });
        if space {
            self.running = !self.running;
        }
        if dot {
            self.step();
        }
        if r {
            self.reset();
        }
        if help {
            self.show_help = !self.show_help;
        }
    }

    fn help(&mut self, ctx: &egui::Context) {
        let mut open = self.show_help;
        egui::Window::new("help")
            .open(&mut open)
            .collapsible(false)
            .show(ctx, |ui| {
                egui::Grid::new("keys").num_columns(2).show(ui, |ui| {
                    for (key, what) in [
                        ("space", "play / pause"),
                        (".", "one step"),
                        ("r", "reset to the scenario"),
                        ("h or ?", "this help"),
                        (
                            "left click / drag",
                            "spawn discs (a drag gives them its velocity); with the segment \
                             tool a drag draws a wall, with the peg tool a click drops a peg",
                        ),
                        ("right drag on a disc", "fling it"),
                        ("right drag elsewhere", "push the discs around the cursor"),
                        ("scroll", "zoom about the cursor"),
                        ("middle drag", "pan"),
                    ] {
                        ui.monospace(key);
                        ui.label(what);
                        ui.end_row();
                    }
                });
            });
        self.show_help = open;
    }

    /// Headless runs count frames, then take and save a screenshot and close.
    fn headless_frame(&mut self, ctx: &egui::Context) {
        let Some(state) = &mut self.headless else {
            return;
        };
        state.frames += 1;
        ctx.request_repaint();
        if state.frames >= state.spec.frames && !state.requested {
            state.requested = true;
            let slot = state.shot.clone();
            let repaint = ctx.clone();
            ctx.request_screenshot(move |image| {
                *slot.lock().expect("screenshot slot") = Some(image);
                repaint.request_repaint();
            });
        }
        let shot = state.shot.lock().expect("screenshot slot").take();
        if let Some(image) = shot {
            let seconds = state.started.elapsed().as_secs_f64();
            let result = crate::save_screenshot(
                &image,
                &state.spec.screenshot,
                state.canvas,
                state.pixels_per_point,
                &self.session.world,
                self.view.as_ref(),
                (self.raster.width, self.raster.height),
            );
            println!(
                "rendered {} frames of {} particles in {seconds:.2} s: {:.1} frames/s (last step {:.2} ms)",
                state.frames,
                self.session.world.len(),
                state.frames as f64 / seconds.max(1e-9),
                self.last_step_ms
            );
            *state.result.lock().expect("result slot") = result;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
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

/// A slider that changes only what it edits: a scenario's value outside the slider's range
/// (a `dt` of 0.1, 32 substeps) stays as the file has it instead of being clamped the
/// first time the panel is drawn.
fn slider<'a, N: egui::emath::Numeric>(
    value: &'a mut N,
    range: std::ops::RangeInclusive<N>,
) -> egui::Slider<'a> {
    egui::Slider::new(value, range).clamping(egui::SliderClamping::Edits)
}

/// The world's global bond order |ψ6| now and, in a box, its profiles along y in 20 bins
/// (what the structure panel shows).
fn structure_of(world: &bounce::World) -> (f64, Option<bounce_scenario::observables::Profile>) {
    use bounce_scenario::observables::{Axis, profile};
    use bounce_scenario::structure::{Snapshot, psi6};
    let order = psi6(&Snapshot::of(world));
    (order, profile(world, Axis::Y, 20).ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn app(name: &str) -> ViewerApp {
        let text = bounce_scenario::template(name).unwrap();
        ViewerApp::new(Some((name.into(), text.into())), None).unwrap()
    }

    fn step_of(status: &str) -> u64 {
        status.split_whitespace().nth(1).unwrap().parse().unwrap()
    }

    #[test]
    fn run_to_pauses_and_reaches_the_step_with_native_bits() {
        let mut a = app("gas");
        a.run_to(25);
        assert!(!a.running);
        let status = a.status();
        assert_eq!(step_of(&status), 25);
        // The same scenario stepped directly gives the same hash.
        let text = bounce_scenario::template("gas").unwrap();
        let scenario = bounce_scenario::parse(text, "gas").unwrap();
        let mut world = scenario.build(text, "gas").unwrap().world;
        for _ in 0..25 {
            world.step(scenario.time.dt).unwrap();
        }
        assert!(
            status.contains(&format!("{:016x}", world.state_hash())),
            "{status}"
        );
    }

    #[test]
    fn checkpoints_save_and_load_through_the_path_field() {
        let dir = std::env::temp_dir().join(format!("bounce-viewer-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("c.bin");
        let mut a = app("mixing");
        a.run_to(10);
        a.path = file.display().to_string();
        a.save_checkpoint();
        assert!(a.message.starts_with("saved"), "{}", a.message);
        let saved = a.status();
        a.run_to(20);
        a.load_checkpoint();
        assert!(a.message.starts_with("loaded"), "{}", a.message);
        assert_eq!(
            a.status().replace("running false", ""),
            saved.replace("running false", "")
        );
        a.path = dir.join("missing.bin").display().to_string();
        a.load_checkpoint();
        assert!(a.message.contains("cannot read"), "{}", a.message);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn opening_and_resetting_scenarios() {
        let mut a = app("gas");
        a.run_to(5);
        assert!(a.open_text("bad.toml", "[world]\n").is_err());
        assert_eq!(step_of(&a.status()), 5, "a bad file leaves the world alone");
        a.open_builtin("newtons-cradle").unwrap();
        assert!(a.status().contains("particles 6"), "{}", a.status());
        assert!(a.open_builtin("nope").is_err());
        a.run_to(3);
        a.reset();
        assert_eq!(step_of(&a.status()), 0);
    }

    #[test]
    fn the_structure_panel_reads_a_crystal_and_a_fluid() {
        // The hard-discs template starts on a triangular lattice and melts.
        let mut a = app("hard-discs");
        let (crystal, profile) = structure_of(&a.session.world);
        assert!(crystal > 0.9, "{crystal}");
        let profile = profile.unwrap();
        assert_eq!(profile.count.iter().sum::<u64>(), 2000);
        a.run_to(100);
        let (fluid, _) = structure_of(&a.session.world);
        assert!(fluid < 0.2, "{fluid}");
        // The panel draws with it on.
        a.show_structure = true;
        let ctx = egui::Context::default();
        let output = ctx.run_ui(egui::RawInput::default(), |ui| a.panels(ui));
        output.drop_without_applying_deltas();
        // An open world has no profiles.
        let mut open = bounce::World::new(bounce::Config::default()).unwrap();
        for x in [0.0, 3.0] {
            open.add_particle(bounce::Particle::new([x, 0.0], [0.0, 0.0], 1.0))
                .unwrap();
        }
        assert!(structure_of(&open).1.is_none());
    }

    #[test]
    fn drawing_the_controls_leaves_a_scenarios_values_alone() {
        // The hard-discs template observes every 0.1, beyond the dt slider's 0.05.
        let mut a = app("hard-discs");
        let (dt, config) = (a.session.dt, a.session.world.config().clone());
        let ctx = egui::Context::default();
        for _ in 0..2 {
            let output = ctx.run_ui(egui::RawInput::default(), |ui| a.controls(ui));
            output.drop_without_applying_deltas();
        }
        assert_eq!(a.session.dt, 0.1);
        assert_eq!((a.session.dt, a.session.world.config()), (dt, &config));
    }

    #[test]
    fn the_method_switch_restarts_the_gas_event_driven_and_back() {
        let mut a = app("gas");
        a.run_to(5);
        a.switch_method(Method::EventDriven);
        assert_eq!(a.session.world.config().method, Method::EventDriven);
        assert_eq!(step_of(&a.status()), 0, "{}", a.message);
        let count = a.session.world.len();
        a.run_to(30);
        assert!(a.session.world.stats().collisions > 0, "{}", a.message);
        assert_eq!(a.session.world.len(), count);
        a.switch_method(Method::TimeStepped);
        assert_eq!(a.session.world.config().method, Method::TimeStepped);
        // A scene the method cannot run says why and keeps the world it had.
        a.open_builtin("pile").unwrap();
        a.switch_method(Method::EventDriven);
        assert!(a.message.contains("method"), "{}", a.message);
        assert_eq!(a.session.world.config().method, Method::TimeStepped);
    }

    #[test]
    fn a_scenario_with_resting_contacts_opens_with_them() {
        let text = bounce_scenario::template("pile")
            .unwrap()
            .replace("[time]", "resting_contacts = \"rest\"\n\n[time]");
        let mut a = app("gas");
        assert_eq!(
            a.session.world.config().resting_contacts,
            RestingContacts::Bounce
        );
        a.open_text("pile.toml", &text).unwrap();
        assert_eq!(
            a.session.world.config().resting_contacts,
            RestingContacts::Rest
        );
    }

    #[test]
    fn rough_discs_show_where_they_turned_and_colour_by_spin() {
        // One large disc turned a quarter turn, spinning counter-clockwise, friction on.
        let text = "[world]\nboundary = \"walls\"\nmin = [0.0, 0.0]\nmax = [40.0, 40.0]\n\
                    friction = 0.5\n[time]\ndt = 0.01\nsteps = 10\n\
                    [[disc]]\nposition = [20.0, 20.0]\nradius = 8.0\nangular_velocity = 1.0\n";
        let mut a = app("gas");
        a.open_text("spin.toml", text).unwrap();
        assert_eq!(a.session.world.config().friction, 0.5);
        // π/2 at ω = 1: the radius points up.
        a.session
            .world
            .set_angular_velocities(&[std::f64::consts::FRAC_PI_2 / 0.1])
            .unwrap();
        a.run_to(10);
        a.session.world.set_angular_velocities(&[1.0]).unwrap();
        a.colour_by = ColorBy::Spin;
        a.palette = Palette::for_world(&a.session.world, ColorBy::Spin, a.session.colours.clone());
        let view = View::fit([0.0, 0.0], [40.0, 40.0], 200, 200);
        let mut raster = Raster::new(200, 200);
        raster.draw(&a.session.world, &view, &a.palette, &a.obstacle_colours);
        let pixel = |p: [f64; 2]| {
            let [x, y] = view.to_pixel(p, 200, 200);
            let k = (y as usize * 200 + x as usize) * 4;
            [raster.pixels[k], raster.pixels[k + 1], raster.pixels[k + 2]]
        };
        let theta = a.session.world.orientations()[0];
        assert!(
            (theta - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
            "{theta}"
        );
        // Counter-clockwise at the palette's scale (2.5 × its own): red of the spin ramp.
        let colour = bounce_scenario::spin_ramp(1.0 / 2.5);
        assert_eq!(pixel([20.0, 14.0]), colour, "the disc below its centre");
        let shade = colour.map(|c| (c as f64 * 0.4) as u8);
        let on_radius = (-2..=2).any(|d| pixel([20.0 + d as f64 * 0.1, 25.0]) == shade);
        assert!(on_radius, "the radius line upwards");
    }

    #[test]
    fn spawning_adds_coloured_discs_and_refuses_bad_places() {
        let mut a = app("newtons-cradle");
        let n = a.session.world.len();
        a.spawn([20.0, 3.0], [1.0, 0.0]);
        assert_eq!(a.session.world.len(), n + 1);
        assert_eq!(a.session.colours.len(), n + 1);
        a.spawn([500.0, 3.0], [0.0, 0.0]);
        assert_eq!(a.session.world.len(), n + 1, "outside the walls");
        assert!(a.message.contains("cannot place"), "{}", a.message);
    }

    #[test]
    fn drawn_obstacles_join_the_world_and_the_picture() {
        // A wall across the gas box and a peg: both in the world, drawn in grey, and a
        // scenario's own obstacles keep their colours.
        let mut a = app("gas");
        a.add_obstacle(Obstacle::segment([10.0, 45.0], [80.0, 45.0]));
        a.add_obstacle(Obstacle::peg([45.0, 20.0], 2.0));
        a.add_obstacle(Obstacle::peg([45.0, 20.0], -1.0));
        assert_eq!(a.obstacle_count(), 2);
        assert!(a.message.contains("cannot add"), "{}", a.message);
        // One step pushes the discs off them.
        a.run_to(1);
        let view = View::fit([0.0, 0.0], [90.0, 90.0], 300, 300);
        let mut raster = Raster::new(300, 300);
        raster.draw(&a.session.world, &view, &a.palette, &a.obstacle_colours);
        let grey = bounce_scenario::OBSTACLE_GREY;
        let pixel = |p: [f64; 2]| {
            let [x, y] = view.to_pixel(p, 300, 300);
            let k = (y as usize * 300 + x as usize) * 4;
            [raster.pixels[k], raster.pixels[k + 1], raster.pixels[k + 2]]
        };
        assert_eq!(pixel([45.0, 20.0]), grey, "the peg");
        let on_wall = (-1..=1).any(|d| pixel([30.0, 45.0 + d as f64 * 0.2]) == grey);
        assert!(on_wall, "the wall");
        let galton = app("galton-board");
        assert_eq!(galton.obstacle_colours[0], [0x8d, 0xa9, 0xc4]);
    }

    #[test]
    fn emitted_discs_appear_in_their_emitters_colour() {
        let text = r##"
[world]
min = [0.0, 0.0]
max = [20.0, 20.0]
[time]
dt = 0.05
steps = 100
[[emitter]]
region = { min = [2.0, 2.0], max = [18.0, 18.0] }
rate = 20.0
radius = 0.3
color = "#00ff00"
[[sink]]
region = { min = [0.0, 0.0], max = [20.0, 1.0] }
"##;
        let mut a = app("gas");
        a.open_text("emit.toml", text).unwrap();
        for _ in 0..10 {
            a.step();
        }
        assert_eq!(a.session.world.len(), 10, "{}", a.status());
        let last = a.session.world.next_id() as usize - 1;
        assert_eq!(a.palette.colours[last], Some([0, 255, 0]));
        // A checkpoint loaded into the freshly opened scenario (through the session, as the
        // CLI resumes) gives the emitted discs their colour again.
        let dir = std::env::temp_dir().join(format!("bounce-viewer-emit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        a.path = dir.join("c.bin").display().to_string();
        a.save_checkpoint();
        let saved = a.status();
        a.open_text("emit.toml", text).unwrap();
        assert_eq!(a.session.world.len(), 0);
        a.path = dir.join("c.bin").display().to_string();
        a.load_checkpoint();
        assert!(a.message.starts_with("loaded"), "{}", a.message);
        assert_eq!(a.status(), saved);
        assert_eq!(a.palette.colours[last], Some([0, 255, 0]));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
