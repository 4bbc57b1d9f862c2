//! Machine definitions and kinematics: 3-axis mills and table-tilting 5-axis machines
//! (LinuxCNC `xyzac-trt` / `xyzbc-trt` style).
//!
//! A machine is a JSON file (see `assets/machines/*.json`; the built-in ones are embedded, so
//! [`Machine::builtin`] needs no file system). Units in files are mm, mm/s, mm/s², mm/s³ for
//! linear axes and degrees, deg/s, deg/s², deg/s³ for rotary axes; in memory everything is mm
//! and rad.
//!
//! # The table-tilting model
//! Table coordinates are fixed to the rotary table and equal machine coordinates when both
//! rotary joints are at 0. The rotary table (C) turns about the machine Z axis through
//! `rot_point_mm` (LinuxCNC's `x/y/z-rot-point`); the tilt axis (A about X, or B about Y) passes
//! through `rot_point_mm + tilt_offset_mm` (LinuxCNC's `y-offset`/`z-offset` for AC,
//! `x-offset`/`z-offset` for BC). A joint angle q turns the table by `direction · q`, and
//! ```text
//! machine_from_table = T(q_t) · R_tilt(dir_t·tilt) · T(−q_t) · T(q_c) · R_z(dir_c·C) · T(−q_c)
//! ```
//! The tool points along machine +Z; the linear joints are the tool tip in machine coordinates.
//! With `direction = −1` on both axes this is the Kelekçi/Can thesis post-processor
//! (`R = R_x(a)·R_z(c)`, NC output `A = −a, C = −c`).

mod bodies;
pub mod collision;
mod definition;
mod kinematics;
mod linearise;

pub use bodies::{
    Body, BodyFile, BodyMesh, CylinderFile, Link, LinkPlacements, Placement, Shape, Side,
    Structure, StructureFile,
};
pub use definition::{Axis, AxisFile, Drawing, MachineFile};
pub use kinematics::{MachineJoints, ToolPose};
pub use linearise::{intended_pose, lerp_joints};

use glam::DVec3;

/// Errors of machine loading and kinematics.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MachineError {
    /// The file could not be read.
    #[error("{path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// The system's message.
        message: String,
    },
    /// The JSON is malformed or has wrong fields.
    #[error("machine file: {0}")]
    Parse(String),
    /// The definition is inconsistent (missing axis, min > max, non-positive limits, ...).
    #[error("machine definition: {0}")]
    Invalid(String),
    /// No built-in machine has this name.
    #[error("unknown machine {0:?} (built in: mill-3axis, trt-ac, trt-bc)")]
    Unknown(String),
    /// The pose is not a valid pose (non-finite, zero axis).
    #[error("bad pose: {0}")]
    BadPose(String),
    /// The pose cannot be reached within the axis limits.
    #[error("unreachable: {0}")]
    Unreachable(String),
}

/// How the axes are arranged.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum KinematicsKind {
    /// X Y Z only; the tool axis is always +Z.
    #[serde(rename = "xyz")]
    ThreeAxis,
    /// Table tilting about X (A) carrying a rotary table about Z (C).
    #[serde(rename = "xyzac-trt")]
    TableAc,
    /// Table tilting about Y (B) carrying a rotary table about Z (C).
    #[serde(rename = "xyzbc-trt")]
    TableBc,
}

/// A validated machine (internal units: mm, rad).
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    /// Short name (`trt-ac`).
    pub name: String,
    /// One line for people.
    pub description: String,
    /// Axis arrangement.
    pub kinematics: KinematicsKind,
    /// X, Y, Z (always), then the tilt axis and C for 5-axis machines.
    pub axes: Vec<Axis>,
    /// C-axis centre of rotation in machine coordinates (mm).
    pub rot_point_mm: DVec3,
    /// From the C-axis centre to a point on the tilt axis (mm).
    pub tilt_offset_mm: DVec3,
    /// Simple geometry for drawing.
    pub drawing: Drawing,
    /// Solid bodies on their links (`None` when the file has none).
    pub structure: Option<Structure>,
    /// Rated spindle power, W, when the machine file gives it.
    pub spindle_power_w: Option<f64>,
    /// Homing order from the machine file (empty: the control's default order).
    pub home_order: Vec<char>,
}

const BUILTIN: [(&str, &str); 3] = [
    (
        "mill-3axis",
        include_str!("../../assets/machines/mill-3axis.json"),
    ),
    ("trt-ac", include_str!("../../assets/machines/trt-ac.json")),
    ("trt-bc", include_str!("../../assets/machines/trt-bc.json")),
];

impl Machine {
    /// Names of the embedded machines.
    #[must_use]
    pub fn builtin_names() -> Vec<&'static str> {
        BUILTIN.iter().map(|(n, _)| *n).collect()
    }

    /// An embedded machine by name.
    ///
    /// # Errors
    /// [`MachineError::Unknown`] for other names.
    pub fn builtin(name: &str) -> Result<Self, MachineError> {
        let (_, text) = BUILTIN
            .iter()
            .find(|(n, _)| *n == name)
            .ok_or_else(|| MachineError::Unknown(name.to_string()))?;
        Self::from_json(text)
    }

    /// A machine from JSON text.
    ///
    /// # Errors
    /// [`MachineError::Parse`] or [`MachineError::Invalid`].
    pub fn from_json(text: &str) -> Result<Self, MachineError> {
        let file: MachineFile =
            serde_json::from_str(text).map_err(|e| MachineError::Parse(e.to_string()))?;
        file.validate()
    }

    /// A machine from a JSON file.
    ///
    /// # Errors
    /// [`MachineError::Io`], [`MachineError::Parse`] or [`MachineError::Invalid`].
    pub fn load(path: &std::path::Path) -> Result<Self, MachineError> {
        let text = crate::storage::read_text_bounded(path, crate::storage::TEXT_LIMIT_BYTES)
            .map_err(|e| MachineError::Io {
                path: path.display().to_string(),
                message: e.to_string(),
            })?;
        let named = |m: String| format!("{}: {m}", path.display());
        Self::from_json(&text).map_err(|e| match e {
            MachineError::Parse(m) => MachineError::Parse(named(m)),
            MachineError::Invalid(m) => MachineError::Invalid(named(m)),
            other => other,
        })
    }

    /// A built-in name, or else a path to a file (the command line's `NAME_OR_FILE`).
    ///
    /// # Errors
    /// As [`Machine::load`] when the argument is not a built-in name.
    pub fn resolve(name_or_file: &str) -> Result<Self, MachineError> {
        match Self::builtin(name_or_file) {
            Ok(m) => Ok(m),
            Err(_) => Self::load(std::path::Path::new(name_or_file)),
        }
    }

    /// The axis with this name (`'X'`, `'A'`, ...).
    #[must_use]
    pub fn axis(&self, name: char) -> Option<&Axis> {
        self.axes.iter().find(|a| a.name == name)
    }

    /// Names of the tilt and rotary axes (`('A', 'C')`, `('B', 'C')`), `None` for 3 axes.
    #[must_use]
    pub fn rotary_names(&self) -> Option<(char, char)> {
        match self.kinematics {
            KinematicsKind::ThreeAxis => None,
            KinematicsKind::TableAc => Some(('A', 'C')),
            KinematicsKind::TableBc => Some(('B', 'C')),
        }
    }
}
