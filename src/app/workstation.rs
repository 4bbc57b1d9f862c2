//! The workstation: owns the project session (document, history, file), the loaded part, the
//! viewport state, the log and the background jobs; lays out the panels each frame; applies the
//! commands they return in one place ([`Workstation::apply`], with the project commands in
//! `project_commands`; operations, simulation, the posted program and the dialogs in their own
//! submodules).

mod dialogs;
mod operations;
mod program;
mod project_commands;
mod reduction;
mod simulation;

pub use simulation::ShownSimulation;

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::command::Command;
use super::document::{Document, Selection};
use super::document_loader::{LoadError, LoadedPart, load_default_part, load_part};
use super::file_chooser::{ChooserPurpose, FileChooser};
use super::file_dialog::{DialogOutcome, OpenDialog, SaveDialog, SavePurpose};
use super::job::{Job, JobPoll};
use super::message_log::MessageLog;
use super::panels::grouped;
use super::panels::log_panel::log_ui;
use super::panels::menu_bar::{UndoLabels, ViewFlags, menu_bar_ui, shortcuts};
use super::panels::playback::playback_ui;
use super::panels::project_dialogs::recovery_ui;
use super::panels::project_tree::project_tree_ui;
use super::panels::properties::{Focus, Forms, PropertiesView, properties_ui};
use super::panels::status_bar::{StatusInfo, status_bar_ui};
use super::project_session::{AUTOSAVE_EVERY, ProjectSession, default_data_dir};
use super::recent_files::RecentFiles;
use super::scalar_field::{CurvatureField, ScalarField, curvature_field, has_surfaces};
use super::theme;
use super::tool_library::{ToolLibrary, library_path};
use super::viewport::picking::SurfacePick;
use super::viewport::{ViewportExtras, ViewportState, viewport_ui};
use crate::diagnostics::Severity;
use crate::project::Project;
use crate::render::DataId;
use dialogs::overlays_ui;

type LoadJob = Job<Result<LoadedPart, LoadError>>;
/// A curvature job: the render id of the document it is for, and the field.
type FieldJob = (DataId, Job<Result<CurvatureField, ()>>);

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
    document: Option<Document>,
    viewport: ViewportState,
    log: MessageLog,
    load_job: Option<LoadJob>,
    field_job: Option<FieldJob>,
    dialog: OpenDialog,
    recent: RecentFiles,
    started: Instant,
    next_data_id: DataId,
    render_problems: Option<Arc<Mutex<Vec<String>>>>,
    ctx: egui::Context,
    session: ProjectSession,
    library: ToolLibrary,
    focus: Focus,
    forms: Forms,
    ops: operations::Operations,
    sims: simulation::Simulations,
    reductions: reduction::Reductions,
    programs: program::Programs,
    save_dialog: SaveDialog,
    pick: Option<SurfacePick>,
    /// The in-window file chooser, while it is open.
    chooser: Option<FileChooser>,
    /// A recovery file to offer (Recover / Discard).
    recovery: Option<PathBuf>,
    title: String,
    /// A command that would discard unsaved changes, waiting for Save / Discard / Cancel.
    unsaved: Option<Command>,
    /// The command to run once the project is saved (Save answered, Save As asked for a path).
    after_save: Option<Command>,
    /// The command being applied was confirmed (no unsaved-changes question).
    confirmed: bool,
    /// Closing the window was confirmed (or nothing was unsaved).
    quit_confirmed: bool,
    /// The camera of an opened project, applied once its part is loaded.
    restore_view: Option<crate::project::ViewState>,
    /// The profile editor's window.
    profile_editor: super::profile_editor::ProfileEditor,
    /// The operator panel's window.
    operator_panel: super::operator_panel::OperatorPanel,
    /// The cutting-forces window.
    forces: super::forces::ForcesWindow,
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
        let mut ws = Self {
            document: None,
            viewport: ViewportState::default(),
            log: MessageLog::default(),
            load_job: None,
            field_job: None,
            dialog: if native {
                OpenDialog::default()
            } else {
                OpenDialog::without_native()
            },
            recent: config.recent,
            started: Instant::now(),
            next_data_id: 1,
            render_problems: render_state.map(super::viewport::bridge::install),
            ctx: ctx.clone(),
            session: ProjectSession::new(project, config.data_dir, config.autosave_every),
            library,
            focus: Focus::Selection,
            forms: Forms::default(),
            ops: operations::Operations::new(),
            sims: simulation::Simulations::default(),
            reductions: reduction::Reductions::default(),
            programs: program::Programs::default(),
            save_dialog: if native {
                SaveDialog::default()
            } else {
                SaveDialog::without_native()
            },
            pick: None,
            chooser: None,
            recovery: None,
            title: String::new(),
            unsaved: None,
            after_save: None,
            confirmed: false,
            quit_confirmed: false,
            restore_view: None,
            profile_editor: super::profile_editor::ProfileEditor::new(),
            operator_panel: super::operator_panel::OperatorPanel::new(),
            forces: super::forces::ForcesWindow::default(),
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
                ws.recovery = super::project_session::pending_recovery(None, &ws.session.data_dir);
            }
        }
        ws
    }

    /// The profile editor (2D profiles and ball electrodes).
    #[must_use]
    pub fn profile_editor(&mut self) -> &mut super::profile_editor::ProfileEditor {
        &mut self.profile_editor
    }

    /// The operator panel of the virtual control.
    #[must_use]
    pub fn operator_panel(&mut self) -> &mut super::operator_panel::OperatorPanel {
        &mut self.operator_panel
    }

    /// The cutting-forces window.
    pub fn forces(&mut self) -> &mut super::forces::ForcesWindow {
        &mut self.forces
    }

    /// The active operation (the one inspected last), if any.
    #[must_use]
    pub fn active_operation(&self) -> Option<usize> {
        self.ops.active
    }

    /// The loaded part.
    #[must_use]
    pub fn document(&self) -> Option<&Document> {
        self.document.as_ref()
    }

    /// The project document with its history and file.
    #[must_use]
    pub fn session(&self) -> &ProjectSession {
        &self.session
    }

    /// The tool library (what a new project starts with; saved in the data folder).
    #[must_use]
    pub fn library(&self) -> &ToolLibrary {
        &self.library
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
        self.recovery.as_deref()
    }

    /// The window title (project name, `*` when there are unsaved changes).
    #[must_use]
    pub fn title(&self) -> String {
        self.session.title()
    }

    /// Is the curvature field being computed?
    #[must_use]
    pub fn is_computing_field(&self) -> bool {
        self.field_job.is_some()
    }

    /// The log.
    #[must_use]
    pub fn log(&self) -> &MessageLog {
        &self.log
    }

    /// Is a file being loaded?
    #[must_use]
    pub fn is_loading(&self) -> bool {
        self.load_job.is_some()
    }

    fn now_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    fn log_info(&mut self, text: impl Into<String>) {
        let t = self.now_s();
        self.log.push(t, Severity::Info, text);
    }

    /// Apply one command. The only place where the document and the workstation state change.
    pub fn apply(&mut self, command: Command) {
        if self.must_ask_first(&command) {
            self.unsaved = Some(command);
            return;
        }
        match command {
            Command::OpenDialog => {
                let start = self
                    .document
                    .as_ref()
                    .and_then(|d| d.part.path.parent().map(Path::to_path_buf));
                let ctx = self.ctx.clone();
                if !self
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
                    self.start_load(path);
                }
            }
            Command::OpenDefaultPart => self.start_default_load(),
            Command::CancelJob => {
                if self.cancel_calculation()
                    || self.cancel_simulation()
                    || self.cancel_post()
                    || self.cancel_reduction()
                {
                } else if let Some(job) = self.load_job.take() {
                    self.cancel_job(&job);
                } else if let Some((_, job)) = self.field_job.take() {
                    self.cancel_job(&job);
                    self.viewport.scalar_field = None;
                }
            }
            Command::Quit => {
                self.quit_confirmed = true;
                self.ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
            Command::FitAll => self.viewport.fit(self.document.as_ref()),
            Command::StandardView(v) => self.viewport.set_view(v, self.document.as_ref()),
            Command::SetProjection(p) => self.viewport.set_projection(p),
            Command::SetEdges(on) => self.viewport.show_edges = on,
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
            Command::OpenProfileEditor => self.profile_editor.open = true,
            Command::OpenOperatorPanel => self.operator_panel.open = true,
            Command::OpenForces => self.forces.open = true,
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
            | Command::Simulate(_)
            | Command::SimulateActive
            | Command::SimulateToPlayback
            | Command::PostActive
            | Command::OpenMachineFileDialog
            | Command::ExportProgramDialog
            | Command::ExportProgramTo(_)
            | Command::SetStockVisible(_)
            | Command::SetDeviationBand(_)
            | Command::PickPose(_)
            | Command::SetPathColouring(_)
            | Command::SetShowAllPaths(_)
            | Command::SetShowAxisVectors(_)
            | Command::CompareOperations
            | Command::Playback(_) => self.apply_operation(command),
            Command::OpenReductionView
            | Command::Reduce(_)
            | Command::SetReductionVisible(_)
            | Command::ExportReductionDialog
            | Command::ExportReductionTo(_) => self.apply_reduction(command),
        }
    }

    /// Forget everything derived from the project or part being replaced: computed paths,
    /// playback, simulations, posted programs and reductions (their jobs are cancelled). View
    /// preferences (path colouring, all paths, axis vectors, playback speed) stay.
    fn reset_derived(&mut self) {
        self.ops.cancel_silently();
        self.sims.cancel_silently();
        self.programs.cancel_silently();
        self.reductions.cancel_silently();
        let old = std::mem::replace(&mut self.ops, operations::Operations::new());
        self.ops.colouring = old.colouring;
        self.ops.show_all = old.show_all;
        self.ops.show_axes = old.show_axes;
        self.ops.speed = old.speed;
        self.ops.next_id = old.next_id;
        self.sims = simulation::Simulations::default();
        self.programs = program::Programs::default();
        self.reductions.forget_result();
        self.pick = None;
    }

    /// Show `field` on the part, computing the curvatures first when needed.
    fn set_scalar_field(&mut self, field: Option<ScalarField>) {
        self.viewport.scalar_field = field;
        let Some(doc) = &self.document else { return };
        if field.is_none() || doc.curvature.is_some() || self.field_job.is_some() {
            return;
        }
        if !has_surfaces(&doc.part) {
            self.log_info("Curvature needs the exact surfaces: open a STEP part");
            return;
        }
        let part = doc.part.clone();
        let id = doc.ids[0];
        let ctx = self.ctx.clone();
        self.field_job = Some((
            id,
            Job::spawn(
                "Evaluating curvature",
                move |progress| curvature_field(&part, progress),
                move || ctx.request_repaint(),
            ),
        ));
    }

    fn start_load(&mut self, path: PathBuf) {
        if let Some(old) = self.load_job.take() {
            old.cancel();
        }
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        self.log_info(format!("Opening {}", path.display()));
        let ctx = self.ctx.clone();
        let worker_path = path;
        self.load_job = Some(Job::spawn(
            format!("Opening {name}"),
            move |progress| load_part(&worker_path, progress),
            move || ctx.request_repaint(),
        ));
    }

    fn start_default_load(&mut self) {
        if let Some(old) = self.load_job.take() {
            old.cancel();
        }
        self.log_info("Opening the default part (bicubic-hills, embedded)");
        let ctx = self.ctx.clone();
        self.load_job = Some(Job::spawn(
            "Opening the default part",
            load_default_part,
            move || ctx.request_repaint(),
        ));
    }

    /// Collect finished work: the load job, the file dialog, renderer problems.
    fn poll_background(&mut self) {
        if let Some(job) = &self.load_job {
            match job.poll() {
                JobPoll::Running => self.ctx.request_repaint_after(Duration::from_millis(100)),
                JobPoll::Done(result) => {
                    let elapsed = job.started.elapsed().as_secs_f64();
                    self.load_job = None;
                    self.finish_load(result, elapsed);
                }
                JobPoll::Lost => {
                    self.load_job = None;
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
        self.poll_sim_job();
        self.poll_post_job();
        self.poll_reduction_job();
        self.autosave_if_due();
        if self.dialog.is_waiting() {
            self.ctx.request_repaint_after(Duration::from_millis(250));
        }
        match self.dialog.poll() {
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
        if self.save_dialog.is_waiting() {
            self.ctx.request_repaint_after(Duration::from_millis(250));
        }
        let saved = self.save_dialog.poll();
        self.after_save_dialog(saved);
        let problems: Vec<String> = self
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
            self.ctx.request_repaint_after(Duration::from_millis(250));
        }
    }

    fn poll_field_job(&mut self) {
        let Some((id, job)) = &self.field_job else {
            return;
        };
        let id = *id;
        let outcome = match job.poll() {
            JobPoll::Running => {
                self.ctx.request_repaint_after(Duration::from_millis(100));
                return;
            }
            JobPoll::Done(r) => r.ok(),
            JobPoll::Lost => None,
        };
        let elapsed = job.started.elapsed().as_secs_f64();
        self.field_job = None;
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

    fn finish_load(&mut self, result: Result<LoadedPart, LoadError>, elapsed_s: f64) {
        let t = self.now_s();
        match result {
            Ok(part) => {
                for d in &part.diagnostics {
                    self.log
                        .push(t, d.severity, format!("{}: {d}", part.path.display()));
                }
                let summary = format!(
                    "Opened {} ({}, {} triangles) in {elapsed_s:.2} s",
                    part.path.display(),
                    part.format,
                    grouped(part.mesh.triangles.len())
                );
                // The embedded default part has no file to reopen.
                if part.path.is_file()
                    && let Some(e) = self.recent.add(&part.path)
                {
                    self.log.push(t, Severity::Warning, e);
                }
                // Referencing the new part is an undoable edit, applied once the part is the
                // loaded one (so the edit does not start another load).
                let part_edit = self.session.part_edit(&part.path);
                let id = self.next_data_id;
                self.next_data_id += 2;
                if let Some((_, job)) = self.field_job.take() {
                    job.cancel();
                }
                if self.document.is_some() {
                    // Paths, simulations and programs of the old part go with it.
                    self.reset_derived();
                }
                self.document = Some(Document::new(part, id));
                self.pick = None;
                self.focus = Focus::Selection;
                self.viewport.fit_requested = true;
                if let Some(view) = self.restore_view.take() {
                    self.apply_view(view);
                }
                self.log.push(t, Severity::Info, summary);
                if let Some(doc) = &self.document
                    && let Err(e) = self.session.project.check_faces(doc.part.faces.len())
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
                .calc_status()
                .or_else(|| self.sim_status())
                .or_else(|| self.post_status())
                .or_else(|| self.reduction_status())
                .or_else(|| self.load_job.as_ref().map(job_status))
                .or_else(|| self.field_job.as_ref().map(|(_, j)| job_status(j))),
            document: self.document.as_ref().map(|d| {
                format!(
                    "{} · {} triangles",
                    d.part.name,
                    grouped(d.part.mesh.triangles.len())
                )
            }),
        }
    }

    /// Lay out one frame and apply what it asked for.
    pub fn frame_ui(&mut self, ui: &mut egui::Ui) {
        self.poll_background();
        let dt = ui.ctx().input(|i| f64::from(i.stable_dt));
        self.ops.hover_pose = None;
        self.tick_playback(dt);
        let mut commands = Vec::new();
        let ctx = ui.ctx().clone();
        self.ctx = ctx.clone();
        self.on_close_request(&ctx);
        shortcuts(&ctx, &mut commands);
        let title = self.session.title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .collect()
        });
        if let Some(path) = dropped.into_iter().next() {
            commands.push(Command::Open(path));
        }

        let flags = ViewFlags {
            projection: self.viewport.camera.projection,
            edges: self.viewport.show_edges,
            grid: self.viewport.options.grid,
            scalar_field: self.viewport.scalar_field,
            fields_available: self
                .document
                .as_ref()
                .is_some_and(|d| has_surfaces(&d.part)),
            path_colouring: self.ops.colouring,
            all_paths: self.ops.show_all,
            axis_vectors: self.ops.show_axes,
            stock: self.sims.visible,
            stock_available: self.sims.shown.is_some(),
            has_faces: self
                .document
                .as_ref()
                .is_some_and(|d| !d.part.faces.is_empty()),
        };
        let undo = UndoLabels {
            undo: self.session.history.undo_label(),
            redo: self.session.history.redo_label(),
        };
        egui::Panel::top("menu bar").show(ui, |ui| {
            menu_bar_ui(ui, &self.recent, flags, undo, &mut commands);
        });
        let status = self.status();
        egui::Panel::bottom("status bar")
            .exact_size(26.0)
            .show(ui, |ui| status_bar_ui(ui, &status, &mut commands));
        egui::Panel::bottom("log")
            .resizable(true)
            .default_size(190.0)
            .size_range(60.0..=700.0)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    let dock = &mut self.programs.dock;
                    ui.selectable_value(dock, program::DockTab::Log, "Log");
                    ui.selectable_value(dock, program::DockTab::Gcode, "G-code");
                    ui.selectable_value(dock, program::DockTab::Motion, "Motion");
                });
                match self.programs.dock {
                    program::DockTab::Log => log_ui(ui, &self.log, &mut commands),
                    program::DockTab::Gcode => self.gcode_tab_ui(ui, &mut commands),
                    program::DockTab::Motion => self.motion_tab_ui(ui, &mut commands),
                }
            });
        egui::Panel::left("project tree")
            .resizable(true)
            .default_size(250.0)
            .size_range(160.0..=500.0)
            .show(ui, |ui| {
                project_tree_ui(
                    ui,
                    self.document.as_ref(),
                    &self.session.project,
                    self.focus,
                    &mut commands,
                );
            });
        let mut forms = std::mem::take(&mut self.forms);
        egui::Panel::right("properties")
            .resizable(true)
            .default_size(290.0)
            .size_range(180.0..=520.0)
            .show(ui, |ui| {
                let operation = match self.focus {
                    Focus::Operation(i) => Some(self.operation_view(i)),
                    _ => None,
                };
                let view = PropertiesView {
                    focus: self.focus,
                    document: self.document.as_ref(),
                    project: &self.session.project,
                    pick: self.pick.as_ref(),
                    operation,
                };
                properties_ui(ui, &view, &mut forms, &mut commands);
            });
        self.forms = forms;
        if let Some(view) = self.playback_view() {
            egui::Panel::bottom("playback")
                .exact_size(30.0)
                .show(ui, |ui| playback_ui(ui, &view, &mut commands));
        }
        let (paths, legend) = self.path_instances();
        let mut viewport = std::mem::take(&mut self.viewport);
        // The tool stands at the pose under the pointer in a plot, else the picked one, else the
        // playback's (playback clears the pick); the marker at program zero.
        viewport.tool_pose = self.active_result().and_then(|r| {
            let i = self.tool_pose_index()?;
            let p = r.toolpath().poses.get(i)?;
            Some(super::viewport::ToolPose {
                tip: p.tip,
                axis: p.axis,
                cutter: r.cutter.clone(),
            })
        });
        viewport.work_offset = Some(glam::DVec3::from_array(
            self.session.project.setup.origin_mm,
        ));
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let rect = ui.available_rect_before_wrap();
            let up_to = self.playback_pose();
            let stock = self.stock_instance();
            let reduced = self.reduction_instance();
            // Over the simulated stock the path would hide the deviation map: it is drawn only
            // while playing back.
            let mut paths = if stock.is_some() && up_to.is_none() {
                Vec::new()
            } else {
                paths
            };
            paths.extend(self.collision_instance());
            // The reduced surface replaces the part (and the stock) while it is shown.
            let (shown_mesh, legend_title) = match (reduced, stock) {
                (Some(r), _) => (Some(r), "Reduction error, model − part (mm)"),
                (None, s) => (s, "Stock deviation (mm)"),
            };
            let extras = ViewportExtras {
                hide_part: shown_mesh.is_some(),
                stock_legend: shown_mesh
                    .as_ref()
                    .map(|(_, m)| (legend_title.to_string(), *m)),
                meshes: shown_mesh.into_iter().map(|(m, _)| m).collect(),
                paths,
                path_legend: legend,
                pick_path: self.active_result().map(|r| (r.toolpath(), up_to)),
            };
            viewport_ui(
                ui,
                &mut viewport,
                self.document.as_ref(),
                extras,
                &mut commands,
            );
            overlays_ui(
                ui,
                rect,
                &self.log,
                ctx.input(|i| !i.raw.hovered_files.is_empty()),
            );
        });
        self.viewport = viewport;
        self.compare_ui(&ctx, &mut commands);
        self.reduction_ui(&ctx, &mut commands);
        self.profile_editor.window(&ctx);
        if self.operator_panel.open {
            let mut panel = std::mem::take(&mut self.operator_panel);
            panel.window(&ctx, &self.panel_source());
            self.operator_panel = panel;
        }
        let mut forces = std::mem::take(&mut self.forces);
        forces.window(&ctx, self, &mut commands);
        self.forces = forces;
        self.chooser_ui(&ctx);
        self.unsaved_ui(&ctx);
        if let Some(recovery) = &self.recovery
            && let Some(answer) = recovery_ui(&ctx, recovery, self.session.path.as_deref())
        {
            commands.push(answer);
        }
        for c in commands {
            self.apply(c);
        }
    }
}

impl Workstation {
    /// Ask `job`'s worker to stop and say so in the log.
    fn cancel_job<T: Send + 'static>(&mut self, job: &Job<T>) {
        job.cancel();
        let t = self.now_s();
        self.log
            .push(t, Severity::Warning, format!("{} cancelled", job.label));
    }

    /// A background job's outcome once it has ended: `Some(Some(result))`, or `Some(None)` when
    /// the worker stopped without one; `None` while it runs (a repaint is then asked for, so the
    /// result is collected soon after it arrives).
    fn finished<T: Send + 'static>(&self, job: &Job<T>) -> Option<Option<T>> {
        match job.poll() {
            JobPoll::Running => {
                self.ctx.request_repaint_after(Duration::from_millis(100));
                None
            }
            JobPoll::Done(r) => Some(Some(r)),
            JobPoll::Lost => Some(None),
        }
    }
}

/// A job as the status bar shows it: label, fraction done, seconds running.
fn job_status<T>(job: &Job<T>) -> (String, f64, f64) {
    (
        job.label.clone(),
        job.progress.fraction(),
        job.started.elapsed().as_secs_f64(),
    )
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
