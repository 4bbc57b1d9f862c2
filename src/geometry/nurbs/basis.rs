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
    /// First derivatives (zeros when not requested).
    pub n1: &'a [f64],
    /// Second derivatives (zeros when not requested).
    pub n2: &'a [f64],
}

/// Compute the basis at `u` (must be finite; clamped into the domain by the caller) and hand it
/// to `f`; with `derivatives == false` only `n0` is filled. Requires a structurally valid knot
/// vector (`knots.len() == n_poles + p + 1`, p ≥ 1).
pub(crate) fn with_basis<R>(
    knots: &[f64],
    p: usize,
    n_poles: usize,
    u: f64,
    derivatives: bool,
    f: impl FnOnce(Basis<'_>) -> R,
) -> R {
    let span = find_span(knots, p, n_poles, u);
    let at = Site {
        knots,
        p,
        span,
        u,
        derivatives,
    };
    let len = 7 * (p + 1);
    if len <= 7 * 5 {
        let mut s = [0.0; 7 * 5];
        at.fill(&mut s[..len], f)
    } else if len <= 7 * 16 {
        let mut s = [0.0; 7 * 16];
        at.fill(&mut s[..len], f)
    } else {
        let mut s = vec![0.0; len];
        at.fill(&mut s, f)
    }
}

/// Where the basis is evaluated.
struct Site<'k> {
    knots: &'k [f64],
    p: usize,
    span: usize,
    u: f64,
    derivatives: bool,
}

impl Site<'_> {
    fn fill<R>(&self, s: &mut [f64], f: impl FnOnce(Basis<'_>) -> R) -> R {
        let (knots, p, span, u) = (self.knots, self.p, self.span, self.u);
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
            if self.derivatives && j + 1 == p {
                nm1[..=j].copy_from_slice(&n[..=j]);
            }
            if self.derivatives && j + 2 == p {
                nm2[..=j].copy_from_slice(&n[..=j]);
            }
        }
        if self.derivatives {
            // First derivative of degree p from the degree p−1 values.
            self.raise_derivative(p, &nm1[..p], d1);
            // Second: derivative of degree p−1 from degree p−2, then once more.
            if p >= 2 {
                let (dm1, _) = left.split_at_mut(p);
                self.raise_derivative(p - 1, &nm2[..p - 1], dm1);
                self.raise_derivative(p, dm1, d2);
            }
        }
        f(Basis {
            span,
            n0: n,
            n1: d1,
            n2: d2,
        })
    }

    /// Eq. 2.9: given `a[r]` for the q functions of degree q−1 non-zero on the span (indices
    /// `span − q + 1 + r`), write for the q+1 functions of degree q (`i = span − q + r`)
    /// `b[r] = q (a_i / (U_{i+q} − U_i) − a_{i+1} / (U_{i+q+1} − U_{i+1}))`.
    fn raise_derivative(&self, q: usize, a: &[f64], b: &mut [f64]) {
        let (knots, span) = (self.knots, self.span);
        // The right term of r and the left term of r + 1 share the knot difference
        // U_{span+r+1} − U_{span−q+r+1}: one division each.
        let qf = q as f64;
        let mut carried = 0.0;
        for r in 0..=q {
            let mut v = carried;
            carried = 0.0;
            if r < q {
                let den = knots[span + r + 1] - knots[span + r + 1 - q];
                if den > 0.0 {
                    let t = a[r] / den;
                    v -= t;
                    carried = t;
                }
            }
            b[r] = qf * v;
        }
    }
}
