//! One computation for a profile and an electrode radius: the exact centre path, the naïve
//! per-point path of the seed's method with every gouge it would make, the largest gouge-free
//! radius, and a certificate of the exact path's distance to the profile.

use glam::DVec2;
use std::f64::consts::PI;

use super::reach::max_gouge_free_radius;
use crate::geometry::planar::{ClPath, Side, offset_paths};
use crate::geometry::planar::{Element, ElementIndex};
use crate::geometry::planar::{Profile, ProfileError};

/// Settings of [`compute_opt`].
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileOptions {
    /// Electrode (ball) radius, mm.
    pub radius_mm: f64,
    /// The material-free side.
    pub side: Side,
    /// Gouges of the naïve path up to this depth are not flagged, mm.
    pub gouge_tolerance_mm: f64,
}

impl ProfileOptions {
    /// Options for radius `radius_mm` on `side`, with a 1 µm gouge tolerance.
    #[must_use]
    pub fn new(radius_mm: f64, side: Side) -> Self {
        Self {
            radius_mm,
            side,
            gouge_tolerance_mm: 1e-3,
        }
    }
}

/// The centre of the naïve path at one profile point: point + R · normal, the normal taken
/// from the neighbouring points (one-sided at the ends of an open profile).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct NaivePoint {
    /// The profile point, mm.
    pub point: DVec2,
    /// Unit normal toward the free side.
    pub normal: DVec2,
    /// Electrode centre, mm.
    pub centre: DVec2,
    /// How far the electrode at this centre cuts into the profile (R − distance), mm; 0 when
    /// it does not.
    pub gouge_mm: f64,
}

/// What a flagged gouge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FlagKind {
    /// The profile next to the point turns concavely into the electrode (concave radius < R).
    Plunge,
    /// Another part of the profile enters the electrode.
    Collision,
}

/// One gouge of the naïve path.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Flag {
    /// Plunge or side collision.
    pub kind: FlagKind,
    /// Index of the profile point (0-based).
    pub point_index: usize,
    /// The profile point, mm.
    pub point: DVec2,
    /// The naïve electrode centre, mm.
    pub centre: DVec2,
    /// Depth of the gouge (R − distance from the centre to the gouged part), mm.
    pub depth_mm: f64,
    /// The deepest gouged profile point, mm.
    pub deepest: DVec2,
    /// The gouged span of the profile, as arc-length positions from its start, mm.
    pub span_mm: (f64, f64),
    /// Radius of the circle through the point and its neighbours when the profile turns
    /// concavely there, mm.
    pub concave_radius_mm: Option<f64>,
}

/// Everything [`compute`] finds.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ProfileResult {
    /// Electrode radius, mm.
    pub radius_mm: f64,
    /// The side resolved to left (true) or right of the direction of travel.
    pub left: bool,
    /// The exact centre path in pieces.
    pub paths: Vec<ClPath>,
    /// The naïve path, one centre per profile point.
    pub naive: Vec<NaivePoint>,
    /// Gouges of the naïve path deeper than the tolerance.
    pub flags: Vec<Flag>,
    /// Largest radius that touches every profile point from the free side, mm.
    pub max_gouge_free_radius_mm: f64,
    /// Largest radius whose ball touching every profile point from the free side gouges it by
    /// at most the gouge tolerance, mm (the radius to suggest for a profile digitised as dense
    /// points, where the exact reach is 0 at every concave kink).
    pub max_radius_within_tolerance_mm: f64,
    /// Smallest radius of the circles through concave points and their neighbours (the
    /// seed's reading of a point profile as a sampled curve), mm; `None` without concave
    /// points.
    pub min_concave_radius_sampled_mm: Option<f64>,
    /// Largest |distance − R| of the exact path's vertices and element midpoints, mm.
    pub max_distance_error_mm: f64,
}

/// [`compute_opt`] with a 1 µm gouge tolerance.
///
/// # Errors
/// As [`compute_opt`].
pub fn compute(
    profile: &Profile,
    radius_mm: f64,
    side: Side,
) -> Result<ProfileResult, ProfileError> {
    compute_opt(profile, &ProfileOptions::new(radius_mm, side))
}

/// Validates the profile and options and computes the exact path, the naïve path and its
/// flags, and the largest gouge-free radius.
///
/// # Errors
/// [`ProfileError`] for an invalid profile, a radius outside (0, 10⁶] mm, a negative or
/// non-finite tolerance, a side that does not fit the profile, or duplicate neighbours that
/// leave a point without a normal.
pub fn compute_opt(
    profile: &Profile,
    opts: &ProfileOptions,
) -> Result<ProfileResult, ProfileError> {
    profile.validate("<memory>")?;
    let r = opts.radius_mm;
    if !(r > 0.0 && r <= crate::geometry::planar::MAX_COORD_MM) {
        return Err(ProfileError::new(
            "<memory>",
            "radius",
            format!("electrode radius {r} mm must be in (0, 1e6] mm"),
        ));
    }
    if !(opts.gouge_tolerance_mm >= 0.0 && opts.gouge_tolerance_mm.is_finite()) {
        return Err(ProfileError::new(
            "<memory>",
            "gouge tolerance",
            format!("{} mm must be ≥ 0", opts.gouge_tolerance_mm),
        ));
    }
    let left = opts
        .side
        .is_left(profile)
        .map_err(|m| ProfileError::new("<memory>", "side", m))?;
    let paths = offset_paths(profile, r, left);
    let elements = profile.elements();
    let index = ElementIndex::new(&elements);
    let naive = naive_path(profile, &index, r, left)?;
    let flags = flags(profile, &index, &naive, r, left, opts.gouge_tolerance_mm);
    let max_distance_error_mm = certify(&paths, &index, r);
    Ok(ProfileResult {
        radius_mm: r,
        left,
        paths,
        naive,
        flags,
        max_gouge_free_radius_mm: max_gouge_free_radius(profile, left),
        max_radius_within_tolerance_mm: super::reach_tolerance::max_radius_within_tolerance(
            profile,
            left,
            opts.gouge_tolerance_mm,
        ),
        min_concave_radius_sampled_mm: min_concave_radius_sampled(profile, left),
        max_distance_error_mm,
    })
}

/// Largest |distance to the profile − R| over the path's vertices and element midpoints.
fn certify(paths: &[ClPath], index: &ElementIndex, r: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for p in paths {
        let mids = p.elements().into_iter().map(|e| e.point_at(0.5));
        for q in p.vertices.iter().map(|v| v.centre).chain(mids) {
            if let Some((d, _, _)) = index.closest(q) {
                worst = worst.max((d - r).abs());
            }
        }
    }
    worst
}

/// The naïve (per-point normal) path: for every profile point the normal of the chord between
/// its neighbours (the tangent of the first or last element at the ends of an open profile).
fn naive_path(
    profile: &Profile,
    index: &ElementIndex,
    r: f64,
    left: bool,
) -> Result<Vec<NaivePoint>, ProfileError> {
    let n = profile.vertices.len();
    let pos = |i: usize| profile.vertices.get(i).map_or(DVec2::ZERO, |v| v.pos());
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let (prev, next) = if profile.closed {
            ((i + n - 1) % n, (i + 1) % n)
        } else {
            (i.saturating_sub(1), (i + 1).min(n - 1))
        };
        let mut t = (pos(next) - pos(prev)).normalize_or_zero();
        if t == DVec2::ZERO {
            // The profile turns back on itself here (the tip of a zero-width slit): the free
            // side is straight ahead, so the tangent is turned from the incoming direction.
            let incoming = (pos(i) - pos(prev)).normalize_or_zero();
            t = if left {
                -incoming.perp()
            } else {
                incoming.perp()
            };
        }
        if t == DVec2::ZERO {
            return Err(ProfileError::new(
                "<memory>",
                format!("vertex {}", i + 1),
                "its neighbours coincide with it, so the point has no normal",
            ));
        }
        let normal = if left { t.perp() } else { -t.perp() };
        let point = pos(i);
        let centre = point + normal * r;
        let d = index.closest(centre).map_or(r, |c| c.0);
        out.push(NaivePoint {
            point,
            normal,
            centre,
            gouge_mm: (r - d).max(0.0),
        });
    }
    Ok(out)
}

/// Radius of the circle through `a`, `b`, `c` and the signed turn at `b` (positive: left).
fn circumradius(a: DVec2, b: DVec2, c: DVec2) -> (f64, f64) {
    let cross = (b - a).perp_dot(c - b);
    let r = (b - a).length() * (c - b).length() * (c - a).length() / (2.0 * cross.abs());
    (r, cross)
}

/// The three-point concave radius at vertex `i`, when the profile turns toward the free side.
fn concave_radius_at(profile: &Profile, i: usize, left: bool) -> Option<f64> {
    let n = profile.vertices.len();
    let (prev, next) = if profile.closed {
        ((i + n - 1) % n, (i + 1) % n)
    } else if i == 0 || i + 1 >= n {
        return None;
    } else {
        (i - 1, i + 1)
    };
    let p = |k: usize| profile.vertices.get(k).map(|v| v.pos());
    let (r, cross) = circumradius(p(prev)?, p(i)?, p(next)?);
    let concave = if left { cross > 0.0 } else { cross < 0.0 };
    (concave && r.is_finite()).then_some(r)
}

fn min_concave_radius_sampled(profile: &Profile, left: bool) -> Option<f64> {
    (0..profile.vertices.len())
        .filter_map(|i| concave_radius_at(profile, i, left))
        .min_by(f64::total_cmp)
}

/// Signed angle from direction `a` to `b`, rad (positive: left).
fn turn(a: DVec2, b: DVec2) -> f64 {
    a.perp_dot(b).atan2(a.dot(b))
}

/// The turns of a profile's joints and arcs, with prefix counts and sums, so that
/// [`Turns::is_local`] answers in O(1) what a walk from the point to the gouged element answers
/// (all turns toward the free side, less than π in all) — a walk over every element between
/// them made the flags cubic on dense point profiles.
struct Turns {
    n: usize,
    closed: bool,
    /// `sign · turn` at each joint walking forward (joint m: from element m−1 into m), and
    /// backward (from element m into m−1), and `sign · sweep` of each element; `sign` is +1 for
    /// a free side on the left. Doubled (index m and m + n) for the wrap of a closed profile.
    fwd: Prefix,
    bwd: Prefix,
    along: Prefix,
    sign: f64,
}

/// Prefix sums of values and of the count of values below −ε.
struct Prefix {
    value: Vec<f64>,
    sum: Vec<f64>,
    bad: Vec<usize>,
}

const WALK_EPS: f64 = 1e-12;

impl Prefix {
    fn new(values: Vec<f64>) -> Self {
        let mut sum = Vec::with_capacity(values.len() + 1);
        let mut bad = Vec::with_capacity(values.len() + 1);
        let (mut s, mut b) = (0.0, 0usize);
        sum.push(s);
        bad.push(b);
        for v in &values {
            s += v;
            b += usize::from(*v < -WALK_EPS);
            sum.push(s);
            bad.push(b);
        }
        Self {
            value: values,
            sum,
            bad,
        }
    }

    /// Sum of values `lo..hi` and whether any is below −ε (`None` when one is).
    fn range(&self, lo: usize, hi: usize) -> Option<f64> {
        if hi <= lo {
            return Some(0.0);
        }
        let (Some(b0), Some(b1), Some(s0), Some(s1)) = (
            self.bad.get(lo),
            self.bad.get(hi),
            self.sum.get(lo),
            self.sum.get(hi),
        ) else {
            return None;
        };
        (b1 == b0).then_some(s1 - s0)
    }

    fn at(&self, m: usize) -> f64 {
        self.value.get(m).copied().unwrap_or(0.0)
    }
}

impl Turns {
    fn new(profile: &Profile, elements: &[Element], left: bool) -> Self {
        let n = elements.len();
        let sign = if left { 1.0 } else { -1.0 };
        let e = |m: usize| elements.get(m % n.max(1));
        let mut fwd = Vec::with_capacity(2 * n);
        let mut bwd = Vec::with_capacity(2 * n);
        let mut along = Vec::with_capacity(2 * n);
        for m in 0..2 * n {
            let (prev, cur) = (e(m + n - 1), e(m));
            let (f, b) = match (prev, cur) {
                (Some(p), Some(c)) => (
                    turn(p.tangent_at(1.0), c.tangent_at(0.0)),
                    turn(-c.tangent_at(0.0), -p.tangent_at(1.0)),
                ),
                _ => (0.0, 0.0),
            };
            fwd.push(sign * f);
            // Walking backward the free side flips, and so does the sign (see concave_walk).
            bwd.push(-sign * b);
            let sweep = match cur {
                Some(Element::Arc { sweep_rad, .. }) => *sweep_rad,
                _ => 0.0,
            };
            along.push(sign * sweep);
        }
        Self {
            n,
            closed: profile.closed,
            fwd: Prefix::new(fwd),
            bwd: Prefix::new(bwd),
            along: Prefix::new(along),
            sign,
        }
    }

    /// True when the profile from point `i` to parameter `t` of element `j` turns only toward
    /// the free side and by less than π in all: the gouged part belongs to the concave
    /// neighbourhood of the point (a plunge). Both directions are tried on a closed profile.
    fn is_local(&self, elements: &[Element], tangent: DVec2, i: usize, j: usize, t: f64) -> bool {
        let n = self.n;
        if n == 0 {
            return false;
        }
        let mut walks: Vec<(bool, usize)> = Vec::new();
        if self.closed {
            walks.push((true, (j + n - i) % n));
            walks.push((false, (i + n - 1 - j) % n));
        } else if j >= i {
            walks.push((true, j - i));
        } else {
            walks.push((false, i - 1 - j));
        }
        walks
            .into_iter()
            .any(|(forward, steps)| self.walk(elements, tangent, i, steps, forward, t))
    }

    /// The walk of `steps` elements past the first from vertex `i`, ending at parameter
    /// `t_end` of the last: every turn toward the free side and the total below π.
    fn walk(
        &self,
        elements: &[Element],
        tangent: DVec2,
        i: usize,
        steps: usize,
        forward: bool,
        t_end: f64,
    ) -> bool {
        let n = self.n;
        let eps = WALK_EPS;
        // The first element, from the point's own tangent.
        let first = if forward { i % n } else { (i + n - 1) % n };
        let Some(e0) = elements.get(first) else {
            return false;
        };
        let sign = if forward { self.sign } else { -self.sign };
        let (corner0, frac0) = if forward {
            (
                sign * turn(tangent, e0.tangent_at(0.0)),
                if steps == 0 { t_end.abs() } else { 1.0 },
            )
        } else {
            (
                sign * turn(-tangent, -e0.tangent_at(1.0)),
                if steps == 0 { (t_end - 1.0).abs() } else { 1.0 },
            )
        };
        let along0 = self.along.at(first) * frac0;
        if corner0 < -eps || along0 < -eps {
            return false;
        }
        let mut total = corner0 + along0;
        if steps > 0 {
            // Joints k = 1..=steps (full turns) and elements k = 1..steps−1 (full sweeps), then
            // the last element's sweep up to t_end.
            let (corners, middle, last, frac) = if forward {
                let lo = i % n + 1;
                let hi = i % n + steps;
                (
                    self.fwd.range(lo, hi + 1),
                    self.along.range(lo, hi),
                    hi,
                    t_end.abs(),
                )
            } else {
                // Joint of element m into m − 1 at index m; elements i−1−k for k = 1..steps.
                let top = i % n + n - 1; // element i − 1, shifted by n
                let lo = top + 1 - steps; // joints i−steps ..= i−1 (shifted)
                (
                    self.bwd.range(lo, top + 1),
                    self.along.range(top + 1 - steps, top),
                    top - steps,
                    (t_end - 1.0).abs(),
                )
            };
            let (Some(c), Some(m)) = (corners, middle) else {
                return false;
            };
            let a_last = self.along.at(last) * frac;
            if a_last < -eps {
                return false;
            }
            total += c + m + a_last;
        }
        total < PI - eps
    }
}

fn flags(
    profile: &Profile,
    index: &ElementIndex,
    naive: &[NaivePoint],
    r: f64,
    left: bool,
    tol: f64,
) -> Vec<Flag> {
    let elements = index.elements();
    let turns = Turns::new(profile, elements, left);
    let lengths: Vec<f64> = elements.iter().map(Element::length).collect();
    let starts: Vec<f64> = lengths
        .iter()
        .scan(0.0, |s, l| {
            let here = *s;
            *s += l;
            Some(here)
        })
        .collect();
    let mut out = Vec::new();
    for (i, np) in naive.iter().enumerate() {
        if np.gouge_mm <= tol {
            continue;
        }
        // The naïve tangent the normal was turned from.
        let tangent = if left {
            -np.normal.perp()
        } else {
            np.normal.perp()
        };
        let mut by_kind: [Option<Flag>; 2] = [None, None];
        // Only elements nearer than r − tol to the centre are gouged.
        for j in index.within(np.centre, r - tol) {
            let Some(e) = elements.get(j) else {
                continue;
            };
            let (q, t) = e.closest(np.centre);
            let depth = r - (q - np.centre).length();
            if depth <= tol {
                continue;
            }
            let local = turns.is_local(elements, tangent, i, j, t);
            let kind = if local {
                FlagKind::Plunge
            } else {
                FlagKind::Collision
            };
            let base = starts.get(j).copied().unwrap_or(0.0);
            let len = lengths.get(j).copied().unwrap_or(0.0);
            let spans = e.inside_disc(np.centre, r, tol);
            let (s0, s1) = spans
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |acc, &(a, b)| {
                    (acc.0.min(base + a * len), acc.1.max(base + b * len))
                });
            let slot = &mut by_kind[usize::from(!local)];
            match slot {
                Some(f) => {
                    if depth > f.depth_mm {
                        f.depth_mm = depth;
                        f.deepest = q;
                    }
                    f.span_mm = (f.span_mm.0.min(s0), f.span_mm.1.max(s1));
                }
                None => {
                    *slot = Some(Flag {
                        kind,
                        point_index: i,
                        point: np.point,
                        centre: np.centre,
                        depth_mm: depth,
                        deepest: q,
                        span_mm: (s0, s1),
                        concave_radius_mm: concave_radius_at(profile, i, left),
                    });
                }
            }
        }
        out.extend(by_kind.into_iter().flatten());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    // The walk element by element that `Turns` replaces: the reference it must agree with.
    /// True when the profile from point `i` to parameter `t` of element `j` turns only toward the
    /// free side and by less than π in all: the gouged part belongs to the concave neighbourhood
    /// of the point (a plunge). Both directions are tried on a closed profile.
    fn is_local(
        profile: &Profile,
        elements: &[Element],
        tangent: DVec2,
        i: usize,
        j: usize,
        t: f64,
        left: bool,
    ) -> bool {
        let n = elements.len();
        let mut walks: Vec<(bool, usize)> = Vec::new();
        if profile.closed {
            walks.push((true, (j + n - i) % n));
            walks.push((false, (i + n - 1 - j) % n));
        } else if j >= i {
            walks.push((true, j - i));
        } else {
            walks.push((false, i - 1 - j));
        }
        walks
            .into_iter()
            .any(|(forward, steps)| concave_walk(elements, tangent, i, steps, forward, t, left))
    }

    /// Walks `steps` elements past the first one from vertex `i` (forward or backward), ending at
    /// parameter `t_end` of the last, and checks that every turn is concave and the total below π.
    fn concave_walk(
        elements: &[Element],
        tangent: DVec2,
        i: usize,
        steps: usize,
        forward: bool,
        t_end: f64,
        left: bool,
    ) -> bool {
        let n = elements.len();
        // Concave turns are toward the free side, which flips when walking backward.
        let sign = if forward == left { 1.0 } else { -1.0 };
        let eps = 1e-12;
        let mut dir = if forward { tangent } else { -tangent };
        let mut total = 0.0;
        for k in 0..=steps {
            let idx = if forward {
                (i + k) % n
            } else {
                (i + n - 1 - k) % n
            };
            let Some(e) = elements.get(idx) else {
                return false;
            };
            // Traversal parameters of this element: from its near end to the far end (or t_end).
            let (t0, t1) = match (forward, k == steps) {
                (true, false) => (0.0, 1.0),
                (true, true) => (0.0, t_end),
                (false, false) => (1.0, 0.0),
                (false, true) => (1.0, t_end),
            };
            let oriented = |t: f64| {
                if forward {
                    e.tangent_at(t)
                } else {
                    -e.tangent_at(t)
                }
            };
            let corner = sign * turn(dir, oriented(t0));
            let along = sign * turn_along(e, t0, t1, forward);
            if corner < -eps || along < -eps {
                return false;
            }
            total += corner + along;
            dir = oriented(t1);
        }
        total < PI - eps
    }

    /// Signed turn of the travel direction along an element from `t0` to `t1`.
    fn turn_along(e: &Element, t0: f64, t1: f64, forward: bool) -> f64 {
        match *e {
            Element::Line { .. } => 0.0,
            Element::Arc { sweep_rad, .. } => {
                let s = sweep_rad * (t1 - t0).abs();
                if forward { s } else { -s }
            }
        }
    }

    /// `Turns::is_local` (prefix sums) answers what the element-by-element walk answers, on
    /// open and closed profiles with lines and arcs, both sides, every pair of point and
    /// element.
    #[test]
    fn prefix_walk_agrees_with_the_element_walk() {
        let mut seed = 99u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for case in 0..40 {
            let closed = case % 2 == 1;
            let n = 5 + case % 9;
            let mut vertices = Vec::new();
            for k in 0..n {
                let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
                let r = 10.0 + 4.0 * rnd();
                let (x, y) = if closed {
                    (r * a.cos(), r * a.sin())
                } else {
                    (f64::from(k) * 3.0, 4.0 * rnd() - 2.0)
                };
                let bulge = if rnd() < 0.3 { rnd() - 0.5 } else { 0.0 };
                vertices.push(crate::geometry::planar::Vertex { x, y, bulge });
            }
            let profile = Profile { vertices, closed };
            let elements = profile.elements();
            for left in [true, false] {
                let turns = Turns::new(&profile, &elements, left);
                let points = profile.vertices.len();
                for i in 0..points {
                    let (prev, next) = if closed {
                        ((i + points - 1) % points, (i + 1) % points)
                    } else {
                        (i.saturating_sub(1), (i + 1).min(points - 1))
                    };
                    let pos = |k: usize| profile.vertices[k].pos();
                    let tangent = (pos(next) - pos(prev)).normalize_or_zero();
                    for j in 0..elements.len() {
                        let t = rnd();
                        let want = is_local(&profile, &elements, tangent, i, j, t, left);
                        let got = turns.is_local(&elements, tangent, i, j, t);
                        assert_eq!(want, got, "case {case} left {left} i {i} j {j} t {t}");
                        checked += usize::from(want);
                    }
                }
            }
        }
        assert!(checked > 50, "{checked} local walks");
    }
}
