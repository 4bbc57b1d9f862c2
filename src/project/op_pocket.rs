//! [`super::Operation::Pocket`]: pocketing the recognised pockets (or a drawn region) from
//! their top to their floor, in the setup's frame ([`super::op_regions`]).

use super::op_common::Common;
use super::op_regions::{PlanarKind, PlanarSettings, RegionTarget};

/// A pocketing operation.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PocketOp {
    /// Name shown in the tree.
    pub name: String,
    /// Index of the tool in [`super::Project::tools`].
    pub tool: usize,
    /// Heights, feeds, spindle, coolant, stock to leave.
    #[serde(flatten)]
    pub common: Common,
    /// What is pocketed (default: the closed pockets recognised from the setup's +Z).
    #[serde(default)]
    pub target: RegionTarget,
    /// Depth of cut per level, mm.
    #[serde(default = "default_step_down")]
    pub step_down_mm: f64,
    /// Step-over, fraction of the tool diameter.
    #[serde(default = "default_step_over")]
    pub step_over_fraction: f64,
    /// Largest angle of the entry ramp, rad.
    #[serde(default = "default_ramp")]
    pub ramp_angle_rad: f64,
    /// Chord tolerance, mm.
    #[serde(default = "default_tolerance")]
    pub tolerance_mm: f64,
}

fn default_step_down() -> f64 {
    2.0
}
fn default_step_over() -> f64 {
    0.4
}
fn default_ramp() -> f64 {
    3f64.to_radians()
}
fn default_tolerance() -> f64 {
    0.01
}

impl PocketOp {
    /// A pocketing operation with `tool`, starting values.
    #[must_use]
    pub fn new(name: String, tool: usize) -> Self {
        Self {
            name,
            tool,
            common: Common::default(),
            target: RegionTarget::default(),
            step_down_mm: default_step_down(),
            step_over_fraction: default_step_over(),
            ramp_angle_rad: default_ramp(),
            tolerance_mm: default_tolerance(),
        }
    }

    /// The kind of planning.
    pub const KIND: PlanarKind = PlanarKind::Pocket;

    /// The strategy's settings (heights and feeds are filled from [`Common`] when planned).
    #[must_use]
    pub fn settings(&self) -> PlanarSettings {
        PlanarSettings {
            step_down_mm: self.step_down_mm,
            step_over_fraction: self.step_over_fraction,
            wall_allowance_mm: self.common.stock_to_leave_walls_mm,
            floor_allowance_mm: self.common.stock_to_leave_floors_mm,
            climb: true,
            zigzag: true,
            clearance_mm: 5.0,
            clearance_is_z: false,
            feed_mm_per_min: self.common.feed_mm_per_min,
            tolerance_mm: self.tolerance_mm,
            outside: false,
            tabs: 0,
            tab_width_mm: 0.0,
            tab_height_mm: 0.0,
            lead_radius_mm: 0.0,
            overrun_mm: 0.0,
            ramp_angle_rad: self.ramp_angle_rad,
            face_stock_above_mm: 0.0,
            engagement_rad: 60f64.to_radians(),
        }
    }

    /// Check the numbers.
    ///
    /// # Errors
    /// What is wrong.
    pub fn validate(&self) -> Result<(), String> {
        self.common.validate()?;
        crate::units::STEP_BOUNDS.check("step-down (mm)", self.step_down_mm)?;
        super::op_regions::fraction("step-over", self.step_over_fraction)?;
        super::op_regions::positive("ramp angle (rad)", self.ramp_angle_rad)?;
        crate::units::TOLERANCE_BOUNDS.check("chord tolerance (mm)", self.tolerance_mm)
    }
}
