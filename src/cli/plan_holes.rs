//! `talas plan PART --strategy drill|dwell|peck|chip-break|tap|bore|ream|helical-bore|thread-mill|spot
//! --holes auto|FACE,FACE|X,Y;X,Y --tool SPEC [--peck MM] [--dwell S] [--pitch MM] [--depth MM]
//! [--r-plane MM] [--clearance MM] [--rpm N] [--feed F] [--post DIALECT [--gcode PATH]] -o PATH.json`:
//! hole making on the holes recognised in the part ([`crate::features::holes`]).
//!
//! Tools: any tool SPEC, or `drill:d=D[,point=DEG]`, `spot:d=D[,point=DEG]`, `reamer:d=D`,
//! `tap:d=D,pitch=P`, `boring:d=D`, `threadmill:d=D,pitch=P[,teeth=N]` (N teeth along the axis
//! at the pitch, default 1: one turn per N pitches). `--holes auto` takes the holes
//! the tool fits: the holes of the tool's diameter (within 0.01 mm) for drill, dwell, peck,
//! chip-break, bore and ream; the holes whose tap drill matches the tap (or thread mill) for tap
//! and thread-mill; every hole for spot (as deep as makes the spot as wide as the countersink, or
//! the hole plus 0.2 mm); holes (or their counterbores) wider than the tool for
//! helical-bore. `FACE,FACE` names the holes by a face of each (indices as `talas inspect`
//! lists them), `X,Y;X,Y` by their centres (the nearest hole within 0.5 mm; `X,Y;` for one).

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::geometry::DVec3;
use crate::geometry::tessellate::{TessellationOptions, tessellate_part};
use crate::import::ImportError;
use crate::import::step::read_step;
use crate::machine::Machine;
use crate::post::{Dialect, PostOptions, post};
use crate::project::op_holes::{HoleCycle, HoleSelection, HoleSettings, hole_job};
use crate::strategies::holes::{HolePlanOptions, HoleStrategy, plan_holes};
use crate::toolpath::ToolRecord;
use crate::tools::hole_tool::{HoleTool, HoleToolKind};
use crate::tools::parse_tool_spec;

/// The hole strategies `talas plan` knows.
pub const HOLE_STRATEGIES: [&str; 10] = [
    "drill",
    "dwell",
    "peck",
    "chip-break",
    "tap",
    "bore",
    "ream",
    "helical-bore",
    "thread-mill",
    "spot",
];

/// The hole options of `talas plan`.
#[derive(Debug, Clone, clap::Args)]
pub struct HoleArgs {
    /// Hole strategies: which holes (`auto`, `FACE,FACE`, or `X,Y;X,Y`).
    #[arg(long, value_name = "auto|FACE,FACE|X,Y;X,Y", default_value = "auto")]
    pub holes: String,
    /// Hole strategies: depth of each peck (peck, chip-break), mm.
    #[arg(long, value_name = "MM", default_value_t = 2.0)]
    pub peck: f64,
    /// Hole strategies: dwell at the bottom (dwell, bore), s.
    #[arg(long, value_name = "S", default_value_t = 0.0)]
    pub dwell: f64,
    /// Hole strategies: thread pitch (tap, thread-mill) or helix descent per turn
    /// (helical-bore), mm [default: the tool's pitch; helical-bore 1 mm].
    #[arg(long, value_name = "MM")]
    pub pitch: Option<f64>,
    /// Hole strategies: depth below the hole's top instead of the recognised one, mm (the
    /// command line's one `--depth`, [`super::plan_25d::PlanarArgs::depth`], set by
    /// [`super::plan::plan`]).
    #[arg(skip)]
    pub depth: Option<f64>,
    /// Hole strategies: R plane above each hole's top, mm.
    #[arg(long, value_name = "MM", default_value_t = 2.0)]
    pub r_plane: f64,
    /// Hole strategies: spindle speed, rev/min (a tap feeds at pitch × speed).
    #[arg(long, value_name = "N", default_value_t = 1000.0)]
    pub rpm: f64,
    /// Hole strategies: radial stock the helical-bore roughing helix leaves for the finishing
    /// one, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.2)]
    pub finish: f64,
    /// Hole strategies: also post the tool path in this dialect (linuxcnc, fanuc, siemens,
    /// heidenhain, grbl, or a dialect file).
    #[arg(long, value_name = "DIALECT")]
    pub post: Option<String>,
    /// Hole strategies: where the posted program goes [default: the output with `.nc`].
    #[arg(long, value_name = "PATH")]
    pub gcode: Option<PathBuf>,
}

/// The most teeth `threadmill:…,teeth=N` takes.
const MAX_TEETH: f64 = 100.0;

fn bad(place: &str, msg: String) -> ImportError {
    ImportError::new(Path::new(place), None, msg)
}

/// A tool SPEC: a hole tool (`drill:d=…`) or any cutter SPEC (a flat end mill for helical
/// boring).
fn parse_hole_tool(spec: &str) -> Result<(Option<HoleTool>, ToolRecord), ImportError> {
    let err = |m: String| bad("--tool", m);
    let (kind, rest) = spec.split_once(':').unwrap_or((spec, ""));
    let mut fields = Vec::new();
    for part in rest.split(',').filter(|p| !p.trim().is_empty()) {
        let (k, v) = part
            .split_once('=')
            .ok_or_else(|| err(format!("'{part}' is not KEY=VALUE")))?;
        let v: f64 = v
            .trim()
            .parse()
            .map_err(|_| err(format!("'{v}' is not a number")))?;
        fields.push((k.trim().to_string(), v));
    }
    let get = |k: &str| fields.iter().find(|(n, _)| n == k).map(|(_, v)| *v);
    let d = get("d");
    let need_pitch = || get("pitch").ok_or_else(|| err(format!("a {kind} needs pitch=MM")));
    let allowed: &[&str] = match kind.trim() {
        "drill" | "spot" => &["d", "point"],
        "reamer" | "boring" => &["d"],
        "tap" => &["d", "pitch"],
        "threadmill" => &["d", "pitch", "teeth"],
        _ => &[],
    };
    if !allowed.is_empty()
        && let Some((k, _)) = fields.iter().find(|(k, _)| !allowed.contains(&k.as_str()))
    {
        return Err(err(format!(
            "unknown key '{k}' for a {kind} (keys: {})",
            allowed.join(", ")
        )));
    }
    let hole_kind = match kind.trim() {
        "drill" => HoleToolKind::TwistDrill {
            point_angle_rad: get("point").unwrap_or(118.0).to_radians(),
        },
        "spot" => HoleToolKind::SpotDrill {
            point_angle_rad: get("point").unwrap_or(90.0).to_radians(),
        },
        "reamer" => HoleToolKind::Reamer,
        "boring" => HoleToolKind::BoringBar,
        "tap" => HoleToolKind::Tap {
            pitch_mm: need_pitch()?,
            right_hand: true,
        },
        "threadmill" => HoleToolKind::ThreadMill {
            pitch_mm: need_pitch()?,
            teeth: match get("teeth") {
                None => 1,
                Some(n) if n.fract() == 0.0 && (1.0..=MAX_TEETH).contains(&n) => n as u32,
                Some(n) => {
                    return Err(err(format!(
                        "teeth={n}: a thread mill's teeth are a whole number from 1 to {MAX_TEETH}"
                    )));
                }
            },
        },
        _ => {
            let cutter = parse_tool_spec(spec).map_err(|e| err(e.to_string()))?;
            return Ok((
                None,
                ToolRecord {
                    spec: spec.to_string(),
                    cutter,
                },
            ));
        }
    };
    let tool = HoleTool {
        kind: hole_kind,
        diameter_mm: d.ok_or_else(|| err(format!("a {kind} needs d=MM")))?,
    };
    let cutter = tool.cutter().map_err(|e| err(e.to_string()))?;
    Ok((
        Some(tool),
        ToolRecord {
            spec: tool.spec(),
            cutter,
        },
    ))
}

/// Plan hole making (called by `talas plan` for the hole strategies).
///
/// # Errors
/// The part, a bad option, or no hole to make.
pub fn plan_holes_cli(
    file: &Path,
    strategy_name: &str,
    tool_spec: &str,
    feed: f64,
    clearance: Option<f64>,
    output: &Path,
    args: &HoleArgs,
) -> Result<Value, ImportError> {
    let (hole_tool, record) = parse_hole_tool(tool_spec)?;
    let tool_pitch = match hole_tool.map(|t| t.kind) {
        Some(HoleToolKind::Tap { pitch_mm, .. } | HoleToolKind::ThreadMill { pitch_mm, .. }) => {
            Some(pitch_mm)
        }
        _ => None,
    };
    let teeth = match hole_tool.map(|t| t.kind) {
        Some(HoleToolKind::ThreadMill { teeth, .. }) => Some(teeth),
        _ => None,
    };
    let part = read_step(file)?;
    let mesh = tessellate_part(
        &part,
        &TessellationOptions::for_size(part.rough_bbox().diagonal()),
    );
    let rep = crate::features::holes::recognize_holes(&part, Some(&mesh), &Default::default());
    let cycle = HoleCycle::from_name(strategy_name).ok_or_else(|| {
        bad(
            "--strategy",
            format!("'{strategy_name}' is not a hole strategy"),
        )
    })?;
    let selection = HoleSelection::parse(&args.holes).map_err(|m| bad("--holes", m))?;
    let settings = HoleSettings {
        peck_mm: args.peck,
        dwell_s: args.dwell,
        pitch_mm: args.pitch,
        depth_mm: args.depth,
        finish_mm: args.finish,
        teeth,
    };
    let job = hole_job(
        &rep, cycle, &record, tool_pitch, &selection, &settings, None,
    )
    .map_err(|m| {
        let place = if m.contains("pitch") {
            "--pitch"
        } else {
            "--holes"
        };
        bad(place, m)
    })?;
    let (targets, strategy, dir, skipped) = (job.targets, job.strategy, job.direction, job.skipped);
    let opts = HolePlanOptions {
        r_plane_mm: args.r_plane,
        clearance_mm: clearance.unwrap_or(10.0),
        feed_mm_per_min: feed,
        spindle_rpm: args.rpm,
        start: DVec3::ZERO,
        ..HolePlanOptions::default()
    };
    let plan = plan_holes(&targets, &strategy, record, Some(&mesh.mesh), &opts)
        .map_err(|m| bad(&file.display().to_string(), m))?;
    let tp = plan
        .toolpath
        .as_ref()
        .ok_or_else(|| bad(&file.display().to_string(), "nothing planned".into()))?;
    tp.save(output)
        .map_err(|e| ImportError::new(output, Some(e.place.clone()), e.message.clone()))?;
    let mut gcode_path = None;
    if let Some(name) = &args.post {
        let dialect = Dialect::resolve(name).map_err(|e| bad("--post", e.to_string()))?;
        let machine = Machine::builtin("mill-3axis").map_err(|e| bad("--post", e.to_string()))?;
        let text = post(
            tp,
            &machine,
            &dialect,
            &PostOptions {
                spindle_rpm: args.rpm,
                ..PostOptions::default()
            },
        )
        .map_err(|e| bad("--post", e.to_string()))?;
        let path = args
            .gcode
            .clone()
            .unwrap_or_else(|| output.with_extension("nc"));
        crate::storage::write_atomic(&path, text.as_bytes())
            .map_err(|e| ImportError::new(&path, None, format!("cannot write: {e}")))?;
        gcode_path = Some(path.display().to_string());
    }
    let holes: Vec<Value> = plan
        .order
        .iter()
        .map(|&i| {
            let t = &targets[i];
            json!({"top_mm": [t.top.x, t.top.y, t.top.z], "depth_mm": t.depth_mm, "diameter_mm": t.diameter_mm})
        })
        .collect();
    Ok(json!({
        "file": file.display().to_string(),
        "strategy": strategy_name,
        "tool": tp.tool.spec,
        "output": output.display().to_string(),
        "gcode": gcode_path,
        "holes": holes,
        "holes_skipped_other_direction": skipped,
        "direction": [dir.x, dir.y, dir.z],
        "tour_mm": plan.tour_mm,
        "r_plane_moves": plan.r_plane_moves,
        "clearance_moves": plan.clearance_moves,
        "poses": tp.poses.len(),
        "exact_moves": tp.exact.len(),
        "passes": plan.order.len(),
        "thread_mill_teeth": match strategy {
            HoleStrategy::ThreadMill { teeth, .. } => Some(teeth),
            _ => None,
        },
        "summary": {
            "pose_count": tp.poses.len(),
            "cut_length_mm": tp.summary.cut_length_mm,
            "other_length_mm": tp.summary.other_length_mm,
            "estimated_time_s": tp.summary.estimated_time_s,
        },
    }))
}
