//! Hole-making tools: what a drill, tap, reamer, boring bar or thread mill is beyond its
//! cutting envelope. Each maps to a [`Cutter`] for the simulation and the checks: a twist or spot
//! drill is a cone-tipped cutter (the point's half angle), a tap or reamer a flat cylinder of its
//! diameter, a thread mill a flat cylinder of its cutting diameter.

use super::{Cutter, CutterKind, ToolError};

/// The kind of hole tool and its own sizes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum HoleToolKind {
    /// Twist drill with its point's included angle, rad (118° usual).
    TwistDrill {
        /// Included point angle, rad.
        point_angle_rad: f64,
    },
    /// Spot (centre) drill with its included angle, rad (90° usual).
    SpotDrill {
        /// Included point angle, rad.
        point_angle_rad: f64,
    },
    /// Reamer.
    Reamer,
    /// Tap.
    Tap {
        /// Pitch, mm per turn.
        pitch_mm: f64,
        /// Right-hand thread.
        right_hand: bool,
    },
    /// Boring bar.
    BoringBar,
    /// Thread mill.
    ThreadMill {
        /// Pitch, mm per turn.
        pitch_mm: f64,
        /// Teeth along the axis (1 for a single-form mill).
        teeth: u32,
    },
    /// Chamfer mill with its included angle, rad.
    ChamferMill {
        /// Included angle, rad.
        angle_rad: f64,
    },
}

/// A hole tool: kind and cutting diameter.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HoleTool {
    /// Kind and its sizes.
    pub kind: HoleToolKind,
    /// Cutting diameter, mm.
    pub diameter_mm: f64,
}

impl HoleTool {
    /// The cutting envelope as a [`Cutter`].
    ///
    /// # Errors
    /// [`ToolError::Dimension`] for a bad diameter or angle (point angles must lie in (0°, 180°)).
    pub fn cutter(&self) -> Result<Cutter, ToolError> {
        let kind = match self.kind {
            HoleToolKind::TwistDrill { point_angle_rad }
            | HoleToolKind::SpotDrill { point_angle_rad }
            | HoleToolKind::ChamferMill {
                angle_rad: point_angle_rad,
            } => CutterKind::Cone {
                half_angle: 0.5 * point_angle_rad,
            },
            HoleToolKind::Reamer
            | HoleToolKind::Tap { .. }
            | HoleToolKind::BoringBar
            | HoleToolKind::ThreadMill { .. } => CutterKind::Flat,
        };
        Cutter::new(kind, self.diameter_mm)
    }

    /// The tool SPEC of its cutter (`cone:d=…,angle=…` or `flat:d=…`).
    #[must_use]
    pub fn spec(&self) -> String {
        match self.kind {
            HoleToolKind::TwistDrill { point_angle_rad }
            | HoleToolKind::SpotDrill { point_angle_rad }
            | HoleToolKind::ChamferMill {
                angle_rad: point_angle_rad,
            } => format!(
                "cone:d={},angle={}",
                self.diameter_mm,
                // Rounded to 1e-9° so that 118° reads back as 59, not 59.00000000000001.
                ((0.5 * point_angle_rad).to_degrees() * 1e9).round() / 1e9
            ),
            _ => format!("flat:d={}", self.diameter_mm),
        }
    }
}
