//! Vertex welding: merging vertices that lie within a tolerance of each other.

use std::collections::HashMap;

use super::TriMesh;
use crate::geometry::DVec3;

impl TriMesh {
    /// Merge vertices within `tol_mm` of each other (Euclidean distance ≤ `tol_mm`); returns how
    /// many vertices were merged away.
    ///
    /// Vertices are visited in index order; each joins the lowest-numbered kept vertex within
    /// the tolerance, or is kept itself. Kept vertices stay in their original order, so the
    /// result is deterministic. A tolerance of 0 (or a negative or non-finite one) merges only
    /// exact duplicates (`-0.0` equals `0.0`). Lookups use a uniform grid of cell size
    /// `tol_mm`, so welding is O(n) for well-spread vertices.
    ///
    /// Triangles that become degenerate (two corners merged into one vertex) or that refer to a
    /// missing vertex are dropped. Per-vertex normals, when present, follow the kept vertices.
    pub fn weld(&mut self, tol_mm: f64) -> usize {
        let tol = if tol_mm.is_finite() && tol_mm > 0.0 {
            tol_mm
        } else {
            0.0
        };
        let (remap, kept) = if tol > 0.0 {
            weld_within(&self.positions, tol)
        } else {
            weld_exact(&self.positions)
        };
        let merged = self.positions.len() - kept.len();
        if self.has_normals() {
            self.normals = kept
                .iter()
                .filter_map(|&i| self.normals.get(i).copied())
                .collect();
        } else {
            self.normals.clear();
        }
        self.positions = kept
            .iter()
            .filter_map(|&i| self.positions.get(i).copied())
            .collect();
        let new_index = |i: u32| remap.get(usize::try_from(i).ok()?).copied();
        self.triangles = self
            .triangles
            .iter()
            .filter_map(|t| {
                let t = [new_index(t[0])?, new_index(t[1])?, new_index(t[2])?];
                (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]).then_some(t)
            })
            .collect();
        merged
    }
}

/// Old index → new index for every vertex, and the old index of every kept vertex.
type WeldMap = (Vec<u32>, Vec<usize>);

/// New index for the next kept vertex (saturating: past u32 vertices the indices go out of range
/// and `validate` reports them instead of wrapping onto wrong vertices).
fn next_index(kept: &[usize]) -> u32 {
    u32::try_from(kept.len()).unwrap_or(u32::MAX)
}

/// Merge bit-identical positions.
fn weld_exact(positions: &[DVec3]) -> WeldMap {
    let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
    let mut remap = Vec::with_capacity(positions.len());
    let mut kept = Vec::new();
    for (i, p) in positions.iter().enumerate() {
        // `+ 0.0` turns -0.0 into 0.0 so that both hash alike.
        let key = [
            (p.x + 0.0).to_bits(),
            (p.y + 0.0).to_bits(),
            (p.z + 0.0).to_bits(),
        ];
        let next = next_index(&kept);
        let id = *seen.entry(key).or_insert(next);
        if id == next {
            kept.push(i);
        }
        remap.push(id);
    }
    (remap, kept)
}

/// Grid cell of a point for cell size `1 / inv` (saturating casts: never panics).
#[allow(clippy::cast_possible_truncation)]
fn cell_of(p: DVec3, inv: f64) -> [i64; 3] {
    let c = (p * inv).floor();
    [c.x as i64, c.y as i64, c.z as i64]
}

/// Coordinates (in cells) from which a double's spacing exceeds the cell size: 2^53.
const FAR: f64 = 9_007_199_254_740_992.0;

/// Merge positions within `tol` (> 0) through a grid of cell size `tol`: a match lies in the
/// point's cell or one of its 26 neighbours.
fn weld_within(positions: &[DVec3], tol: f64) -> WeldMap {
    let inv = 1.0 / tol;
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut far: HashMap<[u64; 3], u32> = HashMap::new();
    let mut remap = Vec::with_capacity(positions.len());
    let mut kept: Vec<usize> = Vec::new();
    for (i, p) in positions.iter().enumerate() {
        if !p.is_finite() {
            // Never within any distance of anything: kept alone, and kept out of the grid.
            remap.push(next_index(&kept));
            kept.push(i);
            continue;
        }
        if (*p * inv).abs().max_element() >= FAR {
            // So far out that neighbouring doubles are more than `tol` apart (and the cell index
            // would saturate, putting every such point in one cell): only equal points weld.
            let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
            let next = next_index(&kept);
            let id = *far.entry(key).or_insert(next);
            if id == next {
                kept.push(i);
            }
            remap.push(id);
            continue;
        }
        let cell = cell_of(*p, inv);
        let mut best: Option<u32> = None;
        for dx in -1..=1_i64 {
            for dy in -1..=1_i64 {
                for dz in -1..=1_i64 {
                    let key = [
                        cell[0].saturating_add(dx),
                        cell[1].saturating_add(dy),
                        cell[2].saturating_add(dz),
                    ];
                    let Some(ids) = grid.get(&key) else { continue };
                    for &id in ids {
                        let close = usize::try_from(id)
                            .ok()
                            .and_then(|k| kept.get(k))
                            .and_then(|&old| positions.get(old))
                            .is_some_and(|q| q.distance(*p) <= tol);
                        // The lowest id wins, whatever order the cells were visited in.
                        if close && best.is_none_or(|b| id < b) {
                            best = Some(id);
                        }
                    }
                }
            }
        }
        let id = best.unwrap_or_else(|| {
            let id = next_index(&kept);
            kept.push(i);
            grid.entry(cell).or_default().push(id);
            id
        });
        remap.push(id);
    }
    (remap, kept)
}
