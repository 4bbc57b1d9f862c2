//! The workstation: owns the project session (document, history, file), the loaded part, the
//! viewport state, the log and the background jobs; lays out the panels each frame; applies the
//! commands they return in one place ([`Workstation::apply`], with the project commands in
//! `project_commands`; operations with the playback and the dialogs in their own submodules).
//! The registered features ([`super::features`]) plug in through [`super::feature::Feature`];
//! the bottom dock shows the log and the features' tabs.

mod dialogs;
mod frame;
mod operations;
mod project_commands;
mod state;

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::actions::{Action, actions, shortcuts};
use super::command::Command;
use super::document::{Document, Selection};
use super::document_loader::{LoadError, LoadedPart, load_default_part, load_part};
use super::feature::{
    Feature, FeatureContext, FeatureView, Lent, Notice, OperationResults, SceneParts, ViewSwitch,
    find, find_ref,
};
use super::file_chooser::ChooserPurpose;
use super::file_dialog::{DialogOutcome, SavePurpose};
use super::job::Job;
use super::message_log::MessageLog;
use super::panels::log_panel::log_ui;
use super::panels::menu_bar::{UndoLabels, ViewFlags, menu_bar_ui};
use super::panels::playback::playback_ui;
use super::panels::project_dialogs::recovery_ui;
use super::panels::project_tree::project_tree_ui;
use super::panels::properties::{Forms, PropertiesView, properties_ui};
use super::panels::status_bar::{StatusInfo, status_bar_ui};
use super::project_session::{AUTOSAVE_EVERY, ProjectSession, default_data_dir};
use super::recent_files::RecentFiles;
use super::scalar_field::{ScalarField, curvature_field, has_surfaces};
use super::state::{DockTab, Focus};
use super::theme;
use super::tool_library::{ToolLibrary, library_path};
use super::toolpaths::ComputedOp;
use super::viewport::picking::SurfacePick;
use super::viewport::{ViewportExtras, ViewportState, viewport_ui};
use super::widgets::grouped;
use crate::diagnostics::Severity;
use crate::project::Project;
use dialogs::overlays_ui;
use state::NewProject;

/// Where the workstation keeps its files and how often it autosaves.
#[derive(Clone, Debug)]
pub struct WorkstationConfig {
    /// A part or project to open at start (`None`: the embedded default part).
    pub file: Option<PathBuf>,
    /// The recent-files list.
    pub recent: RecentFiles,
    /// The data folder: the tool library (`tools.toml`) and the untitled project's recovery
    /// file.
    pub data_dir: PathBuf,
    /// Autosave interval of a project with unsaved changes.
    pub autosave_every: Duration,
    /// Try the system's file dialogs (false: always the in-window chooser).
    pub native_dialogs: bool,
}

impl WorkstationConfig {
    /// The user's folders ([`default_data_dir`], the saved recent-files list), autosave every
    /// [`AUTOSAVE_EVERY`].
    #[must_use]
    pub fn user(file: Option<PathBuf>) -> Self {
        Self {
            file,
            recent: RecentFiles::load(),
            data_dir: default_data_dir(),
            autosave_every: AUTOSAVE_EVERY,
            native_dialogs: true,
        }
    }

    /// Folders under `data_dir` only, an unsaved recent-files list, the in-window file chooser
    /// only (tests, scripted runs).
    #[must_use]
    pub fn isolated(file: Option<PathBuf>, data_dir: PathBuf) -> Self {
        Self {
            file,
            recent: RecentFiles::in_memory(),
            data_dir,
            autosave_every: AUTOSAVE_EVERY,
            native_dialogs: false,
        }
    }
}

/// The workstation application.
pub struct Workstation {
    /// What is saved: the project session, the tool library, the recent files.
    saved: state::Persisted,
    /// What lives only while the window is open: jobs, dialogs, GPU problems, pending questions.
    run: state::Runtime,
    document: Option<Document>,
    viewport: ViewportState,
    log: MessageLog,
    focus: Focus,
    forms: Forms,
    ops: operations::Operations,
    pick: Option<SurfacePick>,
    /// The registered features ([`super::features`]).
    features: Vec<Box<dyn Feature>>,
    /// What the features lend one another (gathered after each pass over them).
    lent: Lent,
    /// The menu entries and keyboard shortcuts (the workstation's and the features').
    actions: Vec<Action>,
}

impl Workstation {
    /// A workstation on `ctx`, drawing through `render_state` when eframe runs on wgpu (without
    /// it, everything but the 3D view works), opening `config.file` at once when given.
    #[must_use]
    pub fn new(
        ctx: &egui::Context,
        render_state: Option<&egui_wgpu::RenderState>,
        config: WorkstationConfig,
    ) -> Self {
        theme::apply(ctx);
        let (library, library_error) =
            ToolLibrary::load_or_builtin(&library_path(&config.data_dir));
        let project = new_project(&library);
        let native = config.native_dialogs && super::file_dialog::portal_reachable();
        let features = super::features();
        let mut table = actions();
        table.extend(features.iter().flat_map(|f| f.actions()));
        let mut ws = Self {
            saved: state::Persisted {
                session: ProjectSession::new(project, config.data_dir, config.autosave_every),
                library_base: library.clone(),
                library,
                recent: config.recent,
            },
            run: state::Runtime::new(
                ctx,
                render_state.map(super::viewport::bridge::install),
                native,
            ),
            document: None,
            viewport: ViewportState::default(),
            log: MessageLog::default(),
            focus: Focus::Selection,
            forms: Forms::default(),
            ops: operations::Operations::new(),
            pick: None,
            features,
            lent: Lent::default(),
            actions: table,
        };
        if let Some(e) = library_error {
            let t = ws.now_s();
            ws.log.notify(
                t,
                Severity::Warning,
                format!("Tool library not read, using the default one: {e}"),
            );
        }
        match render_state {
            Some(rs) => {
                let info = rs.adapter.get_info();
                ws.log_info(format!(
                    "Graphics: {} ({:?}, {:?})",
                    info.name, info.backend, info.device_type
                ));
            }
            None => ws.log.push(
                0.0,
                Severity::Error,
                "No wgpu renderer: the 3D viewport is unavailable",
            ),
        }
        match config.file {
            Some(file) => ws.apply(Command::Open(file)),
            None => {
                ws.apply(Command::OpenDefaultPart);
                if let Some((file, project)) = super::project_session::pending_recovery_at_start(
                    &ws.saved.recent.paths,
                    &ws.saved.session.data_dir,
                ) {
                    ws.run.recovery = Some(file);
                    ws.run.recovery_project = project;
                }
            }
        }
        ws
    }

    /// The registered feature of type `T` (one of those [`super::features`] lists).
    #[must_use]
    pub fn feature<T: Feature>(&mut self) -> Option<&mut T> {
        find(&mut self.features)
    }

    /// The registered feature of type `T`, to read.
    #[must_use]
    pub fn feature_ref<T: Feature>(&self) -> Option<&T> {
        find_ref(&self.features)
    }

    /// The active operation (the one inspected last), if any.
    #[must_use]
    pub fn active_operation(&self) -> Option<usize> {
        self.ops.active
    }

    /// How many tool-path line sets the viewport draws now (each shown operation's path, and
    /// the tool-axis vectors when they are on).
    #[must_use]
    pub fn drawn_path_count(&mut self) -> usize {
        self.path_instances().0.len()
    }

    /// The pose of the active operation's path picked last (a click on the path, a finding,
    /// a collision or a G-code line), if any.
    #[must_use]
    pub fn picked_pose(&self) -> Option<usize> {
        self.ops.picked_pose
    }

    /// The loaded part.
    #[must_use]
    pub fn document(&self) -> Option<&Document> {
        self.document.as_ref()
    }

    /// The project document with its history and file.
    #[must_use]
    pub fn session(&self) -> &ProjectSession {
        &self.saved.session
    }

    /// The tool library (what a new project starts with; saved in the data folder).
    #[must_use]
    pub fn library(&self) -> &ToolLibrary {
        &self.saved.library
    }

    /// What the properties panel shows.
    #[must_use]
    pub fn focus(&self) -> Focus {
        self.focus
    }

    /// The viewport's camera.
    #[must_use]
    pub fn camera(&self) -> &crate::render::Camera {
        &self.viewport.camera
    }

    /// The surface point last clicked in the viewport.
    #[must_use]
    pub fn pick(&self) -> Option<&SurfacePick> {
        self.pick.as_ref()
    }

    /// The recovery file being offered, if any.
    #[must_use]
    pub fn pending_recovery(&self) -> Option<&Path> {
        self.run.recovery.as_deref()
    }

    /// The window title (project name, `*` when there are unsaved changes).
    #[must_use]
    pub fn title(&self) -> String {
        self.saved.session.title()
    }

    /// Is the curvature field being computed?
    #[must_use]
    pub fn is_computing_field(&self) -> bool {
        self.run.field_job.is_running()
    }

    /// The log.
    #[must_use]
    pub fn log(&self) -> &MessageLog {
        &self.log
    }

    /// Is a file being loaded?
    #[must_use]
    pub fn is_loading(&self) -> bool {
        self.run.load_job.is_running()
    }

    fn now_s(&self) -> f64 {
        self.run.started.elapsed().as_secs_f64()
    }

    fn log_info(&mut self, text: impl Into<String>) {
        let t = self.now_s();
        self.log.push(t, Severity::Info, text);
    }

    /// Apply one command. The only place where the document and the workstation state change.
    pub fn apply(&mut self, command: Command) {
        if self.must_ask_first(&command) {
            self.run.unsaved = Some(command);
            return;
        }
        // A feature's command is taken by that feature.
        let Some(command) = self.with_features(|features, cx| {
            features.iter_mut().try_fold(command, |c, f| f.apply(c, cx))
        }) else {
            return;
        };
        match command {
            Command::OpenDialog => {
                let start = self
                    .document
                    .as_ref()
                    .and_then(|d| d.part.path.parent().map(Path::to_path_buf));
                let ctx = self.run.ctx.clone();
                if !self
                    .run
                    .dialog
                    .open(start.clone(), move || ctx.request_repaint())
                {
                    self.open_chooser(ChooserPurpose::OpenPart, start);
                }
            }
            Command::Open(path) => {
                if path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case(crate::project::file::EXTENSION))
                {
                    self.apply(Command::OpenProject(path));
                } else {
                    self.start_load(path, NewProject::Yes);
                }
            }
            Command::OpenDefaultPart => self.start_default_load(),
            Command::CancelJob => {
                let cancelled = self
                    .ops
                    .job
                    .cancel()
                    .or_else(|| self.features.iter_mut().find_map(|f| f.cancel()))
                    .or_else(|| self.run.load_job.cancel())
                    .or_else(|| {
                        let label = self.run.field_job.cancel()?;
                        self.viewport.scalar_field = None;
                        Some(label)
                    });
                if let Some(label) = cancelled {
                    let t = self.now_s();
                    self.log
                        .push(t, Severity::Warning, format!("{label} cancelled"));
                }
            }
            Command::Quit => {
                self.run.quit_confirmed = true;
                self.run.ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
            Command::FitAll => self.viewport.fit(self.document.as_ref()),
            Command::StandardView(v) => self.viewport.set_view(v, self.document.as_ref()),
            Command::SetProjection(p) => self.viewport.set_projection(p),
            Command::SetEdges(on) => self.viewport.show_edges = on,
            Command::SetOrientToSetup(on) => self.viewport.orient_to_setup = on,
            Command::SetGrid(on) => self.viewport.options.grid = on,
            Command::Select(selection) => {
                self.focus = Focus::Selection;
                if let Some(doc) = &mut self.document {
                    doc.selection = match selection {
                        Selection::Face(i) if i >= doc.part.faces.len() => Selection::Part,
                        s => s,
                    };
                    // A surface point picked on another face no longer describes the selection.
                    if self
                        .pick
                        .as_ref()
                        .is_some_and(|p| doc.selection != Selection::Face(p.face))
                    {
                        self.pick = None;
                    }
                }
            }
            Command::ClearLog => self.log.entries.clear(),
            // No registered feature took it.
            Command::Feature(_)
            | Command::FeatureFile { .. }
            | Command::PostActive
            | Command::ExportProgramDialog
            | Command::Simulate(_)
            | Command::SimulateActive
            | Command::SimulateToPlayback
            | Command::SetStockVisible(_)
            | Command::SetDeviationBand(_) => {}
            Command::Inspect(focus) => {
                if let Focus::Operation(i) = focus
                    && self.ops.active != Some(i)
                {
                    self.ops.active = Some(i);
                    self.ops.picked_pose = None;
                    self.ops.t_s = None;
                    self.ops.playing = false;
                }
                self.focus = focus;
            }
            Command::SetPick(pick) => self.pick = pick,
            Command::SetScalarField(field) => self.set_scalar_field(field),
            Command::Edit(_)
            | Command::Undo
            | Command::Redo
            | Command::NewProject
            | Command::OpenProjectDialog
            | Command::OpenProject(_)
            | Command::SaveProject
            | Command::SaveProjectAsDialog
            | Command::SaveProjectAs(_)
            | Command::Recover(_)
            | Command::DiscardRecovery(_) => self.apply_project(command),
            Command::AddOperation(_)
            | Command::Calculate(_)
            | Command::CalculateActive
            | Command::OpenMachineFileDialog
            | Command::PickPose(_)
            | Command::PickOperationPose { .. }
            | Command::SetPathShown { .. }
            | Command::SetPathColouring(_)
            | Command::ReplacePath(..)
            | Command::SetShowAllPaths(_)
            | Command::SetShowAxisVectors(_)
            | Command::CompareOperations
            | Command::Playback(_) => self.apply_operation(command),
        }
    }

    /// Forget everything derived from the project or part being replaced: computed paths,
    /// playback, posted programs and the features' results, the simulation among them (their
    /// jobs are cancelled). View preferences (path colouring, all paths, axis vectors, playback speed)
    /// stay.
    fn reset_derived(&mut self) {
        // Replaced job slots drop their jobs, which cancels them without a word.
        let old = std::mem::replace(&mut self.ops, operations::Operations::new());
        self.ops.colouring = old.colouring;
        self.ops.show_all = old.show_all;
        self.ops.show_axes = old.show_axes;
        self.ops.speed = old.speed;
        self.ops.next_id = old.next_id;
        for f in &mut self.features {
            f.reset();
        }
        self.gather_lent();
        self.run.dock = DockTab::Log;
        self.pick = None;
    }

    /// Show `field` on the part, computing the curvatures first when needed.
    fn set_scalar_field(&mut self, field: Option<ScalarField>) {
        self.viewport.scalar_field = field;
        let Some(doc) = &self.document else { return };
        if field.is_none() || doc.curvature.is_some() || self.run.field_job.is_running() {
            return;
        }
        if !has_surfaces(&doc.part) {
            self.log_info("Curvature needs the exact surfaces: open a STEP part");
            return;
        }
        let part = doc.part.clone();
        let id = doc.ids[0];
        self.run.field_job.start(
            id,
            Job::start("Evaluating curvature", &self.run.ctx, move |progress| {
                curvature_field(&part, progress)
            }),
        );
    }

    fn start_load(&mut self, path: PathBuf, starts_project: NewProject) {
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        self.log_info(format!("Opening {}", path.display()));
        self.run.load_job.start(
            starts_project,
            Job::start(format!("Opening {name}"), &self.run.ctx, move |progress| {
                load_part(&path, progress)
            }),
        );
    }

    fn start_default_load(&mut self) {
        self.log_info("Opening the default part (bicubic-hills, embedded)");
        self.run.load_job.start(
            NewProject::No,
            Job::start("Opening the default part", &self.run.ctx, load_default_part),
        );
    }

    /// Collect finished work: the background jobs, the file dialog, renderer problems.
    fn poll_background(&mut self) {
        if let Some(done) = self.run.load_job.poll() {
            match done.result {
                Some(result) => self.finish_load(result, done.elapsed_s, done.key),
                None => {
                    let t = self.now_s();
                    self.log.notify(
                        t,
                        Severity::Error,
                        "Loading failed: the import worker stopped unexpectedly",
                    );
                }
            }
        }
        self.poll_field_job();
        self.poll_calc_job();
        // What a feature lends as it collects its job (a program just posted) the others read
        // from their next call on.
        self.with_features(|features, cx| {
            for f in features {
                f.poll(cx);
            }
        });
        if self.status().job.is_some() {
            // Each job wakes the UI when it ends; this is the fallback (and moves the bar).
            self.run
                .ctx
                .request_repaint_after(Duration::from_millis(100));
        }
        self.autosave_if_due();
        if self.run.dialog.is_waiting() {
            self.run
                .ctx
                .request_repaint_after(Duration::from_millis(250));
        }
        match self.run.dialog.poll() {
            // The question about unsaved changes was asked before the dialog opened.
            DialogOutcome::Picked(path) => self.apply_confirmed(Command::Open(path)),
            DialogOutcome::Unavailable => {
                self.log_info(
                    "The system file dialog did not open (no XDG desktop portal?): using Talas's own file chooser",
                );
                let start = self
                    .document
                    .as_ref()
                    .and_then(|d| d.part.path.parent().map(Path::to_path_buf));
                self.open_chooser(ChooserPurpose::OpenPart, start);
            }
            DialogOutcome::Waiting | DialogOutcome::Cancelled => {}
        }
        if self.run.save_dialog.is_waiting() {
            self.run
                .ctx
                .request_repaint_after(Duration::from_millis(250));
        }
        let saved = self.run.save_dialog.poll();
        self.after_save_dialog(saved);
        let problems: Vec<String> = self
            .run
            .render_problems
            .as_ref()
            .and_then(|p| p.lock().ok().map(|mut l| std::mem::take(&mut *l)))
            .unwrap_or_default();
        for p in problems {
            let t = self.now_s();
            self.log.push(t, Severity::Error, format!("Viewport: {p}"));
        }
        let now = self.now_s();
        self.log.expire(now);
        if !self.log.toasts.is_empty() {
            self.run
                .ctx
                .request_repaint_after(Duration::from_millis(250));
        }
    }

    fn poll_field_job(&mut self) {
        let Some(done) = self.run.field_job.poll() else {
            return;
        };
        let (id, elapsed) = (done.key, done.elapsed_s);
        let outcome = done.result.and_then(Result::ok);
        match (outcome, &mut self.document) {
            (Some(field), Some(doc)) if doc.ids[0] == id => {
                doc.curvature = Some(field);
                self.log_info(format!("Curvature evaluated in {elapsed:.2} s"));
            }
            (Some(_), _) => {}
            (None, _) => {
                let t = self.now_s();
                self.log
                    .notify(t, Severity::Error, "Curvature could not be evaluated");
            }
        }
    }

    fn finish_load(
        &mut self,
        result: Result<LoadedPart, LoadError>,
        elapsed_s: f64,
        starts_project: NewProject,
    ) {
        let t = self.now_s();
        match result {
            Ok(part) => {
                if starts_project == NewProject::Yes {
                    // A part the user opened starts a project of its own (the question about
                    // unsaved changes was asked before it was opened).
                    let data_dir = self.saved.session.data_dir.clone();
                    let every = self.saved.session.autosave_every;
                    self.saved.session =
                        ProjectSession::new(new_project(&self.saved.library), data_dir, every);
                    self.focus = Focus::Selection;
                    self.reset_derived();
                    self.log_info(format!("New project for {}", part.path.display()));
                }
                for d in &part.diagnostics {
                    self.log
                        .push(t, d.severity, format!("{}: {d}", part.path.display()));
                }
                let summary = format!(
                    "Opened {} ({}, {} triangles) in {elapsed_s:.2} s",
                    part.path.display(),
                    part.format,
                    grouped(part.mesh().triangles.len())
                );
                // The embedded default part has no file to reopen.
                if part.path.is_file()
                    && let Some(e) = self.saved.recent.add(&part.path)
                {
                    self.log.push(t, Severity::Warning, e);
                }
                // Referencing the new part is an undoable edit, applied once the part is the
                // loaded one (so the edit does not start another load).
                let part_edit = self.saved.session.part_edit(&part.path);
                let id = self.run.next_data_id;
                self.run.next_data_id += 2;
                self.run.field_job.cancel();
                if self.document.is_some() {
                    // Paths, simulations and programs of the old part go with it.
                    self.reset_derived();
                }
                self.document = Some(Document::new(part, id));
                self.pick = None;
                self.focus = Focus::Selection;
                self.viewport.fit_requested = true;
                if let Some(view) = self.run.restore_view.take() {
                    self.apply_view(view);
                }
                self.log.push(t, Severity::Info, summary);
                if let Some(doc) = &self.document
                    && let Err(e) = self.saved.session.project.check_faces(doc.part.faces.len())
                {
                    self.log.notify(
                        t,
                        Severity::Warning,
                        format!("The project does not fit this part: {e}"),
                    );
                }
                if let Some(edit) = part_edit {
                    self.apply(Command::Edit(edit));
                }
                // The project's calculated paths saved beside it, where still fresh.
                self.restore_saved_paths();
                // Keep showing the chosen field on the new part.
                let field = self.viewport.scalar_field;
                self.set_scalar_field(field);
            }
            Err(LoadError::Cancelled) => self.log.push(t, Severity::Warning, "Loading cancelled"),
            Err(e) => {
                let kept = if self.document.is_some() {
                    " (the open part is unchanged)"
                } else {
                    ""
                };
                self.log
                    .notify(t, Severity::Error, format!("Could not open {e}{kept}"));
            }
        }
    }

    fn status(&self) -> StatusInfo {
        StatusInfo {
            cursor_mm: self.viewport.hover_point,
            job: self
                .ops
                .job
                .status()
                .or_else(|| self.features.iter().find_map(|f| f.job_status()))
                .or_else(|| self.run.load_job.status())
                .or_else(|| self.run.field_job.status()),
            document: self.document.as_ref().map(|d| {
                format!(
                    "{} · {} triangles",
                    d.part.name,
                    grouped(d.part.mesh().triangles.len())
                )
            }),
        }
    }
}

impl Workstation {
    /// What the features may read this frame.
    #[must_use]
    pub fn feature_view(&self) -> FeatureView<'_> {
        let project = &self.saved.session.project;
        let active = self
            .ops
            .active
            .or((!project.operations.is_empty()).then_some(0));
        FeatureView {
            project,
            document: self.document.as_ref(),
            active_operation: active,
            active_setup: match self.focus {
                Focus::Setup(s) => s,
                Focus::Operation(i) => crate::project::setups::setup_of(project, i).unwrap_or(0),
                _ => active
                    .and_then(|i| crate::project::setups::setup_of(project, i))
                    .unwrap_or(0),
            },
            target_operation: self.target_operation(),
            picked_pose: self.ops.picked_pose,
            playback_pose: self.playback_pose(),
            posted: active
                .and_then(|i| Some((project.operations.get(i)?.name(), self.posted(i)?.text()))),
            data_dir: &self.saved.session.data_dir,
            project_path: self.saved.session.path.as_deref(),
            tool_pose: self.tool_pose_index(),
            results: self,
            ids: &self.run.feature_ids,
        }
    }
}

impl Workstation {
    /// Run `f` on the features with a [`FeatureContext`], then carry out what they asked for.
    fn with_features<R>(
        &mut self,
        f: impl FnOnce(&mut [Box<dyn Feature>], &mut FeatureContext<'_>) -> R,
    ) -> R {
        let mut features = std::mem::take(&mut self.features);
        let (out, notices) = {
            let mut cx = FeatureContext::new(self.feature_view(), &self.run.ctx);
            let out = f(&mut features, &mut cx);
            (out, cx.into_notices())
        };
        self.features = features;
        self.gather_lent();
        for n in notices {
            self.carry_out(n);
        }
        out
    }

    /// Do what a feature asked for.
    fn carry_out(&mut self, notice: Notice) {
        match notice {
            Notice::Log {
                severity,
                text,
                toast,
            } => {
                let t = self.now_s();
                if toast {
                    self.log.notify(t, severity, text);
                } else {
                    self.log.push(t, severity, text);
                }
            }
            Notice::SaveDialog {
                purpose,
                suggestion,
            } => {
                self.run.feature_save_start = Some(suggestion);
                self.save_dialog_for(purpose);
            }
            Notice::Switch(ViewSwitch::HideStock) => self.apply(Command::SetStockVisible(false)),
            Notice::Switch(ViewSwitch::RestartPlayback) => {
                self.ops.t_s = None;
                self.ops.playing = false;
            }
            Notice::Switch(ViewSwitch::DockTab(tab)) => self.run.dock = DockTab::Feature(tab),
        }
    }

    /// Gather what the features lend one another (after they changed).
    fn gather_lent(&mut self) {
        let mut lent = Lent::default();
        for f in &self.features {
            f.lend(&mut lent);
        }
        self.lent = lent;
    }

    /// The bottom dock: the log and the features' tabs (the posted program's G-code and motion
    /// plots).
    fn dock_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.run.dock, DockTab::Log, "Log");
            for tab in self.features.iter().flat_map(|f| f.dock_tabs()) {
                ui.selectable_value(&mut self.run.dock, DockTab::Feature(tab), *tab);
            }
        });
        let DockTab::Feature(tab) = self.run.dock else {
            log_ui(ui, &self.log, commands);
            return;
        };
        let mut features = std::mem::take(&mut self.features);
        let view = self.feature_view();
        if let Some(f) = features.iter_mut().find(|f| f.dock_tabs().contains(&tab)) {
            f.dock_ui(tab, ui, &view, commands);
        }
        self.features = features;
        self.gather_lent();
    }
}

impl OperationResults for Workstation {
    fn operation_result(&self, index: usize) -> Option<(&ComputedOp, bool)> {
        Workstation::operation_result(self, index)
    }

    fn planned_clock(&self, index: usize) -> Option<&[f64]> {
        Workstation::planned_clock(self, index)
    }
}

/// A new project: the default part and the tool library's tools, its default tool selected.
fn new_project(library: &ToolLibrary) -> Project {
    let mut project = Project::default();
    if !library.tools.is_empty() {
        project.tools.clone_from(&library.tools);
        project.selected_tool = library.default_selection();
    }
    project
}

impl eframe::App for Workstation {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame_ui(ui);
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        egui::Color32::from_rgb(30, 32, 36).to_normalized_gamma_f32()
    }
}
