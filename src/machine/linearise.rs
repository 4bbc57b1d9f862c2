//! Linearisation: a controller interpolates the joints linearly between two blocks, so on a
//! 5-axis machine the tool tip leaves the straight line the tool path asks for. Poses are
//! inserted (tip on the straight line, axis on the great circle) until every sub-move stays
//! within a tolerance.

use glam::DVec3;

use super::{Machine, MachineError, MachineJoints, ToolPose};

/// Samples per sub-move when measuring the deviation (interior points).
const SAMPLES: usize = 8;
/// Most poses one move may be split into.
const MAX_POSES: usize = 4096;

/// Joints interpolated linearly, as the controller does.
#[must_use]
pub fn lerp_joints(a: &MachineJoints, b: &MachineJoints, t: f64) -> MachineJoints {
    MachineJoints {
        xyz: a.xyz.lerp(b.xyz, t),
        tilt_rad: a.tilt_rad + (b.tilt_rad - a.tilt_rad) * t,
        rotary_rad: a.rotary_rad + (b.rotary_rad - a.rotary_rad) * t,
    }
}

/// The pose a fraction `t` along the intended move: tip on the straight line, axis on the
/// great circle (normalised linear blend when the axes are opposite).
#[must_use]
pub fn intended_pose(from: &ToolPose, to: &ToolPose, t: f64) -> ToolPose {
    let (a, b) = (from.axis.normalize_or_zero(), to.axis.normalize_or_zero());
    let w = a.cross(b).length().atan2(a.dot(b));
    let axis = if w < 1e-12 || (std::f64::consts::PI - w) < 1e-9 {
        a.lerp(b, t).try_normalize().unwrap_or(a)
    } else {
        (a * ((1.0 - t) * w).sin() + b * (t * w).sin()) / w.sin()
    };
    ToolPose {
        tip: from.tip.lerp(to.tip, t),
        axis,
    }
}

fn point_segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + d * t)
}

impl Machine {
    /// Largest distance (mm) of the tool tip, with joints interpolated linearly from `ja` to
    /// `jb`, from the straight segment between the tips of `from` and `to` (sampled).
    #[must_use]
    pub fn tip_deviation_mm(
        &self,
        ja: &MachineJoints,
        jb: &MachineJoints,
        from: &ToolPose,
        to: &ToolPose,
    ) -> f64 {
        (1..=SAMPLES)
            .map(|k| {
                let t = k as f64 / (SAMPLES + 1) as f64;
                let tip = self.forward(&lerp_joints(ja, jb, t)).tip;
                point_segment_distance(tip, from.tip, to.tip)
            })
            .fold(0.0, f64::max)
    }

    /// The joints for a move from `from` to `to` (starting from the joints `previous`, used
    /// for branch and C-turn choice), with poses inserted until every sub-move's tip stays
    /// within `tolerance_mm` of the straight line. The first entry reaches `from`, the last
    /// `to`.
    ///
    /// # Errors
    /// [`MachineError::BadPose`] for a non-positive tolerance; the errors of
    /// [`Machine::inverse`]; [`MachineError::Unreachable`] when more than 4096 poses would be
    /// needed.
    pub fn linearise(
        &self,
        from: &ToolPose,
        to: &ToolPose,
        previous: &MachineJoints,
        tolerance_mm: f64,
    ) -> Result<Vec<MachineJoints>, MachineError> {
        if !(tolerance_mm > 0.0) || !tolerance_mm.is_finite() {
            return Err(MachineError::BadPose(
                "linearisation tolerance must be positive".into(),
            ));
        }
        // At a singular start C is free: take the C the move heads into, so the first sub-move
        // does not swing C (the caller sees the C change against `previous`).
        let j0 = if self.is_singular(from.axis) {
            let ahead = self.inverse(&intended_pose(from, to, 1e-6), previous)?;
            let seeded = MachineJoints {
                rotary_rad: ahead.rotary_rad,
                ..*previous
            };
            self.inverse(from, &seeded)?
        } else {
            self.inverse(from, previous)?
        };
        let mut out = vec![j0];
        // Stack of (t0, t1) intervals still to emit, processed in order.
        let mut stack = vec![(0.0f64, 1.0f64)];
        let mut last = (0.0f64, j0);
        while let Some((t0, t1)) = stack.pop() {
            let (pa, pb) = (intended_pose(from, to, t0), intended_pose(from, to, t1));
            let jb = self.inverse(&pb, &last.1)?;
            let deviation = self.tip_deviation_mm(&last.1, &jb, &pa, &pb);
            if deviation <= tolerance_mm {
                out.push(jb);
                last = (t1, jb);
            } else if t1 - t0 < 1e-9 {
                return Err(MachineError::Unreachable(format!(
                    "the joints jump near {:.6} of the move (deviation {deviation:.4} mm): a \
                     rotary flip needs a separate safe move",
                    t0
                )));
            } else {
                let tm = 0.5 * (t0 + t1);
                stack.push((tm, t1));
                stack.push((t0, tm));
            }
            if out.len() + stack.len() > MAX_POSES {
                return Err(MachineError::Unreachable(format!(
                    "linearising within {tolerance_mm} mm needs more than {MAX_POSES} poses"
                )));
            }
        }
        debug_assert!((last.0 - 1.0).abs() < 1e-12);
        Ok(out)
    }
}
