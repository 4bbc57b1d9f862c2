//! Display normals for meshes without surface normals (STL): a vertex is split where the surface
//! folds by more than a crease angle, and each copy gets the area-weighted normal of the
//! triangles on its side, so fillets look smooth and edges stay sharp.

use std::collections::HashMap;

use glam::DVec3;

use crate::geometry::mesh::TriMesh;

/// `mesh` with vertices split at creases sharper than `crease_angle_rad` and smooth normals
/// elsewhere. Triangles keep their order; positions are copied, never moved.
#[must_use]
pub fn split_creases(mesh: &TriMesh, crease_angle_rad: f64) -> TriMesh {
    let cos_crease = crease_angle_rad.cos();
    let corner = |i: u32| {
        mesh.positions
            .get(i as usize)
            .copied()
            .unwrap_or(DVec3::ZERO)
    };
    // Area-weighted (unnormalised) face normals.
    let face_normal: Vec<DVec3> = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(corner);
            (b - a).cross(c - a)
        })
        .collect();
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); mesh.positions.len()];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for &v in tri {
            if let Some(list) = incident.get_mut(v as usize) {
                list.push(t);
            }
        }
    }
    let mut out = TriMesh::default();
    let mut copies: HashMap<(u32, [i64; 3]), u32> = HashMap::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let own = face_normal[t].normalize_or_zero();
        let mut new_tri = [0_u32; 3];
        for (k, &v) in tri.iter().enumerate() {
            let n = incident
                .get(v as usize)
                .map_or(DVec3::ZERO, |list| {
                    list.iter()
                        .map(|&o| face_normal[o])
                        .filter(|n| n.normalize_or_zero().dot(own) >= cos_crease)
                        .sum::<DVec3>()
                })
                .normalize_or(own);
            // Copies of a vertex with (nearly) the same normal are shared.
            let key = (v, n.to_array().map(|x| (x * 1e4).round() as i64));
            let next = u32::try_from(out.positions.len()).unwrap_or(u32::MAX);
            new_tri[k] = *copies.entry(key).or_insert_with(|| {
                out.positions.push(corner(v));
                out.normals.push(n);
                next
            });
        }
        out.triangles.push(new_tri);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square (two triangles) and a wall folded up 90° along x = 0, welded.
    fn folded() -> TriMesh {
        TriMesh {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 1.0),
                DVec3::new(0.0, 0.0, 1.0),
            ],
            normals: Vec::new(),
            triangles: vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]],
        }
    }

    #[test]
    fn a_right_angle_is_split_and_flat_parts_are_shared() {
        let out = split_creases(&folded(), 35_f64.to_radians());
        assert_eq!(out.triangles.len(), 4);
        // Six points; the two on the fold get one copy per side: eight vertices.
        assert_eq!(out.positions.len(), 8);
        for (t, tri) in out.triangles.iter().enumerate() {
            let expected = if t < 2 { DVec3::Z } else { DVec3::X };
            for &v in tri {
                assert!((out.normals[v as usize] - expected).length() < 1e-12, "{t}");
            }
        }
    }

    #[test]
    fn a_wide_crease_angle_smooths_the_fold() {
        let out = split_creases(&folded(), 100_f64.to_radians());
        assert_eq!(out.positions.len(), 6);
        // On the fold, the normal bisects the two sides (equal areas).
        let v0 = out.triangles[0][0] as usize;
        assert!((out.normals[v0] - DVec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-12);
    }
}
