//! Edge discretisation: a polyline within the chord and angle tolerances, from the start vertex to
//! the end vertex (whose exact coordinates it uses, so adjacent edges and faces share them).

use super::TessellationOptions;
use crate::geometry::DVec3;
use crate::geometry::brep::{Edge, Vertex};
use crate::geometry::curve::CurveGeom;

/// Deepest midpoint subdivision of one initial segment (2^12 pieces).
const MAX_DEPTH: u32 = 12;

/// Most points on one edge: a budget against curves whose tolerance test never passes
/// (non-finite or astronomically large geometry), not a limit real edges reach.
pub const MAX_EDGE_POINTS: usize = 20_000;

/// Discretise `edge` into a polyline from its start vertex to its end vertex. The first and last
/// points are the vertices' coordinates; interior points lie on the curve.
#[must_use]
pub fn discretize_edge(edge: &Edge, vertices: &[Vertex], opts: &TessellationOptions) -> Vec<DVec3> {
    let start = vertices
        .get(edge.start)
        .map_or_else(|| edge.curve.point(edge.t_start), |v| v.point);
    let end = vertices
        .get(edge.end)
        .map_or_else(|| edge.curve.point(edge.t_end), |v| v.point);
    let params = edge_params(&edge.curve, edge.t_start, edge.t_end, opts);
    let mut pts = Vec::with_capacity(params.len());
    pts.push(start);
    for &t in &params[1..params.len().saturating_sub(1)] {
        let p = edge.curve.point(t);
        if p.is_finite() {
            pts.push(p);
        }
    }
    pts.push(end);
    pts
}

/// Parameters (including both ends) of the discretisation of `curve` over `[t0, t1]` (t1 may be
/// below t0 for a reversed edge).
#[must_use]
pub fn edge_params(curve: &CurveGeom, t0: f64, t1: f64, opts: &TessellationOptions) -> Vec<f64> {
    if !t0.is_finite() || !t1.is_finite() || t0 == t1 {
        return vec![t0, t1];
    }
    let n0 = initial_segments(curve, t0, t1, opts);
    let mut out = vec![t0];
    for k in 0..n0 {
        let a = t0 + (t1 - t0) * (k as f64) / (n0 as f64);
        let b = t0 + (t1 - t0) * ((k + 1) as f64) / (n0 as f64);
        subdivide(curve, a, b, opts, 0, &mut out);
    }
    if let Some(last) = out.last_mut() {
        *last = t1;
    }
    out
}

/// Initial uniform segment count: conics by their angle, B-splines by their knot spans.
fn initial_segments(curve: &CurveGeom, t0: f64, t1: f64, opts: &TessellationOptions) -> usize {
    let span = (t1 - t0).abs();
    let n = match curve {
        CurveGeom::Line(_) => 1.0,
        CurveGeom::Circle(c) => span / angle_step(c.radius, opts),
        CurveGeom::Ellipse(e) => span / angle_step(e.semi_axis_1.max(e.semi_axis_2), opts),
        CurveGeom::BSpline(b) => {
            let (lo, hi) = (t0.min(t1), t0.max(t1));
            let spans = b
                .knots
                .windows(2)
                .filter(|w| w[1] > w[0] && w[1] > lo && w[0] < hi)
                .count();
            (spans * b.degree.max(1)) as f64
        }
    };
    if n.is_finite() {
        (n.ceil() as usize).clamp(1, 4096)
    } else {
        1
    }
}

/// Angle step of a circle of radius `r` within the chord and angle tolerances.
fn angle_step(r: f64, opts: &TessellationOptions) -> f64 {
    let by_chord = if r > opts.chord_tol_mm {
        2.0 * (1.0 - opts.chord_tol_mm / r).acos()
    } else {
        std::f64::consts::PI
    };
    by_chord.min(opts.angle_tol_rad).max(1e-4)
}

/// Append the parameters after `a` up to and including `b`, splitting while the midpoint strays
/// from the chord or the tangent turns too much.
fn subdivide(
    curve: &CurveGeom,
    a: f64,
    b: f64,
    opts: &TessellationOptions,
    depth: u32,
    out: &mut Vec<f64>,
) {
    if depth < MAX_DEPTH && out.len() < MAX_EDGE_POINTS && needs_split(curve, a, b, opts) {
        let m = 0.5 * (a + b);
        subdivide(curve, a, m, opts, depth + 1, out);
        subdivide(curve, m, b, opts, depth + 1, out);
    } else {
        out.push(b);
    }
}

fn needs_split(curve: &CurveGeom, a: f64, b: f64, opts: &TessellationOptions) -> bool {
    if matches!(curve, CurveGeom::Line(_)) {
        return false;
    }
    let da = curve.derivs(a);
    let db = curve.derivs(b);
    let chord = db.p - da.p;
    // Chord error at the quarter points and the midpoint.
    for s in [0.25, 0.5, 0.75] {
        let p = curve.point(a + (b - a) * s);
        let dev = chord.try_normalize().map_or_else(
            || (p - da.p).length(),
            |dir| (p - da.p).reject_from_normalized(dir).length(),
        );
        if dev > opts.chord_tol_mm {
            return true;
        }
    }
    match (da.d1.try_normalize(), db.d1.try_normalize()) {
        (Some(ta), Some(tb)) => ta.dot(tb).clamp(-1.0, 1.0).acos() > opts.angle_tol_rad,
        _ => false,
    }
}
