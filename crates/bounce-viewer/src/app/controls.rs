//! The left panel: run controls, the scenario, the law's and the time step's settings, the
//! tools and colours, checkpoints.

use bounce::{MassModel, Method, RestingContacts, RestitutionModel, VelocityUpdate};
use bounce_scenario::ColorBy;
use eframe::egui::{self};

use crate::canvas::Palette;

use super::{Tool, ViewerApp};

impl ViewerApp {
    pub(super) fn controls(&mut self, ui: &mut egui::Ui) {
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
}

/// A slider that changes only what it edits: a scenario's value outside the slider's range
/// (a `dt` of 0.1, 32 substeps) stays as the file has it instead of being clamped the
/// first time the panel is drawn.
pub(super) fn slider<'a, N: egui::emath::Numeric>(
    value: &'a mut N,
    range: std::ops::RangeInclusive<N>,
) -> egui::Slider<'a> {
    egui::Slider::new(value, range).clamping(egui::SliderClamping::Edits)
}
