//! B-spline data shared by curves and surfaces: degrees, knot vectors (explicit with
//! multiplicities, or implied by the Bézier / uniform / quasi-uniform special forms) and weights.
//! Knot expansion itself is [`crate::geometry::nurbs::expand_knots`].

use crate::geometry::nurbs::expand_knots;

/// Highest degree accepted (Open CASCADE's limit).
pub(super) const MAX_DEGREE: usize = 25;
/// Most poles (or knots) accepted in one direction: guards memory against absurd files.
pub(super) const MAX_POLES: usize = 1 << 20;

/// How a B-spline entity gives its knots.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum KnotSpec {
    /// `*_WITH_KNOTS`: multiplicities and distinct knot values.
    Explicit { mults: Vec<i64>, knots: Vec<f64> },
    /// `BEZIER_*`: one span on [0, 1].
    Bezier,
    /// `UNIFORM_*`: unit-spaced knots, none repeated.
    Uniform,
    /// `QUASI_UNIFORM_*`: unit-spaced, ends repeated `degree + 1` times.
    QuasiUniform,
}

/// A degree read from a file, checked to lie in `1..=MAX_DEGREE`.
pub(super) fn degree(d: i64) -> Result<usize, String> {
    usize::try_from(d)
        .ok()
        .filter(|d| (1..=MAX_DEGREE).contains(d))
        .ok_or_else(|| format!("degree {d} is outside 1..={MAX_DEGREE}"))
}

/// The full knot vector for `n` poles of degree `p`, checked against `n + p + 1`.
///
/// # Errors
/// A message naming the inconsistency.
pub(super) fn knot_vector(spec: &KnotSpec, n: usize, p: usize) -> Result<Vec<f64>, String> {
    if n < p + 1 {
        return Err(format!("{n} poles are too few for degree {p}"));
    }
    if n > MAX_POLES {
        return Err(format!("{n} poles is too many"));
    }
    #[allow(clippy::cast_precision_loss)]
    let knots = match spec {
        KnotSpec::Explicit { mults, knots } => {
            let counts = mults
                .iter()
                .map(|&m| usize::try_from(m).map_err(|_| format!("multiplicity {m} is negative")))
                .collect::<Result<Vec<usize>, String>>()?;
            let full = expand_knots(knots, &counts).map_err(|e| e.to_string())?;
            // As Open CASCADE: end knots at most degree + 1 times, interior knots at most
            // degree times (more would break the curve apart).
            let last = counts.len().saturating_sub(1);
            for (i, &m) in counts.iter().enumerate() {
                let limit = if i == 0 || i == last { p + 1 } else { p };
                if m > limit {
                    return Err(format!(
                        "knot {} has multiplicity {m}, more than {limit}",
                        i + 1
                    ));
                }
            }
            full
        }
        KnotSpec::Bezier => {
            if n != p + 1 {
                return Err(format!(
                    "a Bézier form of degree {p} needs {} poles, has {n}",
                    p + 1
                ));
            }
            let mut k = vec![0.0; p + 1];
            k.extend(std::iter::repeat_n(1.0, p + 1));
            k
        }
        KnotSpec::Uniform => (0..n + p + 1).map(|i| i as f64 - p as f64).collect(),
        KnotSpec::QuasiUniform => {
            let spans = n - p;
            let mut k = vec![0.0; p + 1];
            k.extend((1..spans).map(|i| i as f64));
            k.extend(std::iter::repeat_n(spans as f64, p + 1));
            k
        }
    };
    if knots.len() != n + p + 1 {
        return Err(format!(
            "knot multiplicities sum to {} but {n} poles of degree {p} need {}",
            knots.len(),
            n + p + 1
        ));
    }
    Ok(knots)
}

/// Check weights: one per pole, finite and positive.
///
/// # Errors
/// A message naming the mismatch.
pub(super) fn check_weights(w: &[f64], n: usize) -> Result<(), String> {
    if w.len() != n {
        return Err(format!("{} weights for {n} poles", w.len()));
    }
    if let Some(i) = w.iter().position(|x| !(x.is_finite() && *x > 0.0)) {
        return Err(format!("weight {} is not positive", i + 1));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_forms_give_standard_knots() {
        assert_eq!(
            knot_vector(&KnotSpec::Bezier, 3, 2).unwrap(),
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]
        );
        assert_eq!(
            knot_vector(&KnotSpec::QuasiUniform, 4, 2).unwrap(),
            vec![0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0]
        );
        assert_eq!(
            knot_vector(&KnotSpec::Uniform, 3, 1).unwrap(),
            vec![-1.0, 0.0, 1.0, 2.0, 3.0]
        );
        assert!(knot_vector(&KnotSpec::Bezier, 4, 2).is_err());
        let explicit = KnotSpec::Explicit {
            mults: vec![3, 3],
            knots: vec![0.0, 1.0],
        };
        assert!(knot_vector(&explicit, 3, 2).is_ok());
        assert!(knot_vector(&explicit, 4, 2).is_err());
        assert!(knot_vector(&explicit, 1, 2).is_err());
        // Interior multiplicity above the degree is refused (Open CASCADE refuses it too).
        let broken = KnotSpec::Explicit {
            mults: vec![3, 3, 3],
            knots: vec![0.0, 0.5, 1.0],
        };
        assert!(knot_vector(&broken, 6, 2).is_err());
        let negative = KnotSpec::Explicit {
            mults: vec![-3, 3],
            knots: vec![0.0, 1.0],
        };
        assert!(knot_vector(&negative, 3, 2).is_err());
        assert!(
            degree(0).is_err() && degree(-3).is_err() && degree(26).is_err() && degree(3).is_ok()
        );
        assert!(check_weights(&[1.0, 2.0], 3).is_err());
        assert!(check_weights(&[1.0, 0.0, 1.0], 3).is_err());
    }
}
