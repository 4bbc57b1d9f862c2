//! Arc geometry: centre from IJK offsets or an R word, sweep and helix, in any plane.
//!
//! Planes follow ISO 6983 / RS274NGC: G17 is XY (normal +Z), G18 is ZX (first axis Z, normal
//! +Y), G19 is YZ (normal +X). Counter-clockwise (G3) is a positive rotation about the normal.
//! Note that the Kelekçi thesis maps G18 as X→x, Z→y, which mirrors the sense; Talas follows
//! the standard, so a G18 G3 arc runs counter-clockwise seen from +Y.

use glam::{DVec2, DVec3};
use std::f64::consts::TAU;

use super::block::Arc;

/// The arc plane (modal group 2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Plane {
    /// G17: XY, normal +Z.
    #[default]
    Xy,
    /// G18: ZX, normal +Y.
    Zx,
    /// G19: YZ, normal +X.
    Yz,
}

impl Plane {
    /// Indices (u, v, w) into XYZ: the in-plane axes (u, v) and the normal axis w, with
    /// u × v = w.
    #[must_use]
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Self::Xy => (0, 1, 2),
            Self::Zx => (2, 0, 1),
            Self::Yz => (1, 2, 0),
        }
    }

    /// Unit normal.
    #[must_use]
    pub fn normal(self) -> DVec3 {
        match self {
            Self::Xy => DVec3::Z,
            Self::Zx => DVec3::Y,
            Self::Yz => DVec3::X,
        }
    }

    /// In-plane coordinates (u, v) and the normal coordinate w of a point.
    #[must_use]
    pub fn split(self, p: DVec3) -> (DVec2, f64) {
        let (u, v, w) = self.axes();
        let a = p.to_array();
        (DVec2::new(a[u], a[v]), a[w])
    }

    /// A point from in-plane coordinates and a normal coordinate.
    #[must_use]
    pub fn join(self, uv: DVec2, w: f64) -> DVec3 {
        let (iu, iv, iw) = self.axes();
        let mut a = [0.0; 3];
        a[iu] = uv.x;
        a[iv] = uv.y;
        a[iw] = w;
        DVec3::from_array(a)
    }
}

/// How the centre is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CentreSpec {
    /// The centre point itself (already resolved from IJK, incremental or absolute).
    Centre(DVec3),
    /// Radius: positive for the short arc (≤ 180°), negative for the long one.
    Radius(f64),
}

/// Relative tolerance on start and end radii of an IJK arc (RS274NGC uses similar values).
const RADIUS_TOL_ABS_MM: f64 = 0.002;
const RADIUS_TOL_REL: f64 = 0.001;
/// Start and end closer than this in the plane make an IJK arc a full circle.
const FULL_CIRCLE_MM: f64 = 1e-6;

/// Compute an arc from `start` to `end` (machine coordinates, mm).
///
/// `ccw` is G3; `turns` ≥ 1 is the `P` word (full turns added: P2 adds one extra turn).
///
/// # Errors
/// A message (without position; the caller adds line and column) when the geometry is
/// impossible: zero radius, start and end radii that differ, an R arc with coincident ends, or
/// a chord longer than the diameter.
pub fn arc_geometry(
    start: DVec3,
    end: DVec3,
    plane: Plane,
    ccw: bool,
    spec: CentreSpec,
    turns: u32,
) -> Result<Arc, String> {
    let (s, ws) = plane.split(start);
    let (e, we) = plane.split(end);
    let extra_turns = f64::from(turns.saturating_sub(1));
    let (centre, radius, sweep) = match spec {
        CentreSpec::Centre(c3) => {
            let (c, _) = plane.split(c3);
            let r0 = s.distance(c);
            let r1 = e.distance(c);
            if !(r0 > 1e-9) {
                return Err("arc radius is zero (the centre is at the start point)".into());
            }
            if (r1 - r0).abs() > RADIUS_TOL_ABS_MM.max(RADIUS_TOL_REL * r0) {
                return Err(format!(
                    "arc start radius {r0:.4} mm and end radius {r1:.4} mm differ"
                ));
            }
            let sweep = if s.distance(e) < FULL_CIRCLE_MM {
                TAU
            } else {
                let a = s - c;
                let b = e - c;
                let ang = a.perp_dot(b).atan2(a.dot(b)); // (-π, π], positive CCW
                let signed = if ccw { ang } else { -ang };
                if signed <= 0.0 { signed + TAU } else { signed }
            };
            (c, r0, sweep)
        }
        CentreSpec::Radius(r) => {
            let chord = s.distance(e);
            if !(r.abs() > 1e-9) {
                return Err("arc radius R is zero".into());
            }
            if chord < FULL_CIRCLE_MM {
                return Err(
                    "an R-format arc cannot end where it starts; use I, J, K for a full circle"
                        .into(),
                );
            }
            let half = chord / 2.0;
            let rr = r.abs();
            let h2 = rr * rr - half * half;
            let h = if h2 >= 0.0 {
                h2.sqrt()
            } else if half - rr <= RADIUS_TOL_ABS_MM.max(RADIUS_TOL_REL * rr) {
                0.0 // within tolerance: a half circle
            } else {
                return Err(format!(
                    "arc radius |R| = {rr:.4} mm is smaller than half the chord ({half:.4} mm)"
                ));
            };
            let m = (s + e) / 2.0;
            let left = (e - s).perp() / chord; // left normal of the chord
            // G3 with R > 0 turns left: centre on the left; G2 on the right; R < 0 swaps.
            let on_left = ccw == (r > 0.0);
            let c = if on_left { m + left * h } else { m - left * h };
            let short = 2.0 * (half / rr).min(1.0).asin();
            let sweep = if r > 0.0 { short } else { TAU - short };
            (c, rr.max(half), sweep)
        }
    };
    Ok(Arc {
        centre: plane.join(centre, ws),
        normal: plane.normal(),
        radius_mm: radius,
        sweep_rad: sweep + TAU * extra_turns,
        helix_mm: we - ws,
    })
}
