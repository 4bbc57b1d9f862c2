//! A face group: one finishing operation over several faces of a part. Each face is planned
//! inside its trimming loops (as one face is) with the same tool, strategy and options, the
//! other faces of the group left out of the whole-part check (they are cut by the group), and
//! the faces' paths are joined in the order given: every face's path starts and ends at one
//! common clearance height (5 mm above the part unless the options give one), so the move from
//! one face's last retract to the next face's first approach stays at that height.

use super::face::FacePatch;
use super::plan::plan_finish_in;
use super::tiltaway::{LeftOut, PartContext};
use super::{FinishOptions, PlanError, Strategy};
use crate::checks::part::PartHit;
use crate::diagnostics::Diagnostic;
use crate::geometry::brep::Part;
use crate::geometry::trim::{REGION_CHORD_MM, TrimRegion};
use crate::toolpath::{GougeReport, ToolRecord, Toolpath};
use crate::tools::Cutter;

/// The joined path of a face group.
#[derive(Clone, Debug)]
pub struct GroupResult {
    /// The joined tool path (summary recomputed; gouge reports added up).
    pub toolpath: Toolpath,
    /// Cutting passes over all faces.
    pub passes: usize,
    /// Every face's diagnostics, each placed at its face (`face K: ...`).
    pub diagnostics: Vec<Diagnostic>,
    /// Whole-part hits, pose indices into the joined path.
    pub part_hits: Vec<PartHit>,
    /// Spans the tilt-away left out.
    pub left_out: Vec<LeftOut>,
    /// The common clearance height, mm.
    pub clearance: f64,
}

/// Plan `faces` of `part` as one operation (see the module doc). `context` is the whole-part
/// check and tilt-away; its `skip_faces` should be the group.
///
/// # Errors
/// The face that failed and why (a missing face, its trimming loops, the strategy's error).
pub fn plan_group(
    part: &Part,
    faces: &[usize],
    cutter: &Cutter,
    spec: &str,
    strategy: Strategy,
    opts: &FinishOptions,
    context: Option<&PartContext<'_>>,
) -> Result<GroupResult, (usize, PlanError)> {
    let clearance = opts
        .clearance
        .unwrap_or_else(|| part.rough_bbox().max.z + 5.0);
    let opts = FinishOptions {
        clearance: Some(clearance),
        ..*opts
    };
    let mut poses = Vec::new();
    let mut out = GroupResult {
        toolpath: Toolpath::new(
            ToolRecord {
                spec: spec.to_string(),
                cutter: cutter.clone(),
            },
            Vec::new(),
        ),
        passes: 0,
        diagnostics: Vec::new(),
        part_hits: Vec::new(),
        left_out: Vec::new(),
        clearance,
    };
    let mut report = GougeReport::default();
    for &k in faces {
        let face = part.faces.get(k).ok_or_else(|| {
            (
                k,
                PlanError::Face(format!("the part has {} faces", part.faces.len())),
            )
        })?;
        let region = TrimRegion::of_face(face, part, REGION_CHORD_MM)
            .map_err(|e| (k, PlanError::Face(format!("its trimming loops: {e}"))))?;
        let patch = FacePatch::trimmed(part, k, &region).map_err(|e| (k, e))?;
        let r =
            plan_finish_in(patch, cutter, spec, strategy, &opts, context).map_err(|e| (k, e))?;
        let offset = poses.len();
        out.part_hits.extend(r.part_hits.iter().map(|h| PartHit {
            pose: h.pose + offset,
            ..*h
        }));
        out.left_out.extend(r.left_out);
        out.passes += r.passes.len();
        out.diagnostics
            .extend(r.diagnostics.into_iter().map(|mut d| {
                d.place = Some(match d.place {
                    Some(p) => format!("face {k}, {p}"),
                    None => format!("face {k}"),
                });
                d
            }));
        if let Some(g) = r.toolpath.summary.gouge {
            add_report(&mut report, &g);
        }
        poses.extend(r.toolpath.poses);
    }
    out.toolpath = Toolpath::new(out.toolpath.tool, poses);
    out.toolpath.summary.gouge = Some(report);
    Ok(out)
}

/// Add one face's gouge report to the group's.
fn add_report(total: &mut GougeReport, g: &GougeReport) {
    total.checked_poses += g.checked_poses;
    total.gouging_poses += g.gouging_poses;
    total.found_before_repair += g.found_before_repair;
    total.part_hits += g.part_hits;
    total.part_checked |= g.part_checked;
    total.exact_check |= g.exact_check;
    total.local_gouge |= g.local_gouge;
    total.part_max_depth_mm = total.part_max_depth_mm.max(g.part_max_depth_mm);
    if g.max_depth_mm > total.max_depth_mm {
        total.max_depth_mm = g.max_depth_mm;
        total.worst_at = g.worst_at;
    }
    for (t, v) in [
        (&mut total.lead_raised_deg, g.lead_raised_deg),
        (&mut total.repair_lead_deg, g.repair_lead_deg),
    ] {
        if let Some(v) = v {
            *t = Some(t.map_or(v, |x: f64| x.max(v)));
        }
    }
}
