//! A face's boundary loops in the surface's parameter plane: point inversion of the shared edge
//! polylines, unwrapping across periodic seams, expansion at singular points (poles, apexes), and
//! closing of loops that run once around a periodic direction (bands and caps without seams).

use crate::geometry::brep::{Face, Loop, OrientedEdge, Part};
use crate::geometry::surface::{ParamRect, SurfaceGeom};
use crate::geometry::{DVec2, DVec3};

/// A closed polygon in the parameter plane (last point joins the first) with the exact 3D point
/// of every vertex.
#[derive(Clone, Debug, Default)]
pub(super) struct UvLoop {
    /// Parameter-plane points.
    pub uv: Vec<DVec2>,
    /// Exact 3D points (edge polyline points), same length as `uv`.
    pub p3: Vec<DVec3>,
    /// For each point, the edge (index into [`Part::edges`]) whose curve the segment from this
    /// point to the next follows; `None` for segments that are not a chord of an edge (across a
    /// pole or an apex, along a seam the loop was closed on).
    pub edge: Vec<Option<usize>>,
}

/// A boundary point after inversion.
#[derive(Clone, Copy, Debug)]
struct Pt {
    uv: DVec2,
    p3: DVec3,
    /// The edge that the segment to the next point follows.
    edge: Option<usize>,
    /// Which use of an edge in the loop (its position in the loop) the point starts.
    run: usize,
    /// The surface is degenerate here in u (`S_u = 0`, e.g. a pole) or in v.
    singular_u: bool,
    singular_v: bool,
}

/// The face's loops in the parameter plane, ready to triangulate. `Err` explains why not.
pub(super) fn face_uv_loops(
    face: &Face,
    part: &Part,
    edge_polylines: &[Vec<DVec3>],
    tol: f64,
) -> Result<Vec<UvLoop>, String> {
    let surface = &face.surface;
    let rect = surface.domain();
    let (pu, pv) = surface.periods();
    let mut loops = Vec::new();
    let mut vertex_loop_points = Vec::new();
    for lp in &face.loops {
        match lp {
            Loop::Edges(oes) => {
                let pts3 = loop_points(oes, edge_polylines)?;
                if pts3.len() < 2 {
                    continue;
                }
                let mut pts = invert(surface, rect, &pts3);
                for (p, (_, e, k)) in pts.iter_mut().zip(&pts3) {
                    p.edge = *e;
                    p.run = *k;
                }
                unwrap(&mut pts, pu, pv);
                separate_seam_uses(&mut pts, pu, pv);
                straighten_runs(&mut pts);
                loops.push(pts);
            }
            Loop::Vertex(vi) => {
                let p = part
                    .vertices
                    .get(*vi)
                    .ok_or_else(|| format!("vertex loop refers to missing vertex {vi}"))?
                    .point;
                vertex_loop_points.push((surface.closest_point(p, rect, None).uv, p));
            }
        }
    }
    // Put every loop in the same period window as the first.
    if let Some(first) = loops.first() {
        let c0 = centre(first);
        for l in loops.iter_mut().skip(1) {
            let c = centre(l);
            let shift = DVec2::new(period_shift(c.x, c0.x, pu), period_shift(c.y, c0.y, pv));
            for p in l.iter_mut() {
                p.uv += shift;
            }
        }
    }
    let loops: Vec<Vec<Pt>> = loops
        .into_iter()
        .map(|l| expand_singular(surface, l))
        .collect();
    close_periodic(surface, loops, face.same_sense, &vertex_loop_points, tol)
}

/// The parameter v of a cone's apex (where its radius `r + v sin a` is zero).
fn cone_apex_v(surface: &SurfaceGeom) -> Option<f64> {
    match surface {
        SurfaceGeom::Cone(c) if c.semi_angle.sin().abs() > 1e-12 => {
            Some(-c.radius / c.semi_angle.sin()).filter(|v| v.is_finite())
        }
        _ => None,
    }
}

/// The 3D points of an edge loop in order (each edge's last point is the next edge's first).
/// The importer has already chained the loop (`import::step` repairs loops listed out of order
/// or with reversed edges, as Open CASCADE's wire fixing does).
fn loop_points(
    oes: &[OrientedEdge],
    edge_polylines: &[Vec<DVec3>],
) -> Result<Vec<(DVec3, Option<usize>, usize)>, String> {
    let mut pts = Vec::new();
    for (k, oe) in oes.iter().enumerate() {
        let poly = edge_polylines
            .get(oe.edge)
            .ok_or_else(|| format!("loop refers to missing edge {}", oe.edge))?;
        if poly.is_empty() {
            continue;
        }
        let e = Some(oe.edge);
        if oe.forward {
            pts.extend(poly[..poly.len() - 1].iter().map(|&p| (p, e, k)));
        } else {
            pts.extend(poly[1..].iter().rev().map(|&p| (p, e, k)));
        }
    }
    Ok(pts)
}

/// A boundary point this close to the surface is taken as lying on it (CAD tolerances are
/// 1e-7 to 1e-3 mm).
const NEAR_ENOUGH_MM: f64 = 1e-4;

fn invert(
    surface: &SurfaceGeom,
    rect: ParamRect,
    pts3: &[(DVec3, Option<usize>, usize)],
) -> Vec<Pt> {
    let mut hint = None;
    let mut out = Vec::with_capacity(pts3.len());
    for &(p, _, _) in pts3 {
        // Walking along the loop, Newton from the previous point's parameters is enough; fall
        // back to the global search when it does not land on the surface.
        let near = hint.map(|h| surface.closest_point_near(p, rect, h));
        let sp = match near {
            Some(sp) if sp.distance <= NEAR_ENOUGH_MM => sp,
            _ => {
                let global = surface.closest_point(p, rect, hint);
                match near {
                    Some(n) if n.distance < global.distance => n,
                    _ => global,
                }
            }
        };
        let d = surface.derivs(sp.uv.x, sp.uv.y);
        let scale = d.su.length().max(d.sv.length()).max(1e-300);
        let singular_u = d.su.length() <= 1e-9 * scale.max(1.0);
        let singular_v = d.sv.length() <= 1e-9 * scale.max(1.0);
        if !(singular_u || singular_v) {
            hint = Some(sp.uv);
        }
        out.push(Pt {
            uv: sp.uv,
            p3: p,
            edge: None,
            run: 0,
            singular_u,
            singular_v,
        });
    }
    out
}

/// Make u (and v) continuous along the loop across periodic seams; singular points are skipped
/// as references because their parameter there is arbitrary.
fn unwrap(pts: &mut [Pt], pu: Option<f64>, pv: Option<f64>) {
    let mut prev: Option<DVec2> = None;
    for p in pts.iter_mut() {
        if let Some(q) = prev {
            p.uv.x += period_shift(p.uv.x, q.x, pu);
            p.uv.y += period_shift(p.uv.y, q.y, pv);
        }
        if !(p.singular_u || p.singular_v) {
            prev = Some(p.uv);
        }
    }
}

/// A seam edge used twice in a row through a pole (down the seam to a sphere's pole and back
/// up, as a hemisphere bounded by its equator and the seam is written) unwraps to the same
/// parameter line both times, a spike with no area. Its second use belongs one period over:
/// shift it, and everything after it, by the period that closes the loop.
fn separate_seam_uses(pts: &mut [Pt], pu: Option<f64>, pv: Option<f64>) {
    let n = pts.len();
    if n < 4 {
        return;
    }
    // Runs of consecutive points on one edge: (edge, start, end exclusive).
    let mut runs: Vec<(usize, usize, usize)> = Vec::new();
    let mut run_of: Vec<usize> = Vec::new();
    for (i, p) in pts.iter().enumerate() {
        match (p.edge, runs.last_mut()) {
            (Some(e), Some(last))
                if last.0 == e && last.2 == i && run_of.last() == Some(&p.run) =>
            {
                last.2 = i + 1;
            }
            (Some(e), _) => {
                runs.push((e, i, i + 1));
                run_of.push(p.run);
            }
            (None, _) => {}
        }
    }
    let mean = |a: usize, b: usize, axis: usize| -> Option<f64> {
        let vals: Vec<f64> = pts[a..b]
            .iter()
            .filter(|p| !(p.singular_u || p.singular_v))
            .map(|p| p.uv[axis])
            .collect();
        (!vals.is_empty()).then(|| vals.iter().sum::<f64>() / vals.len() as f64)
    };
    for (k, &(e, a1, b1)) in runs.iter().enumerate() {
        let Some(&(_, a2, b2)) = runs[k + 1..].iter().find(|r| r.0 == e) else {
            continue;
        };
        for (axis, per) in [(0usize, pu), (1usize, pv)] {
            let Some(per) = per.filter(|p| *p > 0.0 && p.is_finite()) else {
                continue;
            };
            let (Some(m1), Some(m2)) = (mean(a1, b1 + 1, axis), mean(a2, b2.min(n), axis)) else {
                continue;
            };
            // Both uses on one parameter line, and the line is constant along the edge.
            let flat = pts[a1..b1]
                .iter()
                .filter(|p| !(p.singular_u || p.singular_v))
                .all(|p| (p.uv[axis] - m1).abs() < 1e-6 * per);
            if !flat || (m1 - m2).abs() > 1e-6 * per {
                continue;
            }
            let (first, last) = (pts[0].uv[axis], pts[n - 1].uv[axis]);
            let Some(jump) = [per, -per]
                .into_iter()
                .find(|j| (first - (last + j)).abs() < 0.5 * per)
            else {
                continue;
            };
            for p in &mut pts[a2..] {
                p.uv[axis] += jump;
            }
            return;
        }
    }
}

/// An edge along a parameter line (a seam, a cylinder's ruling, a torus meridian) inverts to
/// points whose constant parameter differs by rounding (1e-12). The triangulator takes such a
/// chain as bent and fills the bend with slivers that are flat in the parameter plane but span
/// the curved edge in space. Give every such run (an edge's points and the next edge's first)
/// exactly one value of the constant parameter.
fn straighten_runs(pts: &mut [Pt]) {
    let n = pts.len();
    let mut i = 0;
    while i < n {
        let Some(e) = pts[i].edge else {
            i += 1;
            continue;
        };
        let mut j = i + 1;
        while j < n && pts[j].edge == Some(e) && pts[j].run == pts[i].run {
            j += 1;
        }
        // The run is pts[i..j] plus the next point (the shared vertex), when there is one.
        let end = (j + 1).min(n);
        for axis in 0..2 {
            let vals: Vec<f64> = pts[i..end]
                .iter()
                .filter(|p| !(p.singular_u || p.singular_v))
                .map(|p| p.uv[axis])
                .collect();
            if vals.len() < 2 {
                continue;
            }
            let mean = vals.iter().sum::<f64>() / vals.len() as f64;
            if vals
                .iter()
                .all(|v| (v - mean).abs() <= 1e-9 * (1.0 + mean.abs()))
            {
                for p in &mut pts[i..end] {
                    if !(p.singular_u || p.singular_v) {
                        p.uv[axis] = mean;
                    }
                }
            }
        }
        i = j;
    }
}

/// The multiple of `period` to add to `x` to bring it nearest to `target`.
fn period_shift(x: f64, target: f64, period: Option<f64>) -> f64 {
    match period {
        Some(per) if per > 0.0 && per.is_finite() => ((target - x) / per).round() * per,
        _ => 0.0,
    }
}

fn centre(l: &[Pt]) -> DVec2 {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in l {
        lo = lo.min(p.uv);
        hi = hi.max(p.uv);
    }
    0.5 * (lo + hi)
}

/// Replace each singular point by two: one with the parameter of its predecessor, one with that
/// of its successor (a pole becomes a short segment of the parameter plane's boundary).
fn expand_singular(surface: &SurfaceGeom, l: Vec<Pt>) -> Vec<Pt> {
    let n = l.len();
    if n < 3 || !l.iter().any(|p| p.singular_u || p.singular_v) {
        return l;
    }
    let regular = |start: usize, step: isize| -> Option<DVec2> {
        (1..n)
            .map(|k| (start as isize + step * k as isize).rem_euclid(n as isize) as usize)
            .map(|i| &l[i])
            .find(|p| !(p.singular_u || p.singular_v))
            .map(|p| p.uv)
    };
    let _ = surface;
    let mut out = Vec::with_capacity(n + 4);
    for (i, p) in l.iter().enumerate() {
        if !(p.singular_u || p.singular_v) {
            out.push(*p);
            continue;
        }
        let (Some(a), Some(b)) = (regular(i, -1), regular(i, 1)) else {
            out.push(*p);
            continue;
        };
        let (first, second) = if p.singular_u {
            (DVec2::new(a.x, p.uv.y), DVec2::new(b.x, p.uv.y))
        } else {
            (DVec2::new(p.uv.x, a.y), DVec2::new(p.uv.x, b.y))
        };
        out.push(Pt {
            uv: first,
            edge: None,
            ..*p
        });
        if (second - first).length() > 1e-12 {
            out.push(Pt { uv: second, ..*p });
        }
    }
    out
}

/// Close loops that run once around a periodic direction: two such loops bound a band, one such
/// loop bounds a cap closed at the singular end (apex or pole) on the face's side; a cone,
/// whose v runs to infinity both ways, closes at its apex.
fn close_periodic(
    surface: &SurfaceGeom,
    loops: Vec<Vec<Pt>>,
    same_sense: bool,
    vertex_loops: &[(DVec2, DVec3)],
    tol: f64,
) -> Result<Vec<UvLoop>, String> {
    let rect = surface.domain();
    let (pu, pv) = surface.periods();
    // The shift that the closing segment (last → first) needs: non-zero when the loop runs once
    // around the periodic direction.
    let closing_shift = |l: &[Pt], per: Option<f64>, axis: usize| -> f64 {
        match (l.first(), l.last()) {
            (Some(a), Some(b)) => period_shift(a.uv[axis], b.uv[axis], per),
            _ => 0.0,
        }
    };
    let mut closed = Vec::new();
    let mut open_u = Vec::new();
    for l in loops {
        let su = closing_shift(&l, pu, 0);
        if su != 0.0 {
            open_u.push((l, su));
        } else if closing_shift(&l, pv, 1) != 0.0 {
            return Err(
                "a loop runs around the periodic v direction without a seam (not supported yet)"
                    .into(),
            );
        } else {
            closed.push(to_uv_loop(&l));
        }
    }
    match open_u.as_slice() {
        [] => {}
        [(l, shift)] => {
            // A cap: close along the singular end the face lies on (left of a loop running +u
            // is +v when the face normal is S_u × S_v).
            let mut v_end = if let Some((vp, _)) = vertex_loops.first() {
                vp.y
            } else if (*shift > 0.0) == same_sense {
                rect.v.t1
            } else {
                rect.v.t0
            };
            if !v_end.is_finite()
                && let Some(apex) = cone_apex_v(surface)
            {
                v_end = apex;
            }
            if !v_end.is_finite() {
                return Err("a loop runs around the periodic u direction and the surface has no end to close it on".into());
            }
            let Some(first) = l.first() else {
                return Ok(closed);
            };
            let mut ul = to_uv_loop(l);
            let first_u_shifted = first.uv.x + shift;

            // The singular end's own point: the vertex of a vertex loop, else the surface's.
            let end_p3 = vertex_loops
                .first()
                .map_or_else(|| surface.point(first.uv.x, v_end), |(_, p)| *p);
            let down_from = DVec2::new(first_u_shifted, first.uv.y);
            ul.push(down_from, first.p3, None);
            let down_to = DVec2::new(first_u_shifted, v_end);
            for (uv, p) in virtual_seam(surface, down_from, down_to, tol) {
                ul.push(uv, p, None);
            }
            ul.push(down_to, end_p3, None);
            let up_from = DVec2::new(first.uv.x, v_end);
            ul.push(up_from, end_p3, None);
            for (uv, p) in virtual_seam(surface, up_from, first.uv, tol) {
                ul.push(uv, p, None);
            }
            closed.push(ul);
        }
        [(a, sa), (b, sb)] => {
            let sb_orig_sign = sb.signum();
            // A band: run a once around, cross to b, run b once around the other way, cross back.
            let (b_pts, sb): (Vec<Pt>, f64) = if sa.signum() == sb.signum() {
                (b.iter().rev().copied().collect(), -sb)
            } else {
                (b.clone(), *sb)
            };
            let (Some(a0), Some(b0)) = (a.first(), b_pts.first()) else {
                return Ok(closed);
            };
            let a_end = DVec2::new(a0.uv.x + sa, a0.uv.y);
            let b_shift = period_shift(b0.uv.x, a_end.x, pu);
            let mut ul = to_uv_loop(a);
            ul.push(a_end, a0.p3, None);
            let b_start = DVec2::new(b0.uv.x + b_shift, b0.uv.y);
            for (uv, p) in virtual_seam(surface, a_end, b_start, tol) {
                ul.push(uv, p, None);
            }
            // b runs backwards: the segment from b_pts[k] to b_pts[k + 1] is the one b stored
            // at b_pts[k + 1] when b was reversed.
            let reversed = sa.signum() == sb_orig_sign;
            for (k, p) in b_pts.iter().enumerate() {
                ul.uv.push(DVec2::new(p.uv.x + b_shift, p.uv.y));
                ul.p3.push(p.p3);
                let e = if reversed {
                    b_pts.get(k + 1).or(b_pts.first()).and_then(|q| q.edge)
                } else {
                    p.edge
                };
                ul.edge.push(e);
            }
            let b_end = DVec2::new(b0.uv.x + b_shift + sb, b0.uv.y);
            ul.push(b_end, b0.p3, None);
            for (uv, p) in virtual_seam(surface, b_end, a0.uv, tol) {
                ul.push(uv, p, None);
            }
            closed.push(ul);
        }
        _ => {
            return Err(format!(
                "{} loops run around the periodic u direction (not supported)",
                open_u.len()
            ));
        }
    }
    Ok(closed)
}

impl UvLoop {
    fn push(&mut self, uv: DVec2, p3: DVec3, edge: Option<usize>) {
        self.uv.push(uv);
        self.p3.push(p3);
        self.edge.push(edge);
    }
}

/// Deepest bisection of a virtual seam segment.
const SEAM_DEPTH: u32 = 10;

/// The interior points of the surface curve `S(from + t (to − from))`, `0 < t < 1`, within
/// `tol` of its chords: the segments a loop is closed with (down to an apex or pole, across a
/// band) are straight in the parameter plane but curved in space on spheres, tori and
/// surfaces of revolution.
fn virtual_seam(surface: &SurfaceGeom, from: DVec2, to: DVec2, tol: f64) -> Vec<(DVec2, DVec3)> {
    fn split(
        s: &SurfaceGeom,
        a: (f64, DVec3),
        b: (f64, DVec3),
        uv: &dyn Fn(f64) -> DVec2,
        tol: f64,
        depth: u32,
        out: &mut Vec<(DVec2, DVec3)>,
    ) {
        let t = 0.5 * (a.0 + b.0);
        let q = uv(t);
        let m = s.point(q.x, q.y);
        let chord = b.1 - a.1;
        let dev = chord.try_normalize().map_or_else(
            || (m - a.1).length(),
            |d| (m - a.1).reject_from_normalized(d).length(),
        );
        if depth >= SEAM_DEPTH || !m.is_finite() || dev <= tol {
            return;
        }
        split(s, a, (t, m), uv, tol, depth + 1, out);
        out.push((q, m));
        split(s, (t, m), b, uv, tol, depth + 1, out);
    }
    let uv = |t: f64| from + (to - from) * t;
    let mut out = Vec::new();
    // Four pieces to start with, so a half circle is not taken for a straight line.
    let ts = [0.0, 0.25, 0.5, 0.75, 1.0];
    let pts: Vec<(f64, DVec3)> = ts
        .iter()
        .map(|&t| {
            let q = uv(t);
            (t, surface.point(q.x, q.y))
        })
        .collect();
    for k in 0..4 {
        if k > 0 {
            out.push((uv(pts[k].0), pts[k].1));
        }
        split(surface, pts[k], pts[k + 1], &uv, tol, 0, &mut out);
    }
    out
}

fn to_uv_loop(l: &[Pt]) -> UvLoop {
    UvLoop {
        uv: l.iter().map(|p| p.uv).collect(),
        p3: l.iter().map(|p| p.p3).collect(),
        edge: l.iter().map(|p| p.edge).collect(),
    }
}
