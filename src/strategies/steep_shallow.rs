//! Steep-and-shallow finishing on a mesh: one operation that finishes the areas steeper than a
//! threshold angle with waterline contours ([`super::waterline`], only the runs whose contacts
//! are steep, reaching `overlap_rad` flatter) and the rest with raster passes
//! ([`super::raster`], held to the scallop up to the threshold plus the overlap), so the two
//! overlap in a band of slopes around the threshold. The raster passes run first, then the
//! waterline runs from the top down; between the two the tool retracts to the clearance plane.

use crate::diagnostics::Diagnostic;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

use super::raster::{RasterOptions, raster};
use super::waterline::{Cut, Entry, WaterlineOptions, waterline};

/// Default slope of [`Finish3Settings::angle_rad`] for waterline finishing, degrees.
pub const WATERLINE_DEFAULT_ANGLE_DEG: f64 = 30.0;
/// Default threshold of [`Finish3Settings::angle_rad`] for steep-and-shallow finishing, degrees.
pub const STEEP_SHALLOW_DEFAULT_ANGLE_DEG: f64 = 45.0;

/// The settings a user gives a waterline or steep-and-shallow operation, and their one mapping
/// onto the planners' options (the command line and the project pipeline both call it, so the
/// same settings plan the same path).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Finish3Settings {
    /// Scallop height, mm.
    pub scallop_mm: f64,
    /// Chord tolerance of the contours and raster polylines, mm.
    pub tolerance_mm: f64,
    /// Waterline: contacts flatter than this set no limit on the step-down; steep-and-shallow:
    /// the threshold between raster and waterline; rad from horizontal.
    pub angle_rad: f64,
    /// Climb or conventional along the contours.
    pub cut: Cut,
    /// Cutting feed, mm/min (plunges at 30 % of it).
    pub feed_mm_per_min: f64,
    /// Clearance plane above the part, mm.
    pub clearance_mm: f64,
    /// How the waterline's loops are entered.
    pub entry: Entry,
}

impl Finish3Settings {
    /// The options of [`waterline`].
    #[must_use]
    pub fn waterline_options(&self) -> WaterlineOptions {
        WaterlineOptions {
            scallop_mm: self.scallop_mm,
            chord_tol_mm: self.tolerance_mm,
            min_slope_rad: self.angle_rad,
            cut: self.cut,
            clearance_mm: self.clearance_mm,
            feed_mm_per_min: self.feed_mm_per_min,
            plunge_feed_mm_per_min: 0.3 * self.feed_mm_per_min,
            entry: self.entry,
            ..WaterlineOptions::default()
        }
    }

    /// The options of [`steep_shallow`]: raster below the threshold, waterline above it.
    #[must_use]
    pub fn steep_shallow_options(&self) -> SteepShallowOptions {
        SteepShallowOptions {
            threshold_rad: self.angle_rad,
            raster: RasterOptions {
                scallop_mm: self.scallop_mm,
                chord_tol_mm: self.tolerance_mm,
                clearance_mm: self.clearance_mm,
                feed_mm_per_min: self.feed_mm_per_min,
                plunge_feed_mm_per_min: 0.3 * self.feed_mm_per_min,
                ..RasterOptions::default()
            },
            waterline: self.waterline_options(),
            ..SteepShallowOptions::default()
        }
    }
}

/// Options of [`steep_shallow`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SteepShallowOptions {
    /// Slope between shallow (raster) and steep (waterline), rad from horizontal.
    pub threshold_rad: f64,
    /// Width of the band of slopes both cover, rad (each side reaches this far past the
    /// threshold).
    pub overlap_rad: f64,
    /// Raster options (its `max_slope_rad` is set from the threshold and the overlap).
    pub raster: RasterOptions,
    /// Waterline options (its slope threshold and `steep_only` are set here).
    pub waterline: WaterlineOptions,
}

impl Default for SteepShallowOptions {
    fn default() -> Self {
        Self {
            threshold_rad: 45f64.to_radians(),
            overlap_rad: 5f64.to_radians(),
            raster: RasterOptions::default(),
            waterline: WaterlineOptions::default(),
        }
    }
}

/// A planned steep-and-shallow path.
#[derive(Clone, Debug, PartialEq)]
pub struct SteepShallowPlan {
    /// Raster passes, then waterline runs.
    pub toolpath: Toolpath,
    /// Number of raster passes.
    pub raster_passes: usize,
    /// Number of waterline runs.
    pub waterline_runs: usize,
    /// Number of waterline levels.
    pub levels: usize,
    /// Plan-view area of the shallow part where material stays that the raster's ball cannot
    /// reach (corners and valleys narrower than the tool, the foot of walls), mm²: the raster's
    /// view, an upper bound, since the waterline levels in the overlap band may finish some.
    pub unreachable_area_mm2: f64,
    /// Notes of both planners.
    pub diagnostics: Vec<Diagnostic>,
}

/// Plan steep-and-shallow finishing.
///
/// # Errors
/// A message naming the option out of range or what the planners could not do.
pub fn steep_shallow(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &SteepShallowOptions,
) -> Result<SteepShallowPlan, String> {
    let (t, o) = (opts.threshold_rad, opts.overlap_rad);
    if !(t > 0.0 && t < 85f64.to_radians()) {
        return Err(format!(
            "threshold angle must be between 0 and 85 degrees, got {} degrees",
            t.to_degrees()
        ));
    }
    if !(o >= 0.0 && o <= t && t + o < 89f64.to_radians()) {
        return Err(format!(
            "overlap must be 0 to {} degrees, got {} degrees",
            t.to_degrees().min(89.0 - t.to_degrees()),
            o.to_degrees()
        ));
    }
    let ropts = RasterOptions {
        max_slope_rad: t + o,
        ..opts.raster.clone()
    };
    let wopts = WaterlineOptions {
        min_slope_rad: t,
        overlap_rad: o,
        steep_only: true,
        ..opts.waterline.clone()
    };
    let r = raster(mesh, bvh, tool, &ropts).map_err(|e| e.to_string())?;
    let w = waterline(mesh, bvh, tool, &wopts).map_err(|e| e.to_string())?;
    let mut poses: Vec<Pose> = r.toolpath.poses.clone();
    let clear = poses
        .iter()
        .chain(&w.toolpath.poses)
        .map(|p| p.tip.z)
        .fold(f64::MIN, f64::max);
    if let Some(last) = poses.last().copied() {
        let up = last.tip.truncate().extend(clear);
        poses.push(Pose::new(
            MoveKind::Rapid,
            up,
            last.axis,
            last.feed_mm_per_min,
        ));
    }
    poses.extend(w.toolpath.poses.iter().cloned());
    // The raster's advice to finish its steep walls with a Z-level pass is what the waterline
    // part does here.
    let mut diagnostics: Vec<Diagnostic> = r
        .diagnostics
        .into_iter()
        .filter(|d| !d.message.starts_with("steep walls:"))
        .collect();
    if r.steep_area_mm2 > 0.0 {
        diagnostics.push(Diagnostic::info(
            None,
            format!(
                "steep walls: {:.1} mm² of surface beyond {:.0}° finished by the waterline levels",
                r.steep_area_mm2,
                (t + o).to_degrees()
            ),
        ));
    }
    diagnostics.extend(w.diagnostics);
    Ok(SteepShallowPlan {
        toolpath: Toolpath::new(tool.clone(), poses),
        raster_passes: r.passes,
        waterline_runs: w.loops,
        levels: w.levels.len(),
        unreachable_area_mm2: r.unreachable_area_mm2,
        diagnostics,
    })
}
