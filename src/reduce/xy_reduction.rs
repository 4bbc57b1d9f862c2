//! Reduction of an XY-dependent Z-map (thesis Eq. 6.9): X, Y and Z each reduced by its own SVD
//! to the same size, and the vertical error of the original nodes against the reduced surface.

use glam::DVec3;

use super::{RankRule, ReduceError, Reduction, reduce_to_size};
use crate::geometry::bvh::MeshBvh;
use crate::geometry::zmap::{XyZmap, xy_mesh};

/// The result of [`reduce_xy_zmap`].
#[derive(Clone, Debug, PartialEq)]
pub struct XyReduction {
    /// Reduction of the X matrix (its own SVD and rank).
    pub x: Reduction,
    /// Reduction of the Y matrix.
    pub y: Reduction,
    /// Reduction of the Z matrix.
    pub z: Reduction,
    /// The reduced model.
    pub reduced: XyZmap,
    /// Max vertical distance from the original nodes to the reduced mesh, mm.
    pub max_error: f64,
    /// Mean vertical distance from the original nodes to the reduced mesh, mm.
    pub mean_error: f64,
    /// Original nodes outside the reduced mesh's XY footprint (not in the error figures).
    pub uncovered: usize,
}

/// Reduce X, Y and Z separately (each its own SVD and rank under `rank_rule` and `tolerance_mm`)
/// to `rows`×`cols` nodes, and measure the vertical error of the original nodes against the
/// reduced surface (a vertical ray cast onto [`xy_mesh`] of the result).
///
/// # Errors
/// As [`reduce_to_size`]; [`ReduceError::Shape`] when the reduced mesh has non-finite points.
pub fn reduce_xy_zmap(
    map: &XyZmap,
    tolerance_mm: f64,
    rank_rule: RankRule,
    rows: usize,
    cols: usize,
) -> Result<XyReduction, ReduceError> {
    let x = reduce_to_size(&map.x, tolerance_mm, rank_rule, rows, cols)?;
    let y = reduce_to_size(&map.y, tolerance_mm, rank_rule, rows, cols)?;
    let z = reduce_to_size(&map.z, tolerance_mm, rank_rule, rows, cols)?;
    let reduced = XyZmap {
        x: x.reduced.clone(),
        y: y.reduced.clone(),
        z: z.reduced.clone(),
    };
    let bvh = MeshBvh::new(&xy_mesh(&reduced))
        .map_err(|e| ReduceError::Shape(format!("reduced mesh: {e}")))?;
    let top = bvh.bbox().max.z + 1.0;
    let (mut max_error, mut sum, mut count, mut uncovered) = (0.0_f64, 0.0, 0usize, 0usize);
    for r in 0..map.z.rows() {
        for c in 0..map.z.cols() {
            let Some(p) = map.point(r, c) else { continue };
            match bvh.ray_cast(p.truncate().extend(top), DVec3::NEG_Z, f64::INFINITY) {
                Some(h) => {
                    let e = (h.point.z - p.z).abs();
                    max_error = max_error.max(e);
                    sum += e;
                    count += 1;
                }
                None => uncovered += 1,
            }
        }
    }
    Ok(XyReduction {
        x,
        y,
        z,
        reduced,
        max_error,
        mean_error: if count > 0 { sum / count as f64 } else { 0.0 },
        uncovered,
    })
}
