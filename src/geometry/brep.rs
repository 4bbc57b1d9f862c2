//! Boundary representation: faces (a surface trimmed by edge loops), edges (a curve between two
//! vertices), shells. Built by the STEP importer; tessellated by [`super::tessellate`].

use super::DVec3;
use super::curve::CurveGeom;
use super::surface::SurfaceGeom;
use crate::diagnostics::Diagnostic;

/// A vertex: a point in mm.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Vertex {
    /// Position, mm.
    pub point: DVec3,
    /// Source entity id (e.g. STEP `#id`), 0 when none.
    pub source_id: u64,
}

/// An edge: the part of `curve` between `t_start` and `t_end`, running from vertex `start` to
/// vertex `end`. The edge's direction is the direction of increasing curve parameter when
/// `same_sense`, else decreasing; `t_start`/`t_end` are the curve parameters at the start and end
/// vertices, so the edge is always traversed from `t_start` to `t_end` (which may be decreasing).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Edge {
    /// Index into [`Part::vertices`].
    pub start: usize,
    /// Index into [`Part::vertices`].
    pub end: usize,
    /// The underlying curve.
    pub curve: CurveGeom,
    /// Curve parameter at the start vertex.
    pub t_start: f64,
    /// Curve parameter at the end vertex.
    pub t_end: f64,
    /// Source entity id (`EDGE_CURVE` #id).
    pub source_id: u64,
}

/// A use of an edge in a loop, in its own direction (`forward`) or reversed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct OrientedEdge {
    /// Index into [`Part::edges`].
    pub edge: usize,
    /// True when the loop runs along the edge's direction.
    pub forward: bool,
}

/// A closed boundary loop of a face.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Loop {
    /// A chain of edges (already oriented as the loop runs: the loop's own orientation flag has
    /// been applied by the importer).
    Edges(Vec<OrientedEdge>),
    /// A degenerate loop at a single vertex (`VERTEX_LOOP`, e.g. a cone apex or sphere pole).
    Vertex(usize),
}

/// A face: a region of `surface` bounded by `loops`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Face {
    /// The carrier surface.
    pub surface: SurfaceGeom,
    /// True when the face normal agrees with the surface normal `S_u × S_v` (STEP `same_sense`).
    pub same_sense: bool,
    /// Boundary loops. The first is the outer loop when the file marked one (`FACE_OUTER_BOUND`);
    /// a face with no loops covers the whole (finite) surface domain.
    pub loops: Vec<Loop>,
    /// Index of the outer loop in `loops`, if the file said which.
    pub outer: Option<usize>,
    /// Source entity id (`ADVANCED_FACE` #id).
    pub source_id: u64,
}

/// A connected set of faces (`CLOSED_SHELL` or `OPEN_SHELL`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Shell {
    /// Indices into [`Part::faces`].
    pub faces: Vec<usize>,
    /// True for a closed shell (the boundary of a solid).
    pub closed: bool,
    /// Source entity id.
    pub source_id: u64,
}

/// A part: everything the importer read, in mm.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Part {
    /// Name from the file (product name), may be empty.
    pub name: String,
    /// Vertices.
    pub vertices: Vec<Vertex>,
    /// Edges.
    pub edges: Vec<Edge>,
    /// Faces, in file order of their shells.
    pub faces: Vec<Face>,
    /// Shells.
    pub shells: Vec<Shell>,
    /// What the importer skipped or repaired (e.g. faces of unsupported kinds, by entity id).
    pub diagnostics: Vec<Diagnostic>,
}

impl Part {
    /// Approximate bounding box from the vertices and points along the edges (empty when the
    /// part has neither, e.g. untrimmed faces only). Cheap: for choosing tolerances, not for
    /// reporting.
    #[must_use]
    pub fn rough_bbox(&self) -> super::Aabb {
        let mut b = super::Aabb::from_points(self.vertices.iter().map(|v| &v.point));
        for e in &self.edges {
            for k in 1..8 {
                let p = e
                    .curve
                    .point(e.t_start + (e.t_end - e.t_start) * f64::from(k) / 8.0);
                if p.is_finite() {
                    b.add(p);
                }
            }
        }
        b
    }
}

/// The faces joined to each face across an edge: for each edge used by exactly two faces,
/// `(edge, face a, face b)`, in edge order (seam edges, used twice by one face, are left out).
#[must_use]
pub fn face_adjacency(part: &Part) -> Vec<(usize, usize, usize)> {
    let mut users: Vec<Vec<usize>> = vec![Vec::new(); part.edges.len()];
    for (f, face) in part.faces.iter().enumerate() {
        for l in &face.loops {
            if let Loop::Edges(es) = l {
                for oe in es {
                    if let Some(u) = users.get_mut(oe.edge)
                        && !u.contains(&f)
                    {
                        u.push(f);
                    }
                }
            }
        }
    }
    users
        .iter()
        .enumerate()
        .filter_map(|(e, u)| match u.as_slice() {
            [a, b] => Some((e, *a, *b)),
            _ => None,
        })
        .collect()
}

/// Whether faces `a` and `b` meet tangentially along `edge`: at 7 points inside the edge the
/// faces' outward normals (the surface normal, reversed for a `.F.` face) differ by at most
/// `angle_tol_rad`. Points where a face's surface is farther than 0.01 mm from the edge or has
/// no normal are skipped; `false` when no point could be compared.
#[must_use]
pub fn meet_tangentially(part: &Part, edge: usize, a: usize, b: usize, angle_tol_rad: f64) -> bool {
    let (Some(e), Some(fa), Some(fb)) =
        (part.edges.get(edge), part.faces.get(a), part.faces.get(b))
    else {
        return false;
    };
    let normal = |f: &Face, p: DVec3| -> Option<DVec3> {
        let sp = f.surface.closest_point(p, f.surface.domain(), None);
        if sp.distance > 0.01 {
            return None;
        }
        let n = f.surface.derivs(sp.uv.x, sp.uv.y).normal()?;
        Some(if f.same_sense { n } else { -n })
    };
    let cos_tol = angle_tol_rad.cos();
    let mut compared = 0;
    for k in 1..8 {
        let p = e
            .curve
            .point(e.t_start + (e.t_end - e.t_start) * f64::from(k) / 8.0);
        if !p.is_finite() {
            continue;
        }
        let (Some(na), Some(nb)) = (normal(fa, p), normal(fb, p)) else {
            continue;
        };
        if na.dot(nb) < cos_tol {
            return false;
        }
        compared += 1;
    }
    compared > 0
}

/// The tangent-connected faces of `seed`: every face reachable from it across edges where the
/// faces meet tangentially ([`meet_tangentially`] within `angle_tol_rad`), the seed included,
/// in ascending order (empty for a missing seed). The one-click "tangent-connected faces"
/// selection.
#[must_use]
pub fn tangent_connected(part: &Part, seed: usize, angle_tol_rad: f64) -> Vec<usize> {
    if seed >= part.faces.len() {
        return Vec::new();
    }
    let adjacency = face_adjacency(part);
    let mut tangent: Vec<Vec<usize>> = vec![Vec::new(); part.faces.len()];
    for &(e, a, b) in &adjacency {
        if meet_tangentially(part, e, a, b, angle_tol_rad) {
            tangent[a].push(b);
            tangent[b].push(a);
        }
    }
    let mut seen = vec![false; part.faces.len()];
    let mut stack = vec![seed];
    seen[seed] = true;
    while let Some(f) = stack.pop() {
        for &g in &tangent[f] {
            if !seen[g] {
                seen[g] = true;
                stack.push(g);
            }
        }
    }
    (0..part.faces.len()).filter(|&f| seen[f]).collect()
}
