//! bounce in the browser: the desktop viewer compiled to WebAssembly (eframe on WebGL), and a
//! plain simulation handle the page uses to draw on a 2D canvas when WebGL is unavailable.
//!
//! Both expose the step count and the state hash, so a test can check that the browser
//! computes the same bits as a native run. Built by `scripts/build-web` into `web/dist`.
#![cfg(target_arch = "wasm32")]

use bounce::{Region, Shape};
use bounce_scenario::Session;
use bounce_scenario::palette::Palette;
use bounce_viewer::ViewerApp;
use wasm_bindgen::prelude::*;

/// The viewer running on a canvas.
#[wasm_bindgen]
pub struct WebHandle {
    runner: eframe::WebRunner,
}

#[wasm_bindgen]
impl WebHandle {
    /// A handle; call [`WebHandle::start`] next.
    #[wasm_bindgen(constructor)]
    pub fn new() -> Self {
        WebHandle {
            runner: eframe::WebRunner::new(),
        }
    }

    /// Starts the viewer on `canvas` with a built-in scenario (`demo` for the built-in demo).
    pub async fn start(
        &self,
        canvas: web_sys::HtmlCanvasElement,
        scenario: String,
    ) -> Result<(), JsValue> {
        let text = if scenario == "demo" {
            None
        } else {
            let text = bounce_scenario::template(&scenario)
                .ok_or_else(|| JsValue::from_str(&format!("no built-in scenario {scenario:?}")))?;
            Some((scenario.clone(), text.to_string()))
        };
        let app = ViewerApp::new(text, None).map_err(|e| JsValue::from_str(&e))?;
        self.runner
            .start(
                canvas,
                eframe::WebOptions::default(),
                Box::new(|_cc| Ok(Box::new(app))),
            )
            .await
    }

    fn with_app<T>(&self, f: impl FnOnce(&mut ViewerApp) -> T) -> Result<T, JsValue> {
        let mut app = self
            .runner
            .app_mut::<ViewerApp>()
            .ok_or_else(|| JsValue::from_str("the viewer is busy or has stopped"))?;
        Ok(f(&mut app))
    }

    /// `step N hash H particles P running B`.
    pub fn status(&self) -> Result<String, JsValue> {
        self.with_app(|app| app.status())
    }

    /// Centres of the play/pause and step buttons, in CSS pixels of the canvas.
    pub fn buttons(&self) -> Result<String, JsValue> {
        self.with_app(|app| app.button_centres())
    }

    /// Pauses and runs until step `target`; returns the status.
    pub fn run_to(&self, target: u32) -> Result<String, JsValue> {
        self.with_app(|app| {
            app.run_to(target as u64);
            app.status()
        })
    }

    /// Opens a built-in scenario.
    pub fn open_builtin(&self, name: String) -> Result<(), JsValue> {
        self.with_app(|app| app.open_builtin(&name))?
            .map_err(|e| JsValue::from_str(&e))
    }

    /// Opens scenario text (a file dropped on the page).
    pub fn open_text(&self, name: String, text: String) -> Result<(), JsValue> {
        self.with_app(|app| app.open_text(&name, &text))?
            .map_err(|e| JsValue::from_str(&e))
    }

    /// Plays or pauses.
    pub fn set_running(&self, running: bool) -> Result<(), JsValue> {
        self.with_app(|app| app.set_running(running))
    }
}

impl Default for WebHandle {
    fn default() -> Self {
        Self::new()
    }
}

/// A bare simulation for the 2D-canvas fallback: the page steps it and draws the discs, with
/// the same session (scenario, colours, view) as the viewer.
#[wasm_bindgen]
pub struct Simulation {
    session: Session,
    palette: Palette,
}

#[wasm_bindgen]
impl Simulation {
    /// A built-in scenario by name (`demo` for the viewer's built-in demo), or scenario text.
    #[wasm_bindgen(constructor)]
    pub fn new(name: String, text: Option<String>) -> Result<Simulation, JsValue> {
        let session = match (text, name.as_str()) {
            (Some(text), _) => Session::from_text(&name, &text).map_err(|e| e.to_string()),
            (None, "demo") => {
                Session::from_text("built-in demo", bounce_viewer::DEMO).map_err(|e| e.to_string())
            }
            (None, _) => Session::builtin(&name),
        }
        .map_err(|e| JsValue::from_str(&e))?;
        let palette =
            Palette::for_world(&session.world, session.colour_by, session.colours.clone());
        Ok(Simulation { session, palette })
    }

    /// Advances `n` steps.
    pub fn step(&mut self, n: u32) -> Result<(), JsValue> {
        for _ in 0..n {
            self.session
                .step()
                .map_err(|e| JsValue::from_str(&e.to_string()))?;
        }
        Ok(())
    }

    /// `[x, y, r, colour, x, y, r, colour, ...]` of every disc; the colour is `0xRRGGBB` as
    /// the viewer paints it (the scenario's colours, or by speed or radius).
    pub fn discs(&self) -> Vec<f64> {
        let p = self.session.world.particles();
        (0..p.len())
            .flat_map(|i| {
                let speed = p.vx()[i].hypot(p.vy()[i]);
                let spin = p.angular_velocity().get(i).copied().unwrap_or(0.0);
                let [r, g, b] =
                    self.palette
                        .colour(p.ids()[i].0 as usize, speed, p.radius()[i], spin);
                let rgb = (u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b);
                [p.x()[i], p.y()[i], p.radius()[i], rgb as f64]
            })
            .collect()
    }

    /// Each disc's orientation in radians, in the order of [`Simulation::discs`]; empty
    /// while no disc turns (smooth discs).
    pub fn orientations(&self) -> Vec<f64> {
        self.session.world.particles().orientation().to_vec()
    }

    /// `[kind, a, b, c, d, colour, ...]` of every obstacle where it is now: a segment is
    /// kind 0 from `(a, b)` to `(c, d)`, a peg kind 1 at `(a, b)` with radius `c` (`d` = 0);
    /// the colour is `0xRRGGBB`.
    pub fn obstacles(&self) -> Vec<f64> {
        let colours = self.session.obstacle_colours();
        self.session
            .world
            .obstacle_shapes()
            .iter()
            .zip(colours)
            .flat_map(|(shape, [r, g, b])| {
                let rgb = f64::from((u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b));
                match *shape {
                    Shape::Segment { a, b } => [0.0, a[0], a[1], b[0], b[1], rgb],
                    Shape::Peg { centre, radius } => [1.0, centre[0], centre[1], radius, 0.0, rgb],
                }
            })
            .collect()
    }

    /// `[kind, a, b, c, d, ...]` of the regions the page outlines: the emitters' (kind 0)
    /// and the sinks' (kind 1) boxes and the sensors' boxes (kind 2), each from `(a, b)` to
    /// `(c, d)`, and the sensors' circles (kind 3) around `(a, b)` of radius `c` (`d` = 0).
    pub fn regions(&self) -> Vec<f64> {
        let config = self.session.world.config();
        let emitters = config.emitters.iter().map(|e| (0.0, e.min, e.max));
        let sinks = config.sinks.iter().map(|s| (1.0, s.min, s.max));
        let sensors = config.sensors.iter().map(|s| match s.region {
            Region::Box { min, max } => (2.0, min, max),
            Region::Circle { centre, radius } => (3.0, centre, [radius, 0.0]),
        });
        emitters
            .chain(sinks)
            .chain(sensors)
            .flat_map(|(kind, min, max)| [kind, min[0], min[1], max[0], max[1]])
            .collect()
    }

    /// One line per sensor: `NAME: I inside · E in · L out` (the discs inside now, and those
    /// that entered and left since the start).
    pub fn sensors(&self) -> String {
        sensor_lines(&self.session.world)
    }

    /// Records contact events (`true`) or not, for [`Simulation::impacts`].
    pub fn set_flash(&mut self, on: bool) -> Result<(), JsValue> {
        let mut config = self.session.world.config().clone();
        config.contact_events = on;
        (self.session.world)
            .set_config(config)
            .map_err(|e| JsValue::from_str(&e.to_string()))
    }

    /// `[x, y, normal_impulse, ...]` of the contacts that began in the last step (empty
    /// unless [`Simulation::set_flash`] is on): where the page flashes.
    pub fn impacts(&self) -> Vec<f64> {
        impact_points(&self.session.world)
    }

    /// `[x_top, y_top, x_bottom, y_bottom]`: where a Lees–Edwards box's sliding copies
    /// stand (empty in any other boundary), marked on the page like the viewer marks them.
    pub fn slide_marks(&self) -> Vec<f64> {
        slide_marks(&self.session.world)
    }

    /// `[min_x, min_y, max_x, max_y]`: the region the session shows.
    pub fn bounds(&self) -> Vec<f64> {
        let (min, max) = self.session.view;
        vec![min[0], min[1], max[0], max[1]]
    }

    /// `step N hash H particles P scenario NAME`.
    pub fn status(&self) -> String {
        let world = &self.session.world;
        format!(
            "step {} hash {:016x} particles {} scenario {}",
            world.step_count(),
            world.state_hash(),
            world.len(),
            self.session.origin
        )
    }
}

/// The sensors' lines of [`Simulation::sensors`].
pub fn sensor_lines(world: &bounce::World) -> String {
    let lines: Vec<String> = (world.config().sensors.iter())
        .zip(world.sensors())
        .map(|(s, c)| {
            format!(
                "{}: {} inside · {} in · {} out",
                s.name, c.inside, c.entered, c.left
            )
        })
        .collect();
    lines.join("\n")
}

/// The points of [`Simulation::slide_marks`]: the corner of the copy above on the top edge
/// (`min + δ`) and of the copy below on the bottom edge (`min − δ`), each wrapped into the box.
pub fn slide_marks(world: &bounce::World) -> Vec<f64> {
    match (
        world.lees_edwards_offset(),
        world.config().boundary.bounds(),
    ) {
        (Some(offset), Some((min, max))) => {
            let width = max[0] - min[0];
            let along = |shift: f64| min[0] + shift.rem_euclid(width);
            vec![along(offset), max[1], along(-offset), min[1]]
        }
        _ => Vec::new(),
    }
}

/// The points of [`Simulation::impacts`].
pub fn impact_points(world: &bounce::World) -> Vec<f64> {
    (world.contact_events().iter())
        .filter(|e| e.kind == bounce::ContactKind::Begin)
        .flat_map(|e| [e.point[0], e.point[1], e.normal_impulse])
        .collect()
}
