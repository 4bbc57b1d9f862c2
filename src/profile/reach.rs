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
use crate::geometry::planar::{BoxTree, Element, ElementIndex, box_distance};

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
    let index = ElementIndex::new(&elements);
    let boxes: Vec<(DVec2, DVec2)> = features
        .iter()
        .map(|f| feature_box(&elements, *f))
        .collect();
    let tree = BoxTree::new(boxes);
    // Every pair once (g after f), but only the features a bottleneck from f can reach: in
    // front of f along its free-side normals and nearer than twice the best radius so far.
    // The pairs a scan would test and these prune have no bottleneck of a smaller radius, so
    // the answer is the scan's, in near-linear time on a profile's chain of features.
    let slack = 1e-9 * scale;
    for (x, f) in features.iter().enumerate() {
        let Some((flo, fhi)) = tree.item_box(x) else {
            continue;
        };
        let reach = Reach::of(&elements, *f, left, scale);
        let mut found: Vec<usize> = Vec::new();
        tree.search(
            &mut |lo, hi, _first, last| {
                last > x + 1
                    && (!best.is_finite()
                        || box_gap(flo, fhi, lo, hi) <= 2.0 * best * (1.0 + 1e-9) + slack)
                    && reach.may_reach(lo, hi)
            },
            &mut |y| {
                if y > x {
                    found.push(y);
                }
                true
            },
        );
        found.sort_unstable();
        for y in found {
            let Some(g) = features.get(y) else {
                continue;
            };
            for (p, q) in candidates(&elements, *f, *g) {
                if let Some(rho) = bottleneck(&index, *f, *g, p, q, left, scale) {
                    best = best.min(rho);
                }
            }
        }
    }
    best
}

/// The box of a feature.
fn feature_box(elements: &[Element], f: Feature) -> (DVec2, DVec2) {
    match f {
        Feature::Elem(i) => elements
            .get(i)
            .map_or((DVec2::ZERO, DVec2::ZERO), Element::bounds),
        Feature::Corner(v, _, _) => (v, v),
    }
}

/// The gap between two boxes (0 when they overlap).
fn box_gap(alo: DVec2, ahi: DVec2, blo: DVec2, bhi: DVec2) -> f64 {
    let d = (blo - ahi).max(alo - bhi).max(DVec2::ZERO);
    d.length()
}

/// Where the other end q of a bottleneck from a feature can lie: pq is along a free-side
/// normal at p, so q is in front of the feature (a line's strip, outside or inside an arc's
/// circle, a corner's cone of normals). Each test is a half-plane or a disc that holds every
/// such q, widened by `slack`.
enum Reach {
    /// In front of the line from `a` along `n`, across its length along `d` (0 to `len`).
    Strip {
        a: DVec2,
        d: DVec2,
        n: DVec2,
        len: f64,
        slack: f64,
    },
    /// Outside (`outward`) or inside the circle.
    Circle {
        centre: DVec2,
        radius: f64,
        outward: bool,
        slack: f64,
    },
    /// In the cone at `v` between the free-side normals `n_in` and `n_out` (turning by
    /// `theta`, less than π).
    Cone {
        v: DVec2,
        n_in: DVec2,
        n_out: DVec2,
        theta: f64,
        slack: f64,
    },
    /// Anywhere.
    Any,
}

impl Reach {
    fn of(elements: &[Element], f: Feature, left: bool, scale: f64) -> Self {
        // `faces` admits a direction within about 4.5e-5 rad of the normal (its cosine above
        // 1 − 1e-9): over a bottleneck as long as the profile that moves q sideways by
        // 4.5e-5 of the profile's size. Slack of 1e-4 of it covers that.
        let slack = 1e-4 * scale;
        match f {
            Feature::Elem(i) => match elements.get(i) {
                Some(&Element::Line { a, b }) => {
                    let len = (b - a).length();
                    if len <= 0.0 {
                        return Self::Any;
                    }
                    let d = (b - a) / len;
                    let n = if left { d.perp() } else { -d.perp() };
                    Self::Strip {
                        a,
                        d,
                        n,
                        len,
                        slack,
                    }
                }
                Some(e @ &Element::Arc { centre, radius, .. }) => {
                    let mid = e.point_at(0.5);
                    let outward = free_normal(e, 0.5, left).dot(mid - centre) > 0.0;
                    Self::Circle {
                        centre,
                        radius,
                        outward,
                        slack: slack + 1e-4 * radius,
                    }
                }
                None => Self::Any,
            },
            Feature::Corner(v, n_in, n_out) => {
                let theta = signed_turn(n_in, n_out);
                if theta.abs() >= std::f64::consts::PI - 1e-6 {
                    return Self::Any;
                }
                Self::Cone {
                    v,
                    n_in,
                    n_out,
                    theta,
                    slack,
                }
            }
        }
    }

    /// False only when no point of the box `[lo, hi]` can be such a q.
    fn may_reach(&self, lo: DVec2, hi: DVec2) -> bool {
        let corners = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)];
        match *self {
            Self::Strip {
                a,
                d,
                n,
                len,
                slack,
            } => {
                let ahead = corners.iter().any(|c| (*c - a).dot(n) > -slack);
                let along = corners.iter().map(|c| (*c - a).dot(d));
                let (s0, s1) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(x, y), s| {
                    (x.min(s), y.max(s))
                });
                ahead && s1 >= -slack && s0 <= len + slack
            }
            Self::Circle {
                centre,
                radius,
                outward,
                slack,
            } => {
                if outward {
                    let far = corners
                        .iter()
                        .map(|c| (*c - centre).length())
                        .fold(0.0, f64::max);
                    far >= radius - slack
                } else {
                    box_distance(lo, hi, centre) <= radius + slack
                }
            }
            Self::Cone {
                v,
                n_in,
                n_out,
                theta,
                slack,
            } => {
                let s = theta.signum();
                // The cone is the meet of three half-planes: left (for s > 0) of the first
                // normal, right of the second, in front of their bisector.
                let bis = (n_in + n_out).normalize_or_zero();
                let out_of = |f: &dyn Fn(DVec2) -> f64| corners.iter().all(|c| f(*c - v) < -slack);
                !(out_of(&|w| s * n_in.perp_dot(w))
                    || out_of(&|w| s * w.perp_dot(n_out))
                    || out_of(&|w| w.dot(bis)))
            }
            Self::Any => true,
        }
    }
}

/// Half the length of pq when it is a free-side bottleneck between features `f` (at p) and `g`
/// (at q) with an empty diametral ball.
fn bottleneck(
    index: &ElementIndex,
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
    let elements = index.elements();
    if !faces(elements, f, p, u, left) || !faces(elements, g, q, -u, left) {
        return None;
    }
    let rho = len / 2.0;
    let (d, _, _) = index.closest((p + q) / 2.0)?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::planar::{Vertex, closest_on};

    /// Every pair of features, each bottleneck checked with a scan: the reference the pruned
    /// search must agree with.
    fn scan(profile: &Profile, left: bool) -> f64 {
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
        let joints = if profile.closed { m } else { m - 1 };
        for k in 0..joints {
            let (a, b) = (&elements[k], &elements[(k + 1) % m]);
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
        let scale = profile.extent_mm();
        for (x, f) in features.iter().enumerate() {
            for g in features.iter().skip(x + 1) {
                for (p, q) in candidates(&elements, *f, *g) {
                    let len = (q - p).length();
                    if len <= 1e-12 * scale {
                        continue;
                    }
                    let u = (q - p) / len;
                    if !faces(&elements, *f, p, u, left) || !faces(&elements, *g, q, -u, left) {
                        continue;
                    }
                    let rho = len / 2.0;
                    let (d, _, _) = closest_on(&elements, (p + q) / 2.0).unwrap();
                    if d >= rho * (1.0 - 1e-9) {
                        best = best.min(rho);
                    }
                }
            }
        }
        best
    }

    /// Spirals, stars, slots and wavy rings of lines and arcs, both sides: the pruned search
    /// gives the scan's radius, and finite ones occur (bottlenecks found, not all pruned).
    #[test]
    fn the_pruned_search_finds_the_scans_radius() {
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut finite = 0;
        for case in 0..60 {
            let kind = case % 4;
            let n = 12 + case % 17;
            let mut vertices = Vec::new();
            for k in 0..n {
                let s = f64::from(k) / f64::from(n);
                let (x, y) = match kind {
                    // A spiral: its turns face each other.
                    0 => {
                        let a = s * 3.0 * std::f64::consts::TAU;
                        let r = 5.0 + 6.0 * s;
                        (r * a.cos(), r * a.sin())
                    }
                    // A ring with a random radius per vertex.
                    1 | 2 => {
                        let a = s * std::f64::consts::TAU;
                        let r = 10.0 + if kind == 1 { 3.0 * rnd() } else { 0.0 };
                        (r * a.cos(), r * a.sin())
                    }
                    // A slot: two long parallel sides.
                    _ => {
                        let half = n / 2;
                        if k < half {
                            (30.0 * f64::from(k) / f64::from(half), 0.0)
                        } else {
                            (
                                30.0 * f64::from(n - 1 - k) / f64::from(half),
                                4.0 + rnd() * 1e-3,
                            )
                        }
                    }
                };
                let bulge = if kind == 2 && k % 3 == 0 { -0.1 } else { 0.0 };
                vertices.push(Vertex { x, y, bulge });
            }
            let closed = kind != 0;
            let profile = Profile { vertices, closed };
            if profile.validate("test").is_err() {
                continue;
            }
            for left in [true, false] {
                let want = scan(&profile, left);
                let got = max_gouge_free_radius(&profile, left);
                assert!(
                    want == got || (want - got).abs() <= 1e-12 * want.abs(),
                    "case {case} left {left}: {got} vs the scan's {want}"
                );
                finite += usize::from(want.is_finite() && want > 0.0);
            }
        }
        assert!(finite >= 5, "{finite} profiles with a finite reach");
    }
}
