//! Edge topology: boundary edges and closedness (a watertight, consistently oriented surface).

use std::collections::BTreeMap;

use super::TriMesh;

/// How an undirected edge `{lo, hi}` (lo < hi) is used: triangles running lo→hi and hi→lo.
#[derive(Clone, Copy, Debug, Default)]
struct EdgeUse {
    forward: u32,
    backward: u32,
    /// The first directed use seen, as the triangle has it.
    first: [u32; 2],
}

impl TriMesh {
    /// Every undirected edge with its uses, keyed by (lower, higher) vertex index. Edges of a
    /// triangle with a repeated index (a vertex to itself) are skipped.
    fn edge_uses(&self) -> BTreeMap<(u32, u32), EdgeUse> {
        let mut map: BTreeMap<(u32, u32), EdgeUse> = BTreeMap::new();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a == b {
                    continue;
                }
                let e = map.entry((a.min(b), a.max(b))).or_insert(EdgeUse {
                    forward: 0,
                    backward: 0,
                    first: [a, b],
                });
                if a < b {
                    e.forward = e.forward.saturating_add(1);
                } else {
                    e.backward = e.backward.saturating_add(1);
                }
            }
        }
        map
    }

    /// Edges used by exactly one triangle, as that triangle runs them (`[from, to]`), sorted by
    /// (lower index, higher index).
    #[must_use]
    pub fn boundary_edges(&self) -> Vec<[u32; 2]> {
        self.edge_uses()
            .values()
            .filter(|u| u.forward + u.backward == 1)
            .map(|u| u.first)
            .collect()
    }

    /// Edges used by more than two triangles, or twice in the same direction (the two
    /// triangles disagree on orientation), as `[lower, higher]`, sorted.
    #[must_use]
    pub fn bad_edges(&self) -> Vec<[u32; 2]> {
        self.edge_uses()
            .iter()
            .filter(|(_, u)| {
                u.forward + u.backward > 2 || (u.forward + u.backward == 2 && u.forward != 1)
            })
            .map(|(&(lo, hi), _)| [lo, hi])
            .collect()
    }

    /// Is the mesh a closed, consistently oriented surface: at least one triangle, and every
    /// undirected edge used by exactly two triangles running it in opposite directions?
    #[must_use]
    pub fn is_closed(&self) -> bool {
        let uses = self.edge_uses();
        !uses.is_empty() && uses.values().all(|u| u.forward == 1 && u.backward == 1)
    }
}
