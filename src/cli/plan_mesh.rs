//! Planning on meshes for `talas plan`: raster, waterline, steep-and-shallow,
//! pencil and rest finishing and Z-level roughing of an STL file or of a STEP part tessellated
//! at the chord tolerance, each as a one-operation project through the workstation's pipeline.

use std::path::Path;

use super::plan::compute_one;
use crate::diagnostics::{Diagnostic, Progress};
use crate::geometry::stock::StockSpec;
use crate::import::ImportError;
use crate::project::pipeline::{ComputeError, Computed, compute_rest_after};
use crate::project::{Operation, Stock, ToolEntry};
use crate::strategies::boundary::{
    Boundary, BoundaryRule, Region, polygon_from_csv, polygon_from_dxf,
};
use crate::strategies::pencil::PENCIL_DEFAULT_ANGLE_DEG;
use crate::strategies::steep_shallow::{
    STEEP_SHALLOW_DEFAULT_ANGLE_DEG, WATERLINE_DEFAULT_ANGLE_DEG,
};
use crate::strategies::waterline::{Cut, Entry};
use crate::toolpath::Toolpath;
use crate::tools::{Cutter, parse_tool_spec};

/// Options of [`plan_mesh`] (each strategy reads the ones it needs).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MeshPlanOptions {
    /// Raster: scallop height, mm.
    pub scallop_mm: f64,
    /// Chord tolerance (raster polyline, STEP tessellation, roughing contours), mm.
    pub tolerance_mm: f64,
    /// Raster: pass direction, degrees from +X.
    pub angle_deg: f64,
    /// Raster: `zigzag` or `oneway`.
    pub pattern: String,
    /// Roughing stock in the one `--stock` syntax ([`StockSpec::parse`]; `box` is the default
    /// stock around the part); the finishing strategies ignore it.
    pub stock: String,
    /// Roughing step-down, mm.
    pub step_down_mm: f64,
    /// Roughing step-over as a fraction of the tool diameter.
    pub step_over_fraction: f64,
    /// Roughing stock to leave: radial (XY), mm.
    pub stock_to_leave_radial_mm: f64,
    /// Roughing stock to leave: axial (Z), mm.
    pub stock_to_leave_axial_mm: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Clearance above the part (raster) or the stock (roughing), mm.
    pub clearance_mm: f64,
    /// Roughing: a level of its own for each flat area between two levels.
    #[serde(default = "detect_flats_default")]
    pub detect_flats: bool,
    /// Rest finishing: the earlier, larger tool's spec (e.g. `ball:d=10`).
    #[serde(default)]
    pub reference_tool: Option<String>,
    /// Rest finishing: the rest is what the `after` paths left in the stock (`stock`).
    #[serde(default)]
    pub from_stock: bool,
    /// Rest finishing from the stock: the earlier tool path files, in cutting order.
    #[serde(default)]
    pub after: Vec<std::path::PathBuf>,
    /// Finishing: limit the path to a boundary (`silhouette`, `faces:F,F`, a polygon
    /// `X,Y;X,Y;X,Y` in mm, or a `.csv` / `.dxf` file holding a closed loop).
    #[serde(default)]
    pub boundary: Option<String>,
    /// The boundary's rule: the tool centre or the contact point must lie inside.
    #[serde(default)]
    pub boundary_rule: BoundaryRule,
    /// Waterline and steep-and-shallow: the loops' entry (`plunge`, `arc[:R]`, `ramp[:DEG]`;
    /// `None`: plunge).
    #[serde(default)]
    pub entry: Option<String>,
}

fn detect_flats_default() -> bool {
    true
}

impl Default for MeshPlanOptions {
    fn default() -> Self {
        Self {
            scallop_mm: 0.01,
            tolerance_mm: 0.01,
            angle_deg: 0.0,
            pattern: "zigzag".into(),
            stock: "box".into(),
            step_down_mm: 2.0,
            step_over_fraction: 0.4,
            stock_to_leave_radial_mm: 0.3,
            stock_to_leave_axial_mm: 0.3,
            feed_mm_per_min: 1000.0,
            clearance_mm: 5.0,
            detect_flats: true,
            reference_tool: None,
            from_stock: false,
            after: Vec::new(),
            boundary: None,
            boundary_rule: BoundaryRule::ToolCentre,
            entry: None,
        }
    }
}

/// The strategies [`plan_mesh`] plans.
pub const MESH_STRATEGIES: [&str; 6] = [
    "raster",
    "zlevel-rough",
    "waterline",
    "steep-shallow",
    "pencil",
    "rest",
];

/// The one-operation [`Operation`] of `strategy` with `opts` (tool number 0).
///
/// Waterline's `--angle` (slopes flatter than it set no limit on the step-down) is 30° when 0,
/// steep-and-shallow's (the threshold) 45°.
fn mesh_operation(
    file: &Path,
    strategy: &str,
    opts: &MeshPlanOptions,
) -> Result<Operation, ImportError> {
    let bad = |what: &str, msg: String| ImportError::new(file, Some(what.to_string()), msg);
    let name = strategy.to_string();
    let angle = |default: f64| {
        if opts.angle_deg == 0.0 {
            default
        } else {
            opts.angle_deg
        }
        .to_radians()
    };
    let cut = || match opts.pattern.as_str() {
        "zigzag" | "zig-zag" | "climb" => Ok(Cut::Climb),
        "conventional" => Ok(Cut::Conventional),
        other => Err(bad(
            "--pattern",
            format!("waterline direction must be 'climb' or 'conventional', got '{other}'"),
        )),
    };
    let entry = match opts.entry.as_deref() {
        None => Entry::Plunge,
        Some(_) if !matches!(strategy, "waterline" | "steep-shallow") => {
            return Err(bad(
                "--entry",
                "an entry is only for waterline and steep-shallow".into(),
            ));
        }
        Some(s) => s.parse::<Entry>().map_err(|e| bad("--entry", e))?,
    };
    let mut op = match strategy {
        "raster" => Operation::Raster {
            name,
            tool: 0,
            scallop_mm: opts.scallop_mm,
            angle_rad: opts.angle_deg.to_radians(),
            one_way: match opts.pattern.as_str() {
                "zigzag" | "zig-zag" => false,
                "oneway" | "one-way" => true,
                other => {
                    return Err(bad(
                        "--pattern",
                        format!("pattern must be 'zigzag' or 'oneway', got '{other}'"),
                    ));
                }
            },
            tolerance_mm: opts.tolerance_mm,
            feed_mm_per_min: opts.feed_mm_per_min,
            clearance_mm: opts.clearance_mm,
            boundary: None,
        },
        "waterline" => Operation::Waterline {
            name,
            tool: 0,
            scallop_mm: opts.scallop_mm,
            tolerance_mm: opts.tolerance_mm,
            angle_rad: angle(WATERLINE_DEFAULT_ANGLE_DEG),
            cut: cut()?,
            feed_mm_per_min: opts.feed_mm_per_min,
            clearance_mm: opts.clearance_mm,
            entry,
            boundary: None,
        },
        "steep-shallow" => Operation::SteepShallow {
            name,
            tool: 0,
            scallop_mm: opts.scallop_mm,
            tolerance_mm: opts.tolerance_mm,
            angle_rad: angle(STEEP_SHALLOW_DEFAULT_ANGLE_DEG),
            cut: cut()?,
            feed_mm_per_min: opts.feed_mm_per_min,
            clearance_mm: opts.clearance_mm,
            entry,
            boundary: None,
        },
        "zlevel-rough" => Operation::Rough {
            name,
            tool: 0,
            step_down_mm: opts.step_down_mm,
            step_over_fraction: opts.step_over_fraction,
            stock_to_leave_mm: opts.stock_to_leave_radial_mm,
            stock_to_leave_axial_mm: Some(opts.stock_to_leave_axial_mm),
            tolerance_mm: opts.tolerance_mm,
            feed_mm_per_min: opts.feed_mm_per_min,
            flat_levels: opts.detect_flats,
            clearance_mm: opts.clearance_mm,
        },
        "pencil" => Operation::Pencil {
            name,
            tool: 0,
            angle_rad: angle(PENCIL_DEFAULT_ANGLE_DEG),
            tolerance_mm: opts.tolerance_mm,
            feed_mm_per_min: opts.feed_mm_per_min,
            clearance_mm: opts.clearance_mm,
            boundary: None,
        },
        "rest" => Operation::Rest {
            name,
            tool: 0,
            reference_tool: 1,
            from_stock: opts.from_stock,
            scallop_mm: opts.scallop_mm,
            tolerance_mm: opts.tolerance_mm,
            feed_mm_per_min: opts.feed_mm_per_min,
            clearance_mm: opts.clearance_mm,
            boundary: None,
        },
        other => {
            return Err(bad(
                "--strategy",
                format!(
                    "mesh strategies are {}, got '{other}'",
                    MESH_STRATEGIES.join(", ")
                ),
            ));
        }
    };
    if let Some(text) = &opts.boundary {
        let boundary = cli_boundary(text, opts.boundary_rule).map_err(|e| bad("--boundary", e))?;
        let Some(slot) = op.boundary_mut() else {
            return Err(bad(
                "--boundary",
                "boundaries limit the finishing strategies, not roughing".into(),
            ));
        };
        *slot = Some(boundary);
    }
    Ok(op)
}

/// `--boundary`'s region: a `.csv` or `.dxf` file holding a closed loop
/// ([`polygon_from_csv`], [`polygon_from_dxf`]), else the text [`Boundary::parse`] reads.
fn cli_boundary(text: &str, rule: BoundaryRule) -> Result<Boundary, String> {
    let path = Path::new(text.trim());
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let loop_of: fn(&str) -> Result<Vec<[f64; 2]>, String> = match ext.as_deref() {
        Some("csv") => polygon_from_csv,
        Some("dxf") => polygon_from_dxf,
        _ => return Boundary::parse(text, rule),
    };
    let content = crate::storage::read_text_bounded(path, crate::storage::TEXT_LIMIT_BYTES)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let boundary = Boundary {
        region: Region::Polygon(loop_of(&content).map_err(|e| format!("{}: {e}", path.display()))?),
        rule,
    };
    boundary
        .validate()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(boundary)
}

/// Plan `strategy` (one of [`MESH_STRATEGIES`]) on the part in `file` with the tool `tool_spec`.
///
/// # Errors
/// An [`ImportError`] naming the file for unreadable input, and naming the option for a bad
/// tool spec, strategy, pattern, stock or value.
pub fn plan_mesh(
    file: &Path,
    strategy: &str,
    tool_spec: &str,
    opts: &MeshPlanOptions,
) -> Result<Toolpath, ImportError> {
    plan_mesh_noted(file, strategy, tool_spec, opts).map(|(tp, _)| tp)
}

/// [`plan_mesh`] with the planner's notes (steep walls, material no step-over removes, added
/// flat levels, ...).
///
/// # Errors
/// As [`plan_mesh`].
pub fn plan_mesh_noted(
    file: &Path,
    strategy: &str,
    tool_spec: &str,
    opts: &MeshPlanOptions,
) -> Result<(Toolpath, Vec<Diagnostic>), ImportError> {
    plan_mesh_computed(file, strategy, tool_spec, opts, None).map(|c| (c.toolpath, c.diagnostics))
}

/// [`plan_mesh`] as a one-operation project through [`crate::project::pipeline::compute`] (the
/// workstation's path), the part read through [`crate::import::open`] (a STEP part tessellated
/// at the chord tolerance), with the tool axes checked against `machine` when given.
///
/// # Errors
/// As [`plan_mesh`].
pub fn plan_mesh_computed(
    file: &Path,
    strategy: &str,
    tool_spec: &str,
    opts: &MeshPlanOptions,
    machine: Option<&str>,
) -> Result<Computed, ImportError> {
    let bad = |what: &str, msg: String| ImportError::new(file, Some(what.to_string()), msg);
    let cutter = parse_tool_spec(tool_spec).map_err(|e| bad("--tool", e.to_string()))?;
    let tol = opts.tolerance_mm;
    let options = crate::import::OpenOptions {
        chord_tol_mm: (tol > 0.0 && tol.is_finite()).then_some(tol),
    };
    let operation = mesh_operation(file, strategy, opts)?;
    let mut tools = vec![ToolEntry {
        name: tool_spec.to_string(),
        cutter,
    }];
    let earlier = earlier_paths(file, strategy, opts)?;
    if strategy == "rest" {
        let spec = match (opts.reference_tool.as_deref(), &earlier) {
            (Some(spec), _) => spec,
            // From the stock the reference tool is not used: the finishing tool stands in.
            (None, Some(_)) => tool_spec,
            (None, None) => {
                return Err(bad(
                    "--reference-tool",
                    "rest finishing needs the earlier tool, e.g. --reference-tool ball:d=10, \
                     or --from-stock with --after PATH.json"
                        .into(),
                ));
            }
        };
        tools.push(ToolEntry {
            name: spec.to_string(),
            cutter: parse_tool_spec(spec).map_err(|e| bad("--reference-tool", e.to_string()))?,
        });
    }
    let part = crate::import::open(file, &options, &Progress::new())?;
    let stock = if strategy == "zlevel-rough" || earlier.is_some() {
        match StockSpec::parse(&opts.stock, Some(&part.mesh.bbox())) {
            Ok(StockSpec::Shape(stock)) => stock,
            Ok(StockSpec::Mesh(_)) => {
                return Err(bad(
                    "--stock",
                    "roughing needs a box or cylinder stock, not a mesh".into(),
                ));
            }
            Err(e) => return Err(bad("--stock", e)),
        }
    } else {
        Stock::None
    };
    let computed = match &earlier {
        Some(paths) => rest_after(&part, tools, stock, operation, paths)?,
        None => compute_one(&part, tools, stock, operation, machine, strategy)?,
    };
    Ok(computed)
}

/// The `--after` tool paths of a rest from the stock (`None` unless `--from-stock`), each with
/// its own cutter; `--after` without `--from-stock`, or `--from-stock` on another strategy or
/// without `--after`, is refused.
fn earlier_paths(
    file: &Path,
    strategy: &str,
    opts: &MeshPlanOptions,
) -> Result<Option<Vec<(Toolpath, Cutter)>>, ImportError> {
    let bad = |what: &str, msg: &str| ImportError::new(file, Some(what.to_string()), msg);
    match (opts.from_stock, opts.after.is_empty()) {
        (false, true) => return Ok(None),
        (false, false) => return Err(bad("--after", "--after needs --from-stock")),
        (true, _) if strategy != "rest" => {
            return Err(bad("--from-stock", "--from-stock is for --strategy rest"));
        }
        (true, true) => {
            return Err(bad(
                "--from-stock",
                "rest from the stock needs the earlier paths: --after PATH.json (repeat in order)",
            ));
        }
        (true, false) => {}
    }
    opts.after
        .iter()
        .map(|p| {
            let tp = Toolpath::load(p)
                .map_err(|e| ImportError::new(p, Some(e.place.clone()), e.message.clone()))?;
            let cutter = tp.tool.cutter.clone();
            Ok((tp, cutter))
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// A rest from the stock as a one-operation project after `earlier`.
fn rest_after(
    part: &crate::import::Workpiece,
    tools: Vec<ToolEntry>,
    stock: Stock,
    operation: Operation,
    earlier: &[(Toolpath, Cutter)],
) -> Result<Computed, ImportError> {
    let project = crate::project::Project {
        stock,
        tools,
        selected_tool: Some(0),
        operations: vec![operation],
        ..crate::project::Project::default()
    };
    compute_rest_after(&project, 0, part, earlier, &Progress::new()).map_err(|e| {
        let message = match e {
            ComputeError::Plan { message, .. } => message,
            other => other.to_string(),
        };
        ImportError::new(&part.source, Some("rest".into()), message)
    })
}
