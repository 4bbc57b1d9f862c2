//! Step 3: the planned motion in time: the state at any time, samples at the period, peaks.

use super::AxisLimit;
use super::path::{JointVector, SLOTS, Segment, VelocityCap, joint_vector};
use super::profile::{PhaseKind, Profile};
use crate::gcode::MotionBlock;
use std::sync::Arc;

/// Which limit shapes the motion at a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ActiveLimit {
    /// Jerk at its tangential limit.
    Jerk,
    /// Acceleration at its tangential limit.
    Acceleration,
    /// Cruising at the block's velocity cap (see [`VelocityCap`]).
    Velocity(VelocityCap),
    /// Standing still (program end, or no motion).
    None,
}

/// The state of the machine at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Time (s).
    pub t: f64,
    /// Index of the block (in the program) being run.
    pub block: usize,
    /// Path position from the program start (sum of block lengths, mm).
    pub path_position: f64,
    /// Path speed (mm/s).
    pub feed: f64,
    /// Axis positions, slots X Y Z A B C (mm, rad).
    pub position: JointVector,
    /// Axis velocities.
    pub velocity: JointVector,
    /// Axis accelerations.
    pub acceleration: JointVector,
    /// Axis jerks.
    pub jerk: JointVector,
    /// The active limit.
    pub active: ActiveLimit,
}

/// Peak absolute velocity, acceleration and jerk of one axis over the samples.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AxisPeak {
    /// Axis letter.
    pub axis: char,
    /// Peak |velocity|.
    pub velocity: f64,
    /// Peak |acceleration|.
    pub acceleration: f64,
    /// Peak |jerk|.
    pub jerk: f64,
}

/// The most samples [`TimedPath::peaks`] looks at (about 20 s of work on a slow machine).
pub const MAX_PEAK_SAMPLES: usize = 20_000_000;

/// The speeds a plan keeps per segment: enough to rebuild each profile exactly.
#[derive(Clone, Debug)]
pub(super) struct Speeds {
    /// Junction speeds, one more than segments (the program's start and end).
    pub junctions: Vec<f64>,
    /// Each segment's peak velocity.
    pub peaks: Vec<f64>,
    /// Each segment's start time, and the cycle time last.
    pub start_times: Vec<f64>,
    /// Each segment's start along the path (the sum of the lengths before it).
    pub path_starts: Vec<f64>,
}

/// A planned program: profiles per block laid end to end in time.
#[derive(Clone, Debug)]
pub struct TimedPath {
    blocks: Arc<[MotionBlock]>,
    segments: Vec<Segment>,
    speeds: Speeds,
    path_starts: Vec<f64>,
    /// Total duration (s).
    pub cycle_time_s: f64,
    /// Sample period (s).
    pub sample_period_s: f64,
    /// The axes and their limits, machine order.
    pub axes: Vec<(char, AxisLimit)>,
}

impl TimedPath {
    pub(super) fn new(
        blocks: Arc<[MotionBlock]>,
        segments: Vec<Segment>,
        mut speeds: Speeds,
        axes: &[(char, AxisLimit)],
        sample_period_s: f64,
    ) -> Self {
        let path_starts = std::mem::take(&mut speeds.path_starts);
        Self {
            blocks,
            cycle_time_s: speeds.start_times.last().copied().unwrap_or(0.0),
            segments,
            speeds,
            path_starts,
            sample_period_s,
            axes: axes.to_vec(),
        }
    }

    /// Peaks per axis (machine order) over the samples at the period, or, when the program is
    /// so long that would exceed [`MAX_PEAK_SAMPLES`], over that many samples evenly spread
    /// (the work is bounded by the budget, not by the planned time).
    ///
    /// The same values as taking the maxima over [`TimedPath::samples_every`], to the bit, for
    /// a fraction of the work: each segment's profile is built once (see `SampleCursor`), and
    /// on a straight segment, whose joint direction `q'` is fixed, an axis's velocity,
    /// acceleration and jerk are `q'ᵢ·v`, `q'ᵢ·a`, `q'ᵢ·j`, so their largest magnitudes are
    /// `|q'ᵢ|` times the largest `|v|`, `|a|`, `|j|` of the profile over the segment's samples
    /// (rounding is monotone, so the product of the maxima is the maximum of the products).
    #[must_use]
    pub fn peaks(&self) -> Vec<AxisPeak> {
        let mut max = [[0.0_f64; SLOTS]; 3];
        let period = self
            .sample_period_s
            .max(self.cycle_time_s / MAX_PEAK_SAMPLES as f64);
        let mut cursor = SampleCursor::new(self);
        // The straight segment whose samples are being gathered, its direction and the
        // largest |v|, |a|, |j| of its profile at them.
        let mut line: Option<(usize, JointVector, [f64; 3])> = None;
        let flush = |line: &mut Option<(usize, JointVector, [f64; 3])>,
                     max: &mut [[f64; SLOTS]; 3]| {
            if let Some((_, d, m)) = line.take() {
                for (row, mk) in max.iter_mut().zip(m) {
                    for (slot, di) in row.iter_mut().zip(d) {
                        *slot = slot.max(di.abs() * mk);
                    }
                }
            }
        };
        for t in self.sample_times(period) {
            let t = t.clamp(0.0, self.cycle_time_s);
            let k = cursor.seek(t);
            if line.as_ref().is_some_and(|(lk, _, _)| *lk != k) {
                flush(&mut line, &mut max);
            }
            let direction = match line.as_ref() {
                Some((_, d, _)) => Some(*d),
                None => self.segments.get(k).and_then(Segment::line_direction),
            };
            let prof = cursor.profile();
            match (direction, prof) {
                (Some(d), Some(prof)) => {
                    let local = t - self.speeds.start_times.get(k).copied().unwrap_or(0.0);
                    let ((_, v, a, j), _) = prof.at_time_with_kind(local);
                    let entry = line.get_or_insert((k, d, [0.0; 3]));
                    for (m, x) in entry.2.iter_mut().zip([v, a, j]) {
                        *m = m.max(x.abs());
                    }
                }
                _ => {
                    let smp = self.state_in(k, prof, t);
                    for (row, values) in
                        max.iter_mut()
                            .zip([&smp.velocity, &smp.acceleration, &smp.jerk])
                    {
                        for (slot, x) in row.iter_mut().zip(values) {
                            *slot = slot.max(x.abs());
                        }
                    }
                }
            }
        }
        flush(&mut line, &mut max);
        self.axes
            .iter()
            .map(|(c, _)| {
                let at = |row: &[f64; SLOTS]| {
                    super::path::slot_of(*c)
                        .and_then(|k| row.get(k).copied())
                        .unwrap_or(0.0)
                };
                AxisPeak {
                    axis: *c,
                    velocity: at(&max[0]),
                    acceleration: at(&max[1]),
                    jerk: at(&max[2]),
                }
            })
            .collect()
    }

    /// The program's motion blocks the plan was made for.
    #[must_use]
    pub fn blocks(&self) -> &[MotionBlock] {
        &self.blocks
    }

    /// Number of planned segments (non-empty blocks, plus corner blends).
    #[must_use]
    pub fn block_count(&self) -> usize {
        self.segments.len()
    }

    /// The planned segments in order (program blocks, shortened where corners are blended, and
    /// the corner blends between them).
    #[must_use]
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Start and end time of planned segment `k` (see [`TimedPath::segments`]), s.
    #[must_use]
    pub fn segment_span_s(&self, k: usize) -> Option<(f64, f64)> {
        self.segments.get(k)?;
        let times = &self.speeds.start_times;
        Some((*times.get(k)?, *times.get(k + 1)?))
    }

    /// The program's blocks as the plan runs them: `(block index, (start, end) time in s, path
    /// length in mm)` in order, one entry per planned segment, except that a run of blocks
    /// merged into one line (see [`crate::feed::merge`]) gives one entry per block, each the
    /// share of the line its own length is, timed where the line's profile reaches it.
    #[must_use]
    pub fn block_pieces(&self) -> Vec<(usize, (f64, f64), f64)> {
        let mut out = Vec::with_capacity(self.blocks.len());
        for (k, seg) in self.segments.iter().enumerate() {
            let Some((t0, t1)) = self.segment_span_s(k) else {
                continue;
            };
            if seg.last_block <= seg.block {
                out.push((seg.block, (t0, t1), seg.length));
                continue;
            }
            let (Some(blocks), Some(profile)) =
                (self.blocks.get(seg.block..=seg.last_block), self.profile(k))
            else {
                out.push((seg.block, (t0, t1), seg.length));
                continue;
            };
            let total: f64 = blocks.iter().map(MotionBlock::length_mm).sum();
            let (mut along, mut t_prev) = (0.0, t0);
            for (i, b) in blocks.iter().enumerate() {
                let share = if total > 0.0 {
                    seg.length * b.length_mm() / total
                } else {
                    0.0
                };
                along += share;
                let t_end = if i + 1 == blocks.len() {
                    t1
                } else {
                    t0 + time_at_distance(&profile, along.min(seg.length))
                };
                out.push((seg.block + i, (t_prev, t_end.max(t_prev)), share));
                t_prev = t_end.max(t_prev);
            }
        }
        out
    }

    /// The planned path speed at junction `k` (0: the start of segment 0; `k`: the end of
    /// segment `k − 1`), mm/s; `None` past the end.
    #[must_use]
    pub fn junction_speed(&self, k: usize) -> Option<f64> {
        self.speeds.junctions.get(k).copied()
    }

    /// The 1-DoF profile of planned block `k` (along its path length), rebuilt from the kept
    /// speeds (the same as when it was planned).
    #[must_use]
    pub fn profile(&self, k: usize) -> Option<Profile> {
        let seg = self.segments.get(k)?;
        let sp = &self.speeds;
        Some(Profile::with_peak(
            seg.length,
            *sp.junctions.get(k)?,
            *sp.junctions.get(k + 1)?,
            *sp.peaks.get(k)?,
            &seg.limits,
        ))
    }

    /// The state at time `t` (clamped to `[0, cycle_time_s]`; at the end, exactly the last
    /// block's end point).
    #[must_use]
    pub fn state_at(&self, t: f64) -> Sample {
        let t = t.clamp(0.0, self.cycle_time_s);
        let k = self.segment_at(t);
        self.state_in(k, self.profile(k).as_ref(), t)
    }

    /// The segment running at `t`: the last whose start is at or before it.
    fn segment_at(&self, t: f64) -> usize {
        let n = self.segments.len();
        self.speeds.start_times[..n]
            .partition_point(|&t0| t0 <= t)
            .saturating_sub(1)
    }

    /// [`TimedPath::state_at`] at `t` (clamped) in segment `k` ([`TimedPath::segment_at`])
    /// whose profile is `prof` ([`TimedPath::profile`]).
    fn state_in(&self, k: usize, prof: Option<&Profile>, t: f64) -> Sample {
        let (Some(seg), Some(prof), Some(block)) = (
            self.segments.get(k),
            prof,
            self.blocks
                .get(self.segments.get(k).map_or(0, |s| s.last_block)),
        ) else {
            let position = self
                .blocks
                .last()
                .map_or([0.0; SLOTS], |b| joint_vector(&b.end));
            return Sample {
                t,
                block: 0,
                path_position: 0.0,
                feed: 0.0,
                position,
                velocity: [0.0; SLOTS],
                acceleration: [0.0; SLOTS],
                jerk: [0.0; SLOTS],
                active: ActiveLimit::None,
            };
        };
        let local = t - self.speeds.start_times.get(k).copied().unwrap_or(0.0);
        let at_end = t >= self.cycle_time_s && k + 1 == self.segments.len();
        let ((s, v, a, j), kind) = prof.at_time_with_kind(local);
        let d = seg.derivatives(s);
        let position = if at_end {
            joint_vector(&block.end)
        } else if seg.arc().is_none() {
            // Lines (possibly shortened by corner blends) and blends: the segment's own point.
            d[0]
        } else if s >= seg.length {
            joint_vector(&block.end)
        } else {
            // Spread the gap between the arc's geometric end and its programmed end point
            // over the block, so that positions are continuous and end exactly there.
            let u = s / seg.length;
            let mut p = joint_vector(&block.point_at(u));
            let (end_geom, end) = (joint_vector(&block.point_at(1.0)), joint_vector(&block.end));
            for i in 0..SLOTS {
                p[i] += u * (end[i] - end_geom[i]);
            }
            p
        };
        let mut sample = Sample {
            t,
            block: seg.block,
            path_position: self.path_starts.get(k).copied().unwrap_or(0.0) + s,
            feed: v,
            position,
            velocity: [0.0; SLOTS],
            acceleration: [0.0; SLOTS],
            jerk: [0.0; SLOTS],
            active: match kind {
                _ if v <= 0.0 && a == 0.0 && j == 0.0 => ActiveLimit::None,
                PhaseKind::Jerk => ActiveLimit::Jerk,
                PhaseKind::Acceleration => ActiveLimit::Acceleration,
                PhaseKind::Velocity => ActiveLimit::Velocity(seg.cap),
            },
        };
        // One index walks several parallel arrays; an iterator chain would hide that.
        #[allow(clippy::needless_range_loop)]
        for i in 0..SLOTS {
            sample.velocity[i] = d[1][i] * v;
            sample.acceleration[i] = d[1][i] * a + d[2][i] * v * v;
            sample.jerk[i] = d[1][i] * j + 3.0 * d[2][i] * v * a + d[3][i] * v * v * v;
        }
        sample
    }

    /// Samples at `t = 0, T, 2T, ...` and one at the cycle time.
    pub fn samples(&self) -> impl Iterator<Item = Sample> + '_ {
        self.samples_every(self.sample_period_s)
    }

    /// The number of samples [`TimedPath::samples`] gives.
    #[must_use]
    pub fn sample_count(&self) -> f64 {
        (self.cycle_time_s / self.sample_period_s).floor() + 1.0
    }

    /// Samples every `period_s` (a non-positive or non-finite period gives only the end).
    pub fn samples_every(&self, period_s: f64) -> impl Iterator<Item = Sample> + '_ {
        let mut cursor = SampleCursor::new(self);
        self.sample_times(period_s).map(move |t| {
            let t = t.clamp(0.0, self.cycle_time_s);
            let k = cursor.seek(t);
            self.state_in(k, cursor.profile(), t)
        })
    }

    /// The times of [`TimedPath::samples_every`].
    fn sample_times(&self, period_s: f64) -> impl Iterator<Item = f64> + '_ {
        let n = if period_s.is_finite() && period_s > 0.0 && self.cycle_time_s.is_finite() {
            // Saturating: a caller asking for more samples than memory or time allows must
            // bound them itself (see `sample_count`).
            (self.cycle_time_s / period_s).floor() as usize
        } else {
            0
        };
        (0..=n)
            .map(move |i| i as f64 * period_s)
            .filter(move |t| *t < self.cycle_time_s)
            .chain(std::iter::once(self.cycle_time_s))
    }
}

/// Walks a plan's segments along times that never decrease (the samples), building each
/// segment's profile once instead of once per sample: the segment and profile
/// [`TimedPath::state_at`] finds for each time, without its search.
struct SampleCursor<'a> {
    path: &'a TimedPath,
    k: usize,
    /// The profile of segment `k`, built when first asked for.
    profile: Option<Option<Profile>>,
}

impl<'a> SampleCursor<'a> {
    fn new(path: &'a TimedPath) -> Self {
        Self {
            path,
            k: 0,
            profile: None,
        }
    }

    /// The segment [`TimedPath::segment_at`] gives for `t`, for `t` not below the last call's
    /// (the start times never decrease, so the last at or before `t` is found by walking on;
    /// an earlier `t` falls back to the search).
    fn seek(&mut self, t: f64) -> usize {
        let times = &self.path.speeds.start_times;
        let n = self.path.segments.len();
        let k = if times.get(self.k).is_some_and(|&t0| t0 <= t) || self.k == 0 {
            let mut k = self.k;
            while k + 1 < n && times.get(k + 1).is_some_and(|&t1| t1 <= t) {
                k += 1;
            }
            k
        } else {
            self.path.segment_at(t)
        };
        if k != self.k {
            self.k = k;
            self.profile = None;
        }
        k
    }

    /// The profile of the segment of the last [`SampleCursor::seek`].
    fn profile(&mut self) -> Option<&Profile> {
        let (path, k) = (self.path, self.k);
        self.profile.get_or_insert_with(|| path.profile(k)).as_ref()
    }
}

/// The time at which `profile` has run `distance` along its path (bisection on its monotone
/// position, to a nanosecond).
fn time_at_distance(profile: &Profile, distance: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, profile.duration_s());
    for _ in 0..64 {
        if hi - lo <= 1e-9 {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if profile.at_time(mid).0 < distance {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
