//! The dialogs and overlays of the workstation: the path field (no native Open dialog), the
//! native Save dialog for projects and programs with the path prompt as fallback, and the
//! notifications and drop hint over the viewport.

use std::path::{Path, PathBuf};

use super::super::command::Command;
use super::super::file_dialog::{SaveOutcome, SavePurpose};
use super::super::message_log::MessageLog;
use super::super::panels::project_dialogs::PathPrompt;
use super::super::theme;
use super::Workstation;
use crate::diagnostics::Severity;

impl Workstation {
    /// The path field, when there is no native dialog.
    pub(super) fn path_field_ui(&mut self, ctx: &egui::Context, commands: &mut Vec<Command>) {
        if !self.dialog.path_field_open {
            return;
        }
        let mut open = true;
        let mut submit = false;
        egui::Window::new("Open part")
            .collapsible(false)
            .resizable(false)
            .open(&mut open)
            .show(ctx, |ui| {
                ui.label("Path of a STEP (.stp, .step) or STL file:");
                let edit = ui.add(
                    egui::TextEdit::singleline(&mut self.dialog.path_text)
                        .desired_width(420.0)
                        .hint_text("/path/to/part.stp"),
                );
                if std::mem::take(&mut self.dialog.focus_path_field) {
                    edit.request_focus();
                }
                if edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                    submit = true;
                }
                ui.horizontal(|ui| {
                    if ui.button("Open").clicked() {
                        submit = true;
                    }
                    if ui.button("Cancel").clicked() {
                        self.dialog.path_field_open = false;
                    }
                });
            });
        if submit && !self.dialog.path_text.trim().is_empty() {
            commands.push(Command::Open(PathBuf::from(self.dialog.path_text.trim())));
            self.dialog.path_field_open = false;
        }
        if !open {
            self.dialog.path_field_open = false;
        }
    }

    /// Act on what the save dialog returned.
    pub(super) fn after_save_dialog(&mut self, outcome: SaveOutcome) {
        match outcome {
            SaveOutcome::Picked(SavePurpose::Project, path) => {
                self.apply(Command::SaveProjectAs(path));
            }
            SaveOutcome::Picked(SavePurpose::Program, path) => {
                self.apply(Command::ExportProgramTo(path));
            }
            SaveOutcome::Picked(SavePurpose::ReducedStl, path) => {
                self.apply(Command::ExportReductionTo(path));
            }
            SaveOutcome::Unavailable(purpose) => {
                self.prompt = Some(match purpose {
                    SavePurpose::Project => PathPrompt::save_as(self.session.path.as_deref()),
                    SavePurpose::Program => PathPrompt::export(&self.program_suggestion()),
                    SavePurpose::ReducedStl => PathPrompt::export_stl(&self.reduction_suggestion()),
                });
            }
            SaveOutcome::Waiting | SaveOutcome::Cancelled => {}
        }
    }

    /// Open the native save dialog for `purpose` (or the path prompt without one).
    pub(super) fn save_dialog_for(&mut self, purpose: SavePurpose) {
        let start = match purpose {
            SavePurpose::Project => self.session.path.clone().or_else(|| {
                std::env::current_dir()
                    .ok()
                    .map(|d| d.join("untitled.talas"))
            }),
            SavePurpose::Program => Some(self.program_suggestion()),
            SavePurpose::ReducedStl => Some(self.reduction_suggestion()),
        };
        let ctx = self.ctx.clone();
        let outcome = self
            .save_dialog
            .open(purpose, start, move || ctx.request_repaint());
        self.after_save_dialog(outcome);
    }

    /// A file name for the exported program: next to the project, named after it and the
    /// operation, with the dialect's usual extension.
    pub(super) fn program_suggestion(&self) -> PathBuf {
        let dir = self
            .session
            .path
            .as_ref()
            .and_then(|p| p.parent().map(Path::to_path_buf))
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let op = self
            .ops
            .active
            .and_then(|i| self.session.project.operations.get(i))
            .map_or("program", |o| o.name());
        let stem: String = format!("{}-{op}", self.session.project.name)
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let ext = match self.session.project.post.dialect.as_str() {
            "linuxcnc" => "ngc",
            "siemens" => "mpf",
            "heidenhain" => "i",
            _ => "nc",
        };
        dir.join(format!("{stem}.{ext}"))
    }
}

/// Notifications and the drop hint over the viewport.
pub(super) fn overlays_ui(
    ui: &mut egui::Ui,
    rect: egui::Rect,
    log: &MessageLog,
    files_hovered: bool,
) {
    if files_hovered {
        ui.painter()
            .rect_filled(rect, 0.0, egui::Color32::from_black_alpha(140));
        ui.painter().text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "Drop a STEP or STL file to open it",
            egui::FontId::proportional(22.0),
            egui::Color32::WHITE,
        );
    }
    let mut y = rect.top() + 12.0;
    for toast in log.toasts.iter().rev().take(4) {
        let colour = match toast.severity {
            Severity::Error => theme::ERROR,
            Severity::Warning => theme::WARNING,
            Severity::Info => theme::ACCENT,
        };
        let area = egui::Area::new(egui::Id::unique(("toast", toast.until_s.to_bits())))
            .fixed_pos(egui::pos2(rect.right() - 12.0, y))
            .pivot(egui::Align2::RIGHT_TOP)
            .order(egui::Order::Foreground)
            .interactable(false);
        let response = area.show(ui.ctx(), |ui| {
            egui::Frame::popup(ui.style())
                .stroke(egui::Stroke::new(1.0, colour))
                .show(ui, |ui| {
                    ui.set_max_width(440.0);
                    let title = match toast.severity {
                        Severity::Error => "Error",
                        Severity::Warning => "Warning",
                        Severity::Info => "Note",
                    };
                    ui.label(egui::RichText::new(title).strong().color(colour));
                    ui.add(egui::Label::new(&toast.text).wrap());
                });
        });
        y += response.response.rect.height() + 8.0;
    }
}
