//! Double-contact (crease) points of a ball cutter on a mesh and their chaining into polylines.
//!
//! The drop-cutter surface of a ball is the upper envelope of the part's offset surface; where
//! the ball rests on two separate places of the part it has a crease (a valley, or a step where
//! a wall stands), and the contact point jumps across it. A grid edge whose two ends have
//! contact normals (centre − contact, unit) more than half the threshold apart is bisected on
//! the normals (the midpoint joins the end whose normal is nearer) down to `BISECT_MM`; it
//! holds a crease when the two normals still differ by at least the threshold there, since a
//! contact that moves continuously has nearly equal normals that close together. The pose is
//! the end of that tiny interval whose tip is lower (an exact drop-cutter location, within
//! `BISECT_MM` of the crease in XY).
//!
//! Crossings on the edges of one grid cell are connected: two crossings directly; three or more
//! (where creases meet) pairwise, shortest gouge-free pairs first. Every connection, and every
//! chord after refinement, is accepted only if the tool moving straight along it stays within
//! the chord tolerance of the drop-cutter surface below it.

use std::collections::BTreeMap;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::tools::Cutter;
use crate::tools::dropcutter::{ClPoint, drop_cutter, drop_cutter_at};

/// Width in XY down to which a crease is bisected, mm.
const BISECT_MM: f64 = 1e-4;

/// A point where the ball touches the part at two places.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreasePoint {
    /// Tool tip (exact drop-cutter location), mm.
    pub tip: DVec3,
    /// The contact on the side the pose lies on, mm.
    pub cc: DVec3,
    /// The contact on the other side of the crease, mm.
    pub cc_other: DVec3,
    /// Angle between the two contact normals, rad.
    pub angle_rad: f64,
}

/// The ball-cutter context of one search.
pub(crate) struct Ctx<'a> {
    pub mesh: &'a TriMesh,
    pub bvh: &'a MeshBvh,
    pub cutter: &'a Cutter,
    pub min_angle: f64,
    pub tol: f64,
}

impl Ctx<'_> {
    fn radius(&self) -> f64 {
        self.cutter.radius()
    }

    fn drop(&self, p: DVec2) -> Option<ClPoint> {
        drop_cutter_at(self.bvh, self.mesh, self.cutter, p)
    }

    /// Unit contact normal of a ball resting at `p` (from the contact toward the centre).
    fn normal(&self, p: DVec2, cl: &ClPoint) -> DVec3 {
        let centre = p.extend(cl.z + self.radius());
        (centre - cl.cc).normalize_or(DVec3::Z)
    }

    /// Bisect the segment `a`–`b` for a crease; `None` when the contact does not jump there.
    pub fn crease_between(&self, a: DVec2, b: DVec2) -> Option<CreasePoint> {
        let (mut pa, mut pb) = (a, b);
        let (mut ca, mut cb) = (self.drop(pa)?, self.drop(pb)?);
        let (mut na, mut nb) = (self.normal(pa, &ca), self.normal(pb, &cb));
        if na.angle_between(nb) < 0.5 * self.min_angle {
            return None;
        }
        while pa.distance(pb) > BISECT_MM {
            let pm = 0.5 * (pa + pb);
            let cm = self.drop(pm)?;
            let nm = self.normal(pm, &cm);
            if nm.angle_between(na) <= nm.angle_between(nb) {
                (pa, ca, na) = (pm, cm, nm);
            } else {
                (pb, cb, nb) = (pm, cm, nm);
            }
        }
        let angle = na.angle_between(nb);
        if angle < self.min_angle {
            return None;
        }
        let (p, c, other) = if ca.z <= cb.z {
            (pa, ca, cb)
        } else {
            (pb, cb, ca)
        };
        Some(CreasePoint {
            tip: p.extend(c.z),
            cc: c.cc,
            cc_other: other.cc,
            angle_rad: angle,
        })
    }

    /// Whether the tool moving straight from `a` to `b` stays above the drop-cutter surface
    /// (within the tolerance) at samples no farther apart than a tenth of the tool radius.
    pub fn chord_clear(&self, a: DVec3, b: DVec3) -> bool {
        let len = a.truncate().distance(b.truncate());
        let n = ((len / (0.1 * self.radius())).ceil() as usize).clamp(2, 64);
        (1..n).all(|i| {
            let p = a.lerp(b, i as f64 / n as f64);
            self.drop(p.truncate())
                .is_none_or(|c| c.z <= p.z + self.tol)
        })
    }

    /// Insert crease points between `a` and `b` until every chord lies within the tolerance
    /// of the crease (at most `depth` halvings).
    pub fn refine(&self, a: &CreasePoint, b: &CreasePoint, depth: u32, out: &mut Vec<CreasePoint>) {
        if depth == 0 {
            return;
        }
        let (pa, pb) = (a.tip.truncate(), b.tip.truncate());
        let half = 0.5 * pa.distance(pb);
        if half < 4.0 * BISECT_MM {
            return;
        }
        let m = 0.5 * (pa + pb);
        let across = (pb - pa).perp().normalize_or_zero() * half;
        let Some(c) = self.crease_between(m + across, m - across) else {
            return;
        };
        if c.tip.distance(0.5 * (a.tip + b.tip)) <= self.tol {
            return;
        }
        self.refine(a, &c, depth - 1, out);
        out.push(c);
        self.refine(&c, b, depth - 1, out);
    }
}

/// A regular XY grid over the part.
pub(crate) struct Grid {
    pub origin: DVec2,
    pub step: f64,
    pub nx: usize,
    pub ny: usize,
}

impl Grid {
    pub fn over(min: DVec2, max: DVec2, step: f64) -> Self {
        let nx = ((max.x - min.x) / step).ceil().max(1.0) as usize + 1;
        let ny = ((max.y - min.y) / step).ceil().max(1.0) as usize + 1;
        let span = DVec2::new((nx - 1) as f64, (ny - 1) as f64) * step;
        Self {
            origin: 0.5 * (min + max) - 0.5 * span,
            step,
            nx,
            ny,
        }
    }

    pub fn at(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64, j as f64) * self.step
    }
}

/// Grid edge key: (0 = along x / 1 = along y, i, j) of its first node.
type EdgeKey = (u8, usize, usize);

/// Find the crease crossings on every grid edge (in parallel), keyed by edge.
pub(crate) fn crossings(ctx: &Ctx, grid: &Grid) -> BTreeMap<EdgeKey, CreasePoint> {
    let nodes: Vec<DVec2> = (0..grid.ny)
        .flat_map(|j| (0..grid.nx).map(move |i| grid.at(i, j)))
        .collect();
    let cls = drop_cutter(ctx.bvh, ctx.mesh, ctx.cutter, &nodes);
    let normal = |i: usize, j: usize| {
        let k = j * grid.nx + i;
        cls[k].as_ref().map(|c| ctx.normal(nodes[k], c))
    };
    let mut edges: Vec<EdgeKey> = Vec::new();
    for j in 0..grid.ny {
        for i in 0..grid.nx {
            for (dir, (i2, j2)) in [(0u8, (i + 1, j)), (1u8, (i, j + 1))] {
                if i2 >= grid.nx || j2 >= grid.ny {
                    continue;
                }
                if let (Some(a), Some(b)) = (normal(i, j), normal(i2, j2))
                    && a.angle_between(b) >= 0.5 * ctx.min_angle
                {
                    edges.push((dir, i, j));
                }
            }
        }
    }
    edges
        .par_iter()
        .filter_map(|&(dir, i, j)| {
            let (i2, j2) = if dir == 0 { (i + 1, j) } else { (i, j + 1) };
            ctx.crease_between(grid.at(i, j), grid.at(i2, j2))
                .map(|c| ((dir, i, j), c))
        })
        .collect()
}

/// Connect the crossings cell by cell; returns the pairs of connected edge keys.
pub(crate) fn connections(
    ctx: &Ctx,
    grid: &Grid,
    cross: &BTreeMap<EdgeKey, CreasePoint>,
) -> Vec<(EdgeKey, EdgeKey)> {
    let cells: Vec<(usize, usize)> = (0..grid.ny.saturating_sub(1))
        .flat_map(|j| (0..grid.nx.saturating_sub(1)).map(move |i| (i, j)))
        .collect();
    cells
        .par_iter()
        .flat_map_iter(|&(i, j)| {
            let here: Vec<EdgeKey> = [(0u8, i, j), (0, i, j + 1), (1, i, j), (1, i + 1, j)]
                .into_iter()
                .filter(|k| cross.contains_key(k))
                .collect();
            let mut pairs: Vec<(f64, EdgeKey, EdgeKey)> = Vec::new();
            for (x, a) in here.iter().enumerate() {
                for b in &here[x + 1..] {
                    let (pa, pb) = (cross[a].tip, cross[b].tip);
                    pairs.push((pa.distance(pb), *a, *b));
                }
            }
            pairs.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)).then(p.2.cmp(&q.2)));
            let mut used: Vec<EdgeKey> = Vec::new();
            let mut out = Vec::new();
            for (_, a, b) in pairs {
                if used.contains(&a) || used.contains(&b) {
                    continue;
                }
                if ctx.chord_clear(cross[&a].tip, cross[&b].tip) {
                    used.extend([a, b]);
                    out.push((a, b));
                }
            }
            out
        })
        .collect()
}

/// Walk the connections into polylines of edge keys: open chains first (from their ends,
/// in key order), then closed loops (first point repeated at the end).
pub(crate) fn chains(
    cross: &BTreeMap<EdgeKey, CreasePoint>,
    links: &[(EdgeKey, EdgeKey)],
) -> Vec<Vec<EdgeKey>> {
    let mut adj: BTreeMap<EdgeKey, Vec<EdgeKey>> = cross.keys().map(|k| (*k, Vec::new())).collect();
    for (a, b) in links {
        adj.entry(*a).or_default().push(*b);
        adj.entry(*b).or_default().push(*a);
    }
    let mut seen: std::collections::BTreeSet<EdgeKey> = std::collections::BTreeSet::new();
    let mut out = Vec::new();
    let walk = |start: EdgeKey, seen: &mut std::collections::BTreeSet<EdgeKey>| {
        let mut chain = vec![start];
        seen.insert(start);
        let mut cur = start;
        loop {
            let next = adj[&cur].iter().find(|n| !seen.contains(n)).copied();
            match next {
                Some(n) => {
                    seen.insert(n);
                    chain.push(n);
                    cur = n;
                }
                None => {
                    if chain.len() > 2 && adj[&cur].contains(&start) {
                        chain.push(start);
                    }
                    return chain;
                }
            }
        }
    };
    let ends: Vec<EdgeKey> = adj
        .iter()
        .filter(|(_, v)| v.len() != 2)
        .map(|(k, _)| *k)
        .collect();
    for k in ends {
        if !seen.contains(&k) {
            out.push(walk(k, &mut seen));
        }
    }
    let rest: Vec<EdgeKey> = adj.keys().copied().collect();
    for k in rest {
        if !seen.contains(&k) {
            out.push(walk(k, &mut seen));
        }
    }
    out
}
