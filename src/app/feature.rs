//! Workstation features: a tool window or panel with its own state, commands, background jobs
//! and 3D-scene contribution, plugged into the workstation through the [`Feature`] trait.
//!
//! A feature lives in its own folder (`src/app/<feature>/`) and is registered by one line in
//! [`super::features`]. The workstation then, each frame:
//! 1. offers every [`Command`] to each feature ([`Feature::apply`]) before its own router;
//! 2. polls the features' jobs ([`Feature::poll`]), shows a running one in the status bar
//!    ([`Feature::job_status`]) and cancels it from there ([`Feature::cancel`]);
//! 3. lets each feature draw its windows or panels ([`Feature::ui`]), its section of the
//!    operation editor ([`Feature::operation_ui`]) and its View-menu check boxes
//!    ([`Feature::toggles`]) from a read-only [`FeatureView`] of the workstation, collecting the
//!    commands they return;
//! 4. lets each feature steer the viewport (camera, drawn tool: [`Feature::steer_view`]) and
//!    adds the features' meshes and lines to it ([`Feature::scene`]); one feature may draw a
//!    surface instead of the part ([`SceneParts::instead_of_part`]);
//! 5. shows the features' tabs of the bottom dock ([`Feature::dock_tabs`], [`Feature::dock_ui`])
//!    beside the log, and tells them where the tool was moved on the active path (a pick, a
//!    playback step or seek, the running clock: [`Feature::follow_pose`]).
//!
//! Features are taken out of the workstation while they are called, so what one lends the
//! others (the posted program's run) is gathered into a [`Lent`] snapshot after each pass over
//! them ([`Feature::lend`]: shared pointers, cheap to clone) and read from there through the
//! [`FeatureView`] (`posted`, [`OperationResults::planned_clock`], `tool_pose`); what one lends
//! during a pass the others see from the next pass on.
//!
//! While it applies a command or collects its jobs a feature gets a [`FeatureContext`]: the
//! read-only view, the egui context its jobs wake, fresh render ids (one [`RenderIds`] counter
//! for all features, also through [`FeatureView::next_id`]), and a list of [`Notice`]s
//! (log lines, a save dialog, a view switch such as hiding the stock) that the workstation
//! carries out afterwards, so that no feature reaches into the workstation's fields. A file a
//! feature writes is asked for with [`FeatureContext::ask_save_path`] (its id, title and file
//! types in a [`FeatureSave`]): the system's Save dialog or the in-window chooser, and the
//! chosen path comes back as [`Command::FeatureFile`] with the feature's id ([`chosen_file`]).
//!
//! The features' menu entries and keys join the one table of [`super::actions`]
//! ([`Feature::actions`]); their commands are [`Command::Feature`] with the feature's id, so a
//! new feature needs no new [`Command`] variant. (Every command passes the features first, so
//! a feature may also take one of the workstation's own variants, as the stock simulation
//! takes `Simulate`, or watch one go by, as it watches `ReplacePath`.)

use std::any::Any;
use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::actions::Action;
pub use super::actions::Toggle;
use super::command::{Command, FeatureCommand};
use super::document::Document;
pub use super::file_dialog::FeatureSave;
use super::file_dialog::SavePurpose;
use super::job::JobStatus;
use super::toolpaths::ComputedOp;
use super::viewport::ViewportState;
use crate::diagnostics::Severity;
use crate::project::Project;
use crate::render::{DataId, LineInstance, MeshInstance, ScalarMapping};

/// What a feature may read of the workstation while it draws.
#[derive(Clone, Copy)]
pub struct FeatureView<'a> {
    /// The project document.
    pub project: &'a Project,
    /// The loaded part.
    pub document: Option<&'a Document>,
    /// The active operation (the one played back, posted, simulated), else the first.
    /// The setup in view: the one in focus, or that of the operation in focus or active
    /// (0 when none).
    pub active_setup: usize,
    pub active_operation: Option<usize>,
    /// The operation a menu entry or key acts on: the one in the properties panel, else the
    /// active one, else the first.
    pub target_operation: Option<usize>,
    /// The pose picked on the active operation's path.
    pub picked_pose: Option<usize>,
    /// The pose the playback has reached on the active path (`None`: the whole path shown).
    pub playback_pose: Option<usize>,
    /// The active operation's posted program, when current: operation name and G-code text.
    pub posted: Option<(&'a str, &'a str)>,
    /// The data folder (settings files such as the force coefficient library).
    pub data_dir: &'a Path,
    /// The project's file, once saved.
    pub project_path: Option<&'a Path>,
    /// The pose the tool is drawn at (hovered in a plot, picked, or played back).
    pub tool_pose: Option<usize>,
    /// The operations' computed paths and planned clocks.
    pub results: &'a dyn OperationResults,
    /// The features' render ids ([`FeatureView::next_id`]).
    pub ids: &'a RenderIds,
}

impl FeatureView<'_> {
    /// A render id no other mesh or line of the scene has (new data needs a new id).
    #[must_use]
    pub fn next_id(&self) -> DataId {
        self.ids.next()
    }
}

/// The one counter the features' render ids come from, above the workstation's own (paths
/// from 2^48, viewport highlights and tools from 2^40).
#[derive(Debug)]
pub struct RenderIds(Cell<DataId>);

impl Default for RenderIds {
    fn default() -> Self {
        Self(Cell::new(1 << 52))
    }
}

impl RenderIds {
    /// A fresh id.
    #[must_use]
    pub fn next(&self) -> DataId {
        let id = self.0.get() + 1;
        self.0.set(id);
        id
    }
}

/// The computed operations, as features read them.
pub trait OperationResults {
    /// Operation `index`'s computed path and whether it is fresh (its settings unchanged since).
    fn operation_result(&self, index: usize) -> Option<(&ComputedOp, bool)>;

    /// The planned time (s) of every pose of operation `index`, when its posted program is current.
    fn planned_clock(&self, index: usize) -> Option<&[f64]>;
}

/// What the features lend one another and the workstation, gathered from them after each pass
/// over them ([`Feature::lend`]): shared values found by their type (the posted program's
/// run), so a feature lends a new kind of value without a change here.
#[derive(Clone, Default)]
pub struct Lent {
    values: Vec<Rc<dyn Any>>,
    /// The pose of the active path under the pointer in a feature's panel this frame (a motion
    /// plot): the tool is drawn there.
    pub hover_pose: Option<usize>,
}

impl Lent {
    /// Lend `value` (the first lent value of a type is the one found).
    pub fn lend<T: Any>(&mut self, value: Rc<T>) {
        self.values.push(value);
    }

    /// The lent value of type `T`, if any.
    #[must_use]
    pub fn get<T: Any>(&self) -> Option<&T> {
        self.values.iter().find_map(|v| v.downcast_ref::<T>())
    }
}

/// What a feature uses of the workstation while it applies a command or collects its jobs.
pub struct FeatureContext<'a> {
    /// What it may read.
    pub view: FeatureView<'a>,
    /// The egui context its background jobs wake.
    pub egui: &'a egui::Context,
    /// What the workstation is to do afterwards, in order.
    notices: Vec<Notice>,
}

/// What a feature asks the workstation to do (carried out after the feature returns).
#[derive(Clone, Debug, PartialEq)]
pub enum Notice {
    /// Add a line to the log (`toast`: also shown over the viewport for a while).
    Log {
        /// How serious.
        severity: Severity,
        /// The line.
        text: String,
        /// Also a notification over the viewport.
        toast: bool,
    },
    /// Ask where to save for `purpose`, starting at `suggestion`; the chosen path comes back as
    /// the purpose's command.
    SaveDialog {
        /// What is saved.
        purpose: SavePurpose,
        /// The suggested file.
        suggestion: PathBuf,
    },
    /// Change what the 3D view shows.
    Switch(ViewSwitch),
}

/// A switch of the workstation's own view that a feature may ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewSwitch {
    /// Stop drawing the simulated stock (the feature's surface replaces it).
    HideStock,
    /// Stop the playback and show the whole path (its clock changed: a program was posted).
    RestartPlayback,
    /// Show this tab of the bottom dock (one of a feature's [`Feature::dock_tabs`]).
    DockTab(&'static str),
}

impl<'a> FeatureContext<'a> {
    /// A context reading `view`, waking `egui`.
    #[must_use]
    pub fn new(view: FeatureView<'a>, egui: &'a egui::Context) -> Self {
        Self {
            view,
            egui,
            notices: Vec::new(),
        }
    }

    /// A render id no other mesh or line of the scene has ([`FeatureView::next_id`]).
    pub fn next_id(&mut self) -> DataId {
        self.view.next_id()
    }

    /// Add a line to the log.
    pub fn log(&mut self, severity: Severity, text: impl Into<String>) {
        self.notices.push(Notice::Log {
            severity,
            text: text.into(),
            toast: false,
        });
    }

    /// Add a line to the log and show it over the viewport for a while.
    pub fn notify(&mut self, severity: Severity, text: impl Into<String>) {
        self.notices.push(Notice::Log {
            severity,
            text: text.into(),
            toast: true,
        });
    }

    /// Ask where to save the feature's `file`, starting at `suggestion`; the chosen path comes
    /// back to the feature as [`Command::FeatureFile`] (see [`chosen_file`]).
    pub fn ask_save_path(&mut self, file: FeatureSave, suggestion: PathBuf) {
        self.notices.push(Notice::SaveDialog {
            purpose: SavePurpose::Feature(file),
            suggestion,
        });
    }

    /// Switch the workstation's view.
    pub fn switch(&mut self, switch: ViewSwitch) {
        self.notices.push(Notice::Switch(switch));
    }

    /// What was asked for, in order.
    #[must_use]
    pub fn into_notices(self) -> Vec<Notice> {
        self.notices
    }
}

/// What a feature adds to the 3D view.
#[derive(Default)]
pub struct SceneParts {
    /// Meshes drawn with the part.
    pub meshes: Vec<MeshInstance>,
    /// Polylines drawn over it.
    pub lines: Vec<LineInstance>,
    /// A surface drawn instead of the part and the stock (the first feature's wins).
    pub instead_of_part: Option<InsteadOfPart>,
    /// A legend for its coloured lines, in place of the path colouring's.
    pub path_legend: Option<SceneLegend>,
    /// The computed paths are drawn only while playing back (they would hide its surface).
    pub hide_paths: bool,
}

/// A surface drawn instead of the part, coloured by a scalar with a legend.
pub struct InsteadOfPart {
    /// The mesh (its scalar mapped by `mapping`).
    pub mesh: MeshInstance,
    /// The legend's title, with the unit.
    pub legend: String,
    /// How its scalar maps to colours.
    pub mapping: ScalarMapping,
}

/// The legend of a feature's coloured lines.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneLegend {
    /// Title with the unit.
    pub title: String,
    /// The colour bar.
    pub mapping: ScalarMapping,
    /// A value marked on the bar (e.g. a limit) and its label with the unit.
    pub mark: Option<(f32, String)>,
}

/// A workstation feature (see the module documentation for when each method is called).
pub trait Feature: Any {
    /// A short stable name, used in its [`FeatureCommand`]s (`"operator_panel"`).
    fn id(&self) -> &'static str;

    /// Its menu entries and keyboard shortcuts.
    fn actions(&self) -> Vec<Action> {
        Vec::new()
    }

    /// Apply `command` when it is this feature's (`None`: taken); give it back otherwise.
    fn apply(&mut self, command: Command, _cx: &mut FeatureContext<'_>) -> Option<Command> {
        Some(command)
    }

    /// Collect finished background work (once a frame, before the layout).
    fn poll(&mut self, _cx: &mut FeatureContext<'_>) {}

    /// Its running job, as the status bar shows it.
    fn job_status(&self) -> Option<JobStatus> {
        None
    }

    /// Cancel its running job; the job's label when there was one.
    fn cancel(&mut self) -> Option<String> {
        None
    }

    /// The part or the project was replaced: forget what was derived from the old one.
    fn reset(&mut self) {}

    /// Draw its windows or panels; commands for the workstation go to `commands`.
    fn ui(&mut self, ctx: &egui::Context, view: &FeatureView<'_>, commands: &mut Vec<Command>);

    /// What it adds to the 3D view this frame.
    fn scene(&self) -> SceneParts {
        SceneParts::default()
    }

    /// Its section in operation `index`'s editor, under the computed path's summary (shown once
    /// the operation has a path).
    fn operation_ui(
        &self,
        _ui: &mut egui::Ui,
        _index: usize,
        _view: &FeatureView<'_>,
        _commands: &mut Vec<Command>,
    ) {
    }

    /// Its check boxes at the end of View → Tool Paths.
    fn toggles(&self) -> Vec<Toggle> {
        Vec::new()
    }

    /// Steer the 3D view before it is drawn (fit the camera, place the drawn tool); the meshes
    /// it adds, drawn before the [`Feature::scene`] ones (the operator panel's machine), with
    /// new data's ids from `ids`.
    fn steer_view(&mut self, _viewport: &mut ViewportState, _ids: &RenderIds) -> Vec<MeshInstance> {
        Vec::new()
    }

    /// The titles of its tabs in the bottom dock (shown after the log).
    fn dock_tabs(&self) -> &'static [&'static str] {
        &[]
    }

    /// Draw its dock tab `tab` (one of [`Feature::dock_tabs`]) while it is shown.
    fn dock_ui(
        &mut self,
        _tab: &str,
        _ui: &mut egui::Ui,
        _view: &FeatureView<'_>,
        _commands: &mut Vec<Command>,
    ) {
    }

    /// The tool was moved to pose `pose` of the active path (a pick, a playback step or seek,
    /// the running clock): show it.
    fn follow_pose(&mut self, _pose: usize, _view: &FeatureView<'_>) {}

    /// Add what it lends the others to `lent` (after each pass over the features).
    fn lend(&self, _lent: &mut Lent) {}

    /// Itself, for [`find`].
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// Is `command` the action `action` of feature `id`?
#[must_use]
pub fn is_action(command: &Command, id: &str, action: &str) -> bool {
    matches!(command, Command::Feature(FeatureCommand { feature, action: a }) if *feature == id && *a == action)
}

/// The file chosen in feature `id`'s save dialog, when `command` carries it.
#[must_use]
pub fn chosen_file<'c>(command: &'c Command, id: &str) -> Option<&'c Path> {
    match command {
        Command::FeatureFile { feature, path } if *feature == id => Some(path),
        _ => None,
    }
}

/// The registered feature of type `T`, to read.
#[must_use]
pub fn find_ref<T: Feature>(features: &[Box<dyn Feature>]) -> Option<&T> {
    features
        .iter()
        .find_map(|f| (f.as_ref() as &dyn Any).downcast_ref::<T>())
}

/// The registered feature of type `T`.
pub fn find<T: Feature>(features: &mut [Box<dyn Feature>]) -> Option<&mut T> {
    features
        .iter_mut()
        .find_map(|f| f.as_any_mut().downcast_mut::<T>())
}
