//! Picking: which triangle of the part lies under the cursor (a ray cast through the engine's
//! triangle hierarchy, [`MeshBvh`]), and, for a click on a B-rep face, the surface point under
//! it: (u, v) by point inversion on the face's surface, the exact point, normal and principal
//! curvatures from [`crate::geometry::diffgeom::SurfaceDerivs`].

use glam::{DVec2, DVec3};

use super::super::document_loader::FaceSummary;
use crate::geometry::bvh::MeshBvh;

/// A hit on the part's mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The point on the mesh, mm.
    pub point: DVec3,
    /// Index of the triangle hit.
    pub triangle: usize,
    /// Distance along the ray (in units of the ray direction's length).
    pub distance: f64,
}

/// The nearest triangle hit by the ray `origin + t · dir`, t ≥ 0.
#[must_use]
pub fn ray_cast(bvh: &MeshBvh, origin: DVec3, dir: DVec3) -> Option<Hit> {
    bvh.ray_cast(origin, dir, f64::INFINITY).map(|h| Hit {
        point: h.point,
        triangle: h.triangle,
        distance: h.t,
    })
}

/// The surface under a click, evaluated on the exact surface (not the mesh).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePick {
    /// Face index (into the part's faces).
    pub face: usize,
    /// Surface parameters.
    pub uv: DVec2,
    /// The surface point S(u, v), mm.
    pub point: DVec3,
    /// Distance from the mesh hit to the surface point (the tessellation's local chord error), mm.
    pub distance_mm: f64,
    /// Unit normal pointing out of the face (`None` at a degenerate point).
    pub normal: Option<DVec3>,
    /// Principal curvatures (k_min, k_max), 1/mm, signed about `normal`.
    pub curvature: Option<(f64, f64)>,
}

/// Evaluate `face` at the surface point closest to the mesh point `near` (mm).
#[must_use]
pub fn surface_pick(face_index: usize, face: &FaceSummary, near: DVec3) -> Option<SurfacePick> {
    let surface = face.surface.as_ref()?;
    let sp = surface.closest_point(near, surface.domain(), None);
    let d = surface.derivs(sp.uv.x, sp.uv.y);
    let sign = if face.same_sense { 1.0 } else { -1.0 };
    let normal = d.normal().map(|n| n * sign);
    // Flipping the normal negates the curvatures and swaps which one is smaller.
    let curvature = d.principal().map(|p| {
        if face.same_sense {
            (p.k_min, p.k_max)
        } else {
            (-p.k_max, -p.k_min)
        }
    });
    Some(SurfacePick {
        face: face_index,
        uv: sp.uv,
        point: sp.point,
        distance_mm: sp.distance,
        normal,
        curvature,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::mesh::TriMesh;

    /// Möller–Trumbore over every triangle: the reference for the hierarchy.
    fn brute_force(mesh: &TriMesh, origin: DVec3, dir: DVec3) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            let (e1, e2) = (b - a, c - a);
            let p = dir.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-18 {
                continue;
            }
            let s = origin - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = dir.dot(q) / det;
            let dist = e2.dot(q) / det;
            if (0.0..=1.0).contains(&u)
                && v >= 0.0
                && u + v <= 1.0
                && dist >= 0.0
                && best.is_none_or(|(_, d)| dist < d)
            {
                best = Some((t, dist));
            }
        }
        best
    }

    #[test]
    fn the_hierarchy_hits_what_brute_force_hits() {
        // A bumpy 20 × 20 height field, z = sin x cos y, and rays from above at a slant.
        let n = 20;
        let mut mesh = TriMesh::default();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (f64::from(i) * 0.5, f64::from(j) * 0.5);
                mesh.positions.push(DVec3::new(x, y, x.sin() * y.cos()));
            }
        }
        let row = n + 1;
        for j in 0..n {
            for i in 0..n {
                let a = j * row + i;
                mesh.triangles.push([a, a + 1, a + row + 1]);
                mesh.triangles.push([a, a + row + 1, a + row]);
            }
        }
        let bvh = MeshBvh::new(&mesh).expect("hierarchy");
        let mut hits = 0;
        for k in 0..200 {
            let t = f64::from(k);
            let origin = DVec3::new((t * 0.37) % 10.0, (t * 0.61) % 10.0, 5.0);
            let dir = DVec3::new(0.1 * (t * 0.3).sin(), 0.1 * (t * 0.7).cos(), -1.0);
            let reference = brute_force(&mesh, origin, dir);
            let hit = ray_cast(&bvh, origin, dir);
            match (reference, hit) {
                (Some((_, d)), Some(h)) => {
                    hits += 1;
                    assert!(
                        (h.distance - d).abs() < 1e-9,
                        "ray {k}: {} vs {d}",
                        h.distance
                    );
                }
                (None, None) => {}
                (r, h) => panic!("ray {k}: brute force {r:?}, hierarchy {h:?}"),
            }
        }
        assert!(hits > 150, "{hits} hits");
    }
}
