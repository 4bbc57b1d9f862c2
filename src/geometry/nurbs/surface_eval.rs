//! B-spline / NURBS surface evaluation: point and partial derivatives to second order (A3.6/A4.4
//! on homogeneous poles, then the quotient rule), domain, periodicity, exact iso-curves,
//! control-hull box.

use glam::DVec4;

use super::basis::with_basis;
use super::{BSplineCurve, BSplineSurface, knots};
use crate::geometry::diffgeom::SurfaceDerivs;
use crate::geometry::surface::ParamRect;
use crate::geometry::{Aabb, DVec3, Interval};

impl BSplineSurface {
    /// Is the data consistent enough to index safely (counts, degrees)?
    fn is_well_formed(&self) -> bool {
        self.degree_u >= 1
            && self.degree_v >= 1
            && self.n_u > self.degree_u
            && self.n_v > self.degree_v
            && self.n_u.checked_mul(self.n_v) == Some(self.poles.len())
            && self.knots_u.len() == self.n_u + self.degree_u + 1
            && self.knots_v.len() == self.n_v + self.degree_v + 1
            && self
                .weights
                .as_ref()
                .is_none_or(|w| w.len() == self.poles.len())
    }

    /// Parameter domain `[U_p, U_{n+1}]` in each direction.
    #[must_use]
    pub fn domain(&self) -> ParamRect {
        ParamRect {
            u: knots::domain(&self.knots_u, self.degree_u, self.n_u),
            v: knots::domain(&self.knots_v, self.degree_v, self.n_v),
        }
    }

    fn same_pole(&self, a: usize, b: usize, tol: f64) -> bool {
        let poles = match (self.poles.get(a), self.poles.get(b)) {
            (Some(x), Some(y)) => x.distance(*y) <= tol,
            _ => false,
        };
        poles
            && self
                .weights
                .as_ref()
                .is_none_or(|w| match (w.get(a), w.get(b)) {
                    (Some(x), Some(y)) => (x - y).abs() <= 1e-12 * x.abs().max(y.abs()),
                    _ => false,
                })
    }

    /// Periods in u and v for splines stored in OCCT's unperiodised periodic form (see
    /// [`BSplineCurve::period`]), `None` where not periodic.
    #[must_use]
    pub fn periods(&self) -> (Option<f64>, Option<f64>) {
        if !self.is_well_formed() {
            return (None, None);
        }
        let tol = 1e-10 * self.bbox().diagonal().max(1e-300);
        let nv = self.n_v;
        let pu = knots::period(&self.knots_u, self.degree_u, self.n_u, |i, j| {
            (0..nv).all(|k| self.same_pole(i * nv + k, j * nv + k, tol))
        });
        let pv = knots::period(&self.knots_v, self.degree_v, self.n_v, |i, j| {
            (0..self.n_u).all(|k| self.same_pole(k * nv + i, k * nv + j, tol))
        });
        (pu, pv)
    }

    /// The parameters actually evaluated for `(u, v)`: wrapped into the domain in a periodic
    /// direction, clamped otherwise (NaN goes to the domain start).
    #[must_use]
    pub fn eval_params(&self, u: f64, v: f64) -> (f64, f64) {
        let ParamRect { u: du, v: dv } = self.domain();
        let inside = |t: f64, d: Interval| t >= d.t0 && t <= d.t1;
        if inside(u, du) && inside(v, dv) {
            return (u, v);
        }
        let (pu, pv) = self.periods();
        let fix = |t: f64, d: Interval, period: Option<f64>| match period {
            _ if inside(t, d) => t,
            Some(per) if t.is_finite() => knots::wrap(t, d, per),
            _ if t.is_nan() => d.t0,
            _ => d.clamp(t),
        };
        (fix(u, du, pu), fix(v, dv, pv))
    }

    /// Point and partial derivatives to second order at `(u, v)` (see [`Self::eval_params`]
    /// outside the domain).
    #[must_use]
    pub fn derivs(&self, u: f64, v: f64) -> SurfaceDerivs {
        if !self.is_well_formed() {
            let p = self.poles.first().copied().unwrap_or(DVec3::ZERO);
            return SurfaceDerivs {
                p,
                su: DVec3::ZERO,
                sv: DVec3::ZERO,
                suu: DVec3::ZERO,
                suv: DVec3::ZERO,
                svv: DVec3::ZERO,
            };
        }
        let (u, v) = self.eval_params(u, v);
        let (pu, pv, nv) = (self.degree_u, self.degree_v, self.n_v);
        with_basis(&self.knots_u, pu, self.n_u, u, true, |bu| {
            with_basis(&self.knots_v, pv, nv, v, true, |bv| {
                let (iu0, jv0) = (bu.span - pu, bv.span - pv);
                match &self.weights {
                    None => {
                        let mut a = [DVec3::ZERO; 6]; // 00, 10, 01, 20, 11, 02
                        for r in 0..=pu {
                            let row = (iu0 + r) * nv + jv0;
                            let (mut r0, mut r1, mut r2) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
                            for (s, pole) in self.poles[row..=row + pv].iter().enumerate() {
                                r0 += *pole * bv.n0[s];
                                r1 += *pole * bv.n1[s];
                                r2 += *pole * bv.n2[s];
                            }
                            let (n0, n1, n2) = (bu.n0[r], bu.n1[r], bu.n2[r]);
                            a[0] += r0 * n0;
                            a[1] += r0 * n1;
                            a[2] += r1 * n0;
                            a[3] += r0 * n2;
                            a[4] += r1 * n1;
                            a[5] += r2 * n0;
                        }
                        let [p, su, sv, suu, suv, svv] = a;
                        SurfaceDerivs {
                            p,
                            su,
                            sv,
                            suu,
                            suv,
                            svv,
                        }
                    }
                    Some(w) => {
                        let mut a = [DVec4::ZERO; 6];
                        for r in 0..=pu {
                            let row = (iu0 + r) * nv + jv0;
                            let (mut r0, mut r1, mut r2) = (DVec4::ZERO, DVec4::ZERO, DVec4::ZERO);
                            let poles = self.poles[row..=row + pv].iter().zip(&w[row..=row + pv]);
                            for (s, (pole, &wi)) in poles.enumerate() {
                                let h = (*pole * wi).extend(wi);
                                r0 += h * bv.n0[s];
                                r1 += h * bv.n1[s];
                                r2 += h * bv.n2[s];
                            }
                            let (n0, n1, n2) = (bu.n0[r], bu.n1[r], bu.n2[r]);
                            a[0] += r0 * n0;
                            a[1] += r0 * n1;
                            a[2] += r1 * n0;
                            a[3] += r0 * n2;
                            a[4] += r1 * n1;
                            a[5] += r2 * n0;
                        }
                        rational_surface(&a)
                    }
                }
            })
        })
    }

    /// Point at `(u, v)` (basis values only: cheaper than [`Self::derivs`]).
    #[must_use]
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        if !self.is_well_formed() {
            return self.poles.first().copied().unwrap_or(DVec3::ZERO);
        }
        let (u, v) = self.eval_params(u, v);
        let (pu, pv, nv) = (self.degree_u, self.degree_v, self.n_v);
        with_basis(&self.knots_u, pu, self.n_u, u, false, |bu| {
            with_basis(&self.knots_v, pv, nv, v, false, |bv| {
                let jv0 = bv.span - pv;
                let mut a = DVec4::ZERO;
                for r in 0..=pu {
                    let row = (bu.span - pu + r) * nv + jv0;
                    let mut r0 = DVec4::ZERO;
                    for (s, k) in (row..=row + pv).enumerate() {
                        r0 += self.homogeneous(k) * bv.n0[s];
                    }
                    a += r0 * bu.n0[r];
                }
                if a.w > 0.0 {
                    a.truncate() / a.w
                } else {
                    a.truncate()
                }
            })
        })
    }

    /// The iso-parametric curve `v ↦ S(u, v)` (exact: homogeneous poles combined with the u
    /// basis; rational stays rational). `u` is clamped or wrapped as in [`Self::eval_params`].
    #[must_use]
    pub fn iso_u(&self, u: f64) -> BSplineCurve {
        if !self.is_well_formed() {
            return self.degenerate_iso(self.degree_v, &self.knots_v);
        }
        let (u, _) = self.eval_params(u, self.domain().v.t0);
        let (pu, nv) = (self.degree_u, self.n_v);
        let h: Vec<DVec4> = with_basis(&self.knots_u, pu, self.n_u, u, false, |bu| {
            (0..nv)
                .map(|j| {
                    (0..=pu).fold(DVec4::ZERO, |acc, r| {
                        acc + self.homogeneous((bu.span - pu + r) * nv + j) * bu.n0[r]
                    })
                })
                .collect()
        });
        self.iso_from_homogeneous(self.degree_v, self.knots_v.clone(), &h)
    }

    /// The iso-parametric curve `u ↦ S(u, v)` (exact, rational preserved).
    #[must_use]
    pub fn iso_v(&self, v: f64) -> BSplineCurve {
        if !self.is_well_formed() {
            return self.degenerate_iso(self.degree_u, &self.knots_u);
        }
        let (_, v) = self.eval_params(self.domain().u.t0, v);
        let (pv, nv) = (self.degree_v, self.n_v);
        let h: Vec<DVec4> = with_basis(&self.knots_v, pv, nv, v, false, |bv| {
            (0..self.n_u)
                .map(|i| {
                    (0..=pv).fold(DVec4::ZERO, |acc, s| {
                        acc + self.homogeneous(i * nv + bv.span - pv + s) * bv.n0[s]
                    })
                })
                .collect()
        });
        self.iso_from_homogeneous(self.degree_u, self.knots_u.clone(), &h)
    }

    /// Box around the control net (contains the surface: weights are positive).
    #[must_use]
    pub fn bbox(&self) -> Aabb {
        Aabb::from_points(&self.poles)
    }

    fn homogeneous(&self, k: usize) -> DVec4 {
        let p = self.poles.get(k).copied().unwrap_or(DVec3::ZERO);
        match &self.weights {
            None => p.extend(1.0),
            Some(w) => {
                let wi = w.get(k).copied().unwrap_or(1.0);
                (p * wi).extend(wi)
            }
        }
    }

    fn iso_from_homogeneous(&self, degree: usize, knots: Vec<f64>, h: &[DVec4]) -> BSplineCurve {
        let poles = h
            .iter()
            .map(|q| {
                if q.w > 0.0 {
                    q.truncate() / q.w
                } else {
                    q.truncate()
                }
            })
            .collect();
        let weights = self
            .weights
            .as_ref()
            .map(|_| h.iter().map(|q| q.w).collect());
        BSplineCurve {
            degree,
            knots,
            poles,
            weights,
        }
    }

    fn degenerate_iso(&self, degree: usize, knots: &[f64]) -> BSplineCurve {
        BSplineCurve {
            degree,
            knots: knots.to_vec(),
            poles: Vec::new(),
            weights: None,
        }
    }
}

/// Quotient rule for `S = A / w` from homogeneous partials `[00, 10, 01, 20, 11, 02]` (A4.4).
fn rational_surface(a: &[DVec4; 6]) -> SurfaceDerivs {
    let [a00, a10, a01, a20, a11, a02] = *a;
    let w = a00.w;
    if w.is_nan() || w <= 0.0 {
        let z = DVec3::ZERO;
        return SurfaceDerivs {
            p: a00.truncate(),
            su: z,
            sv: z,
            suu: z,
            suv: z,
            svv: z,
        };
    }
    let p = a00.truncate() / w;
    let su = (a10.truncate() - p * a10.w) / w;
    let sv = (a01.truncate() - p * a01.w) / w;
    let suu = (a20.truncate() - su * (2.0 * a10.w) - p * a20.w) / w;
    let suv = (a11.truncate() - su * a01.w - sv * a10.w - p * a11.w) / w;
    let svv = (a02.truncate() - sv * (2.0 * a01.w) - p * a02.w) / w;
    SurfaceDerivs {
        p,
        su,
        sv,
        suu,
        suv,
        svv,
    }
}
