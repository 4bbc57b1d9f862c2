//! Tool paths: cutter-location poses in part coordinates, as the contract's "Tool path JSON"
//! (written by `plan`, read by `post`, `simulate`, `render`).
//!
//! A pose is the tool tip (the tool's lowest point on its axis), the unit axis from the tip
//! toward the spindle, the kind of move that reaches it, the contact point when known, and the
//! feed. Lengths are mm, feeds mm/min.

mod file;
mod moves;
mod summary;

pub use file::{ToolFile, ToolpathFile, schema};

pub use moves::{
    ArcMove, CycleKind, CycleMove, CycleRetract, CycleStep, ExactMove, ExactSegment, MAX_SAMPLES,
    Move, PECK_CLEARANCE_MM, SpindleSwitch,
};
pub use summary::{GougeReport, Summary, move_time_at_feed_s, pose_times_at_feed};

use glam::DVec3;
use std::path::Path;

use crate::tools::Cutter;

/// The kind of move that reaches a pose.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum MoveKind {
    /// Cutting move at the pose's feed.
    Cut,
    /// Linking move between cuts (fed, clear of the part).
    Link,
    /// Rapid positioning.
    Rapid,
    /// Feed move into the material along the axis.
    Plunge,
}

/// Where the cutter touches the part at a pose.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum ContactKind {
    /// On the spherical end of a ball end mill.
    Ball,
    /// On the toroidal corner of a bull-nose cutter (or the rim of a flat end mill).
    Corner,
    /// On the flat bottom of a flat or bull-nose cutter.
    Bottom,
    /// On the cylindrical or conical flank.
    Flank,
    /// A mesh vertex touches the cutter (drop-cutter).
    MeshVertex,
    /// A mesh edge touches the cutter (drop-cutter).
    MeshEdge,
    /// A mesh facet's interior touches the cutter (drop-cutter).
    MeshFacet,
}

/// One cutter-location pose (part coordinates, mm).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pose {
    /// Tool tip, mm.
    pub tip: DVec3,
    /// Unit tool axis from the tip toward the spindle.
    pub axis: DVec3,
    /// The move that reaches this pose.
    pub kind: MoveKind,
    /// Cutter contact point on the part, when known.
    pub cc: Option<DVec3>,
    /// Feed of the move reaching this pose, mm/min (ignored for rapids).
    pub feed_mm_per_min: f64,
    /// Predicted scallop height toward the neighbouring pass at this pose, mm, when the
    /// strategy predicts one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scallop_mm: Option<f64>,
    /// Where the cutter touches the part, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactKind>,
}

impl Pose {
    /// A pose with no contact information (cc, scallop and contact unset).
    #[must_use]
    pub fn new(kind: MoveKind, tip: DVec3, axis: DVec3, feed_mm_per_min: f64) -> Self {
        Self {
            tip,
            axis,
            kind,
            cc: None,
            feed_mm_per_min,
            scallop_mm: None,
            contact: None,
        }
    }

    /// This pose with its cutter contact point and contact kind.
    #[must_use]
    pub fn with_contact(mut self, cc: DVec3, contact: ContactKind) -> Self {
        self.cc = Some(cc);
        self.contact = Some(contact);
        self
    }

    /// This pose with its predicted scallop height, mm.
    #[must_use]
    pub fn with_scallop(mut self, scallop_mm: f64) -> Self {
        self.scallop_mm = Some(scallop_mm);
        self
    }
}

/// The tool of a tool path: its SPEC string and the cutter it describes.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ToolRecord {
    /// The contract's tool SPEC (`ball:d=6`, ...).
    pub spec: String,
    /// Dimensions.
    #[serde(flatten)]
    pub cutter: Cutter,
}

/// A tool path (the contract's Tool path JSON).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Toolpath {
    /// Always `"mm"`.
    pub units: String,
    /// The cutter.
    pub tool: ToolRecord,
    /// Poses in order: the sampled view of every move.
    pub poses: Vec<Pose>,
    /// Exact moves (arcs, helices, cycles), each over the poses that sample it, in pose order
    /// and not overlapping; empty for paths of straight moves only.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub exact: Vec<ExactSegment>,
    /// Lengths, counts, time and extent (recomputed by [`Toolpath::new`] and on load).
    #[serde(default)]
    pub summary: Summary,
}

/// A tool path file error: file, place (`line L, column C` or `pose K`) and what.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{file}: {place}: {message}")]
pub struct ToolpathError {
    /// The file (or `<memory>`).
    pub file: String,
    /// Where in it.
    pub place: String,
    /// What is wrong.
    pub message: String,
}

impl Toolpath {
    /// A tool path in mm with its summary computed.
    #[must_use]
    pub fn new(tool: ToolRecord, poses: Vec<Pose>) -> Self {
        let summary = Summary::of(&poses);
        Self {
            units: "mm".into(),
            tool,
            poses,
            exact: Vec::new(),
            summary,
        }
    }

    /// Checks of the contract: units mm, finite numbers, unit axes (within 1e-6), feeds
    /// positive on fed moves.
    ///
    /// # Errors
    /// A [`ToolpathError`] naming `file` and the pose.
    pub fn validate(&self, file: &str) -> Result<(), ToolpathError> {
        let err = |place: String, message: String| ToolpathError {
            file: file.to_string(),
            place,
            message,
        };
        if self.units != "mm" {
            return Err(err(
                "units".into(),
                format!("units must be \"mm\", not {:?}", self.units),
            ));
        }
        for (k, p) in self.poses.iter().enumerate() {
            let place = format!("pose {k}");
            if !p.tip.is_finite() || !p.axis.is_finite() || p.cc.is_some_and(|c| !c.is_finite()) {
                return Err(err(place, "non-finite coordinate".into()));
            }
            if (p.axis.length() - 1.0).abs() > 1e-6 {
                return Err(err(
                    place,
                    format!("axis length {} is not 1", p.axis.length()),
                ));
            }
            if p.kind != MoveKind::Rapid
                && !(p.feed_mm_per_min > 0.0 && p.feed_mm_per_min.is_finite())
            {
                return Err(err(
                    place,
                    format!("feed {} mm/min must be positive", p.feed_mm_per_min),
                ));
            }
        }
        build::validate_exact(self).map_err(|(k, m)| err(format!("exact move {k}"), m))
    }

    /// Parse JSON text (`file` names it in errors), generously (see [`ToolpathFile`]); axes are
    /// renormalised, the summary recomputed. Unknown keys are dropped; use
    /// [`Toolpath::from_json_with_warnings`] to hear about them.
    ///
    /// # Errors
    /// [`ToolpathError`] with `line L, column C` for malformed JSON, `tool` for a tool that
    /// is missing or contradicts its spec, `pose K` for bad poses.
    pub fn from_json(text: &str, file: &str) -> Result<Self, ToolpathError> {
        file::read(text, file).map(|(tp, _)| tp)
    }

    /// As [`Toolpath::from_json`], with one warning (`FILE: unknown key 'PATH' ignored`) per
    /// key the reader did not use.
    ///
    /// # Errors
    /// As [`Toolpath::from_json`].
    pub fn from_json_with_warnings(
        text: &str,
        file: &str,
    ) -> Result<(Self, Vec<String>), ToolpathError> {
        file::read(text, file)
    }

    /// Load a tool path file.
    ///
    /// # Errors
    /// As [`Toolpath::from_json`]; unreadable files give place `file`.
    pub fn load(path: &Path) -> Result<Self, ToolpathError> {
        Self::load_with_warnings(path).map(|(tp, _)| tp)
    }

    /// Load a tool path file with the warnings of [`Toolpath::from_json_with_warnings`].
    ///
    /// # Errors
    /// As [`Toolpath::load`].
    pub fn load_with_warnings(path: &Path) -> Result<(Self, Vec<String>), ToolpathError> {
        let file = path.display().to_string();
        let text = crate::storage::read_text_bounded(path, crate::storage::PROGRAM_LIMIT_BYTES)
            .map_err(|e| ToolpathError {
                file: file.clone(),
                place: "file".into(),
                message: e.to_string(),
            })?;
        Self::from_json_with_warnings(&text, &file)
    }

    /// Pretty JSON text.
    ///
    /// # Errors
    /// When serialisation fails (non-finite numbers).
    pub fn to_json(&self) -> Result<String, ToolpathError> {
        serde_json::to_string_pretty(self).map_err(|e| ToolpathError {
            file: "<memory>".into(),
            place: "json".into(),
            message: e.to_string(),
        })
    }

    /// Save atomically: write a temporary file beside `path`, then rename it over `path`.
    ///
    /// # Errors
    /// [`ToolpathError`] naming the file on I/O failure.
    pub fn save(&self, path: &Path) -> Result<(), ToolpathError> {
        let file = path.display().to_string();
        let text = self.to_json()?;
        let io = |e: std::io::Error| ToolpathError {
            file: file.clone(),
            place: "file".into(),
            message: e.to_string(),
        };
        crate::storage::write_atomic(path, text.as_bytes()).map_err(io)
    }
}

/// serde_json appends " at line L column C"; the place already says it.
pub(crate) fn strip_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(i) => message[..i].to_string(),
        None => message.to_string(),
    }
}

mod build;

#[cfg(test)]
mod tests;
