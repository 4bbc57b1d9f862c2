//! The deepest penetration of one placed tool into the surface under its footprint (see
//! [`super::gouge`] for the method and its error bound).

use glam::{DVec2, DVec3};

use super::FacePatch;
use super::gouge::GougeOptions;
use super::motion::Placement;
use crate::tools::solid::{ToolPart, ToolSolid};
use crate::tools::{Cutter, CutterKind};

/// The deepest point of a penetration.
pub(crate) struct Deepest {
    /// How far the tool reaches below the surface there, mm.
    pub depth: f64,
    /// Surface parameters.
    pub uv: DVec2,
    /// Surface point, mm.
    pub point: DVec3,
    /// The tool part that penetrates.
    pub part: ToolPart,
}

pub(crate) fn project(patch: &FacePatch<'_>, p: DVec3, hint: Option<DVec2>) -> DVec2 {
    match hint {
        Some(h) => patch.surface.closest_point_near(p, patch.rect, h).uv,
        None => patch.surface.closest_point(p, patch.rect, None).uv,
    }
}

/// The deepest penetration of the placed tool: the surface side (surface points inside the
/// solid, by signed distance) and, for sharp edges, the tool side (the rim of a flat end mill or
/// the apex of a cone below the surface, by distance to the surface): a sharp edge grazing a
/// surface cuts a sliver too thin for the surface grid to hit.
pub(crate) fn deepest(
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
