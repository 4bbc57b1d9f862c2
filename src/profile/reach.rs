//! The largest gouge-free electrode radius of a profile: the largest ball that touches every
//! point of the profile from its material-free side without crossing the profile elsewhere
//! (the one-sided reach).
//!
//! For lines and arcs the reach is the least of three closed-form bounds: zero at a concave
//! corner (a tangent break turning toward the free side), the radius of every concave arc, and
//! half the length of the shortest *bottleneck*: a segment pq normal to the profile at both
//! ends, facing the free side at both, whose diametral ball holds no profile point. The
//! candidate bottlenecks of two lines, a line and an arc, two arcs, and of convex corners (with
//! their cones of normals) against the rest are each found in closed form.

use glam::DVec2;

use crate::geometry::planar::Profile;
use crate::geometry::planar::{Element, closest_on};

/// Angles below this are treated as no turn (tangent-continuous joints), rad.
const ANGLE_EPS: f64 = 1e-9;

/// Something a bottleneck can end on.
#[derive(Clone, Copy, Debug)]
enum Feature {
    /// The interior of element `index`.
    Elem(usize),
    /// A convex corner: its point and the free-side normals before and after it.
    Corner(DVec2, DVec2, DVec2),
}

fn signed_turn(a: DVec2, b: DVec2) -> f64 {
    a.perp_dot(b).atan2(a.dot(b))
}

/// The free-side unit normal of an element at parameter `t`.
fn free_normal(e: &Element, t: f64, left: bool) -> DVec2 {
    let tan = e.tangent_at(t);
    if left { tan.perp() } else { -tan.perp() }
}

/// The largest radius that touches every point of `profile` from the side left (`left`) or
/// right of its direction, mm; 0 when it has a concave corner.
#[must_use]
pub fn max_gouge_free_radius(profile: &Profile, left: bool) -> f64 {
    let elements = profile.elements();
    let sign = if left { 1.0 } else { -1.0 };
    let mut best = f64::INFINITY;
    for e in &elements {
        if let Element::Arc {
            radius, sweep_rad, ..
        } = *e
            && sign * sweep_rad > 0.0
        {
            best = best.min(radius);
        }
    }
    let mut features: Vec<Feature> = (0..elements.len()).map(Feature::Elem).collect();
    let m = elements.len();
    let joints = if profile.closed {
        m
    } else {
        m.saturating_sub(1)
    };
    for k in 0..joints {
        let (Some(a), Some(b)) = (elements.get(k), elements.get((k + 1) % m)) else {
            continue;
        };
        let theta = signed_turn(a.tangent_at(1.0), b.tangent_at(0.0));
        if sign * theta > ANGLE_EPS {
            return 0.0;
        }
        if sign * theta < -ANGLE_EPS {
            features.push(Feature::Corner(
                a.end(),
                free_normal(a, 1.0, left),
                free_normal(b, 0.0, left),
            ));
        }
    }
    let scale = profile.extent_mm().max(1e-300);
    for (x, f) in features.iter().enumerate() {
        for g in features.iter().skip(x + 1) {
            for (p, q) in candidates(&elements, *f, *g) {
                if let Some(rho) = bottleneck(&elements, *f, *g, p, q, left, scale) {
                    best = best.min(rho);
                }
            }
        }
    }
    best
}

/// Half the length of pq when it is a free-side bottleneck between features `f` (at p) and `g`
/// (at q) with an empty diametral ball.
fn bottleneck(
    elements: &[Element],
    f: Feature,
    g: Feature,
    p: DVec2,
    q: DVec2,
    left: bool,
    scale: f64,
) -> Option<f64> {
    let len = (q - p).length();
    if len <= 1e-12 * scale {
        return None;
    }
    let u = (q - p) / len;
    if !faces(elements, f, p, u, left) || !faces(elements, g, q, -u, left) {
        return None;
    }
    let rho = len / 2.0;
    let (d, _, _) = closest_on(elements, (p + q) / 2.0)?;
    (d >= rho * (1.0 - 1e-9)).then_some(rho)
}

/// True when direction `u` at point `p` of feature `f` is a free-side normal there.
fn faces(elements: &[Element], f: Feature, p: DVec2, u: DVec2, left: bool) -> bool {
    match f {
        Feature::Elem(i) => elements.get(i).is_some_and(|e| {
            let (_, t) = e.closest(p);
            free_normal(e, t, left).dot(u) > 1.0 - 1e-9
        }),
        Feature::Corner(_, n_in, n_out) => {
            let theta = signed_turn(n_in, n_out);
            let a = signed_turn(n_in, u);
            a * theta >= -1e-12 && a.abs() <= theta.abs() + 1e-12
        }
    }
}

/// Foot of `p` on the line element from `a` to `b`, when it falls inside it.
fn foot(a: DVec2, b: DVec2, p: DVec2) -> Option<DVec2> {
    let d = b - a;
    let t = (p - a).dot(d) / d.length_squared();
    (t > 0.0 && t < 1.0).then(|| a + d * t)
}

/// The points of an arc on the line through its centre in direction `w`.
fn arc_points_along(e: &Element, w: DVec2) -> Vec<DVec2> {
    let Element::Arc { centre, radius, .. } = *e else {
        return Vec::new();
    };
    [w, -w]
        .into_iter()
        .map(|d| centre + d * radius)
        .filter(|q| (e.closest(*q).0 - *q).length() <= 1e-12 * radius.max(1.0))
        .collect()
}

/// Candidate bottleneck end points (p on `f`, q on `g`) in closed form.
fn candidates(elements: &[Element], f: Feature, g: Feature) -> Vec<(DVec2, DVec2)> {
    match (f, g) {
        (Feature::Elem(i), Feature::Elem(j)) => match (elements.get(i), elements.get(j)) {
            (Some(a), Some(b)) => elem_elem(a, b),
            _ => Vec::new(),
        },
        (Feature::Elem(i), Feature::Corner(v, _, _)) => elements
            .get(i)
            .map(|e| point_elem(v, e).into_iter().map(|p| (p, v)).collect())
            .unwrap_or_default(),
        (Feature::Corner(v, _, _), Feature::Elem(j)) => elements
            .get(j)
            .map(|e| point_elem(v, e).into_iter().map(|q| (v, q)).collect())
            .unwrap_or_default(),
        (Feature::Corner(v, _, _), Feature::Corner(w, _, _)) => vec![(v, w)],
    }
}

/// Points of element `e` where the segment to `v` is normal to `e`.
fn point_elem(v: DVec2, e: &Element) -> Vec<DVec2> {
    match *e {
        Element::Line { a, b } => foot(a, b, v).into_iter().collect(),
        Element::Arc { centre, .. } => {
            let w = (v - centre).normalize_or_zero();
            if w == DVec2::ZERO {
                return Vec::new();
            }
            arc_points_along(e, w)
        }
    }
}

fn elem_elem(e: &Element, f: &Element) -> Vec<(DVec2, DVec2)> {
    match (*e, *f) {
        (Element::Line { a, b }, Element::Line { a: c, b: d }) => line_line(a, b, c, d),
        (Element::Line { a, b }, Element::Arc { centre, .. }) => {
            let Some(ft) = foot(a, b, centre) else {
                return Vec::new();
            };
            let w = (ft - centre).normalize_or_zero();
            if w == DVec2::ZERO {
                return Vec::new();
            }
            arc_points_along(f, w)
                .into_iter()
                .map(|q| (ft, q))
                .collect()
        }
        (Element::Arc { .. }, Element::Line { .. }) => {
            elem_elem(f, e).into_iter().map(|(p, q)| (q, p)).collect()
        }
        (Element::Arc { centre: c1, .. }, Element::Arc { centre: c2, .. }) => {
            let w = (c2 - c1).normalize_or_zero();
            if w == DVec2::ZERO {
                return concentric(e, f);
            }
            let mut out = Vec::new();
            for p in arc_points_along(e, w) {
                for q in arc_points_along(f, w) {
                    out.push((p, q));
                }
            }
            out
        }
    }
}

/// Two parallel lines whose projections overlap: the pair at the middle of the overlap.
fn line_line(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> Vec<(DVec2, DVec2)> {
    let u = b - a;
    let v = d - c;
    let (lu, lv) = (u.length(), v.length());
    if u.perp_dot(v).abs() > 1e-12 * lu * lv {
        return Vec::new();
    }
    let dir = u / lu;
    let (s0, s1) = {
        let sc = (c - a).dot(dir);
        let sd = (d - a).dot(dir);
        (sc.min(sd).max(0.0), sc.max(sd).min(lu))
    };
    if s1 <= s0 {
        return Vec::new();
    }
    let p = a + dir * ((s0 + s1) / 2.0);
    let q = c + v * ((p - c).dot(v) / (lv * lv));
    vec![(p, q)]
}

/// Two arcs about one centre: a radial pair in the middle of their common angles, when they
/// share one.
fn concentric(e: &Element, f: &Element) -> Vec<(DVec2, DVec2)> {
    let Element::Arc { centre, .. } = *e else {
        return Vec::new();
    };
    // Sample the common angles at the arcs' own end and middle directions.
    let mut dirs = Vec::new();
    for el in [e, f] {
        for t in [0.0, 0.5, 1.0] {
            dirs.push((el.point_at(t) - centre).normalize_or_zero());
        }
    }
    dirs.into_iter()
        .filter(|w| *w != DVec2::ZERO)
        .filter_map(|w| {
            let p = arc_points_along(e, w)
                .into_iter()
                .find(|p| (*p - centre).dot(w) > 0.0)?;
            let q = arc_points_along(f, w)
                .into_iter()
                .find(|q| (*q - centre).dot(w) > 0.0)?;
            Some((p, q))
        })
        .take(1)
        .collect()
}
