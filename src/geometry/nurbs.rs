//! B-spline and NURBS curves and surfaces (The NURBS Book, Piegl & Tiller): knot span search,
//! basis functions with derivatives, rational quotient rule, iso-curves, bounding boxes.

use super::DVec3;

/// A B-spline or NURBS curve. `knots` is the full (expanded) knot vector:
/// `knots.len() == poles.len() + degree + 1`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BSplineCurve {
    /// Polynomial degree p ≥ 1.
    pub degree: usize,
    /// Expanded, non-decreasing knot vector.
    pub knots: Vec<f64>,
    /// Control points, mm.
    pub poles: Vec<DVec3>,
    /// Weights (one per pole) for a rational curve; `None` when polynomial.
    pub weights: Option<Vec<f64>>,
}

/// A B-spline or NURBS surface. Poles are stored u-major: pole (i, j) at `poles[i * n_v + j]`,
/// i along u (0..n_u), j along v (0..n_v).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BSplineSurface {
    /// Degree in u.
    pub degree_u: usize,
    /// Degree in v.
    pub degree_v: usize,
    /// Expanded u knot vector (`n_u + degree_u + 1` values).
    pub knots_u: Vec<f64>,
    /// Expanded v knot vector (`n_v + degree_v + 1` values).
    pub knots_v: Vec<f64>,
    /// Pole count along u.
    pub n_u: usize,
    /// Pole count along v.
    pub n_v: usize,
    /// Control points, mm, u-major.
    pub poles: Vec<DVec3>,
    /// Weights (u-major, one per pole) for a rational surface; `None` when polynomial.
    pub weights: Option<Vec<f64>>,
}
