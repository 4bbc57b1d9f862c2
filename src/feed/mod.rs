//! Jerk-limited feed planning with look-ahead (layer L4), in the shape of ruckig:
//! input ([`PlanInput`]: motion blocks, per-axis limits, options) → [`plan`] → result
//! ([`TimedPath`]: duration, state at any time, samples, peaks; or a [`FeedError`]).
//!
//! ```text
//! MotionBlocks ─path─▶ Segments (length, q', q'', q''' bounds, tangential v/a/j)
//!              ─merge─▶ runs of short lines as one line within half the tolerance
//!              ─blend─▶ corner blends between straight segments (CornerPolicy::Blend)
//!              ─lookahead─▶ junction speeds (backward, forward pass)
//!              ─profile─▶ one 7-phase S-curve per block ─timed_path─▶ samples, peaks
//! ```
//!
//! Per-axis limits are enforced by projection (see [`path`]): inside a block the tangential
//! limits bound every axis's velocity, acceleration and jerk. Junctions have a = 0; with
//! [`CornerPolicy::ExactStop`] the motion stops wherever the path is not smooth (the only way to
//! keep the axis jerk finite without blending corners); with
//! [`CornerPolicy::JunctionDeviation`] it passes corners at the junction-deviation speed, which
//! steps axis velocities at corners (as grbl and LinuxCNC do); with [`CornerPolicy::Blend`] the
//! corners between straight moves are replaced by curvature-continuous clothoid blends within
//! the tolerance ([`blend`]), so the path stays smooth and every axis limit holds.

pub mod blend;
pub mod estimate;
pub mod lookahead;
pub mod merge;
pub mod path;
pub mod profile;
pub mod timed_path;
pub mod travel;

pub use estimate::naive_time_s;
pub use profile::{Limits1, PhaseKind, Profile, ProfileError, reachable_velocity};
pub use timed_path::{AxisPeak, Sample, TimedPath};
pub use travel::{TravelViolation, travel_violations};

use crate::gcode::MotionBlock;
use crate::machine::Machine;

/// Velocity, acceleration and jerk limit of one axis (mm/s, mm/s², mm/s³; rad for rotary).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AxisLimit {
    /// Velocity limit.
    #[serde(rename = "v")]
    pub velocity: f64,
    /// Acceleration limit.
    #[serde(rename = "a")]
    pub acceleration: f64,
    /// Jerk limit.
    #[serde(rename = "j")]
    pub jerk: f64,
}

/// How corners (non-smooth junctions) are passed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CornerPolicy {
    /// Stop at every junction where the path is not smooth: all axis limits hold everywhere.
    ExactStop,
    /// Junction-deviation speed `sqrt(a·δ·sin(θ/2)/(1−sin(θ/2)))` with tolerance δ (mm):
    /// faster, but axis velocities step at corners.
    JunctionDeviation {
        /// Path-deviation tolerance δ (mm), default 0.01.
        tolerance_mm: f64,
    },
    /// Replace every sharp junction between two straight X/Y/Z moves by a clothoid-pair blend
    /// ([`blend::ClothoidBlend`]) within `tolerance_mm` of the corner (taking at most half of
    /// either move), planned under the axis limits along its curvature: all axis limits hold
    /// everywhere. Runs of short lines are first merged into one line within half the
    /// tolerance ([`merge`]); near-tangent junctions that move rotary axes or join arcs pass at
    /// the speed of the arc they imply ([`lookahead::near_tangent_cap`]); other non-smooth
    /// junctions (reversals, sharp corners at arcs) stop exactly.
    Blend {
        /// Path-deviation tolerance δ (mm): the largest distance of the blend from the corner.
        tolerance_mm: f64,
    },
}

/// The corner tolerance `talas feed` and the control's AUTO and MDI plan with by default (mm).
pub const DEFAULT_TOLERANCE_MM: f64 = 0.05;

/// The corner policy `talas feed` and the control's AUTO and MDI plan with by default:
/// clothoid blends (and near-tangent junctions passed on the curve they sample) within
/// [`DEFAULT_TOLERANCE_MM`].
pub const DEFAULT_CORNERS: CornerPolicy = CornerPolicy::Blend {
    tolerance_mm: DEFAULT_TOLERANCE_MM,
};

/// Planner options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanOptions {
    /// Corner handling (default exact stop).
    pub corner: CornerPolicy,
    /// Optional tangential (path) limits on top of the per-axis ones (the thesis's `V, A, J`).
    pub path_limits: Option<Limits1>,
    /// Sample period for [`TimedPath::samples`] and peaks (s), default 1 ms.
    pub sample_period_s: f64,
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            corner: CornerPolicy::ExactStop,
            path_limits: None,
            sample_period_s: 1e-3,
        }
    }
}

/// Why planning failed, grouped by cause.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FeedError {
    /// A limit is not finite and within [`MIN_LIMIT`, `MAX_LIMIT`].
    #[error("axis {axis}: velocity, acceleration and jerk limits must lie between 1e-6 and 1e12")]
    InvalidLimit {
        /// The axis letter.
        axis: char,
    },
    /// A block moves an axis the machine does not have.
    #[error("line {line}: moves an axis the machine does not have, or cannot be planned")]
    UnplannableBlock {
        /// Source line of the block.
        line: usize,
    },
    /// The corner tolerance is not finite and positive.
    #[error("corner tolerance must be finite and positive")]
    InvalidTolerance,
    /// The sample period is not finite and positive.
    #[error("sample period must be finite and positive")]
    InvalidSamplePeriod,
    /// A profile could not be built (internal: the look-ahead guarantees feasibility).
    #[error("line {line}: {source}")]
    Profile {
        /// Source line of the block.
        line: usize,
        /// The 1-DoF error.
        source: ProfileError,
    },
}

/// The planner's input.
#[derive(Clone, Debug)]
pub struct PlanInput {
    /// The interpreted program's motion blocks, shared with the [`TimedPath`] planned from them
    /// (a plan keeps them without copying: `program.blocks.as_slice().into()` copies once
    /// when the input is built, a `Vec` converts with `.into()`).
    pub blocks: std::sync::Arc<[MotionBlock]>,
    /// Axes with their limits, in the machine's order.
    pub axes: Vec<(char, AxisLimit)>,
    /// Options.
    pub options: PlanOptions,
}

/// The per-axis limits of a machine, in its axis order.
#[must_use]
pub fn machine_limits(machine: &Machine) -> Vec<(char, AxisLimit)> {
    machine
        .axes
        .iter()
        .map(|a| {
            (
                a.name,
                AxisLimit {
                    velocity: a.velocity,
                    acceleration: a.acceleration,
                    jerk: a.jerk,
                },
            )
        })
        .collect()
}

/// Smallest axis limit (velocity, acceleration or jerk) the planner accepts, in mm or rad per
/// s, s², s³.
pub const MIN_LIMIT: f64 = 1e-6;
/// Largest axis limit the planner accepts.
pub const MAX_LIMIT: f64 = 1e12;

/// Plan the whole program.
///
/// # Errors
/// [`FeedError`] for invalid limits, a block on an axis the machine lacks, or a bad sample period.
pub fn plan(input: &PlanInput) -> Result<TimedPath, FeedError> {
    let opts = &input.options;
    if !(opts.sample_period_s.is_finite() && opts.sample_period_s > 0.0) {
        return Err(FeedError::InvalidSamplePeriod);
    }
    let mut slots: path::AxisLimits = [None; path::SLOTS];
    for (name, lim) in &input.axes {
        // Limits outside this range are typing errors (1e-6 mm/s is 3.6 mm an hour; 1e12 is far
        // beyond any machine) and would make the planned time or its sampling unbounded.
        let ok = [lim.velocity, lim.acceleration, lim.jerk]
            .iter()
            .all(|x| (MIN_LIMIT..=MAX_LIMIT).contains(x));
        if !ok {
            return Err(FeedError::InvalidLimit { axis: *name });
        }
        if let Some(k) = path::slot_of(*name) {
            slots[k] = Some(*lim);
        }
    }
    // The segments of the blocks in order (blocks of no length left out), until one cannot be
    // planned: its line is kept in `unplannable`.
    let mut unplannable = None;
    let mut blocks = input.blocks.iter().enumerate();
    let segment_stream = std::iter::from_fn(|| {
        for (i, b) in blocks.by_ref() {
            match path::Segment::new(i, b, &slots, opts.path_limits) {
                Some(s) => return Some(s),
                None if joint_zero_length(b) => {}
                None => {
                    unplannable = Some(b.source_line);
                    return None;
                }
            }
        }
        None
    });
    let segments = match opts.corner {
        CornerPolicy::Blend { tolerance_mm } if tolerance_mm.is_finite() && tolerance_mm > 0.0 => {
            // Runs of short lines merged within half the tolerance, then the corners blended.
            let merged = merge::merge_runs(
                segment_stream,
                &input.blocks,
                &slots,
                opts.path_limits,
                0.5 * tolerance_mm,
            );
            blend_corners(
                merged.into_iter(),
                input.blocks.len(),
                &slots,
                opts.path_limits,
                tolerance_mm,
            )
        }
        CornerPolicy::JunctionDeviation { tolerance_mm }
            if tolerance_mm.is_finite() && tolerance_mm > 0.0 =>
        {
            merge::merge_runs(
                segment_stream,
                &input.blocks,
                &slots,
                opts.path_limits,
                0.5 * tolerance_mm,
            )
        }
        _ => {
            let mut v = Vec::with_capacity(input.blocks.len());
            v.extend(segment_stream);
            v
        }
    };
    if let Some(line) = unplannable {
        return Err(FeedError::UnplannableBlock { line });
    }
    if let CornerPolicy::Blend { tolerance_mm } = opts.corner
        && !(tolerance_mm.is_finite() && tolerance_mm > 0.0)
    {
        return Err(FeedError::InvalidTolerance);
    }
    let mut speeds = lookahead::backward_speeds(&segments, &slots, opts.corner);
    // Each profile is kept as its peak velocity (with the junction speeds and the segment it
    // is rebuilt on demand), and its duration as the next start time. The look-ahead's
    // forward pass runs in the same loop: its step at a segment makes both of the segment's
    // junction speeds final.
    let mut peaks = Vec::with_capacity(segments.len());
    let mut start_times = Vec::with_capacity(segments.len() + 1);
    let mut path_starts = Vec::with_capacity(segments.len());
    let (mut t, mut along) = (0.0, 0.0);
    start_times.push(t);
    for (k, s) in segments.iter().enumerate() {
        path_starts.push(along);
        along += s.length;
        lookahead::forward_step(&mut speeds, k, s);
        let (peak, duration) =
            Profile::peak_and_duration(s.length, speeds[k], speeds[k + 1], &s.limits).map_err(
                |e| FeedError::Profile {
                    line: input.blocks.get(s.block).map_or(0, |b| b.source_line),
                    source: e,
                },
            )?;
        peaks.push(peak);
        t += duration;
        start_times.push(t);
    }
    Ok(TimedPath::new(
        std::sync::Arc::clone(&input.blocks),
        segments,
        timed_path::Speeds {
            junctions: speeds,
            peaks,
            start_times,
            path_starts,
        },
        &input.axes,
        opts.sample_period_s,
    ))
}

/// Replace the sharp junctions between straight X/Y/Z segments by clothoid blends (each taking at
/// most half of either neighbour); other junctions are left as they are. One pass: the blend at
/// each junction is decided when its second segment is reached, and nothing is kept per blend
/// but the output.
fn blend_corners(
    segments: impl Iterator<Item = path::Segment>,
    count_hint: usize,
    axes: &path::AxisLimits,
    path_limits: Option<Limits1>,
    tolerance: f64,
) -> Vec<path::Segment> {
    // At most one blend per junction; pages never written are never touched.
    let mut out = Vec::with_capacity(2 * count_hint);
    // The speed each segment reaches at its ends from a stop at the other (computed once).
    let reach = |s: &path::Segment| {
        let l = s.limits;
        reachable_velocity(0.0, s.length, l.velocity, l.acceleration, l.jerk)
    };
    let mut reach_here: Option<f64> = None;
    // The cost of an exact stop on the current segment's side of its corner ahead: the same
    // as on the side of the corner behind it, where that was weighed (same segment, same reach).
    let mut stop_here: Option<f64> = None;
    // The set-back of the blend before the current segment, if there is one.
    let mut before: Option<f64> = None;
    let mut segments = segments;
    let mut current = segments.next();
    while let Some(seg) = current {
        let next = segments.next();
        let mut after = None;
        let mut reach_next = None;
        let mut stop_next = None;
        if let Some(next) = &next
            && let (Some(t0), Some(t1)) =
                (seg.straight_xyz_direction(), next.straight_xyz_direction())
        {
            let (start, delta) = (seg.start(), seg.delta());
            let point = glam::DVec3::new(
                start[0] + delta[0],
                start[1] + delta[1],
                start[2] + delta[2],
            );
            let reached = (*reach_here.get_or_insert_with(|| reach(&seg)), reach(next));
            reach_next = Some(reached.1);
            let stops = (
                *stop_here.get_or_insert_with(|| slow_side(&seg, reached.0, 0.0)),
                slow_side(next, reached.1, 0.0),
            );
            stop_next = Some(stops.1);
            let mut corner = Corner {
                point,
                t0,
                t1,
                max_setback: 0.5 * seg.length.min(next.length),
                reached,
                stop_cost: stops.0 + stops.1,
            };
            // Next to a merged run, half the tolerance is the merge's.
            let merged = seg.last_block != seg.block || next.last_block != next.block;
            let tolerance = if merged { 0.5 * tolerance } else { tolerance };
            after = best_blend(&seg, next, &corner, tolerance, axes, path_limits);
            // The straight piece left between this blend and the one before is either none
            // or at least `MIN_PIECE_MM` long: a sliver of a piece is timed with less
            // precision than its length.
            let room = seg.length - before.unwrap_or(0.0);
            if let Some(a) = after.as_ref().and_then(|b| b.blend()).map(|b| b.setback)
                && room - a > 0.0
                && room - a < MIN_PIECE_MM
                && room - MIN_PIECE_MM > 0.0
            {
                corner.max_setback = corner.max_setback.min(room - MIN_PIECE_MM);
                after = best_blend(&seg, next, &corner, tolerance, axes, path_limits);
            }
        }
        let after_setback = after
            .as_ref()
            .and_then(|s: &path::Segment| s.blend())
            .map(|b| b.setback);
        match (before, after_setback) {
            (None, None) => out.push(seg),
            (b, a) => {
                let (from, to) = (b.unwrap_or(0.0), seg.length - a.unwrap_or(0.0));
                if let Some(piece) = seg.straight_piece(from, to) {
                    out.push(piece);
                }
            }
        }
        if let Some(b) = after {
            out.push(b);
        }
        before = after_setback;
        reach_here = reach_next;
        stop_here = stop_next;
        current = next;
    }
    out
}

/// One corner between two straight segments.
struct Corner {
    /// The corner point.
    point: glam::DVec3,
    /// Incoming and outgoing unit directions.
    t0: glam::DVec3,
    t1: glam::DVec3,
    /// The largest set-back along either line (half the shorter segment).
    max_setback: f64,
    /// The speed each neighbour reaches at the corner from a stop at its far end.
    reached: (f64, f64),
    /// The cost of an exact stop at the corner (`slow_side` at 0 on both sides, summed).
    stop_cost: f64,
}

/// The blend at one corner that costs the least time against cruising straight through, among
/// the largest one the tolerance and the neighbours allow and up to five smaller ones (each a quarter
/// of the previous deviation), or none (exact stop) when stopping is cheaper.
///
/// A blend is planned at one speed cap (its uniform bounds), so a large blend round a sharp
/// corner can be slower than stopping: its curvature rate makes the centripetal-jerk speed low
/// while its length grows. The estimate per corner, with the neighbours' speed `F` and
/// tangential limits: slowing from `F` to `v` and back costs
/// `change_time(v, F) − change_distance(v, F)/F` on each side, running half the blend's length
/// `ℓ` at `v` instead of each neighbour's cap `F` costs `ℓ/2·(1/v − 1/F)`; exact stop is the
/// case `v = 0`, `ℓ = 0`. Only the limits of each candidate are computed; the segment is built
/// for the winner.
fn best_blend(
    a: &path::Segment,
    b: &path::Segment,
    corner: &Corner,
    tolerance: f64,
    axes: &path::AxisLimits,
    path_limits: Option<Limits1>,
) -> Option<path::Segment> {
    let feed = a.limits.velocity.min(b.limits.velocity);
    // The cost of slowing to v at the corner, both sides.
    let (fa, fb) = corner.reached;
    let slow_down = |v: f64| slow_side(a, fa, v) + slow_side(b, fb, v);
    let mut best: Option<(blend::ClothoidBlend, Limits1, path::VelocityCap)> = None;
    // Candidates are weighed by their velocity bound; the tangential limits are taken only
    // for one that is the best so far (`blend_velocity` says why they then exist).
    let mut best_cost = corner.stop_cost;
    let first = blend::ClothoidBlend::new(
        corner.point,
        corner.t0,
        corner.t1,
        tolerance,
        corner.max_setback,
    )?;
    let first_terms = path::blend_terms(&first, axes);
    // The smaller candidates are the blend of half length `base` shrunk by 4^−k: their bound
    // terms are the base's scaled (exactly; see `path::BoundTerms`), taken once. A candidate
    // is kept as its half length; its blend is built only where it is the best so far.
    let base = first.deviation / first.deviation_unit();
    let mut base_terms = None;
    let mut deviation = first.deviation;
    let mut previous = f64::INFINITY;
    for k in 0..CANDIDATES {
        // A smaller candidate's own terms, where they are not the base's scaled.
        let own;
        let candidate = if k == 0 {
            first_terms.as_ref().map(|t| (first.half_length, t, 0))
        } else {
            // `first.shrunk_to(deviation)`'s half length, where it has one.
            deviation *= 0.25;
            let half_length = deviation / first.deviation_unit();
            if !(deviation > 0.0 && deviation < first.deviation) {
                None
            } else if half_length == base * QUARTER_POWERS[usize::from(k)] && base > 1e-100 {
                if base_terms.is_none() {
                    base_terms = Some(if base == first.half_length {
                        first_terms
                    } else {
                        path::blend_terms(&first.with_half_length(base), axes)
                    });
                }
                base_terms
                    .as_ref()
                    .and_then(Option::as_ref)
                    .map(|t| (half_length, t, u32::from(k)))
            } else {
                own = path::blend_terms(&first.with_half_length(half_length), axes);
                own.as_ref().map(|t| (half_length, t, 0))
            }
        };
        let Some((half, weighed)) = candidate.and_then(|(half, t, shrunk)| {
            path::blend_velocity(t, shrunk, feed, path_limits).map(|w| (half, w))
        }) else {
            continue;
        };
        let v = weighed.0;
        // Half the blend replaces each neighbour's line at that neighbour's speed.
        let cost = slow_down(v)
            + half * (2.0 / v - 1.0 / a.limits.velocity.max(v) - 1.0 / b.limits.velocity.max(v));
        if cost < best_cost {
            let c = if k == 0 {
                first
            } else {
                first.with_half_length(half)
            };
            let Some((limits, cap)) = path::blend_limits_at(&c, weighed, axes, path_limits) else {
                continue;
            };
            best_cost = cost;
            best = Some((c, limits, cap));
        }
        if cost > previous {
            // Past the best size (the cost is unimodal in the size in practice).
            break;
        }
        previous = cost;
    }
    best.map(|(c, limits, cap)| path::Segment::blend_segment(a.last_block, c, limits, cap))
}

/// The cost of slowing to `v` at a corner on the side of segment `s`, whose speed there is `f`:
/// change_time(v, F) − change_distance(v, F)/F with the time taken once; no change (v = F)
/// costs exactly 0.
#[inline]
fn slow_side(s: &path::Segment, f: f64, v: f64) -> f64 {
    let l = s.limits;
    let v = v.min(f);
    if f > 0.0 && v < f {
        let t = profile::change_time(v, f, l.acceleration, l.jerk);
        t - 0.5 * (v + f) * t / f
    } else {
        0.0
    }
}

/// The shortest straight piece left between two corner blends (mm); shorter ones are none.
const MIN_PIECE_MM: f64 = 1e-3;

/// Blend candidates weighed per corner by [`best_blend`]: the first and five shrunk by 4^−k.
const CANDIDATES: u8 = 6;

/// `4^−k` for the candidates `k` of [`best_blend`] (exact powers of two, the values `powi` gives).
const QUARTER_POWERS: [f64; CANDIDATES as usize] =
    [1.0, 0.25, 0.0625, 0.015_625, 0.003_906_25, 0.000_976_562_5];

/// The block moves no joint at all.
fn joint_zero_length(b: &MotionBlock) -> bool {
    let (s, e) = (path::joint_vector(&b.start), path::joint_vector(&b.end));
    b.length_mm() <= 1e-12 && s.iter().zip(e.iter()).all(|(a, b)| (a - b).abs() <= 1e-12)
}

#[cfg(test)]
mod blend_choice_tests {
    use super::QUARTER_POWERS;

    #[test]
    fn quarter_powers_are_powi() {
        for (k, p) in QUARTER_POWERS.iter().enumerate() {
            let k = i32::try_from(k).unwrap();
            assert_eq!(p.to_bits(), 0.25_f64.powi(k).to_bits(), "{k}");
        }
    }
}
