//! Corner blending: a sharp junction between two straight segments is replaced by a pair of
//! mirrored clothoids (Euler spirals), a curve that is tangent and curvature continuous with both
//! lines (curvature 0 where it meets them), so the centripetal acceleration ramps up from 0
//! instead of stepping, and the axis jerk stays bounded.
//!
//! For a corner `P` turning by `θ` (angle between the incoming direction `t0` and the outgoing
//! `t1`), each clothoid has length `L` and curvature `κ(s) = c·s` with `c = θ/L²`, so it turns
//! by `θ/2`; the heading is `φ(s) = c·s²/2`. In the plane of the corner with the inward normal
//! `n0`, the first clothoid is `A + t0·X(s) + n0·Y(s)` with the Fresnel-type integrals
//! `X + iY = ∫₀ˢ e^{iφ(u)} du = s·Σₙ (iφ)ⁿ / (n!·(2n+1))` (φ ≤ π/2, at most 26 terms reach
//! round-off), and the second is its mirror image from the end point `B`. With the unit-length
//! values `x̂ = X(1)`, `ŷ = Y(1)` (for `c = θ`), everything scales with `L`:
//! - set-back from the corner along each line: `d = L·(x̂ + ŷ·tan(θ/2))`,
//! - distance from the corner to the curve (its mid point, the largest distance from the
//!   polyline): `L·ŷ / cos(θ/2)`; it is set to the tolerance δ, then `L` is shrunk if `d`
//!   would exceed half of either adjacent segment.
//!
//! The per-axis bounds on `q'`, `q''`, `q'''` along the blend (exact over the swept heading) feed
//! the same tangential-limit construction as arcs (see [`super::path`]): centripetal
//! acceleration `κ·v²` and its rate `c·v³ + κ²·v³ + 3κ·v·a` stay within every axis's limits.

use glam::DVec3;

use super::path::{JointVector, SLOTS};

/// Turning angles at or below this are continued without a blend (the velocity kink it leaves
/// is below round-off of the position).
pub const MIN_TURN_RAD: f64 = 1e-10;

/// Turning angles above `π − MAX_TURN_MARGIN_RAD` are reversals: exact stop.
pub const MAX_TURN_MARGIN_RAD: f64 = 1e-6;

/// A clothoid-pair corner blend in Cartesian space, parameterised by arc length `s ∈ [0, 2L]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClothoidBlend {
    /// Start point (on the incoming line, `d` before the corner).
    pub start: DVec3,
    /// End point (on the outgoing line, `d` after the corner).
    pub end: DVec3,
    /// Incoming unit direction.
    pub t0: DVec3,
    /// Unit normal of the incoming line in the corner's plane, pointing into the corner.
    pub n0: DVec3,
    /// Outgoing unit direction.
    pub t1: DVec3,
    /// Unit normal of the outgoing line in the corner's plane, pointing into the corner.
    pub n1: DVec3,
    /// Length of each clothoid (mm); the blend is `2·half_length` long.
    pub half_length: f64,
    /// Curvature rate `c = θ/L²` (1/mm²).
    pub sharpness: f64,
    /// Turning angle θ (rad).
    pub turn_rad: f64,
    /// Set-back `d` from the corner along each line (mm).
    pub setback: f64,
    /// Distance from the corner to the blend's mid point (mm), ≤ the tolerance.
    pub deviation: f64,
    /// The corner point.
    pub corner: DVec3,
    /// Per axis X Y Z: the largest `|q'|` over the swept heading.
    pub tangent_max: [f64; 3],
    /// Per axis X Y Z: the largest component of the unit normal over the swept heading.
    pub normal_max: [f64; 3],
    /// Set-back per unit half length, `x̂ + ŷ·tan(θ/2)`.
    setback_unit: f64,
    /// Deviation per unit half length, `ŷ/cos(θ/2)`.
    deviation_unit: f64,
}

/// Terms of the series in [`fresnel`]: enough for φ ≤ π/2.
const FRESNEL_TERMS: usize = 26;

/// `1/(2n + 1)` for the series' terms.
const INV_ODD: [f64; FRESNEL_TERMS] = {
    let mut t = [0.0; FRESNEL_TERMS];
    let mut n = 0;
    while n < FRESNEL_TERMS {
        t[n] = 1.0 / (2 * n + 1) as f64;
        n += 1;
    }
    t
};

/// `1/(n + 1)` for the series' factorials.
const INV_NEXT: [f64; FRESNEL_TERMS] = {
    let mut t = [0.0; FRESNEL_TERMS];
    let mut n = 0;
    while n < FRESNEL_TERMS {
        t[n] = 1.0 / (n + 1) as f64;
        n += 1;
    }
    t
};

/// `X(s), Y(s)` of a clothoid with curvature rate `c` from curvature 0 (heading 0). The series
/// stops once the next factor `φⁿ/n!` is below round-off of both sums (`X ≈ 1`, `Y ≈ φ/3` per
/// unit length), after a handful of terms for the small turns of dense programs.
fn fresnel(c: f64, s: f64) -> (f64, f64) {
    let phi = 0.5 * c * s * s;
    let stop = 3e-18 * phi.min(1.0);
    // p = φⁿ/n!, multiplied by iⁿ: the sign pattern is +X, +Y, −X, −Y, ... (four terms per
    // round, each followed by the stop test).
    let (mut x, mut y, mut p) = (0.0, 0.0, 1.0);
    let mut n = 0;
    // One term: add it with its sign, advance p; false once the series stops.
    let mut step = |acc: &mut f64, negative: bool| {
        let term = p * INV_ODD[n];
        if negative {
            *acc -= term;
        } else {
            *acc += term;
        }
        p *= phi * INV_NEXT[n];
        n += 1;
        !(p <= stop || n == FRESNEL_TERMS)
    };
    while step(&mut x, false) && step(&mut y, false) && step(&mut x, true) && step(&mut y, true) {}
    (s * x, s * y)
}

/// Largest `|p·cos ψ + q·sin ψ|` over `ψ ∈ [0, hi]`, `0 ≤ hi < π`, given `cos hi` and `sin hi`.
/// The peak `|(p, q)|` is reached where `(cos ψ, sin ψ)` is parallel to `±(p, q)`: when one of
/// the two lies in the swept sector (upper half-plane, not past `hi`), else at an end.
fn max_abs_harmonic(p: f64, q: f64, cos_hi: f64, sin_hi: f64) -> f64 {
    let past = p * sin_hi - q * cos_hi;
    if (q >= 0.0 && past >= 0.0) || (q <= 0.0 && past <= 0.0) {
        return p.hypot(q);
    }
    p.abs().max((p * cos_hi + q * sin_hi).abs())
}

impl ClothoidBlend {
    /// The blend at corner `corner` between directions `t0` → `t1` (unit) with tolerance
    /// `tolerance` (mm) and at most `max_setback` along either line; `None` when the corner is
    /// too shallow to need one, a reversal, or the input is degenerate.
    #[must_use]
    // One index walks several parallel arrays; an iterator chain would hide that.
    #[allow(clippy::needless_range_loop)]
    pub fn new(
        corner: DVec3,
        t0: DVec3,
        t1: DVec3,
        tolerance: f64,
        max_setback: f64,
    ) -> Option<Self> {
        let cos = t0.dot(t1).clamp(-1.0, 1.0);
        let perp0 = t1 - t0 * cos;
        let sin = perp0.length();
        let turn = sin.atan2(cos);
        let ok = tolerance.is_finite() && tolerance > 0.0 && max_setback.is_finite();
        if !ok
            || !(turn > MIN_TURN_RAD)
            || turn >= std::f64::consts::PI - MAX_TURN_MARGIN_RAD
            || !(max_setback > 0.0)
        {
            return None;
        }
        let n0 = perp0 / sin;
        let n1 = -(t0 - t1 * cos).normalize_or_zero();
        let (xh, yh) = fresnel(turn, 1.0);
        // sin and cos of θ/2 by the half-angle formulas, each root taken where its radicand
        // does not cancel (1 + cos θ ≥ 1 or 1 − cos θ ≥ 1).
        let (sh, ch) = if cos >= 0.0 {
            let ch = (0.5 * (1.0 + cos)).sqrt();
            (0.5 * sin / ch, ch)
        } else {
            let sh = (0.5 * (1.0 - cos)).sqrt();
            (sh, 0.5 * sin / sh)
        };
        // Set-back per unit L: x̂ + ŷ·tan(θ/2); deviation per unit L: ŷ/cos(θ/2).
        let setback_unit = xh + yh * sh / ch;
        let deviation_unit = yh / ch;
        let half_length = (tolerance / deviation_unit).min(max_setback / setback_unit);
        if !(half_length.is_finite() && half_length > 0.0) {
            return None;
        }
        let mut tangent_max = [0.0; 3];
        let mut normal_max = [0.0; 3];
        for k in 0..3 {
            // Tangent: t0·cos ψ + n0·sin ψ; normal: −t0·sin ψ + n0·cos ψ, ψ ∈ [0, θ].
            tangent_max[k] = max_abs_harmonic(t0[k], n0[k], cos, sin);
            normal_max[k] = max_abs_harmonic(n0[k], -t0[k], cos, sin);
        }
        let unit = Self {
            start: corner,
            end: corner,
            t0,
            n0,
            t1,
            n1,
            half_length: 1.0,
            sharpness: turn,
            turn_rad: turn,
            setback: setback_unit,
            deviation: deviation_unit,
            corner,
            tangent_max,
            normal_max,
            setback_unit,
            deviation_unit,
        };
        Some(unit.with_half_length(half_length))
    }

    /// The same corner's blend with another half length.
    #[must_use]
    #[inline]
    pub fn with_half_length(&self, half_length: f64) -> Self {
        let setback = half_length * self.setback_unit;
        Self {
            start: self.corner - self.t0 * setback,
            end: self.corner + self.t1 * setback,
            half_length,
            sharpness: self.turn_rad / (half_length * half_length),
            setback,
            deviation: half_length * self.deviation_unit,
            ..*self
        }
    }

    /// The same corner's blend shrunk to `deviation` (mm), if that is smaller (no new
    /// series evaluation: everything scales with the half length).
    #[must_use]
    pub fn shrunk_to(&self, deviation: f64) -> Option<Self> {
        (deviation > 0.0 && deviation < self.deviation)
            .then(|| self.with_half_length(deviation / self.deviation_unit))
    }

    /// Arc length of the blend (mm).
    #[must_use]
    pub fn length(&self) -> f64 {
        2.0 * self.half_length
    }

    /// Deviation per unit half length, `ŷ/cos(θ/2)` ([`ClothoidBlend::shrunk_to`] divides by it).
    #[must_use]
    pub fn deviation_unit(&self) -> f64 {
        self.deviation_unit
    }

    /// Position and its first three derivatives with respect to arc length at `s`, in the
    /// X Y Z slots.
    #[must_use]
    pub fn derivatives(&self, s: f64) -> [JointVector; 4] {
        self.curve().derivatives(s)
    }

    /// The curve alone, in the compact form a planned segment keeps.
    #[must_use]
    pub fn curve(&self) -> BlendCurve {
        BlendCurve {
            corner: self.corner,
            t0: self.t0,
            t1: self.t1,
            setback: self.setback,
            half_length: self.half_length,
            sharpness: self.sharpness,
        }
    }

    /// Per-axis bounds `(|q'|, |q''|, |q'''|)` over the blend in the X Y Z slots (exact over
    /// the swept heading for `q'` and the normal direction).
    #[must_use]
    // One index walks several parallel arrays; an iterator chain would hide that.
    #[allow(clippy::needless_range_loop)]
    pub fn derivative_bounds(&self) -> [JointVector; 3] {
        let kappa_max = self.sharpness * self.half_length;
        let mut out = [[0.0; SLOTS]; 3];
        for k in 0..3 {
            let (tan_max, nor_max) = (self.tangent_max[k], self.normal_max[k]);
            out[0][k] = tan_max;
            out[1][k] = kappa_max * nor_max;
            out[2][k] = self.sharpness * nor_max + kappa_max * kappa_max * tan_max;
        }
        out
    }
}

/// The curve of a [`ClothoidBlend`] as a planned segment keeps it: the corner, both directions
/// and the size. The end points and the in-plane normals are recomputed from these with the
/// same arithmetic as [`ClothoidBlend::new`], so they are bit for bit the blend's own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlendCurve {
    /// The corner point.
    pub corner: DVec3,
    /// Incoming unit direction.
    pub t0: DVec3,
    /// Outgoing unit direction.
    pub t1: DVec3,
    /// Set-back `d` from the corner along each line (mm).
    pub setback: f64,
    /// Length of each clothoid (mm).
    pub half_length: f64,
    /// Curvature rate `c = θ/L²` (1/mm²).
    pub sharpness: f64,
}

impl BlendCurve {
    /// Start point (on the incoming line, `d` before the corner).
    #[must_use]
    pub fn start(&self) -> DVec3 {
        self.corner - self.t0 * self.setback
    }

    /// End point (on the outgoing line, `d` after the corner).
    #[must_use]
    pub fn end(&self) -> DVec3 {
        self.corner + self.t1 * self.setback
    }

    /// Unit normals of the incoming and the outgoing line in the corner's plane, pointing into
    /// the corner.
    #[must_use]
    pub fn normals(&self) -> (DVec3, DVec3) {
        let cos = self.t0.dot(self.t1).clamp(-1.0, 1.0);
        let perp0 = self.t1 - self.t0 * cos;
        let n0 = perp0 / perp0.length();
        let n1 = -(self.t0 - self.t1 * cos).normalize_or_zero();
        (n0, n1)
    }

    /// Arc length (mm).
    #[must_use]
    pub fn length(&self) -> f64 {
        2.0 * self.half_length
    }

    /// Position and its first three derivatives with respect to arc length at `s`, in the
    /// X Y Z slots.
    #[must_use]
    // One index walks several parallel arrays; an iterator chain would hide that.
    #[allow(clippy::needless_range_loop)]
    pub fn derivatives(&self, s: f64) -> [JointVector; 4] {
        let l = self.half_length;
        let c = self.sharpness;
        let s = s.clamp(0.0, 2.0 * l);
        let (n0, n1) = self.normals();
        // First half from the start, second half mirrored from the end (r runs backwards).
        let (origin, t, n, r, sign) = if s <= l {
            (self.start(), self.t0, n0, s, 1.0)
        } else {
            (self.end(), self.t1, n1, 2.0 * l - s, -1.0)
        };
        let (x, y) = fresnel(c, r);
        let kappa = c * r;
        let (sp, cp) = (0.5 * c * r * r).sin_cos();
        // Local derivatives with respect to r.
        let (x1, y1) = (cp, sp);
        let (x2, y2) = (-kappa * sp, kappa * cp);
        let (x3, y3) = (-c * sp - kappa * kappa * cp, c * cp - kappa * kappa * sp);
        // Q(s) = origin + sign·t·X(r) + n·Y(r) with r = s (first half) or 2L − s (second):
        // each derivative with respect to s picks up a factor dr/ds = sign.
        let p = origin + t * (sign * x) + n * y;
        let d1 = t * x1 + n * (sign * y1);
        let d2 = t * (sign * x2) + n * y2;
        let d3 = t * x3 + n * (sign * y3);
        let mut out = [[0.0; SLOTS]; 4];
        for k in 0..3 {
            out[0][k] = p[k];
            out[1][k] = d1[k];
            out[2][k] = d2[k];
            out[3][k] = d3[k];
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vec(v: JointVector) -> DVec3 {
        DVec3::new(v[0], v[1], v[2])
    }

    #[test]
    fn blend_meets_lines_g2_and_keeps_tolerance() {
        let t0 = DVec3::X;
        let t1 = DVec3::new(0.3, 0.8, -0.2).normalize();
        let p = DVec3::new(1.0, 2.0, 3.0);
        let b = ClothoidBlend::new(p, t0, t1, 0.05, 10.0).unwrap();
        let d0 = b.derivatives(0.0);
        let d1 = b.derivatives(b.length());
        assert!(vec(d0[0]).distance(b.start) < 1e-14);
        assert!(
            vec(d1[0]).distance(b.end) < 1e-12,
            "{}",
            vec(d1[0]).distance(b.end)
        );
        assert!(vec(d0[1]).distance(t0) < 1e-15 && vec(d1[1]).distance(t1) < 1e-12);
        assert!(vec(d0[2]).length() < 1e-15 && vec(d1[2]).length() < 1e-12);
        // Mid point at the tolerance from the corner, halves meet continuously.
        let l = b.half_length;
        let (a, c) = (
            b.derivatives(l * (1.0 - 1e-12)),
            b.derivatives(l * (1.0 + 1e-12)),
        );
        for i in 0..3 {
            assert!(vec(a[i]).distance(vec(c[i])) < 1e-9 * (1.0 + vec(a[i]).length()));
        }
        assert!((vec(b.derivatives(l)[0]).distance(p) - 0.05).abs() < 1e-12);
        // Finite differences of the position agree with the derivatives (arc length).
        let h = 1e-5;
        for s in [0.1 * l, 0.7 * l, 1.4 * l] {
            let f = |x: f64| vec(b.derivatives(x)[0]);
            let fd = (f(s + h) - f(s - h)) / (2.0 * h);
            assert!(fd.distance(vec(b.derivatives(s)[1])) < 1e-8);
            assert!((vec(b.derivatives(s)[1]).length() - 1.0).abs() < 1e-14);
            let g = |x: f64| vec(b.derivatives(x)[1]);
            let fd2 = (g(s + h) - g(s - h)) / (2.0 * h);
            assert!(fd2.distance(vec(b.derivatives(s)[2])) < 1e-6 * (1.0 + fd2.length()));
        }
        // Set-back caps the size.
        let small = ClothoidBlend::new(p, t0, t1, 0.05, 0.01).unwrap();
        assert!((small.setback - 0.01).abs() < 1e-15 && small.deviation < 0.05);
        assert!(ClothoidBlend::new(p, t0, -t0, 0.05, 1.0).is_none());
        assert!(ClothoidBlend::new(p, t0, t0, 0.05, 1.0).is_none());
    }

    #[test]
    fn harmonic_bound_is_the_maximum() {
        let mut cases = vec![(1.0, 0.0, 1.0), (0.3, -0.7, 2.5), (-0.2, 0.4, 0.3)];
        // (p, q) all round the circle, sectors from narrow to nearly a half turn.
        for i in 0..24 {
            let a = f64::from(i) * std::f64::consts::PI / 12.0 + 0.1;
            for hi in [0.05, 0.8, 1.6, 3.0] {
                cases.push((0.7 * a.cos(), 0.7 * a.sin(), hi));
            }
        }
        for (p, q, hi) in cases {
            let brute = (0..=10_000)
                .map(|i| {
                    let psi = hi * f64::from(i) / 10_000.0;
                    (p * psi.cos() + q * psi.sin()).abs()
                })
                .fold(0.0, f64::max);
            let m = max_abs_harmonic(p, q, hi.cos(), hi.sin());
            assert!(m >= brute - 1e-12 && m <= brute + 1e-6, "{m} {brute}");
        }
    }
}
