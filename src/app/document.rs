//! The open document: the loaded part plus what the workstation derives from it once (bounds,
//! areas, draw data for the viewport, feature edges) and the current selection.

use std::collections::HashMap;
use std::sync::Arc;

use glam::DVec3;

use super::document_loader::LoadedPart;
use super::scalar_field::CurvatureField;
use crate::geometry::Aabb;
use crate::geometry::bvh::MeshBvh;
use crate::render::{DataId, LineData, MeshData};

/// What the user has selected.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Selection {
    /// Nothing.
    #[default]
    None,
    /// The whole part.
    Part,
    /// One face of the part (index into [`LoadedPart::faces`]).
    Face(usize),
}

/// Colour of the part's feature edges (sRGB).
const EDGE_COLOUR: [u8; 4] = [24, 26, 30, 255];

/// A loaded part with its derived data.
#[derive(Debug)]
pub struct Document {
    /// The part as loaded.
    pub part: LoadedPart,
    /// Bounding box (mm).
    pub bounds: Aabb,
    /// Total surface area of the mesh (mm²).
    pub area_mm2: f64,
    /// Surface area of each face's triangles (mm²), by face index.
    pub face_area_mm2: Vec<f64>,
    /// Triangles of each face, by face index.
    pub face_triangles: Vec<usize>,
    /// The mesh in render form.
    pub render_mesh: Arc<MeshData>,
    /// Feature edges (face boundaries, open boundaries, creases) in render form.
    pub render_edges: Arc<LineData>,
    /// Render ids of `render_mesh` and `render_edges`.
    pub ids: [DataId; 2],
    /// Current selection.
    pub selection: Selection,
    /// Triangle hierarchy for picking (`None` for a mesh without a triangle of non-zero area).
    pub bvh: Option<MeshBvh>,
    /// Curvatures at the mesh vertices, once computed (a background job).
    pub curvature: Option<CurvatureField>,
}

impl Document {
    /// Derive everything from `part`; `first_id` and `first_id + 1` become the render ids.
    #[must_use]
    pub fn new(part: LoadedPart, first_id: DataId) -> Self {
        let mesh = part.mesh();
        let bounds = Aabb::from_points(&mesh.positions);
        let face_count = part.faces.len().max(1);
        let mut face_area_mm2 = vec![0.0; face_count];
        let mut face_triangles = vec![0; face_count];
        let mut area_mm2 = 0.0;
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let a = triangle_area(mesh.positions.as_slice(), *tri);
            area_mm2 += a;
            let face = part.face_of_triangle().get(t).map_or(0, |&f| f as usize);
            if let (Some(fa), Some(ft)) =
                (face_area_mm2.get_mut(face), face_triangles.get_mut(face))
            {
                *fa += a;
                *ft += 1;
            }
        }
        let bvh = MeshBvh::new(part.mesh()).ok();
        let render_mesh = Arc::new(render_mesh(&part));
        let render_edges = Arc::new(feature_edges(&part));
        Self {
            part,
            bounds,
            area_mm2,
            face_area_mm2,
            face_triangles,
            render_mesh,
            render_edges,
            ids: [first_id, first_id + 1],
            selection: Selection::Part,
            bvh,
            curvature: None,
        }
    }

    /// The triangles of face `face` as a mesh (for highlighting).
    #[must_use]
    pub fn face_mesh(&self, face: usize) -> MeshData {
        let mut out = MeshData::default();
        let mut remap: HashMap<u32, u32> = HashMap::new();
        let src = &self.render_mesh;
        for (t, tri) in self.part.mesh().triangles.iter().enumerate() {
            if self.part.face_of_triangle().get(t).map(|&f| f as usize) != Some(face) {
                continue;
            }
            for &v in tri {
                let next = u32::try_from(out.positions.len()).unwrap_or(u32::MAX);
                let i = *remap.entry(v).or_insert_with(|| {
                    out.positions
                        .push(src.positions.get(v as usize).copied().unwrap_or_default());
                    out.normals.push(
                        src.normals
                            .get(v as usize)
                            .copied()
                            .unwrap_or([0.0, 0.0, 1.0]),
                    );
                    next
                });
                out.indices.push(i);
            }
        }
        out
    }
}

fn triangle_area(points: &[DVec3], tri: [u32; 3]) -> f64 {
    let p = |i: u32| points.get(i as usize).copied().unwrap_or(DVec3::ZERO);
    let [a, b, c] = tri.map(p);
    0.5 * (b - a).cross(c - a).length()
}

fn render_mesh(part: &LoadedPart) -> MeshData {
    let mesh = part.mesh();
    let f = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
    let normals = if mesh.normals.len() == mesh.positions.len() {
        mesh.normals.iter().map(|&n| f(n)).collect()
    } else {
        // No normals from the importer: area-weighted vertex normals.
        let mut acc = vec![DVec3::ZERO; mesh.positions.len()];
        for tri in &mesh.triangles {
            let [a, b, c] = tri.map(|i| {
                mesh.positions
                    .get(i as usize)
                    .copied()
                    .unwrap_or(DVec3::ZERO)
            });
            let n = (b - a).cross(c - a);
            for &i in tri {
                if let Some(s) = acc.get_mut(i as usize) {
                    *s += n;
                }
            }
        }
        acc.into_iter()
            .map(|n| f(n.normalize_or(DVec3::Z)))
            .collect()
    };
    MeshData {
        positions: mesh.positions.iter().map(|&p| f(p)).collect(),
        normals,
        scalars: Vec::new(),
        indices: mesh.triangles.iter().flatten().copied().collect(),
    }
}

/// Edges where the face changes, the mesh is open, or the surface folds by more than 35°.
/// Vertices are matched by position, so meshes with split normals still give one edge.
fn feature_edges(part: &LoadedPart) -> LineData {
    let mesh = part.mesh();
    let mut canonical: HashMap<[u64; 3], u32> = HashMap::new();
    let key_of: Vec<u32> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let idx = u32::try_from(i).unwrap_or(u32::MAX);
            *canonical
                .entry(p.to_array().map(|v| (v + 0.0).to_bits()))
                .or_insert(idx)
        })
        .collect();
    let cos_crease = 35.0_f64.to_radians().cos();
    // Edge (low, high canonical vertex) -> triangles using it.
    let mut uses: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let (ka, kb) = (
                key_of.get(a as usize).copied().unwrap_or(a),
                key_of.get(b as usize).copied().unwrap_or(b),
            );
            if ka != kb {
                uses.entry((ka.min(kb), ka.max(kb))).or_default().push(t);
            }
        }
    }
    let normal = |t: usize| {
        mesh.triangles.get(t).map_or(DVec3::Z, |tri| {
            let [a, b, c] = tri.map(|i| {
                mesh.positions
                    .get(i as usize)
                    .copied()
                    .unwrap_or(DVec3::ZERO)
            });
            (b - a).cross(c - a).normalize_or_zero()
        })
    };
    let face = |t: usize| part.face_of_triangle().get(t).copied().unwrap_or(0);
    let mut edges: Vec<(u32, u32)> = uses
        .into_iter()
        .filter(|(_, ts)| match ts.as_slice() {
            [a, b] => face(*a) != face(*b) || normal(*a).dot(normal(*b)) < cos_crease,
            _ => true,
        })
        .map(|(e, _)| e)
        .collect();
    edges.sort_unstable();
    let mut lines = LineData::default();
    let mut vertex_of: HashMap<u32, u32> = HashMap::new();
    for (a, b) in edges {
        for v in [a, b] {
            let next = u32::try_from(lines.positions.len()).unwrap_or(u32::MAX);
            let i = *vertex_of.entry(v).or_insert_with(|| {
                let p = mesh
                    .positions
                    .get(v as usize)
                    .copied()
                    .unwrap_or(DVec3::ZERO);
                lines.positions.push([p.x as f32, p.y as f32, p.z as f32]);
                lines.colours.push(EDGE_COLOUR);
                next
            });
            lines.indices.push(i);
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::document_loader::FaceSummary;
    use crate::geometry::mesh::TriMesh;

    /// A unit square (two triangles, one face) next to a second face folded up 90°.
    fn two_faces() -> LoadedPart {
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, 2.0),
            DVec3::new(0.0, 1.0, 2.0),
        ];
        let mesh = TriMesh {
            positions,
            normals: Vec::new(),
            triangles: vec![[0, 1, 2], [0, 2, 3], [0, 3, 5], [0, 5, 4]],
        };
        let mut workpiece =
            crate::import::Workpiece::from_mesh(std::path::Path::new("test.stl"), mesh, Vec::new());
        workpiece.face_of_triangle = vec![0, 0, 1, 1];
        LoadedPart {
            workpiece: std::sync::Arc::new(workpiece),
            path: "test.stl".into(),
            name: "t".into(),
            product_name: String::new(),
            display_mesh: None,
            faces: vec![
                FaceSummary {
                    kind: "plane".into(),
                    source_id: 10,
                    surface: None,
                    same_sense: true,
                },
                FaceSummary {
                    kind: "plane".into(),
                    source_id: 11,
                    surface: None,
                    same_sense: true,
                },
            ],
            diagnostics: Vec::new(),
            format: "STEP",
            features: Vec::new(),
        }
    }

    #[test]
    fn areas_and_edges_follow_the_faces() {
        let d = Document::new(two_faces(), 1);
        // Square 1 mm², wall 1 × 2 = 2 mm².
        assert!((d.area_mm2 - 3.0).abs() < 1e-12);
        assert_eq!(d.face_triangles, vec![2, 2]);
        assert!(
            (d.face_area_mm2[0] - 1.0).abs() < 1e-12 && (d.face_area_mm2[1] - 2.0).abs() < 1e-12
        );
        assert_eq!(d.face_mesh(1).triangle_count(), 2);
        // Boundary: 3 square edges + 3 wall edges, plus the shared fold (0-3): 7; the square's and
        // the wall's diagonals are interior and flat.
        assert_eq!(d.render_edges.segment_count(), 7);
        assert_eq!(d.render_mesh.triangle_count(), 4);
        assert_eq!(d.render_mesh.problem(), None);
    }
}
