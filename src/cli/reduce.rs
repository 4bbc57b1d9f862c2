//! `talas reduce ZMAP.csv --tolerance T [--rank-rule R] [--rank N] [--tool-radius MM --step MM]
//! [--stl OUT.stl] [--json]`: SVD data reduction of a Z-map (CSV of heights, one grid row a line, no header).
//!
//! The input may also be a part (`.stp`, `.step`, `.stl`): its Z-map is sampled at `--step` over
//! its XY bounding box (for STEP, every height refined onto the exact face surface; see
//! [`crate::reduce::part_zmap`]) and reduced the same way, as the workstation's data-reduction
//! view does.

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::diagnostics::Progress;
use crate::geometry::zmap::{Grid, grid_mesh};
use crate::import::ImportError;
use crate::import::stl::{StlFormat, save_stl};
use crate::reduce::{
    ExactFaces, PartZmap, RankRule, ReduceError, ReduceOptions, Resampling, part_zmap,
    point_spacing, reduce as run_reduce,
};
use crate::strategies::zmap::{ZmapPathOptions, cl_zmap, zmap_raster};
use crate::toolpath::ToolRecord;
use crate::tools::{CutterKind, parse_tool_spec};

/// Options of `talas reduce`.
#[derive(Debug, clap::Args)]
pub struct ReduceArgs {
    /// The Z-map: heights (mm), one grid row a line, comma-separated, no header; or a part
    /// (.stp, .step, .stl) whose Z-map is sampled at --step.
    pub file: PathBuf,
    /// Tolerance t (mm): chooses the rank and, with --tool-radius, the resampling spacing.
    #[arg(long, value_name = "MM")]
    pub tolerance: f64,
    /// Rank rule: `spectral` (smallest r with σ_(r+1) ≤ t, a guaranteed node-error bound) or
    /// `term` (the thesis's loop: stop when a term changes the model by less than t).
    #[arg(long, value_name = "RULE", default_value = "spectral")]
    pub rank_rule: String,
    /// Keep exactly this many singular values (overrides --rank-rule).
    #[arg(long, value_name = "N")]
    pub rank: Option<usize>,
    /// Ball end-mill radius ρ (mm): resample the singular vectors at l = √(4ρt − t²).
    #[arg(long, value_name = "MM")]
    pub tool_radius: Option<f64>,
    /// Grid step γ of the Z-map (mm): used with --tool-radius and --stl, and the sampling step
    /// of a part.
    #[arg(long, value_name = "MM", default_value_t = 1.0)]
    pub step: f64,
    /// Write the reduced Z-map as a binary STL (grid step --step, origin 0, the original
    /// extent kept).
    #[arg(long, value_name = "OUT.stl")]
    pub stl: Option<PathBuf>,
    /// Write a raster finishing path computed on the reduced model (the contract's tool-path
    /// JSON): the CL Z-map of --path-tool by inverse offset, every k-th row a zig-zag pass.
    #[arg(long, value_name = "OUT.json")]
    pub path: Option<PathBuf>,
    /// Tool SPEC for --path.
    #[arg(long, value_name = "SPEC", default_value = "ball:d=6")]
    pub path_tool: String,
    /// Scallop height for --path's step-over (a ball: 2·√(2ρh − h²)), mm.
    #[arg(long, value_name = "MM", default_value_t = 0.01)]
    pub scallop: f64,
    /// Step-over for --path, mm (overrides --scallop; needed for non-ball tools).
    #[arg(long, value_name = "MM")]
    pub stepover: Option<f64>,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// Run the reduction and build the contract's JSON document.
///
/// # Errors
/// An [`ImportError`] naming the file (and line) for a bad Z-map, or the option for a bad value.
pub fn reduce(args: &ReduceArgs) -> Result<Value, ImportError> {
    let file_err = |e: ReduceError| match e {
        ReduceError::Parse { line, message } => {
            ImportError::new(&args.file, Some(format!("line {line}")), message)
        }
        other => ImportError::new(&args.file, None, other.to_string()),
    };
    let rank_rule = match (args.rank, args.rank_rule.as_str()) {
        (Some(r), _) => RankRule::Fixed(r),
        (None, "spectral") => RankRule::SpectralBound,
        (None, "term") => RankRule::TermChange,
        (None, other) => {
            return Err(ImportError::new(
                &args.file,
                None,
                format!("--rank-rule must be 'spectral' or 'term', got '{other}'"),
            ));
        }
    };
    let (grid, zmap) = if is_part(&args.file) {
        let z = sample_part(&args.file, args.step)?;
        (z.grid.clone(), Some(z))
    } else {
        let text = crate::storage::read_text_bounded(&args.file, crate::storage::TEXT_LIMIT_BYTES)
            .map_err(|e| ImportError::new(&args.file, None, format!("cannot read file: {e}")))?;
        (
            Grid::parse_csv(&text).map_err(|e| file_err(e.into()))?,
            None,
        )
    };
    let opts = ReduceOptions {
        tolerance_mm: args.tolerance,
        rank_rule,
        resampling: args.tool_radius.map(|r| Resampling {
            tool_radius_mm: r,
            grid_step_mm: args.step,
        }),
    };
    let r = run_reduce(&grid, &opts).map_err(file_err)?;
    if let Some(out) = &args.stl {
        if !(args.step > 0.0 && args.step.is_finite()) {
            return Err(ImportError::new(
                &args.file,
                None,
                format!("--step must be a positive length in mm, got {}", args.step),
            ));
        }
        let width = (grid.cols().saturating_sub(1)) as f64 * args.step;
        let height = (grid.rows().saturating_sub(1)) as f64 * args.step;
        let origin = zmap.as_ref().map_or(glam::DVec2::ZERO, |z| z.origin);
        let mesh = grid_mesh(&r.reduced, origin, width, height);
        save_stl(out, &mesh, StlFormat::Binary)?;
    }
    let origin = zmap.as_ref().map_or(glam::DVec2::ZERO, |z| z.origin);
    let path = match &args.path {
        Some(out) => Some(write_path(
            args,
            &r.at_nodes(grid.rows(), grid.cols()),
            origin,
            out,
        )?),
        None => None,
    };
    Ok(json!({
        "path": path,
        "rows": grid.rows(),
        "cols": grid.cols(),
        "tolerance_mm": args.tolerance,
        "rank_rule": rank_rule,
        "singular_values": r.singular_values,
        "rank": r.rank,
        "rank_error_bound": r.rank_error_bound,
        "spacing_mm": r.spacing_mm.or_else(|| args.tool_radius.map(|t| point_spacing(t, args.tolerance))),
        "reduced_rows": r.reduced.rows(),
        "reduced_cols": r.reduced.cols(),
        "original_numbers": grid.rows() * grid.cols(),
        "stored_numbers": r.stored_numbers,
        "reduced_points": r.reduced.rows() * r.reduced.cols(),
        "max_error": r.max_error,
        "mean_error": r.mean_error,
        "stl": args.stl.as_ref().map(|p| p.display().to_string()),
        "zmap": zmap.as_ref().map(|z| json!({
            "origin_mm": [z.origin.x, z.origin.y],
            "step_mm": z.step_mm,
            "exact_nodes": z.exact_nodes,
            "mesh_nodes": z.grid.values().len() - z.exact_nodes - z.misses,
            "misses": z.misses,
        })),
    }))
}

/// Whether `file` is a part the reader opens (STEP or STL) rather than a Z-map CSV.
fn is_part(file: &Path) -> bool {
    crate::import::FileFormat::of(file).is_ok()
}

/// The Z-map of the part in `file` at `step` mm (read by [`crate::import::open`]; STEP heights
/// refined onto the exact faces).
fn sample_part(file: &Path, step: f64) -> Result<PartZmap, ImportError> {
    let w = crate::import::open(
        file,
        &crate::import::OpenOptions::default(),
        &Progress::new(),
    )?;
    let exact = w.part.is_some().then(|| ExactFaces {
        face_of_triangle: w.face_of_triangle.clone(),
        surfaces: w.surfaces.clone(),
    });
    let bvh = w
        .bvh()
        .map_err(|e| ImportError::new(file, None, format!("no surface to sample: {e}")))?;
    part_zmap(&bvh, exact.as_ref(), step, &Progress::new())
        .map_err(|e| ImportError::new(file, Some("--step".into()), e.to_string()))
}

/// A short human summary of the JSON document.
#[must_use]
pub fn human(doc: &Value) -> String {
    format!(
        "{}×{} grid: rank {} (bound σ_r+1 = {}), reduced to {}×{} ({} numbers stored), max error {} mm, mean error {} mm\n",
        doc["rows"],
        doc["cols"],
        doc["rank"],
        doc["rank_error_bound"],
        doc["reduced_rows"],
        doc["reduced_cols"],
        doc["stored_numbers"],
        doc["max_error"],
        doc["mean_error"]
    )
}

/// Plan the raster path on the reduced model `model` (at the Z-map's nodes) and write it to
/// `out`; returns its summary for the JSON document.
fn write_path(
    args: &ReduceArgs,
    model: &Grid,
    origin: glam::DVec2,
    out: &Path,
) -> Result<Value, ImportError> {
    let opt = |what: &str, msg: String| ImportError::new(&args.file, Some(what.to_string()), msg);
    let cutter = parse_tool_spec(&args.path_tool).map_err(|e| opt("--path-tool", e.to_string()))?;
    let stepover = match (args.stepover, cutter.kind) {
        (Some(s), _) => s,
        (None, CutterKind::Ball) => {
            let (rho, h) = (cutter.radius(), args.scallop);
            if !(h > 0.0 && h < rho) {
                return Err(opt(
                    "--scallop",
                    format!("must be between 0 and the ball radius, got {h}"),
                ));
            }
            2.0 * (2.0 * rho * h - h * h).sqrt()
        }
        (None, _) => {
            return Err(opt(
                "--stepover",
                "a non-ball tool needs --stepover (the scallop rule is for a ball)".into(),
            ));
        }
    };
    // Drop-cutter on the triangulated model: the node-only inverse offset would let the tool
    // sink between nodes (see `strategies::zmap::inverse_offset`).
    let cl = cl_zmap(model, origin, args.step, &cutter, &Progress::new())
        .map_err(|e| opt("--step", e.to_string()))?;
    let tool = ToolRecord {
        spec: args.path_tool.clone(),
        cutter,
    };
    let popts = ZmapPathOptions {
        stepover_mm: stepover,
        chord_tol_mm: (0.5 * args.tolerance).max(1e-4),
        ..ZmapPathOptions::default()
    };
    let tp = zmap_raster(&cl, origin, args.step, tool, &popts)
        .map_err(|e| opt("--stepover", e.to_string()))?;
    let text = tp
        .to_json()
        .map_err(|e| ImportError::new(out, None, e.to_string()))?;
    crate::storage::write_atomic(out, text.as_bytes())
        .map_err(|e| ImportError::new(out, None, format!("cannot write: {e}")))?;
    Ok(json!({
        "file": out.display().to_string(),
        "tool": args.path_tool,
        "stepover_mm": stepover,
        "poses": tp.summary.pose_count,
        "cut_length_mm": tp.summary.cut_length_mm,
        "estimated_time_s": tp.summary.estimated_time_s,
    }))
}
