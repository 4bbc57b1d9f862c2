//! Tilt-away: where the tool's flutes, shank or holder would enter another face of the part
//! (the whole-part check, [`crate::checks::part`]), turn the tool axis away from it, within
//! limits, smoothly; where no allowed tilt is free, leave that span out and report it.
//!
//! The rule, per cutting run:
//! 1. Every pose is checked against the part (drive faces left out). A hit in the ball cannot
//!    be tilted away (the ball is what touches the face); a hit in the flutes above it, the
//!    shank or the holder can.
//! 2. Ball cutters only: the axis turns about the ball centre (the contact and the cut surface
//!    stay the same; the tip follows), in the plane of the axis and the hit point, away from
//!    the hit (else toward the contact normal, else toward +z: the first free one), by the
//!    least whole degree `θ ≤ max_angle_rad` that leaves the pose free and keeps the axis
//!    within `max_from_vertical_rad` of +z (the machine's tilt travel); where no such tilt
//!    frees it (a hole wall whose far side the flutes reach), up to `steep_angle_rad` when set.
//! 3. Smoothing: the tilt angle along the run is the upper envelope of the required tilts
//!    falling off at `rate_rad_per_mm` of path on each side (two sweeps); a pose takes the
//!    direction of the requirement that set its angle. The axis therefore turns at most at that
//!    rate (plus the change of the planned axis itself).
//!    With the drive face given ([`DriveFace`]), a candidate tilt must also leave the drive face
//!    itself ungouged (exact check, depth ≤ its tolerance): a steep tilt across a hole swings
//!    the flutes toward the hole's own far wall.
//! 4. Every pose is checked again (and, in a run that tilted, every pose and move against the
//!    drive face); the poses still hitting (no free tilt, a cutting-end hit,
//!    another cutter kind) are left out: the run splits there, the linking retracts over the
//!    gap, and each left-out span is reported with where it starts and ends, its length, the
//!    face hit and the tool part.
//! 5. The approach to each piece's ends (in a run that tilted, the fed plunge along the axis also
//!    checked exactly against the drive face): straight down the axis (vertically when the axis is
//!    level) when clear, else out along the tool axis far enough to leave the part sideways,
//!    then up ([`approach_route`], a pin between plates); ends reachable by neither are left
//!    out and reported as approach spans.

use glam::DVec3;
use rayon::prelude::*;

use crate::checks::FacePatch;
use crate::checks::gouge::{GougeOptions, check_move, check_pose};
use crate::checks::motion::{Placement, interpolate, motion_bound};
use crate::checks::part::{PartCheck, PartHit, PlacementHit, ToolPieces};
use crate::diagnostics::Diagnostic;
use crate::toolpath::{GougeReport, Pose, Toolpath};
use crate::tools::solid::ToolPart;
use crate::tools::{Cutter, CutterKind};

/// Limits of the tilt-away.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TiltAway {
    /// Largest angle between the planned axis and the tilted one, rad (0: never tilt, only
    /// leave out and report).
    pub max_angle_rad: f64,
    /// Largest rate of the tilt angle along the path, rad per mm.
    pub rate_rad_per_mm: f64,
    /// Largest angle of the axis from +z, rad (the machine's tilt travel).
    pub max_from_vertical_rad: f64,
    /// Largest tilt for a pose that no tilt within `max_angle_rad` frees (the wall of a hole
    /// whose far side the flutes reach, a pin between plates), rad; 0: never beyond
    /// `max_angle_rad`. Still bounded by `max_from_vertical_rad`.
    pub steep_angle_rad: f64,
}

impl Default for TiltAway {
    /// 30° at most, 2° per mm, up to 90° from vertical, never steeper.
    fn default() -> Self {
        Self {
            max_angle_rad: 30f64.to_radians(),
            rate_rad_per_mm: 2f64.to_radians(),
            max_from_vertical_rad: std::f64::consts::FRAC_PI_2,
            steep_angle_rad: 0.0,
        }
    }
}

/// The drive face for the tilt-away: tilted poses must not gouge it (exact check).
#[derive(Clone, Copy, Debug)]
pub struct DriveFace<'a> {
    /// The drive face's exact patch.
    pub patch: FacePatch<'a>,
    /// Its exact check's options (tolerance, motion step).
    pub opts: GougeOptions,
    /// Its face index (for the report of left-out spans).
    pub face: usize,
}

impl DriveFace<'_> {
    /// The exact gouge of pose `p` (and of the move from `prev` into it) into the drive face.
    fn hit(&self, cutter: &Cutter, prev: Option<&Pose>, p: &Pose) -> Option<PlacementHit> {
        let g = check_pose(&self.patch, cutter, p, 0, &self.opts)
            .or_else(|| check_move(&self.patch, cutter, prev?, p, 0, &self.opts))?;
        let part = match g.kind {
            crate::checks::gouge::GougeKind::Flank => ToolPart::Flutes,
            crate::checks::gouge::GougeKind::Shank => ToolPart::Shank,
            _ => ToolPart::CuttingEnd,
        };
        Some((g.point, g.depth_mm, self.face, part))
    }
}

/// The part a face is finished on, for the planner: the whole-part check and, when set, the
/// tilt-away limits.
#[derive(Clone, Copy, Debug)]
pub struct PartContext<'a> {
    /// The check against the part's other faces (give it `whole_tool`).
    pub check: PartCheck<'a>,
    /// Tilt away from the part (`None`: plan as is, only check).
    pub tilt: Option<TiltAway>,
}

/// Hits listed one by one in the diagnostics (then a count).
const MAX_LISTED: usize = 10;

/// The tilt-away's totals and every left-out span into the diagnostics.
pub(crate) fn note_tilt(
    left_out: &[LeftOut],
    tilted: usize,
    max_tilt: f64,
    diags: &mut Vec<Diagnostic>,
) {
    if tilted > 0 {
        diags.push(Diagnostic::info(
            None,
            format!(
                "tilt-away: {tilted} poses tilted away from the part's other faces (up to {:.1}°)",
                max_tilt.to_degrees()
            ),
        ));
    }
    for l in left_out.iter().take(MAX_LISTED) {
        diags.push(Diagnostic::warning(
            None,
            format!(
                "left out {:.2} mm ({} poses) from ({:.3}, {:.3}, {:.3}) to ({:.3}, {:.3}, {:.3}) mm: \
                 the tool's {:?} would enter face {} by {:.3} mm {}",
                l.length_mm,
                l.poses,
                l.start.x,
                l.start.y,
                l.start.z,
                l.end.x,
                l.end.y,
                l.end.z,
                l.tool_part,
                l.face,
                l.depth_mm,
                if l.approach {
                    "on the way down to it or up from it"
                } else {
                    "and no allowed tilt frees it"
                }
            ),
        ));
    }
    if left_out.len() > MAX_LISTED {
        let length: f64 = left_out.iter().map(|l| l.length_mm).sum();
        diags.push(Diagnostic::warning(
            None,
            format!(
                "{} spans left out in all ({length:.2} mm of path)",
                left_out.len()
            ),
        ));
    }
}

/// The whole-part check of a linked path: into the report and one diagnostic per hit (the
/// deepest first, then a count); the hits, in pose order.
pub(crate) fn part_check(
    check: &PartCheck<'_>,
    cutter: &Cutter,
    toolpath: &Toolpath,
    report: &mut GougeReport,
    diags: &mut Vec<Diagnostic>,
) -> Vec<PartHit> {
    let r = check.check_path(cutter, &toolpath.poses);
    report.part_checked = true;
    report.part_hits = r.hits.len();
    report.part_max_depth_mm = r.max_depth_mm;
    let mut worst: Vec<&PartHit> = r.hits.iter().collect();
    worst.sort_by(|a, b| b.depth_mm.total_cmp(&a.depth_mm));
    for h in worst.iter().take(MAX_LISTED) {
        diags.push(Diagnostic::error(
            Some(format!("pose {}", h.pose)),
            format!(
                "the tool's {:?} enters face {} by {:.1} µm at ({:.3}, {:.3}, {:.3}) mm",
                h.tool_part,
                h.face,
                h.depth_mm * 1e3,
                h.point.x,
                h.point.y,
                h.point.z
            ),
        ));
    }
    if worst.len() > MAX_LISTED {
        diags.push(Diagnostic::error(
            None,
            format!(
                "{} poses enter other faces of the part in all, deepest {:.1} µm",
                worst.len(),
                r.max_depth_mm * 1e3
            ),
        ));
    }
    r.hits
}

/// A span of a run left out because no allowed tilt frees the tool there.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LeftOut {
    /// First left-out pose's tip, mm.
    pub start: DVec3,
    /// Last left-out pose's tip, mm.
    pub end: DVec3,
    /// Path length of the span, mm (0 for one pose).
    pub length_mm: f64,
    /// How many poses.
    pub poses: usize,
    /// The face the tool enters at the span's deepest pose.
    pub face: usize,
    /// The tool part that enters it.
    pub tool_part: ToolPart,
    /// The deepest entry, mm.
    pub depth_mm: f64,
    /// Left out because the tool cannot come down to the span's end (or leave it) along the
    /// approach line from above the part without entering another face; `false`: the tool
    /// enters another face on the span itself.
    pub approach: bool,
}

/// The runs after the tilt-away.
#[derive(Clone, Debug, Default)]
pub struct TiltResult {
    /// The runs, split where spans were left out.
    pub runs: Vec<Vec<Pose>>,
    /// Poses whose axis was tilted.
    pub tilted_poses: usize,
    /// Largest tilt-away angle used, rad.
    pub max_tilt_rad: f64,
    /// What was left out.
    pub left_out: Vec<LeftOut>,
}

/// Apply the tilt-away to every run (see the module doc); the check should have `whole_tool`.
/// With `drive`, tilts that gouge the drive face are refused.
#[must_use]
pub fn tilt_away(
    check: &PartCheck<'_>,
    cutter: &Cutter,
    runs: &[Vec<Pose>],
    limits: &TiltAway,
    drive: Option<&DriveFace<'_>>,
) -> TiltResult {
    let tool = ToolPieces::of(cutter, check.whole_tool);
    let per_run: Vec<TiltResult> = runs
        .par_iter()
        .map(|run| tilt_run(check, &tool, cutter, run, limits, drive))
        .collect();
    let mut out = TiltResult::default();
    for r in per_run {
        out.runs.extend(r.runs);
        out.tilted_poses += r.tilted_poses;
        out.max_tilt_rad = out.max_tilt_rad.max(r.max_tilt_rad);
        out.left_out.extend(r.left_out);
    }
    out
}

/// Whether `point` lies above the ball's equator: in the flutes, which a turn about the ball
/// centre moves (the ball itself it does not).
fn above_ball(p: &Pose, point: DVec3, radius: f64) -> bool {
    (point - (p.tip + p.axis * radius)).dot(p.axis) > 1e-9
}

/// `axis` turned by `theta` toward `-away` (about the ball centre); `away` ⟂ `axis`, unit.
fn turned(axis: DVec3, away: DVec3, theta: f64) -> DVec3 {
    (axis * theta.cos() - away * theta.sin()).normalize_or(axis)
}

/// The pose with its axis turned about the ball centre.
fn pose_turned(p: &Pose, radius: f64, away: DVec3, theta: f64) -> Pose {
    let centre = p.tip + p.axis * radius;
    let axis = turned(p.axis, away, theta);
    Pose {
        tip: centre - axis * radius,
        axis,
        ..*p
    }
}

/// A required tilt: angle and direction (`None` angle: no allowed tilt frees the pose).
type Need = Option<(f64, DVec3)>;

fn free(check: &PartCheck<'_>, tool: &ToolPieces, p: &Pose) -> bool {
    !check.enters(tool, p.tip, p.axis)
}

/// The least whole-degree tilt that frees pose `p`, hit at `point` in a part above the cutting
/// end; `None` when none within the limits does. At each angle the axis turns (about the ball
/// centre) in these directions, the first free one wins: away from the hit point, toward the
/// contact normal (ball centre − contact), toward +z.
fn required(
    (check, tool, drive): (
        &PartCheck<'_>,
        &ToolPieces,
        Option<(&DriveFace<'_>, &Cutter)>,
    ),
    radius: f64,
    p: &Pose,
    point: DVec3,
    limits: &TiltAway,
) -> Need {
    let perp = |v: DVec3| (v - p.axis * v.dot(p.axis)).try_normalize();
    let centre = p.tip + p.axis * radius;
    // `away` directions: the axis turns toward −away.
    let dirs: Vec<DVec3> = [
        perp(point - p.tip),
        p.cc.and_then(|cc| perp(cc - centre)),
        perp(-DVec3::Z),
    ]
    .into_iter()
    .flatten()
    .collect();
    let steps = (limits.max_angle_rad.to_degrees().floor() as usize).min(90);
    let steep = (limits.steep_angle_rad.to_degrees().floor() as usize).min(90);
    (1..=steps.max(steep)).find_map(|k| {
        let theta = (k as f64).to_radians();
        dirs.iter().find_map(|&away| {
            let q = pose_turned(p, radius, away, theta);
            let vertical_ok = q.axis.z.clamp(-1.0, 1.0).acos() <= limits.max_from_vertical_rad;
            let own_ok = || drive.is_none_or(|(d, c)| d.hit(c, None, &q).is_none());
            (vertical_ok && free(check, tool, &q) && own_ok()).then_some((theta, away))
        })
    })
}

/// Path length along the run's tips: s[i].
fn arc_lengths(run: &[Pose]) -> Vec<f64> {
    let mut s = Vec::with_capacity(run.len());
    let mut acc = 0.0;
    for (i, p) in run.iter().enumerate() {
        if i > 0 {
            acc += p.tip.distance(run[i - 1].tip);
        }
        s.push(acc);
    }
    s
}

/// Upper envelope of the needs falling off at `rate` per mm on both sides.
fn spread(needs: &[(f64, DVec3)], s: &[f64], rate: f64) -> Vec<(f64, DVec3)> {
    let n = needs.len();
    let mut env = needs.to_vec();
    for i in 1..n {
        let carried = env[i - 1].0 - rate * (s[i] - s[i - 1]);
        if carried > env[i].0 {
            env[i] = (carried, env[i - 1].1);
        }
    }
    for i in (0..n.saturating_sub(1)).rev() {
        let carried = env[i + 1].0 - rate * (s[i + 1] - s[i]);
        if carried > env[i].0 {
            env[i] = (carried, env[i + 1].1);
        }
    }
    env
}

fn tilt_run(
    check: &PartCheck<'_>,
    tool: &ToolPieces,
    cutter: &Cutter,
    run: &[Pose],
    limits: &TiltAway,
    drive: Option<&DriveFace<'_>>,
) -> TiltResult {
    let hits: Vec<_> = run
        .iter()
        .map(|p| check.placement(tool, p.tip, p.axis))
        .collect();
    if hits.iter().all(Option::is_none) {
        let mut result = TiltResult::default();
        split_left_out(check, tool, &densify(check, tool, run), None, &mut result);
        return result;
    }
    let ball = cutter.kind == CutterKind::Ball;
    let radius = cutter.radius();
    let can_tilt = ball && limits.max_angle_rad > 0.0;
    let needs: Vec<(f64, DVec3)> = run
        .iter()
        .zip(&hits)
        .map(|(p, h)| match h {
            Some((point, _, _, part))
                if can_tilt && (*part != ToolPart::CuttingEnd || above_ball(p, *point, radius)) =>
            {
                required(
                    (check, tool, drive.map(|d| (d, cutter))),
                    radius,
                    p,
                    *point,
                    limits,
                )
                .unwrap_or((0.0, DVec3::ZERO))
            }
            _ => (0.0, DVec3::ZERO),
        })
        .collect();
    let s = arc_lengths(run);
    let env = spread(&needs, &s, limits.rate_rad_per_mm.max(0.0));
    let mut tilted = Vec::with_capacity(run.len());
    let mut result = TiltResult::default();
    for (p, &(theta, w)) in run.iter().zip(&env) {
        let away = (w - p.axis * w.dot(p.axis)).try_normalize();
        match away {
            Some(away) if theta > 0.0 => {
                let mut q = pose_turned(p, radius, away, theta);
                if q.axis.z.clamp(-1.0, 1.0).acos() > limits.max_from_vertical_rad {
                    q = *p;
                } else {
                    result.tilted_poses += 1;
                    result.max_tilt_rad = result.max_tilt_rad.max(theta);
                }
                tilted.push(q);
            }
            _ => tilted.push(*p),
        }
    }
    let tilted = follow_planned(run, &tilted, radius);
    let own = drive
        .filter(|_| result.tilted_poses > 0)
        .map(|d| (d, cutter));
    split_left_out(
        check,
        tool,
        &densify(check, tool, &tilted),
        own,
        &mut result,
    );
    result
}

/// Largest distance between the ball centre on a move between tilted poses and on the planned
/// move it replaces, mm.
const CENTRE_DRIFT_MM: f64 = 5e-5;

/// The tilted run with poses inserted into each move whose ends were tilted, so that the ball
/// centre follows the planned move. The machine moves the tip on a straight line and turns the
/// axis on a great circle, so the ball centre (tip + R·axis) bulges from the line of the
/// centres by about R·θ²/8 for an axis turn θ; the planned poses' steps (chord tolerance) rely
/// on the bulge of the planned axis turn, and a tilt that turns the axis less than the planned
/// axis turns lets the centre sag toward a convex face (1.4 µm on a 9 mm sphere). Inserted
/// poses put the centre on the planned move's centre at the tilted move's axis; between them
/// the difference falls with the square of the number of pieces.
fn follow_planned(run: &[Pose], tilted: &[Pose], radius: f64) -> Vec<Pose> {
    let mut out = Vec::with_capacity(tilted.len());
    for (i, qb) in tilted.iter().enumerate() {
        let prev = i
            .checked_sub(1)
            .and_then(|j| Some((run.get(j)?, run.get(i)?, tilted.get(j)?)));
        if let Some((a, b, qa)) = prev
            && (qa.axis != a.axis || qb.axis != b.axis)
        {
            let (pa, pb) = (Placement::of(a), Placement::of(b));
            let (ta, tb) = (Placement::of(qa), Placement::of(qb));
            let centre = |q: Placement| q.tip + q.axis * radius;
            let drift = centre(interpolate(ta, tb, 0.5)).distance(centre(interpolate(pa, pb, 0.5)));
            let pieces = ((drift / CENTRE_DRIFT_MM).sqrt().ceil() as usize).clamp(1, 64);
            out.extend((1..pieces).map(|k| {
                let s = k as f64 / pieces as f64;
                let axis = interpolate(ta, tb, s).axis;
                Pose {
                    tip: centre(interpolate(pa, pb, s)) - axis * radius,
                    axis,
                    cc: qa.cc.zip(qb.cc).map(|(x, y)| x.lerp(y, s)),
                    ..*qb
                }
            }));
        }
        out.push(*qb);
    }
    out
}

/// The run with poses inserted into every move that enters the part between its two poses
/// (a long straight step across a neighbouring face): placements every `step_mm` of tool
/// motion, so that the split leaves out just the part of the move that enters.
fn densify(check: &PartCheck<'_>, tool: &ToolPieces, run: &[Pose]) -> Vec<Pose> {
    let step = if check.step_mm.is_finite() && check.step_mm > 0.0 {
        check.step_mm
    } else {
        0.1
    };
    let mut out: Vec<Pose> = Vec::with_capacity(run.len());
    for (i, b) in run.iter().enumerate() {
        if let Some(a) = i.checked_sub(1).and_then(|j| run.get(j)) {
            let (pa, pb) = (Placement::of(a), Placement::of(b));
            let n = (motion_bound(pa, pb, tool.top(), tool.radius()) / step)
                .ceil()
                .clamp(1.0, 1e5) as usize;
            let mids: Vec<Pose> = (1..n)
                .map(|k| {
                    let t = k as f64 / n as f64;
                    let q = interpolate(pa, pb, t);
                    let cc = a.cc.zip(b.cc).map(|(x, y)| x.lerp(y, t));
                    Pose {
                        tip: q.tip,
                        axis: q.axis,
                        cc,
                        ..*b
                    }
                })
                .collect();
            if mids.iter().any(|q| !free(check, tool, q)) {
                out.extend(mids);
            }
        }
        out.push(*b);
    }
    out
}

/// Height above which the tool is clear of the part: the part's top plus the tool's largest
/// radius (a tilted holder reaches that far below its axis), mm.
#[must_use]
pub fn clear_height(check: &PartCheck<'_>, cutter: &Cutter) -> f64 {
    let tool = ToolPieces::of(cutter, check.whole_tool);
    check.bvh.bbox().max.z + tool.radius() + 1e-3
}

/// Where the tool, coming down to `p` along the linking's straight approach line (from above
/// the part, the last `APPROACH_HEIGHT` a fed plunge), enters another face; `None` when the
/// line is clear.
fn approach_hit(
    check: &PartCheck<'_>,
    tool: &ToolPieces,
    p: &Pose,
    top: f64,
) -> Option<PlacementHit> {
    let height = super::linking::APPROACH_HEIGHT;
    if p.axis.z <= super::linking::LEVEL_AXIS_Z {
        // Out along the level axis, then up (as the linking does).
        let out = p.tip + p.axis * height;
        let up = DVec3::new(out.x, out.y, top.max(out.z));
        return line_hit(check, tool, p.axis, p.tip, out, height)
            .or_else(|| line_hit(check, tool, p.axis, out, up, 0.0));
    }
    let end = super::linking::above(p, top.max(p.tip.z));
    let dir = (end - p.tip).try_normalize()?;
    let plunge = super::linking::APPROACH_HEIGHT / dir.z.max(0.1);
    line_hit(check, tool, p.axis, p.tip, end, plunge)
}

/// Where the tool (axis `axis`) moving with its tip from `from` to `to` enters another face;
/// checked every `step_mm` over the first `fine_mm`, every 1 mm beyond.
fn line_hit(
    check: &PartCheck<'_>,
    tool: &ToolPieces,
    axis: DVec3,
    from: DVec3,
    to: DVec3,
    fine_mm: f64,
) -> Option<PlacementHit> {
    let line = to - from;
    let length = line.length();
    let dir = line.try_normalize()?;
    let step = check.step_mm.max(0.01);
    let fine = fine_mm + step;
    let mut d = 0.0;
    while d < length {
        d += if d < fine { step } else { 1.0 };
        let tip = from + dir * d.min(length);
        if check.enters(tool, tip, axis) {
            return check.placement(tool, tip, axis);
        }
    }
    None
}

/// Distances along the tool axis tried for a sideways approach, mm.
const ESCAPES_MM: [f64; 6] = [10.0, 20.0, 40.0, 80.0, 160.0, 320.0];

/// The sideways approach to `p` where its straight approach (see
/// [`super::linking::above`]) enters the part: the least of [`ESCAPES_MM`] such that the tool
/// moving out along its own axis by that length, then straight up above the part, stays clear
/// (the linking plunges back along the same line). `None` when the straight approach is clear
/// or no escape is.
fn escape(check: &PartCheck<'_>, tool: &ToolPieces, p: &Pose, top: f64) -> Option<f64> {
    approach_hit(check, tool, p, top)?;
    sideways(check, tool, p, top)
}

/// The least of [`ESCAPES_MM`] whose escape (out along `p`'s axis, then up to `top`) is clear.
/// The line out along the axis is scanned once, with the samples [`line_hit`] takes on each
/// length (every `step_mm` over the first [`super::linking::APPROACH_HEIGHT`], every 1 mm
/// beyond, and the length's end): a hit at distance `d` blocks every length beyond `d`, so the
/// search ends there.
fn sideways(check: &PartCheck<'_>, tool: &ToolPieces, p: &Pose, top: f64) -> Option<f64> {
    // Beyond the part's box (grown by the tool's radius) a longer escape frees nothing more.
    let b = check.bvh.bbox();
    let grow = DVec3::splat(tool.radius());
    let exit = (0..3)
        .filter_map(|k| {
            let (d, t) = (p.axis[k], p.tip[k]);
            let wall = if d > 0.0 {
                b.max[k] + grow[k]
            } else {
                b.min[k] - grow[k]
            };
            (d.abs() > 1e-9).then(|| ((wall - t) / d).max(0.0))
        })
        .fold(f64::INFINITY, f64::min);
    let beyond = ESCAPES_MM
        .iter()
        .position(|&l| l >= exit)
        .unwrap_or(ESCAPES_MM.len() - 1);
    let dir = p.axis.try_normalize()?;
    let step = check.step_mm.max(0.01);
    let fine = super::linking::APPROACH_HEIGHT + step;
    let mut next = step;
    for &l in &ESCAPES_MM[..=beyond] {
        while next < l {
            if check.enters(tool, p.tip + dir * next, p.axis) {
                return None;
            }
            next += if next < fine { step } else { 1.0 };
        }
        let out = p.tip + dir * l;
        let up = DVec3::new(out.x, out.y, top.max(out.z));
        if !check.enters(tool, out, p.axis) && line_hit(check, tool, p.axis, out, up, 0.0).is_none()
        {
            return Some(l);
        }
    }
    None
}

/// The linking's approach route to (and retract from) pose `p` on a part: the length of the
/// sideways escape along the tool axis where the straight approach enters the part (out along
/// the axis by the least of 10–320 mm that is clear, then up), `None` for the straight approach.
#[must_use]
pub fn approach_route(check: &PartCheck<'_>, cutter: &Cutter, p: &Pose) -> Option<f64> {
    let tool = ToolPieces::of(cutter, check.whole_tool);
    escape(check, &tool, p, clear_height(check, cutter))
}

/// The approach to `p` enters the part both straight and along every escape: the hit of the
/// straight one.
fn approach_blocked(
    check: &PartCheck<'_>,
    tool: &ToolPieces,
    p: &Pose,
    top: f64,
) -> Option<PlacementHit> {
    let hit = approach_hit(check, tool, p, top)?;
    sideways(check, tool, p, top).is_none().then_some(hit)
}

/// Whether every move between consecutive `poses` is clear of the part (placements every
/// `step_mm` of tool motion): for stay-down links over the drive surface.
#[must_use]
pub fn moves_clear(check: &PartCheck<'_>, cutter: &Cutter, poses: &[Pose]) -> bool {
    let tool = ToolPieces::of(cutter, check.whole_tool);
    let dense = densify(check, &tool, poses);
    dense.len() == poses.len() && dense.iter().all(|p| free(check, &tool, p))
}

/// Check every pose again (with `drive`, also every pose and the move into it against the
/// drive face, exactly); split the run at the poses still hitting, and report each span. Then each piece loses its first and last poses while the approach line to them (or the
/// retract from them) enters the part; those are reported as approach spans.
fn split_left_out(
    check: &PartCheck<'_>,
    tool: &ToolPieces,
    run: &[Pose],
    drive: Option<(&DriveFace<'_>, &Cutter)>,
    result: &mut TiltResult,
) {
    let s = arc_lengths(run);
    let s = s.as_slice();
    let hits: Vec<_> = run
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            check.placement(tool, p.tip, p.axis).or_else(|| {
                let (d, c) = drive?;
                d.hit(c, i.checked_sub(1).and_then(|j| run.get(j)), p)
            })
        })
        .collect();
    let mut pieces: Vec<(usize, usize)> = Vec::new();
    let mut current: Vec<Pose> = Vec::new();
    let mut span: Option<(usize, usize, PlacementHit)> = None;
    for (i, (p, h)) in run.iter().zip(&hits).enumerate() {
        match h {
            Some(hit) => {
                if !current.is_empty() {
                    pieces.push((i - current.len(), i));
                    current.clear();
                }
                span = Some(match span {
                    Some((a, _, worst)) if worst.1 >= hit.1 => (a, i, worst),
                    Some((a, _, _)) => (a, i, *hit),
                    None => (i, i, *hit),
                });
            }
            None => {
                if let Some(sp) = span.take() {
                    result.left_out.push(left_out(run, s, sp));
                }
                current.push(*p);
            }
        }
    }
    if let Some(sp) = span {
        result.left_out.push(left_out(run, s, sp));
    }
    if !current.is_empty() {
        pieces.push((run.len() - current.len(), run.len()));
    }
    let top = check.bvh.bbox().max.z + tool.radius() + 1e-3;
    for (a, b) in pieces {
        let (a, b) = trim_approach((check, tool, drive), run, s, (a, b), top, result);
        if a < b {
            result.runs.push(run[a..b].to_vec());
        }
    }
}

/// The piece `run[a..b]` without its leading and trailing poses whose approach line enters
/// the part (each such stretch reported as an approach span).
fn trim_approach(
    (check, tool, drive): (
        &PartCheck<'_>,
        &ToolPieces,
        Option<(&DriveFace<'_>, &Cutter)>,
    ),
    run: &[Pose],
    s: &[f64],
    (mut a, mut b): (usize, usize),
    top: f64,
    result: &mut TiltResult,
) -> (usize, usize) {
    let mut worst: Option<PlacementHit> = None;
    let start = a;
    while a < b {
        match approach_blocked(check, tool, &run[a], top).or_else(|| plunge_gouge(drive, &run[a])) {
            Some(h) => {
                worst = Some(worst.filter(|w| w.1 >= h.1).unwrap_or(h));
                a += 1;
            }
            None => break,
        }
    }
    if let Some(w) = worst.take() {
        result.left_out.push(LeftOut {
            approach: true,
            ..left_out(run, s, (start, a - 1, w))
        });
    }
    let end = b;
    while b > a {
        match approach_blocked(check, tool, &run[b - 1], top)
            .or_else(|| plunge_gouge(drive, &run[b - 1]))
        {
            Some(h) => {
                worst = Some(worst.filter(|w| w.1 >= h.1).unwrap_or(h));
                b -= 1;
            }
            None => break,
        }
    }
    if let Some(w) = worst {
        result.left_out.push(LeftOut {
            approach: true,
            ..left_out(run, s, (b, end - 1, w))
        });
    }
    (a, b)
}

/// Step of the exact check along the fed plunge, mm.
const PLUNGE_STEP_MM: f64 = 0.05;

/// Where the fed plunge into `p` (along its axis: the last [`super::linking::APPROACH_HEIGHT`]
/// of the approach, measured in z unless the axis is level) gouges the drive face, exactly.
fn plunge_gouge(drive: Option<(&DriveFace<'_>, &Cutter)>, p: &Pose) -> Option<PlacementHit> {
    let (d, cutter) = drive?;
    let height = super::linking::APPROACH_HEIGHT;
    let length = if p.axis.z <= super::linking::LEVEL_AXIS_Z {
        height
    } else {
        height / p.axis.z.max(0.1)
    };
    let n = (length / PLUNGE_STEP_MM).ceil() as usize;
    (1..=n).find_map(|k| {
        let q = Pose {
            tip: p.tip + p.axis * (length * k as f64 / n as f64),
            cc: None,
            ..*p
        };
        d.hit(cutter, None, &q)
    })
}

fn left_out(run: &[Pose], s: &[f64], (a, b, worst): (usize, usize, PlacementHit)) -> LeftOut {
    LeftOut {
        start: run[a].tip,
        end: run[b].tip,
        length_mm: s[b] - s[a],
        poses: b - a + 1,
        face: worst.2,
        tool_part: worst.3,
        depth_mm: worst.1,
        approach: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_falls_off_at_the_rate() {
        let d = DVec3::X;
        let needs = vec![
            (0.0, DVec3::ZERO),
            (0.0, DVec3::ZERO),
            (0.3, d),
            (0.0, DVec3::ZERO),
        ];
        let s = [0.0, 1.0, 2.0, 10.0];
        let env = spread(&needs, &s, 0.1);
        assert!((env[1].0 - 0.2).abs() < 1e-12);
        assert!((env[0].0 - 0.1).abs() < 1e-12);
        assert_eq!(env[0].1, d);
        assert!(env[3].0 <= 0.0);
    }

    #[test]
    fn turning_about_the_ball_centre_keeps_the_centre() {
        let p = Pose::new(
            crate::toolpath::MoveKind::Cut,
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::Z,
            1000.0,
        );
        let q = pose_turned(&p, 3.0, DVec3::X, 20f64.to_radians());
        let c0 = p.tip + p.axis * 3.0;
        let c1 = q.tip + q.axis * 3.0;
        assert!(c0.distance(c1) < 1e-12);
        assert!((q.axis.angle_between(DVec3::Z) - 20f64.to_radians()).abs() < 1e-12);
        assert!(q.axis.x < 0.0, "turned away from +x");
    }
}
