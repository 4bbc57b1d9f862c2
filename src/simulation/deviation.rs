//! Deviation of the simulated stock from the design part, for closed parts and open sheets
//! (a surface model, one face of a part) alike; the command line and the workstation both
//! measure here, so they report the same numbers for the same run:
//! - [`deviation`]: a signed distance at every stock surface point over the region the part
//!   covers (positive: material left, negative: gouge) and its statistics (max gouge, max
//!   remaining, scallop height distribution);
//! - [`top_deviation`]: the signed distance of the cut stock's top, one value per vertex of
//!   [`DexelStock::height_field_mesh`] (what the workstation colours), with the deepest gouge
//!   and the 99th percentile of the material left over the part.
//!
//! Inside a closed part is decided by ray crossings; an open sheet has no inside, so there the
//! side is the one the closest triangle's normal points to.

use glam::DVec3;
use rayon::prelude::*;

use super::SimError;
use super::stock::{DexelStock, mesh_intervals};
use super::surface::SurfacePoint;
use crate::diagnostics::Progress;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;

/// Settings of the deviation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviationOptions {
    /// Leave out stock points on the initial stock boundary (never cut), counted apart.
    pub skip_uncut: bool,
    /// Distance along the ray within which a point counts as on the initial boundary, mm.
    pub uncut_tolerance_mm: f64,
    /// Bins of the remaining-material histogram.
    pub histogram_bins: usize,
}

impl Default for DeviationOptions {
    fn default() -> Self {
        Self {
            skip_uncut: false,
            uncut_tolerance_mm: 1e-4,
            histogram_bins: 20,
        }
    }
}

/// Counts of values in equal bins from `min_mm` to `max_mm`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Histogram {
    /// Lower edge of the first bin, mm.
    pub min_mm: f64,
    /// Upper edge of the last bin, mm.
    pub max_mm: f64,
    /// Count per bin.
    pub counts: Vec<u64>,
}

/// Deviation of the stock from the part.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct DeviationReport {
    /// Stock surface points measured (on rays that cross the part).
    pub points: usize,
    /// Points left out because they lie on the never-cut initial stock boundary.
    pub uncut_points: usize,
    /// Deepest gouge (material removed inside the part), mm, ≥ 0.
    pub max_gouge_mm: f64,
    /// Where the deepest gouge is.
    pub max_gouge_at: Option<[f64; 3]>,
    /// Largest remaining material (distance from a stock point outside the part to it), mm.
    pub max_remaining_mm: f64,
    /// Where it is.
    pub max_remaining_at: Option<[f64; 3]>,
    /// Mean remaining material over points outside the part, mm.
    pub mean_remaining_mm: f64,
    /// Remaining material (scallop) percentiles 50, 90, 99 over points outside the part, mm.
    pub remaining_percentiles_mm: [f64; 3],
    /// Histogram of remaining material over points outside the part.
    pub remaining_histogram: Histogram,
    /// Whether the part is closed (sign by inside/outside) or an open sheet (sign by the
    /// closest triangle's normal).
    pub closed_part: bool,
    /// The measured points.
    #[serde(skip)]
    pub samples: Vec<SurfacePoint>,
    /// Signed distance of each sample, mm (same order).
    #[serde(skip)]
    pub values: Vec<f64>,
}

/// Signed distances of the stock surface to `part` (a closed, outward-wound mesh) and their
/// statistics. Only rays that cross the part count ("the region the part covers").
///
/// # Errors
/// [`SimError::Part`] when the part has no usable triangle, [`SimError::Cancelled`].
pub fn deviation(
    stock: &DexelStock,
    part: &TriMesh,
    opts: &DeviationOptions,
    progress: &Progress,
) -> Result<DeviationReport, SimError> {
    let bvh = MeshBvh::new(part).map_err(|e| SimError::Part(e.to_string()))?;
    let bounds = part.bbox();
    let closed = is_closed(part);
    let mut samples = Vec::new();
    let mut values = Vec::new();
    let mut uncut = 0usize;
    let families = stock.families.len().max(1);
    for (f, fam) in stock.families.iter().enumerate() {
        progress.check().map_err(|_| SimError::Cancelled)?;
        let (_, _, w) = fam.axis.axes();
        let dir = fam.axis.direction();
        let per_ray: Vec<(Vec<(SurfacePoint, f64)>, usize)> = (0..fam.dexels.len())
            .into_par_iter()
            .map(|k| {
                let mut out = Vec::new();
                let mut skipped = 0;
                let Some(d) = fam.dexels.get(k) else {
                    return (out, skipped);
                };
                if d.intervals().is_empty() || progress.is_cancelled() {
                    return (out, skipped);
                }
                let (i, j) = (k % fam.nu, k / fam.nu);
                let origin = fam.ray_origin(i, j);
                let inside = mesh_intervals(&bvh, &bounds, origin, fam.axis);
                if closed && inside.is_empty() {
                    return (out, skipped);
                }
                for [a, b] in d.intervals() {
                    for (s, n) in [(*a, -dir), (*b, dir)] {
                        let p = origin + dir * f64::from(s);
                        if opts.skip_uncut
                            && stock.on_initial_boundary(p, fam.axis, opts.uncut_tolerance_mm)
                        {
                            skipped += 1;
                            continue;
                        }
                        let Some(hit) = bvh.closest_point(p) else {
                            continue;
                        };
                        let value = if closed {
                            let x = p.to_array()[w];
                            let is_in = inside.iter().any(|[lo, hi]| x > *lo && x < *hi);
                            if is_in { -hit.distance } else { hit.distance }
                        } else {
                            // Only points straight above or below the sheet, on stock faces
                            // turned the way the sheet faces, count: a sheet bounds material
                            // on one side only, and the stock's far side is not its surface.
                            match sheet_side(part, &bvh, p, dir, &hit, Some(n)) {
                                Some(v) => v,
                                None => continue,
                            }
                        };
                        out.push((
                            SurfacePoint {
                                position: p,
                                normal: n,
                                axis: fam.axis,
                                ray: k,
                            },
                            value,
                        ));
                    }
                }
                (out, skipped)
            })
            .collect();
        for (pts, skipped) in per_ray {
            uncut += skipped;
            for (p, v) in pts {
                samples.push(p);
                values.push(v);
            }
        }
        #[allow(clippy::cast_precision_loss)]
        progress.set((f + 1) as f64 / families as f64);
    }
    progress.check().map_err(|_| SimError::Cancelled)?;
    let mut report = statistics(samples, values, uncut, opts.histogram_bins);
    report.closed_part = closed;
    Ok(report)
}

/// The signed distance of `p` from an open sheet when `p` lies straight above or below it:
/// the line through `p` along `ray` (the dexel's direction) crosses the sheet, and `p` lies
/// along the closest triangle's normal (within 25°); positive on the normal's side. When
/// `facing` (the stock surface's outward normal at `p`) is given, the stock surface must face
/// the way the sheet does (a sheet bounds material on one side only, and the stock's far side
/// is not its surface).
fn sheet_side(
    part: &TriMesh,
    bvh: &MeshBvh,
    p: DVec3,
    ray: DVec3,
    hit: &crate::geometry::bvh::ClosestHit,
    facing: Option<DVec3>,
) -> Option<f64> {
    let n = part
        .triangles
        .get(hit.triangle)
        .map_or(DVec3::Z, |t| triangle_normal(part, *t));
    if facing.is_some_and(|f| f.dot(n) <= 0.0) {
        return None;
    }
    let along = (p - hit.point).dot(n);
    if along.abs() < 0.9 * hit.distance {
        return None;
    }
    // Beside the sheet's outline, the line misses it both ways.
    let crosses = bvh.ray_cast(p, ray, f64::INFINITY).is_some()
        || bvh.ray_cast(p, -ray, f64::INFINITY).is_some();
    crosses.then_some(along)
}

/// Whether `mesh` bounds a solid: every edge is shared by exactly two triangles, vertices
/// being the same where their positions are equal (so face-by-face tessellations and meshes
/// split at creases for display count as closed when their seams meet).
#[must_use]
pub fn is_closed(mesh: &TriMesh) -> bool {
    use std::collections::HashMap;
    let key = |p: DVec3| (p + DVec3::ZERO).to_array().map(f64::to_bits);
    let mut ids: HashMap<[u64; 3], u32> = HashMap::with_capacity(mesh.positions.len());
    let canonical: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let next = u32::try_from(ids.len()).unwrap_or(u32::MAX);
            *ids.entry(key(*p)).or_insert(next)
        })
        .collect();
    let id = |v: u32| canonical.get(v as usize).copied().unwrap_or(u32::MAX);
    let mut edges: HashMap<(u32, u32), u32> = HashMap::with_capacity(mesh.triangles.len() * 3);
    for t in &mesh.triangles {
        let [a, b, c] = t.map(id);
        if a == b || b == c || c == a {
            continue;
        }
        for (a, b) in [(a, b), (b, c), (c, a)] {
            *edges.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    !edges.is_empty() && edges.values().all(|&n| n == 2)
}

/// Unit normal of triangle `t` of `mesh` (+Z when degenerate).
fn triangle_normal(mesh: &TriMesh, t: [u32; 3]) -> DVec3 {
    let p = |i: u32| mesh.positions.get(i as usize).copied().unwrap_or_default();
    let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
    (b - a).cross(c - a).try_normalize().unwrap_or(DVec3::Z)
}

/// The deviation of the cut stock's top from the part (see [`top_deviation`]).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct TopDeviation {
    /// Signed distance of each top point from the part, mm, in the order of the vertices of
    /// [`DexelStock::height_field_mesh`]: positive where material is left, negative where the
    /// part was cut into. Points beside the part's outline get their (positive) distance.
    #[serde(skip)]
    pub values_mm: Vec<f64>,
    /// Top points measured (Z rays holding material).
    pub points: usize,
    /// Of these, the points straight above or below the part.
    pub over_part: usize,
    /// Deepest cut into the part, mm (≥ 0).
    pub max_gouge_mm: f64,
    /// 99th percentile of the material left over the part, mm.
    pub remaining_p99_mm: f64,
    /// Whether the part is closed (see [`is_closed`]).
    pub closed_part: bool,
}

/// The signed deviation of the top of every Z ray holding material from `part`: straight above
/// or below the part (along the closest triangle's normal, within 25°) the distance signed by
/// the side (inside/outside for a closed part, the normal's side for an open sheet); beside
/// the part's outline, the distance as material left.
///
/// # Errors
/// [`SimError::Part`] when the part has no usable triangle, [`SimError::Cancelled`].
pub fn top_deviation(
    stock: &DexelStock,
    part: &TriMesh,
    progress: &Progress,
) -> Result<TopDeviation, SimError> {
    let bvh = MeshBvh::new(part).map_err(|e| SimError::Part(e.to_string()))?;
    let bounds = part.bbox();
    let closed = is_closed(part);
    let Some(fam) = stock.families.first() else {
        return Ok(TopDeviation::default());
    };
    let tops: Vec<DVec3> = fam
        .dexels
        .iter()
        .enumerate()
        .filter_map(|(k, d)| {
            let [_, top] = d.intervals().last()?;
            Some(fam.point(k % fam.nu, k / fam.nu, f64::from(*top)))
        })
        .collect();
    let measured: Vec<(f64, bool)> = tops
        .par_iter()
        .map(|p| {
            let Some(hit) = bvh.closest_point(*p) else {
                return (0.0, false);
            };
            match sheet_side(part, &bvh, *p, DVec3::Z, &hit, None) {
                Some(_) if closed => {
                    // The signed distance of `p` (`signed_distance`) with this closest point:
                    // negative inside the part, and +0 on its surface.
                    let inside = hit.distance > 0.0
                        && mesh_intervals(&bvh, &bounds, *p, super::dexel::RayAxis::Z)
                            .iter()
                            .any(|[lo, hi]| p.z > *lo && p.z < *hi);
                    (if inside { -hit.distance } else { hit.distance }, true)
                }
                Some(along) => (along, true),
                None => (hit.distance, false),
            }
        })
        .collect();
    progress.check().map_err(|_| SimError::Cancelled)?;
    let values_mm: Vec<f64> = measured.iter().map(|(v, _)| *v).collect();
    let max_gouge_mm = values_mm
        .iter()
        .fold(0.0_f64, |g, &d| if d < 0.0 { g.max(-d) } else { g });
    let mut over: Vec<f64> = measured
        .iter()
        .filter(|(v, over)| *over && *v >= 0.0)
        .map(|(v, _)| *v)
        .collect();
    over.sort_by(f64::total_cmp);
    #[allow(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        clippy::cast_precision_loss
    )]
    let remaining_p99_mm = over
        .len()
        .checked_sub(1)
        .and_then(|n| over.get((n as f64 * 0.99).round() as usize).copied())
        .unwrap_or(0.0);
    Ok(TopDeviation {
        points: values_mm.len(),
        over_part: measured.iter().filter(|(_, o)| *o).count(),
        values_mm,
        max_gouge_mm,
        remaining_p99_mm,
        closed_part: closed,
    })
}

fn statistics(
    samples: Vec<SurfacePoint>,
    values: Vec<f64>,
    uncut: usize,
    bins: usize,
) -> DeviationReport {
    let mut r = DeviationReport {
        points: values.len(),
        uncut_points: uncut,
        ..DeviationReport::default()
    };
    let at = |k: usize| samples.get(k).map(|p: &SurfacePoint| p.position.to_array());
    let mut remaining: Vec<f64> = Vec::new();
    for (k, v) in values.iter().enumerate() {
        if *v < 0.0 {
            if -v > r.max_gouge_mm {
                r.max_gouge_mm = -v;
                r.max_gouge_at = at(k);
            }
        } else {
            remaining.push(*v);
            if *v > r.max_remaining_mm || r.max_remaining_at.is_none() {
                r.max_remaining_mm = *v;
                r.max_remaining_at = at(k);
            }
        }
    }
    remaining.sort_by(f64::total_cmp);
    if !remaining.is_empty() {
        #[allow(clippy::cast_precision_loss)]
        let n = remaining.len() as f64;
        r.mean_remaining_mm = remaining.iter().sum::<f64>() / n;
        let pick = |q: f64| {
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let k = ((n - 1.0) * q).round() as usize;
            remaining.get(k).copied().unwrap_or(0.0)
        };
        r.remaining_percentiles_mm = [pick(0.5), pick(0.9), pick(0.99)];
        let bins = bins.max(1);
        let max = r.max_remaining_mm.max(1e-12);
        let mut counts = vec![0u64; bins];
        for v in &remaining {
            #[allow(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                clippy::cast_precision_loss
            )]
            let b = ((v / max) * bins as f64).floor() as usize;
            if let Some(c) = counts.get_mut(b.min(bins - 1)) {
                *c += 1;
            }
        }
        r.remaining_histogram = Histogram {
            min_mm: 0.0,
            max_mm: max,
            counts,
        };
    }
    r.samples = samples;
    r.values = values;
    r
}

/// Signed distance of one point to a part (positive outside); `None` for a non-finite point.
#[must_use]
pub fn signed_distance(
    bvh: &MeshBvh,
    part_bounds: &crate::geometry::Aabb,
    p: DVec3,
) -> Option<f64> {
    let hit = bvh.closest_point(p)?;
    let inside = mesh_intervals(bvh, part_bounds, p, super::dexel::RayAxis::Z)
        .iter()
        .any(|[lo, hi]| p.z > *lo && p.z < *hi);
    Some(if inside { -hit.distance } else { hit.distance })
}
