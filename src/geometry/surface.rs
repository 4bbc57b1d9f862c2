//! Parametric surfaces: B-spline/NURBS and the analytic kinds STEP carries, with one evaluation
//! interface (point, derivatives to second order, domain, periodicity, point inversion).
//!
//! Parameterisations follow Open CASCADE's (so `(u, v)` agree with OCCT's for the same STEP data):
//! - plane: `o + u·x + v·y`
//! - cylinder: `o + r(cos u·x + sin u·y) + v·z`
//! - cone: `o + (r + v sin a)(cos u·x + sin u·y) + v cos a·z`
//! - sphere: `o + r cos v(cos u·x + sin u·y) + r sin v·z`, v ∈ [−π/2, π/2]
//! - torus: `o + (R + r cos v)(cos u·x + sin u·y) + r sin v·z`
//! - revolution: the meridian curve `C(v)` rotated by angle `u` about the axis
//! - extrusion: `C(u) + v·d` (d unit)

use super::curve::CurveGeom;
use super::diffgeom::SurfaceDerivs;
use super::nurbs::BSplineSurface;
use super::{DVec2, DVec3, Interval, frame::Frame};

/// A rectangle in parameter space.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ParamRect {
    /// u interval.
    pub u: Interval,
    /// v interval.
    pub v: Interval,
}

/// Plane through `frame.origin` spanned by `frame.x`, `frame.y`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plane {
    /// Placement.
    pub frame: Frame,
}

/// Circular cylinder around `frame.z`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cylinder {
    /// Placement.
    pub frame: Frame,
    /// Radius, mm.
    pub radius: f64,
}

/// Circular cone around `frame.z`; `radius` at the placement origin, `semi_angle` in rad.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cone {
    /// Placement.
    pub frame: Frame,
    /// Radius at v = 0, mm.
    pub radius: f64,
    /// Half apex angle, rad.
    pub semi_angle: f64,
}

/// Sphere centred at `frame.origin`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sphere {
    /// Placement.
    pub frame: Frame,
    /// Radius, mm.
    pub radius: f64,
}

/// Torus around `frame.z`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Torus {
    /// Placement.
    pub frame: Frame,
    /// Distance from the axis to the tube centre, mm.
    pub major_radius: f64,
    /// Tube radius, mm.
    pub minor_radius: f64,
}

/// Surface of revolution: `meridian` rotated about the axis through `axis_origin` along `axis_dir`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Revolution {
    /// The generating curve (parameter v).
    pub meridian: Box<CurveGeom>,
    /// A point on the axis.
    pub axis_origin: DVec3,
    /// Unit axis direction.
    pub axis_dir: DVec3,
}

/// Linear extrusion: `profile(u) + v·dir`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Extrusion {
    /// The swept curve (parameter u).
    pub profile: Box<CurveGeom>,
    /// Unit sweep direction.
    pub dir: DVec3,
}

/// Any surface Talas can evaluate.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum SurfaceGeom {
    /// B-spline or NURBS surface.
    BSpline(BSplineSurface),
    /// Plane.
    Plane(Plane),
    /// Cylinder.
    Cylinder(Cylinder),
    /// Cone.
    Cone(Cone),
    /// Sphere.
    Sphere(Sphere),
    /// Torus.
    Torus(Torus),
    /// Surface of revolution.
    Revolution(Revolution),
    /// Linear extrusion.
    Extrusion(Extrusion),
}

/// Result of a point inversion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Parameters of the closest point.
    pub uv: DVec2,
    /// The closest point, mm.
    pub point: DVec3,
    /// Distance from the query point, mm.
    pub distance: f64,
}

impl SurfaceGeom {
    /// Short kind name used in reports (`bspline`, `plane`, `cylinder`, ...).
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Self::BSpline(_) => "bspline",
            Self::Plane(_) => "plane",
            Self::Cylinder(_) => "cylinder",
            Self::Cone(_) => "cone",
            Self::Sphere(_) => "sphere",
            Self::Torus(_) => "torus",
            Self::Revolution(_) => "revolution",
            Self::Extrusion(_) => "extrusion",
        }
    }

    /// Natural parameter domain (infinite in the unbounded directions of planes, cylinders,
    /// cones and extrusions).
    #[must_use]
    pub fn domain(&self) -> ParamRect {
        todo!("geometry helper")
    }

    /// Periods in u and v (`None` where not periodic).
    #[must_use]
    pub fn periods(&self) -> (Option<f64>, Option<f64>) {
        todo!("geometry helper")
    }

    /// Point and derivatives up to second order at `(u, v)`.
    #[must_use]
    pub fn derivs(&self, u: f64, v: f64) -> SurfaceDerivs {
        let _ = (u, v);
        todo!("geometry helper")
    }

    /// Point at `(u, v)`.
    #[must_use]
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        self.derivs(u, v).p
    }

    /// Closest point on the surface to `p` within `rect` (robust: several seeds, bounded Newton,
    /// never NaN). `hint` is a starting guess, e.g. the previous answer when walking along a curve.
    #[must_use]
    pub fn closest_point(&self, p: DVec3, rect: ParamRect, hint: Option<DVec2>) -> SurfacePoint {
        let _ = (p, rect, hint);
        todo!("geometry helper")
    }
}
