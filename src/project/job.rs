//! The job end to end: each operation planned in its setup's frame, and one program per setup
//! (its operations in order, its work offset, its tool changes; for a tilted 3+2 setup on a
//! 5-axis machine the rotary positioning and the rotated coordinates through the machine's
//! kinematics, which every 5-axis dialect writes as explicit rotary words).
//!
//! The 3-axis strategies plan with +Z up: they plan on the part moved into the setup's work
//! plane ([`setups::workpiece_in_plane`]) with the setup's stock box there, and their poses are
//! turned back into the setup frame. Face finishing plans in the part frame (it reads the exact
//! surfaces) and its poses are moved into the setup frame. Every tool path this module returns
//! is in the setup frame, i.e. in program coordinates.

use super::pipeline::{ComputeError, Computed, compute};
use super::run::RunError;
use super::setups::{self, Placement, transform_toolpath};
use super::{Project, Stock};
use crate::diagnostics::Progress;
use crate::geometry::Aabb;
use crate::import::Workpiece;
use crate::machine::Machine;
use crate::post::{Dialect, PostOptions, PostedProgram, post_program};
use crate::toolpath::Toolpath;

/// Plan operation `op` in the frame of the setup that holds it; the tool path comes back in
/// that setup's frame (program coordinates).
///
/// # Errors
/// [`ComputeError`] naming the operation, also when no setup holds it or its setup's frame or
/// stock cannot be resolved.
pub fn plan_in_setup(
    project: &Project,
    op: usize,
    part: &Workpiece,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    let name = project
        .operations
        .get(op)
        .map(|o| o.name().to_string())
        .ok_or(ComputeError::NoOperation {
            index: op,
            count: project.operations.len(),
        })?;
    let plan_err = |message: String| ComputeError::Plan {
        operation: name.clone(),
        message,
    };
    let index = setups::setup_of(project, op)
        .ok_or_else(|| plan_err("the operation is in no setup".into()))?;
    let placements = setups::placements(project, Some(part)).map_err(plan_err)?;
    let here = placements[index];
    let bounds = part.mesh.bbox();
    if !project.operations[op].faces().is_empty() {
        // Face finishing: in the part frame, then moved into the setup frame.
        let mut c = compute(project, op, part, progress)?;
        c.toolpath = transform_toolpath(&c.toolpath, here.rotation, -(here.rotation * here.origin));
        c.clearance_mm = None;
        return Ok(c);
    }
    let stock = setups::planning_stock(project, index, &placements, &bounds).map_err(plan_err)?;
    let mut in_plane = setups::workpiece_in_plane(part, &here);
    if project.operations[op].is_planar()
        && let Some(brep) = part.part.as_deref()
    {
        // The 2.5D and hole kinds recognise their regions and holes on the B-rep as it lies
        // in the work plane (the recognisers look along +Z, the setup's tool axis).
        let r = here.plane_rotation();
        in_plane.part = Some(std::sync::Arc::new(crate::geometry::rigid::transform_part(
            brep,
            r,
            -(r * here.origin),
        )));
    }
    let planning = Project {
        stock,
        ..project.clone()
    };
    let mut c = compute(&planning, op, &in_plane, progress)?;
    c.toolpath = transform_toolpath(&c.toolpath, here.work_plane, glam::DVec3::ZERO);
    Ok(c)
}

/// The stock box of setup `index` in its work plane (what its roughing clears), for callers
/// that show or check it.
///
/// # Errors
/// As [`setups::planning_stock`].
pub fn setup_stock(project: &Project, index: usize, part: &Workpiece) -> Result<Stock, String> {
    let placements = setups::placements(project, Some(part))?;
    setups::planning_stock(project, index, &placements, &part.mesh.bbox())
}

/// The machine of setup `index` and the project's dialect, resolved.
///
/// # Errors
/// [`RunError::Machine`] or [`RunError::Dialect`].
pub fn resolve_setup(project: &Project, index: usize) -> Result<(Machine, Dialect), RunError> {
    let name = project
        .setups
        .get(index)
        .map_or(project.machine.as_str(), |s| s.machine_name(project));
    super::posting::resolve_named(project, name)
}

/// Post the operations of setup `index` in order into one program: `toolpaths[k]` is the tool
/// path of the setup's k-th operation in the setup frame (from [`plan_in_setup`]); the tool
/// number of each is its library index + 1; the work offset is the setup's.
///
/// # Errors
/// [`RunError::Post`] for a wrong count, the machine or dialect that cannot be found, or the
/// post's own error (a pose the kinematics cannot reach).
pub fn post_setup(
    project: &Project,
    index: usize,
    toolpaths: &[Toolpath],
) -> Result<PostedProgram, RunError> {
    let (machine, dialect) = resolve_setup(project, index)?;
    let post_err = |source| RunError::Post {
        machine: machine.name.clone(),
        dialect: project.post.dialect.clone(),
        source,
    };
    let options_err = |m: String| post_err(crate::post::PostError::Options(m));
    let setup = project
        .setups
        .get(index)
        .ok_or_else(|| options_err(format!("no setup {}", index + 1)))?;
    if toolpaths.len() != setup.operations.len() {
        return Err(options_err(format!(
            "setup '{}' has {} operations but {} tool paths were given",
            setup.name,
            setup.operations.len(),
            toolpaths.len()
        )));
    }
    let ops: Vec<crate::post::Operation<'_>> = setup
        .operations
        .iter()
        .zip(toolpaths)
        .map(|(&op, tp)| crate::post::Operation {
            toolpath: tp,
            tool_number: project
                .operations
                .get(op)
                .map_or(1, |o| u32::try_from(o.tool() + 1).unwrap_or(1)),
            spindle_rpm: project
                .operations
                .get(op)
                .and_then(|o| o.common())
                .and_then(|c| c.spindle_rpm)
                .unwrap_or(project.post.spindle_rpm),
            coolant: project
                .operations
                .get(op)
                .and_then(|o| o.common())
                .is_none_or(|c| c.coolant),
        })
        .collect();
    let top = toolpaths
        .iter()
        .flat_map(|t| t.poses.iter().map(|p| p.tip.z))
        .fold(f64::NEG_INFINITY, f64::max);
    let Some(first) = toolpaths.first() else {
        return Err(options_err(format!(
            "setup '{}' has no operation to post",
            setup.name
        )));
    };
    let base = super::posting::post_options(project, first, 1);
    let options = PostOptions {
        work_offset: setup.frame.work_offset_code(),
        clearance_z_mm: if top.is_finite() {
            (top + 10.0).max(base.clearance_z_mm)
        } else {
            base.clearance_z_mm
        },
        program_name: format!("{}_{}", base.program_name, program_stem(&setup.name)),
        work_plane: setup.tilt.as_ref().and_then(|t| t.work_plane().ok()),
        ..base
    };
    post_program(&ops, &machine, &dialect, &options).map_err(post_err)
}

/// Setup `s`'s tool paths linked and cut in order on the setup's starting stock (the box of
/// [`setups::stock_solid`] in the setup frame): each path (setup frame, from
/// [`plan_in_setup`]) has its rapids lifted over the stock the paths before it left
/// ([`super::rapids::link`], the same step [`super::Results::linked`] runs on the store's
/// stock), and that stock is then cut by the linked path. With `measure`, the cut stock is
/// measured against the part (in the setup frame). The earlier setups' material is not
/// carried.
///
/// # Errors
/// The setup's frame or stock that cannot be resolved, or the simulation's error, as text.
pub fn link_setup(
    project: &Project,
    s: usize,
    part: &Workpiece,
    paths: &[Toolpath],
    measure: bool,
    progress: &Progress,
) -> Result<
    (
        Vec<super::rapids::Linked>,
        Option<super::simulate::Simulated>,
    ),
    String,
> {
    let placements = setups::placements(project, Some(part))?;
    let here = *placements
        .get(s)
        .ok_or_else(|| format!("no setup {}", s + 1))?;
    let solid = setups::stock_solid(project, s, &placements, &part.mesh.bbox())?;
    let b = solid.bbox();
    let stock = Stock::Box {
        min_mm: b.min.to_array(),
        max_mm: b.max.to_array(),
    };
    let mesh = setups::transform_mesh(&part.mesh, here.rotation, -(here.rotation * here.origin));
    let settings = super::simulate::SimulationSettings::default();
    let (mut dexels, resolution) = super::simulate::stock_grid(&stock, &mesh, &settings)
        .map_err(|e| format!("simulation: {e}"))?;
    let mut linked = Vec::with_capacity(paths.len());
    let mut reports = Vec::with_capacity(paths.len());
    for tp in paths {
        let l = super::rapids::link(tp, &dexels);
        reports.push(
            super::simulate::cut_path(
                &mut dexels,
                resolution,
                &l.toolpath,
                &l.toolpath.tool.cutter,
                progress,
            )
            .map_err(|e| format!("simulation: {e}"))?,
        );
        linked.push(l);
    }
    let measured = if measure && !reports.is_empty() {
        Some(
            super::simulate::measured(&dexels, &mesh, reports, progress)
                .map_err(|e| format!("simulation: {e}"))?,
        )
    } else {
        None
    };
    Ok((linked, measured))
}

/// A setup name as a file stem: ASCII letters, digits, `-` and `_` (others become `_`).
#[must_use]
pub fn program_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .take(40)
        .collect();
    if s.is_empty() { "setup".into() } else { s }
}

/// Every setup's placement and the part's box, for callers that carry stock or place
/// workholding.
///
/// # Errors
/// The first setup whose frame cannot be resolved.
pub fn placements(project: &Project, part: &Workpiece) -> Result<(Vec<Placement>, Aabb), String> {
    Ok((setups::placements(project, Some(part))?, part.mesh.bbox()))
}

/// One posted program of a job: the setup it is for and its text.
#[derive(Clone, Debug)]
pub struct SetupProgram {
    /// The setup's index.
    pub setup: usize,
    /// The file name the job writes it to: `NN-SETUP.EXT` (`ext` given by the caller).
    pub stem: String,
    /// The program.
    pub program: PostedProgram,
}

/// Plan every operation of each setup that has some (in its frame, [`plan_in_setup`]), link
/// each setup's paths ([`link_setup`]) and post one program per setup ([`post_setup`]), as
/// `talas job --post` does; progress runs over the operations and is checked between them.
///
/// # Errors
/// The first operation that cannot be planned or setup that cannot be posted, named; or
/// "cancelled".
pub fn post_job(
    project: &Project,
    part: &Workpiece,
    progress: &Progress,
) -> Result<Vec<SetupProgram>, String> {
    let total = project.operations.len().max(1) as f64;
    let mut done = 0usize;
    let mut out = Vec::new();
    for (s, setup) in project.setups.iter().enumerate() {
        if setup.operations.is_empty() {
            continue;
        }
        let mut paths = Vec::with_capacity(setup.operations.len());
        for &op in &setup.operations {
            progress.check().map_err(|_| "cancelled".to_string())?;
            let c =
                plan_in_setup(project, op, part, &Progress::new()).map_err(|e| e.to_string())?;
            paths.push(c.toolpath);
            done += 1;
            progress.set(done as f64 / total);
        }
        // Linked as `talas job` links them: rapids lifted over the stock left before each.
        let (linked, _) = link_setup(project, s, part, &paths, false, progress)
            .map_err(|e| format!("setup {} ('{}'): {e}", s + 1, setup.name))?;
        let paths: Vec<Toolpath> = linked.into_iter().map(|l| l.toolpath).collect();
        let program = post_setup(project, s, &paths)
            .map_err(|e| format!("setup {} ('{}'): {e}", s + 1, setup.name))?;
        out.push(SetupProgram {
            setup: s,
            stem: format!("{:02}-{}", s + 1, program_stem(&setup.name)),
            program,
        });
    }
    if out.is_empty() {
        return Err("the job has no operation to post".into());
    }
    Ok(out)
}
