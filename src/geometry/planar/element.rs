//! Lines and circular arcs of a profile: closest points, tangents, lengths, bounds, and the
//! parts of an element inside a disc. All closed forms; no sampling.

use glam::DVec2;
use std::f64::consts::{PI, TAU};

use super::Profile;

/// One element of a profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Element {
    /// A straight line from `a` to `b`.
    Line {
        /// Start.
        a: DVec2,
        /// End.
        b: DVec2,
    },
    /// A circular arc from `a` to `b` about `centre`; `sweep` is signed (positive
    /// counter-clockwise), |sweep| ≤ 2π.
    Arc {
        /// Start.
        a: DVec2,
        /// End.
        b: DVec2,
        /// Centre.
        centre: DVec2,
        /// Radius, mm.
        radius: f64,
        /// Angle of `a` about the centre, rad.
        start_rad: f64,
        /// Signed sweep, rad.
        sweep_rad: f64,
    },
}

impl Element {
    /// The element from `a` to `b` with a bulge (`tan(sweep / 4)`); a bulge of (almost) zero
    /// gives a line.
    #[must_use]
    pub fn from_bulge(a: DVec2, b: DVec2, bulge: f64) -> Self {
        let chord = b - a;
        let c = chord.length();
        if bulge.abs() < 1e-12 || c == 0.0 {
            return Self::Line { a, b };
        }
        let sweep = 4.0 * bulge.atan();
        let radius = c / (2.0 * (sweep / 2.0).sin().abs());
        // Signed distance from the chord's midpoint to the centre, along the chord's left
        // normal: (c/2) / tan(sweep/2) (positive for a counter-clockwise minor arc).
        let h = (c / 2.0) / (sweep / 2.0).tan();
        let left = DVec2::new(-chord.y, chord.x) / c;
        let centre = (a + b) / 2.0 + left * h;
        let start = (a - centre).to_angle();
        Self::Arc {
            a,
            b,
            centre,
            radius,
            start_rad: start,
            sweep_rad: sweep,
        }
    }

    /// Start point.
    #[must_use]
    pub fn start(&self) -> DVec2 {
        match *self {
            Self::Line { a, .. } | Self::Arc { a, .. } => a,
        }
    }

    /// End point.
    #[must_use]
    pub fn end(&self) -> DVec2 {
        match *self {
            Self::Line { b, .. } | Self::Arc { b, .. } => b,
        }
    }

    /// Straight distance from start to end, mm.
    #[must_use]
    pub fn chord_length(&self) -> f64 {
        (self.end() - self.start()).length()
    }

    /// Length along the element, mm.
    #[must_use]
    pub fn length(&self) -> f64 {
        match *self {
            Self::Line { a, b } => (b - a).length(),
            Self::Arc {
                radius, sweep_rad, ..
            } => radius * sweep_rad.abs(),
        }
    }

    /// The point at parameter `t` ∈ [0, 1] (proportional to length).
    #[must_use]
    pub fn point_at(&self, t: f64) -> DVec2 {
        match *self {
            Self::Line { a, b } => a + (b - a) * t,
            Self::Arc {
                centre,
                radius,
                start_rad,
                sweep_rad,
                ..
            } => centre + DVec2::from_angle(start_rad + sweep_rad * t) * radius,
        }
    }

    /// Unit tangent in the direction of travel at parameter `t`.
    #[must_use]
    pub fn tangent_at(&self, t: f64) -> DVec2 {
        match *self {
            Self::Line { a, b } => (b - a).normalize_or_zero(),
            Self::Arc {
                start_rad,
                sweep_rad,
                ..
            } => {
                let r = DVec2::from_angle(start_rad + sweep_rad * t);
                DVec2::new(-r.y, r.x) * sweep_rad.signum()
            }
        }
    }

    /// Signed curvature (positive: turning left), 1/mm.
    #[must_use]
    pub fn curvature(&self) -> f64 {
        match *self {
            Self::Line { .. } => 0.0,
            Self::Arc {
                radius, sweep_rad, ..
            } => sweep_rad.signum() / radius,
        }
    }

    /// Parameter t ∈ [0, 1] of the angle `ang` on an arc, when the angle is within the sweep.
    fn arc_param(start_rad: f64, sweep_rad: f64, ang: f64) -> Option<f64> {
        let d = (ang - start_rad).rem_euclid(TAU);
        let d = if sweep_rad >= 0.0 { d } else { (TAU - d) % TAU };
        let t = d / sweep_rad.abs();
        (t <= 1.0).then_some(t)
    }

    /// The closest point of the element to `p` and its parameter t ∈ [0, 1].
    #[must_use]
    pub fn closest(&self, p: DVec2) -> (DVec2, f64) {
        match *self {
            Self::Line { a, b } => {
                let d = b - a;
                let l2 = d.length_squared();
                let t = if l2 > 0.0 {
                    ((p - a).dot(d) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (a + d * t, t)
            }
            Self::Arc {
                a,
                b,
                centre,
                radius,
                start_rad,
                sweep_rad,
            } => {
                let v = p - centre;
                if v.length_squared() > 0.0
                    && let Some(t) = Self::arc_param(start_rad, sweep_rad, v.to_angle())
                {
                    return (centre + v.normalize() * radius, t);
                }
                if (p - a).length_squared() <= (p - b).length_squared() {
                    (a, 0.0)
                } else {
                    (b, 1.0)
                }
            }
        }
    }

    /// Distance from `p` to the element, mm.
    #[must_use]
    pub fn distance(&self, p: DVec2) -> f64 {
        (self.closest(p).0 - p).length()
    }

    /// Bounding box (exact for arcs: the axis extremes inside the sweep count).
    #[must_use]
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let (a, b) = (self.start(), self.end());
        let mut lo = a.min(b);
        let mut hi = a.max(b);
        if let Self::Arc {
            centre,
            radius,
            start_rad,
            sweep_rad,
            ..
        } = *self
        {
            for k in 0..4 {
                let ang = f64::from(k) * PI / 2.0;
                if Self::arc_param(start_rad, sweep_rad, ang).is_some() {
                    let q = centre + DVec2::from_angle(ang) * radius;
                    lo = lo.min(q);
                    hi = hi.max(q);
                }
            }
        }
        (lo, hi)
    }

    /// The parameter intervals of the element strictly inside the disc about `c` of radius
    /// `r` (shrunk by `tol`), ascending.
    #[must_use]
    pub fn inside_disc(&self, c: DVec2, r: f64, tol: f64) -> Vec<(f64, f64)> {
        let rr = (r - tol).max(0.0);
        let mut cuts = vec![0.0, 1.0];
        match *self {
            Self::Line { a, b } => {
                let d = b - a;
                let f = a - c;
                let qa = d.length_squared();
                let qb = 2.0 * f.dot(d);
                let qc = f.length_squared() - rr * rr;
                let disc = qb * qb - 4.0 * qa * qc;
                if qa > 0.0 && disc > 0.0 {
                    let s = disc.sqrt();
                    for t in [(-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa)] {
                        if t > 0.0 && t < 1.0 {
                            cuts.push(t);
                        }
                    }
                }
            }
            Self::Arc {
                centre,
                radius,
                start_rad,
                sweep_rad,
                ..
            } => {
                let d = (c - centre).length();
                if d > 0.0 && d < radius + rr && d > (radius - rr).abs() {
                    // Angle at the arc's centre between the line of centres and the crossing.
                    let cos = (d * d + radius * radius - rr * rr) / (2.0 * d * radius);
                    let base = (c - centre).to_angle();
                    let half = cos.clamp(-1.0, 1.0).acos();
                    for ang in [base - half, base + half] {
                        if let Some(t) = Self::arc_param(start_rad, sweep_rad, ang)
                            && t > 0.0
                            && t < 1.0
                        {
                            cuts.push(t);
                        }
                    }
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        let mut out: Vec<(f64, f64)> = Vec::new();
        for w in cuts.windows(2) {
            let (Some(&t0), Some(&t1)) = (w.first(), w.get(1)) else {
                continue;
            };
            if t1 - t0 <= 0.0 {
                continue;
            }
            let mid = self.point_at((t0 + t1) / 2.0);
            if (mid - c).length() < rr {
                match out.last_mut() {
                    Some(last) if (last.1 - t0).abs() < 1e-15 => last.1 = t1,
                    _ => out.push((t0, t1)),
                }
            }
        }
        out
    }
}

/// Distance from `p` to the profile, with the index of the closest element and the closest
/// point (the first element wins a tie).
#[must_use]
pub fn distance_to_profile(profile: &Profile, p: DVec2) -> Option<(f64, usize, DVec2)> {
    closest_on(&profile.elements(), p)
}

/// [`distance_to_profile`] over a list of elements.
pub(crate) fn closest_on(elements: &[Element], p: DVec2) -> Option<(f64, usize, DVec2)> {
    let mut best: Option<(f64, usize, DVec2)> = None;
    for (i, e) in elements.iter().enumerate() {
        let (q, _) = e.closest(p);
        let d = (q - p).length();
        if best.is_none_or(|b| d < b.0) {
            best = Some((d, i, q));
        }
    }
    best
}
