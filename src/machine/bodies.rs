//! The machine's solid bodies and their forward kinematics.
//!
//! A machine file may carry a `structure`: which linear axes move the table (`table_axes`,
//! from the bed upward) and which move the spindle head (`head_axes`), and a list of bodies,
//! each a box or a cylinder given where it is when every axis stands at its physical zero,
//! attached to a link: `bed`, a linear axis letter, the tilt axis (`A`/`B`) or the rotary
//! table (`C`). The tilt and rotary links turn exactly as [`Machine::machine_from_table`]
//! says, so the bodies on `C` move with the part.
//!
//! Physical axis values are the joints with the tool's gauge length added to Z: the joints
//! are the tool tip, and the head bodies are given with the spindle nose (gauge line) centre
//! at the machine origin. A table-side linear axis moves its bodies by −value, a head-side one
//! by +value, so the tip seen from the table is always the joints.

use glam::{DMat3, DVec3};

use super::{Machine, MachineError, MachineJoints};

/// A body's shape as written (mm), in machine coordinates at physical zero.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyFile {
    /// Name used in collision alarms (`cradle`, `spindle nose`).
    pub name: String,
    /// `bed`, or the axis letter that carries the body.
    pub link: String,
    /// A box: its two opposite corners.
    #[serde(default, rename = "box", skip_serializing_if = "Option::is_none")]
    pub box_: Option<[[f64; 3]; 2]>,
    /// A cylinder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cylinder: Option<CylinderFile>,
}

/// A cylinder as written: the centre of its base disc, its axis direction, radius and length.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderFile {
    /// Centre of the base disc, mm.
    pub base: [f64; 3],
    /// Direction from the base to the top (any length).
    pub axis: [f64; 3],
    /// Radius, mm.
    pub radius: f64,
    /// Length along the axis, mm.
    pub length: f64,
}

/// The `structure` section of a machine file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureFile {
    /// Linear axes that move the table, from the bed upward (`"YX"`).
    pub table_axes: String,
    /// Linear axes that move the spindle head, from the bed upward (`"Z"`).
    pub head_axes: String,
    /// The bodies.
    pub bodies: Vec<BodyFile>,
    /// Pairs of body names never checked against each other (parts that touch by design).
    #[serde(default)]
    pub ignore_pairs: Vec<[String; 2]>,
}

/// A primitive solid (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// Axis-aligned box (in its link's frame).
    Box {
        /// Lower corner.
        min: DVec3,
        /// Upper corner.
        max: DVec3,
    },
    /// Cylinder.
    Cylinder {
        /// Centre of the base disc.
        base: DVec3,
        /// Unit axis from the base to the top.
        axis: DVec3,
        /// Radius.
        radius: f64,
        /// Length.
        length: f64,
    },
}

/// Which part of the machine carries a body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Link {
    /// The fixed bed.
    Bed,
    /// A linear axis (X, Y or Z).
    Linear(char),
    /// The tilt axis (trunnion cradle).
    Tilt,
    /// The rotary table (table coordinates).
    Rotary,
}

/// Which side of the machine a link is on (bodies on different sides may collide).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The bed and what stands on it.
    Bed,
    /// What carries the part.
    Table,
    /// What carries the tool.
    Head,
}

/// A validated body.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name.
    pub name: String,
    /// Carrier.
    pub link: Link,
    /// Shape at physical zero.
    pub shape: Shape,
}

/// A validated structure.
#[derive(Clone, Debug, PartialEq)]
pub struct Structure {
    /// Table-side linear axes, bed upward.
    pub table_axes: Vec<char>,
    /// Head-side linear axes, bed upward.
    pub head_axes: Vec<char>,
    /// The bodies.
    pub bodies: Vec<Body>,
    /// Body-name pairs not checked.
    pub ignore_pairs: Vec<[String; 2]>,
}

/// A rigid placement: `p_world = rotation · p_link + translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Rotation.
    pub rotation: DMat3,
    /// Translation, mm.
    pub translation: DVec3,
}

impl Placement {
    /// No motion.
    pub const IDENTITY: Self = Self {
        rotation: DMat3::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// A pure translation.
    #[must_use]
    pub fn shift(t: DVec3) -> Self {
        Self {
            rotation: DMat3::IDENTITY,
            translation: t,
        }
    }

    /// `self ∘ other` (apply `other` first).
    #[must_use]
    pub fn then_inner(&self, other: &Self) -> Self {
        Self {
            rotation: self.rotation * other.rotation,
            translation: self.rotation * other.translation + self.translation,
        }
    }

    /// Map a point.
    #[must_use]
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation
    }
}

/// A triangle mesh of a body (mm): vertices and counter-clockwise triangles seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BodyMesh {
    /// Vertices.
    pub vertices: Vec<DVec3>,
    /// Triangles (vertex indices).
    pub triangles: Vec<[u32; 3]>,
}

impl Shape {
    /// A closed triangle mesh (cylinders with `segments` sides, at least 3).
    #[must_use]
    pub fn mesh(&self, segments: usize) -> BodyMesh {
        match *self {
            Shape::Box { min, max } => box_mesh(min, max),
            Shape::Cylinder {
                base,
                axis,
                radius,
                length,
            } => cylinder_mesh(base, axis, radius, length, segments.max(3)),
        }
    }
}

fn box_mesh(min: DVec3, max: DVec3) -> BodyMesh {
    let corner = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1], // −Z
        [4, 5, 7, 6], // +Z
        [0, 1, 5, 4], // −Y
        [2, 6, 7, 3], // +Y
        [0, 4, 6, 2], // −X
        [1, 3, 7, 5], // +X
    ];
    let mut triangles = Vec::with_capacity(12);
    for q in quads {
        triangles.push([q[0], q[1], q[2]]);
        triangles.push([q[0], q[2], q[3]]);
    }
    BodyMesh {
        vertices: (0..8).map(corner).collect(),
        triangles,
    }
}

fn cylinder_mesh(base: DVec3, axis: DVec3, radius: f64, length: f64, n: usize) -> BodyMesh {
    let (u, v) = axis.any_orthonormal_pair();
    let top = base + axis * length;
    let mut vertices = vec![base, top];
    for i in 0..n {
        let t = std::f64::consts::TAU * i as f64 / n as f64;
        let r = (u * t.cos() + v * t.sin()) * radius;
        vertices.push(base + r);
        vertices.push(top + r);
    }
    let mut triangles = Vec::with_capacity(4 * n);
    let idx = |i: usize| u32::try_from(i).unwrap_or(u32::MAX);
    for i in 0..n {
        let (b0, t0) = (2 + 2 * i, 3 + 2 * i);
        let (b1, t1) = (2 + 2 * ((i + 1) % n), 3 + 2 * ((i + 1) % n));
        triangles.push([idx(0), idx(b1), idx(b0)]);
        triangles.push([idx(1), idx(t0), idx(t1)]);
        triangles.push([idx(b0), idx(b1), idx(t1)]);
        triangles.push([idx(b0), idx(t1), idx(t0)]);
    }
    BodyMesh {
        vertices,
        triangles,
    }
}

fn parse_axes(text: &str, what: &str, machine: &Machine) -> Result<Vec<char>, String> {
    let mut out = Vec::new();
    for c in text.chars().filter(|c| !c.is_whitespace()) {
        let c = c.to_ascii_uppercase();
        if !matches!(c, 'X' | 'Y' | 'Z') || machine.axis(c).is_none() {
            return Err(format!("{what}: {c:?} is not a linear axis of the machine"));
        }
        out.push(c);
    }
    Ok(out)
}

fn finite3(v: [f64; 3], what: &str) -> Result<DVec3, String> {
    let d = DVec3::from_array(v);
    if d.is_finite() && d.abs().max_element() <= 1e6 {
        Ok(d)
    } else {
        Err(format!("{what} must be finite and within ±1e6 mm"))
    }
}

impl BodyFile {
    fn validate(&self, structure: &Structure, machine: &Machine) -> Result<Body, String> {
        let l = self.link.trim();
        let link = if l.eq_ignore_ascii_case("bed") {
            Link::Bed
        } else {
            let mut it = l.chars();
            let (Some(c), None) = (it.next(), it.next()) else {
                return Err(format!("link {l:?} is neither \"bed\" nor an axis letter"));
            };
            let c = c.to_ascii_uppercase();
            match machine.rotary_names() {
                Some((t, _)) if c == t => Link::Tilt,
                Some((_, r)) if c == r => Link::Rotary,
                _ if structure.table_axes.contains(&c) || structure.head_axes.contains(&c) => {
                    Link::Linear(c)
                }
                _ => return Err(format!("link {l:?} is not an axis of the machine")),
            }
        };
        let shape = match (&self.box_, &self.cylinder) {
            (Some([a, b]), None) => {
                let (a, b) = (finite3(*a, "box corner")?, finite3(*b, "box corner")?);
                let (min, max) = (a.min(b), a.max(b));
                if (max - min).min_element() <= 0.0 {
                    return Err("box has a zero extent".into());
                }
                Shape::Box { min, max }
            }
            (None, Some(c)) => {
                let base = finite3(c.base, "cylinder base")?;
                let axis = finite3(c.axis, "cylinder axis")?
                    .try_normalize()
                    .ok_or("cylinder axis is zero")?;
                let ok = |v: f64| v.is_finite() && v > 0.0 && v <= 1e6;
                if !ok(c.radius) || !ok(c.length) {
                    return Err(format!(
                        "cylinder radius {} mm and length {} mm must be in (0, 1e6]",
                        c.radius, c.length
                    ));
                }
                Shape::Cylinder {
                    base,
                    axis,
                    radius: c.radius,
                    length: c.length,
                }
            }
            _ => return Err("needs exactly one of \"box\" and \"cylinder\"".into()),
        };
        Ok(Body {
            name: self.name.clone(),
            link,
            shape,
        })
    }
}

impl StructureFile {
    /// Check the structure against the machine's axes.
    ///
    /// # Errors
    /// A message naming the body (index and name) or the axis list at fault.
    pub fn validate(&self, machine: &Machine) -> Result<Structure, String> {
        let mut s = Structure {
            table_axes: parse_axes(&self.table_axes, "table_axes", machine)?,
            head_axes: parse_axes(&self.head_axes, "head_axes", machine)?,
            bodies: Vec::new(),
            ignore_pairs: self.ignore_pairs.clone(),
        };
        for c in ['X', 'Y', 'Z'] {
            let n = s.table_axes.iter().chain(&s.head_axes).filter(|&&a| a == c);
            if n.count() != 1 {
                return Err(format!(
                    "axis {c} must be in exactly one of table_axes and head_axes"
                ));
            }
        }
        for (i, b) in self.bodies.iter().enumerate() {
            let body = b
                .validate(&s, machine)
                .map_err(|m| format!("body {} ({:?}): {m}", i + 1, b.name))?;
            s.bodies.push(body);
        }
        for [a, b] in &s.ignore_pairs {
            for n in [a, b] {
                if !s.bodies.iter().any(|x| &x.name == n) {
                    return Err(format!("ignore_pairs names no body {n:?}"));
                }
            }
        }
        Ok(s)
    }
}

impl Structure {
    /// The side a link is on.
    #[must_use]
    pub fn side(&self, link: Link) -> Side {
        match link {
            Link::Bed => Side::Bed,
            Link::Tilt | Link::Rotary => Side::Table,
            Link::Linear(c) if self.head_axes.contains(&c) => Side::Head,
            Link::Linear(_) => Side::Table,
        }
    }

    /// Whether the pair is listed as never checked.
    #[must_use]
    pub fn ignored(&self, a: &str, b: &str) -> bool {
        self.ignore_pairs
            .iter()
            .any(|[x, y]| (x == a && y == b) || (x == b && y == a))
    }
}

/// Where every link is at some joints: forward kinematics of the bodies.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkPlacements {
    table_linear: Vec<(char, Placement)>,
    head_linear: Vec<(char, Placement)>,
    /// The cradle (tilt link).
    pub tilt: Placement,
    /// The part (table coordinates): the rotary table, else the last table-side link.
    pub table: Placement,
    /// The tool tip frame (tip at the origin, tool axis +Z).
    pub tool: Placement,
}

impl LinkPlacements {
    /// The placement of a link.
    #[must_use]
    pub fn of(&self, link: Link) -> Placement {
        let find = |v: &[(char, Placement)], c: char| {
            v.iter()
                .find(|(a, _)| *a == c)
                .map(|(_, p)| *p)
                .unwrap_or(Placement::IDENTITY)
        };
        match link {
            Link::Bed => Placement::IDENTITY,
            Link::Tilt => self.tilt,
            Link::Rotary => self.table,
            Link::Linear(c) if self.head_linear.iter().any(|(a, _)| *a == c) => {
                find(&self.head_linear, c)
            }
            Link::Linear(c) => find(&self.table_linear, c),
        }
    }
}

impl Machine {
    /// Forward kinematics of the links at `joints` with a tool of gauge length `gauge_mm`
    /// (tip to spindle nose). `None` when the machine has no structure.
    #[must_use]
    pub fn link_placements(&self, joints: &MachineJoints, gauge_mm: f64) -> Option<LinkPlacements> {
        let s = self.structure.as_ref()?;
        let phys = |c: char| match c {
            'X' => joints.xyz.x,
            'Y' => joints.xyz.y,
            _ => joints.xyz.z + gauge_mm,
        };
        let unit = |c: char| match c {
            'X' => DVec3::X,
            'Y' => DVec3::Y,
            _ => DVec3::Z,
        };
        let mut acc = DVec3::ZERO;
        let mut table_linear = Vec::new();
        for &c in &s.table_axes {
            acc -= unit(c) * phys(c);
            table_linear.push((c, Placement::shift(acc)));
        }
        let carrier = Placement::shift(acc);
        let mut acc = DVec3::ZERO;
        let mut head_linear = Vec::new();
        for &c in &s.head_axes {
            acc += unit(c) * phys(c);
            head_linear.push((c, Placement::shift(acc)));
        }
        let tool = Placement::shift(acc - DVec3::Z * gauge_mm);
        let (tilt, table) = if self.rotary_names().is_some() {
            let (r, t) = self.machine_from_table(joints);
            let only_tilt = MachineJoints {
                rotary_rad: 0.0,
                ..*joints
            };
            let (rt, tt) = self.machine_from_table(&only_tilt);
            (
                carrier.then_inner(&Placement {
                    rotation: rt,
                    translation: tt,
                }),
                carrier.then_inner(&Placement {
                    rotation: r,
                    translation: t,
                }),
            )
        } else {
            (carrier, carrier)
        };
        Some(LinkPlacements {
            table_linear,
            head_linear,
            tilt,
            table,
            tool,
        })
    }
}

/// Validation errors of the structure as machine errors.
pub(super) fn structure_error(machine: &str, m: &str) -> MachineError {
    MachineError::Invalid(format!("{machine}: structure: {m}"))
}
