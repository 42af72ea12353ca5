//! The keyboard shortcuts and the help window that lists them.

use eframe::egui::{self};

use super::ViewerApp;

impl ViewerApp {
    pub(super) fn keyboard(&mut self, ctx: &egui::Context) {
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

    pub(super) fn help(&mut self, ctx: &egui::Context) {
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
}
