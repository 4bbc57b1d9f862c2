//! Whether the project's machine can hold the tool axes of a planned path: a 3-axis machine
//! only the vertical axis, a table-tilting 5-axis machine every axis whose angle from +z is a
//! tilt within its tilt axis's travel (the rotary table turns the rest, unlimited or not,
//! as the post's inverse kinematics choose). Checked when an operation is planned, so a
//! 5-axis path for a 3-axis machine is flagged then and not only when it is posted.

use crate::diagnostics::Diagnostic;
use crate::machine::{KinematicsKind, Machine};
use crate::toolpath::{MoveKind, Toolpath};

/// A tilt from +z below this counts as vertical, rad.
const VERTICAL: f64 = 1e-6;

/// The cutting poses whose axis `machine` cannot hold, as one warning naming the machine,
/// how many poses, the largest tilt asked for, the first such pose and the tilt the machine
/// allows; `None` when every pose is reachable.
#[must_use]
pub fn unreachable_axes(toolpath: &Toolpath, machine: &Machine) -> Option<Diagnostic> {
    let (lo, hi) = tilt_range(machine);
    let mut count = 0usize;
    let mut first = None;
    let mut worst: f64 = 0.0;
    for (k, p) in toolpath.poses.iter().enumerate() {
        if p.kind != MoveKind::Cut {
            continue;
        }
        let Some(a) = p.axis.try_normalize() else {
            continue;
        };
        let theta = a.z.clamp(-1.0, 1.0).acos();
        // A tilt of ±θ reaches the axis (the table turns it about z).
        let ok =
            theta <= VERTICAL || (theta >= lo && theta <= hi) || (-theta >= lo && -theta <= hi);
        if !ok {
            count += 1;
            first.get_or_insert(k);
            worst = worst.max(theta);
        }
    }
    let first = first?;
    let allowed = if machine.kinematics == KinematicsKind::ThreeAxis {
        "it has 3 axes: only a vertical tool".to_string()
    } else {
        format!(
            "its tilt axis turns {:.1}° to {:.1}°",
            lo.to_degrees(),
            hi.to_degrees()
        )
    };
    Some(Diagnostic::warning(
        Some(format!("pose {first}")),
        format!(
            "{count} cutting poses tilt the tool up to {:.1}° from vertical, which machine {} \
             cannot reach ({allowed}); the path cannot be posted for this machine",
            worst.to_degrees(),
            machine.name
        ),
    ))
}

/// The tilt axis's travel, rad (`(0, 0)` for a 3-axis machine).
/// The tilt-away limits for a project's machine: the default angle and rate, and at most the
/// tilt axis's travel from vertical on a 5-axis machine (90° where the machine has no tilt axis:
/// such a path is flagged by [`unreachable_axes`] anyway).
#[must_use]
pub fn tilt_away_limits(
    machine: Option<&Machine>,
) -> crate::strategies::finish::tiltaway::TiltAway {
    let mut t = crate::strategies::finish::tiltaway::TiltAway::default();
    if let Some(m) = machine {
        let (lo, hi) = tilt_range(m);
        let reach = lo.abs().max(hi.abs());
        if reach > 0.0 {
            t.max_from_vertical_rad = reach;
        }
    }
    t
}

fn tilt_range(machine: &Machine) -> (f64, f64) {
    let name = match machine.rotary_names() {
        Some((tilt, _)) => tilt,
        None => return (0.0, 0.0),
    };
    machine.axis(name).map_or((0.0, 0.0), |a| (a.min, a.max))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::{Pose, ToolRecord};
    use crate::tools::parse_tool_spec;
    use glam::DVec3;

    fn path(axis: DVec3) -> Toolpath {
        let cutter = parse_tool_spec("ball:d=6").expect("tool");
        let pose = |x: f64| Pose {
            tip: DVec3::new(x, 0.0, 0.0),
            axis,
            kind: MoveKind::Cut,
            cc: None,
            feed_mm_per_min: 1000.0,
            scallop_mm: None,
            contact: None,
        };
        Toolpath::new(
            ToolRecord {
                spec: "ball:d=6".into(),
                cutter,
            },
            vec![pose(0.0), pose(1.0)],
        )
    }

    #[test]
    fn a_tilted_path_is_flagged_on_three_axes_and_not_on_five() {
        let tilted = path(DVec3::new(0.5, 0.0, 1.0).normalize());
        let names = Machine::builtin_names();
        for &name in &names {
            let m = Machine::builtin(name).expect("machine");
            let flagged = unreachable_axes(&tilted, &m);
            if m.kinematics == KinematicsKind::ThreeAxis {
                let d = flagged.expect("a 3-axis machine cannot tilt");
                assert!(d.message.contains("26.6°"), "{}", d.message);
            } else {
                assert!(flagged.is_none(), "{name} tilts 26.6°");
            }
            assert!(unreachable_axes(&path(DVec3::Z), &m).is_none());
        }
        // Upside down is beyond every machine's tilt.
        let m = Machine::builtin(names[0]).expect("machine");
        assert!(unreachable_axes(&path(-DVec3::Z), &m).is_some());
    }
}
