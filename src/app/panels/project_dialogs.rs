//! Small windows about the project file: the crash-recovery question, and the unsaved-changes
//! question (Save / Discard / Cancel) before New, Open and Quit.

use std::path::Path;

use super::super::command::Command;

/// Ask whether to recover the unsaved changes in `recovery` (for the project `project`, or an
/// untitled one). Returns the answer's command once given.
pub fn recovery_ui(
    ctx: &egui::Context,
    recovery: &Path,
    project: Option<&Path>,
) -> Option<Command> {
    let mut answer = None;
    egui::Modal::new(egui::Id::unique("recovery")).show(ctx, |ui| {
        ui.set_max_width(480.0);
        ui.heading("Recover unsaved changes?");
        ui.add_space(4.0);
        let what = project.map_or_else(
            || "an untitled project".to_string(),
            |p| p.display().to_string(),
        );
        ui.label(format!(
            "The last session ended with unsaved changes to {what}. They were autosaved to {}.",
            recovery.display()
        ));
        ui.add_space(8.0);
        ui.horizontal(|ui| {
            if ui.button("Recover").clicked() {
                answer = Some(Command::Recover(recovery.to_path_buf()));
            }
            if ui.button("Discard").clicked() {
                answer = Some(Command::DiscardRecovery(recovery.to_path_buf()));
            }
        });
    });
    answer
}

/// The answer to "Save changes?".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnsavedAnswer {
    /// Save the project, then go on.
    Save,
    /// Go on without saving (the changes are lost).
    Discard,
    /// Do not go on.
    Cancel,
}

/// Ask what to do with the unsaved changes of the project `name` before `action` ("New
/// project", "Open", "Quit"). Returns the answer once given (Escape or a click outside: Cancel).
pub fn unsaved_changes_ui(ctx: &egui::Context, name: &str, action: &str) -> Option<UnsavedAnswer> {
    let mut answer = None;
    let modal = egui::Modal::new(egui::Id::unique("unsaved changes")).show(ctx, |ui| {
        ui.set_max_width(440.0);
        ui.heading(format!("Save the changes to '{name}'?"));
        ui.add_space(4.0);
        ui.label(format!(
            "The project has unsaved changes. {action} discards them unless they are saved first."
        ));
        ui.add_space(8.0);
        ui.horizontal(|ui| {
            if ui.button("Save").clicked() {
                answer = Some(UnsavedAnswer::Save);
            }
            if ui.button("Discard").clicked() {
                answer = Some(UnsavedAnswer::Discard);
            }
            if ui.button("Cancel").clicked() {
                answer = Some(UnsavedAnswer::Cancel);
            }
        });
    });
    if answer.is_none() && modal.should_close() {
        answer = Some(UnsavedAnswer::Cancel);
    }
    answer
}
