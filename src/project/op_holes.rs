//! Hole making, shared by `talas plan --strategy drill|…` and the project's
//! [`super::Operation::Holes`]: which holes (recognised by [`crate::features::holes`]: the
//! holes the tool fits, filtered by diameter; or named by a face or by their centres), how deep
//! each tool goes, and the cycle ([`crate::strategies::holes::plan_holes`]). The cycles stay
//! exact moves in the tool path, so the post writes them as canned cycles where the dialect
//! has them.

use glam::{DVec2, DVec3};

use super::op_common::Common;
use crate::features::holes::{Hole, HoleBottom, HoleReport, HoleStep, thread_for_tap_drill};
use crate::strategies::holes::{HolePlanOptions, HoleStrategy, HoleTarget, plan_holes};
use crate::toolpath::{CycleKind, ToolRecord};

/// The hole cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HoleCycle {
    /// Drill to depth, rapid out (G81).
    Drill,
    /// Drill with a dwell at the bottom (G82).
    Dwell,
    /// Peck drilling, full retracts (G83).
    Peck,
    /// Chip-breaking pecks (G73).
    ChipBreak,
    /// Rigid tapping (G84).
    Tap,
    /// Boring, fed out (G85/G89).
    Bore,
    /// Reaming, fed out.
    Ream,
    /// Helical boring with an end mill.
    HelicalBore,
    /// Thread milling.
    ThreadMill,
    /// Spot drilling (as deep as makes the spot as wide as the countersink, or the hole plus
    /// 0.2 mm).
    Spot,
}

impl HoleCycle {
    /// Every cycle, in `talas plan`'s order.
    pub const ALL: [Self; 10] = [
        Self::Drill,
        Self::Dwell,
        Self::Peck,
        Self::ChipBreak,
        Self::Tap,
        Self::Bore,
        Self::Ream,
        Self::HelicalBore,
        Self::ThreadMill,
        Self::Spot,
    ];

    /// The command line's name (`chip-break`, `helical-bore`, …).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Drill => "drill",
            Self::Dwell => "dwell",
            Self::Peck => "peck",
            Self::ChipBreak => "chip-break",
            Self::Tap => "tap",
            Self::Bore => "bore",
            Self::Ream => "ream",
            Self::HelicalBore => "helical-bore",
            Self::ThreadMill => "thread-mill",
            Self::Spot => "spot",
        }
    }

    /// The cycle of a command-line name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// Which holes.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "by", rename_all = "snake_case")]
pub enum HoleSelection {
    /// The recognised holes the tool fits (see [`hole_job`]), within the diameter range when
    /// one is given.
    Auto {
        /// Smallest main-bore diameter taken, mm.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        min_diameter_mm: Option<f64>,
        /// Largest main-bore diameter taken, mm.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        max_diameter_mm: Option<f64>,
    },
    /// The holes that hold these faces (0-based, STEP order).
    Faces {
        /// Faces, one of each hole.
        faces: Vec<usize>,
    },
    /// The holes whose entry centre lies within 0.5 mm of these points (X, Y in the frame the
    /// holes were recognised in: the setup's planning frame for an operation).
    Points {
        /// Centres, mm.
        points: Vec<[f64; 2]>,
    },
}

impl Default for HoleSelection {
    fn default() -> Self {
        Self::Auto {
            min_diameter_mm: None,
            max_diameter_mm: None,
        }
    }
}

impl HoleSelection {
    /// The command line's `--holes`: `auto`, `FACE,FACE` (as `talas inspect` numbers them) or
    /// `X,Y;X,Y`.
    ///
    /// # Errors
    /// A part that is not a number or a pair.
    pub fn parse(text: &str) -> Result<Self, String> {
        let sel = text.trim();
        if sel == "auto" {
            return Ok(Self::default());
        }
        let num = |t: &str| {
            t.trim()
                .parse::<f64>()
                .map_err(|_| format!("'{t}' is not a number"))
        };
        if sel.contains(';') || sel.contains('.') {
            let mut points = Vec::new();
            for pair in sel.split(';').filter(|p| !p.trim().is_empty()) {
                let (x, y) = pair
                    .split_once(',')
                    .ok_or_else(|| format!("'{pair}' is not X,Y"))?;
                points.push([num(x)?, num(y)?]);
            }
            Ok(Self::Points { points })
        } else {
            let faces = sel
                .split(',')
                .map(|f| {
                    f.trim()
                        .parse::<usize>()
                        .map_err(|_| format!("'{f}' is not a face index"))
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok(Self::Faces { faces })
        }
    }
}

/// The cycle's own numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoleSettings {
    /// Depth of each peck (peck, chip-break), mm.
    pub peck_mm: f64,
    /// Dwell at the bottom (dwell, bore, ream), s.
    pub dwell_s: f64,
    /// Thread pitch (tap, thread-mill) or helix descent per turn (helical-bore), mm; `None`:
    /// the tool's pitch (helical-bore 1 mm).
    pub pitch_mm: Option<f64>,
    /// Depth below each hole's top instead of the recognised one, mm.
    pub depth_mm: Option<f64>,
    /// Radial stock the helical-bore roughing helix leaves for the finishing one, mm.
    pub finish_mm: f64,
    /// Teeth of the thread mill along its axis at the pitch (`None`: 1, a single-form mill).
    pub teeth: Option<u32>,
}

/// The holes to make, the cycle, and what was left out.
#[derive(Clone, Debug, PartialEq)]
pub struct HoleJob {
    /// One target per hole.
    pub targets: Vec<HoleTarget>,
    /// The cycle.
    pub strategy: HoleStrategy,
    /// The direction out of the holes made.
    pub direction: DVec3,
    /// Holes selected but pointing another way.
    pub skipped: usize,
}

fn add<'a>(chosen: &mut Vec<&'a Hole>, h: &'a Hole) {
    if !chosen.iter().any(|o| std::ptr::eq(*o, h)) {
        chosen.push(h);
    }
}

fn counterbore(h: &Hole) -> Option<(f64, f64)> {
    h.steps.iter().find_map(|s| match *s {
        HoleStep::Cylinder {
            diameter_mm,
            depth_mm,
        } => Some((diameter_mm, depth_mm)),
        HoleStep::Cone { .. } => None,
    })
}

/// How deep a tool goes into a hole, mm (a through hole: the point past the exit and 0.5 mm).
fn drill_depth(h: &Hole, tool: &ToolRecord) -> f64 {
    let point = match tool.cutter.kind {
        crate::tools::CutterKind::Cone { half_angle } => {
            0.5 * tool.cutter.diameter / half_angle.tan()
        }
        _ => 0.0,
    };
    match h.bottom {
        HoleBottom::Through => h.depth_mm + point + 0.5,
        HoleBottom::Point { tip_depth_mm, .. } => tip_depth_mm,
        HoleBottom::Flat | HoleBottom::Other { .. } => h.depth_mm,
    }
}

/// The holes of `rep` that `sel` names and the tool fits: for drill, dwell, peck, chip-break,
/// bore and ream the holes of the tool's diameter (within 0.01 mm); for tap and thread-mill
/// those whose tap drill matches the tap (or the thread mill's pitch); every hole for spot;
/// holes (or their counterbores) wider than the tool for helical-bore. With `direction`, only
/// the holes that open that way (within 1e-6), else the way most of them open.
///
/// # Errors
/// A bad selection, no hole, or a missing pitch.
pub fn hole_job(
    rep: &HoleReport,
    cycle: HoleCycle,
    record: &ToolRecord,
    tool_pitch: Option<f64>,
    sel: &HoleSelection,
    s: &HoleSettings,
    direction: Option<DVec3>,
) -> Result<HoleJob, String> {
    let d_tool = record.cutter.diameter;
    let fits = |h: &Hole| match cycle {
        HoleCycle::Spot => true,
        HoleCycle::Tap | HoleCycle::ThreadMill => {
            thread_for_tap_drill(h.diameter_mm).is_some_and(|t| {
                (t.major_diameter_mm - d_tool).abs() <= 0.01
                    || cycle == HoleCycle::ThreadMill
                        && tool_pitch.is_none_or(|p| (p - t.pitch_mm).abs() < 1e-9)
            })
        }
        HoleCycle::HelicalBore => counterbore(h).map_or(h.diameter_mm, |c| c.0) > d_tool + 1e-6,
        _ => (h.diameter_mm - d_tool).abs() <= 0.01,
    };
    let mut chosen: Vec<&Hole> = Vec::new();
    match sel {
        HoleSelection::Auto {
            min_diameter_mm,
            max_diameter_mm,
        } => {
            for h in rep.holes.iter().filter(|h| {
                fits(h)
                    && min_diameter_mm.is_none_or(|d| h.diameter_mm >= d - 1e-9)
                    && max_diameter_mm.is_none_or(|d| h.diameter_mm <= d + 1e-9)
            }) {
                add(&mut chosen, h);
            }
        }
        HoleSelection::Faces { faces } => {
            for &f in faces {
                let h = rep
                    .holes
                    .iter()
                    .find(|h| h.faces.contains(&f))
                    .ok_or_else(|| format!("face {f} belongs to no hole"))?;
                add(&mut chosen, h);
            }
        }
        HoleSelection::Points { points } => {
            for &[x, y] in points {
                let at = DVec2::new(x, y);
                let h = rep
                    .holes
                    .iter()
                    .min_by(|a, b| {
                        (a.top.truncate() - at)
                            .length()
                            .total_cmp(&(b.top.truncate() - at).length())
                    })
                    .filter(|h| (h.top.truncate() - at).length() <= 0.5)
                    .ok_or_else(|| format!("no hole within 0.5 mm of ({x}, {y}) mm"))?;
                add(&mut chosen, h);
            }
        }
    }
    if chosen.is_empty() {
        return Err(format!(
            "no hole for a {} with a {d_tool} mm tool among the part's {} holes",
            cycle.name(),
            rep.holes.len()
        ));
    }
    let dir = direction.unwrap_or_else(|| {
        chosen
            .iter()
            .map(|h| h.direction)
            .max_by_key(|d| {
                chosen
                    .iter()
                    .filter(|h| h.direction.distance(*d) < 1e-6)
                    .count()
            })
            .unwrap_or(DVec3::Z)
    });
    let total = chosen.len();
    chosen.retain(|h| h.direction.distance(dir) < 1e-6);
    let skipped = total - chosen.len();
    if chosen.is_empty() {
        return Err(format!(
            "none of the {total} holes chosen opens towards ({:.3}, {:.3}, {:.3})",
            dir.x, dir.y, dir.z
        ));
    }
    let pitch = s.pitch_mm.or(tool_pitch);
    let strategy = match cycle {
        HoleCycle::Drill | HoleCycle::Spot => HoleStrategy::Cycle(CycleKind::Drill),
        HoleCycle::Dwell => HoleStrategy::Cycle(CycleKind::Dwell { dwell_s: s.dwell_s }),
        HoleCycle::Peck => HoleStrategy::Cycle(CycleKind::Peck { peck_mm: s.peck_mm }),
        HoleCycle::ChipBreak => HoleStrategy::Cycle(CycleKind::ChipBreak { peck_mm: s.peck_mm }),
        HoleCycle::Tap => HoleStrategy::Cycle(CycleKind::Tap {
            pitch_mm: pitch.ok_or("a tap needs its pitch")?,
        }),
        HoleCycle::Bore | HoleCycle::Ream => {
            HoleStrategy::Cycle(CycleKind::Bore { dwell_s: s.dwell_s })
        }
        HoleCycle::HelicalBore => HoleStrategy::HelicalBore {
            pitch_mm: s.pitch_mm.unwrap_or(1.0),
            finish_mm: s.finish_mm,
        },
        HoleCycle::ThreadMill => HoleStrategy::ThreadMill {
            pitch_mm: pitch.ok_or("a thread mill needs the pitch")?,
            teeth: s.teeth.unwrap_or(1).max(1),
        },
    };
    let targets = chosen
        .iter()
        .map(|h| {
            let (diameter_mm, depth_mm) = match cycle {
                HoleCycle::Spot => {
                    let half = match record.cutter.kind {
                        crate::tools::CutterKind::Cone { half_angle } => half_angle,
                        _ => std::f64::consts::FRAC_PI_4,
                    };
                    // As wide as the countersink, else the hole plus 0.2 mm.
                    let width = h
                        .steps
                        .iter()
                        .find_map(|s| match *s {
                            HoleStep::Cone {
                                top_diameter_mm, ..
                            } => Some(top_diameter_mm),
                            HoleStep::Cylinder { .. } => None,
                        })
                        .unwrap_or(h.diameter_mm + 0.2);
                    (h.diameter_mm, 0.5 * width / half.tan())
                }
                HoleCycle::HelicalBore => counterbore(h).unwrap_or((h.diameter_mm, h.depth_mm)),
                HoleCycle::ThreadMill => (
                    thread_for_tap_drill(h.diameter_mm)
                        .map_or(h.diameter_mm, |t| t.major_diameter_mm),
                    h.depth_mm,
                ),
                HoleCycle::Tap => (h.diameter_mm, h.depth_mm),
                _ => (h.diameter_mm, drill_depth(h, record)),
            };
            HoleTarget {
                top: h.top,
                direction: h.direction,
                depth_mm: s.depth_mm.unwrap_or(depth_mm),
                diameter_mm,
            }
        })
        .collect();
    Ok(HoleJob {
        targets,
        strategy,
        direction: dir,
        skipped,
    })
}

/// A hole-making operation.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HolesOp {
    /// Name shown in the tree.
    pub name: String,
    /// Index of the tool in [`super::Project::tools`] (a drill is a cone cutter of the drill's
    /// point angle; a tap, reamer or boring bar a flat one of its diameter).
    pub tool: usize,
    /// Heights (the retract height is the cycles' R plane), feeds, spindle, coolant.
    #[serde(flatten)]
    pub common: Common,
    /// The cycle.
    pub cycle: HoleCycle,
    /// Which holes (default: those the tool fits, opening towards the setup's +Z).
    #[serde(default)]
    pub holes: HoleSelection,
    /// Depth of each peck (peck, chip-break), mm.
    #[serde(default = "default_peck")]
    pub peck_mm: f64,
    /// Dwell at the bottom, s.
    #[serde(default)]
    pub dwell_s: f64,
    /// Thread pitch or helix descent per turn, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pitch_mm: Option<f64>,
    /// Depth below each hole's top instead of the recognised one, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_mm: Option<f64>,
    /// Radial stock the helical-bore roughing helix leaves, mm.
    #[serde(default = "default_finish")]
    pub finish_mm: f64,
    /// Teeth of the thread mill along its axis at the pitch (thread-mill; absent: 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub teeth: Option<u32>,
}

fn default_peck() -> f64 {
    2.0
}
fn default_finish() -> f64 {
    0.2
}

impl HolesOp {
    /// A drilling operation with `tool`, starting values.
    #[must_use]
    pub fn new(name: String, tool: usize) -> Self {
        Self {
            name,
            tool,
            common: Common {
                feed_mm_per_min: 200.0,
                ..Common::default()
            },
            cycle: HoleCycle::Drill,
            holes: HoleSelection::default(),
            peck_mm: default_peck(),
            dwell_s: 0.0,
            pitch_mm: None,
            depth_mm: None,
            finish_mm: default_finish(),
            teeth: None,
        }
    }

    /// Check the numbers.
    ///
    /// # Errors
    /// What is wrong.
    pub fn validate(&self) -> Result<(), String> {
        self.common.validate()?;
        crate::units::STEP_BOUNDS.check("peck (mm)", self.peck_mm)?;
        super::op_regions::non_negative("dwell (s)", self.dwell_s)?;
        super::op_regions::non_negative("finishing stock (mm)", self.finish_mm)?;
        for (what, v) in [("pitch (mm)", self.pitch_mm), ("depth (mm)", self.depth_mm)] {
            if let Some(v) = v {
                super::op_regions::positive(what, v)?;
            }
        }
        if self.teeth == Some(0) {
            return Err("teeth: a thread mill has at least one".into());
        }
        Ok(())
    }

    /// Plan on `part` as it lies in the planning frame: the holes recognised there that open
    /// towards +Z (the setup's tool axis), the R plane at the retract height (its distance
    /// above the highest hole's top), the clearance height above the part's top.
    ///
    /// # Errors
    /// No B-rep part, no hole, or the planner's message.
    pub fn compute(
        &self,
        part: &crate::import::Workpiece,
        tool: &ToolRecord,
        stock_top_z: Option<f64>,
    ) -> Result<super::computed::Computed, String> {
        let brep = part
            .part
            .as_deref()
            .ok_or("recognising holes needs a STEP part (the part is a mesh)")?;
        let mesh = crate::geometry::tessellate::tessellate_part(
            brep,
            &crate::geometry::tessellate::TessellationOptions::for_size(
                brep.rough_bbox().diagonal(),
            ),
        );
        let rep = crate::features::holes::recognize_holes(brep, Some(&mesh), &Default::default());
        let settings = HoleSettings {
            peck_mm: self.peck_mm,
            dwell_s: self.dwell_s,
            pitch_mm: self.pitch_mm,
            depth_mm: self.depth_mm,
            finish_mm: self.finish_mm,
            teeth: self.teeth,
        };
        let job = hole_job(
            &rep,
            self.cycle,
            tool,
            self.pitch_mm,
            &self.holes,
            &settings,
            Some(DVec3::Z),
        )?;
        let levels = super::op_common::levels(part, stock_top_z);
        let highest = job
            .targets
            .iter()
            .map(|t| t.top.z)
            .fold(f64::NEG_INFINITY, f64::max);
        let opts = HolePlanOptions {
            r_plane_mm: (self.common.retract.z(&levels) - highest).max(0.5),
            clearance_mm: (self.common.clearance.z(&levels) - levels.part_top_z).max(0.5),
            feed_mm_per_min: self.common.feed_mm_per_min,
            spindle_rpm: self.common.spindle_rpm.unwrap_or(1000.0),
            start: DVec3::ZERO,
            ..HolePlanOptions::default()
        };
        let plan = plan_holes(
            &job.targets,
            &job.strategy,
            tool.clone(),
            Some(&mesh.mesh),
            &opts,
        )?;
        let mut toolpath = plan.toolpath.ok_or("nothing planned")?;
        super::op_common::apply_feeds(&mut toolpath, &self.common);
        let mut diagnostics = Vec::new();
        if job.skipped > 0 {
            diagnostics.push(crate::diagnostics::Diagnostic::info(
                Some(self.name.clone()),
                format!(
                    "{} of the holes chosen open another way than the setup's +Z and are left out",
                    job.skipped
                ),
            ));
        }
        Ok(super::computed::Computed {
            passes: plan.order.len(),
            lead_rad: None,
            clearance_mm: None,
            part_hits: Vec::new(),
            left_out: Vec::new(),
            toolpath,
            diagnostics,
        })
    }
}
