//! Forward and inverse kinematics of the machines (see the module docs for the model).

use glam::{DMat3, DVec3};
use std::f64::consts::TAU;

use super::{Axis, KinematicsKind, Machine, MachineError};

/// Joint positions: the linear axes (tool tip in machine coordinates, mm), the tilt axis (A or
/// B) and the rotary table C in rad (both 0 on a 3-axis machine).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MachineJoints {
    /// X, Y, Z in mm.
    pub xyz: DVec3,
    /// A (AC machines) or B (BC machines), rad.
    pub tilt_rad: f64,
    /// C, rad.
    pub rotary_rad: f64,
}

/// A tool pose in table (part) coordinates: the tip and the unit axis from the tip toward the
/// spindle.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ToolPose {
    /// Tool tip, mm.
    pub tip: DVec3,
    /// Unit tool axis.
    pub axis: DVec3,
}

/// `|n_xy|` below this counts as the singular pose (tool along the C axis): C is kept.
const SINGULAR: f64 = 1e-14;

impl Machine {
    fn tilt_rotation(&self, angle: f64) -> DMat3 {
        match self.kinematics {
            KinematicsKind::TableBc => DMat3::from_rotation_y(angle),
            KinematicsKind::TableAc | KinematicsKind::ThreeAxis => DMat3::from_rotation_x(angle),
        }
    }

    fn axis_at(&self, i: usize) -> Option<&Axis> {
        self.axes.get(i)
    }

    /// Table rotation angles (tilt, C) for joint values.
    fn table_angles(&self, j: &MachineJoints) -> (f64, f64) {
        match (self.axis_at(3), self.axis_at(4)) {
            (Some(t), Some(c)) => (t.direction * j.tilt_rad, c.direction * j.rotary_rad),
            _ => (0.0, 0.0),
        }
    }

    /// The rigid map from table coordinates to machine coordinates at these joints:
    /// `p_machine = rotation · p_table + translation`.
    #[must_use]
    pub fn machine_from_table(&self, j: &MachineJoints) -> (DMat3, DVec3) {
        let (t, c) = self.table_angles(j);
        let rt = self.tilt_rotation(t);
        let rc = DMat3::from_rotation_z(c);
        let qc = self.rot_point_mm;
        let qt = qc + self.tilt_offset_mm;
        // T(qt) Rt T(-qt) T(qc) Rc T(-qc) p = Rt Rc p + [Rt (qc - Rc qc - qt) + qt]
        let rotation = rt * rc;
        let translation = rt * (qc - rc * qc - qt) + qt;
        (rotation, translation)
    }

    /// Forward kinematics: joints → tool tip and axis in table (part) coordinates.
    #[must_use]
    pub fn forward(&self, j: &MachineJoints) -> ToolPose {
        let (r, t) = self.machine_from_table(j);
        let inv = r.transpose();
        ToolPose {
            tip: inv * (j.xyz - t),
            axis: inv * DVec3::Z,
        }
    }

    /// Inverse kinematics: the joints reaching `pose`, chosen among both solution branches
    /// and every C turn within the limits for the least rotary travel from `previous`
    /// (|Δtilt| + |ΔC|). At the singular pose (axis along the C axis) C keeps its previous value.
    ///
    /// # Errors
    /// [`MachineError::BadPose`] for a non-finite pose or zero axis;
    /// [`MachineError::Unreachable`] when no solution lies within the axis limits.
    pub fn inverse(
        &self,
        pose: &ToolPose,
        previous: &MachineJoints,
    ) -> Result<MachineJoints, MachineError> {
        let mut c = self.inverse_candidates(pose, previous)?;
        let cost = |j: &MachineJoints| {
            (j.tilt_rad - previous.tilt_rad).abs() + (j.rotary_rad - previous.rotary_rad).abs()
        };
        c.sort_by(|a, b| cost(a).total_cmp(&cost(b)));
        c.into_iter().next().ok_or_else(|| {
            MachineError::Unreachable(format!(
                "tool axis {:?} at tip {:?} is outside the limits of {}",
                pose.axis.to_array(),
                pose.tip.to_array(),
                self.name
            ))
        })
    }

    /// Every solution within the limits: per branch, the C turn nearest `previous` that is
    /// within the limits (empty when the pose is unreachable).
    ///
    /// # Errors
    /// [`MachineError::BadPose`] for a non-finite pose, a zero axis or non-finite `previous`.
    pub fn inverse_candidates(
        &self,
        pose: &ToolPose,
        previous: &MachineJoints,
    ) -> Result<Vec<MachineJoints>, MachineError> {
        if !pose.tip.is_finite() || !pose.axis.is_finite() {
            return Err(MachineError::BadPose("non-finite tip or axis".into()));
        }
        if !previous.xyz.is_finite()
            || !previous.tilt_rad.is_finite()
            || !previous.rotary_rad.is_finite()
        {
            return Err(MachineError::BadPose("non-finite previous joints".into()));
        }
        let n = pose
            .axis
            .try_normalize()
            .ok_or_else(|| MachineError::BadPose("zero tool axis".into()))?;
        let mut out = Vec::new();
        let (Some(tilt_axis), Some(c_axis)) = (self.axis_at(3), self.axis_at(4)) else {
            // Three axes: the axis must be +Z.
            let off = n.truncate().length().atan2(n.z);
            if off > 1e-9 {
                return Err(MachineError::Unreachable(format!(
                    "{} has no rotary axes; tool axis is {:.6}° from +Z",
                    self.name,
                    off.to_degrees()
                )));
            }
            let j = MachineJoints {
                xyz: pose.tip,
                ..MachineJoints::default()
            };
            if self.linear_ok(&j) {
                out.push(j);
            }
            return Ok(out);
        };
        let nxy = n.truncate().length();
        let theta = nxy.atan2(n.z); // tilt magnitude in [0, π]
        for s in [1.0, -1.0] {
            let t = s * theta;
            // v = R_tilt(−t)·e_z, then n_xy = R_z(−c)·v_xy, so c = angle(v) − angle(n).
            let v = self.tilt_rotation(-t) * DVec3::Z;
            let c_table = if nxy < SINGULAR {
                None
            } else {
                Some(v.y.atan2(v.x) - n.y.atan2(n.x))
            };
            let tilt = t * tilt_axis.direction;
            if !tilt_axis.contains(tilt) {
                continue;
            }
            let c_base = c_table.map_or(previous.rotary_rad, |c| c * c_axis.direction);
            let Some(c) = nearest_turn(c_base, previous.rotary_rad, c_axis) else {
                continue;
            };
            let mut j = MachineJoints {
                xyz: DVec3::ZERO,
                tilt_rad: tilt,
                rotary_rad: c,
            };
            let (r, tr) = self.machine_from_table(&j);
            j.xyz = r * pose.tip + tr;
            if self.linear_ok(&j) && !out.contains(&j) {
                out.push(j);
            }
        }
        Ok(out)
    }

    /// Is this tool axis the singular pose (along the C axis, where C is free)? Always false
    /// on a 3-axis machine.
    #[must_use]
    pub fn is_singular(&self, axis: DVec3) -> bool {
        let n = axis.normalize_or_zero();
        self.axes.len() > 3 && n != DVec3::ZERO && n.truncate().length() < SINGULAR
    }

    fn linear_ok(&self, j: &MachineJoints) -> bool {
        j.xyz
            .to_array()
            .iter()
            .enumerate()
            .all(|(i, v)| self.axis_at(i).is_some_and(|a| a.contains(*v)))
    }
}

/// `base + 2πk` nearest `previous` within the axis limits (C unwinding), if any.
#[must_use]
pub(crate) fn nearest_turn(base: f64, previous: f64, axis: &Axis) -> Option<f64> {
    let k0 = ((previous - base) / TAU).round();
    if !k0.is_finite() || k0.abs() > 1e6 {
        return None;
    }
    let mut best: Option<f64> = None;
    for dk in [0.0, -1.0, 1.0, -2.0, 2.0] {
        let c = base + (k0 + dk) * TAU;
        if axis.contains(c) && best.is_none_or(|b| (c - previous).abs() < (b - previous).abs()) {
            best = Some(c);
        }
    }
    if best.is_none() {
        // Far from the previous value: any turn within the limits, nearest the previous.
        let k = ((axis.min - base) / TAU).ceil();
        let c = base + k * TAU;
        if k.is_finite() && axis.contains(c) {
            best = Some(c);
        }
    }
    best
}
