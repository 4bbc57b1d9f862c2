//! The 2.5D planning shared by `talas plan --strategy face|pocket|contour` and the project's
//! [`super::Operation::Face`], [`super::Operation::Pocket`] and [`super::Operation::Contour`]:
//! which regions (recognised from +Z by [`crate::features::regions`], chosen by kind or by floor
//! faces, or one drawn boundary file) and the strategy run on each, region after region, into
//! one tool path.

use std::path::Path;

use crate::features::regions::{MachinableRegion, RegionKind, find_regions};
use crate::geometry::brep::Part;
use crate::geometry::planar::{Region, read_profile};
use crate::strategies::planar::{
    AdaptiveOptions, ContourOptions, ContourSide, FacingOptions, PocketOptions, adaptive, contour,
    facing, pocket,
};
use crate::toolpath::{ToolRecord, Toolpath};

/// Which 2.5D strategy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanarKind {
    /// Facing: the region's top down to its face height.
    Face,
    /// Pocketing: the region from its top to its floor.
    Pocket,
    /// Contouring: along the region's boundary from its top to its floor.
    Contour,
    /// Adaptive clearing: the region from its top to its floor at a constant engagement.
    Adaptive,
}

impl PlanarKind {
    /// The recognised regions the strategy takes by default (`auto` without a filter):
    /// pockets for pocketing, the outer profile for facing and contouring.
    #[must_use]
    pub fn default_kinds(self) -> Vec<RegionKind> {
        match self {
            Self::Pocket | Self::Adaptive => vec![RegionKind::ClosedPocket],
            Self::Face | Self::Contour => vec![RegionKind::OuterProfile],
        }
    }
}

/// One region to machine: its geometry, its top and floor heights.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionJob {
    /// The region in XY.
    pub region: Region,
    /// The material's top above it, mm.
    pub top: f64,
    /// Its floor, mm.
    pub floor: f64,
    /// How it is named in messages.
    pub name: String,
    /// Drawn (its top and depth given), not recognised.
    pub drawn: bool,
}

/// The regions of `part` seen from +Z: those whose floor is one of `faces` (0-based) when it is
/// not empty, else those of the `kinds`.
///
/// # Errors
/// No region matches.
pub fn recognised_jobs(
    part: &Part,
    kinds: &[RegionKind],
    faces: &[usize],
) -> Result<Vec<RegionJob>, String> {
    let report = find_regions(part);
    let chosen: Vec<&MachinableRegion> = if faces.is_empty() {
        report
            .regions
            .iter()
            .filter(|r| kinds.contains(&r.kind))
            .collect()
    } else {
        report
            .regions
            .iter()
            .filter(|r| r.faces.iter().any(|f| faces.contains(f)))
            .collect()
    };
    if chosen.is_empty() {
        return Err(if faces.is_empty() {
            format!(
                "no region of kind {kinds:?} seen from +Z (found {})",
                report.regions.len()
            )
        } else {
            "no region has these floor faces (see talas features)".into()
        });
    }
    Ok(chosen
        .into_iter()
        .map(|r| RegionJob {
            region: r.region.clone(),
            top: r.top_z_mm,
            floor: r.floor_z_mm,
            name: format!("{:?} at z = {:.4} mm", r.kind, r.floor_z_mm),
            drawn: false,
        })
        .collect())
}

/// One drawn region: the closed boundary in `file` (DXF, SVG or CSV, mm) from `top` down by
/// `depth`.
///
/// # Errors
/// The file, with the place, or a bad depth.
pub fn drawn_job(file: &Path, top: f64, depth: f64, tolerance: f64) -> Result<RegionJob, String> {
    if !(top.is_finite() && depth.is_finite() && depth > 0.0) {
        return Err("the depth must be a positive number of mm".into());
    }
    let profile = read_profile(file, tolerance)
        .map_err(|e| format!("{}: {}: {}", file.display(), e.place, e.message))?;
    let region = Region::from_outline(&profile).map_err(|e| format!("{}: {e}", file.display()))?;
    Ok(RegionJob {
        region,
        top,
        floor: top - depth,
        name: file.display().to_string(),
        drawn: true,
    })
}

/// The numbers the three strategies read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarSettings {
    /// Depth of cut per level, mm.
    pub step_down_mm: f64,
    /// Step-over as a fraction of the tool diameter.
    pub step_over_fraction: f64,
    /// Material left on walls, mm.
    pub wall_allowance_mm: f64,
    /// Material left on floors, mm (facing: the depth of its finishing pass).
    pub floor_allowance_mm: f64,
    /// Climb (else conventional) milling along contours.
    pub climb: bool,
    /// Facing: zig-zag (else one way).
    pub zigzag: bool,
    /// Clearance above each region's top (facing: above its stock top), mm; or, with
    /// `clearance_is_z`, the clearance height itself (at least 0.5 mm above each top).
    pub clearance_mm: f64,
    /// `clearance_mm` is a height in the planning frame, not a distance above the top.
    pub clearance_is_z: bool,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Chord tolerance, mm.
    pub tolerance_mm: f64,
    /// Contour: cut outside (else inside) the boundary.
    pub outside: bool,
    /// Contour: tabs per loop.
    pub tabs: usize,
    /// Contour: tab width, mm.
    pub tab_width_mm: f64,
    /// Contour: tab height above the bottom, mm.
    pub tab_height_mm: f64,
    /// Contour: lead-in/out arc radius, mm.
    pub lead_radius_mm: f64,
    /// Facing: overrun past the region's box, mm.
    pub overrun_mm: f64,
    /// Pocket entry ramp and contour ramp angle, rad.
    pub ramp_angle_rad: f64,
    /// Facing a recognised region: the stock above the part's top, mm.
    pub face_stock_above_mm: f64,
    /// Adaptive clearing: the largest radial engagement angle, rad.
    pub engagement_rad: f64,
}

/// Plans `kind` on every job in order, into one tool path (each region left at its clearance).
///
/// # Errors
/// The job's name and the strategy's message.
pub fn plan_regions(
    kind: PlanarKind,
    jobs: &[RegionJob],
    tool: &ToolRecord,
    s: &PlanarSettings,
) -> Result<Toolpath, (String, String)> {
    let mut out = Toolpath::new(tool.clone(), Vec::new());
    for job in jobs {
        let above = |top: f64| {
            if s.clearance_is_z {
                (s.clearance_mm - top).max(0.5)
            } else {
                s.clearance_mm
            }
        };
        let tp = match kind {
            PlanarKind::Face => {
                // A drawn region faces from its top down to its floor; a recognised one faces
                // the part's top from the stock above it.
                let (stock_top, face_z) = if job.drawn {
                    (job.top, job.floor)
                } else {
                    (job.top + s.face_stock_above_mm, job.top)
                };
                facing(
                    &job.region,
                    tool,
                    &FacingOptions {
                        stock_top_z_mm: stock_top,
                        face_z_mm: face_z,
                        step_down_mm: s.step_down_mm,
                        finish_depth_mm: s.floor_allowance_mm,
                        stepover_frac: s.step_over_fraction,
                        overrun_mm: s.overrun_mm,
                        zigzag: s.zigzag,
                        clearance_mm: above(stock_top),
                        feed_mm_per_min: s.feed_mm_per_min,
                    },
                )
            }
            PlanarKind::Contour => contour(
                &job.region,
                tool,
                &ContourOptions {
                    side: if s.outside {
                        ContourSide::Outside
                    } else {
                        ContourSide::Inside
                    },
                    climb: s.climb,
                    top_z_mm: job.top,
                    bottom_z_mm: job.floor,
                    step_down_mm: s.step_down_mm,
                    allowance_mm: s.wall_allowance_mm,
                    lead_radius_mm: s.lead_radius_mm,
                    tab_count: s.tabs,
                    tab_width_mm: s.tab_width_mm,
                    tab_height_mm: s.tab_height_mm,
                    ramp_angle_rad: s.ramp_angle_rad,
                    clearance_mm: above(job.top),
                    feed_mm_per_min: s.feed_mm_per_min,
                    chord_tol_mm: s.tolerance_mm,
                },
            ),
            PlanarKind::Adaptive => adaptive(
                &job.region,
                tool,
                &AdaptiveOptions {
                    top_z_mm: job.top,
                    floor_z_mm: job.floor,
                    step_down_mm: s.step_down_mm,
                    engagement_rad: s.engagement_rad,
                    wall_allowance_mm: s.wall_allowance_mm,
                    floor_allowance_mm: s.floor_allowance_mm,
                    clearance_mm: above(job.top),
                    ramp_angle_rad: s.ramp_angle_rad,
                    feed_mm_per_min: s.feed_mm_per_min,
                    chord_tol_mm: s.tolerance_mm,
                    ..AdaptiveOptions::default()
                },
            ),
            PlanarKind::Pocket => pocket(
                &job.region,
                tool,
                &PocketOptions {
                    top_z_mm: job.top,
                    floor_z_mm: job.floor,
                    step_down_mm: s.step_down_mm,
                    stepover_frac: s.step_over_fraction,
                    wall_allowance_mm: s.wall_allowance_mm,
                    floor_allowance_mm: s.floor_allowance_mm,
                    clearance_mm: above(job.top),
                    ramp_angle_rad: s.ramp_angle_rad,
                    feed_mm_per_min: s.feed_mm_per_min,
                    chord_tol_mm: s.tolerance_mm,
                },
            ),
        }
        .map_err(|e| (job.name.clone(), e.0))?;
        append(&mut out, &tp);
    }
    out.resummarise();
    Ok(out)
}

/// Appends `b` to `a` (poses and exact segments).
pub fn append(a: &mut Toolpath, b: &Toolpath) {
    let off = a.poses.len();
    a.poses.extend(b.poses.iter().copied());
    a.exact.extend(b.exact.iter().map(|s| {
        let mut s = *s;
        s.from += off;
        s.to += off;
        s
    }));
}

/// What a 2.5D operation machines.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "by", rename_all = "snake_case")]
pub enum RegionTarget {
    /// The regions recognised from the setup's +Z, of these kinds (empty: the strategy's
    /// default, [`PlanarKind::default_kinds`]).
    Auto {
        /// The kinds to take.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        kinds: Vec<RegionKind>,
    },
    /// The recognised regions whose floor is one of these faces (0-based, STEP order).
    Faces {
        /// Floor faces.
        faces: Vec<usize>,
    },
    /// One closed boundary drawn in a DXF, SVG or CSV file (mm, in the setup's XY), its path
    /// relative to the folder of the project's part file, from `top_mm` (a height in the
    /// setup's planning frame) down by `depth_mm`.
    Drawn {
        /// The file.
        file: std::path::PathBuf,
        /// The material's top, mm.
        top_mm: f64,
        /// The depth below it, mm.
        depth_mm: f64,
    },
}

impl Default for RegionTarget {
    fn default() -> Self {
        Self::Auto { kinds: Vec::new() }
    }
}

impl RegionTarget {
    /// The drawn file resolved against `folder` (`None`: not drawn).
    #[must_use]
    pub fn drawn_file(&self, folder: Option<&Path>) -> Option<std::path::PathBuf> {
        match self {
            Self::Drawn { file, .. } => Some(match folder {
                Some(f) if file.is_relative() => f.join(file),
                _ => file.clone(),
            }),
            _ => None,
        }
    }

    /// The regions to machine on `part` (in the planning frame), for `kind`.
    ///
    /// # Errors
    /// No B-rep part (recognition needs one), no region, or the drawn file.
    pub fn jobs(
        &self,
        kind: PlanarKind,
        part: Option<&Part>,
        folder: Option<&Path>,
        tolerance_mm: f64,
    ) -> Result<Vec<RegionJob>, String> {
        let need_part = || {
            part.ok_or_else(|| {
                "recognising regions needs a STEP part (the part is a mesh)".to_string()
            })
        };
        match self {
            Self::Auto { kinds } => {
                let kinds = if kinds.is_empty() {
                    kind.default_kinds()
                } else {
                    kinds.clone()
                };
                recognised_jobs(need_part()?, &kinds, &[])
            }
            Self::Faces { faces } => {
                if faces.is_empty() {
                    return Err("no floor faces given".into());
                }
                recognised_jobs(need_part()?, &[], faces)
            }
            Self::Drawn {
                top_mm, depth_mm, ..
            } => {
                let file = self.drawn_file(folder).unwrap_or_default();
                Ok(vec![drawn_job(&file, *top_mm, *depth_mm, tolerance_mm)?])
            }
        }
    }
}

/// The folder relative paths of a project's operations are resolved against: the folder of
/// the part file.
#[must_use]
pub fn part_folder(part: &crate::import::Workpiece) -> Option<&Path> {
    part.source.parent()
}

/// Plan a 2.5D operation on `part` as it lies in the planning frame (+Z the tool axis), with
/// the stock's top at `stock_top_z`: the regions of `target`, the strategy, then the shared
/// feeds and the feed-from height.
///
/// # Errors
/// What is wrong, in words.
pub fn compute_planar(
    kind: PlanarKind,
    target: &RegionTarget,
    common: &super::op_common::Common,
    settings: PlanarSettings,
    part: &crate::import::Workpiece,
    tool: &ToolRecord,
    stock_top_z: Option<f64>,
) -> Result<super::computed::Computed, String> {
    let levels = super::op_common::levels(part, stock_top_z);
    let jobs = target.jobs(
        kind,
        part.part.as_deref(),
        part_folder(part),
        settings.tolerance_mm,
    )?;
    let s = PlanarSettings {
        clearance_mm: common.clearance.z(&levels),
        clearance_is_z: true,
        feed_mm_per_min: common.feed_mm_per_min,
        wall_allowance_mm: common.stock_to_leave_walls_mm,
        floor_allowance_mm: common.stock_to_leave_floors_mm,
        ..settings
    };
    let mut tp = plan_regions(kind, &jobs, tool, &s).map_err(|(n, m)| format!("{n}: {m}"))?;
    super::op_common::apply_feeds(&mut tp, common);
    super::op_common::apply_feed_from(&mut tp, common.feed_from.z(&levels), common.plunge_feed());
    Ok(super::computed::Computed {
        passes: jobs.len(),
        lead_rad: None,
        clearance_mm: None,
        part_hits: Vec::new(),
        left_out: Vec::new(),
        toolpath: tp,
        diagnostics: Vec::new(),
    })
}

/// The largest value [`positive`] and [`non_negative`] accept (a length of 100 m, a dwell of a
/// day): beyond it a number is a typing error or hostile, and loops it sizes would not end.
pub(super) const MAX_VALUE: f64 = 1e5;

pub(super) fn positive(what: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 && v <= MAX_VALUE {
        Ok(())
    } else {
        Err(format!(
            "{what} must be a positive number up to {MAX_VALUE:e}, got {v}"
        ))
    }
}

pub(super) fn non_negative(what: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && (0.0..=MAX_VALUE).contains(&v) {
        Ok(())
    } else {
        Err(format!(
            "{what} must be zero or more, up to {MAX_VALUE:e}, got {v}"
        ))
    }
}

pub(super) fn fraction(what: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 && v <= 1.0 {
        Ok(())
    } else {
        Err(format!(
            "{what} must lie in (0, 100 %] of the diameter, got {:.1} %",
            v * 100.0
        ))
    }
}
