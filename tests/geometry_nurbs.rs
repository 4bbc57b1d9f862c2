//! B-spline / NURBS kernel: evaluation against the Cox–de Boor definition, derivatives against
//! central differences, exact conics, span search at the domain end, iso-curves, validation.

mod common;

use common::geometry::*;
use talas::geometry::curve::CurveGeom;
use talas::geometry::nurbs::{BSplineCurve, BSplineSurface, expand_knots};
use talas::geometry::{DVec3, GeometryError};

fn cubic(rational: bool) -> BSplineCurve {
    let knots = expand_knots(&[0.0, 0.7, 1.9, 2.0, 3.5], &[4, 1, 1, 1, 4]).unwrap();
    let poles = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(10.0, 5.0, 1.0),
        DVec3::new(20.0, -3.0, 4.0),
        DVec3::new(28.0, 8.0, -2.0),
        DVec3::new(35.0, 12.0, 6.0),
        DVec3::new(44.0, 2.0, 3.0),
        DVec3::new(50.0, 9.0, 0.0),
    ];
    let weights = rational.then(|| vec![1.0, 2.5, 0.4, 1.3, 3.0, 0.7, 1.0]);
    BSplineCurve::new(3, knots, poles, weights).unwrap()
}

#[test]
fn curve_points_match_cox_de_boor() {
    for rational in [false, true] {
        let c = cubic(rational);
        for k in 0..=70 {
            let t = 3.5 * k as f64 / 70.0 * 0.999_999;
            assert_vec_near(
                c.point(t),
                reference_curve_point(&c, t),
                1e-13,
                "curve point",
            );
        }
    }
}

#[test]
fn curve_derivatives_match_finite_differences() {
    for rational in [false, true] {
        let c = CurveGeom::BSpline(cubic(rational));
        // Away from knots, so each central difference stays on one polynomial piece.
        for t in [0.2, 0.45, 1.1, 1.5, 1.95, 2.6, 3.3] {
            check_curve_fd(&c, t, 1e-5, 1e-7);
        }
    }
    // Degree 1: second derivative is exactly zero.
    let l = BSplineCurve::new(
        1,
        vec![0.0, 0.0, 1.0, 2.0, 2.0],
        vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0)],
        None,
    )
    .unwrap();
    let d = l.derivs(0.5);
    assert_eq!(d.d2, DVec3::ZERO);
    assert_vec_near(d.d1, DVec3::X, 1e-15, "degree-1 slope");
}

#[test]
fn domain_end_uses_last_nonempty_span() {
    let c = cubic(true);
    assert_eq!(c.domain().t1, 3.5);
    assert_vec_near(
        c.point(3.5),
        DVec3::new(50.0, 9.0, 0.0),
        1e-14,
        "clamped end = last pole",
    );
    assert_vec_near(
        c.point(0.0),
        DVec3::ZERO,
        1e-14,
        "clamped start = first pole",
    );
    // Unclamped, with a repeated knot at the domain end: U = 0 1 2 3 3 4 5, p = 2, domain [2, 3];
    // the span [U_3, U_4) is empty, evaluation at 3 must use [2, 3) (limit from the left).
    let poles = vec![
        DVec3::ZERO,
        DVec3::new(1.0, 2.0, 0.0),
        DVec3::new(3.0, 1.0, 1.0),
        DVec3::new(4.0, 4.0, 2.0),
    ];
    let u = BSplineCurve::new(2, vec![0.0, 1.0, 2.0, 3.0, 3.0, 4.0, 5.0], poles, None).unwrap();
    let end = u.derivs(3.0);
    assert!(end.p.is_finite() && end.d1.is_finite() && end.d2.is_finite());
    assert_vec_near(
        end.p,
        reference_curve_point(&u, 3.0 - 1e-12),
        1e-10,
        "end of unclamped",
    );
    // Outside the domain: clamped, never NaN.
    assert_vec_near(u.point(17.0), end.p, 1e-15, "clamped above");
    assert!(u.point(f64::NAN).is_finite());
    assert!(c.derivs(f64::NEG_INFINITY).d2.is_finite());
}

#[test]
fn surface_points_match_definition_and_derivatives_match_differences() {
    for rational in [false, true] {
        let s = hills(rational);
        for &(u, v) in &[
            (0.0_f64, -1.0_f64),
            (3.0, 4.0),
            (0.3, 0.1),
            (1.2, 1.0),
            (2.5, 3.1),
            (1.9, 0.4),
        ] {
            let (uu, vv) = (u.min(3.0 - 1e-12), v.min(4.0 - 1e-12));
            assert_vec_near(
                s.point(u, v),
                reference_surface_point(&s, uu, vv),
                1e-10,
                "surface point",
            );
        }
        let f = |u, v| s.derivs(u, v);
        for &(u, v) in &[(0.3, 0.1), (1.2, 1.0), (2.5, 3.1), (1.85, 0.4), (0.5, 3.0)] {
            check_surface_fd(&f, u, v, 1e-5, 2e-7);
        }
    }
}

#[test]
fn nurbs_circle_is_exact() {
    let c0 = DVec3::new(3.0, -2.0, 5.0);
    let r = 7.0;
    let c = nurbs_circle(c0, r);
    for k in 0..=400 {
        let t = k as f64 / 400.0;
        let d = c.derivs(t);
        assert!(
            ((d.p - c0).length() - r).abs() <= 1e-12 * r,
            "radius at {t}"
        );
        let kappa = d.d1.cross(d.d2).length() / d.d1.length().powi(3);
        assert!(
            (kappa - 1.0 / r).abs() <= 1e-10 / r,
            "curvature {kappa} at {t}"
        );
    }
    check_curve_fd(&CurveGeom::BSpline(c), 0.1, 1e-6, 1e-7);
}

#[test]
fn iso_curves_are_exact() {
    for rational in [false, true] {
        let s = hills(rational);
        for u in [0.0, 0.8, 1.33, 3.0] {
            let c = s.iso_u(u);
            assert_eq!(c.is_rational(), rational);
            c.validate().unwrap();
            for v in [-1.0, -0.2, 0.4, 2.0, 3.9, 4.0] {
                assert_vec_near(c.point(v), s.point(u, v), 1e-12, "iso_u");
                assert_vec_near(c.derivs(v).d1, s.derivs(u, v).sv, 1e-10, "iso_u tangent");
            }
        }
        for v in [-1.0, 0.3, 1.7, 4.0] {
            let c = s.iso_v(v);
            c.validate().unwrap();
            for u in [0.0, 0.4, 1.0, 2.2, 3.0] {
                assert_vec_near(c.point(u), s.point(u, v), 1e-12, "iso_v");
                assert_vec_near(
                    c.derivs(u).d2,
                    s.derivs(u, v).suu,
                    1e-9,
                    "iso_v curvature vector",
                );
            }
        }
    }
}

#[test]
fn bbox_contains_surface_samples() {
    let s = hills(true);
    let b = s.bbox();
    for i in 0..=30 {
        for j in 0..=30 {
            let p = s.point(3.0 * i as f64 / 30.0, -1.0 + 5.0 * j as f64 / 30.0);
            assert!(p.cmpge(b.min - 1e-12).all() && p.cmple(b.max + 1e-12).all());
        }
    }
    let c = cubic(true);
    assert!(c.bbox().min.x == 0.0 && c.bbox().max.x == 50.0);
}

#[test]
fn periodic_curve_detected_and_wrapped() {
    // Uniform periodic cubic in OCCT's unperiodised form: 4 distinct poles + 3 repeated.
    let base = [
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(-1.0, 0.0, 0.0),
        DVec3::new(0.0, -1.0, 0.5),
    ];
    let poles: Vec<DVec3> = (0..7).map(|i| base[i % 4]).collect();
    let knots: Vec<f64> = (0..11).map(|i| i as f64 - 3.0).collect();
    let c = BSplineCurve::new(3, knots, poles, None).unwrap();
    assert_eq!(c.period(), Some(4.0));
    let g = CurveGeom::BSpline(c.clone());
    assert_eq!(g.period(), Some(4.0));
    for t in [0.3, 1.7, 3.9] {
        assert_vec_near(c.point(t + 4.0), c.point(t), 1e-13, "wrapped +T");
        assert_vec_near(c.point(t - 8.0), c.point(t), 1e-13, "wrapped -2T");
    }
    // Continuity across the seam (C² for a cubic).
    let (a, b) = (c.derivs(4.0 - 1e-12), c.derivs(0.0));
    assert_vec_near(a.p, b.p, 1e-10, "seam point");
    assert_vec_near(a.d2, b.d2, 1e-8, "seam C''");
    assert_eq!(cubic(false).period(), None);
}

#[expect(
    clippy::too_many_lines,
    reason = "a table of refused constructions, one case after another"
)]
#[test]
fn invalid_constructions_are_rejected() {
    let p3 = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
    let bad =
        |r: Result<BSplineCurve, GeometryError>| matches!(r, Err(GeometryError::InvalidBSpline(_)));
    let nonfinite =
        |r: Result<BSplineCurve, GeometryError>| matches!(r, Err(GeometryError::NonFinite(_)));
    let k = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
    assert!(BSplineCurve::new(2, k.clone(), p3.clone(), None).is_ok());
    assert!(
        bad(BSplineCurve::new(
            0,
            vec![0.0, 1.0, 2.0, 3.0],
            p3.clone(),
            None
        )),
        "degree 0"
    );
    assert!(
        bad(BSplineCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0],
            p3.clone(),
            None
        )),
        "knot count"
    );
    assert!(
        bad(BSplineCurve::new(3, vec![0.0; 6], p3.clone(), None)),
        "too few poles"
    );
    assert!(
        bad(BSplineCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 0.5, 1.0],
            p3.clone(),
            None
        )),
        "decreasing"
    );
    assert!(
        bad(BSplineCurve::new(2, vec![1.0; 6], p3.clone(), None)),
        "degenerate domain"
    );
    assert!(
        bad(BSplineCurve::new(
            1,
            vec![0.0, 0.0, 0.0, 1.0, 1.0],
            p3.clone(),
            None
        )),
        "multiplicity > p+1"
    );
    assert!(
        nonfinite(BSplineCurve::new(
            2,
            vec![0.0, 0.0, 0.0, f64::NAN, 1.0, 1.0],
            p3.clone(),
            None
        )),
        "NaN knot"
    );
    assert!(
        nonfinite(BSplineCurve::new(
            2,
            k.clone(),
            vec![DVec3::ZERO, DVec3::NAN, DVec3::Y],
            None
        )),
        "NaN pole"
    );
    assert!(
        bad(BSplineCurve::new(
            2,
            k.clone(),
            p3.clone(),
            Some(vec![1.0, 0.0, 1.0])
        )),
        "zero weight"
    );
    assert!(
        bad(BSplineCurve::new(
            2,
            k.clone(),
            p3.clone(),
            Some(vec![1.0, -2.0, 1.0])
        )),
        "negative weight"
    );
    assert!(
        bad(BSplineCurve::new(
            2,
            k.clone(),
            p3.clone(),
            Some(vec![1.0, 1.0])
        )),
        "weight count"
    );
    assert!(
        nonfinite(BSplineCurve::new(
            2,
            k.clone(),
            p3.clone(),
            Some(vec![1.0, f64::INFINITY, 1.0])
        )),
        "inf weight"
    );

    let grid: Vec<DVec3> = (0..6).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
    let ks = |n: usize| {
        let mut v = vec![0.0; 2];
        v.extend((0..n - 1).map(|i| i as f64));
        v.push((n - 2) as f64);
        v
    };
    assert!(
        BSplineSurface::new(
            1,
            1,
            vec![0.0, 0.0, 1.0, 1.0],
            vec![0.0, 0.0, 1.0, 2.0, 2.0],
            2,
            3,
            grid.clone(),
            None
        )
        .is_ok()
    );
    assert!(matches!(
        BSplineSurface::new(
            1,
            1,
            vec![0.0, 0.0, 1.0, 1.0],
            vec![0.0, 0.0, 1.0, 2.0, 2.0],
            3,
            3,
            grid.clone(),
            None
        ),
        Err(GeometryError::InvalidBSpline(_))
    ));
    assert!(matches!(
        BSplineSurface::new(
            1,
            1,
            vec![0.0, 0.0, 1.0, 1.0],
            ks(3),
            2,
            3,
            grid.clone(),
            Some(vec![1.0; 5])
        ),
        Err(GeometryError::InvalidBSpline(_))
    ));
    assert!(matches!(
        BSplineSurface::new(
            1,
            0,
            vec![0.0, 0.0, 1.0, 1.0],
            vec![0.0, 1.0, 2.0],
            2,
            3,
            grid,
            None
        ),
        Err(GeometryError::InvalidBSpline(_))
    ));

    assert_eq!(
        expand_knots(&[0.0, 0.5, 1.0], &[3, 1, 3]).unwrap(),
        vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0]
    );
    assert!(matches!(
        expand_knots(&[0.0, 1.0], &[3]),
        Err(GeometryError::InvalidBSpline(_))
    ));
    assert!(matches!(
        expand_knots(&[0.0, 1.0], &[3, 0]),
        Err(GeometryError::InvalidBSpline(_))
    ));
    assert!(matches!(
        expand_knots(&[0.0, 0.0], &[3, 3]),
        Err(GeometryError::InvalidBSpline(_))
    ));
    assert!(matches!(
        expand_knots(&[], &[]),
        Err(GeometryError::InvalidBSpline(_))
    ));
    assert!(matches!(
        expand_knots(&[0.0, f64::NAN], &[3, 3]),
        Err(GeometryError::NonFinite(_))
    ));
    assert!(matches!(
        expand_knots(&[0.0, 1.0], &[usize::MAX, 3]),
        Err(GeometryError::InvalidBSpline(_))
    ));
}

#[test]
fn malformed_structs_evaluate_without_panic() {
    let c = BSplineCurve {
        degree: 3,
        knots: vec![0.0, 1.0],
        poles: vec![DVec3::X],
        weights: None,
    };
    assert!(c.derivs(0.5).p.is_finite());
    assert!(c.validate().is_err());
    let s = BSplineSurface {
        degree_u: 2,
        degree_v: 2,
        knots_u: vec![],
        knots_v: vec![],
        n_u: 4,
        n_v: 4,
        poles: vec![DVec3::ONE; 3],
        weights: None,
    };
    assert!(s.derivs(0.1, 0.2).p.is_finite());
    assert!(s.iso_u(0.3).poles.is_empty());
    assert!(s.validate().is_err());
}

#[test]
fn high_degree_uses_heap_fallback_and_matches_definition() {
    // Degree 20 Bézier (beyond the stack scratch), checked against Cox–de Boor.
    let p = 20;
    let poles: Vec<DVec3> = (0..=p)
        .map(|i| DVec3::new(i as f64, ((i * i) % 7) as f64, (i as f64).sin()))
        .collect();
    let mut knots = vec![0.0; p + 1];
    knots.extend(vec![1.0; p + 1]);
    let c = BSplineCurve::new(p, knots, poles, None).unwrap();
    for t in [0.0, 0.13, 0.5, 0.77, 0.999] {
        assert_vec_near(c.point(t), reference_curve_point(&c, t), 1e-11, "degree 20");
    }
    check_curve_fd(&CurveGeom::BSpline(c), 0.4, 1e-5, 1e-6);
}

#[test]
fn periodic_surface_rows_detected_and_wrapped() {
    // u: uniform periodic cubic (4 distinct rows + 3 repeated), v: clamped linear.
    let ring = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.2)];
    let mut poles = Vec::new();
    for i in 0..7 {
        let (x, y) = ring[i % 4];
        for z in [0.0, 5.0] {
            poles.push(DVec3::new(x * (1.0 + z * 0.1), y, z));
        }
    }
    let knots_u: Vec<f64> = (0..11).map(|i| 0.5 * i as f64).collect();
    let s =
        BSplineSurface::new(3, 1, knots_u, vec![0.0, 0.0, 1.0, 1.0], 7, 2, poles, None).unwrap();
    assert_eq!(s.periods(), (Some(2.0), None));
    assert_eq!(s.domain().u, talas::geometry::Interval::new(1.5, 3.5));
    for (u, v) in [(1.7, 0.2), (2.9, 0.8)] {
        assert_vec_near(s.point(u + 2.0, v), s.point(u, v), 1e-13, "wrapped u");
        assert_vec_near(
            s.derivs(u - 4.0, v).suu,
            s.derivs(u, v).suu,
            1e-12,
            "wrapped S_uu",
        );
    }
    // v is not periodic: clamped instead.
    assert_vec_near(s.point(2.0, 3.0), s.point(2.0, 1.0), 1e-15, "clamped v");
}
