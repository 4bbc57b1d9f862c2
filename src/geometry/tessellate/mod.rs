//! Tessellation of B-rep faces to a chord tolerance, with normals.
//!
//! The method, per part:
//! 1. every edge is discretised once (`edge`): its polyline is shared by the faces on both
//!    sides, and its end points are the vertices' own coordinates, so a model that is watertight
//!    in the CAD system gives a closed mesh;
//! 2. each face's loops are mapped to the surface's parameter plane by point inversion, unwrapped
//!    across periodic seams and expanded at singular points such as sphere poles (`loops`);
//! 3. the parameter plane (scaled to approximate arc length) gets a grid of interior points whose
//!    spacing bounds the chord error from the surface's second derivatives, and a constrained
//!    Delaunay triangulation (the `spade` crate) of boundary plus interior points keeps the
//!    triangles inside the loops (crossing parity) (`face`);
//! 4. boundary vertices keep their exact 3D edge points; interior ones are evaluated on the
//!    surface; normals come from the surface, flipped where the face is reversed.

mod edge;
mod face;
mod loops;

use super::brep::Part;
use super::mesh::TriMesh;
use super::{Aabb, DVec3};
use crate::diagnostics::Diagnostic;

pub use edge::discretize_edge;
pub use face::{FaceMesh, tessellate_face};

/// A face's boundary loops in its surface's parameter plane, as the tessellator triangulates
/// them: each loop's edges discretised to `opts`, inverted onto the surface, unwrapped across
/// periodic seams (all loops in one period window), expanded at poles, and loops that run once
/// around a periodic direction closed into bands or caps. Closed polygons (last joins first);
/// the face is their even-odd interior. Empty for a face without loops.
///
/// # Errors
/// A message when the loops cannot be mapped to the parameter plane.
pub fn face_param_loops(
    face: &super::brep::Face,
    part: &Part,
    opts: &TessellationOptions,
) -> Result<Vec<Vec<super::DVec2>>, String> {
    let opts = opts.sanitized();
    let mut polylines: Vec<Vec<DVec3>> = vec![Vec::new(); part.edges.len()];
    for lp in &face.loops {
        if let super::brep::Loop::Edges(oes) = lp {
            for oe in oes {
                if let (Some(slot), Some(e)) = (polylines.get_mut(oe.edge), part.edges.get(oe.edge))
                    && slot.is_empty()
                {
                    *slot = discretize_edge(e, &part.vertices, &opts);
                }
            }
        }
    }
    let loops = loops::face_uv_loops(face, part, &polylines, opts.chord_tol_mm)?;
    Ok(loops.into_iter().map(|l| l.uv).collect())
}

/// How finely to tessellate.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TessellationOptions {
    /// Maximum distance between a triangle (or edge segment) and the exact surface, mm.
    pub chord_tol_mm: f64,
    /// Maximum angle between the normals (tangents) at the ends of an edge or segment, rad
    /// (default 0.5 rad, Open CASCADE's default angular deflection: it only governs where the
    /// radius is under 0.04 mm at the default chord tolerance; the chord tolerance sets the step
    /// everywhere else).
    pub angle_tol_rad: f64,
    /// Upper bound on interior grid points per face (protects against absurd requests).
    pub max_grid_points_per_face: usize,
}

impl Default for TessellationOptions {
    fn default() -> Self {
        Self {
            chord_tol_mm: 0.01,
            angle_tol_rad: 0.5,
            max_grid_points_per_face: 400_000,
        }
    }
}

impl TessellationOptions {
    /// Options with a given chord tolerance and the default angle tolerance.
    #[must_use]
    pub fn with_chord_tol(chord_tol_mm: f64) -> Self {
        Self {
            chord_tol_mm,
            ..Self::default()
        }
    }

    /// Options for a part of the given size (bounding-box diagonal, mm): the default 0.01 mm chord
    /// tolerance, tightened to 1e-4 of the size for small parts so that areas and volumes stay
    /// within 0.1 % of the exact ones whatever the scale.
    #[must_use]
    pub fn for_size(diagonal_mm: f64) -> Self {
        let d = Self::default();
        let rel = if diagonal_mm.is_finite() && diagonal_mm > 0.0 {
            1e-4 * diagonal_mm
        } else {
            d.chord_tol_mm
        };
        Self::with_chord_tol(d.chord_tol_mm.min(rel).max(1e-6))
    }

    /// The options with non-finite or non-positive values replaced by the defaults.
    #[must_use]
    pub fn sanitized(self) -> Self {
        let d = Self::default();
        Self {
            chord_tol_mm: if self.chord_tol_mm.is_finite() && self.chord_tol_mm > 0.0 {
                self.chord_tol_mm
            } else {
                d.chord_tol_mm
            },
            angle_tol_rad: if self.angle_tol_rad.is_finite() && self.angle_tol_rad > 1e-4 {
                self.angle_tol_rad.min(1.5)
            } else {
                d.angle_tol_rad
            },
            max_grid_points_per_face: self.max_grid_points_per_face.max(16),
        }
    }
}

/// The finest chord tolerance relative to the part's bounding-box diagonal.
pub const RELATIVE_TOLERANCE_FLOOR: f64 = 1e-6;

/// One face's triangles inside a [`PartMesh`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FaceRange {
    /// First triangle index.
    pub first: usize,
    /// Number of triangles.
    pub count: usize,
    /// Area of the face on the exact surface, mm² (see [`FaceMesh::area_mm2`]); 0 for a face
    /// that could not be tessellated.
    pub area_mm2: f64,
    /// Area of the face's triangles, mm² (below `area_mm2` on convex faces by about the chord
    /// tolerance over the radius).
    pub mesh_area_mm2: f64,
    /// The face's share of the enclosed volume, mm³ (see [`FaceMesh::volume_mm3`]).
    pub volume_mm3: f64,
}

/// One body of a part: a shell, whether its mesh closes, and the volume it encloses.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Body {
    /// Index into [`Part::shells`].
    pub shell: usize,
    /// Source entity id of the shell.
    pub source_id: u64,
    /// Number of faces.
    pub faces: usize,
    /// True when the file calls the shell closed, every face was tessellated and the shell's
    /// triangles, welded, leave no boundary edge.
    pub closed: bool,
    /// Volume enclosed by the exact faces (divergence theorem), mm³; `None` when the shell is
    /// not closed.
    pub volume_mm3: Option<f64>,
}

/// A tessellated part: one mesh, with the face each triangle came from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PartMesh {
    /// All faces' triangles, welded along shared edges.
    pub mesh: TriMesh,
    /// For each triangle, the index of its face in [`Part::faces`].
    pub face_of_triangle: Vec<u32>,
    /// Per face (same order as [`Part::faces`]): its triangles and area.
    pub faces: Vec<FaceRange>,
    /// One entry per shell of the part, in [`Part::shells`] order.
    pub bodies: Vec<Body>,
    /// Faces that could not be tessellated, and other notes.
    pub diagnostics: Vec<Diagnostic>,
}

impl PartMesh {
    /// Total area of the faces on the exact surfaces, mm².
    #[must_use]
    pub fn area_mm2(&self) -> f64 {
        self.faces.iter().map(|f| f.area_mm2).sum()
    }

    /// Total volume of the bodies when every body is closed, mm³.
    #[must_use]
    pub fn volume_mm3(&self) -> Option<f64> {
        if self.bodies.is_empty() {
            return None;
        }
        self.bodies.iter().map(|b| b.volume_mm3).sum()
    }

    /// Bounding box of the mesh.
    #[must_use]
    pub fn bbox(&self) -> Aabb {
        Aabb::from_points(&self.mesh.positions)
    }
}

/// Tessellate every face of `part`. Faces that fail are left out and reported in
/// [`PartMesh::diagnostics`] by their source entity id.
#[must_use]
pub fn tessellate_part(part: &Part, opts: &TessellationOptions) -> PartMesh {
    let mut opts = opts.sanitized();
    let mut out = PartMesh::default();
    // A budget: never finer than 1e-6 of the part's size (a 250 m part gets 0.25 mm), so a part
    // in metres or kilometres, or a vertex far out, cannot ask for billions of triangles.
    let diagonal = part.rough_bbox().diagonal();
    let floor = RELATIVE_TOLERANCE_FLOOR * diagonal;
    if floor.is_finite() && floor > opts.chord_tol_mm {
        out.diagnostics.push(Diagnostic::warning(
            None,
            format!(
                "chord tolerance raised from {} mm to {floor:.4} mm (1e-6 of the part's {diagonal:.0} mm \
                 size) to keep the mesh within memory",
                opts.chord_tol_mm
            ),
        ));
        opts.chord_tol_mm = floor;
    }
    let edge_polylines: Vec<Vec<DVec3>> = part
        .edges
        .iter()
        .map(|e| discretize_edge(e, &part.vertices, &opts))
        .collect();
    for (fi, face) in part.faces.iter().enumerate() {
        let first = out.mesh.triangles.len();
        let (mut area, mut exact_area, mut volume) = (0.0, 0.0, 0.0);
        match tessellate_face(face, part, &edge_polylines, &opts) {
            Ok(fm) => {
                exact_area = fm.area_mm2;
                volume = fm.volume_mm3;
                // Each face keeps its own vertices (so normals stay sharp at edges); shared edge
                // points are bit-identical across faces, so welding joins them exactly.
                let base = u32::try_from(out.mesh.positions.len()).unwrap_or(u32::MAX);
                out.mesh.positions.extend_from_slice(&fm.positions);
                out.mesh.normals.extend_from_slice(&fm.normals);
                for t in &fm.triangles {
                    let tri = t.map(|i| base + i);
                    if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                        continue;
                    }
                    let [a, b, c] = tri.map(|i| out.mesh.positions[i as usize]);
                    area += 0.5 * (b - a).cross(c - a).length();
                    out.mesh.triangles.push(tri);
                    out.face_of_triangle
                        .push(u32::try_from(fi).unwrap_or(u32::MAX));
                }
                out.diagnostics.extend(fm.diagnostics);
            }
            Err(msg) => out.diagnostics.push(Diagnostic::error(
                Some(format!("#{}", face.source_id)),
                format!("face not tessellated: {msg}"),
            )),
        }
        let count = out.mesh.triangles.len() - first;
        let reported = out
            .diagnostics
            .iter()
            .any(|d| d.place.as_deref() == Some(&format!("#{}", face.source_id)));
        if count == 0 && !reported {
            // A face may never vanish silently.
            out.diagnostics.push(Diagnostic::error(
                Some(format!("#{}", face.source_id)),
                "face not tessellated: it gave no triangles (degenerate or non-finite geometry)",
            ));
        }
        if count == 0 {
            exact_area = 0.0;
            volume = 0.0;
        }
        out.faces.push(FaceRange {
            first,
            count,
            area_mm2: exact_area,
            mesh_area_mm2: area,
            volume_mm3: volume,
        });
    }
    out.bodies = bodies(part, &out);
    out
}

/// Each shell's closedness and volume.
fn bodies(part: &Part, pm: &PartMesh) -> Vec<Body> {
    let weld_tol = 1e-9 * part.rough_bbox().diagonal().max(1.0);
    part.shells
        .iter()
        .enumerate()
        .map(|(si, shell)| {
            if !shell.closed {
                // An open shell bounds no solid: no volume to give, nothing to weld.
                return Body {
                    shell: si,
                    source_id: shell.source_id,
                    faces: shell.faces.len(),
                    closed: false,
                    volume_mm3: None,
                };
            }
            let mut sub = TriMesh::default();
            let mut all = !shell.faces.is_empty();
            let mut volume = 0.0;
            for &f in &shell.faces {
                let Some(r) = pm.faces.get(f).filter(|r| r.count > 0) else {
                    all = false;
                    continue;
                };
                volume += r.volume_mm3;
                for t in &pm.mesh.triangles[r.first..r.first + r.count] {
                    let base = u32::try_from(sub.positions.len()).unwrap_or(u32::MAX);
                    sub.positions
                        .extend(t.iter().map(|&i| pm.mesh.positions[i as usize]));
                    sub.normals
                        .extend(t.iter().map(|&i| pm.mesh.normals[i as usize]));
                    sub.triangles.push([base, base + 1, base + 2]);
                }
            }
            sub.weld(weld_tol);
            let closed = all && !sub.triangles.is_empty() && sub.is_closed();
            Body {
                shell: si,
                source_id: shell.source_id,
                faces: shell.faces.len(),
                closed,
                volume_mm3: closed.then_some(volume.abs()),
            }
        })
        .collect()
}
