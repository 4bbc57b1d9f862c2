//! `talas job … --sheet OUT.html`: the job's setup sheet ([`crate::project::sheet`]) from the
//! setups as `talas job` plans them: per setup the part, stock and workholding in its frame,
//! and per operation its feeds, speeds, heights, time at feed and its jerk-limited time in the
//! setup's posted program.

use crate::gcode::{InterpretOptions, Syntax, interpret};
use crate::import::Workpiece;
use crate::project::job::{post_setup, resolve_setup};
use crate::project::op_common::HeightFrom;
use crate::project::results::RUN_CORNER_TOLERANCE_MM;
use crate::project::run::RunMotion;
use crate::project::setups::{self, Placement, SetupStock};
use crate::project::sheet::{self, Body, SheetOperation, SheetSetup, SheetTool};
use crate::project::{Operation, Project};
use crate::toolpath::{MoveKind, Toolpath};

/// Picture size on the sheet, pixels.
const PICTURE_PX: (u32, u32) = (560, 400);

/// Part, workholding colours on the pictures (sRGB).
const PART_COLOUR: [u8; 3] = [176, 196, 210];
const HOLDING_COLOUR: [u8; 3] = [120, 120, 132];

/// The sheet page of setup `s` whose linked paths (in machining order) are `paths`.
///
/// # Errors
/// Why the setup's stock or workholding cannot be built.
pub fn setup_page(
    project: &Project,
    s: usize,
    part: &Workpiece,
    placements: &[Placement],
    base: &std::path::Path,
    paths: &[Toolpath],
) -> Result<SheetSetup, String> {
    let setup = &project.setups[s];
    let here = placements[s];
    let bounds = part.mesh.bbox();
    let mesh = setups::transform_mesh(&part.mesh, here.rotation, -(here.rotation * here.origin));
    let stock = setups::stock_solid(project, s, placements, &bounds)?.bbox();
    let holding = setups::workholding_meshes(project, s, placements, &bounds, base)?;
    let mut bodies = vec![Body {
        mesh: &mesh,
        colour: PART_COLOUR,
    }];
    bodies.extend(holding.iter().map(|m| Body {
        mesh: m,
        colour: HOLDING_COLOUR,
    }));
    let picture = sheet::picture(&bodies, Some(&stock), PICTURE_PX.0, PICTURE_PX.1);
    let size = stock.max - stock.min;
    let stock_text = match setup.stock {
        SetupStock::Project => "the project's stock".to_string(),
        SetupStock::Around { margin_mm } => format!("box around the part + {margin_mm:.2} mm"),
        SetupStock::Box { .. } => "box".to_string(),
        SetupStock::Previous => "what the previous setup left".to_string(),
    };
    let axis = here.tool_axis();
    let times = setup_times(project, s, paths);
    let operations = setup
        .operations
        .iter()
        .zip(paths)
        .enumerate()
        .map(|(k, (&op, path))| {
            let time = match &times {
                Ok(t) => t
                    .get(k)
                    .copied()
                    .ok_or_else(|| "not in the program".to_string()),
                Err(e) => Err(e.clone()),
            };
            operation_row(project, op, path, time)
        })
        .collect();
    Ok(SheetSetup {
        number: s + 1,
        name: setup.name.clone(),
        machine: setup.machine_name(project).to_string(),
        work_offset: setup.frame.work_offset_code(),
        tool_axis: [axis.x, axis.y, axis.z],
        stock_size_mm: [size.x, size.y, size.z],
        stock: stock_text,
        workholding: setup
            .workholding
            .iter()
            .map(|w| w.kind_name().to_string())
            .collect(),
        picture,
        operations,
    })
}

/// The jerk-limited time of each operation of setup `s` in the setup's posted program (as
/// `talas job --post` writes it, on the setup's machine: a tilted setup with its rotary
/// positioning), s: from the first line the operation writes to its last.
fn setup_times(project: &Project, s: usize, paths: &[Toolpath]) -> Result<Vec<f64>, String> {
    let posted = post_setup(project, s, paths).map_err(|e| e.to_string())?;
    let (machine, _) = resolve_setup(project, s).map_err(|e| e.to_string())?;
    let options = InterpretOptions {
        machine: Some(machine.clone()),
        ..InterpretOptions::for_syntax(Syntax::detect(&posted.text))
    };
    let program =
        interpret(&posted.text, &options).map_err(|e| format!("line {}: {}", e.line, e.message))?;
    let lines = posted.text.lines().count();
    let motion = RunMotion::plan(program, &machine, RUN_CORNER_TOLERANCE_MM, lines, &[])
        .map_err(|e| e.to_string())?;
    let mut spans: Vec<(f64, f64)> = vec![(f64::INFINITY, f64::NEG_INFINITY); paths.len()];
    for (line, span) in motion.line_spans.iter().enumerate() {
        let (Some(span), Some(src)) = (span, posted.source_of_line.get(line)) else {
            continue;
        };
        if let Some(t) = spans.get_mut(src.operation) {
            t.0 = t.0.min(span.start_s);
            t.1 = t.1.max(span.end_s);
        }
    }
    Ok(spans
        .into_iter()
        .map(|(a, b)| if b >= a { b - a } else { 0.0 })
        .collect())
}

/// Operation `op`'s row from its linked path, with its cycle time in the setup's program.
fn operation_row(
    project: &Project,
    op: usize,
    path: &Toolpath,
    cycle_time_s: Result<f64, String>,
) -> SheetOperation {
    let o: &Operation = &project.operations[op];
    let cut_feed = path
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .map(|p| p.feed_mm_per_min)
        .fold(0.0_f64, f64::max);
    let common = o.common();
    let above = |h: crate::project::op_common::Height| {
        let from = match h.from {
            HeightFrom::StockTop => "the stock's top",
            HeightFrom::PartTop => "the part's top",
            HeightFrom::Origin => "the setup origin",
        };
        format!("{:.1} mm above {from}", h.mm)
    };
    let heights = common.map_or_else(
        || "from the part (the strategy's clearance)".to_string(),
        |c| {
            format!(
                "clearance {}, retract {}, feed from {}",
                above(c.clearance),
                above(c.retract),
                above(c.feed_from)
            )
        },
    );
    let tool_number = o.tool() + 1;
    SheetOperation {
        number: op + 1,
        name: o.name().to_string(),
        strategy: o.kind().label().to_string(),
        tool: tool_number,
        feed_mm_per_min: common.map_or(cut_feed, |c| c.feed_mm_per_min),
        plunge_mm_per_min: common.and_then(|c| c.plunge_feed_mm_per_min),
        spindle_rpm: common
            .and_then(|c| c.spindle_rpm)
            .unwrap_or(project.post.spindle_rpm),
        heights,
        speeds_from: crate::project::cutting::SpeedsOrigin::of(project, o).describe(),
        time_at_feed_s: path.summary.estimated_time_s,
        cycle_time_s,
        warnings: Vec::new(),
    }
}

/// The tools the chosen setups use, by number.
#[must_use]
pub fn tools(project: &Project, setups: &[usize]) -> Vec<SheetTool> {
    let mut used: Vec<usize> = setups
        .iter()
        .flat_map(|&s| project.setups[s].operations.iter())
        .flat_map(|&op| project.operations[op].tools_used())
        .collect();
    used.sort_unstable();
    used.dedup();
    used.into_iter()
        .filter_map(|i| {
            let t = project.tools.get(i)?;
            let c = &t.cutter;
            let holder = if c.holder.is_empty() {
                "none given".to_string()
            } else {
                c.holder
                    .iter()
                    .map(|h| format!("Ø{:.1} × {:.1}", h.diameter, h.length))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            Some(SheetTool {
                number: i + 1,
                name: t.name.clone(),
                spec: crate::tools::tool_spec(c),
                diameter_mm: c.diameter,
                flute_mm: c.flute_length,
                stick_out_mm: c.overall_length,
                holder,
            })
        })
        .collect()
}
