//! Closed-form point and derivatives of the analytic surfaces, in Open CASCADE's
//! parameterisations (`ElSLib`), plus surfaces of revolution (Rodrigues rotation of the
//! meridian) and linear extrusions.

use super::{Extrusion, Revolution};
use crate::geometry::DVec3;
use crate::geometry::diffgeom::SurfaceDerivs;
use crate::geometry::frame::Frame;

/// `e(u) = cos u·x + sin u·y` and `e'(u) = −sin u·x + cos u·y`.
fn radial(f: &Frame, u: f64) -> (DVec3, DVec3) {
    let (s, c) = u.sin_cos();
    (f.x * c + f.y * s, f.y * c - f.x * s)
}

/// Plane `o + u·x + v·y`.
pub(super) fn plane(f: &Frame, u: f64, v: f64) -> SurfaceDerivs {
    let z = DVec3::ZERO;
    SurfaceDerivs {
        p: f.origin + f.x * u + f.y * v,
        su: f.x,
        sv: f.y,
        suu: z,
        suv: z,
        svv: z,
    }
}

/// Cylinder `o + r·e(u) + v·z`.
pub(super) fn cylinder(f: &Frame, r: f64, u: f64, v: f64) -> SurfaceDerivs {
    let (e, de) = radial(f, u);
    let z = DVec3::ZERO;
    SurfaceDerivs {
        p: f.origin + e * r + f.z * v,
        su: de * r,
        sv: f.z,
        suu: -e * r,
        suv: z,
        svv: z,
    }
}

/// Cone `o + (r + v sin a)·e(u) + v cos a·z` (`ElSLib::ConeValue`).
pub(super) fn cone(f: &Frame, r: f64, a: f64, u: f64, v: f64) -> SurfaceDerivs {
    let (e, de) = radial(f, u);
    let (sa, ca) = a.sin_cos();
    let rho = r + v * sa;
    SurfaceDerivs {
        p: f.origin + e * rho + f.z * (v * ca),
        su: de * rho,
        sv: e * sa + f.z * ca,
        suu: -e * rho,
        suv: de * sa,
        svv: DVec3::ZERO,
    }
}

/// Sphere `o + r cos v·e(u) + r sin v·z`.
pub(super) fn sphere(f: &Frame, r: f64, u: f64, v: f64) -> SurfaceDerivs {
    let (e, de) = radial(f, u);
    let (sv, cv) = v.sin_cos();
    let p = e * (r * cv) + f.z * (r * sv);
    SurfaceDerivs {
        p: f.origin + p,
        su: de * (r * cv),
        sv: f.z * (r * cv) - e * (r * sv),
        suu: -e * (r * cv),
        suv: -de * (r * sv),
        svv: -p,
    }
}

/// Torus `o + (R + r cos v)·e(u) + r sin v·z`.
pub(super) fn torus(f: &Frame, big_r: f64, r: f64, u: f64, v: f64) -> SurfaceDerivs {
    let (e, de) = radial(f, u);
    let (sv, cv) = v.sin_cos();
    let rho = big_r + r * cv;
    SurfaceDerivs {
        p: f.origin + e * rho + f.z * (r * sv),
        su: de * rho,
        sv: f.z * (r * cv) - e * (r * sv),
        suu: -e * rho,
        suv: -de * (r * sv),
        svv: -(e * (r * cv) + f.z * (r * sv)),
    }
}

/// Meridian `C(v)` rotated by `u` about the axis (right-handed about `axis_dir`):
/// `R(u)w = w cos u + (k × w) sin u + k (k·w)(1 − cos u)`, `w = C(v) − A`.
pub(super) fn revolution(s: &Revolution, u: f64, v: f64) -> SurfaceDerivs {
    let k = s.axis_dir.try_normalize().unwrap_or(DVec3::Z);
    let c = s.meridian.derivs(v);
    let (su_, cu) = u.sin_cos();
    let rot = |w: DVec3| w * cu + k.cross(w) * su_ + k * (k.dot(w) * (1.0 - cu));
    let drot = |w: DVec3| -w * su_ + k.cross(w) * cu + k * (k.dot(w) * su_);
    let ddrot = |w: DVec3| -w * cu - k.cross(w) * su_ + k * (k.dot(w) * cu);
    let w = c.p - s.axis_origin;
    SurfaceDerivs {
        p: s.axis_origin + rot(w),
        su: drot(w),
        sv: rot(c.d1),
        suu: ddrot(w),
        suv: drot(c.d1),
        svv: rot(c.d2),
    }
}

/// Extrusion `C(u) + v·d`.
pub(super) fn extrusion(s: &Extrusion, u: f64, v: f64) -> SurfaceDerivs {
    let c = s.profile.derivs(u);
    let z = DVec3::ZERO;
    SurfaceDerivs {
        p: c.p + s.dir * v,
        su: c.d1,
        sv: s.dir,
        suu: c.d2,
        suv: z,
        svv: z,
    }
}
