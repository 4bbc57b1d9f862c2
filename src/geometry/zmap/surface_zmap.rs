//! A regular Z-map sampled from a parametric surface (the thesis's "2D Jacobian
//! inversion"): at every XY grid node find (u, v) with x(u,v) = x_i, y(u,v) = y_j by Newton's
//! method on the 2×2 Jacobian [[x_u, x_v], [y_u, y_v]], seeded from the neighbouring node's
//! solution (or, failing that, from the nearest point of a coarse parameter lattice), and store
//! z(u, v).

use glam::DVec2;

use super::error::ZmapError;
use super::grid::Grid;
use crate::geometry::surface::SurfaceGeom;

/// Lattice size per direction for the fallback seeds.
const SEED_LATTICE: usize = 33;
/// Newton iterations per attempt.
const NEWTON_ITERATIONS: usize = 40;

/// The result of [`zmap_from_surface`].
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceZmap {
    /// Heights (row ↔ y, column ↔ x); nodes the surface does not cover hold the empty value.
    pub grid: Grid,
    /// The (u, v) found for every node, row-major (`None` where the surface does not cover it).
    pub params: Vec<Option<DVec2>>,
    /// Number of nodes not covered.
    pub misses: usize,
}

/// Sample `surface` over `rows`×`cols` nodes at (x, y) = origin + (col·step, row·step): each
/// node's height is z(u, v) at the (u, v) whose x and y match the node within `xy_tol_mm`.
/// Nodes outside the surface's XY footprint (no such (u, v) inside the parameter domain) get
/// `empty_z`. Trimming curves are not considered (the whole carrier surface is sampled), and a
/// surface folding over itself in XY gives one of its sheets, not necessarily the top one.
///
/// # Errors
/// [`ZmapError::Option`] for a non-positive step or tolerance or a non-finite origin or empty
/// value, [`ZmapError::Shape`] for an empty or oversized grid.
pub fn zmap_from_surface(
    surface: &SurfaceGeom,
    origin: DVec2,
    step: f64,
    rows: usize,
    cols: usize,
    empty_z: f64,
    xy_tol_mm: f64,
) -> Result<SurfaceZmap, ZmapError> {
    let valid = step > 0.0
        && step.is_finite()
        && xy_tol_mm > 0.0
        && xy_tol_mm.is_finite()
        && origin.is_finite()
        && empty_z.is_finite();
    if !valid {
        return Err(ZmapError::Option(format!(
            "grid step and tolerance must be positive and origin finite, got step {step}, \
             tolerance {xy_tol_mm}"
        )));
    }
    if rows
        .checked_mul(cols)
        .is_none_or(|n| n == 0 || n > 10_000_000)
    {
        return Err(ZmapError::Shape(format!("{rows}×{cols} grid")));
    }
    let rect = surface.domain();
    let (u0, u1, v0, v1) = (rect.u.t0, rect.u.t1, rect.v.t0, rect.v.t1);
    if ![u0, u1, v0, v1].iter().all(|t| t.is_finite()) || u1 < u0 || v1 < v0 {
        return Err(ZmapError::Option(
            "the surface's parameter domain is not finite".into(),
        ));
    }
    // Coarse lattice of (parameter, XY position) for fallback seeds.
    let lattice: Vec<(DVec2, DVec2)> = (0..SEED_LATTICE * SEED_LATTICE)
        .map(|k| {
            let fu = (k % SEED_LATTICE) as f64 / (SEED_LATTICE - 1) as f64;
            let fv = (k / SEED_LATTICE) as f64 / (SEED_LATTICE - 1) as f64;
            let uv = DVec2::new(u0 + fu * (u1 - u0), v0 + fv * (v1 - v0));
            (uv, surface.point(uv.x, uv.y).truncate())
        })
        .filter(|(_, xy)| xy.is_finite())
        .collect();
    let newton = |target: DVec2, start: DVec2| invert_xy(surface, target, start, xy_tol_mm);
    let mut values = Vec::with_capacity(rows * cols);
    let mut params: Vec<Option<DVec2>> = Vec::with_capacity(rows * cols);
    let mut misses = 0;
    for r in 0..rows {
        for c in 0..cols {
            let target = origin + DVec2::new(c as f64, r as f64) * step;
            let left = if c > 0 {
                params.last().copied().flatten()
            } else {
                None
            };
            let below = if r > 0 {
                params.get((r - 1) * cols + c).copied().flatten()
            } else {
                None
            };
            let mut found = left
                .and_then(|s| newton(target, s))
                .or_else(|| below.and_then(|s| newton(target, s)));
            if found.is_none() {
                // Three nearest lattice points in XY as seeds.
                let mut near: Vec<&(DVec2, DVec2)> = lattice.iter().collect();
                near.sort_by(|p, q| {
                    p.1.distance_squared(target)
                        .total_cmp(&q.1.distance_squared(target))
                });
                found = near.iter().take(3).find_map(|(uv, _)| newton(target, *uv));
            }
            let z = found.map(|uv| surface.point(uv.x, uv.y).z);
            match z {
                Some(z) if z.is_finite() => values.push(z),
                _ => {
                    values.push(empty_z);
                    misses += 1;
                    found = None;
                }
            }
            params.push(found);
        }
    }
    Ok(SurfaceZmap {
        grid: Grid::new(rows, cols, values)?,
        params,
        misses,
    })
}

/// The (u, v) of `surface` whose x and y equal `target` within `xy_tol_mm`: Newton on the 2×2
/// Jacobian [[x_u, x_v], [y_u, y_v]] from `start`, kept inside the parameter domain. `None` when
/// it does not converge or leaves the domain (the point is outside the surface's footprint).
pub(crate) fn invert_xy(
    surface: &SurfaceGeom,
    target: DVec2,
    start: DVec2,
    xy_tol_mm: f64,
) -> Option<DVec2> {
    let rect = surface.domain();
    let clamp = |p: DVec2| {
        DVec2::new(
            p.x.clamp(rect.u.t0.min(rect.u.t1), rect.u.t1.max(rect.u.t0)),
            p.y.clamp(rect.v.t0.min(rect.v.t1), rect.v.t1.max(rect.v.t0)),
        )
    };
    let mut uv = clamp(start);
    for _ in 0..NEWTON_ITERATIONS {
        let d = surface.derivs(uv.x, uv.y);
        let r = target - d.p.truncate();
        if !r.is_finite() {
            return None;
        }
        if r.length() <= xy_tol_mm {
            return Some(uv);
        }
        let (a, b, c, e) = (d.su.x, d.sv.x, d.su.y, d.sv.y);
        let det = a * e - b * c;
        if !(det.abs() > 1e-300) {
            return None;
        }
        let du = (e * r.x - b * r.y) / det;
        let dv = (a * r.y - c * r.x) / det;
        let next = clamp(uv + DVec2::new(du, dv));
        if next == uv {
            return None; // stuck on the domain boundary: the node is outside
        }
        uv = next;
    }
    None
}
