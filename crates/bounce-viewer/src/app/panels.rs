//! The right panel: energy and momentum over time, the speed histogram against
//! Maxwell–Boltzmann, the structure (|ψ6| and the profiles along y).

use eframe::egui::{self, Color32};
use egui_plot::{Bar, BarChart, Legend, Line, Plot, PlotPoints};

use super::ViewerApp;

impl ViewerApp {
    pub(super) fn panels(&mut self, ui: &mut egui::Ui) {
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
    pub(super) fn structure(&self, ui: &mut egui::Ui) {
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

    pub(super) fn speed_histogram(&self) -> (Vec<Bar>, PlotPoints<'static>) {
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
}

/// The world's global bond order |ψ6| now and, in a box, its profiles along y in 20 bins
/// (what the structure panel shows).
pub(super) fn structure_of(
    world: &bounce::World,
) -> (f64, Option<bounce_scenario::observables::Profile>) {
    use bounce_scenario::observables::{Axis, profile};
    use bounce_scenario::structure::{Snapshot, psi6};
    let order = psi6(&Snapshot::of(world));
    (order, profile(world, Axis::Y, 20).ok())
}
