//! [`super::Operation::Contour`]: contouring along the recognised outer profile (or a drawn
//! region) from its top to its floor, in the setup's frame ([`super::op_regions`]).

use super::op_common::Common;
use super::op_regions::{PlanarKind, PlanarSettings, RegionTarget};

/// A contouring operation.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContourOp {
    /// Name shown in the tree.
    pub name: String,
    /// Index of the tool in [`super::Project::tools`].
    pub tool: usize,
    /// Heights, feeds, spindle, coolant, stock to leave (walls: the contour's allowance).
    #[serde(flatten)]
    pub common: Common,
    /// What is contoured (default: the outer profile recognised from the setup's +Z).
    #[serde(default)]
    pub target: RegionTarget,
    /// Cut outside the boundary (else inside).
    #[serde(default = "yes")]
    pub outside: bool,
    /// Climb milling (else conventional).
    #[serde(default = "yes")]
    pub climb: bool,
    /// Depth of cut per level, mm.
    #[serde(default = "default_step_down")]
    pub step_down_mm: f64,
    /// Lead-in and lead-out arc radius, mm.
    #[serde(default = "default_lead")]
    pub lead_radius_mm: f64,
    /// Tabs per loop.
    #[serde(default)]
    pub tabs: usize,
    /// Tab width at the part, mm.
    #[serde(default = "default_tab_width")]
    pub tab_width_mm: f64,
    /// Tab height above the bottom, mm.
    #[serde(default = "default_tab_height")]
    pub tab_height_mm: f64,
    /// Largest angle of the ramp after tabs, rad.
    #[serde(default = "default_ramp")]
    pub ramp_angle_rad: f64,
    /// Chord tolerance, mm.
    #[serde(default = "default_tolerance")]
    pub tolerance_mm: f64,
}

fn yes() -> bool {
    true
}
fn default_step_down() -> f64 {
    2.0
}
fn default_lead() -> f64 {
    2.0
}
fn default_tab_width() -> f64 {
    5.0
}
fn default_tab_height() -> f64 {
    1.0
}
fn default_ramp() -> f64 {
    3f64.to_radians()
}
fn default_tolerance() -> f64 {
    0.01
}

impl ContourOp {
    /// A contouring operation with `tool`, starting values.
    #[must_use]
    pub fn new(name: String, tool: usize) -> Self {
        Self {
            name,
            tool,
            common: Common::default(),
            target: RegionTarget::default(),
            outside: true,
            climb: true,
            step_down_mm: default_step_down(),
            lead_radius_mm: default_lead(),
            tabs: 0,
            tab_width_mm: default_tab_width(),
            tab_height_mm: default_tab_height(),
            ramp_angle_rad: default_ramp(),
            tolerance_mm: default_tolerance(),
        }
    }

    /// The kind of planning.
    pub const KIND: PlanarKind = PlanarKind::Contour;

    /// The strategy's settings (heights and feeds are filled from [`Common`] when planned).
    #[must_use]
    pub fn settings(&self) -> PlanarSettings {
        PlanarSettings {
            step_down_mm: self.step_down_mm,
            step_over_fraction: 0.5,
            wall_allowance_mm: self.common.stock_to_leave_walls_mm,
            floor_allowance_mm: self.common.stock_to_leave_floors_mm,
            climb: self.climb,
            zigzag: true,
            clearance_mm: 5.0,
            clearance_is_z: false,
            feed_mm_per_min: self.common.feed_mm_per_min,
            tolerance_mm: self.tolerance_mm,
            outside: self.outside,
            tabs: self.tabs,
            tab_width_mm: self.tab_width_mm,
            tab_height_mm: self.tab_height_mm,
            lead_radius_mm: self.lead_radius_mm,
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
        super::op_regions::non_negative("lead radius (mm)", self.lead_radius_mm)?;
        crate::units::STEP_BOUNDS.check("tab width (mm)", self.tab_width_mm)?;
        super::op_regions::non_negative("tab height (mm)", self.tab_height_mm)?;
        super::op_regions::positive("ramp angle (rad)", self.ramp_angle_rad)?;
        crate::units::TOLERANCE_BOUNDS.check("chord tolerance (mm)", self.tolerance_mm)
    }
}
