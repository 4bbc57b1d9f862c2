//! Coarse passes: where a pass line lies inside the boundary, its drop-cutter samples on a
//! regular grid along the line, and the cusp between two neighbouring passes.

use glam::{DVec2, DVec3};

use super::Frame;
use super::envelope::swept_lower;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::tools::dropcutter::{ClPoint, drop_cutter};

use crate::tools::{Cutter, CutterKind};

/// Where passes may run.
pub(crate) enum Region<'a> {
    /// Over the part's XY outline: a vertical ray through the tool axis meets the mesh.
    Silhouette(&'a MeshBvh, f64),
    /// Wherever the tool touches the part, up to where its contact point reaches the part's
    /// XY outline (the rim): the axis may leave the outline, the contact may not.
    Contact(&'a MeshBvh, f64),
    /// Inside a closed polygon (even-odd rule).
    Polygon(&'a [DVec2]),
}

impl Region<'_> {
    /// Whether `p` lies over the part (silhouette, contact) or inside the polygon.
    pub(crate) fn contains(&self, p: DVec2) -> bool {
        match self {
            Region::Silhouette(bvh, top) | Region::Contact(bvh, top) => bvh
                .ray_cast(p.extend(*top), DVec3::NEG_Z, f64::INFINITY)
                .is_some(),
            Region::Polygon(poly) => {
                let mut inside = false;
                let n = poly.len();
                for i in 0..n {
                    let (Some(a), Some(b)) = (poly.get(i), poly.get((i + 1) % n)) else {
                        continue;
                    };
                    if (a.y > p.y) != (b.y > p.y) {
                        let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
                        if p.x < x {
                            inside = !inside;
                        }
                    }
                }
                inside
            }
        }
    }

    /// Whether the tool axis at `p` may stand there (the contact region leaves that to the
    /// drop-cutter and the contact point).
    fn axis_allowed(&self, p: DVec2) -> bool {
        match self {
            Region::Contact(..) => true,
            _ => self.contains(p),
        }
    }

    /// Whether a contact point at `cc` lies on the rim of the part's XY outline (within
    /// [`RIM_EPS`]): one of the four points `RIM_EPS` away along and across the passes is off
    /// the part. Always false outside the contact region.
    fn on_rim(&self, frame: &Frame, cc: DVec2) -> bool {
        let Region::Contact(..) = self else {
            return false;
        };
        [frame.u, -frame.u, frame.c, -frame.c]
            .iter()
            .any(|d| !self.contains(cc + *d * RIM_EPS))
    }
}

/// How close to the part's outline a contact point counts as on its rim, mm.
const RIM_EPS: f64 = 0.005;

/// One pass sampled on the grid `t_j = t0 + j·dt`.
pub(crate) struct CoarsePass {
    /// Offset across the passes, mm.
    pub w: f64,
    /// Drop-cutter result per grid point (None outside the region or off the mesh).
    pub cl: Vec<Option<ClPoint>>,
    /// Per grid point: the contact lies on the rim of the part's outline (the tool rolls over
    /// the edge; only with [`Region::Contact`]).
    pub rim: Vec<bool>,
    /// Moves between a run's end off the grid and its nearest grid point, as (t, CL z) pairs
    /// in ascending t (the contact region's ends, where the contact reaches the rim).
    pub ends: Vec<[(f64, f64); 2]>,
    /// Runs of the pass inside the region: (t_start, t_end, samples with their t), ascending.
    pub runs: Vec<Vec<(f64, ClPoint)>>,
}

/// Sample the pass at offset `w`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn coarse_pass(
    frame: &Frame,
    w: f64,
    grid: &[f64],
    region: &Region,
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
) -> CoarsePass {
    let xy: Vec<DVec2> = grid.iter().map(|&t| frame.at(t, w)).collect();
    let inside: Vec<bool> = xy.iter().map(|p| region.axis_allowed(*p)).collect();
    let mut cl: Vec<Option<ClPoint>> = drop_cutter(bvh, mesh, cutter, &xy)
        .into_iter()
        .zip(&inside)
        .map(|(c, &i)| if i { c } else { None })
        .collect();
    let rim: Vec<bool> = cl
        .iter()
        .map(|c| c.is_some_and(|c| region.on_rim(frame, c.cc.truncate())))
        .collect();
    if let Region::Contact(..) = region {
        let mut ends = Vec::new();
        let runs = contact_runs(
            frame, w, grid, &mut cl, &rim, region, bvh, mesh, cutter, &mut ends,
        );
        return CoarsePass {
            w,
            cl,
            rim,
            ends,
            runs,
        };
    }
    // Runs of consecutive grid points with a CL point; their ends are moved to the region's
    // boundary by bisection where the run stops because the boundary was crossed.
    let mut runs = Vec::new();
    let mut cur: Vec<(f64, ClPoint)> = Vec::new();
    for (j, c) in cl.iter().enumerate() {
        let t = grid.get(j).copied().unwrap_or(0.0);
        match c {
            Some(p) => {
                if cur.is_empty() && j > 0 && !inside.get(j - 1).copied().unwrap_or(true) {
                    let tb = boundary(frame, w, grid.get(j - 1).copied().unwrap_or(t), t, region);
                    if let Some(e) = drop_one(frame, w, tb, bvh, mesh, cutter)
                        && tb < t - 1e-6
                    {
                        cur.push((tb, e));
                    }
                }
                cur.push((t, *p));
            }
            None => {
                if !cur.is_empty() {
                    if !inside.get(j).copied().unwrap_or(true) {
                        let ta = cur.last().map_or(t, |l| l.0);
                        let tb = boundary(frame, w, ta, t, region);
                        if let Some(e) = drop_one(frame, w, tb, bvh, mesh, cutter)
                            && tb > ta + 1e-6
                        {
                            cur.push((tb, e));
                        }
                    }
                    runs.push(std::mem::take(&mut cur));
                }
            }
        }
    }
    if !cur.is_empty() {
        runs.push(cur);
    }
    runs.retain(|r| r.len() >= 2);
    CoarsePass {
        w,
        cl,
        rim,
        ends: Vec::new(),
        runs,
    }
}

/// The runs of a pass in the contact region: each stretch of grid points where the tool
/// touches the part, with the ends where the tool only rolls over the rim cut off at the first
/// rim contact (found by bisection): there the contact point has reached the edge, and beyond
/// it the tool touches nothing else. The cut-off grid points lose their CL point. A stretch
/// with rim contacts only (a pass hanging over an edge along it) is kept whole.
#[allow(clippy::too_many_arguments)]
fn contact_runs(
    frame: &Frame,
    w: f64,
    grid: &[f64],
    cl: &mut [Option<ClPoint>],
    rim: &[bool],
    region: &Region,
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
    ends: &mut Vec<[(f64, f64); 2]>,
) -> Vec<Vec<(f64, ClPoint)>> {
    let interior = |t: f64| {
        drop_one(frame, w, t, bvh, mesh, cutter)
            .map(|c| (!region.on_rim(frame, c.cc.truncate()), c))
    };
    // The first rim contact going from the interior contact at `t_in` toward `t_rim`.
    let edge = |t_in: f64, t_rim: f64| -> Option<(f64, ClPoint)> {
        let (mut a, mut b) = (t_in, t_rim);
        let mut at_b = None;
        for _ in 0..24 {
            let m = 0.5 * (a + b);
            match interior(m) {
                Some((true, _)) => a = m,
                other => {
                    b = m;
                    at_b = other.map(|(_, c)| c);
                }
            }
        }
        at_b.or_else(|| interior(b).map(|(_, c)| c)).map(|c| (b, c))
    };
    let mut runs = Vec::new();
    let mut j = 0;
    while j < cl.len() {
        if cl.get(j).copied().flatten().is_none() {
            j += 1;
            continue;
        }
        let start = j;
        while cl.get(j).copied().flatten().is_some() {
            j += 1;
        }
        let end = j - 1; // last grid point of the stretch
        let is_interior = |k: usize| !rim.get(k).copied().unwrap_or(true);
        let first = (start..=end).find(|&k| is_interior(k));
        let last = (start..=end).rev().find(|&k| is_interior(k));
        let sample = |k: usize, cl: &[Option<ClPoint>]| {
            Some((grid.get(k).copied()?, cl.get(k).copied().flatten()?))
        };
        let (Some(a), Some(b)) = (first, last) else {
            let run: Vec<(f64, ClPoint)> = (start..=end).filter_map(|k| sample(k, cl)).collect();
            runs.push(run);
            continue;
        };
        let mut run = Vec::new();
        if a > start
            && let (Some(&ti), Some(&tr)) = (grid.get(a), grid.get(a - 1))
            && let Some(e) = edge(ti, tr)
        {
            run.push(e);
            if let Some((t, c)) = sample(a, cl) {
                ends.push([(e.0, e.1.z), (t, c.z)]);
            }
        }
        run.extend((a..=b).filter_map(|k| sample(k, cl)));
        if b < end
            && let (Some(&ti), Some(&tr)) = (grid.get(b), grid.get(b + 1))
            && let Some(e) = edge(ti, tr)
        {
            run.push(e);
            if let Some((t, c)) = sample(b, cl) {
                ends.push([(t, c.z), (e.0, e.1.z)]);
            }
        }
        for k in (start..a).chain(b + 1..=end) {
            if let Some(c) = cl.get_mut(k) {
                *c = None;
            }
        }
        runs.push(run);
    }
    runs.retain(|r| r.len() >= 2);
    runs
}

fn drop_one(
    frame: &Frame,
    w: f64,
    t: f64,
    bvh: &MeshBvh,
    mesh: &TriMesh,
    cutter: &Cutter,
) -> Option<ClPoint> {
    crate::tools::dropcutter::drop_cutter_at(bvh, mesh, cutter, frame.at(t, w))
}

/// The boundary crossing between `t_a` and `t_b` (one inside, one outside), by bisection; the
/// inside end is returned.
fn boundary(frame: &Frame, w: f64, t_a: f64, t_b: f64, region: &Region) -> f64 {
    let a_in = region.contains(frame.at(t_a, w));
    let (mut tin, mut tout) = if a_in { (t_a, t_b) } else { (t_b, t_a) };
    for _ in 0..30 {
        let mid = 0.5 * (tin + tout);
        if region.contains(frame.at(mid, w)) {
            tin = mid;
        } else {
            tout = mid;
        }
    }
    tin
}

/// The cusp between two neighbouring passes at one grid point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cusp {
    /// Remaining material thickness at the cusp, mm.
    pub height: f64,
    /// The grid point ends a run of either pass (the tool does not pass beyond it, so the
    /// material there is bounded by the run's end, not by the step-over).
    pub at_end: bool,
    /// Material at the cusp that a pass right between the two would not remove either (a
    /// corner or valley narrower than the tool, the foot of a wall), mm.
    pub unreachable: f64,
    /// Plan-view position of the ridge, mm.
    pub at: DVec2,
    /// The ridge's closest part point faces steeper than the slope limit (the foot of a wall
    /// the raster leaves to a Z-level pass, not a corner narrower than the tool).
    pub steep: bool,
}

/// Sections sampled across the bracket of the two passes when looking for the cusp.
const SECTION_SAMPLES: usize = 16;

/// Cusps between two neighbouring passes per grid point: the ridges of the lower envelope of
/// the two passes' swept volumes in the vertical section across the passes (the tools moving
/// along the passes, `envelope`), each measured as its distance to the mesh, i.e. the
/// remaining material thickness there (exact on a plane, and it sees curvature across the
/// passes). The ridge is where one pass's envelope takes over from the other's; it lies between
/// the two contact points, not between the two tool axes: on a cross slope φ each contact sits
/// R·sin φ uphill of its axis, so once the step is below 2R·sin φ the ridge is uphill of both
/// axes (between them the downhill pass's envelope is the lower one everywhere). The section is
/// therefore searched over the span of both axes and both contacts, and the highest crossing
/// counts.
///
/// Only the part of that thickness the step-over is responsible for is a scallop: the pass
/// `mid` halfway between the two shows what a pass there would leave at the same point (its
/// envelope's distance to the mesh), and the cusp height is the ridge's distance to the mesh
/// less that. On a plane the midway pass touches the plane right under the ridge (by symmetry),
/// so this is exact; where the tool cannot reach the surface at all (a corner narrower than
/// the tool, the foot of a vertical wall met along the pass) the material is reported as
/// [`Cusp::unreachable`] instead of driving the step down. None where either pass has no CL
/// point or the CL rises across the passes more steeply than `max_slope`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn cusps(
    frame: &Frame,
    grid: &[f64],
    a: &CoarsePass,
    b: &CoarsePass,
    mid: &CoarsePass,
    cutter: &Cutter,
    bvh: &MeshBvh,
    cos_max_slope: f64,
) -> Vec<Option<Cusp>> {
    use rayon::prelude::*;
    let (wa, wb) = (a.w, b.w);
    let has =
        |p: &CoarsePass, j: Option<usize>| j.and_then(|j| p.cl.get(j)).is_some_and(Option::is_some);
    (0..grid.len())
        .into_par_iter()
        .map(|j| {
            let (Some(Some(ca)), Some(Some(cb)), Some(&t)) =
                (a.cl.get(j), b.cl.get(j), grid.get(j))
            else {
                return None;
            };
            let rise = (cb.z - ca.z).abs();
            let run = (wb - wa).abs();
            if rise * cos_max_slope > run * (1.0 - cos_max_slope * cos_max_slope).sqrt() {
                return None; // steeper than the limit across the passes
            }
            let at_end = [j.checked_sub(1), j.checked_add(1)]
                .iter()
                .any(|&k| !has(a, k) || !has(b, k));
            let pa = |x: f64| swept_lower(cutter, grid, a, j, x - wa);
            let pb = |x: f64| swept_lower(cutter, grid, b, j, x - wb);
            // a − b, with a pass that does not reach counting as far above.
            let diff = |x: f64| {
                let (za, zb) = (pa(x), pb(x));
                match (za.is_finite(), zb.is_finite()) {
                    (true, true) => Some(za - zb),
                    (false, true) => Some(1.0e9),
                    (true, false) => Some(-1.0e9),
                    (false, false) => None,
                }
            };
            let span = [
                wa,
                wb,
                ca.cc.truncate().dot(frame.c),
                cb.cc.truncate().dot(frame.c),
            ];
            let lo = span.iter().copied().fold(f64::INFINITY, f64::min) - 1.0e-6;
            let hi = span.iter().copied().fold(f64::NEG_INFINITY, f64::max) + 1.0e-6;
            let xs: Vec<f64> = (0..=SECTION_SAMPLES)
                .map(|i| lo + (hi - lo) * i as f64 / SECTION_SAMPLES as f64)
                .collect();
            let fs: Vec<Option<f64>> = xs.iter().map(|&x| diff(x)).collect();
            let mut best: Option<Cusp> = None;
            for (xw, fw) in xs.windows(2).zip(fs.windows(2)) {
                let ([x0, x1], [Some(f0), Some(f1)]) = (xw, fw) else {
                    continue;
                };
                if (*f0 > 0.0) == (*f1 > 0.0) {
                    continue;
                }
                let (mut l, mut r) = (*x0, *x1);
                let left_positive = *f0 > 0.0;
                for _ in 0..40 {
                    let mid = 0.5 * (l + r);
                    match diff(mid) {
                        Some(f) if (f > 0.0) == left_positive => l = mid,
                        _ => r = mid,
                    }
                }
                let x = 0.5 * (l + r);
                let z = pa(x).min(pb(x));
                if !z.is_finite() {
                    continue;
                }
                let ridge = frame.at(t, x).extend(z);
                let Some(hit) = bvh.closest_point(ridge) else {
                    continue;
                };
                let steep = (ridge - hit.point).normalize_or_zero().z < cos_max_slope;
                let zm = swept_lower(cutter, grid, mid, j, x - mid.w);
                // A midway pass that only rolls over the part's rim there says nothing of what
                // a pass can reach: all of the ridge's material counts.
                let mid_on_rim = mid.rim.get(j).copied().unwrap_or(false);
                let left = if mid_on_rim {
                    0.0
                } else if zm.is_finite() && zm < z {
                    bvh.closest_point(frame.at(t, x).extend(zm))
                        .map_or(0.0, |m| m.distance)
                } else {
                    hit.distance
                };
                let c = Cusp {
                    height: (hit.distance - left).max(0.0),
                    at_end,
                    unreachable: left,
                    at: frame.at(t, x),
                    steep,
                };
                if best.is_none_or(|b: Cusp| c.height > b.height) {
                    best = Some(c);
                }
            }
            best
        })
        .collect()
}

/// The direction of the surface normal at a contact: for a ball the exact contact normal
/// (centre − CC), otherwise the touched triangle's normal (pointing up).
pub(crate) fn contact_normal(cutter: &Cutter, mesh: &TriMesh, tip: DVec3, cl: &ClPoint) -> DVec3 {
    if matches!(cutter.kind, CutterKind::Ball)
        && let Some(n) = (tip + DVec3::Z * cutter.radius() - cl.cc).try_normalize()
    {
        return n;
    }
    mesh.triangle_corners(cl.triangle)
        .and_then(|[a, b, c]| (b - a).cross(c - a).try_normalize())
        .map_or(DVec3::Z, |n| if n.z < 0.0 { -n } else { n })
}
