//! Surfaces of the dexel stock: stock-surface points (every interval end of every family),
//! a height-field mesh of the Z rays' tops for drawing, and a closed column mesh whose volume
//! is exactly the Z family's material (for STL export).

use glam::DVec3;

use super::dexel::{Dexel, DexelFamily, RayAxis};
use super::stock::DexelStock;
use crate::geometry::mesh::TriMesh;

/// A point of the stock surface: an end of a material interval on a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Position, mm.
    pub position: DVec3,
    /// Outward direction along the ray (−ray at an interval's start, +ray at its end).
    pub normal: DVec3,
    /// The ray family.
    pub axis: RayAxis,
    /// Ray index in its family (`j * nu + i`).
    pub ray: usize,
}

impl DexelStock {
    /// Every interval end of every family, in family then ray order (a point cloud of the
    /// stock surface; for a tri-dexel stock the surface seen from three directions).
    #[must_use]
    pub fn surface_points(&self) -> Vec<SurfacePoint> {
        let mut out = Vec::new();
        for fam in &self.families {
            let dir = fam.axis.direction();
            for (k, d) in fam.dexels.iter().enumerate() {
                let (i, j) = (k % fam.nu.max(1), k / fam.nu.max(1));
                for [a, b] in d.intervals() {
                    for (s, n) in [(*a, -dir), (*b, dir)] {
                        out.push(SurfacePoint {
                            position: fam.point(i, j, f64::from(s)),
                            normal: n,
                            axis: fam.axis,
                            ray: k,
                        });
                    }
                }
            }
        }
        out
    }

    /// The top of every Z ray that holds material, triangulated over the grid (two triangles
    /// per 2×2 block of rays with material, one when three have), with vertex normals. For
    /// drawing: overhangs are not shown.
    #[must_use]
    pub fn height_field_mesh(&self) -> TriMesh {
        let Some(fam) = self.families.first() else {
            return TriMesh::default();
        };
        let (nu, nv) = (fam.nu, fam.nv);
        let mut index = vec![u32::MAX; nu * nv];
        let mut positions = Vec::new();
        for (k, d) in fam.dexels.iter().enumerate() {
            if let Some([_, top]) = d.intervals().last()
                && let Ok(n) = u32::try_from(positions.len())
            {
                positions.push(fam.point(k % nu, k / nu, f64::from(*top)));
                if let Some(slot) = index.get_mut(k) {
                    *slot = n;
                }
            }
        }
        let at = |i: usize, j: usize| index.get(j * nu + i).copied().unwrap_or(u32::MAX);
        let mut triangles = Vec::new();
        for j in 0..nv.saturating_sub(1) {
            for i in 0..nu.saturating_sub(1) {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                let ok = |x: u32| x != u32::MAX;
                match (ok(a), ok(b), ok(c), ok(d)) {
                    (true, true, true, true) => {
                        triangles.push([a, b, c]);
                        triangles.push([a, c, d]);
                    }
                    (false, true, true, true) => triangles.push([b, c, d]),
                    (true, false, true, true) => triangles.push([a, c, d]),
                    (true, true, false, true) => triangles.push([a, b, d]),
                    (true, true, true, false) => triangles.push([a, b, c]),
                    _ => {}
                }
            }
        }
        let mut mesh = TriMesh::new(positions, triangles);
        mesh.compute_normals();
        mesh
    }

    /// A closed mesh of the Z family: each material interval is a square column of the cell
    /// size, with the faces between neighbouring columns left out where both hold material.
    /// Watertight (with T-junctions where heights differ) and its volume equals the Z
    /// family's material volume exactly. Large: about 4 triangles per ray plus the walls.
    #[must_use]
    pub fn closed_mesh(&self) -> TriMesh {
        let Some(fam) = self.families.first() else {
            return TriMesh::default();
        };
        let mut mesh = ColumnMesh::default();
        let h = 0.5 * fam.spacing;
        let (nu, nv) = (fam.nu, fam.nv);
        let empty = Dexel::Empty;
        let get = |i: isize, j: isize| -> &Dexel {
            if i < 0 || j < 0 {
                return &empty;
            }
            #[allow(clippy::cast_sign_loss)]
            let (i, j) = (i as usize, j as usize);
            if i >= nu || j >= nv {
                return &empty;
            }
            fam.dexels.get(j * nu + i).unwrap_or(&empty)
        };
        for j in 0..nv {
            for i in 0..nu {
                #[allow(clippy::cast_possible_wrap)]
                let (ii, jj) = (i as isize, j as isize);
                let d = get(ii, jj);
                if d.intervals().is_empty() {
                    continue;
                }
                let c = fam.ray_origin(i, j);
                let base = fam.origin.z;
                for [a, b] in d.intervals() {
                    let (za, zb) = (base + f64::from(*a), base + f64::from(*b));
                    mesh.quad_z(c, h, zb, true);
                    mesh.quad_z(c, h, za, false);
                    for (di, dj, n) in [
                        (1, 0, DVec3::X),
                        (-1, 0, -DVec3::X),
                        (0, 1, DVec3::Y),
                        (0, -1, -DVec3::Y),
                    ] {
                        for [x, y] in exposed(*a, *b, get(ii + di, jj + dj)) {
                            mesh.side(c, h, n, base + f64::from(x), base + f64::from(y));
                        }
                    }
                }
            }
        }
        TriMesh::new(mesh.positions, mesh.triangles)
    }
}

/// Parts of `[a, b]` not covered by the neighbour's material.
fn exposed(a: f32, b: f32, other: &Dexel) -> Vec<[f32; 2]> {
    let mut d = Dexel::One([a, b]);
    for [x, y] in other.intervals() {
        d.subtract(*x, *y);
    }
    d.intervals().to_vec()
}

#[derive(Default)]
struct ColumnMesh {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

impl ColumnMesh {
    fn push_quad(&mut self, corners: [DVec3; 4]) {
        let Ok(n) = u32::try_from(self.positions.len()) else {
            return;
        };
        self.positions.extend(corners);
        self.triangles.push([n, n + 1, n + 2]);
        self.triangles.push([n, n + 2, n + 3]);
    }

    /// Horizontal square at height z around c, facing up or down.
    fn quad_z(&mut self, c: DVec3, h: f64, z: f64, up: bool) {
        let p = |dx: f64, dy: f64| DVec3::new(c.x + dx, c.y + dy, z);
        let q = [p(-h, -h), p(h, -h), p(h, h), p(-h, h)];
        if up {
            self.push_quad(q);
        } else {
            self.push_quad([q[0], q[3], q[2], q[1]]);
        }
    }

    /// Vertical face of the column at c toward `n` (±X or ±Y), from z0 to z1.
    fn side(&mut self, c: DVec3, h: f64, n: DVec3, z0: f64, z1: f64) {
        let centre = DVec3::new(c.x, c.y, 0.0) + n * h;
        let t = DVec3::Z.cross(n) * h; // tangent, so (t, z) × ... faces outward
        let q = [
            centre - t + DVec3::Z * z0,
            centre + t + DVec3::Z * z0,
            centre + t + DVec3::Z * z1,
            centre - t + DVec3::Z * z1,
        ];
        self.push_quad(q);
    }
}

impl DexelFamily {
    /// Top of the highest interval of ray (i, j), absolute coordinate along the ray, mm.
    #[must_use]
    pub fn top(&self, i: usize, j: usize) -> Option<f64> {
        let d = self.dexels.get(j * self.nu + i)?;
        let [_, b] = d.intervals().last()?;
        Some(self.origin.to_array()[self.axis.axes().2] + f64::from(*b))
    }
}
