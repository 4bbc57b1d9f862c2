//! Drop-cutter: lower a cutter along −Z at a given XY until it touches a triangle mesh, and report
//! the tool-tip height (the CL point's z), the contact point (CC) and the kind of contact.
//!
//! For every candidate triangle (those whose box meets the cutter's footprint, from
//! [`MeshBvh::triangles_in_aabb`]) the classic trio runs, as in OpenCAMLib: vertex drop, facet
//! drop and edge drop (see `contact`); the highest tip wins. Triangles are visited from the
//! highest down and skipped once their top lies below the best tip found, which is exact because
//! the tip is the tool's lowest point. Points run in parallel (rayon); results keep input order.

mod contact;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::Cutter;
use crate::diagnostics::{Cancelled, Progress};
use crate::geometry::Aabb;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;

/// Which feature of the mesh the cutter rests on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Contact {
    /// A mesh vertex.
    Vertex,
    /// The interior of a mesh edge.
    Edge,
    /// The interior of a triangle.
    Facet,
}

/// A cutter location found by the drop-cutter.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClPoint {
    /// Height of the tool tip (the lowest point on the axis), mm.
    pub z: f64,
    /// The cutter-contact point on the mesh, mm.
    pub cc: DVec3,
    /// The kind of contact.
    pub contact: Contact,
    /// Index of the touched triangle in [`TriMesh::triangles`].
    pub triangle: usize,
}

/// Drop `cutter` onto the mesh at every XY of `points` (tool axis +Z).
///
/// `bvh` must have been built from `mesh`. The result has one entry per point, in input order:
/// `None` where the cutter's footprint (a disc of radius d/2) meets no triangle, or where the
/// point is not finite.
#[must_use]
pub fn drop_cutter(
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
    points: &[DVec2],
) -> Vec<Option<ClPoint>> {
    // A fresh handle is never cancelled, so the error branch cannot happen.
    drop_cutter_progress(bvh, mesh, cutter, points, &Progress::new()).unwrap_or_default()
}

/// Points handled between two progress reports and cancel checks.
const CHUNK: usize = 4096;

/// [`drop_cutter`] reporting the fraction done to `progress` and stopping when it is cancelled.
///
/// # Errors
/// [`Cancelled`] when `progress` was cancelled before the last chunk of points finished.
pub fn drop_cutter_progress(
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
    points: &[DVec2],
    progress: &Progress,
) -> Result<Vec<Option<ClPoint>>, Cancelled> {
    let bbox = bvh.bbox();
    let mut out = Vec::with_capacity(points.len());
    for chunk in points.chunks(CHUNK) {
        progress.check()?;
        out.par_extend(
            chunk
                .par_iter()
                .map(|p| drop_one(bvh, mesh, cutter, *p, &bbox)),
        );
        progress.set(out.len() as f64 / points.len() as f64);
    }
    Ok(out)
}

/// Drop-cutter at a single point (see [`drop_cutter`]).
#[must_use]
pub fn drop_cutter_at(
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
    point: DVec2,
) -> Option<ClPoint> {
    drop_one(bvh, mesh, cutter, point, &bvh.bbox())
}

fn drop_one(
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
    c: DVec2,
    bbox: &Aabb,
) -> Option<ClPoint> {
    if !c.is_finite() {
        return None;
    }
    let r = cutter.radius();
    let query = Aabb {
        min: DVec3::new(c.x - r, c.y - r, bbox.min.z - 1.0),
        max: DVec3::new(c.x + r, c.y + r, bbox.max.z + 1.0),
    };
    let mut candidates: Vec<(f64, usize, [DVec3; 3])> = bvh
        .triangles_in_aabb(&query)
        .into_iter()
        .filter_map(|t| {
            let tri = mesh.triangle_corners(t)?;
            let top = tri[0].z.max(tri[1].z).max(tri[2].z);
            Some((top, t, tri))
        })
        .collect();
    // Highest first; ties by index so the result does not depend on the candidate order.
    candidates.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut best: Option<ClPoint> = None;
    for (top, t, tri) in candidates {
        if best.is_some_and(|b| top <= b.z) {
            break;
        }
        contact::drop_on_triangle(cutter, c, &tri, t, &mut best);
    }
    best
}
