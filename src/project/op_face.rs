//! [`super::Operation::Face`]: facing the recognised top (or a drawn region) flat, from the
//! stock above it, in the setup's frame ([`super::op_regions`]).

use super::op_common::Common;
use super::op_regions::{PlanarKind, PlanarSettings, RegionTarget};

/// A facing operation.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FaceOp {
    /// Name shown in the tree.
    pub name: String,
    /// Index of the tool in [`super::Project::tools`].
    pub tool: usize,
    /// Heights, feeds, spindle, coolant, stock to leave (floors: the finishing pass's depth).
    #[serde(flatten)]
    pub common: Common,
    /// What is faced (default: the outer profile recognised from the setup's +Z, faced at the
    /// part's top).
    #[serde(default)]
    pub target: RegionTarget,
    /// Material above the part's top that is faced off (recognised regions), mm.
    #[serde(default = "one")]
    pub stock_above_mm: f64,
    /// Depth of cut per level, mm.
    #[serde(default = "one")]
    pub step_down_mm: f64,
    /// Step-over, fraction of the tool diameter.
    #[serde(default = "default_step_over")]
    pub step_over_fraction: f64,
    /// How far the tool's edge runs past the region's box, mm.
    #[serde(default = "two")]
    pub overrun_mm: f64,
    /// Zig-zag passes (else one way).
    #[serde(default = "yes")]
    pub zigzag: bool,
}

fn one() -> f64 {
    1.0
}
fn two() -> f64 {
    2.0
}
fn yes() -> bool {
    true
}
fn default_step_over() -> f64 {
    0.7
}

impl FaceOp {
    /// A facing operation with `tool`, starting values.
    #[must_use]
    pub fn new(name: String, tool: usize) -> Self {
        Self {
            name,
            tool,
            common: Common::default(),
            target: RegionTarget::default(),
            stock_above_mm: one(),
            step_down_mm: one(),
            step_over_fraction: default_step_over(),
            overrun_mm: two(),
            zigzag: true,
        }
    }

    /// The strategy's settings (heights and feeds are filled from [`Common`] when planned).
    #[must_use]
    pub fn settings(&self) -> PlanarSettings {
        PlanarSettings {
            step_down_mm: self.step_down_mm,
            step_over_fraction: self.step_over_fraction,
            wall_allowance_mm: self.common.stock_to_leave_walls_mm,
            floor_allowance_mm: self.common.stock_to_leave_floors_mm,
            climb: true,
            zigzag: self.zigzag,
            clearance_mm: 5.0,
            clearance_is_z: false,
            feed_mm_per_min: self.common.feed_mm_per_min,
            tolerance_mm: 0.01,
            outside: true,
            tabs: 0,
            tab_width_mm: 0.0,
            tab_height_mm: 0.0,
            lead_radius_mm: 0.0,
            overrun_mm: self.overrun_mm,
            ramp_angle_rad: 0.0,
            face_stock_above_mm: self.stock_above_mm,
            engagement_rad: 60f64.to_radians(),
        }
    }

    /// The kind of planning.
    pub const KIND: PlanarKind = PlanarKind::Face;

    /// Check the numbers.
    ///
    /// # Errors
    /// What is wrong.
    pub fn validate(&self) -> Result<(), String> {
        self.common.validate()?;
        crate::units::STEP_BOUNDS.check("step-down (mm)", self.step_down_mm)?;
        super::op_regions::fraction("step-over", self.step_over_fraction)?;
        super::op_regions::non_negative("stock above the part (mm)", self.stock_above_mm)?;
        super::op_regions::non_negative("overrun (mm)", self.overrun_mm)
    }
}
