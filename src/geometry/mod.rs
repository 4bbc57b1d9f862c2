//! L0 geometry kernel: parametric curves and surfaces (B-spline/NURBS and the analytic kinds STEP
//! carries), their differential geometry, point inversion, tessellation, boundary representation
//! (faces trimmed by edge loops) and triangle meshes with a BVH.
//!
//! All lengths in mm, angles in rad. Points and vectors are `glam::DVec3` (f64).

pub mod brep;
pub mod bvh;
pub mod curve;
pub mod diffgeom;
pub mod frame;
pub mod mesh;
pub mod minimize;
pub mod nurbs;
pub mod planar;
pub mod rigid;
pub mod stock;
pub mod surface;
pub mod tessellate;
pub mod trim;
pub mod zmap;

pub use glam::{DVec2, DVec3};

/// A closed parameter interval `[t0, t1]` (t0 ≤ t1; either end may be infinite for unbounded
/// analytic geometry such as a line or a plane).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Interval {
    /// Lower end.
    pub t0: f64,
    /// Upper end.
    pub t1: f64,
}

impl Interval {
    /// `[t0, t1]`.
    #[must_use]
    pub const fn new(t0: f64, t1: f64) -> Self {
        Self { t0, t1 }
    }

    /// Length `t1 - t0`.
    #[must_use]
    pub fn len(&self) -> f64 {
        self.t1 - self.t0
    }

    /// Is the interval empty or degenerate (zero length)?
    #[must_use]
    pub fn is_empty(&self) -> bool {
        !(self.t1 > self.t0)
    }

    /// Both ends finite?
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.t0.is_finite() && self.t1.is_finite()
    }

    /// Clamp `t` into the interval.
    #[must_use]
    pub fn clamp(&self, t: f64) -> f64 {
        t.max(self.t0).min(self.t1)
    }

    /// The parameter at fraction `s` (0 → t0, 1 → t1).
    #[must_use]
    pub fn lerp(&self, s: f64) -> f64 {
        self.t0 + (self.t1 - self.t0) * s
    }
}

/// Axis-aligned bounding box in mm.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aabb {
    /// Minimum corner.
    pub min: DVec3,
    /// Maximum corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (adding any point makes it that point).
    pub const EMPTY: Self = Self {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    /// Grow to contain `p`.
    pub fn add(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// Grow to contain another box.
    pub fn union(&mut self, other: &Self) {
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }

    /// Box around points (EMPTY for none).
    pub fn from_points<'a>(pts: impl IntoIterator<Item = &'a DVec3>) -> Self {
        let mut b = Self::EMPTY;
        for p in pts {
            b.add(*p);
        }
        b
    }

    /// No point added yet?
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// Diagonal length (0 for an empty box).
    #[must_use]
    pub fn diagonal(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            (self.max - self.min).length()
        }
    }
}

/// Errors from building or querying geometry.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GeometryError {
    /// B-spline data is inconsistent (knot count, degree, weights, ...).
    #[error("invalid B-spline: {0}")]
    InvalidBSpline(String),
    /// A direction or vector of zero length where a direction was needed.
    #[error("zero-length vector where a direction is needed")]
    ZeroVector,
    /// A non-finite number (NaN or infinite) in the input.
    #[error("non-finite value in geometry: {0}")]
    NonFinite(String),
    /// A radius or other length that must be positive was not.
    #[error("invalid dimension: {0}")]
    InvalidDimension(String),
}
