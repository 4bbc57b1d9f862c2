//! Jog along the tool axis: the pseudo-axis `T` of the jog actions moves the tool tip along
//! the tool's own axis (from the tip toward the spindle) with the rotary axes standing.
//!
//! The direction is found by the machine's forward kinematics: the tool axis in the work
//! (table) frame at the present joints, carried back into machine coordinates by the same
//! rigid map; the linear axes move along it. On the table-tilting machines the tool stands
//! along machine +Z, so the move is a pure Z move whatever the tilt; in the work frame it is
//! the tilted tool axis. A jog that would leave the travel ends where the first linear axis
//! reaches its limit.

use crate::feed::path::JointVector;
use crate::machine::Machine;

/// The pseudo-axis letter of the tool axis in jog actions.
pub const TOOL_AXIS: char = 'T';

/// The target of a jog by `d` mm along the tool axis from `pos`, shortened to the travel,
/// and the axis and limit (mm) it stops at when shortened.
#[must_use]
pub fn tool_axis_target(
    machine: &Machine,
    pos: &JointVector,
    d: f64,
) -> (JointVector, Option<(char, f64)>) {
    let joints = super::collide::machine_joints(machine, pos);
    let (rotation, _) = machine.machine_from_table(&joints);
    let axis_work = machine.forward(&joints).axis;
    let dir = (rotation * axis_work).to_array();
    let mut fraction = 1.0_f64;
    let mut limit = None;
    for (k, name) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        let step = d * dir[k];
        let Some(ax) = machine.axis(name) else {
            continue;
        };
        if step.abs() <= 1e-12 {
            continue;
        }
        let want = pos[k] + step;
        let reach = want.clamp(ax.min, ax.max);
        let f = (reach - pos[k]) / step;
        if f < fraction {
            fraction = f.max(0.0);
            limit = Some((name, reach));
        }
    }
    let mut target = *pos;
    for k in 0..3 {
        target[k] = pos[k] + fraction * d * dir[k];
    }
    if let Some((name, reach)) = limit
        && let Some(k) = crate::feed::path::slot_of(name)
    {
        // The limiting axis lands exactly on its limit.
        target[k] = reach;
    }
    (target, limit)
}
