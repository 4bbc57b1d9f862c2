//! Output of the electrode-centre path: G-code with G1 and G2/G3 (arcs kept) through the one
//! post ([`crate::post`]) in any of its dialects, in the plane G17, G18 or G19, and a tool path
//! of poses for the simulation.
//!
//! Plane mapping (profile x, y → machine axes): G17 x→X, y→Y with the depth on Z; G18 x→X,
//! y→Z (the profile's y is the vertical axis, as for a sinker electrode) with Y fixed; G19
//! x→Y, y→Z with X fixed. Arc centres are incremental I, J, K from the arc's start. Each
//! piece of the path is entered from the clearance height in Z and left back to it.

use glam::{DVec2, DVec3};

use crate::gcode::Plane;
use crate::geometry::planar::ClPath;
use crate::geometry::planar::{Element, closest_on};
use crate::geometry::planar::{Profile, ProfileError};
use crate::machine::Machine;
use crate::post::{Dialect, PostOptions};
use crate::toolpath::{ContactKind, MoveKind, Pose, ToolRecord, Toolpath};

/// The machine plane of the profile.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfilePlane {
    /// XY (profile y on Y, depth on Z).
    G17,
    /// ZX (profile x on X, y on Z).
    #[default]
    G18,
    /// YZ (profile x on Y, y on Z).
    G19,
}

impl ProfilePlane {
    /// The plane word.
    #[must_use]
    pub fn code(self) -> &'static str {
        match self {
            Self::G17 => "G17",
            Self::G18 => "G18",
            Self::G19 => "G19",
        }
    }

    /// The interpreter's plane.
    #[must_use]
    pub fn plane(self) -> Plane {
        match self {
            Self::G17 => Plane::Xy,
            Self::G18 => Plane::Zx,
            Self::G19 => Plane::Yz,
        }
    }

    /// Machine point of profile point `p` with the fixed axis at `fixed`.
    #[must_use]
    pub fn to_machine(self, p: DVec2, fixed: f64) -> DVec3 {
        match self {
            Self::G17 => DVec3::new(p.x, p.y, fixed),
            Self::G18 => DVec3::new(p.x, fixed, p.y),
            Self::G19 => DVec3::new(fixed, p.x, p.y),
        }
    }

    /// True when a counter-clockwise turn in the profile's (x, y) is counter-clockwise about
    /// the plane's normal (G3); false when the mapping mirrors it (G18: X × Z = −Y).
    #[must_use]
    pub fn keeps_sense(self) -> bool {
        let ex = self.to_machine(DVec2::X, 0.0);
        let ey = self.to_machine(DVec2::Y, 0.0);
        ex.cross(ey).dot(self.plane().normal()) > 0.0
    }
}

/// Settings of [`write_gcode`] and [`to_toolpath`].
#[derive(Clone, Debug, PartialEq)]
pub struct GcodeOptions {
    /// Machine plane.
    pub plane: ProfilePlane,
    /// Value of the axis normal to the plane, mm.
    pub fixed_mm: f64,
    /// Machine Z of the retract between pieces, mm.
    pub clearance_z_mm: f64,
    /// Feed of the path, mm/min.
    pub feed_mm_per_min: f64,
    /// Program name for the header.
    pub program_name: String,
    /// Electrode (tool) number.
    pub tool_number: u32,
    /// Electrode radius, mm (for the comment and the tool record).
    pub radius_mm: f64,
    /// Chord tolerance of an arc the dialect cannot write as G2/G3 (its plane, radius or a
    /// sweep too long for R), mm.
    pub tolerance_mm: f64,
}

impl Default for GcodeOptions {
    fn default() -> Self {
        Self {
            plane: ProfilePlane::G18,
            fixed_mm: 0.0,
            clearance_z_mm: 50.0,
            feed_mm_per_min: 100.0,
            program_name: "PROFILE".into(),
            tool_number: 1,
            radius_mm: 1.0,
            tolerance_mm: 1e-3,
        }
    }
}

/// The G-code of the centre path through the one post ([`crate::post`]) in `dialect`
/// (deterministic: the same input gives the same bytes): the post's header, setup (its `G17`
/// replaced by the profile's plane), tool change, number format and line numbers; the arcs
/// as G2/G3 where the dialect writes arcs in that plane, else as lines within
/// [`GcodeOptions::tolerance_mm`].
///
/// # Errors
/// [`ProfileError`] for a radius, feed or tolerance that is not positive, a program name the
/// post refuses, or a path the post cannot write.
pub fn write_gcode(
    paths: &[ClPath],
    dialect: &Dialect,
    o: &GcodeOptions,
) -> Result<String, ProfileError> {
    let toolpath = centre_toolpath(paths, o)?;
    let mut machine = Machine::builtin("mill-3axis")
        .map_err(|e| ProfileError::new("<memory>", "machine", e.to_string()))?;
    // The program is for no machine in particular (its header says so).
    machine.name = "any".into();
    let number = |v: f64| dialect.number(v, dialect.decimals_linear);
    let options = PostOptions {
        tcp: false,
        tolerance_mm: o.tolerance_mm,
        program_name: o.program_name.clone(),
        tool_number: o.tool_number,
        spindle_rpm: 0.0,
        coolant: false,
        clearance_z_mm: o.clearance_z_mm,
        comments: vec![format!(
            "BALL ELECTRODE R{} MM, CENTRE PATH, {} PIECE(S), PLANE {}",
            number(o.radius_mm),
            paths.len(),
            o.plane.code()
        )],
        setup_plane: Some(o.plane.plane()),
        ..PostOptions::default()
    };
    crate::post::post(&toolpath, &machine, dialect, &options)
        .map_err(|e| ProfileError::new("<memory>", "G-code", e.to_string()))
}

/// The centre path as the tool path the post writes: the programmed point is the electrode's
/// centre (in the plane's machine axes, the normal axis at [`GcodeOptions::fixed_mm`]); each
/// piece is entered by a rapid to the clearance height in Z above its start and a feed down,
/// and left by a rapid back up; arcs are exact moves ([`Toolpath::push_arc`], sampled within
/// [`GcodeOptions::tolerance_mm`]).
///
/// # Errors
/// [`ProfileError`] for a radius, feed or tolerance that is not positive.
pub fn centre_toolpath(paths: &[ClPath], o: &GcodeOptions) -> Result<Toolpath, ProfileError> {
    let bad = |place: &str, m: String| ProfileError::new("<memory>", place, m);
    if !(o.feed_mm_per_min > 0.0 && o.feed_mm_per_min.is_finite()) {
        return Err(bad(
            "feed",
            format!("{} mm/min must be positive", o.feed_mm_per_min),
        ));
    }
    if !(o.tolerance_mm > 0.0 && o.tolerance_mm.is_finite()) {
        return Err(bad(
            "tolerance",
            format!("{} mm must be positive", o.tolerance_mm),
        ));
    }
    let cutter = crate::tools::Cutter::new(crate::tools::CutterKind::Ball, 2.0 * o.radius_mm)
        .map_err(|e| bad("radius", e.to_string()))?;
    let tool = ToolRecord {
        spec: format!("ball:d={}", 2.0 * o.radius_mm),
        cutter,
    };
    let mut tp = Toolpath::new(tool, Vec::new());
    let f = o.feed_mm_per_min;
    let to_machine = |p: DVec2| o.plane.to_machine(p, o.fixed_mm);
    let clear = |p: DVec3| DVec3::new(p.x, p.y, o.clearance_z_mm);
    // The arcs' normal: profile x × profile y in the machine (−Y in G18).
    let normal = o
        .plane
        .to_machine(DVec2::X, 0.0)
        .cross(o.plane.to_machine(DVec2::Y, 0.0));
    for path in paths {
        let Some(first) = path.vertices.first() else {
            continue;
        };
        let start = to_machine(first.centre);
        tp.poses
            .push(Pose::new(MoveKind::Rapid, clear(start), DVec3::Z, 0.0));
        tp.poses
            .push(Pose::new(MoveKind::Plunge, start, DVec3::Z, f));
        for e in path.elements() {
            match e {
                Element::Line { b, .. } => {
                    tp.poses
                        .push(Pose::new(MoveKind::Cut, to_machine(b), DVec3::Z, f));
                }
                Element::Arc {
                    centre, sweep_rad, ..
                } => tp
                    .push_arc(
                        to_machine(centre),
                        normal,
                        sweep_rad,
                        MoveKind::Cut,
                        f,
                        o.tolerance_mm,
                    )
                    .map_err(|e| bad("arc", e.message))?,
            }
        }
        if let Some(last) = tp.poses.last().copied() {
            tp.poses
                .push(Pose::new(MoveKind::Rapid, clear(last.tip), DVec3::Z, 0.0));
        }
    }
    tp.resummarise();
    Ok(tp)
}

/// The centre path as a tool path: the tip is the electrode's lowest point along machine Z,
/// the contact point is the profile point it touches; arcs become chords within
/// `chord_tol_mm`; pieces are joined by rapids at the clearance height.
///
/// # Errors
/// [`ProfileError`] for a radius or feed that is not positive.
pub fn to_toolpath(
    profile: &Profile,
    paths: &[ClPath],
    o: &GcodeOptions,
    chord_tol_mm: f64,
) -> Result<Toolpath, ProfileError> {
    let r = o.radius_mm;
    if !(o.feed_mm_per_min > 0.0 && o.feed_mm_per_min.is_finite()) {
        return Err(ProfileError::new(
            "<memory>",
            "feed",
            format!("{} mm/min must be positive", o.feed_mm_per_min),
        ));
    }
    let cutter = crate::tools::Cutter::new(crate::tools::CutterKind::Ball, 2.0 * r)
        .map_err(|e| ProfileError::new("<memory>", "radius", e.to_string()))?;
    let profile_elements = profile.elements();
    let tip_of = |c: DVec2| o.plane.to_machine(c, o.fixed_mm) - DVec3::Z * r;
    let mut poses = Vec::new();
    let elements_of = |p: &ClPath| p.elements();
    for path in paths {
        let els = elements_of(path);
        let Some(first) = path.vertices.first() else {
            continue;
        };
        let start = tip_of(first.centre);
        poses.push(Pose::new(
            MoveKind::Rapid,
            DVec3::new(start.x, start.y, o.clearance_z_mm),
            DVec3::Z,
            0.0,
        ));
        let cc0 = o.plane.to_machine(first.contact, o.fixed_mm);
        poses.push(
            Pose::new(MoveKind::Plunge, start, DVec3::Z, o.feed_mm_per_min)
                .with_contact(cc0, ContactKind::Ball),
        );
        for (k, e) in els.iter().enumerate() {
            let steps = match *e {
                Element::Line { .. } => 1,
                Element::Arc {
                    radius, sweep_rad, ..
                } => {
                    let tol = chord_tol_mm.clamp(1e-9, radius);
                    let step = 2.0 * (1.0 - tol / radius).clamp(-1.0, 1.0).acos();
                    ((sweep_rad.abs() / step.max(1e-6)).ceil() as usize).clamp(1, 100_000)
                }
            };
            let next = path.vertices.get((k + 1) % path.vertices.len());
            for s in 1..=steps {
                let t = s as f64 / steps as f64;
                let c = e.point_at(t);
                let contact = if s == steps {
                    next.map_or(c, |v| v.contact)
                } else {
                    closest_on(&profile_elements, c).map_or(c, |q| q.2)
                };
                let cc = o.plane.to_machine(contact, o.fixed_mm);
                poses.push(
                    Pose::new(MoveKind::Cut, tip_of(c), DVec3::Z, o.feed_mm_per_min)
                        .with_contact(cc, ContactKind::Ball),
                );
            }
        }
        if let Some(last) = poses.last().copied() {
            poses.push(Pose::new(
                MoveKind::Rapid,
                DVec3::new(last.tip.x, last.tip.y, o.clearance_z_mm),
                DVec3::Z,
                0.0,
            ));
        }
    }
    let tool = ToolRecord {
        spec: format!("ball:d={}", 2.0 * r),
        cutter,
    };
    Ok(Toolpath::new(tool, poses))
}
