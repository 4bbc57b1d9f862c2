//! Surfaces of the dexel stock: stock-surface points (every interval end of every family),
//! a height-field mesh of the Z rays' tops for drawing, and a closed column mesh whose volume
//! is exactly the Z family's material (for STL export).

use std::collections::HashMap;

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
    /// Its volume is the Z family's material volume with every interval end on a grid of
    /// [`MESH_HEIGHT_STEP_MM`] (so no two heights are closer than what an STL reader welds,
    /// 1e-5 mm, even in f32 far from the origin), and it is closed edge by
    /// edge (every edge used by two triangles in opposite directions, what
    /// [`TriMesh::is_closed`] and a mesh stock ask), so the written stock reads back as a
    /// stock: the corners are shared vertices; each wall is split where the walls and floors
    /// of the other columns around its vertical edges meet them (no T-junctions); and where
    /// material touches only along an edge or at a point (diagonal neighbours, a column
    /// ending where its neighbour begins) each touching piece has its own copy of the
    /// vertex. Large: about 4 triangles per ray plus the walls.
    #[must_use]
    pub fn closed_mesh(&self) -> TriMesh {
        let Some(fam) = self.families.first() else {
            return TriMesh::default();
        };
        let cols = snapped_columns(fam);
        let mut mesh = WeldedColumns {
            fam,
            cols: &cols,
            index: HashMap::new(),
            positions: Vec::new(),
            triangles: Vec::new(),
        };
        for j in 0..fam.nv {
            for i in 0..fam.nu {
                #[allow(clippy::cast_possible_wrap)]
                let (ii, jj) = (i as isize, j as isize);
                for &[a, b] in mesh.column(ii, jj) {
                    mesh.square(ii, jj, b, true);
                    mesh.square(ii, jj, a, false);
                    // Each wall: its neighbour, and its left and right corners seen from
                    // outside.
                    let walls = [
                        ((ii + 1, jj), (ii + 1, jj), (ii + 1, jj + 1)),
                        ((ii - 1, jj), (ii, jj + 1), (ii, jj)),
                        ((ii, jj + 1), (ii + 1, jj + 1), (ii, jj + 1)),
                        ((ii, jj - 1), (ii, jj), (ii + 1, jj)),
                    ];
                    for ((ni, nj), left, right) in walls {
                        for [z0, z1] in exposed(a, b, mesh.column(ni, nj)) {
                            mesh.wall((ii, jj), left, right, z0, z1);
                        }
                    }
                }
            }
        }
        TriMesh::new(mesh.positions, mesh.triangles)
    }
}

/// The step the closed mesh's heights are rounded to, mm (2⁻¹⁴: f32 holds every multiple
/// exactly, and two of them stay more than 1e-5 mm apart in f32 out to 512 mm).
pub const MESH_HEIGHT_STEP_MM: f64 = 1.0 / 16384.0;

/// How far apart the vertices of two pieces of material that only touch at a point or along
/// an edge are drawn, each toward its own material, mm.
pub const TOUCH_GAP_MM: f64 = 1e-4;

/// Each ray's intervals with their ends rounded to [`MESH_HEIGHT_STEP_MM`]; intervals that
/// vanish are dropped and those that come to touch are joined.
fn snapped_columns(fam: &DexelFamily) -> Vec<Vec<[f32; 2]>> {
    #[allow(clippy::cast_possible_truncation)]
    let q = MESH_HEIGHT_STEP_MM as f32;
    let snap = |z: f32| (z / q).round() * q;
    fam.dexels
        .iter()
        .map(|d| {
            let mut out: Vec<[f32; 2]> = Vec::with_capacity(d.intervals().len());
            for &[a, b] in d.intervals() {
                let (a, b) = (snap(a), snap(b));
                if b <= a {
                    continue;
                }
                match out.last_mut() {
                    Some(last) if a <= last[1] => last[1] = last[1].max(b),
                    _ => out.push([a, b]),
                }
            }
            out
        })
        .collect()
}

/// Parts of `[a, b]` not covered by the neighbour's material.
fn exposed(a: f32, b: f32, other: &[[f32; 2]]) -> Vec<[f32; 2]> {
    let mut d = Dexel::One([a, b]);
    for [x, y] in other {
        d.subtract(*x, *y);
    }
    d.intervals().to_vec()
}

/// The column mesh of a Z family with its vertices shared. A vertex is a grid corner
/// `(ci, cj)` (corner (0, 0) at the family's origin) at a height the dexels store (f32 along
/// the ray, so equal heights are equal bits), once per piece of material that meets there:
/// the eight octants around the point (the four columns around the corner, below and above
/// the height) joined where they share a face.
struct WeldedColumns<'a> {
    fam: &'a DexelFamily,
    /// The rays' intervals as meshed ([`snapped_columns`]).
    cols: &'a [Vec<[f32; 2]>],
    index: HashMap<(isize, isize, u32, u8), u32>,
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

impl<'a> WeldedColumns<'a> {
    fn column(&self, i: isize, j: isize) -> &'a [[f32; 2]] {
        let (Ok(i), Ok(j)) = (usize::try_from(i), usize::try_from(j)) else {
            return &[];
        };
        if i >= self.fam.nu || j >= self.fam.nv {
            return &[];
        }
        self.cols
            .get(j * self.fam.nu + i)
            .map_or(&[], Vec::as_slice)
    }

    /// The four columns around corner (ci, cj), in the order (−,−), (+,−), (−,+), (+,+).
    fn around(ci: isize, cj: isize) -> [(isize, isize); 4] {
        [(ci - 1, cj - 1), (ci, cj - 1), (ci - 1, cj), (ci, cj)]
    }

    /// The piece of material around (ci, cj, z) that holds octant `owner` (a column around
    /// the corner, above or below z): the smallest octant index of its face-connected group,
    /// and where two or more pieces meet at the point, the offset of this piece's vertex
    /// ([`TOUCH_GAP_MM`] toward the middle of its octants, so that pieces which only touch
    /// keep apart in an STL file, whose readers join vertices by position).
    fn piece(
        &self,
        ci: isize,
        cj: isize,
        z: f32,
        owner: (isize, isize),
        above: bool,
    ) -> (u8, DVec3) {
        let cols = Self::around(ci, cj);
        let mut full = [false; 8];
        for (q, &(i, j)) in cols.iter().enumerate() {
            for &[a, b] in self.column(i, j) {
                full[q] |= a < z && z <= b;
                full[q + 4] |= a <= z && z < b;
            }
        }
        // Octant k: column k % 4, above when k ≥ 4; faces shared with the side neighbours
        // (0–1, 0–2, 1–3, 2–3) and with the octant above or below.
        let mut group: [u8; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
        let pairs = [
            (0, 1),
            (0, 2),
            (1, 3),
            (2, 3),
            (4, 5),
            (4, 6),
            (5, 7),
            (6, 7),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ];
        loop {
            let mut changed = false;
            for &(a, b) in &pairs {
                if full[a] && full[b] && group[a] != group[b] {
                    let g = group[a].min(group[b]);
                    group[a] = g;
                    group[b] = g;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let q = cols.iter().position(|&c| c == owner).unwrap_or(0);
        let mine = group[q + if above { 4 } else { 0 }];
        let mut pieces: Vec<u8> = (0..8).filter(|&k| full[k]).map(|k| group[k]).collect();
        pieces.sort_unstable();
        pieces.dedup();
        if pieces.len() < 2 {
            return (mine, DVec3::ZERO);
        }
        let dir: DVec3 = (0..8)
            .filter(|&k| full[k] && group[k] == mine)
            .map(|k| {
                let sx = if k % 2 == 1 { 1.0 } else { -1.0 };
                let sy = if k % 4 >= 2 { 1.0 } else { -1.0 };
                let sz = if k >= 4 { 1.0 } else { -1.0 };
                DVec3::new(sx, sy, sz)
            })
            .sum();
        (mine, dir.normalize_or_zero() * TOUCH_GAP_MM)
    }

    fn vertex(
        &mut self,
        (ci, cj): (isize, isize),
        z: f32,
        owner: (isize, isize),
        above: bool,
    ) -> u32 {
        let (piece, offset) = self.piece(ci, cj, z, owner, above);
        let key = (ci, cj, z.to_bits(), piece);
        if let Some(&k) = self.index.get(&key) {
            return k;
        }
        let k = u32::try_from(self.positions.len()).unwrap_or(u32::MAX);
        let (o, s) = (self.fam.origin, self.fam.spacing);
        #[allow(clippy::cast_precision_loss)]
        self.positions.push(
            DVec3::new(o.x + ci as f64 * s, o.y + cj as f64 * s, o.z + f64::from(z)) + offset,
        );
        self.index.insert(key, k);
        k
    }

    /// The square of column (i, j) at height z: its top (`up`, material below) or bottom.
    fn square(&mut self, i: isize, j: isize, z: f32, up: bool) {
        let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
        let v = corners.map(|c| self.vertex(c, z, (i, j), !up));
        if up {
            self.triangles.push([v[0], v[1], v[2]]);
            self.triangles.push([v[0], v[2], v[3]]);
        } else {
            self.triangles.push([v[0], v[2], v[1]]);
            self.triangles.push([v[0], v[3], v[2]]);
        }
    }

    /// The heights where a wall's vertical edge on corner (ci, cj) is split, strictly
    /// between z0 and z1, ascending: where material starts or ends in the four columns
    /// around the corner, and the middle of each stretch where only two diagonal columns
    /// hold material (their walls meet on the edge there, and each needs its own vertex so
    /// that no edge is shared by four triangles).
    fn breaks(&self, (ci, cj): (isize, isize), z0: f32, z1: f32) -> Vec<f32> {
        let cols = Self::around(ci, cj);
        let mut ends: Vec<f32> = cols
            .iter()
            .flat_map(|&(i, j)| self.column(i, j).iter().flatten().copied())
            .filter(|&z| z >= z0 && z <= z1)
            .chain([z0, z1])
            .collect();
        ends.sort_by(f32::total_cmp);
        ends.dedup();
        let mut out = Vec::with_capacity(2 * ends.len());
        for w in ends.windows(2) {
            let m = 0.5 * (w[0] + w[1]);
            let full = cols.map(|(i, j)| self.column(i, j).iter().any(|&[a, b]| a < m && m < b));
            if full == [true, false, false, true] || full == [false, true, true, false] {
                out.push(m);
            }
            if w[1] < z1 {
                out.push(w[1]);
            }
        }
        out
    }

    /// The wall of column `col` from z0 to z1 between its left and right corners (as seen
    /// from outside), its edges split where other walls and floors meet them: triangles
    /// zipped up the two edges, facing outward.
    fn wall(
        &mut self,
        col: (isize, isize),
        left: (isize, isize),
        right: (isize, isize),
        z0: f32,
        z1: f32,
    ) {
        let chain = |inner: Vec<f32>| {
            let mut c = Vec::with_capacity(inner.len() + 2);
            c.push(z0);
            c.extend(inner);
            c.push(z1);
            c
        };
        let lz = chain(self.breaks(left, z0, z1));
        let rz = chain(self.breaks(right, z0, z1));
        // The bottom vertex belongs to the material above it, every other to the material
        // below it (inside the wall both are the column's own).
        let mut verts = |corner: (isize, isize), zs: &[f32]| -> Vec<u32> {
            zs.iter()
                .enumerate()
                .map(|(k, &z)| self.vertex(corner, z, col, k == 0))
                .collect()
        };
        let lv = verts(left, &lz);
        let rv = verts(right, &rz);
        let (mut a, mut b) = (0, 0);
        while a + 1 < lv.len() || b + 1 < rv.len() {
            let right_next = b + 1 < rv.len() && (a + 1 >= lv.len() || rz[b + 1] <= lz[a + 1]);
            if right_next {
                self.triangles.push([lv[a], rv[b], rv[b + 1]]);
                b += 1;
            } else {
                self.triangles.push([lv[a], rv[b], lv[a + 1]]);
                a += 1;
            }
        }
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
