//! Closed-form intervals of a line inside a body swept along a straight step with a fixed
//! axis, for any line direction (the rays of X, Y and Z families against a tilted tool).
//!
//! - A finite cylinder (radius ρ, heights z₀…z₁ along the axis a) swept by d: a point
//!   `o + s·e` is inside when some `t ∈ [0, 1]` puts `q = o + s·e − p₀ − t·d` inside the
//!   cylinder. In the (s, t) plane that is an ellipse `|A s + B t + C|² ≤ ρ²` (the radial
//!   condition; a strip or the whole plane when degenerate) cut by two slabs (the heights
//!   and `0 ≤ t ≤ 1`). The region is convex and compact, so the least and the greatest s are
//!   reached at one of: the ellipse's points with a vertical tangent, an ellipse–line
//!   crossing, or a line–line corner. Every candidate is checked against all constraints.
//! - A sphere swept by d is a capsule: the entry and exit of the line are closed forms.
//! - The ball end mill is the sphere (centre R up the axis) united with the cylinder from R
//!   to the flute length; the flat end mill is the cylinder from 0; shank and holder
//!   sections are cylinders. The union of the swept parts is convex (it is the sweep of a
//!   convex body), so the line meets it in one interval: the hull of the parts' intervals.

use glam::{DVec2, DVec3};

/// A slab `lo ≤ n·(s, t) ≤ hi` in the (s, t) plane.
#[derive(Clone, Copy, Debug)]
struct Slab {
    n: DVec2,
    lo: f64,
    hi: f64,
}

impl Slab {
    fn contains(&self, x: DVec2) -> bool {
        let v = self.n.dot(x);
        let eps = 1e-9 * (1.0 + self.lo.abs().max(self.hi.abs()));
        v >= self.lo - eps && v <= self.hi + eps
    }

    /// The two boundary lines as (point, direction).
    fn lines(&self) -> [(DVec2, DVec2); 2] {
        let nn = self.n.length_squared();
        let v = DVec2::new(-self.n.y, self.n.x);
        [(self.n * (self.lo / nn), v), (self.n * (self.hi / nn), v)]
    }
}

/// The radial condition `|A s + B t + C|² ≤ ρ²` of a cylinder in the (s, t) plane.
#[derive(Clone, Copy, Debug)]
struct Radial {
    a: DVec3,
    b: DVec3,
    c: DVec3,
    rr: f64,
}

impl Radial {
    fn value(&self, x: DVec2) -> f64 {
        (self.a * x.x + self.b * x.y + self.c).length_squared() - self.rr
    }

    fn contains(&self, x: DVec2) -> bool {
        self.value(x) <= 1e-9 * self.rr + 1e-12
    }

    /// Crossings of the line `p + λ v` with the ellipse's boundary.
    fn crossings(&self, p: DVec2, v: DVec2, out: &mut Candidates) {
        let m = self.a * p.x + self.b * p.y + self.c;
        let n = self.a * v.x + self.b * v.y;
        let qa = n.length_squared();
        if qa < 1e-30 {
            return;
        }
        let qb = m.dot(n);
        let disc = qb * qb - qa * (m.length_squared() - self.rr);
        if disc < 0.0 {
            return;
        }
        let sq = disc.sqrt();
        out.push(p + v * ((-qb - sq) / qa));
        out.push(p + v * ((-qb + sq) / qa));
    }

    /// The points of the ellipse's boundary where s is extreme (`∂/∂t = 0`).
    fn s_extremes(&self, out: &mut Candidates) {
        let bb = self.b.length_squared();
        if bb < 1e-30 {
            return;
        }
        let a1 = self.a - self.b * (self.b.dot(self.a) / bb);
        let c1 = self.c - self.b * (self.b.dot(self.c) / bb);
        let qa = a1.length_squared();
        if qa < 1e-30 {
            return;
        }
        let qb = a1.dot(c1);
        let disc = qb * qb - qa * (c1.length_squared() - self.rr);
        if disc < 0.0 {
            return;
        }
        let sq = disc.sqrt();
        for s in [(-qb - sq) / qa, (-qb + sq) / qa] {
            let t = -self.b.dot(self.a * s + self.c) / bb;
            out.push(DVec2::new(s, t));
        }
    }
}

/// A small fixed buffer of candidate points (no allocation per ray).
struct Candidates {
    pts: [DVec2; 40],
    n: usize,
}

impl Candidates {
    fn push(&mut self, p: DVec2) {
        if let Some(slot) = self.pts.get_mut(self.n) {
            *slot = p;
            self.n += 1;
        }
    }
}

/// A finite cylinder around the unit axis `a` through the tip: radius `rho`, heights
/// `z0…z1` above the tip.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cyl {
    pub a: DVec3,
    pub rho: f64,
    pub z0: f64,
    pub z1: f64,
}

/// Interval of s on the line `o + s·e` (unit e) inside the cylinder `cyl`, its tip swept from
/// `p0` to `p0 + d`.
pub(super) fn swept_cylinder(
    o: DVec3,
    e: DVec3,
    p0: DVec3,
    d: DVec3,
    cyl: Cyl,
) -> Option<(f64, f64)> {
    let Cyl { a, rho, z0, z1 } = cyl;
    if !(z1 > z0) {
        return None;
    }
    let y = o - p0;
    let perp = |v: DVec3| v - a * a.dot(v);
    let (pa, pb, pc) = (perp(e), -perp(d), perp(y));
    let t_slab = Slab {
        n: DVec2::new(0.0, 1.0),
        lo: 0.0,
        hi: 1.0,
    };
    let mut slabs = [t_slab; 3];
    let mut nslabs = 1;
    let axial = Slab {
        n: DVec2::new(a.dot(e), -a.dot(d)),
        lo: z0 - a.dot(y),
        hi: z1 - a.dot(y),
    };
    if axial.n.length_squared() < 1e-24 {
        // The height along the axis is the same everywhere on the line and the step.
        if !(axial.lo <= 0.0 && axial.hi >= 0.0) {
            return None;
        }
    } else if let Some(s) = slabs.get_mut(1) {
        *s = axial;
        nslabs = 2;
    }
    let mut ellipse = None;
    let (aa, bb) = (pa.length_squared(), pb.length_squared());
    let cross = pa.cross(pb).length_squared();
    let rr = rho * rho;
    if aa + bb < 1e-24 {
        // The radial distance does not change along the line or the step.
        if pc.length_squared() > rr {
            return None;
        }
    } else if cross <= 1e-18 * aa * bb || aa < 1e-24 || bb < 1e-24 {
        // Rank one: a strip |as + bt + c_w| ≤ h.
        let w = if aa >= bb { pa } else { pb }.normalize();
        let (cw, c2) = (pc.dot(w), pc.length_squared());
        let h2 = rr - (c2 - cw * cw);
        if h2 < 0.0 {
            return None;
        }
        let h = h2.sqrt();
        if let Some(s) = slabs.get_mut(nslabs) {
            *s = Slab {
                n: DVec2::new(pa.dot(w), pb.dot(w)),
                lo: -cw - h,
                hi: -cw + h,
            };
            nslabs += 1;
        }
    } else {
        ellipse = Some(Radial {
            a: pa,
            b: pb,
            c: pc,
            rr,
        });
    }
    let slabs = slabs.get(..nslabs).unwrap_or(&[]);
    let mut cand = Candidates {
        pts: [DVec2::ZERO; 40],
        n: 0,
    };
    if let Some(el) = &ellipse {
        el.s_extremes(&mut cand);
        for s in slabs {
            for (p, v) in s.lines() {
                el.crossings(p, v, &mut cand);
            }
        }
    }
    for (k, s1) in slabs.iter().enumerate() {
        for s2 in slabs.iter().skip(k + 1) {
            let det = s1.n.x * s2.n.y - s1.n.y * s2.n.x;
            if det.abs() <= 1e-15 * s1.n.length() * s2.n.length() {
                continue;
            }
            for c1 in [s1.lo, s1.hi] {
                for c2 in [s2.lo, s2.hi] {
                    cand.push(DVec2::new(
                        (c1 * s2.n.y - s1.n.y * c2) / det,
                        (s1.n.x * c2 - c1 * s2.n.x) / det,
                    ));
                }
            }
        }
    }
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for x in cand.pts.iter().take(cand.n) {
        let inside = x.is_finite()
            && slabs.iter().all(|s| s.contains(*x))
            && ellipse.as_ref().is_none_or(|el| el.contains(*x));
        if inside {
            lo = lo.min(x.x);
            hi = hi.max(x.x);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Entry of the line `o + s·e` (unit e) into the ball of radius r at c.
fn sphere_entry(o: DVec3, e: DVec3, c: DVec3, r: f64) -> Option<f64> {
    let oc = o - c;
    let b = e.dot(oc);
    let h = b * b - (oc.length_squared() - r * r);
    (h >= 0.0).then(|| -b - h.sqrt())
}

/// Entry of the line `o + s·e` (unit e) into the capsule of radius r around segment [pa, pb].
pub(super) fn capsule_entry(o: DVec3, e: DVec3, pa: DVec3, pb: DVec3, r: f64) -> Option<f64> {
    let ba = pb - pa;
    let oa = o - pa;
    let baba = ba.length_squared();
    let bard = ba.dot(e);
    let baoa = ba.dot(oa);
    let rdoa = e.dot(oa);
    let oaoa = oa.length_squared();
    let a = baba - bard * bard;
    let mut best: Option<f64> = None;
    let mut keep = |s: f64| best = Some(best.map_or(s, |b: f64| b.min(s)));
    if a > 1e-12 * baba.max(1e-300) {
        let b = baba * rdoa - baoa * bard;
        let c = baba * oaoa - baoa * baoa - r * r * baba;
        let h = b * b - a * c;
        if h >= 0.0 {
            let s = (-b - h.sqrt()) / a;
            let y = baoa + s * bard;
            if y > 0.0 && y < baba {
                keep(s);
            }
        }
    }
    if let Some(s) = sphere_entry(o, e, pa, r) {
        keep(s);
    }
    if let Some(s) = sphere_entry(o, e, pb, r) {
        keep(s);
    }
    best
}

/// Interval of the line `o + s·e` (unit e) inside the capsule of radius r around [pa, pb].
pub(super) fn capsule_interval(
    o: DVec3,
    e: DVec3,
    pa: DVec3,
    pb: DVec3,
    r: f64,
) -> Option<(f64, f64)> {
    let entry = capsule_entry(o, e, pa, pb, r)?;
    let exit = -capsule_entry(o, -e, pa, pb, r)?;
    (entry <= exit).then_some((entry, exit))
}

/// The hull of two optional intervals.
pub(super) fn hull(x: Option<(f64, f64)>, y: Option<(f64, f64)>) -> Option<(f64, f64)> {
    match (x, y) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, None) => a,
        (None, b) => b,
    }
}

/// The x-interval of the row `y = const` inside the stadium of radius `r` around the segment
/// [a, b] (the footprint of a vertical tool's sweep).
pub(super) fn stadium_span(a: DVec2, b: DVec2, r: f64, y: f64) -> Option<(f64, f64)> {
    let out = hull(disc_span(a, r, y), disc_span(b, r, y));
    match StadiumEdge::new(a, b) {
        Some(edge) => hull(out, edge.span(r, y)),
        None => out,
    }
}

/// The x-interval of the row at `y` within the disc of radius `r` about `c`.
#[inline]
pub(super) fn disc_span(c: DVec2, r: f64, y: f64) -> Option<(f64, f64)> {
    let dy = y - c.y;
    let h2 = r * r - dy * dy;
    (h2 >= 0.0).then(|| {
        let h = h2.sqrt();
        (c.x - h, c.x + h)
    })
}

/// The rectangle of a stadium from `a` to `b` (the part between the end discs), its
/// directions taken once for every row (the same values as [`stadium_span`] takes per row).
#[derive(Clone, Copy, Debug)]
pub(super) struct StadiumEdge {
    a: DVec2,
    u: DVec2,
    n: DVec2,
    len: f64,
}

impl StadiumEdge {
    /// `None` for a segment shorter than 1e-12 (then the discs are the stadium).
    pub(super) fn new(a: DVec2, b: DVec2) -> Option<Self> {
        let d = b - a;
        let len = d.length();
        (len > 1e-12).then(|| Self {
            a,
            u: d / len,
            n: DVec2::new(-d.y, d.x) / len,
            len,
        })
    }

    /// The x-interval of the row at `y` within the rectangle `a + λ·u + μ·n`,
    /// λ ∈ [0, len], μ ∈ [−r, r] (two slabs linear in x).
    #[inline]
    pub(super) fn span(&self, r: f64, y: f64) -> Option<(f64, f64)> {
        let a = self.a;
        let mut lo = f64::NEG_INFINITY;
        let mut hi = f64::INFINITY;
        let mut empty = false;
        for (dir, l0, l1) in [(self.u, 0.0, self.len), (self.n, -r, r)] {
            // (x − a.x)·dir.x + (y − a.y)·dir.y ∈ [l0, l1]
            let k = (y - a.y) * dir.y;
            if dir.x.abs() < 1e-15 {
                if k < l0 || k > l1 {
                    empty = true;
                }
                continue;
            }
            let (x0, x1) = (a.x + (l0 - k) / dir.x, a.x + (l1 - k) / dir.x);
            lo = lo.max(x0.min(x1));
            hi = hi.min(x0.max(x1));
        }
        (!empty && lo <= hi).then_some((lo, hi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: the s-range of sampled line points inside the swept cylinder.
    fn brute_cylinder(o: DVec3, e: DVec3, p0: DVec3, d: DVec3, cyl: Cyl) -> Option<(f64, f64)> {
        let Cyl { a, rho, z0, z1 } = cyl;
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for k in 0..=4000 {
            let s = -30.0 + 60.0 * f64::from(k) / 4000.0;
            let x = o + e * s;
            let inside = (0..=2000).any(|m| {
                let q = x - p0 - d * (f64::from(m) / 2000.0);
                let h = a.dot(q);
                (q - a * h).length() <= rho && h >= z0 && h <= z1
            });
            if inside {
                lo = lo.min(s);
                hi = hi.max(s);
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    #[test]
    fn swept_cylinder_matches_sampling() {
        let axes = [
            DVec3::Z,
            DVec3::new(0.0, 0.3, 1.0).normalize(),
            DVec3::new(0.5, -0.2, 0.8).normalize(),
            DVec3::X,
        ];
        let moves = [
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(3.0, 2.0, -1.0),
            DVec3::ZERO,
            DVec3::new(0.0, 0.0, 4.0),
        ];
        let rays = [
            (DVec3::new(1.0, 0.5, 0.0), DVec3::Z),
            (DVec3::new(0.0, 1.0, 2.0), DVec3::X),
            (DVec3::new(2.0, 0.0, 1.5), DVec3::Y),
            (DVec3::new(4.5, -2.0, 0.0), DVec3::Z),
        ];
        let step = 60.0 / 4000.0;
        for a in axes {
            let cyl = Cyl {
                a,
                rho: 2.5,
                z0: 0.5,
                z1: 6.0,
            };
            for d in moves {
                for (o, e) in rays {
                    let got = swept_cylinder(o, e, DVec3::ZERO, d, cyl);
                    let want = brute_cylinder(o, e, DVec3::ZERO, d, cyl);
                    match (got, want) {
                        (Some(g), Some(w)) => {
                            assert!(
                                (g.0 - w.0).abs() < 2.0 * step,
                                "{a} {d} {o} {e}: {g:?} {w:?}"
                            );
                            assert!(
                                (g.1 - w.1).abs() < 2.0 * step,
                                "{a} {d} {o} {e}: {g:?} {w:?}"
                            );
                        }
                        (None, None) => {}
                        // A graze thinner than the sampling step.
                        (Some(g), None) => assert!(g.1 - g.0 < 2.0 * step, "{g:?}"),
                        (None, Some(w)) => assert!(w.1 - w.0 < 2.0 * step, "{w:?}"),
                    }
                }
            }
        }
    }

    #[test]
    fn stadium_rows() {
        let (a, b) = (DVec2::new(0.0, 0.0), DVec2::new(4.0, 3.0));
        for k in 0..=100 {
            let y = -3.0 + 9.0 * f64::from(k) / 100.0;
            let got = stadium_span(a, b, 1.5, y);
            let mut lo = f64::INFINITY;
            let mut hi = f64::NEG_INFINITY;
            for m in 0..=20_000 {
                let x = -3.0 + 10.0 * f64::from(m) / 20_000.0;
                let p = DVec2::new(x, y);
                let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                if (p - a.lerp(b, t)).length() <= 1.5 {
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
            }
            match got {
                Some((g0, g1)) => {
                    assert!(
                        (g0 - lo).abs() < 1e-3 && (g1 - hi).abs() < 1e-3,
                        "{y}: {got:?}"
                    );
                }
                None => assert!(lo > hi, "{y}"),
            }
        }
    }
}
