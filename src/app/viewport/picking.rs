//! Picking: which triangle of the part lies under the cursor (a ray cast on the CPU, brute force
//! over the triangles with a bounding-box reject; replace with the engine's BVH when it lands).

use glam::DVec3;

use crate::geometry::mesh::TriMesh;

/// Meshes larger than this are not picked on hover (the brute-force cast would stall the UI).
pub const MAX_HOVER_TRIANGLES: usize = 400_000;

/// A hit on the part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The point, mm.
    pub point: DVec3,
    /// Index of the triangle hit.
    pub triangle: usize,
    /// Distance along the ray.
    pub distance: f64,
}

/// The nearest triangle hit by the ray `origin + t · dir`, t ≥ 0 (Möller–Trumbore).
#[must_use]
pub fn ray_cast(mesh: &TriMesh, origin: DVec3, dir: DVec3) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let Some([a, b, c]) = corners(mesh, *tri) else {
            continue;
        };
        let e1 = b - a;
        let e2 = c - a;
        let p = dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-18 {
            continue;
        }
        let inv = 1.0 / det;
        let s = origin - a;
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            continue;
        }
        let q = s.cross(e1);
        let v = dir.dot(q) * inv;
        if v < 0.0 || u + v > 1.0 {
            continue;
        }
        let distance = e2.dot(q) * inv;
        if distance >= 0.0 && best.is_none_or(|h| distance < h.distance) {
            best = Some(Hit {
                point: origin + dir * distance,
                triangle: t,
                distance,
            });
        }
    }
    best
}

fn corners(mesh: &TriMesh, tri: [u32; 3]) -> Option<[DVec3; 3]> {
    Some([
        *mesh.positions.get(tri[0] as usize)?,
        *mesh.positions.get(tri[1] as usize)?,
        *mesh.positions.get(tri[2] as usize)?,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearest_of_two_parallel_triangles_is_hit() {
        let mesh = TriMesh {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(0.0, 2.0, 0.0),
                DVec3::new(0.0, 0.0, 1.0),
                DVec3::new(2.0, 0.0, 1.0),
                DVec3::new(0.0, 2.0, 1.0),
            ],
            normals: Vec::new(),
            triangles: vec![[0, 1, 2], [3, 4, 5]],
        };
        let hit = ray_cast(&mesh, DVec3::new(0.5, 0.5, 5.0), -DVec3::Z);
        assert_eq!(hit.map(|h| h.triangle), Some(1));
        assert!(hit.is_some_and(|h| (h.point - DVec3::new(0.5, 0.5, 1.0)).length() < 1e-12));
        assert_eq!(ray_cast(&mesh, DVec3::new(3.0, 3.0, 5.0), -DVec3::Z), None);
    }
}
