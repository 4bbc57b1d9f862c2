//! The log (bottom panel): every message of the session, newest at the bottom.

use super::super::command::Command;
use super::super::message_log::MessageLog;
use super::super::theme;
use crate::diagnostics::Severity;

/// The log panel.
pub fn log_ui(ui: &mut egui::Ui, log: &MessageLog, commands: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        ui.label(egui::RichText::new("LOG").small().strong().weak());
        let errors = log.count_at_least(Severity::Error);
        let warnings = log.count_at_least(Severity::Warning) - errors;
        if errors > 0 {
            ui.colored_label(theme::ERROR, plural(errors, "error"));
        }
        if warnings > 0 {
            ui.colored_label(theme::WARNING, plural(warnings, "warning"));
        }
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            if ui.small_button("Clear").clicked() {
                commands.push(Command::ClearLog);
            }
        });
    });
    ui.separator();
    let row_height = ui.text_style_height(&egui::TextStyle::Monospace) + 2.0;
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .stick_to_bottom(true)
        .show_rows(ui, row_height, log.entries.len(), |ui, rows| {
            for entry in log.entries.get(rows).unwrap_or_default() {
                let (tag, colour) = match entry.severity {
                    Severity::Info => ("info ", ui.visuals().weak_text_color()),
                    Severity::Warning => ("warn ", theme::WARNING),
                    Severity::Error => ("error", theme::ERROR),
                };
                ui.horizontal(|ui| {
                    ui.label(
                        egui::RichText::new(format!("{:>8.2} s", entry.time_s))
                            .monospace()
                            .weak(),
                    );
                    ui.label(egui::RichText::new(tag).monospace().color(colour));
                    ui.label(egui::RichText::new(&entry.text).monospace());
                });
            }
        });
}

/// `1 error`, `2 errors`.
fn plural(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}
