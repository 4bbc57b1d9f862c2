//! Drop-cutter: lower a cutter along −Z at a given XY until it touches a triangle mesh, and report
//! the tool-tip height (the CL point's z), the contact point (CC) and the kind of contact.
//!
//! For every candidate triangle (those whose box meets the cutter's footprint, from
//! [`MeshBvh::triangles_in_aabb`]) the classic trio runs, as in OpenCAMLib: vertex drop, facet
//! drop and edge drop (see `contact`); the highest tip wins. Triangles are visited from the
//! highest down and skipped once their top lies below the best tip found, which is exact because
//! the tip is the tool's lowest point; a triangle whose top less the profile height at its
//! nearest XY distance cannot beat the best tip is skipped too. Neighbouring points share one
//! hierarchy query and one sorted candidate list (a packet); packets run in parallel (rayon);
//! results keep input order.

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

/// Most points in one packet (neighbouring points sharing one candidate list).
const PACKET_POINTS: usize = 64;

/// A packet's footprints may together span at most this many cutter diameters per axis, so that
/// the shared candidate list stays close to each point's own.
const PACKET_SPAN_DIAMETERS: f64 = 3.0;

/// [`drop_cutter`] reporting the fraction done to `progress` and stopping when it is cancelled.
///
/// Consecutive neighbouring points are handled as packets: one hierarchy query for the union of
/// their footprints, one sort of the candidates (highest top first), then per point a scan of
/// that list skipping triangles whose XY box misses the point's own footprint. Every point
/// sees exactly the triangles, in exactly the order, of a query of its own (less those that
/// cannot beat its best tip), so the result does not depend on how points are grouped.
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
        let packets = packets(chunk, cutter.radius());
        let done: Vec<Vec<Option<ClPoint>>> = packets
            .par_iter()
            .map_init(Vec::new, |scratch, range| {
                drop_packet(bvh, mesh, cutter, &chunk[range.clone()], &bbox, scratch)
            })
            .collect();
        for part in done {
            out.extend(part);
        }
        progress.set(out.len() as f64 / points.len() as f64);
    }
    Ok(out)
}

/// Split `points` into runs of consecutive points whose footprints (squares of half side `r`)
/// stay within [`PACKET_SPAN_DIAMETERS`] per axis, at most [`PACKET_POINTS`] long.
fn packets(points: &[DVec2], r: f64) -> Vec<std::ops::Range<usize>> {
    let span = PACKET_SPAN_DIAMETERS * 2.0 * r;
    let mut out = Vec::with_capacity(points.len() / 8 + 1);
    let mut start = 0;
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for (i, p) in points.iter().enumerate() {
        let (nlo, nhi) = (lo.min(*p), hi.max(*p));
        let wide = (nhi - nlo).max_element() + 2.0 * r > span;
        if i > start && (i - start >= PACKET_POINTS || wide || !p.is_finite()) {
            out.push(start..i);
            start = i;
            (lo, hi) = (*p, *p);
        } else {
            (lo, hi) = (nlo, nhi);
        }
    }
    if start < points.len() {
        out.push(start..points.len());
    }
    out
}

/// A candidate triangle of a packet.
struct Candidate {
    /// Highest corner's z.
    top: f64,
    /// Index in the source mesh.
    index: usize,
    /// XY box of the triangle.
    lo: DVec2,
    hi: DVec2,
    corners: [DVec3; 3],
    /// Upward unit normal (`None`: degenerate).
    normal: Option<DVec3>,
}

/// Drop the cutter at every point of one packet (see [`drop_cutter_progress`]).
fn drop_packet(
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
    points: &[DVec2],
    bbox: &Aabb,
    candidates: &mut Vec<Candidate>,
) -> Vec<Option<ClPoint>> {
    let r = cutter.radius();
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in points.iter().filter(|p| p.is_finite()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    candidates.clear();
    if lo.x <= hi.x {
        let query = Aabb {
            min: DVec3::new(lo.x - r, lo.y - r, bbox.min.z - 1.0),
            max: DVec3::new(hi.x + r, hi.y + r, bbox.max.z + 1.0),
        };
        candidates.extend(bvh.triangles_in_aabb(&query).into_iter().filter_map(|t| {
            let tri = mesh.triangle_corners(t)?;
            let top = tri[0].z.max(tri[1].z).max(tri[2].z);
            let (a, b, c) = (tri[0].truncate(), tri[1].truncate(), tri[2].truncate());
            Some(Candidate {
                top,
                index: t,
                lo: a.min(b).min(c),
                hi: a.max(b).max(c),
                corners: tri,
                normal: contact::upward_normal(&tri),
            })
        }));
        // Highest first; ties by index so the result does not depend on the candidate order.
        candidates.sort_unstable_by(|a, b| b.top.total_cmp(&a.top).then(a.index.cmp(&b.index)));
    }
    points
        .iter()
        .map(|c| drop_in(cutter, *c, candidates))
        .collect()
}

/// Drop the cutter at `c` onto the triangles of `candidates` (highest top first) whose XY box
/// meets its footprint square.
fn drop_in(cutter: &Cutter, c: DVec2, candidates: &[Candidate]) -> Option<ClPoint> {
    if !c.is_finite() {
        return None;
    }
    let r = cutter.radius();
    let (qlo, qhi) = (c - DVec2::splat(r), c + DVec2::splat(r));
    let mut best: Option<ClPoint> = None;
    for cand in candidates {
        if best.is_some_and(|b| cand.top <= b.z) {
            break;
        }
        if cand.lo.x > qhi.x || cand.lo.y > qhi.y || cand.hi.x < qlo.x || cand.hi.y < qlo.y {
            continue;
        }
        if cannot_beat(cutter, c, cand, best) {
            continue;
        }
        contact::drop_on_triangle(cutter, c, &cand.corners, cand.normal, cand.index, &mut best);
    }
    best
}

/// Margin (mm) of [`cannot_beat`]: far above the round-off of the contact tests (the facet
/// test's inside tolerance, the plane's height), far below any height that matters.
const SKIP_MARGIN_MM: f64 = 1e-9;

/// Whether triangle `cand` certainly cannot give a tip higher than `best` for the cutter at `c`.
///
/// Every contact lies on the triangle at some horizontal distance q from the axis, no closer
/// than the distance `q_min` from the axis to the triangle's XY box, and no higher than the
/// triangle's top; the tip is then the contact's height less h(q) ≥ h(q_min) (the profile
/// height h rises with the radius). So a triangle whose box lies wholly outside the footprint
/// disc has no contact, and one with `top − h(q_min) < best` cannot win. `q_min` is taken
/// [`SKIP_MARGIN_MM`] closer and the comparison given the same margin, so round-off in the
/// contact tests cannot make a skipped triangle win.
fn cannot_beat(cutter: &Cutter, c: DVec2, cand: &Candidate, best: Option<ClPoint>) -> bool {
    let r = cutter.radius();
    let dx = (cand.lo.x - c.x).max(c.x - cand.hi.x).max(0.0);
    let dy = (cand.lo.y - c.y).max(c.y - cand.hi.y).max(0.0);
    let q = ((dx * dx + dy * dy).sqrt() - SKIP_MARGIN_MM).max(0.0);
    if q > r {
        return true;
    }
    match (best, cutter.height_at_radius(q)) {
        (Some(b), Some(h)) => cand.top - h + SKIP_MARGIN_MM < b.z,
        _ => false,
    }
}

/// Drop-cutter at a single point (see [`drop_cutter`]).
#[must_use]
pub fn drop_cutter_at(
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
    point: DVec2,
) -> Option<ClPoint> {
    drop_packet(bvh, mesh, cutter, &[point], &bvh.bbox(), &mut Vec::new())
        .pop()
        .flatten()
}
