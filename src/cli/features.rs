//! `talas features PART [--json]`: the machining features recognised on a STEP part: holes
//! (position, direction, diameter, depth, bottom, steps, groups) and the machinable regions
//! seen from +Z (`"regions"`, [`super::features_regions`]).

use std::fmt::Write as _;
use std::path::PathBuf;

use serde_json::{Value, json};

use crate::features::holes::{HoleBottom, HoleReport, HoleStep};
use crate::import::ImportError;
use crate::import::step::read_step;

/// Options of `talas features`.
#[derive(Debug, clap::Args)]
pub struct FeaturesArgs {
    /// The part (STEP, .stp/.step).
    pub file: PathBuf,
    /// Print one JSON document instead of the human list.
    #[arg(long)]
    pub json: bool,
}

/// The part's holes, recognised from its B-rep (the tessellation tells reversed shells).
///
/// # Errors
/// The import error (file and place) when the part cannot be read.
pub fn find_holes(file: &std::path::Path) -> Result<HoleReport, ImportError> {
    Ok(holes_of(&read_step(file)?))
}

/// The holes of a read part ([`crate::features::holes_of`]).
#[must_use]
pub fn holes_of(part: &crate::geometry::brep::Part) -> HoleReport {
    crate::features::holes_of(part)
}

/// What `features` found, as JSON (lengths in mm, angles in degrees, keys say so).
///
/// # Errors
/// The import error when the part cannot be read.
pub fn features(args: &FeaturesArgs) -> Result<Value, ImportError> {
    let part = read_step(&args.file)?;
    let mut doc = holes_json(&holes_of(&part), &args.file.display().to_string());
    let regions =
        super::features_regions::regions_json(&crate::features::regions::find_regions(&part));
    if let Some(o) = doc.as_object_mut() {
        o.insert("regions".into(), regions["regions"].clone());
        o.insert("regions_skipped".into(), regions["skipped"].clone());
    }
    Ok(doc)
}

/// The holes as JSON.
#[must_use]
pub fn holes_json(rep: &HoleReport, file: &str) -> Value {
    let v3 = |p: crate::geometry::DVec3| json!([p.x, p.y, p.z]);
    let holes: Vec<Value> = rep
        .holes
        .iter()
        .enumerate()
        .map(|(i, h)| {
            let bottom = match h.bottom {
                HoleBottom::Through => json!({"kind": "through"}),
                HoleBottom::Flat => json!({"kind": "flat"}),
                HoleBottom::Other { tip_depth_mm } => {
                    json!({"kind": "other", "tip_depth_mm": tip_depth_mm})
                }
                HoleBottom::Point {
                    angle_rad,
                    tip_depth_mm,
                } => json!({"kind": "point", "angle_deg": angle_rad.to_degrees(),
                            "tip_depth_mm": tip_depth_mm}),
            };
            let steps: Vec<Value> = h
                .steps
                .iter()
                .map(|s| match *s {
                    HoleStep::Cylinder {
                        diameter_mm,
                        depth_mm,
                    } => json!({"kind": "cylinder", "diameter_mm": diameter_mm, "depth_mm": depth_mm}),
                    HoleStep::Cone {
                        top_diameter_mm,
                        bottom_diameter_mm,
                        angle_rad,
                        depth_mm,
                    } => json!({"kind": "cone", "top_diameter_mm": top_diameter_mm,
                                "bottom_diameter_mm": bottom_diameter_mm,
                                "angle_deg": angle_rad.to_degrees(), "depth_mm": depth_mm}),
                })
                .collect();
            json!({
                "index": i,
                "top_mm": v3(h.top),
                "direction": v3(h.direction),
                "diameter_mm": h.diameter_mm,
                "depth_mm": h.depth_mm,
                "full_depth_mm": h.full_depth_mm(),
                "bottom": bottom,
                "kind": h.kind,
                "steps": steps,
                "faces": h.faces,
                "split": h.split,
                "thread_suggestion": h.thread_suggestion.map(|t| json!({
                    "name": t.name, "major_diameter_mm": t.major_diameter_mm, "pitch_mm": t.pitch_mm})),
            })
        })
        .collect();
    let groups: Vec<Value> = rep
        .groups
        .iter()
        .map(|g| json!({"diameter_mm": g.diameter_mm, "direction": v3(g.direction), "holes": g.holes}))
        .collect();
    let diagnostics: Vec<Value> = rep
        .diagnostics
        .iter()
        .map(|d| json!({"severity": format!("{:?}", d.severity).to_lowercase(), "place": d.place, "message": d.message}))
        .collect();
    json!({"file": file, "holes": holes, "hole_groups": groups, "diagnostics": diagnostics})
}

/// The human list.
#[must_use]
pub fn human(doc: &Value) -> String {
    let mut s = String::new();
    let holes = doc["holes"].as_array().map_or(&[][..], Vec::as_slice);
    let _ = writeln!(
        s,
        "{}: {} holes",
        doc["file"].as_str().unwrap_or(""),
        holes.len()
    );
    let num = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    for h in holes {
        let t = &h["top_mm"];
        let d = &h["direction"];
        let bottom = match h["bottom"]["kind"].as_str() {
            Some("point") => format!(
                "drill point {:.1}°, tip at {:.4} mm",
                num(&h["bottom"]["angle_deg"]),
                num(&h["bottom"]["tip_depth_mm"])
            ),
            Some("other") => format!(
                "closed by another face, deepest at {:.4} mm",
                num(&h["bottom"]["tip_depth_mm"])
            ),
            Some(k) => k.to_string(),
            None => String::new(),
        };
        let _ = write!(
            s,
            "  [{}] Ø{:.4} mm × {:.4} mm deep, {}, {} at ({:.4}, {:.4}, {:.4}) mm, axis ({:.3}, {:.3}, {:.3})",
            h["index"],
            num(&h["diameter_mm"]),
            num(&h["depth_mm"]),
            bottom,
            h["kind"].as_str().unwrap_or(""),
            num(&t[0]),
            num(&t[1]),
            num(&t[2]),
            num(&d[0]),
            num(&d[1]),
            num(&d[2]),
        );
        for st in h["steps"].as_array().map_or(&[][..], Vec::as_slice) {
            if st["kind"] == "cylinder" {
                let _ = write!(
                    s,
                    "; step Ø{:.4} mm to {:.4} mm",
                    num(&st["diameter_mm"]),
                    num(&st["depth_mm"])
                );
            } else {
                let _ = write!(
                    s,
                    "; cone Ø{:.4}→Ø{:.4} mm {:.1}°",
                    num(&st["top_diameter_mm"]),
                    num(&st["bottom_diameter_mm"]),
                    num(&st["angle_deg"])
                );
            }
        }
        if let Some(name) = h["thread_suggestion"]["name"].as_str() {
            let _ = write!(s, "; tap drill of {name}?");
        }
        if h["split"] == true {
            s.push_str("; wall in several faces");
        }
        s.push('\n');
    }
    for g in doc["hole_groups"].as_array().map_or(&[][..], Vec::as_slice) {
        let _ = writeln!(
            s,
            "  group Ø{:.4} mm: holes {}",
            num(&g["diameter_mm"]),
            g["holes"]
        );
    }
    for d in doc["diagnostics"].as_array().map_or(&[][..], Vec::as_slice) {
        let _ = writeln!(
            s,
            "{}: {}{}",
            d["severity"].as_str().unwrap_or(""),
            d["place"]
                .as_str()
                .map(|p| format!("{p}: "))
                .unwrap_or_default(),
            d["message"].as_str().unwrap_or("")
        );
    }
    if doc.get("regions").is_some() {
        let mut r = doc.clone();
        if let Some(o) = r.as_object_mut() {
            o.insert("skipped".into(), doc["regions_skipped"].clone());
        }
        s.push_str(&super::features_regions::human(&r));
    }
    s
}
