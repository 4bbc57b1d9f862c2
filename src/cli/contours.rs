//! `talas contours FILE.stl --tool SPEC --levels Z1,Z2,... [--sampling MM] [--json]`: the
//! cutter's waterline contours at the given tool-tip heights. The JSON's `"levels"` holds, per
//! height, `{"z": Z, "loops": [[[x, y], ...], ...]}` (each loop closed implicitly, the part on
//! its right); `"time_s"` is the planning time (hierarchy built and every level contoured,
//! without reading the file).

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::{Value, json};

use crate::geometry::bvh::MeshBvh;
use crate::import::ImportError;
use crate::import::stl::{StlOptions, read_stl};
use crate::strategies::waterline::contours_at;
use crate::tools::parse_tool_spec;

/// Options of `talas contours`.
#[derive(Debug, clap::Args)]
pub struct ContoursArgs {
    /// The part mesh (.stl, mm).
    pub file: PathBuf,
    /// The tool: `ball:d=6`, `flat:d=10`, `bull:d=10,r=2`, `cone:d=10,angle=45`.
    #[arg(long, value_name = "SPEC")]
    pub tool: String,
    /// Tool-tip heights, mm, separated by commas.
    #[arg(long, value_name = "Z1,Z2,...", allow_hyphen_values = true)]
    pub levels: String,
    /// Distance between the fibres, mm (0.001 to 10).
    #[arg(long, value_name = "MM", default_value_t = 0.1)]
    pub sampling: f64,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// Contour every level and build the JSON document.
///
/// # Errors
/// An [`ImportError`] naming the file for an unreadable mesh, or naming the option for a bad
/// tool, level or sampling.
pub fn contours(args: &ContoursArgs) -> Result<Value, ImportError> {
    let bad = |what: &str, msg: String| ImportError::new(&args.file, Some(what.to_string()), msg);
    let cutter = parse_tool_spec(&args.tool).map_err(|e| bad("--tool", e.to_string()))?;
    if !(1e-3..=10.0).contains(&args.sampling) {
        return Err(bad(
            "--sampling",
            format!("must be 0.001 to 10 mm, got {}", args.sampling),
        ));
    }
    let levels: Vec<f64> = args
        .levels
        .split(',')
        .map(|v| {
            v.trim()
                .parse::<f64>()
                .ok()
                .filter(|z| z.is_finite())
                .ok_or_else(|| bad("--levels", format!("'{v}' is not a height in mm")))
        })
        .collect::<Result<_, _>>()?;
    let stl = read_stl(&args.file, &StlOptions::default())?;
    let t0 = Instant::now();
    let bvh =
        MeshBvh::new(&stl.mesh).map_err(|e| ImportError::new(&args.file, None, e.to_string()))?;
    let all: Vec<_> = levels
        .iter()
        .map(|&z| contours_at(&stl.mesh, &bvh, &cutter, z, args.sampling))
        .collect();
    let time_s = t0.elapsed().as_secs_f64();
    let out: Vec<Value> = levels
        .iter()
        .zip(&all)
        .map(|(z, loops)| {
            let loops: Vec<Value> = loops
                .iter()
                .map(|lp| lp.iter().map(|p| json!([p.tip.x, p.tip.y])).collect())
                .collect();
            json!({ "z": z, "loops": loops })
        })
        .collect();
    Ok(json!({
        "file": Path::new(&args.file).display().to_string(),
        "tool": args.tool,
        "sampling_mm": args.sampling,
        "levels": out,
        "time_s": time_s,
    }))
}

/// The human summary: loops and points per level.
#[must_use]
pub fn human(doc: &Value) -> String {
    let mut s = String::new();
    for lv in doc["levels"].as_array().into_iter().flatten() {
        let loops = lv["loops"].as_array().map_or(0, Vec::len);
        let pts: usize = lv["loops"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|l| l.as_array().map_or(0, Vec::len))
            .sum();
        s.push_str(&format!(
            "z = {} mm: {loops} loops, {pts} points\n",
            lv["z"]
        ));
    }
    s.push_str(&format!(
        "planned in {:.3} s\n",
        doc["time_s"].as_f64().unwrap_or(0.0)
    ));
    s
}
