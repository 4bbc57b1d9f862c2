//! Small windows about the project file: the path prompt for Open Project and Save As (works
//! without a system file dialog), and the crash-recovery question.

use std::path::{Path, PathBuf};

use super::super::command::Command;

/// Which question the path prompt asks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PromptKind {
    /// Open a project.
    Open,
    /// Save the project as.
    SaveAs,
    /// Export the posted program.
    Export,
    /// Use a machine definition file.
    MachineFile,
    /// Export the reduced surface (STL).
    ExportStl,
}

/// A small window asking for a project path.
#[derive(Clone, Debug)]
pub struct PathPrompt {
    /// Open or Save As.
    pub kind: PromptKind,
    /// The typed path.
    pub text: String,
    focus: bool,
}

impl PathPrompt {
    /// Ask for a project to open.
    #[must_use]
    pub fn open() -> Self {
        Self {
            kind: PromptKind::Open,
            text: String::new(),
            focus: true,
        }
    }

    /// Ask where to save, starting from `current` (or `untitled.talas` in the working folder).
    #[must_use]
    pub fn save_as(current: Option<&Path>) -> Self {
        let text = current.map_or_else(
            || {
                std::env::current_dir()
                    .unwrap_or_default()
                    .join("untitled.talas")
                    .display()
                    .to_string()
            },
            |p| p.display().to_string(),
        );
        Self {
            kind: PromptKind::SaveAs,
            text,
            focus: true,
        }
    }

    /// Ask where to export the posted program, starting from `suggested`.
    #[must_use]
    pub fn export(suggested: &Path) -> Self {
        Self {
            kind: PromptKind::Export,
            text: suggested.display().to_string(),
            focus: true,
        }
    }

    /// Ask where to export the reduced surface, starting from `suggested`.
    #[must_use]
    pub fn export_stl(suggested: &Path) -> Self {
        Self {
            kind: PromptKind::ExportStl,
            text: suggested.display().to_string(),
            focus: true,
        }
    }

    /// Ask for a machine definition file (JSON).
    #[must_use]
    pub fn machine_file() -> Self {
        Self {
            kind: PromptKind::MachineFile,
            text: String::new(),
            focus: true,
        }
    }

    /// Show the prompt; `Some(commands)` when it closes (empty when cancelled).
    pub fn ui(&mut self, ctx: &egui::Context) -> Option<Vec<Command>> {
        let (title, action) = match self.kind {
            PromptKind::Open => ("Open project", "Open"),
            PromptKind::SaveAs => ("Save project as", "Save"),
            PromptKind::Export => ("Export G-code", "Export"),
            PromptKind::MachineFile => ("Machine file", "Use"),
            PromptKind::ExportStl => ("Export reduced surface", "Export"),
        };
        let mut result = None;
        let mut open = true;
        egui::Window::new(title)
            .collapsible(false)
            .resizable(false)
            .open(&mut open)
            .show(ctx, |ui| {
                let label = ui.label(match self.kind {
                    PromptKind::Export => "Path of the G-code file:",
                    PromptKind::ExportStl => "Path of the STL file:",
                    PromptKind::MachineFile => {
                        "Path of a machine definition (JSON, as assets/machines/*.json):"
                    }
                    PromptKind::Open | PromptKind::SaveAs => "Path of the project file (.talas):",
                });
                let edit = ui
                    .add(
                        egui::TextEdit::singleline(&mut self.text)
                            .desired_width(420.0)
                            .id_salt("project path"),
                    )
                    .labelled_by(label.id);
                if std::mem::take(&mut self.focus) {
                    edit.request_focus();
                }
                let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                ui.horizontal(|ui| {
                    if (ui.button(action).clicked() || enter) && !self.text.trim().is_empty() {
                        let mut path = PathBuf::from(self.text.trim());
                        if self.kind == PromptKind::SaveAs && path.extension().is_none() {
                            path.set_extension(crate::project::file::EXTENSION);
                        }
                        result = Some(vec![match self.kind {
                            PromptKind::Open => Command::OpenProject(path),
                            PromptKind::SaveAs => Command::SaveProjectAs(path),
                            PromptKind::Export => Command::ExportProgramTo(path),
                            PromptKind::ExportStl => Command::ExportReductionTo(path),
                            PromptKind::MachineFile => Command::Edit(
                                crate::project::Edit::SetMachine(path.display().to_string()),
                            ),
                        }]);
                    }
                    if ui.button("Cancel").clicked() {
                        result = Some(Vec::new());
                    }
                });
            });
        if !open {
            return Some(Vec::new());
        }
        result
    }
}

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
