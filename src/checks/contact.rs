//! The tool at a contact point: effective radius, the local-gouge (curvature) margin, and the
//! placement from a contact point, feed, lead and tilt.

use glam::{DVec2, DVec3};

use super::FacePatch;
use super::motion::angle_between;
use crate::tools::{Cutter, CutterKind};

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
pub(crate) fn torus_sizes(c: &Cutter) -> Option<(f64, f64)> {
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
/// `a = cos S cos T n + sin S f + cos S sin T t`, and the cutter-location formula of Choi for
/// torus-type cutters. Cones touch with their apex. `None` when `feed` is along `n`.
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
