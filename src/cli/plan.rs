//! `talas plan FILE --tool SPEC --strategy NAME --scallop H --tolerance E [options] -o PATH.json`:
//! a finishing tool path on one face of a STEP part (iso-parametric, iso-planar, iso-scallop), or
//! on the whole part's mesh (raster, waterline and steep-and-shallow finishing, Z-level
//! roughing; see [`super::plan_mesh`]), written as the contract's tool-path JSON.

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde_json::{Value, json};

use crate::checks::part::PartCheck;
use crate::cli::plan_mesh::{MeshPlanOptions, plan_mesh_computed};
use crate::diagnostics::Progress;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::trim::{REGION_CHORD_MM, TrimRegion};
use crate::import::step::read_step;
use crate::import::{ImportError, OpenOptions, Workpiece};
use crate::project::pipeline::{self, ComputeError, Computed};
use crate::project::{FINISH_3AXIS_CLEARANCE_MM, Operation, Project, Stock, ToolEntry};
use crate::strategies::boundary::BoundaryRule;
use crate::strategies::finish::axis::AxisMode;
use crate::strategies::finish::face::FacePatch;
use crate::strategies::finish::plan::plan_finish_in;
use crate::strategies::finish::tiltaway::{PartContext, TiltAway};
use crate::strategies::finish::{Direction, FinishOptions, Pattern, Strategy};
use crate::toolpath::Toolpath;
use crate::tools::parse_tool_spec;

/// Options of `talas plan`.
#[derive(Debug, clap::Args)]
pub struct PlanArgs {
    /// The part: .stp/.step (mm) for every strategy, .stl also for `raster` and `zlevel-rough`.
    pub file: PathBuf,
    /// The tool: `ball:d=6`, `flat:d=10`, `bull:d=10,r=2`, optionally `,flute=20,shank=8`.
    #[arg(long, value_name = "SPEC")]
    pub tool: String,
    /// Strategy: `iso-parametric`, `iso-planar`, `iso-scallop` (5-axis finishing of one exact
    /// face), `raster` (3-axis drop-cutter finishing of the whole part), `waterline` (Z-level
    /// finishing; `--angle`: slopes flatter than it set no limit on the step-down, default 30),
    /// `steep-shallow` (waterline above `--angle`, default 45, raster below), `pencil` (along
    /// valleys and corners where a ball touches twice; `--angle`: smallest angle between the two
    /// contact normals, default 20), `rest` (parallel passes where `--reference-tool` left more
    /// than the scallop height) or `zlevel-rough` (Z-level roughing from a stock).
    #[arg(long, value_name = "NAME")]
    pub strategy: String,
    /// Target scallop height h, mm.
    #[arg(long, value_name = "H", default_value_t = 0.01)]
    pub scallop: f64,
    /// Chord tolerance ε of the tool-tip path, mm.
    #[arg(long, value_name = "E", default_value_t = 0.01)]
    pub tolerance: f64,
    /// `zlevel-rough`: the stock, `box` (the default stock: the part's box plus 2 mm on the
    /// sides and the top), `box:X0,Y0,Z0,X1,Y1,Z1`, `cylinder` (the default cylinder around the
    /// part) or `cylinder:CX,CY,R,Z0,Z1` (centre, radius, bottom and top), mm.
    #[arg(long, value_name = "STOCK", default_value = "box")]
    pub stock: String,
    /// `zlevel-rough`: step-down between levels, mm.
    #[arg(long, value_name = "MM", default_value_t = 2.0)]
    pub step_down: f64,
    /// `zlevel-rough`: step-over as a fraction of the tool diameter.
    #[arg(long, value_name = "FRACTION", default_value_t = 0.4)]
    pub step_over: f64,
    /// `zlevel-rough`: stock to leave on walls (radial), mm.
    #[arg(long, value_name = "MM", default_value_t = 0.3)]
    pub stock_to_leave: f64,
    /// `zlevel-rough`: stock to leave on floors (axial), mm.
    #[arg(long, value_name = "MM", default_value_t = 0.3)]
    pub stock_to_leave_axial: f64,
    /// `zlevel-rough`: no extra level at flat areas (by default each flat floor between two
    /// levels gets its own level at the floor plus the stock to leave).
    #[arg(long)]
    pub no_flat_levels: bool,
    /// Lead (the thesis's Sturz): tilt of the axis from the normal toward the feed, degrees.
    /// Raised automatically where a flat or bull-nose cutter would gouge locally.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_hyphen_values = true
    )]
    pub lead: f64,
    /// Sideways tilt of the axis (toward n × feed), degrees.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_hyphen_values = true
    )]
    pub tilt: f64,
    /// Tool axis mode instead of the normal with lead/tilt: `fixed:I,J,K` (3-axis: `fixed:0,0,1`),
    /// `toward:X,Y,Z`, `away:X,Y,Z` (a point), `toward-line:X,Y,Z,I,J,K`, `away-line:...`.
    #[arg(long, value_name = "MODE")]
    pub axis: Option<String>,
    /// Face index (0-based, file order), default 0; several (`--face 3,4,7`) plan one
    /// operation over the face group, the faces' paths joined in that order at one clearance.
    #[arg(
        long,
        value_name = "K[,K...]",
        value_delimiter = ',',
        default_value = "0"
    )]
    pub face: Vec<usize>,
    /// Feed, mm/min.
    #[arg(long, value_name = "F", default_value_t = 1000.0)]
    pub feed: f64,
    /// Parameter the passes run along: `u` or `v`.
    #[arg(long, value_name = "u|v", default_value = "v")]
    pub direction: String,
    /// Pattern: `zigzag` (two-way), `oneway` or (iso-parametric) `spiral`; waterline and
    /// steep-shallow: `climb` (default) or `conventional`.
    #[arg(long, value_name = "PATTERN", default_value = "zigzag")]
    pub pattern: String,
    /// Waterline and steep-shallow: how each loop is entered: `plunge` (default), `arc[:R]`
    /// (tangential lead-in and lead-out of radius R mm, default the tool's radius) or
    /// `ramp[:DEG]` (down along the loop from 1 mm above, default 5°).
    #[arg(long, value_name = "plunge|arc[:R]|ramp[:DEG]")]
    pub entry: Option<String>,
    /// Iso-planar: angle of the planes' normal from +x about +z; raster: direction of the
    /// passes from +x; degrees.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_hyphen_values = true
    )]
    pub angle: f64,
    /// Clearance plane height z, mm (default: 5 mm above the path and the face); for `raster`
    /// and `zlevel-rough`, the height above the part (stock), default 5 mm.
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub clearance: Option<f64>,
    /// Largest change of the tool axis between poses, degrees.
    #[arg(long, value_name = "DEG", default_value_t = 5.0)]
    pub max_axis_step: f64,
    /// Radius of tangential lead-in/lead-out arcs at the ends of the passes entered from
    /// above, mm (0: plunge straight onto the pass).
    #[arg(long, value_name = "MM", default_value_t = 0.0)]
    pub lead_arc: f64,
    /// Check every pose and cutting move for gouges against the exact surface and put the
    /// result in the summary's gouge report (slower).
    #[arg(long)]
    pub check: bool,
    /// Check the path's tool axes against this machine's axis limits (`talas machines`, or a
    /// machine JSON file) and say where it cannot follow.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub machine: Option<String>,
    /// Tilt the tool axis away from the part's other faces where the flutes, shank or holder
    /// would enter them, by at most this many degrees (2°/mm along the path); spans that no
    /// such tilt frees are left out and reported (0: never tilt, only leave out).
    #[arg(long, value_name = "DEG")]
    pub tilt_away: Option<f64>,
    /// Largest angle of the tool axis from vertical allowed to the tilt-away, degrees (the
    /// machine's tilt travel).
    #[arg(long, value_name = "DEG", default_value_t = 90.0)]
    pub max_tilt: f64,
    /// Largest tilt-away where no tilt within `--tilt-away` frees the tool (the wall of a hole
    /// whose far side the flutes reach), degrees, still within `--max-tilt` (0, the default:
    /// never beyond `--tilt-away`; such spans are left out and reported).
    #[arg(long, value_name = "DEG", default_value_t = 0.0)]
    pub steep_tilt: f64,
    /// Print one JSON document (summary and diagnostics) instead of the human summary.
    #[arg(long)]
    pub json: bool,
    /// `rest`: the earlier, larger tool whose leftovers are finished, e.g. `ball:d=10`.
    #[arg(long, value_name = "SPEC")]
    pub reference_tool: Option<String>,
    /// `rest`: finish what the `--after` paths, cut in order into `--stock`, left (instead of
    /// what `--reference-tool` alone would leave).
    #[arg(long)]
    pub from_stock: bool,
    /// `rest --from-stock`: an earlier tool path (`talas plan … -o PATH.json`, its tool inside),
    /// cut into the stock before this one; repeat in cutting order.
    #[arg(long, value_name = "PATH.json")]
    pub after: Vec<PathBuf>,
    /// 3-axis finishing: cut only inside `silhouette` (the part's outline from above),
    /// `faces:F,F,...` (part face numbers), a polygon `X,Y;X,Y;X,Y` (mm), or the closed loop
    /// of a `.csv` (`X,Y` a line) or `.dxf` (first LWPOLYLINE / POLYLINE) file.
    #[arg(long, value_name = "REGION", allow_hyphen_values = true)]
    pub boundary: Option<String>,
    /// Which point must lie inside the boundary: `centre` (tool tip) or `contact`.
    #[arg(long, value_name = "RULE", default_value = "centre")]
    pub boundary_rule: String,
    /// Where to write the tool path JSON.
    #[arg(short = 'o', long = "output", value_name = "PATH.json")]
    pub output: PathBuf,
    #[command(flatten)]
    pub holes: Box<super::plan_holes::HoleArgs>,
    /// 2.5D strategies (`pocket`, `contour`): regions and their options.
    #[command(flatten)]
    pub planar: Box<super::plan_25d::PlanarArgs>,
}

pub(crate) fn opt_err(name: &str, message: impl Into<String>) -> ImportError {
    ImportError::new(Path::new(name), None, message)
}

fn numbers(text: &str, n: usize, name: &str) -> Result<Vec<f64>, ImportError> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| opt_err(name, format!("'{text}' is not {n} comma-separated numbers")))?;
    if v.len() != n || v.iter().any(|x| !x.is_finite()) {
        return Err(opt_err(
            name,
            format!("'{text}' is not {n} comma-separated numbers"),
        ));
    }
    Ok(v)
}

fn parse_axis(args: &PlanArgs) -> Result<AxisMode, ImportError> {
    let Some(text) = &args.axis else {
        return Ok(AxisMode::Normal {
            lead: args.lead.to_radians(),
            tilt: args.tilt.to_radians(),
        });
    };
    let (kind, rest) = text.split_once(':').unwrap_or((text.as_str(), ""));
    let v3 = |v: &[f64], k: usize| DVec3::new(v[k], v[k + 1], v[k + 2]);
    match kind {
        "fixed" => {
            let v = numbers(rest, 3, "--axis")?;
            let a = v3(&v, 0)
                .try_normalize()
                .ok_or_else(|| opt_err("--axis", "the fixed axis has zero length"))?;
            Ok(AxisMode::Fixed(a))
        }
        "toward" | "away" => {
            let v = numbers(rest, 3, "--axis")?;
            Ok(if kind == "toward" {
                AxisMode::TowardPoint(v3(&v, 0))
            } else {
                AxisMode::AwayFromPoint(v3(&v, 0))
            })
        }
        "toward-line" | "away-line" => {
            let v = numbers(rest, 6, "--axis")?;
            let d = v3(&v, 3)
                .try_normalize()
                .ok_or_else(|| opt_err("--axis", "the line direction has zero length"))?;
            Ok(if kind == "toward-line" {
                AxisMode::TowardLine(v3(&v, 0), d)
            } else {
                AxisMode::AwayFromLine(v3(&v, 0), d)
            })
        }
        other => Err(opt_err(
            "--axis",
            format!("unknown axis mode '{other}' (fixed, toward, away, toward-line, away-line)"),
        )),
    }
}

fn parse_strategy(args: &PlanArgs) -> Result<Strategy, ImportError> {
    match args.strategy.as_str() {
        "iso-parametric" => {
            let pattern = match args.pattern.as_str() {
                "zigzag" => Pattern::Zigzag,
                "oneway" => Pattern::Oneway,
                "spiral" => Pattern::Spiral,
                other => {
                    return Err(opt_err(
                        "--pattern",
                        format!("unknown pattern '{other}' (zigzag, oneway, spiral)"),
                    ));
                }
            };
            Ok(Strategy::IsoParametric { pattern })
        }
        "iso-planar" => {
            if !args.angle.is_finite() {
                return Err(opt_err("--angle", "the angle must be a finite number"));
            }
            Ok(Strategy::IsoPlanar {
                angle: args.angle.to_radians(),
            })
        }
        "iso-scallop" => Ok(Strategy::IsoScallop),
        "raster" | "zlevel-rough" => Err(opt_err(
            "--strategy",
            format!(
                "'{}' plans on a mesh, not on one face (internal dispatch error)",
                args.strategy
            ),
        )),
        other => Err(opt_err(
            "--strategy",
            format!(
                "unknown strategy '{other}' (iso-parametric, iso-planar, iso-scallop, raster, waterline, steep-shallow, pencil, rest, zlevel-rough; holes: drill, dwell, peck, chip-break, tap, bore, ream, helical-bore, thread-mill, spot)"
            ),
        )),
    }
}

/// Plan, save the tool path, and build the JSON report. Every strategy runs as a one-operation
/// project through [`crate::project::pipeline::compute`], the workstation's path, so the same
/// settings give the same tool path in both.
///
/// # Errors
/// An [`ImportError`] naming the file (and the face) or the bad option.
pub fn plan(args: &PlanArgs) -> Result<Value, ImportError> {
    if super::plan_holes::HOLE_STRATEGIES.contains(&args.strategy.as_str()) {
        let a = args;
        let mut holes = (*a.holes).clone();
        holes.depth = a.planar.depth;
        return super::plan_holes::plan_holes_cli(
            &a.file,
            &a.strategy,
            &a.tool,
            a.feed,
            a.clearance,
            &a.output,
            &holes,
        );
    }
    if super::plan_mesh::MESH_STRATEGIES.contains(&args.strategy.as_str()) {
        return plan_on_mesh(args);
    }
    if super::plan_25d::PLANAR_STRATEGIES.contains(&args.strategy.as_str()) {
        return super::plan_25d::plan_planar(args);
    }
    let cutter = parse_tool_spec(&args.tool).map_err(|e| opt_err("--tool", e.to_string()))?;
    let strategy = parse_strategy(args)?;
    let direction = match args.direction.as_str() {
        "u" => Direction::U,
        "v" => Direction::V,
        other => return Err(opt_err("--direction", format!("'{other}' is not u or v"))),
    };
    let opts = FinishOptions {
        scallop: args.scallop,
        tolerance: args.tolerance,
        axis: parse_axis(args)?,
        feed: args.feed,
        direction,
        clearance: args.clearance,
        max_axis_step: args.max_axis_step.to_radians(),
        exact_check: args.check,
        curvature_lead: true,
        lead_arc_mm: args.lead_arc,
    };
    let part = read_step(&args.file)?;
    if args.face.len() > 1 {
        return super::plan_group::plan_group_cli(args, &part, &cutter, strategy, &opts);
    }
    let index = args.face.first().copied().unwrap_or(0);
    let face = part.faces.get(index).ok_or_else(|| {
        ImportError::new(
            &args.file,
            Some(format!("face {index}")),
            format!("the part has {} faces", part.faces.len()),
        )
    })?;
    let place = Some(format!("face {index} (#{})", face.source_id));
    let face_err = |e: crate::strategies::finish::PlanError| {
        ImportError::new(&args.file, place.clone(), e.to_string())
    };
    let region = TrimRegion::of_face(face, &part, REGION_CHORD_MM).map_err(|e| {
        face_err(crate::strategies::finish::PlanError::Face(format!(
            "its trimming loops: {e}"
        )))
    })?;
    let patch = FacePatch::trimmed(&part, index, &region).map_err(face_err)?;
    let whole = if args.check || args.tilt_away.is_some() {
        Some(whole_part(args, &part)?)
    } else {
        None
    };
    let skip = [index];
    let context = whole.as_ref().map(|(wp, bvh)| PartContext {
        check: PartCheck::of_workpiece(wp, bvh, &skip),
        tilt: args.tilt_away.map(|deg| TiltAway {
            max_angle_rad: deg.to_radians(),
            max_from_vertical_rad: args.max_tilt.to_radians(),
            steep_angle_rad: args.steep_tilt.to_radians(),
            ..TiltAway::default()
        }),
    });
    let result = plan_finish_in(
        patch,
        &cutter,
        &crate::tools::tool_spec(&cutter),
        strategy,
        &opts,
        context.as_ref(),
    )
    .map_err(face_err)?;
    result
        .toolpath
        .save(&args.output)
        .map_err(|e| ImportError::new(&args.output, Some(e.place.clone()), e.message.clone()))?;
    let mut diagnostics = result.diagnostics.clone();
    if let Some(m) = &args.machine {
        let machine = crate::machine::Machine::resolve(m)
            .map_err(|e| ImportError::new(Path::new(m), None, e.to_string()))?;
        diagnostics.extend(crate::project::reach::unreachable_axes(
            &result.toolpath,
            &machine,
        ));
    }
    let s = &result.toolpath.summary;
    Ok(json!({
        "file": args.file.display().to_string(),
        "output": args.output.display().to_string(),
        "face": index,
        "strategy": args.strategy,
        "tool": args.tool,
        "summary": s,
        "passes": result.passes.len(),
        "lead_deg": result.used.axis.lead().to_degrees(),
        "clearance_mm": result.used.clearance,
        "diagnostics": diagnostics,
        "part_hits": result.part_hits,
        "left_out": result.left_out,
    }))
}

/// The whole part as check: the part tessellated as `talas` opens it, and its hierarchy.
pub(crate) fn whole_part(
    args: &PlanArgs,
    part: &crate::geometry::brep::Part,
) -> Result<(Workpiece, std::sync::Arc<MeshBvh>), ImportError> {
    for (name, v) in [
        ("--tilt-away", args.tilt_away),
        ("--max-tilt", Some(args.max_tilt)),
        ("--steep-tilt", Some(args.steep_tilt)),
    ] {
        if let Some(v) = v
            && !(v.is_finite() && (0.0..=90.0).contains(&v))
        {
            return Err(opt_err(
                name,
                format!("{v} is not between 0 and 90 degrees"),
            ));
        }
    }
    let wp = Workpiece::from_part(&args.file, part.clone(), &OpenOptions::default());
    let bvh = wp
        .bvh()
        .map_err(|e| ImportError::new(&args.file, None, e))?;
    Ok((wp, bvh))
}

/// Run `operation` on `part` as a one-operation project with the library `tools` (the
/// operation's tool first) and `stock`, through [`crate::project::pipeline::compute`]. With
/// `machine` the tool axes are checked against that machine's limits. Errors name the file and
/// `place` (the face, or the strategy).
pub(crate) fn compute_one(
    part: &Workpiece,
    tools: Vec<ToolEntry>,
    stock: Stock,
    operation: Operation,
    machine: Option<&str>,
    place: &str,
) -> Result<Computed, ImportError> {
    if let Some(m) = machine {
        crate::machine::Machine::resolve(m)
            .map_err(|e| ImportError::new(Path::new(m), None, e.to_string()))?;
    }
    let project = Project {
        stock,
        tools,
        selected_tool: Some(0),
        // No machine: no reach check (an unresolvable name skips it).
        machine: machine.unwrap_or_default().to_string(),
        operations: vec![operation],
        ..Project::default()
    };
    pipeline::compute(&project, 0, part, &Progress::new()).map_err(|e| {
        let message = match e {
            ComputeError::Face { message, .. } | ComputeError::Plan { message, .. } => message,
            other => other.to_string(),
        };
        ImportError::new(&part.source, Some(place.to_string()), message)
    })
}

/// Write `toolpath` to `output`, the error naming the file.
fn save(toolpath: &Toolpath, output: &Path) -> Result<(), ImportError> {
    toolpath
        .save(output)
        .map_err(|e| ImportError::new(output, Some(e.place.clone()), e.message.clone()))
}

/// The mesh strategies (raster, waterline, steep-and-shallow, pencil, rest, Z-level
/// roughing): plan on the part's mesh, save, report.
fn plan_on_mesh(args: &PlanArgs) -> Result<Value, ImportError> {
    let opts = MeshPlanOptions {
        scallop_mm: args.scallop,
        tolerance_mm: args.tolerance,
        angle_deg: args.angle,
        pattern: args.pattern.clone(),
        stock: args.stock.clone(),
        step_down_mm: args.step_down,
        step_over_fraction: args.step_over,
        stock_to_leave_radial_mm: args.stock_to_leave,
        stock_to_leave_axial_mm: args.stock_to_leave_axial,
        feed_mm_per_min: args.feed,
        clearance_mm: args.clearance.unwrap_or(FINISH_3AXIS_CLEARANCE_MM),
        detect_flats: !args.no_flat_levels,
        reference_tool: args.reference_tool.clone(),
        from_stock: args.from_stock,
        after: args.after.clone(),
        boundary: args.boundary.clone(),
        entry: args.entry.clone(),
        boundary_rule: match args.boundary_rule.as_str() {
            "centre" | "center" => BoundaryRule::ToolCentre,
            "contact" => BoundaryRule::Contact,
            other => {
                return Err(ImportError::new(
                    &args.file,
                    Some("--boundary-rule".into()),
                    format!("unknown boundary rule '{other}' (centre, contact)"),
                ));
            }
        },
    };
    let computed = plan_mesh_computed(
        &args.file,
        &args.strategy,
        &args.tool,
        &opts,
        args.machine.as_deref(),
    )?;
    save(&computed.toolpath, &args.output)?;
    Ok(json!({
        "file": args.file.display().to_string(),
        "output": args.output.display().to_string(),
        "strategy": args.strategy,
        "tool": args.tool,
        "summary": computed.toolpath.summary,
        "passes": computed.passes,
        "diagnostics": computed.diagnostics,
    }))
}

/// A short human summary of the JSON document.
#[must_use]
pub fn human(doc: &Value) -> String {
    let s = &doc["summary"];
    let face = doc["face"]
        .as_u64()
        .map_or_else(String::new, |f| format!(" face {f}"));
    let mut notes = String::new();
    for d in doc["diagnostics"].as_array().into_iter().flatten() {
        notes.push_str(&format!(
            "{}: {}\n",
            d["severity"].as_str().unwrap_or("note"),
            d["message"].as_str().unwrap_or("")
        ));
    }
    notes
        + &format!(
            "{} on {}{}: {} passes, {} poses, cut {:.1} mm, other {:.1} mm, {:.1} s at feed{}{}\n\
             wrote {}\n",
            doc["strategy"].as_str().unwrap_or("?"),
            doc["file"].as_str().unwrap_or("?"),
            face,
            doc["passes"],
            s["pose_count"],
            s["cut_length_mm"].as_f64().unwrap_or(0.0),
            s["other_length_mm"].as_f64().unwrap_or(0.0),
            s["estimated_time_s"].as_f64().unwrap_or(0.0),
            // Roughing predicts no scallop: say nothing rather than "?".
            s["predicted_max_scallop_mm"]
                .as_f64()
                .map_or_else(String::new, |h| format!(
                    ", predicted max scallop {h:.4} mm"
                )),
            not_reached(s),
            doc["output"].as_str().unwrap_or("?"),
        )
}

/// ", at N poses the next pass does not reach (scallop not predicted there)" when any.
fn not_reached(s: &Value) -> String {
    s["scallop_not_reached_poses"]
        .as_u64()
        .map_or_else(String::new, |n| {
            format!(", at {n} poses the next pass does not reach (scallop not predicted there)")
        })
}
