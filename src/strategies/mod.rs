//! Tool-path strategies (L3): iso-parametric, iso-planar and iso-scallop finishing on exact
//! surfaces, raster, waterline, steep-and-shallow, pencil and rest finishing and Z-level roughing
//! on meshes and Z-maps. Each strategy takes a
//! part (or face), a cutter and its parameters, and returns a [`crate::toolpath::Toolpath`] plus
//! diagnostics.
//!
//! Finishing on one face ([`finish::plan_finish`]): the face's parameter rectangle, or its
//! trimmed region inside that rectangle ([`face::FacePatch::trimmed`]), is covered by passes
//! (polylines in parameter space, clipped to the region), each pass is turned into poses by forward steps on
//! the tool-tip curve ([`stepping`]), with the exact check its gouges are repaired and its axes
//! smoothed ([`repair`]), and the passes are joined by links with optional lead-in/lead-out arcs
//! ([`linking`]).

pub mod axis;
pub mod boundary;
pub mod face;
pub mod finish;
pub mod group;
pub mod isoparam;
pub mod isoplanar;
pub mod isoscallop;
pub mod linking;
pub mod pass;
pub mod pencil;
pub mod raster;
pub mod raster_check;
pub mod repair;
pub mod rest;
pub mod scallop;
pub mod steep_shallow;
pub mod stepping;
pub mod tiltaway;
pub mod waterline;
pub mod zlevel;

/// Which parameter the passes run along.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Passes run along u (v stepped across).
    U,
    /// Passes run along v (u stepped across), the thesis's default.
    #[default]
    V,
}

/// How iso-parametric passes are ordered and linked.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Pattern {
    /// Two-way zig-zag: alternate directions, stay down between passes when safe.
    #[default]
    Zigzag,
    /// One-way: every pass in the same direction, retract and return between passes.
    Oneway,
    /// Rectangular spiral: concentric iso-parametric loops stepping inward.
    Spiral,
}

/// The finishing strategy and its own parameters.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Strategy {
    /// Iso-parametric passes at a constant parametric side step chosen for the scallop limit.
    IsoParametric {
        /// Pass ordering.
        pattern: Pattern,
    },
    /// Passes on parallel planes at an angle about the z axis (0° = planes ⟂ x).
    IsoPlanar {
        /// Angle of the planes' normal from the x axis in the xy plane, rad.
        angle: f64,
    },
    /// Iso-scallop (the thesis's ISC-II): each pass placed from the previous one so the scallop
    /// between them is the requested height everywhere.
    IsoScallop,
}

/// Shared finishing options.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FinishOptions {
    /// Target scallop height h, mm.
    pub scallop: f64,
    /// Chord tolerance ε on the tool-tip path, mm.
    pub tolerance: f64,
    /// Tool-axis mode.
    pub axis: axis::AxisMode,
    /// Feed, mm/min.
    pub feed: f64,
    /// Pass direction.
    pub direction: Direction,
    /// Clearance plane height (z), mm; `None`: 5 mm above the face.
    pub clearance: Option<f64>,
    /// Largest change of the tool axis between consecutive poses, rad (poses are inserted).
    pub max_axis_step: f64,
    /// Check every pose and cutting move for gouges against the exact surface
    /// ([`crate::checks::check_path`]), repair what gouges on the passes (lead raised locally,
    /// poses inserted: [`repair`]) and report what is left in the summary (slower).
    pub exact_check: bool,
    /// Raise the lead over the whole face to clear its largest concave curvature before
    /// planning ([`finish::min_lead`], the thesis's Sturz; default on). Off: keep the given
    /// lead; with `exact_check`, the repair raises it only where the tool gouges.
    #[serde(default = "default_true")]
    pub curvature_lead: bool,
    /// Radius of the tangential lead-in/lead-out arcs at the passes' ends, mm (0: none; see
    /// [`linking`]).
    #[serde(default)]
    pub lead_arc_mm: f64,
}

fn default_true() -> bool {
    true
}

impl Default for FinishOptions {
    fn default() -> Self {
        Self {
            scallop: 0.01,
            tolerance: 0.01,
            axis: axis::AxisMode::default(),
            feed: 1000.0,
            direction: Direction::V,
            clearance: None,
            max_axis_step: 5f64.to_radians(),
            exact_check: false,
            curvature_lead: true,
            lead_arc_mm: 0.0,
        }
    }
}

/// Why a plan could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// An option is out of range.
    #[error("{0}")]
    Option(String),
    /// The face cannot be machined this way (unbounded, degenerate, wrong kind).
    #[error("{0}")]
    Face(String),
    /// The cutter cannot be used by this strategy.
    #[error("{0}")]
    Tool(String),
}
