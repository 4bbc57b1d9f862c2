//! The stock simulation's section of the operation editor.

use super::StockSimulation;
use crate::app::command::Command;
use crate::app::feature::FeatureView;
use crate::app::number_field::NumberField;
use crate::app::widgets::{grid, grouped, mm3};

/// The "Stock simulation" section of operation `index`'s editor: Simulate (or its progress and
/// Cancel), the report of the simulation shown for it, its tolerance band and the collisions.
pub fn section_ui(
    sim: &StockSimulation,
    ui: &mut egui::Ui,
    index: usize,
    view: &FeatureView<'_>,
    commands: &mut Vec<Command>,
) {
    let fresh = matches!(view.results.operation_result(index), Some((_, true)));
    let active = view.active_operation == Some(index);
    let simulating = sim.job.status().filter(|_| active).map(|(_, f, e)| (f, e));
    let picked_pose = view.picked_pose.filter(|_| active);
    ui.add_space(8.0);
    ui.horizontal(|ui| {
        ui.label(egui::RichText::new("Stock simulation").strong());
        match simulating {
            Some((fraction, elapsed)) => {
                ui.add(
                    egui::ProgressBar::new(fraction as f32)
                        .desired_width(120.0)
                        .text(format!("{:.0} % · {elapsed:.1} s", fraction * 100.0)),
                );
                if ui.button("Cancel").clicked() {
                    commands.push(Command::CancelJob);
                }
            }
            None => {
                if ui
                    .add_enabled(fresh, egui::Button::new("Simulate"))
                    .on_hover_text(
                        "Cut the stock with this path (dexels) and compare it with the part",
                    )
                    .on_disabled_hover_text("Calculate the operation first")
                    .clicked()
                {
                    commands.push(Command::Simulate(index));
                }
            }
        }
    });
    let Some(sim) = sim.simulation_of(index, view) else {
        return;
    };
    let s = &sim.simulated;
    let r = &s.report;
    grid(
        ui,
        "simulation",
        &[
            (
                "Path cut",
                sim.up_to_pose().map_or_else(
                    || "whole".to_string(),
                    |p| format!("up to pose {} (Stock here)", grouped(p + 1)),
                ),
            ),
            (
                "Dexel spacing",
                format!("{:.3} mm (Z rays)", s.resolution_mm),
            ),
            ("Removed", format!("{:.0} mm³", r.removed_volume_mm3)),
            ("Stock left", format!("{:.0} mm³", r.final_volume_mm3)),
            (
                "Deepest gouge",
                format!("{:.1} µm", s.max_gouge_mm * 1000.0),
            ),
            (
                "Material left (99 %)",
                format!("{:.1} µm", s.remaining_p99_mm * 1000.0),
            ),
            ("Collisions", grouped(r.collisions.len())),
            ("Simulated in", format!("{:.1} s", sim.elapsed_s)),
        ],
    );
    ui.horizontal(|ui| {
        let l = ui
            .label("Tolerance band ±")
            .on_hover_text("Deviation within ± this is graded blue → white → orange; gouges beyond it are violet, material left beyond it red");
        let mut band = sim.band_mm;
        if NumberField::new("deviation band", &mut band)
            .labelled_by(l.id)
            .range(0.001..=50.0)
            .decimals(4)
            .unit("mm")
            .show(ui)
        {
            commands.push(Command::SetDeviationBand(band));
        }
    });
    if !r.collisions.is_empty() {
        egui::ScrollArea::vertical()
            .id_salt("collisions")
            .max_height(140.0)
            .show(ui, |ui| {
                for c in r.collisions.iter().take(500) {
                    let text = format!(
                        "{:?} at pose {}: {:.2} mm deep at {}",
                        c.kind,
                        grouped(c.block + 1),
                        c.depth_mm,
                        mm3(c.position)
                    );
                    if ui
                        .selectable_label(picked_pose == Some(c.block), text)
                        .on_hover_text("Show this pose")
                        .clicked()
                    {
                        commands.push(Command::PickOperationPose {
                            operation: index,
                            pose: c.block,
                        });
                    }
                }
            });
    }
}
