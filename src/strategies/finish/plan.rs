//! Finishing one face: [`plan_finish`] checks the options, raises the lead against local
//! gouging ([`min_lead`]), runs a strategy's passes through forward stepping, repair and linking
//! into a [`Toolpath`], and applies the exact and whole-part checks.

use glam::{DVec2, DVec3};

use super::axis::AxisMode;
use super::face::FacePatch;
use super::pass::Pass;
use super::setup::Setup;
use super::tiltaway::{
    DriveFace, PartContext, approach_route, clear_height, moves_clear, note_tilt, part_check,
    tilt_away,
};
use super::{FinishOptions, Pattern, PlanError, Strategy};
use super::{isoparam, isoplanar, isoscallop, linking, repair};
use crate::diagnostics::Diagnostic;
use crate::toolpath::{GougeReport, Pose, ToolRecord, Toolpath};
use crate::tools::effective::{CrossProfile, torus_radii};
use crate::tools::{Cutter, CutterKind};

/// The result of finishing a face.
#[derive(Clone, Debug)]
pub struct FinishResult {
    /// The tool path (summary with predicted max scallop and the gouge report).
    pub toolpath: Toolpath,
    /// The passes in machining order (parameter space).
    pub passes: Vec<Pass>,
    /// The options actually used (lead raised against local gouging, clearance chosen).
    pub used: FinishOptions,
    /// Warnings and notes.
    pub diagnostics: Vec<Diagnostic>,
    /// Where the tool enters other faces of the part (whole-part check), when one was given.
    pub part_hits: Vec<crate::checks::part::PartHit>,
    /// Spans left out by the tilt-away (no allowed tilt frees the tool there).
    pub left_out: Vec<super::tiltaway::LeftOut>,
}

/// Smallest lead (rad, in 0.25° steps up to 45°) at which the cutter's cross-feed and
/// along-feed outlines clear a surface of concave curvature `k` (1/mm) to second order, for
/// normal-relative axes with sideways `tilt`; `None` when even 45° does not.
#[must_use]
pub fn min_lead(cutter: &Cutter, k: f64, tilt: f64) -> Option<f64> {
    let (rf, _) = torus_radii(cutter)?;
    if rf == 0.0 || k <= 0.0 {
        return Some(0.0);
    }
    let (n, f) = (DVec3::Z, DVec3::X);
    let t = n.cross(f);
    (0..=180)
        .map(|i| f64::from(i) * 0.25f64.to_radians())
        .find(|&lead| {
            let a = AxisMode::Normal { lead, tilt }.axis(DVec3::ZERO, n, f);
            let clears = |p: Option<CrossProfile>| {
                p.is_some_and(|p| {
                    let (hi, lo) = p.reach();
                    (0..=200).all(|j| {
                        let x = -lo + (hi + lo) * f64::from(j) / 200.0;
                        let y = p.height(x);
                        !y.is_finite() || y >= 0.5 * k * x * x - 1e-9
                    })
                })
            };
            // Across the feed, and along it (the heel behind the contact).
            clears(CrossProfile::new(cutter, a, n, f, t))
                && clears(CrossProfile::new(cutter, a, n, t, f))
        })
}

/// Plan a finishing path on one face.
///
/// # Errors
/// [`PlanError`] for options out of range, cone cutters, or a face that cannot be covered.
pub fn plan_finish(
    patch: FacePatch<'_>,
    cutter: &Cutter,
    spec: &str,
    strategy: Strategy,
    opts: &FinishOptions,
) -> Result<FinishResult, PlanError> {
    plan_finish_in(patch, cutter, spec, strategy, opts, None)
}

/// Plan a finishing path on one face of a part: as [`plan_finish`], and with `part` the tool is
/// tilted away from the part's other faces (when `part.tilt` is set; spans left out are
/// reported) and, with `opts.exact_check`, checked against the whole part.
///
/// # Errors
/// As [`plan_finish`].
pub fn plan_finish_in(
    patch: FacePatch<'_>,
    cutter: &Cutter,
    spec: &str,
    strategy: Strategy,
    opts: &FinishOptions,
    part: Option<&PartContext<'_>>,
) -> Result<FinishResult, PlanError> {
    check_options(opts)?;
    if torus_radii(cutter).is_none() {
        return Err(PlanError::Tool(
            "cone cutters are not supported for finishing; use ball, flat or bull".into(),
        ));
    }
    let mut diags = Vec::new();
    let mut used = *opts;
    let mut report = GougeReport::default();
    // Local gouging: raise the lead until the cutter clears the face's largest concave
    // curvature (the thesis's Sturz; S is only ever increased).
    let k_max = max_concave(&patch);
    if let AxisMode::Normal { lead, tilt } = opts.axis
        && opts.curvature_lead
    {
        match min_lead(cutter, k_max, tilt) {
            Some(s) if s > lead => {
                used.axis = AxisMode::Normal { lead: s, tilt };
                report.lead_raised_deg = Some(s.to_degrees());
                diags.push(Diagnostic::warning(
                    None,
                    format!(
                        "lead raised from {:.2}° to {:.2}° to clear the concave radius {:.2} mm",
                        lead.to_degrees(),
                        s.to_degrees(),
                        1.0 / k_max
                    ),
                ));
            }
            Some(_) => {}
            None => {
                report.local_gouge = true;
                diags.push(Diagnostic::error(
                    None,
                    format!(
                        "no lead up to 45° clears the concave radius {:.2} mm: local gouging",
                        1.0 / k_max
                    ),
                ));
            }
        }
    }
    if cutter.kind == CutterKind::Ball && k_max * cutter.radius() > 1.0 {
        report.local_gouge = true;
        diags.push(Diagnostic::error(
            None,
            format!(
                "ball radius {} mm exceeds the smallest concave radius {:.2} mm: local gouging",
                cutter.radius(),
                1.0 / k_max
            ),
        ));
    }
    let setup = Setup::new(patch, cutter, used);
    let (passes, zigzag) = match strategy {
        Strategy::IsoScallop => (isoscallop::passes(&setup, &mut diags)?, true),
        Strategy::IsoParametric { pattern } => (
            isoparam::passes(&setup, pattern, &mut diags)?,
            pattern == Pattern::Zigzag,
        ),
        Strategy::IsoPlanar { angle } => (isoplanar::passes(&setup, angle, &mut diags)?, true),
    };
    if passes.is_empty() {
        return Err(PlanError::Face(
            "no pass could be placed on the face".into(),
        ));
    }
    let spiral = matches!(
        strategy,
        Strategy::IsoParametric {
            pattern: Pattern::Spiral
        }
    );
    let ordered: Vec<Pass> = if setup.patch.region.is_some() {
        orient_greedy(&setup.patch, &passes, zigzag && !spiral)
    } else {
        passes
            .iter()
            .enumerate()
            .map(|(k, p)| {
                if zigzag && !spiral && k % 2 == 1 {
                    p.reversed()
                } else {
                    p.clone()
                }
            })
            .collect()
    };
    let planned = repair::plan_passes(&setup, &ordered, opts.exact_check, true);
    note_repairs(&planned, used.axis.lead(), &mut report, &mut diags);
    let mut runs: Vec<Vec<Pose>> = planned.into_iter().map(|r| r.poses).collect();
    let mut left_out = Vec::new();
    if let Some(ctx) = part
        && let Some(limits) = ctx.tilt
    {
        let drive = repair::check_patch(&setup).map(|patch| DriveFace {
            patch,
            opts: repair::check_options(),
            face: ctx.check.skip_faces.first().copied().unwrap_or(usize::MAX),
        });
        let t = tilt_away(&ctx.check, cutter, &runs, &limits, drive.as_ref());
        runs = t.runs;
        note_tilt(&t.left_out, t.tilted_poses, t.max_tilt_rad, &mut diags);
        left_out = t.left_out;
    }
    // With the part known, the clearance plane lies above all of it (rapids are not checked).
    let clearance = used.clearance.unwrap_or_else(|| {
        let own = linking::default_clearance(&setup, &runs);
        part.map_or(own, |ctx| {
            own.max(clear_height(&ctx.check, cutter) + linking::DEFAULT_CLEARANCE_ABOVE)
        })
    });
    used.clearance = Some(clearance);
    let clear = |chain: &[Pose]| part.is_none_or(|ctx| moves_clear(&ctx.check, cutter, chain));
    let route = |p: &Pose| part.and_then(|ctx| approach_route(&ctx.check, cutter, p));
    let poses = linking::link(&setup, &runs, clearance, !zigzag, &clear, &route);
    let record = ToolRecord {
        spec: spec.to_string(),
        cutter: cutter.clone(),
    };
    let mut toolpath = Toolpath::new(record, poses);
    report.checked_poses = toolpath.poses.len();
    if opts.exact_check {
        exact_check(&setup, &toolpath, &mut report, &mut diags);
    }
    let part_hits = match part {
        Some(ctx) if opts.exact_check => {
            part_check(&ctx.check, cutter, &toolpath, &mut report, &mut diags)
        }
        _ => Vec::new(),
    };
    toolpath.summary.gouge = Some(report);
    Ok(FinishResult {
        toolpath,
        passes,
        used,
        diagnostics: diags,
        part_hits,
        left_out,
    })
}

/// Two-way order on a trimmed face, where an iso-line may give several runs: each pass starts
/// at whichever of its ends is nearer (3D) to where the previous pass ended. One-way (`two_way`
/// false): every pass as given.
fn orient_greedy(patch: &FacePatch<'_>, passes: &[Pass], two_way: bool) -> Vec<Pass> {
    let point = |uv: Option<&DVec2>| uv.map(|q| patch.surface.point(q.x, q.y));
    let mut out: Vec<Pass> = Vec::with_capacity(passes.len());
    for p in passes {
        let prev_end = out.last().and_then(|q| point(q.uv.last()));
        let flip = match (two_way, prev_end, point(p.uv.first()), point(p.uv.last())) {
            (true, Some(e), Some(a), Some(b)) => e.distance(b) < e.distance(a),
            _ => false,
        };
        out.push(if flip { p.reversed() } else { p.clone() });
    }
    out
}

/// The repair's totals into the report and the diagnostics.
fn note_repairs(
    planned: &[repair::PassRepair],
    base: f64,
    report: &mut GougeReport,
    diags: &mut Vec<Diagnostic>,
) {
    let found: usize = planned.iter().map(|r| r.found).sum();
    if found == 0 {
        return;
    }
    let unfixed: usize = planned.iter().map(|r| r.unfixed.len()).sum();
    let inserted: usize = planned.iter().map(|r| r.inserted).sum();
    let depth = planned.iter().fold(0.0_f64, |m, r| m.max(r.found_depth_mm));
    let lead = planned.iter().fold(0.0_f64, |m, r| m.max(r.max_lead));
    report.found_before_repair = found;
    if lead > base + 1e-9 {
        report.repair_lead_deg = Some(lead.to_degrees());
    }
    diags.push(Diagnostic::info(
        None,
        format!(
            "gouge repair: {found} gouges found on the passes (deepest {:.1} µm), {} fixed \
             (lead raised locally up to {:.2}°, {inserted} poses inserted)",
            depth * 1e3,
            found.saturating_sub(unfixed),
            lead.to_degrees()
        ),
    ));
}

/// Gouge check of every pose and cutting move of the linked path against the exact surface
/// (after the repair of the passes), into the report; what still gouges is reported with its
/// place (mm) and depth (µm), never dropped.
fn exact_check(
    setup: &Setup<'_>,
    toolpath: &Toolpath,
    report: &mut GougeReport,
    diags: &mut Vec<Diagnostic>,
) {
    let Some(patch) = repair::check_patch(setup) else {
        return;
    };
    let o = repair::check_options();
    match crate::checks::check_path(&patch, setup.cutter, &toolpath.poses, &o) {
        Ok(r) => {
            report.exact_check = true;
            report.gouging_poses = r.gouges.len();
            report.max_depth_mm = r.max_depth_mm;
            let mut worst: Vec<&crate::checks::Gouge> = r.gouges.iter().collect();
            worst.sort_by(|a, b| b.depth_mm.total_cmp(&a.depth_mm));
            report.worst_at = worst.first().map(|g| g.point);
            for g in worst.iter().take(MAX_GOUGE_DIAGNOSTICS) {
                diags.push(Diagnostic::error(
                    Some(format!("pose {}", g.pose)),
                    format!(
                        "unfixed {:?} gouge {:.1} µm deep at ({:.3}, {:.3}, {:.3}) mm",
                        g.kind,
                        g.depth_mm * 1e3,
                        g.point.x,
                        g.point.y,
                        g.point.z
                    ),
                ));
            }
            if worst.len() > MAX_GOUGE_DIAGNOSTICS {
                diags.push(Diagnostic::error(
                    None,
                    format!(
                        "{} gouging poses in all, deepest {:.1} µm",
                        worst.len(),
                        r.max_depth_mm * 1e3
                    ),
                ));
            }
        }
        Err(e) => diags.push(Diagnostic::warning(
            None,
            format!("gouge check failed: {e}"),
        )),
    }
}

/// Unfixed gouges listed one by one in the diagnostics (then a count).
const MAX_GOUGE_DIAGNOSTICS: usize = 10;

/// Largest concave curvature over a 41×41 grid of the face (the points inside its trimmed
/// region, and points along the region's loops), 1/mm (≥ 0).
#[must_use]
pub fn max_concave(patch: &FacePatch<'_>) -> f64 {
    let mut k: f64 = 0.0;
    for uv in patch.samples(40) {
        if let Some(f) = patch.frame(uv) {
            k = k.max(patch.max_concave(&f));
        }
    }
    k
}

fn check_options(o: &FinishOptions) -> Result<(), PlanError> {
    let bad = |what: &str, v: f64| PlanError::Option(format!("{what} {v} is out of range"));
    if !(o.scallop > 0.0 && o.scallop.is_finite()) {
        return Err(bad("scallop height (mm)", o.scallop));
    }
    if !(o.tolerance > 0.0 && o.tolerance.is_finite()) {
        return Err(bad("chord tolerance (mm)", o.tolerance));
    }
    if !(o.feed > 0.0 && o.feed.is_finite()) {
        return Err(bad("feed (mm/min)", o.feed));
    }
    if !(o.max_axis_step > 0.0 && o.max_axis_step.is_finite()) {
        return Err(bad("axis step (rad)", o.max_axis_step));
    }
    if !(o.lead_arc_mm >= 0.0 && o.lead_arc_mm.is_finite()) {
        return Err(bad("lead arc radius (mm)", o.lead_arc_mm));
    }
    if o.clearance.is_some_and(|c| !c.is_finite()) {
        return Err(PlanError::Option("clearance must be finite".into()));
    }
    if let AxisMode::Normal { lead, tilt } = o.axis {
        let lim = 60f64.to_radians();
        if !(lead >= 0.0 && lead <= lim) {
            return Err(bad("lead (deg)", lead.to_degrees()));
        }
        if !(tilt.abs() <= lim) {
            return Err(bad("tilt (deg)", tilt.to_degrees()));
        }
    }
    Ok(())
}
