//! Per-vertex scalar fields shown on the part through a colour map: the principal curvatures
//! and the mean curvature, evaluated on the exact surfaces at each tessellation vertex (its
//! (u, v) found by point inversion, seeded from the previous vertex of the same face).

use crate::diagnostics::Progress;
use crate::geometry::DVec2;
use crate::geometry::diffgeom::Principal;
use crate::geometry::surface::SurfaceGeom;
use crate::render::{ColourMap, ScalarMapping};

use super::document_loader::LoadedPart;

/// Smallest tolerance band, mm (1 µm).
pub const MIN_BAND_MM: f64 = 1e-3;

/// The deviation mapping for a tolerance band of ±`band_mm` (mapped over ±2 × band, see
/// [`ColourMap::Band`]).
#[must_use]
pub fn band_mapping(band_mm: f64) -> ScalarMapping {
    let b = band_mm.max(MIN_BAND_MM) as f32;
    ScalarMapping {
        map: ColourMap::Band,
        min: -2.0 * b,
        max: 2.0 * b,
    }
}

/// A scalar field the viewport can show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ScalarField {
    /// Smaller principal curvature.
    KMin,
    /// Larger principal curvature.
    KMax,
    /// Mean curvature (k_min + k_max) / 2.
    Mean,
}

impl ScalarField {
    /// Every field, menu order.
    pub const ALL: [Self; 3] = [Self::KMin, Self::KMax, Self::Mean];

    /// Name for menus and the legend.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::KMin => "Curvature k_min",
            Self::KMax => "Curvature k_max",
            Self::Mean => "Mean curvature",
        }
    }

    /// Unit of the values.
    #[must_use]
    pub fn unit(self) -> &'static str {
        "1/mm"
    }
}

/// Curvatures at every vertex of a part's mesh (1/mm, signed about the face normal; 0 where a
/// vertex has no surface or the point is degenerate).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurvatureField {
    /// k_min per vertex.
    pub k_min: Vec<f32>,
    /// k_max per vertex.
    pub k_max: Vec<f32>,
    /// Mean curvature per vertex.
    pub mean: Vec<f32>,
}

impl CurvatureField {
    /// The values of `field`.
    #[must_use]
    pub fn values(&self, field: ScalarField) -> &[f32] {
        match field {
            ScalarField::KMin => &self.k_min,
            ScalarField::KMax => &self.k_max,
            ScalarField::Mean => &self.mean,
        }
    }
}

/// Does `part` have surfaces to evaluate (a B-rep, not a mesh file)?
#[must_use]
pub fn has_surfaces(part: &LoadedPart) -> bool {
    part.faces.iter().any(|f| f.surface.is_some())
}

/// Points further than this from their inverted surface point are re-inverted with the global
/// search, mm.
const LOCAL_INVERSION_TOL_MM: f64 = 1e-4;

/// Evaluate the curvatures at every vertex of `part` (on a worker thread).
///
/// # Errors
/// `Err(())` when `progress` was cancelled.
#[allow(clippy::result_unit_err)]
pub fn curvature_field(part: &LoadedPart, progress: &Progress) -> Result<CurvatureField, ()> {
    let n = part.mesh().positions.len();
    // The face of each vertex (faces keep their own vertices).
    let mut face_of_vertex: Vec<Option<u32>> = vec![None; n];
    for (tri, &f) in part.mesh().triangles.iter().zip(part.face_of_triangle()) {
        for &v in tri {
            if let Some(slot) = face_of_vertex.get_mut(v as usize) {
                *slot = Some(f);
            }
        }
    }
    let mut out = CurvatureField {
        k_min: vec![0.0; n],
        k_max: vec![0.0; n],
        mean: vec![0.0; n],
    };
    let mut previous: Option<(u32, DVec2)> = None;
    for (v, (&p, face)) in part
        .mesh()
        .positions
        .iter()
        .zip(&face_of_vertex)
        .enumerate()
    {
        if v % 4096 == 0 {
            progress.check().map_err(|_| ())?;
            progress.set(v as f64 / n.max(1) as f64);
        }
        let Some(fi) = *face else { continue };
        let Some(face) = part.faces.get(fi as usize) else {
            continue;
        };
        let Some(surface) = face.surface.as_deref() else {
            continue;
        };
        let rect = surface.domain();
        let sp = match previous {
            Some((pf, uv)) if pf == fi => {
                let near = surface.closest_point_near(p, rect, uv);
                if near.distance <= LOCAL_INVERSION_TOL_MM {
                    near
                } else {
                    surface.closest_point(p, rect, Some(uv))
                }
            }
            _ => surface.closest_point(p, rect, None),
        };
        previous = Some((fi, sp.uv));
        let Some(pr) = principal_near(surface, sp.uv) else {
            continue;
        };
        let (k_min, k_max) = if face.same_sense {
            (pr.k_min, pr.k_max)
        } else {
            (-pr.k_max, -pr.k_min)
        };
        if let (Some(a), Some(b), Some(m)) = (
            out.k_min.get_mut(v),
            out.k_max.get_mut(v),
            out.mean.get_mut(v),
        ) {
            *a = k_min as f32;
            *b = k_max as f32;
            *m = (0.5 * (k_min + k_max)) as f32;
        }
    }
    progress.set(1.0);
    Ok(out)
}

/// Relative step toward the domain's centre where the parameterisation is degenerate.
const DEGENERATE_NUDGE: f64 = 1e-6;

/// Principal curvatures at `uv`; at a degenerate point (the pole of a sphere, a collapsed edge)
/// those a hair inside the domain, which are the limit the surface has there.
fn principal_near(surface: &SurfaceGeom, uv: DVec2) -> Option<Principal> {
    if let Some(p) = surface.derivs(uv.x, uv.y).principal() {
        return Some(p);
    }
    let rect = surface.domain();
    let step = |lo: f64, hi: f64, x: f64| {
        if lo.is_finite() && hi.is_finite() {
            x + (0.5 * (lo + hi) - x) * DEGENERATE_NUDGE * 10.0
        } else {
            x + DEGENERATE_NUDGE
        }
    };
    let nudged = DVec2::new(
        step(rect.u.t0, rect.u.t1, uv.x),
        step(rect.v.t0, rect.v.t1, uv.y),
    );
    surface.derivs(nudged.x, nudged.y).principal()
}

/// The colour mapping of `values`: a diverging map, symmetric about zero, over the 2nd to 98th
/// percentile of |value| (a few singular points do not wash out the rest).
#[must_use]
pub fn mapping_for(values: &[f32]) -> ScalarMapping {
    let mut mags: Vec<f32> = values
        .iter()
        .filter(|v| v.is_finite())
        .map(|v| v.abs())
        .collect();
    mags.sort_by(f32::total_cmp);
    let at = |q: f64| {
        let i = ((mags.len().saturating_sub(1)) as f64 * q).round() as usize;
        mags.get(i).copied().unwrap_or(0.0)
    };
    let m = at(0.98);
    let m = if m > 0.0 { m } else { 1e-3 };
    ScalarMapping {
        map: ColourMap::CoolWarm,
        min: -m,
        max: m,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mapping_is_symmetric_and_ignores_spikes() {
        let mut v: Vec<f32> = (0..100).map(|i| (i as f32 - 50.0) * 0.001).collect();
        v.push(1000.0);
        v.push(f32::NAN);
        let m = mapping_for(&v);
        assert_eq!(m.min, -m.max);
        assert!(m.max > 0.04 && m.max <= 0.05, "{}", m.max);
        assert!(mapping_for(&[]).max > 0.0);
    }
}
