//! The cutter's contours at one level: fibres in x and in y on a regular grid, each pushed
//! against every triangle near it ([`super::push`]), their intervals merged, and the closed
//! loops read off the grid by marching squares whose crossings are the fibres' exact interval
//! ends (a node is blocked when its x fibre's intervals hold it). Every contour point is
//! therefore an exact cutter location (to the push-cutter's precision); between points the
//! contour is a chord.
//!
//! Loops are oriented with the blocked side (the part) on the right of the direction of travel,
//! which is climb milling for a spindle turning clockwise (M3). An interval narrower than the
//! grid step that lies inside one cell edge is not seen (the grid step bounds the features
//! found).

use std::collections::HashMap;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::push::{End, Fibre, Profile, push_triangle};
use crate::geometry::Aabb;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;

/// A point of a contour: the tool tip and its contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourPoint {
    /// Tool tip, mm.
    pub tip: DVec3,
    /// Contact point on the mesh, mm.
    pub cc: DVec3,
    /// Slope of the surface at the contact, rad from horizontal.
    pub slope: f64,
}

/// Merged intervals of one fibre (sorted, disjoint).
pub(crate) type Intervals = Vec<(End, End)>;

/// All intervals where the cutter meets the mesh along `fibre` between s = 0 and `len`.
pub(crate) fn fibre_intervals(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    prof: &Profile,
    fibre: &Fibre,
    len: f64,
) -> Intervals {
    let big = prof.radius();
    let a = fibre.at(0.0).truncate();
    let b = fibre.at(len).truncate();
    let top = bvh.bbox().max.z;
    if top < fibre.z {
        return Vec::new();
    }
    let pad = DVec2::splat(big);
    let bx = Aabb {
        min: (a.min(b) - pad).extend(fibre.z),
        max: (a.max(b) + pad).extend(top + 1.0),
    };
    // Highest triangles first: their intervals are the widest, and a triangle whose reach
    // (its extent along the fibre widened by the radius) lies inside what is already blocked
    // cannot change the union.
    let mut cands: Vec<([DVec3; 3], f64, f64, f64)> = bvh
        .triangles_in_aabb(&bx)
        .into_iter()
        .filter_map(|t| mesh.triangle_corners(t))
        .map(|tri| {
            let al = tri.map(|p| (p.truncate() - fibre.origin).dot(fibre.dir));
            let lo = al[0].min(al[1]).min(al[2]) - big;
            let hi = al[0].max(al[1]).max(al[2]) + big;
            let top = tri[0].z.max(tri[1].z).max(tri[2].z);
            (tri, lo, hi, top)
        })
        .filter(|c| c.2 > 0.0 && c.1 < len && c.3 >= fibre.z)
        .collect();
    cands.sort_by(|a, b| b.3.total_cmp(&a.3).then(a.1.total_cmp(&b.1)));
    let mut out: Intervals = Vec::new();
    for (tri, lo_b, hi_b, _) in cands {
        let k = out.partition_point(|iv| iv.1.s < hi_b);
        if k < out.len() && out[k].0.s <= lo_b {
            continue;
        }
        if let Some(iv) = push_triangle(prof, fibre, &tri)
            && iv.1.s > 0.0
            && iv.0.s < len
        {
            insert(&mut out, iv);
        }
    }
    out
}

/// Add an interval to sorted disjoint ones, merging what overlaps.
fn insert(out: &mut Intervals, iv: (End, End)) {
    let first = out.partition_point(|x| x.1.s < iv.0.s);
    let mut last = first;
    let (mut lo, mut hi) = iv;
    while last < out.len() && out[last].0.s <= hi.s {
        if out[last].0.s < lo.s {
            lo = out[last].0;
        }
        if out[last].1.s > hi.s {
            hi = out[last].1;
        }
        last += 1;
    }
    out.splice(first..last, [(lo, hi)]);
}

fn blocked_at(iv: &Intervals, s: f64) -> bool {
    iv.iter().any(|(lo, hi)| lo.s < s && s < hi.s)
}

/// The interval end within (a, b) nearest the middle; when none (the two fibres disagree at
/// a tangency), the end nearest to the edge.
fn crossing(iv: &Intervals, a: f64, b: f64) -> Option<End> {
    let mid = 0.5 * (a + b);
    iv.iter().flat_map(|(lo, hi)| [*lo, *hi]).min_by(|x, y| {
        let dx = (x.s - mid).abs() - 0.5 * (b - a);
        let dy = (y.s - mid).abs() - 0.5 * (b - a);
        dx.max(0.0)
            .total_cmp(&dy.max(0.0))
            .then((x.s - mid).abs().total_cmp(&(y.s - mid).abs()))
    })
}

/// The sampling grid of a level.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Grid {
    pub x0: f64,
    pub y0: f64,
    pub step: f64,
    pub nx: usize,
    pub ny: usize,
}

impl Grid {
    /// A grid of step ≤ `step` covering `bbox` grown by the cutter radius and one step, so the
    /// outermost nodes are free.
    pub(crate) fn around(bbox: &Aabb, big: f64, step: f64) -> Self {
        let pad = big + 2.0 * step;
        let (x0, y0) = (bbox.min.x - pad, bbox.min.y - pad);
        let (wx, wy) = (bbox.max.x + pad - x0, bbox.max.y + pad - y0);
        let nx = (wx / step).ceil().max(2.0) as usize;
        let ny = (wy / step).ceil().max(2.0) as usize;
        Self {
            x0,
            y0,
            step,
            nx,
            ny,
        }
    }

    fn x(&self, i: usize) -> f64 {
        self.x0 + self.step * i as f64
    }

    fn y(&self, j: usize) -> f64 {
        self.y0 + self.step * j as f64
    }
}

/// Crossing on an edge of the grid: horizontal (i, j)–(i+1, j) or vertical (i, j)–(i, j+1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum EdgeId {
    H(usize, usize),
    V(usize, usize),
}

/// The closed contours of `prof` at tip height `z`, blocked side on the right.
pub(crate) fn level_contours(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    prof: &Profile,
    grid: &Grid,
    z: f64,
) -> Vec<Vec<ContourPoint>> {
    let xlen = grid.step * grid.nx as f64;
    let ylen = grid.step * grid.ny as f64;
    let xf: Vec<Intervals> = (0..=grid.ny)
        .into_par_iter()
        .map(|j| {
            let f = Fibre {
                origin: DVec2::new(grid.x0, grid.y(j)),
                dir: DVec2::X,
                z,
            };
            fibre_intervals(mesh, bvh, prof, &f, xlen)
        })
        .collect();
    let yf: Vec<Intervals> = (0..=grid.nx)
        .into_par_iter()
        .map(|i| {
            let f = Fibre {
                origin: DVec2::new(grid.x(i), grid.y0),
                dir: DVec2::Y,
                z,
            };
            fibre_intervals(mesh, bvh, prof, &f, ylen)
        })
        .collect();
    let blocked = |i: usize, j: usize| blocked_at(&xf[j], grid.step * i as f64);
    let point = |id: EdgeId| -> ContourPoint {
        let (end, tip) = match id {
            EdgeId::H(i, j) => {
                let (a, b) = (grid.step * i as f64, grid.step * (i + 1) as f64);
                let e = crossing(&xf[j], a, b);
                let s = e.map_or(0.5 * (a + b), |e| e.s.clamp(a, b));
                (e, DVec3::new(grid.x0 + s, grid.y(j), z))
            }
            EdgeId::V(i, j) => {
                let (a, b) = (grid.step * j as f64, grid.step * (j + 1) as f64);
                let e = crossing(&yf[i], a, b);
                let margin = 1e-9 * grid.step;
                if e.is_none_or(|e| e.s <= a + margin || e.s >= b - margin)
                    && let Some(exact) = tangent_crossing(mesh, bvh, prof, grid, z, &xf, i, j)
                {
                    return exact;
                }
                let s = e.map_or(0.5 * (a + b), |e| e.s.clamp(a, b));
                (e, DVec3::new(grid.x(i), grid.y0 + s, z))
            }
        };
        ContourPoint {
            tip,
            cc: end.map_or(tip, |e| e.cc),
            slope: end.map_or(std::f64::consts::FRAC_PI_2, |e| e.slope),
        }
    };
    let mut next: HashMap<EdgeId, EdgeId> = HashMap::new();
    for j in 0..grid.ny {
        for i in 0..grid.nx {
            cell_segments(i, j, &blocked, &mut next);
        }
    }
    chain_loops(next, point)
}

/// Bisection steps on a vertical grid edge: 0.1 mm / 2⁴⁴ ≈ 6e-15 mm.
const EDGE_BISECT_ITERS: usize = 44;

/// The crossing of the vertical edge (i, j)–(i, j+1) where its y fibre has no interval end on
/// the edge. Node states come from the x fibres, so this happens where the contour touches
/// the y fibre tangentially and the two fibre families disagree by the sag of the
/// tessellation; clamping the y fibre's nearest end to the edge would give a point inside the
/// material. Instead the edge is bisected for the height where short x fibres through it
/// change state, and the point is that x fibre's interval end nearest to the edge: an exact
/// cutter location within the bisection's width of where the contour crosses x = x(i).
/// When short fibres see no difference (the nodes differ only by rounding at an interval end
/// on a node), the point is that end of either row's x fibre. `None` when no end lies within
/// a step of the edge.
#[allow(clippy::too_many_arguments)]
fn tangent_crossing(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    prof: &Profile,
    grid: &Grid,
    z: f64,
    xf: &[Intervals],
    i: usize,
    j: usize,
) -> Option<ContourPoint> {
    let x = grid.x(i);
    let h = grid.step;
    let short = |y: f64| {
        let f = Fibre {
            origin: DVec2::new(x - h, y),
            dir: DVec2::X,
            z,
        };
        fibre_intervals(mesh, bvh, prof, &f, 2.0 * h)
    };
    let (mut lo, mut hi) = (grid.y(j), grid.y(j + 1));
    let lo_blocked = blocked_at(&short(lo), h);
    if lo_blocked == blocked_at(&short(hi), h) {
        // The nodes differ only by rounding at an interval end on the node itself: that
        // end of either row's x fibre is the exact point.
        let s0 = h * i as f64;
        let row = |r: usize| {
            xf[r]
                .iter()
                .flat_map(|(l, u)| [*l, *u])
                .filter(|e| (e.s - s0).abs() <= h)
                .map(move |e| (e, grid.y(r)))
        };
        let (e, y) = row(j)
            .chain(row(j + 1))
            .min_by(|p, q| (p.0.s - s0).abs().total_cmp(&(q.0.s - s0).abs()))?;
        return Some(ContourPoint {
            tip: DVec3::new(grid.x0 + e.s, y, z),
            cc: e.cc,
            slope: e.slope,
        });
    }
    for _ in 0..EDGE_BISECT_ITERS {
        let m = 0.5 * (lo + hi);
        if blocked_at(&short(m), h) == lo_blocked {
            lo = m;
        } else {
            hi = m;
        }
    }
    let y = if lo_blocked { hi } else { lo };
    let iv = short(y);
    let e = iv
        .iter()
        .flat_map(|(l, u)| [*l, *u])
        .min_by(|p, q| (p.s - h).abs().total_cmp(&(q.s - h).abs()))
        .filter(|e| (e.s - h).abs() <= h)?;
    Some(ContourPoint {
        tip: DVec3::new(x - h + e.s, y, z),
        cc: e.cc,
        slope: e.slope,
    })
}

/// Marching squares in one cell: walking its corners counter-clockwise, each crossing into
/// the blocked side is joined to the next crossing out of it.
fn cell_segments(
    i: usize,
    j: usize,
    blocked: &impl Fn(usize, usize) -> bool,
    next: &mut HashMap<EdgeId, EdgeId>,
) {
    let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
    let edges = [
        EdgeId::H(i, j),
        EdgeId::V(i + 1, j),
        EdgeId::H(i, j + 1),
        EdgeId::V(i, j),
    ];
    let b: Vec<bool> = corners.iter().map(|&(a, c)| blocked(a, c)).collect();
    // Crossing k lies on the edge from corner k to corner k+1.
    for k in 0..4 {
        let into = !b[k] && b[(k + 1) % 4];
        if !into {
            continue;
        }
        for d in 1..4 {
            let m = (k + d) % 4;
            if b[m] && !b[(m + 1) % 4] {
                next.insert(edges[k], edges[m]);
                break;
            }
        }
    }
}

fn chain_loops(
    mut next: HashMap<EdgeId, EdgeId>,
    point: impl Fn(EdgeId) -> ContourPoint,
) -> Vec<Vec<ContourPoint>> {
    // Start loops from their smallest edge so the result does not depend on hash order.
    let mut starts: Vec<EdgeId> = next.keys().copied().collect();
    starts.sort_by_key(|e| match *e {
        EdgeId::H(i, j) => (j, i, 0),
        EdgeId::V(i, j) => (j, i, 1),
    });
    let mut loops = Vec::new();
    for s in starts {
        if !next.contains_key(&s) {
            continue;
        }
        let mut ids = vec![s];
        let mut cur = s;
        while let Some(n) = next.remove(&cur) {
            if n == s {
                break;
            }
            ids.push(n);
            cur = n;
        }
        let mut pts: Vec<ContourPoint> = ids.into_iter().map(&point).collect();
        // A tangent crossing may resolve to the point of the neighbouring crossing.
        pts.dedup_by(|b, a| a.tip == b.tip);
        if pts.len() > 1 && pts[0].tip == pts[pts.len() - 1].tip {
            pts.pop();
        }
        if pts.len() >= 3 {
            loops.push(pts);
        }
    }
    loops
}
