//! The tool path file as other programs write it: what is read generously and how.
//!
//! Talas writes every field ([`super::Toolpath::to_json`]); other programs often write less. The
//! reader accepts:
//! - `units`: optional, `"mm"` when missing (any other value is an error);
//! - `tool`: the SPEC alone defines the cutter (`{"spec": "ball:d=6"}`); the dimension fields
//!   Talas writes (`kind`, `diameter`, `flute_length`, `shank_diameter`, `overall_length`,
//!   `holder`) are optional and, when present, must agree with the SPEC; without a SPEC the
//!   fields define the cutter;
//! - poses: `axis` optional (+Z), `cc`, `scallop_mm`, `contact` optional; `feed_mm_per_min`
//!   may be missing or `null` on a rapid, and on a fed move it is then modal (the previous fed
//!   move's feed), as in G-code;
//! - `exact`: optional, the exact moves (arcs, helices, cycles) over the poses that sample them
//!   (files written before tool paths had exact moves have none: every move is straight);
//! - `summary`: optional; it is recomputed from the poses (only the planner's gouge report is
//!   kept);
//! - unknown keys anywhere are ignored with a warning naming them.
//!
//! [`schema`] gives the JSON Schema of this format (published as
//! `assets/schema/toolpath.schema.json`).

use glam::DVec3;

use super::{
    ContactKind, ExactSegment, GougeReport, MoveKind, Pose, ToolRecord, Toolpath, ToolpathError,
};
use crate::tools::{
    Cutter, CutterKind, Flutes, HolderSection, ToolLimits, parse_tool_spec, tool_spec,
};

/// A tool path file as read (everything optional that has an obvious default).
#[derive(serde::Deserialize, schemars::JsonSchema)]
#[schemars(
    title = "Talas tool path",
    description = "Cutter-location poses in part coordinates (mm, mm/min). Only `tool` and `poses` are required."
)]
pub struct ToolpathFile {
    /// Length unit: only "mm" (the default).
    #[serde(default)]
    pub units: Option<String>,
    /// The cutter.
    pub tool: ToolFile,
    /// Poses in order (the sampled view of every move).
    pub poses: Vec<PoseFile>,
    /// Exact moves (arcs, helices, canned cycles), each over the poses `from..=to` that sample
    /// it; absent for paths of straight moves.
    #[serde(default)]
    pub exact: Vec<ExactSegment>,
    /// Recomputed on load; only `gouge` (the planner's gouge report) is kept.
    #[serde(default)]
    pub summary: Option<SummaryFile>,
}

/// The summary as read: only the planner's gouge report survives a load.
#[derive(serde::Deserialize, schemars::JsonSchema)]
pub struct SummaryFile {
    /// The planner's gouge report.
    #[serde(default)]
    pub gouge: Option<GougeReport>,
}

/// The tool as read (also the tool entries of tool libraries and projects).
#[derive(Default, serde::Deserialize, schemars::JsonSchema)]
pub struct ToolFile {
    /// Tool SPEC (`ball:d=6`, `flat:d=10,flute=20`, `bull:d=10,r=2`, `cone:d=10,angle=45`, with
    /// optional `shank=`, `length=`, `holder=DxL+DxL`). Defines the cutter on its own.
    #[serde(default)]
    pub spec: Option<String>,
    /// Cutting end (`{"type": "ball"}`, `{"type": "bull_nose", "corner_radius": 2}`, ...).
    #[serde(default)]
    pub kind: Option<CutterKind>,
    /// Cutting diameter, mm.
    #[serde(default)]
    pub diameter: Option<f64>,
    /// Fluted length from the tip, mm.
    #[serde(default)]
    pub flute_length: Option<f64>,
    /// Shank diameter, mm.
    #[serde(default)]
    pub shank_diameter: Option<f64>,
    /// Tip to holder face, mm.
    #[serde(default)]
    pub overall_length: Option<f64>,
    /// Holder cylinders from the bottom up.
    #[serde(default)]
    pub holder: Option<Vec<HolderSection>>,
    /// Flute count, helix and rake (rad), for the cutting-force model.
    #[serde(default)]
    pub flutes: Option<Flutes>,
    /// Load limits (`max_force_n`, `max_torque_nm`, `max_power_w`), each optional.
    #[serde(default)]
    pub limits: Option<ToolLimits>,
}

/// One pose as read.
#[derive(serde::Deserialize, schemars::JsonSchema)]
pub struct PoseFile {
    /// Tool tip [x, y, z], mm.
    #[schemars(with = "[f64; 3]")]
    pub tip: DVec3,
    /// Tool axis [x, y, z] from the tip toward the spindle (normalised on load); default +Z.
    #[serde(default)]
    #[schemars(with = "Option<[f64; 3]>")]
    pub axis: Option<DVec3>,
    /// The move reaching this pose.
    pub kind: MoveKind,
    /// Cutter contact point [x, y, z], mm.
    #[serde(default)]
    #[schemars(with = "Option<[f64; 3]>")]
    pub cc: Option<DVec3>,
    /// Feed, mm/min: may be missing or null on rapids; on a fed move missing means the previous
    /// fed move's feed.
    #[serde(default)]
    pub feed_mm_per_min: Option<f64>,
    /// Predicted scallop height, mm.
    #[serde(default)]
    pub scallop_mm: Option<f64>,
    /// Where the cutter touches the part.
    #[serde(default)]
    pub contact: Option<ContactKind>,
}

/// The JSON Schema of the tool path file, pretty-printed.
#[must_use]
pub fn schema() -> String {
    let schema = schemars::schema_for!(ToolpathFile);
    serde_json::to_string_pretty(&schema).unwrap_or_default() + "\n"
}

/// Parse a tool path file generously; returns the path and one warning per ignored key.
pub(super) fn read(text: &str, file: &str) -> Result<(Toolpath, Vec<String>), ToolpathError> {
    let err = |place: String, message: String| ToolpathError {
        file: file.to_string(),
        place,
        message,
    };
    let mut ignored = Vec::new();
    let mut de = serde_json::Deserializer::from_str(text);
    let parsed: Result<ToolpathFile, _> = serde_ignored::deserialize(&mut de, |path| {
        ignored.push(path.to_string());
    });
    let parsed = parsed.and_then(|p| de.end().map(|()| p)).map_err(|e| {
        err(
            format!("line {}, column {}", e.line(), e.column()),
            super::strip_position(&e.to_string()),
        )
    })?;
    let warnings = ignored
        .into_iter()
        .filter(|k| !k.starts_with("summary."))
        .map(|k| format!("{file}: unknown key '{k}' ignored"))
        .collect();
    let units = parsed.units.unwrap_or_else(|| "mm".into());
    let tool = parsed.tool.record().map_err(|m| err("tool".into(), m))?;
    let mut poses = Vec::with_capacity(parsed.poses.len());
    let mut modal_feed: Option<f64> = None;
    for (k, p) in parsed.poses.iter().enumerate() {
        let feed = match (p.kind, p.feed_mm_per_min) {
            (_, Some(f)) => {
                if p.kind != MoveKind::Rapid {
                    modal_feed = Some(f);
                }
                f
            }
            (MoveKind::Rapid, None) => 0.0,
            (_, None) => modal_feed.ok_or_else(|| {
                err(
                    format!("pose {k}"),
                    "a fed move needs feed_mm_per_min (no earlier fed move gives one)".into(),
                )
            })?,
        };
        let mut pose = Pose::new(p.kind, p.tip, p.axis.unwrap_or(DVec3::Z), feed);
        pose.cc = p.cc;
        pose.scallop_mm = p.scallop_mm;
        pose.contact = p.contact;
        poses.push(pose);
    }
    let mut tp = Toolpath::new(tool, poses);
    tp.units = units;
    tp.exact = parsed.exact;
    tp.validate(file)?;
    for p in &mut tp.poses {
        p.axis = p.axis.normalize();
    }
    tp.summary.gouge = parsed.summary.and_then(|s| s.gouge);
    tp.resummarise();
    Ok((tp, warnings))
}

impl ToolFile {
    /// The cutter from the SPEC, checked against the dimension fields given; or from the
    /// fields alone when there is no SPEC.
    ///
    /// # Errors
    /// What is missing or contradicts the SPEC, in words.
    pub fn record(&self) -> Result<ToolRecord, String> {
        tool_record(self)
    }
}

fn tool_record(t: &ToolFile) -> Result<ToolRecord, String> {
    let Some(spec) = &t.spec else {
        let kind = t
            .kind
            .ok_or("the tool needs a spec (e.g. \"ball:d=6\") or a kind")?;
        let diameter = t.diameter.ok_or("the tool needs a spec or a diameter")?;
        let mut cutter = Cutter::new(kind, diameter).map_err(|e| e.to_string())?;
        if let Some(v) = t.flute_length {
            cutter.flute_length = v;
        }
        if let Some(v) = t.shank_diameter {
            cutter.shank_diameter = v;
        }
        if let Some(v) = t.overall_length {
            cutter.overall_length = v;
        }
        if let Some(h) = &t.holder {
            cutter.holder.clone_from(h);
        }
        cutter.flutes = t.flutes;
        cutter.limits = t.limits.unwrap_or_default();
        cutter.validate().map_err(|e| e.to_string())?;
        return Ok(ToolRecord {
            spec: tool_spec(&cutter),
            cutter,
        });
    };
    let mut cutter = parse_tool_spec(spec).map_err(|e| e.to_string())?;
    cutter.limits = t.limits.unwrap_or_default();
    cutter.limits.validate().map_err(|e| e.to_string())?;
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
    let disagree = |name: &str, given: f64, from_spec: f64| {
        format!("{name} {given} disagrees with the spec '{spec}' ({from_spec})")
    };
    let checks = [
        ("diameter", t.diameter, cutter.diameter),
        ("flute_length", t.flute_length, cutter.flute_length),
        ("shank_diameter", t.shank_diameter, cutter.shank_diameter),
        ("overall_length", t.overall_length, cutter.overall_length),
    ];
    for (name, given, from_spec) in checks {
        if let Some(g) = given
            && !same(g, from_spec)
        {
            return Err(disagree(name, g, from_spec));
        }
    }
    if let Some(kind) = t.kind
        && !same_kind(kind, cutter.kind)
    {
        return Err(format!(
            "kind {kind:?} disagrees with the spec '{spec}' ({:?})",
            cutter.kind
        ));
    }
    if let Some(f) = t.flutes {
        let agree = cutter
            .flutes
            .is_some_and(|c| c.count == f.count && same(c.helix, f.helix) && same(c.rake, f.rake));
        if !agree {
            return Err(format!("flutes disagree with the spec '{spec}'"));
        }
    }
    if let Some(h) = &t.holder {
        let agree = h.len() == cutter.holder.len()
            && h.iter()
                .zip(&cutter.holder)
                .all(|(a, b)| same(a.diameter, b.diameter) && same(a.length, b.length));
        if !agree {
            return Err(format!("holder disagrees with the spec '{spec}'"));
        }
    }
    Ok(ToolRecord {
        spec: spec.trim().to_string(),
        cutter,
    })
}

fn same_kind(a: CutterKind, b: CutterKind) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * x.abs().max(1.0);
    match (a, b) {
        (CutterKind::Ball, CutterKind::Ball) | (CutterKind::Flat, CutterKind::Flat) => true,
        (CutterKind::BullNose { corner_radius: x }, CutterKind::BullNose { corner_radius: y }) => {
            close(x, y)
        }
        (CutterKind::Cone { half_angle: x }, CutterKind::Cone { half_angle: y }) => close(x, y),
        _ => false,
    }
}
