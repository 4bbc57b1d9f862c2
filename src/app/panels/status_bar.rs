//! The status bar: cursor position on the part, the running job with its progress and Cancel,
//! and a summary of the document.

use glam::DVec3;

use super::super::command::Command;

/// What the status bar shows.
#[derive(Clone, Debug, Default)]
pub struct StatusInfo {
    /// Point of the part under the cursor (mm).
    pub cursor_mm: Option<DVec3>,
    /// Running job: label, fraction done (0..1), seconds since it started.
    pub job: Option<(String, f64, f64)>,
    /// Short description of the open document.
    pub document: Option<String>,
}

/// The status bar.
pub fn status_bar_ui(ui: &mut egui::Ui, info: &StatusInfo, commands: &mut Vec<Command>) {
    ui.horizontal_centered(|ui| {
        match info.cursor_mm {
            Some(p) => ui.label(
                egui::RichText::new(format!(
                    "X {:>10.3}   Y {:>10.3}   Z {:>10.3}  mm",
                    p.x, p.y, p.z
                ))
                .monospace(),
            ),
            None => ui.label(
                egui::RichText::new("X          –   Y          –   Z          –  mm")
                    .monospace()
                    .weak(),
            ),
        };
        ui.separator();
        if let Some((label, fraction, elapsed_s)) = &info.job {
            ui.add(egui::Spinner::new());
            ui.label(label);
            ui.add(
                egui::ProgressBar::new(*fraction as f32)
                    .desired_width(160.0)
                    .show_percentage()
                    .fill(super::super::theme::ACCENT),
            );
            ui.weak(format!("{elapsed_s:.1} s"));
            if ui.small_button("Cancel").clicked() {
                commands.push(Command::CancelJob);
            }
        } else {
            ui.weak("Ready");
        }
        if let Some(doc) = &info.document {
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                ui.weak(doc);
            });
        }
    });
}
