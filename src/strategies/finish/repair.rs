//! Gouge repair of cutting passes against the exact surface (the checks module's rear and local
//! gouge checks, [`crate::checks::check_path`]): each pass is stepped, its poses and moves
//! checked, and every gouge fixed where it is, then the pass is stepped and checked again:
//!
//! - a gouge **at a pose** (or one on a move whose pose is already forced), normal-relative axes
//!   only: the lead at that σ is raised in 0.5° steps until the tool placed there clears
//!   ([`crate::checks::check_pose`]), up to [`MAX_REPAIR_LEAD`]; the raise is blended over the
//!   neighbours (held over one cutter radius each side, then ramped down at
//!   [`LEAD_RAMP_DEG_PER_MM`]) so the axis stays smooth, and the forward steps (chord tolerance,
//!   axis step) are recomputed with that lead profile;
//! - a gouge **between poses** (the straight move cuts where neither end does): a pose is forced
//!   at the gouge's place, so the move follows the true tool curve more closely.
//!
//! What is still gouging after [`ROUNDS`] rounds (or would need a lead above 45°, or an axis
//! mode without a lead) is returned as unfixed, with its place and depth.
//!
//! Axis smoothing (`smooth_pass`) runs after the repair: the axes of a pass are averaged with
//! [`super::axis::smooth_axes`], each kept within [`SMOOTH_MAX_DEV_DEG`] of the planned axis and
//! the tips recomputed from the contacts; a smoothed pose that gouges (checked exactly, when the
//! exact check is on) or exceeds the axis step keeps its planned axis.

use glam::{DQuat, DVec3};
use rayon::prelude::*;

use super::axis::{AxisMode, axis_angle, smooth_axes};
use super::pass::Pass;
use super::setup::Setup;
use super::stepping::{CurvePoint, PassCurve, make_pose};
use crate::checks::{FacePatch, Gouge, GougeOptions, check_move, check_path, check_pose};
use crate::toolpath::{MoveKind, Pose};
use crate::tools::CutterKind;
use crate::tools::effective::contact_to_tip;

/// Largest lead the repair raises to, rad (45°; beyond it the gouge is reported).
pub const MAX_REPAIR_LEAD: f64 = std::f64::consts::FRAC_PI_4;

/// How fast a raised lead falls back to the planned one along the pass, degrees per mm.
pub const LEAD_RAMP_DEG_PER_MM: f64 = 2.0;

/// Check-and-fix rounds per pass.
pub const ROUNDS: usize = 5;

/// Largest deviation of a smoothed axis from the planned one, degrees.
pub const SMOOTH_MAX_DEV_DEG: f64 = 2.0;

/// Moving-average passes of the axis smoothing.
pub const SMOOTH_PASSES: usize = 3;

/// Lead search step, rad (0.5°).
const LEAD_STEP: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// The result of repairing one pass.
#[derive(Clone, Debug, Default)]
pub struct PassRepair {
    /// The cut poses.
    pub poses: Vec<Pose>,
    /// Gouges found in the first check (before any fix).
    pub found: usize,
    /// Deepest gouge before any fix, mm.
    pub found_depth_mm: f64,
    /// Gouges still there after the repair (pose indices into `poses`).
    pub unfixed: Vec<Gouge>,
    /// Largest lead used on the pass, rad.
    pub max_lead: f64,
    /// Poses forced between poses.
    pub inserted: usize,
    /// Poses whose axis the smoothing changed.
    pub smoothed: usize,
}

/// The gouge-check options of the planner's exact check (0.25 mm motion steps, 11 × 11 footprint,
/// 1 µm tolerance).
#[must_use]
pub fn check_options() -> GougeOptions {
    GougeOptions {
        step_mm: 0.25,
        footprint_n: 11,
        fix_leads: false,
        tolerance_mm: 1e-3,
        ..GougeOptions::default()
    }
}

/// The checks module's patch of the setup's face.
pub(crate) fn check_patch<'a>(setup: &Setup<'a>) -> Option<FacePatch<'a>> {
    let p = &setup.patch;
    FacePatch::new(p.surface, p.domain, p.side < 0.0).ok()
}

/// Raised-lead blend: the largest of the base lead and each bump held over `hold` (σ units)
/// around its σ, then falling at `slope` per σ unit.
fn lead_profile(base: f64, bumps: &[(f64, f64)], hold: f64, slope: f64, s: f64) -> f64 {
    bumps.iter().fold(base, |m, &(sb, lb)| {
        let d = ((s - sb).abs() - hold).max(0.0);
        m.max(lb - slope * d)
    })
}

/// Step every pass (in parallel), repairing its gouges when `repair` and smoothing its axes
/// when `smooth`; one result per pass, in order.
#[must_use]
pub fn plan_passes(
    setup: &Setup<'_>,
    passes: &[Pass],
    repair: bool,
    smooth: bool,
) -> Vec<PassRepair> {
    let gp = if repair { check_patch(setup) } else { None };
    let o = check_options();
    passes
        .par_iter()
        .map(|p| plan_pass(setup, gp.as_ref(), p, &o, smooth))
        .collect()
}

/// Step one pass, fix its gouges against `gp` when given (see the module doc), and smooth its
/// axes when `smooth`.
#[must_use]
pub fn plan_pass(
    setup: &Setup<'_>,
    gp: Option<&FacePatch<'_>>,
    pass: &Pass,
    o: &GougeOptions,
    smooth: bool,
) -> PassRepair {
    let Some(curve) = PassCurve::new(setup, pass) else {
        return PassRepair::default();
    };
    let normal = matches!(setup.opts.axis, AxisMode::Normal { .. });
    let base = setup.opts.axis.lead();
    // σ is close to arc length / guide spacing (passes are resampled to it).
    let spacing = setup.guide_spacing.max(1e-6);
    let hold = setup.cutter.radius() / spacing;
    let slope = LEAD_RAMP_DEG_PER_MM.to_radians() * spacing;
    let mut bumps: Vec<(f64, f64)> = Vec::new();
    let mut through: Vec<f64> = Vec::new();
    let mut out = PassRepair {
        max_lead: base,
        ..PassRepair::default()
    };
    let mut sigmas: Vec<f64> = Vec::new();
    for round in 0..ROUNDS {
        let profile = |s: f64| {
            (normal && !bumps.is_empty()).then(|| lead_profile(base, &bumps, hold, slope, s))
        };
        let stepped = curve.step(&profile, &through);
        out.poses = stepped.iter().map(|(p, _)| *p).collect();
        sigmas = stepped.iter().map(|(_, s)| *s).collect();
        out.max_lead = bumps.iter().fold(base, |m, b| m.max(b.1));
        let Some(gp) = gp else { break };
        let gouges = match check_path(gp, setup.cutter, &out.poses, o) {
            Ok(r) => r.gouges,
            Err(_) => Vec::new(),
        };
        if round == 0 {
            out.found = gouges.len();
            out.found_depth_mm = gouges.iter().fold(0.0, |m, g| m.max(g.depth_mm));
        }
        if gouges.is_empty() || round + 1 == ROUNDS {
            out.unfixed = gouges;
            break;
        }
        let mut changed = false;
        let mut unfixable = Vec::new();
        let mut raised = Vec::new();
        for g in gouges {
            let sb = sigmas.get(g.pose).copied().unwrap_or(0.0);
            let sa = g
                .pose
                .checked_sub(1)
                .and_then(|i| sigmas.get(i))
                .copied()
                .unwrap_or(sb);
            let between = g.move_param < 1.0 - 1e-9 && g.pose > 0;
            let sg = if between {
                sa + (sb - sa) * g.move_param
            } else {
                sb
            };
            if between && !through.iter().any(|&t| (t - sg).abs() < 1e-6) {
                through.push(sg);
                out.inserted += 1;
                changed = true;
                continue;
            }
            if !normal {
                unfixable.push(g);
                continue;
            }
            let from = profile(sg).unwrap_or(base);
            match clearing_lead(&curve, setup, gp, sg, from, o) {
                Some(l) if l > from => {
                    raised.push((sg, l));
                    changed = true;
                }
                // The tool placed at σ clears, the move into it does not: raise a little over
                // the current lead.
                Some(_) if from < MAX_REPAIR_LEAD => {
                    raised.push((sg, (from + LEAD_STEP).min(MAX_REPAIR_LEAD)));
                    changed = true;
                }
                _ => unfixable.push(g),
            }
        }
        bumps.extend(raised);
        through.sort_by(f64::total_cmp);
        if !changed {
            out.unfixed = unfixable;
            break;
        }
    }
    if smooth && normal {
        let profile =
            |s: f64| (!bumps.is_empty()).then(|| lead_profile(base, &bumps, hold, slope, s));
        let points: Vec<Option<CurvePoint>> =
            sigmas.iter().map(|&s| curve.eval(s, profile(s))).collect();
        let ball = setup.cutter.kind == CutterKind::Ball;
        // Ball end mills: the envelope does not depend on the axis, nothing to re-check.
        let check = if ball { None } else { gp };
        if ball || gp.is_some() {
            out.smoothed = smooth_pass(setup, &mut out.poses, &points, check, o);
        }
    }
    out
}

/// The smallest lead ≥ `from` (in 0.5° steps, up to [`MAX_REPAIR_LEAD`]) at which the tool
/// placed at σ clears the surface.
fn clearing_lead(
    curve: &PassCurve<'_, '_>,
    setup: &Setup<'_>,
    gp: &FacePatch<'_>,
    sigma: f64,
    from: f64,
    o: &GougeOptions,
) -> Option<f64> {
    let clears = |lead: f64| {
        curve
            .eval(sigma, Some(lead))
            .is_some_and(|c| check_pose(gp, setup.cutter, &make_pose(setup, &c), 0, o).is_none())
    };
    // Hopeless when even the largest lead gouges (the depth falls with the lead).
    if from > MAX_REPAIR_LEAD || !clears(MAX_REPAIR_LEAD) {
        return None;
    }
    let mut lead = from;
    while lead < MAX_REPAIR_LEAD {
        if clears(lead) {
            return Some(lead);
        }
        lead += LEAD_STEP;
    }
    Some(MAX_REPAIR_LEAD)
}

/// Largest angle between the axes of consecutive cut poses of `poses` (moves within the
/// passes), rad.
#[must_use]
pub fn max_axis_change(poses: &[Pose]) -> f64 {
    poses
        .windows(2)
        .filter(|w| w[0].kind == MoveKind::Cut && w[1].kind == MoveKind::Cut)
        .map(|w| axis_angle(w[0].axis, w[1].axis))
        .fold(0.0, f64::max)
}

/// `a` turned toward `b` by the fraction `t` of the angle between them.
fn turn_toward(a: DVec3, b: DVec3, t: f64) -> DVec3 {
    let q = DQuat::from_rotation_arc(a, b);
    (DQuat::IDENTITY.slerp(q, t) * a).normalize_or(a)
}

/// Smooth the axes of one pass's cut poses (`points`: the curve point of each pose): three-point
/// averages ([`smooth_axes`]), each axis kept within [`SMOOTH_MAX_DEV_DEG`] of the planned one
/// and the tip recomputed from the (lifted) contact. A changed pose that breaks the axis step,
/// or (with `gp`) gouges at itself or on the moves beside it, keeps its planned axis. Returns
/// how many poses changed.
fn smooth_pass(
    setup: &Setup<'_>,
    poses: &mut [Pose],
    points: &[Option<CurvePoint>],
    gp: Option<&FacePatch<'_>>,
    o: &GougeOptions,
) -> usize {
    if poses.len() < 3 {
        return 0;
    }
    let planned: Vec<Pose> = poses.to_vec();
    let mut axes: Vec<DVec3> = poses.iter().map(|p| p.axis).collect();
    smooth_axes(&mut axes, SMOOTH_PASSES);
    let max_dev = SMOOTH_MAX_DEV_DEG.to_radians();
    let mut changed = vec![false; poses.len()];
    for (((p, a), c), ch) in poses
        .iter_mut()
        .zip(&axes)
        .zip(points)
        .zip(changed.iter_mut())
    {
        let Some(c) = c else { continue };
        let dev = axis_angle(p.axis, *a);
        if dev < 1e-12 {
            continue;
        }
        let axis = turn_toward(p.axis, *a, (max_dev / dev).min(1.0));
        let Some(tip) = contact_to_tip(setup.cutter, c.lifted, c.n, axis, c.f) else {
            continue;
        };
        let mut q = make_pose(setup, &CurvePoint { tip, axis, ..*c });
        q.scallop_mm = p.scallop_mm;
        *p = q;
        *ch = true;
    }
    for _ in 0..3 {
        let mut reverted = false;
        for i in 0..poses.len() {
            if !changed.get(i).copied().unwrap_or(false) {
                continue;
            }
            let near = [i.checked_sub(1), Some(i + 1)];
            let too_far = near
                .iter()
                .flatten()
                .filter_map(|&j| poses.get(j))
                .any(|q| {
                    poses
                        .get(i)
                        .is_some_and(|p| axis_angle(p.axis, q.axis) > setup.opts.max_axis_step)
                });
            let gouges = gp.is_some_and(|gp| {
                let at = poses
                    .get(i)
                    .is_some_and(|p| check_pose(gp, setup.cutter, p, i, o).is_some());
                at || near.iter().flatten().any(|&j| {
                    let (a, b) = (i.min(j), i.max(j));
                    match (poses.get(a), poses.get(b)) {
                        (Some(pa), Some(pb)) => {
                            check_move(gp, setup.cutter, pa, pb, b, o).is_some()
                        }
                        _ => false,
                    }
                })
            });
            if too_far || gouges {
                if let (Some(p), Some(q)) = (poses.get_mut(i), planned.get(i)) {
                    *p = *q;
                }
                if let Some(c) = changed.get_mut(i) {
                    *c = false;
                }
                reverted = true;
            }
        }
        if !reverted {
            break;
        }
    }
    changed.iter().filter(|&&c| c).count()
}

#[cfg(test)]
mod tests {
    use super::lead_profile;

    #[test]
    fn raised_lead_is_held_then_ramped_back() {
        let (base, hold, slope) = (1.0, 2.0, 0.5);
        let bumps = [(10.0, 5.0), (30.0, 3.0)];
        let at = |s: f64| lead_profile(base, &bumps, hold, slope, s);
        assert_eq!(at(10.0), 5.0);
        assert_eq!(at(12.0), 5.0);
        assert_eq!(at(8.0), 5.0);
        assert_eq!(at(14.0), 4.0);
        assert_eq!(at(19.0), 1.5);
        assert_eq!(at(0.0), 1.0);
        // The lower bump where it dominates, the base far from both.
        assert_eq!(at(31.0), 3.0);
        assert_eq!(at(100.0), 1.0);
    }
}
