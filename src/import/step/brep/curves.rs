//! Edge curves: `LINE`, `CIRCLE`, `ELLIPSE`, B-spline curves (with knots, Bézier, uniform,
//! quasi-uniform, rational complex instances), `POLYLINE`, and the wrappers whose 3D curve is used
//! (`SURFACE_CURVE`, `SEAM_CURVE`, `INTERSECTION_CURVE`, `TRIMMED_CURVE`). Also the curve
//! parameter of a vertex, for edge bounds.

use std::f64::consts::TAU;

use glam::DVec3;

use super::entities::Entity;
use super::points::Geo;
use super::splines::{KnotSpec, check_weights, degree, knot_vector};
use super::{BrepError, ErrorKind};
use crate::geometry::Interval;
use crate::geometry::curve::{Circle, CurveGeom, Ellipse, Line};
use crate::geometry::nurbs::BSplineCurve;

/// Deepest chain of curve wrappers followed (guards self-referencing curves).
const MAX_CURVE_DEPTH: usize = 8;

/// The curve `#id` referred to by `from`, in mm.
pub(super) fn curve(
    geo: &Geo<'_, '_>,
    from: Entity<'_>,
    id: u64,
    depth: usize,
) -> Result<CurveGeom, BrepError> {
    let e = geo.entity(from, id)?;
    if depth > MAX_CURVE_DEPTH {
        return Err(e.error(
            ErrorKind::Cycle,
            "curve definitions nest too deeply (self reference?)",
        ));
    }
    if e.has("LINE") {
        let a = e.args("LINE")?;
        let origin = geo.point(e, a.reference(1, "pnt")?)?;
        let dir = geo.vector_dir(e, a.reference(2, "dir")?)?;
        return Ok(CurveGeom::Line(Line { origin, dir }));
    }
    if e.has("CIRCLE") {
        let a = e.args("CIRCLE")?;
        let frame = geo.placement(e, a.reference(1, "position")?)?;
        let radius = geo.positive_length(e, a.real(2, "radius")?, "radius")?;
        return Ok(CurveGeom::Circle(Circle { frame, radius }));
    }
    if e.has("ELLIPSE") {
        let a = e.args("ELLIPSE")?;
        let frame = geo.placement(e, a.reference(1, "position")?)?;
        let semi_axis_1 = geo.positive_length(e, a.real(2, "semi_axis_1")?, "semi_axis_1")?;
        let semi_axis_2 = geo.positive_length(e, a.real(3, "semi_axis_2")?, "semi_axis_2")?;
        return Ok(CurveGeom::Ellipse(Ellipse {
            frame,
            semi_axis_1,
            semi_axis_2,
        }));
    }
    for wrapper in [
        "SURFACE_CURVE",
        "SEAM_CURVE",
        "INTERSECTION_CURVE",
        "TRIMMED_CURVE",
    ] {
        if e.has(wrapper) {
            let basis = e.args(wrapper)?.reference(1, "curve")?;
            return curve(geo, e, basis, depth + 1);
        }
    }
    if e.has("POLYLINE") {
        return polyline(geo, e);
    }
    if let Some(spline) = bspline_curve(geo, e)? {
        return Ok(CurveGeom::BSpline(spline));
    }
    let is_curve = e.inst.records.iter().any(|r| {
        r.name.contains("CURVE")
            || ["PARABOLA", "HYPERBOLA", "CLOTHOID", "CONIC"].contains(&r.name.as_str())
    });
    Err(if is_curve {
        e.error(
            ErrorKind::Unsupported,
            format!("unsupported curve type {}", e.type_name()),
        )
    } else {
        e.error(
            ErrorKind::WrongType,
            format!("expected a curve, found {}", e.type_name()),
        )
    })
}

/// A `POLYLINE` as a degree-1 B-spline with knots 0, 1, 2, ... at its points.
fn polyline(geo: &Geo<'_, '_>, e: Entity<'_>) -> Result<CurveGeom, BrepError> {
    let ids = e.args("POLYLINE")?.refs(1, "points")?;
    if ids.len() < 2 {
        return Err(e.error(
            ErrorKind::BadParameter,
            "a polyline needs at least two points",
        ));
    }
    let poles = ids
        .iter()
        .map(|&id| geo.point(e, id))
        .collect::<Result<Vec<_>, _>>()?;
    #[allow(clippy::cast_precision_loss)]
    let mut knots: Vec<f64> = (0..poles.len()).map(|i| i as f64).collect();
    let (first, last) = (0.0, knots.last().copied().unwrap_or(0.0));
    knots.insert(0, first);
    knots.push(last);
    BSplineCurve::new(1, knots, poles, None)
        .map(CurveGeom::BSpline)
        .map_err(|err| e.error(ErrorKind::InvalidGeometry, err.to_string()))
}

/// A B-spline curve in any of its simple or complex forms; `None` when `e` is not one.
fn bspline_curve(geo: &Geo<'_, '_>, e: Entity<'_>) -> Result<Option<BSplineCurve>, BrepError> {
    // (degree, control points, knot spec)
    let (deg, pole_ids, spec) = if let Some(_rec) = e.record("B_SPLINE_CURVE") {
        // Complex instance: B_SPLINE_CURVE(degree, points, form, closed, self_intersect) + a form.
        let a = e.args("B_SPLINE_CURVE")?;
        let spec = if e.has("B_SPLINE_CURVE_WITH_KNOTS") {
            let k = e.args("B_SPLINE_CURVE_WITH_KNOTS")?;
            KnotSpec::Explicit {
                mults: k.ints(0, "knot_multiplicities")?,
                knots: k.reals(1, "knots")?,
            }
        } else if e.has("BEZIER_CURVE") {
            KnotSpec::Bezier
        } else if e.has("QUASI_UNIFORM_CURVE") {
            KnotSpec::QuasiUniform
        } else if e.has("UNIFORM_CURVE") {
            KnotSpec::Uniform
        } else {
            return Err(e.error(ErrorKind::Unsupported, "B_SPLINE_CURVE without a knot form"));
        };
        (a.int(0, "degree")?, a.refs(1, "control_points_list")?, spec)
    } else if let Ok(k) = e.args("B_SPLINE_CURVE_WITH_KNOTS") {
        let spec = KnotSpec::Explicit {
            mults: k.ints(6, "knot_multiplicities")?,
            knots: k.reals(7, "knots")?,
        };
        (k.int(1, "degree")?, k.refs(2, "control_points_list")?, spec)
    } else if let Ok(a) = e.args_any(&["BEZIER_CURVE", "UNIFORM_CURVE", "QUASI_UNIFORM_CURVE"]) {
        let spec = match a.rec.name.as_str() {
            "BEZIER_CURVE" => KnotSpec::Bezier,
            "UNIFORM_CURVE" => KnotSpec::Uniform,
            _ => KnotSpec::QuasiUniform,
        };
        (a.int(1, "degree")?, a.refs(2, "control_points_list")?, spec)
    } else {
        return Ok(None);
    };
    let bad = |m: String| e.error(ErrorKind::InvalidGeometry, m);
    let p = degree(deg).map_err(bad)?;
    let knots = knot_vector(&spec, pole_ids.len(), p).map_err(bad)?;
    let poles = pole_ids
        .iter()
        .map(|&id| geo.point(e, id))
        .collect::<Result<Vec<_>, _>>()?;
    let weights = match e.record("RATIONAL_B_SPLINE_CURVE") {
        Some(_) => {
            let w = e
                .args("RATIONAL_B_SPLINE_CURVE")?
                .reals(0, "weights_data")?;
            check_weights(&w, poles.len()).map_err(bad)?;
            Some(w)
        }
        None => None,
    };
    BSplineCurve::new(p, knots, poles, weights)
        .map(Some)
        .map_err(|err| bad(err.to_string()))
}

/// A clamped B-spline whose ends are this close (mm) is closed in space.
const CLOSED_SPLINE_MM: f64 = 1e-6;

/// Curve parameters `(t_start, t_end)` of an edge running from `p_start` to `p_end` along `curve`,
/// in the curve's direction when `same_sense`, else against it. A closed edge (`closed`: the same
/// start and end vertex) spans one full period of a periodic curve, or the whole B-spline domain.
pub(super) fn edge_params(
    curve: &CurveGeom,
    p_start: DVec3,
    p_end: DVec3,
    closed: bool,
    same_sense: bool,
) -> (f64, f64) {
    match curve {
        CurveGeom::Line(l) => (
            (p_start - l.origin).dot(l.dir),
            (p_end - l.origin).dot(l.dir),
        ),
        CurveGeom::Circle(_) | CurveGeom::Ellipse(_) => {
            let ts = angle_param(curve, p_start);
            let te = if closed {
                ts
            } else {
                angle_param(curve, p_end)
            };
            wrap(ts, te, TAU, same_sense)
        }
        CurveGeom::BSpline(b) => {
            let (k0, k1) = spline_domain(b);
            if let Some(period) = curve.period().filter(|t| *t > 0.0) {
                let ts = spline_param(b, curve, p_start, (k0, k1));
                let te = if closed {
                    ts
                } else {
                    spline_param(b, curve, p_end, (k0, k1))
                };
                return wrap(ts, te, period, same_sense);
            }
            if closed {
                return if same_sense { (k0, k1) } else { (k1, k0) };
            }
            let (mut ts, mut te) = (
                spline_param(b, curve, p_start, (k0, k1)),
                spline_param(b, curve, p_end, (k0, k1)),
            );
            // A clamped spline closed in space (its first and last poles coincide, as a full
            // circle written as a B-spline): a vertex at the joint is at both ends of the
            // domain. Take the end that runs the edge in its sense; the other gives the
            // complementary arc (on a fan's hub rim, 300° instead of 60°).
            let at = |t: f64, k: f64| (t - k).abs() <= 1e-9 * (1.0 + (k1 - k0).abs());
            if curve.point(k0).distance(curve.point(k1)) <= CLOSED_SPLINE_MM {
                if same_sense && te < ts {
                    if at(ts, k1) {
                        ts = k0;
                    } else if at(te, k0) {
                        te = k1;
                    }
                } else if !same_sense && te > ts {
                    if at(ts, k0) {
                        ts = k1;
                    } else if at(te, k1) {
                        te = k0;
                    }
                }
            }
            (ts, te)
        }
    }
}

/// On a periodic curve, move `te` by one period so that the edge runs from `ts` in the sense's
/// direction, by less than one period (exactly one when `te == ts`: a closed edge).
fn wrap(ts: f64, mut te: f64, period: f64, same_sense: bool) -> (f64, f64) {
    if same_sense {
        if te <= ts {
            te += period;
        }
    } else if te >= ts {
        te -= period;
    }
    (ts, te)
}

/// Parameter in [0, 2π) of a point on a circle or ellipse.
fn angle_param(curve: &CurveGeom, p: DVec3) -> f64 {
    let (frame, a, b) = match curve {
        CurveGeom::Circle(c) => (c.frame, c.radius, c.radius),
        CurveGeom::Ellipse(e) => (e.frame, e.semi_axis_1, e.semi_axis_2),
        _ => return 0.0,
    };
    let local = frame.to_local(p);
    let t = (local.y / b).atan2(local.x / a);
    let t = if t < 0.0 { t + TAU } else { t };
    if t.is_finite() && t < TAU { t } else { 0.0 }
}

/// The parameter domain `[knots[p], knots[n]]` of a B-spline curve.
fn spline_domain(b: &BSplineCurve) -> (f64, f64) {
    let n = b.poles.len();
    let k0 = b.knots.get(b.degree).copied().unwrap_or(0.0);
    let k1 = b.knots.get(n).copied().unwrap_or(k0);
    (k0, k1)
}

/// Parameter of a vertex on a B-spline: the domain end when the vertex sits on a clamped end
/// pole, otherwise the closest point.
fn spline_param(b: &BSplineCurve, curve: &CurveGeom, p: DVec3, (k0, k1): (f64, f64)) -> f64 {
    let clamped = |range: &[f64]| range.windows(2).all(|w| w.first() == w.last());
    let p1 = b.degree + 1;
    let start_clamped = b.knots.get(..p1).is_some_and(clamped);
    let end_clamped = b.knots.len() >= p1 && b.knots.get(b.knots.len() - p1..).is_some_and(clamped);
    let scale = b
        .poles
        .iter()
        .fold(1.0_f64, |m, q| m.max(q.abs().max_element()));
    // Vertices sit on curve ends within the writer's modelling tolerance (CATIA: 0.005 mm).
    let tol = 1e-7 * scale + 1e-2;
    let d0 = b.poles.first().map_or(f64::INFINITY, |q| q.distance(p));
    let d1 = b.poles.last().map_or(f64::INFINITY, |q| q.distance(p));
    if start_clamped && d0 <= tol && d0 <= d1 {
        return k0;
    }
    if end_clamped && d1 <= tol {
        return k1;
    }
    curve.closest_param(p, Interval::new(k0, k1))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use super::*;
    use crate::geometry::frame::Frame;

    #[test]
    fn circle_edges_run_with_their_sense() {
        let c = CurveGeom::Circle(Circle {
            frame: Frame::WORLD,
            radius: 2.0,
        });
        let (a, b) = (DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 2.0, 0.0));
        let (ts, te) = edge_params(&c, a, b, false, true);
        assert!(ts.abs() < 1e-15 && (te - FRAC_PI_2).abs() < 1e-15);
        // Against the sense: from a to b the long way round, decreasing.
        let (ts, te) = edge_params(&c, a, b, false, false);
        assert!(ts.abs() < 1e-15 && (te + 3.0 * FRAC_PI_2).abs() < 1e-12);
        // Closed: one full turn either way, starting at the vertex.
        let (ts, te) = edge_params(&c, b, b, true, false);
        assert!((ts - FRAC_PI_2).abs() < 1e-15 && (te - (FRAC_PI_2 - TAU)).abs() < 1e-12);
    }

    #[test]
    fn periodic_spline_edges_span_one_period_from_the_vertex() {
        // A closed degree-1 B-spline A → B → C → A in Open CASCADE's unperiodised form: the first
        // pole repeats at the end and the knots repeat shifted by the period 3.
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let spline = BSplineCurve::new(
            1,
            vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
            vec![a, b, c, a],
            None,
        )
        .unwrap();
        let curve = CurveGeom::BSpline(spline);
        assert_eq!(curve.period(), Some(3.0));
        let (ts, te) = edge_params(&curve, b, b, true, true);
        assert!(
            (ts - 2.0).abs() < 1e-9 && (te - 5.0).abs() < 1e-9,
            "{ts} {te}"
        );
        // From C back to B along the sense wraps through A.
        let (ts, te) = edge_params(&curve, c, b, false, true);
        assert!(
            (ts - 3.0).abs() < 1e-9 && (te - 5.0).abs() < 1e-9,
            "{ts} {te}"
        );
    }

    #[test]
    fn closed_clamped_spline_edges_from_the_joint_run_with_their_sense() {
        // A closed, clamped degree-1 B-spline A → B → C → A: the vertex A is at both ends of
        // the domain [0, 3]. An edge C → A along the sense ends at 3, not at 0 (which would run
        // it backwards through B, the complementary arc).
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let spline = BSplineCurve::new(
            1,
            vec![0.0, 0.0, 1.0, 2.0, 3.0, 3.0],
            vec![a, b, c, a],
            None,
        )
        .unwrap();
        let curve = CurveGeom::BSpline(spline);
        assert_eq!(curve.period(), None);
        let (ts, te) = edge_params(&curve, c, a, false, true);
        assert!(
            (ts - 2.0).abs() < 1e-9 && (te - 3.0).abs() < 1e-9,
            "{ts} {te}"
        );
        // A → C against the sense starts at 3 and runs down to 2.
        let (ts, te) = edge_params(&curve, a, c, false, false);
        assert!(
            (ts - 3.0).abs() < 1e-9 && (te - 2.0).abs() < 1e-9,
            "{ts} {te}"
        );
        // Away from the joint nothing changes: A → B along the sense is [0, 1].
        let (ts, te) = edge_params(&curve, a, b, false, true);
        assert!(ts.abs() < 1e-9 && (te - 1.0).abs() < 1e-9, "{ts} {te}");
    }
}
