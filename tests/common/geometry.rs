//! Shared builders and reference checks for the geometry tests (finite differences, an
//! independent Cox–de Boor evaluator, exact rational quadratic conics).
#![allow(dead_code)]

use talas::geometry::DVec3;
use talas::geometry::curve::{CurveDerivs, CurveGeom};
use talas::geometry::diffgeom::SurfaceDerivs;
use talas::geometry::nurbs::{BSplineCurve, BSplineSurface};
use talas::geometry::surface::SurfaceGeom;

/// √2/2, the corner weight of a rational quadratic quarter circle.
pub const W45: f64 = std::f64::consts::FRAC_1_SQRT_2;

pub use super::Lcg;

/// Relative closeness of vectors.
pub fn assert_vec_near(a: DVec3, b: DVec3, tol: f64, what: &str) {
    let err = (a - b).length();
    let scale = a.length().max(b.length()).max(1.0);
    assert!(
        err <= tol * scale,
        "{what}: {a} vs {b} (error {err:e}, tol {tol:e} × {scale})"
    );
}

/// Cox–de Boor recursion N_{i,p}(u), half-open spans, 0/0 = 0 (textbook definition).
pub fn cox_de_boor(knots: &[f64], i: usize, p: usize, u: f64) -> f64 {
    if p == 0 {
        return if knots[i] <= u && u < knots[i + 1] {
            1.0
        } else {
            0.0
        };
    }
    let mut v = 0.0;
    let d1 = knots[i + p] - knots[i];
    if d1 > 0.0 {
        v += (u - knots[i]) / d1 * cox_de_boor(knots, i, p - 1, u);
    }
    let d2 = knots[i + p + 1] - knots[i + 1];
    if d2 > 0.0 {
        v += (knots[i + p + 1] - u) / d2 * cox_de_boor(knots, i + 1, p - 1, u);
    }
    v
}

/// Reference curve point by the definition Σ N_i w_i P_i / Σ N_i w_i.
pub fn reference_curve_point(c: &BSplineCurve, t: f64) -> DVec3 {
    let (mut num, mut den) = (DVec3::ZERO, 0.0);
    for (i, p) in c.poles.iter().enumerate() {
        let w = c.weights.as_ref().map_or(1.0, |w| w[i]);
        let n = cox_de_boor(&c.knots, i, c.degree, t) * w;
        num += *p * n;
        den += n;
    }
    num / den
}

/// Reference surface point by the definition.
pub fn reference_surface_point(s: &BSplineSurface, u: f64, v: f64) -> DVec3 {
    let (mut num, mut den) = (DVec3::ZERO, 0.0);
    for i in 0..s.n_u {
        let nu = cox_de_boor(&s.knots_u, i, s.degree_u, u);
        if nu == 0.0 {
            continue;
        }
        for j in 0..s.n_v {
            let k = i * s.n_v + j;
            let w = s.weights.as_ref().map_or(1.0, |w| w[k]);
            let n = nu * cox_de_boor(&s.knots_v, j, s.degree_v, v) * w;
            num += s.poles[k] * n;
            den += n;
        }
    }
    num / den
}

/// Central differences of a curve at t: (d1 from points, d2 from first derivatives).
pub fn curve_fd(f: &dyn Fn(f64) -> CurveDerivs, t: f64, h: f64) -> (DVec3, DVec3) {
    let (a, b) = (f(t - h), f(t + h));
    ((b.p - a.p) / (2.0 * h), (b.d1 - a.d1) / (2.0 * h))
}

/// Check a curve's derivatives against central differences.
pub fn check_curve_fd(c: &CurveGeom, t: f64, h: f64, tol: f64) {
    let d = c.derivs(t);
    let (d1, d2) = curve_fd(&|t| c.derivs(t), t, h);
    assert_vec_near(d.d1, d1, tol, &format!("C' at {t}"));
    assert_vec_near(d.d2, d2, tol, &format!("C'' at {t}"));
}

/// Check a surface's partials against central differences (second partials from the first).
pub fn check_surface_fd(s: &dyn Fn(f64, f64) -> SurfaceDerivs, u: f64, v: f64, h: f64, tol: f64) {
    let d = s(u, v);
    let (um, up, vm, vp) = (s(u - h, v), s(u + h, v), s(u, v - h), s(u, v + h));
    let k = 1.0 / (2.0 * h);
    let at = format!("at ({u}, {v})");
    assert_vec_near(d.su, (up.p - um.p) * k, tol, &format!("S_u {at}"));
    assert_vec_near(d.sv, (vp.p - vm.p) * k, tol, &format!("S_v {at}"));
    assert_vec_near(d.suu, (up.su - um.su) * k, tol, &format!("S_uu {at}"));
    assert_vec_near(
        d.suv,
        (vp.su - vm.su) * k,
        tol,
        &format!("S_uv (from S_u) {at}"),
    );
    assert_vec_near(
        d.suv,
        (up.sv - um.sv) * k,
        tol,
        &format!("S_uv (from S_v) {at}"),
    );
    assert_vec_near(d.svv, (vp.sv - vm.sv) * k, tol, &format!("S_vv {at}"));
}

/// Unit-circle control points and weights of the 9-pole rational quadratic full circle
/// (knots 0,0,0,¼,¼,½,½,¾,¾,1,1,1), as (x, y, w).
pub fn unit_circle_net() -> [(f64, f64, f64); 9] {
    [
        (1.0, 0.0, 1.0),
        (1.0, 1.0, W45),
        (0.0, 1.0, 1.0),
        (-1.0, 1.0, W45),
        (-1.0, 0.0, 1.0),
        (-1.0, -1.0, W45),
        (0.0, -1.0, 1.0),
        (1.0, -1.0, W45),
        (1.0, 0.0, 1.0),
    ]
}

/// Full-circle knot vector for [`unit_circle_net`].
pub fn circle_knots() -> Vec<f64> {
    vec![
        0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
    ]
}

/// Exact NURBS circle of radius r about `c` in the XY plane.
pub fn nurbs_circle(c: DVec3, r: f64) -> BSplineCurve {
    let net = unit_circle_net();
    let poles = net
        .iter()
        .map(|&(x, y, _)| c + DVec3::new(x * r, y * r, 0.0))
        .collect();
    let weights = net.iter().map(|&(_, _, w)| w).collect();
    BSplineCurve::new(2, circle_knots(), poles, Some(weights)).unwrap()
}

/// Exact NURBS cylinder (u around, v along +Z from 0 to `h`), radius r, axis Z through c.
pub fn nurbs_cylinder(c: DVec3, r: f64, h: f64) -> BSplineSurface {
    let net = unit_circle_net();
    let mut poles = Vec::new();
    let mut weights = Vec::new();
    for &(x, y, w) in &net {
        for z in [0.0, h] {
            poles.push(c + DVec3::new(x * r, y * r, z));
            weights.push(w);
        }
    }
    BSplineSurface::new(
        2,
        1,
        circle_knots(),
        vec![0.0, 0.0, 1.0, 1.0],
        9,
        2,
        poles,
        Some(weights),
    )
    .unwrap()
}

/// Exact NURBS sphere of radius r about c: u = longitude circle, v = meridian from south to
/// north pole (rational quadratic half circle, knots 0,0,0,½,½,1,1,1).
pub fn nurbs_sphere(c: DVec3, r: f64) -> BSplineSurface {
    let net = unit_circle_net();
    let meridian = [
        (0.0, -1.0, 1.0),
        (1.0, -1.0, W45),
        (1.0, 0.0, 1.0),
        (1.0, 1.0, W45),
        (0.0, 1.0, 1.0),
    ];
    let mut poles = Vec::new();
    let mut weights = Vec::new();
    for &(x, y, wu) in &net {
        for &(rho, z, wv) in &meridian {
            poles.push(c + DVec3::new(x * rho * r, y * rho * r, z * r));
            weights.push(wu * wv);
        }
    }
    BSplineSurface::new(
        2,
        2,
        circle_knots(),
        vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0],
        9,
        5,
        poles,
        Some(weights),
    )
    .unwrap()
}

/// A non-uniform clamped bicubic-by-quadratic "hills" surface (7 × 6 poles), optionally rational.
pub fn hills(rational: bool) -> BSplineSurface {
    let knots_u = vec![0.0, 0.0, 0.0, 0.0, 0.8, 1.7, 2.0, 3.0, 3.0, 3.0, 3.0];
    let knots_v = vec![-1.0, -1.0, -1.0, 0.3, 0.5, 2.2, 4.0, 4.0, 4.0];
    let (nu, nv) = (7, 6);
    let mut poles = Vec::new();
    let mut weights = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (
                i as f64 * 20.0 + (j as f64 * 1.3).sin() * 3.0,
                j as f64 * 15.0 + i as f64 * 2.0,
            );
            let z =
                8.0 * ((i as f64) * 0.9).sin() * ((j as f64) * 1.1).cos() + (i * j) as f64 * 0.3;
            poles.push(DVec3::new(x, y, z));
            weights.push(1.0 + 0.6 * ((i * 7 + j * 3) % 5) as f64 / 4.0);
        }
    }
    BSplineSurface::new(
        3,
        2,
        knots_u,
        knots_v,
        nu,
        nv,
        poles,
        rational.then_some(weights),
    )
    .unwrap()
}

/// Wrap a surface's derivs as a closure for [`check_surface_fd`].
pub fn surf_fn(s: &SurfaceGeom) -> impl Fn(f64, f64) -> SurfaceDerivs + '_ {
    move |u, v| s.derivs(u, v)
}

/// Closest point on a triangle (Ericson, Real-Time Collision Detection, 5.1.5).
pub fn closest_on_triangle(p: DVec3, [a, b, c]: [DVec3; 3]) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let s = 1.0 / (va + vb + vc);
    a + ab * (vb * s) + ac * (vc * s)
}
