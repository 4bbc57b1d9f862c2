//! Analytic surfaces and curves: derivatives against central differences, revolution and
//! extrusion against the analytic kinds they reproduce, point inversion against closed forms
//! and dense brute-force sampling (far points, boundaries, axis points; never NaN).

mod common;

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use common::geometry::*;
use talas::geometry::curve::{Circle, CurveGeom, Ellipse, Line};
use talas::geometry::frame::Frame;
use talas::geometry::surface::{
    Cone, Cylinder, Extrusion, ParamRect, Plane, Revolution, Sphere, SurfaceGeom, Torus,
};
use talas::geometry::{DVec2, DVec3, Interval};

fn frame() -> Frame {
    Frame::from_axis_ref(
        DVec3::new(1.0, -2.0, 3.0),
        DVec3::new(0.3, -0.4, 1.0),
        Some(DVec3::new(1.0, 0.2, 0.0)),
    )
    .unwrap()
}

fn meridian() -> CurveGeom {
    let poles = vec![
        DVec3::new(5.0, 0.0, -4.0),
        DVec3::new(9.0, 0.0, -1.0),
        DVec3::new(4.0, 0.0, 2.0),
        DVec3::new(7.0, 0.0, 6.0),
        DVec3::new(3.0, 0.0, 9.0),
    ];
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
    CurveGeom::BSpline(
        talas::geometry::nurbs::BSplineCurve::new(
            3,
            knots,
            poles,
            Some(vec![1.0, 0.6, 1.8, 0.9, 1.0]),
        )
        .unwrap(),
    )
}

fn all_kinds() -> Vec<SurfaceGeom> {
    let f = frame();
    vec![
        SurfaceGeom::Plane(Plane { frame: f }),
        SurfaceGeom::Cylinder(Cylinder {
            frame: f,
            radius: 6.0,
        }),
        SurfaceGeom::Cone(Cone {
            frame: f,
            radius: 4.0,
            semi_angle: 0.35,
        }),
        SurfaceGeom::Sphere(Sphere {
            frame: f,
            radius: 9.0,
        }),
        SurfaceGeom::Torus(Torus {
            frame: f,
            major_radius: 20.0,
            minor_radius: 5.0,
        }),
        SurfaceGeom::Revolution(Revolution {
            meridian: Box::new(meridian()),
            axis_origin: DVec3::new(0.5, 0.5, 0.0),
            axis_dir: DVec3::new(0.0, 0.6, 0.8),
        }),
        SurfaceGeom::Extrusion(Extrusion {
            profile: Box::new(meridian()),
            dir: DVec3::new(0.0, 0.6, 0.8),
        }),
        SurfaceGeom::BSpline(hills(true)),
    ]
}

#[test]
fn every_kind_matches_finite_differences() {
    for s in all_kinds() {
        let d = s.domain();
        let pick =
            |i: Interval, a: f64, fallback: f64| if i.is_finite() { i.lerp(a) } else { fallback };
        for (a, b) in [(0.13, 0.31), (0.52, 0.47), (0.91, 0.77)] {
            let (u, v) = (pick(d.u, a, 3.0 * a - 1.0), pick(d.v, b, 5.0 * b - 2.0));
            check_surface_fd(&surf_fn(&s), u, v, 1e-5, 2e-7);
        }
    }
}

#[test]
fn analytic_points_follow_occt_parameterisations() {
    let f = frame();
    let (u, v) = (0.7_f64, -0.4_f64);
    let e = f.x * u.cos() + f.y * u.sin();
    let cone = SurfaceGeom::Cone(Cone {
        frame: f,
        radius: 4.0,
        semi_angle: 0.35,
    });
    let expect = f.origin + e * (4.0 + v * 0.35_f64.sin()) + f.z * (v * 0.35_f64.cos());
    assert_vec_near(cone.point(u, v), expect, 1e-15, "cone");
    let sphere = SurfaceGeom::Sphere(Sphere {
        frame: f,
        radius: 9.0,
    });
    assert_vec_near(
        sphere.point(u, v),
        f.origin + e * (9.0 * v.cos()) + f.z * (9.0 * v.sin()),
        1e-15,
        "sphere",
    );
    assert_vec_near(
        sphere.point(1.0, FRAC_PI_2),
        f.origin + f.z * 9.0,
        1e-14,
        "sphere north pole",
    );
    let torus = SurfaceGeom::Torus(Torus {
        frame: f,
        major_radius: 20.0,
        minor_radius: 5.0,
    });
    assert_vec_near(
        torus.point(u, v),
        f.origin + e * (20.0 + 5.0 * v.cos()) + f.z * (5.0 * v.sin()),
        1e-15,
        "torus",
    );
    assert_eq!(sphere.domain().v, Interval::new(-FRAC_PI_2, FRAC_PI_2));
    assert_eq!(torus.periods(), (Some(TAU), Some(TAU)));
    assert_eq!(cone.periods(), (Some(TAU), None));
    assert!(!cone.domain().v.is_finite());
}

#[test]
fn revolution_of_circle_is_torus_and_extrusion_of_circle_is_cylinder() {
    let f = frame();
    // Meridian: circle of radius 5 centred 20 along x, in the (x, z) plane.
    let mframe = Frame {
        origin: f.origin + f.x * 20.0,
        x: f.x,
        y: f.z,
        z: -f.y,
    };
    let rev = SurfaceGeom::Revolution(Revolution {
        meridian: Box::new(CurveGeom::Circle(Circle {
            frame: mframe,
            radius: 5.0,
        })),
        axis_origin: f.origin,
        axis_dir: f.z,
    });
    let torus = SurfaceGeom::Torus(Torus {
        frame: f,
        major_radius: 20.0,
        minor_radius: 5.0,
    });
    let ext = SurfaceGeom::Extrusion(Extrusion {
        profile: Box::new(CurveGeom::Circle(Circle {
            frame: f,
            radius: 6.0,
        })),
        dir: f.z,
    });
    let cyl = SurfaceGeom::Cylinder(Cylinder {
        frame: f,
        radius: 6.0,
    });
    for (u, v) in [(0.0, 0.0), (0.4, 2.0), (3.0, -1.2), (5.9, 4.4)] {
        let (a, b) = (rev.derivs(u, v), torus.derivs(u, v));
        for (x, y) in [
            (a.p, b.p),
            (a.su, b.su),
            (a.sv, b.sv),
            (a.suu, b.suu),
            (a.suv, b.suv),
            (a.svv, b.svv),
        ] {
            assert_vec_near(x, y, 1e-13, "revolution vs torus");
        }
        let (a, b) = (ext.derivs(u, v), cyl.derivs(u, v));
        for (x, y) in [
            (a.p, b.p),
            (a.su, b.su),
            (a.sv, b.sv),
            (a.suu, b.suu),
            (a.suv, b.suv),
            (a.svv, b.svv),
        ] {
            assert_vec_near(x, y, 1e-13, "extrusion vs cylinder");
        }
    }
}

#[test]
fn nurbs_cylinder_and_sphere_lie_on_the_analytic_surfaces() {
    let c0 = DVec3::new(2.0, 1.0, -3.0);
    let cyl = nurbs_cylinder(c0, 6.0, 10.0);
    let sph = nurbs_sphere(c0, 9.0);
    let acyl = SurfaceGeom::Cylinder(Cylinder {
        frame: Frame {
            origin: c0,
            ..Frame::WORLD
        },
        radius: 6.0,
    });
    let asph = SurfaceGeom::Sphere(Sphere {
        frame: Frame {
            origin: c0,
            ..Frame::WORLD
        },
        radius: 9.0,
    });
    for i in 0..=40 {
        for j in 0..=10 {
            let (u, v) = (i as f64 / 40.0, j as f64 / 10.0);
            let p = cyl.point(u, v);
            assert!(((p - c0).truncate().length() - 6.0).abs() <= 1e-12 * 6.0);
            let q = sph.point(u, v);
            assert!(
                ((q - c0).length() - 9.0).abs() <= 1e-12 * 9.0,
                "sphere radius at ({u}, {v})"
            );
            // The analytic surfaces' inversion finds them at distance ~0.
            let full = acyl.domain();
            assert!(acyl.closest_point(p, full, None).distance <= 1e-10);
            assert!(asph.closest_point(q, asph.domain(), None).distance <= 1e-10);
        }
    }
}

fn brute_force(s: &SurfaceGeom, p: DVec3, rect: ParamRect, n: usize) -> f64 {
    let mut best = f64::INFINITY;
    for i in 0..=n {
        for j in 0..=n {
            let q = s.point(
                rect.u.lerp(i as f64 / n as f64),
                rect.v.lerp(j as f64 / n as f64),
            );
            best = best.min(q.distance(p));
        }
    }
    best
}

fn check_result(
    s: &SurfaceGeom,
    p: DVec3,
    rect: ParamRect,
    r: &talas::geometry::surface::SurfacePoint,
) {
    assert!(
        r.uv.is_finite() && r.point.is_finite() && r.distance.is_finite(),
        "finite result for {p}"
    );
    assert_vec_near(s.point(r.uv.x, r.uv.y), r.point, 1e-12, "point = S(uv)");
    assert!((r.point.distance(p) - r.distance).abs() <= 1e-9 * r.distance.max(1.0));
    let (u, v) = (r.uv.x, r.uv.y);
    assert!(
        u >= rect.u.t0 - 1e-12
            && u <= rect.u.t1 + 1e-12
            && v >= rect.v.t0 - 1e-12
            && v <= rect.v.t1 + 1e-12,
        "uv in rect"
    );
}

#[test]
fn sphere_inversion_matches_closed_form() {
    let f = frame();
    let s = SurfaceGeom::Sphere(Sphere {
        frame: f,
        radius: 9.0,
    });
    let dom = s.domain();
    let mut rng = Lcg(7);
    let mut pts: Vec<DVec3> = (0..300)
        .map(|_| {
            f.origin
                + DVec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                ) * rng.range(0.1, 40.0)
        })
        .collect();
    pts.extend([
        f.origin + f.z * 30.0,
        f.origin - f.z * 2.0,
        f.origin + f.x * 1e6,
        f.origin,
    ]);
    for p in pts {
        let r = s.closest_point(p, dom, None);
        check_result(&s, p, dom, &r);
        let expect = ((p - f.origin).length() - 9.0).abs();
        assert!(
            (r.distance - expect).abs() <= 1e-9 * expect.max(1.0),
            "sphere: {} vs {expect} for {p}",
            r.distance
        );
    }
    // Restricted patch: the answer often lies on an edge or corner; compare with brute force.
    let rect = ParamRect {
        u: Interval::new(0.3, 1.4),
        v: Interval::new(-0.2, 0.6),
    };
    for _ in 0..100 {
        let p = f.origin
            + DVec3::new(
                rng.range(-20.0, 20.0),
                rng.range(-20.0, 20.0),
                rng.range(-20.0, 20.0),
            );
        let r = s.closest_point(p, rect, None);
        check_result(&s, p, rect, &r);
        let b = brute_force(&s, p, rect, 200);
        assert!(r.distance <= b + 1e-9, "patch: {} > brute {b}", r.distance);
        assert!(
            r.distance >= b - 1e-3,
            "patch: {} far below brute {b}",
            r.distance
        );
    }
}

#[test]
fn cylinder_cone_plane_inversion_with_infinite_ranges() {
    let f = frame();
    let cyl = SurfaceGeom::Cylinder(Cylinder {
        frame: f,
        radius: 6.0,
    });
    let cone = SurfaceGeom::Cone(Cone {
        frame: f,
        radius: 4.0,
        semi_angle: 0.35,
    });
    let plane = SurfaceGeom::Plane(Plane { frame: f });
    let mut rng = Lcg(11);
    let (sa, ca) = 0.35_f64.sin_cos();
    for k in 0..300 {
        let scale = if k % 10 == 0 { 1e5 } else { 30.0 };
        let mut q = DVec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ) * scale;
        if k % 17 == 0 {
            q.x = 0.0;
            q.y = 0.0; // on the axis
        }
        let p = f.to_world(q);
        let rho = q.x.hypot(q.y);
        let r = cyl.closest_point(p, cyl.domain(), None);
        check_result(&cyl, p, cyl.domain(), &r);
        assert!(
            (r.distance - (rho - 6.0).abs()).abs() <= 1e-9 * scale,
            "cylinder"
        );
        let r = cone.closest_point(p, cone.domain(), None);
        check_result(&cone, p, cone.domain(), &r);
        let expect = ((rho - 4.0) * ca - q.z * sa)
            .abs()
            .min(((rho + 4.0) * ca + q.z * sa).abs());
        assert!(
            (r.distance - expect).abs() <= 1e-9 * scale,
            "cone: {} vs {expect} at {q}",
            r.distance
        );
        let r = plane.closest_point(p, plane.domain(), Some(DVec2::new(f64::NAN, 3.0)));
        check_result(&plane, p, plane.domain(), &r);
        assert!((r.distance - q.z.abs()).abs() <= 1e-9 * scale);
    }
    // A half-infinite cylinder window: the closest point lies on the v = 0 boundary circle.
    let rect = ParamRect {
        u: Interval::new(0.0, TAU),
        v: Interval::new(0.0, f64::INFINITY),
    };
    let p = f.to_world(DVec3::new(10.0, 0.0, -5.0));
    let r = cyl.closest_point(p, rect, None);
    assert!((r.distance - (16.0_f64 + 25.0).sqrt()).abs() <= 1e-9 && r.uv.y.abs() <= 1e-12);
}

#[test]
fn torus_inversion_matches_closed_form_including_axis_points() {
    let f = frame();
    let t = SurfaceGeom::Torus(Torus {
        frame: f,
        major_radius: 20.0,
        minor_radius: 5.0,
    });
    let dom = t.domain();
    let mut rng = Lcg(3);
    for k in 0..300 {
        let mut q = DVec3::new(
            rng.range(-40.0, 40.0),
            rng.range(-40.0, 40.0),
            rng.range(-15.0, 15.0),
        );
        if k % 25 == 0 {
            q = DVec3::new(0.0, 0.0, q.z); // on the axis: every u is closest
        }
        if k % 31 == 0 {
            q *= 1e4;
        }
        let p = f.to_world(q);
        let r = t.closest_point(p, dom, None);
        check_result(&t, p, dom, &r);
        let expect = ((q.x.hypot(q.y) - 20.0).hypot(q.z) - 5.0).abs();
        assert!(
            (r.distance - expect).abs() <= 1e-9 * expect.max(1.0),
            "torus: {} vs {expect} at {q}",
            r.distance
        );
    }
}

#[test]
fn revolution_inversion_on_axis_and_bspline_inversion_against_brute_force() {
    let rev = SurfaceGeom::Revolution(Revolution {
        meridian: Box::new(meridian()),
        axis_origin: DVec3::ZERO,
        axis_dir: DVec3::Z,
    });
    let dom = rev.domain();
    for z in [-10.0, 0.0, 3.0, 12.0] {
        let p = DVec3::new(0.0, 0.0, z);
        let r = rev.closest_point(p, dom, None);
        check_result(&rev, p, dom, &r);
        let b = brute_force(&rev, p, dom, 300);
        assert!(
            r.distance <= b + 1e-9 && r.distance >= b - 1e-3,
            "axis point {z}: {} vs {b}",
            r.distance
        );
    }
    let s = SurfaceGeom::BSpline(hills(true));
    let d = s.domain();
    let mut rng = Lcg(5);
    for k in 0..60 {
        // Points above, below, beside (boundary answers) and far away.
        let scale = if k % 12 == 0 { 1e4 } else { 1.0 };
        let p = DVec3::new(
            rng.range(-30.0, 150.0),
            rng.range(-20.0, 100.0),
            rng.range(-30.0, 30.0),
        ) * scale;
        let r = s.closest_point(p, d, None);
        check_result(&s, p, d, &r);
        let b = brute_force(&s, p, d, 300);
        assert!(
            r.distance <= b + 1e-9 * scale,
            "bspline {k}: {} > brute {b}",
            r.distance
        );
        assert!(
            r.distance >= b - 2e-2 * scale,
            "bspline {k}: {} far below brute {b}",
            r.distance
        );
        // Interior answers are stationary: the residual is normal to the surface.
        let inner = |t: f64, i: Interval| t > i.t0 + 1e-9 && t < i.t1 - 1e-9;
        if inner(r.uv.x, d.u) && inner(r.uv.y, d.v) && r.distance > 1e-9 {
            let dd = s.derivs(r.uv.x, r.uv.y);
            let w = (r.point - p) / r.distance;
            assert!(w.dot(dd.su.normalize()).abs() < 1e-7 && w.dot(dd.sv.normalize()).abs() < 1e-7);
        }
    }
    // Local search from a hint converges to the same point as the global one nearby.
    let p = s.point(1.3, 2.1) + DVec3::new(0.0, 0.0, 0.5);
    let g = s.closest_point(p, d, None);
    let l = s.closest_point_near(p, d, DVec2::new(1.2, 2.0));
    assert!((g.distance - l.distance).abs() < 1e-10 && (g.uv - l.uv).length() < 1e-7);
    // Non-finite query: finite answer, no NaN.
    let r = s.closest_point(DVec3::NAN, d, None);
    assert!(r.uv.is_finite() && r.point.is_finite() && !r.distance.is_nan());
}

#[test]
fn curve_derivatives_and_projection() {
    let f = frame();
    let curves = [
        CurveGeom::Line(Line {
            origin: f.origin,
            dir: f.x,
        }),
        CurveGeom::Circle(Circle {
            frame: f,
            radius: 7.0,
        }),
        CurveGeom::Ellipse(Ellipse {
            frame: f,
            semi_axis_1: 12.0,
            semi_axis_2: 4.0,
        }),
        meridian(),
    ];
    for c in &curves {
        let d = c.domain();
        for a in [0.17, 0.5, 0.83] {
            let t = if d.is_finite() { d.lerp(a) } else { 10.0 * a };
            check_curve_fd(c, t, 1e-5, 1e-7);
        }
    }
    assert_eq!(curves[0].period(), None);
    assert_eq!(curves[1].period(), Some(TAU));
    let mut rng = Lcg(9);
    for k in 0..200 {
        let scale = if k % 20 == 0 { 1e5 } else { 20.0 };
        let p = f.origin
            + DVec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ) * scale;
        // Line over an infinite range: the exact projection.
        let t = curves[0].closest_param(p, curves[0].domain());
        assert!((t - (p - f.origin).dot(f.x)).abs() <= 1e-12 * scale);
        // Circle: the closed form, brought into [π, 3π].
        let q = f.to_local(p);
        let t = curves[1].closest_param(p, Interval::new(PI, 3.0 * PI));
        assert!((PI..=3.0 * PI).contains(&t));
        let expect = (q.x.hypot(q.y) - 7.0).hypot(q.z);
        assert!((curves[1].point(t).distance(p) - expect).abs() <= 1e-9 * scale);
        // Ellipse and B-spline: dense sampling bound.
        for (c, range) in [
            (&curves[2], Interval::new(0.0, TAU)),
            (&curves[2], Interval::new(1.0, 2.0)),
            (&curves[3], Interval::new(0.1, 0.9)),
        ] {
            let t = c.closest_param(p, range);
            assert!(t >= range.t0 && t <= range.t1);
            let best = (0..=20000)
                .map(|i| c.point(range.lerp(i as f64 / 20000.0)).distance(p))
                .fold(f64::INFINITY, f64::min);
            let got = c.point(t).distance(p);
            assert!(
                got <= best + 1e-9 * scale,
                "curve projection {got} > sampled {best}"
            );
        }
    }
    // On the circle's axis every parameter is closest: a finite one in range.
    let t = curves[1].closest_param(f.origin + f.z * 3.0, Interval::new(1.0, 2.0));
    assert!((1.0..=2.0).contains(&t));
    for c in &curves {
        assert!(c.closest_param(DVec3::NAN, c.domain()).is_finite());
        assert!(
            c.closest_param(DVec3::ONE, Interval::new(f64::NAN, f64::NAN))
                .is_finite()
        );
    }
}

#[test]
fn periodic_rectangles_across_the_seam() {
    let f = frame();
    let cyl = SurfaceGeom::Cylinder(Cylinder {
        frame: f,
        radius: 6.0,
    });
    let rect = ParamRect {
        u: Interval::new(-0.5, 0.5),
        v: Interval::new(-10.0, 10.0),
    };
    for ang in [-0.3_f64, 0.2, 0.45] {
        let p = f.to_world(DVec3::new(9.0 * ang.cos(), 9.0 * ang.sin(), 2.0));
        let r = cyl.closest_point(p, rect, None);
        assert!(
            (r.uv.x - ang).abs() < 1e-9 && (r.distance - 3.0).abs() < 1e-9,
            "seam: {:?}",
            r.uv
        );
    }
    // Outside the patch's angular range: the nearer edge, u = 0.5.
    let p = f.to_world(DVec3::new(9.0 * 1.0_f64.cos(), 9.0 * 1.0_f64.sin(), 2.0));
    let r = cyl.closest_point(p, rect, None);
    assert!((r.uv.x - 0.5).abs() < 1e-12, "edge: {:?}", r.uv);
    // A rectangle longer than a period: answer inside it, distance exact.
    let rect = ParamRect {
        u: Interval::new(2.0, 2.0 + 3.0 * PI),
        v: Interval::new(-10.0, 10.0),
    };
    let p = f.to_world(DVec3::new(-9.0, 0.5, 1.0));
    let r = cyl.closest_point(p, rect, None);
    check_result(&cyl, p, rect, &r);
    assert!((r.distance - (9.0_f64.hypot(0.5) - 6.0)).abs() < 1e-9);
    // The same through the local search started on the far side of the seam.
    let sphere = SurfaceGeom::Sphere(Sphere {
        frame: f,
        radius: 9.0,
    });
    let rect = ParamRect {
        u: Interval::new(PI - 0.4, PI + 0.4),
        v: Interval::new(-1.0, 1.0),
    };
    let p = f.to_world(DVec3::new(-20.0, -1.0, 3.0));
    let r = sphere.closest_point_near(p, rect, DVec2::new(-PI + 0.1, 0.0));
    check_result(&sphere, p, rect, &r);
    assert!((r.distance - ((p - f.origin).length() - 9.0)).abs() < 1e-9);
}

#[test]
fn revolution_with_meridian_on_the_axis() {
    // A dome: quarter circle from the pole (on the axis) down to the equator, revolved about Z.
    let mframe = Frame {
        origin: DVec3::ZERO,
        x: DVec3::Z,
        y: DVec3::X,
        z: -DVec3::Y,
    };
    let arc = CurveGeom::Circle(Circle {
        frame: mframe,
        radius: 8.0,
    });
    let dome = SurfaceGeom::Revolution(Revolution {
        meridian: Box::new(arc),
        axis_origin: DVec3::ZERO,
        axis_dir: DVec3::Z,
    });
    let rect = ParamRect {
        u: Interval::new(0.0, TAU),
        v: Interval::new(0.0, FRAC_PI_2),
    };
    // The pole is a degenerate point: no normal, no curvature, no NaN.
    let pole = dome.derivs(1.0, 0.0);
    assert!(pole.p.distance(DVec3::new(0.0, 0.0, 8.0)) < 1e-12 && pole.normal().is_none());
    for z in [20.0, 8.0, 3.0, 0.0, -5.0] {
        let p = DVec3::new(0.0, 0.0, z);
        let r = dome.closest_point(p, rect, None);
        check_result(&dome, p, rect, &r);
        // Above the centre the pole is closest; below, the equator circle (|p| to the rim).
        let expect = if z > 0.0 {
            (z - 8.0).abs()
        } else {
            8.0_f64.hypot(z)
        };
        assert!(
            (r.distance - expect).abs() < 1e-9,
            "dome axis point z = {z}: {} vs {expect}",
            r.distance
        );
    }
}
