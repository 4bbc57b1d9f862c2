//! The cutter-location (CL) Z-map of a Z-map by inverse offset (thesis Eqs. 4.7–4.10): the tool dropped onto every node, touching only at nodes.
//!
//! For a ball of radius ρ on a Z-map of step γ the thesis gives the ball centre's height
//! z_b[m,n] = max{ z[i,j] + √(ρ² − γ²((m−i)² + (n−j)²)) : γ²((m−i)² + (n−j)²) ≤ ρ² }.
//! **Erratum:** the printed Eq. 4.8 misplaces the parentheses of the distance term; the form
//! above (distance √((m−i)² + (n−j)²) scaled by γ) is implemented. The generalisation (ours, not
//! the thesis's) works for every cutter through its profile g(d), the height of its lower surface above the
//! tip at distance d from the axis: tip_z[m,n] = max{ z[i,j] − g(d_ij) : d_ij ≤ ρ }. For the ball
//! g(d) = ρ − √(ρ² − d²), so tip_z = z_b − ρ exactly.
//!
//! The stencil (node offsets inside the disc and their g) is built once; each output row is
//! computed in parallel. Nodes of the stencil outside the grid are ignored (the part ends at the
//! grid's edge). Cost ≈ π(ρ/γ)² per node, as the thesis states.
//!
//! **Weakness of the node-only form.** The tool touches the Z-map only at its nodes, so between
//! them it sinks into the surface by up to the gap between tool and surface half a grid diagonal
//! from the contact, δ²/2 · (1/ρ + κ) with δ = γ/√2: 21 µm for a Ø6 ball at γ = 0.5 mm. For
//! paths, [`cl_zmap`] drops the cutter onto the triangulated Z-map instead (vertex, edge and
//! facet contacts), which is exact for that surface.

use rayon::prelude::*;

use glam::DVec2;

use crate::diagnostics::Progress;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::zmap::{Grid, ZmapError, grid_mesh};
use crate::tools::Cutter;
use crate::tools::dropcutter::drop_cutter_progress;

/// Most stencil entries (π(ρ/γ)²) accepted: a finer grid should be coarsened first.
const MAX_STENCIL: usize = 4_000_000;

/// The tip-height CL Z-map of `cutter` (axis +Z) over the Z-map `z` of grid step `step_mm`
/// (rows and columns): every node's tool tip height when the tool rests on the Z-map's nodes.
///
/// # Errors
/// [`ZmapError::Option`] for a non-positive step, or a tool so much wider than the step that
/// its stencil has more than 4 M nodes; [`ZmapError::Cancelled`] when `progress` is cancelled.
pub fn inverse_offset(
    z: &Grid,
    step_mm: f64,
    cutter: &Cutter,
    progress: &Progress,
) -> Result<Grid, ZmapError> {
    if !(step_mm > 0.0 && step_mm.is_finite()) {
        return Err(ZmapError::Option(format!(
            "grid step must be a positive length in mm, got {step_mm}"
        )));
    }
    let rho = cutter.radius();
    let reach = (rho / step_mm).floor();
    if !(reach.is_finite() && std::f64::consts::PI * reach * reach <= MAX_STENCIL as f64) {
        return Err(ZmapError::Option(format!(
            "a tool of radius {rho} mm spans too many nodes at a {step_mm} mm step"
        )));
    }
    let k = reach as i64;
    // (row offset, column offset, g(d)) for every node within the tool's radius.
    let stencil: Vec<(i64, i64, f64)> = (-k..=k)
        .flat_map(|di| (-k..=k).map(move |dj| (di, dj)))
        .filter_map(|(di, dj)| {
            let d = step_mm * ((di * di + dj * dj) as f64).sqrt();
            cutter.height_at_radius(d).map(|g| (di, dj, g))
        })
        .collect();
    let (rows, cols) = (z.rows(), z.cols());
    let values = z.values();
    let row_values: Vec<Option<Vec<f64>>> = (0..rows)
        .into_par_iter()
        .map(|m| {
            if progress.is_cancelled() {
                return None;
            }
            let row = (0..cols)
                .map(|n| {
                    stencil
                        .iter()
                        .filter_map(|&(di, dj, g)| {
                            let i = usize::try_from(m as i64 + di).ok().filter(|i| *i < rows)?;
                            let j = usize::try_from(n as i64 + dj).ok().filter(|j| *j < cols)?;
                            values.get(i * cols + j).map(|zij| zij - g)
                        })
                        .fold(f64::NEG_INFINITY, f64::max)
                })
                .collect();
            Some(row)
        })
        .collect();
    let mut out = Vec::with_capacity(rows * cols);
    for row in row_values {
        out.extend(row.ok_or(ZmapError::Cancelled)?);
    }
    progress.set(1.0);
    Grid::new(rows, cols, out)
}

/// The tip-height CL Z-map of `cutter` over the surface of the Z-map `z` triangulated as
/// [`grid_mesh`] does (node (r, c) at origin + (c, r)·step): drop-cutter at every node, with
/// vertex, edge and facet contacts, so the tool never sinks into that surface between nodes.
/// Nodes where the tool meets nothing (none inside the grid) get the lowest Z-map height.
///
/// # Errors
/// [`ZmapError::Option`] for a non-positive step or a flat Z-map without a triangle of
/// non-zero area; [`ZmapError::Cancelled`] when `progress` is cancelled.
pub fn cl_zmap(
    z: &Grid,
    origin: DVec2,
    step_mm: f64,
    cutter: &Cutter,
    progress: &Progress,
) -> Result<Grid, ZmapError> {
    if !(step_mm > 0.0 && step_mm.is_finite() && origin.is_finite()) {
        return Err(ZmapError::Option(format!(
            "grid step must be a positive length in mm, got {step_mm}"
        )));
    }
    let (rows, cols) = (z.rows(), z.cols());
    let width = cols.saturating_sub(1) as f64 * step_mm;
    let height = rows.saturating_sub(1) as f64 * step_mm;
    let mesh = grid_mesh(z, origin, width, height);
    let bvh = MeshBvh::new(&mesh).map_err(|e| ZmapError::Option(e.to_string()))?;
    let nodes: Vec<DVec2> = (0..rows * cols)
        .map(|k| origin + DVec2::new((k % cols) as f64, (k / cols) as f64) * step_mm)
        .collect();
    let low = z.values().iter().fold(f64::INFINITY, |a, b| a.min(*b));
    let dropped = drop_cutter_progress(&bvh, &mesh, cutter, &nodes, progress)
        .map_err(|_| ZmapError::Cancelled)?;
    Grid::new(
        rows,
        cols,
        dropped
            .iter()
            .map(|d| d.as_ref().map_or(low, |p| p.z))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::CutterKind;

    /// A ball of radius ρ on a sphere cap of radius R: its tip follows the sphere of radius
    /// R + ρ (closed form), approached from below as the grid refines (contacts only at nodes).
    #[test]
    fn ball_on_a_sphere_follows_the_offset_sphere() {
        let (big_r, step, n) = (40.0_f64, 0.25, 121);
        let half = (n - 1) as f64 * step / 2.0;
        let z = Grid::from_fn(n, n, |r, c| {
            let (x, y) = (c as f64 * step - half, r as f64 * step - half);
            (big_r * big_r - x * x - y * y).sqrt()
        });
        let ball = Cutter::new(CutterKind::Ball, 6.0).unwrap();
        let cl = inverse_offset(&z, step, &ball, &Progress::new()).unwrap();
        let rho = 3.0;
        let mut worst = 0.0_f64;
        // Interior nodes (the stencil inside the grid).
        for r in 12..n - 12 {
            for c in 12..n - 12 {
                let (x, y) = (c as f64 * step - half, r as f64 * step - half);
                let exact = ((big_r + rho).powi(2) - x * x - y * y).sqrt() - rho;
                let got = cl.get(r, c).unwrap();
                assert!(got <= exact + 1e-9, "({x}, {y}): {got} above {exact}");
                worst = worst.max(exact - got);
            }
        }
        // The node nearest the true contact is at most δ = γ/√2 away in XY; the ball sinks at
        // most the gap between ball and sphere there: δ²/2 · (1/ρ + 1/R) along the normal,
        // over cos² of the steepest slope met (corners: 17 mm off centre on the R + ρ sphere).
        let delta2 = 0.5 * step * step;
        let cos2 = 1.0 - (17.0 / (big_r + rho)).powi(2);
        let bound = 0.5 * delta2 * (1.0 / rho + 1.0 / big_r) / cos2;
        assert!(worst <= bound, "{worst} vs {bound}");
        assert!(
            worst >= 0.5 * bound,
            "{worst} vs {bound}: the bound is too loose to test"
        );
        assert!(worst > 0.0);
    }

    /// A flat end mill over a single spike: the CL Z-map is the spike's height over the disc of
    /// the tool's radius around it and the floor elsewhere; a cone descends along its flank.
    #[test]
    fn flat_and_cone_over_a_spike() {
        let n = 41;
        let z = Grid::from_fn(n, n, |r, c| if (r, c) == (20, 20) { 5.0 } else { 0.0 });
        let flat = Cutter::new(CutterKind::Flat, 4.0).unwrap();
        let cl = inverse_offset(&z, 0.5, &flat, &Progress::new()).unwrap();
        for r in 0..n {
            for c in 0..n {
                let d = 0.5 * (((r as f64) - 20.0).powi(2) + ((c as f64) - 20.0).powi(2)).sqrt();
                let want = if d <= 2.0 { 5.0 } else { 0.0 };
                assert_eq!(cl.get(r, c), Some(want), "{r},{c}");
            }
        }
        let cone = Cutter::new(
            CutterKind::Cone {
                half_angle: 45f64.to_radians(),
            },
            4.0,
        )
        .unwrap();
        let cl = inverse_offset(&z, 0.5, &cone, &Progress::new()).unwrap();
        // 45°: the tip sits 5 − d below the spike's top while the spike is under the flank.
        for (c, want) in [(20, 5.0), (21, 4.5), (22, 4.0), (24, 3.0), (25, 0.0)] {
            let got = cl.get(20, c).unwrap();
            assert!((got - want).abs() < 1e-12, "col {c}: {got} vs {want}");
        }
    }

    #[test]
    fn bad_step_huge_tool_and_cancel() {
        let z = Grid::from_fn(3, 3, |_, _| 0.0);
        let ball = Cutter::new(CutterKind::Ball, 6.0).unwrap();
        assert!(inverse_offset(&z, 0.0, &ball, &Progress::new()).is_err());
        assert!(inverse_offset(&z, 1e-5, &ball, &Progress::new()).is_err());
        let p = Progress::new();
        p.cancel();
        assert_eq!(
            inverse_offset(&z, 0.5, &ball, &p),
            Err(ZmapError::Cancelled)
        );
    }
}
