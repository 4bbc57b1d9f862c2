//! The largest electrode radius whose gouge stays within a tolerance: what a machinist asks of a
//! profile digitised as dense points, where the exact one-sided reach
//! ([`super::max_gouge_free_radius`]) is 0 because every concave kink of the polyline is taken
//! literally.
//!
//! A ball of radius R touching the profile at point p from the free side (centre p + R·n) gouges
//! by `R − d(centre, profile)`. The balls touching at one point with one normal are nested as R
//! grows, so the gouge grows with R and the largest admissible R at each point is found by
//! bisection; the answer is the least over the points. The points are every vertex with the
//! per-point path's normal (square to the chord of its neighbours: the gouge the flags measure;
//! at a concave kink of turn θ between equal sides it is R·(1 − cos θ/2), so
//! R = tol / (1 − cos θ/2)), and points inside each element no farther apart than 1/2000 of the
//! profile's extent (at most [`MAX_SAMPLES`]) with the element's normal, which find the narrow
//! gaps. A uniform grid of the elements answers "is any element closer than R − tol to the
//! centre?". (A one-sided normal at a vertex is not tried: on a densely digitised curve it is
//! the chord's, half a kink off the curve's, and would gouge a ball the curve admits.)

use glam::DVec2;

use crate::geometry::planar::{Element, Profile};

/// At most this many touching points are tried.
const MAX_SAMPLES: usize = 100_000;
/// Bisection steps per point (relative precision 2⁻⁴⁰ of the bracket).
const STEPS: usize = 40;

/// The elements binned in a uniform grid of their bounding boxes.
struct Grid {
    lo: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    bins: Vec<Vec<u32>>,
}

impl Grid {
    fn new(elements: &[Element], lo: DVec2, hi: DVec2) -> Self {
        let size = (hi - lo).max(DVec2::splat(1e-9));
        let n = (elements.len() as f64).sqrt().ceil().clamp(1.0, 512.0);
        let cell = (size.max_element() / n).max(1e-9);
        let nx = ((size.x / cell).ceil() as usize).max(1);
        let ny = ((size.y / cell).ceil() as usize).max(1);
        let mut grid = Self {
            lo,
            cell,
            nx,
            ny,
            bins: vec![Vec::new(); nx * ny],
        };
        for (i, e) in elements.iter().enumerate() {
            let (a, b) = e.bounds();
            let (x0, y0) = grid.index(a);
            let (x1, y1) = grid.index(b);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    grid.bins[y * nx + x].push(u32::try_from(i).unwrap_or(u32::MAX));
                }
            }
        }
        grid
    }

    fn index(&self, p: DVec2) -> (usize, usize) {
        let f = (p - self.lo) / self.cell;
        let clamp = |v: f64, n: usize| (v.floor().max(0.0) as usize).min(n - 1);
        (clamp(f.x, self.nx), clamp(f.y, self.ny))
    }

    /// Is an element closer than `reach` to `c`?
    fn any_within(&self, elements: &[Element], c: DVec2, reach: f64) -> bool {
        if reach <= 0.0 {
            return false;
        }
        let (x0, y0) = self.index(c - DVec2::splat(reach));
        let (x1, y1) = self.index(c + DVec2::splat(reach));
        for y in y0..=y1 {
            for x in x0..=x1 {
                for &i in &self.bins[y * self.nx + x] {
                    if let Some(e) = elements.get(i as usize)
                        && e.distance(c) < reach
                    {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// The free-side unit normal of `e` at `t`.
fn free_normal(e: &Element, t: f64, left: bool) -> DVec2 {
    let tan = e.tangent_at(t);
    if left { tan.perp() } else { -tan.perp() }
}

/// The touching points and their free-side normals: each vertex with the normal the per-point
/// path gives it (square to its neighbours' chord, as the flags measure it), and points inside
/// each element (its midpoint, and points no farther apart than the spacing on long ones) with
/// the element's own normal.
fn samples(profile: &Profile, elements: &[Element], left: bool) -> Vec<(DVec2, DVec2)> {
    let extent = profile.extent_mm().max(1e-9);
    let total: f64 = elements.iter().map(Element::length).sum();
    let spacing = (extent / 2000.0).max(total / MAX_SAMPLES as f64);
    let mut out = Vec::new();
    let n = profile.vertices.len();
    let pos = |i: usize| profile.vertices.get(i).map_or(DVec2::ZERO, |v| v.pos());
    for i in 0..n {
        let (prev, next) = if profile.closed {
            ((i + n - 1) % n, (i + 1) % n)
        } else {
            (i.saturating_sub(1), (i + 1).min(n - 1))
        };
        let t = (pos(next) - pos(prev)).normalize_or_zero();
        if t != DVec2::ZERO {
            out.push((pos(i), if left { t.perp() } else { -t.perp() }));
        }
    }
    for e in elements {
        let pieces = ((e.length() / spacing).ceil() as usize).clamp(2, MAX_SAMPLES);
        for j in 1..pieces {
            let t = j as f64 / pieces as f64;
            out.push((e.point_at(t), free_normal(e, t, left)));
        }
    }
    out
}

/// The largest radius, mm, whose ball touching every point of `profile` from the side left
/// (`left`) or right of its direction gouges it by at most `tolerance_mm`; infinite when no
/// ball ever gouges (a convex open profile), capped at 10⁶ mm otherwise.
#[must_use]
pub fn max_radius_within_tolerance(profile: &Profile, left: bool, tolerance_mm: f64) -> f64 {
    let elements = profile.elements();
    if elements.is_empty() || !(tolerance_mm >= 0.0) {
        return 0.0;
    }
    let (lo, hi) = profile.bounds();
    let grid = Grid::new(&elements, lo, hi);
    let cap = crate::geometry::planar::MAX_COORD_MM;
    let gouges = |p: DVec2, n: DVec2, r: f64| {
        // The element the ball touches is at distance r (to rounding): only what comes closer
        // than r − tol (and a hair for rounding) counts.
        let slack = tolerance_mm.max(1e-12 * r.max(1.0));
        grid.any_within(&elements, p + n * r, r - slack)
    };
    let mut best = f64::INFINITY;
    for (p, n) in samples(profile, &elements, left) {
        let top = best.min(cap);
        if !gouges(p, n, top) {
            continue;
        }
        let (mut ok, mut bad) = (0.0, top);
        for _ in 0..STEPS {
            let mid = 0.5 * (ok + bad);
            if gouges(p, n, mid) {
                bad = mid;
            } else {
                ok = mid;
            }
        }
        best = ok;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::planar::Vertex;

    fn polyline(points: &[(f64, f64)], closed: bool) -> Profile {
        Profile {
            vertices: points.iter().map(|&(x, y)| Vertex::point(x, y)).collect(),
            closed,
        }
    }

    #[test]
    fn a_concave_kink_admits_tol_over_one_minus_cos_of_half_its_turn() {
        // A V opening upwards (free side up: left of the direction of travel, left to right),
        // its two sides turning by θ at the bottom.
        for theta_deg in [5.0_f64, 10.0, 30.0, 60.0, 90.0] {
            let half = theta_deg.to_radians() / 2.0;
            let (s, c) = half.sin_cos();
            let p = polyline(
                &[(-50.0 * c, 50.0 * s), (0.0, 0.0), (50.0 * c, 50.0 * s)],
                false,
            );
            let tol = 1e-3;
            let got = max_radius_within_tolerance(&p, true, tol);
            let want = tol / (1.0 - half.cos());
            assert!(
                (got - want).abs() <= 1e-6 * want,
                "θ {theta_deg}°: {got} against {want}"
            );
        }
    }

    #[test]
    fn a_slot_with_sharp_floor_corners_admits_the_tolerance() {
        // A slot 10 mm wide, 30 mm deep, the air above the profile (left of travel): its sharp
        // floor corners admit almost nothing: the ball touching the wall 0.02 mm (the spacing)
        // above the floor with the wall's normal reaches the floor unless R ≤ 0.02 mm + tol.
        let p = polyline(
            &[
                (-20.0, 0.0),
                (-5.0, 0.0),
                (-5.0, -30.0),
                (5.0, -30.0),
                (5.0, 0.0),
                (20.0, 0.0),
            ],
            false,
        );
        let sharp = max_radius_within_tolerance(&p, true, 1e-3);
        let spacing = 40.0 / 2000.0;
        assert!(sharp <= spacing + 1e-3 + 1e-9 && sharp > 1e-3, "{sharp}");
        // A convex profile seen from outside never gouges.
        let hill = polyline(&[(-10.0, 0.0), (0.0, 5.0), (10.0, 0.0)], false);
        assert!(max_radius_within_tolerance(&hill, true, 1e-3) >= 1e5);
    }
}
