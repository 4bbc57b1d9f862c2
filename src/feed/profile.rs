//! Step 1 of the method: the time-optimal jerk-limited 1-DoF profile between two velocities at
//! rest acceleration (a = 0 at both ends), over a given distance.
//!
//! A velocity change `va → vb` under `|a| ≤ A`, `|j| ≤ J` with zero acceleration at both ends
//! takes, in closed form,
//! - `T = |Δv|/A + A/J` when `|Δv|·J ≥ A²` (a constant-acceleration phase exists),
//! - `T = 2·sqrt(|Δv|/J)` otherwise (the acceleration peaks at `sqrt(J·|Δv|)` < A),
//!
//! and, because the acceleration pulse is symmetric, covers `(va + vb)/2 · T`. A move over `s`
//! is accelerate `v0 → vp`, cruise at `vp`, decelerate `vp → v1` (7 phases of constant jerk);
//! `vp` is the largest peak ≤ `vmax` whose two changes fit in `s`: in closed form when both
//! changes or only one have a constant-acceleration phase and when `v0 = v1`, by a quartic
//! solved by Newton's method from a closed-form bound when neither has one, with a bracketed
//! iteration as the fallback (see `peak_velocity`; it never yields NaN).

/// Tangential limits of one 1-DoF move (all positive, finite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits1 {
    /// Velocity limit (units/s).
    pub velocity: f64,
    /// Acceleration limit (units/s²).
    pub acceleration: f64,
    /// Jerk limit (units/s³).
    pub jerk: f64,
}

impl Limits1 {
    /// All three limits are finite and positive.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        [self.velocity, self.acceleration, self.jerk]
            .iter()
            .all(|x| x.is_finite() && *x > 0.0)
    }
}

/// Why a 1-DoF profile cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// A limit, the distance or a boundary velocity is not finite, or negative, or a limit is 0.
    #[error("invalid input: distance, velocities and limits must be finite, limits positive")]
    InvalidInput,
    /// A boundary velocity exceeds the velocity limit.
    #[error("boundary velocity {velocity} exceeds the velocity limit {limit}")]
    BoundaryAboveLimit {
        /// The offending boundary velocity.
        velocity: f64,
        /// The limit.
        limit: f64,
    },
    /// `v1` cannot be reached from `v0` within the distance: changing the velocity needs
    /// `needed` but only `distance` is available.
    #[error("cannot change velocity within {distance}: needs {needed}")]
    Unreachable {
        /// Distance available.
        distance: f64,
        /// Distance the velocity change needs.
        needed: f64,
    },
}

/// Duration of the velocity change `va → vb` (a = 0 at both ends), closed form.
#[must_use]
#[inline]
pub fn change_time(va: f64, vb: f64, acceleration: f64, jerk: f64) -> f64 {
    change_parts((vb - va).abs(), acceleration, jerk).2
}

/// The jerk-phase time, the constant-acceleration time (it may round below 0) and the total
/// time of a velocity change by `dv` ≥ 0 (a = 0 at both ends), from one division or square
/// root: `(A/J, dv/A − A/J, dv/A + A/J)` when `dv·J ≥ A²`, else `(t, 0, 2t)` with
/// `t = sqrt(dv/J)`.
#[inline]
fn change_parts(dv: f64, acceleration: f64, jerk: f64) -> (f64, f64, f64) {
    if dv * jerk >= acceleration * acceleration {
        let (q, r) = (dv / acceleration, acceleration / jerk);
        (r, q - r, q + r)
    } else {
        let t = (dv / jerk).sqrt();
        (t, 0.0, 2.0 * t)
    }
}

/// A move's two velocity changes `v0 → vp → v1` evaluated once: their summed distance
/// (`change_distance(v0, vp) + change_distance(vp, v1)`) and each change's jerk-phase and
/// constant-acceleration times (as [`change_parts`] gives them).
#[derive(Clone, Copy, Debug)]
struct Changes {
    /// Distance of both changes.
    total: f64,
    /// Jerk-phase and constant-acceleration time of `v0 → vp`.
    up: (f64, f64),
    /// The same of `vp → v1`.
    down: (f64, f64),
}

impl Changes {
    /// Both changes of a move from `v0` through the peak `vp` to `v1`.
    #[inline]
    fn of(v0: f64, vp: f64, v1: f64, acceleration: f64, jerk: f64) -> Self {
        let (u1, u2, tu) = change_parts((vp - v0).abs(), acceleration, jerk);
        let (d1, d2, td) = change_parts((v1 - vp).abs(), acceleration, jerk);
        Self {
            total: 0.5 * (v0 + vp) * tu + 0.5 * (vp + v1) * td,
            up: (u1, u2),
            down: (d1, d2),
        }
    }
}

/// Distance covered by the velocity change `va → vb` (a = 0 at both ends).
#[must_use]
#[inline]
pub fn change_distance(va: f64, vb: f64, acceleration: f64, jerk: f64) -> f64 {
    0.5 * (va + vb) * change_time(va, vb, acceleration, jerk)
}

/// The largest velocity ≤ `cap` that can be reached from `v_from` (a = 0) within `distance`,
/// going up; by symmetry also the largest velocity from which `v_from` can be reached. Never
/// less than `min(v_from, cap)`.
///
/// Closed form (the look-ahead's hot path, no iteration): with `Δv = v − v_from`,
/// - below the threshold `Δv < A²/J` (no constant-acceleration phase) the distance is
///   `(2·v_from + Δv)·sqrt(Δv/J)`; with `x = sqrt(Δv/J)` this is the cubic
///   `x³ + p·x = q`, `p = 2·v_from/J`, `q = distance/J`, whose one real root is Cardano's
///   `x = u + w`, `u = cbrt(q/2 + sqrt(q²/4 + p³/27))`, `w = −p/(3u)`, evaluated as
///   `q/(u² − u·w + w²)` to avoid cancellation, then one Newton step;
/// - above it the distance is `(2·v_from + Δv)/2·(Δv/A + A/J)`, a quadratic in `Δv` whose
///   positive root is taken in the cancellation-free form `2|c|/(b + sqrt(b² + 4|c|))`.
#[must_use]
#[inline]
pub fn reachable_velocity(
    v_from: f64,
    distance: f64,
    cap: f64,
    acceleration: f64,
    jerk: f64,
) -> f64 {
    if v_from >= cap {
        return cap;
    }
    if !(distance > 0.0) {
        return v_from;
    }
    if change_distance(v_from, cap, acceleration, jerk) <= distance {
        return cap;
    }
    reachable_velocity_below_cap(v_from, distance, cap, acceleration, jerk)
}

/// [`reachable_velocity`] where the caller knows that `v_from < cap`, `distance > 0` and that
/// the change to `cap` does not fit: the closed form itself.
pub(super) fn reachable_velocity_below_cap(
    v_from: f64,
    distance: f64,
    cap: f64,
    acceleration: f64,
    jerk: f64,
) -> f64 {
    let (a, j) = (acceleration, jerk);
    let threshold = a * a / j;
    // Distance of the change by exactly the threshold: (2·v_from + A²/J)·A/J.
    let d_threshold = (2.0 * v_from + threshold) * a / j;
    let dv = if distance <= d_threshold {
        let p = 2.0 * v_from / j;
        let q = distance / j;
        let mut x = if v_from == 0.0 && q > 1e-150 && q < 1e150 {
            // p = 0: the same values with the zero terms left out (the square root of the
            // rounded square (q/2)² is q/2 exactly, so u is cbrt(q)).
            let u = cbrt(q);
            q / (u * u)
        } else {
            let u = cbrt(0.5 * q + (0.25 * q * q + p * p * p / 27.0).sqrt());
            let w = p / (3.0 * u);
            q / (u * u + p / 3.0 + w * w)
        };
        // One Newton step on x³ + p·x − q polishes the round-off.
        let f = x * (x * x + p) - q;
        let df = 3.0 * x * x + p;
        if df > 0.0 {
            x -= f / df;
        }
        j * x * x
    } else {
        let b = 2.0 * v_from + threshold;
        let c_abs = 2.0 * distance * a - 2.0 * v_from * threshold;
        2.0 * c_abs / (b + (b * b + 4.0 * c_abs).sqrt())
    };
    let mut v = (v_from + dv).min(cap);
    if v.is_finite() {
        // v is a rounded sum: step down to the feasible side (a few ulps at most).
        for _ in 0..16 {
            if v <= v_from || change_distance(v_from, v, acceleration, jerk) <= distance {
                break;
            }
            v = v.next_down();
        }
        v.max(v_from)
    } else {
        reachable_velocity_bisection(v_from, distance, cap, acceleration, jerk)
    }
}

/// [`reachable_velocity`] by bisection on the monotone distance (the reference the closed form
/// is tested against, and its fallback for non-finite intermediate values).
#[must_use]
pub fn reachable_velocity_bisection(
    v_from: f64,
    distance: f64,
    cap: f64,
    acceleration: f64,
    jerk: f64,
) -> f64 {
    if v_from >= cap {
        return cap;
    }
    if change_distance(v_from, cap, acceleration, jerk) <= distance {
        return cap;
    }
    let (mut lo, mut hi) = (v_from, cap);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if change_distance(v_from, mid, acceleration, jerk) <= distance {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    lo
}

#[cfg(test)]
mod reachable_tests {
    use super::*;
    use crate::test_uniform as uniform;

    #[test]
    fn closed_form_matches_bisection() {
        let mut rnd = uniform(3);
        let mut worst = 0.0f64;
        for _ in 0..20_000 {
            let scale = |r: f64, lo: f64, hi: f64| lo * (hi / lo).powf(r);
            let (a, j) = (scale(rnd(), 10.0, 1e5), scale(rnd(), 100.0, 1e7));
            let cap = scale(rnd(), 0.1, 2000.0);
            let v0 = if rnd() < 0.2 { 0.0 } else { rnd() * cap };
            let d = scale(rnd(), 1e-5, 100.0);
            let fast = reachable_velocity(v0, d, cap, a, j);
            let slow = reachable_velocity_bisection(v0, d, cap, a, j);
            let rel = (fast - slow).abs() / slow.max(1e-12);
            worst = worst.max(rel);
            assert!(
                rel < 1e-9,
                "v0 {v0} d {d} cap {cap} a {a} j {j}: {fast} vs {slow}"
            );
            // The result is feasible (the profile accepts 1e-9 relative slack).
            let need = change_distance(v0, fast, a, j);
            assert!(
                need <= d * (1.0 + 1e-10) + 1e-15,
                "v0 {v0} d {d} cap {cap} a {a} j {j}: needs {need}"
            );
        }
        assert!(worst < 1e-9, "{worst}");
    }

    #[test]
    fn peak_velocity_matches_bisection() {
        let mut rnd = uniform(5);
        let mut n = 0;
        for case in 0..20_000 {
            let scale = |r: f64, lo: f64, hi: f64| lo * (hi / lo).powf(r);
            let lim = Limits1 {
                velocity: scale(rnd(), 0.1, 2000.0),
                acceleration: scale(rnd(), 10.0, 1e5),
                jerk: scale(rnd(), 100.0, 1e7),
            };
            let v0 = if rnd() < 0.2 {
                0.0
            } else {
                rnd() * lim.velocity
            };
            let v1 = match case % 3 {
                0 => v0,
                1 => 0.0,
                _ => rnd() * lim.velocity,
            };
            let (a, j) = (lim.acceleration, lim.jerk);
            let total = |vp: f64| change_distance(v0, vp, a, j) + change_distance(vp, v1, a, j);
            let lo = v0.max(v1);
            // A distance between the lower and the upper end.
            let d = total(lo) + rnd() * (total(lim.velocity) - total(lo));
            if !(d > total(lo) && d < total(lim.velocity)) {
                continue;
            }
            let (mut bl, mut bh) = (lo, lim.velocity);
            for _ in 0..200 {
                let mid = 0.5 * (bl + bh);
                if total(mid) <= d {
                    bl = mid;
                } else {
                    bh = mid;
                }
            }
            let vp = peak_velocity_of(v0, v1, d, &lim);
            assert!(
                (vp - bl).abs() <= 1e-9 * bl.max(1e-9),
                "v0 {v0} v1 {v1} d {d} {lim:?}: {vp} vs {bl}"
            );
            n += 1;
        }
        assert!(n > 10_000, "{n}");
    }

    #[test]
    fn fast_cbrt_is_within_an_ulp_of_the_correctly_rounded_one() {
        let mut rnd = uniform(11);
        for _ in 0..100_000 {
            let x = (rnd() - 0.5) * 10f64.powf(600.0 * rnd() - 300.0);
            let (fast, exact) = (cbrt(x), x.cbrt());
            let ulp = exact.abs().next_up() - exact.abs();
            assert!((fast - exact).abs() <= ulp, "{x}: {fast} vs {exact}");
        }
        for x in [
            0.0,
            -0.0,
            1e-310,
            -1e-310,
            8.0,
            -27.0,
            f64::INFINITY,
            f64::MAX,
        ] {
            assert_eq!(cbrt(x).to_bits(), x.cbrt().to_bits(), "{x}");
        }
        assert!(cbrt(f64::NAN).is_nan());
    }

    /// The quartic of the short peak case gives the peak of the distance it was built from
    /// (both changes without a constant-acceleration phase), and the same as the Newton
    /// iteration in `x` to round-off.
    #[test]
    fn short_peak_quartic_matches_its_distance_and_the_iteration() {
        let mut rnd = uniform(7);
        let scale = |r: f64, lo: f64, hi: f64| lo * (hi / lo).powf(r);
        let (mut n, mut closed) = (0, 0);
        for _ in 0..20_000 {
            let lim = Limits1 {
                velocity: scale(rnd(), 0.1, 2000.0),
                acceleration: scale(rnd(), 10.0, 1e5),
                jerk: scale(rnd(), 100.0, 1e7),
            };
            let (a, j) = (lim.acceleration, lim.jerk);
            let top = lim.velocity.min(a * a / j);
            // w < h < vp ≤ w + A²/J, spread over many orders of magnitude of h − w.
            let w = rnd() * (lim.velocity - top);
            let vp = w + top * scale(rnd(), 1e-6, 1.0);
            let h = vp - (vp - w) * rnd();
            if !(w < h && h < vp) {
                continue;
            }
            let (v0, v1) = if rnd() < 0.5 { (w, h) } else { (h, w) };
            let d = change_distance(v0, vp, a, j) + change_distance(vp, v1, a, j);
            n += 1;
            let Some((got, at)) = peak_velocity_short_quartic(v0, v1, d, &lim) else {
                continue;
            };
            closed += 1;
            assert!(at.total <= d, "{v0} {v1} {d} {lim:?}");
            assert!(
                (got - vp).abs() <= 1e-12 * vp,
                "{v0} {v1} {d}: {got} vs {vp}"
            );
            if let Some((newton, _)) = peak_velocity_short_in_x(v0, v1, d, &lim) {
                assert!((got - newton).abs() <= 1e-14 * vp, "{got} vs {newton}");
            }
        }
        assert!(n > 15_000 && closed >= n - n / 100, "{closed} of {n}");
    }
}

/// `peak_velocity` from the inputs alone (the reference the unit tests call).
#[cfg(test)]
fn peak_velocity_of(v0: f64, v1: f64, distance: f64, lim: &Limits1) -> f64 {
    let (a, j) = (lim.acceleration, lim.jerk);
    let total = |vp: f64| change_distance(v0, vp, a, j) + change_distance(vp, v1, a, j);
    peak_velocity(
        v0,
        v1,
        distance,
        lim,
        total(v0.max(v1)),
        total(lim.velocity),
    )
    .0
}

/// The peak velocity `vp ∈ [max(v0, v1), V)` with `change_distance(v0, vp) +
/// change_distance(vp, v1) = distance`, given that the distance is too short to cruise at `V`
/// and long enough for `v0 → v1`. Closed forms where they exist ([`peak_velocity_mixed`] for
/// one change with a constant-acceleration phase), a quartic solved by Newton from a
/// closed-form bound ([`peak_velocity_short`]) for none, else a bracketed Newton iteration in
/// `x = sqrt(vp − max(v0, v1))` (the distance has an infinite slope in `vp` there):
/// - both changes with a constant-acceleration phase (`vp − v0`, `vp − v1` ≥ A²/J): the distance
///   is `vp²/A + vp·A/J + (v0 + v1)·A/(2J) − (v0² + v1²)/(2A)`, a quadratic;
/// - `v0 = v1 = w` and no constant-acceleration phase: `2·(2w + J·x²)·x = distance` with
///   `x = sqrt((vp − w)/J)`, the cubic of [`reachable_velocity`].
///
/// The caller passes the distance of both changes at the peak `max(v0, v1)` (that is
/// `change_distance(v0, v1)`) and at `V`, which it has already computed; the two changes at
/// the peak come back where a closed form evaluated them already.
fn peak_velocity(
    v0: f64,
    v1: f64,
    distance: f64,
    lim: &Limits1,
    total_lo: f64,
    total_vmax: f64,
) -> (f64, Option<Changes>) {
    let (a, j, vmax) = (lim.acceleration, lim.jerk, lim.velocity);
    let lo = v0.max(v1);
    let threshold = a * a / j;
    let total = |vp: f64| change_distance(v0, vp, a, j) + change_distance(vp, v1, a, j);
    if !(distance > total_lo) {
        return (lo, None);
    }
    // Quadratic region: vp²/A + vp·A/J + c0 = distance. Its root is taken only within
    // [lo + A²/J, V], which is empty when lo + A²/J > V.
    if lo + threshold <= vmax {
        let c0 = (v0 + v1) * a / (2.0 * j) - (v0 * v0 + v1 * v1) / (2.0 * a);
        let (qa, qb, qc) = (1.0 / a, a / j, c0 - distance);
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 && qc < 0.0 {
            // Positive root, cancellation-free.
            let r = -2.0 * qc / (qb + disc.sqrt());
            if r >= lo + threshold && r <= vmax {
                return (r, None);
            }
        }
    }
    if v0 == v1 {
        // 2·(2w + J·x²)·x = d  ⇔  x³ + p·x = q with p = 2w/J, q = d/(2J).
        let (p, q) = (2.0 * v0 / j, distance / (2.0 * j));
        let u = cbrt(0.5 * q + (0.25 * q * q + p * p * p / 27.0).sqrt());
        let w = p / (3.0 * u);
        let mut x = q / (u * u + p / 3.0 + w * w);
        let f = x * (x * x + p) - q;
        let df = 3.0 * x * x + p;
        if df > 0.0 {
            x -= f / df;
        }
        let vp = v0 + j * x * x;
        if vp.is_finite() && vp - v0 <= threshold && vp >= lo && vp <= vmax {
            return (vp, None);
        }
    }
    if v0 != v1 {
        // Which change has a constant-acceleration phase: neither when the peak is at most
        // min(v0, v1) + A²/J, else only the one from the lower end (the quadratic above covers
        // both).
        let bound = (v0.min(v1) + threshold).min(vmax);
        let short = if bound == vmax {
            total_vmax
        } else {
            total(bound)
        } >= distance;
        let closed = if short {
            peak_velocity_short(v0, v1, distance, lim)
        } else {
            peak_velocity_mixed(v0, v1, distance, lim)
        };
        if let Some((vp, changes)) = closed {
            return (vp, Some(changes));
        }
    }
    // Bracketed Newton in x = sqrt(vp − lo); g(x) = total(lo + x²) − distance is increasing.
    let g = |x: f64| total(lo + x * x) - distance;
    // dg/dx = 2x·d(total)/d(vp); each change (va → vp, Δ = vp − va) contributes
    // T(Δ)/2 + (va + vp)/2·T'(Δ), with T' = 1/A above the threshold and 1/sqrt(J·Δ) below, so
    // 2x·T' below is 2x/sqrt(J·Δ) (= 2/sqrt(J) for the change from `lo`, where Δ = x²).
    let dg = |x: f64| {
        let vp = lo + x * x;
        let mut d = 0.0;
        for va in [v0, v1] {
            let dv = vp - va;
            let t = change_time(va, vp, a, j);
            let two_x_tprime = if dv >= threshold {
                2.0 * x / a
            } else if va == lo {
                2.0 / j.sqrt()
            } else {
                2.0 * x / (j * dv).sqrt()
            };
            d += x * t + 0.5 * (va + vp) * two_x_tprime;
        }
        d
    };
    let (mut xa, mut xb) = (0.0, (vmax - lo).max(0.0).sqrt());
    let mut x = 0.5 * (xa + xb);
    for _ in 0..100 {
        let gx = g(x);
        if gx <= 0.0 {
            xa = x;
        } else {
            xb = x;
        }
        if xb - xa <= 1e-15 * xb.max(1e-300) || gx == 0.0 {
            break;
        }
        if gx.abs() <= 1e-14 * distance {
            // Converged to round-off: settle on the feasible side of the bracket.
            if gx > 0.0 {
                x = (x - gx / dg(x)).max(xa);
            }
            break;
        }
        let step = gx / dg(x);
        let next = x - step;
        if step.is_finite() && step.abs() <= 1e-13 * x {
            // Converged: settle on the feasible side of the bracket.
            if gx > 0.0 {
                x = xa.max(next.min(x));
            }
            break;
        }
        x = if step.is_finite() && next > xa && next < xb {
            next
        } else {
            0.5 * (xa + xb)
        };
    }
    (lo + x * x, None)
}

/// The mixed case of [`peak_velocity`] in closed form: the change from the lower end velocity
/// `w = min(v0, v1)` has a constant-acceleration phase (`vp − w ≥ A²/J`), the one from the higher
/// `h = max(v0, v1)` has not (`vp − h < A²/J`). With `x = sqrt((vp − h)/J)`, `α = A/J`,
/// `β = 2h/J`, the distance condition times `2A/J²` is the quartic
/// `x⁴ + 2α·x³ + (α² + β)·x² + 2αβ·x + c = 0`, `c = 2A/J²·((h² − w²)/(2A) + (w + h)·A/(2J) − d)`;
/// `x = z − α/2` depresses it to `z⁴ + p·z² + q·z + r = 0` with `p = β − α²/2`, `q = αβ`,
/// `r = α⁴/16 − 3α²β/4 + c`, solved by Ferrari: `m > 0` a root of the resolvent cubic
/// `m³ + p·m² + (p²/4 − r)·m − q²/8 = 0` (Cardano or the trigonometric form) splits it into
/// `z² ∓ √(2m)·z + p/2 + m ± √(2m)·q/(4m) = 0`. The root in the case's range is polished by two
/// Newton steps on the quartic; `None` (the caller iterates) when no root lands in the range or
/// the distance is not met to round-off.
fn peak_velocity_mixed(v0: f64, v1: f64, distance: f64, lim: &Limits1) -> Option<(f64, Changes)> {
    let (a, j, vmax) = (lim.acceleration, lim.jerk, lim.velocity);
    let (w, h) = (v0.min(v1), v0.max(v1));
    let (alpha, beta) = (a / j, 2.0 * h / j);
    let threshold = a * a / j;
    let c = 2.0 * a / (j * j) * ((h * h - w * w) / (2.0 * a) + (w + h) * a / (2.0 * j) - distance);
    let (a2, ab) = (alpha * alpha, alpha * beta);
    let p = beta - 0.5 * a2;
    let q = ab;
    let r = a2 * a2 / 16.0 - 0.75 * a2 * beta + c;
    let m = largest_cubic_root(p, 0.25 * p * p - r, -0.125 * q * q)?;
    if !(m > 0.0) {
        return None;
    }
    let s = (2.0 * m).sqrt();
    let k = s * q / (4.0 * m);
    let quartic = |x: f64| x * (x * (x * (x + 2.0 * alpha) + a2 + beta) + 2.0 * ab) + c;
    let slope = |x: f64| x * (x * (4.0 * x + 6.0 * alpha) + 2.0 * (a2 + beta)) + 2.0 * ab;
    let x_max = alpha; // vp − h < A²/J  ⇔  x < α
    let mut found = None;
    for (sign, k) in [(1.0, k), (-1.0, -k)] {
        // z² − sign·s·z + (p/2 + m + k) = 0.
        let (bq, cq) = (-sign * s, 0.5 * p + m + k);
        let disc = bq * bq - 4.0 * cq;
        if disc < 0.0 {
            continue;
        }
        let root = disc.sqrt();
        for z in [0.5 * (-bq + root), 0.5 * (-bq - root)] {
            let x = z - 0.5 * alpha;
            if x >= -1e-9 * alpha && x <= x_max * (1.0 + 1e-9) {
                found = Some(x.clamp(0.0, x_max));
            }
        }
    }
    let mut x = found?;
    for _ in 0..2 {
        let d = slope(x);
        if d > 0.0 {
            x = (x - quartic(x) / d).clamp(0.0, x_max);
        }
    }
    let vp = h + j * x * x;
    let in_case = vp - w >= threshold && vp - h <= threshold && vp >= h && vp <= vmax;
    if !(vp.is_finite() && in_case) {
        return None;
    }
    // Settle on the feasible side (a few ulps at most), as the iteration does.
    let (vp, at_vp) = settle(vp, distance, v0, v1, a, j);
    let err = (at_vp.total - distance).abs();
    (err <= 1e-12 * distance.max(1e-300) && vp >= h).then_some((vp, at_vp))
}

/// The case of [`peak_velocity`] where neither change has a constant-acceleration phase, with
/// `w = min(v0, v1) < h = max(v0, v1)`, in closed form. With `x = sqrt((vp − h)/J)`,
/// `D = h − w` and `δ = D/J` the condition is
/// `G(x) = (w + h + J·x²)·sqrt(δ + x²) + (2h + J·x²)·x − d = 0`; the substitution
/// `x = sqrt(δ)·sinh t`, `z = e^t` (so `sqrt(δ + x²) = sqrt(δ)·cosh t`) turns it, times
/// `4z/sqrt(δ)`, into the quartic
/// `f(z) = D·z⁴ + 4(w + h)·z² − 4k·z − D = 0`, `k = d·sqrt(J/D)`, and the peak is
/// `vp = h + J·x² = h + D/4·(z − 1/z)²`. `f` is convex (`f'' > 0`) with `f(0) = −D < 0`, so it
/// has one positive root (`z ≥ 1` as `x ≥ 0`), and the root is well conditioned (at the root
/// `z·f'(z) = 3D·z⁴ + 4(w + h)·z² + D` exceeds every term). Dropping `−D` leaves the cubic
/// `D·z³ + 4(w + h)·z = 4k` (Cardano) whose root is a lower bound with `f' > 0`; one Newton step
/// from it lands at or right of the root, from where the iterates decrease monotonically to it
/// (quadratic convergence, no square root per step). Where that fails (non-finite values when
/// `D` is below round-off of `w + h`, a result outside the case) the Newton iteration in `x`
/// ([`peak_velocity_short_in_x`]) decides; `None` when that fails too.
fn peak_velocity_short(v0: f64, v1: f64, distance: f64, lim: &Limits1) -> Option<(f64, Changes)> {
    peak_velocity_short_quartic(v0, v1, distance, lim)
        .or_else(|| peak_velocity_short_in_x(v0, v1, distance, lim))
}

/// The quartic of [`peak_velocity_short`]; `None` where it does not give a root in the case.
fn peak_velocity_short_quartic(
    v0: f64,
    v1: f64,
    distance: f64,
    lim: &Limits1,
) -> Option<(f64, Changes)> {
    let (a, j, vmax) = (lim.acceleration, lim.jerk, lim.velocity);
    let (w, h) = (v0.min(v1), v0.max(v1));
    let (dd, sum) = (h - w, w + h);
    let inv = 1.0 / dd;
    let k = distance * (j * inv).sqrt();
    // Cardano on z³ + p·z = q (cancellation-free form), p = 4(w + h)/D, q = 4k/D.
    let (p, q) = (4.0 * sum * inv, 4.0 * k * inv);
    let u = cbrt(0.5 * q + (0.25 * q * q + p * p * p / 27.0).sqrt());
    let wu = p / (3.0 * u);
    let mut z = q / (u * u + p / 3.0 + wu * wu);
    let mut converged = false;
    for _ in 0..12 {
        let z2 = z * z;
        let f = (dd * z2 + 4.0 * sum) * z2 - 4.0 * k * z - dd;
        let df = (4.0 * dd * z2 + 8.0 * sum) * z - 4.0 * k;
        if !(df > 0.0) {
            break;
        }
        let step = f / df;
        z -= step;
        // The next step would move z by about (z·f''/2f')·step²/z ≤ 2·step²/z (at the root
        // z·f' = 3D·z⁴ + 4(w + h)·z² + D): below 2e-16·z after this one.
        if step.abs() <= 1e-8 * z {
            converged = true;
            break;
        }
    }
    let vp = if converged && z >= 1.0 {
        // z − 1/z = (z − 1)(z + 1)/z: z − 1 is exact near 1.
        let s = (z - 1.0) * (z + 1.0) / z;
        h + 0.25 * dd * s * s
    } else {
        f64::NAN
    };
    let in_case = |vp: f64| vp.is_finite() && vp >= h && vp <= vmax && vp - w <= a * a / j;
    if in_case(vp) {
        // Settle on the feasible side (a few ulps at most).
        let (vp, at_vp) = settle(vp, distance, v0, v1, a, j);
        let err = (at_vp.total - distance).abs();
        if in_case(vp) && err <= 1e-12 * distance.max(1e-300) {
            return Some((vp, at_vp));
        }
    }
    None
}

/// [`peak_velocity_short`] by Newton's method on `G(x)` itself (its fallback). `G` is
/// increasing and convex for `x ≥ 0`, and `sqrt(δ + x²) ≥ x` makes the cubic
/// `2J·x³ + (w + 3h)·x = d` (Cardano) give a start at or right of the root, from which
/// Newton's iterates decrease monotonically to it. `None` when the result leaves the case.
fn peak_velocity_short_in_x(
    v0: f64,
    v1: f64,
    distance: f64,
    lim: &Limits1,
) -> Option<(f64, Changes)> {
    let (a, j, vmax) = (lim.acceleration, lim.jerk, lim.velocity);
    let (w, h) = (v0.min(v1), v0.max(v1));
    let delta = (h - w) / j;
    let (p, q) = ((w + 3.0 * h) / (2.0 * j), distance / (2.0 * j));
    let u = cbrt(0.5 * q + (0.25 * q * q + p * p * p / 27.0).sqrt());
    let wu = p / (3.0 * u);
    let mut x = q / (u * u + p / 3.0 + wu * wu);
    for _ in 0..16 {
        let x2 = x * x;
        let root = (delta + x2).sqrt();
        let g = (w + h + j * x2) * root + (2.0 * h + j * x2) * x - distance;
        if g.abs() <= 1e-15 * distance {
            break;
        }
        let ratio = if root > 0.0 { x / root } else { 1.0 };
        let dg = 2.0 * j * x * root + (w + h + j * x2) * ratio + 2.0 * h + 3.0 * j * x2;
        if !(dg > 0.0) {
            break;
        }
        let step = g / dg;
        x = (x - step).max(0.0);
        if step.abs() <= 1e-14 * x {
            break;
        }
    }
    // Settle on the feasible side (a few ulps at most).
    let (vp, at_vp) = settle(h + j * x * x, distance, v0, v1, a, j);
    let in_case = vp.is_finite() && vp >= h && vp <= vmax && vp - w <= a * a / j;
    let err = (at_vp.total - distance).abs();
    (in_case && err <= 1e-12 * distance.max(1e-300)).then_some((vp, at_vp))
}

/// The cube root of `x` to within an ulp (error < 0.667 ulp), about a fifth of the cost of the
/// correctly rounded `f64::cbrt` (which is what the standard library resolves to here, with
/// out-of-line fused multiply-adds). The algorithm of FreeBSD's `s_cbrt.c`: an estimate from
/// the exponent bits divided by 3, a polynomial for `1/cbrt` to 23 bits, rounded to 23 bits so
/// its square is exact, then one Newton-type step to 53 bits. Zero, subnormal, infinite and NaN
/// input goes to `f64::cbrt`. Hand-written because no maintained crate offers the fast, not
/// correctly rounded variant (the `libm` crate's is the correctly rounded one).
#[must_use]
#[inline]
pub(crate) fn cbrt(x: f64) -> f64 {
    /// `(1023 − 1023/3 − 0.03306235651)·2²⁰`: the exponent estimate's bias.
    const B1: u64 = 715_094_163;
    /// The polynomial for `1/cbrt` (error below 2^−23.5).
    const P: [f64; 5] = [
        f64::from_bits(0x3ffe_03e6_0f61_e692),
        f64::from_bits(0xbffe_28e0_92f0_2420),
        f64::from_bits(0x3ff9_f160_4a49_d6c2),
        f64::from_bits(0xbfe8_44cb_bee7_51d9),
        f64::from_bits(0x3fc2_b000_d4e4_edd7),
    ];
    let bits = x.to_bits();
    let high = (bits >> 32) & 0x7fff_ffff;
    if !(0x0010_0000..0x7ff0_0000).contains(&high) {
        return x.cbrt();
    }
    let t = f64::from_bits((bits & (1 << 63)) | ((high / 3 + B1) << 32));
    // 1/cbrt to 23 bits.
    let r = (t * t) * (t / x);
    let t = t * ((P[0] + r * (P[1] + r * P[2])) + ((r * r) * r) * (P[3] + r * P[4]));
    // Round away from zero to 23 bits: t·t is then exact.
    let t = f64::from_bits((t.to_bits() + 0x8000_0000) & 0xffff_ffff_c000_0000);
    let s = t * t;
    let r = x / s;
    let r = (r - t) / (t + t + r);
    t + t * r
}

/// Step the peak `vp` down by ulps (16 at most) until both changes `v0 → vp → v1` fit in
/// `distance`; the result and its changes.
#[inline]
fn settle(
    mut vp: f64,
    distance: f64,
    v0: f64,
    v1: f64,
    acceleration: f64,
    jerk: f64,
) -> (f64, Changes) {
    let mut at = Changes::of(v0, vp, v1, acceleration, jerk);
    for _ in 0..16 {
        if at.total <= distance {
            break;
        }
        vp = vp.next_down();
        at = Changes::of(v0, vp, v1, acceleration, jerk);
    }
    (vp, at)
}

/// The largest real root of `m³ + b·m² + c·m + d = 0` (Cardano with one real root, else the
/// trigonometric form), polished by one Newton step; `None` when not finite.
fn largest_cubic_root(b: f64, c: f64, d: f64) -> Option<f64> {
    let shift = b / 3.0;
    let pp = c - b * shift;
    let qq = 2.0 * shift * shift * shift - c * shift + d;
    let disc = 0.25 * qq * qq + pp * pp * pp / 27.0;
    let t = if disc >= 0.0 {
        let sq = disc.sqrt();
        // u·v = −pp/3; take u from the larger magnitude side to avoid cancellation.
        let u = cbrt(-0.5 * qq + if qq <= 0.0 { sq } else { -sq });
        if u == 0.0 { 0.0 } else { u - pp / (3.0 * u) }
    } else {
        let rad = (-pp / 3.0).sqrt();
        let arg = (-0.5 * qq / (rad * rad * rad)).clamp(-1.0, 1.0);
        2.0 * rad * (arg.acos() / 3.0).cos()
    };
    let mut m = t - shift;
    let f = m * (m * (m + b) + c) + d;
    let df = m * (3.0 * m + 2.0 * b) + c;
    if df != 0.0 {
        m -= f / df;
    }
    m.is_finite().then_some(m)
}

/// One phase of constant jerk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phase {
    /// Duration (s), ≥ 0.
    pub duration_s: f64,
    /// Jerk during the phase.
    pub jerk: f64,
    /// Position at the phase's start.
    pub s0: f64,
    /// Velocity at the phase's start.
    pub v0: f64,
    /// Acceleration at the phase's start.
    pub a0: f64,
}

impl Phase {
    /// State `(s, v, a)` at time `t` into the phase.
    #[must_use]
    pub fn state(&self, t: f64) -> (f64, f64, f64) {
        let j = self.jerk;
        let s = self.s0 + t * (self.v0 + t * (0.5 * self.a0 + t * j / 6.0));
        let v = self.v0 + t * (self.a0 + 0.5 * t * j);
        let a = self.a0 + t * j;
        (s, v, a)
    }
}

/// What bounds the motion during a phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseKind {
    /// Jerk at its limit.
    Jerk,
    /// Acceleration at its limit (jerk 0).
    Acceleration,
    /// Constant velocity.
    Velocity,
}

/// A time-optimal jerk-limited 1-DoF profile: 7 phases of constant jerk (some of zero length).
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// The phases in order: ramp-up (3), cruise (1), ramp-down (3).
    pub phases: [Phase; 7],
    /// The distance.
    pub distance: f64,
    /// Peak velocity.
    pub peak_velocity: f64,
}

/// Jerk-phase and constant-acceleration time of a velocity change by `dv` (the latter may
/// round below 0).
fn change_times(dv: f64, lim: &Limits1) -> (f64, f64) {
    let (a, j) = (lim.acceleration, lim.jerk);
    if dv.abs() * j >= a * a {
        (a / j, dv.abs() / a - a / j)
    } else {
        ((dv.abs() / j).sqrt(), 0.0)
    }
}

/// Phases of one velocity change starting at `(s0, va, a=0)`.
fn change_phases(s0: f64, va: f64, vb: f64, lim: &Limits1) -> [Phase; 3] {
    let dv = vb - va;
    let sign = if dv >= 0.0 { 1.0 } else { -1.0 };
    let j = lim.jerk;
    let (t1, t2) = change_times(dv, lim);
    let mut p1 = Phase {
        duration_s: t1,
        jerk: sign * j,
        s0,
        v0: va,
        a0: 0.0,
    };
    let (s, v, acc) = p1.state(t1);
    let p2 = Phase {
        duration_s: t2.max(0.0),
        jerk: 0.0,
        s0: s,
        v0: v,
        a0: acc,
    };
    let (s, v, acc) = p2.state(p2.duration_s);
    let p3 = Phase {
        duration_s: t1,
        jerk: -sign * j,
        s0: s,
        v0: v,
        a0: acc,
    };
    p1.duration_s = t1;
    [p1, p2, p3]
}

impl Profile {
    /// The time-optimal profile from `v0` to `v1` (a = 0 at both ends) over `distance` ≥ 0.
    ///
    /// # Errors
    /// [`ProfileError`] for invalid input, a boundary velocity above the limit, or a velocity
    /// change that needs more distance than given (relative slack 1e-9 is accepted).
    pub fn calculate(distance: f64, v0: f64, v1: f64, lim: &Limits1) -> Result<Self, ProfileError> {
        let (v0, v1, vp, _) = Self::peak_of(distance, v0, v1, lim)?;
        Ok(Self::with_peak_clamped(distance, v0, v1, vp, lim))
    }

    /// The peak velocity and the duration of [`Profile::calculate`]'s profile (the same
    /// values, bit for bit), without building its phases.
    ///
    /// # Errors
    /// As [`Profile::calculate`].
    pub fn peak_and_duration(
        distance: f64,
        v0: f64,
        v1: f64,
        lim: &Limits1,
    ) -> Result<(f64, f64), ProfileError> {
        let (_, _, vp, changes) = Self::peak_of(distance, v0, v1, lim)?;
        let cruise = if vp > 0.0 {
            ((distance - changes.total) / vp).max(0.0)
        } else {
            0.0
        };
        let ((u1, u2), (d1, d2)) = (changes.up, changes.down);
        let (u2, d2) = (u2.max(0.0), d2.max(0.0));
        // The phase durations summed in order, as `duration_s` does.
        let duration = [u1, u2, u1, cruise, d1, d2, d1].into_iter().sum::<f64>();
        Ok((vp, duration))
    }

    /// The boundary velocities (clamped to the limit), the peak velocity of the profile and
    /// its two velocity changes.
    fn peak_of(
        distance: f64,
        v0: f64,
        v1: f64,
        lim: &Limits1,
    ) -> Result<(f64, f64, f64, Changes), ProfileError> {
        let finite_nonneg = |x: f64| x.is_finite() && x >= 0.0;
        if !lim.is_valid() || !finite_nonneg(distance) || !finite_nonneg(v0) || !finite_nonneg(v1) {
            return Err(ProfileError::InvalidInput);
        }
        let tol = 1e-9 * lim.velocity;
        for v in [v0, v1] {
            if v > lim.velocity + tol {
                return Err(ProfileError::BoundaryAboveLimit {
                    velocity: v,
                    limit: lim.velocity,
                });
            }
        }
        let (v0, v1) = (v0.min(lim.velocity), v1.min(lim.velocity));
        let (a, j) = (lim.acceleration, lim.jerk);
        let needed = change_distance(v0, v1, a, j);
        if needed > distance * (1.0 + 1e-9) + 1e-12 {
            return Err(ProfileError::Unreachable { distance, needed });
        }
        let at_vmax = Changes::of(v0, lim.velocity, v1, a, j);
        if at_vmax.total <= distance {
            return Ok((v0, v1, lim.velocity, at_vmax));
        }
        // `needed` is also the distance of both changes at the peak max(v0, v1) (one of them
        // is empty and adds +0).
        let (vp, changes) = peak_velocity(v0, v1, distance, lim, needed, at_vmax.total);
        let changes = changes.unwrap_or_else(|| Changes::of(v0, vp, v1, a, j));
        Ok((v0, v1, vp, changes))
    }

    /// The profile [`Profile::calculate`] gives for the same input, rebuilt from its peak
    /// velocity `vp` (bit for bit the same phases, without searching for the peak).
    #[must_use]
    pub fn with_peak(distance: f64, v0: f64, v1: f64, vp: f64, lim: &Limits1) -> Self {
        let (v0, v1) = (v0.min(lim.velocity), v1.min(lim.velocity));
        Self::with_peak_clamped(distance, v0, v1, vp, lim)
    }

    /// The phases from the boundary velocities (at most the limit) and the peak.
    fn with_peak_clamped(distance: f64, v0: f64, v1: f64, vp: f64, lim: &Limits1) -> Self {
        let (a, j) = (lim.acceleration, lim.jerk);
        let total = |vp: f64| change_distance(v0, vp, a, j) + change_distance(vp, v1, a, j);
        let cruise = if vp > 0.0 {
            ((distance - total(vp)) / vp).max(0.0)
        } else {
            0.0
        };
        let up = change_phases(0.0, v0, vp, lim);
        let (s, _, _) = up[2].state(up[2].duration_s);
        let mid = Phase {
            duration_s: cruise,
            jerk: 0.0,
            s0: s,
            v0: vp,
            a0: 0.0,
        };
        let down = change_phases(s + vp * cruise, vp, v1, lim);
        Self {
            phases: [up[0], up[1], up[2], mid, down[0], down[1], down[2]],
            distance,
            peak_velocity: vp,
        }
    }

    /// Rest-to-rest profile over `distance`.
    ///
    /// # Errors
    /// [`ProfileError::InvalidInput`] for a non-finite or negative distance or invalid limits.
    pub fn rest_to_rest(distance: f64, lim: &Limits1) -> Result<Self, ProfileError> {
        Self::calculate(distance, 0.0, 0.0, lim)
    }

    /// Total duration (s).
    #[must_use]
    pub fn duration_s(&self) -> f64 {
        self.phases.iter().map(|p| p.duration_s).sum()
    }

    /// State `(s, v, a, j)` at time `t` (clamped to the profile; the end position is the
    /// exact distance).
    #[must_use]
    pub fn at_time(&self, t: f64) -> (f64, f64, f64, f64) {
        self.at_time_with_kind(t).0
    }

    /// State `(s, v, a, j)` at `t` and the kind of the active phase.
    #[must_use]
    pub fn at_time_with_kind(&self, t: f64) -> ((f64, f64, f64, f64), PhaseKind) {
        let mut rest = t.max(0.0);
        if rest >= self.duration_s() {
            rest = f64::INFINITY;
        }
        for (i, p) in self.phases.iter().enumerate() {
            if rest <= p.duration_s && p.duration_s > 0.0 {
                let (s, v, a) = p.state(rest);
                let kind = match (i, p.jerk == 0.0) {
                    (3, _) => PhaseKind::Velocity,
                    (_, true) => PhaseKind::Acceleration,
                    (_, false) => PhaseKind::Jerk,
                };
                return ((s.clamp(0.0, self.distance), v.max(0.0), a, p.jerk), kind);
            }
            rest -= p.duration_s;
        }
        let v_end = self.phases[6].state(self.phases[6].duration_s).1;
        (
            (self.distance, v_end.max(0.0), 0.0, 0.0),
            PhaseKind::Velocity,
        )
    }
}
