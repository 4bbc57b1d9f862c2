//! Commands: what panels, menus and shortcuts ask for. They are collected during the UI pass and
//! applied in one place ([`super::workstation::Workstation::apply`]).

use std::path::PathBuf;

use super::document::Selection;
use super::scalar_field::ScalarField;
use super::state::Focus;
use super::toolpaths::PathColouring;
use super::viewport::picking::SurfacePick;
use crate::project::{Edit, OperationKind};
use crate::render::{Projection, StandardView};

/// A request from the UI.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Show the Open dialog.
    OpenDialog,
    /// Open this file (replaces the document when it loads).
    Open(PathBuf),
    /// Open the embedded default part.
    OpenDefaultPart,
    /// Cancel the running job.
    CancelJob,
    /// Close the workstation.
    Quit,
    /// Fit the view to the part.
    FitAll,
    /// Snap to a standard view.
    StandardView(StandardView),
    /// Switch projection.
    SetProjection(Projection),
    /// Show or hide the part's edges.
    SetEdges(bool),
    /// Show or hide the ground grid.
    SetGrid(bool),
    /// Orbit in the active setup's frame (the part as it lies on that setup's table) or in the
    /// part's own.
    SetOrientToSetup(bool),
    /// Change the selection.
    Select(Selection),
    /// Empty the log.
    ClearLog,
    /// Change the project document (through the undo history).
    Edit(Edit),
    /// Undo the last document change.
    Undo,
    /// Redo the last undone change.
    Redo,
    /// Show this item in the properties panel.
    Inspect(Focus),
    /// Start a new project (the default part and the tool library).
    NewProject,
    /// Ask for a project file to open.
    OpenProjectDialog,
    /// Open this project file.
    OpenProject(PathBuf),
    /// Save the project to its file (asks for a path when it has none).
    SaveProject,
    /// Ask for a path and save the project there.
    SaveProjectAsDialog,
    /// Save the project to this path.
    SaveProjectAs(PathBuf),
    /// Replace the open project by its recovery file (unsaved changes of a crashed session).
    Recover(PathBuf),
    /// Delete the offered recovery file.
    DiscardRecovery(PathBuf),
    /// Remember the surface point clicked in the viewport (or forget it).
    SetPick(Option<SurfacePick>),
    /// Colour the part by a per-vertex scalar field (or not).
    SetScalarField(Option<ScalarField>),
    /// Add an operation of this kind (selected tool, selected face) and edit it.
    AddOperation(OperationKind),
    /// Plan operation `i` in the background.
    Calculate(usize),
    /// Plan the active (or the focused) operation.
    CalculateActive,
    /// Simulate operation `i`'s computed path on the stock.
    Simulate(usize),
    /// Simulate the active (or the focused) operation.
    SimulateActive,
    /// Simulate the active operation up to the playback pose (the stock at that moment).
    SimulateToPlayback,
    /// Ask for a machine definition file (JSON) to use.
    OpenMachineFileDialog,
    /// Post the active operation (and plan its motion).
    PostActive,
    /// Ask where to export the posted program.
    ExportProgramDialog,
    /// Show the simulated stock (instead of the part) or not.
    SetStockVisible(bool),
    /// Colour the simulated stock's deviation against a tolerance band of ± this, mm.
    SetDeviationBand(f64),
    /// Show this pose of the active operation's path in the properties (or none).
    PickPose(Option<usize>),
    /// Make `operation`'s path the active one and show its pose `pose` (a click in that
    /// operation's own list of findings or collisions, whichever path was active before).
    PickOperationPose {
        /// The operation whose path the pose is on.
        operation: usize,
        /// The pose.
        pose: usize,
    },
    /// Draw operation `operation`'s path in the viewport (and let clicks pick it) or hide it.
    SetPathShown {
        /// The operation.
        operation: usize,
        /// Drawn or hidden.
        shown: bool,
    },
    /// How tool paths are coloured.
    SetPathColouring(PathColouring),
    /// Make this path operation `.0`'s computed path (a feed schedule applied).
    ReplacePath(usize, std::sync::Arc<crate::toolpath::Toolpath>),
    /// Draw every operation's path (true) or only the active one's.
    SetShowAllPaths(bool),
    /// Draw tool-axis vectors at the active path's cutting poses.
    SetShowAxisVectors(bool),
    /// Open the window comparing the computed operations.
    CompareOperations,
    /// Playback of the active path.
    Playback(PlaybackCommand),
    /// An action of a registered [`super::feature::Feature`] (its menu entry or key).
    Feature(FeatureCommand),
    /// The file chosen in a feature's save dialog
    /// ([`super::file_dialog::SavePurpose::Feature`]), taken by the feature with this id.
    FeatureFile {
        /// The feature's [`super::feature::Feature::id`].
        feature: &'static str,
        /// The chosen file.
        path: PathBuf,
    },
}

/// What the playback bar asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlaybackCommand {
    /// Run the clock.
    Play,
    /// Stop the clock where it is.
    Pause,
    /// Play when paused, pause when playing.
    Toggle,
    /// Show the whole path again (no playback position).
    Reset,
    /// Jump to this time of the path's clock, s.
    Seek(f64),
    /// Step this many poses forward (negative: back).
    Step(i64),
    /// Playback speed, × real time at feed.
    Speed(f64),
}

/// An action of a workstation feature: the feature's id and the action's name (the feature
/// that owns the id takes it, see [`super::feature::Feature::apply`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FeatureCommand {
    /// The feature's [`super::feature::Feature::id`].
    pub feature: &'static str,
    /// What it should do (`"open"`).
    pub action: &'static str,
}
