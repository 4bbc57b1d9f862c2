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
//!   and for the bull-nose over its axis (d = 0); otherwise for the bull-nose by a bracketed
//!   Newton iteration on the monotone f′ (the torus–line contact that OpenCAMLib solves with its
//!   offset ellipse, a quartic).

use glam::{DVec2, DVec3};

use super::{ClPoint, Contact};
use crate::tools::{Cutter, CutterKind};

/// Keep `cand` if it is higher than `best`.
fn offer(best: &mut Option<ClPoint>, cand: ClPoint) {
    if cand.z.is_finite() && best.is_none_or(|b| cand.z > b.z) {
        *best = Some(cand);
    }
}

/// The unit normal of a triangle pointing up (z ≥ 0), as the facet test uses it; `None` for a
/// degenerate triangle.
pub(super) fn upward_normal(tri: &[DVec3; 3]) -> Option<DVec3> {
    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).try_normalize()?;
    Some(if n.z < 0.0 { -n } else { n })
}

/// Run the vertex, facet and edge tests of triangle `tri` (index `t`, upward unit normal
/// `normal` from [`upward_normal`]) for the cutter at `c`.
pub(super) fn drop_on_triangle(
    cutter: &Cutter,
    c: DVec2,
    tri: &[DVec3; 3],
    normal: Option<DVec3>,
    t: usize,
    best: &mut Option<ClPoint>,
) {
    for p in tri {
        vertex(cutter, c, *p, t, best);
    }
    if let Some(n) = normal {
        facet(cutter, c, tri, n, t, best);
    }
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

fn facet(
    cutter: &Cutter,
    c: DVec2,
    tri: &[DVec3; 3],
    n: DVec3,
    t: usize,
    best: &mut Option<ClPoint>,
) {
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
        CutterKind::BullNose { corner_radius } => {
            bull_tangency(d, m, big - corner_radius, corner_radius, lo, hi)
        }
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

/// The t in [lo, hi] maximising m·t − f(t) for the bull-nose (flat radius a, corner radius r),
/// f(t) = h(ρ), ρ = √(d² + t²), convex: the root of the non-increasing g(t) = m − f′(t).
///
/// On the torus (q = ρ − a > 0, w = √(r² − q²)): h′ = q/w, h″ = r²/w³, f′ = h′·t/ρ and
/// f″ = h″·t²/ρ² + h′·d²/ρ³. Over the axis (d = 0) the root is closed form:
/// q = r·|m|/√(1 + m²), t = sign(m)·(a + q). Otherwise the torus–line tangency is a quartic
/// (OpenCAMLib's offset ellipse), solved by Newton's method kept inside the bracket (a
/// bisection step whenever Newton would leave it, as on the flat part where g is constant).
fn bull_tangency(d: f64, m: f64, a: f64, r: f64, mut lo: f64, mut hi: f64) -> f64 {
    // (g, g′) at t; at the rim the slope is infinite: g takes the sign of −t there.
    let g = |t: f64| -> (f64, f64) {
        let rho = (d * d + t * t).sqrt();
        let q = rho - a;
        if !(rho > 0.0) || q <= 0.0 {
            return (m, 0.0);
        }
        let w = (r * r - q * q).max(0.0).sqrt();
        if !(w > 0.0) {
            return (m - t.signum() * f64::INFINITY, f64::NEG_INFINITY);
        }
        let h1 = q / w;
        let h2 = r * r / (w * w * w);
        let (c, s) = (t / rho, d / rho);
        (m - h1 * c, -(h2 * c * c + h1 * s * s / rho))
    };
    if g(lo).0 <= 0.0 {
        return lo;
    }
    if g(hi).0 >= 0.0 {
        return hi;
    }
    if d == 0.0 {
        let q = r * m.abs() / (1.0 + m * m).sqrt();
        return (m.signum() * (a + q)).clamp(lo, hi);
    }
    // The optimum is interior (f′ = m there), so the tip height's error is second order in the
    // bracket: 1e-9 of the radius leaves it far below 1e-12 mm.
    let stop = 1e-9 * (a + r);
    let mut t = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (gt, dg) = g(t);
        if gt > 0.0 {
            lo = t;
        } else if gt < 0.0 {
            hi = t;
        } else {
            return t;
        }
        if hi - lo <= stop {
            break;
        }
        let next = t - gt / dg;
        if next.is_finite() && next > lo && next < hi {
            let converged = (next - t).abs() <= 1e-3 * stop;
            t = next;
            if converged {
                return t;
            }
        } else {
            t = 0.5 * (lo + hi);
        }
    }
    0.5 * (lo + hi)
}
