//! B-spline basis functions and their first two derivatives at one parameter (The NURBS Book
//! A2.2 and eq. 2.9 applied twice, equivalent to A2.3), on stack scratch for degrees up to 15.

use super::knots::find_span;

/// The `p + 1` non-zero basis functions of degree `p` at `u` and their derivatives; entry `r`
/// belongs to basis function `span − p + r`.
pub(crate) struct Basis<'a> {
    /// Knot span index.
    pub span: usize,
    /// N_{span−p+r, p}(u).
    pub n0: &'a [f64],
    /// First derivatives.
    pub n1: &'a [f64],
    /// Second derivatives.
    pub n2: &'a [f64],
}

/// Compute the basis at `u` (must be finite; clamped into the domain by the caller) and hand it
/// to `f`. Requires a structurally valid knot vector (`knots.len() == n_poles + p + 1`, p ≥ 1).
pub(crate) fn with_basis<R>(
    knots: &[f64],
    p: usize,
    n_poles: usize,
    u: f64,
    f: impl FnOnce(Basis<'_>) -> R,
) -> R {
    let span = find_span(knots, p, n_poles, u);
    let len = 7 * (p + 1);
    if len <= 7 * 5 {
        let mut s = [0.0; 7 * 5];
        fill(knots, p, span, u, &mut s[..len], f)
    } else if len <= 7 * 16 {
        let mut s = [0.0; 7 * 16];
        fill(knots, p, span, u, &mut s[..len], f)
    } else {
        let mut s = vec![0.0; len];
        fill(knots, p, span, u, &mut s, f)
    }
}

fn fill<R>(
    knots: &[f64],
    p: usize,
    span: usize,
    u: f64,
    s: &mut [f64],
    f: impl FnOnce(Basis<'_>) -> R,
) -> R {
    let m = p + 1;
    let (left, rest) = s.split_at_mut(m);
    let (right, rest) = rest.split_at_mut(m);
    let (n, rest) = rest.split_at_mut(m);
    let (nm1, rest) = rest.split_at_mut(m);
    let (nm2, rest) = rest.split_at_mut(m);
    let (d1, rest) = rest.split_at_mut(m);
    let d2 = &mut rest[..m];

    // A2.2, keeping the degree p−1 and p−2 values.
    n[0] = 1.0;
    if p == 1 {
        nm1[0] = 1.0;
    }
    if p == 2 {
        nm2[0] = 1.0;
    }
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let den = right[r + 1] + left[j - r];
            let temp = if den > 0.0 { n[r] / den } else { 0.0 };
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
        if j + 1 == p {
            nm1[..=j].copy_from_slice(&n[..=j]);
        }
        if j + 2 == p {
            nm2[..=j].copy_from_slice(&n[..=j]);
        }
    }

    // First derivative of degree p from the degree p−1 values.
    raise_derivative(knots, p, span, &nm1[..p], d1);
    // Second derivative: derivative of degree p−1 from degree p−2, then once more.
    if p >= 2 {
        let (dm1, _) = left.split_at_mut(p);
        raise_derivative(knots, p - 1, span, &nm2[..p - 1], dm1);
        raise_derivative(knots, p, span, dm1, d2);
    } else {
        d2.fill(0.0);
    }
    f(Basis {
        span,
        n0: n,
        n1: d1,
        n2: d2,
    })
}

/// Eq. 2.9: given `a[r]` for the q functions of degree q−1 non-zero on `span` (indices
/// `span − q + 1 + r`), write `b[r] = q (a_{i}/(U_{i+q} − U_i) − a_{i+1}/(U_{i+q+1} − U_{i+1}))`
/// for the q+1 functions of degree q (`i = span − q + r`). `b` may alias nothing in `a`.
fn raise_derivative(knots: &[f64], q: usize, span: usize, a: &[f64], b: &mut [f64]) {
    let qf = q as f64;
    for r in 0..=q {
        let i = span - q + r;
        let mut v = 0.0;
        if r >= 1 {
            let den = knots[i + q] - knots[i];
            if den > 0.0 {
                v += a[r - 1] / den;
            }
        }
        if r < q {
            let den = knots[i + q + 1] - knots[i + 1];
            if den > 0.0 {
                v -= a[r] / den;
            }
        }
        b[r] = qf * v;
    }
}
