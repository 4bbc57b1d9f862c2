//! The active tilted work plane as the interpreter's state holds it, and its map between plane
//! coordinates and machine joints: its own file so that the state can hold it without using
//! the plane reader ([`super::workplane`]), which uses the state.

use glam::{DMat3, DVec3};

use super::block::Joints;
use crate::machine::{Machine, MachineJoints};

/// An active tilted work plane.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct WorkPlane {
    /// Columns: the plane's X, Y, Z in work coordinates.
    pub(super) r: DMat3,
    /// The plane's origin in work coordinates, mm.
    pub(super) origin: DVec3,
    /// The kinematics that map work coordinates to joints.
    pub(super) machine: Machine,
}

/// The machine joints of the rotary axes of `pos` (0 where never set).
pub(super) fn rotary_of(machine: &Machine, pos: &Joints) -> MachineJoints {
    let (t, c) = machine.rotary_names().unwrap_or(('A', 'C'));
    let get = |l: char| match l {
        'A' => pos.a,
        'B' => pos.b,
        _ => pos.c,
    };
    MachineJoints {
        xyz: pos.xyz,
        tilt_rad: get(t).unwrap_or(0.0),
        rotary_rad: get(c).unwrap_or(0.0),
    }
}

/// `pos` with the rotary axes set to `j`'s.
pub(super) fn with_rotary(machine: &Machine, pos: Joints, j: &MachineJoints) -> Joints {
    let (t, c) = machine.rotary_names().unwrap_or(('A', 'C'));
    let mut p = pos;
    for (l, v) in [(t, j.tilt_rad), (c, j.rotary_rad)] {
        match l {
            'A' => p.a = Some(v),
            'B' => p.b = Some(v),
            _ => p.c = Some(v),
        }
    }
    p
}

impl WorkPlane {
    /// Machine joints of plane point `p` (mm) at the rotary angles of `pos`, with `offset` added.
    pub(super) fn joints(&self, p: DVec3, pos: &Joints, offset: DVec3) -> Joints {
        let j = rotary_of(&self.machine, pos);
        let (m, t) = self.machine.machine_from_table(&j);
        let work = self.origin + self.r * p;
        Joints {
            xyz: m * work + t + offset,
            ..*pos
        }
    }

    /// The plane point (mm) of machine position `pos` less `offset`.
    pub(super) fn point(&self, pos: &Joints, offset: DVec3) -> DVec3 {
        let j = rotary_of(&self.machine, pos);
        let (m, t) = self.machine.machine_from_table(&j);
        let work = m.transpose() * (pos.xyz - offset - t);
        self.r.transpose() * (work - self.origin)
    }
}
