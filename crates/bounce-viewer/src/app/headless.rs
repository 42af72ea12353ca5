//! What tests and `--headless-frames` drive: the status line, running to a step, the
//! buttons' places, a frame captured to a file.

use std::ops::ControlFlow;

use bounce::Method;
use eframe::egui::{self};

use super::ViewerApp;

impl ViewerApp {
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
    pub(super) fn fps(&self) -> f64 {
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

    /// Headless runs count frames, then take and save a screenshot and close.
    pub(super) fn headless_frame(&mut self, ctx: &egui::Context) {
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
