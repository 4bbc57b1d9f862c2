//! The three contact tests of the drop-cutter for one triangle: vertex, facet and edge.
//!
//! - Vertex: a vertex at horizontal distance q ≤ R from the axis touches the profile at height
//!   h(q), so the tip rests at z − h(q).
//! - Facet: a plane with unit upward normal n touches the cutter where the cutter's surface
//!   normal is −n; that point lies at radius r_c from the axis in the direction −n_xy/|n_xy|
//!   and height h_c above the tip (ball: R·s, R(1 − n_z); flat: the rim; bull-nose: the torus
//!   ring plus r·s; cone: the apex or the rim). The contact counts when that point of the plane
//!   lies inside the triangle.
//! - Edge: in the vertical plane through the edge, at distance d from the axis, the cutter's
//!   section is f(t) = h(√(d² + t²)) for |t| ≤ √(R² − d²), a convex function of the position t
//!   along the edge. The tip height z_line(t) − f(t) is concave, so its maximum on the edge is
//!   the clamped root of f′(t) = m (m = the edge's slope): in closed form for ball, flat and cone,
//!   by bisection on the monotone f′ for the bull-nose (the torus–line contact that OpenCAMLib
//!   solves with its offset ellipse).

use glam::{DVec2, DVec3};

use super::{ClPoint, Contact};
use crate::tools::{Cutter, CutterKind};

/// Keep `cand` if it is higher than `best`.
fn offer(best: &mut Option<ClPoint>, cand: ClPoint) {
    if cand.z.is_finite() && best.is_none_or(|b| cand.z > b.z) {
        *best = Some(cand);
    }
}

/// Run the vertex, facet and edge tests of triangle `tri` (index `t`) for the cutter at `c`.
pub(super) fn drop_on_triangle(
    cutter: &Cutter,
    c: DVec2,
    tri: &[DVec3; 3],
    t: usize,
    best: &mut Option<ClPoint>,
) {
    for p in tri {
        vertex(cutter, c, *p, t, best);
    }
    facet(cutter, c, tri, t, best);
    for (a, b) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
        edge(cutter, c, a, b, t, best);
    }
}

fn vertex(cutter: &Cutter, c: DVec2, p: DVec3, t: usize, best: &mut Option<ClPoint>) {
    let q = p.truncate().distance(c);
    if let Some(h) = cutter.height_at_radius(q) {
        offer(
            best,
            ClPoint {
                z: p.z - h,
                cc: p,
                contact: Contact::Vertex,
                triangle: t,
            },
        );
    }
}

fn facet(cutter: &Cutter, c: DVec2, tri: &[DVec3; 3], t: usize, best: &mut Option<ClPoint>) {
    let Some(mut n) = (tri[1] - tri[0]).cross(tri[2] - tri[0]).try_normalize() else {
        return;
    };
    if n.z < 0.0 {
        n = -n;
    }
    if n.z < 1e-12 {
        return; // vertical: only its edges and vertices can be touched from above
    }
    let s = n.truncate().length();
    let big = cutter.radius();
    let mut candidates = [(0.0, 0.0); 2];
    let count = match cutter.kind {
        CutterKind::Ball => {
            candidates[0] = (big * s, big * (1.0 - n.z));
            1
        }
        CutterKind::Flat => {
            candidates[0] = (if s > 0.0 { big } else { 0.0 }, 0.0);
            1
        }
        CutterKind::BullNose { corner_radius } => {
            let a = big - corner_radius;
            candidates[0] = (
                if s > 0.0 { a + corner_radius * s } else { 0.0 },
                corner_radius * (1.0 - n.z),
            );
            1
        }
        CutterKind::Cone { .. } => {
            candidates[1] = (big, cutter.profile_height());
            2
        }
    };
    let dir = if s > 0.0 {
        -n.truncate() / s
    } else {
        DVec2::ZERO
    };
    for &(rc, hc) in candidates.iter().take(count) {
        let xy = c + dir * rc;
        if !inside_xy(tri, xy) {
            continue;
        }
        let z = tri[0].z - (n.x * (xy.x - tri[0].x) + n.y * (xy.y - tri[0].y)) / n.z;
        offer(
            best,
            ClPoint {
                z: z - hc,
                cc: xy.extend(z),
                contact: Contact::Facet,
                triangle: t,
            },
        );
    }
}

/// Is `p` inside (or on) the XY projection of the triangle?
fn inside_xy(tri: &[DVec3; 3], p: DVec2) -> bool {
    let a = tri[0].truncate();
    let b = tri[1].truncate();
    let c = tri[2].truncate();
    let area = (b - a).perp_dot(c - a);
    if area == 0.0 {
        return false;
    }
    let w0 = (b - p).perp_dot(c - p) / area;
    let w1 = (c - p).perp_dot(a - p) / area;
    let w2 = 1.0 - w0 - w1;
    let eps = -1e-12;
    w0 >= eps && w1 >= eps && w2 >= eps
}

fn edge(cutter: &Cutter, c: DVec2, p1: DVec3, p2: DVec3, t: usize, best: &mut Option<ClPoint>) {
    let e = (p2 - p1).truncate();
    let len = e.length();
    if !(len > 1e-12) {
        return; // vertical or degenerate: the vertex tests cover it
    }
    let u = e / len;
    let rel = p1.truncate() - c;
    let t1 = rel.dot(u);
    let d = u.perp_dot(rel).abs();
    let big = cutter.radius();
    if d > big {
        return;
    }
    // Every point of the section is at least h(d) above the tip and the edge is no higher than
    // its top end: skip edges that cannot beat the best contact so far.
    if let (Some(b), Some(hd)) = (*best, cutter.height_at_radius(d))
        && p1.z.max(p2.z) - hd <= b.z
    {
        return;
    }
    let s = (big * big - d * d).max(0.0).sqrt();
    let lo = t1.max(-s);
    let hi = (t1 + len).min(s);
    if lo > hi {
        return;
    }
    let m = (p2.z - p1.z) / len;
    let t_star = match cutter.kind {
        CutterKind::Ball => s * m / (1.0 + m * m).sqrt(),
        CutterKind::Flat => {
            if m > 0.0 {
                s
            } else if m < 0.0 {
                -s
            } else {
                0.0
            }
        }
        CutterKind::Cone { half_angle } => {
            let k = m * half_angle.tan();
            if k.abs() < 1.0 {
                k * d / (1.0 - k * k).sqrt()
            } else {
                s * m.signum()
            }
        }
        CutterKind::BullNose { .. } => bisect_tangency(cutter, d, m, lo, hi),
    }
    .clamp(lo, hi);
    if t_star <= t1 || t_star >= t1 + len {
        return; // an end of the edge: the vertex test covers it
    }
    let rho = (d * d + t_star * t_star).sqrt().min(big);
    let Some(h) = cutter.height_at_radius(rho) else {
        return;
    };
    let cc = p1 + (p2 - p1) * ((t_star - t1) / len);
    offer(
        best,
        ClPoint {
            z: cc.z - h,
            cc,
            contact: Contact::Edge,
            triangle: t,
        },
    );
}

/// The t in [lo, hi] maximising m·t − f(t), f(t) = h(√(d² + t²)) convex: bisection on the
/// non-increasing g(t) = m − f′(t).
fn bisect_tangency(cutter: &Cutter, d: f64, m: f64, mut lo: f64, mut hi: f64) -> f64 {
    let g = |t: f64| {
        let rho = (d * d + t * t).sqrt();
        let df = if rho > 0.0 {
            cutter.slope_at_radius(rho.min(cutter.radius())) * t / rho
        } else {
            0.0
        };
        // At the rim the slope is infinite: treat ∞·0 as the sign of t.
        if df.is_nan() {
            m - t.signum() * f64::INFINITY
        } else {
            m - df
        }
    };
    if g(lo) <= 0.0 {
        return lo;
    }
    if g(hi) >= 0.0 {
        return hi;
    }
    // The optimum is interior (f′ = m there), so the tip height's error is second order in the
    // bracket: 1e-9 of the radius leaves it far below 1e-12 mm.
    let stop = 1e-9 * cutter.radius();
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if hi - lo <= stop || mid <= lo || mid >= hi {
            break;
        }
        if g(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
