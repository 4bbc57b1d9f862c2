//! Deviation of the simulated stock from the design part: a signed distance at every stock
//! surface point over the region the part covers (positive: material left, negative: gouge)
//! and its statistics (max gouge, max remaining, scallop height distribution).

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
                if inside.is_empty() {
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
                        let x = p.to_array()[w];
                        let is_in = inside.iter().any(|[lo, hi]| x > *lo && x < *hi);
                        let value = if is_in { -hit.distance } else { hit.distance };
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
    Ok(statistics(samples, values, uncut, opts.histogram_bins))
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
