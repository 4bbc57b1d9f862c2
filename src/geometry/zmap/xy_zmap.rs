//! The thesis's XY-dependent Z-map (Eq. 6.9): three matrices X, Y, Z of
//! equal size whose quad topology is regular but whose nodes are real input points, built from
//! scattered points (mesh vertices or a point cloud).
//!
//! Construction: a reference grid of step g over the points' XY bounding box, cells centred on
//! the nodes (r = round((y − y_min)/g), c = round((x − x_min)/g)); each cell keeps its highest
//! point; empty rows/columns are deleted, then interior rows/columns whose points are collinear
//! with their neighbours' along every column/row (our reading of the thesis's "rows that repeat
//! the same values": deleting them leaves the piecewise-linear surface unchanged); remaining
//! empty cells get the cell centre with z from a vertical ray cast onto the mesh (polygon input)
//! or linear interpolation along the row and column (point clouds).
//!
//! Its reduction, matrix by matrix, is [`crate::reduce::reduce_xy_zmap`].

use glam::{DVec2, DVec3};

use super::error::ZmapError;
use super::grid::Grid;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;

/// How empty cells of the reference grid are filled.
#[derive(Clone, Copy, Debug)]
pub enum EmptyCellFill<'a> {
    /// Polygon input: the cell centre projected vertically onto this mesh (top hit); cells
    /// the mesh does not cover fall back to [`EmptyCellFill::Linear`].
    Mesh(&'a MeshBvh),
    /// Point-cloud input: z linearly interpolated along the row and the column from the filled
    /// cells (the mean of both estimates).
    Linear,
}

/// An XY-dependent Z-map: node (r, c) is (X(r,c), Y(r,c), Z(r,c)); row ↔ y, column ↔ x.
#[derive(Clone, Debug, PartialEq)]
pub struct XyZmap {
    /// X coordinates, mm.
    pub x: Grid,
    /// Y coordinates, mm.
    pub y: Grid,
    /// Heights, mm.
    pub z: Grid,
}

impl XyZmap {
    /// The node (r, c) as a point.
    #[must_use]
    pub fn point(&self, r: usize, c: usize) -> Option<DVec3> {
        Some(DVec3::new(
            self.x.get(r, c)?,
            self.y.get(r, c)?,
            self.z.get(r, c)?,
        ))
    }
}

/// Build the XY-dependent Z-map of `points` with reference step `step` (see the module docs).
///
/// # Errors
/// [`ZmapError::Option`] for a non-positive step, [`ZmapError::NonFinite`] for a
/// non-finite point (row 1, column = its 1-based index), [`ZmapError::Shape`] for no points
/// or a reference grid over 20 million cells.
pub fn xy_zmap_from_points(
    points: &[DVec3],
    step: f64,
    fill: EmptyCellFill<'_>,
) -> Result<XyZmap, ZmapError> {
    if !(step > 0.0 && step.is_finite()) {
        return Err(ZmapError::Option(format!(
            "reference step must be a positive length in mm, got {step}"
        )));
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(ZmapError::NonFinite { row: 1, col: i + 1 });
    }
    let Some(first) = points.first() else {
        return Err(ZmapError::Shape("no points".into()));
    };
    let (lo, hi) = points
        .iter()
        .fold((first.truncate(), first.truncate()), |(l, h), p| {
            (l.min(p.truncate()), h.max(p.truncate()))
        });
    let size = ((hi - lo) / step).round();
    let (rows, cols) = (size.y as usize + 1, size.x as usize + 1);
    if rows.checked_mul(cols).is_none_or(|n| n > 20_000_000) {
        return Err(ZmapError::Shape(format!("{rows}×{cols} reference grid")));
    }
    let mut cells: Vec<Option<DVec3>> = vec![None; rows * cols];
    for p in points {
        let r = (((p.y - lo.y) / step).round() as usize).min(rows - 1);
        let c = (((p.x - lo.x) / step).round() as usize).min(cols - 1);
        if let Some(cell) = cells.get_mut(r * cols + c) {
            // Keep the higher point: the model stays on the positive-tolerance side.
            if cell.is_none_or(|q| p.z > q.z) {
                *cell = Some(*p);
            }
        }
    }
    let at = |r: usize, c: usize| cells.get(r * cols + c).copied().flatten();
    // Step 3a: drop empty rows and columns.
    let mut keep_r: Vec<usize> = (0..rows)
        .filter(|&r| (0..cols).any(|c| at(r, c).is_some()))
        .collect();
    let mut keep_c: Vec<usize> = (0..cols)
        .filter(|&c| (0..rows).any(|r| at(r, c).is_some()))
        .collect();
    // Step 3b: drop interior rows (columns) collinear with their kept neighbours.
    let eps = 1e-6 * step;
    keep_r = drop_collinear(&keep_r, &keep_c, eps, at);
    keep_c = drop_collinear(&keep_c, &keep_r, eps, |line, other| at(other, line));
    // Step 4: fill.
    let (m, n) = (keep_r.len(), keep_c.len());
    let mut nodes = Vec::with_capacity(m * n);
    for &r in &keep_r {
        for &c in &keep_c {
            nodes.push(at(r, c));
        }
    }
    let filled = nodes.clone();
    let get = |i: usize, j: usize| filled.get(i * n + j).copied().flatten();
    for (k, node) in nodes.iter_mut().enumerate() {
        if node.is_some() {
            continue;
        }
        let (i, j) = (k / n, k % n);
        let centre = lo
            + DVec2::new(
                keep_c.get(j).copied().unwrap_or(0) as f64,
                keep_r.get(i).copied().unwrap_or(0) as f64,
            ) * step;
        let hit = match fill {
            EmptyCellFill::Mesh(bvh) => bvh
                .ray_cast(
                    centre.extend(bvh.bbox().max.z + 1.0),
                    DVec3::NEG_Z,
                    f64::INFINITY,
                )
                .map(|h| h.point.z),
            EmptyCellFill::Linear => None,
        };
        let z = hit.unwrap_or_else(|| {
            let along_row = interpolate((0..n).filter_map(|jj| get(i, jj)), centre.x, |p| p.x);
            let along_col = interpolate((0..m).filter_map(|ii| get(ii, j)), centre.y, |p| p.y);
            match (along_row, along_col) {
                (Some(a), Some(b)) => 0.5 * (a + b),
                (Some(a), None) | (None, Some(a)) => a,
                (None, None) => 0.0,
            }
        });
        *node = Some(centre.extend(z));
    }
    let pts: Vec<DVec3> = nodes.into_iter().map(Option::unwrap_or_default).collect();
    Ok(XyZmap {
        x: Grid::new(m, n, pts.iter().map(|p| p.x).collect())?,
        y: Grid::new(m, n, pts.iter().map(|p| p.y).collect())?,
        z: Grid::new(m, n, pts.iter().map(|p| p.z).collect())?,
    })
}

/// Keep the first and last of `lines` and every interior one that some `other` index makes
/// non-collinear with the previous kept line and the next line (all three points present).
fn drop_collinear(
    lines: &[usize],
    others: &[usize],
    eps: f64,
    at: impl Fn(usize, usize) -> Option<DVec3>,
) -> Vec<usize> {
    let mut kept: Vec<usize> = Vec::with_capacity(lines.len());
    for (k, &line) in lines.iter().enumerate() {
        let (Some(&prev), Some(&next)) = (kept.last(), lines.get(k + 1)) else {
            kept.push(line);
            continue;
        };
        let redundant = others
            .iter()
            .all(|&o| match (at(prev, o), at(line, o), at(next, o)) {
                (Some(a), Some(b), Some(c)) => {
                    let ac = c - a;
                    let t = if ac.length_squared() > 0.0 {
                        ((b - a).dot(ac) / ac.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    (a + ac * t).distance(b) <= eps
                }
                (_, None, _) => true,
                _ => false,
            });
        if !redundant {
            kept.push(line);
        }
    }
    kept
}

/// Linear interpolation of z at `t` (coordinate `key`) from `points`; constant beyond the ends.
fn interpolate(
    points: impl Iterator<Item = DVec3>,
    t: f64,
    key: impl Fn(DVec3) -> f64,
) -> Option<f64> {
    let (mut below, mut above): (Option<DVec3>, Option<DVec3>) = (None, None);
    for p in points {
        let k = key(p);
        if k <= t && below.is_none_or(|b| k > key(b)) {
            below = Some(p);
        }
        if k >= t && above.is_none_or(|a| k < key(a)) {
            above = Some(p);
        }
    }
    match (below, above) {
        (Some(a), Some(b)) => {
            let span = key(b) - key(a);
            if span > 0.0 {
                Some(a.z + (b.z - a.z) * (t - key(a)) / span)
            } else {
                Some(a.z.max(b.z))
            }
        }
        (Some(p), None) | (None, Some(p)) => Some(p.z),
        (None, None) => None,
    }
}

/// The XY-dependent Z-map as a triangle mesh: each quad split along its shorter 3-D diagonal.
#[must_use]
pub fn xy_mesh(map: &XyZmap) -> TriMesh {
    let (m, n) = (map.z.rows(), map.z.cols());
    let positions: Vec<DVec3> = (0..m * n)
        .map(|k| map.point(k / n, k % n).unwrap_or_default())
        .collect();
    let id = |r: usize, c: usize| u32::try_from(r * n + c).unwrap_or(u32::MAX);
    let p = |i: u32| positions.get(i as usize).copied().unwrap_or_default();
    let mut triangles = Vec::new();
    for r in 0..m.saturating_sub(1) {
        for c in 0..n.saturating_sub(1) {
            let (a, b, cc, d) = (id(r, c), id(r, c + 1), id(r + 1, c + 1), id(r + 1, c));
            if p(a).distance(p(cc)) <= p(b).distance(p(d)) {
                triangles.extend([[a, b, cc], [a, cc, d]]);
            } else {
                triangles.extend([[a, b, d], [b, cc, d]]);
            }
        }
    }
    TriMesh::new(positions, triangles)
}
