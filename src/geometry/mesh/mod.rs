//! Indexed triangle meshes (mm): welding, normals, area, volume of closed meshes, closedness.
//!
//! Every method tolerates bad data (indices out of range, non-finite positions): such triangles
//! are skipped by the measures, reported by [`TriMesh::validate`] and
//! [`TriMesh::degenerate_triangles`], and never cause a panic.
//!
//! Results are deterministic: nothing depends on hash-map iteration order.

mod edges;
mod weld;

use super::{Aabb, DVec3, GeometryError};

/// An indexed triangle mesh. Triangles are counter-clockwise seen from outside (right-hand rule
/// gives the outward normal).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TriMesh {
    /// Vertex positions, mm.
    pub positions: Vec<DVec3>,
    /// Per-vertex unit normals (same length as `positions`), empty when not computed.
    pub normals: Vec<DVec3>,
    /// Vertex indices of each triangle.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// A mesh from positions and triangles (no normals).
    #[must_use]
    pub fn new(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Self {
        Self {
            positions,
            normals: Vec::new(),
            triangles,
        }
    }

    /// The three corner positions of triangle `t`, or `None` when `t` is out of range or one of
    /// its indices is.
    #[must_use]
    pub fn triangle_corners(&self, t: usize) -> Option<[DVec3; 3]> {
        let tri = self.triangles.get(t)?;
        self.corners(*tri)
    }

    /// Corner positions of an index triple, `None` when an index is out of range.
    fn corners(&self, tri: [u32; 3]) -> Option<[DVec3; 3]> {
        let p = |i: u32| self.positions.get(usize::try_from(i).ok()?).copied();
        Some([p(tri[0])?, p(tri[1])?, p(tri[2])?])
    }

    /// Check that every index is in range and every position finite.
    ///
    /// # Errors
    /// [`GeometryError::NonFinite`] naming the first non-finite vertex, or
    /// [`GeometryError::InvalidDimension`] naming the first triangle with an index out of range.
    pub fn validate(&self) -> Result<(), GeometryError> {
        if let Some(v) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(GeometryError::NonFinite(format!("mesh vertex {v}")));
        }
        if let Some(t) = self
            .triangles
            .iter()
            .position(|tri| self.corners(*tri).is_none())
        {
            return Err(GeometryError::InvalidDimension(format!(
                "triangle {t} has a vertex index out of range ({} vertices)",
                self.positions.len()
            )));
        }
        Ok(())
    }

    /// Total surface area, mm² (triangles with bad indices count as zero).
    #[must_use]
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .filter_map(|t| self.corners(*t))
            .map(|[a, b, c]| 0.5 * (b - a).cross(c - a).length())
            .sum()
    }

    /// Signed enclosed volume, mm³, by the divergence theorem: Σ a·(b×c)/6 over the triangles.
    ///
    /// Positive for a closed mesh with outward (counter-clockwise from outside) triangles,
    /// negative when it is turned inside out; meaningless for an open mesh.
    #[must_use]
    pub fn signed_volume(&self) -> f64 {
        // Subtract a reference point (the first vertex) so that large coordinates do not cancel.
        let o = self.positions.first().copied().unwrap_or(DVec3::ZERO);
        self.triangles
            .iter()
            .filter_map(|t| self.corners(*t))
            .map(|[a, b, c]| (a - o).dot((b - o).cross(c - o)))
            .sum::<f64>()
            / 6.0
    }

    /// Bounding box of all vertex positions ([`Aabb::EMPTY`] for none).
    #[must_use]
    pub fn bbox(&self) -> Aabb {
        Aabb::from_points(&self.positions)
    }

    /// Indices of triangles with area ≤ `area_tol` (mm²), a repeated vertex index, an index out
    /// of range or a non-finite corner, ascending.
    #[must_use]
    pub fn degenerate_triangles(&self, area_tol: f64) -> Vec<usize> {
        self.triangles
            .iter()
            .enumerate()
            .filter(|(_, tri)| {
                if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                    return true;
                }
                match self.corners(**tri) {
                    None => true,
                    Some([a, b, c]) => {
                        let area = 0.5 * (b - a).cross(c - a).length();
                        area.is_nan() || area <= area_tol
                    }
                }
            })
            .map(|(i, _)| i)
            .collect()
    }

    /// Per-vertex unit normals, angle-weighted (each triangle contributes its unit normal times
    /// its interior angle at the vertex), which does not depend on how a flat region happens to
    /// be split into triangles. Vertices touched by no non-degenerate triangle get a zero normal.
    pub fn compute_normals(&mut self) {
        let mut acc = vec![DVec3::ZERO; self.positions.len()];
        for tri in &self.triangles {
            let Some(p) = self.corners(*tri) else {
                continue;
            };
            let Some(n) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else {
                continue;
            };
            for k in 0..3 {
                let here = p[k];
                let e1 = p[(k + 1) % 3] - here;
                let e2 = p[(k + 2) % 3] - here;
                let angle = e1.angle_between(e2);
                let slot = usize::try_from(tri[k]).ok().and_then(|i| acc.get_mut(i));
                if let (true, Some(slot)) = (angle.is_finite(), slot) {
                    *slot += n * angle;
                }
            }
        }
        self.normals = acc
            .into_iter()
            .map(|n| n.try_normalize().unwrap_or(DVec3::ZERO))
            .collect();
    }

    /// Append another mesh (its indices shifted past this mesh's vertices). Normals are kept
    /// only when both meshes have them.
    pub fn append(&mut self, other: &Self) {
        let both_normals = self.has_normals() && other.has_normals();
        // Meshes are limited to u32 vertices; past that the indices saturate and become out of
        // range, which `validate` reports, rather than wrapping onto wrong vertices.
        let offset = u32::try_from(self.positions.len()).unwrap_or(u32::MAX);
        self.positions.extend_from_slice(&other.positions);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| t.map(|i| i.saturating_add(offset))),
        );
        if both_normals {
            self.normals.extend_from_slice(&other.normals);
        } else {
            self.normals.clear();
        }
    }

    /// Turn the mesh inside out: reverse every triangle's winding and negate the normals.
    pub fn flip(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
        for n in &mut self.normals {
            *n = -*n;
        }
    }

    /// Are there per-vertex normals, one per position (true for an empty mesh)?
    #[must_use]
    pub fn has_normals(&self) -> bool {
        self.normals.len() == self.positions.len()
    }
}
