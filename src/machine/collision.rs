//! Collisions between the machine's bodies, the tool in the spindle and what sits on the table
//! (stock, fixture), with parry3d's exact primitive intersection tests.
//!
//! Pairs checked: every body carried by the head (head-side links and the tool's cylinders)
//! against every body of the bed, the table side and the table extras, except the pairs the
//! machine file lists in `ignore_pairs` and the tool against extras marked as cut by the tool
//! (the stock, whose contact with the tool is the material simulation's business). Bodies on
//! the same side never collide with each other by construction.

use glam::DVec3;
use parry3d_f64::math::{Pose, Rot3};
use parry3d_f64::query::intersection_test;
use parry3d_f64::shape::{Cuboid, Cylinder, Shape as ParryShape, TriMesh as ParryTriMesh};

use super::bodies::{BodyMesh, Link, LinkPlacements, Placement, Shape, Side};
use super::{Machine, MachineJoints};

/// One cylinder of the tool assembly, coaxial with the tool, heights from the tip (mm).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolCylinder {
    /// Name in alarms (`tool`, `holder`).
    pub name: String,
    /// Radius, mm.
    pub radius: f64,
    /// Bottom height above the tip, mm.
    pub bottom: f64,
    /// Top height above the tip, mm.
    pub top: f64,
}

/// A solid on the table (in table coordinates, which move with the rotary table).
#[derive(Clone, Debug, PartialEq)]
pub struct TableExtra {
    /// Name in alarms (`stock`, `fixture`, `vise`).
    pub name: String,
    /// Shape in table coordinates.
    pub shape: TableShape,
    /// The tool cuts it: tool against it is not checked here.
    pub cut_by_tool: bool,
}

/// The shape of a table extra: a primitive, or a closed triangle mesh (a setup's workholding:
/// a vise's jaws, a plate, a body from a file), tested as parry's triangle mesh (surface
/// contact: a body wholly inside the mesh is not seen, it passed the surface earlier).
#[derive(Clone, Debug, PartialEq)]
pub enum TableShape {
    /// A box or a cylinder.
    Solid(Shape),
    /// A closed triangle mesh, table coordinates.
    Mesh(std::sync::Arc<BodyMesh>),
}

impl From<Shape> for TableShape {
    fn from(s: Shape) -> Self {
        Self::Solid(s)
    }
}

impl TableShape {
    /// A closed triangle mesh of the shape (cylinders with `segments` sides).
    #[must_use]
    pub fn mesh(&self, segments: usize) -> BodyMesh {
        match self {
            Self::Solid(s) => s.mesh(segments),
            Self::Mesh(m) => BodyMesh::clone(m),
        }
    }
}

impl TableExtra {
    /// A mesh named `name` (never cut by the tool: workholding); `None` for a mesh parry
    /// cannot take (no triangles, an index out of range, a coordinate not finite).
    #[must_use]
    pub fn mesh(name: &str, mesh: BodyMesh) -> Option<Self> {
        let n = mesh.vertices.len();
        let ok = !mesh.triangles.is_empty()
            && mesh.vertices.iter().all(|v| v.is_finite())
            && mesh.triangles.iter().flatten().all(|&i| (i as usize) < n);
        ok.then(|| Self {
            name: name.to_string(),
            shape: TableShape::Mesh(std::sync::Arc::new(mesh)),
            cut_by_tool: false,
        })
    }
}

/// Where an entry hangs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Carrier {
    Link(Link),
    Tool,
}

struct Entry {
    name: String,
    carrier: Carrier,
    local: Placement,
    shape: Box<dyn ParryShape>,
}

/// Two bodies in contact.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// The moving (head-side) body first, then the other.
    pub bodies: [String; 2],
}

/// The machine's bodies, the tool and the table extras ready for intersection tests.
pub struct CollisionModel {
    entries: Vec<Entry>,
    pairs: Vec<(usize, usize)>,
    gauge_mm: f64,
    has_mesh: bool,
}

/// Largest linear step between two tests along a motion when the table carries a mesh (the
/// step planning and the job's simulation test workholding at), mm.
pub const MESH_SAMPLE_MM: f64 = 0.25;

impl std::fmt::Debug for CollisionModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionModel")
            .field("entries", &self.entries.len())
            .field("pairs", &self.pairs.len())
            .field("gauge_mm", &self.gauge_mm)
            .field("has_mesh", &self.has_mesh)
            .finish()
    }
}

fn table_shape(shape: &TableShape) -> Option<(Placement, Box<dyn ParryShape>)> {
    match shape {
        TableShape::Solid(s) => Some(primitive(s)),
        TableShape::Mesh(m) => {
            let mesh = ParryTriMesh::new(m.vertices.clone(), m.triangles.clone()).ok()?;
            Some((Placement::IDENTITY, Box::new(mesh)))
        }
    }
}

fn primitive(shape: &Shape) -> (Placement, Box<dyn ParryShape>) {
    match *shape {
        Shape::Box { min, max } => (
            Placement::shift((min + max) * 0.5),
            Box::new(Cuboid::new((max - min) * 0.5)),
        ),
        Shape::Cylinder {
            base,
            axis,
            radius,
            length,
        } => {
            let q = glam::DQuat::from_rotation_arc(DVec3::Y, axis);
            (
                Placement {
                    rotation: glam::DMat3::from_quat(q),
                    translation: base + axis * (length * 0.5),
                },
                Box::new(Cylinder::new(length * 0.5, radius)),
            )
        }
    }
}

fn pose_of(p: &Placement) -> Pose {
    Pose::from_parts(p.translation, Rot3::from_mat3(&p.rotation).normalize())
}

impl CollisionModel {
    /// The model of `machine` with the tool cylinders and the table extras; `None` when the
    /// machine has no structure. The gauge length (tip to spindle nose) is the highest tool
    /// cylinder top (0 without a tool).
    #[must_use]
    pub fn new(machine: &Machine, tool: &[ToolCylinder], extras: &[TableExtra]) -> Option<Self> {
        let structure = machine.structure.as_ref()?;
        let mut entries = Vec::new();
        let mut sides = Vec::new();
        for b in &structure.bodies {
            let (local, shape) = primitive(&b.shape);
            sides.push((structure.side(b.link), false));
            entries.push(Entry {
                name: b.name.clone(),
                carrier: Carrier::Link(b.link),
                local,
                shape,
            });
        }
        let mut has_mesh = false;
        for e in extras {
            let Some((local, shape)) = table_shape(&e.shape) else {
                continue;
            };
            has_mesh |= matches!(e.shape, TableShape::Mesh(_));
            sides.push((Side::Table, e.cut_by_tool));
            entries.push(Entry {
                name: e.name.clone(),
                carrier: Carrier::Link(Link::Rotary),
                local,
                shape,
            });
        }
        let mut gauge_mm: f64 = 0.0;
        for t in tool.iter().filter(|t| t.radius > 0.0 && t.top > t.bottom) {
            gauge_mm = gauge_mm.max(t.top);
            sides.push((Side::Head, false));
            entries.push(Entry {
                name: t.name.clone(),
                carrier: Carrier::Tool,
                local: Placement::shift(DVec3::Z * (t.bottom + t.top) * 0.5),
                shape: Box::new(Cylinder::new((t.top - t.bottom) * 0.5, t.radius)),
            });
        }
        // Tool cylinders are about Z; parry's cylinders about Y.
        for e in entries.iter_mut().filter(|e| e.carrier == Carrier::Tool) {
            e.local.rotation = glam::DMat3::from_rotation_x(std::f64::consts::FRAC_PI_2);
        }
        let mut pairs = Vec::new();
        for (i, (si, _)) in sides.iter().enumerate() {
            if *si != Side::Head {
                continue;
            }
            for (j, (sj, cut)) in sides.iter().enumerate() {
                let tool_on_cut = *cut && entries[i].carrier == Carrier::Tool;
                if *sj == Side::Head
                    || tool_on_cut
                    || structure.ignored(&entries[i].name, &entries[j].name)
                {
                    continue;
                }
                pairs.push((i, j));
            }
        }
        Some(Self {
            entries,
            pairs,
            gauge_mm,
            has_mesh,
        })
    }

    /// Tip to spindle nose, mm.
    #[must_use]
    pub fn gauge_mm(&self) -> f64 {
        self.gauge_mm
    }

    /// Whether a table extra is a mesh (workholding): motion is then tested at steps of
    /// [`MESH_SAMPLE_MM`], since a jaw's edge can be grazed over less than the primitives' step.
    #[must_use]
    pub fn has_mesh(&self) -> bool {
        self.has_mesh
    }

    /// Number of body pairs tested per pose.
    #[must_use]
    pub fn pair_count(&self) -> usize {
        self.pairs.len()
    }

    /// Every pair of bodies in contact at `joints` (touching counts).
    #[must_use]
    pub fn contacts(&self, machine: &Machine, joints: &MachineJoints) -> Vec<Contact> {
        let Some(links) = machine.link_placements(joints, self.gauge_mm) else {
            return Vec::new();
        };
        let poses: Vec<Pose> = self
            .entries
            .iter()
            .map(|e| pose_of(&self.world(&links, e)))
            .collect();
        self.pairs
            .iter()
            .filter(|(i, j)| {
                let (a, b) = (&self.entries[*i], &self.entries[*j]);
                intersection_test(&poses[*i], a.shape.as_ref(), &poses[*j], b.shape.as_ref())
                    .is_ok_and(|r| r.intersecting)
            })
            .map(|(i, j)| Contact {
                bodies: [self.entries[*i].name.clone(), self.entries[*j].name.clone()],
            })
            .collect()
    }

    fn world(&self, links: &LinkPlacements, e: &Entry) -> Placement {
        let carrier = match e.carrier {
            Carrier::Tool => links.tool,
            Carrier::Link(l) => links.of(l),
        };
        carrier.then_inner(&e.local)
    }
}

/// The tool assembly as cylinders: the cutting end and shank up to the holder face (the wider
/// of the cutting and shank diameters, so the model never misses a contact) and each holder
/// section above it (heights in mm from the tip).
#[must_use]
pub fn tool_cylinders(
    diameter: f64,
    shank_diameter: f64,
    overall_length: f64,
    holder: &[(f64, f64)],
) -> Vec<ToolCylinder> {
    let mut out = vec![ToolCylinder {
        name: "tool".into(),
        radius: diameter.max(shank_diameter) * 0.5,
        bottom: 0.0,
        top: overall_length,
    }];
    let mut z = overall_length;
    for (d, l) in holder {
        out.push(ToolCylinder {
            name: "holder".into(),
            radius: d * 0.5,
            bottom: z,
            top: z + l,
        });
        z += l;
    }
    out
}
