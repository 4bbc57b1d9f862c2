//! Indexed triangle meshes (mm): welding, normals, area, volume of closed meshes, closedness.

use super::DVec3;

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
