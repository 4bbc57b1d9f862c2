//! Machining operations as the document stores them: which tool, what it cuts, and the
//! strategy's parameters (mm, rad, mm/min), with defaults a machinist would start from.

use crate::strategies::boundary::Boundary;
use crate::strategies::finish::{FinishOptions, Pattern, Strategy};
use crate::strategies::pencil::PENCIL_DEFAULT_ANGLE_DEG;
use crate::strategies::steep_shallow::{
    Finish3Settings, STEEP_SHALLOW_DEFAULT_ANGLE_DEG, WATERLINE_DEFAULT_ANGLE_DEG,
};
use crate::strategies::waterline::{Cut, Entry};

pub use super::finish_group::TiltAwaySettings;
pub use super::op_contour::ContourOp;
pub use super::op_face::FaceOp;
pub use super::op_holes::HolesOp;
pub use super::op_pocket::PocketOp;

/// A machining operation. Each kind names the engine strategy that runs it
/// ([`super::pipeline::compute`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Operation {
    /// 5-axis (or 3-axis with a fixed axis) finishing of one B-spline/analytic face:
    /// iso-parametric, iso-planar or iso-scallop (the first thesis).
    Finish {
        /// Name shown in the tree.
        name: String,
        /// Index of the tool in [`super::Project::tools`].
        tool: usize,
        /// Index of the face in the part (STEP order).
        face: usize,
        /// The strategy and its own parameters.
        strategy: Strategy,
        /// Scallop, chord tolerance, axis mode, feed, direction, clearance.
        options: FinishOptions,
        /// Further faces finished with `face` as one group, in this order after it (empty: one
        /// face).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        group: Vec<usize>,
        /// Tilting the tool away from the part's other faces (on by default).
        #[serde(default)]
        tilt_away: TiltAwaySettings,
    },
    /// Raster drop-cutter finishing over the whole part (3-axis).
    Raster {
        /// Name shown in the tree.
        name: String,
        /// Index of the tool in [`super::Project::tools`].
        tool: usize,
        /// Scallop height between passes, mm.
        #[serde(default = "default_scallop_mm")]
        scallop_mm: f64,
        /// Direction of the raster lines from +X, rad.
        angle_rad: f64,
        /// Cut in one direction only (climb everywhere) instead of zig-zag.
        #[serde(default)]
        one_way: bool,
        /// Chord tolerance of the cutter-location polyline, mm.
        #[serde(default = "default_tolerance_mm")]
        tolerance_mm: f64,
        /// Cutting feed, mm/min.
        #[serde(default = "default_feed")]
        feed_mm_per_min: f64,
        /// Clearance plane above the part, mm.
        #[serde(default = "default_clearance_mm")]
        clearance_mm: f64,
        /// Limits the path to a region with a rule (`None`: the whole part); a region of faces
        /// holds the part's face indices (STEP order).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        boundary: Option<Boundary>,
    },
    /// Z-level (waterline) roughing of the project's stock down to the part plus an allowance
    /// (3-axis).
    Rough {
        /// Name shown in the tree.
        name: String,
        /// Index of the tool in [`super::Project::tools`].
        tool: usize,
        /// Depth of cut per level, mm.
        step_down_mm: f64,
        /// Distance between neighbouring contours, as a fraction of the tool diameter.
        step_over_fraction: f64,
        /// Material left on the part for finishing (radial, and axial unless
        /// `stock_to_leave_axial_mm` is given), mm.
        stock_to_leave_mm: f64,
        /// Material left on floors (axial), mm, when it differs from the radial one.
        #[serde(default)]
        stock_to_leave_axial_mm: Option<f64>,
        /// Contour tolerance, mm.
        tolerance_mm: f64,
        /// Cutting feed, mm/min.
        feed_mm_per_min: f64,
        /// A level of its own at each flat floor between two levels (floor + stock to leave).
        #[serde(default = "yes")]
        flat_levels: bool,
        /// Clearance plane above the stock, mm.
        #[serde(default = "default_clearance_mm")]
        clearance_mm: f64,
    },
    /// Waterline (Z-level) finishing of the whole part (3-axis), the step-down set by the
    /// scallop height on the local wall slope.
    Waterline {
        /// Name shown in the tree.
        name: String,
        /// Index of the tool in [`super::Project::tools`].
        tool: usize,
        /// Scallop height between levels, mm.
        scallop_mm: f64,
        /// Chord tolerance of the contours, mm.
        tolerance_mm: f64,
        /// Contacts flatter than this set no limit on the step-down, rad from horizontal.
        angle_rad: f64,
        /// Climb or conventional.
        cut: Cut,
        /// Cutting feed, mm/min.
        feed_mm_per_min: f64,
        /// Clearance plane above the part, mm.
        #[serde(default = "default_clearance_mm")]
        clearance_mm: f64,
        /// How the waterline's loops are entered (plunge, arc or ramp).
        #[serde(default, skip_serializing_if = "is_plunge")]
        entry: Entry,
        /// Limits the path to a region with a rule (`None`: the whole part); a region of faces
        /// holds the part's face indices (STEP order).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        boundary: Option<Boundary>,
    },
    /// Steep-and-shallow finishing of the whole part (3-axis): waterline above the threshold
    /// angle, raster below it, overlapping in a band around it.
    SteepShallow {
        /// Name shown in the tree.
        name: String,
        /// Index of the tool in [`super::Project::tools`].
        tool: usize,
        /// Scallop height, mm.
        scallop_mm: f64,
        /// Chord tolerance of the contours and raster polylines, mm.
        tolerance_mm: f64,
        /// Threshold slope between raster and waterline, rad from horizontal.
        angle_rad: f64,
        /// Climb or conventional along the waterline contours.
        cut: Cut,
        /// Cutting feed, mm/min.
        feed_mm_per_min: f64,
        /// Clearance plane above the part, mm.
        #[serde(default = "default_clearance_mm")]
        clearance_mm: f64,
        /// How the waterline's loops are entered (plunge, arc or ramp).
        #[serde(default, skip_serializing_if = "is_plunge")]
        entry: Entry,
        /// Limits the path to a region with a rule (`None`: the whole part); a region of faces
        /// holds the part's face indices (STEP order).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        boundary: Option<Boundary>,
    },
    /// Pencil finishing (3-axis, ball end mill): along the valleys and corners where the ball
    /// touches the part twice.
    Pencil {
        /// Name shown in the tree.
        name: String,
        /// Index of the tool in [`super::Project::tools`].
        tool: usize,
        /// Smallest angle between the two contact normals that makes a pencil line, rad.
        angle_rad: f64,
        /// Chord tolerance of the pencil lines, mm.
        tolerance_mm: f64,
        /// Cutting feed, mm/min.
        feed_mm_per_min: f64,
        /// Clearance plane above the part, mm.
        #[serde(default = "default_clearance_mm")]
        clearance_mm: f64,
        /// Limits the path to a region with a rule (`None`: the whole part); a region of faces
        /// holds the part's face indices (STEP order).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        boundary: Option<Boundary>,
    },
    /// Rest finishing (3-axis, ball end mill): parallel passes where an earlier, larger tool
    /// left more than the scallop height.
    Rest {
        /// Name shown in the tree.
        name: String,
        /// Index of the tool in [`super::Project::tools`].
        tool: usize,
        /// Index of the earlier (reference) tool in [`super::Project::tools`].
        reference_tool: usize,
        /// Take the rest from the simulated stock of the operations before this one (in the
        /// project's order) instead of from the reference tool: finish where it keeps more
        /// than the scallop height plus the chord tolerance.
        #[serde(default)]
        from_stock: bool,
        /// Rest thickness that counts as finished, and the scallop between passes, mm.
        scallop_mm: f64,
        /// Chord tolerance along the passes, mm.
        tolerance_mm: f64,
        /// Cutting feed, mm/min.
        feed_mm_per_min: f64,
        /// Clearance plane above the part, mm.
        #[serde(default = "default_clearance_mm")]
        clearance_mm: f64,
        /// Limits the path to a region with a rule (`None`: the whole part); a region of faces
        /// holds the part's face indices (STEP order).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        boundary: Option<Boundary>,
    },
    /// 2.5D facing in the setup's frame ([`super::op_face`]).
    Face(FaceOp),
    /// 2.5D pocketing in the setup's frame ([`super::op_pocket`]).
    Pocket(PocketOp),
    /// 2.5D contouring in the setup's frame ([`super::op_contour`]).
    Contour(ContourOp),
    /// Hole making (drilling, tapping, boring, … cycles) in the setup's frame
    /// ([`super::op_holes`]).
    Holes(HolesOp),
}

/// Default clearance plane of the 3-axis operations above the part (roughing: the stock), mm.
pub const FINISH_3AXIS_CLEARANCE_MM: f64 = 5.0;

fn is_plunge(e: &Entry) -> bool {
    *e == Entry::Plunge
}

fn default_clearance_mm() -> f64 {
    FINISH_3AXIS_CLEARANCE_MM
}

fn yes() -> bool {
    true
}

fn default_scallop_mm() -> f64 {
    0.01
}

fn default_tolerance_mm() -> f64 {
    0.01
}

fn default_feed() -> f64 {
    1000.0
}

/// The kinds of operation, for menus.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperationKind {
    /// [`Operation::Finish`] with an iso-scallop strategy.
    IsoScallop,
    /// [`Operation::Finish`] with a zig-zag iso-parametric strategy.
    IsoParametric,
    /// [`Operation::Finish`] with an iso-planar strategy.
    IsoPlanar,
    /// [`Operation::Raster`].
    Raster,
    /// [`Operation::Rough`].
    Rough,
    /// [`Operation::Waterline`].
    Waterline,
    /// [`Operation::SteepShallow`].
    SteepShallow,
    /// [`Operation::Pencil`].
    Pencil,
    /// [`Operation::Rest`].
    Rest,
    /// [`Operation::Face`].
    Face,
    /// [`Operation::Pocket`].
    Pocket,
    /// [`Operation::Contour`].
    Contour,
    /// [`Operation::Holes`].
    Holes,
}

impl OperationKind {
    /// Every kind, in menu order.
    pub const ALL: [Self; 13] = [
        Self::IsoScallop,
        Self::IsoParametric,
        Self::IsoPlanar,
        Self::Raster,
        Self::Waterline,
        Self::SteepShallow,
        Self::Pencil,
        Self::Rest,
        Self::Rough,
        Self::Face,
        Self::Pocket,
        Self::Contour,
        Self::Holes,
    ];

    /// Name for menus and new operations.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::IsoScallop => "Iso-scallop finishing",
            Self::IsoParametric => "Iso-parametric finishing",
            Self::IsoPlanar => "Iso-planar finishing",
            Self::Raster => "Raster finishing",
            Self::Rough => "Z-level roughing",
            Self::Waterline => "Waterline finishing",
            Self::SteepShallow => "Steep-and-shallow finishing",
            Self::Pencil => "Pencil finishing",
            Self::Rest => "Rest finishing",
            Self::Face => "Facing",
            Self::Pocket => "Pocketing",
            Self::Contour => "Contouring",
            Self::Holes => "Hole making",
        }
    }

    /// Does the kind machine one face (and so need a B-rep part)?
    #[must_use]
    pub fn needs_face(self) -> bool {
        matches!(
            self,
            Self::IsoScallop | Self::IsoParametric | Self::IsoPlanar
        )
    }
}

impl Operation {
    /// A new operation of `kind` with `tool` on `face`, with starting values: 0.01 mm scallop
    /// and chord tolerance for finishing, 2 mm step-down, 40 % step-over and 0.3 mm allowance for
    /// roughing, 1000 mm/min.
    #[must_use]
    pub fn new(kind: OperationKind, tool: usize, face: usize) -> Self {
        let name = kind.label().to_string();
        let finish = |strategy| Self::Finish {
            name: name.clone(),
            tool,
            face,
            strategy,
            options: FinishOptions::default(),
            group: Vec::new(),
            tilt_away: TiltAwaySettings::default(),
        };
        match kind {
            OperationKind::IsoScallop => finish(Strategy::IsoScallop),
            OperationKind::IsoParametric => finish(Strategy::IsoParametric {
                pattern: Pattern::Zigzag,
            }),
            OperationKind::IsoPlanar => finish(Strategy::IsoPlanar { angle: 0.0 }),
            OperationKind::Raster => Self::Raster {
                name,
                tool,
                scallop_mm: default_scallop_mm(),
                angle_rad: 0.0,
                one_way: false,
                tolerance_mm: default_tolerance_mm(),
                feed_mm_per_min: default_feed(),
                clearance_mm: FINISH_3AXIS_CLEARANCE_MM,
                boundary: None,
            },
            OperationKind::Rough => Self::Rough {
                name,
                tool,
                step_down_mm: 2.0,
                step_over_fraction: 0.4,
                stock_to_leave_mm: 0.3,
                stock_to_leave_axial_mm: None,
                tolerance_mm: 0.05,
                feed_mm_per_min: default_feed(),
                flat_levels: true,
                clearance_mm: FINISH_3AXIS_CLEARANCE_MM,
            },
            OperationKind::Waterline => Self::Waterline {
                name,
                tool,
                scallop_mm: default_scallop_mm(),
                tolerance_mm: default_tolerance_mm(),
                angle_rad: WATERLINE_DEFAULT_ANGLE_DEG.to_radians(),
                cut: Cut::Climb,
                feed_mm_per_min: default_feed(),
                clearance_mm: FINISH_3AXIS_CLEARANCE_MM,
                entry: Entry::Plunge,
                boundary: None,
            },
            OperationKind::SteepShallow => Self::SteepShallow {
                name,
                tool,
                scallop_mm: default_scallop_mm(),
                tolerance_mm: default_tolerance_mm(),
                angle_rad: STEEP_SHALLOW_DEFAULT_ANGLE_DEG.to_radians(),
                cut: Cut::Climb,
                feed_mm_per_min: default_feed(),
                clearance_mm: FINISH_3AXIS_CLEARANCE_MM,
                entry: Entry::Plunge,
                boundary: None,
            },
            OperationKind::Pencil => Self::Pencil {
                name,
                tool,
                angle_rad: PENCIL_DEFAULT_ANGLE_DEG.to_radians(),
                tolerance_mm: default_tolerance_mm(),
                feed_mm_per_min: default_feed(),
                clearance_mm: FINISH_3AXIS_CLEARANCE_MM,
                boundary: None,
            },
            // The reference starts as the same tool: the user picks the earlier, larger one.
            OperationKind::Rest => Self::Rest {
                name,
                tool,
                reference_tool: tool,
                from_stock: false,
                scallop_mm: 0.05,
                tolerance_mm: default_tolerance_mm(),
                feed_mm_per_min: default_feed(),
                clearance_mm: FINISH_3AXIS_CLEARANCE_MM,
                boundary: None,
            },
            OperationKind::Face => Self::Face(FaceOp::new(name, tool)),
            OperationKind::Pocket => Self::Pocket(PocketOp::new(name, tool)),
            OperationKind::Contour => Self::Contour(ContourOp::new(name, tool)),
            OperationKind::Holes => Self::Holes(HolesOp::new(name, tool)),
        }
    }

    /// The settings shared by the 2.5D and hole kinds (`None` for the others).
    #[must_use]
    pub fn common(&self) -> Option<&super::op_common::Common> {
        match self {
            Self::Face(o) => Some(&o.common),
            Self::Pocket(o) => Some(&o.common),
            Self::Contour(o) => Some(&o.common),
            Self::Holes(o) => Some(&o.common),
            _ => None,
        }
    }

    /// [`Operation::common`], to change.
    pub fn common_mut(&mut self) -> Option<&mut super::op_common::Common> {
        match self {
            Self::Face(o) => Some(&mut o.common),
            Self::Pocket(o) => Some(&mut o.common),
            Self::Contour(o) => Some(&mut o.common),
            Self::Holes(o) => Some(&mut o.common),
            _ => None,
        }
    }

    /// Is it a 2.5D or hole kind (planned on the B-rep turned into the setup's frame)?
    #[must_use]
    pub fn is_planar(&self) -> bool {
        self.common().is_some()
    }

    /// For waterline and steep-and-shallow: the settings the planners' options are mapped from.
    #[must_use]
    pub fn finish_3axis_settings(&self) -> Option<Finish3Settings> {
        match self {
            Self::Waterline {
                scallop_mm,
                tolerance_mm,
                angle_rad,
                cut,
                feed_mm_per_min,
                clearance_mm,
                entry,
                ..
            }
            | Self::SteepShallow {
                scallop_mm,
                tolerance_mm,
                angle_rad,
                cut,
                feed_mm_per_min,
                clearance_mm,
                entry,
                ..
            } => Some(Finish3Settings {
                scallop_mm: *scallop_mm,
                tolerance_mm: *tolerance_mm,
                angle_rad: *angle_rad,
                cut: *cut,
                feed_mm_per_min: *feed_mm_per_min,
                clearance_mm: *clearance_mm,
                entry: *entry,
            }),
            _ => None,
        }
    }

    /// The faces a finishing operation cuts: its face, then its group's further faces (empty
    /// for the other kinds).
    #[must_use]
    pub fn faces(&self) -> Vec<usize> {
        match self {
            Self::Finish { face, group, .. } => std::iter::once(*face)
                .chain(group.iter().copied())
                .collect(),
            _ => Vec::new(),
        }
    }

    /// The kind (for finishing, from the strategy).
    #[must_use]
    pub fn kind(&self) -> OperationKind {
        match self {
            Self::Finish { strategy, .. } => match strategy {
                Strategy::IsoScallop => OperationKind::IsoScallop,
                Strategy::IsoParametric { .. } => OperationKind::IsoParametric,
                Strategy::IsoPlanar { .. } => OperationKind::IsoPlanar,
            },
            Self::Raster { .. } => OperationKind::Raster,
            Self::Rough { .. } => OperationKind::Rough,
            Self::Waterline { .. } => OperationKind::Waterline,
            Self::SteepShallow { .. } => OperationKind::SteepShallow,
            Self::Pencil { .. } => OperationKind::Pencil,
            Self::Rest { .. } => OperationKind::Rest,
            Self::Face(_) => OperationKind::Face,
            Self::Pocket(_) => OperationKind::Pocket,
            Self::Contour(_) => OperationKind::Contour,
            Self::Holes(_) => OperationKind::Holes,
        }
    }

    /// Name shown in the tree.
    #[must_use]
    pub fn name(&self) -> &str {
        match self {
            Self::Finish { name, .. }
            | Self::Raster { name, .. }
            | Self::Rough { name, .. }
            | Self::Waterline { name, .. }
            | Self::SteepShallow { name, .. }
            | Self::Pencil { name, .. }
            | Self::Rest { name, .. } => name,
            Self::Face(o) => &o.name,
            Self::Pocket(o) => &o.name,
            Self::Contour(o) => &o.name,
            Self::Holes(o) => &o.name,
        }
    }

    /// Index of the operation's tool in the project's library.
    #[must_use]
    pub fn tool(&self) -> usize {
        match self {
            Self::Finish { tool, .. }
            | Self::Raster { tool, .. }
            | Self::Rough { tool, .. }
            | Self::Waterline { tool, .. }
            | Self::SteepShallow { tool, .. }
            | Self::Pencil { tool, .. }
            | Self::Rest { tool, .. } => *tool,
            Self::Face(o) => o.tool,
            Self::Pocket(o) => o.tool,
            Self::Contour(o) => o.tool,
            Self::Holes(o) => o.tool,
        }
    }

    /// The region a 3-axis finishing operation is limited to (`None`: the whole part, and
    /// always for face finishing and roughing).
    #[must_use]
    pub fn boundary(&self) -> Option<&Boundary> {
        self.boundary_slot().and_then(|b| b.as_ref())
    }

    /// The boundary field of a 3-axis finishing operation (`None` for the kinds without one).
    pub fn boundary_mut(&mut self) -> Option<&mut Option<Boundary>> {
        match self {
            Self::Raster { boundary, .. }
            | Self::Waterline { boundary, .. }
            | Self::SteepShallow { boundary, .. }
            | Self::Pencil { boundary, .. }
            | Self::Rest { boundary, .. } => Some(boundary),
            Self::Finish { .. }
            | Self::Rough { .. }
            | Self::Face(_)
            | Self::Pocket(_)
            | Self::Contour(_)
            | Self::Holes(_) => None,
        }
    }

    fn boundary_slot(&self) -> Option<&Option<Boundary>> {
        match self {
            Self::Raster { boundary, .. }
            | Self::Waterline { boundary, .. }
            | Self::SteepShallow { boundary, .. }
            | Self::Pencil { boundary, .. }
            | Self::Rest { boundary, .. } => Some(boundary),
            Self::Finish { .. }
            | Self::Rough { .. }
            | Self::Face(_)
            | Self::Pocket(_)
            | Self::Contour(_)
            | Self::Holes(_) => None,
        }
    }

    /// The same operation with tool index `tool`.
    #[must_use]
    pub fn with_tool(mut self, new_tool: usize) -> Self {
        match &mut self {
            Self::Finish { tool, .. }
            | Self::Raster { tool, .. }
            | Self::Rough { tool, .. }
            | Self::Waterline { tool, .. }
            | Self::SteepShallow { tool, .. }
            | Self::Pencil { tool, .. }
            | Self::Rest { tool, .. }
            | Self::Face(FaceOp { tool, .. })
            | Self::Pocket(PocketOp { tool, .. })
            | Self::Contour(ContourOp { tool, .. })
            | Self::Holes(HolesOp { tool, .. }) => {
                *tool = new_tool;
            }
        }
        self
    }

    /// Every library index the operation uses: its tool, and rest finishing's reference tool.
    #[must_use]
    pub fn tools_used(&self) -> Vec<usize> {
        match self {
            Self::Rest {
                tool,
                reference_tool,
                ..
            } => vec![*tool, *reference_tool],
            other => vec![other.tool()],
        }
    }

    /// The same operation with every library index `i` it uses replaced by `f(i)` (tools
    /// inserted into or removed from the library).
    #[must_use]
    pub fn remap_tools(self, f: impl Fn(usize) -> usize) -> Self {
        let tool = f(self.tool());
        let mut op = self.with_tool(tool);
        if let Self::Rest { reference_tool, .. } = &mut op {
            *reference_tool = f(*reference_tool);
        }
        op
    }

    /// The same operation renamed.
    #[must_use]
    pub fn with_name(mut self, new_name: impl Into<String>) -> Self {
        match &mut self {
            Self::Finish { name, .. }
            | Self::Raster { name, .. }
            | Self::Rough { name, .. }
            | Self::Waterline { name, .. }
            | Self::SteepShallow { name, .. }
            | Self::Pencil { name, .. }
            | Self::Rest { name, .. }
            | Self::Face(FaceOp { name, .. })
            | Self::Pocket(PocketOp { name, .. })
            | Self::Contour(ContourOp { name, .. })
            | Self::Holes(HolesOp { name, .. }) => {
                *name = new_name.into();
            }
        }
        self
    }

    /// Check the numbers (finite, in range), in words with units.
    ///
    /// # Errors
    /// What is wrong.
    pub fn validate(&self) -> Result<(), String> {
        if let Some(b) = self.boundary() {
            b.validate().map_err(|e| format!("boundary: {e}"))?;
        }
        if let Some(e) = self.finish_3axis_settings().map(|s| s.entry) {
            e.validate()?;
        }
        self.validate_fields()
    }

    fn validate_fields(&self) -> Result<(), String> {
        let positive = |what: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{what} must be a positive number, got {v}"))
            }
        };
        use crate::units::{
            ALLOWANCE_BOUNDS, CLEARANCE_BOUNDS, FEED_BOUNDS, STEP_BOUNDS, TOLERANCE_BOUNDS,
        };
        let clearance = |v: f64| CLEARANCE_BOUNDS.check("the clearance (mm)", v);
        match self {
            Self::Finish {
                strategy,
                options,
                face,
                group,
                tilt_away,
                ..
            } => {
                super::finish_group::validate(*face, group, tilt_away)?;
                TOLERANCE_BOUNDS.check("scallop height (mm)", options.scallop)?;
                TOLERANCE_BOUNDS.check("chord tolerance (mm)", options.tolerance)?;
                FEED_BOUNDS.check("feed (mm/min)", options.feed)?;
                positive("largest axis step (rad)", options.max_axis_step)?;
                if let Strategy::IsoPlanar { angle } = strategy
                    && !angle.is_finite()
                {
                    return Err("the plane angle must be a finite number".into());
                }
                if let crate::strategies::finish::axis::AxisMode::Normal { lead, tilt } =
                    options.axis
                    && !(lead.abs() < std::f64::consts::FRAC_PI_2
                        && tilt.abs() < std::f64::consts::FRAC_PI_2)
                {
                    return Err("lead and tilt must lie between −90° and 90°".into());
                }
                if let Some(c) = options.clearance
                    && !(c.is_finite() && c.abs() <= crate::units::MAX_COORDINATE_MM)
                {
                    return Err(format!(
                        "the clearance height must lie within ±{} mm, got {c}",
                        crate::units::MAX_COORDINATE_MM
                    ));
                }
                Ok(())
            }
            Self::Raster {
                scallop_mm,
                angle_rad,
                tolerance_mm,
                feed_mm_per_min,
                clearance_mm,
                ..
            } => {
                clearance(*clearance_mm)?;
                TOLERANCE_BOUNDS.check("scallop height (mm)", *scallop_mm)?;
                TOLERANCE_BOUNDS.check("chord tolerance (mm)", *tolerance_mm)?;
                FEED_BOUNDS.check("feed (mm/min)", *feed_mm_per_min)?;
                if angle_rad.is_finite() {
                    Ok(())
                } else {
                    Err("the raster angle must be a finite number".into())
                }
            }
            Self::Rough {
                step_down_mm,
                step_over_fraction,
                stock_to_leave_mm,
                stock_to_leave_axial_mm,
                tolerance_mm,
                feed_mm_per_min,
                clearance_mm,
                ..
            } => {
                clearance(*clearance_mm)?;
                STEP_BOUNDS.check("step-down (mm)", *step_down_mm)?;
                TOLERANCE_BOUNDS.check("tolerance (mm)", *tolerance_mm)?;
                FEED_BOUNDS.check("feed (mm/min)", *feed_mm_per_min)?;
                if !(step_over_fraction.is_finite()
                    && *step_over_fraction > 0.0
                    && *step_over_fraction <= 1.0)
                {
                    return Err(format!(
                        "step-over must lie in (0, 100 %] of the diameter, got {:.1} %",
                        step_over_fraction * 100.0
                    ));
                }
                for v in std::iter::once(stock_to_leave_mm).chain(stock_to_leave_axial_mm) {
                    ALLOWANCE_BOUNDS.check("stock to leave (mm)", *v)?;
                }
                Ok(())
            }
            Self::Waterline { .. } | Self::SteepShallow { .. } => self.validate_finish_3axis(),
            Self::Pencil {
                angle_rad,
                tolerance_mm,
                feed_mm_per_min,
                clearance_mm,
                ..
            } => {
                clearance(*clearance_mm)?;
                TOLERANCE_BOUNDS.check("chord tolerance (mm)", *tolerance_mm)?;
                FEED_BOUNDS.check("feed (mm/min)", *feed_mm_per_min)?;
                let deg = angle_rad.to_degrees();
                if deg.is_finite() && (1.0..=170.0).contains(&deg) {
                    Ok(())
                } else {
                    Err(format!(
                        "the pencil angle must lie between 1° and 170°, got {deg:.2}°"
                    ))
                }
            }
            Self::Rest {
                scallop_mm,
                tolerance_mm,
                feed_mm_per_min,
                clearance_mm,
                ..
            } => {
                clearance(*clearance_mm)?;
                TOLERANCE_BOUNDS.check("scallop height (mm)", *scallop_mm)?;
                TOLERANCE_BOUNDS.check("chord tolerance (mm)", *tolerance_mm)?;
                FEED_BOUNDS.check("feed (mm/min)", *feed_mm_per_min)
            }
            Self::Face(o) => o.validate(),
            Self::Pocket(o) => o.validate(),
            Self::Contour(o) => o.validate(),
            Self::Holes(o) => o.validate(),
        }
    }

    fn validate_finish_3axis(&self) -> Result<(), String> {
        let Some(s) = self.finish_3axis_settings() else {
            return Ok(());
        };
        use crate::units::{CLEARANCE_BOUNDS, FEED_BOUNDS, TOLERANCE_BOUNDS};
        CLEARANCE_BOUNDS.check("the clearance (mm)", s.clearance_mm)?;
        TOLERANCE_BOUNDS.check("scallop height (mm)", s.scallop_mm)?;
        TOLERANCE_BOUNDS.check("chord tolerance (mm)", s.tolerance_mm)?;
        FEED_BOUNDS.check("feed (mm/min)", s.feed_mm_per_min)?;
        let deg = s.angle_rad.to_degrees();
        let (lo, hi, what) = if matches!(self, Self::Waterline { .. }) {
            (0.0, 89.0, "the slope angle")
        } else {
            (5.0, 80.0, "the steep/shallow threshold")
        };
        if deg.is_finite() && (lo..=hi).contains(&deg) {
            Ok(())
        } else {
            Err(format!(
                "{what} must lie between {lo}° and {hi}°, got {deg:.2}°"
            ))
        }
    }
}
