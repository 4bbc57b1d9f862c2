//! Push-cutter: the exact interval of a horizontal fibre over which a cutter, its tip at a
//! fixed height, intersects a triangle.
//!
//! The cutter is a convex solid (the profile's lower surface and, above it, a cylinder of the
//! cutting radius that goes up without end, as in OpenCAMLib), so the positions s along a fibre
//! at which it meets a (convex) triangle form one interval. For a point q of the triangle at
//! height h above the tip, `along` and `across` the fibre, the cutter meets q for
//! s ∈ [along − w, along + w], w = √(ρ(h)² − across²), ρ(h) the cutter's radius at height h.
//! The interval is [min over q of (along − w), max over q of (along + w)]; both functions are
//! convex (concave) on the triangle, so each extreme lies either at an interior point where the
//! cutter is tangent to the facet (facet contact: the cutter's support point in the direction
//! of the facet's downward normal, a closed form per cutter kind) or on the boundary of the
//! triangle clipped to h ≥ 0 (edge and vertex contacts; the clip edge is where a flat bottom's
//! rim meets the facet). On each boundary segment the extreme of the convex function is found
//! by golden-section search on the part of the segment the cutter can reach (found by
//! maximising the concave ρ(h) − |across| and bisecting for its zeros), to 1e-11 of the
//! segment's length.

use glam::{DVec2, DVec3};

use crate::tools::{Cutter, CutterKind};

/// The cutter as the push-cutter sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Profile {
    kind: CutterKind,
    big: f64,
    /// Height above the tip where the profile reaches the full radius.
    top: f64,
}

impl Profile {
    pub(crate) fn new(cutter: &Cutter) -> Self {
        Self {
            kind: cutter.kind,
            big: cutter.radius(),
            top: cutter.profile_height(),
        }
    }

    /// Cutting radius, mm.
    pub(crate) fn radius(&self) -> f64 {
        self.big
    }

    /// Radius of the cutter at height `h` ≥ 0 above the tip (the cutting radius above the
    /// profile).
    pub(crate) fn reach(&self, h: f64) -> f64 {
        let h = h.max(0.0);
        if h >= self.top {
            return self.big;
        }
        match self.kind {
            CutterKind::Ball => {
                let d = self.big - h;
                (self.big * self.big - d * d).max(0.0).sqrt()
            }
            CutterKind::Flat => self.big,
            CutterKind::BullNose { corner_radius: r } => {
                let d = r - h;
                self.big - r + (r * r - d * d).max(0.0).sqrt()
            }
            CutterKind::Cone { half_angle } => h * half_angle.tan(),
        }
    }

    /// The cutter's point extreme in the direction (−e·sin θ, −cos θ) for a unit horizontal
    /// e: (radial distance, height above the tip), for a facet of slope θ (tan θ = `tan_t`).
    fn support(&self, tan_t: f64) -> (f64, f64) {
        let s = tan_t / (1.0 + tan_t * tan_t).sqrt();
        let c = 1.0 / (1.0 + tan_t * tan_t).sqrt();
        match self.kind {
            CutterKind::Ball => (self.big * s, self.big * (1.0 - c)),
            CutterKind::Flat => (self.big, 0.0),
            CutterKind::BullNose { corner_radius: r } => (self.big - r + r * s, r * (1.0 - c)),
            CutterKind::Cone { half_angle } => {
                if tan_t * half_angle.tan() > 1.0 {
                    (self.big, self.top)
                } else {
                    (0.0, 0.0)
                }
            }
        }
    }

    /// Slope of the surface (rad from horizontal) at a contact `rho` from the axis and `h`
    /// above the tip, where the cutter's surface is smooth there; `None` at a sharp rim or tip.
    pub(crate) fn contact_slope(&self, rho: f64, h: f64) -> Option<f64> {
        let eps = 1e-9 * self.big.max(1.0);
        if h >= self.top - eps && rho >= self.big - eps && self.top > eps {
            return Some(std::f64::consts::FRAC_PI_2);
        }
        match self.kind {
            CutterKind::Ball => Some((rho / self.big).clamp(0.0, 1.0).asin()),
            CutterKind::BullNose { corner_radius: r } => {
                let q = rho - (self.big - r);
                (q > eps).then(|| (q / r).clamp(0.0, 1.0).asin())
            }
            CutterKind::Flat => (h > eps).then_some(std::f64::consts::FRAC_PI_2),
            CutterKind::Cone { half_angle } => (rho > eps && rho < self.big - eps)
                .then_some(std::f64::consts::FRAC_PI_2 - half_angle),
        }
    }
}

/// A horizontal line: `origin + s·dir` at tip height `z`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fibre {
    pub origin: DVec2,
    /// Unit direction.
    pub dir: DVec2,
    pub z: f64,
}

impl Fibre {
    /// (along, across, height above the tip) of a point.
    fn local(&self, p: DVec3) -> DVec3 {
        let d = p.truncate() - self.origin;
        DVec3::new(d.dot(self.dir), d.perp_dot(self.dir), p.z - self.z)
    }

    /// The tip at parameter s.
    pub(crate) fn at(&self, s: f64) -> DVec3 {
        (self.origin + self.dir * s).extend(self.z)
    }
}

/// One end of an interval: the fibre parameter and the contact point there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct End {
    pub s: f64,
    /// Contact point on the mesh.
    pub cc: DVec3,
    /// Surface slope at the contact, rad from horizontal.
    pub slope: f64,
}

const GOLDEN_ITERS: usize = 56;
const BISECT_ITERS: usize = 56;

fn golden_min(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    crate::geometry::minimize::golden_argmin(a, b, GOLDEN_ITERS, f)
}

/// Zero of `f` between `a` (f < 0) and `b` (f ≥ 0).
fn bisect(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let (mut lo, mut hi) = (a, b);
    for _ in 0..BISECT_ITERS {
        let m = 0.5 * (lo + hi);
        if f(m) >= 0.0 {
            hi = m;
        } else {
            lo = m;
        }
    }
    hi
}

/// Keeps the lowest and highest contact found so far.
struct Extremes {
    lo: Option<End>,
    hi: Option<End>,
}

impl Extremes {
    fn add_lo(&mut self, e: End) {
        if self.lo.is_none_or(|l| e.s < l.s) {
            self.lo = Some(e);
        }
    }
    fn add_hi(&mut self, e: End) {
        if self.hi.is_none_or(|h| e.s > h.s) {
            self.hi = Some(e);
        }
    }
}

/// The interval of `fibre` over which the cutter meets the triangle `tri`, with the contact
/// at each end; `None` when it never does.
pub(crate) fn push_triangle(prof: &Profile, fibre: &Fibre, tri: &[DVec3; 3]) -> Option<(End, End)> {
    if tri.iter().all(|p| p.z < fibre.z) {
        return None;
    }
    let local: Vec<DVec3> = tri.iter().map(|p| fibre.local(*p)).collect();
    let big = prof.big;
    if local.iter().all(|l| l.y > big) || local.iter().all(|l| l.y < -big) {
        return None;
    }
    let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
    let len = normal.length();
    if !(len > 0.0) {
        return None;
    }
    let tri_slope = (normal.z.abs() / len).clamp(0.0, 1.0).acos();
    let mut ext = Extremes { lo: None, hi: None };
    // Clip to h ≥ 0.
    let mut poly: Vec<DVec3> = Vec::with_capacity(4);
    for i in 0..3 {
        let (a, b) = (local[i], local[(i + 1) % 3]);
        if a.z >= 0.0 {
            poly.push(a);
        }
        if (a.z >= 0.0) != (b.z >= 0.0) {
            let t = a.z / (a.z - b.z);
            let mut p = a.lerp(b, t);
            p.z = 0.0;
            poly.push(p);
        }
    }
    for i in 0..poly.len() {
        edge_extremes(
            prof,
            poly[i],
            poly[(i + 1) % poly.len()],
            tri_slope,
            &mut ext,
        );
    }
    facet_extreme(prof, &local, tri_slope, &mut ext);
    let (lo, hi) = (ext.lo?, ext.hi?);
    let back = |e: End| End {
        cc: to_world(fibre, e.cc),
        ..e
    };
    Some((back(lo), back(hi)))
}

fn to_world(fibre: &Fibre, l: DVec3) -> DVec3 {
    let p = fibre.origin + fibre.dir * l.x - fibre.dir.perp() * l.y;
    p.extend(l.z + fibre.z)
}

fn slope_at(prof: &Profile, rel_along: f64, q: DVec3, tri_slope: f64) -> f64 {
    let rho = (rel_along * rel_along + q.y * q.y).sqrt();
    prof.contact_slope(rho, q.z).unwrap_or(tri_slope)
}

/// Edge and vertex contacts on the segment a→b (local coordinates, h ≥ 0).
fn edge_extremes(prof: &Profile, a: DVec3, b: DVec3, tri_slope: f64, ext: &mut Extremes) {
    let p = |t: f64| a.lerp(b, t);
    let g = |t: f64| {
        let q = p(t);
        prof.reach(q.z) - q.y.abs()
    };
    let w = |t: f64| {
        let q = p(t);
        let r = prof.reach(q.z);
        (r * r - q.y * q.y).max(0.0).sqrt()
    };
    let (g0, g1) = (g(0.0), g(1.0));
    let (ta, tb) = if g0 >= 0.0 && g1 >= 0.0 {
        (0.0, 1.0)
    } else {
        let tm = golden_min(|t| -g(t), 0.0, 1.0);
        if g(tm) < 0.0 {
            return;
        }
        let ta = if g0 >= 0.0 { 0.0 } else { bisect(g, 0.0, tm) };
        let tb = if g1 >= 0.0 {
            1.0
        } else {
            1.0 - bisect(|u| g(1.0 - u), 0.0, 1.0 - tm)
        };
        (ta, tb)
    };
    let lo_f = |t: f64| p(t).x - w(t);
    let hi_f = |t: f64| -(p(t).x + w(t));
    for (f, is_lo) in [(&lo_f as &dyn Fn(f64) -> f64, true), (&hi_f, false)] {
        let mut best = golden_min(f, ta, tb);
        for t in [ta, tb] {
            if f(t) < f(best) {
                best = t;
            }
        }
        let q = p(best);
        let s = if is_lo { lo_f(best) } else { -hi_f(best) };
        let end = End {
            s,
            cc: q,
            slope: slope_at(prof, q.x - s, q, tri_slope),
        };
        if is_lo {
            ext.add_lo(end);
        } else {
            ext.add_hi(end);
        }
    }
}

/// The facet contact: the cutter tangent to the triangle's plane at an interior point.
fn facet_extreme(prof: &Profile, l: &[DVec3], tri_slope: f64, ext: &mut Extremes) {
    let mut n = (l[1] - l[0]).cross(l[2] - l[0]);
    let len = n.length();
    n /= len;
    if n.z.abs() < 1e-12 {
        return;
    }
    if n.z < 0.0 {
        n = -n;
    }
    let nh = DVec2::new(n.x, n.y);
    let nh_len = nh.length();
    if n.x.abs() < 1e-12 || nh_len < 1e-15 {
        return;
    }
    let e = -nh / nh_len;
    let (rho, hh) = prof.support(nh_len / n.z);
    let off = DVec3::new(rho * e.x, rho * e.y, hh);
    // Cutter tip at (s, 0, 0): n·((s, 0, 0) + off) = n·l0.
    let s = (n.dot(l[0]) - n.dot(off)) / n.x;
    let q = DVec3::new(s, 0.0, 0.0) + off;
    if !inside(l, q) {
        return;
    }
    let end = End {
        s,
        cc: q,
        slope: tri_slope,
    };
    ext.add_lo(end);
    ext.add_hi(end);
}

/// Whether q (on the plane of the triangle) lies inside it, by barycentric coordinates.
fn inside(l: &[DVec3], q: DVec3) -> bool {
    let (v0, v1, v2) = (l[1] - l[0], l[2] - l[0], q - l[0]);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let den = d00 * d11 - d01 * d01;
    if !(den.abs() > 0.0) {
        return false;
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    v >= 0.0 && w >= 0.0 && v + w <= 1.0
}
