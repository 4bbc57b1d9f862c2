//! The workstation's state split by lifetime.
//!
//! - [`Persisted`]: what is written to files and read back: the project document with its undo
//!   history and file (the project file and its recovery file), the tool library
//!   (`tools.toml` in the data folder) and the recent-files list.
//! - [`Runtime`]: what lives only while the window is open: background jobs, the file dialogs,
//!   the renderer's problem list (GPU side), the egui context, the clock, the render-id counter
//!   and the questions waiting for an answer. Nothing here is saved.
//!
//! The loaded part, the view and the computed paths stay on the workstation beside these two,
//! the features' own state (simulations, posted programs, reductions) in the features; they
//! are rebuilt from the persisted state and the part file.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::super::command::Command;
use super::super::document_loader::{LoadError, LoadedPart};
use super::super::file_chooser::FileChooser;
use super::super::file_dialog::{OpenDialog, SaveDialog};
use super::super::job::JobSlot;
use super::super::project_session::ProjectSession;
use super::super::recent_files::RecentFiles;
use super::super::scalar_field::CurvatureField;
use super::super::state::DockTab;
use super::super::tool_library::ToolLibrary;
use crate::render::DataId;

/// Loading a part.
/// Loading a part; the key says whether the part starts a new project once it has loaded (a
/// part the user opened, not the part of an opened project).
pub(super) type LoadJob = JobSlot<Result<LoadedPart, LoadError>, NewProject>;

/// Whether a loaded part starts a new project.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum NewProject {
    /// The part is the open project's (a project opened, its part reloaded).
    No,
    /// The user opened this part: once it has loaded it starts a new project, so the last
    /// part's stock, operations and machine do not stay on it and Save does not overwrite the
    /// last project's file.
    Yes,
}
/// A curvature job, keyed by the render id of the document it is for.
pub(super) type FieldJob = JobSlot<Result<CurvatureField, ()>, DataId>;

/// What the workstation writes to files and reads back.
pub(super) struct Persisted {
    /// The project document, its undo history and its file.
    pub session: ProjectSession,
    /// The tool library (what a new project starts with).
    pub library: ToolLibrary,
    /// The library as this workstation last read or wrote the file: the base of the merged
    /// save (another workstation's tools added since are kept).
    pub library_base: ToolLibrary,
    /// The recently opened files.
    pub recent: RecentFiles,
}

/// What lives only while the workstation runs.
pub(super) struct Runtime {
    /// The egui context (to wake the UI and send viewport commands).
    pub ctx: egui::Context,
    /// When the workstation started (the log's clock).
    pub started: Instant,
    /// The next render id for a document.
    pub next_data_id: DataId,
    /// Problems the renderer reported from the GPU side, collected each frame.
    pub render_problems: Option<Arc<Mutex<Vec<String>>>>,
    /// Loading a part.
    pub load_job: LoadJob,
    /// Evaluating the curvature field.
    pub field_job: FieldJob,
    /// The native Open dialog.
    pub dialog: OpenDialog,
    /// The native Save dialog.
    pub save_dialog: SaveDialog,
    /// The in-window file chooser, while it is open.
    pub chooser: Option<FileChooser>,
    /// A recovery file to offer (Recover / Discard).
    pub recovery: Option<PathBuf>,
    /// The project file that recovery file belongs to, when it is not the open project's (a
    /// recent project's changes offered at start): Recover makes it the project's file.
    pub recovery_project: Option<PathBuf>,
    /// The window title last sent.
    pub title: String,
    /// A command that would discard unsaved changes, waiting for Save / Discard / Cancel.
    pub unsaved: Option<Command>,
    /// The command to run once the project is saved (Save answered, Save As asked for a path).
    pub after_save: Option<Command>,
    /// The command being applied was confirmed (no unsaved-changes question).
    pub confirmed: bool,
    /// Closing the window was confirmed (or nothing was unsaved).
    pub quit_confirmed: bool,
    /// The camera of an opened project, applied once its part is loaded.
    pub restore_view: Option<crate::project::ViewState>,
    /// Where the save dialog a feature asked for starts (its suggested file).
    pub feature_save_start: Option<PathBuf>,
    /// The features' render ids.
    pub feature_ids: super::super::feature::RenderIds,
    /// The bottom dock's tab.
    pub dock: DockTab,
}

impl Runtime {
    /// Fresh runtime state on `ctx`; the native dialogs are tried when `native`.
    pub fn new(
        ctx: &egui::Context,
        render_problems: Option<Arc<Mutex<Vec<String>>>>,
        native: bool,
    ) -> Self {
        Self {
            ctx: ctx.clone(),
            started: Instant::now(),
            next_data_id: 1,
            render_problems,
            load_job: LoadJob::default(),
            field_job: FieldJob::default(),
            dialog: if native {
                OpenDialog::default()
            } else {
                OpenDialog::without_native()
            },
            save_dialog: if native {
                SaveDialog::default()
            } else {
                SaveDialog::without_native()
            },
            chooser: None,
            recovery: None,
            recovery_project: None,
            title: String::new(),
            unsaved: None,
            after_save: None,
            confirmed: false,
            quit_confirmed: false,
            restore_view: None,
            feature_save_start: None,
            feature_ids: super::super::feature::RenderIds::default(),
            dock: DockTab::Log,
        }
    }
}
