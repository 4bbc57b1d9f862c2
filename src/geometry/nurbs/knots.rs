//! Knot vectors: expansion from STEP's distinct values with multiplicities, validation, span
//! search (The NURBS Book A2.1) and periodicity.

use crate::geometry::{GeometryError, Interval};

/// Highest degree accepted (far above anything CAD systems write; keeps scratch buffers bounded).
pub const MAX_DEGREE: usize = 32;

/// Largest expanded knot vector accepted from a file (guards against absurd allocations).
const MAX_KNOTS: usize = 1 << 22;

/// Expand STEP-style knots (`knots[i]` repeated `mults[i]` times) into a full knot vector.
///
/// # Errors
/// [`GeometryError::InvalidBSpline`] when the lists differ in length, are empty, a multiplicity is
/// zero, the distinct knots are not strictly increasing, or the total is absurdly large;
/// [`GeometryError::NonFinite`] for a NaN or infinite knot.
pub fn expand_knots(knots: &[f64], mults: &[usize]) -> Result<Vec<f64>, GeometryError> {
    if knots.len() != mults.len() {
        return Err(GeometryError::InvalidBSpline(format!(
            "{} distinct knots but {} multiplicities",
            knots.len(),
            mults.len()
        )));
    }
    if knots.is_empty() {
        return Err(GeometryError::InvalidBSpline("empty knot list".into()));
    }
    let mut total = 0usize;
    let mut prev = f64::NEG_INFINITY;
    for (i, (&k, &m)) in knots.iter().zip(mults).enumerate() {
        if !k.is_finite() {
            return Err(GeometryError::NonFinite(format!("knot {i}")));
        }
        if m == 0 {
            return Err(GeometryError::InvalidBSpline(format!(
                "knot {i} has multiplicity 0"
            )));
        }
        if k <= prev {
            return Err(GeometryError::InvalidBSpline(format!(
                "distinct knots not strictly increasing at index {i} ({prev} then {k})"
            )));
        }
        prev = k;
        total = total.saturating_add(m);
    }
    if total > MAX_KNOTS {
        return Err(GeometryError::InvalidBSpline(format!(
            "{total} knots is too many"
        )));
    }
    let mut out = Vec::with_capacity(total);
    for (&k, &m) in knots.iter().zip(mults) {
        out.extend(std::iter::repeat_n(k, m));
    }
    Ok(out)
}

/// Check a full knot vector for `n_poles` poles of degree `p` (`dir` names it in messages).
pub(crate) fn check_knots(
    knots: &[f64],
    p: usize,
    n_poles: usize,
    dir: &str,
) -> Result<(), GeometryError> {
    let bad = |msg: String| Err(GeometryError::InvalidBSpline(format!("{dir}: {msg}")));
    if p == 0 {
        return bad("degree must be at least 1".into());
    }
    if p > MAX_DEGREE {
        return bad(format!(
            "degree {p} exceeds the supported maximum {MAX_DEGREE}"
        ));
    }
    if n_poles < p + 1 {
        return bad(format!(
            "{n_poles} poles is too few for degree {p} (need at least {})",
            p + 1
        ));
    }
    if knots.len() != n_poles + p + 1 {
        return bad(format!(
            "{} knots for {n_poles} poles of degree {p} (need poles + degree + 1 = {})",
            knots.len(),
            n_poles + p + 1
        ));
    }
    if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
        return Err(GeometryError::NonFinite(format!("{dir}: knot {i}")));
    }
    let mut run = 1usize;
    for (i, w) in knots.windows(2).enumerate() {
        if let [a, b] = w {
            if b < a {
                return bad(format!("knots decrease at index {} ({a} then {b})", i + 1));
            }
            run = if b == a { run + 1 } else { 1 };
            if run > p + 1 {
                return bad(format!(
                    "knot {b} has multiplicity above degree + 1 = {}",
                    p + 1
                ));
            }
        }
    }
    let (lo, hi) = (knots[p], knots[n_poles]);
    if hi <= lo {
        return bad(format!("degenerate parameter domain [{lo}, {hi}]"));
    }
    Ok(())
}

/// Parameter domain `[U_p, U_{n+1}]` (assumes a structurally valid knot vector).
pub(crate) fn domain(knots: &[f64], p: usize, n_poles: usize) -> Interval {
    match (knots.get(p), knots.get(n_poles)) {
        (Some(&a), Some(&b)) => Interval::new(a, b),
        _ => Interval::new(0.0, 0.0),
    }
}

/// Knot span index `i` with `U_i ≤ u < U_{i+1}` and `p ≤ i ≤ n` (A2.1), always a non-empty span:
/// at or beyond the domain end the last non-empty span, at or before the start the first.
/// Requires `knots.len() == n_poles + p + 1` and `n_poles > p`; `u` must not be NaN.
pub(crate) fn find_span(knots: &[f64], p: usize, n_poles: usize, u: f64) -> usize {
    let n = n_poles - 1;
    let hi = knots[n + 1];
    if u >= hi {
        let mut i = n;
        while i > p && knots[i] >= hi {
            i -= 1;
        }
        return i;
    }
    let lo = knots[p];
    if u <= lo {
        let mut i = p;
        while i < n && knots[i + 1] <= lo {
            i += 1;
        }
        return i;
    }
    // Number of knots in U_p..=U_n that are ≤ u is at least 1 here.
    let k = knots[p..=n].partition_point(|&x| x <= u);
    (p + k).saturating_sub(1).clamp(p, n)
}

/// Period of a B-spline stored in OCCT's unperiodised form (knots repeat with a shift, the first
/// `p` pole rows equal the last `p`), `None` otherwise. `same_row(i, j)` says whether pole row `i`
/// equals pole row `j` (rows along this direction).
pub(crate) fn period(
    knots: &[f64],
    p: usize,
    n_poles: usize,
    same_row: impl Fn(usize, usize) -> bool,
) -> Option<f64> {
    if knots.len() != n_poles + p + 1 || n_poles <= 2 * p {
        return None;
    }
    let dom = domain(knots, p, n_poles);
    let t = dom.len();
    if t.is_nan() || t <= 0.0 {
        return None;
    }
    let tol = 1e-12 * (dom.t0.abs() + dom.t1.abs() + t);
    let shift = n_poles - p;
    let knots_periodic = (0..=2 * p).all(|i| match (knots.get(i), knots.get(i + shift)) {
        (Some(a), Some(b)) => (b - a - t).abs() <= tol,
        _ => false,
    });
    if knots_periodic && (0..p).all(|i| same_row(i, i + shift)) {
        Some(t)
    } else {
        None
    }
}

/// Bring `u` into `dom` modulo `period` (for evaluation of periodic splines outside the domain).
pub(crate) fn wrap(u: f64, dom: Interval, period: f64) -> f64 {
    let w = dom.t0 + (u - dom.t0).rem_euclid(period);
    if w.is_finite() { w.min(dom.t1) } else { dom.t0 }
}
