//! Regular Z-maps from meshes and back: the highest surface point over every grid node (a
//! vertical ray cast through the mesh's hierarchy), and a Z-map (for instance a reduced one) as
//! a triangle mesh for STL export.

use glam::{DVec2, DVec3};

use super::error::ZmapError;
use super::grid::Grid;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;

/// A regular Z-map of the mesh behind `bvh`: `rows`×`cols` nodes at
/// (x, y) = origin + (col·step, row·step) (row ↔ y, column ↔ x, as in the thesis), each the
/// highest point of the mesh above that node; nodes the mesh does not cover get `empty_z`.
///
/// # Errors
/// [`ZmapError::Shape`] for an empty or oversized grid, [`ZmapError::Option`] for a
/// non-positive step or non-finite origin.
pub fn zmap_from_mesh(
    bvh: &MeshBvh,
    origin: DVec2,
    step: f64,
    rows: usize,
    cols: usize,
    empty_z: f64,
) -> Result<Grid, ZmapError> {
    if !(step > 0.0 && step.is_finite() && origin.is_finite() && empty_z.is_finite()) {
        return Err(ZmapError::Option(format!(
            "grid step must be positive and origin finite, got step {step}"
        )));
    }
    if rows
        .checked_mul(cols)
        .is_none_or(|n| n == 0 || n > 50_000_000)
    {
        return Err(ZmapError::Shape(format!("{rows}×{cols} grid")));
    }
    let top = bvh.bbox().max.z + 1.0;
    let values = (0..rows * cols)
        .map(|k| {
            let p = origin + DVec2::new((k % cols) as f64, (k / cols) as f64) * step;
            bvh.ray_cast(p.extend(top), DVec3::NEG_Z, f64::INFINITY)
                .map_or(empty_z, |h| h.point.z)
        })
        .collect();
    Grid::new(rows, cols, values)
}

/// The Z-map as a triangle mesh over the rectangle `origin` + [0, width] × [0, height]
/// (columns spread over the width, rows over the height), each grid cell split along the
/// diagonal whose two triangles deviate least from the four corners' bilinear surface (the
/// shorter 3-D diagonal), triangles facing up.
#[must_use]
pub fn grid_mesh(grid: &Grid, origin: DVec2, width: f64, height: f64) -> TriMesh {
    let (m, n) = (grid.rows(), grid.cols());
    let dx = if n > 1 { width / (n - 1) as f64 } else { 0.0 };
    let dy = if m > 1 { height / (m - 1) as f64 } else { 0.0 };
    let positions: Vec<DVec3> = (0..m * n)
        .map(|k| {
            let (r, c) = (k / n, k % n);
            (origin + DVec2::new(c as f64 * dx, r as f64 * dy))
                .extend(grid.get(r, c).unwrap_or(0.0))
        })
        .collect();
    let mut triangles = Vec::new();
    let id = |r: usize, c: usize| u32::try_from(r * n + c).unwrap_or(u32::MAX);
    for r in 0..m.saturating_sub(1) {
        for c in 0..n.saturating_sub(1) {
            let (a, b, cc, d) = (id(r, c), id(r, c + 1), id(r + 1, c + 1), id(r + 1, c));
            let p = |i: u32| positions.get(i as usize).copied().unwrap_or_default();
            if p(a).distance(p(cc)) <= p(b).distance(p(d)) {
                triangles.push([a, b, cc]);
                triangles.push([a, cc, d]);
            } else {
                triangles.push([a, b, d]);
                triangles.push([b, cc, d]);
            }
        }
    }
    TriMesh::new(positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Z-map of a tilted plane sampled from its own mesh reproduces the plane at the nodes.
    #[test]
    fn plane_round_trip() {
        let g = Grid::from_fn(5, 7, |r, c| 0.5 * r as f64 + 0.25 * c as f64);
        let mesh = grid_mesh(&g, DVec2::ZERO, 6.0, 4.0);
        assert_eq!(mesh.triangles.len(), 2 * 4 * 6);
        let bvh = MeshBvh::new(&mesh).unwrap();
        let z = zmap_from_mesh(&bvh, DVec2::new(0.5, 0.5), 0.5, 5, 9, -1.0).unwrap();
        for r in 0..5 {
            for c in 0..9 {
                let (x, y) = (0.5 + 0.5 * c as f64, 0.5 + 0.5 * r as f64);
                let want = 0.5 * y + 0.25 * x;
                assert!((z.get(r, c).unwrap() - want).abs() < 1e-9, "{r},{c}");
            }
        }
        // Outside the mesh: the empty value.
        let z = zmap_from_mesh(&bvh, DVec2::new(-10.0, -10.0), 1.0, 1, 1, -1.0).unwrap();
        assert_eq!(z.get(0, 0), Some(-1.0));
    }
}
