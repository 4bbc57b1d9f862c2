//! Snapping the library's offset onto the exact offset curves.
//!
//! `cavalier_contours` places some vertices by intersecting curves that touch tangentially
//! (an offset arc meeting the end-cap circle of an open profile, an offset line meeting the
//! round join of a convex corner), where a floating-point intersection is only good to about
//! √ε: the vertex lies on the right circle but up to 1e-7 of the size along it. Each element of
//! the path is therefore matched to the exact curve it offsets (a profile line moved by R, a
//! profile arc with its radius changed by R, or the circle of radius R about a convex corner),
//! and each vertex is recomputed from its two curves: along the line of centres where they
//! touch, by their transversal intersection where they cross, and at the profile's end offset
//! at the ends of an open path. Bulges follow from the new vertices and the exact centres.

use glam::DVec2;

use super::element::Element;
use super::index::ElementIndex;

/// The exact curve an element of the path lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Carrier {
    /// A line through `p` with unit direction `d`.
    Line { p: DVec2, d: DVec2 },
    /// A circle.
    Circle { c: DVec2, r: f64 },
}

impl Carrier {
    /// The point of the carrier nearest `q`.
    fn project(self, q: DVec2) -> DVec2 {
        match self {
            Self::Line { p, d } => p + d * (q - p).dot(d),
            Self::Circle { c, r } => {
                let v = q - c;
                if v.length() > 0.0 {
                    c + v.normalize() * r
                } else {
                    q
                }
            }
        }
    }
}

/// The exact carrier of path element `e` among the profile's offset curves: the one that
/// passes closest to the element's two ends and its midpoint, within `eps`. Matching by points
/// rather than by the element's direction or arc centre keeps short elements, whose direction
/// and centre the library's vertices fix only roughly, on their curves.
fn carrier(e: &Element, index: &ElementIndex, radius: f64, eps: f64) -> Option<Carrier> {
    let probes = [e.start(), e.end(), e.point_at(0.5)];
    // The element the path element was offset from lies at the radius from its midpoint
    // (within eps): only the profile's elements that near are candidates (all of them made
    // the polish quadratic).
    let all = index.elements();
    let near = index.within(e.point_at(0.5), radius * (1.0 + 1e-9) + 2.0 * eps);
    let profile: Vec<&Element> = near.iter().filter_map(|&i| all.get(i)).collect();
    let fit = |c: Carrier| {
        probes
            .iter()
            .map(|q| (c.project(*q) - *q).length())
            .fold(0.0_f64, f64::max)
    };
    let candidates: Vec<Carrier> = match *e {
        Element::Line { a, b } => {
            let mid = (a + b) / 2.0;
            profile
                .iter()
                .copied()
                .filter_map(|pe| {
                    let Element::Line { a: pa, b: pb } = *pe else {
                        return None;
                    };
                    let pd = (pb - pa).normalize_or_zero();
                    let side = (mid - pa).perp_dot(pd);
                    let n = DVec2::new(-pd.y, pd.x) * side.signum();
                    Some(Carrier::Line {
                        p: pa + n * radius,
                        d: pd,
                    })
                })
                .collect()
        }
        Element::Arc { .. } => profile
            .iter()
            .copied()
            .flat_map(|pe| {
                let mut out: Vec<Carrier> = Vec::new();
                if let Element::Arc {
                    centre: pc,
                    radius: pr,
                    ..
                } = *pe
                {
                    out.extend(
                        [pr + radius, pr - radius]
                            .into_iter()
                            .filter(|rr| *rr > 0.0)
                            .map(|rr| Carrier::Circle { c: pc, r: rr }),
                    );
                }
                out.push(Carrier::Circle {
                    c: pe.start(),
                    r: radius,
                });
                out.push(Carrier::Circle {
                    c: pe.end(),
                    r: radius,
                });
                out
            })
            .collect(),
    };
    candidates
        .into_iter()
        .map(|c| (fit(c), c))
        .filter(|(f, _)| *f <= eps)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
}

/// The unit tangent of a carrier at a point on it (up to sign).
fn tangent(c: Carrier, q: DVec2) -> DVec2 {
    match c {
        Carrier::Line { d, .. } => d,
        Carrier::Circle { c, .. } => (q - c).perp().normalize_or_zero(),
    }
}

/// The meeting point of two carriers nearest `q`: along the line of centres where they touch,
/// their crossing otherwise; `None` when nothing lies within `eps`.
fn meet(a: Carrier, b: Carrier, q: DVec2, eps: f64) -> Option<DVec2> {
    let ta = tangent(a, q);
    let tb = tangent(b, q);
    let touching = ta.perp_dot(tb).abs() < 1e-6;
    let cand = if touching {
        match (a, b) {
            (Carrier::Line { .. }, Carrier::Circle { c, .. }) => a.project(c),
            (Carrier::Circle { c, .. }, Carrier::Line { .. }) => b.project(c),
            (Carrier::Circle { c: c1, r: r1 }, Carrier::Circle { c: c2, r: r2 }) => {
                // The touching point lies on the line of centres, on the larger circle.
                let (big_c, big_r, small_c) = if r1 >= r2 { (c1, r1, c2) } else { (c2, r2, c1) };
                let u = (small_c - big_c).normalize_or_zero();
                if u == DVec2::ZERO {
                    a.project(q)
                } else {
                    let p1 = big_c + u * big_r;
                    let p2 = big_c - u * big_r;
                    if (p1 - q).length() <= (p2 - q).length() {
                        p1
                    } else {
                        p2
                    }
                }
            }
            (Carrier::Line { .. }, Carrier::Line { .. }) => a.project(q),
        }
    } else {
        crossing(a, b, q)?
    };
    ((cand - q).length() <= eps).then_some(cand)
}

/// The transversal intersection of two carriers nearest `q`.
fn crossing(a: Carrier, b: Carrier, q: DVec2) -> Option<DVec2> {
    let roots: Vec<DVec2> = match (a, b) {
        (Carrier::Line { p, d }, Carrier::Line { p: p2, d: d2 }) => {
            let den = d.perp_dot(d2);
            if den == 0.0 {
                return None;
            }
            vec![p + d * ((p2 - p).perp_dot(d2) / den)]
        }
        (Carrier::Line { p, d }, Carrier::Circle { c, r })
        | (Carrier::Circle { c, r }, Carrier::Line { p, d }) => {
            let foot = p + d * (c - p).dot(d);
            let h2 = r * r - (foot - c).length_squared();
            if h2 < 0.0 {
                return None;
            }
            let h = h2.sqrt();
            vec![foot + d * h, foot - d * h]
        }
        (Carrier::Circle { c: c1, r: r1 }, Carrier::Circle { c: c2, r: r2 }) => {
            let dv = c2 - c1;
            let dist = dv.length();
            if dist == 0.0 {
                return None;
            }
            let x = (dist * dist + r1 * r1 - r2 * r2) / (2.0 * dist);
            let h2 = r1 * r1 - x * x;
            if h2 < 0.0 {
                return None;
            }
            let u = dv / dist;
            let base = c1 + u * x;
            let h = h2.sqrt();
            vec![base + u.perp() * h, base - u.perp() * h]
        }
    };
    roots
        .into_iter()
        .min_by(|x, y| (*x - q).length().total_cmp(&(*y - q).length()))
}

/// Snaps the vertices `(position, bulge)` of one path piece onto the exact offset of
/// `profile` by `radius`. `ends` are the exact offsets of an open profile's two end points.
pub(super) fn polish(
    verts: &mut [(DVec2, f64)],
    closed: bool,
    profile: &ElementIndex,
    radius: f64,
    ends: [Option<DVec2>; 2],
    eps: f64,
) {
    let n = verts.len();
    if n < 2 {
        return;
    }
    let m = if closed { n } else { n - 1 };
    let elements: Vec<Element> = (0..m)
        .filter_map(|i| {
            let (a, bulge) = *verts.get(i)?;
            let (b, _) = *verts.get((i + 1) % n)?;
            Some(Element::from_bulge(a, b, bulge))
        })
        .collect();
    let carriers: Vec<Option<Carrier>> = elements
        .iter()
        .map(|e| carrier(e, profile, radius, eps))
        .collect();
    for k in 0..n {
        let Some(&(q, _)) = verts.get(k) else {
            continue;
        };
        let before = if k > 0 {
            carriers.get(k - 1).copied().flatten()
        } else if closed {
            carriers.get(m - 1).copied().flatten()
        } else {
            None
        };
        let after = if k < m {
            carriers.get(k).copied().flatten()
        } else {
            None
        };
        let snapped = match (before, after) {
            // Where the meeting point is not found within eps, the vertex goes onto the
            // nearer of its curves: on an offset curve it is at distance R all the same.
            (Some(a), Some(b)) => meet(a, b, q, eps).or_else(|| {
                [a.project(q), b.project(q)]
                    .into_iter()
                    .filter(|p| (*p - q).length() <= eps)
                    .min_by(|x, y| (*x - q).length().total_cmp(&(*y - q).length()))
            }),
            (None, Some(c)) | (Some(c), None) => {
                let end = ends
                    .iter()
                    .flatten()
                    .copied()
                    .find(|e| (*e - q).length() <= eps);
                end.or_else(|| Some(c.project(q)).filter(|p| (*p - q).length() <= eps))
            }
            (None, None) => None,
        };
        if let (Some(p), Some(slot)) = (snapped, verts.get_mut(k)) {
            slot.0 = p;
        }
    }
    for (i, c) in carriers.iter().enumerate() {
        let Some(Carrier::Circle { c, .. }) = *c else {
            continue;
        };
        let (Some(&(a, bulge)), Some(&(b, _))) = (verts.get(i), verts.get((i + 1) % n)) else {
            continue;
        };
        let old = 4.0 * bulge.atan();
        let (va, vb) = (a - c, b - c);
        let mut sweep = va.perp_dot(vb).atan2(va.dot(vb));
        if old.abs() > std::f64::consts::PI - 1e-3 && sweep.signum() != old.signum() {
            sweep += std::f64::consts::TAU * old.signum();
        }
        if (sweep - old).abs() < 1e-4
            && let Some(slot) = verts.get_mut(i)
        {
            slot.1 = (sweep / 4.0).tan();
        }
    }
}
