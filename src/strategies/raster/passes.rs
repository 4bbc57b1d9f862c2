//! Coarse passes: where a pass line lies inside the boundary, its drop-cutter samples on a
//! regular grid along the line, and the cusp between two neighbouring passes.

use glam::{DVec2, DVec3};

use super::Frame;
use super::stepover::profile;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::tools::dropcutter::{ClPoint, drop_cutter};

use crate::tools::{Cutter, CutterKind};

/// Where passes may run.
pub(crate) enum Region<'a> {
    /// Over the part's XY outline: a vertical ray through the tool axis meets the mesh.
    Silhouette(&'a MeshBvh, f64),
    /// Inside a closed polygon (even-odd rule).
    Polygon(&'a [DVec2]),
}

impl Region<'_> {
    pub(crate) fn contains(&self, p: DVec2) -> bool {
        match self {
            Region::Silhouette(bvh, top) => bvh
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
}

/// One pass sampled on the grid `t_j = t0 + j·dt`.
pub(crate) struct CoarsePass {
    /// Offset across the passes, mm.
    pub w: f64,
    /// Drop-cutter result per grid point (None outside the region or off the mesh).
    pub cl: Vec<Option<ClPoint>>,
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
    let inside: Vec<bool> = xy.iter().map(|p| region.contains(*p)).collect();
    let cl: Vec<Option<ClPoint>> = drop_cutter(bvh, mesh, cutter, &xy)
        .into_iter()
        .zip(&inside)
        .map(|(c, &i)| if i { c } else { None })
        .collect();
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
    CoarsePass { w, cl, runs }
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

/// Cusp heights between two neighbouring passes per grid point: the highest point of the two
/// tools' envelope in the vertical section across the passes (the instantaneous profiles, an
/// upper bound of the swept envelope), measured as its distance to the mesh, i.e. the remaining
/// material thickness there (exact on a plane, and it sees curvature across the passes). None
/// where either pass has no CL point or the CL rises across the passes more steeply than
/// `max_slope`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn cusps(
    frame: &Frame,
    grid: &[f64],
    a: &CoarsePass,
    b: &CoarsePass,
    cutter: &Cutter,
    bvh: &MeshBvh,
    cos_max_slope: f64,
) -> Vec<Option<f64>> {
    use rayon::prelude::*;
    let (wa, wb) = (a.w, b.w);
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
            let pa = |x: f64| ca.z + profile(cutter, x - wa);
            let pb = |x: f64| cb.z + profile(cutter, x - wb);
            // pa − pb increases from wa to wb: bisection for the crossing.
            let (mut lo, mut hi) = (wa.min(wb), wa.max(wb));
            let sign = if wa <= wb { 1.0 } else { -1.0 };
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if sign * (pa(mid) - pb(mid)) < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let x = 0.5 * (lo + hi);
            let z = pa(x).min(pb(x));
            let hit = bvh.closest_point(frame.at(t, x).extend(z))?;
            Some(hit.distance)
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
