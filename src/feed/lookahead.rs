//! Step 2b: junction speeds and the look-ahead over the whole program.
//!
//! Every junction gets a cap: 0 where the path is not smooth (exact stop), the segments' own
//! velocity where it is (collinear lines, the same circle continued), or with
//! [`CornerPolicy::JunctionDeviation`] the junction-deviation speed. Then a backward pass caps
//! each junction by what can still decelerate to the next one within the block, and a forward
//! pass by what can be reached from the previous one; both use the jerk-limited
//! [`reachable_velocity`] with a = 0 at junctions, so every block's profile exists afterwards.

use super::path::{JointVector, SLOTS, Segment};
use super::profile::{change_distance, reachable_velocity, reachable_velocity_below_cap};
use super::{AxisLimit, CornerPolicy};

/// Cosine of the angle between two tangents, and whether both segments continue each other
/// smoothly (same direction and same curvature: collinear lines or the same circle).
fn junction(a: &Segment, b: &Segment) -> (f64, bool) {
    let da = a.derivatives(a.length);
    let db = b.derivatives(0.0);
    let (ta, tb): (JointVector, JointVector) = (da[1], db[1]);
    let dot: f64 = (0..SLOTS).map(|k| ta[k] * tb[k]).sum();
    let na = ta.iter().map(|x| x * x).sum::<f64>().sqrt();
    let nb = tb.iter().map(|x| x * x).sum::<f64>().sqrt();
    let cos = (dot / (na * nb).max(1e-300)).clamp(-1.0, 1.0);
    let same_curvature = (0..SLOTS)
        .all(|k| (da[2][k] - db[2][k]).abs() <= 1e-12 && (da[3][k] - db[3][k]).abs() <= 1e-12);
    let same_direction = (0..SLOTS).all(|k| (ta[k] - tb[k]).abs() <= 1e-12);
    (cos, same_direction && same_curvature)
}

/// Junction speeds (one more than segments: start and end are 0) after both passes.
#[must_use]
pub fn junction_speeds(
    segments: &[Segment],
    axes: &[Option<AxisLimit>; SLOTS],
    corner: CornerPolicy,
) -> Vec<f64> {
    let mut v = backward_speeds(segments, axes, corner);
    for (k, s) in segments.iter().enumerate() {
        forward_step(&mut v, k, s);
    }
    v
}

/// The junction caps after the backward pass (the caps and the pass in one sweep from the
/// end); [`forward_step`] over every segment in order completes [`junction_speeds`].
#[must_use]
pub(super) fn backward_speeds(
    segments: &[Segment],
    axes: &[Option<AxisLimit>; SLOTS],
    corner: CornerPolicy,
) -> Vec<f64> {
    let n = segments.len();
    let mut v = vec![0.0; n + 1];
    let a_min = axes
        .iter()
        .flatten()
        .map(|l| l.acceleration)
        .fold(f64::INFINITY, f64::min);
    for k in (0..n).rev() {
        if k > 0 {
            v[k] = junction_cap(&segments[k - 1], &segments[k], corner, a_min, axes);
        }
        v[k] = v[k].min(cap_from(v[k + 1], v[k], &segments[k]));
    }
    v
}

/// The forward pass at segment `k` (`s`): caps the speed at its end by what its start speed
/// (already final) can reach. After this step `v[k]` and `v[k + 1]` are final.
#[inline]
pub(super) fn forward_step(v: &mut [f64], k: usize, s: &Segment) {
    v[k + 1] = v[k + 1].min(cap_from(v[k], v[k + 1], s));
}

/// The cap at the junction from `a` to `b` before the passes: their lower velocity where the
/// path is smooth, else 0 or the junction-deviation speed.
fn junction_cap(
    a: &Segment,
    b: &Segment,
    corner: CornerPolicy,
    a_min: f64,
    axes: &[Option<AxisLimit>; SLOTS],
) -> f64 {
    let both = a.limits.velocity.min(b.limits.velocity);
    // Blends meet their neighbours tangent and curvature continuous by construction.
    let (cos, smooth) = if a.blend().is_some() || b.blend().is_some() {
        (1.0, true)
    } else {
        junction(a, b)
    };
    if smooth {
        return both;
    }
    // Next to a run merged into one line, half the tolerance is the merge's
    // (`super::merge`), the other half the corner's.
    let merged = a.last_block != a.block || b.last_block != b.block;
    let half_if_merged = |t: f64| if merged { 0.5 * t } else { t };
    match corner {
        CornerPolicy::ExactStop => 0.0,
        CornerPolicy::Blend { tolerance_mm } => {
            near_tangent_cap(a, b, half_if_merged(tolerance_mm), axes, true).unwrap_or(0.0)
        }
        CornerPolicy::JunctionDeviation { tolerance_mm } => {
            let tolerance_mm = half_if_merged(tolerance_mm);
            // grbl's rule: the circle tangent to both moves whose distance from the corner is
            // δ has radius δ·h/(1 − h), h = sin of half the interior angle = cos(θ/2) for a
            // turn θ (straight through: h = 1, no limit; a reversal: h = 0, a stop).
            let turn = cos.acos();
            let h = (0.5 * turn).cos();
            let jd = if h <= 1e-9 {
                0.0
            } else if h >= 1.0 - 1e-15 {
                f64::INFINITY
            } else {
                (a_min * tolerance_mm * h / (1.0 - h)).sqrt()
            };
            // That circle must also fit the moves (set back at most half the shorter one from
            // the corner); on dense programs the circle that fits is the curve they sample.
            let setback = 0.5 * a.length.min(b.length);
            let fits = (a_min * setback / (0.5 * turn).tan().max(1e-300)).sqrt();
            let near = near_tangent_cap(a, b, tolerance_mm, axes, false).unwrap_or(0.0);
            jd.min(fits).max(near).min(both)
        }
    }
}

/// Largest turn of the tool path (rad, X Y Z) at a junction that is passed as near tangent
/// ([`near_tangent_cap`]): about 5.7°.
pub const NEAR_TANGENT_MAX_TURN_RAD: f64 = 0.1;

/// Share of every axis's acceleration and jerk limits given to the curvature of a
/// near-tangent junction's implied arc (the rest is left to the tangential change next to it).
pub const NEAR_TANGENT_SHARE: f64 = 0.5;

/// The speed at which a near-tangent junction between `a` and `b` is passed, if it is one
/// (`None` otherwise).
///
/// A posted 5-axis program samples a smooth tool path with short moves of X Y Z and the rotary
/// axes together, whose junctions turn a little (the clothoid blends are built in X Y Z
/// alone): the junction is passed on the arc tangent to both moves that is set back half the
/// shorter move from it (LinuxCNC's tangent blending passes such junctions at its kink speed
/// likewise). The axes' velocities then change at the junction by at most the turn times the
/// speed: the arc's acceleration and jerk bound what the servo sees while it follows. It is near tangent when its X Y Z
/// turn `θ` is at most [`NEAR_TANGENT_MAX_TURN_RAD`], the arc's distance from the corner
/// `d·tan(θ/2)·tan(θ/4)` (set-back `d`) is within `tolerance`, every rotary axis's kink
/// `Δq'` smoothed over the same span stays within it (`Δq'·d/4` times
/// [`super::merge::ROTARY_LEVER_MM`]),
/// and it is not (`clothoid`, for [`CornerPolicy::Blend`]) a corner between two straight X Y Z
/// moves, which gets a clothoid blend or a stop instead.
/// On that arc of length `2d` every axis has `|q''| ≤ |Δq'|/(2d)` and
/// `|q'''| ≤ κ·|q''|` (κ the arc's curvature): the speed keeps the centripetal acceleration and
/// jerk of every axis within [`NEAR_TANGENT_SHARE`] of its limits. For a polygon inscribed in a
/// circle of radius `R`, the arc is the circle itself (`d/tan(θ/2) = R`).
#[must_use]
pub fn near_tangent_cap(
    a: &Segment,
    b: &Segment,
    tolerance: f64,
    axes: &[Option<AxisLimit>; SLOTS],
    clothoid: bool,
) -> Option<f64> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return None;
    }
    let (ta, tb) = (a.tangent(true), b.tangent(false));
    let ua = glam::DVec3::new(ta[0], ta[1], ta[2]);
    let ub = glam::DVec3::new(tb[0], tb[1], tb[2]);
    let (na, nb) = (ua.length(), ub.length());
    if !(na > 0.5 && nb > 0.5) {
        // A rotary-only move (its path length is in rad): no tool-path tangent to keep.
        return None;
    }
    let (ua, ub) = (ua / na, ub / nb);
    let turn = ua.dot(ub).clamp(-1.0, 1.0).acos();
    if !(turn <= NEAR_TANGENT_MAX_TURN_RAD) {
        return None;
    }
    let setback = 0.5 * a.length.min(b.length);
    if !(setback > 0.0) {
        return None;
    }
    let deviation = setback * (0.5 * turn).tan() * (0.25 * turn).tan();
    if !(deviation <= tolerance) {
        return None;
    }
    for k in 3..SLOTS {
        if (tb[k] - ta[k]).abs() * setback * 0.25 * super::merge::ROTARY_LEVER_MM > tolerance {
            return None;
        }
    }
    if clothoid && a.straight_xyz_direction().is_some() && b.straight_xyz_direction().is_some() {
        // Corners between straight X Y Z lines are blended (or stopped at) by `blend`.
        return None;
    }
    let span = 2.0 * setback;
    let mut d2 = [0.0; SLOTS];
    for k in 0..SLOTS {
        d2[k] = (tb[k] - ta[k]).abs() / span;
    }
    let kappa = (d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2]).sqrt();
    let mut v = a.limits.velocity.min(b.limits.velocity);
    for (k, lim) in axes.iter().enumerate() {
        let Some(l) = lim else { continue };
        if d2[k] > 0.0 {
            v = v.min((NEAR_TANGENT_SHARE * l.acceleration / d2[k]).sqrt());
            let d3 = kappa * d2[k];
            if d3 > 0.0 {
                v = v.min(super::profile::cbrt(NEAR_TANGENT_SHARE * l.jerk / d3));
            }
        }
    }
    (v.is_finite() && v > 0.0).then_some(v)
}

/// The highest speed at the other end of `s` that `from` can reach or be reached from
/// ([`reachable_velocity`]), or `wanted` itself where that is plainly no higher: no faster than
/// `from` (the change is then no climb at all), or a change to `wanted` that fits the segment.
#[inline]
fn cap_from(from: f64, wanted: f64, s: &Segment) -> f64 {
    let l = &s.limits;
    let target = wanted.min(l.velocity);
    if wanted <= from || change_distance(from, target, l.acceleration, l.jerk) <= s.length {
        return wanted;
    }
    if target == l.velocity && from < target && s.length > 0.0 {
        // The change to the cap was just found not to fit.
        return reachable_velocity_below_cap(from, s.length, l.velocity, l.acceleration, l.jerk);
    }
    reachable_velocity(from, s.length, l.velocity, l.acceleration, l.jerk)
}
