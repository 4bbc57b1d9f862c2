//! `talas plan PART --strategy face|pocket|contour|adaptive …`: 2.5D strategies on regions recognised from
//! +Z (`--features auto`, or the floor faces `--faces F,F` as `talas features` numbers them) or
//! drawn (`--region FILE.dxf|FILE.svg|FILE.csv --top Z --depth D`, one closed boundary).
//! Several regions give one tool path, region after region, each left at the clearance height.

use std::path::PathBuf;

use serde_json::{Value, json};

use super::plan::{PlanArgs, opt_err};
use crate::import::ImportError;
use crate::import::step::read_step;
use crate::project::op_regions::{
    PlanarKind, PlanarSettings, RegionJob, drawn_job, plan_regions, recognised_jobs,
};
use crate::toolpath::ToolRecord;
use crate::tools::parse_tool_spec;

/// The 2.5D strategies.
pub const PLANAR_STRATEGIES: &[&str] = &["face", "pocket", "contour", "adaptive"];

/// The 2.5D options of `talas plan` (the shared ones, `--step-down`, `--step-over`,
/// `--stock-to-leave`, `--stock-to-leave-axial`, `--pattern climb|conventional`, `--feed`,
/// `--clearance`, `--tolerance`, are `plan`'s own).
#[derive(Debug, Clone, clap::Args)]
pub struct PlanarArgs {
    /// The floor faces of one region (1-based, as `talas features` lists them).
    #[arg(long, value_name = "F[,F...]", value_delimiter = ',')]
    pub faces: Vec<usize>,
    /// A drawn region: one closed boundary in a DXF, SVG or CSV file (mm), placed at `--top`.
    #[arg(long, value_name = "FILE")]
    pub region: Option<PathBuf>,
    /// With `--region`: the height of the material's top, mm.
    #[arg(long, value_name = "Z", allow_hyphen_values = true)]
    pub top: Option<f64>,
    /// With `--region`: the depth below `--top`, mm; `face` on a part: the stock above the
    /// part's top, mm (default 1); hole strategies: the depth below each hole's top instead of
    /// the recognised one, mm.
    #[arg(long, value_name = "D")]
    pub depth: Option<f64>,
    /// `auto`: every region of the part seen from +Z that fits the strategy (pocket: closed
    /// pockets; contour and face: the outer profile).
    #[arg(long, value_name = "auto")]
    pub features: Option<String>,
    /// Contour: `outside` (default) or `inside`.
    #[arg(long, value_name = "outside|inside", default_value = "outside")]
    pub side: String,
    /// Contour: tabs per loop.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub tabs: usize,
    /// Contour: tab width at the part, mm.
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    pub tab_width: f64,
    /// Contour: tab height above the bottom, mm.
    #[arg(long, value_name = "MM", default_value_t = 1.0)]
    pub tab_height: f64,
    /// Contour: lead-in and lead-out arc radius, mm.
    #[arg(long, value_name = "MM", default_value_t = 2.0)]
    pub lead_radius: f64,
    /// Facing: how far the tool's edge runs past the region's box, mm.
    #[arg(long, value_name = "MM", default_value_t = 2.0)]
    pub overrun: f64,
    /// Adaptive: the largest radial engagement angle of the tool, degrees.
    #[arg(long, value_name = "DEG", default_value_t = 60.0)]
    pub engagement: f64,
    /// Pocket entry ramp and contour ramp after tabs: the largest angle, degrees.
    #[arg(long, value_name = "DEG", default_value_t = 3.0)]
    pub ramp_angle: f64,
}

fn jobs(args: &PlanArgs, kind: PlanarKind) -> Result<Vec<RegionJob>, ImportError> {
    let p = &args.planar;
    if let Some(file) = &p.region {
        let (Some(top), Some(depth)) = (p.top, p.depth) else {
            return Err(opt_err(
                "--region",
                "a drawn region needs --top Z and --depth D",
            ));
        };
        if !(top.is_finite() && depth.is_finite() && depth > 0.0) {
            return Err(opt_err(
                "--depth",
                "the depth must be a positive number of mm",
            ));
        }
        return drawn_job(file, top, depth, args.tolerance)
            .map(|j| vec![j])
            .map_err(|e| ImportError::new(file, None, e));
    }
    let part = read_step(&args.file)?;
    let faces: Vec<usize> = p.faces.iter().map(|f| f.saturating_sub(1)).collect();
    if faces.is_empty() && p.features.as_deref() != Some("auto") {
        return Err(opt_err(
            "--strategy",
            "pocket and contour need --features auto, --faces F,F or --region FILE --top Z --depth D",
        ));
    }
    let place = if faces.is_empty() {
        None
    } else {
        Some("--faces".to_string())
    };
    recognised_jobs(&part, &kind.default_kinds(), &faces)
        .map_err(|e| ImportError::new(&args.file, place, format!("{e} ({})", args.strategy)))
}

/// Plans a 2.5D strategy and saves the tool path.
///
/// # Errors
/// An [`ImportError`] naming the file or the option.
pub fn plan_planar(args: &PlanArgs) -> Result<Value, ImportError> {
    let cutter = parse_tool_spec(&args.tool).map_err(|e| opt_err("--tool", e.to_string()))?;
    let tool = ToolRecord {
        spec: args.tool.clone(),
        cutter,
    };
    let climb = match args.pattern.as_str() {
        "conventional" => false,
        "climb" | "zigzag" => true,
        other => {
            return Err(opt_err(
                "--pattern",
                format!("'{other}' is not climb or conventional"),
            ));
        }
    };
    let kind = match args.strategy.as_str() {
        "face" => PlanarKind::Face,
        "contour" => PlanarKind::Contour,
        "adaptive" => PlanarKind::Adaptive,
        _ => PlanarKind::Pocket,
    };
    let outside = match args.planar.side.as_str() {
        "outside" => true,
        "inside" => false,
        other => {
            return Err(opt_err(
                "--side",
                format!("'{other}' is not outside or inside"),
            ));
        }
    };
    let settings = PlanarSettings {
        step_down_mm: args.step_down,
        step_over_fraction: args.step_over,
        wall_allowance_mm: args.stock_to_leave,
        floor_allowance_mm: args.stock_to_leave_axial,
        climb,
        zigzag: args.pattern != "oneway",
        clearance_mm: args.clearance.unwrap_or(5.0),
        clearance_is_z: false,
        feed_mm_per_min: args.feed,
        tolerance_mm: args.tolerance,
        outside,
        tabs: args.planar.tabs,
        tab_width_mm: args.planar.tab_width,
        tab_height_mm: args.planar.tab_height,
        lead_radius_mm: args.planar.lead_radius,
        overrun_mm: args.planar.overrun,
        ramp_angle_rad: args.planar.ramp_angle.to_radians(),
        face_stock_above_mm: args.planar.depth.unwrap_or(1.0),
        engagement_rad: args.planar.engagement.to_radians(),
    };
    let started = std::time::Instant::now();
    let jobs = jobs(args, kind)?;
    let names: Vec<String> = jobs.iter().map(|j| j.name.clone()).collect();
    let mut out = plan_regions(kind, &jobs, &tool, &settings)
        .map_err(|(name, e)| ImportError::new(&args.file, Some(name), e))?;
    out.resummarise();
    let seconds = started.elapsed().as_secs_f64();
    out.save(&args.output)
        .map_err(|e| ImportError::new(&args.output, Some(e.place.clone()), e.message.clone()))?;
    Ok(json!({
        "strategy": args.strategy,
        "file": args.file.display().to_string(),
        "regions": names,
        "passes": names.len(),
        "arcs": out.exact.len(),
        "summary": out.summary,
        "planning_s": seconds,
        "output": args.output.display().to_string(),
    }))
}
