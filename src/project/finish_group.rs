//! Face groups and tilt-away in the project: a finishing operation over several faces of the
//! part ([`crate::strategies::finish::group::plan_group`]: each face inside its trimming loops, the
//! paths joined in the operation's order at one clearance), its tilt-away settings, and the
//! remaining gouges and collisions of a computed path as a list ([`findings`]) that the
//! workstation shows and jumps to.

use glam::DVec3;

use super::computed::{ComputeError, Computed};
use super::{Operation, Project};
use crate::checks::part::PartCheck;
use crate::import::Workpiece;
use crate::machine::Machine;
use crate::strategies::finish::group::plan_group;
use crate::strategies::finish::tiltaway::{PartContext, TiltAway};
use crate::toolpath::ToolRecord;
use crate::tools::solid::ToolPart;

/// How a finishing operation tilts the tool away from the part's other faces where the flutes,
/// shank or holder would enter them. The largest angle from vertical is the project machine's
/// tilt travel.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct TiltAwaySettings {
    /// Tilt at all (off: the whole part is only checked; every hit is reported).
    pub enabled: bool,
    /// Largest tilt from the planned axis, rad (0: leave out and report, never tilt).
    pub max_angle_rad: f64,
    /// Largest rate of the tilt along the path, rad per mm.
    pub rate_rad_per_mm: f64,
    /// Largest tilt where no tilt within `max_angle_rad` frees the tool (the wall of a hole
    /// whose far side the flutes reach, a pin between plates), rad; 0 (the default): never
    /// beyond `max_angle_rad`, such spans are left out and reported.
    pub steep_angle_rad: f64,
}

impl Default for TiltAwaySettings {
    /// On, 30° at most, 2° per mm, never beyond.
    fn default() -> Self {
        let t = TiltAway::default();
        Self {
            enabled: true,
            max_angle_rad: t.max_angle_rad,
            rate_rad_per_mm: t.rate_rad_per_mm,
            steep_angle_rad: 0.0,
        }
    }
}

impl TiltAwaySettings {
    /// The planner's limits on `machine` (its tilt travel), `None` when off. Where no tilt
    /// within the angle frees the tool (a hole's wall, a pin between plates), the planner tilts
    /// further only up to `steep_angle_rad` (issue 35: the steep fallback once went to 90°
    /// whatever the operation's largest tilt said, and a blade face's path reached 88°).
    #[must_use]
    pub fn limits(&self, machine: Option<&Machine>) -> Option<TiltAway> {
        self.enabled.then(|| TiltAway {
            max_angle_rad: self.max_angle_rad,
            rate_rad_per_mm: self.rate_rad_per_mm,
            steep_angle_rad: self.steep_angle_rad,
            ..super::reach::tilt_away_limits(machine)
        })
    }
}

/// Check a finishing operation's group and tilt-away numbers, in words with units.
///
/// # Errors
/// A face named twice, or a tilt limit out of range.
pub fn validate(face: usize, group: &[usize], tilt: &TiltAwaySettings) -> Result<(), String> {
    let mut seen = vec![face];
    for &g in group {
        if seen.contains(&g) {
            return Err(format!("face {g} is named twice in the face group"));
        }
        seen.push(g);
    }
    let steep = tilt.steep_angle_rad.to_degrees();
    if !(steep.is_finite() && (0.0..=90.0).contains(&steep)) {
        return Err(format!(
            "the steep tilt must lie between 0° and 90°, got {steep:.2}°"
        ));
    }
    let deg = tilt.max_angle_rad.to_degrees();
    if !(deg.is_finite() && (0.0..=90.0).contains(&deg)) {
        return Err(format!(
            "the tilt-away angle must lie between 0° and 90°, got {deg:.2}°"
        ));
    }
    let rate = tilt.rate_rad_per_mm.to_degrees();
    if !(rate.is_finite() && rate > 0.0 && rate <= 90.0) {
        return Err(format!(
            "the tilt-away rate must lie in (0, 90] °/mm, got {rate:.3} °/mm"
        ));
    }
    Ok(())
}

/// Plan a finishing operation whose group is not empty: its faces in order, the group left
/// out of the whole-part check, the tool tilting away within the operation's settings.
pub(crate) fn compute_group(
    project: &Project,
    op: &Operation,
    part: &Workpiece,
    tool: &ToolRecord,
) -> Result<Computed, ComputeError> {
    let Operation::Finish {
        strategy,
        options,
        tilt_away,
        ..
    } = op
    else {
        return Err(plan_err(op, "not a face-finishing operation".into()));
    };
    let faces = op.faces();
    let Some(brep) = part.part.as_ref() else {
        return Err(ComputeError::Face {
            operation: op.name().to_string(),
            message: format!(
                "the part {} is a mesh without exact faces (a face group needs a STEP part)",
                part.source.display()
            ),
        });
    };
    let bvh = part.bvh().ok();
    let machine = Machine::resolve(&project.machine).ok();
    let context = bvh.as_deref().map(|b| PartContext {
        check: PartCheck::of_workpiece(part, b, &faces),
        tilt: tilt_away.limits(machine.as_ref()),
    });
    let r = plan_group(
        brep,
        &faces,
        &tool.cutter,
        &tool.spec,
        *strategy,
        options,
        context.as_ref(),
    )
    .map_err(|(k, e)| plan_err(op, format!("face {k}: {e}")))?;
    Ok(Computed {
        passes: r.passes,
        lead_rad: None,
        clearance_mm: Some(r.clearance),
        toolpath: r.toolpath,
        diagnostics: r.diagnostics,
        part_hits: r.part_hits,
        left_out: r.left_out,
    })
}

fn plan_err(op: &Operation, message: String) -> ComputeError {
    ComputeError::Plan {
        operation: op.name().to_string(),
        message,
    }
}

/// What a finding is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FindingKind {
    /// The tool (the part named) enters another face of the part.
    Collision(ToolPart),
    /// A span the tilt-away left out (no allowed tilt frees the tool), with its length, mm.
    LeftOut(ToolPart, f64),
    /// The deepest gouge the exact check left in the drive face.
    Gouge,
}

/// One remaining gouge or collision of a computed path, with the pose to show it at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Finding {
    /// What it is.
    pub kind: FindingKind,
    /// The pose to jump to (index into the path's poses).
    pub pose: usize,
    /// Where it is, mm.
    pub point: DVec3,
    /// Depth, mm.
    pub depth_mm: f64,
    /// The face it is on, when known.
    pub face: Option<usize>,
}

impl Finding {
    /// One line for a list: what, how deep, where, which face.
    #[must_use]
    pub fn label(&self) -> String {
        let face = self.face.map_or_else(String::new, |f| format!(" face {f}"));
        let p = self.point;
        let at = format!("({:.2}, {:.2}, {:.2}) mm", p.x, p.y, p.z);
        let depth = format!("{:.1} µm", self.depth_mm * 1000.0);
        match self.kind {
            FindingKind::Collision(part) => {
                format!(
                    "{part:?} enters{face} by {depth} at {at}, pose {}",
                    self.pose
                )
            }
            FindingKind::LeftOut(part, len) => {
                format!("left out {len:.1} mm ({part:?} would enter{face} by {depth}) from {at}")
            }
            FindingKind::Gouge => format!("gouge {depth} at {at}, pose {}", self.pose),
        }
    }
}

/// The remaining gouges and collisions of `computed`: every whole-part hit, every span the
/// tilt-away left out (shown at the path's pose nearest its start), and the exact check's
/// deepest gouge when one is left (at the nearest cutting contact).
#[must_use]
pub fn findings(computed: &Computed) -> Vec<Finding> {
    let poses = &computed.toolpath.poses;
    let nearest = |p: DVec3, contact: bool| {
        poses
            .iter()
            .enumerate()
            .map(|(i, q)| {
                let at = if contact {
                    q.cc.unwrap_or(q.tip)
                } else {
                    q.tip
                };
                (i, at.distance_squared(p))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(0, |(i, _)| i)
    };
    let mut out: Vec<Finding> = computed
        .part_hits
        .iter()
        .map(|h| Finding {
            kind: FindingKind::Collision(h.tool_part),
            pose: h.pose,
            point: h.point,
            depth_mm: h.depth_mm,
            face: Some(h.face),
        })
        .collect();
    out.extend(computed.left_out.iter().map(|l| Finding {
        kind: FindingKind::LeftOut(l.tool_part, l.length_mm),
        pose: nearest(l.start, false),
        point: l.start,
        depth_mm: l.depth_mm,
        face: Some(l.face),
    }));
    if let Some(g) = &computed.toolpath.summary.gouge
        && g.gouging_poses > 0
        && let Some(at) = g.worst_at
    {
        out.push(Finding {
            kind: FindingKind::Gouge,
            pose: nearest(at, true),
            point: at,
            depth_mm: g.max_depth_mm,
            face: None,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn project(op: Operation) -> Project {
        Project {
            operations: vec![op],
            ..Project::default()
        }
    }

    #[test]
    fn a_group_and_its_tilt_away_go_through_the_project_file() {
        let mut op = Operation::new(crate::project::OperationKind::IsoScallop, 0, 13);
        if let Operation::Finish {
            group, tilt_away, ..
        } = &mut op
        {
            *group = vec![16, 14];
            tilt_away.max_angle_rad = 12f64.to_radians();
        }
        let p = project(op.clone());
        let text = p.to_toml().expect("toml");
        let back = Project::from_toml(&text, Path::new("g.talas")).expect("reads");
        assert_eq!(back.operations[0], op);
        assert_eq!(back.operations[0].faces(), vec![13, 16, 14]);
        assert!(back.check_faces(17).is_ok());
        let e = back.check_faces(15).expect_err("face 16 is missing");
        assert!(e.contains("face 17 but the part has 15"), "{e}");
        // A file written before groups and tilt-away: one face, tilt-away on by default.
        let one = Operation::new(crate::project::OperationKind::IsoScallop, 0, 13);
        let old: String = project(one.clone())
            .to_toml()
            .expect("toml")
            .lines()
            .filter(|l| !l.contains("tilt_away") && !l.contains("enabled"))
            .filter(|l| !l.contains("max_angle_rad") && !l.contains("rate_rad_per_mm"))
            .map(|l| format!("{l}\n"))
            .collect();
        assert!(!old.contains("tilt_away"), "{old}");
        let read = Project::from_toml(&old, Path::new("old.talas")).expect("reads");
        assert_eq!(read.operations[0], one);
    }

    #[test]
    fn a_face_twice_or_a_tilt_out_of_range_is_refused() {
        let ok = TiltAwaySettings::default();
        assert!(validate(3, &[4, 5], &ok).is_ok());
        let e = validate(3, &[4, 3], &ok).expect_err("twice");
        assert!(e.contains("face 3 is named twice"), "{e}");
        let wide = TiltAwaySettings {
            max_angle_rad: 100f64.to_radians(),
            ..ok
        };
        assert!(
            validate(3, &[], &wide)
                .expect_err("100°")
                .contains("100.00°")
        );
        let still = TiltAwaySettings {
            rate_rad_per_mm: 0.0,
            ..ok
        };
        assert!(validate(3, &[], &still).is_err());
        let off = TiltAwaySettings {
            enabled: false,
            ..ok
        };
        assert!(off.limits(None).is_none());
        let m = Machine::resolve("mill-3axis").ok();
        let on = ok.limits(m.as_ref()).expect("on");
        assert!((on.max_angle_rad - 30f64.to_radians()).abs() < 1e-12);
        // Never beyond the largest tilt unless a steep tilt is asked for.
        assert!(on.steep_angle_rad.abs() < 1e-12);
        let steep = TiltAwaySettings {
            steep_angle_rad: 60f64.to_radians(),
            ..ok
        };
        let l = steep.limits(m.as_ref()).expect("on");
        assert!((l.steep_angle_rad - 60f64.to_radians()).abs() < 1e-12);
        let bad = TiltAwaySettings {
            steep_angle_rad: 120f64.to_radians(),
            ..ok
        };
        assert!(validate(3, &[], &bad).is_err());
    }
}
