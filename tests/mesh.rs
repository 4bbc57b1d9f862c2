//! Triangle meshes against closed forms (cube, octahedron, sphere), and the BVH against brute
//! force on random queries (fixed seed) on the bicubic-hills STL and a unit sphere.

mod common;

use std::collections::BTreeMap;
use std::f64::consts::PI;

use glam::DVec3;
use talas::geometry::Aabb;
use talas::geometry::bvh::{BvhError, MeshBvh};
use talas::geometry::mesh::TriMesh;

/// Unit cube [0, 1]³, outward triangles; faces split on alternating diagonals so that corners
/// touch one or two triangles of a face.
fn cube() -> TriMesh {
    let p = (0..8)
        .map(|i| {
            DVec3::new(
                f64::from(i & 1),
                f64::from((i >> 1) & 1),
                f64::from((i >> 2) & 1),
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut t = Vec::new();
    for (i, q) in quads.iter().enumerate() {
        if i % 2 == 0 {
            t.push([q[0], q[1], q[2]]);
            t.push([q[0], q[2], q[3]]);
        } else {
            t.push([q[0], q[1], q[3]]);
            t.push([q[1], q[2], q[3]]);
        }
    }
    TriMesh::new(p, t)
}

/// The same cube as a facet soup: three fresh vertices per triangle.
fn soup(mesh: &TriMesh) -> TriMesh {
    let mut out = TriMesh::default();
    for t in &mesh.triangles {
        let n = out.positions.len() as u32;
        out.positions
            .extend(t.iter().map(|&i| mesh.positions[i as usize]));
        out.triangles.push([n, n + 1, n + 2]);
    }
    out
}

/// Regular octahedron with vertices at ±1 on the axes: volume 4/3, area 4√3.
fn octahedron() -> TriMesh {
    let p = vec![
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
    ];
    let t = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    TriMesh::new(p, t)
}

/// Unit icosphere: icosahedron subdivided `level` times, vertices pushed onto the sphere.
fn icosphere(level: usize) -> TriMesh {
    let g = (1.0 + 5.0_f64.sqrt()) / 2.0;
    let mut p: Vec<DVec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut t: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        let mut next = Vec::new();
        for [a, b, c] in t {
            let mut m = |i: u32, j: u32| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    p.push(((p[i as usize] + p[j as usize]) * 0.5).normalize());
                    p.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        t = next;
    }
    TriMesh::new(p, t)
}

/// xorshift64* with a fixed seed.
struct Rng(u64);

impl Rng {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
    fn point_in(&mut self, lo: DVec3, hi: DVec3) -> DVec3 {
        DVec3::new(
            self.range(lo.x, hi.x),
            self.range(lo.y, hi.y),
            self.range(lo.z, hi.z),
        )
    }
    fn direction(&mut self) -> DVec3 {
        loop {
            let v = self.point_in(DVec3::splat(-1.0), DVec3::splat(1.0));
            if (0.01..=1.0).contains(&v.length_squared()) {
                return v.normalize();
            }
        }
    }
}

fn corners(m: &TriMesh, t: usize) -> [DVec3; 3] {
    m.triangle_corners(t).unwrap()
}

fn has_area(m: &TriMesh, t: usize) -> bool {
    let [a, b, c] = corners(m, t);
    (b - a).cross(c - a).length() > 0.0
}

/// Möller–Trumbore ray/triangle intersection.
fn ray_triangle(o: DVec3, d: DVec3, [a, b, c]: [DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det == 0.0 {
        return None;
    }
    let tv = o - a;
    let u = tv.dot(pv) / det;
    let qv = tv.cross(e1);
    let v = d.dot(qv) / det;
    let t = e2.dot(qv) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t >= 0.0).then_some(t)
}

// ---- closed forms -------------------------------------------------------------------------

#[test]
fn cube_area_volume_box_and_closedness() {
    let mut m = cube();
    assert!((m.area() - 6.0).abs() < 1e-12);
    assert!((m.signed_volume() - 1.0).abs() < 1e-12);
    assert!(m.is_closed());
    assert!(m.boundary_edges().is_empty());
    let b = m.bbox();
    assert_eq!((b.min, b.max), (DVec3::ZERO, DVec3::ONE));
    m.flip();
    assert!((m.signed_volume() + 1.0).abs() < 1e-12, "inside out");
    assert!(m.is_closed());
    // Remove one triangle: its three edges become the boundary, run as that hole's rim.
    let removed = m.triangles.pop().unwrap();
    assert!(!m.is_closed());
    let mut rim = m.boundary_edges();
    rim.sort_unstable();
    let mut expected: Vec<[u32; 2]> = (0..3).map(|k| [removed[(k + 1) % 3], removed[k]]).collect();
    expected.sort_unstable();
    assert_eq!(rim, expected);
}

#[test]
fn inconsistent_orientation_is_not_closed() {
    let mut m = cube();
    m.triangles[0].swap(1, 2);
    assert!(!m.is_closed());
    assert!(m.boundary_edges().is_empty(), "every edge still used twice");
    assert_eq!(m.bad_edges().len(), 3);
}

#[test]
fn octahedron_volume_and_area() {
    let m = octahedron();
    assert!((m.signed_volume() - 4.0 / 3.0).abs() < 1e-12);
    assert!((m.area() - 4.0 * 3.0_f64.sqrt()).abs() < 1e-12);
    assert!(m.is_closed());
    // Volume does not depend on where the solid is.
    let mut far = m.clone();
    far.positions
        .iter_mut()
        .for_each(|p| *p += DVec3::new(1e5, -2e5, 3e5));
    assert!((far.signed_volume() - 4.0 / 3.0).abs() < 1e-8);
}

#[test]
fn icosphere_approaches_the_sphere_from_inside() {
    let m = icosphere(3);
    assert_eq!(m.triangles.len(), 1280);
    assert!(m.is_closed());
    let (v, a) = (m.signed_volume(), m.area());
    assert!(
        v < 4.0 / 3.0 * PI && v > 0.98 * 4.0 / 3.0 * PI,
        "volume {v}"
    );
    assert!(a < 4.0 * PI && a > 0.98 * 4.0 * PI, "area {a}");
}

#[test]
fn angle_weighted_normals() {
    // Cube corners: each face meets a corner at a right angle however it is split, so the
    // normal is the diagonal exactly (area weighting would tilt it towards faces split there).
    let mut m = cube();
    m.compute_normals();
    for (p, n) in m.positions.iter().zip(&m.normals) {
        let expected = (*p * 2.0 - DVec3::ONE).normalize();
        assert!(n.abs_diff_eq(expected, 1e-12), "{p} → {n}");
    }
    // Sphere: the radial direction, to within a fraction of a degree.
    let mut s = icosphere(3);
    s.compute_normals();
    for (p, n) in s.positions.iter().zip(&s.normals) {
        assert!(n.dot(*p) > (0.5_f64).to_radians().cos(), "{p} → {n}");
    }
    // A vertex used by no triangle gets a zero normal, not NaN.
    s.positions.push(DVec3::new(5.0, 5.0, 5.0));
    s.compute_normals();
    assert_eq!(*s.normals.last().unwrap(), DVec3::ZERO);
}

#[test]
fn weld_turns_a_soup_into_the_cube() {
    let mut s = soup(&cube());
    assert_eq!(s.positions.len(), 36);
    assert!(!s.is_closed());
    let merged = s.weld(1e-9);
    assert_eq!(merged, 28);
    assert_eq!(s.positions.len(), 8);
    assert!(s.is_closed());
    assert!((s.signed_volume() - 1.0).abs() < 1e-12);
    // Kept vertices keep their first-seen order: the first triangle's corners come first.
    let c = cube();
    let first = c.triangles[0].map(|i| c.positions[i as usize]);
    assert_eq!(&s.positions[..3], &first);

    // Noise below the tolerance still welds; the result does not depend on it.
    let mut rng = Rng(7);
    let mut noisy = soup(&cube());
    for p in &mut noisy.positions {
        *p += rng.point_in(DVec3::splat(-1e-7), DVec3::splat(1e-7));
    }
    let mut exact = noisy.clone();
    assert_eq!(noisy.weld(1e-6), 28);
    assert!(noisy.is_closed());
    assert_eq!(exact.weld(0.0), 0, "no bit-identical vertices");
}

#[test]
fn weld_drops_collapsed_triangles_and_merges_signed_zeros() {
    let p = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::new(1.0, 1e-9, 0.0),
        DVec3::Y,
        DVec3::new(-0.0, 1.0, 0.0),
    ];
    let mut m = TriMesh::new(p, vec![[0, 1, 2], [0, 1, 3], [0, 4, 1], [0, 1, 9]]);
    assert_eq!(m.degenerate_triangles(1e-6), vec![0, 3]);
    let merged = m.weld(1e-6);
    assert_eq!(merged, 2);
    // [0,1,2] collapsed (2 joined 1); [0,1,9] refers to a missing vertex.
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 1]]);
    let mut z = TriMesh::new(
        vec![DVec3::new(0.0, 1.0, 0.0), DVec3::new(-0.0, 1.0, -0.0)],
        vec![],
    );
    assert_eq!(z.weld(0.0), 1);
}

#[test]
fn degenerate_triangles_and_bad_indices_do_not_panic() {
    let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0), DVec3::Y];
    let m = TriMesh::new(p, vec![[0, 1, 3], [0, 1, 2], [0, 0, 3], [0, 1, 7]]);
    assert_eq!(m.degenerate_triangles(0.0), vec![1, 2, 3]);
    assert!(
        (m.area() - 0.5).abs() < 1e-15,
        "bad triangles count as zero"
    );
    assert!(m.validate().is_err());
    let mut n = m.clone();
    n.compute_normals();
    n.flip();
    let _ = (n.signed_volume(), n.is_closed(), n.boundary_edges());
}

#[test]
fn append_two_cubes() {
    let mut a = cube();
    let mut b = cube();
    b.positions.iter_mut().for_each(|p| *p += DVec3::splat(3.0));
    b.compute_normals();
    a.append(&b);
    assert_eq!(a.positions.len(), 16);
    assert!(a.is_closed());
    assert!((a.signed_volume() - 2.0).abs() < 1e-12);
    assert!(a.normals.is_empty(), "only one side had normals");
    let bb = a.bbox();
    assert_eq!((bb.min, bb.max), (DVec3::ZERO, DVec3::splat(4.0)));
    let mut c = TriMesh::default();
    c.append(&b);
    assert_eq!(c, b, "appending to an empty mesh copies, normals included");
}

// ---- BVH against brute force --------------------------------------------------------------

fn check_rays(m: &TriMesh, bvh: &MeshBvh, rays: &[(DVec3, DVec3)]) -> usize {
    let mut hits = 0;
    for (i, &(o, d)) in rays.iter().enumerate() {
        let brute = (0..m.triangles.len())
            .filter(|&t| has_area(m, t))
            .filter_map(|t| ray_triangle(o, d, corners(m, t)))
            .fold(None, |best: Option<f64>, t| {
                Some(best.map_or(t, |b| b.min(t)))
            });
        let got = bvh.ray_cast(o, d, f64::INFINITY);
        match (brute, got) {
            (None, None) => {}
            (Some(t), Some(h)) => {
                hits += 1;
                assert!(
                    (h.t - t).abs() <= 1e-9 * t.max(1.0),
                    "ray {i}: {} vs {t}",
                    h.t
                );
                assert!(h.point.distance(o + d * t) < 1e-8);
                let tri = corners(m, h.triangle);
                assert!(
                    common::geometry::closest_on_triangle(h.point, tri).distance(h.point) < 1e-8,
                    "ray {i}"
                );
                let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
                assert!(h.normal.abs_diff_eq(n, 1e-12));
                // A shorter ray stops before the hit.
                assert!(bvh.ray_cast(o, d, t * 0.999).is_none(), "ray {i}");
            }
            _ => panic!("ray {i} from {o} along {d}: brute {brute:?}, bvh {got:?}"),
        }
    }
    hits
}

fn check_closest(m: &TriMesh, bvh: &MeshBvh, points: &[DVec3]) {
    for (i, &p) in points.iter().enumerate() {
        let brute = (0..m.triangles.len())
            .filter(|&t| has_area(m, t))
            .map(|t| common::geometry::closest_on_triangle(p, corners(m, t)).distance(p))
            .fold(f64::INFINITY, f64::min);
        let h = bvh.closest_point(p).unwrap();
        assert!(
            (h.distance - brute).abs() <= 1e-9 * brute.max(1.0),
            "point {i}: {} vs {brute}",
            h.distance
        );
        assert!((h.point.distance(p) - h.distance).abs() < 1e-12);
        let on = common::geometry::closest_on_triangle(h.point, corners(m, h.triangle))
            .distance(h.point);
        assert!(on < 1e-9, "point {i} lies {on} off its triangle");
    }
}

fn check_boxes(m: &TriMesh, bvh: &MeshBvh, boxes: &[Aabb]) -> usize {
    let mut total = 0;
    for (i, b) in boxes.iter().enumerate() {
        let brute: Vec<usize> = (0..m.triangles.len())
            .filter(|&t| has_area(m, t))
            .filter(|&t| {
                let tb = Aabb::from_points(&corners(m, t));
                tb.min.cmple(b.max).all() && tb.max.cmpge(b.min).all()
            })
            .collect();
        assert_eq!(bvh.triangles_in_aabb(b), brute, "box {i}");
        total += brute.len();
    }
    total
}

fn random_box(rng: &mut Rng, lo: DVec3, hi: DVec3, max_size: f64) -> Aabb {
    let c = rng.point_in(lo, hi);
    let h = DVec3::new(
        rng.range(0.0, max_size),
        rng.range(0.0, max_size),
        rng.range(0.0, max_size),
    );
    Aabb {
        min: c - h,
        max: c + h,
    }
}

#[test]
fn bvh_matches_brute_force_on_bicubic_hills() {
    let m = common::hills_stl();
    let bvh = MeshBvh::new(&m).unwrap();
    assert_eq!(bvh.triangle_count(), m.triangles.len());
    let mut rng = Rng(0x5EED_1234);
    let (lo, hi) = (
        DVec3::new(-20.0, -20.0, -40.0),
        DVec3::new(180.0, 140.0, 40.0),
    );
    let mut rays: Vec<(DVec3, DVec3)> = (0..150)
        .map(|_| (rng.point_in(lo, hi), rng.direction()))
        .collect();
    // Drop-cutter-like rays straight down, and slanted ones with non-unit directions.
    for _ in 0..150 {
        let o = rng.point_in(DVec3::new(0.0, 0.0, 30.0), DVec3::new(160.0, 120.0, 30.0));
        rays.push((o, -DVec3::Z));
        rays.push((o, (rng.direction() - DVec3::new(0.0, 0.0, 2.0)) * 3.0));
    }
    let hits = check_rays(&m, &bvh, &rays);
    assert!(hits > 300, "most downward rays hit: {hits}");
    let points: Vec<DVec3> = (0..200).map(|_| rng.point_in(lo, hi)).collect();
    check_closest(&m, &bvh, &points);
    let boxes: Vec<Aabb> = (0..100)
        .map(|_| random_box(&mut rng, lo, hi, 15.0))
        .collect();
    assert!(check_boxes(&m, &bvh, &boxes) > 0);
}

#[test]
fn bvh_matches_brute_force_and_closed_forms_on_a_sphere() {
    let m = icosphere(3);
    let bvh = MeshBvh::new(&m).unwrap();
    let mut rng = Rng(42);
    let (lo, hi) = (DVec3::splat(-2.0), DVec3::splat(2.0));
    let rays: Vec<(DVec3, DVec3)> = (0..300)
        .map(|_| (rng.point_in(lo, hi), rng.direction()))
        .collect();
    check_rays(&m, &bvh, &rays);
    let points: Vec<DVec3> = (0..300).map(|_| rng.point_in(lo, hi)).collect();
    check_closest(&m, &bvh, &points);
    let boxes: Vec<Aabb> = (0..100)
        .map(|_| random_box(&mut rng, lo, hi, 0.5))
        .collect();
    check_boxes(&m, &bvh, &boxes);
    // From the centre every ray leaves through the inscribed polyhedron: 0.98 < t ≤ 1, and the
    // closest point lies between the polyhedron's inradius and 1.
    for _ in 0..100 {
        let d = rng.direction();
        let h = bvh.ray_cast(DVec3::ZERO, d, 10.0).unwrap();
        assert!(h.t > 0.98 && h.t <= 1.0 + 1e-12, "{}", h.t);
        assert!(h.normal.dot(d) > 0.99, "outward normal");
    }
    let c = bvh.closest_point(DVec3::ZERO).unwrap();
    assert!(c.distance > 0.98 && c.distance < 1.0);
    let far = bvh.closest_point(DVec3::new(0.0, 0.0, 10.0)).unwrap();
    assert!(
        (far.distance - 9.0).abs() < 1e-12,
        "the pole is a vertex: {}",
        far.distance
    );
}

#[test]
fn bvh_rejects_bad_meshes_and_queries() {
    assert_eq!(
        MeshBvh::new(&TriMesh::default()).unwrap_err(),
        BvhError::NoTriangles { triangles: 0 }
    );
    let flat = TriMesh::new(
        vec![DVec3::ZERO, DVec3::X, DVec3::X * 2.0],
        vec![[0, 1, 2], [0, 1, 5]],
    );
    assert_eq!(
        MeshBvh::new(&flat).unwrap_err(),
        BvhError::NoTriangles { triangles: 2 }
    );
    let mut nan = cube();
    nan.positions[3].y = f64::NAN;
    assert_eq!(
        MeshBvh::new(&nan).unwrap_err(),
        BvhError::NonFinite { vertex: 3 }
    );
    // Degenerate and out-of-range triangles are left out; indices still refer to the source.
    let mut c = cube();
    c.triangles.insert(0, [0, 0, 1]);
    c.triangles.insert(0, [0, 1, 99]);
    let bvh = MeshBvh::new(&c).unwrap();
    assert_eq!(bvh.triangle_count(), 12);
    let h = bvh
        .ray_cast(DVec3::new(0.25, 0.5, 5.0), -DVec3::Z, f64::INFINITY)
        .unwrap();
    assert!((h.t - 4.0).abs() < 1e-12 && h.triangle >= 2);
    assert_eq!(h.normal, DVec3::Z);
    assert!(bvh.ray_cast(DVec3::ZERO, DVec3::ZERO, 1.0).is_none());
    assert!(
        bvh.ray_cast(DVec3::splat(f64::NAN), DVec3::Z, 1.0)
            .is_none()
    );
    assert!(
        bvh.ray_cast(DVec3::new(0.5, 0.5, 5.0), -DVec3::Z, f64::NAN)
            .is_none()
    );
    assert!(bvh.closest_point(DVec3::splat(f64::INFINITY)).is_none());
    assert!(bvh.triangles_in_aabb(&Aabb::EMPTY).is_empty());
    let b = bvh.bbox();
    assert_eq!((b.min, b.max), (DVec3::ZERO, DVec3::ONE));
}
