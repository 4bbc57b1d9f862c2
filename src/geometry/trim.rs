//! A face's trimmed region in its surface's parameter plane: the even-odd interior of its
//! boundary loops (outer loop and holes) as the tessellator maps them (inverted onto the
//! surface, unwrapped across periodic seams into one period window, expanded at poles, bands
//! and caps closed), with point-in-region queries and the clipping of parameter polylines.
//!
//! The even-odd rule is the tessellator's, so a point the planner keeps is one whose
//! triangle the mesh keeps. Queries go through a slab index over v (each slab lists the loop
//! segments that span it), so a test costs the segments of one slab instead of every segment of
//! every loop: the planners ask millions of times per face (every march sub-step and every
//! bisection step toward the boundary).

use super::brep::{Face, Part};
use super::surface::ParamRect;
use super::tessellate::{TessellationOptions, face_param_loops};
use super::{DVec2, Interval};

/// Most slabs of the index.
const MAX_SLABS: usize = 512;

/// Chord tolerance of the edges that bound a face's trimmed region, mm: a contact on the
/// region's boundary is this close to the face's true edge.
pub const REGION_CHORD_MM: f64 = 0.002;

/// The trimmed parameter region of a face.
#[derive(Clone, Debug)]
pub struct TrimRegion {
    loops: Vec<Vec<DVec2>>,
    lo: DVec2,
    hi: DVec2,
    /// Per slab: (loop, segment start) of every segment whose v range meets the slab.
    slabs: Vec<Vec<(u32, u32)>>,
    slab_h: f64,
}

impl TrimRegion {
    /// The region bounded by closed polygons (last point joins the first; even-odd interior).
    /// `None` when no polygon has three points or the bounds are not finite and non-empty.
    #[must_use]
    pub fn from_loops(loops: Vec<Vec<DVec2>>) -> Option<Self> {
        let loops: Vec<Vec<DVec2>> = loops
            .into_iter()
            .filter(|l| l.len() >= 3 && l.iter().all(|p| p.is_finite()))
            .collect();
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for p in loops.iter().flatten() {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if !(lo.is_finite() && hi.is_finite() && hi.x > lo.x && hi.y > lo.y) {
            return None;
        }
        let count: usize = loops.iter().map(Vec::len).sum();
        let n = ((count as f64).sqrt().ceil() as usize).clamp(1, MAX_SLABS);
        let slab_h = (hi.y - lo.y) / n as f64;
        let mut slabs = vec![Vec::new(); n];
        for (li, l) in loops.iter().enumerate() {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                let j0 = slab_of(a.y.min(b.y), lo.y, slab_h, n);
                let j1 = slab_of(a.y.max(b.y), lo.y, slab_h, n);
                for s in slabs.iter_mut().take(j1 + 1).skip(j0) {
                    s.push((li as u32, k as u32));
                }
            }
        }
        Some(Self {
            loops,
            lo,
            hi,
            slabs,
            slab_h,
        })
    }

    /// The region of a B-rep face: its loops as the tessellator maps them, the edges
    /// discretised to `chord_tol_mm`; a face without loops covers its surface's domain.
    ///
    /// # Errors
    /// A message when the loops cannot be mapped or enclose nothing, or a face without loops
    /// lies on an unbounded surface.
    pub fn of_face(face: &Face, part: &Part, chord_tol_mm: f64) -> Result<Self, String> {
        let opts = TessellationOptions::with_chord_tol(chord_tol_mm);
        let mut loops = face_param_loops(face, part, &opts)?;
        if loops.is_empty() {
            let r = face.surface.domain();
            if !(r.u.is_finite() && r.v.is_finite()) {
                return Err("the face has no loops and its surface is unbounded".into());
            }
            loops.push(vec![
                DVec2::new(r.u.t0, r.v.t0),
                DVec2::new(r.u.t1, r.v.t0),
                DVec2::new(r.u.t1, r.v.t1),
                DVec2::new(r.u.t0, r.v.t1),
            ]);
        }
        Self::from_loops(loops).ok_or_else(|| "the face's loops enclose no area".to_string())
    }

    /// The bounding rectangle of the loops (finite, non-empty).
    #[must_use]
    pub fn bounds(&self) -> ParamRect {
        ParamRect {
            u: Interval::new(self.lo.x, self.hi.x),
            v: Interval::new(self.lo.y, self.hi.y),
        }
    }

    /// The loops (closed polygons).
    #[must_use]
    pub fn loops(&self) -> &[Vec<DVec2>] {
        &self.loops
    }

    fn segment(&self, li: u32, k: u32) -> Option<(DVec2, DVec2)> {
        let l = self.loops.get(li as usize)?;
        let k = k as usize;
        Some((*l.get(k)?, *l.get((k + 1) % l.len())?))
    }

    /// Is `uv` inside (even-odd rule, as the tessellator classifies triangles)?
    #[must_use]
    pub fn contains(&self, uv: DVec2) -> bool {
        if !(uv.y >= self.lo.y && uv.y <= self.hi.y && uv.x >= self.lo.x && uv.x <= self.hi.x) {
            return false;
        }
        let j = slab_of(uv.y, self.lo.y, self.slab_h, self.slabs.len());
        let mut odd = false;
        for &(li, k) in self.slabs.get(j).map_or(&[][..], Vec::as_slice) {
            let Some((a, b)) = self.segment(li, k) else {
                continue;
            };
            if (a.y > uv.y) != (b.y > uv.y) {
                let x = a.x + (uv.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if uv.x < x {
                    odd = !odd;
                }
            }
        }
        odd
    }

    /// The first crossing of the segment `a → b` with a loop, as the fraction along it.
    #[must_use]
    pub fn first_crossing(&self, a: DVec2, b: DVec2) -> Option<f64> {
        let n = self.slabs.len();
        let j0 = slab_of(a.y.min(b.y), self.lo.y, self.slab_h, n);
        let j1 = slab_of(a.y.max(b.y), self.lo.y, self.slab_h, n);
        let d = b - a;
        let mut best: Option<f64> = None;
        for slab in self.slabs.iter().take(j1 + 1).skip(j0) {
            for &(li, k) in slab {
                let Some((p, q)) = self.segment(li, k) else {
                    continue;
                };
                let e = q - p;
                let den = d.perp_dot(e);
                if den == 0.0 {
                    continue;
                }
                let w = p - a;
                let t = w.perp_dot(e) / den;
                let s = w.perp_dot(d) / den;
                if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&s) {
                    best = Some(best.map_or(t, |x: f64| x.min(t)));
                }
            }
        }
        best
    }

    /// The point where `a → b` leaves (or enters) the region: the loop crossing nearest to `a`,
    /// else by bisection on [`TrimRegion::contains`].
    #[must_use]
    pub fn crossing(&self, a: DVec2, b: DVec2) -> DVec2 {
        let ia = self.contains(a);
        if let Some(t) = self.first_crossing(a, b) {
            return a.lerp(b, t);
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..50 {
            let m = 0.5 * (lo + hi);
            if self.contains(a.lerp(b, m)) == ia {
                lo = m;
            } else {
                hi = m;
            }
        }
        a.lerp(b, 0.5 * (lo + hi))
    }

    /// The runs of a parameter polyline inside the region, each with the fraction index
    /// (segment k plus the fraction along it) of every point, so callers can interpolate data
    /// carried along the polyline. A run starts and ends on a loop where the polyline crosses
    /// one (and at the polyline's own ends where they are inside).
    #[must_use]
    pub fn clip(&self, pts: &[DVec2]) -> Vec<Vec<(DVec2, f64)>> {
        let mut runs = Vec::new();
        let mut cur: Vec<(DVec2, f64)> = Vec::new();
        let mut prev: Option<(DVec2, bool)> = None;
        for (k, &p) in pts.iter().enumerate() {
            let inside = self.contains(p);
            if let Some((a, ina)) = prev
                && ina != inside
            {
                let x = self.crossing(a, p);
                let len = (p - a).length();
                let t = if len > 0.0 {
                    (x - a).length() / len
                } else {
                    0.0
                };
                cur.push((x, (k - 1) as f64 + t.clamp(0.0, 1.0)));
                if ina {
                    runs.push(std::mem::take(&mut cur));
                }
            }
            if inside {
                cur.push((p, k as f64));
            }
            prev = Some((p, inside));
        }
        if !cur.is_empty() {
            runs.push(cur);
        }
        runs.retain(|r| r.len() >= 2);
        runs
    }

    /// Sample points along the loops, about `per_loop` per loop (every vertex when fewer).
    #[must_use]
    pub fn boundary_samples(&self, per_loop: usize) -> Vec<DVec2> {
        let mut out = Vec::new();
        for l in &self.loops {
            let step = (l.len() / per_loop.max(1)).max(1);
            out.extend(l.iter().step_by(step).copied());
        }
        out
    }
}

fn slab_of(y: f64, lo: f64, h: f64, n: usize) -> usize {
    let j = (y - lo) / h;
    if j.is_nan() || j < 0.0 {
        0
    } else {
        (j as usize).min(n.saturating_sub(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(c: DVec2, r: f64) -> Vec<DVec2> {
        vec![
            c + DVec2::new(-r, -r),
            c + DVec2::new(r, -r),
            c + DVec2::new(r, r),
            c + DVec2::new(-r, r),
        ]
    }

    #[test]
    fn a_hole_is_outside_and_clipping_splits_a_line_crossing_it() {
        let r = TrimRegion::from_loops(vec![square(DVec2::ZERO, 2.0), square(DVec2::ZERO, 1.0)])
            .expect("region");
        assert!(r.contains(DVec2::new(1.5, 0.3)));
        assert!(!r.contains(DVec2::new(0.5, 0.3)));
        assert!(!r.contains(DVec2::new(2.5, 0.3)));
        let line: Vec<DVec2> = (0..=60)
            .map(|k| DVec2::new(-3.0 + 0.1 * f64::from(k), 0.25))
            .collect();
        let runs = r.clip(&line);
        assert_eq!(runs.len(), 2);
        let ends: Vec<(f64, f64)> = runs
            .iter()
            .map(|r| (r[0].0.x, r[r.len() - 1].0.x))
            .collect();
        for (got, want) in ends.iter().zip([(-2.0, -1.0), (1.0, 2.0)]) {
            assert!((got.0 - want.0).abs() < 1e-12 && (got.1 - want.1).abs() < 1e-12);
        }
    }
}
