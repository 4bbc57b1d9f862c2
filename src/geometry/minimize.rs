//! One-dimensional minimisation shared by the sweep computations (gouge verification, stock
//! removal): golden-section search of a function that is convex (unimodal) on an interval.

/// 1/φ, the golden-section ratio.
pub const INV_PHI: f64 = 0.618_033_988_749_894_8;

/// The smallest value of a unimodal `f` on `[a, b]` found by `iterations` golden-section steps
/// (the bracket shrinks by 1/φ per step), including the end values `f(a)` and `f(b)`.
pub fn golden_min(a: f64, b: f64, iterations: usize, f: impl Fn(f64) -> f64) -> f64 {
    let ends = f(a).min(f(b));
    let (_, f1, f2) = golden_bracket(a, b, iterations, &f);
    ends.min(f1).min(f2)
}

/// The smallest value of a unimodal `f` on `[a, b]` and where it is: the better of the two
/// inner points left after `iterations` golden-section steps and the two ends.
pub fn golden_point(a: f64, b: f64, iterations: usize, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let ((lo, hi), f1, f2) = golden_bracket(a, b, iterations, &f);
    let mut best = if f1 <= f2 {
        (hi - INV_PHI * (hi - lo), f1)
    } else {
        (lo + INV_PHI * (hi - lo), f2)
    };
    for x in [a, b] {
        let v = f(x);
        if v < best.1 {
            best = (x, v);
        }
    }
    best
}

/// The place of the smallest value of a unimodal `f` on `[a, b]`: the middle of the bracket
/// left after `iterations` golden-section steps.
pub fn golden_argmin(a: f64, b: f64, iterations: usize, f: impl Fn(f64) -> f64) -> f64 {
    let ((a, b), _, _) = golden_bracket(a, b, iterations, &f);
    0.5 * (a + b)
}

/// The bracket after `iterations` golden-section steps and the values at its two inner points.
fn golden_bracket(
    mut a: f64,
    mut b: f64,
    iterations: usize,
    f: &impl Fn(f64) -> f64,
) -> ((f64, f64), f64, f64) {
    let mut x1 = b - INV_PHI * (b - a);
    let mut x2 = a + INV_PHI * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..iterations {
        if f1 <= f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - INV_PHI * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + INV_PHI * (b - a);
            f2 = f(x2);
        }
    }
    ((a, b), f1, f2)
}

/// Golden-section steps needed to shrink a bracket of width `width` to `resolution`
/// (at least 1, at most `max`).
#[must_use]
pub fn golden_iterations(width: f64, resolution: f64, max: usize) -> usize {
    let n = ((width / resolution).ln() / (1.0 / INV_PHI).ln()).ceil();
    if n.is_nan() {
        return max;
    }
    n.clamp(1.0, max as f64) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_minimum_of_a_parabola_and_of_monotone_ends() {
        let m = golden_min(-1.0, 3.0, 60, |x| (x - 0.3).powi(2) + 2.0);
        assert!((m - 2.0).abs() < 1e-12, "{m}");
        // Monotone: the minimum is at an end.
        assert_eq!(golden_min(0.0, 1.0, 5, |x| x + 7.0), 7.0);
        assert_eq!(golden_iterations(1.0, 1e-9, 80), 44);
        assert_eq!(golden_iterations(0.0, 1e-9, 80), 1);
    }
}
