//! The project commands: document edits through the undo history, new/open/save/save as,
//! autosave and crash recovery, and keeping the tool library file in step with the tools.

use std::path::Path;

use super::super::command::Command;
use super::super::panels::project_dialogs::PathPrompt;
use super::super::panels::properties::Focus;
use super::super::project_session::{ProjectSession, part_file, pending_recovery};
use super::super::tool_library::library_path;
use super::{Workstation, new_project};
use crate::diagnostics::Severity;
use crate::project::{Project, ToolEntry};

impl Workstation {
    /// Apply a project command (see [`Workstation::apply`]).
    pub(super) fn apply_project(&mut self, command: Command) {
        let tools_before = (
            self.session.project.tools.clone(),
            self.session.project.selected_tool,
        );
        match command {
            Command::Edit(edit) => {
                let what = edit.describe();
                match self.session.edit(edit) {
                    Ok(()) => self.after_document_change(&tools_before),
                    Err(e) => {
                        let t = self.now_s();
                        self.log
                            .notify(t, Severity::Warning, format!("{what} not applied: {e}"));
                    }
                }
            }
            Command::Undo => {
                let label = self.session.undo();
                self.log_info(label.map_or("Nothing to undo".into(), |l| format!("Undo: {l}")));
                self.after_document_change(&tools_before);
            }
            Command::Redo => {
                let label = self.session.redo();
                self.log_info(label.map_or("Nothing to redo".into(), |l| format!("Redo: {l}")));
                self.after_document_change(&tools_before);
            }
            Command::NewProject => {
                let data_dir = self.session.data_dir.clone();
                let every = self.session.autosave_every;
                self.session = ProjectSession::new(new_project(&self.library), data_dir, every);
                self.focus = Focus::Selection;
                self.log_info("New project");
                self.load_project_part();
            }
            Command::OpenProjectDialog => self.prompt = Some(PathPrompt::open()),
            Command::SaveProjectAsDialog => {
                self.save_dialog_for(super::SavePurpose::Project);
            }
            Command::OpenProject(path) => self.open_project(&path),
            Command::SaveProject => match self.session.path.clone() {
                Some(path) => self.apply(Command::SaveProjectAs(path)),
                None => self.apply(Command::SaveProjectAsDialog),
            },
            Command::SaveProjectAs(path) => match self.session.save_as(&path) {
                Ok(()) => {
                    self.log_info(format!("Saved {}", path.display()));
                    if let Some(e) = self.recent.add(&path) {
                        let t = self.now_s();
                        self.log.push(t, Severity::Warning, e);
                    }
                }
                Err(e) => {
                    let t = self.now_s();
                    self.log
                        .notify(t, Severity::Error, format!("Not saved: {e}"));
                }
            },
            Command::Recover(file) => {
                self.recovery = None;
                match Project::load(&file) {
                    Ok(project) => {
                        // The recovered project keeps its file (if it had one): saving writes
                        // there, and the recovery file goes.
                        let path = self.session.path.clone();
                        self.session.replace(project, path, true);
                        self.focus = Focus::Selection;
                        self.log_info(format!("Recovered unsaved changes from {}", file.display()));
                        self.load_project_part();
                    }
                    Err(e) => {
                        let t = self.now_s();
                        self.log
                            .notify(t, Severity::Error, format!("Could not recover: {e}"));
                    }
                }
            }
            Command::DiscardRecovery(file) => {
                self.recovery = None;
                let _ = std::fs::remove_file(&file);
                self.log_info(format!(
                    "Discarded the autosaved changes in {}",
                    file.display()
                ));
            }
            _ => {}
        }
    }

    fn open_project(&mut self, path: &Path) {
        match ProjectSession::read(path) {
            Ok(project) => {
                self.session
                    .replace(project, Some(path.to_path_buf()), false);
                self.focus = Focus::Selection;
                self.log_info(format!("Opened project {}", path.display()));
                if let Some(e) = self.recent.add(path) {
                    let t = self.now_s();
                    self.log.push(t, Severity::Warning, e);
                }
                if let Some(w) = self.session.part_warning() {
                    let t = self.now_s();
                    self.log.notify(t, Severity::Warning, w);
                }
                self.recovery = pending_recovery(Some(path), &self.session.data_dir);
                self.load_project_part();
            }
            Err(e) => {
                let kept = " (the open project is unchanged)";
                let t = self.now_s();
                self.log.notify(
                    t,
                    Severity::Error,
                    format!("Could not open project {e}{kept}"),
                );
            }
        }
    }

    /// Load the part the project references, unless it is the one loaded.
    fn load_project_part(&mut self) {
        let wanted = self.session.project.part.as_ref().map(|p| p.path.clone());
        let loaded = self
            .document
            .as_ref()
            .and_then(|d| part_file(&d.part.path).map(Path::to_path_buf));
        if wanted == loaded && self.document.is_some() {
            return;
        }
        match wanted {
            Some(path) => self.start_load(path),
            None => self.start_default_load(),
        }
    }

    /// After an edit, undo or redo: follow the part reference, keep the focus valid, and write the
    /// tool library when the tools changed.
    fn after_document_change(&mut self, tools_before: &(Vec<ToolEntry>, Option<usize>)) {
        let project = &self.session.project;
        if let Focus::Tool(i) = self.focus
            && i >= project.tools.len()
        {
            self.focus = Focus::Selection;
        }
        if let Focus::Operation(i) = self.focus
            && i >= project.operations.len()
        {
            self.focus = Focus::Selection;
        }
        if (&project.tools, project.selected_tool) != (&tools_before.0, tools_before.1) {
            self.library.tools.clone_from(&project.tools);
            self.library.default_tool = project.selected_tool;
            let path = library_path(&self.session.data_dir);
            if let Err(e) = self.library.save(&path) {
                let t = self.now_s();
                self.log
                    .push(t, Severity::Warning, format!("Tool library not saved: {e}"));
            }
        }
        self.load_project_part();
    }

    /// Write the recovery file when the project has had unsaved changes for the autosave
    /// interval.
    pub(super) fn autosave_if_due(&mut self) {
        if !self.session.autosave_due() {
            if self.session.is_dirty() {
                self.ctx.request_repaint_after(self.session.autosave_every);
            }
            return;
        }
        match self.session.autosave() {
            Ok(file) => self.log_info(format!("Autosaved to {}", file.display())),
            Err(e) => {
                let t = self.now_s();
                self.log
                    .push(t, Severity::Warning, format!("Autosave failed: {e}"));
            }
        }
    }
}
