//! A bounding-volume hierarchy over a [`TriMesh`] for fast queries: ray casts, closest points and
//! triangles near a box (the drop-cutter's candidate set). Built on parry3d's `TriMesh`, whose
//! vectors are the same glam `DVec3` as Talas's.
//!
//! Triangles of zero area (or with an out-of-range index) are left out of the hierarchy: they
//! have no normal and cannot be the unique answer to any query. Every triangle index in a result
//! is the index in the source [`TriMesh::triangles`].

use parry3d_f64::bounding_volume::Aabb as ParryAabb;
use parry3d_f64::query::Ray;
use parry3d_f64::shape::{CompositeShapeRef, TriMesh as ParryTriMesh};

use super::mesh::TriMesh;
use super::{Aabb, DVec3};

/// Why a [`MeshBvh`] could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BvhError {
    /// The mesh has no triangle with a non-zero area.
    #[error("mesh has no triangle with non-zero area ({triangles} triangles in all)")]
    NoTriangles {
        /// How many triangles the mesh has in all (degenerate ones included).
        triangles: usize,
    },
    /// A vertex position is NaN or infinite.
    #[error("mesh vertex {vertex} is not finite")]
    NonFinite {
        /// Index of the first non-finite vertex.
        vertex: usize,
    },
    /// The mesh is too large for 32-bit triangle indices.
    #[error("mesh too large: {0} vertices (at most 2^32 - 1)")]
    TooLarge(usize),
    /// parry3d refused the mesh.
    #[error("could not build the triangle hierarchy: {0}")]
    Backend(String),
}

/// Where a ray first meets the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Ray parameter: `point = origin + t · dir` (in units of `|dir|`).
    pub t: f64,
    /// The hit point, mm.
    pub point: DVec3,
    /// Index of the triangle hit in the source mesh.
    pub triangle: usize,
    /// Unit normal of that triangle by its winding (outward for a closed, outward-wound mesh),
    /// whichever side the ray came from.
    pub normal: DVec3,
}

/// The point of the mesh closest to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestHit {
    /// The closest point on the mesh surface, mm.
    pub point: DVec3,
    /// Distance from the query point to `point`, mm.
    pub distance: f64,
    /// Index of the triangle `point` lies on, in the source mesh.
    pub triangle: usize,
}

/// A triangle hierarchy for ray, closest-point and box queries on one mesh.
#[derive(Clone)]
pub struct MeshBvh {
    shape: ParryTriMesh,
    /// Hierarchy triangle → source triangle index.
    source: Vec<usize>,
    /// Unit normal of each hierarchy triangle, by its winding.
    normals: Vec<DVec3>,
}

impl std::fmt::Debug for MeshBvh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshBvh")
            .field("triangles", &self.source.len())
            .finish_non_exhaustive()
    }
}

impl MeshBvh {
    /// Build the hierarchy over the triangles of `mesh` that have a non-zero area.
    ///
    /// # Errors
    /// [`BvhError::NonFinite`] for a NaN or infinite vertex, [`BvhError::NoTriangles`] when no
    /// triangle has a non-zero area, [`BvhError::TooLarge`] past 2³² − 1 vertices, and
    /// [`BvhError::Backend`] when parry3d refuses the mesh.
    pub fn new(mesh: &TriMesh) -> Result<Self, BvhError> {
        if let Some(vertex) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(BvhError::NonFinite { vertex });
        }
        if u32::try_from(mesh.positions.len()).is_err() {
            return Err(BvhError::TooLarge(mesh.positions.len()));
        }
        let mut indices = Vec::with_capacity(mesh.triangles.len());
        let mut source = Vec::with_capacity(mesh.triangles.len());
        let mut normals = Vec::with_capacity(mesh.triangles.len());
        for (i, tri) in mesh.triangles.iter().enumerate() {
            let Some([a, b, c]) = mesh.triangle_corners(i) else {
                continue;
            };
            let Some(n) = (b - a).cross(c - a).try_normalize() else {
                continue;
            };
            indices.push(*tri);
            source.push(i);
            normals.push(n);
        }
        if indices.is_empty() {
            return Err(BvhError::NoTriangles {
                triangles: mesh.triangles.len(),
            });
        }
        let shape = ParryTriMesh::new(mesh.positions.clone(), indices)
            .map_err(|e| BvhError::Backend(e.to_string()))?;
        Ok(Self {
            shape,
            source,
            normals,
        })
    }

    /// Number of triangles in the hierarchy (the source's non-degenerate ones).
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.source.len()
    }

    /// Bounding box of the triangles in the hierarchy.
    #[must_use]
    pub fn bbox(&self) -> Aabb {
        let b = self.shape.local_aabb();
        Aabb {
            min: b.mins,
            max: b.maxs,
        }
    }

    /// The first hit of the ray `origin + t · dir`, 0 ≤ t ≤ `max_t`, with either side of any
    /// triangle. `None` when it misses, or when `dir` is zero or any input is not finite
    /// (`max_t` may be `f64::INFINITY`).
    #[must_use]
    pub fn ray_cast(&self, origin: DVec3, dir: DVec3, max_t: f64) -> Option<RayHit> {
        if !origin.is_finite() || !dir.is_finite() || dir == DVec3::ZERO || max_t.is_nan() {
            return None;
        }
        let max_t = max_t.min(f64::MAX);
        let ray = Ray::new(origin, dir);
        let (id, hit) =
            CompositeShapeRef(&self.shape).cast_local_ray_and_get_normal(&ray, max_t, false)?;
        let k = usize::try_from(id).ok()?;
        let t = hit.time_of_impact;
        if !(0.0..=max_t).contains(&t) {
            return None;
        }
        Some(RayHit {
            t,
            point: origin + dir * t,
            triangle: *self.source.get(k)?,
            normal: *self.normals.get(k)?,
        })
    }

    /// The point of the mesh surface closest to `p`; `None` when `p` is not finite.
    #[must_use]
    pub fn closest_point(&self, p: DVec3) -> Option<ClosestHit> {
        if !p.is_finite() {
            return None;
        }
        let (id, proj) = CompositeShapeRef(&self.shape).project_local_point(p, f64::MAX, false)?;
        let k = usize::try_from(id).ok()?;
        Some(ClosestHit {
            point: proj.point,
            distance: proj.point.distance(p),
            triangle: *self.source.get(k)?,
        })
    }

    /// Source indices (ascending) of the triangles whose bounding box meets `aabb` (boxes that
    /// touch count). This is the conservative candidate set for exact tests such as the
    /// drop-cutter's; empty for an empty or non-finite box.
    #[must_use]
    pub fn triangles_in_aabb(&self, aabb: &Aabb) -> Vec<usize> {
        if aabb.is_empty() || !aabb.min.is_finite() || !aabb.max.is_finite() {
            return Vec::new();
        }
        let query = ParryAabb::new(aabb.min, aabb.max);
        let mut out: Vec<usize> = self
            .shape
            .bvh()
            .intersect_aabb(&query)
            .filter_map(|id| {
                let k = usize::try_from(id).ok()?;
                let tri = self.shape.triangle(id);
                let lo = tri.a.min(tri.b).min(tri.c);
                let hi = tri.a.max(tri.b).max(tri.c);
                let meets = lo.cmple(aabb.max).all() && hi.cmpge(aabb.min).all();
                if meets {
                    self.source.get(k).copied()
                } else {
                    None
                }
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }
}
