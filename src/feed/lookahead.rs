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
            v[k] = junction_cap(&segments[k - 1], &segments[k], corner, a_min);
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
fn junction_cap(a: &Segment, b: &Segment, corner: CornerPolicy, a_min: f64) -> f64 {
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
    match corner {
        CornerPolicy::ExactStop | CornerPolicy::Blend { .. } => 0.0,
        CornerPolicy::JunctionDeviation { tolerance_mm } => {
            let half = (0.5 * cos.acos()).sin();
            if half >= 1.0 - 1e-9 {
                0.0
            } else {
                (a_min * tolerance_mm * half / (1.0 - half))
                    .sqrt()
                    .min(both)
            }
        }
    }
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
