//! Independent geometry for the profile tests: exact distances between points, lines and
//! circular arcs written from scratch here (not the engine's), and a seeded generator.

#![allow(dead_code)]

use glam::DVec2;
use std::f64::consts::{PI, TAU};

/// A line or arc, from a start, an end and a bulge (tan of a quarter of the signed sweep).
#[derive(Clone, Copy, Debug)]
pub enum Seg {
    Line(DVec2, DVec2),
    /// start, end, centre, radius, start angle, signed sweep
    Arc(DVec2, DVec2, DVec2, f64, f64, f64),
}

pub fn seg(a: DVec2, b: DVec2, bulge: f64) -> Seg {
    if bulge == 0.0 {
        return Seg::Line(a, b);
    }
    let sweep = 4.0 * bulge.atan();
    // Centre from the inscribed-angle relation: the chord subtends `sweep` at the centre.
    let m = (a + b) * 0.5;
    let half = (b - a).length() * 0.5;
    let r = half / (sweep * 0.5).sin().abs();
    let dir = (b - a).normalize();
    let left = DVec2::new(-dir.y, dir.x);
    let off = (r * r - half * half).max(0.0).sqrt();
    // The centre lies left of the chord for a CCW minor arc or a CW major arc.
    let c = if (sweep > 0.0) == (sweep.abs() < PI) {
        m + left * off
    } else {
        m - left * off
    };
    let a0 = (a - c).y.atan2((a - c).x);
    Seg::Arc(a, b, c, r, a0, sweep)
}

fn within(a0: f64, sweep: f64, ang: f64) -> bool {
    let mut d = (ang - a0) % TAU;
    if d < 0.0 {
        d += TAU;
    }
    if sweep < 0.0 {
        d = (TAU - d) % TAU;
    }
    d <= sweep.abs() + 1e-15
}

pub fn point_dist(s: &Seg, p: DVec2) -> f64 {
    match *s {
        Seg::Line(a, b) => {
            let d = b - a;
            let t = ((p - a).dot(d) / d.dot(d)).clamp(0.0, 1.0);
            (a + d * t - p).length()
        }
        Seg::Arc(a, b, c, r, a0, sw) => {
            let v = p - c;
            if v.length() > 0.0 && within(a0, sw, v.y.atan2(v.x)) {
                (v.length() - r).abs()
            } else {
                (p - a).length().min((p - b).length())
            }
        }
    }
}

pub fn seg_point(s: &Seg, t: f64) -> DVec2 {
    match *s {
        Seg::Line(a, b) => a + (b - a) * t,
        Seg::Arc(_, _, c, r, a0, sw) => {
            let ang = a0 + sw * t;
            c + DVec2::new(ang.cos(), ang.sin()) * r
        }
    }
}

fn ends(s: &Seg) -> (DVec2, DVec2) {
    match *s {
        Seg::Line(a, b) | Seg::Arc(a, b, ..) => (a, b),
    }
}

fn on_seg(s: &Seg, p: DVec2, eps: f64) -> bool {
    point_dist(s, p) <= eps
}

/// Points where the two elements' carrier lines/circles meet (candidates for contact).
fn crossings(s: &Seg, t: &Seg) -> Vec<DVec2> {
    match (*s, *t) {
        (Seg::Line(a, b), Seg::Line(c, d)) => {
            let r = b - a;
            let q = d - c;
            let den = r.perp_dot(q);
            if den == 0.0 {
                return vec![];
            }
            let u = (c - a).perp_dot(q) / den;
            vec![a + r * u]
        }
        (Seg::Line(a, b), Seg::Arc(_, _, c, rad, ..))
        | (Seg::Arc(_, _, c, rad, ..), Seg::Line(a, b)) => {
            let d = b - a;
            let f = a - c;
            let qa = d.dot(d);
            let qb = 2.0 * f.dot(d);
            let qc = f.dot(f) - rad * rad;
            let disc = qb * qb - 4.0 * qa * qc;
            if disc < 0.0 {
                return vec![];
            }
            let sq = disc.sqrt();
            vec![
                a + d * ((-qb - sq) / (2.0 * qa)),
                a + d * ((-qb + sq) / (2.0 * qa)),
            ]
        }
        (Seg::Arc(_, _, c1, r1, ..), Seg::Arc(_, _, c2, r2, ..)) => {
            let d = (c2 - c1).length();
            if d == 0.0 || d > r1 + r2 || d < (r1 - r2).abs() {
                return vec![];
            }
            let x = (d * d + r1 * r1 - r2 * r2) / (2.0 * d);
            let h = (r1 * r1 - x * x).max(0.0).sqrt();
            let u = (c2 - c1) / d;
            let n = DVec2::new(-u.y, u.x);
            vec![c1 + u * x + n * h, c1 + u * x - n * h]
        }
    }
}

/// Exact minimum distance between two elements.
pub fn seg_dist(s: &Seg, t: &Seg) -> f64 {
    let scale = 1.0;
    for p in crossings(s, t) {
        if on_seg(s, p, 1e-12 * scale) && on_seg(t, p, 1e-12 * scale) {
            return 0.0;
        }
    }
    let (sa, sb) = ends(s);
    let (ta, tb) = ends(t);
    let mut best = point_dist(t, sa)
        .min(point_dist(t, sb))
        .min(point_dist(s, ta))
        .min(point_dist(s, tb));
    // Interior-interior critical points: the arc point nearest the other element's carrier.
    let arc_candidates = |arc: &Seg, other: &Seg| -> Vec<DVec2> {
        let Seg::Arc(_, _, c, r, ..) = *arc else {
            return vec![];
        };
        let dirs: Vec<DVec2> = match *other {
            Seg::Line(a, b) => {
                let d = (b - a).normalize();
                let n = DVec2::new(-d.y, d.x);
                vec![n, -n]
            }
            Seg::Arc(_, _, c2, ..) => {
                let u = (c2 - c).normalize_or_zero();
                vec![u, -u]
            }
        };
        dirs.into_iter()
            .map(|u| c + u * r)
            .filter(|p| on_seg(arc, *p, 1e-9 * r.max(1.0)))
            .collect()
    };
    for p in arc_candidates(s, t) {
        best = best.min(point_dist(t, p));
    }
    for p in arc_candidates(t, s) {
        best = best.min(point_dist(s, p));
    }
    best
}

/// Segments of a vertex list (x, y, bulge) that may be closed.
pub fn segs(v: &[(f64, f64, f64)], closed: bool) -> Vec<Seg> {
    let n = v.len();
    let m = if closed { n } else { n - 1 };
    (0..m)
        .map(|i| {
            let (x0, y0, b) = v[i];
            let (x1, y1, _) = v[(i + 1) % n];
            seg(DVec2::new(x0, y0), DVec2::new(x1, y1), b)
        })
        .collect()
}

pub fn dist_to(segs: &[Seg], p: DVec2) -> f64 {
    segs.iter()
        .map(|s| point_dist(s, p))
        .fold(f64::INFINITY, f64::min)
}

/// splitmix64.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// True when no two non-adjacent elements (flattened finely) cross or touch.
pub fn is_simple(segs: &[Seg], closed: bool) -> bool {
    let n = segs.len();
    for i in 0..n {
        for j in i + 1..n {
            let adjacent = j == i + 1 || (closed && i == 0 && j == n - 1);
            let d = seg_dist(&segs[i], &segs[j]);
            if adjacent {
                // Adjacent elements may only meet at their shared point: check interiors.
                let mid_i = seg_point(&segs[i], 0.5);
                if point_dist(&segs[j], mid_i) < 1e-6 {
                    return false;
                }
                continue;
            }
            if d < 1e-3 {
                return false;
            }
        }
    }
    true
}
