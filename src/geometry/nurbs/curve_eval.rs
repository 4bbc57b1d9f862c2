//! B-spline / NURBS curve evaluation: point and derivatives to order 2 (A3.2/A4.2: derivatives of
//! the homogeneous curve, then the quotient rule), domain, periodicity, control-hull box.

use glam::DVec4;

use super::basis::with_basis;
use super::{BSplineCurve, knots};
use crate::geometry::curve::CurveDerivs;
use crate::geometry::{Aabb, DVec3, Interval};

impl BSplineCurve {
    /// Is the data consistent enough to index safely (counts, degree)?
    fn is_well_formed(&self) -> bool {
        self.degree >= 1
            && self.poles.len() > self.degree
            && self.knots.len() == self.poles.len() + self.degree + 1
            && self
                .weights
                .as_ref()
                .is_none_or(|w| w.len() == self.poles.len())
    }

    /// Parameter domain `[U_p, U_{n+1}]`.
    #[must_use]
    pub fn domain(&self) -> Interval {
        knots::domain(&self.knots, self.degree, self.poles.len())
    }

    /// Period when the curve is stored in OCCT's unperiodised periodic form (knot intervals repeat
    /// and the first `degree` poles and weights equal the last ones), `None` otherwise.
    #[must_use]
    pub fn period(&self) -> Option<f64> {
        if !self.is_well_formed() {
            return None;
        }
        let tol = 1e-10 * Aabb::from_points(&self.poles).diagonal().max(1e-300);
        knots::period(&self.knots, self.degree, self.poles.len(), |i, j| {
            let same_pole = match (self.poles.get(i), self.poles.get(j)) {
                (Some(a), Some(b)) => a.distance(*b) <= tol,
                _ => false,
            };
            let same_weight = self
                .weights
                .as_ref()
                .is_none_or(|w| match (w.get(i), w.get(j)) {
                    (Some(a), Some(b)) => (a - b).abs() <= 1e-12 * a.abs().max(b.abs()),
                    _ => false,
                });
            same_pole && same_weight
        })
    }

    /// The parameter actually evaluated for `t`: wrapped into the domain for a periodic curve,
    /// clamped otherwise (NaN goes to the domain start).
    #[must_use]
    pub fn eval_param(&self, t: f64) -> f64 {
        let dom = self.domain();
        if t >= dom.t0 && t <= dom.t1 {
            return t;
        }
        if t.is_finite()
            && let Some(period) = self.period()
        {
            return knots::wrap(t, dom, period);
        }
        if t.is_nan() { dom.t0 } else { dom.clamp(t) }
    }

    /// Point and first two derivatives at `t` (see [`Self::eval_param`] for `t` outside the
    /// domain). Derivatives of order above the degree are zero.
    #[must_use]
    pub fn derivs(&self, t: f64) -> CurveDerivs {
        if !self.is_well_formed() {
            let p = self.poles.first().copied().unwrap_or(DVec3::ZERO);
            return CurveDerivs {
                p,
                d1: DVec3::ZERO,
                d2: DVec3::ZERO,
            };
        }
        let t = self.eval_param(t);
        let p = self.degree;
        with_basis(&self.knots, p, self.poles.len(), t, true, |b| {
            let first = b.span - p;
            match &self.weights {
                None => {
                    let (mut a0, mut a1, mut a2) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
                    for (r, pole) in self.poles[first..=b.span].iter().enumerate() {
                        a0 += *pole * b.n0[r];
                        a1 += *pole * b.n1[r];
                        a2 += *pole * b.n2[r];
                    }
                    CurveDerivs {
                        p: a0,
                        d1: a1,
                        d2: a2,
                    }
                }
                Some(w) => {
                    let (mut a0, mut a1, mut a2) = (DVec4::ZERO, DVec4::ZERO, DVec4::ZERO);
                    for (r, (pole, &wi)) in self.poles[first..=b.span]
                        .iter()
                        .zip(&w[first..=b.span])
                        .enumerate()
                    {
                        let h = (*pole * wi).extend(wi);
                        a0 += h * b.n0[r];
                        a1 += h * b.n1[r];
                        a2 += h * b.n2[r];
                    }
                    rational_curve(a0, a1, a2)
                }
            }
        })
    }

    /// Point at `t` (basis values only: cheaper than [`Self::derivs`]).
    #[must_use]
    pub fn point(&self, t: f64) -> DVec3 {
        if !self.is_well_formed() {
            return self.poles.first().copied().unwrap_or(DVec3::ZERO);
        }
        let t = self.eval_param(t);
        let p = self.degree;
        with_basis(&self.knots, p, self.poles.len(), t, false, |b| {
            let first = b.span - p;
            let mut a = DVec4::ZERO;
            for (r, k) in (first..=b.span).enumerate() {
                let pole = self.poles[k];
                let w = self.weights.as_ref().map_or(1.0, |w| w[k]);
                a += (pole * w).extend(w) * b.n0[r];
            }
            if a.w > 0.0 {
                a.truncate() / a.w
            } else {
                a.truncate()
            }
        })
    }

    /// Box around the control polygon (contains the curve: weights are positive).
    #[must_use]
    pub fn bbox(&self) -> Aabb {
        Aabb::from_points(&self.poles)
    }
}

/// Quotient rule for `C = A / w` with homogeneous derivatives `(A, w)` (A4.2).
pub(crate) fn rational_curve(a0: DVec4, a1: DVec4, a2: DVec4) -> CurveDerivs {
    let w = a0.w;
    if w.is_nan() || w <= 0.0 {
        return CurveDerivs {
            p: a0.truncate(),
            d1: DVec3::ZERO,
            d2: DVec3::ZERO,
        };
    }
    let p = a0.truncate() / w;
    let d1 = (a1.truncate() - p * a1.w) / w;
    let d2 = (a2.truncate() - d1 * (2.0 * a1.w) - p * a2.w) / w;
    CurveDerivs { p, d1, d2 }
}
