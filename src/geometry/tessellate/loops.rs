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
}

/// A boundary point after inversion.
#[derive(Clone, Copy, Debug)]
struct Pt {
    uv: DVec2,
    p3: DVec3,
    /// The surface is degenerate here in u (`S_u = 0`, e.g. a pole) or in v.
    singular_u: bool,
    singular_v: bool,
}

/// The face's loops in the parameter plane, ready to triangulate. `Err` explains why not.
pub(super) fn face_uv_loops(
    face: &Face,
    part: &Part,
    edge_polylines: &[Vec<DVec3>],
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
                unwrap(&mut pts, pu, pv);
                loops.push(pts);
            }
            Loop::Vertex(vi) => {
                let p = part
                    .vertices
                    .get(*vi)
                    .ok_or_else(|| format!("vertex loop refers to missing vertex {vi}"))?
                    .point;
                vertex_loop_points.push(surface.closest_point(p, rect, None).uv);
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
    close_periodic(loops, pu, pv, face.same_sense, &vertex_loop_points, rect)
}

/// The 3D points of an edge loop in order (each edge's last point is the next edge's first).
/// The importer has already chained the loop (`import::step` repairs loops listed out of order
/// or with reversed edges, as Open CASCADE's wire fixing does).
fn loop_points(oes: &[OrientedEdge], edge_polylines: &[Vec<DVec3>]) -> Result<Vec<DVec3>, String> {
    let mut pts = Vec::new();
    for oe in oes {
        let poly = edge_polylines
            .get(oe.edge)
            .ok_or_else(|| format!("loop refers to missing edge {}", oe.edge))?;
        if poly.is_empty() {
            continue;
        }
        if oe.forward {
            pts.extend_from_slice(&poly[..poly.len() - 1]);
        } else {
            pts.extend(poly[1..].iter().rev());
        }
    }
    Ok(pts)
}

/// A boundary point this close to the surface is taken as lying on it (CAD tolerances are
/// 1e-7 to 1e-3 mm).
const NEAR_ENOUGH_MM: f64 = 1e-4;

fn invert(surface: &SurfaceGeom, rect: ParamRect, pts3: &[DVec3]) -> Vec<Pt> {
    let mut hint = None;
    let mut out = Vec::with_capacity(pts3.len());
    for &p in pts3 {
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
        out.push(Pt { uv: first, ..*p });
        if (second - first).length() > 1e-12 {
            out.push(Pt { uv: second, ..*p });
        }
    }
    out
}

/// Close loops that run once around a periodic direction: two such loops bound a band, one such
/// loop bounds a cap closed at the singular end (apex or pole) on the face's side.
fn close_periodic(
    loops: Vec<Vec<Pt>>,
    pu: Option<f64>,
    pv: Option<f64>,
    same_sense: bool,
    vertex_loops: &[DVec2],
    rect: ParamRect,
) -> Result<Vec<UvLoop>, String> {
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
            let v_end = if let Some(vp) = vertex_loops.first() {
                vp.y
            } else if (*shift > 0.0) == same_sense {
                rect.v.t1
            } else {
                rect.v.t0
            };
            if !v_end.is_finite() {
                return Err("a loop runs around the periodic u direction and the surface has no end to close it on".into());
            }
            let Some(first) = l.first() else {
                return Ok(closed);
            };
            let mut ul = to_uv_loop(l);
            let first_u_shifted = first.uv.x + shift;
            let end_p3 = first.p3;
            ul.uv.push(DVec2::new(first_u_shifted, first.uv.y));
            ul.p3.push(first.p3);
            ul.uv.push(DVec2::new(first_u_shifted, v_end));
            ul.p3.push(end_p3);
            ul.uv.push(DVec2::new(first.uv.x, v_end));
            ul.p3.push(end_p3);
            closed.push(ul);
        }
        [(a, sa), (b, sb)] => {
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
            ul.uv.push(a_end);
            ul.p3.push(a0.p3);
            for p in &b_pts {
                ul.uv.push(DVec2::new(p.uv.x + b_shift, p.uv.y));
                ul.p3.push(p.p3);
            }
            ul.uv.push(DVec2::new(b0.uv.x + b_shift + sb, b0.uv.y));
            ul.p3.push(b0.p3);
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

fn to_uv_loop(l: &[Pt]) -> UvLoop {
    UvLoop {
        uv: l.iter().map(|p| p.uv).collect(),
        p3: l.iter().map(|p| p.p3).collect(),
    }
}
