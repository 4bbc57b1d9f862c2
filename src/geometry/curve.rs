//! Parametric curves in 3D: the kinds STEP edge curves use, with one evaluation interface.

mod projection;

use std::f64::consts::TAU;

use super::nurbs::BSplineCurve;
use super::{DVec3, Interval, frame::Frame};

/// Position and derivatives of a curve at a parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveDerivs {
    /// C(t), mm.
    pub p: DVec3,
    /// C'(t).
    pub d1: DVec3,
    /// C''(t).
    pub d2: DVec3,
}

/// Straight line `origin + t·dir` (dir is a unit vector, so t is arc length in mm).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Line {
    /// A point on the line.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
}

/// Circle `origin + r(cos t·x + sin t·y)` in its frame, t in rad.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Circle {
    /// Placement (centre and plane).
    pub frame: Frame,
    /// Radius in mm.
    pub radius: f64,
}

/// Ellipse `origin + a cos t·x + b sin t·y`, t in rad.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ellipse {
    /// Placement (centre, major axis along x).
    pub frame: Frame,
    /// Semi-axis along x, mm.
    pub semi_axis_1: f64,
    /// Semi-axis along y, mm.
    pub semi_axis_2: f64,
}

/// Any curve Talas can evaluate.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum CurveGeom {
    /// Straight line.
    Line(Line),
    /// Circle.
    Circle(Circle),
    /// Ellipse.
    Ellipse(Ellipse),
    /// B-spline or NURBS curve.
    BSpline(BSplineCurve),
}

impl CurveGeom {
    /// Natural parameter domain (infinite for a line; `[0, 2π]` for conics).
    #[must_use]
    pub fn domain(&self) -> Interval {
        match self {
            Self::Line(_) => Interval::new(f64::NEG_INFINITY, f64::INFINITY),
            Self::Circle(_) | Self::Ellipse(_) => Interval::new(0.0, TAU),
            Self::BSpline(b) => b.domain(),
        }
    }

    /// Period of a periodic curve (2π for circles and ellipses, the knot span of a periodic
    /// B-spline), `None` otherwise.
    #[must_use]
    pub fn period(&self) -> Option<f64> {
        match self {
            Self::Line(_) => None,
            Self::Circle(_) | Self::Ellipse(_) => Some(TAU),
            Self::BSpline(b) => b.period(),
        }
    }

    /// Point and first two derivatives at `t`. A B-spline clamps `t` into its domain (wraps it
    /// when periodic); conics and lines accept any finite `t`.
    #[must_use]
    pub fn derivs(&self, t: f64) -> CurveDerivs {
        match self {
            Self::Line(l) => CurveDerivs {
                p: l.origin + l.dir * t,
                d1: l.dir,
                d2: DVec3::ZERO,
            },
            Self::Circle(c) => ellipse_derivs(&c.frame, c.radius, c.radius, t),
            Self::Ellipse(e) => ellipse_derivs(&e.frame, e.semi_axis_1, e.semi_axis_2, t),
            Self::BSpline(b) => b.derivs(t),
        }
    }

    /// Point at `t`.
    #[must_use]
    pub fn point(&self, t: f64) -> DVec3 {
        match self {
            Self::BSpline(b) => b.point(t),
            _ => self.derivs(t).p,
        }
    }

    /// Parameter of the point on the curve closest to `p`, searched within `range` (robust: several
    /// seeds, bounded Newton, never NaN; for periodic curves the result is brought into `range`
    /// where possible).
    #[must_use]
    pub fn closest_param(&self, p: DVec3, range: Interval) -> f64 {
        projection::closest_param(self, p, range)
    }
}

/// `o + a cos t·x + b sin t·y` and its derivatives.
fn ellipse_derivs(f: &Frame, a: f64, b: f64, t: f64) -> CurveDerivs {
    let (s, c) = t.sin_cos();
    let cx = f.x * (a * c) + f.y * (b * s);
    CurveDerivs {
        p: f.origin + cx,
        d1: f.y * (b * c) - f.x * (a * s),
        d2: -cx,
    }
}
