//! Posting a computed operation the way the project says: its machine, dialect, TCP choice,
//! spindle speed, work offset, and the program origin of the setup (program = part − origin).

use glam::DVec3;

use super::Project;
use crate::machine::Machine;
use crate::post::{Dialect, PostOptions, Posted, post_mapped};
use crate::toolpath::Toolpath;

/// `toolpath` moved into program coordinates: tips (and contacts) less `origin`.
#[must_use]
pub fn to_program_coordinates(toolpath: &Toolpath, origin: DVec3) -> Toolpath {
    let mut out = toolpath.clone();
    for p in &mut out.poses {
        p.tip -= origin;
        if let Some(cc) = p.cc.as_mut() {
            *cc -= origin;
        }
    }
    Toolpath::new(out.tool, out.poses)
}

/// Post `toolpath` (in part coordinates) with the project's machine and post settings, as tool
/// `tool_number`, with the line ↔ pose map.
///
/// # Errors
/// A message naming the machine or dialect that cannot be found, or the post's error.
pub fn post_operation(
    project: &Project,
    toolpath: &Toolpath,
    tool_number: u32,
) -> Result<Posted, String> {
    let machine = Machine::resolve(&project.machine)
        .map_err(|e| format!("machine '{}': {e}", project.machine))?;
    let dialect = Dialect::resolve(&project.post.dialect)
        .map_err(|e| format!("dialect '{}': {e}", project.post.dialect))?;
    let program = to_program_coordinates(toolpath, DVec3::from_array(project.setup.origin_mm));
    // The safe height stays 10 mm above the highest tip of the program (100 mm at least).
    let top = program
        .poses
        .iter()
        .map(|p| p.tip.z)
        .fold(f64::NEG_INFINITY, f64::max);
    let clearance = if top.is_finite() {
        (top + 10.0).max(100.0)
    } else {
        100.0
    };
    let name: String = project
        .name
        .chars()
        .filter(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '-')
        .take(24)
        .collect();
    let options = PostOptions {
        tcp: project.post.tcp,
        program_name: if name.is_empty() {
            "TALAS".into()
        } else {
            name
        },
        tool_number,
        spindle_rpm: project.post.spindle_rpm,
        clearance_z_mm: clearance,
        work_offset: project.setup.work_offset_code(),
        ..PostOptions::default()
    };
    post_mapped(&program, &machine, &dialect, &options)
        .map_err(|e| format!("post ({}, {}): {e}", project.machine, project.post.dialect))
}

/// The posted program planned on the project's machine with jerk-limited motion (corners
/// blended within `corner_tolerance_mm`): the true cycle time and the motion over time.
///
/// # Errors
/// A message with the line of a block the interpreter or the planner refuses.
pub fn plan_motion(
    project: &Project,
    text: &str,
    corner_tolerance_mm: f64,
) -> Result<crate::feed::TimedPath, String> {
    use crate::feed::{CornerPolicy, PlanInput, PlanOptions, machine_limits, plan};
    use crate::gcode::{InterpretOptions, Syntax, interpret};
    let machine = Machine::resolve(&project.machine)
        .map_err(|e| format!("machine '{}': {e}", project.machine))?;
    let options = InterpretOptions::for_syntax(Syntax::detect(text));
    let program = interpret(text, &options)
        .map_err(|e| format!("posted program, line {}: {}", e.line, e.message))?;
    let input = PlanInput {
        blocks: &program.blocks,
        axes: machine_limits(&machine),
        options: PlanOptions {
            corner: CornerPolicy::Blend {
                tolerance_mm: corner_tolerance_mm,
            },
            ..PlanOptions::default()
        },
    };
    plan(&input).map_err(|e| format!("feed planning: {e}"))
}
