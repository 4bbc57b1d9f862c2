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
//! `vp` is the largest peak ≤ `vmax` whose two changes fit in `s`, found by bisection on a
//! monotone function (the only numeric step; it never yields NaN).

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
pub fn change_time(va: f64, vb: f64, acceleration: f64, jerk: f64) -> f64 {
    let dv = (vb - va).abs();
    if dv * jerk >= acceleration * acceleration {
        dv / acceleration + acceleration / jerk
    } else {
        2.0 * (dv / jerk).sqrt()
    }
}

/// Distance covered by the velocity change `va → vb` (a = 0 at both ends).
#[must_use]
pub fn change_distance(va: f64, vb: f64, acceleration: f64, jerk: f64) -> f64 {
    0.5 * (va + vb) * change_time(va, vb, acceleration, jerk)
}

/// The largest velocity ≤ `cap` that can be reached from `v_from` (a = 0) within `distance`,
/// going up; by symmetry also the largest velocity from which `v_from` can be reached. Never
/// less than `min(v_from, cap)`.
#[must_use]
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
    if change_distance(v_from, cap, acceleration, jerk) <= distance {
        return cap;
    }
    let (mut lo, mut hi) = (v_from, cap);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if change_distance(v_from, mid, acceleration, jerk) <= distance {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-13 * hi {
            break;
        }
    }
    lo
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

/// Phases of one velocity change starting at `(s0, va, a=0)`.
fn change_phases(s0: f64, va: f64, vb: f64, lim: &Limits1) -> [Phase; 3] {
    let dv = vb - va;
    let sign = if dv >= 0.0 { 1.0 } else { -1.0 };
    let (a, j) = (lim.acceleration, lim.jerk);
    let (t1, t2) = if dv.abs() * j >= a * a {
        (a / j, dv.abs() / a - a / j)
    } else {
        ((dv.abs() / j).sqrt(), 0.0)
    };
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
        let total = |vp: f64| change_distance(v0, vp, a, j) + change_distance(vp, v1, a, j);
        let vp = if total(lim.velocity) <= distance {
            lim.velocity
        } else {
            let (mut lo, mut hi) = (v0.max(v1), lim.velocity);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if total(mid) <= distance {
                    lo = mid;
                } else {
                    hi = mid;
                }
                if hi - lo <= 1e-14 * hi.max(1e-300) {
                    break;
                }
            }
            lo
        };
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
        Ok(Self {
            phases: [up[0], up[1], up[2], mid, down[0], down[1], down[2]],
            distance,
            peak_velocity: vp,
        })
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
