//! Drop-cutter against closed forms (planes, a sphere, a single vertex, a single edge) and against
//! a brute-force lift of the densely sampled cutter surface on `bicubic-hills.stl`.

mod common;

use std::f64::consts::PI;

use glam::{DVec2, DVec3};
use talas::geometry::bvh::MeshBvh;
use talas::geometry::mesh::TriMesh;
use talas::tools::dropcutter::{Contact, drop_cutter, drop_cutter_at};
use talas::tools::{Cutter, CutterKind};

fn cutters() -> Vec<Cutter> {
    vec![
        Cutter::new(CutterKind::Ball, 6.0).unwrap(),
        Cutter::new(CutterKind::Flat, 10.0).unwrap(),
        Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0).unwrap(),
        Cutter::new(
            CutterKind::Cone {
                half_angle: 45f64.to_radians(),
            },
            10.0,
        )
        .unwrap(),
    ]
}

/// A plane z = tan θ · x over [−50, 50]², as two triangles.
fn tilted_plane(theta: f64, z0: f64) -> TriMesh {
    let z = |x: f64| z0 + theta.tan() * x;
    TriMesh::new(
        vec![
            DVec3::new(-50.0, -50.0, z(-50.0)),
            DVec3::new(50.0, -50.0, z(50.0)),
            DVec3::new(50.0, 50.0, z(50.0)),
            DVec3::new(-50.0, 50.0, z(-50.0)),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

fn drop(mesh: &TriMesh, c: &Cutter, p: DVec2) -> talas::tools::dropcutter::ClPoint {
    let bvh = MeshBvh::new(mesh).unwrap();
    drop_cutter_at(&bvh, mesh, c, p).expect("the cutter meets the mesh")
}

#[test]
fn horizontal_plane_every_cutter_rests_on_its_tip() {
    let mesh = tilted_plane(0.0, 1.25);
    for c in cutters() {
        for p in [DVec2::new(0.3, -7.0), DVec2::new(12.0, 4.5)] {
            let cl = drop(&mesh, &c, p);
            assert!((cl.z - 1.25).abs() < 1e-12, "{:?}: {}", c.kind, cl.z);
        }
    }
}

#[test]
fn tilted_plane_closed_forms() {
    let theta = 20f64.to_radians();
    let mesh = tilted_plane(theta, 0.0);
    let t = theta.tan();
    let x = 3.7;
    let p = DVec2::new(x, 1.1);
    // Ball: R(1/cos θ − 1) above the plane under the axis.
    let ball = Cutter::new(CutterKind::Ball, 6.0).unwrap();
    let want = x * t + 3.0 * (1.0 / theta.cos() - 1.0);
    let cl = drop(&mesh, &ball, p);
    assert!((cl.z - want).abs() < 1e-12, "ball {} vs {want}", cl.z);
    assert_eq!(cl.contact, Contact::Facet);
    // CC = centre − R n.
    let n = DVec3::new(-theta.sin(), 0.0, theta.cos());
    let centre = DVec3::new(x, 1.1, want + 3.0);
    assert!((cl.cc - (centre - 3.0 * n)).length() < 1e-12);
    // Flat: the rim on the uphill side.
    let flat = Cutter::new(CutterKind::Flat, 10.0).unwrap();
    let cl = drop(&mesh, &flat, p);
    assert!((cl.z - (x + 5.0) * t).abs() < 1e-12, "flat {}", cl.z);
    // Bull-nose: a·tan θ + r(1/cos θ − 1).
    let bull = Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0).unwrap();
    let cl = drop(&mesh, &bull, p);
    let want = x * t + 3.0 * t + 2.0 * (1.0 / theta.cos() - 1.0);
    assert!((cl.z - want).abs() < 1e-12, "bull {} vs {want}", cl.z);
    // Cone 45°: the plane is shallower than the flank, so the apex touches.
    let cone = Cutter::new(
        CutterKind::Cone {
            half_angle: 45f64.to_radians(),
        },
        10.0,
    )
    .unwrap();
    let cl = drop(&mesh, &cone, p);
    assert!((cl.z - x * t).abs() < 1e-12, "cone {}", cl.z);
    // Cone 80°: the flank is at 10° to the horizontal, the plane at 20°: the rim touches.
    let alpha = 80f64.to_radians();
    let wide = Cutter::new(CutterKind::Cone { half_angle: alpha }, 10.0).unwrap();
    let cl = drop(&mesh, &wide, p);
    let want = (x + 5.0) * t - 5.0 / alpha.tan();
    assert!((cl.z - want).abs() < 1e-12, "wide cone {} vs {want}", cl.z);
}

/// The upper half of a UV sphere of radius `rs` centred at the origin (vertices on the sphere).
fn hemisphere(rs: f64, nu: usize, nv: usize) -> TriMesh {
    let mut pos = Vec::new();
    for j in 0..=nv {
        let phi = 0.5 * PI * j as f64 / nv as f64; // from the pole down to the equator
        for i in 0..nu {
            let th = 2.0 * PI * i as f64 / nu as f64;
            pos.push(rs * DVec3::new(phi.sin() * th.cos(), phi.sin() * th.sin(), phi.cos()));
        }
    }
    let mut tris = Vec::new();
    let id = |i: usize, j: usize| (j * nu + i % nu) as u32;
    for j in 0..nv {
        for i in 0..nu {
            tris.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    TriMesh::new(pos, tris)
}

#[test]
fn ball_on_sphere_matches_the_offset_sphere() {
    let (rs, r) = (20.0, 3.0);
    let (nu, nv) = (256, 64);
    let mesh = hemisphere(rs, nu, nv);
    let bvh = MeshBvh::new(&mesh).unwrap();
    let ball = Cutter::new(CutterKind::Ball, 2.0 * r).unwrap();
    // The mesh is inscribed: its distance from the sphere is at most the sagitta of the longest
    // chord (a diagonal of a cell at the equator).
    let dth = 2.0 * PI / nu as f64;
    let dphi = 0.5 * PI / nv as f64;
    let chord = rs * (dth * dth + dphi * dphi).sqrt();
    let sagitta = rs - (rs * rs - chord * chord / 4.0).sqrt();
    let pts: Vec<DVec2> = (0..40)
        .map(|k| {
            let a = k as f64 * 0.7;
            let rad = 15.0 * (k as f64 / 40.0);
            DVec2::new(rad * a.cos(), rad * a.sin())
        })
        .collect();
    let cls = drop_cutter(&bvh, &mesh, &ball, &pts);
    let mut worst = 0.0_f64;
    for (p, cl) in pts.iter().zip(&cls) {
        let cl = cl.expect("on the sphere");
        let want = ((rs + r).powi(2) - p.length_squared()).sqrt() - r;
        let below = want - cl.z;
        worst = worst.max(below.abs());
        assert!(
            (-1e-9..=sagitta).contains(&below),
            "at {p}: {} vs {want} (sagitta {sagitta})",
            cl.z
        );
    }
    assert!(worst < sagitta, "worst {worst}");
}

/// A steep pyramid with its apex at (0, 0, 5).
fn spike() -> TriMesh {
    let pos = vec![
        DVec3::new(0.0, 0.0, 5.0),
        DVec3::new(-10.0, -10.0, -50.0),
        DVec3::new(10.0, -10.0, -50.0),
        DVec3::new(10.0, 10.0, -50.0),
        DVec3::new(-10.0, 10.0, -50.0),
    ];
    TriMesh::new(pos, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]])
}

#[test]
fn single_vertex_contact() {
    let mesh = spike();
    for c in cutters() {
        for q in [0.0, 0.5, 1.0, 1.7] {
            let p = DVec2::new(q * 0.6, q * 0.8);
            let cl = drop(&mesh, &c, p);
            let want = 5.0 - c.height_at_radius(q).unwrap();
            assert!((cl.z - want).abs() < 1e-12, "{:?} q {q}: {}", c.kind, cl.z);
            assert_eq!(cl.contact, Contact::Vertex, "{:?} q {q}", c.kind);
            assert!((cl.cc - DVec3::new(0.0, 0.0, 5.0)).length() < 1e-12);
        }
    }
}

/// A steep roof whose ridge runs from (−20, 0, −20m) to (20, 0, 20m).
fn roof(m: f64) -> TriMesh {
    let pos = vec![
        DVec3::new(-20.0, 0.0, -20.0 * m),
        DVec3::new(20.0, 0.0, 20.0 * m),
        DVec3::new(-20.0, 20.0, -20.0 * m - 200.0),
        DVec3::new(20.0, 20.0, 20.0 * m - 200.0),
        DVec3::new(-20.0, -20.0, -20.0 * m - 200.0),
        DVec3::new(20.0, -20.0, 20.0 * m - 200.0),
    ];
    TriMesh::new(pos, vec![[0, 1, 3], [0, 3, 2], [0, 5, 1], [0, 4, 5]])
}

/// max over the cutter's section at distance d of (m·t − f(t)), by dense sampling of t.
fn section_max(c: &Cutter, d: f64, m: f64) -> f64 {
    let s = (c.radius().powi(2) - d * d).sqrt();
    let n = 2_000_000;
    (0..=n)
        .map(|i| {
            let t = -s + 2.0 * s * i as f64 / n as f64;
            let rho = (d * d + t * t).sqrt().min(c.radius());
            m * t - c.height_at_radius(rho).unwrap()
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn single_edge_contact_matches_a_dense_section() {
    for m in [0.0, 0.1, -0.35, 0.8] {
        let mesh = roof(m);
        for c in cutters() {
            for d in [0.0, 0.9, 2.2, 3.9] {
                if d >= c.radius() {
                    continue;
                }
                let cl = drop(&mesh, &c, DVec2::new(1.3, d));
                let want = 1.3 * m + section_max(&c, d, m);
                // Dense sampling resolves the maximum to about (slope · step)²; 1e-7 is ample.
                assert!(
                    (cl.z - want).abs() < 1e-7,
                    "{:?} m {m} d {d}: {} vs {want}",
                    c.kind,
                    cl.z
                );
                // (With d = 0 the cone's apex sits on the ridge, which is also the facets' border.)
                if d > 0.0 {
                    assert_ne!(cl.contact, Contact::Facet, "{:?} m {m} d {d}", c.kind);
                }
            }
        }
        // Ball closed form: s·√(1 + m²) − R.
        let ball = Cutter::new(CutterKind::Ball, 6.0).unwrap();
        let d: f64 = 1.5;
        let s = (9.0 - d * d).sqrt();
        let cl = drop(&mesh, &ball, DVec2::new(0.0, d));
        assert!((cl.z - (s * (1.0 + m * m).sqrt() - 3.0)).abs() < 1e-12);
        assert_eq!(cl.contact, Contact::Edge);
    }
}

/// Brute force: the lowest tip such that no sample of the cutter's lower surface lies under the
/// mesh's top surface (found by a downward ray cast).
fn brute_force(bvh: &MeshBvh, c: &Cutter, p: DVec2, top_z: f64) -> Option<f64> {
    let (nr, na) = (120, 720);
    let mut best: Option<f64> = None;
    for i in 0..=nr {
        let rho = c.radius() * i as f64 / nr as f64;
        let h = c.height_at_radius(rho).unwrap();
        let na_here = if i == 0 { 1 } else { na };
        for j in 0..na_here {
            let a = 2.0 * PI * j as f64 / na as f64;
            let q = p + rho * DVec2::new(a.cos(), a.sin());
            if let Some(hit) = bvh.ray_cast(q.extend(top_z + 1.0), DVec3::NEG_Z, f64::INFINITY) {
                let z = hit.point.z - h;
                best = Some(best.map_or(z, |b: f64| b.max(z)));
            }
        }
    }
    best
}

#[test]
fn bicubic_hills_matches_brute_force() {
    let mesh = common::hills_stl();
    let bvh = MeshBvh::new(&mesh).unwrap();
    let bb = bvh.bbox();
    // A fixed-seed LCG for reproducible points inside the part, away from the border.
    let mut rng = common::Lcg(0x2545_f491_4f6c_dd1d);
    let mut next = || rng.next();
    let pts: Vec<DVec2> = (0..12)
        .map(|_| {
            let x = bb.min.x + 6.0 + (bb.max.x - bb.min.x - 12.0) * next();
            let y = bb.min.y + 6.0 + (bb.max.y - bb.min.y - 12.0) * next();
            DVec2::new(x, y)
        })
        .collect();
    for c in cutters() {
        let cls = drop_cutter(&bvh, &mesh, &c, &pts);
        // Sampling resolution: radial step R/120 and arc step 2πR/720 at the rim (≤ 0.044 mm).
        // At a smooth (facet or edge) contact the lift error is second order in that step; the
        // measured gaps are ≤ 2e-5 mm (ball, flat, cone) and 1.1e-4 mm (bull-nose).
        let tol = 2e-3;
        for (p, cl) in pts.iter().zip(&cls) {
            let cl = cl.expect("inside the part");
            let bf = brute_force(&bvh, &c, *p, bb.max.z).unwrap();
            assert!(
                bf <= cl.z + 1e-9,
                "{:?} at {p}: brute {bf} above exact {}",
                c.kind,
                cl.z
            );
            assert!(
                cl.z - bf <= tol,
                "{:?} at {p}: exact {} brute {bf}",
                c.kind,
                cl.z
            );
        }
    }
}

#[test]
fn progress_reaches_one_and_cancel_stops() {
    use talas::diagnostics::Progress;
    use talas::tools::dropcutter::drop_cutter_progress;
    let mesh = tilted_plane(0.1, 0.0);
    let bvh = MeshBvh::new(&mesh).unwrap();
    let ball = Cutter::new(CutterKind::Ball, 6.0).unwrap();
    let pts: Vec<DVec2> = (0..10_000)
        .map(|i| DVec2::new(f64::from(i % 100) - 50.0, 0.0))
        .collect();
    let progress = Progress::new();
    let cls = drop_cutter_progress(&bvh, &mesh, &ball, &pts, &progress).unwrap();
    assert_eq!(cls.len(), pts.len());
    assert!((progress.fraction() - 1.0).abs() < 1e-12);
    // Same answers, same order as the plain call.
    assert_eq!(cls, drop_cutter(&bvh, &mesh, &ball, &pts));
    let cancelled = Progress::new();
    cancelled.cancel();
    assert!(drop_cutter_progress(&bvh, &mesh, &ball, &pts, &cancelled).is_err());
}
