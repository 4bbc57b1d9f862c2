//! `talas dropcutter FILE.stl --tool SPEC --points XY.csv [--json]`: drop-cutter against a mesh.
//! The JSON's `"cl"` is `[[x, y, z], ...]` in input order (z = tool-tip height), `null` where the
//! tool misses the mesh; `"contacts"` counts vertex, edge and facet contacts and misses.

use std::path::{Path, PathBuf};

use glam::DVec2;
use serde_json::{Value, json};

use crate::geometry::bvh::MeshBvh;
use crate::import::ImportError;
use crate::import::stl::{StlOptions, read_stl};
use crate::tools::dropcutter::{Contact, drop_cutter};
use crate::tools::parse_tool_spec;

/// Options of `talas dropcutter`.
#[derive(Debug, clap::Args)]
pub struct DropcutterArgs {
    /// The part mesh (.stl, mm).
    pub file: PathBuf,
    /// The tool: `ball:d=6`, `flat:d=10`, `bull:d=10,r=2`, `cone:d=10,angle=45` (half-angle,
    /// degrees), optionally `,flute=20,shank=8`.
    #[arg(long, value_name = "SPEC")]
    pub tool: String,
    /// The XY points: a CSV with the header line `x,y`, then one point a line (mm).
    #[arg(long, value_name = "XY.csv")]
    pub points: PathBuf,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// Run the drop-cutter and build the contract's JSON document.
///
/// # Errors
/// An [`ImportError`] naming the file (and line) for an unreadable mesh or points file, or
/// naming `--tool` for a bad tool spec.
pub fn dropcutter(args: &DropcutterArgs) -> Result<Value, ImportError> {
    let cutter = parse_tool_spec(&args.tool)
        .map_err(|e| ImportError::new(Path::new("--tool"), None, e.to_string()))?;
    let points = read_points(&args.points)?;
    let stl = read_stl(&args.file, &StlOptions::default())?;
    let bvh =
        MeshBvh::new(&stl.mesh).map_err(|e| ImportError::new(&args.file, None, e.to_string()))?;
    let cls = drop_cutter(&bvh, &stl.mesh, &cutter, &points);
    let mut counts = [0usize; 4];
    let cl: Vec<Value> = points
        .iter()
        .zip(&cls)
        .map(|(p, c)| match c {
            Some(c) => {
                let k = match c.contact {
                    Contact::Vertex => 0,
                    Contact::Edge => 1,
                    Contact::Facet => 2,
                };
                if let Some(n) = counts.get_mut(k) {
                    *n += 1;
                }
                json!([p.x, p.y, c.z])
            }
            None => {
                if let Some(n) = counts.get_mut(3) {
                    *n += 1;
                }
                Value::Null
            }
        })
        .collect();
    Ok(json!({
        "units": "mm",
        "tool": cutter,
        "points": points.len(),
        "contacts": {"vertex": counts[0], "edge": counts[1], "facet": counts[2], "miss": counts[3]},
        "cl": cl,
    }))
}

/// A short human summary of the JSON document.
#[must_use]
pub fn human(doc: &Value) -> String {
    let c = &doc["contacts"];
    format!(
        "{} points: {} vertex, {} edge, {} facet contacts, {} misses\n",
        doc["points"], c["vertex"], c["edge"], c["facet"], c["miss"]
    )
}

/// Read the points CSV: header `x,y`, then `x,y` a line (blank lines skipped).
///
/// # Errors
/// An [`ImportError`] naming the file and 1-based line.
pub fn read_points(path: &Path) -> Result<Vec<DVec2>, ImportError> {
    let text = crate::storage::read_text_bounded(path, crate::storage::TEXT_LIMIT_BYTES)
        .map_err(|e| ImportError::new(path, None, format!("cannot read file: {e}")))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.replace(' ', "").trim().eq_ignore_ascii_case("x,y") => {}
        _ => {
            return Err(ImportError::new(
                path,
                Some("line 1".to_string()),
                "expected the header line 'x,y'",
            ));
        }
    }
    let mut out = Vec::new();
    for (i, line) in lines {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let place = || Some(format!("line {}", i + 1));
        let mut it = line.split(',').map(str::trim);
        let (Some(x), Some(y), None) = (it.next(), it.next(), it.next()) else {
            return Err(ImportError::new(path, place(), "expected two values 'x,y'"));
        };
        let num = |v: &str| {
            v.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| ImportError::new(path, place(), format!("'{v}' is not a number")))
        };
        out.push(DVec2::new(num(x)?, num(y)?));
    }
    Ok(out)
}
