//! The project commands: document edits through the undo history, new/open/save/save as,
//! autosave and crash recovery, and keeping the tool library file in step with the tools.

use std::f32::consts::FRAC_PI_2;
use std::path::Path;

use super::super::command::Command;
use super::super::file_chooser::ChooserPurpose;
use super::super::project_session::{ProjectSession, part_file, pending_recovery};
use super::super::state::Focus;
use super::super::tool_library::library_path;
use super::{Workstation, new_project};
use crate::diagnostics::Severity;
use crate::project::{Edit, Project, ToolEntry, ViewState};
use crate::render::Projection;

impl Workstation {
    /// Apply a project command (see [`Workstation::apply`]).
    pub(super) fn apply_project(&mut self, command: Command) {
        let tools_before = (
            self.saved.session.project.tools.clone(),
            self.saved.session.project.selected_tool,
        );
        match command {
            Command::Edit(edit) => {
                let what = edit.describe();
                match self.saved.session.edit(edit) {
                    Ok(()) => self.after_document_change(&tools_before),
                    Err(e) => {
                        let t = self.now_s();
                        self.log
                            .notify(t, Severity::Warning, format!("{what} not applied: {e}"));
                    }
                }
            }
            Command::Undo => {
                let label = self.saved.session.undo();
                self.log_info(label.map_or("Nothing to undo".into(), |l| format!("Undo: {l}")));
                self.after_document_change(&tools_before);
            }
            Command::Redo => {
                let label = self.saved.session.redo();
                self.log_info(label.map_or("Nothing to redo".into(), |l| format!("Redo: {l}")));
                self.after_document_change(&tools_before);
            }
            Command::NewProject => {
                let data_dir = self.saved.session.data_dir.clone();
                let every = self.saved.session.autosave_every;
                self.saved.session =
                    ProjectSession::new(new_project(&self.saved.library), data_dir, every);
                self.focus = Focus::Selection;
                self.reset_derived();
                self.log_info("New project");
                self.load_project_part();
                // A new project starts from the default view of its part.
                self.viewport
                    .set_view(crate::render::StandardView::Iso, self.document.as_ref());
            }
            Command::OpenProjectDialog => {
                let start = self
                    .saved
                    .session
                    .path
                    .as_ref()
                    .and_then(|p| p.parent().map(Path::to_path_buf));
                let ctx = self.run.ctx.clone();
                if !self
                    .run
                    .dialog
                    .open(start.clone(), move || ctx.request_repaint())
                {
                    self.open_chooser(ChooserPurpose::OpenProject, start);
                }
            }
            Command::SaveProjectAsDialog => {
                self.save_dialog_for(super::SavePurpose::Project);
            }
            Command::OpenProject(path) => self.open_project(&path),
            Command::SaveProject => match self.saved.session.path.clone() {
                Some(path) => self.apply(Command::SaveProjectAs(path)),
                None => self.apply(Command::SaveProjectAsDialog),
            },
            Command::SaveProjectAs(path) => self.save_project_as(&path),
            Command::Recover(file) => {
                self.run.recovery = None;
                let owner = self.run.recovery_project.take();
                match Project::load(&file) {
                    Ok(project) => {
                        // The recovered project keeps its file (if it had one, or the recent
                        // project the changes were offered for at start): saving writes
                        // there, and the recovery file goes.
                        let path = owner.or_else(|| self.saved.session.path.clone());
                        self.saved.session.replace(project, path, true);
                        self.focus = Focus::Selection;
                        self.reset_derived();
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
                self.run.recovery = None;
                self.run.recovery_project = None;
                let _ = std::fs::remove_file(&file);
                self.log_info(format!(
                    "Discarded the autosaved changes in {}",
                    file.display()
                ));
            }
            _ => {}
        }
    }

    /// Save to `path`: an untitled project takes the file's name, the current camera is written,
    /// and a command waiting for the save runs once it succeeded.
    fn save_project_as(&mut self, path: &Path) {
        let untitled = Project::default().name;
        if self.saved.session.project.name == untitled
            && let Some(stem) = path.file_stem().map(|s| s.to_string_lossy().into_owned())
            && !stem.is_empty()
        {
            let _ = self.saved.session.edit(Edit::Rename(stem));
        }
        self.saved.session.project.view = self.view_state();
        let waiting = self.run.after_save.take();
        match self.saved.session.save_as(path) {
            Ok(()) => {
                self.log_info(format!("Saved {}", path.display()));
                self.save_paths(path);
                if let Some(e) = self.saved.recent.add(path) {
                    let t = self.now_s();
                    self.log.push(t, Severity::Warning, e);
                }
                if let Some(command) = waiting {
                    self.apply_confirmed(command);
                }
            }
            Err(e) => {
                let t = self.now_s();
                self.log
                    .notify(t, Severity::Error, format!("Not saved: {e}"));
            }
        }
    }

    /// The camera as the project keeps it.
    fn view_state(&self) -> ViewState {
        let c = &self.viewport.camera;
        ViewState {
            target_mm: c.target.as_dvec3().to_array(),
            distance_mm: f64::from(c.distance),
            yaw_rad: f64::from(c.yaw_rad),
            pitch_rad: f64::from(c.pitch_rad),
            orthographic: c.projection == Projection::Orthographic,
        }
    }

    /// Show the part from the project's camera (a project saved with the default camera, or with
    /// one that is not finite, is fitted instead).
    pub(super) fn apply_view(&mut self, v: ViewState) {
        self.viewport.fit(self.document.as_ref());
        let finite = v.target_mm.iter().all(|x| x.is_finite())
            && [v.distance_mm, v.yaw_rad, v.pitch_rad]
                .iter()
                .all(|x| x.is_finite())
            && v.distance_mm > 0.0;
        if v == ViewState::default() || !finite {
            return;
        }
        let c = &mut self.viewport.camera;
        c.target = glam::DVec3::from_array(v.target_mm).as_vec3();
        c.distance = v.distance_mm as f32;
        c.yaw_rad = v.yaw_rad as f32;
        c.pitch_rad = (v.pitch_rad as f32).clamp(-FRAC_PI_2, FRAC_PI_2);
        c.projection = if v.orthographic {
            Projection::Orthographic
        } else {
            Projection::Perspective
        };
    }

    fn open_project(&mut self, path: &Path) {
        match ProjectSession::read(path) {
            Ok((project, warnings)) => {
                for w in warnings {
                    let t = self.now_s();
                    self.log.push(t, Severity::Warning, w);
                }
                self.run.restore_view = Some(project.view);
                self.saved
                    .session
                    .replace(project, Some(path.to_path_buf()), false);
                self.focus = Focus::Selection;
                self.reset_derived();
                self.log_info(format!("Opened project {}", path.display()));
                if let Some(e) = self.saved.recent.add(path) {
                    let t = self.now_s();
                    self.log.push(t, Severity::Warning, e);
                }
                if let Some(w) = self.saved.session.part_warning() {
                    let t = self.now_s();
                    self.log.notify(t, Severity::Warning, w);
                }
                self.run.recovery = pending_recovery(Some(path), &self.saved.session.data_dir);
                self.run.recovery_project = None;
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
        let wanted = self
            .saved
            .session
            .project
            .part
            .as_ref()
            .map(|p| p.path.clone());
        let loaded = self
            .document
            .as_ref()
            .and_then(|d| part_file(&d.part.path).map(Path::to_path_buf));
        if wanted == loaded && self.document.is_some() {
            if let Some(view) = self.run.restore_view.take() {
                self.apply_view(view);
            }
            return;
        }
        match wanted {
            Some(path) => self.start_load(path, super::state::NewProject::No),
            None => self.start_default_load(),
        }
    }

    /// After an edit, undo or redo: follow the part reference, keep the focus valid, and write the
    /// tool library when the tools changed.
    fn after_document_change(&mut self, tools_before: &(Vec<ToolEntry>, Option<usize>)) {
        let project = &self.saved.session.project;
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
            self.saved.library.tools.clone_from(&project.tools);
            self.saved.library.default_tool = project.selected_tool;
            let path = library_path(&self.saved.session.data_dir);
            match self
                .saved
                .library
                .save_merged(&self.saved.library_base, &path)
            {
                Ok(merged) => {
                    let added = merged
                        .tools
                        .len()
                        .saturating_sub(self.saved.library.tools.len());
                    if added > 0 {
                        self.log_info(format!(
                            "Tool library: {added} tools another workstation saved in {} are kept",
                            path.display()
                        ));
                    }
                    self.saved.library_base = merged.clone();
                    self.saved.library = merged;
                }
                Err(e) => {
                    let t = self.now_s();
                    self.log
                        .notify(t, Severity::Warning, format!("Tool library not saved: {e}"));
                }
            }
        }
        self.load_project_part();
    }

    /// Write the recovery file when the project has had unsaved changes for the autosave
    /// interval.
    pub(super) fn autosave_if_due(&mut self) {
        if !self.saved.session.autosave_due() {
            if self.saved.session.is_dirty() {
                self.run
                    .ctx
                    .request_repaint_after(self.saved.session.autosave_every);
            }
            return;
        }
        match self.saved.session.autosave() {
            Ok(file) => self.log_info(format!("Autosaved to {}", file.display())),
            Err(e) => {
                let t = self.now_s();
                self.log
                    .push(t, Severity::Warning, format!("Autosave failed: {e}"));
            }
        }
    }
}
