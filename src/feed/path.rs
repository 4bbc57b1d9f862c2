//! Step 2a: the program as a path in joint space, parameterised by length, with the bounds on
//! the derivatives of every axis along the path and the tangential limits they imply.
//!
//! For an axis `q_i(s)` along a block, with path speed `v`, acceleration `a`, jerk `j`:
//! `q̇ = q'·v`, `q̈ = q'·a + q''·v²`, `q⃛ = q'·j + 3·q''·v·a + q'''·v³`. With bounds
//! `|q'| ≤ d1`, `|q''| ≤ d2`, `|q'''| ≤ d3` over the block, the tangential limits
//! `(v_b, a_b, j_b)` chosen in [`Segment::new`] satisfy `d1·v_b ≤ V`, `d1·a_b + d2·v_b² ≤ A`,
//! `d1·j_b + 3·d2·v_b·a_b + d3·v_b³ ≤ J` for every axis, so any motion with `v ≤ v_b`,
//! `|a| ≤ a_b`, `|j| ≤ j_b` keeps every axis within its limits inside the block (triangle
//! inequality). Junctions are handled by the look-ahead (stop, or a = 0 on smooth joins).

use glam::DVec3;

use crate::gcode::{Joints, MotionBlock, MotionKind};

/// Number of joint slots: X Y Z A B C.
pub const SLOTS: usize = 6;

/// A joint-space vector indexed X Y Z A B C (mm, rad).
pub type JointVector = [f64; SLOTS];

/// Joint slot of an axis letter.
#[must_use]
pub fn slot_of(name: char) -> Option<usize> {
    "XYZABC".find(name.to_ascii_uppercase())
}

/// Joints as a slot vector (missing rotary axes read 0).
#[must_use]
pub fn joint_vector(j: &Joints) -> JointVector {
    [
        j.xyz.x,
        j.xyz.y,
        j.xyz.z,
        j.a.unwrap_or(0.0),
        j.b.unwrap_or(0.0),
        j.c.unwrap_or(0.0),
    ]
}

/// Per-axis limits in slot order (`None`: the machine has no such axis; it must not move).
pub type AxisLimits = [Option<super::AxisLimit>; SLOTS];

/// What caps a block's velocity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "kind", content = "axis")]
pub enum VelocityCap {
    /// The programmed feed (or inverse-time duration).
    Feed,
    /// An axis's velocity limit projected on the tangent.
    AxisVelocity(char),
    /// Centripetal acceleration of an axis on a curved block.
    Centripetal(char),
    /// Centripetal jerk (v³·|q'''|) of an axis on a curved block.
    CentripetalJerk(char),
    /// The optional tangential path limit.
    Path,
}

/// One block as a path segment.
///
/// Kept small (the planner stores one per planned segment): the geometry is one enum
/// (a line's start and change, a corner blend's corner, directions and size, or a boxed arc).
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// Index of the block in the program (the first, for a run of blocks merged into one line).
    pub block: usize,
    /// Index of the last block the segment runs through: `block` itself, except for a run of
    /// short blocks merged into one line within the tolerance (see `feed::merge`).
    pub last_block: usize,
    /// Path length (mm; rad for rotary-only blocks).
    pub length: f64,
    /// Tangential limits valid over the whole block.
    pub limits: super::Limits1,
    /// What caps the velocity.
    pub cap: VelocityCap,
    /// The geometry.
    shape: Shape,
}

/// The geometry of a segment.
#[derive(Clone, Debug, PartialEq)]
enum Shape {
    /// Joints linear in the path length: start joints and the change over the segment.
    Line {
        start: JointVector,
        delta: JointVector,
    },
    /// An arc (rare; boxed so that lines and blends stay small): the joints' linear part
    /// (rotary axes, and the chord for reference) and the arc's frame in X Y Z.
    Arc(Box<ArcShape>),
    /// A corner blend.
    Blend(super::blend::BlendCurve),
}

/// An arc segment's data.
#[derive(Clone, Debug, PartialEq)]
struct ArcShape {
    start: JointVector,
    delta: JointVector,
    frame: ArcFrame,
}

/// The frame of an arc segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcFrame {
    /// Centre.
    pub centre: DVec3,
    /// Unit vector from the centre to the start (in the plane), times the radius.
    pub r1: DVec3,
    /// The in-plane vector 90° ahead in the direction of motion, times the radius.
    pub r2: DVec3,
    /// Angle per unit path length (rad/mm).
    pub omega: f64,
    /// Normal travel per unit path length.
    pub rise: DVec3,
}

impl Segment {
    /// Build the segment of `block` (index `index`) under `axes` and the optional path limit;
    /// `None` for a block with no length.
    #[must_use]
    pub fn new(
        index: usize,
        block: &MotionBlock,
        axes: &AxisLimits,
        path: Option<super::Limits1>,
    ) -> Option<Self> {
        let start = joint_vector(&block.start);
        let end = joint_vector(&block.end);
        let mut delta = [0.0; SLOTS];
        for k in 0..SLOTS {
            delta[k] = end[k] - start[k];
        }
        let xyz_len = block.length_mm();
        let rot_len = delta[3..].iter().map(|d| d * d).sum::<f64>().sqrt();
        let length = if xyz_len > 1e-12 { xyz_len } else { rot_len };
        if !(length > 1e-12) || !length.is_finite() {
            return None;
        }
        let arc = block.kind.arc().map(|a| {
            let sign = if matches!(block.kind, MotionKind::ArcCw(_)) {
                -1.0
            } else {
                1.0
            };
            let r0 = block.start.xyz - a.centre;
            let r1 = r0 - a.normal * r0.dot(a.normal);
            ArcFrame {
                centre: a.centre,
                r1,
                r2: a.normal.cross(r1) * sign,
                omega: a.sweep_rad / length,
                rise: a.normal * (a.helix_mm / length),
            }
        });
        // Derivative bounds per slot.
        let mut d1 = [0.0; SLOTS];
        let mut d2 = [0.0; SLOTS];
        let mut d3 = [0.0; SLOTS];
        for k in 0..SLOTS {
            d1[k] = (delta[k] / length).abs();
        }
        if let Some(f) = &arc {
            let r = f.r1.length();
            for k in 0..3 {
                let inplane = f.r1[k].hypot(f.r2[k]) / r.max(1e-300);
                d1[k] = (r * f.omega * inplane + f.rise[k].abs()).min(1.0);
                d2[k] = r * f.omega * f.omega * inplane;
                d3[k] = r * f.omega.powi(3) * inplane;
            }
        }
        let feed = if let Some(t) = block.inverse_time_duration_s() {
            length / t
        } else if matches!(block.kind, MotionKind::Rapid) || block.feed_mm_per_min <= 0.0 {
            f64::INFINITY
        } else {
            block.feed_mm_per_min / 60.0
        };
        let (limits, cap) = if arc.is_some() {
            tangential_limits(&[d1, d2, d3], feed, axes, path, Share::BLOCK)?
        } else {
            line_limits(&d1, feed, axes, path)?
        };
        let shape = match arc {
            Some(frame) => Shape::Arc(Box::new(ArcShape {
                start,
                delta,
                frame,
            })),
            None => Shape::Line { start, delta },
        };
        Some(Self {
            block: index,
            last_block: index,
            length,
            limits,
            cap,
            shape,
        })
    }

    /// Start joints (for a blend, its start point in X Y Z).
    #[must_use]
    pub fn start(&self) -> JointVector {
        match &self.shape {
            Shape::Line { start, .. } => *start,
            Shape::Arc(a) => a.start,
            Shape::Blend(b) => {
                let p = b.start();
                [p.x, p.y, p.z, 0.0, 0.0, 0.0]
            }
        }
    }

    /// Joint change from the start to the end (for an arc, the chord).
    #[must_use]
    // One index walks several parallel arrays; an iterator chain would hide that.
    #[allow(clippy::needless_range_loop)]
    pub fn delta(&self) -> JointVector {
        match &self.shape {
            Shape::Line { delta, .. } => *delta,
            Shape::Arc(a) => a.delta,
            Shape::Blend(b) => {
                let (p, q) = (b.start(), b.end());
                let (start, end) = (
                    [p.x, p.y, p.z, 0.0, 0.0, 0.0],
                    [q.x, q.y, q.z, 0.0, 0.0, 0.0],
                );
                let mut delta = [0.0; SLOTS];
                for k in 0..SLOTS {
                    delta[k] = end[k] - start[k];
                }
                delta
            }
        }
    }

    /// The arc's frame, for an arc segment.
    #[must_use]
    pub fn arc(&self) -> Option<&ArcFrame> {
        match &self.shape {
            Shape::Arc(a) => Some(&a.frame),
            _ => None,
        }
    }

    /// A straight segment's joint direction `q'` (the same at every `s`, with `q'' = q''' =
    /// 0`: the first derivatives [`Segment::derivatives`] gives); `None` for arcs and blends.
    #[must_use]
    pub fn line_direction(&self) -> Option<JointVector> {
        let Shape::Line { delta, .. } = &self.shape else {
            return None;
        };
        let mut d = [0.0; SLOTS];
        for (out, dk) in d.iter_mut().zip(delta) {
            *out = dk / self.length;
        }
        Some(d)
    }

    /// The corner blend this segment is, if it is one.
    #[must_use]
    pub fn blend(&self) -> Option<&super::blend::BlendCurve> {
        match &self.shape {
            Shape::Blend(b) => Some(b),
            _ => None,
        }
    }

    /// The straight piece `[from, to]` (path lengths) of a straight segment: the part a corner
    /// blend leaves; `None` if it is empty or the segment is not straight.
    #[must_use]
    // One index walks several parallel arrays; an iterator chain would hide that.
    #[allow(clippy::needless_range_loop)]
    pub fn straight_piece(&self, from: f64, to: f64) -> Option<Self> {
        let Shape::Line {
            start: s0,
            delta: d0,
        } = &self.shape
        else {
            return None;
        };
        if !(to - from > 1e-12) {
            return None;
        }
        let mut start = *s0;
        let mut delta = *d0;
        for k in 0..SLOTS {
            let dir = d0[k] / self.length;
            start[k] = s0[k] + dir * from;
            delta[k] = dir * (to - from);
        }
        Some(Self {
            length: to - from,
            shape: Shape::Line { start, delta },
            ..*self
        })
    }

    /// The segment of a corner blend whose limits are already known (see [`blend_limits_at`]).
    #[must_use]
    pub fn blend_segment(
        block: usize,
        blend: super::blend::ClothoidBlend,
        limits: super::Limits1,
        cap: VelocityCap,
    ) -> Self {
        Self {
            block,
            last_block: block,
            length: blend.length(),
            limits,
            cap,
            shape: Shape::Blend(blend.curve()),
        }
    }

    /// The straight segment from `start` to `end` (joints linear in the X Y Z length) for blocks
    /// `first..=last` merged into one, at the path speed `feed` (mm/s); `None` where it has no
    /// X Y Z length or an axis the machine lacks would move.
    #[must_use]
    // One index walks several parallel arrays; an iterator chain would hide that.
    #[allow(clippy::needless_range_loop)]
    pub fn merged_line(
        (first, last): (usize, usize),
        start: JointVector,
        end: JointVector,
        feed: f64,
        axes: &AxisLimits,
        path: Option<super::Limits1>,
    ) -> Option<Self> {
        let mut delta = [0.0; SLOTS];
        for k in 0..SLOTS {
            delta[k] = end[k] - start[k];
        }
        let length = (delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2]).sqrt();
        if !(length > 1e-12 && length.is_finite()) {
            return None;
        }
        let mut d1 = [0.0; SLOTS];
        for k in 0..SLOTS {
            d1[k] = (delta[k] / length).abs();
        }
        let (limits, cap) = line_limits(&d1, feed, axes, path)?;
        Some(Self {
            block: first,
            last_block: last,
            length,
            limits,
            cap,
            shape: Shape::Line { start, delta },
        })
    }

    /// Whether the segment is a plain straight line (not an arc or a blend).
    #[must_use]
    pub fn is_line(&self) -> bool {
        matches!(self.shape, Shape::Line { .. })
    }

    /// A straight segment moving only X, Y, Z: its unit direction.
    #[must_use]
    pub fn straight_xyz_direction(&self) -> Option<DVec3> {
        let Shape::Line { delta, .. } = &self.shape else {
            return None;
        };
        let rot = delta[3..].iter().any(|d| *d != 0.0);
        (!rot).then(|| DVec3::new(delta[0], delta[1], delta[2]) / self.length)
    }

    /// Joint position and its first three derivatives with respect to path length at `s`.
    #[must_use]
    // One index walks several parallel arrays; an iterator chain would hide that.
    #[allow(clippy::needless_range_loop)]
    pub fn derivatives(&self, s: f64) -> [JointVector; 4] {
        let (start, delta, frame) = match &self.shape {
            Shape::Blend(b) => return b.derivatives(s),
            Shape::Line { start, delta } => (start, delta, None),
            Shape::Arc(a) => (&a.start, &a.delta, Some(&a.frame)),
        };
        let u = (s / self.length).clamp(0.0, 1.0);
        let mut out = [[0.0; SLOTS]; 4];
        for k in 0..SLOTS {
            out[0][k] = start[k] + delta[k] * u;
            out[1][k] = delta[k] / self.length;
        }
        if let Some(f) = frame {
            let th = f.omega * s.clamp(0.0, self.length);
            let (sn, cs) = th.sin_cos();
            let w = f.omega;
            let p = f.centre + f.r1 * cs + f.r2 * sn + f.rise * s.clamp(0.0, self.length);
            let d1 = (f.r2 * cs - f.r1 * sn) * w + f.rise;
            let d2 = -(f.r1 * cs + f.r2 * sn) * (w * w);
            let d3 = (f.r1 * sn - f.r2 * cs) * (w * w * w);
            for k in 0..3 {
                out[0][k] = p[k];
                out[1][k] = d1[k];
                out[2][k] = d2[k];
                out[3][k] = d3[k];
            }
        }
        out
    }

    /// Unit-free tangent `q'` at the start (`at_end == false`) or the end.
    #[must_use]
    pub fn tangent(&self, at_end: bool) -> JointVector {
        self.derivatives(if at_end { self.length } else { 0.0 })[1]
    }
}

/// The terms of a corner blend's velocity bound under the axes (see [`BoundTerms`]), from
/// which [`blend_velocity`] weighs it and its shrunk copies; `None` when an axis the machine
/// lacks would move.
#[must_use]
#[inline]
pub fn blend_terms(blend: &super::blend::ClothoidBlend, axes: &AxisLimits) -> Option<BoundTerms> {
    BoundTerms::of(&blend.derivative_bounds(), axes, Share::BLEND)
}

/// The velocity bound alone of a blend's tangential limits (the same value and cap as
/// `tangential_limits` with the blend's share) from the blend's
/// terms ([`blend_terms`]), or from those of a blend `4^shrunk` times its size, for weighing candidate blends before the tangential acceleration and jerk of the
/// chosen one are taken ([`blend_limits_at`]); `None` where it is not finite and positive.
/// Where it is, `blend_limits_at` gives valid limits: the shares leave
/// `a_b ≥ (1 − share)·A/d1` and `j_b ≥ (1 − share)/2·J/d1` (the construction in the module
/// docs), and a blend's `d1` is not zero on every axis.
#[must_use]
#[inline]
pub fn blend_velocity(
    terms: &BoundTerms,
    shrunk: u32,
    feed: f64,
    path: Option<super::Limits1>,
) -> Option<(f64, VelocityCap)> {
    let (velocity, cap) = terms.bound_shrunk(shrunk, feed, path);
    (velocity.is_finite() && velocity > 0.0).then_some((velocity, cap))
}

/// The tangential limits of a blend already weighed by [`blend_velocity`] (the same limits, without
/// taking the velocity bound again).
#[must_use]
#[inline]
pub fn blend_limits_at(
    blend: &super::blend::ClothoidBlend,
    weighed: (f64, VelocityCap),
    axes: &AxisLimits,
    path: Option<super::Limits1>,
) -> Option<(super::Limits1, VelocityCap)> {
    limits_at(
        &blend.derivative_bounds(),
        weighed,
        axes,
        path,
        Share::BLEND,
    )
}

/// Shares of the axis acceleration and jerk limits given to the curvature terms.
#[derive(Clone, Copy, Debug)]
struct Share {
    acceleration: f64,
    jerk: f64,
}

impl Share {
    /// Program blocks (arcs): half the acceleration, a third of the jerk.
    const BLOCK: Self = Self {
        acceleration: 0.5,
        jerk: 1.0 / 3.0,
    };
    /// Corner blends: 80 % of both.
    const BLEND: Self = Self {
        acceleration: 0.8,
        jerk: 0.8,
    };
}

/// The velocity bound of [`tangential_limits`] and what sets it: the least of the feed, the
/// path limit and, per axis, `V/d1`, `sqrt(share·A/d2)` and `cbrt(share·J/d3)`, the cap being the
/// first of these (in that order, axis by axis) that equals the least. `None` when an axis the
/// machine lacks would move.
fn velocity_bound(
    bounds: &[JointVector; 3],
    feed: f64,
    axes: &AxisLimits,
    path: Option<super::Limits1>,
    share: Share,
) -> Option<(f64, VelocityCap)> {
    Some(BoundTerms::of(bounds, axes, share)?.bound(feed, path))
}

/// The per-axis terms of a velocity bound (see [`blend_velocity`]): `V/d1`, the square
/// `share·A/d2` of the centripetal term and the cube `share·J/d3` of the centripetal-jerk term,
/// `∞` where the bound on that derivative is 0 or the machine lacks the axis.
///
/// A corner blend shrunk by `2^−2k` in size has `d1` unchanged, `d2` times `4^k` and `d3`
/// times `16^k` (exactly: every factor is a power of two), so its terms are these with the
/// squares times `4^−k` and the cubes times `16^−k`, again exactly ([`blend_velocity`]).
#[derive(Clone, Copy, Debug)]
pub struct BoundTerms {
    velocity: JointVector,
    squared: JointVector,
    cubed: JointVector,
    /// The slots after the last one with a finite term have none.
    slots: usize,
}

impl BoundTerms {
    /// The terms of `bounds` under `axes`; `None` when an axis the machine lacks would move.
    fn of(bounds: &[JointVector; 3], axes: &AxisLimits, share: Share) -> Option<Self> {
        let [d1, d2, d3] = bounds;
        let mut terms = Self {
            velocity: [f64::INFINITY; SLOTS],
            squared: [f64::INFINITY; SLOTS],
            cubed: [f64::INFINITY; SLOTS],
            slots: 0,
        };
        for (k, lim) in axes.iter().enumerate() {
            match lim {
                Some(l) => {
                    if d1[k] > 0.0 || d2[k] > 0.0 || d3[k] > 0.0 {
                        terms.slots = k + 1;
                    }
                    if d1[k] > 0.0 {
                        terms.velocity[k] = l.velocity / d1[k];
                    }
                    if d2[k] > 0.0 {
                        terms.squared[k] = share.acceleration * l.acceleration / d2[k];
                    }
                    if d3[k] > 0.0 {
                        terms.cubed[k] = share.jerk * l.jerk / d3[k];
                    }
                }
                None => {
                    if d1[k] > 0.0 {
                        return None;
                    }
                }
            }
        }
        Some(terms)
    }

    /// The bound and what sets it.
    ///
    /// The cube root is monotone, so the least jerk term is the cube root of the least cube:
    /// one `cbrt` instead of one per axis, except where another axis's cube is so close that
    /// its root may round to the same value (then it is evaluated, to find the first axis).
    fn bound(&self, feed: f64, path: Option<super::Limits1>) -> (f64, VelocityCap) {
        self.bound_shrunk(0, feed, path)
    }

    /// [`BoundTerms::bound`] of the same blend shrunk by `4^−k` in size (`k` ≤ 8): the squares
    /// times `4^−k`, the cubes times `16^−k` (exact).
    fn bound_shrunk(&self, k: u32, feed: f64, path: Option<super::Limits1>) -> (f64, VelocityCap) {
        let scale_sq = f64::from_bits((1023 - 2 * u64::from(k.min(8))) << 52);
        let scale_cu = scale_sq * scale_sq;
        let slots = self.slots.min(SLOTS);
        let least_ratio = self.cubed[..slots]
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            * scale_cu;
        // Straight segments have no jerk term (and no root to take).
        let least_root = if least_ratio < f64::INFINITY {
            super::profile::cbrt(least_ratio)
        } else {
            f64::INFINITY
        };
        // A ratio this close above the least may have the same cube root.
        let near = least_ratio * (1.0 + 1e-12);
        // The bound so far and what sets it (which term, on which slot); a value lowers it only
        // if strictly less.
        let (mut v_b, mut why, mut slot) = (f64::INFINITY, Term::Feed, 0);
        if feed < v_b {
            v_b = feed;
        }
        if let Some(p) = path
            && p.velocity < v_b
        {
            (v_b, why) = (p.velocity, Term::Path);
        }
        for k in 0..slots {
            if self.velocity[k] < v_b {
                (v_b, why, slot) = (self.velocity[k], Term::Velocity, k);
            }
            // A root is skipped where its radicand is above the bound's power by a margin
            // that covers the rounding of both (and the cube root's error below an ulp): the
            // root is then at least the bound and could not lower it.
            let squared = self.squared[k] * scale_sq;
            if !(squared >= v_b * v_b * (1.0 + 1e-14)) {
                let root = squared.sqrt();
                if root < v_b {
                    (v_b, why, slot) = (root, Term::Centripetal, k);
                }
            }
            let cubed = self.cubed[k] * scale_cu;
            if !(cubed >= v_b * v_b * v_b * (1.0 + 1e-12)) {
                // Terms above the least root cannot lower the bound below it.
                let root = if cubed == least_ratio {
                    least_root
                } else if cubed <= near {
                    super::profile::cbrt(cubed)
                } else {
                    continue;
                };
                if root < v_b {
                    (v_b, why, slot) = (root, Term::CentripetalJerk, k);
                }
            }
        }
        let name = "XYZABC".as_bytes()[slot] as char;
        let cap = match why {
            Term::Feed => VelocityCap::Feed,
            Term::Path => VelocityCap::Path,
            Term::Velocity => VelocityCap::AxisVelocity(name),
            Term::Centripetal => VelocityCap::Centripetal(name),
            Term::CentripetalJerk => VelocityCap::CentripetalJerk(name),
        };
        (v_b, cap)
    }
}

/// Which term of a velocity bound sets it (see [`BoundTerms::bound`]).
#[derive(Clone, Copy)]
enum Term {
    Feed,
    Path,
    Velocity,
    Centripetal,
    CentripetalJerk,
}

/// Tangential limits `(v_b, a_b, j_b)` and the velocity cap from per-axis bounds
/// `[|q'|, |q''|, |q'''|]` over a segment (see the module docs); `None` when an axis the machine
/// lacks would move or the limits degenerate.
///
/// `share` is the part of each axis's acceleration and jerk given to the path's curvature
/// (`d2·v²` and `d3·v³`): 1/2 and 1/3 for program blocks, which must also change speed along
/// their length; more for corner blends, which are short and passed near their cap (what is
/// left still gives positive tangential limits: `a_b ≥ (1 − share)·A/d1`,
/// `j_b ≥ (1 − share − (1 − share)/2)·J/d1`).
fn tangential_limits(
    bounds: &[JointVector; 3],
    feed: f64,
    axes: &AxisLimits,
    path: Option<super::Limits1>,
    share: Share,
) -> Option<(super::Limits1, VelocityCap)> {
    let bound = velocity_bound(bounds, feed, axes, path, share)?;
    limits_at(bounds, bound, axes, path, share)
}

/// [`tangential_limits`] given its velocity bound and cap.
fn limits_at(
    bounds: &[JointVector; 3],
    (v_b, cap): (f64, VelocityCap),
    axes: &AxisLimits,
    path: Option<super::Limits1>,
    share: Share,
) -> Option<(super::Limits1, VelocityCap)> {
    let [d1, d2, d3] = bounds;
    let mut a_b = path.map_or(f64::INFINITY, |p| p.acceleration);
    for (k, lim) in axes.iter().enumerate() {
        if let Some(l) = lim {
            if d1[k] > 0.0 {
                a_b = a_b.min((l.acceleration - d2[k] * v_b * v_b) / d1[k]);
            }
            if d2[k] > 0.0 {
                // 3·d2·v·a ≤ (1 − share)·J/2 leaves the same again for the tangential jerk.
                a_b = a_b.min((1.0 - share.jerk) * l.jerk / (6.0 * d2[k] * v_b));
            }
        }
    }
    let mut j_b = path.map_or(f64::INFINITY, |p| p.jerk);
    for (k, lim) in axes.iter().enumerate() {
        if let Some(l) = lim
            && d1[k] > 0.0
        {
            j_b = j_b.min((l.jerk - 3.0 * d2[k] * v_b * a_b - d3[k] * v_b.powi(3)) / d1[k]);
        }
    }
    let limits = super::Limits1 {
        velocity: v_b,
        acceleration: a_b,
        jerk: j_b,
    };
    limits.is_valid().then_some((limits, cap))
}

/// [`tangential_limits`] of a straight segment (`d2 = d3 = 0`): the same values, without the
/// curvature terms, which are exactly 0 (`A − 0·v² = A`, `J − 0 − 0 = J`).
fn line_limits(
    d1: &JointVector,
    feed: f64,
    axes: &AxisLimits,
    path: Option<super::Limits1>,
) -> Option<(super::Limits1, VelocityCap)> {
    let mut bound = (f64::INFINITY, VelocityCap::Feed);
    if feed < bound.0 {
        bound = (feed, VelocityCap::Feed);
    }
    let mut a_b = f64::INFINITY;
    let mut j_b = f64::INFINITY;
    if let Some(p) = path {
        if p.velocity < bound.0 {
            bound = (p.velocity, VelocityCap::Path);
        }
        a_b = p.acceleration;
        j_b = p.jerk;
    }
    for (k, lim) in axes.iter().enumerate() {
        match lim {
            Some(l) => {
                if d1[k] > 0.0 {
                    let v = l.velocity / d1[k];
                    if v < bound.0 {
                        bound = (v, VelocityCap::AxisVelocity("XYZABC".as_bytes()[k] as char));
                    }
                    a_b = a_b.min(l.acceleration / d1[k]);
                    j_b = j_b.min(l.jerk / d1[k]);
                }
            }
            None => {
                if d1[k] > 0.0 {
                    return None;
                }
            }
        }
    }
    let limits = super::Limits1 {
        velocity: bound.0,
        acceleration: a_b,
        jerk: j_b,
    };
    limits.is_valid().then_some((limits, bound.1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feed::AxisLimit;
    use crate::feed::blend::ClothoidBlend;
    use crate::test_uniform as uniform;

    fn axes(r: &mut impl FnMut() -> f64) -> AxisLimits {
        let mut axes = [None; SLOTS];
        for a in axes.iter_mut().take(3) {
            *a = Some(AxisLimit {
                velocity: 10.0 + 1000.0 * r(),
                acceleration: 100.0 + 5000.0 * r(),
                jerk: 1e3 + 1e5 * r(),
            });
        }
        axes
    }

    /// The scaled terms give every shrunk candidate the bound and cap its own derivative
    /// bounds give, bit for bit, and a line's limits are those of the general construction.
    #[test]
    fn shrunk_terms_and_line_limits_are_the_general_ones() {
        let mut r = uniform(19);
        for _ in 0..2000 {
            let axes = axes(&mut r);
            let mut unit =
                || glam::DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize_or(glam::DVec3::X);
            let (t0, t1) = (unit(), unit());
            let feed = 5.0 + 100.0 * r();
            let Some(first) = ClothoidBlend::new(glam::DVec3::ZERO, t0, t1, 0.05, 0.5 * r()) else {
                continue;
            };
            let base = first.deviation / first.deviation_unit();
            let terms = blend_terms(&first.with_half_length(base), &axes).unwrap();
            let mut deviation = first.deviation;
            for k in 1..6_u32 {
                deviation *= 0.25;
                let c = first.shrunk_to(deviation).unwrap();
                assert_eq!(c.half_length, base * 0.25_f64.powi(k as i32));
                let own = blend_terms(&c, &axes).unwrap();
                assert_eq!(
                    blend_velocity(&terms, k, feed, None),
                    blend_velocity(&own, 0, feed, None)
                );
            }
            let d1 = [t0.x.abs(), t0.y.abs(), t0.z.abs(), 0.0, 0.0, 0.0];
            let path = (r() < 0.5).then(|| super::super::Limits1 {
                velocity: 50.0 * r() + 1.0,
                acceleration: 1000.0 * r() + 1.0,
                jerk: 1e4 * r() + 1.0,
            });
            let zero = [0.0; SLOTS];
            assert_eq!(
                line_limits(&d1, feed, &axes, path),
                tangential_limits(&[d1, zero, zero], feed, &axes, path, Share::BLOCK)
            );
        }
    }
}
