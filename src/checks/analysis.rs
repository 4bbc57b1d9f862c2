//! Surface analysis (thesis §2.4, with signed normal curvatures in place of 3-point circles):
//! scan a patch for its smallest concave and convex radii along the u and v iso-directions
//! (normal curvature of the iso-parametric curves) and principal, with their locations; and
//! per-point curvatures for the workstation's colour map.
//!
//! Curvatures come from the analytic fundamental forms (not 3-point circles) and are signed
//! with respect to the tool-side normal: positive = concave as the tool sees it. Extremes are
//! tracked in curvature, not radius, so flat regions give no meaningless huge radii; each
//! extreme found on the grid is then refined by a local pattern search in uv.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::{CheckError, FacePatch};

/// Curvatures at one sample, signed with respect to the tool-side normal (1/mm).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CurvatureSample {
    /// Smaller principal curvature.
    pub k_min: f64,
    /// Larger principal curvature.
    pub k_max: f64,
    /// Mean curvature (k_min + k_max)/2.
    pub mean: f64,
    /// Gaussian curvature k_min·k_max.
    pub gaussian: f64,
    /// Normal curvature along the u iso-direction (`S_u`).
    pub k_u: f64,
    /// Normal curvature along the v iso-direction (`S_v`).
    pub k_v: f64,
}

/// Curvatures at each of `uvs` (`None` where the normal is undefined), tool-side signs.
#[must_use]
pub fn curvature_at(patch: &FacePatch<'_>, uvs: &[DVec2]) -> Vec<Option<CurvatureSample>> {
    uvs.par_iter().map(|&uv| sample(patch, uv)).collect()
}

fn sample(patch: &FacePatch<'_>, uv: DVec2) -> Option<CurvatureSample> {
    let d = patch.derivs(uv);
    let p = d.principal()?;
    let s = patch.sign();
    let (k_min, k_max) = if s > 0.0 {
        (p.k_min, p.k_max)
    } else {
        (-p.k_max, -p.k_min)
    };
    let k_u = s * d.normal_curvature(1.0, 0.0)?;
    let k_v = s * d.normal_curvature(0.0, 1.0)?;
    Some(CurvatureSample {
        k_min,
        k_max,
        mean: 0.5 * (k_min + k_max),
        gaussian: k_min * k_max,
        k_u,
        k_v,
    })
}

/// An extreme radius and where it is.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RadiusExtreme {
    /// Radius, mm (positive; concave or convex is said by the field holding it).
    pub radius_mm: f64,
    /// Parameters.
    pub uv: DVec2,
    /// Surface point, mm.
    pub point: DVec3,
}

/// Smallest concave and convex radii of a patch (`None` where the patch has no such region).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct SurfaceAnalysis {
    /// Smallest concave radius along the u iso-direction.
    pub min_concave_u: Option<RadiusExtreme>,
    /// Smallest concave radius along the v iso-direction.
    pub min_concave_v: Option<RadiusExtreme>,
    /// Smallest concave principal radius (1 / largest positive k_max).
    pub min_concave_principal: Option<RadiusExtreme>,
    /// Smallest convex radius along u.
    pub min_convex_u: Option<RadiusExtreme>,
    /// Smallest convex radius along v.
    pub min_convex_v: Option<RadiusExtreme>,
    /// Smallest convex principal radius (1 / |most negative k_min|).
    pub min_convex_principal: Option<RadiusExtreme>,
    /// Samples scanned (grid), and those with an undefined normal.
    pub samples: usize,
    /// Samples skipped for an undefined normal.
    pub degenerate: usize,
}

/// The six tracked quantities: curvature values whose maximum gives the smallest radius.
const QUANTITIES: usize = 6;

fn quantities(c: &CurvatureSample) -> [f64; QUANTITIES] {
    [c.k_u, c.k_v, c.k_max, -c.k_u, -c.k_v, -c.k_min]
}

fn quantity(patch: &FacePatch<'_>, uv: DVec2, q: usize) -> Option<f64> {
    sample(patch, uv).and_then(|c| quantities(&c).get(q).copied())
}

/// Scan `patch` on an `n × n` grid (ends included, n ≥ 2) and refine each extreme locally.
///
/// # Errors
/// [`CheckError::BadOption`] for n < 2 or n > 10 000.
pub fn analyze(patch: &FacePatch<'_>, n: usize) -> Result<SurfaceAnalysis, CheckError> {
    if !(2..=10_000).contains(&n) {
        return Err(CheckError::BadOption {
            name: "n",
            message: format!("grid size must be 2..=10000, got {n}"),
        });
    }
    let rect = patch.rect;
    let grid: Vec<(DVec2, Option<CurvatureSample>)> = (0..n * n)
        .into_par_iter()
        .map(|k| {
            let uv = DVec2::new(
                rect.u.lerp((k / n) as f64 / (n - 1) as f64),
                rect.v.lerp((k % n) as f64 / (n - 1) as f64),
            );
            (uv, sample(patch, uv))
        })
        .collect();
    let mut best: [Option<(f64, DVec2)>; QUANTITIES] = [None; QUANTITIES];
    let mut degenerate = 0;
    for (uv, c) in &grid {
        let Some(c) = c else {
            degenerate += 1;
            continue;
        };
        for (slot, v) in best.iter_mut().zip(quantities(c)) {
            if v > 0.0 && slot.is_none_or(|(b, _)| v > b) {
                *slot = Some((v, *uv));
            }
        }
    }
    let step = DVec2::new(rect.u.len(), rect.v.len()) / (n - 1) as f64;
    let refined: Vec<Option<RadiusExtreme>> = best
        .iter()
        .enumerate()
        .map(|(q, slot)| {
            slot.map(|(k, uv)| {
                let (k, uv) = refine(patch, q, k, uv, step);
                RadiusExtreme {
                    radius_mm: 1.0 / k,
                    uv,
                    point: patch.derivs(uv).p,
                }
            })
        })
        .collect();
    let get = |i: usize| refined.get(i).copied().flatten();
    Ok(SurfaceAnalysis {
        min_concave_u: get(0),
        min_concave_v: get(1),
        min_concave_principal: get(2),
        min_convex_u: get(3),
        min_convex_v: get(4),
        min_convex_principal: get(5),
        samples: n * n,
        degenerate,
    })
}

/// Pattern search maximising quantity `q` from a grid point, step halving down to 1e-7 of the
/// grid step, staying inside the rectangle.
fn refine(patch: &FacePatch<'_>, q: usize, k0: f64, uv0: DVec2, step: DVec2) -> (f64, DVec2) {
    let (mut k, mut uv) = (k0, uv0);
    let mut h = step;
    let dirs = [
        DVec2::new(1.0, 0.0),
        DVec2::new(-1.0, 0.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(0.0, -1.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(-1.0, -1.0),
        DVec2::new(1.0, -1.0),
        DVec2::new(-1.0, 1.0),
    ];
    for _ in 0..200 {
        let mut moved = false;
        for d in dirs {
            let cand = patch.clamp(uv + d * h);
            if let Some(v) = quantity(patch, cand, q)
                && v > k
            {
                (k, uv) = (v, cand);
                moved = true;
            }
        }
        if !moved {
            h *= 0.5;
            if h.x < 1e-7 * step.x && h.y < 1e-7 * step.y {
                break;
            }
        }
    }
    (k, uv)
}
