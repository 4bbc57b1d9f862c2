//! Effective cutting radius and the cross-feed profile of a cutter at a contact point.
//!
//! A cutter moving along the feed `f` sweeps an envelope whose section across the feed (in the
//! plane ⟂ f) is the outline of the cutter projected along `f`. Ball, flat and bull-nose cutters
//! are `disc(R_f) ⊕ ball(r_c)` at the bottom (R_f the flat radius, r_c the corner radius: ball
//! R_f = 0, r_c = R; flat r_c = 0), so that outline is the projected corner-centre circle (an
//! ellipse, the image of a circle under the 2×2 map `M`) offset by r_c.
//!
//! **Exact effective radius.** With the contact normal `n` (unit, pointing from the surface to
//! the tool) and the cross direction `t = n × f`, `M = R_f [[e1·t, e2·t], [e1·n, e2·n]]` for an
//! orthonormal pair `e1, e2 ⟂ a`. The radius of curvature of an ellipse `M·S¹` at the point
//! whose outward normal is `ν` is `det(M)² / |Mᵀν|³`; at the contact `ν = −n`, `|Mᵀν| =
//! R_f √(1 − (a·n)²)` and `det M = R_f² (a·(t × n)) = R_f² (a·f)`, so
//!
//! `r_eff = r_c + R_f (a·f)² / (1 − (a·n)²)^{3/2}`.
//!
//! With lead S only (`a = cos S n + sin S f`) this is `r_c + R_f / sin S`: the thesis's `r/sin S`
//! for a flat end mill and `R/sin α + r` for a bull-nose (Rao 1997). With a sideways tilt the
//! `(a·f)²` factor shrinks the radius (pure tilt leaves only the corner, `r_eff = r_c`). This is
//! the curvature of the swept envelope's section, which is what sets the scallop; the normal
//! curvature of the cutter's own surface in direction `t` (Euler's formula on the torus) agrees
//! with it only without tilt.

use glam::{DVec2, DVec3};

use super::{Cutter, CutterKind};

/// Flat radius R_f and corner radius r_c of the cutting end (ball: 0, R; flat: R, 0;
/// bull-nose: R − r, r); `None` for cones.
#[must_use]
pub fn torus_radii(cutter: &Cutter) -> Option<(f64, f64)> {
    match cutter.kind {
        CutterKind::Ball => Some((0.0, cutter.radius())),
        CutterKind::Flat => Some((cutter.radius(), 0.0)),
        CutterKind::BullNose { corner_radius } => {
            Some((cutter.radius() - corner_radius, corner_radius))
        }
        CutterKind::Cone { .. } => None,
    }
}

/// Exact effective cutting radius across the feed (see the module docs): `r_c + R_f (a·f)² /
/// (1 − (a·n)²)^{3/2}`, mm. `axis`, `normal` and `feed` must be unit vectors, `feed ⟂ normal`.
/// Infinite for a flat bottom lying on the surface (`a = n`); `None` for cones.
#[must_use]
pub fn effective_radius(cutter: &Cutter, axis: DVec3, normal: DVec3, feed: DVec3) -> Option<f64> {
    let (rf, rc) = torus_radii(cutter)?;
    if rf == 0.0 {
        return Some(rc);
    }
    let an = axis.dot(normal).clamp(-1.0, 1.0);
    let s2 = 1.0 - an * an;
    if s2 <= 1e-18 {
        return Some(f64::INFINITY);
    }
    let af = axis.dot(feed);
    Some(rc + rf * af * af / (s2 * s2.sqrt()))
}

/// The tool tip for a contact at `cc` with surface normal `normal` (toward the tool) and tool
/// axis `axis`: `tip = cc + r_c (n − a) + R_f (n − (a·n)a)/|n − (a·n)a|` (Choi 1998, eq. 3.11,
/// moved from the corner-centre height down to the tip). When the flat bottom lies on the
/// surface (`a ∥ n`) the contact is taken at the front of the bottom, `tip = cc − R_f f` (the
/// thesis's TK = TT − r·f). `None` for cones.
#[must_use]
pub fn contact_to_tip(
    cutter: &Cutter,
    cc: DVec3,
    normal: DVec3,
    axis: DVec3,
    feed: DVec3,
) -> Option<DVec3> {
    let (rf, rc) = torus_radii(cutter)?;
    let radial = normal - axis * axis.dot(normal);
    let len = radial.length();
    let side = if len > 1e-9 { radial / len } else { -feed };
    Some(cc + (normal - axis) * rc + side * rf)
}

/// The lower outline of a cutter projected along the feed, in the contact's cross-feed frame:
/// lateral coordinate `x` along a chosen unit direction `τ ⟂ f` (toward the neighbouring pass),
/// height `y` along the surface normal, both measured from the contact point. A sorted table
/// of outline points, interpolated linearly; exact for the ball (a circle).
#[derive(Clone, Debug, PartialEq)]
pub struct CrossProfile {
    /// Outline points (x, y), x increasing, relative to the contact.
    points: Vec<DVec2>,
    /// Ball radius when the profile is a circle (closed form).
    circle: Option<f64>,
}

/// Outline samples per profile table.
const OUTLINE_SAMPLES: usize = 257;

impl CrossProfile {
    /// The profile of `cutter` with `axis` at a contact with `normal`, moving along `feed`, with
    /// lateral direction `tau` (unit, ⟂ feed and normal). `None` for cones.
    #[must_use]
    pub fn new(
        cutter: &Cutter,
        axis: DVec3,
        normal: DVec3,
        feed: DVec3,
        tau: DVec3,
    ) -> Option<Self> {
        let (rf, rc) = torus_radii(cutter)?;
        if rf == 0.0 {
            return Some(Self {
                points: Vec::new(),
                circle: Some(rc),
            });
        }
        let _ = feed;
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        // M maps the unit circle to the projected corner-centre circle in (τ, n) coordinates.
        let m = [
            [rf * e1.dot(tau), rf * e2.dot(tau)],
            [rf * e1.dot(normal), rf * e2.dot(normal)],
        ];
        let support = |nu: DVec2| -> DVec2 {
            let mt = DVec2::new(
                m[0][0] * nu.x + m[1][0] * nu.y,
                m[0][1] * nu.x + m[1][1] * nu.y,
            );
            let len = mt.length();
            let e = if len > 1e-12 * rf {
                let w = mt / len;
                DVec2::new(m[0][0] * w.x + m[0][1] * w.y, m[1][0] * w.x + m[1][1] * w.y)
            } else {
                DVec2::ZERO
            };
            e + nu * rc
        };
        let p0 = support(DVec2::new(0.0, -1.0));
        let mut points = Vec::with_capacity(OUTLINE_SAMPLES);
        let half = (OUTLINE_SAMPLES / 2) as f64;
        for i in 0..OUTLINE_SAMPLES {
            // φ = (π/2)·s³ concentrates samples near the contact, where the outline is flattest.
            let s = (i as f64 - half) / half;
            let phi = std::f64::consts::FRAC_PI_2 * 0.999_999 * s * s * s;
            let nu = DVec2::new(phi.sin(), -phi.cos());
            points.push(support(nu) - p0);
        }
        // Monotone in x by construction (a convex outline); enforce against round-off.
        for i in 1..points.len() {
            let prev = points.get(i - 1).map_or(f64::NEG_INFINITY, |p| p.x);
            if let Some(p) = points.get_mut(i) {
                p.x = p.x.max(prev);
            }
        }
        Some(Self {
            points,
            circle: None,
        })
    }

    /// Height of the outline above the contact at lateral offset `x`, mm; `f64::INFINITY` beyond
    /// the cutter's reach.
    #[must_use]
    pub fn height(&self, x: f64) -> f64 {
        if let Some(r) = self.circle {
            let q = r * r - x * x;
            return if q >= 0.0 {
                r - q.sqrt()
            } else {
                f64::INFINITY
            };
        }
        let pts = &self.points;
        let (Some(first), Some(last)) = (pts.first(), pts.last()) else {
            return f64::INFINITY;
        };
        if !(x >= first.x - 1e-12 && x <= last.x + 1e-12) {
            return f64::INFINITY;
        }
        let i = pts.partition_point(|p| p.x < x);
        match (i.checked_sub(1).and_then(|j| pts.get(j)), pts.get(i)) {
            (Some(a), Some(b)) => {
                let dx = b.x - a.x;
                if dx > 1e-15 {
                    a.y + (b.y - a.y) * (x - a.x) / dx
                } else {
                    a.y.min(b.y)
                }
            }
            (None, Some(b)) => b.y,
            (Some(a), None) => a.y,
            (None, None) => f64::INFINITY,
        }
    }

    /// Lateral reach of the outline on the `+x` and `−x` sides, mm.
    #[must_use]
    pub fn reach(&self) -> (f64, f64) {
        if let Some(r) = self.circle {
            return (r, r);
        }
        let lo = self.points.first().map_or(0.0, |p| -p.x);
        let hi = self.points.last().map_or(0.0, |p| p.x);
        (hi.max(0.0), lo.max(0.0))
    }
}

#[cfg(test)]
mod tests;
