//! Output of the electrode-centre path: G-code with G1 and G2/G3 (arcs kept) in the text of a
//! post dialect, in the plane G17, G18 or G19, and a tool path of poses for the simulation.
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
use crate::post::Dialect;
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
        }
    }
}

struct Blocks<'a> {
    d: &'a Dialect,
    lines: Vec<String>,
    number: u64,
    last: [Option<String>; 3],
    last_motion: Option<String>,
    last_feed: Option<String>,
}

impl Blocks<'_> {
    fn fill(&self, t: &str, o: &GcodeOptions) -> String {
        t.replace("{program}", &o.program_name)
            .replace("{machine}", "any")
            .replace("{dialect}", &self.d.name)
            .replace("{tool_spec}", &format!("ball:d={}", 2.0 * o.radius_mm))
            .replace("{tool}", &o.tool_number.to_string())
            .replace("{rpm}", "0")
            .replace("{work_offset}", "G54")
    }

    fn block(&mut self, body: &str) {
        if let Some(raw) = body.strip_prefix('!') {
            self.lines.push(raw.to_string());
            return;
        }
        if self.d.line_numbers {
            let n = self.number;
            self.number += u64::from(self.d.line_number_step);
            self.lines.push(format!("N{n} {body}{}", self.d.block_end));
        } else {
            self.lines.push(format!("{body}{}", self.d.block_end));
        }
    }

    fn comment(&mut self, text: &str) {
        let clean: String = text
            .chars()
            .map(|c| {
                if matches!(c, '(' | ')' | '\n' | '\r' | ';') {
                    ' '
                } else {
                    c
                }
            })
            .collect();
        let line = format!("{}{}{}", self.d.comment_open, clean, self.d.comment_close);
        self.lines.push(line);
    }

    fn num(&self, v: f64) -> String {
        self.d.number(v, self.d.decimals_linear)
    }

    /// A motion block: the code when it changes, the axis words that change, `extra` words
    /// and the feed when it changes.
    fn motion(&mut self, code: &str, p: DVec3, extra: &[String], feed: Option<f64>) {
        let mut words = Vec::new();
        if self.last_motion.as_deref() != Some(code) {
            words.push(code.to_string());
            self.last_motion = Some(code.to_string());
        }
        let mut moved = false;
        for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            let v = self.num(p.to_array().get(i).copied().unwrap_or(0.0));
            if let Some(slot) = self.last.get_mut(i)
                && slot.as_deref() != Some(v.as_str())
            {
                words.push(format!("{l}{v}"));
                *slot = Some(v);
                moved = true;
            }
        }
        if !moved && extra.is_empty() {
            if words.len() == 1 {
                // Only a modal code and no motion: leave it for the next block.
                self.last_motion = None;
            }
            return;
        }
        words.extend(extra.iter().cloned());
        if let Some(f) = feed {
            let f = self.d.number(f, self.d.decimals_feed);
            if self.last_feed.as_deref() != Some(f.as_str()) {
                words.push(format!("F{f}"));
                self.last_feed = Some(f);
            }
        }
        self.block(&words.join(" "));
    }
}

/// The G-code of the centre path in `dialect`'s text (deterministic: the same input gives the
/// same bytes).
#[must_use]
pub fn write_gcode(paths: &[ClPath], dialect: &Dialect, o: &GcodeOptions) -> String {
    let mut b = Blocks {
        d: dialect,
        lines: Vec::new(),
        number: u64::from(dialect.line_number_start),
        last: Default::default(),
        last_motion: None,
        last_feed: None,
    };
    for t in &dialect.header {
        let s = b.fill(t, o);
        b.block(&s);
    }
    for t in &dialect.header_comments {
        let s = b.fill(t, o);
        b.comment(&s);
    }
    b.comment(&format!(
        "BALL ELECTRODE R{} MM, CENTRE PATH, {} PIECE(S), PLANE {}",
        b.num(o.radius_mm),
        paths.len(),
        o.plane.code()
    ));
    let mut plane_written = false;
    for t in &dialect.setup {
        let mut s = b.fill(t, o);
        if s.contains("G17") {
            s = s.replace("G17", o.plane.code());
            plane_written = true;
        }
        b.block(&s);
    }
    if !plane_written {
        b.block(o.plane.code());
    }
    for t in &dialect.tool_change {
        let s = b.fill(t, o);
        b.block(&s);
    }
    let arc_codes = if dialect.linear.len() > 2 {
        ("G02", "G03")
    } else {
        ("G2", "G3")
    };
    for path in paths {
        piece(&mut b, path, o, arc_codes);
    }
    for t in dialect.footer.iter().chain(&dialect.trailer) {
        let s = b.fill(t, o);
        b.block(&s);
    }
    let mut s = b.lines.join("\n");
    s.push('\n');
    s
}

fn piece(b: &mut Blocks<'_>, path: &ClPath, o: &GcodeOptions, arc_codes: (&str, &str)) {
    let Some(first) = path.vertices.first() else {
        return;
    };
    let rapid = b.d.rapid.clone();
    let linear = b.d.linear.clone();
    let start = o.plane.to_machine(first.centre, o.fixed_mm);
    let cur = b.last.clone();
    let clear = |p: DVec3| DVec3::new(p.x, p.y, o.clearance_z_mm);
    // Up to the clearance where we are, across at the clearance, down at the feed.
    if cur.iter().any(Option::is_some) {
        let here = DVec3::from_array(std::array::from_fn(|i| {
            cur.get(i)
                .and_then(|s| s.as_deref())
                .and_then(|s| s.parse().ok())
                .unwrap_or(0.0)
        }));
        b.motion(&rapid, clear(here), &[], None);
    } else {
        b.motion(&rapid, DVec3::new(0.0, 0.0, o.clearance_z_mm), &[], None);
    }
    b.motion(&rapid, clear(start), &[], None);
    b.motion(&linear, start, &[], Some(o.feed_mm_per_min));
    for e in path.elements() {
        let end = o.plane.to_machine(e.end(), o.fixed_mm);
        match e {
            Element::Line { .. } => b.motion(&linear, end, &[], Some(o.feed_mm_per_min)),
            Element::Arc {
                a,
                centre,
                sweep_rad,
                ..
            } => {
                let ccw = (sweep_rad > 0.0) == o.plane.keeps_sense();
                let code = if ccw { arc_codes.1 } else { arc_codes.0 };
                let off = o.plane.to_machine(centre - a, 0.0);
                let (iu, iv, _) = o.plane.plane().axes();
                let letters = ['I', 'J', 'K'];
                let arr = off.to_array();
                let mut words = Vec::new();
                let mut idx = [iu, iv];
                idx.sort_unstable();
                for i in idx {
                    let (Some(l), Some(v)) = (letters.get(i), arr.get(i)) else {
                        continue;
                    };
                    words.push(format!("{l}{}", b.num(*v)));
                }
                // An arc block always carries its end point, so the axis words are reset.
                b.last = Default::default();
                b.last_motion = None;
                b.motion(code, end, &words, Some(o.feed_mm_per_min));
            }
        }
    }
    let end = b.last.clone();
    let here = DVec3::from_array(std::array::from_fn(|i| {
        end.get(i)
            .and_then(|s| s.as_deref())
            .and_then(|s| s.parse().ok())
            .unwrap_or(0.0)
    }));
    b.motion(&rapid, clear(here), &[], None);
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
