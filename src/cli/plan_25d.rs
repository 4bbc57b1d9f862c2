//! `talas plan PART --strategy face|pocket|contour …`: 2.5D strategies on regions recognised from
//! +Z (`--features auto`, or the floor faces `--faces F,F` as `talas features` numbers them) or
//! drawn (`--region FILE.dxf|FILE.svg|FILE.csv --top Z --depth D`, one closed boundary).
//! Several regions give one tool path, region after region, each left at the clearance height.

use std::path::PathBuf;

use serde_json::{Value, json};

use super::plan::{PlanArgs, opt_err};
use crate::features::regions::{MachinableRegion, RegionKind, find_regions};
use crate::geometry::planar::{Region, read_profile};
use crate::import::ImportError;
use crate::import::step::read_step;
use crate::strategies::planar::{
    ContourOptions, ContourSide, FacingOptions, PocketOptions, contour, facing, pocket,
};
use crate::toolpath::{ToolRecord, Toolpath};
use crate::tools::parse_tool_spec;

/// The 2.5D strategies.
pub const PLANAR_STRATEGIES: &[&str] = &["face", "pocket", "contour"];

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
    /// Pocket entry ramp and contour ramp after tabs: the largest angle, degrees.
    #[arg(long, value_name = "DEG", default_value_t = 3.0)]
    pub ramp_angle: f64,
}

/// One region to machine: its floor, its top and its geometry.
struct Job {
    region: Region,
    top: f64,
    floor: f64,
    name: String,
    /// From `--region` (its top and depth typed), not recognised.
    drawn: bool,
}

fn jobs(args: &PlanArgs) -> Result<Vec<Job>, ImportError> {
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
        let profile = read_profile(file, args.tolerance)
            .map_err(|e| ImportError::new(file, Some(e.place.clone()), e.message.clone()))?;
        let region = Region::from_outline(&profile)
            .map_err(|e| ImportError::new(file, None, e.to_string()))?;
        return Ok(vec![Job {
            region,
            top,
            floor: top - depth,
            name: file.display().to_string(),
            drawn: true,
        }]);
    }
    let part = read_step(&args.file)?;
    let report = find_regions(&part);
    let wanted = |r: &MachinableRegion| match args.strategy.as_str() {
        "contour" | "face" => r.kind == RegionKind::OuterProfile,
        _ => r.kind == RegionKind::ClosedPocket,
    };
    let chosen: Vec<&MachinableRegion> = if !p.faces.is_empty() {
        let faces: Vec<usize> = p.faces.iter().map(|f| f.saturating_sub(1)).collect();
        let found: Vec<&MachinableRegion> = report
            .regions
            .iter()
            .filter(|r| r.faces.iter().any(|f| faces.contains(f)))
            .collect();
        if found.is_empty() {
            return Err(ImportError::new(
                &args.file,
                Some("--faces".into()),
                "no region has these floor faces (see talas features)",
            ));
        }
        found
    } else if p.features.as_deref() == Some("auto") {
        report.regions.iter().filter(|r| wanted(r)).collect()
    } else {
        return Err(opt_err(
            "--strategy",
            "pocket and contour need --features auto, --faces F,F or --region FILE --top Z --depth D",
        ));
    };
    if chosen.is_empty() {
        return Err(ImportError::new(
            &args.file,
            None,
            format!("no region for {} seen from +Z", args.strategy),
        ));
    }
    Ok(chosen
        .into_iter()
        .map(|r| Job {
            region: r.region.clone(),
            top: r.top_z_mm,
            floor: r.floor_z_mm,
            name: format!("{:?} at z = {:.4} mm", r.kind, r.floor_z_mm),
            drawn: false,
        })
        .collect())
}

/// Appends `b` to `a` (poses and exact segments).
fn append(a: &mut Toolpath, b: &Toolpath) {
    let off = a.poses.len();
    a.poses.extend(b.poses.iter().copied());
    a.exact.extend(b.exact.iter().map(|s| {
        let mut s = *s;
        s.from += off;
        s.to += off;
        s
    }));
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
    let clearance = args.clearance.unwrap_or(5.0);
    let started = std::time::Instant::now();
    let mut out = Toolpath::new(tool.clone(), Vec::new());
    let mut names = Vec::new();
    for job in jobs(args)? {
        let tp = match args.strategy.as_str() {
            "face" => {
                // A drawn region faces from --top down by --depth; a recognised outline faces
                // the part's top from --depth (default 1 mm) above it.
                let (stock_top, face_z) = if job.drawn {
                    (job.top, job.floor)
                } else {
                    (job.top + args.planar.depth.unwrap_or(1.0), job.top)
                };
                let o = FacingOptions {
                    stock_top_z_mm: stock_top,
                    face_z_mm: face_z,
                    step_down_mm: args.step_down,
                    finish_depth_mm: args.stock_to_leave_axial,
                    stepover_frac: args.step_over,
                    overrun_mm: args.planar.overrun,
                    zigzag: args.pattern != "oneway",
                    clearance_mm: clearance,
                    feed_mm_per_min: args.feed,
                };
                facing(&job.region, &tool, &o)
            }
            "contour" => {
                let side = match args.planar.side.as_str() {
                    "outside" => ContourSide::Outside,
                    "inside" => ContourSide::Inside,
                    other => {
                        return Err(opt_err(
                            "--side",
                            format!("'{other}' is not outside or inside"),
                        ));
                    }
                };
                let o = ContourOptions {
                    side,
                    climb,
                    top_z_mm: job.top,
                    bottom_z_mm: job.floor,
                    step_down_mm: args.step_down,
                    allowance_mm: args.stock_to_leave,
                    lead_radius_mm: args.planar.lead_radius,
                    tab_count: args.planar.tabs,
                    tab_width_mm: args.planar.tab_width,
                    tab_height_mm: args.planar.tab_height,
                    ramp_angle_rad: args.planar.ramp_angle.to_radians(),
                    clearance_mm: clearance,
                    feed_mm_per_min: args.feed,
                    chord_tol_mm: args.tolerance,
                };
                contour(&job.region, &tool, &o)
            }
            _ => {
                let o = PocketOptions {
                    top_z_mm: job.top,
                    floor_z_mm: job.floor,
                    step_down_mm: args.step_down,
                    stepover_frac: args.step_over,
                    wall_allowance_mm: args.stock_to_leave,
                    floor_allowance_mm: args.stock_to_leave_axial,
                    clearance_mm: clearance,
                    ramp_angle_rad: args.planar.ramp_angle.to_radians(),
                    feed_mm_per_min: args.feed,
                    chord_tol_mm: args.tolerance,
                };
                pocket(&job.region, &tool, &o)
            }
        }
        .map_err(|e| ImportError::new(&args.file, Some(job.name.clone()), e.0))?;
        append(&mut out, &tp);
        names.push(job.name);
    }
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
