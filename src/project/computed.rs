//! What running one operation gives: the [`Computed`] result or the [`ComputeError`] that says
//! why not. The pipeline and the face-group planner both produce them.

use crate::diagnostics::Diagnostic;
use crate::toolpath::Toolpath;

/// What running an operation produced.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Computed {
    /// The tool path (summary with lengths, time at feed, predicted scallop, gouge report).
    pub toolpath: Toolpath,
    /// Number of cutting passes (contours for roughing).
    pub passes: usize,
    /// Warnings and notes of the strategy.
    pub diagnostics: Vec<Diagnostic>,
    /// For finishing: the lead actually used, rad (raised against local gouging).
    pub lead_rad: Option<f64>,
    /// The clearance plane's height used, mm (5-axis finishing: chosen above the path and the
    /// face unless the operation sets it); `None` for the 3-axis kinds, whose operation gives
    /// the clearance above the part.
    pub clearance_mm: Option<f64>,
    /// For finishing: where the tool enters other faces of the part (whole-part check), pose
    /// indices into `toolpath`.
    pub part_hits: Vec<crate::checks::part::PartHit>,
    /// For finishing: spans the tilt-away left out.
    pub left_out: Vec<crate::strategies::finish::tiltaway::LeftOut>,
}

/// Why an operation could not be run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ComputeError {
    /// No operation at that index.
    #[error("no operation number {index} (there are {count})")]
    NoOperation {
        /// The index asked for.
        index: usize,
        /// How many there are.
        count: usize,
    },
    /// The operation names a tool the library lacks.
    #[error("operation '{operation}': no tool number {tool} in the library")]
    NoTool {
        /// Operation name.
        operation: String,
        /// Tool index.
        tool: usize,
    },
    /// The operation's face is missing or has no exact surface.
    #[error("operation '{operation}': {message}")]
    Face {
        /// Operation name.
        operation: String,
        /// What is wrong with the face.
        message: String,
    },
    /// The strategy refused (options out of range, cutter unsupported, nothing to cut).
    #[error("operation '{operation}': {message}")]
    Plan {
        /// Operation name.
        operation: String,
        /// The strategy's message.
        message: String,
    },
    /// The user cancelled.
    #[error("cancelled")]
    Cancelled,
}
