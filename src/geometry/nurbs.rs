//! B-spline and NURBS curves and surfaces (The NURBS Book, Piegl & Tiller): knot span search,
//! basis functions with derivatives, rational quotient rule, iso-curves, bounding boxes.
//!
//! Evaluation clamps the parameter into the domain (periodic splines wrap instead), so it never
//! extrapolates, never allocates for degrees up to 15 and never panics, even on a hand-built
//! struct that skipped [`BSplineCurve::new`] (inconsistent data then evaluates to zeros).

mod basis;
mod curve_eval;
mod knots;
mod surface_eval;

pub use knots::{MAX_DEGREE, expand_knots};

use super::{DVec3, GeometryError};

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

/// Poles finite, weights (if any) one per pole, finite and positive.
fn check_poles(poles: &[DVec3], weights: Option<&[f64]>) -> Result<(), GeometryError> {
    if let Some(i) = poles.iter().position(|p| !p.is_finite()) {
        return Err(GeometryError::NonFinite(format!("pole {i}")));
    }
    if let Some(w) = weights {
        if w.len() != poles.len() {
            return Err(GeometryError::InvalidBSpline(format!(
                "{} weights for {} poles",
                w.len(),
                poles.len()
            )));
        }
        if let Some(i) = w.iter().position(|w| !w.is_finite()) {
            return Err(GeometryError::NonFinite(format!("weight {i}")));
        }
        if let Some(i) = w.iter().position(|&w| w <= 0.0) {
            return Err(GeometryError::InvalidBSpline(format!(
                "weight {i} is not positive"
            )));
        }
    }
    Ok(())
}

impl BSplineCurve {
    /// A validated curve: degree ≥ 1, `knots.len() == poles.len() + degree + 1`, finite
    /// non-decreasing knots with multiplicity ≤ degree + 1, a non-degenerate domain, finite poles
    /// and (if rational) one finite positive weight per pole.
    ///
    /// # Errors
    /// [`GeometryError::InvalidBSpline`] or [`GeometryError::NonFinite`] naming the problem.
    pub fn new(
        degree: usize,
        knots: Vec<f64>,
        poles: Vec<DVec3>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self, GeometryError> {
        knots::check_knots(&knots, degree, poles.len(), "curve")?;
        check_poles(&poles, weights.as_deref())?;
        Ok(Self {
            degree,
            knots,
            poles,
            weights,
        })
    }

    /// Check a curve built field by field (e.g. deserialised) as [`Self::new`] does.
    ///
    /// # Errors
    /// As [`Self::new`].
    pub fn validate(&self) -> Result<(), GeometryError> {
        knots::check_knots(&self.knots, self.degree, self.poles.len(), "curve")?;
        check_poles(&self.poles, self.weights.as_deref())
    }

    /// Rational (has weights)?
    #[must_use]
    pub fn is_rational(&self) -> bool {
        self.weights.is_some()
    }
}

impl BSplineSurface {
    /// A validated surface (poles u-major, `poles.len() == n_u · n_v`); the checks of
    /// [`BSplineCurve::new`] apply in each direction.
    ///
    /// # Errors
    /// [`GeometryError::InvalidBSpline`] or [`GeometryError::NonFinite`] naming the problem.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        degree_u: usize,
        degree_v: usize,
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        n_u: usize,
        n_v: usize,
        poles: Vec<DVec3>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self, GeometryError> {
        let s = Self {
            degree_u,
            degree_v,
            knots_u,
            knots_v,
            n_u,
            n_v,
            poles,
            weights,
        };
        s.validate()?;
        Ok(s)
    }

    /// Check a surface built field by field (e.g. deserialised) as [`Self::new`] does.
    ///
    /// # Errors
    /// As [`Self::new`].
    pub fn validate(&self) -> Result<(), GeometryError> {
        if self.n_u.checked_mul(self.n_v) != Some(self.poles.len()) {
            return Err(GeometryError::InvalidBSpline(format!(
                "{} poles for a {} × {} grid",
                self.poles.len(),
                self.n_u,
                self.n_v
            )));
        }
        knots::check_knots(&self.knots_u, self.degree_u, self.n_u, "u")?;
        knots::check_knots(&self.knots_v, self.degree_v, self.n_v, "v")?;
        check_poles(&self.poles, self.weights.as_deref())
    }

    /// Rational (has weights)?
    #[must_use]
    pub fn is_rational(&self) -> bool {
        self.weights.is_some()
    }
}
