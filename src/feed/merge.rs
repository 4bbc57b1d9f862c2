//! Step 1b: runs of short straight blocks merged into one line within the tolerance, as
//! LinuxCNC's naive-CAM tolerance does (`G64 P… Q…`).
//!
//! Dense CAM output samples a smooth curve with many short lines (a circle of R50 in 100 000
//! blocks is 3 µm per block). Blended one corner at a time, each corner's blend must fit in half
//! of its blocks, so it is tiny and sharp and the feed collapses with the block count. Here a run
//! of consecutive lines is replaced by the line from the run's first start to its last end while
//! every vertex in between lies within `tolerance` of it (perpendicular distance in X Y Z, and
//! each rotary axis within `tolerance` / [`ROTARY_LEVER_MM`] rad of its value interpolated along
//! the line) and the vertices run forwards along it. The merged lines then meet at corners that
//! turn by a few degrees and are blended as any corner ([`super::blend`]) within the other half
//! of the tolerance, so the path stays within the whole tolerance of the program.
//!
//! The merged line runs at the speed that keeps the run's time at its blocks' speeds
//! (`Σ ℓᵢ / vᵢ`), but never faster than its slowest block (a scheduled feed is a limit, not an
//! average); blocks are merged only where their speeds differ by at most
//! [`MAX_SPEED_RATIO`], and a rapid only with rapids. Each run is at most [`MAX_RUN`] blocks, so
//! the check (every vertex of the run against each longer chord) stays bounded.

use super::Limits1;
use super::path::{AxisLimits, JointVector, SLOTS, Segment};
use crate::gcode::{MotionBlock, MotionKind};

/// Tool-tip lever (mm) that turns a rotary axis's deviation (rad) into a distance: the tool
/// tip of a 5-axis machine runs about this far from its rotary axes.
pub const ROTARY_LEVER_MM: f64 = 100.0;

/// Largest ratio of the speeds of two blocks merged into one line: equal speeds only (within
/// rounding), so a scheduled feed is kept block by block.
pub const MAX_SPEED_RATIO: f64 = 1.0 + 1e-9;

/// Most blocks merged into one line.
pub const MAX_RUN: usize = 2048;

/// A run being merged.
struct Run {
    /// The run's first segment (kept as it is when nothing joins it).
    first: Segment,
    start: JointVector,
    end: JointVector,
    /// Vertices between the blocks of the run.
    inner: Vec<JointVector>,
    /// Index of the last block.
    last: usize,
    /// `Σ ℓᵢ / vᵢ` over the run (s).
    time: f64,
    /// Slowest and fastest block speed.
    slowest: f64,
    fastest: f64,
    rapid: bool,
}

/// Whether every vertex of `inner` lies within `tolerance` of the line `start → end` and they
/// run forwards along it.
fn fits(start: &JointVector, end: &JointVector, inner: &[JointVector], tolerance: f64) -> bool {
    let c = glam::DVec3::new(end[0] - start[0], end[1] - start[1], end[2] - start[2]);
    let cc = c.length_squared();
    if !(cc > 1e-24) {
        return false;
    }
    let mut previous = 0.0;
    for v in inner {
        let d = glam::DVec3::new(v[0] - start[0], v[1] - start[1], v[2] - start[2]);
        let u = d.dot(c) / cc;
        if !(u > previous && u < 1.0) {
            return false;
        }
        previous = u;
        if (d - c * u).length() > tolerance {
            return false;
        }
        for k in 3..SLOTS {
            let along = start[k] + u * (end[k] - start[k]);
            if (v[k] - along).abs() * ROTARY_LEVER_MM > tolerance {
                return false;
            }
        }
    }
    true
}

/// Merge the runs of short straight blocks of `segments` within `tolerance` (mm).
pub fn merge_runs(
    segments: impl Iterator<Item = Segment>,
    blocks: &[MotionBlock],
    axes: &AxisLimits,
    path: Option<Limits1>,
    tolerance: f64,
) -> Vec<Segment> {
    let mut out = Vec::new();
    let mut run: Option<Run> = None;
    let close = |run: Run, out: &mut Vec<Segment>| {
        if run.inner.is_empty() {
            out.push(run.first);
            return;
        }
        let length = (0..3)
            .map(|k| (run.end[k] - run.start[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let feed = if run.rapid {
            f64::INFINITY
        } else {
            // Never faster than the slowest block it covers: a block's feed is a limit (a
            // feed schedule slows the blocks where the force would pass its target).
            (length / run.time).min(run.slowest)
        };
        match Segment::merged_line(
            (run.first.block, run.last),
            run.start,
            run.end,
            feed,
            axes,
            path,
        ) {
            Some(s) => out.push(s),
            // Not expected: the chord has length and moves only the blocks' axes. Where it
            // happens the run is kept whole as one line of its first block's limits.
            None => out.push(run.first),
        }
    };
    for seg in segments {
        // Lines that move X, Y or Z (a rotary-only move's length is in rad).
        let mergeable = seg.is_line() && xyz_length(&seg) > 1e-12;
        let rapid = blocks
            .get(seg.block)
            .is_some_and(|b| matches!(b.kind, MotionKind::Rapid));
        let speed = seg.limits.velocity;
        let (start, delta) = (seg.start(), seg.delta());
        let mut end = [0.0; SLOTS];
        for k in 0..SLOTS {
            end[k] = start[k] + delta[k];
        }
        if let Some(r) = &mut run {
            let joins = mergeable
                && r.rapid == rapid
                && r.inner.len() + 1 < MAX_RUN
                && r.slowest.min(speed) * MAX_SPEED_RATIO >= r.fastest.max(speed);
            if joins {
                r.inner.push(r.end);
                if fits(&r.start, &end, &r.inner, tolerance) {
                    r.end = end;
                    r.last = seg.block;
                    r.time += seg.length / speed;
                    r.slowest = r.slowest.min(speed);
                    r.fastest = r.fastest.max(speed);
                    continue;
                }
                r.inner.pop();
            }
        }
        if let Some(r) = run.take() {
            close(r, &mut out);
        }
        if mergeable && speed > 0.0 {
            run = Some(Run {
                start,
                end,
                inner: Vec::new(),
                last: seg.block,
                time: seg.length / speed,
                slowest: speed,
                fastest: speed,
                rapid,
                first: seg,
            });
        } else {
            out.push(seg);
        }
    }
    if let Some(r) = run.take() {
        close(r, &mut out);
    }
    out
}

/// The X Y Z length of a straight segment.
fn xyz_length(s: &Segment) -> f64 {
    let d = s.delta();
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}
