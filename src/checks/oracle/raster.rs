//! An independent check of 3-axis ball-end paths on a mesh: remaining height and gouge.
//!
//! It does not use the drop-cutter. The tool is a ball of radius R on a vertical shank, so the
//! volume it sweeps along the path is exactly the region above the lower envelope
//! L(x, y) = min over moves and s ∈ [0, 1] of c_z(s) − √(R² − |(x, y) − c_xy(s)|²) (c = ball
//! centre, only where the horizontal distance is ≤ R). For one straight move this minimum has a
//! closed form (the function is convex in s): with the move's XY direction u, the foot t_q and
//! distance d of (x, y) from its line, S = √(R² − d²) and slope m = dz/dt, the minimum lies at
//! t* = t_q − m·S/√(1 + m²), clamped to the move.
//!
//! The mesh is sampled densely (Metro's "similar triangles": each triangle split into k² similar
//! ones of area ≤ spacing²/2, one sample at each centroid). Samples are kept where the surface faces up at most
//! `max_slope_rad` from vertical and is the first surface a vertical ray from above meets there.
//! For each sample p with upward unit normal n:
//! - **gouge**: p_z − L(p_xy) where positive (vertical depth of the surface inside the swept
//!   volume; at least the normal depth);
//! - **remaining height**: the smallest t ≥ 0 with p + t·n in the swept volume, by marching and
//!   bisection (capped at `max_height_mm`; `uncovered` counts samples the tool never reaches
//!   within the cap).

use glam::{DVec2, DVec3};

use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::toolpath::Toolpath;
use crate::tools::CutterKind;

/// Options of [`ball_remaining_height`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RemainingOptions {
    /// Largest distance between samples on a triangle, mm.
    pub sample_spacing_mm: f64,
    /// Steepest surface checked, rad from horizontal.
    pub max_slope_rad: f64,
    /// Remaining heights are searched up to this, mm.
    pub max_height_mm: f64,
    /// Marching step along the normal, mm (bisection refines to 1e-6 mm).
    pub march_step_mm: f64,
    /// Only samples whose XY lies inside this box (min, max) count (None: all).
    pub region: Option<(DVec2, DVec2)>,
}

impl Default for RemainingOptions {
    fn default() -> Self {
        Self {
            sample_spacing_mm: 0.5,
            max_slope_rad: 70f64.to_radians(),
            max_height_mm: 1.0,
            march_step_mm: 0.002,
            region: None,
        }
    }
}

/// What the check found.
#[derive(Clone, Debug, PartialEq)]
pub struct RemainingReport {
    /// Remaining height per kept sample, mm, ascending (capped samples are left out).
    pub heights_mm: Vec<f64>,
    /// Samples the tool does not reach within `max_height_mm` along the normal.
    pub uncovered: usize,
    /// Largest gouge (vertical penetration of the surface into the swept volume), mm (≥ 0).
    pub max_gouge_mm: f64,
    /// Where the largest gouge is.
    pub max_gouge_at: Option<DVec3>,
    /// The 20 samples with the largest remaining height (uncovered ones as +∞), largest first.
    pub worst: Vec<(DVec3, f64)>,
}

impl RemainingReport {
    /// Number of samples checked.
    #[must_use]
    pub fn samples(&self) -> usize {
        self.heights_mm.len() + self.uncovered
    }

    /// The `q`-quantile (0 ≤ q ≤ 1) of the remaining height over all samples (uncovered ones
    /// count as infinite), mm.
    #[must_use]
    pub fn quantile(&self, q: f64) -> f64 {
        let n = self.samples();
        if n == 0 {
            return 0.0;
        }
        let k = ((q.clamp(0.0, 1.0) * (n - 1) as f64).round()) as usize;
        self.heights_mm.get(k).copied().unwrap_or(f64::INFINITY)
    }

    /// Fraction of samples whose remaining height is ≤ `h`.
    #[must_use]
    pub fn fraction_within(&self, h: f64) -> f64 {
        let n = self.samples();
        if n == 0 {
            return 1.0;
        }
        self.heights_mm.partition_point(|v| *v <= h) as f64 / n as f64
    }
}

/// Why the check could not run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RemainingError {
    /// The path's tool is not a ball end mill.
    #[error("the remaining-height check is exact for ball end mills only")]
    NotBall,
    /// The mesh has no usable triangle.
    #[error("mesh: {0}")]
    Mesh(String),
    /// An option is out of range.
    #[error("invalid option: {0}")]
    Option(String),
}

/// One straight move of the ball centre.
#[derive(Clone, Copy)]
struct Move {
    a: DVec3,
    b: DVec3,
}

/// The swept volume's lower envelope, with an XY bucket grid of moves.
struct Envelope {
    radius: f64,
    moves: Vec<Move>,
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    buckets: Vec<Vec<u32>>,
}

impl Envelope {
    fn new(path: &Toolpath, radius: f64) -> Self {
        let up = DVec3::Z * radius;
        let mut moves: Vec<Move> = path
            .poses
            .windows(2)
            .filter_map(|w| match w {
                [p, q] => Some(Move {
                    a: p.tip + up,
                    b: q.tip + up,
                }),
                _ => None,
            })
            .collect();
        if let [only] = path.poses.as_slice() {
            moves.push(Move {
                a: only.tip + up,
                b: only.tip + up,
            });
        }
        let mut lo = DVec2::splat(f64::MAX);
        let mut hi = DVec2::splat(f64::MIN);
        for m in &moves {
            lo = lo.min(m.a.truncate()).min(m.b.truncate());
            hi = hi.max(m.a.truncate()).max(m.b.truncate());
        }
        let cell = radius.max(1e-3);
        let origin = lo - DVec2::splat(radius);
        let size = (hi - lo + DVec2::splat(2.0 * radius)).max(DVec2::ZERO);
        let nx = ((size.x / cell).ceil() as usize).clamp(1, 4096);
        let ny = ((size.y / cell).ceil() as usize).clamp(1, 4096);
        let cell = cell.max(size.x / nx as f64).max(size.y / ny as f64);
        let mut buckets = vec![Vec::new(); nx * ny];
        for (i, m) in moves.iter().enumerate() {
            let mlo = m.a.truncate().min(m.b.truncate()) - DVec2::splat(radius);
            let mhi = m.a.truncate().max(m.b.truncate()) + DVec2::splat(radius);
            let (i0, j0) = Self::index(origin, cell, nx, ny, mlo);
            let (i1, j1) = Self::index(origin, cell, nx, ny, mhi);
            for j in j0..=j1 {
                for ii in i0..=i1 {
                    // Long moves (rapids) are filtered by their distance to the cell.
                    let c = origin + DVec2::new((ii as f64 + 0.5) * cell, (j as f64 + 0.5) * cell);
                    if seg_dist(c, m.a.truncate(), m.b.truncate()) <= radius + cell
                        && let (Some(bk), Ok(idx)) =
                            (buckets.get_mut(j * nx + ii), u32::try_from(i))
                    {
                        bk.push(idx);
                    }
                }
            }
        }
        Self {
            radius,
            moves,
            origin,
            cell,
            nx,
            ny,
            buckets,
        }
    }

    fn index(origin: DVec2, cell: f64, nx: usize, ny: usize, p: DVec2) -> (usize, usize) {
        let f = (p - origin) / cell;
        let i = if f.x.is_finite() {
            f.x.floor().clamp(0.0, (nx - 1) as f64) as usize
        } else {
            0
        };
        let j = if f.y.is_finite() {
            f.y.floor().clamp(0.0, (ny - 1) as f64) as usize
        } else {
            0
        };
        (i, j)
    }

    /// L(q): the lowest point of the swept ball over `q`, or +∞ where no move reaches.
    fn lower(&self, q: DVec2) -> f64 {
        let f = (q - self.origin) / self.cell;
        if !(f.x >= 0.0 && f.y >= 0.0 && f.x < self.nx as f64 && f.y < self.ny as f64) {
            return f64::INFINITY;
        }
        let (i, j) = (f.x as usize, f.y as usize);
        let Some(bucket) = self.buckets.get(j * self.nx + i) else {
            return f64::INFINITY;
        };
        bucket
            .iter()
            .filter_map(|&k| self.moves.get(k as usize))
            .map(|m| move_lower(m, q, self.radius))
            .fold(f64::INFINITY, f64::min)
    }
}

fn seg_dist(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let e = b - a;
    let l2 = e.length_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(e) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + e * s)
}

/// The lowest point over `q` of a ball of radius `r` whose centre moves from `m.a` to `m.b`.
fn move_lower(m: &Move, q: DVec2, r: f64) -> f64 {
    let (a, b) = (m.a.truncate(), m.b.truncate());
    let e = b - a;
    let len = e.length();
    if len < 1e-12 {
        let d2 = q.distance_squared(a);
        if d2 > r * r {
            return f64::INFINITY;
        }
        return m.a.z.min(m.b.z) - (r * r - d2).sqrt();
    }
    let u = e / len;
    let rel = q - a;
    let tq = rel.dot(u);
    let d = u.perp_dot(rel);
    let s2 = r * r - d * d;
    if s2 < 0.0 {
        return f64::INFINITY;
    }
    let s = s2.sqrt();
    let (lo, hi) = ((tq - s).max(0.0), (tq + s).min(len));
    if lo > hi {
        return f64::INFINITY;
    }
    let slope = (m.b.z - m.a.z) / len;
    let t = (tq - slope * s / (1.0 + slope * slope).sqrt()).clamp(lo, hi);
    let dt = t - tq;
    m.a.z + slope * t - (s2 - dt * dt).max(0.0).sqrt()
}

/// Sample points (with upward unit normals) of the triangles facing up within the slope limit
/// and visible from above.
fn samples(mesh: &TriMesh, bvh: &MeshBvh, opts: &RemainingOptions) -> Vec<(DVec3, DVec3)> {
    let cos_max = opts.max_slope_rad.cos();
    let top = bvh.bbox().max.z + 1.0;
    let mut out = Vec::new();
    for t in 0..mesh.triangles.len() {
        let Some([p0, p1, p2]) = mesh.triangle_corners(t) else {
            continue;
        };
        let Some(mut n) = (p1 - p0).cross(p2 - p0).try_normalize() else {
            continue;
        };
        if n.z < 0.0 {
            n = -n;
        }
        if n.z < cos_max {
            continue;
        }
        // k² similar sub-triangles of area ≤ spacing²/2 each (by area, so slivers are not
        // oversampled).
        let area = 0.5 * (p1 - p0).cross(p2 - p0).length();
        let sp = opts.sample_spacing_mm;
        let k = (area / (0.5 * sp * sp)).sqrt().ceil().clamp(1.0, 1000.0) as usize;
        let kf = k as f64;
        let mut push = |u: f64, v: f64| {
            let p = p0 + (p1 - p0) * u + (p2 - p0) * v;
            if let Some((lo, hi)) = opts.region
                && !(p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y)
            {
                return;
            }
            let visible = bvh
                .ray_cast(p.truncate().extend(top), DVec3::NEG_Z, f64::INFINITY)
                .is_some_and(|h| h.point.z <= p.z + 1e-6);
            if visible {
                out.push((p, n));
            }
        };
        for i in 0..k {
            for j in 0..k - i {
                push((i as f64 + 1.0 / 3.0) / kf, (j as f64 + 1.0 / 3.0) / kf);
                if i + j + 2 <= k {
                    push((i as f64 + 2.0 / 3.0) / kf, (j as f64 + 2.0 / 3.0) / kf);
                }
            }
        }
    }
    out
}

/// Remaining height and gouge of a ball-end tool path over `mesh` (see the module docs).
///
/// # Errors
/// [`RemainingError::NotBall`] for another cutter, [`RemainingError::Mesh`] when the mesh has
/// no usable triangle, [`RemainingError::Option`] for non-positive sizes.
pub fn ball_remaining_height(
    mesh: &TriMesh,
    path: &Toolpath,
    opts: &RemainingOptions,
) -> Result<RemainingReport, RemainingError> {
    ball_remaining_height_where(mesh, path, opts, &|_, _| true)
}

/// [`ball_remaining_height`] over the samples `keep(point, upward unit normal)` accepts only (a
/// reach mask, a region of interest).
///
/// # Errors
/// As [`ball_remaining_height`].
pub fn ball_remaining_height_where(
    mesh: &TriMesh,
    path: &Toolpath,
    opts: &RemainingOptions,
    keep: &(dyn Fn(DVec3, DVec3) -> bool + Sync),
) -> Result<RemainingReport, RemainingError> {
    use rayon::prelude::*;
    if path.tool.cutter.kind != CutterKind::Ball {
        return Err(RemainingError::NotBall);
    }
    for (what, v) in [
        ("sample spacing", opts.sample_spacing_mm),
        ("max height", opts.max_height_mm),
        ("march step", opts.march_step_mm),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(RemainingError::Option(format!(
                "{what} must be positive, got {v}"
            )));
        }
    }
    let bvh = MeshBvh::new(mesh).map_err(|e| RemainingError::Mesh(e.to_string()))?;
    let env = Envelope::new(path, path.tool.cutter.radius());
    let pts: Vec<(DVec3, DVec3)> = samples(mesh, &bvh, opts)
        .into_par_iter()
        .filter(|&(p, n)| keep(p, n))
        .collect();
    let inside = |p: DVec3| p.z >= env.lower(p.truncate());
    let results: Vec<(Option<f64>, f64)> = pts
        .par_iter()
        .map(|&(p, n)| {
            let gouge = p.z - env.lower(p.truncate());
            if gouge >= 0.0 {
                return (Some(0.0), gouge);
            }
            let mut t0 = 0.0;
            let mut t = opts.march_step_mm;
            while t <= opts.max_height_mm + opts.march_step_mm {
                if inside(p + n * t) {
                    let (mut lo, mut hi) = (t0, t);
                    while hi - lo > 1e-6 {
                        let mid = 0.5 * (lo + hi);
                        if inside(p + n * mid) {
                            hi = mid;
                        } else {
                            lo = mid;
                        }
                    }
                    return (Some(hi), 0.0);
                }
                t0 = t;
                t += opts.march_step_mm;
            }
            (None, 0.0)
        })
        .collect();
    let mut heights = Vec::with_capacity(results.len());
    let mut uncovered = 0;
    let mut max_gouge = 0.0;
    let mut max_gouge_at = None;
    for ((h, g), (p, _)) in results.iter().zip(&pts) {
        match h {
            Some(v) => heights.push(*v),
            None => uncovered += 1,
        }
        if *g > max_gouge {
            max_gouge = *g;
            max_gouge_at = Some(*p);
        }
    }
    heights.sort_by(f64::total_cmp);
    let mut worst: Vec<(DVec3, f64)> = results
        .iter()
        .zip(&pts)
        .map(|((h, _), (p, _))| (*p, h.unwrap_or(f64::INFINITY)))
        .collect();
    worst.sort_by(|a, b| b.1.total_cmp(&a.1));
    worst.truncate(20);
    Ok(RemainingReport {
        heights_mm: heights,
        uncovered,
        max_gouge_mm: max_gouge,
        max_gouge_at,
        worst,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::{MoveKind, Pose, ToolRecord};
    use crate::tools::Cutter;

    /// Two parallel ball passes at distance s over a plane leave the closed-form cusp
    /// R − √(R² − s²/4) midway, and nothing right under the passes.
    #[test]
    fn two_passes_over_a_plane() {
        let mesh = TriMesh::new(
            vec![
                DVec3::new(-10.0, -10.0, 0.0),
                DVec3::new(10.0, -10.0, 0.0),
                DVec3::new(10.0, 10.0, 0.0),
                DVec3::new(-10.0, 10.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        let cutter = Cutter::new(CutterKind::Ball, 6.0).unwrap();
        let s = 2.0;
        let pose =
            |x: f64, y: f64| Pose::new(MoveKind::Cut, DVec3::new(x, y, 0.0), DVec3::Z, 100.0);
        let path = Toolpath::new(
            ToolRecord {
                spec: "ball:d=6".into(),
                cutter,
            },
            vec![
                pose(-12.0, 0.0),
                pose(12.0, 0.0),
                pose(12.0, s),
                pose(-12.0, s),
            ],
        );
        let opts = RemainingOptions {
            sample_spacing_mm: 0.05,
            region: Some((DVec2::new(-1.0, 0.0), DVec2::new(1.0, s))),
            march_step_mm: 0.001,
            ..RemainingOptions::default()
        };
        let rep = ball_remaining_height(&mesh, &path, &opts).unwrap();
        let want = 3.0 - (9.0 - s * s / 4.0_f64).sqrt();
        let max = rep.quantile(1.0);
        assert!((max - want).abs() < 0.05 * want, "{max} vs {want}");
        assert!(rep.max_gouge_mm < 1e-9);
        // A pass 0.05 mm too low gouges by 0.05 mm.
        let mut low = path.clone();
        for p in &mut low.poses {
            p.tip.z -= 0.05;
        }
        let rep = ball_remaining_height(&mesh, &low, &opts).unwrap();
        assert!(
            (rep.max_gouge_mm - 0.05).abs() < 1e-4,
            "{}",
            rep.max_gouge_mm
        );
    }
}
