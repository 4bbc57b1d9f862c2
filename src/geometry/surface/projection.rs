//! Point inversion on surfaces: seeds (closed-form projections for the analytic kinds, a grid
//! over the parameter rectangle, the caller's hint), then a bounded, monotone projected Newton
//! on the squared distance from each of the best seeds. Handles rectangle edges and corners
//! (active-set projection), periodic directions (free, wrapped back at the end), infinite
//! rectangles (seed windows around the projection) and degenerate points (poles, axis points:
//! Gauss-Newton and scaled-gradient fallbacks). Never produces NaN.

use std::f64::consts::PI;

use super::{ParamRect, SurfaceGeom, SurfacePoint};
use crate::geometry::{DVec2, DVec3, Interval};

/// One parameter direction of the search.
#[derive(Clone, Copy, Debug)]
struct Axis {
    /// Bounds Newton is clamped to (may be infinite); ignored when `free`.
    lo: f64,
    /// Upper bound.
    hi: f64,
    /// Periodic direction covering a full period: no clamping, wrap into `[win.t0, win.t0 + T]`.
    free: Option<f64>,
    /// Finite window for seeding.
    win: Interval,
    /// Period of the direction, if periodic.
    period: Option<f64>,
}

impl Axis {
    fn clamp(&self, t: f64) -> f64 {
        if self.free.is_some() {
            t
        } else {
            t.clamp(self.lo, self.hi)
        }
    }

    fn at_lo(&self, t: f64) -> bool {
        self.free.is_none() && t <= self.lo
    }

    fn at_hi(&self, t: f64) -> bool {
        self.free.is_none() && t >= self.hi
    }

    /// A seed coordinate: periodic representatives moved next to the window, then clamped.
    fn seed(&self, t: f64) -> f64 {
        let Some(per) = self.period.filter(|_| t.is_finite()) else {
            return self.clamp(t);
        };
        let a = self.win.t0 + (t - self.win.t0).rem_euclid(per);
        // `a` or `a − T`, whichever is nearer the window.
        let b = a - per;
        if a <= self.win.t1 || (a - self.win.t1) <= (self.win.t0 - b) {
            self.clamp(a)
        } else {
            self.clamp(b)
        }
    }

    fn finish(&self, t: f64) -> f64 {
        match self.free {
            Some(per) => self.win.t0 + (t - self.win.t0).rem_euclid(per),
            None => self.clamp(t),
        }
    }
}

/// Replace NaN ends by the domain's, order the ends.
fn sanitize(r: Interval, dom: Interval) -> Interval {
    let t0 = if r.t0.is_nan() { dom.t0 } else { r.t0 };
    let t1 = if r.t1.is_nan() { dom.t1 } else { r.t1 };
    Interval::new(t0.min(t1), t0.max(t1))
}

/// Bounds and periodic freedom of one direction (window filled in later).
fn axis(r: Interval, dom: Interval, period: Option<f64>) -> Axis {
    match period {
        Some(per) if !r.is_finite() || r.len() >= per => {
            let a = if r.t0.is_finite() {
                r.t0
            } else if r.t1.is_finite() {
                r.t1 - per
            } else {
                dom.t0
            };
            let a = if a.is_finite() { a } else { 0.0 };
            Axis {
                lo: a,
                hi: a + per,
                free: Some(per),
                win: Interval::new(a, a + per),
                period,
            }
        }
        Some(_) => Axis {
            lo: r.t0,
            hi: r.t1,
            free: None,
            win: r,
            period,
        },
        None => {
            let (mut lo, mut hi) = (r.t0.max(dom.t0), r.t1.min(dom.t1));
            if lo > hi {
                // Rectangle entirely outside the domain: the nearest domain end.
                let e = if r.t1 < dom.t0 { dom.t0 } else { dom.t1 };
                (lo, hi) = (e, e);
            }
            Axis {
                lo,
                hi,
                free: None,
                win: Interval::new(lo, hi),
                period: None,
            }
        }
    }
}

/// Make an axis window finite around `centre` with half-width `half`.
fn finite_window(a: &mut Axis, centre: f64, half: f64) {
    if a.win.is_finite() {
        return;
    }
    let c = if centre.is_finite() {
        a.clamp(centre)
    } else {
        a.clamp(0.0)
    };
    let c = if c.is_finite() { c } else { 0.0 };
    a.win = Interval::new((c - half).max(a.lo), (c + half).min(a.hi));
}

/// Closed-form projections of `p` for the analytic kinds (up to two candidates).
fn analytic_seeds(s: &SurfaceGeom, p: DVec3) -> [Option<DVec2>; 2] {
    let polar = |q: DVec3| {
        let rho = q.x.hypot(q.y);
        (if rho > 0.0 { q.y.atan2(q.x) } else { 0.0 }, rho)
    };
    match s {
        SurfaceGeom::Plane(pl) => {
            let q = pl.frame.to_local(p);
            [Some(DVec2::new(q.x, q.y)), None]
        }
        SurfaceGeom::Cylinder(c) => {
            let q = c.frame.to_local(p);
            [Some(DVec2::new(polar(q).0, q.z)), None]
        }
        SurfaceGeom::Cone(c) => {
            let q = c.frame.to_local(p);
            let (u, rho) = polar(q);
            let (sa, ca) = c.semi_angle.sin_cos();
            [
                Some(DVec2::new(u, (rho - c.radius) * sa + q.z * ca)),
                Some(DVec2::new(u + PI, (-rho - c.radius) * sa + q.z * ca)),
            ]
        }
        SurfaceGeom::Sphere(sp) => {
            let q = sp.frame.to_local(p);
            let (u, rho) = polar(q);
            [Some(DVec2::new(u, q.z.atan2(rho))), None]
        }
        SurfaceGeom::Torus(t) => {
            let q = t.frame.to_local(p);
            let (u, rho) = polar(q);
            [
                Some(DVec2::new(u, q.z.atan2(rho - t.major_radius))),
                Some(DVec2::new(u + PI, q.z.atan2(-rho - t.major_radius))),
            ]
        }
        SurfaceGeom::Extrusion(e) => {
            let dd = e.dir.length_squared();
            let u = e.profile.domain();
            let u0 = if u.is_finite() { u.lerp(0.5) } else { 0.0 };
            let v = if dd > 0.0 {
                (p - e.profile.point(u0)).dot(e.dir) / dd
            } else {
                0.0
            };
            [Some(DVec2::new(u0, v)), None]
        }
        SurfaceGeom::BSpline(_) | SurfaceGeom::Revolution(_) => [None, None],
    }
}

/// Grid resolution per direction.
fn grid_size(s: &SurfaceGeom) -> (usize, usize) {
    let curve_n = |c: &crate::geometry::curve::CurveGeom| match c {
        crate::geometry::curve::CurveGeom::BSpline(b) => (2 * b.poles.len()).clamp(8, 40),
        crate::geometry::curve::CurveGeom::Line(_) => 4,
        _ => 16,
    };
    match s {
        SurfaceGeom::BSpline(b) => ((2 * b.n_u).clamp(8, 40), (2 * b.n_v).clamp(8, 40)),
        SurfaceGeom::Plane(_) => (4, 4),
        SurfaceGeom::Cylinder(_) | SurfaceGeom::Cone(_) => (16, 6),
        SurfaceGeom::Sphere(_) => (16, 9),
        SurfaceGeom::Torus(_) => (16, 16),
        SurfaceGeom::Revolution(r) => (16, curve_n(&r.meridian)),
        SurfaceGeom::Extrusion(e) => (curve_n(&e.profile), 6),
    }
}

/// The search set-up for `rect`; windows of infinite directions centred on `centre`.
fn setup(s: &SurfaceGeom, p: DVec3, rect: ParamRect, centre: Option<DVec2>) -> (Axis, Axis) {
    let dom = s.domain();
    let (pu, pv) = s.periods();
    let mut au = axis(sanitize(rect.u, dom.u), dom.u, pu);
    let mut av = axis(sanitize(rect.v, dom.v), dom.v, pv);
    if !au.win.is_finite() || !av.win.is_finite() {
        let c = centre.filter(|c| c.is_finite()).unwrap_or(DVec2::ZERO);
        let (cu, cv) = (au.clamp(c.x), av.clamp(c.y));
        let q = s.point(
            if cu.is_finite() { cu } else { 0.0 },
            if cv.is_finite() { cv } else { 0.0 },
        );
        let half = 2.0 * q.distance(p).max(1.0);
        finite_window(&mut au, c.x, half);
        finite_window(&mut av, c.y, half);
    }
    (au, av)
}

fn result(s: &SurfaceGeom, p: DVec3, uv: DVec2) -> SurfacePoint {
    let point = s.point(uv.x, uv.y);
    let distance = point.distance(p);
    SurfacePoint {
        uv,
        point,
        distance: if distance.is_nan() {
            f64::INFINITY
        } else {
            distance
        },
    }
}

/// A finite parameter pair inside the axes.
fn anchor(au: &Axis, av: &Axis) -> DVec2 {
    DVec2::new(au.win.lerp(0.5), av.win.lerp(0.5))
}

/// See [`SurfaceGeom::closest_point`].
pub(super) fn closest_point(
    s: &SurfaceGeom,
    p: DVec3,
    rect: ParamRect,
    hint: Option<DVec2>,
) -> SurfacePoint {
    let hint = hint.filter(|h| h.is_finite());
    let an = if p.is_finite() {
        analytic_seeds(s, p)
    } else {
        [None, None]
    };
    let (au, av) = setup(s, p, rect, an[0].or(hint));
    if !p.is_finite() {
        return result(s, p, anchor(&au, &av));
    }
    let (nu, nv) = grid_size(s);
    let lerp = |a: &Axis, n: usize, i: usize| {
        if i == n {
            a.win.t1
        } else {
            a.win.lerp(i as f64 / n as f64)
        }
    };
    // Grid over the window (a free periodic direction drops its duplicate last column).
    let cols_u = if au.free.is_some() { nu } else { nu + 1 };
    let cols_v = if av.free.is_some() { nv } else { nv + 1 };
    let mut grid = Vec::with_capacity(cols_u * cols_v);
    for i in 0..cols_u {
        let u = lerp(&au, nu, i);
        for j in 0..cols_v {
            let v = lerp(&av, nv, j);
            grid.push(s.point(u, v).distance_squared(p));
        }
    }
    let at = |i: isize, j: isize| -> f64 {
        let wrap = |k: isize, n: usize, free: bool| {
            if free {
                Some(k.rem_euclid(n as isize) as usize)
            } else if k < 0 || k >= n as isize {
                None
            } else {
                Some(k as usize)
            }
        };
        match (
            wrap(i, cols_u, au.free.is_some()),
            wrap(j, cols_v, av.free.is_some()),
        ) {
            (Some(a), Some(b)) => grid.get(a * cols_v + b).copied().unwrap_or(f64::INFINITY),
            _ => f64::INFINITY,
        }
    };
    let mut seeds: Vec<(f64, DVec2)> = Vec::new();
    for i in 0..cols_u as isize {
        for j in 0..cols_v as isize {
            let d = at(i, j);
            let is_min = [(-1, 0), (1, 0), (0, -1), (0, 1)]
                .iter()
                .all(|&(di, dj)| d <= at(i + di, j + dj));
            if is_min {
                seeds.push((
                    d,
                    DVec2::new(lerp(&au, nu, i as usize), lerp(&av, nv, j as usize)),
                ));
            }
        }
    }
    seeds.sort_by(|a, b| a.0.total_cmp(&b.0));
    seeds.truncate(4);
    let mut starts: Vec<DVec2> = seeds.into_iter().map(|(_, uv)| uv).collect();
    starts.extend(
        an.into_iter()
            .flatten()
            .chain(hint)
            .map(|uv| DVec2::new(au.seed(uv.x), av.seed(uv.y))),
    );
    let max_step = DVec2::new(au.win.len().max(1e-300), av.win.len().max(1e-300)) * 0.25;
    let mut best: Option<(f64, DVec2)> = None;
    for st in starts {
        if !st.is_finite() {
            continue;
        }
        let (uv, d) = descend(s, p, st, &au, &av, max_step);
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, uv));
        }
    }
    let uv = best.map_or_else(|| anchor(&au, &av), |(_, uv)| uv);
    result(s, p, DVec2::new(au.finish(uv.x), av.finish(uv.y)))
}

/// See [`SurfaceGeom::closest_point_near`].
pub(super) fn closest_point_near(
    s: &SurfaceGeom,
    p: DVec3,
    rect: ParamRect,
    start: DVec2,
) -> SurfacePoint {
    let start = if start.is_finite() { Some(start) } else { None };
    let (au, av) = setup(s, p, rect, start);
    let st = start.map_or_else(
        || anchor(&au, &av),
        |st| DVec2::new(au.seed(st.x), av.seed(st.y)),
    );
    if !p.is_finite() || !st.is_finite() {
        return result(s, p, anchor(&au, &av));
    }
    let max_step = DVec2::new(au.win.len().max(1e-300), av.win.len().max(1e-300)) * 0.25;
    let (uv, _) = descend(s, p, st, &au, &av, max_step);
    result(s, p, DVec2::new(au.finish(uv.x), av.finish(uv.y)))
}

/// Bounded, monotone projected Newton on `½|S(u, v) − p|²`; returns `(uv, |S − p|²)`.
fn descend(
    s: &SurfaceGeom,
    p: DVec3,
    mut uv: DVec2,
    au: &Axis,
    av: &Axis,
    max_step: DVec2,
) -> (DVec2, f64) {
    let project = |q: DVec2| DVec2::new(au.clamp(q.x), av.clamp(q.y));
    let mut f = s.point(uv.x, uv.y).distance_squared(p);
    for _ in 0..60 {
        let d = s.derivs(uv.x, uv.y);
        let r = d.p - p;
        let g = DVec2::new(r.dot(d.su), r.dot(d.sv));
        let (e, ff, gg) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
        let h = [e + r.dot(d.suu), ff + r.dot(d.suv), gg + r.dot(d.svv)];
        let gn = [e, ff, gg];
        let act_u = (au.at_lo(uv.x) && g.x > 0.0) || (au.at_hi(uv.x) && g.x < 0.0);
        let act_v = (av.at_lo(uv.y) && g.y > 0.0) || (av.at_hi(uv.y) && g.y < 0.0);
        if act_u && act_v {
            break;
        }
        let dirs = [
            newton_step(h, g, act_u, act_v),
            newton_step(gn, g, act_u, act_v),
            scaled_gradient(gn, g, act_u, act_v),
        ];
        let mut moved = None;
        for step in dirs.into_iter().flatten() {
            // Limit the step, keeping its direction.
            let k = [1.0, max_step.x / step.x.abs(), max_step.y / step.y.abs()]
                .into_iter()
                .filter(|k| k.is_finite())
                .fold(1.0_f64, f64::min);
            let mut step = step * k;
            for _ in 0..40 {
                let cand = project(uv + step);
                let fc = s.point(cand.x, cand.y).distance_squared(p);
                if fc <= f && cand.is_finite() {
                    moved = Some((cand, fc));
                    break;
                }
                step *= 0.5;
            }
            if moved.is_some() {
                break;
            }
        }
        let Some((cand, fc)) = moved else { break };
        let delta = cand - uv;
        let stalled = fc >= f;
        uv = cand;
        f = fc;
        if stalled || (delta.x.abs() <= 1e-12 * max_step.x && delta.y.abs() <= 1e-12 * max_step.y) {
            break;
        }
    }
    (uv, f)
}

/// Solve the (possibly reduced) 2×2 system `H δ = −g` when `H` is positive definite.
fn newton_step(h: [f64; 3], g: DVec2, act_u: bool, act_v: bool) -> Option<DVec2> {
    let [a, b, c] = h;
    let step = if act_u {
        (c > 0.0).then(|| DVec2::new(0.0, -g.y / c))
    } else if act_v {
        (a > 0.0).then(|| DVec2::new(-g.x / a, 0.0))
    } else {
        let det = a * c - b * b;
        (a > 0.0 && c > 0.0 && det > 1e-14 * a * c)
            .then(|| DVec2::new(-(c * g.x - b * g.y) / det, -(a * g.y - b * g.x) / det))
    };
    step.filter(|s| s.is_finite() && (s.x != 0.0 || s.y != 0.0))
}

/// Gradient step scaled by the Gauss-Newton diagonal (regularised), always a descent direction.
fn scaled_gradient(gn: [f64; 3], g: DVec2, act_u: bool, act_v: bool) -> Option<DVec2> {
    let [e, _, gg] = gn;
    let lam = 1e-12 * (e + gg) + 1e-300;
    let s = DVec2::new(
        if act_u { 0.0 } else { -g.x / (e + lam) },
        if act_v { 0.0 } else { -g.y / (gg + lam) },
    );
    (s.is_finite() && (s.x != 0.0 || s.y != 0.0)).then_some(s)
}
