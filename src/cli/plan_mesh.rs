//! Planning on meshes for `talas plan`: raster, waterline, steep-and-shallow, pencil and rest
//! finishing and
//! Z-level roughing of an STL file or
//! of a STEP part tessellated at the chord tolerance. The `plan` subcommand calls [`plan_mesh`].

use std::path::Path;

use crate::diagnostics::Diagnostic;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::import::ImportError;
use crate::strategies::raster::{Boundary, RasterOptions, RasterPattern, raster};
use crate::strategies::steep_shallow::{
    Finish3Settings, STEEP_SHALLOW_DEFAULT_ANGLE_DEG, WATERLINE_DEFAULT_ANGLE_DEG, steep_shallow,
};
use crate::strategies::waterline::{Cut, waterline};
use crate::strategies::zlevel::{Stock, ZlevelOptions, roughing_grid_mm, zlevel_rough};
use crate::toolpath::{ToolRecord, Toolpath};
use crate::tools::parse_tool_spec;

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
    /// Roughing stock: `box` (the part's box), `box:X0,Y0,Z0,X1,Y1,Z1` or
    /// `cylinder:CX,CY,R,Z0,Z1` (mm); raster ignores it.
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

/// Waterline (`--angle`: slopes flatter than it set no limit on the step-down, 30° when 0)
/// and steep-and-shallow (`--angle`: the threshold, 45° when 0) finishing.
fn plan_finish_3axis(
    file: &Path,
    strategy: &str,
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &MeshPlanOptions,
) -> Result<(Toolpath, Vec<Diagnostic>), ImportError> {
    let bad = |what: &str, msg: String| ImportError::new(file, Some(what.to_string()), msg);
    let cut = match opts.pattern.as_str() {
        "zigzag" | "zig-zag" | "climb" => Cut::Climb,
        "conventional" => Cut::Conventional,
        other => {
            return Err(bad(
                "--pattern",
                format!("waterline direction must be 'climb' or 'conventional', got '{other}'"),
            ));
        }
    };
    let angle = |default: f64| {
        if opts.angle_deg == 0.0 {
            default
        } else {
            opts.angle_deg
        }
    };
    let waterline_mode = strategy == "waterline";
    let settings = Finish3Settings {
        scallop_mm: opts.scallop_mm,
        tolerance_mm: opts.tolerance_mm,
        angle_rad: if waterline_mode {
            angle(WATERLINE_DEFAULT_ANGLE_DEG)
        } else {
            angle(STEEP_SHALLOW_DEFAULT_ANGLE_DEG)
        }
        .to_radians(),
        cut,
        feed_mm_per_min: opts.feed_mm_per_min,
        clearance_mm: opts.clearance_mm,
    };
    if waterline_mode {
        let plan = waterline(mesh, bvh, tool, &settings.waterline_options())
            .map_err(|e| bad("waterline", e.to_string()))?;
        return Ok((plan.toolpath, plan.diagnostics));
    }
    let sopts = settings.steep_shallow_options();
    let plan = steep_shallow(mesh, bvh, tool, &sopts).map_err(|e| bad("steep-shallow", e))?;
    Ok((plan.toolpath, plan.diagnostics))
}

/// Read an STL or STEP file (through [`crate::import::open`]) as a mesh, STEP tessellated at
/// `tol` mm (a non-positive `tol`: the reader's size-relative default).
///
/// # Errors
/// The reader's [`ImportError`].
pub fn read_mesh(file: &Path, tol: f64) -> Result<TriMesh, ImportError> {
    let options = crate::import::OpenOptions {
        chord_tol_mm: (tol > 0.0 && tol.is_finite()).then_some(tol),
    };
    Ok(crate::import::open(file, &options, &crate::diagnostics::Progress::new())?.mesh)
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
    let bad = |what: &str, msg: String| ImportError::new(file, Some(what.to_string()), msg);
    let cutter = parse_tool_spec(tool_spec).map_err(|e| bad("--tool", e.to_string()))?;
    let tool = ToolRecord {
        spec: tool_spec.to_string(),
        cutter,
    };
    if !MESH_STRATEGIES.contains(&strategy) {
        return Err(bad(
            "--strategy",
            format!(
                "mesh strategies are {}, got '{strategy}'",
                MESH_STRATEGIES.join(", ")
            ),
        ));
    }
    let mesh = read_mesh(file, opts.tolerance_mm)?;
    let bvh = MeshBvh::new(&mesh).map_err(|e| ImportError::new(file, None, e.to_string()))?;
    if strategy == "pencil" || strategy == "rest" {
        return super::plan_corners::plan_corners(file, strategy, &mesh, &bvh, &tool, opts);
    }
    if strategy == "waterline" || strategy == "steep-shallow" {
        return plan_finish_3axis(file, strategy, &mesh, &bvh, &tool, opts);
    }
    if strategy == "raster" {
        let pattern = match opts.pattern.as_str() {
            "zigzag" | "zig-zag" => RasterPattern::ZigZag,
            "oneway" | "one-way" => RasterPattern::OneWay,
            other => {
                return Err(bad(
                    "--pattern",
                    format!("pattern must be 'zigzag' or 'oneway', got '{other}'"),
                ));
            }
        };
        let ropts = RasterOptions {
            angle_rad: opts.angle_deg.to_radians(),
            pattern,
            scallop_mm: opts.scallop_mm,
            chord_tol_mm: opts.tolerance_mm,
            boundary: Boundary::Silhouette,
            clearance_mm: opts.clearance_mm,
            feed_mm_per_min: opts.feed_mm_per_min,
            plunge_feed_mm_per_min: 0.3 * opts.feed_mm_per_min,
            ..RasterOptions::default()
        };
        let plan = raster(&mesh, &bvh, &tool, &ropts).map_err(|e| bad("raster", e.to_string()))?;
        return Ok((plan.toolpath, plan.diagnostics));
    }
    let stock = Stock::parse(&opts.stock, &mesh.bbox()).map_err(|e| bad("--stock", e))?;
    let grid_mm = roughing_grid_mm(
        &stock,
        tool.cutter.radius(),
        opts.tolerance_mm,
        opts.stock_to_leave_radial_mm
            .min(opts.stock_to_leave_axial_mm),
    );
    let zopts = ZlevelOptions {
        stock,
        step_down_mm: opts.step_down_mm,
        step_over_mm: opts.step_over_fraction * tool.cutter.diameter,
        stock_to_leave_radial_mm: opts.stock_to_leave_radial_mm,
        stock_to_leave_axial_mm: opts.stock_to_leave_axial_mm,
        tolerance_mm: grid_mm,
        feed_mm_per_min: opts.feed_mm_per_min,
        clearance_mm: opts.clearance_mm,
        detect_flats: opts.detect_flats,
        ..ZlevelOptions::default()
    };
    let plan =
        zlevel_rough(&mesh, &bvh, &tool, &zopts).map_err(|e| bad("zlevel-rough", e.to_string()))?;
    Ok((plan.toolpath, plan.diagnostics))
}
