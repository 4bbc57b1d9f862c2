//! Data reduction of a whole part, as the workstation's data-reduction view runs it: the part's
//! regular Z-map over its XY bounding box (vertical ray casts, parallel over rows, with progress
//! and cancel; for a B-rep part each hit is refined onto the exact surface of the face it hit, so
//! the Z-map carries no tessellation error), the truncated SVD with the rank from the tolerance, optional resampling for a
//! ball end mill, and the reduced surface evaluated back at every original node with its signed
//! error (the error map).

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::{
    ReduceError, ReduceOptions, Reduction, XyReduction, point_spacing, reduce, reduce_xy_zmap,
    resampled_count,
};
use crate::diagnostics::Progress;
use crate::geometry::bvh::{MeshBvh, RayHit};
use crate::geometry::mesh::TriMesh;
use crate::geometry::surface::SurfaceGeom;
use crate::geometry::zmap::{
    EmptyCellFill, Grid, XyZmap, grid_mesh, invert_xy, xy_mesh, xy_zmap_from_points,
};

/// XY tolerance of the exact refinement, mm.
const EXACT_XY_TOL_MM: f64 = 1e-7;

/// The exact surfaces behind a tessellated B-rep part: the face each triangle belongs to and
/// each face's carrier surface (`None` where there is none).
#[derive(Clone, Debug, Default)]
pub struct ExactFaces {
    /// Face index of every triangle of the mesh.
    pub face_of_triangle: Vec<u32>,
    /// Carrier surface of every face.
    pub surfaces: Vec<Option<Arc<SurfaceGeom>>>,
}

impl ExactFaces {
    /// The height of the face hit by `hit` exactly above the node `xy`: Newton on x(u,v), y(u,v)
    /// from the surface point closest to the hit. `None` (keep the mesh's height) when the
    /// triangle has no surface, Newton does not converge, or the answer lies more than
    /// `max_gap_mm` from the mesh (another sheet of a surface folding over itself).
    fn height(&self, hit: &RayHit, xy: DVec2, max_gap_mm: f64) -> Option<f64> {
        let face = *self.face_of_triangle.get(hit.triangle)? as usize;
        let surface = self.surfaces.get(face)?.as_deref()?;
        let seed = surface.closest_point(hit.point, surface.domain(), None).uv;
        let uv = invert_xy(surface, xy, seed, EXACT_XY_TOL_MM)?;
        let z = surface.point(uv.x, uv.y).z;
        (z.is_finite() && (z - hit.point.z).abs() <= max_gap_mm).then_some(z)
    }
}

/// Most nodes a part Z-map may have (the SVD holds three dense matrices of this size).
pub const MAX_PART_ZMAP_NODES: usize = 4_000_000;

/// A regular Z-map of a part over its XY bounding box.
#[derive(Clone, Debug, PartialEq)]
pub struct PartZmap {
    /// Heights (row ↔ y, column ↔ x), mm.
    pub grid: Grid,
    /// XY of node (0, 0), mm.
    pub origin: DVec2,
    /// Grid step (rows and columns), mm.
    pub step_mm: f64,
    /// Nodes above which the mesh has no surface (they hold the part's lowest Z).
    pub misses: usize,
    /// Nodes whose height is the exact surface's (the others are the mesh's).
    pub exact_nodes: usize,
}

impl PartZmap {
    /// Extent along X covered by the columns, mm.
    #[must_use]
    pub fn width_mm(&self) -> f64 {
        self.grid.cols().saturating_sub(1) as f64 * self.step_mm
    }

    /// Extent along Y covered by the rows, mm.
    #[must_use]
    pub fn height_mm(&self) -> f64 {
        self.grid.rows().saturating_sub(1) as f64 * self.step_mm
    }
}

/// Rows and columns of a Z-map at `step_mm` over an XY extent `size` (mm): ⌈size/step⌉ + 1 each
/// (a size within 1e-9 of a whole number of steps counts as that number: tessellated bounds
/// carry rounding).
#[must_use]
pub fn zmap_size(size: DVec2, step_mm: f64) -> (usize, usize) {
    let count = |len: f64| {
        let k = (len.max(0.0) / step_mm - 1e-9).ceil().max(0.0);
        if k.is_finite() && k < 1.0e9 {
            k as usize + 1
        } else {
            usize::MAX
        }
    };
    (count(size.y), count(size.x))
}

/// The Z-map of the mesh behind `bvh` at `step_mm` over its XY bounding box (the grid starts at
/// the box's lower corner and covers it, the last row and column may reach past it by less than
/// a step). Each node holds the highest point of the mesh above it, refined onto the exact
/// surface of the face hit when `exact` gives one; nodes the mesh does not cover hold the mesh's
/// lowest Z (the floor the part stands on).
///
/// # Errors
/// [`ReduceError::Option`] for a non-positive step, [`ReduceError::Shape`] for a grid of more
/// than [`MAX_PART_ZMAP_NODES`] nodes, [`ReduceError::Cancelled`] when `progress` is cancelled.
pub fn part_zmap(
    bvh: &MeshBvh,
    exact: Option<&ExactFaces>,
    step_mm: f64,
    progress: &Progress,
) -> Result<PartZmap, ReduceError> {
    if !(step_mm > 0.0 && step_mm.is_finite()) {
        return Err(ReduceError::Option(format!(
            "grid step must be a positive length in mm, got {step_mm}"
        )));
    }
    let b = bvh.bbox();
    let origin = DVec2::new(b.min.x, b.min.y);
    let (rows, cols) = zmap_size(DVec2::new(b.max.x - b.min.x, b.max.y - b.min.y), step_mm);
    if rows
        .checked_mul(cols)
        .is_none_or(|n| n > MAX_PART_ZMAP_NODES)
    {
        return Err(ReduceError::Shape(format!(
            "a {step_mm} mm step gives {rows}×{cols} nodes, more than {MAX_PART_ZMAP_NODES}; \
             choose a coarser step"
        )));
    }
    let top = b.max.z + 1.0;
    let floor = b.min.z;
    // Nodes on the box's edges are moved inside by a hair: a ray exactly along the part's
    // outline slips past its boundary triangles.
    let eps = 1e-9 * (1.0 + (b.max - b.min).length());
    let (lo, hi) = (
        DVec2::new(b.min.x, b.min.y) + eps,
        DVec2::new(b.max.x, b.max.y) - eps,
    );
    // The exact surface may lie off the chordal mesh by its sag; more than this is another sheet.
    let max_gap = (0.01 * (b.max - b.min).length()).clamp(0.01, 1.0);
    let done = AtomicUsize::new(0);
    let row_values: Vec<Option<Vec<(f64, Node)>>> = (0..rows)
        .into_par_iter()
        .map(|r| {
            if progress.is_cancelled() {
                return None;
            }
            let y = origin.y + r as f64 * step_mm;
            let y = if y > hi.y && y - hi.y <= 2.0 * eps {
                hi.y
            } else {
                y.max(lo.y)
            };
            let row = (0..cols)
                .map(|c| {
                    let x = origin.x + c as f64 * step_mm;
                    let x = if x > hi.x && x - hi.x <= 2.0 * eps {
                        hi.x
                    } else {
                        x.max(lo.x)
                    };
                    let Some(hit) =
                        bvh.ray_cast(DVec3::new(x, y, top), DVec3::NEG_Z, f64::INFINITY)
                    else {
                        return (floor, Node::Miss);
                    };
                    match exact.and_then(|e| e.height(&hit, DVec2::new(x, y), max_gap)) {
                        Some(z) => (z, Node::Exact),
                        None => (hit.point.z, Node::Mesh),
                    }
                })
                .collect();
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress.set(n as f64 / rows as f64);
            Some(row)
        })
        .collect();
    let mut values = Vec::with_capacity(rows * cols);
    let (mut misses, mut exact_nodes) = (0, 0);
    for row in row_values {
        let row = row.ok_or(ReduceError::Cancelled)?;
        misses += row.iter().filter(|(_, n)| *n == Node::Miss).count();
        exact_nodes += row.iter().filter(|(_, n)| *n == Node::Exact).count();
        values.extend(row.into_iter().map(|(z, _)| z));
    }
    Ok(PartZmap {
        grid: Grid::new(rows, cols, values)?,
        origin,
        step_mm,
        misses,
        exact_nodes,
    })
}

/// Where a node's height came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Node {
    /// No surface above it: the floor.
    Miss,
    /// The tessellated mesh.
    Mesh,
    /// The exact surface of the face hit.
    Exact,
}

/// A part's Z-map, its reduction, and the reduced surface back at the Z-map's nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct PartReduction {
    /// The Z-map that was reduced.
    pub zmap: PartZmap,
    /// The reduction (singular values, rank, reduced grid, errors).
    pub reduction: Reduction,
    /// The reduced model evaluated at every node of `zmap` (bilinear in the reduced grid), mm.
    pub approximation: Grid,
    /// Signed error Z′ − Z at every node of `zmap`, mm (positive: the model lies above the part).
    pub signed_error: Grid,
}

impl PartReduction {
    /// The reduced surface at the original nodes as a mesh (one vertex per node, row-major, so
    /// `signed_error`'s values are its per-vertex scalars).
    #[must_use]
    pub fn approximation_mesh(&self) -> TriMesh {
        grid_mesh(
            &self.approximation,
            self.zmap.origin,
            self.zmap.width_mm(),
            self.zmap.height_mm(),
        )
    }

    /// The reduced grid itself as a mesh over the same extent (what an STL export writes).
    #[must_use]
    pub fn reduced_mesh(&self) -> TriMesh {
        grid_mesh(
            &self.reduction.reduced,
            self.zmap.origin,
            self.zmap.width_mm(),
            self.zmap.height_mm(),
        )
    }
}

/// Reduce the Z-map of the part behind `bvh` at `step_mm` (see [`part_zmap`] and [`reduce`]).
/// With resampling in `opts`, its grid step is taken from `step_mm`.
///
/// # Errors
/// As [`part_zmap`] and [`reduce`].
pub fn reduce_part(
    bvh: &MeshBvh,
    exact: Option<&ExactFaces>,
    step_mm: f64,
    opts: &ReduceOptions,
    progress: &Progress,
) -> Result<PartReduction, ReduceError> {
    let zmap = part_zmap(bvh, exact, step_mm, progress)?;
    let mut opts = *opts;
    if let Some(rs) = &mut opts.resampling {
        rs.grid_step_mm = step_mm;
    }
    let reduction = reduce(&zmap.grid, &opts)?;
    progress.check().map_err(|_| ReduceError::Cancelled)?;
    let approximation = reduction.at_nodes(zmap.grid.rows(), zmap.grid.cols());
    let signed_error = Grid::from_fn(zmap.grid.rows(), zmap.grid.cols(), |r, c| {
        approximation.get(r, c).unwrap_or(0.0) - zmap.grid.get(r, c).unwrap_or(0.0)
    });
    Ok(PartReduction {
        zmap,
        reduction,
        approximation,
        signed_error,
    })
}

/// A part's XY-dependent Z-map (built from its mesh vertices, the thesis's irregular-data
/// program), its reduction (X, Y and Z each by its own SVD), and the signed vertical error of
/// every original node against the reduced surface.
#[derive(Clone, Debug, PartialEq)]
pub struct PartXyReduction {
    /// The XY-dependent Z-map that was reduced.
    pub map: XyZmap,
    /// The reduction of its three matrices.
    pub reduction: XyReduction,
    /// Reduced surface − node height at every node of `map` (row-major), mm; `None` where the
    /// node lies outside the reduced surface's XY footprint.
    pub signed_error: Vec<Option<f64>>,
}

impl PartXyReduction {
    /// The original XY-dependent Z-map as a mesh (one vertex per node, row-major, so
    /// `signed_error`'s values are its per-vertex scalars).
    #[must_use]
    pub fn original_mesh(&self) -> TriMesh {
        xy_mesh(&self.map)
    }

    /// The reduced model as a mesh (what an STL export writes).
    #[must_use]
    pub fn reduced_mesh(&self) -> TriMesh {
        xy_mesh(&self.reduction.reduced)
    }

    /// Numbers the reduced model stores (the three matrices' factors).
    #[must_use]
    pub fn stored_numbers(&self) -> usize {
        let r = &self.reduction;
        r.x.stored_numbers + r.y.stored_numbers + r.z.stored_numbers
    }
}

/// Reduce the XY-dependent Z-map of `mesh`'s vertices at reference step `step_mm` (empty cells
/// filled from the mesh behind `bvh`): each matrix to the rank `opts` chooses, resampled to the
/// ball's spacing when `opts` asks for it (the grid step being `step_mm`).
///
/// # Errors
/// As [`xy_zmap_from_points`] and [`reduce_xy_zmap`]; [`ReduceError::Cancelled`] when
/// `progress` is cancelled.
pub fn reduce_part_xy(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    step_mm: f64,
    opts: &ReduceOptions,
    progress: &Progress,
) -> Result<PartXyReduction, ReduceError> {
    let map = xy_zmap_from_points(&mesh.positions, step_mm, EmptyCellFill::Mesh(bvh))?;
    progress.check().map_err(|_| ReduceError::Cancelled)?;
    progress.set(0.3);
    let (m, n) = (map.z.rows(), map.z.cols());
    let (rows, cols) = match opts.resampling {
        Some(rs) => {
            let l = point_spacing(rs.tool_radius_mm, opts.tolerance_mm);
            (
                resampled_count(m, step_mm, l),
                resampled_count(n, step_mm, l),
            )
        }
        None => (m, n),
    };
    let reduction = reduce_xy_zmap(&map, opts.tolerance_mm, opts.rank_rule, rows, cols)?;
    progress.check().map_err(|_| ReduceError::Cancelled)?;
    progress.set(0.8);
    let reduced = MeshBvh::new(&xy_mesh(&reduction.reduced))
        .map_err(|e| ReduceError::Shape(format!("reduced mesh: {e}")))?;
    let top = reduced.bbox().max.z + 1.0;
    let signed_error = (0..m * n)
        .into_par_iter()
        .map(|k| {
            let p = map.point(k / n, k % n)?;
            let hit = reduced.ray_cast(p.truncate().extend(top), DVec3::NEG_Z, f64::INFINITY)?;
            Some(hit.point.z - p.z)
        })
        .collect();
    progress.set(1.0);
    Ok(PartXyReduction {
        map,
        reduction,
        signed_error,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dome z = 5 − (x² + y²)/20 over [−5, 5]², meshed finely.
    fn dome() -> MeshBvh {
        let n = 80;
        let g = Grid::from_fn(n + 1, n + 1, |r, c| {
            let (x, y) = (
                -5.0 + 10.0 * c as f64 / n as f64,
                -5.0 + 10.0 * r as f64 / n as f64,
            );
            5.0 - (x * x + y * y) / 20.0
        });
        MeshBvh::new(&grid_mesh(&g, DVec2::splat(-5.0), 10.0, 10.0)).unwrap()
    }

    #[test]
    fn zmap_covers_the_box_and_samples_the_mesh() {
        let z = part_zmap(&dome(), None, 0.5, &Progress::new()).unwrap();
        assert_eq!((z.grid.rows(), z.grid.cols()), (21, 21));
        assert_eq!(z.misses, 0);
        assert!((z.width_mm() - 10.0).abs() < 1e-12);
        for (r, c) in [(0, 0), (10, 10), (3, 17), (20, 20)] {
            let (x, y) = (-5.0 + 0.5 * c as f64, -5.0 + 0.5 * r as f64);
            let want = 5.0 - (x * x + y * y) / 20.0;
            // The mesh is a chordal approximation: within its sag (step 0.125 mm, κ = 0.1/mm).
            assert!((z.grid.get(r, c).unwrap() - want).abs() < 2e-4, "{r},{c}");
        }
        // A step past the box's size: the grid reaches beyond it and misses hold the floor.
        let z = part_zmap(&dome(), None, 3.0, &Progress::new()).unwrap();
        assert_eq!((z.grid.rows(), z.grid.cols()), (5, 5));
        assert_eq!(z.misses, 9);
        assert!((z.grid.get(4, 4).unwrap() - 2.5).abs() < 1e-9);
    }

    #[test]
    fn reduction_error_map_agrees_with_the_report_and_the_bound() {
        let opts = ReduceOptions {
            tolerance_mm: 1e-3,
            rank_rule: super::super::RankRule::SpectralBound,
            resampling: None,
        };
        let r = reduce_part(&dome(), None, 0.25, &opts, &Progress::new()).unwrap();
        // The dome is a sum of a function of x and one of y: rank 2 up to the mesh's facets.
        assert!(r.reduction.rank >= 2, "{}", r.reduction.rank);
        let max = r
            .signed_error
            .values()
            .iter()
            .fold(0.0_f64, |a, e| a.max(e.abs()));
        assert!((max - r.reduction.max_error).abs() < 1e-12);
        assert!(max <= r.reduction.rank_error_bound + 1e-12);
        assert!(max <= opts.tolerance_mm);
        let mesh = r.approximation_mesh();
        assert_eq!(mesh.positions.len(), r.signed_error.values().len());
    }

    #[test]
    fn xy_reduction_errors_agree_with_the_report() {
        let n = 40;
        let g = Grid::from_fn(n + 1, n + 1, |r, c| {
            let (x, y) = (c as f64 * 0.25, r as f64 * 0.25);
            (0.7 * x).sin() + 0.3 * (0.5 * y).cos() * x
        });
        let mesh = grid_mesh(&g, DVec2::ZERO, 10.0, 10.0);
        let bvh = MeshBvh::new(&mesh).unwrap();
        let opts = ReduceOptions {
            tolerance_mm: 0.01,
            rank_rule: super::super::RankRule::SpectralBound,
            resampling: None,
        };
        let r = reduce_part_xy(&mesh, &bvh, 0.25, &opts, &Progress::new()).unwrap();
        assert_eq!(r.signed_error.len(), r.map.z.values().len());
        let covered: Vec<f64> = r.signed_error.iter().flatten().map(|e| e.abs()).collect();
        assert_eq!(r.signed_error.len() - covered.len(), r.reduction.uncovered);
        let max = covered.iter().fold(0.0_f64, |a, b| a.max(*b));
        assert!((max - r.reduction.max_error).abs() < 1e-12, "{max}");
        assert!(r.stored_numbers() > 0);
        assert_eq!(r.original_mesh().positions.len(), r.signed_error.len());
    }

    #[test]
    fn bad_step_too_many_nodes_and_cancel_are_errors() {
        let bvh = dome();
        for step in [0.0, -1.0, f64::NAN] {
            assert!(matches!(
                part_zmap(&bvh, None, step, &Progress::new()),
                Err(ReduceError::Option(_))
            ));
        }
        assert!(matches!(
            part_zmap(&bvh, None, 1e-4, &Progress::new()),
            Err(ReduceError::Shape(_))
        ));
        let p = Progress::new();
        p.cancel();
        assert_eq!(part_zmap(&bvh, None, 0.5, &p), Err(ReduceError::Cancelled));
    }
}
