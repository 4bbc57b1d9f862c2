//! Machine collisions along motion: the machine's bodies, the tool assembly and the table
//! extras ([`crate::machine::collision`]) tested along a path, with the first contact found to
//! a small fraction of a millimetre by bisection.
//!
//! A path is sampled so that no linear axis moves more than [`SAMPLE_MM`] and no rotary axis
//! more than [`SAMPLE_DEG`] between two tests (at a 250 mm radius that is 2.2 mm); the bodies
//! are at least tens of millimetres thick, so a contact cannot fall between two samples
//! unless a corner is merely grazed. The first sample in contact is bisected against the last
//! one clear until the parameter interval moves no axis more than 1e-4 mm (or 1e-6 rad).

use crate::feed::path::{JointVector, SLOTS};
use crate::gcode::MotionBlock;
use crate::machine::collision::{CollisionModel, Contact, TableExtra};
use crate::machine::{Machine, MachineJoints, Shape};

/// Largest linear axis move between two collision tests, mm.
pub const SAMPLE_MM: f64 = 2.0;
/// Largest rotary axis move between two collision tests, degrees.
pub const SAMPLE_DEG: f64 = 0.5;

/// The joints of a slot vector (X Y Z A B C) for `machine`'s kinematics.
#[must_use]
pub fn machine_joints(machine: &Machine, p: &JointVector) -> MachineJoints {
    let tilt = match machine.rotary_names() {
        Some(('B', _)) => p[4],
        Some(_) => p[3],
        None => 0.0,
    };
    MachineJoints {
        xyz: glam::DVec3::new(p[0], p[1], p[2]),
        tilt_rad: tilt,
        rotary_rad: if machine.rotary_names().is_some() {
            p[5]
        } else {
            0.0
        },
    }
}

/// The stock's bounding box as a table extra cut by the tool (the head's bodies must not
/// enter it; the tool's contact with it is the material simulation's).
#[must_use]
pub fn stock_extra(min: glam::DVec3, max: glam::DVec3) -> Option<TableExtra> {
    ((max - min).min_element() > 0.0).then(|| TableExtra {
        name: "stock".into(),
        shape: Shape::Box { min, max }.into(),
        cut_by_tool: true,
    })
}

/// How many samples a move from `a` to `b` needs, at most `linear_mm` of a linear axis apart.
fn samples(a: &JointVector, b: &JointVector, linear_mm: f64) -> usize {
    let mut n: f64 = 1.0;
    for k in 0..SLOTS {
        let step = if k < 3 {
            linear_mm
        } else {
            SAMPLE_DEG.to_radians()
        };
        n = n.max(((b[k] - a[k]).abs() / step).ceil());
    }
    n.min(1e6) as usize
}

/// Whether the axes have moved far enough from `last` for the next collision test.
#[must_use]
pub fn due(last: &JointVector, now: &JointVector) -> bool {
    samples(last, now, SAMPLE_MM) > 1
}

fn moved(a: &JointVector, b: &JointVector) -> f64 {
    (0..SLOTS)
        .map(|k| (b[k] - a[k]).abs() * if k < 3 { 1.0 } else { 100.0 })
        .fold(0.0, f64::max)
}

/// The first contact along `at(u)` for `u` from `u0` to `u1`, leaving out the pairs in
/// `already` (bodies in contact where the motion starts, which it may separate): the
/// parameter of the first contact and the bodies in contact there. `None` when the path
/// stays clear.
pub fn first_contact_along(
    model: &CollisionModel,
    machine: &Machine,
    at: impl Fn(f64) -> JointVector,
    (u0, u1): (f64, f64),
    already: &[Contact],
) -> Option<(f64, Vec<Contact>)> {
    let test = |u: f64| {
        let mut c = model.contacts(machine, &machine_joints(machine, &at(u)));
        c.retain(|x| !already.contains(x));
        c
    };
    let first = test(u0);
    if !first.is_empty() {
        return Some((u0, first));
    }
    let linear = if model.has_mesh() {
        crate::machine::collision::MESH_SAMPLE_MM
    } else {
        SAMPLE_MM
    };
    let n = samples(&at(u0), &at(u1), linear);
    let mut lo = u0;
    for i in 1..=n {
        let hi = u0 + (u1 - u0) * i as f64 / n as f64;
        let found = test(hi);
        if found.is_empty() {
            lo = hi;
            continue;
        }
        let (mut lo, mut hi, mut found) = (lo, hi, found);
        for _ in 0..60 {
            if moved(&at(lo), &at(hi)) <= 1e-4 {
                break;
            }
            let mid = 0.5 * (lo + hi);
            let c = test(mid);
            if c.is_empty() {
                lo = mid;
            } else {
                hi = mid;
                found = c;
            }
        }
        return Some((hi, found));
    }
    None
}

/// A contact found on a program: the block (index), its source line, the joints and bodies.
#[derive(Clone, Debug, PartialEq)]
pub struct PathContact {
    /// Index of the block in the list checked.
    pub block: usize,
    /// Source line of the block (0 when none).
    pub line: usize,
    /// Joints at the first contact (slots X Y Z A B C, mm and rad).
    pub position: JointVector,
    /// The bodies in contact.
    pub contacts: Vec<Contact>,
}

/// The first machine collision along `blocks` (as programmed), if any.
#[must_use]
pub fn check_blocks(
    model: &CollisionModel,
    machine: &Machine,
    blocks: &[MotionBlock],
) -> Option<PathContact> {
    blocks.iter().enumerate().find_map(|(i, b)| {
        let at = |u: f64| crate::feed::path::joint_vector(&b.point_at(u));
        first_contact_along(model, machine, at, (0.0, 1.0), &[]).map(|(u, contacts)| PathContact {
            block: i,
            line: b.source_line,
            position: at(u),
            contacts,
        })
    })
}

/// A text for a position: machine X Y Z in mm and the rotaries in degrees.
#[must_use]
pub fn describe_position(machine: &Machine, p: &JointVector) -> String {
    let mut parts = Vec::new();
    for a in &machine.axes {
        let Some(k) = crate::feed::path::slot_of(a.name) else {
            continue;
        };
        if a.is_rotary() {
            parts.push(format!("{}{:.3}°", a.name, p[k].to_degrees()));
        } else {
            parts.push(format!("{}{:.3} mm", a.name, p[k]));
        }
    }
    parts.join(" ")
}

/// Height of the table's top in table (part) coordinates at zero joints: the highest point
/// of the table-side bodies (mm); `None` without bodies.
#[must_use]
pub fn table_top_z(machine: &Machine) -> Option<f64> {
    let s = machine.structure.as_ref()?;
    let links = machine.link_placements(&MachineJoints::default(), 0.0)?;
    let r = links.table.rotation.transpose();
    let view = crate::machine::Placement {
        rotation: r,
        translation: -(r * links.table.translation),
    };
    s.bodies
        .iter()
        .filter(|b| s.side(b.link) == crate::machine::Side::Table)
        .flat_map(|b| {
            let place = view.then_inner(&links.of(b.link));
            b.shape
                .mesh(16)
                .vertices
                .into_iter()
                .map(move |v| place.apply(v).z)
        })
        .reduce(f64::max)
}

/// A riser block (parallels) under the stock, from the table's top up to the stock's bottom
/// with the stock's footprint, so the part rests on the table rather than floating above it;
/// `None` when the stock already reaches the table (or the machine has no bodies).
#[must_use]
pub fn riser_under(
    machine: &Machine,
    stock_min: glam::DVec3,
    stock_max: glam::DVec3,
) -> Option<TableExtra> {
    let top = table_top_z(machine)?;
    let footprint = (stock_max - stock_min).truncate().min_element();
    (stock_min.z - top > 1e-6 && footprint > 0.0).then(|| TableExtra {
        name: "riser".into(),
        shape: Shape::Box {
            min: glam::DVec3::new(stock_min.x, stock_min.y, top),
            max: glam::DVec3::new(stock_max.x, stock_max.y, stock_min.z),
        }
        .into(),
        cut_by_tool: false,
    })
}
