//! Feeds and speeds from the project's work material (issue 31, "Feeds and speeds from cutting
//! data"): the project names a material of the cutting-data library
//! ([`crate::force::cutting_data`]) and the tool material; an operation's spindle speed and
//! feeds are worked out from its tool and the engagement its own parameters give (the step-over
//! and step-down it cuts with, or the step a scallop height gives a finishing pass), with a line
//! per number saying where it came from. [`apply`] writes them into the operation; an operation
//! whose numbers are the library's [`follows`] it, one whose numbers were typed does not, and
//! the editor says which.

use crate::force::cutting_data::{self, Case, Source, Speeds, ToolMaterial};
use crate::tools::{Cutter, CutterKind};

use super::{Operation, Project};

/// Flutes assumed for a tool that does not say how many it has.
pub const ASSUMED_FLUTES: u32 = 2;

/// The project's work material: a key of the cutting-data library (`6061`, `7075`, `1045`,
/// `4140`, `304`, `ti64`, `brass`, `acetal`) and what the tools' edges are made of.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WorkMaterial {
    /// The library's key.
    pub key: String,
    /// The tools' material (carbide when a file leaves it out).
    #[serde(default = "carbide")]
    pub tool_material: ToolMaterial,
}

fn carbide() -> ToolMaterial {
    ToolMaterial::Carbide
}

impl WorkMaterial {
    /// The library entry.
    ///
    /// # Errors
    /// A message naming the key and the library's keys when the key is not in the library.
    pub fn material(&self) -> Result<&'static cutting_data::Material, String> {
        cutting_data::material(&self.key).ok_or_else(|| {
            let keys: Vec<&str> = cutting_data::MATERIALS.iter().map(|m| m.key).collect();
            format!(
                "work material '{}' is not in the cutting-data library ({})",
                self.key,
                keys.join(", ")
            )
        })
    }
}

/// The speeds the library gives one operation, with the engagement they were worked out for.
#[derive(Clone, Debug, PartialEq)]
pub struct OperationSpeeds {
    /// The recommendation (spindle speed, feeds, chip, and a source line per number).
    pub speeds: Speeds,
    /// Radial depth of cut a_e the operation cuts with, mm.
    pub radial_mm: f64,
    /// Axial depth of cut a_p, mm.
    pub axial_mm: f64,
    /// Flutes used (the tool's, or [`ASSUMED_FLUTES`]).
    pub flutes: u32,
    /// Where a_e, a_p and the flute count came from, one line each.
    pub engagement: Vec<Source>,
}

impl OperationSpeeds {
    /// Every source line: the engagement's, then the recommendation's.
    #[must_use]
    pub fn sources(&self) -> Vec<Source> {
        self.engagement
            .iter()
            .chain(&self.speeds.sources)
            .cloned()
            .collect()
    }
}

/// The step between passes that leaves a scallop `h` between two cuts of `cutter` (mm): the
/// chord of the tool's round at depth `h` (a ball's or a bull nose's corner; a flat end mill
/// cuts a flat floor, so its step is its flat, taken as 0.5·D).
fn scallop_step(cutter: &Cutter, h: f64) -> f64 {
    let d = cutter.diameter;
    let r = match cutter.kind {
        CutterKind::Ball => 0.5 * d,
        CutterKind::BullNose { corner_radius } => corner_radius,
        CutterKind::Flat | CutterKind::Cone { .. } => return 0.5 * d,
    };
    let h = h.clamp(0.0, r);
    let chord = 2.0 * (h * (2.0 * r - h)).max(0.0).sqrt();
    let flat = d - 2.0 * r;
    (chord + flat).clamp(1e-3 * d, d)
}

/// a_e, a_p (mm) and their source lines for `op` cut by `cutter`.
///
/// # Errors
/// A message for an operation that does not mill (the hole cycles: a drill's feed is per
/// revolution, not per tooth, and not in the milling library).
fn engagement(op: &Operation, cutter: &Cutter) -> Result<(f64, f64, Vec<Source>), String> {
    let d = cutter.diameter;
    let line = |quantity: &'static str, from: String| Source { quantity, from };
    let finishing = |scallop: f64, what: &str| {
        let ae = scallop_step(cutter, scallop);
        let ap = (0.05 * d).max(1e-3);
        (
            ae,
            ap,
            vec![
                line(
                    "radial depth",
                    format!(
                        "{what}: the step a {scallop} mm scallop gives this tool, a_e = {ae:.3} mm"
                    ),
                ),
                line(
                    "axial depth",
                    format!(
                        "a finishing pass: a_p = 5 % of D = {ap:.3} mm (sets only the removal rate)"
                    ),
                ),
            ],
        )
    };
    let stepped = |fraction: f64, step_down: f64, what: &str| {
        let ae = (fraction * d).clamp(1e-3 * d, d);
        let ap = step_down.max(1e-3);
        (
            ae,
            ap,
            vec![
                line(
                    "radial depth",
                    format!(
                        "{what}: step-over {:.0} % of D = {ae:.3} mm",
                        100.0 * fraction
                    ),
                ),
                line("axial depth", format!("{what}: step-down {ap:.3} mm")),
            ],
        )
    };
    Ok(match op {
        Operation::Finish { options, .. } => finishing(options.scallop, "5-axis finishing"),
        Operation::Raster { scallop_mm, .. } => finishing(*scallop_mm, "raster finishing"),
        Operation::Waterline { scallop_mm, .. } => finishing(*scallop_mm, "waterline"),
        Operation::SteepShallow { scallop_mm, .. } => finishing(*scallop_mm, "steep-and-shallow"),
        Operation::Rest { scallop_mm, .. } => finishing(*scallop_mm, "rest finishing"),
        Operation::Pencil { .. } => {
            let ae = 0.5 * d;
            (
                ae,
                (0.05 * d).max(1e-3),
                vec![line(
                    "radial depth",
                    format!("a pencil pass runs in a corner: a_e = D/2 = {ae:.3} mm"),
                )],
            )
        }
        Operation::Rough {
            step_down_mm,
            step_over_fraction,
            ..
        } => stepped(*step_over_fraction, *step_down_mm, "Z-level roughing"),
        Operation::Face(o) => stepped(o.step_over_fraction, o.step_down_mm, "facing"),
        Operation::Pocket(o) => stepped(o.step_over_fraction, o.step_down_mm, "pocket"),
        Operation::Contour(o) => {
            let ae = 0.25 * d;
            let ap = o.step_down_mm.max(1e-3);
            (
                ae,
                ap,
                vec![
                    line(
                        "radial depth",
                        format!("a profile pass: a_e = 25 % of D = {ae:.3} mm assumed"),
                    ),
                    line("axial depth", format!("contour: step-down {ap:.3} mm")),
                ],
            )
        }
        Operation::Holes(_) => {
            return Err(
                "hole cycles take a drill's feed per revolution, which the milling library \
                 does not give: type the hole operation's feed and spindle speed"
                    .into(),
            );
        }
    })
}

/// The library's speeds for operation `index` of `project` (its tool, the project's material).
///
/// # Errors
/// A message when the project has no work material, the material is not in the library, the
/// operation or its tool does not exist, the operation does not mill, or the case is outside
/// the library's range (a tool over 200 mm, say).
pub fn suggest(project: &Project, index: usize) -> Result<OperationSpeeds, String> {
    let op = project
        .operations
        .get(index)
        .ok_or_else(|| format!("no operation {}", index + 1))?;
    suggest_for(project, op)
}

/// A new operation with the library's speeds written in when the project has a work material
/// and the operation mills; unchanged otherwise.
#[must_use]
pub fn with_library_speeds(project: &Project, op: Operation) -> Operation {
    match suggest_for(project, &op) {
        Ok(s) => apply(op, &s),
        Err(_) => op,
    }
}

/// [`suggest`] for an operation `op` of `project` (its tool an index into the project's tools).
///
/// # Errors
/// As [`suggest`].
pub fn suggest_for(project: &Project, op: &Operation) -> Result<OperationSpeeds, String> {
    let wm = project
        .material
        .as_ref()
        .ok_or("the project has no work material (choose one under Stock)")?;
    let material = wm.material()?;
    let cutter = &project
        .tools
        .get(op.tool())
        .ok_or_else(|| format!("the operation has no tool {}", op.tool() + 1))?
        .cutter;
    let (radial_mm, axial_mm, mut engagement) = engagement(op, cutter)?;
    let (flutes, from) = match &cutter.flutes {
        Some(f) => (f.count, format!("the tool's {} flutes", f.count)),
        None => (
            ASSUMED_FLUTES,
            format!("{ASSUMED_FLUTES} flutes assumed (the tool does not say how many)"),
        ),
    };
    engagement.push(Source {
        quantity: "flutes",
        from,
    });
    let case = Case {
        material,
        tool_material: wm.tool_material,
        diameter_mm: cutter.diameter,
        flutes,
        radial_mm,
        axial_mm,
        max_rpm: None,
    };
    let speeds = cutting_data::recommend(&case).map_err(|e| e.to_string())?;
    Ok(OperationSpeeds {
        speeds,
        radial_mm,
        axial_mm,
        flutes,
        engagement,
    })
}

/// The cutting feed field of `op`, mm/min (`None` for none).
/// The cutting feed `op` programs, mm/min (`None` for a kind without one).
#[must_use]
pub fn cutting_feed(op: &Operation) -> Option<f64> {
    feed_mut(&mut op.clone()).copied()
}

fn feed_mut(op: &mut Operation) -> Option<&mut f64> {
    match op {
        Operation::Finish { options, .. } => Some(&mut options.feed),
        Operation::Raster {
            feed_mm_per_min, ..
        }
        | Operation::Rough {
            feed_mm_per_min, ..
        }
        | Operation::Waterline {
            feed_mm_per_min, ..
        }
        | Operation::SteepShallow {
            feed_mm_per_min, ..
        }
        | Operation::Pencil {
            feed_mm_per_min, ..
        }
        | Operation::Rest {
            feed_mm_per_min, ..
        } => Some(feed_mm_per_min),
        other => other.common_mut().map(|c| &mut c.feed_mm_per_min),
    }
}

/// Round a feed to 1 mm/min and a speed to 1 rpm, as a machinist types them.
fn typed(v: f64) -> f64 {
    v.round().max(1.0)
}

/// `op` with the library's numbers written in: the cutting feed, and where the operation has
/// them (the 2.5D kinds) the spindle speed, the ramp and the plunge feed.
#[must_use]
pub fn apply(mut op: Operation, s: &OperationSpeeds) -> Operation {
    if let Some(feed) = feed_mut(&mut op) {
        *feed = typed(s.speeds.feed_mm_min);
    }
    if let Some(c) = op.common_mut() {
        c.spindle_rpm = Some(typed(s.speeds.spindle_rpm));
        c.ramp_feed_mm_per_min = Some(typed(s.speeds.ramp_feed_mm_min));
        c.plunge_feed_mm_per_min = Some(typed(s.speeds.plunge_feed_mm_min));
    }
    op
}

/// Are `op`'s numbers the library's (as [`apply`] writes them)? `false` when any was typed.
#[must_use]
pub fn follows(op: &Operation, s: &OperationSpeeds) -> bool {
    apply(op.clone(), s) == *op
}

/// Where an operation's feeds and speeds come from, as the setup sheet and `talas job --json`
/// say it.
#[derive(Clone, Debug, PartialEq)]
pub enum SpeedsOrigin {
    /// The cutting-data library's numbers for the project's material, unchanged.
    Library {
        /// The material's full name.
        material: &'static str,
        /// The tools' material (`carbide`, `hss`).
        tool_material: &'static str,
    },
    /// Typed: at least one number differs from the library's.
    Typed {
        /// What the library gives instead (spindle rpm, cutting feed mm/min).
        library_rpm_feed: (f64, f64),
    },
    /// Typed, and the library gives nothing for it (why: no material set, a drilling cycle).
    TypedOnly {
        /// Why the library has no numbers.
        why: String,
    },
}

impl SpeedsOrigin {
    /// Of operation `op` of `project`.
    #[must_use]
    pub fn of(project: &Project, op: &Operation) -> Self {
        match suggest_for(project, op) {
            Ok(s) if follows(op, &s) => Self::Library {
                material: cutting_data::material(s.speeds.material)
                    .map_or(s.speeds.material, |m| m.name),
                tool_material: project
                    .material
                    .as_ref()
                    .map_or("carbide", |m| m.tool_material.name()),
            },
            Ok(s) => Self::Typed {
                library_rpm_feed: (s.speeds.spindle_rpm, s.speeds.feed_mm_min),
            },
            Err(why) => Self::TypedOnly { why },
        }
    }

    /// A short key: `library`, `typed` or `typed_only`.
    #[must_use]
    pub fn key(&self) -> &'static str {
        match self {
            Self::Library { .. } => "library",
            Self::Typed { .. } => "typed",
            Self::TypedOnly { .. } => "typed_only",
        }
    }

    /// One line for a reader, with units.
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            Self::Library {
                material,
                tool_material,
            } => format!("from the cutting data for {material} ({tool_material} tools)"),
            Self::Typed {
                library_rpm_feed: (rpm, feed),
            } => format!("typed (the cutting data give {rpm:.0} rpm, {feed:.0} mm/min)"),
            Self::TypedOnly { why } => format!("typed ({why})"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::project::{OperationKind, ToolEntry};
    use crate::tools::parse_tool_spec;

    fn project(spec: &str, kind: OperationKind) -> Project {
        let mut p = Project {
            material: Some(WorkMaterial {
                key: "6061".into(),
                tool_material: ToolMaterial::Carbide,
            }),
            ..Project::default()
        };
        p.tools = vec![ToolEntry {
            name: "t".into(),
            cutter: parse_tool_spec(spec).expect("spec"),
        }];
        p.operations = vec![Operation::new(kind, 0, 0)];
        p
    }

    #[test]
    fn a_ball_scallop_step_is_the_chord_at_the_scallop_depth() {
        // R = 3, h = 0.01: s = 2·√(h(2R − h)) = 2·√(0.01·5.99) = 0.48949 mm.
        let ball = parse_tool_spec("ball:d=6").expect("ball");
        assert!((scallop_step(&ball, 0.01) - 2.0 * (0.01_f64 * 5.99).sqrt()).abs() < 1e-12);
        // A bull nose adds its flat: D = 10, r = 2, h = 0.02 → 6 + 2·√(0.02·3.98).
        let bull = parse_tool_spec("bull:d=10,r=2").expect("bull");
        let s = 6.0 + 2.0 * (0.02_f64 * 3.98).sqrt();
        assert!((scallop_step(&bull, 0.02) - s).abs() < 1e-12);
    }

    #[test]
    fn a_pocket_gets_the_closed_form_speeds_and_follows_them_until_typed() {
        // 6061, carbide, Ø10 flat, 3 flutes, step-over 40 % (a_e = 4 mm): worked by hand from
        // the library's table, independently of `recommend`'s code path:
        // n = 1000·v_c/(π·D); f_z = table chip load × D/(2√(a_e(D − a_e))) (a_e < D/2);
        // v_f = f_z·z·n.
        let mut p = project("flat:d=10,flutes=3", OperationKind::Pocket);
        if let Operation::Pocket(o) = &mut p.operations[0] {
            o.step_over_fraction = 0.4;
            o.step_down_mm = 2.0;
        }
        let s = suggest(&p, 0).expect("speeds");
        let m = cutting_data::material("6061").expect("6061");
        let n = 1000.0 * m.vc_carbide_m_min / (std::f64::consts::PI * 10.0);
        let fz =
            m.chip_load_mm(10.0, ToolMaterial::Carbide) * 10.0 / (2.0 * (4.0_f64 * 6.0).sqrt());
        assert!((s.speeds.spindle_rpm - n).abs() < 1e-3 * n);
        assert!((s.speeds.feed_mm_min - fz * 3.0 * n).abs() < 1e-3 * fz * 3.0 * n);
        assert_eq!((s.radial_mm, s.axial_mm, s.flutes), (4.0, 2.0, 3));
        assert!(
            s.sources()
                .iter()
                .any(|l| l.from.contains("step-over 40 %"))
        );
        let op = apply(p.operations[0].clone(), &s);
        assert!(follows(&op, &s));
        let c = op.common().expect("common");
        assert_eq!(c.spindle_rpm, Some(n.round()));
        assert_eq!(c.feed_mm_per_min, (fz * 3.0 * n).round());
        // A typed feed no longer follows the library.
        let mut typed = op.clone();
        if let Operation::Pocket(o) = &mut typed {
            o.common.feed_mm_per_min += 10.0;
        }
        assert!(!follows(&typed, &s));
        // Where the numbers come from, as the setup sheet and `talas job --json` say it.
        assert_eq!(
            SpeedsOrigin::of(&p, &op),
            SpeedsOrigin::Library {
                material: "aluminium 6061-T6",
                tool_material: "carbide"
            }
        );
        let SpeedsOrigin::Typed {
            library_rpm_feed: (rpm, feed),
        } = SpeedsOrigin::of(&p, &typed)
        else {
            panic!("typed")
        };
        assert!((rpm - n).abs() < 1e-3 * n && (feed - fz * 3.0 * n).abs() < 1e-3 * feed);
        let mut none = p.clone();
        none.material = None;
        assert_eq!(SpeedsOrigin::of(&none, &op).key(), "typed_only");
    }

    #[test]
    fn a_raster_finish_reads_its_step_from_the_scallop_and_assumes_two_flutes() {
        let p = project("ball:d=6", OperationKind::Raster);
        let s = suggest(&p, 0).expect("speeds");
        let Operation::Raster { scallop_mm, .. } = p.operations[0] else {
            panic!("raster")
        };
        let ae = 2.0 * (scallop_mm * (6.0 - scallop_mm)).sqrt();
        assert!((s.radial_mm - ae).abs() < 1e-12);
        assert_eq!(s.flutes, ASSUMED_FLUTES);
        assert!(s.sources().iter().any(|l| l.from.contains("assumed")));
        let op = apply(p.operations[0].clone(), &s);
        let Operation::Raster {
            feed_mm_per_min, ..
        } = op
        else {
            panic!("raster")
        };
        assert_eq!(feed_mm_per_min, s.speeds.feed_mm_min.round());
    }

    #[test]
    fn what_the_library_cannot_answer_says_why() {
        let mut p = project("ball:d=6", OperationKind::Raster);
        p.material = None;
        assert!(suggest(&p, 0).unwrap_err().contains("no work material"));
        p.material = Some(WorkMaterial {
            key: "unobtainium".into(),
            tool_material: ToolMaterial::Hss,
        });
        let e = suggest(&p, 0).unwrap_err();
        assert!(e.contains("unobtainium") && e.contains("6061"), "{e}");
        let p = project("flat:d=5", OperationKind::Holes);
        assert!(suggest(&p, 0).unwrap_err().contains("hole cycles"));
        assert!(suggest(&p, 3).is_err());
    }
}
