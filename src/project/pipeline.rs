//! The pipeline that runs one operation of a project end to end: the operation's tool from the
//! library, its face or the part's mesh, the project's stock, into the strategy, out as a
//! [`Toolpath`] with diagnostics. The workstation runs it on a worker thread; the command line
//! and the tests call it directly.

use std::sync::Arc;

pub use super::computed::{ComputeError, Computed};
use super::op_common::stock_top;
use super::op_regions::{PlanarKind, RegionTarget, compute_planar};
use super::results::{Digest, DigestBuilder, Keys, Results, STOCK_MAX_RAYS, StockLeftover};
use super::{Operation, Project, Stock};
use crate::checks::part::PartCheck;
use crate::diagnostics::{Diagnostic, Progress};
use crate::geometry::trim::{REGION_CHORD_MM, TrimRegion};
use crate::import::Workpiece;
use crate::strategies::boundary::{Boundary as PathBoundary, Region, limit};
use crate::strategies::finish::face::FacePatch;
use crate::strategies::finish::plan::plan_finish_in;
use crate::strategies::finish::tiltaway::PartContext;
use crate::strategies::pencil::{PencilOptions, pencil};
use crate::strategies::raster::{Boundary, RasterOptions, RasterPattern, raster_progress};
use crate::strategies::rest::{RestOptions, rest, rest_where};
use crate::strategies::steep_shallow::steep_shallow;
use crate::strategies::waterline::{WaterlineError, waterline_progress};
use crate::strategies::zlevel::{ZlevelOptions, roughing_grid_mm, zlevel_rough};
use crate::toolpath::{MoveKind, ToolRecord, Toolpath};
use crate::tools::{Cutter, tool_spec};

/// Run operation `index` of `project` on `part`. Reports progress through `progress` and stops
/// early when it is cancelled (finishing checks between its stages only). A rest finishing from
/// the stock plans the operations before it once each, in a store of this call's own; keep a
/// [`Results`] to reuse results between calls.
///
/// # Errors
/// [`ComputeError`] naming the operation and what is wrong.
pub fn compute(
    project: &Project,
    index: usize,
    part: &Workpiece,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    Results::new()
        .get_or_compute(project, part, index, progress)
        .map(Arc::unwrap_or_clone)
}

/// The digests of every result of `project` on the part whose digest is `part`
/// ([`super::results::part_digest`]): per operation, exactly the inputs [`compute`] reads for
/// it, and per stock, the inputs of the posted runs cut into it.
///
/// - Every operation: the part, the operation's settings (its name left out), its cutter, the
///   machine (the reach check; the tilt limits of 5-axis finishing).
/// - Roughing: the project's stock. Rest: the reference cutter, and (from the stock) the stock
///   before it.
/// - The stock before operation k: the project's stock, the part, the setup, the post
///   settings, the machine, the grid rule, and each earlier operation's digest and cutter.
#[must_use]
pub fn digests(project: &Project, part: Digest) -> Keys {
    digests_in(project, part, None)
}

/// As [`digests`], a drawn region's file read relative to `folder` (the folder of the part
/// file, as the 2.5D operations resolve it: [`super::op_regions::part_folder`]).
///
/// - 2.5D and hole operations: also the project's stock (their heights may be measured from
///   its top) and, for a drawn region, the file's contents (or why it cannot be read).
#[must_use]
pub fn digests_in(project: &Project, part: Digest, folder: Option<&std::path::Path>) -> Keys {
    let machine = match crate::machine::Machine::resolve(&project.machine) {
        Ok(m) => format!("{m:?}"),
        Err(e) => format!("{}: {e}", project.machine),
    };
    let cutter = |i: usize| project.tools.get(i).map(|t| &t.cutter);
    let mut stock = DigestBuilder::new("stock");
    stock.digest("part", part);
    stock.json("stock", &project.stock);
    stock.json("setups", &project.setups);
    stock.json("post", &project.post);
    stock.text("machine", &machine);
    stock.json(
        "grid: Z dexels, 2 significant digits, rays",
        &STOCK_MAX_RAYS,
    );
    let mut stocks = vec![stock.finish()];
    let mut operations = Vec::with_capacity(project.operations.len());
    for op in &project.operations {
        let mut b = DigestBuilder::new("operation");
        b.digest("part", part);
        let mut settings = serde_json::to_value(op).unwrap_or(serde_json::Value::Null);
        if let Some(o) = settings.as_object_mut() {
            o.remove("name");
        }
        b.json("settings", &settings);
        b.json("cutter", &cutter(op.tool()));
        b.text("machine", &machine);
        match op {
            Operation::Rough { .. } => b.json("stock", &project.stock),
            Operation::Rest {
                reference_tool,
                from_stock,
                ..
            } => {
                b.json("reference", &cutter(*reference_tool));
                if *from_stock && let Some(s) = stocks.last() {
                    b.digest("stock before", *s);
                }
            }
            Operation::Face(_)
            | Operation::Pocket(_)
            | Operation::Contour(_)
            | Operation::Holes(_) => {
                b.json("stock", &project.stock);
                let target = match op {
                    Operation::Face(o) => Some(&o.target),
                    Operation::Pocket(o) => Some(&o.target),
                    Operation::Contour(o) => Some(&o.target),
                    _ => None,
                };
                if let Some(file) = target.and_then(|t: &RegionTarget| t.drawn_file(folder)) {
                    match std::fs::read(&file) {
                        Ok(bytes) => {
                            b.text("region file", "contents");
                            b.bytes(&bytes);
                        }
                        Err(e) => b.text("region file", &format!("{}: {e}", file.display())),
                    }
                }
            }
            _ => {}
        }
        let d = b.finish();
        operations.push(d);
        stock.digest("operation", d);
        stock.json("cutter", &cutter(op.tool()));
        stocks.push(stock.finish());
    }
    Keys {
        part,
        operations,
        stocks,
    }
}

/// Where a rest finishing from the stock finds the stock before it.
#[derive(Clone, Copy)]
enum Earlier<'a> {
    /// The stock these paths cut (the command line's `--after`).
    Given(&'a [(Toolpath, Cutter)]),
    /// The store's in-process stock.
    Store(&'a Results, &'a Keys),
}

/// Run operation `index` with `store` giving the in-process stock a rest finishing reads
/// (called by [`Results::get_or_compute`], which keeps the result).
pub(super) fn compute_in(
    project: &Project,
    index: usize,
    part: &Workpiece,
    store: &Results,
    keys: &Keys,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    compute_with(project, index, part, Earlier::Store(store, keys), progress)
}

/// Run operation `index` of `project`, a rest finishing from the simulated stock, with the
/// stock cut by `earlier` (paths and their cutters, in order, into the project's stock) instead
/// of by the project's operations before it (the command line's `--after` paths).
///
/// # Errors
/// As [`compute`]; also when `earlier` is empty.
pub fn compute_rest_after(
    project: &Project,
    index: usize,
    part: &Workpiece,
    earlier: &[(Toolpath, Cutter)],
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    compute_with(project, index, part, Earlier::Given(earlier), progress)
}

fn compute_with(
    project: &Project,
    index: usize,
    part: &Workpiece,
    earlier: Earlier<'_>,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    let op = project
        .operations
        .get(index)
        .ok_or(ComputeError::NoOperation {
            index,
            count: project.operations.len(),
        })?;
    let name = op.name().to_string();
    let entry = project
        .tools
        .get(op.tool())
        .ok_or_else(|| ComputeError::NoTool {
            operation: name.clone(),
            tool: op.tool(),
        })?;
    let plan_err = plan_error(op);
    op.validate().map_err(plan_err)?;
    let tool = ToolRecord {
        spec: tool_spec(&entry.cutter),
        cutter: entry.cutter.clone(),
    };
    cancelled(progress)?;
    progress.set(0.02);
    let mut computed = match op {
        Operation::Finish { group, .. } if !group.is_empty() => {
            super::finish_group::compute_group(project, op, part, &tool)?
        }
        Operation::Finish { .. } => finish_face(project, op, part, &tool, progress)?,
        Operation::Raster { .. } => raster_3axis(op, part, &tool, progress)?,
        Operation::Rough { .. } => rough_3axis(project, op, part, &tool, progress)?,
        Operation::Pencil { .. } | Operation::Rest { .. } => {
            corners_3axis(project, index, part, &tool, earlier, progress)?
        }
        Operation::Waterline { .. } | Operation::SteepShallow { .. } => {
            finish_3axis(op, part, &tool, progress).map_err(|e| match e {
                ComputeError::Plan { message, .. } => plan_err(message),
                other => other,
            })?
        }
        // The 2.5D and hole kinds: one arm each (a new kind adds its file under src/project/,
        // its variant in `Operation`, and its arm here).
        Operation::Face(o) => compute_planar(
            PlanarKind::Face,
            &o.target,
            &o.common,
            o.settings(),
            part,
            &tool,
            stock_top(&project.stock),
        )
        .map_err(plan_err)?,
        Operation::Pocket(o) => compute_planar(
            PlanarKind::Pocket,
            &o.target,
            &o.common,
            o.settings(),
            part,
            &tool,
            stock_top(&project.stock),
        )
        .map_err(plan_err)?,
        Operation::Contour(o) => compute_planar(
            PlanarKind::Contour,
            &o.target,
            &o.common,
            o.settings(),
            part,
            &tool,
            stock_top(&project.stock),
        )
        .map_err(plan_err)?,
        Operation::Holes(o) => o
            .compute(part, &tool, stock_top(&project.stock))
            .map_err(plan_err)?,
    };
    cancelled(progress)?;
    if let Some(boundary) = op.boundary() {
        computed = within_boundary(computed, boundary, part).map_err(plan_err)?;
    }
    // Flag tool axes the project's machine cannot hold now, not only when posting.
    if let Ok(machine) = crate::machine::Machine::resolve(&project.machine)
        && let Some(d) = super::reach::unreachable_axes(&computed.toolpath, &machine)
    {
        computed.diagnostics.push(d);
    }
    progress.set(1.0);
    Ok(computed)
}

/// 5-axis finishing of one face inside its trimming loops, the whole part as check (the tool
/// tilting away from the other faces within the project machine's tilt travel).
fn finish_face(
    project: &Project,
    op: &Operation,
    part: &Workpiece,
    tool: &ToolRecord,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    let name = op.name().to_string();
    let plan_err = plan_error(op);
    let Operation::Finish {
        face,
        strategy,
        options,
        tilt_away,
        ..
    } = op
    else {
        return Err(plan_err("not a face-finishing operation".into()));
    };
    cancelled(progress)?;
    let face_err = |message: String| ComputeError::Face {
        operation: name.clone(),
        message,
    };
    let surface = match part.surfaces.get(*face) {
        None if part.part.is_none() => {
            return Err(face_err(format!(
                "the part {} is a mesh without exact faces (finishing needs a STEP part)",
                part.source.display()
            )));
        }
        None => {
            return Err(face_err(format!(
                "no face number {face} (the part has {})",
                part.surfaces.len()
            )));
        }
        Some(None) => {
            return Err(face_err(format!(
                "face {face} has no exact surface (finishing needs a STEP part)"
            )));
        }
        Some(Some(s)) => s.as_ref(),
    };
    // A face of a B-rep is planned inside its trimming loops, on the material's side
    // (the face's sense); a bare surface over its natural domain.
    let region = match (
        &part.part,
        part.part.as_ref().and_then(|p| p.faces.get(*face)),
    ) {
        (Some(brep), Some(f)) => Some(
            TrimRegion::of_face(f, brep, REGION_CHORD_MM)
                .map_err(|e| face_err(format!("face {face}: its trimming loops: {e}")))?,
        ),
        _ => None,
    };
    let patch = match (&part.part, &region) {
        (Some(brep), Some(region)) => FacePatch::trimmed(brep, *face, region),
        _ => FacePatch::from_surface(surface),
    }
    .map_err(|e| face_err(format!("face {face}: {e}")))?;
    // The whole part as check: the tool tilts away from the other faces.
    let (bvh, skip) = (part.bvh().ok(), [*face]);
    let machine = crate::machine::Machine::resolve(&project.machine).ok();
    let context = bvh.as_deref().map(|b| PartContext {
        check: PartCheck::of_workpiece(part, b, &skip),
        tilt: tilt_away.limits(machine.as_ref()),
    });
    let r = plan_finish_in(
        patch,
        &tool.cutter,
        &tool.spec,
        *strategy,
        options,
        context.as_ref(),
    )
    .map_err(|e| plan_err(format!("face {face}: {e}")))?;
    Ok(Computed {
        passes: r.passes.len(),
        lead_rad: Some(r.used.axis.lead()),
        clearance_mm: r.used.clearance,
        toolpath: r.toolpath,
        diagnostics: r.diagnostics,
        part_hits: r.part_hits,
        left_out: r.left_out,
    })
}

/// Raster drop-cutter finishing of the whole part.
fn raster_3axis(
    op: &Operation,
    part: &Workpiece,
    tool: &ToolRecord,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    let plan_err = plan_error(op);
    let Operation::Raster {
        scallop_mm,
        angle_rad,
        one_way,
        tolerance_mm,
        feed_mm_per_min,
        clearance_mm,
        ..
    } = op
    else {
        return Err(plan_err("not a raster operation".into()));
    };
    let bvh = part.bvh().map_err(plan_err)?;
    cancelled(progress)?;
    let opts = RasterOptions {
        angle_rad: *angle_rad,
        pattern: if *one_way {
            RasterPattern::OneWay
        } else {
            RasterPattern::ZigZag
        },
        scallop_mm: *scallop_mm,
        chord_tol_mm: *tolerance_mm,
        boundary: Boundary::Silhouette,
        feed_mm_per_min: *feed_mm_per_min,
        clearance_mm: *clearance_mm,
        plunge_feed_mm_per_min: 0.3 * feed_mm_per_min,
        ..RasterOptions::default()
    };
    let plan = raster_progress(&part.mesh, &bvh, tool, &opts, progress)
        .map_err(|e| plan_err(e.to_string()))?;
    cancelled(progress)?;
    Ok(Computed {
        passes: plan.passes,
        lead_rad: None,
        clearance_mm: None,
        part_hits: Vec::new(),
        left_out: Vec::new(),
        toolpath: plan.toolpath,
        diagnostics: plan.diagnostics,
    })
}

/// Z-level roughing of the project's stock (the one default around the part when none is set).
fn rough_3axis(
    project: &Project,
    op: &Operation,
    part: &Workpiece,
    tool: &ToolRecord,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    let plan_err = plan_error(op);
    let Operation::Rough {
        step_down_mm,
        step_over_fraction,
        stock_to_leave_mm,
        stock_to_leave_axial_mm,
        tolerance_mm,
        feed_mm_per_min,
        flat_levels,
        clearance_mm,
        ..
    } = op
    else {
        return Err(plan_err("not a roughing operation".into()));
    };
    let bvh = part.bvh().map_err(plan_err)?;
    let axial = stock_to_leave_axial_mm.unwrap_or(*stock_to_leave_mm);
    let grid = roughing_grid_mm(
        &project.stock,
        &part.mesh.bbox(),
        tool.cutter.radius(),
        *tolerance_mm,
        stock_to_leave_mm.min(axial),
    );
    let opts = ZlevelOptions {
        stock: project.stock,
        step_down_mm: *step_down_mm,
        step_over_mm: step_over_fraction * tool.cutter.diameter,
        stock_to_leave_radial_mm: *stock_to_leave_mm,
        stock_to_leave_axial_mm: axial,
        tolerance_mm: grid,
        feed_mm_per_min: *feed_mm_per_min,
        clearance_mm: *clearance_mm,
        detect_flats: *flat_levels,
        ..ZlevelOptions::default()
    };
    cancelled(progress)?;
    let plan = zlevel_rough(&part.mesh, &bvh, tool, &opts).map_err(|e| plan_err(e.to_string()))?;
    let mut diagnostics = plan.diagnostics;
    if matches!(project.stock, Stock::None) {
        diagnostics.push(Diagnostic::info(
            None,
            "no stock defined: roughing the part's bounding box",
        ));
    }
    Ok(Computed {
        passes: plan.contours,
        lead_rad: None,
        clearance_mm: None,
        part_hits: Vec::new(),
        left_out: Vec::new(),
        toolpath: plan.toolpath,
        diagnostics,
    })
}

/// The strategy's refusal of `op`, naming the operation.
fn plan_error(op: &Operation) -> impl Fn(String) -> ComputeError + Copy + '_ {
    move |message| ComputeError::Plan {
        operation: op.name().to_string(),
        message,
    }
}

/// `Err(Cancelled)` once the user cancelled.
fn cancelled(progress: &Progress) -> Result<(), ComputeError> {
    if progress.is_cancelled() {
        Err(ComputeError::Cancelled)
    } else {
        Ok(())
    }
}

/// Waterline or steep-and-shallow finishing of the whole part, with the options mapped by
/// [`crate::strategies::steep_shallow::Finish3Settings`] (as `talas plan` maps them).
fn finish_3axis(
    op: &Operation,
    part: &Workpiece,
    tool: &ToolRecord,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    let plan_err = plan_error(op);
    let settings = op
        .finish_3axis_settings()
        .ok_or_else(|| plan_err("not a 3-axis finishing operation".into()))?;
    let bvh = part.bvh().map_err(plan_err)?;
    if progress.is_cancelled() {
        return Err(ComputeError::Cancelled);
    }
    if matches!(op, Operation::Waterline { .. }) {
        let plan = waterline_progress(
            &part.mesh,
            &bvh,
            tool,
            &settings.waterline_options(),
            progress,
        )
        .map_err(|e| match e {
            WaterlineError::Cancelled => ComputeError::Cancelled,
            e => plan_err(e.to_string()),
        })?;
        return Ok(Computed {
            passes: plan.loops,
            lead_rad: None,
            clearance_mm: None,
            part_hits: Vec::new(),
            left_out: Vec::new(),
            toolpath: plan.toolpath,
            diagnostics: plan.diagnostics,
        });
    }
    let plan = steep_shallow(&part.mesh, &bvh, tool, &settings.steep_shallow_options())
        .map_err(plan_err)?;
    Ok(Computed {
        passes: plan.raster_passes + plan.waterline_runs,
        lead_rad: None,
        clearance_mm: None,
        part_hits: Vec::new(),
        left_out: Vec::new(),
        toolpath: plan.toolpath,
        diagnostics: plan.diagnostics,
    })
}

/// Pencil or rest finishing of the whole part (3-axis, ball end mill), the plunge feed 30 % of
/// the cutting feed and (rest) the runs grown by half the tool's radius past the rest areas.
fn corners_3axis(
    project: &Project,
    index: usize,
    part: &Workpiece,
    tool: &ToolRecord,
    earlier: Earlier<'_>,
    progress: &Progress,
) -> Result<Computed, ComputeError> {
    let op = &project.operations[index];
    let plan_err = plan_error(op);
    let bvh = part.bvh().map_err(plan_err)?;
    if progress.is_cancelled() {
        return Err(ComputeError::Cancelled);
    }
    let (toolpath, diagnostics) = match *op {
        Operation::Pencil {
            angle_rad,
            tolerance_mm,
            feed_mm_per_min,
            clearance_mm,
            ..
        } => {
            let opts = PencilOptions {
                min_angle_rad: angle_rad,
                chord_tol_mm: tolerance_mm,
                clearance_mm,
                feed_mm_per_min,
                plunge_feed_mm_per_min: 0.3 * feed_mm_per_min,
                ..PencilOptions::default()
            };
            let plan =
                pencil(&part.mesh, &bvh, tool, &opts).map_err(|e| plan_err(e.to_string()))?;
            (plan.toolpath, plan.diagnostics)
        }
        Operation::Rest {
            reference_tool,
            from_stock,
            scallop_mm,
            tolerance_mm,
            feed_mm_per_min,
            clearance_mm,
            ..
        } => {
            let reference = project
                .tools
                .get(reference_tool)
                .ok_or_else(|| ComputeError::NoTool {
                    operation: op.name().to_string(),
                    tool: reference_tool,
                })?
                .cutter
                .clone();
            let opts = RestOptions {
                reference,
                // The chord tolerance covers the earlier paths' and the stock grid's deviation.
                threshold_mm: if from_stock {
                    scallop_mm + tolerance_mm
                } else {
                    scallop_mm
                },
                scallop_mm,
                chord_tol_mm: tolerance_mm,
                sampling_mm: None,
                overlap_mm: 0.5 * tool.cutter.radius(),
                clearance_mm,
                feed_mm_per_min,
                plunge_feed_mm_per_min: 0.3 * feed_mm_per_min,
            };
            let plan = if from_stock {
                let stock = earlier_stock(project, index, part, earlier, progress)?;
                let leftover =
                    |c: glam::DVec3, n: glam::DVec3| stock.thickness(c, n, REST_MAX_LAYER_MM);
                let source = format!(
                    "the simulated stock of the earlier operations ({} mm grid)",
                    stock.resolution_mm()
                );
                rest_where(&part.mesh, &bvh, tool, &opts, &leftover, &source)
            } else {
                rest(&part.mesh, &bvh, tool, &opts)
            }
            .map_err(|e| plan_err(e.to_string()))?;
            (plan.toolpath, plan.diagnostics)
        }
        _ => return Err(plan_err("not a pencil or rest operation".into())),
    };
    Ok(Computed {
        passes: cutting_runs(&toolpath),
        toolpath,
        diagnostics,
        lead_rad: None,
        clearance_mm: None,
        part_hits: Vec::new(),
        left_out: Vec::new(),
    })
}

/// `computed` limited to `boundary` ([`crate::strategies::boundary::limit`]); a region of faces
/// names the part's faces, turned here into the triangles they were tessellated into.
fn within_boundary(
    mut computed: Computed,
    boundary: &PathBoundary,
    part: &Workpiece,
) -> Result<Computed, String> {
    let mut boundary = boundary.clone();
    if let Region::Faces(faces) = &boundary.region {
        let count = part
            .face_of_triangle
            .iter()
            .max()
            .map_or(0, |m| *m as usize + 1);
        if let Some(f) = faces.iter().find(|f| **f >= count) {
            return Err(format!(
                "boundary face {f} is not a face of the part (it has {count})"
            ));
        }
        let triangles = part
            .face_of_triangle
            .iter()
            .enumerate()
            .filter(|(_, f)| faces.contains(&(**f as usize)))
            .map(|(t, _)| t)
            .collect();
        boundary.region = Region::Faces(triangles);
    }
    let bvh = part.bvh()?;
    let (toolpath, report) = limit(&computed.toolpath, &bvh, &boundary)?;
    if report.pieces == 0 {
        return Err("no cutting move of the path lies inside the boundary".into());
    }
    computed.diagnostics.push(Diagnostic::info(
        None,
        format!(
            "boundary: {} cutting pieces kept, {} cutting poses outside removed",
            report.pieces, report.removed
        ),
    ));
    computed.toolpath = toolpath;
    computed.passes = report.pieces;
    Ok(computed)
}

/// Thickest layer the rest from the stock measures along a contact normal, mm.
const REST_MAX_LAYER_MM: f64 = 10.0;

/// The stock the operations before `index` leave: the store's in-process stock (their posted
/// runs, each cut once), or the stock the `given` paths leave; both on the engine's one grid
/// ([`super::results::stock_resolution_mm`]).
fn earlier_stock(
    project: &Project,
    index: usize,
    part: &Workpiece,
    earlier: Earlier<'_>,
    progress: &Progress,
) -> Result<StockLeftover, ComputeError> {
    let plan_err = plan_error(&project.operations[index]);
    match earlier {
        Earlier::Given([]) => Err(plan_err(
            "rest from the stock needs at least one earlier path".into(),
        )),
        Earlier::Given(paths) => {
            StockLeftover::simulate(&project.stock, &part.mesh, paths, progress)
                .map_err(|e| plan_err(format!("simulating the earlier operations: {e}")))
        }
        Earlier::Store(..) if index == 0 => Err(plan_err(
            "rest from the stock needs an earlier operation before it in the list".into(),
        )),
        Earlier::Store(store, keys) => {
            cancelled(progress)?;
            let stock = store.stock_before_keyed(project, part, keys, index, progress)?;
            Ok(StockLeftover::of(stock))
        }
    }
}

/// Number of cutting runs in `toolpath` (a run starts where a cut follows a non-cut).
#[must_use]
pub fn cutting_runs(toolpath: &Toolpath) -> usize {
    let mut runs = 0;
    let mut cutting = false;
    for p in &toolpath.poses {
        let cut = p.kind == MoveKind::Cut;
        if cut && !cutting {
            runs += 1;
        }
        cutting = cut;
    }
    runs
}
