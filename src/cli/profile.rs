//! `talas profile PROFILE.csv|.dxf|.svg --radius R`: the ball-electrode centre path of a 2D
//! profile (exact offset), the gouges the per-point method would make, and the largest
//! gouge-free radius; optionally the G-code.

use std::path::PathBuf;

use clap::Args;
use serde_json::json;

use crate::post::Dialect;
use crate::profile::{
    FlagKind, GcodeOptions, ProfileError, ProfileOptions, ProfilePlane, ProfileResult, Side,
    compute_opt, read_profile, write_gcode,
};

/// Arguments of `talas profile`.
#[derive(Debug, Args)]
pub struct ProfileArgs {
    /// The profile: CSV (x, y[, bulge] per row), DXF (LWPOLYLINE or chained LINE/ARC) or SVG.
    pub profile: PathBuf,
    /// Electrode (ball) radius, mm.
    #[arg(long)]
    pub radius: f64,
    /// The material-free side: left, right (of the direction of travel), above, outside,
    /// inside.
    #[arg(long, value_enum, default_value = "above")]
    pub side: SideArg,
    /// Machine plane of the G-code.
    #[arg(long, value_enum, default_value = "g18")]
    pub plane: PlaneArg,
    /// Post dialect (built-in name or JSON file).
    #[arg(long, default_value = "linuxcnc")]
    pub dialect: String,
    /// Feed, mm/min.
    #[arg(long, default_value_t = 100.0)]
    pub feed: f64,
    /// Naïve-path gouges up to this depth are not flagged, mm.
    #[arg(long, default_value_t = 1e-3)]
    pub gouge_tolerance: f64,
    /// Chord tolerance for flattening SVG curves, mm.
    #[arg(long, default_value_t = 1e-3)]
    pub tolerance: f64,
    /// Print one JSON document.
    #[arg(long)]
    pub json: bool,
    /// Write the G-code here.
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
}

/// `--side` values.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum SideArg {
    /// Left of the direction of travel.
    Left,
    /// Right of the direction of travel.
    Right,
    /// Above (+y); outside for a closed profile.
    Above,
    /// Outside a closed profile.
    Outside,
    /// Inside a closed profile.
    Inside,
}

/// `--plane` values.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum PlaneArg {
    /// XY.
    G17,
    /// ZX (profile y on Z).
    G18,
    /// YZ (profile x on Y, y on Z).
    G19,
}

impl From<SideArg> for Side {
    fn from(s: SideArg) -> Self {
        match s {
            SideArg::Left => Self::Left,
            SideArg::Right => Self::Right,
            SideArg::Above => Self::Above,
            SideArg::Outside => Self::Outside,
            SideArg::Inside => Self::Inside,
        }
    }
}

impl From<PlaneArg> for ProfilePlane {
    fn from(p: PlaneArg) -> Self {
        match p {
            PlaneArg::G17 => Self::G17,
            PlaneArg::G18 => Self::G18,
            PlaneArg::G19 => Self::G19,
        }
    }
}

/// Runs the command; the JSON document on success.
///
/// # Errors
/// One [`ProfileError`] naming the file and place.
pub fn profile(args: &ProfileArgs) -> Result<serde_json::Value, ProfileError> {
    let file = args.profile.display().to_string();
    let prof = read_profile(&args.profile, args.tolerance)?;
    let opts = ProfileOptions {
        radius_mm: args.radius,
        side: args.side.into(),
        gouge_tolerance_mm: args.gouge_tolerance,
    };
    let result = compute_opt(&prof, &opts).map_err(|e| ProfileError {
        file: file.clone(),
        ..e
    })?;
    if result.paths.is_empty() {
        return Err(ProfileError::new(
            &file,
            "radius",
            format!(
                "an electrode of radius {} mm fits nowhere on the free side",
                args.radius
            ),
        ));
    }
    if !(args.feed > 0.0 && args.feed.is_finite()) {
        return Err(ProfileError::new(
            &file,
            "--feed",
            format!("{} mm/min must be positive", args.feed),
        ));
    }
    if let Some(out) = &args.output {
        let dialect = Dialect::resolve(&args.dialect)
            .map_err(|e| ProfileError::new(&args.dialect, "dialect", e.to_string()))?;
        let g = GcodeOptions {
            plane: args.plane.into(),
            feed_mm_per_min: args.feed,
            radius_mm: args.radius,
            ..GcodeOptions::default()
        };
        let text = write_gcode(&result.paths, &dialect, &g).map_err(|e| ProfileError {
            file: out.display().to_string(),
            ..e
        })?;
        crate::storage::write_atomic(out, text.as_bytes())
            .map_err(|e| ProfileError::new(&out.display().to_string(), "file", e.to_string()))?;
    }
    Ok(document(&result))
}

fn xy(p: glam::DVec2) -> serde_json::Value {
    json!([p.x, p.y])
}

/// The JSON document of a result.
#[must_use]
pub fn document(r: &ProfileResult) -> serde_json::Value {
    let verts = || r.paths.iter().flat_map(|p| p.vertices.iter());
    let flags = |kind: FlagKind| -> Vec<serde_json::Value> {
        r.flags
            .iter()
            .filter(|f| f.kind == kind)
            .map(|f| {
                json!({
                    "x": f.point.x, "y": f.point.y, "depth": f.depth_mm,
                    "point": f.point_index, "centre": xy(f.centre), "deepest": xy(f.deepest),
                    "span_mm": [f.span_mm.0, f.span_mm.1],
                    "concave_radius_mm": f.concave_radius_mm,
                })
            })
            .collect()
    };
    let mut start = 0;
    let pieces: Vec<serde_json::Value> = r
        .paths
        .iter()
        .map(|p| {
            let v = json!({"first": start, "count": p.vertices.len(), "closed": p.closed, "length_mm": p.length_mm()});
            start += p.vertices.len();
            v
        })
        .collect();
    json!({
        "units": "mm",
        "radius_mm": r.radius_mm,
        "side": if r.left { "left" } else { "right" },
        "cl": verts().map(|v| xy(v.centre)).collect::<Vec<_>>(),
        "cl_bulge": verts().map(|v| v.bulge).collect::<Vec<_>>(),
        "contacts": verts().map(|v| xy(v.contact)).collect::<Vec<_>>(),
        "lowest": verts().map(|v| xy(v.lowest)).collect::<Vec<_>>(),
        "pieces": pieces,
        "naive_cl": r.naive.iter().map(|n| xy(n.centre)).collect::<Vec<_>>(),
        "plunges": flags(FlagKind::Plunge),
        "collisions": flags(FlagKind::Collision),
        "max_gouge_free_radius": r.max_gouge_free_radius_mm,
        "max_radius_within_tolerance": r.max_radius_within_tolerance_mm,
        "min_concave_radius_sampled": r.min_concave_radius_sampled_mm,
        "max_distance_error_mm": r.max_distance_error_mm,
    })
}

/// The human summary.
#[must_use]
pub fn human(doc: &serde_json::Value) -> String {
    let n = |k: &str| doc[k].as_array().map_or(0, Vec::len);
    let radius = |k: &str| {
        doc[k]
            .as_f64()
            .map_or("none".to_string(), |v| format!("{v:.6} mm"))
    };
    format!(
        "centre path: {} vertices in {} piece(s), side {}\nplunges of the per-point path: {}\nside collisions of the per-point path: {}\nlargest gouge-free radius: {}\nlargest radius within the gouge tolerance: {}\nsmallest sampled concave radius: {}\nlargest |distance - R| of the path: {:.3e} mm\n",
        n("cl"),
        n("pieces"),
        doc["side"].as_str().unwrap_or("?"),
        n("plunges"),
        n("collisions"),
        radius("max_gouge_free_radius"),
        radius("max_radius_within_tolerance"),
        radius("min_concave_radius_sampled"),
        doc["max_distance_error_mm"].as_f64().unwrap_or(f64::NAN),
    )
}
