//! One planned motion of the control: motion blocks planned by the jerk-limited planner into a
//! [`TimedPath`], played on the simulated clock, and braked on a jerk-limited stop (feed hold,
//! jog release, stop) along the same path, so every axis keeps its limits while braking too.
//!
//! The brake is the time-optimal stop from the path state `(v0, a0)` at the moment of the
//! hold with the tangential limits `(A, J)` of the segments it crosses (which bound every
//! axis, see `feed::path`): jerk −J until the deceleration reaches `ap`, constant −ap, jerk +J
//! until a = 0 exactly as v = 0, with `ap = min(A, sqrt(J·v0 + a0²/2))` (from
//! `v0 + a0²/(2J) − ap²/J − ap·t2 = 0`).

use crate::feed::path::{JointVector, SLOTS, joint_vector};
use crate::feed::{
    AxisLimit, CornerPolicy, FeedError, Limits1, PlanInput, PlanOptions, TimedPath, plan,
};
use crate::gcode::{Joints, MotionBlock, MotionKind};

/// Axis positions, velocities, accelerations and jerks (slots X Y Z A B C; mm, rad) and the
/// path speed at one time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kinematics {
    /// Positions.
    pub position: JointVector,
    /// Velocities.
    pub velocity: JointVector,
    /// Accelerations.
    pub acceleration: JointVector,
    /// Jerks.
    pub jerk: JointVector,
    /// Path speed (mm/s, or rad/s on a rotary-only block).
    pub feed: f64,
}

/// A jerk-limited stop in progress.
#[derive(Clone, Debug)]
struct Brake {
    /// Time into the brake (s).
    t: f64,
    /// Path position where it began.
    s0: f64,
    v0: f64,
    a0: f64,
    /// (duration, jerk) of its three phases.
    phases: [(f64, f64); 3],
}

impl Brake {
    fn duration(&self) -> f64 {
        self.phases.iter().map(|p| p.0).sum()
    }

    /// `(s, v, a, j)` at time `t` into the brake (v never below 0).
    fn state(&self, t: f64) -> (f64, f64, f64, f64) {
        let (mut s, mut v, mut a) = (self.s0, self.v0, self.a0);
        let mut left = t.max(0.0);
        let mut jerk = 0.0;
        for &(d, j) in &self.phases {
            let h = left.min(d);
            s += v * h + a * h * h / 2.0 + j * h * h * h / 6.0;
            v += a * h + j * h * h / 2.0;
            a += j * h;
            jerk = j;
            left -= h;
            if left <= 0.0 {
                break;
            }
        }
        if t >= self.duration() {
            (s, 0.0, 0.0, 0.0)
        } else {
            (s, v.max(0.0), a, jerk)
        }
    }
}

/// The phases of the time-optimal stop from `(v0, a0)` under `(A, J)`.
fn brake_phases(v0: f64, a0: f64, lim: &Limits1) -> [(f64, f64); 3] {
    let (big_a, j) = (lim.acceleration, lim.jerk);
    let v0 = v0.max(0.0);
    let a0 = a0.clamp(-big_a, big_a);
    let mut ap = (j * v0 + a0 * a0 / 2.0).max(0.0).sqrt();
    let mut t2 = 0.0;
    if ap > big_a {
        ap = big_a;
        t2 = ((v0 + a0 * a0 / (2.0 * j) - big_a * big_a / j) / big_a).max(0.0);
    }
    if ap < -a0 {
        // Already braking harder than needed (only by rounding): release the deceleration.
        return [(0.0, -j), (0.0, 0.0), (-a0 / j, j)];
    }
    [((a0 + ap) / j, -j), (t2, 0.0), (ap / j, j)]
}

/// A planned motion being played.
#[derive(Clone, Debug)]
pub struct Run {
    path: TimedPath,
    /// The blocks as the program gave them (same indices as `path.blocks()`, whose copies
    /// carry the override-scaled feeds).
    blocks: Vec<MotionBlock>,
    /// Path position where each planned segment starts.
    seg_s0: Vec<f64>,
    /// Time where each planned segment starts.
    seg_t0: Vec<f64>,
    total_length: f64,
    /// Time into the path.
    t: f64,
    brake: Option<Brake>,
}

impl Run {
    /// Plan `blocks` (`planned`: the same with the override-scaled feeds) under the axis limits
    /// with the corner policy (the program's motion: [`crate::feed::DEFAULT_CORNERS`], as
    /// `talas feed` plans it).
    ///
    /// # Errors
    /// The planner's [`FeedError`].
    pub fn plan(
        blocks: Vec<MotionBlock>,
        planned: &[MotionBlock],
        axes: &[(char, AxisLimit)],
        corner: CornerPolicy,
    ) -> Result<Self, FeedError> {
        let path = plan(&PlanInput {
            blocks: planned.into(),
            axes: axes.to_vec(),
            options: PlanOptions {
                corner,
                ..PlanOptions::default()
            },
        })?;
        let (mut s, mut t) = (0.0, 0.0);
        let (mut seg_s0, mut seg_t0) = (Vec::new(), Vec::new());
        for (k, seg) in path.segments().iter().enumerate() {
            seg_s0.push(s);
            seg_t0.push(t);
            s += seg.length;
            t += path
                .profile(k)
                .as_ref()
                .map_or(0.0, crate::feed::Profile::duration_s);
        }
        Ok(Self {
            path,
            blocks,
            seg_s0,
            seg_t0,
            total_length: s,
            t: 0.0,
            brake: None,
        })
    }

    /// The blocks as programmed.
    #[must_use]
    pub fn blocks(&self) -> &[MotionBlock] {
        &self.blocks
    }

    /// Whether the motion has come to its end (or the brake to rest).
    #[must_use]
    pub fn finished(&self) -> bool {
        match &self.brake {
            Some(b) => b.t >= b.duration(),
            None => self.t >= self.path.cycle_time_s,
        }
    }

    /// Whether a brake is in progress or done.
    #[must_use]
    pub fn braking(&self) -> bool {
        self.brake.is_some()
    }

    /// Time left until the end of the motion or brake (s).
    #[must_use]
    pub fn time_left(&self) -> f64 {
        match &self.brake {
            Some(b) => (b.duration() - b.t).max(0.0),
            None => (self.path.cycle_time_s - self.t).max(0.0),
        }
    }

    /// Move the clock on by at most `dt`; returns the time used.
    pub fn step(&mut self, dt: f64) -> f64 {
        let h = dt.min(self.time_left()).max(0.0);
        match &mut self.brake {
            Some(b) => b.t += h,
            None => self.t += h,
        }
        h
    }

    /// Move the clock on by at most `dt` but not past the end of the present segment; returns
    /// the time used. (Used only where that end is at rest: see [`Run::rests_after_present`].)
    pub fn step_within_segment(&mut self, dt: f64) -> f64 {
        if self.brake.is_some() {
            return self.step(dt);
        }
        let t = self.t;
        let k = self.seg_t0.partition_point(|&t0| t0 <= t).saturating_sub(1);
        let end = self
            .seg_t0
            .get(k + 1)
            .copied()
            .unwrap_or(self.path.cycle_time_s);
        if end - t <= dt {
            self.t = end;
            (end - t).max(0.0)
        } else {
            self.t += dt;
            dt
        }
    }

    /// Whether the present segment ends at rest (a junction speed of 0 in the plan, or the end
    /// of the motion): the motion can be planned again from there without a brake.
    #[must_use]
    pub fn rests_after_present(&self) -> bool {
        let t = self.t;
        let k = self.seg_t0.partition_point(|&t0| t0 <= t).saturating_sub(1);
        self.path.junction_speed(k + 1).is_none_or(|v| v == 0.0)
    }

    /// Whether the clock stands exactly at the start of a segment after the first (the
    /// motion at rest between two blocks, not braking).
    #[must_use]
    pub fn at_segment_boundary(&self) -> bool {
        self.brake.is_none()
            && self.t > 0.0
            && self.t < self.path.cycle_time_s
            && self.seg_t0.contains(&self.t)
    }

    /// The planned segment holding path position `s` and the position inside it.
    fn segment_at(&self, s: f64) -> (usize, f64) {
        let k = self.seg_s0.partition_point(|&s0| s0 <= s).saturating_sub(1);
        (k, s - self.seg_s0.get(k).copied().unwrap_or(0.0))
    }

    /// Path position, speed, acceleration, jerk now.
    fn path_state(&self) -> (f64, f64, f64, f64) {
        if let Some(b) = &self.brake {
            return b.state(b.t);
        }
        let t = self.t.clamp(0.0, self.path.cycle_time_s);
        let k = self.seg_t0.partition_point(|&t0| t0 <= t).saturating_sub(1);
        let Some(p) = self.path.profile(k) else {
            return (self.total_length, 0.0, 0.0, 0.0);
        };
        let (s, v, a, j) = p.at_time(t - self.seg_t0.get(k).copied().unwrap_or(0.0));
        (self.seg_s0.get(k).copied().unwrap_or(0.0) + s, v, a, j)
    }

    /// Path position now (mm from the start of the motion; rad on rotary-only blocks).
    #[must_use]
    pub fn path_position(&self) -> f64 {
        self.path_state().0
    }

    /// Path length of the whole motion.
    #[must_use]
    pub fn total_length(&self) -> f64 {
        self.total_length
    }

    /// The axis state now.
    #[must_use]
    pub fn kinematics(&self) -> Kinematics {
        if self.brake.is_none() {
            let smp = self.path.state_at(self.t);
            return Kinematics {
                position: smp.position,
                velocity: smp.velocity,
                acceleration: smp.acceleration,
                jerk: smp.jerk,
                feed: smp.feed,
            };
        }
        let (s, v, a, j) = self.path_state();
        let (k, sl) = self.segment_at(s);
        let Some(seg) = self.path.segments().get(k) else {
            return Kinematics {
                position: self.point_on(k, sl),
                ..Kinematics::default()
            };
        };
        let d = seg.derivatives(sl);
        let mut out = Kinematics {
            position: self.point_on(k, sl),
            feed: v,
            ..Kinematics::default()
        };
        // One index walks several parallel arrays; an iterator chain would hide that.
        #[allow(clippy::needless_range_loop)]
        for i in 0..SLOTS {
            out.velocity[i] = d[1][i] * v;
            out.acceleration[i] = d[1][i] * a + d[2][i] * v * v;
            out.jerk[i] = d[1][i] * j + 3.0 * d[2][i] * v * a + d[3][i] * v * v * v;
        }
        out
    }

    /// Index (in [`Run::blocks`]) of the block being run.
    #[must_use]
    pub fn current_block(&self) -> Option<usize> {
        let (k, _) = self.segment_at(self.path_position());
        self.path.segments().get(k).map(|s| s.block)
    }

    /// The position at path position `s` of the whole motion (clamped to the path).
    #[must_use]
    pub fn position_at(&self, s: f64) -> JointVector {
        let (k, sl) = self.segment_at(s.clamp(0.0, self.total_length));
        self.point_on(k, sl)
    }

    /// Index (in [`Run::blocks`]) of the block at path position `s`.
    #[must_use]
    pub fn block_at(&self, s: f64) -> Option<usize> {
        let (k, _) = self.segment_at(s.clamp(0.0, self.total_length));
        self.path.segments().get(k).map(|g| g.block)
    }

    /// The position at path position `sl` into planned segment `k` (as `TimedPath::state_at`
    /// places it).
    fn point_on(&self, k: usize, sl: f64) -> JointVector {
        let blocks = self.path.blocks();
        let (Some(seg), last) = (self.path.segments().get(k), blocks.last()) else {
            // A motion of no length (homing an axis already at its switch): it stays put.
            return blocks.last().map_or([0.0; SLOTS], |b| joint_vector(&b.end));
        };
        let Some(block) = blocks.get(seg.last_block) else {
            return last.map_or([0.0; SLOTS], |b| joint_vector(&b.end));
        };
        if k + 1 == self.path.segments().len() && sl >= seg.length {
            return joint_vector(&block.end);
        }
        if seg.arc().is_none() {
            return seg.derivatives(sl)[0];
        }
        if sl >= seg.length {
            return joint_vector(&block.end);
        }
        let u = sl / seg.length;
        let mut p = joint_vector(&block.point_at(u));
        let (geom, end) = (joint_vector(&block.point_at(1.0)), joint_vector(&block.end));
        for i in 0..SLOTS {
            p[i] += u * (end[i] - geom[i]);
        }
        p
    }

    /// Begin the jerk-limited stop from the present state (no effect when already braking).
    pub fn start_brake(&mut self) {
        if self.brake.is_some() {
            return;
        }
        let (s0, v0, a0, _) = self.path_state();
        let (k, _) = self.segment_at(s0);
        let segs = self.path.segments();
        let mut lim = segs.get(k).map_or(
            Limits1 {
                velocity: 1.0,
                acceleration: 1.0,
                jerk: 1.0,
            },
            |s| s.limits,
        );
        // A brake that runs into the next segments must respect their limits too.
        for _ in 0..8 {
            let b = Brake {
                t: 0.0,
                s0,
                v0,
                a0,
                phases: brake_phases(v0, a0, &lim),
            };
            let end = b.state(b.duration()).0;
            let (k_end, _) = self.segment_at(end.min(self.total_length));
            let mut tighter = lim;
            for seg in segs.get(k..=k_end).unwrap_or(&[]) {
                tighter.acceleration = tighter.acceleration.min(seg.limits.acceleration);
                tighter.jerk = tighter.jerk.min(seg.limits.jerk);
            }
            if tighter == lim {
                self.brake = Some(b);
                return;
            }
            lim = tighter;
        }
        self.brake = Some(Brake {
            t: 0.0,
            s0,
            v0,
            a0,
            phases: brake_phases(v0, a0, &lim),
        });
    }

    /// The programmed blocks from the present path position to the end (the block being run
    /// cut at the present position).
    #[must_use]
    pub fn remaining_blocks(&self) -> Vec<MotionBlock> {
        let s = self.path_position();
        if s >= self.total_length - 1e-12 {
            return Vec::new();
        }
        let (k, sl) = self.segment_at(s);
        let Some(seg) = self.path.segments().get(k) else {
            return Vec::new();
        };
        let mut out = Vec::new();
        let here = self.point_on(k, sl);
        // On a corner blend the rest of the corner's block is its outgoing block, from here
        // (within the blend's tolerance of the programmed corner).
        // On a run of blocks merged into one line, the rest of the run is the line from here
        // to the run's end (the merge's tolerance of the programmed vertices).
        let (first, whole) = if seg.blend().is_some() {
            (seg.block + 1, true)
        } else if seg.last_block > seg.block {
            (seg.last_block, true)
        } else {
            (seg.block, false)
        };
        if let Some(b) = self.blocks.get(first) {
            let u = if whole {
                0.0
            } else {
                block_parameter(b, seg, sl)
            };
            let mut piece = sub_block(b, u, 1.0);
            piece.start = joints_like(&here, &b.start);
            out.push(piece);
        }
        out.extend(self.blocks.iter().skip(first + 1).cloned());
        out
    }

    /// The programmed motion between path positions `s0` and `s1` as pieces of blocks (for
    /// cutting).
    #[must_use]
    pub fn pieces(&self, s0: f64, s1: f64) -> Vec<CutPiece> {
        let mut out = Vec::new();
        if !(s1 > s0) {
            return out;
        }
        // The segments before the one holding `s0` end at or before it (and those from the
        // first starting at `s1` on begin after): only those between are visited.
        let first = self.seg_s0.partition_point(|&a| a <= s0).saturating_sub(1);
        for (k, seg) in self.path.segments().iter().enumerate().skip(first) {
            let a = self.seg_s0.get(k).copied().unwrap_or(0.0);
            let b = a + seg.length;
            if a >= s1 {
                break;
            }
            if b <= s0 {
                continue;
            }
            let Some(block) = self.blocks.get(seg.block) else {
                continue;
            };
            let u0 = ((s0 - a) / seg.length).clamp(0.0, 1.0);
            let u1 = ((s1 - a) / seg.length).clamp(0.0, 1.0);
            let mut piece = sub_block(block, u0, u1);
            piece.start = joints_like(&self.point_on(k, s0.max(a) - a), &block.start);
            // A segment that is not its whole block (a line shortened by corner blends, a
            // blend, a merged run) ends where the segment does, not where the block does.
            let whole = seg.blend().is_none()
                && seg.last_block == seg.block
                && (seg.length - block.length_mm()).abs() <= 1e-9;
            if u1 < 1.0 || !whole {
                piece.end = joints_like(&self.point_on(k, s1.min(b) - a), &block.end);
            }
            out.push(CutPiece {
                block: block.clone(),
                piece,
                to: u1,
            });
        }
        out
    }
}

/// A piece of a programmed block that the motion has played.
#[derive(Clone, Debug, PartialEq)]
pub struct CutPiece {
    /// The whole block.
    pub block: MotionBlock,
    /// The piece, as a block of its own.
    pub piece: MotionBlock,
    /// Fraction of the block's path where the piece ends (1 at its end).
    pub to: f64,
}

/// A slot vector as joints, keeping only the rotary axes `like` has.
/// The block parameter `u` (0 at its start, 1 at its end) at path position `sl` into planned
/// segment `seg` of block `b`: the segment's own fraction where it is the whole block (arcs,
/// unblended lines), else (a line shortened by corner blends) the fraction of the block's
/// length from its start to that point.
fn block_parameter(b: &MotionBlock, seg: &crate::feed::path::Segment, sl: f64) -> f64 {
    let (s0, e0) = (joint_vector(&b.start), joint_vector(&b.end));
    let p = seg.derivatives(sl)[0];
    let (mut along, mut whole) = (0.0, 0.0);
    for i in 0..SLOTS {
        along += (p[i] - s0[i]) * (e0[i] - s0[i]);
        whole += (e0[i] - s0[i]) * (e0[i] - s0[i]);
    }
    if seg.arc().is_some() || !(whole > 0.0) {
        (sl / seg.length).clamp(0.0, 1.0)
    } else {
        (along / whole).clamp(0.0, 1.0)
    }
}

fn joints_like(p: &JointVector, like: &Joints) -> Joints {
    Joints {
        xyz: glam::DVec3::new(p[0], p[1], p[2]),
        a: like.a.map(|_| p[3]),
        b: like.b.map(|_| p[4]),
        c: like.c.map(|_| p[5]),
    }
}

/// The part `[u0, u1]` of a block (fractions of its motion).
#[must_use]
pub fn sub_block(b: &MotionBlock, u0: f64, u1: f64) -> MotionBlock {
    let mut out = b.clone();
    out.start = b.point_at(u0);
    out.end = if u1 >= 1.0 { b.end } else { b.point_at(u1) };
    let frac = (u1 - u0).max(0.0);
    let scale_arc = |a: &crate::gcode::Arc| {
        let mut a = *a;
        a.centre += a.normal * a.normal.dot(out.start.xyz - a.centre);
        a.sweep_rad *= frac;
        a.helix_mm *= frac;
        a
    };
    out.kind = match b.kind {
        MotionKind::ArcCw(a) => MotionKind::ArcCw(scale_arc(&a)),
        MotionKind::ArcCcw(a) => MotionKind::ArcCcw(scale_arc(&a)),
        k => k,
    };
    if out.inverse_time && frac > 0.0 {
        // The same speed over a shorter piece: the inverse time grows with 1/frac.
        out.feed_mm_per_min /= frac;
    }
    out
}
