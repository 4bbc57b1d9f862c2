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

mod analytic;
mod projection;

use std::f64::consts::{FRAC_PI_2, TAU};

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
        let all = Interval::new(f64::NEG_INFINITY, f64::INFINITY);
        let turn = Interval::new(0.0, TAU);
        let (u, v) = match self {
            Self::BSpline(b) => {
                let d = b.domain();
                (d.u, d.v)
            }
            Self::Plane(_) => (all, all),
            Self::Cylinder(_) | Self::Cone(_) => (turn, all),
            Self::Sphere(_) => (turn, Interval::new(-FRAC_PI_2, FRAC_PI_2)),
            Self::Torus(_) => (turn, turn),
            Self::Revolution(r) => (turn, r.meridian.domain()),
            Self::Extrusion(e) => (e.profile.domain(), all),
        };
        ParamRect { u, v }
    }

    /// Periods in u and v (`None` where not periodic).
    #[must_use]
    pub fn periods(&self) -> (Option<f64>, Option<f64>) {
        match self {
            Self::BSpline(b) => b.periods(),
            Self::Plane(_) => (None, None),
            Self::Cylinder(_) | Self::Cone(_) | Self::Sphere(_) => (Some(TAU), None),
            Self::Torus(_) => (Some(TAU), Some(TAU)),
            Self::Revolution(r) => (Some(TAU), r.meridian.period()),
            Self::Extrusion(e) => (e.profile.period(), None),
        }
    }

    /// Point and derivatives up to second order at `(u, v)`. Analytic surfaces accept any finite
    /// parameters; B-splines (and the curves inside revolutions and extrusions) clamp into their
    /// domain or wrap when periodic.
    #[must_use]
    pub fn derivs(&self, u: f64, v: f64) -> SurfaceDerivs {
        match self {
            Self::BSpline(b) => b.derivs(u, v),
            Self::Plane(s) => analytic::plane(&s.frame, u, v),
            Self::Cylinder(s) => analytic::cylinder(&s.frame, s.radius, u, v),
            Self::Cone(s) => analytic::cone(&s.frame, s.radius, s.semi_angle, u, v),
            Self::Sphere(s) => analytic::sphere(&s.frame, s.radius, u, v),
            Self::Torus(s) => analytic::torus(&s.frame, s.major_radius, s.minor_radius, u, v),
            Self::Revolution(s) => analytic::revolution(s, u, v),
            Self::Extrusion(s) => analytic::extrusion(s, u, v),
        }
    }

    /// Point at `(u, v)`.
    #[must_use]
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        match self {
            Self::BSpline(b) => b.point(u, v),
            _ => self.derivs(u, v).p,
        }
    }

    /// Closest point on the surface to `p` within `rect` (robust: several seeds, bounded Newton,
    /// never NaN). `hint` is a starting guess, e.g. the previous answer when walking along a curve.
    /// Infinite ends of `rect` are allowed. For a cheaper local search from a good guess, see
    /// [`Self::closest_point_near`].
    #[must_use]
    pub fn closest_point(&self, p: DVec3, rect: ParamRect, hint: Option<DVec2>) -> SurfacePoint {
        projection::closest_point(self, p, rect, hint)
    }

    /// Local closest point: bounded Newton from `start` only (no global seeding), for walking
    /// along a curve where the previous answer is a good guess. Never NaN; may return a local
    /// minimum of the distance.
    #[must_use]
    pub fn closest_point_near(&self, p: DVec3, rect: ParamRect, start: DVec2) -> SurfacePoint {
        projection::closest_point_near(self, p, rect, start)
    }
}
