//! Posting a computed operation the way the project says: its machine, dialect, TCP choice,
//! spindle speed, work offset, and the program origin of the setup (program = part − origin).

use glam::DVec3;

use super::Project;
use super::run::{MachiningRun, RunError};
use crate::machine::Machine;
use crate::post::{Dialect, PostOptions, Posted, post_mapped};
use crate::toolpath::Toolpath;

/// `toolpath` moved into program coordinates: tips (and contacts) less `origin`.
#[must_use]
pub fn to_program_coordinates(toolpath: &Toolpath, origin: DVec3) -> Toolpath {
    let mut out = toolpath.translated(-origin);
    out.summary.gouge = None;
    out
}

/// The machine and dialect the project names, resolved.
///
/// # Errors
/// [`RunError::Machine`] or [`RunError::Dialect`] naming what cannot be found or read.
pub fn resolve(project: &Project) -> Result<(Machine, Dialect), RunError> {
    resolve_named(project, &project.machine)
}

/// The machine named `machine` and the project's dialect, resolved.
///
/// # Errors
/// [`RunError::Machine`] or [`RunError::Dialect`] naming what cannot be found or read.
pub fn resolve_named(project: &Project, machine: &str) -> Result<(Machine, Dialect), RunError> {
    let resolved = Machine::resolve(machine).map_err(|e| RunError::Machine {
        name: machine.to_string(),
        message: e.to_string(),
    })?;
    let dialect = Dialect::resolve(&project.post.dialect).map_err(|e| RunError::Dialect {
        name: project.post.dialect.clone(),
        message: e.to_string(),
    })?;
    Ok((resolved, dialect))
}

/// The post options the project gives `program` (a tool path in program coordinates) as tool
/// `tool_number`: TCP, spindle speed, work offset, the program name from the project's name,
/// and a safe height 10 mm above the highest tip (100 mm at least).
#[must_use]
pub fn post_options(project: &Project, program: &Toolpath, tool_number: u32) -> PostOptions {
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
    PostOptions {
        tcp: project.post.tcp,
        program_name: if name.is_empty() {
            "TALAS".into()
        } else {
            name
        },
        tool_number,
        spindle_rpm: project.post.spindle_rpm,
        clearance_z_mm: clearance,
        work_offset: project.first_setup().frame.work_offset_code(),
        ..PostOptions::default()
    }
}

/// The setup that holds operation `operation` (the first setup when none does), its index,
/// and its machine with the project's dialect, resolved.
///
/// # Errors
/// [`RunError::Machine`] or [`RunError::Dialect`] naming what cannot be found or read.
pub fn resolve_operation(
    project: &Project,
    operation: usize,
) -> Result<(super::Setup, Machine, Dialect), RunError> {
    let setup = super::setups::setup_of(project, operation)
        .and_then(|i| project.setups.get(i).cloned())
        .unwrap_or_else(|| project.first_setup());
    let (machine, dialect) = resolve_named(project, setup.machine_name(project))?;
    Ok((setup, machine, dialect))
}

/// Post `toolpath` (in part coordinates) of operation `operation` as tool `tool_number`, in
/// the frame, work offset and machine of the setup that holds the operation (the first setup
/// when none does), with the project's post settings and the line ↔ pose map.
///
/// # Errors
/// The machine or dialect that cannot be found, or the post's error.
pub fn post_operation(
    project: &Project,
    operation: usize,
    toolpath: &Toolpath,
    tool_number: u32,
) -> Result<Posted, RunError> {
    let (setup, machine, dialect) = resolve_operation(project, operation)?;
    post_with(project, &setup, toolpath, tool_number, &machine, &dialect)
}

fn post_with(
    project: &Project,
    setup: &super::Setup,
    toolpath: &Toolpath,
    tool_number: u32,
    machine: &Machine,
    dialect: &Dialect,
) -> Result<Posted, RunError> {
    // The setup's frame: program = R·(part − origin). A face-picked orientation needs the
    // part: `job` posts those.
    let placement = super::setups::Placement::of(setup, None).map_err(|e| RunError::Post {
        machine: machine.name.clone(),
        dialect: project.post.dialect.clone(),
        source: crate::post::PostError::Options(format!("setup '{}': {e}", setup.name)),
    })?;
    let program = if placement.rotation == glam::DMat3::IDENTITY {
        to_program_coordinates(toolpath, placement.origin)
    } else {
        let mut p = super::setups::transform_toolpath(
            toolpath,
            placement.rotation,
            -(placement.rotation * placement.origin),
        );
        p.summary.gouge = None;
        p
    };
    let options = PostOptions {
        work_offset: setup.frame.work_offset_code(),
        ..post_options(project, &program, tool_number)
    };
    post_mapped(&program, machine, dialect, &options).map_err(|source| RunError::Post {
        machine: machine.name.clone(),
        dialect: project.post.dialect.clone(),
        source,
    })
}

/// The machining run of `toolpath` (in part coordinates) of operation `operation` as the
/// project posts it (in the operation's setup, [`post_operation`]), as tool
/// `tool_number`, its motion planned with corners blended within `corner_tolerance_mm`: the
/// program, the true cycle time, and the line ↔ pose ↔ time maps.
///
/// # Errors
/// As [`post_operation`]; interpretation and planning errors are kept in the run.
pub fn run_operation(
    project: &Project,
    operation: usize,
    toolpath: &Toolpath,
    tool_number: u32,
    corner_tolerance_mm: f64,
) -> Result<MachiningRun, RunError> {
    let (setup, machine, dialect) = resolve_operation(project, operation)?;
    let posted = post_with(project, &setup, toolpath, tool_number, &machine, &dialect)?;
    Ok(MachiningRun::from_posted(
        posted,
        toolpath.poses.len(),
        &machine,
        corner_tolerance_mm,
    ))
}
