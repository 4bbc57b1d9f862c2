//! Differential geometry: principal curvatures of the analytic surfaces against closed forms,
//! exact NURBS cylinder/sphere against ±1/r, fundamental-form identities on a skewed B-spline
//! patch, Euler's theorem for normal curvature, degenerate points.

mod common;

use std::f64::consts::{FRAC_PI_2, PI};

use common::geometry::*;
use talas::geometry::DVec3;
use talas::geometry::diffgeom::SurfaceDerivs;
use talas::geometry::frame::Frame;
use talas::geometry::nurbs::BSplineSurface;
use talas::geometry::surface::{Cylinder, Plane, Sphere, SurfaceGeom, Torus};

fn frame() -> Frame {
    Frame::from_axis_ref(
        DVec3::new(4.0, 1.0, -2.0),
        DVec3::new(-0.2, 0.5, 1.0),
        Some(DVec3::new(0.0, 1.0, 0.3)),
    )
    .unwrap()
}

fn near(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1e-3)
}

#[test]
fn sphere_cylinder_plane_closed_forms() {
    let f = frame();
    let sphere = SurfaceGeom::Sphere(Sphere {
        frame: f,
        radius: 9.0,
    });
    for (u, v) in [(0.0, 0.0), (1.0, 0.7), (4.0, -1.2), (2.0, 1.5)] {
        let d = sphere.derivs(u, v);
        let pr = d.principal().unwrap();
        assert!(
            near(pr.k_min, -1.0 / 9.0, 1e-12) && near(pr.k_max, -1.0 / 9.0, 1e-12),
            "sphere {pr:?}"
        );
        // Umbilic: directions still unit, orthogonal and tangent.
        let n = d.normal().unwrap();
        assert!(
            (pr.dir_min.length() - 1.0).abs() < 1e-12 && pr.dir_min.dot(pr.dir_max).abs() < 1e-12
        );
        assert!(pr.dir_min.dot(n).abs() < 1e-12 && pr.dir_max.dot(n).abs() < 1e-12);
        // Outward normal.
        assert!(n.dot(d.p - f.origin) > 0.0);
        let (h, k) = d.mean_gaussian().unwrap();
        assert!(near(h, -1.0 / 9.0, 1e-12) && near(k, 1.0 / 81.0, 1e-12));
    }
    // Poles: degenerate parameterisation, no normal, no NaN.
    let pole = sphere.derivs(0.3, FRAC_PI_2);
    assert!(
        pole.normal().is_none()
            && pole.principal().is_none()
            && pole.normal_curvature(1.0, 0.0).is_none()
    );

    let cyl = SurfaceGeom::Cylinder(Cylinder {
        frame: f,
        radius: 6.0,
    });
    for (u, v) in [(0.0, 0.0), (2.5, -3.0)] {
        let d = cyl.derivs(u, v);
        let pr = d.principal().unwrap();
        assert!(
            near(pr.k_min, -1.0 / 6.0, 1e-12) && pr.k_max.abs() < 1e-14,
            "cylinder {pr:?}"
        );
        assert!(
            pr.dir_max.dot(f.z).abs() > 1.0 - 1e-12,
            "k_max along the axis"
        );
        assert!(
            pr.dir_min.dot(d.su.normalize()).abs() > 1.0 - 1e-12,
            "k_min around"
        );
    }
    let plane = SurfaceGeom::Plane(Plane { frame: f });
    let d = plane.derivs(3.0, -1.0);
    let pr = d.principal().unwrap();
    assert!(pr.k_min == 0.0 && pr.k_max == 0.0 && pr.dir_min.dot(pr.dir_max).abs() < 1e-15);
    assert_vec_near(d.normal().unwrap(), f.z, 1e-15, "plane normal");
}

#[test]
fn torus_equators() {
    let f = frame();
    let (big, r) = (20.0, 5.0);
    let t = SurfaceGeom::Torus(Torus {
        frame: f,
        major_radius: big,
        minor_radius: r,
    });
    for u in [0.0, 1.3, 5.0] {
        let outer = t.derivs(u, 0.0);
        let pr = outer.principal().unwrap();
        assert!(
            near(pr.k_min, -1.0 / r, 1e-12) && near(pr.k_max, -1.0 / (big + r), 1e-12),
            "outer {pr:?}"
        );
        assert!(
            pr.dir_min.dot(outer.sv.normalize()).abs() > 1.0 - 1e-12,
            "tube direction"
        );
        let inner = t.derivs(u, PI);
        let pr = inner.principal().unwrap();
        assert!(
            near(pr.k_min, -1.0 / r, 1e-12) && near(pr.k_max, 1.0 / (big - r), 1e-12),
            "inner {pr:?}"
        );
        // General v: k = −1/r and −cos v / (R + r cos v).
        for v in [0.6, 2.0, 4.0] {
            let pr = t.derivs(u, v).principal().unwrap();
            let k2 = -f64::cos(v) / (big + r * f64::cos(v));
            let (lo, hi) = if k2 < -1.0 / r {
                (k2, -1.0 / r)
            } else {
                (-1.0 / r, k2)
            };
            assert!(
                near(pr.k_min, lo, 1e-11) && near(pr.k_max, hi, 1e-11),
                "torus v = {v}"
            );
        }
    }
}

#[test]
fn nurbs_cylinder_and_sphere_curvatures() {
    let c = DVec3::new(1.0, 2.0, 3.0);
    let cyl = nurbs_cylinder(c, 6.0, 10.0);
    let sph = nurbs_sphere(c, 9.0);
    for i in 0..20 {
        for j in 1..10 {
            let (u, v) = (i as f64 / 20.0 + 0.013, j as f64 / 10.0);
            let pr = cyl.derivs(u, v).principal().unwrap();
            assert!(
                near(pr.k_min, -1.0 / 6.0, 1e-9) && pr.k_max.abs() < 1e-9,
                "NURBS cylinder {pr:?}"
            );
            let pr = sph.derivs(u, v).principal().unwrap();
            assert!(
                near(pr.k_min, -1.0 / 9.0, 1e-9) && near(pr.k_max, -1.0 / 9.0, 1e-9),
                "NURBS sphere {pr:?}"
            );
        }
    }
    // Reversing u flips the normal: curvatures become +1/r.
    let mut flipped = sph.clone();
    let (nu, nv) = (flipped.n_u, flipped.n_v);
    let mut poles = Vec::new();
    let mut weights = Vec::new();
    let w = flipped.weights.clone().unwrap();
    for i in (0..nu).rev() {
        for j in 0..nv {
            poles.push(flipped.poles[i * nv + j]);
            weights.push(w[i * nv + j]);
        }
    }
    flipped.poles = poles;
    flipped.weights = Some(weights);
    flipped.validate().unwrap();
    let d = flipped.derivs(0.3, 0.4);
    assert!(d.normal().unwrap().dot(d.p - c) < 0.0, "inward normal");
    let pr = d.principal().unwrap();
    assert!(near(pr.k_min, 1.0 / 9.0, 1e-9) && near(pr.k_max, 1.0 / 9.0, 1e-9));
}

/// Mean and Gaussian curvature from the textbook fundamental-form formulas.
fn textbook(d: &SurfaceDerivs) -> (f64, f64) {
    let n = d.su.cross(d.sv).normalize();
    let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
    let (l, m, nn) = (d.suu.dot(n), d.suv.dot(n), d.svv.dot(n));
    let den = e * g - f * f;
    (
        (e * nn + g * l - 2.0 * f * m) / (2.0 * den),
        (l * nn - m * m) / den,
    )
}

#[test]
fn skewed_bspline_matches_fundamental_forms_and_euler() {
    let s: BSplineSurface = hills(true);
    for (u, v) in [
        (0.3, 0.1),
        (1.2, 1.0),
        (2.5, 3.1),
        (1.85, -0.4),
        (0.05, 3.9),
    ] {
        let d = s.derivs(u, v);
        let (h, k) = textbook(&d);
        let (hm, km) = d.mean_gaussian().unwrap();
        let pr = d.principal().unwrap();
        let scale = pr.k_min.abs().max(pr.k_max.abs());
        assert!(
            (hm - h).abs() <= 1e-10 * scale && (km - k).abs() <= 1e-10 * scale * scale,
            "H, K at ({u}, {v})"
        );
        assert!(pr.k_min <= pr.k_max);
        // Principal directions: normal curvature along them equals the principal curvatures.
        assert!((d.normal_curvature_along(pr.dir_min).unwrap() - pr.k_min).abs() <= 1e-10 * scale);
        assert!((d.normal_curvature_along(pr.dir_max).unwrap() - pr.k_max).abs() <= 1e-10 * scale);
        // Euler: k(θ) = k_min cos²θ + k_max sin²θ for any tangent direction (with a normal
        // component added, which must be projected away).
        let n = d.normal().unwrap();
        for th in [0.2, 0.9, 2.0] {
            let t = pr.dir_min * f64::cos(th) + pr.dir_max * f64::sin(th) + n * 0.7;
            let euler = pr.k_min * f64::cos(th).powi(2) + pr.k_max * f64::sin(th).powi(2);
            assert!((d.normal_curvature_along(t).unwrap() - euler).abs() <= 1e-10 * scale);
        }
        // Parametric directions: k along S_u is L/E.
        let (e, _, _) = d.first_form();
        let (l, _, _) = d.second_form(n);
        assert!((d.normal_curvature(1.0, 0.0).unwrap() - l / e).abs() <= 1e-12 * scale);
        assert!(d.normal_curvature(0.0, 0.0).is_none());
        assert!(d.normal_curvature_along(n).is_none());
    }
}
