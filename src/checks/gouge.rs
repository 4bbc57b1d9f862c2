//! Gouge checks at poses and along moves, against the exact surface (thesis §2.11, done as
//! distance queries instead of the thesis's 181-line footprint scan):
//!
//! - **Local gouge** (curvature, §2.11a): at the contact the tool must curve at least as much as
//!   the surface in every tangent direction. The tool's lower surface at the contact is a torus
//!   point (ball: r_c = R, flat: r_c = 0) with curvature 1/r_c along the meridian and
//!   sin γ/(R_f + r_c sin γ) along the parallel (γ = angle between axis and normal; for a pure
//!   lead S this is the effective radius R_f/sin S + r_c across the feed, Rao 1997). The test is
//!   that `K_tool − K_surface` is positive semi-definite ([`curvature_margin`]).
//! - **Rear gouge** (§2.11b): the surface under the tool's footprint is sampled on a uv grid
//!   around the contact and the signed distance of each surface point to the tool solid
//!   ([`crate::tools::solid`]) is evaluated; the deepest point is refined by a pattern search
//!   in uv. Depth = −(minimum signed distance).
//!
//! Along a move, placements are checked at parameter steps in which no tool point moves more
//! than `step_mm`: the swept tool between two checked placements lies within `step_mm / 2` of
//! one of them, so a gouge missed between them is at most `step_mm / 2` deep (the report's
//! `bound_mm`). The footprint grid is refined locally, so within a placement the depth is exact
//! up to the pattern search's tolerance (1e-9 of the grid step) when the deepest point's basin is
//! hit by the grid (grid spacing ≈ 2.6·R / (n − 1)).

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::motion::{Placement, angle_between, cutting_moves, interpolate, motion_bound};
use super::{CheckError, FacePatch};
use crate::toolpath::Pose;
use crate::tools::solid::{ToolPart, ToolSolid};
use crate::tools::{Cutter, CutterKind};

/// Where a gouge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum GougeKind {
    /// At the contact: the surface curves into the tool more than the tool curves.
    Local,
    /// Elsewhere under the cutting end (the heel of a flat or bull-nose bottom).
    Rear,
    /// The fluted cylinder above the cutting end.
    Flank,
    /// Shank or holder (only with `whole_tool`).
    Shank,
}

/// A gouge found at a pose or on the move into it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Gouge {
    /// Index of the pose (the move into it when `move_param` < 1).
    pub pose: usize,
    /// Parameter along the move into the pose where it is deepest (1 = at the pose).
    pub move_param: f64,
    /// Surface parameters of the deepest point.
    pub uv: DVec2,
    /// Deepest surface point, mm.
    pub point: DVec3,
    /// Depth, mm (> 0).
    pub depth_mm: f64,
    /// Kind.
    pub kind: GougeKind,
    /// Smallest lead (rad) at the pose's contact and feed direction with no penetration, when
    /// one ≤ `max_lead_rad` exists and it was asked for.
    pub fixing_lead_rad: Option<f64>,
}

/// Options of the gouge checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GougeOptions {
    /// Depths up to this are not gouges, mm.
    pub tolerance_mm: f64,
    /// Footprint grid: n × n surface samples (≥ 3).
    pub footprint_n: usize,
    /// Footprint half-width as a multiple of the tool's largest radius.
    pub footprint_scale: f64,
    /// Along moves: largest motion of any tool point between checked placements, mm.
    pub step_mm: f64,
    /// Check the whole tool (shank and holder) instead of the fluted part.
    pub whole_tool: bool,
    /// Upper end of the lead search, rad.
    pub max_lead_rad: f64,
    /// Compute the fixing lead for each gouge of a path report.
    pub fix_leads: bool,
}

impl Default for GougeOptions {
    fn default() -> Self {
        Self {
            tolerance_mm: 1e-4,
            footprint_n: 21,
            footprint_scale: 1.3,
            step_mm: 0.05,
            whole_tool: false,
            max_lead_rad: 60f64.to_radians(),
            fix_leads: true,
        }
    }
}

/// Gouges of a whole path.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GougeReport {
    /// One entry per gouging pose (the deepest of the pose and the move into it), in pose
    /// order.
    pub gouges: Vec<Gouge>,
    /// Largest depth, mm (0 when none).
    pub max_depth_mm: f64,
    /// Placements checked (poses and intermediate placements).
    pub placements: usize,
    /// Bound on a gouge missed between checked placements, mm (`step_mm / 2`).
    pub bound_mm: f64,
}

/// Effective radius of `cutter` at the contact across the feed for an angle `gamma_rad` between
/// its axis and the surface normal (the curvature radius of the tool along the parallel through
/// the contact): ball R, bull-nose R_f/sin γ + r_c, flat R/sin γ (infinite at γ = 0); `None` for a
/// cone.
#[must_use]
pub fn effective_radius(cutter: &Cutter, gamma_rad: f64) -> Option<f64> {
    let (flat, corner) = torus_sizes(cutter)?;
    let s = gamma_rad.sin().abs();
    if flat <= 0.0 {
        return Some(corner);
    }
    Some(if s > 0.0 {
        flat / s + corner
    } else {
        f64::INFINITY
    })
}

/// Flat radius and corner radius of a torus-type cutter (ball: 0 and R; flat: R and 0).
fn torus_sizes(c: &Cutter) -> Option<(f64, f64)> {
    match c.kind {
        CutterKind::Ball => Some((0.0, c.radius())),
        CutterKind::Flat => Some((c.radius(), 0.0)),
        CutterKind::BullNose { corner_radius } => Some((c.radius() - corner_radius, corner_radius)),
        CutterKind::Cone { .. } => None,
    }
}

/// Local-gouge margin at the contact `uv` for the tool axis `axis`: the smallest eigenvalue of
/// `K_tool − K_surface` (1/mm) in the tangent plane, tool-side signs. Negative = local gouge.
/// `None` for a cone or where the normal is undefined. A sharp corner (flat end mill) counts as
/// infinitely curved along its meridian.
#[must_use]
pub fn curvature_margin(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    uv: DVec2,
    axis: DVec3,
) -> Option<f64> {
    let (flat, corner) = torus_sizes(cutter)?;
    let d = patch.derivs(uv);
    let n = d.normal()? * patch.sign();
    let gamma = angle_between(axis, n);
    let e_par = axis
        .cross(n)
        .try_normalize()
        .unwrap_or_else(|| n.any_orthonormal_vector());
    let e_mer = n.cross(e_par);
    let k_par = if flat + corner * gamma.sin() > 0.0 {
        gamma.sin() / (flat + corner * gamma.sin())
    } else {
        1.0 / corner.max(1e-300)
    };
    let s = patch.sign();
    let ks_par = s * d.normal_curvature_along(e_par)?;
    let ks_mer = s * d.normal_curvature_along(e_mer)?;
    let ks_diag = s * d.normal_curvature_along(e_par + e_mer)?;
    // Off-diagonal term of the surface's second form in (e_par, e_mer): κ(45°) = (a + c)/2 + b.
    let b = ks_diag - 0.5 * (ks_par + ks_mer);
    let a = k_par - ks_par;
    if corner <= 0.0 {
        // Infinite meridian curvature: only the parallel direction constrains.
        return Some(a);
    }
    let c = 1.0 / corner - ks_mer;
    let mean = 0.5 * (a + c);
    let rad = (0.5 * (a - c)).hypot(b);
    Some(mean - rad)
}

/// Build the tool placement (tip, unit axis) touching the surface at `cc` with tool-side normal
/// `n`, feed direction `feed` (projected into the tangent plane), lead `lead_rad` (axis leaning
/// toward the feed) and tilt `tilt_rad` (sideways, toward `t = f × n`):
/// `a = cos S cos T n + sin S f + cos S sin T t`, and the cutter-location formula of Choi (digest
/// §2.10) for torus-type cutters. Cones touch with their apex. `None` when `feed` is along `n`.
#[must_use]
pub fn pose_from_contact(
    cutter: &Cutter,
    cc: DVec3,
    n: DVec3,
    feed: DVec3,
    lead_rad: f64,
    tilt_rad: f64,
) -> Option<(DVec3, DVec3)> {
    let n = n.try_normalize()?;
    let f = (feed - n * feed.dot(n)).try_normalize()?;
    let t = f.cross(n);
    let (ss, cs) = lead_rad.sin_cos();
    let (st, ct) = tilt_rad.sin_cos();
    let a = (n * (cs * ct) + f * ss + t * (cs * st)).try_normalize()?;
    let Some((flat, corner)) = torus_sizes(cutter) else {
        return Some((cc, a));
    };
    let an = a.dot(n);
    let w = n - a * an;
    let w = w.try_normalize().unwrap_or(-f);
    let centre = cc + n * corner + w * flat;
    Some((centre - a * corner, a))
}

struct Deepest {
    depth: f64,
    uv: DVec2,
    point: DVec3,
    part: ToolPart,
}

fn project(patch: &FacePatch<'_>, p: DVec3, hint: Option<DVec2>) -> DVec2 {
    match hint {
        Some(h) => patch.surface.closest_point_near(p, patch.rect, h).uv,
        None => patch.surface.closest_point(p, patch.rect, None).uv,
    }
}

/// The deepest penetration of the placed tool: the surface side (surface points inside the
/// solid, by signed distance) and, for sharp edges, the tool side (the rim of a flat end mill or
/// the apex of a cone below the surface, by distance to the surface): a sharp edge grazing a
/// surface cuts a sliver too thin for the surface grid to hit.
fn deepest(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    solid: &ToolSolid,
    q: Placement,
    hint: DVec2,
    opts: &GougeOptions,
) -> Option<Deepest> {
    let uv0 = project(patch, q.tip, Some(hint));
    let surface_side = deepest_surface_point(patch, solid, q, uv0, opts);
    let edge = match cutter.kind {
        CutterKind::Flat => deepest_rim(patch, q, cutter.radius(), uv0),
        CutterKind::Cone { .. } => deepest_rim(patch, q, 0.0, uv0),
        CutterKind::Ball | CutterKind::BullNose { .. } => None,
    };
    match (surface_side, edge) {
        (Some(a), Some(b)) => Some(if b.depth > a.depth { b } else { a }),
        (a, b) => a.or(b),
    }
}

/// Depth below the surface of the tool point `p`: its distance to the closest surface point,
/// positive when it lies on the material side of the tool-side normal there.
fn point_depth(patch: &FacePatch<'_>, p: DVec3, hint: DVec2) -> Option<(f64, DVec2, DVec3)> {
    let sp = patch.surface.closest_point_near(p, patch.rect, hint);
    let (_, n) = patch.point_normal(sp.uv)?;
    Some((-(p - sp.point).dot(n), sp.uv, sp.point))
}

/// The deepest point of the circle of radius `radius` at the tip plane (the rim of a flat end
/// mill; radius 0 = the apex): 96 points walked around the circle, the best refined by golden
/// section on the angle.
fn deepest_rim(patch: &FacePatch<'_>, q: Placement, radius: f64, uv0: DVec2) -> Option<Deepest> {
    let e1 = q.axis.any_orthonormal_vector();
    let e2 = q.axis.cross(e1);
    let at = |phi: f64| q.tip + (e1 * phi.cos() + e2 * phi.sin()) * radius;
    let m = if radius > 0.0 { 96 } else { 1 };
    let mut hint = uv0;
    let mut best: Option<(f64, f64, DVec2, DVec3)> = None;
    for k in 0..m {
        let phi = std::f64::consts::TAU * k as f64 / m as f64;
        let Some((d, uv, p)) = point_depth(patch, at(phi), hint) else {
            continue;
        };
        hint = uv;
        if best.is_none_or(|b| d > b.0) {
            best = Some((d, phi, uv, p));
        }
    }
    let (mut d, phi, mut uv, mut point) = best?;
    if m > 1 {
        let g = 0.5 * (5.0_f64.sqrt() - 1.0);
        let h = std::f64::consts::TAU / m as f64;
        let (mut lo, mut hi) = (phi - h, phi + h);
        for _ in 0..40 {
            let x1 = hi - g * (hi - lo);
            let x2 = lo + g * (hi - lo);
            let f1 = point_depth(patch, at(x1), uv);
            let f2 = point_depth(patch, at(x2), uv);
            let (d1, d2) = (
                f1.map_or(f64::NEG_INFINITY, |f| f.0),
                f2.map_or(f64::NEG_INFINITY, |f| f.0),
            );
            if d1 >= d2 {
                hi = x2;
            } else {
                lo = x1;
            }
            for f in [f1, f2].into_iter().flatten() {
                if f.0 > d {
                    (d, uv, point) = f;
                }
            }
        }
    }
    (d > 0.0).then_some(Deepest {
        depth: d,
        uv,
        point,
        part: ToolPart::CuttingEnd,
    })
}

/// Deepest surface point inside the placed solid, over the footprint around `uv0`.
fn deepest_surface_point(
    patch: &FacePatch<'_>,
    solid: &ToolSolid,
    q: Placement,
    uv0: DVec2,
    opts: &GougeOptions,
) -> Option<Deepest> {
    let d0 = patch.derivs(uv0);
    let ext = opts.footprint_scale * solid.max_radius();
    let half = DVec2::new(
        ext / d0.su.length().max(1e-12),
        ext / d0.sv.length().max(1e-12),
    );
    let half = half.min(DVec2::new(patch.rect.u.len(), patch.rect.v.len()));
    let n = opts.footprint_n.max(3);
    let sd = |uv: DVec2| {
        let p = patch.surface.point(uv.x, uv.y);
        solid.signed_distance_at(p, q.tip, q.axis)
    };
    let mut best = (f64::INFINITY, uv0);
    for i in 0..n {
        for j in 0..n {
            let s = DVec2::new(i as f64, j as f64) / (n - 1) as f64 * 2.0 - 1.0;
            let uv = patch.clamp(uv0 + half * s);
            let v = sd(uv);
            if v < best.0 {
                best = (v, uv);
            }
        }
    }
    let step = 2.0 * half / (n - 1) as f64;
    if best.0 >= 0.5 * step.length() * d0.su.length().max(d0.sv.length()) {
        return None;
    }
    // Pattern search from the best grid point.
    let (mut v, mut uv) = best;
    let mut h = step;
    for _ in 0..300 {
        let mut moved = false;
        for dir in [
            DVec2::X,
            DVec2::NEG_X,
            DVec2::Y,
            DVec2::NEG_Y,
            DVec2::ONE,
            DVec2::NEG_ONE,
            DVec2::new(1.0, -1.0),
            DVec2::new(-1.0, 1.0),
        ] {
            let c = patch.clamp(uv + dir * h);
            let w = sd(c);
            if w < v {
                (v, uv) = (w, c);
                moved = true;
            }
        }
        if !moved {
            h *= 0.5;
            if h.x <= 1e-9 * step.x && h.y <= 1e-9 * step.y {
                break;
            }
        }
    }
    if v >= 0.0 {
        return None;
    }
    let point = patch.surface.point(uv.x, uv.y);
    let dp = point - q.tip;
    let z = dp.dot(q.axis);
    let rho = (dp - q.axis * z).length();
    let (_, part) = solid.signed_distance_part_rz(rho, z);
    // Depth = how far the tool reaches below this point along the normal (≥ −v): march to the
    // solid's exit along −n (the distance field is exact, so each step stays inside).
    let n = patch.point_normal(uv).map_or(-q.axis, |(_, n)| n);
    let mut t = -v;
    for _ in 0..200 {
        let d = solid.signed_distance_at(point - n * t, q.tip, q.axis);
        if d >= -1e-12 {
            break;
        }
        t -= d;
    }
    Some(Deepest {
        depth: t,
        uv,
        point,
        part,
    })
}

fn kind_of(part: ToolPart, local: bool) -> GougeKind {
    match part {
        ToolPart::CuttingEnd if local => GougeKind::Local,
        ToolPart::CuttingEnd => GougeKind::Rear,
        ToolPart::Flutes => GougeKind::Flank,
        ToolPart::Shank | ToolPart::Holder(_) => GougeKind::Shank,
    }
}

fn solid_for(cutter: &Cutter, opts: &GougeOptions) -> ToolSolid {
    if opts.whole_tool {
        cutter.solid()
    } else {
        cutter.cutting_solid()
    }
}

/// Check one placement (tip, unit axis) with an optional contact `cc_uv` (used for the
/// footprint's centre and the local test; otherwise the tip is projected onto the surface).
fn check_placement(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    solid: &ToolSolid,
    q: Placement,
    cc_uv: Option<DVec2>,
    opts: &GougeOptions,
) -> Option<(Deepest, GougeKind)> {
    let uv0 = match cc_uv {
        Some(uv) => uv,
        None => project(patch, q.tip, None),
    };
    let dp = deepest(patch, cutter, solid, q, uv0, opts)?;
    if dp.depth <= opts.tolerance_mm {
        return None;
    }
    let near_contact = cc_uv.is_some_and(|uv| {
        let c = patch.surface.point(uv.x, uv.y);
        (c - dp.point).length() <= 0.25 * cutter.radius()
    });
    let local = near_contact
        && cc_uv
            .and_then(|uv| curvature_margin(patch, cutter, uv, q.axis))
            .is_some_and(|m| m < 0.0);
    let kind = kind_of(dp.part, local);
    Some((dp, kind))
}

/// Check one pose: the deepest point of the surface inside the tool, when deeper than the
/// tolerance. The pose's `cc`, when set, centres the footprint and decides Local against Rear.
#[must_use]
pub fn check_pose(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    pose: &Pose,
    index: usize,
    opts: &GougeOptions,
) -> Option<Gouge> {
    let solid = solid_for(cutter, opts);
    let q = Placement::of(pose);
    let axis = q.axis.try_normalize()?;
    let q = Placement { axis, ..q };
    let cc_uv = pose.cc.map(|c| project(patch, c, None));
    let (dp, kind) = check_placement(patch, cutter, &solid, q, cc_uv, opts)?;
    Some(Gouge {
        pose: index,
        move_param: 1.0,
        uv: dp.uv,
        point: dp.point,
        depth_mm: dp.depth,
        kind,
        fixing_lead_rad: None,
    })
}

/// Check the move from `a` to `b` (pose index `index` = `b`'s), its interior placements only
/// (the ends are poses: check them with [`check_pose`]); the deepest gouge on it.
#[must_use]
pub fn check_move(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    a: &Pose,
    b: &Pose,
    index: usize,
    opts: &GougeOptions,
) -> Option<Gouge> {
    let solid = solid_for(cutter, opts);
    move_gouges(patch, cutter, &solid, a, b, index, opts, false).0
}

#[allow(clippy::too_many_arguments)]
fn move_gouges(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    solid: &ToolSolid,
    a: &Pose,
    b: &Pose,
    index: usize,
    opts: &GougeOptions,
    with_end: bool,
) -> (Option<Gouge>, usize) {
    let (Some(aa), Some(ba)) = (a.axis.try_normalize(), b.axis.try_normalize()) else {
        return (None, 0);
    };
    let pa = Placement {
        tip: a.tip,
        axis: aa,
    };
    let pb = Placement {
        tip: b.tip,
        axis: ba,
    };
    let motion = motion_bound(pa, pb, solid.top(), solid.max_radius());
    let steps = (motion / opts.step_mm.max(1e-6)).ceil().clamp(1.0, 1e5) as usize;
    let ca = a.cc.map(|c| project(patch, c, None));
    let cb = b.cc.map(|c| project(patch, c, None));
    let mut hint = ca.unwrap_or_else(|| project(patch, pa.tip, None));
    let mut best: Option<Gouge> = None;
    let mut count = 0;
    let last = if with_end {
        steps
    } else {
        steps.saturating_sub(1)
    };
    for k in 1..=last {
        let s = k as f64 / steps as f64;
        let q = interpolate(pa, pb, s);
        let is_end = k == steps;
        let cc_uv = if is_end { cb } else { None };
        hint = project(patch, q.tip, Some(hint));
        let centre = cc_uv.or(Some(hint));
        count += 1;
        let Some((dp, kind)) = check_placement(patch, cutter, solid, q, centre, opts) else {
            continue;
        };
        let kind = if cc_uv.is_none() && kind == GougeKind::Local {
            GougeKind::Rear
        } else {
            kind
        };
        if best.is_none_or(|g| dp.depth > g.depth_mm) {
            best = Some(Gouge {
                pose: index,
                move_param: s,
                uv: dp.uv,
                point: dp.point,
                depth_mm: dp.depth,
                kind,
                fixing_lead_rad: None,
            });
        }
    }
    (best, count)
}

/// The smallest lead (rad) in `[min_lead_rad, opts.max_lead_rad]` at which the tool touching
/// `cc_uv` with feed direction `feed` and tilt `tilt_rad` does not penetrate the surface deeper
/// than the tolerance, by bisection to 1e-6 rad (assumes the depth decreases with the lead, as it
/// does for the heel of flat and bull-nose cutters). `Some(min_lead_rad)` when that already
/// clears; `None` when even the maximum lead gouges.
#[must_use]
pub fn required_lead(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    cc_uv: DVec2,
    feed: DVec3,
    tilt_rad: f64,
    min_lead_rad: f64,
    opts: &GougeOptions,
) -> Option<f64> {
    let (cc, n) = patch.point_normal(cc_uv)?;
    let solid = solid_for(cutter, opts);
    let gouges = |lead: f64| -> Option<bool> {
        let (tip, axis) = pose_from_contact(cutter, cc, n, feed, lead, tilt_rad)?;
        let q = Placement { tip, axis };
        let d = deepest(patch, cutter, &solid, q, cc_uv, opts);
        Some(d.is_some_and(|d| d.depth > opts.tolerance_mm))
    };
    let (mut lo, mut hi) = (min_lead_rad, opts.max_lead_rad);
    if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
        return None;
    }
    if !gouges(lo)? {
        return Some(lo);
    }
    if gouges(hi)? {
        return None;
    }
    while hi - lo > 1e-6 {
        let mid = 0.5 * (lo + hi);
        if gouges(mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(hi)
}

/// Lead and tilt of `axis` relative to the tool-side normal `n` and feed `f` (inverse of
/// [`pose_from_contact`]'s axis formula).
fn lead_tilt(axis: DVec3, n: DVec3, f: DVec3) -> (f64, f64) {
    let t = f.cross(n);
    let lead = axis.dot(f).clamp(-1.0, 1.0).asin();
    let tilt = axis.dot(t).atan2(axis.dot(n));
    (lead, tilt)
}

/// Check every cutting pose and every cutting move of a path (in parallel). For each gouge with a
/// known contact (`cc`) and `opts.fix_leads`, the fixing lead is searched from the pose's current
/// lead with its current tilt, the feed being the move's direction.
///
/// # Errors
/// [`CheckError::BadPose`] for a non-finite tip or axis, [`CheckError::BadOption`] for bad
/// options, [`CheckError::Tool`] for an invalid cutter.
pub fn check_path(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    poses: &[Pose],
    opts: &GougeOptions,
) -> Result<GougeReport, CheckError> {
    cutter.validate()?;
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if !positive(opts.step_mm) || !positive(opts.footprint_scale) || !(opts.tolerance_mm >= 0.0) {
        return Err(CheckError::BadOption {
            name: "step_mm/footprint_scale/tolerance_mm",
            message: "must be positive and finite".into(),
        });
    }
    for (index, p) in poses.iter().enumerate() {
        if !(p.tip.is_finite() && p.axis.is_finite() && p.axis.length() > 0.5) {
            return Err(CheckError::BadPose { index });
        }
    }
    let solid = solid_for(cutter, opts);
    let moves = cutting_moves(poses);
    let results: Vec<(Option<Gouge>, usize)> = moves
        .par_iter()
        .map(|&(i0, i1)| {
            let (Some(a), Some(b)) = (poses.get(i0), poses.get(i1)) else {
                return (None, 0);
            };
            let (mut g, count) = if i0 == i1 {
                (check_pose(patch, cutter, b, i1, opts), 1)
            } else {
                move_gouges(patch, cutter, &solid, a, b, i1, opts, true)
            };
            if let Some(gg) = g.as_mut()
                && opts.fix_leads
            {
                gg.fixing_lead_rad = fixing_lead(patch, cutter, a, b, opts);
            }
            (g, count)
        })
        .collect();
    let placements = results.iter().map(|r| r.1).sum();
    let gouges: Vec<Gouge> = results.into_iter().filter_map(|r| r.0).collect();
    let max_depth_mm = gouges.iter().fold(0.0_f64, |m, g| m.max(g.depth_mm));
    Ok(GougeReport {
        gouges,
        max_depth_mm,
        placements,
        bound_mm: 0.5 * opts.step_mm,
    })
}

fn fixing_lead(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    a: &Pose,
    b: &Pose,
    opts: &GougeOptions,
) -> Option<f64> {
    let cc = b.cc?;
    let uv = project(patch, cc, None);
    let (_, n) = patch.point_normal(uv)?;
    let dir = b.tip - a.tip;
    let f = (dir - n * dir.dot(n)).try_normalize()?;
    let (lead, tilt) = lead_tilt(b.axis.try_normalize()?, n, f);
    required_lead(patch, cutter, uv, f, tilt, lead.max(0.0), opts)
}
