//! The canvas and what the mouse does on it: discs spawned and flung, segments and pegs
//! drawn into the world.

use bounce::{Obstacle, Particle};
use eframe::egui::{self, Color32, PointerButton, Sense, TextureOptions};

use crate::canvas::{Raster, View};

use super::{Tool, ViewerApp};

impl ViewerApp {
    /// The picture and its mouse handling.
    pub(super) fn canvas(&mut self, ui: &mut egui::Ui) {
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

    pub(super) fn handle_mouse(
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

    pub(super) fn spawn(&mut self, at: [f64; 2], velocity: [f64; 2]) {
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
}
