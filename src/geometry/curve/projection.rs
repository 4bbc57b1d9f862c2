//! Point projection onto curves (closest parameter): exact for lines and circles; for ellipses
//! and B-splines, dense seeds over the range, then monotone, step-limited Newton on
//! `f(t) = (C(t) − p)·C'(t)` from the best local minima.

use std::f64::consts::TAU;

use super::CurveGeom;
use crate::geometry::{DVec3, Interval};

/// A finite parameter in `range` to return when nothing better is defined.
fn fallback(range: Interval, dom: Interval) -> f64 {
    let r = Interval::new(range.t0.max(dom.t0), range.t1.min(dom.t1));
    [r.t0, r.t1, range.t0, range.t1, dom.t0, dom.t1]
        .into_iter()
        .find(|t| t.is_finite())
        .unwrap_or(0.0)
}

/// See [`CurveGeom::closest_param`].
pub(super) fn closest_param(curve: &CurveGeom, p: DVec3, range: Interval) -> f64 {
    let dom = curve.domain();
    let range = sanitize(range, dom);
    if !p.is_finite() || range.t0 == range.t1 {
        return fallback(range, dom);
    }
    let t = match curve {
        CurveGeom::Line(l) => {
            let dd = l.dir.length_squared();
            if dd > 0.0 {
                range.clamp((p - l.origin).dot(l.dir) / dd)
            } else {
                fallback(range, dom)
            }
        }
        CurveGeom::Circle(c) => {
            let q = c.frame.to_local(p);
            if q.x.hypot(q.y) <= 1e-15 * (q.z.abs() + c.radius.abs()) {
                fallback(range, dom)
            } else {
                into_periodic_range(curve, p, q.y.atan2(q.x), TAU, range)
            }
        }
        CurveGeom::Ellipse(_) | CurveGeom::BSpline(_) => numeric(curve, p, range, dom),
    };
    if t.is_finite() {
        t
    } else {
        fallback(range, dom)
    }
}

/// Replace NaN ends by the domain's, order the ends.
fn sanitize(range: Interval, dom: Interval) -> Interval {
    let t0 = if range.t0.is_nan() { dom.t0 } else { range.t0 };
    let t1 = if range.t1.is_nan() { dom.t1 } else { range.t1 };
    Interval::new(t0.min(t1), t0.max(t1))
}

/// `t` (any representative) brought into `range` modulo `period`; when no representative lies
/// in a finite range, the closer range end.
fn into_periodic_range(curve: &CurveGeom, p: DVec3, t: f64, period: f64, range: Interval) -> f64 {
    if range.t0.is_finite() {
        let tk = range.t0 + (t - range.t0).rem_euclid(period);
        if tk <= range.t1 {
            return tk;
        }
        if range.t1.is_finite() {
            let d0 = curve.point(range.t0).distance_squared(p);
            let d1 = curve.point(range.t1).distance_squared(p);
            return if d1 < d0 { range.t1 } else { range.t0 };
        }
        return range.t0;
    }
    if range.t1.is_finite() {
        return range.t1 - (range.t1 - t).rem_euclid(period);
    }
    t.rem_euclid(period)
}

/// Seeds + bounded Newton for curves without a closed form.
fn numeric(curve: &CurveGeom, p: DVec3, range: Interval, dom: Interval) -> f64 {
    let period = curve.period();
    // The search window and whether Newton is clamped to it.
    let (lo, hi, bounded) = match period {
        Some(per) if !range.is_finite() || range.len() >= per => {
            let a = if range.t0.is_finite() {
                range.t0
            } else if range.t1.is_finite() {
                range.t1 - per
            } else {
                dom.t0
            };
            (a, a + per, false)
        }
        Some(_) => (range.t0, range.t1, true),
        None => {
            let (lo, hi) = (range.t0.max(dom.t0), range.t1.min(dom.t1));
            if lo > hi {
                return if range.t1 < dom.t0 {
                    range.t1
                } else {
                    range.t0
                };
            }
            (lo, hi, true)
        }
    };
    if !lo.is_finite() || !hi.is_finite() || hi <= lo {
        return fallback(range, dom);
    }
    let n = match curve {
        CurveGeom::BSpline(b) => (b.poles.len() * 3 + 8).clamp(16, 256),
        _ => 24,
    };
    let h = (hi - lo) / n as f64;
    let samples: Vec<(f64, f64)> = (0..=n)
        .map(|i| {
            let t = if i == n { hi } else { lo + h * i as f64 };
            (t, curve.point(t).distance_squared(p))
        })
        .collect();
    // Local minima of the sampled distance (ends count), best first.
    let mut seeds: Vec<(f64, f64)> = (0..samples.len())
        .filter(|&i| {
            let d = samples[i].1;
            let left = if i > 0 {
                samples[i - 1].1
            } else if bounded {
                f64::INFINITY
            } else {
                samples[n].1
            };
            let right = if i < n {
                samples[i + 1].1
            } else if bounded {
                f64::INFINITY
            } else {
                samples[0].1
            };
            d <= left && d <= right
        })
        .map(|i| samples[i])
        .collect();
    seeds.sort_by(|a, b| a.1.total_cmp(&b.1));
    seeds.truncate(4);
    let mut best = seeds.first().copied().unwrap_or((lo, f64::INFINITY));
    let clamp = |t: f64| if bounded { t.clamp(lo, hi) } else { t };
    for &(t0, d0) in &seeds {
        let (t, d) = newton(curve, p, t0, d0, 2.0 * h, clamp);
        if d < best.1 {
            best = (t, d);
        }
    }
    let t = best.0;
    if bounded {
        t
    } else if let Some(per) = period {
        into_periodic_range(curve, p, t, per, range)
    } else {
        t
    }
}

/// Monotone Newton on `(C − p)·C'` with step limit `max_step`; returns `(t, |C(t) − p|²)`.
fn newton(
    curve: &CurveGeom,
    p: DVec3,
    mut t: f64,
    mut d: f64,
    max_step: f64,
    clamp: impl Fn(f64) -> f64,
) -> (f64, f64) {
    for _ in 0..50 {
        let c = curve.derivs(t);
        let r = c.p - p;
        let f = r.dot(c.d1);
        let gn = c.d1.length_squared();
        let fp = gn + r.dot(c.d2);
        let mut step = if fp > 0.0 {
            -f / fp
        } else if gn > 0.0 {
            -f / gn
        } else {
            break;
        };
        if !step.is_finite() {
            break;
        }
        step = step.clamp(-max_step, max_step);
        let mut improved = false;
        for _ in 0..30 {
            let tn = clamp(t + step);
            let dn = curve.point(tn).distance_squared(p);
            if dn <= d {
                improved = tn != t && dn < d;
                t = tn;
                d = dn;
                break;
            }
            step *= 0.5;
        }
        if !improved || step.abs() <= 1e-12 * max_step {
            break;
        }
    }
    (t, d)
}
