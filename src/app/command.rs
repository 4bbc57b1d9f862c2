//! Commands: what panels, menus and shortcuts ask for. They are collected during the UI pass and
//! applied in one place ([`super::workstation::Workstation::apply`]).

use std::path::PathBuf;

use super::document::Selection;
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
    /// Change the selection.
    Select(Selection),
    /// Empty the log.
    ClearLog,
}
