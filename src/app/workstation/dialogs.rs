//! The dialogs and overlays of the workstation: the in-window file chooser where the native
//! Open and Save dialogs are unavailable, the
//! unsaved-changes question before New, Open and Quit (the window's close button included), and
//! the notifications and drop hint over the viewport.

use std::path::PathBuf;

use super::super::command::Command;
use super::super::file_chooser::{ChooserPurpose, FileChooser};
use super::super::file_dialog::{SaveOutcome, SavePurpose};
use super::super::message_log::MessageLog;
use super::super::panels::project_dialogs::{UnsavedAnswer, unsaved_changes_ui};
use super::super::theme;
use super::Workstation;
use crate::diagnostics::Severity;

impl Workstation {
    /// Open the in-window file chooser for `purpose` at `start` (a folder or a file).
    pub(super) fn open_chooser(&mut self, purpose: ChooserPurpose, start: Option<PathBuf>) {
        let start = start.or_else(|| std::env::current_dir().ok());
        self.run.chooser = Some(FileChooser::new(purpose, start, &self.saved.recent.paths));
    }

    /// The in-window file chooser: the chosen file is used at once (the question about unsaved
    /// changes was asked before it opened).
    pub(super) fn chooser_ui(&mut self, ctx: &egui::Context) {
        let Some(chooser) = &mut self.run.chooser else {
            return;
        };
        let Some(outcome) = chooser.ui(ctx) else {
            return;
        };
        let purpose = chooser.purpose();
        self.run.chooser = None;
        match outcome {
            Some(path) => {
                if let Some(command) = purpose.command(path) {
                    self.apply_confirmed(command);
                }
            }
            // Save As was cancelled: what waited for the save does not happen.
            None => self.run.after_save = None,
        }
    }

    /// The file chooser while it is open (what it is for).
    #[must_use]
    pub fn chooser(&self) -> Option<&FileChooser> {
        self.run.chooser.as_ref()
    }

    /// Act on what the save dialog returned.
    pub(super) fn after_save_dialog(&mut self, outcome: SaveOutcome) {
        match outcome {
            SaveOutcome::Picked(SavePurpose::Project, path) => {
                self.apply(Command::SaveProjectAs(path));
            }
            SaveOutcome::Picked(SavePurpose::Feature(f), path) => {
                self.apply(Command::FeatureFile {
                    feature: f.feature,
                    path,
                });
            }
            SaveOutcome::Unavailable(purpose) => {
                let start = self.save_suggestion(purpose);
                self.open_chooser(ChooserPurpose::Save(purpose), start);
            }
            SaveOutcome::Cancelled => self.run.after_save = None,
            SaveOutcome::Waiting => {}
        }
    }

    /// Would `command` discard unsaved changes without having been confirmed?
    pub(super) fn must_ask_first(&self, command: &Command) -> bool {
        let discards = matches!(
            command,
            Command::NewProject
                | Command::OpenDialog
                | Command::OpenProjectDialog
                | Command::Open(_)
                | Command::OpenProject(_)
                | Command::Quit
        );
        discards && !self.run.confirmed && self.saved.session.is_dirty()
    }

    /// Apply `command` without asking about unsaved changes (the user answered already).
    pub(super) fn apply_confirmed(&mut self, command: Command) {
        let was = std::mem::replace(&mut self.run.confirmed, true);
        self.apply(command);
        self.run.confirmed = was;
    }

    /// The window's close button: with unsaved changes the close is held back and the question
    /// asked (as for Quit).
    pub(super) fn on_close_request(&mut self, ctx: &egui::Context) {
        let requested = ctx.input(|i| i.viewport().close_requested());
        if requested && !self.run.quit_confirmed && self.saved.session.is_dirty() {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.run.unsaved = Some(Command::Quit);
        }
    }

    /// The question about unsaved changes, while a command waits for its answer.
    pub(super) fn unsaved_ui(&mut self, ctx: &egui::Context) {
        let Some(waiting) = &self.run.unsaved else {
            return;
        };
        let action = match waiting {
            Command::NewProject => "A new project",
            Command::Quit => "Quitting",
            _ => "Opening another file",
        };
        let Some(answer) = unsaved_changes_ui(ctx, &self.saved.session.project.name, action) else {
            return;
        };
        let Some(command) = self.run.unsaved.take() else {
            return;
        };
        match answer {
            UnsavedAnswer::Save => match self.saved.session.path.clone() {
                Some(path) => {
                    self.apply(Command::SaveProjectAs(path));
                    if !self.saved.session.is_dirty() {
                        self.apply_confirmed(command);
                    }
                }
                None => {
                    // Ask where to save; the command follows a successful save.
                    self.run.after_save = Some(command);
                    self.apply(Command::SaveProjectAsDialog);
                }
            },
            UnsavedAnswer::Discard => {
                self.saved.session.discard_recovery();
                self.log_info("Unsaved changes discarded");
                let opens_part = match &command {
                    Command::OpenDialog => true,
                    Command::Open(path) => !path
                        .extension()
                        .is_some_and(|e| e.eq_ignore_ascii_case(crate::project::file::EXTENSION)),
                    _ => false,
                };
                if opens_part {
                    // A part opens into the open project: its unsaved changes go first (back to
                    // the saved file, or a new project).
                    match self.saved.session.path.clone() {
                        Some(path) => self.apply_confirmed(Command::OpenProject(path)),
                        None => self.apply_confirmed(Command::NewProject),
                    }
                }
                self.apply_confirmed(command);
            }
            UnsavedAnswer::Cancel => {}
        }
    }

    /// Is a command waiting for the answer to "Save the changes?" (the command)?
    #[must_use]
    pub fn waiting_for_unsaved_answer(&self) -> Option<&Command> {
        self.run.unsaved.as_ref()
    }

    /// Open the native save dialog for `purpose` (or the path prompt without one).
    pub(super) fn save_dialog_for(&mut self, purpose: SavePurpose) {
        let start = self.save_suggestion(purpose);
        let ctx = self.run.ctx.clone();
        let outcome = self
            .run
            .save_dialog
            .open(purpose, start, move || ctx.request_repaint());
        self.after_save_dialog(outcome);
    }

    /// Where a save dialog for `purpose` starts: the project's file (or `NAME.talas` in the
    /// working folder), or the export file the feature suggested.
    fn save_suggestion(&self, purpose: SavePurpose) -> Option<PathBuf> {
        match purpose {
            SavePurpose::Project => self.saved.session.path.clone().or_else(|| {
                let name = format!(
                    "{}.{}",
                    self.saved.session.project.name,
                    crate::project::file::EXTENSION
                );
                std::env::current_dir().ok().map(|d| d.join(name))
            }),
            SavePurpose::Feature(_) => self.run.feature_save_start.clone(),
        }
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
