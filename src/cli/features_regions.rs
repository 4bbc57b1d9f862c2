//! The regions part of `talas features PART [--json]` ([`super::features`]): the machinable
//! regions of a STEP part seen from +Z (kind, floor height, depth, area, smallest corner
//! radius, islands, open sides).

use serde_json::{Value, json};

use crate::features::regions::RegionReport;

/// The regions of a report as JSON (the region geometry left out: kind, faces, heights, area,
/// corner radius, islands, open sides, bounding box; every number carries its unit in its name).
#[must_use]
pub fn regions_json(report: &RegionReport) -> Value {
    let regions: Vec<Value> = report
        .regions
        .iter()
        .map(|r| {
            json!({
                "kind": r.kind,
                "faces": r.faces.iter().map(|f| f + 1).collect::<Vec<_>>(),
                "floor_z_mm": r.floor_z_mm,
                "top_z_mm": r.top_z_mm,
                "depth_mm": r.depth_mm,
                "area_mm2": r.area_mm2,
                "smallest_corner_radius_mm": r.smallest_corner_radius_mm,
                "islands": r.islands,
                "open_sides": r.open_sides,
                "bbox_mm": r.bbox_mm,
            })
        })
        .collect();
    json!({ "regions": regions, "skipped": report.skipped })
}

/// A table of the regions.
#[must_use]
pub fn human(doc: &Value) -> String {
    let mut s = String::new();
    let empty = Vec::new();
    let regions = doc["regions"].as_array().unwrap_or(&empty);
    s.push_str(&format!("{} regions seen from +Z\n", regions.len()));
    s.push_str("kind           floor mm   depth mm    area mm²  corner mm  islands  open  faces\n");
    for r in regions {
        let corner = r["smallest_corner_radius_mm"]
            .as_f64()
            .map_or_else(|| "-".to_string(), |c| format!("{c:.3}"));
        let faces: Vec<String> = r["faces"]
            .as_array()
            .unwrap_or(&empty)
            .iter()
            .map(ToString::to_string)
            .collect();
        s.push_str(&format!(
            "{:<14} {:>9.4} {:>10.4} {:>11.3} {:>10} {:>8} {:>5}  {}\n",
            r["kind"].as_str().unwrap_or("?"),
            r["floor_z_mm"].as_f64().unwrap_or(f64::NAN),
            r["depth_mm"].as_f64().unwrap_or(f64::NAN),
            r["area_mm2"].as_f64().unwrap_or(f64::NAN),
            corner,
            r["islands"].as_u64().unwrap_or(0),
            r["open_sides"].as_u64().unwrap_or(0),
            faces.join(",")
        ));
    }
    for k in doc["skipped"].as_array().unwrap_or(&empty) {
        s.push_str(&format!("skipped: {}\n", k.as_str().unwrap_or("")));
    }
    s
}
