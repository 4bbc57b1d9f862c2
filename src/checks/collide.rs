//! The tool assembly (cutter and shank up to the holder face, each holder section) against
//! fixed obstacles given as closed triangle meshes (a setup's workholding), along a motion: the
//! first pose or move where they touch. Exact cylinder–triangle-mesh intersection tests by
//! parry3d; a move is tested at its end and at steps of at most `step_mm` along it (tip and
//! axis interpolated), so a body thinner than the step can be missed between samples. Only
//! surface contact is seen: a tool wholly inside an obstacle passed its surface earlier.

use glam::{DMat3, DQuat, DVec3};
use parry3d_f64::math::{Pose, Rot3};
use parry3d_f64::query::intersection_test;
use parry3d_f64::shape::{Cylinder, TriMesh as ParryTriMesh};

use crate::geometry::mesh::TriMesh;
use crate::machine::collision::{ToolCylinder, tool_cylinders};
use crate::tools::Cutter;

/// An obstacle ready for the tests.
pub struct Obstacle {
    /// Name in reports (`vise`, `plate`, …).
    pub name: String,
    mesh: ParryTriMesh,
}

impl std::fmt::Debug for Obstacle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Obstacle")
            .field("name", &self.name)
            .finish()
    }
}

impl Obstacle {
    /// An obstacle of `mesh` named `name`.
    ///
    /// # Errors
    /// A mesh parry cannot take (no triangles, bad indices), named.
    pub fn new(name: &str, mesh: &TriMesh) -> Result<Self, String> {
        let shape = ParryTriMesh::new(mesh.positions.clone(), mesh.triangles.clone())
            .map_err(|e| format!("{name}: {e}"))?;
        Ok(Self {
            name: name.to_string(),
            mesh: shape,
        })
    }
}

/// The first contact along a motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Hit {
    /// Index of the placement reached by the move on which the contact is (0: the start).
    pub index: usize,
    /// Fraction of that move at the first touching sample (1: its end).
    pub fraction: f64,
    /// Index of the obstacle touched.
    pub obstacle: usize,
    /// Its name.
    pub obstacle_name: String,
    /// The tool piece (`tool` or `holder`).
    pub tool_part: String,
    /// The tip at the contact, mm.
    pub tip: DVec3,
}

/// The tool's cylinders for `cutter` (cutting end and shank up to the holder face, then each
/// holder section).
#[must_use]
pub fn assembly(cutter: &Cutter) -> Vec<ToolCylinder> {
    let holder: Vec<(f64, f64)> = cutter
        .holder
        .iter()
        .map(|h| (h.diameter, h.length))
        .collect();
    tool_cylinders(
        cutter.diameter,
        cutter.shank_diameter,
        cutter.overall_length,
        &holder,
    )
}

fn touching(
    tool: &[ToolCylinder],
    obstacles: &[Obstacle],
    tip: DVec3,
    axis: DVec3,
) -> Option<(usize, String)> {
    let axis = axis.normalize_or(DVec3::Z);
    let rot = DMat3::from_quat(DQuat::from_rotation_arc(DVec3::Y, axis));
    for c in tool {
        if c.top <= c.bottom || c.radius <= 0.0 {
            continue;
        }
        let centre = tip + axis * (0.5 * (c.bottom + c.top));
        let pose = Pose::from_parts(centre, Rot3::from_mat3(&rot).normalize());
        let cyl = Cylinder::new(0.5 * (c.top - c.bottom), c.radius);
        for (i, o) in obstacles.iter().enumerate() {
            let hit = intersection_test(&pose, &cyl, &Pose::IDENTITY, &o.mesh)
                .is_ok_and(|r| r.intersecting);
            if hit {
                return Some((i, c.name.clone()));
            }
        }
    }
    None
}

/// The first contact of `tool` with `obstacles` along the placements (tip, axis) in order,
/// each move tested at steps of at most `step_mm`.
#[must_use]
pub fn first_hit(
    tool: &[ToolCylinder],
    obstacles: &[Obstacle],
    placements: &[(DVec3, DVec3)],
    step_mm: f64,
) -> Option<Hit> {
    let step = if step_mm.is_finite() && step_mm > 0.0 {
        step_mm
    } else {
        1.0
    };
    let hit = |index: usize, fraction: f64, tip: DVec3, axis: DVec3| {
        touching(tool, obstacles, tip, axis).map(|(o, part)| Hit {
            index,
            fraction,
            obstacle: o,
            obstacle_name: obstacles[o].name.clone(),
            tool_part: part,
            tip,
        })
    };
    let (&(t0, a0), rest) = placements.split_first()?;
    if let Some(h) = hit(0, 1.0, t0, a0) {
        return Some(h);
    }
    let (mut tip, mut axis) = (t0, a0);
    for (k, &(t1, a1)) in rest.iter().enumerate() {
        let n = ((t1 - tip).length() / step).ceil().clamp(1.0, 1e6) as usize;
        for i in 1..=n {
            let f = i as f64 / n as f64;
            let a = axis.lerp(a1, f).normalize_or(a1);
            if let Some(h) = hit(k + 1, f, tip.lerp(t1, f), a) {
                return Some(h);
            }
        }
        (tip, axis) = (t1, a1);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed box (counter-clockwise from outside).
    fn box_mesh(min: DVec3, max: DVec3) -> TriMesh {
        let c = |i: u32| {
            DVec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        };
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        TriMesh::new(
            (0..8).map(c).collect(),
            quads
                .iter()
                .flat_map(|q: &[u32; 4]| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
                .collect(),
        )
    }

    #[test]
    fn a_tool_crossing_a_block_is_caught_at_the_move_that_enters_it() {
        let cutter = crate::tools::parse_tool_spec("flat:d=10").unwrap();
        let tool = assembly(&cutter);
        // A block x 20…30, z −10…5; the tool (radius 5) moves along X at z = 0.
        let block = Obstacle::new(
            "jaw",
            &box_mesh(DVec3::new(20.0, -5.0, -10.0), DVec3::new(30.0, 5.0, 5.0)),
        )
        .unwrap();
        let moves: Vec<(DVec3, DVec3)> = [0.0, 10.0, 40.0]
            .iter()
            .map(|&x| (DVec3::new(x, 0.0, 0.0), DVec3::Z))
            .collect();
        let h = first_hit(&tool, &[block], &moves, 0.1).expect("a hit");
        assert_eq!(
            (h.index, h.obstacle_name.as_str(), h.tool_part.as_str()),
            (2, "jaw", "tool")
        );
        // The side of the tool touches x = 20 when the tip is at x = 15: 5/30 of the move.
        assert!((h.tip.x - 15.0).abs() <= 0.1 + 1e-9, "{}", h.tip);
        // Lifted over it (tool bottom at 5.5 > 5): no contact.
        let over: Vec<(DVec3, DVec3)> = moves
            .iter()
            .map(|(t, a)| (*t + DVec3::Z * 5.5, *a))
            .collect();
        let block = Obstacle::new(
            "jaw",
            &box_mesh(DVec3::new(20.0, -5.0, -10.0), DVec3::new(30.0, 5.0, 5.0)),
        )
        .unwrap();
        assert_eq!(first_hit(&tool, &[block], &over, 0.1), None);
    }
}
