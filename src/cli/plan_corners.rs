//! Pencil and rest finishing for `talas plan` (`--strategy pencil|rest`): the options of
//! [`super::plan_mesh::MeshPlanOptions`] mapped onto [`crate::strategies::pencil`] (`--angle`:
//! the smallest angle between the two contact normals, 20° when 0) and
//! [`crate::strategies::rest`] (`--reference-tool SPEC`: the earlier tool; material thicker
//! than the scallop height counts as rest).

use std::path::Path;

use crate::diagnostics::Diagnostic;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::import::ImportError;
use crate::strategies::pencil::{PencilOptions, pencil};
use crate::strategies::rest::{RestOptions, rest};
use crate::toolpath::{ToolRecord, Toolpath};
use crate::tools::parse_tool_spec;

use super::plan_mesh::MeshPlanOptions;

/// Default bitangency angle of `--strategy pencil`, degrees.
pub const PENCIL_DEFAULT_ANGLE_DEG: f64 = 20.0;

/// Plan `pencil` or `rest` on `mesh`.
///
/// # Errors
/// An [`ImportError`] naming the option for a bad value, a missing or bad reference tool, or
/// what the planner could not do.
pub fn plan_corners(
    file: &Path,
    strategy: &str,
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &MeshPlanOptions,
) -> Result<(Toolpath, Vec<Diagnostic>), ImportError> {
    let bad = |what: &str, msg: String| ImportError::new(file, Some(what.to_string()), msg);
    let plunge = 0.3 * opts.feed_mm_per_min;
    if strategy == "pencil" {
        let deg = if opts.angle_deg == 0.0 {
            PENCIL_DEFAULT_ANGLE_DEG
        } else {
            opts.angle_deg
        };
        let popts = PencilOptions {
            min_angle_rad: deg.to_radians(),
            chord_tol_mm: opts.tolerance_mm,
            clearance_mm: opts.clearance_mm,
            feed_mm_per_min: opts.feed_mm_per_min,
            plunge_feed_mm_per_min: plunge,
            ..PencilOptions::default()
        };
        let plan = pencil(mesh, bvh, tool, &popts).map_err(|e| bad("pencil", e.to_string()))?;
        return Ok((plan.toolpath, plan.diagnostics));
    }
    let Some(spec) = opts.reference_tool.as_deref() else {
        return Err(bad(
            "--reference-tool",
            "rest finishing needs the earlier tool, e.g. --reference-tool ball:d=10".into(),
        ));
    };
    let reference = parse_tool_spec(spec).map_err(|e| bad("--reference-tool", e.to_string()))?;
    let ropts = RestOptions {
        reference,
        threshold_mm: opts.scallop_mm,
        scallop_mm: opts.scallop_mm,
        chord_tol_mm: opts.tolerance_mm,
        sampling_mm: None,
        overlap_mm: 0.5 * tool.cutter.radius(),
        clearance_mm: opts.clearance_mm,
        feed_mm_per_min: opts.feed_mm_per_min,
        plunge_feed_mm_per_min: plunge,
    };
    let plan = rest(mesh, bvh, tool, &ropts).map_err(|e| bad("rest", e.to_string()))?;
    Ok((plan.toolpath, plan.diagnostics))
}
