//! Differential geometry of a surface at a point: unit normal, first and second fundamental
//! forms, principal curvatures and directions, normal curvature in a tangent direction.
//!
//! Sign convention (as Open CASCADE's `GeomLProp_SLProps`): the normal is `S_u × S_v` normalised
//! and curvatures are signed with respect to it (k_min ≤ k_max, 1/mm).

use super::DVec3;

/// Point and partial derivatives up to second order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivs {
    /// S(u, v), mm.
    pub p: DVec3,
    /// ∂S/∂u.
    pub su: DVec3,
    /// ∂S/∂v.
    pub sv: DVec3,
    /// ∂²S/∂u².
    pub suu: DVec3,
    /// ∂²S/∂u∂v.
    pub suv: DVec3,
    /// ∂²S/∂v².
    pub svv: DVec3,
}

/// Principal curvatures and directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principal {
    /// Smaller principal curvature, 1/mm.
    pub k_min: f64,
    /// Larger principal curvature, 1/mm.
    pub k_max: f64,
    /// Unit 3D tangent direction of k_min.
    pub dir_min: DVec3,
    /// Unit 3D tangent direction of k_max.
    pub dir_max: DVec3,
}

/// Relative threshold below which `|S_u × S_v|` counts as zero (degenerate parameterisation).
const DEGENERATE: f64 = 1e-12;

impl SurfaceDerivs {
    /// Unit normal `S_u × S_v / |S_u × S_v|`, `None` where the parameterisation is degenerate
    /// (a pole, a collapsed edge, non-finite derivatives): `|S_u × S_v| ≤ 1e-12 (|S_u|² + |S_v|²)`.
    #[must_use]
    pub fn normal(&self) -> Option<DVec3> {
        let n = self.su.cross(self.sv);
        let len = n.length();
        // Scale-free test: |S_u × S_v| against |S_u|² + |S_v|² also catches a parameter direction
        // that has (numerically) collapsed, as at the pole of a sphere, where cos(π/2) ≠ 0.
        let scale = self.su.length_squared() + self.sv.length_squared();
        (len.is_finite() && len > DEGENERATE * scale && len > 0.0).then(|| n / len)
    }

    /// First fundamental form `(E, F, G) = (S_u·S_u, S_u·S_v, S_v·S_v)`.
    #[must_use]
    pub fn first_form(&self) -> (f64, f64, f64) {
        (
            self.su.dot(self.su),
            self.su.dot(self.sv),
            self.sv.dot(self.sv),
        )
    }

    /// Second fundamental form `(L, M, N) = (S_uu·n, S_uv·n, S_vv·n)` for the unit normal `n`.
    #[must_use]
    pub fn second_form(&self, n: DVec3) -> (f64, f64, f64) {
        (self.suu.dot(n), self.suv.dot(n), self.svv.dot(n))
    }

    /// Parametric components `(du, dv)` of a tangent vector `t` (least squares against
    /// `S_u`, `S_v`); `None` when the first form is singular.
    fn tangent_components(&self, t: DVec3) -> Option<(f64, f64)> {
        let (e, f, g) = self.first_form();
        let det = e * g - f * f;
        let regular = det > DEGENERATE * DEGENERATE * e * g && det > 0.0;
        if !regular {
            return None;
        }
        let (a, b) = (t.dot(self.su), t.dot(self.sv));
        let (du, dv) = ((g * a - f * b) / det, (e * b - f * a) / det);
        (du.is_finite() && dv.is_finite()).then_some((du, dv))
    }

    /// Principal curvatures and directions, signed with respect to the `S_u × S_v` normal as
    /// Open CASCADE's `GeomLProp_SLProps` (k_min ≤ k_max). Computed as the eigen-decomposition of
    /// the shape operator in an orthonormal tangent basis, so umbilics (any direction is
    /// principal) and flat points give well-defined orthogonal directions. `None` where the
    /// normal is undefined.
    #[must_use]
    pub fn principal(&self) -> Option<Principal> {
        let n = self.normal()?;
        let e1 = self.su.try_normalize()?;
        let e2 = n.cross(e1);
        let (l, m, nn) = self.second_form(n);
        let (a1, b1) = self.tangent_components(e1)?;
        let (a2, b2) = self.tangent_components(e2)?;
        let ii = |x: (f64, f64), y: (f64, f64)| {
            l * x.0 * y.0 + m * (x.0 * y.1 + x.1 * y.0) + nn * x.1 * y.1
        };
        // Shape operator in the orthonormal basis (e1, e2): symmetric [[a, b], [b, c]].
        let a = ii((a1, b1), (a1, b1));
        let b = ii((a1, b1), (a2, b2));
        let c = ii((a2, b2), (a2, b2));
        let mean = 0.5 * (a + c);
        let half_diff = 0.5 * (a - c);
        let rad = half_diff.hypot(b);
        let theta = 0.5 * b.atan2(half_diff);
        let (s, co) = theta.sin_cos();
        let dir_max = e1 * co + e2 * s;
        let dir_min = e2 * co - e1 * s;
        let out = Principal {
            k_min: mean - rad,
            k_max: mean + rad,
            dir_min,
            dir_max,
        };
        (out.k_min.is_finite() && out.k_max.is_finite()).then_some(out)
    }

    /// Normal curvature in the parametric direction `(du, dv)`:
    /// `(L du² + 2M du dv + N dv²) / (E du² + 2F du dv + G dv²)`; `None` where the normal is
    /// undefined or the direction has zero length on the surface.
    #[must_use]
    pub fn normal_curvature(&self, du: f64, dv: f64) -> Option<f64> {
        let n = self.normal()?;
        let (e, f, g) = self.first_form();
        let (l, m, nn) = self.second_form(n);
        let den = e * du * du + 2.0 * f * du * dv + g * dv * dv;
        let scale = (e + g) * (du * du + dv * dv);
        let regular = den > DEGENERATE * scale && den > 0.0;
        if !regular {
            return None;
        }
        let k = (l * du * du + 2.0 * m * du * dv + nn * dv * dv) / den;
        k.is_finite().then_some(k)
    }

    /// Normal curvature along the 3D direction `t` (projected into the tangent plane first);
    /// `None` when `t` is (nearly) along the normal or the normal is undefined.
    #[must_use]
    pub fn normal_curvature_along(&self, t: DVec3) -> Option<f64> {
        let n = self.normal()?;
        let tt = t - n * t.dot(n);
        let tangential = tt.length() > DEGENERATE * t.length();
        if !tangential {
            return None;
        }
        let (du, dv) = self.tangent_components(tt)?;
        self.normal_curvature(du, dv)
    }

    /// Mean and Gaussian curvature `(H, K) = ((k_min + k_max)/2, k_min·k_max)`, signed as
    /// [`Self::principal`].
    #[must_use]
    pub fn mean_gaussian(&self) -> Option<(f64, f64)> {
        let p = self.principal()?;
        Some((0.5 * (p.k_min + p.k_max), p.k_min * p.k_max))
    }
}
