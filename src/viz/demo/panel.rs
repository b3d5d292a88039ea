//! The egui control panel: scenes, run controls, solver knobs, effects, counts, stage
//! timings (from Bevy diagnostics), a live plot of energy and momentum, debug gizmos.

use bevy::diagnostic::DiagnosticsStore;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};
use egui_plot::{Legend, Line, Plot, PlotPoints};

use super::scenes::{DemoScenes, SwitchScene};
use super::stage_path;
use super::stats::{EnergyHistory, SceneStats};
use crate::body::{Friction, Restitution, RigidBody};
use crate::effects::Effects;
use crate::scene::integrator_name;
use crate::settings::{Gravity, Integrator, SolverSettings};
use crate::timings::STAGES;
use crate::viz::DebugRenderSettings;

/// Material sliders' last values, applied to every body when moved.
#[derive(Default)]
pub struct MaterialSliders {
    restitution: f32,
    friction: f32,
    initialised: bool,
}

#[allow(clippy::too_many_arguments)]
pub fn draw_panel(
    mut contexts: EguiContexts,
    scenes: Res<DemoScenes>,
    mut switch: MessageWriter<SwitchScene>,
    mut time: ResMut<Time<Virtual>>,
    mut fixed: ResMut<Time<Fixed>>,
    mut integrator: ResMut<Integrator>,
    mut solver: ResMut<SolverSettings>,
    mut gravity: ResMut<Gravity>,
    mut effects: ResMut<Effects>,
    mut debug: ResMut<DebugRenderSettings>,
    stats: Res<SceneStats>,
    history: Res<EnergyHistory>,
    diagnostics: Res<DiagnosticsStore>,
    mut materials: Query<(&mut Restitution, &mut Friction), With<RigidBody>>,
    mut sliders: Local<MaterialSliders>,
    mut commands: Commands,
) -> Result {
    if !sliders.initialised {
        *sliders = MaterialSliders {
            restitution: 0.0,
            friction: 0.5,
            initialised: true,
        };
    }
    let ctx = contexts.ctx_mut()?;
    // The panel fits the window: its contents scroll within the height left below its
    // title bar (a 720-pixel window cut off the gizmo toggles at the bottom).
    let fits = (ctx.input(|i| i.content_rect().height()) - 56.0).max(120.0);
    egui::Window::new("tumble").default_pos([8.0, 8.0]).default_width(290.0).show(ctx, |ui| {
        egui::ScrollArea::vertical().max_height(fits).show(ui, |ui| {
            let current = scenes.names.get(scenes.current).map_or("", |n| n.trim_end_matches(".scene.ron"));
            let n = scenes.names.len().max(1);
            ui.horizontal(|ui| {
                if ui.button("◀").on_hover_text("previous scene (PageUp, [)").clicked() {
                    switch.write(SwitchScene((scenes.current + n - 1) % n));
                }
                egui::ComboBox::from_id_salt("scene").selected_text(current).show_ui(ui, |ui| {
                    for (i, name) in scenes.names.iter().enumerate() {
                        if ui.selectable_label(i == scenes.current, name.trim_end_matches(".scene.ron")).clicked() {
                            switch.write(SwitchScene(i));
                        }
                    }
                });
                if ui.button("▶").on_hover_text("next scene (PageDown, ])").clicked() {
                    switch.write(SwitchScene((scenes.current + 1) % n));
                }
            });
            ui.small(format!("scene {} of {n} · keys 1–9, 0, PageUp/PageDown", scenes.current + 1));
            if let Some(err) = &scenes.error {
                ui.colored_label(egui::Color32::LIGHT_RED, err);
            }
            ui.horizontal(|ui| {
                let label = if time.is_paused() { "▶ play" } else { "⏸ pause" };
                if ui.button(label).clicked() {
                    if time.is_paused() { time.unpause() } else { time.pause() }
                }
                if ui.button("step").clicked() && time.is_paused() {
                    commands.run_schedule(bevy::app::FixedMain);
                }
                if ui.button("reset").clicked() {
                    switch.write(SwitchScene(scenes.current));
                }
            });

            egui::CollapsingHeader::new("Solver").default_open(true).show(ui, |ui| {
                egui::ComboBox::from_label("integrator").selected_text(integrator_name(*integrator)).show_ui(ui, |ui| {
                    for i in Integrator::ALL {
                        ui.selectable_value(&mut *integrator, i, integrator_name(i));
                    }
                });
                let mut hz = (1.0 / fixed.timestep().as_secs_f64()).round();
                if ui.add(egui::Slider::new(&mut hz, 15.0..=480.0).text("steps/s")).changed() {
                    fixed.set_timestep_hz(hz);
                }
                ui.add(egui::Slider::new(&mut solver.substeps, 1..=16).text("substeps"));
                ui.add(egui::Slider::new(&mut solver.iterations, 1..=8).text("iterations"));
                ui.add(egui::Slider::new(&mut gravity.0.y, -30.0..=0.0).text("gravity y"));
                let r = ui.add(egui::Slider::new(&mut sliders.restitution, 0.0..=1.0).text("restitution (all)"));
                let f = ui.add(egui::Slider::new(&mut sliders.friction, 0.0..=1.5).text("friction (all)"));
                if r.changed() || f.changed() {
                    for (mut rest, mut fric) in &mut materials {
                        rest.0 = sliders.restitution;
                        fric.0 = sliders.friction;
                    }
                }
            });

            egui::CollapsingHeader::new("Effects").default_open(false).show(ui, |ui| {
                ui.horizontal_wrapped(|ui| {
                    for (name, on) in effects.toggles() {
                        ui.checkbox(on, name);
                    }
                });
            });

            ui.label(format!(
                "bodies {}  awake {}  contacts {} ({} points)",
                stats.bodies, stats.awake, stats.touching_pairs, stats.contact_points
            ));
            let ms: Vec<f64> = (0..STAGES.len())
                .map(|i| diagnostics.get(&stage_path(i)).and_then(|d| d.smoothed()).unwrap_or(0.0))
                .collect();
            egui::CollapsingHeader::new(format!("step {:.3} ms", ms.iter().sum::<f64>())).show(ui, |ui| {
                egui::Grid::new("timings").show(ui, |ui| {
                    for (stage, ms) in STAGES.iter().zip(&ms) {
                        ui.label(*stage);
                        ui.label(format!("{ms:.3} ms"));
                        ui.end_row();
                    }
                });
            });
            // The cost of the current settings (step ms above) next to their energy drift.
            let drift = history.samples.front().map_or(0.0, |&(_, e0, _)| (stats.energy as f64 - e0) / e0.abs().max(1e-9));
            ui.label(format!(
                "energy {:.2} J (drift {:+.3} % over the plot)   momentum {:.2} kg·m/s",
                stats.energy,
                drift * 100.0,
                stats.momentum
            ));
            let energy: PlotPoints = history.samples.iter().map(|&(t, e, _)| [t, e]).collect();
            let momentum: PlotPoints = history.samples.iter().map(|&(t, _, p)| [t, p]).collect();
            Plot::new("energy").height(110.0).legend(Legend::default()).show(ui, |plot| {
                plot.line(Line::new("energy (J)", energy));
                plot.line(Line::new("momentum (kg·m/s)", momentum));
            });

            ui.horizontal_wrapped(|ui| {
                ui.label("gizmos");
                ui.checkbox(&mut debug.joints, "joints");
                ui.checkbox(&mut debug.contacts, "contacts");
                ui.checkbox(&mut debug.aabbs, "AABBs");
                ui.checkbox(&mut debug.velocities, "velocities");
            });
            ui.small("drag: pull · A/D Q/E W/S: push · B/V: add box/ball · Del: remove · Space/N/R");
        });
    });
    Ok(())
}
