//! A raster finishing path read straight off a CL Z-map (the thesis's "tool paths on Z-maps"):
//! every k-th grid row is a pass along X at the CL heights, with k from
//! the step-over; consecutive passes are joined along the grid column at the CL heights
//! (zig-zag) or by a retract, a rapid and a plunge (one way). Within a pass, nodes are dropped
//! while the chord between the kept ones stays within the chord tolerance of every dropped
//! node's CL height, so the path follows the CL surface without redundant points.
//!
//! The tip is gouge-free at the nodes by construction of the CL Z-map
//! ([`super::inverse_offset`]); between nodes the path interpolates linearly, as every Z-map
//! method does (choose the Z-map step accordingly).

use glam::{DVec2, DVec3};

use crate::geometry::zmap::{Grid, ZmapError};
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

/// Options of [`zmap_raster`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZmapPathOptions {
    /// Distance between passes, mm (rounded down to whole grid rows, at least one).
    pub stepover_mm: f64,
    /// Largest vertical distance between the path and a dropped node's CL height, mm.
    pub chord_tol_mm: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Clearance above the highest CL height for rapids, mm.
    pub clearance_mm: f64,
    /// Zig-zag (true) or one way, every pass in +X (false).
    pub zigzag: bool,
}

impl Default for ZmapPathOptions {
    fn default() -> Self {
        Self {
            stepover_mm: 0.5,
            chord_tol_mm: 0.005,
            feed_mm_per_min: 1000.0,
            clearance_mm: 5.0,
            zigzag: true,
        }
    }
}

/// The raster path over the CL Z-map `cl` (tip heights; node (r, c) at origin + (c, r)·step).
///
/// # Errors
/// [`ZmapError::Option`] for a non-positive step, step-over, tolerance or feed, or a grid
/// with fewer than two columns.
pub fn zmap_raster(
    cl: &Grid,
    origin: DVec2,
    step_mm: f64,
    tool: ToolRecord,
    opts: &ZmapPathOptions,
) -> Result<Toolpath, ZmapError> {
    for (what, v) in [
        ("grid step", step_mm),
        ("step-over", opts.stepover_mm),
        ("chord tolerance", opts.chord_tol_mm),
        ("feed", opts.feed_mm_per_min),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(ZmapError::Option(format!(
                "{what} must be positive, got {v}"
            )));
        }
    }
    if !(opts.clearance_mm >= 0.0 && opts.clearance_mm.is_finite() && origin.is_finite()) {
        return Err(ZmapError::Option(format!(
            "clearance must be ≥ 0, got {}",
            opts.clearance_mm
        )));
    }
    let (rows, cols) = (cl.rows(), cl.cols());
    if cols < 2 {
        return Err(ZmapError::Shape(format!(
            "a {rows}×{cols} CL Z-map has no pass to cut"
        )));
    }
    let stride = ((opts.stepover_mm / step_mm).floor() as usize).max(1);
    let mut pass_rows: Vec<usize> = (0..rows).step_by(stride).collect();
    if pass_rows.last() != Some(&(rows - 1)) {
        pass_rows.push(rows - 1);
    }
    let top = cl.values().iter().fold(f64::NEG_INFINITY, |a, b| a.max(*b)) + opts.clearance_mm;
    let at = |r: usize, c: usize| {
        DVec3::new(
            origin.x + c as f64 * step_mm,
            origin.y + r as f64 * step_mm,
            cl.get(r, c).unwrap_or(top),
        )
    };
    let pose = |kind, p: DVec3| Pose::new(kind, p, DVec3::Z, opts.feed_mm_per_min);
    let mut poses: Vec<Pose> = Vec::new();
    let mut previous: Option<(usize, usize)> = None; // (row, column where the last pass ended)
    for (k, &r) in pass_rows.iter().enumerate() {
        let forward = !opts.zigzag || k % 2 == 0;
        let columns: Vec<usize> = if forward {
            (0..cols).collect()
        } else {
            (0..cols).rev().collect()
        };
        let pass: Vec<DVec3> = columns.iter().map(|&c| at(r, c)).collect();
        let first = columns.first().copied().unwrap_or(0);
        match previous {
            Some((pr, pc)) if opts.zigzag && pc == first => {
                // Along the column at the CL heights, down to the next pass.
                let link: Vec<DVec3> = (pr..=r).map(|i| at(i, pc)).collect();
                for p in thin(&link, opts.chord_tol_mm).into_iter().skip(1) {
                    poses.push(pose(MoveKind::Cut, p));
                }
            }
            Some(_) => {
                if let Some(last) = poses.last().map(|p| p.tip) {
                    poses.push(pose(MoveKind::Rapid, DVec3::new(last.x, last.y, top)));
                }
                poses.push(pose(MoveKind::Rapid, DVec3::new(pass[0].x, pass[0].y, top)));
                poses.push(pose(MoveKind::Plunge, pass[0]));
            }
            None => {
                poses.push(pose(MoveKind::Rapid, DVec3::new(pass[0].x, pass[0].y, top)));
                poses.push(pose(MoveKind::Plunge, pass[0]));
            }
        }
        for p in thin(&pass, opts.chord_tol_mm).into_iter().skip(1) {
            poses.push(pose(MoveKind::Cut, p));
        }
        previous = Some((r, columns.last().copied().unwrap_or(0)));
    }
    if let Some(last) = poses.last().map(|p| p.tip) {
        poses.push(pose(MoveKind::Rapid, DVec3::new(last.x, last.y, top)));
    }
    Ok(Toolpath::new(tool, poses))
}

/// The points of the polyline `p` to keep so that every dropped point lies within `tol` (in Z)
/// of the chord between the kept ones around it: greedy, extending each chord while it holds.
/// The first and last points are always kept.
fn thin(p: &[DVec3], tol: f64) -> Vec<DVec3> {
    let Some(&first) = p.first() else {
        return Vec::new();
    };
    let mut out = vec![first];
    let mut start = 0;
    let mut end = 1;
    while end < p.len() {
        // Can the chord start → end + 1 replace every point between?
        let next = end + 1;
        let holds = next < p.len() && {
            let (a, b) = (p[start], p[next]);
            let len = (b - a).truncate().length();
            (start + 1..next).all(|i| {
                let t = if len > 0.0 {
                    (p[i] - a).truncate().length() / len
                } else {
                    0.0
                };
                (a.z + t * (b.z - a.z) - p[i].z).abs() <= tol
            })
        };
        if holds {
            end = next;
        } else {
            out.push(p[end]);
            start = end;
            end += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::{Cutter, CutterKind};

    fn tool() -> ToolRecord {
        ToolRecord {
            spec: "ball:d=6".into(),
            cutter: Cutter::new(CutterKind::Ball, 6.0).unwrap(),
        }
    }

    #[test]
    fn thinning_keeps_the_curve_within_the_tolerance() {
        let p: Vec<DVec3> = (0..=200)
            .map(|i| {
                let x = f64::from(i) * 0.1;
                DVec3::new(x, 0.0, (0.3 * x).sin() * 4.0)
            })
            .collect();
        let tol = 0.01;
        let kept = thin(&p, tol);
        assert_eq!(kept.first(), p.first());
        assert_eq!(kept.last(), p.last());
        assert!(kept.len() < p.len() / 3, "{}", kept.len());
        // Every original point within tol of the kept polyline (in Z at its x).
        for q in &p {
            let w = kept
                .windows(2)
                .find(|w| w[0].x <= q.x && q.x <= w[1].x)
                .unwrap();
            let t = (q.x - w[0].x) / (w[1].x - w[0].x).max(1e-12);
            let z = w[0].z + t * (w[1].z - w[0].z);
            assert!((z - q.z).abs() <= tol + 1e-12, "{q}");
        }
        // A straight line keeps its two ends only.
        let line: Vec<DVec3> = (0..50)
            .map(|i| DVec3::new(f64::from(i), 0.0, 0.5 * f64::from(i)))
            .collect();
        assert_eq!(thin(&line, 1e-9).len(), 2);
    }

    #[test]
    fn zigzag_passes_cover_the_rows_at_the_stepover() {
        let cl = Grid::from_fn(11, 21, |r, c| 0.1 * r as f64 + 0.01 * (c * c) as f64);
        let opts = ZmapPathOptions {
            stepover_mm: 1.0,
            ..ZmapPathOptions::default()
        };
        let tp = zmap_raster(&cl, DVec2::new(10.0, 20.0), 0.5, tool(), &opts).unwrap();
        // Step-over 1 mm at 0.5 mm rows: every second row, 0..=10 → 6 passes, one plunge
        let ys: std::collections::BTreeSet<i64> = tp
            .poses
            .iter()
            .filter(|p| p.kind == MoveKind::Cut)
            .map(|p| ((p.tip.y - 20.0) * 1000.0).round() as i64)
            .collect();
        // (the links along the columns are straight here, so they keep only their ends).
        assert_eq!(
            ys.iter().copied().collect::<Vec<_>>(),
            vec![0, 1000, 2000, 3000, 4000, 5000]
        );
        let plunges = tp
            .poses
            .iter()
            .filter(|p| p.kind == MoveKind::Plunge)
            .count();
        assert_eq!(plunges, 1);
        // Every cut pose lies on the CL Z-map's node heights.
        for p in tp.poses.iter().filter(|p| p.kind == MoveKind::Cut) {
            let c = ((p.tip.x - 10.0) / 0.5).round() as usize;
            let r = ((p.tip.y - 20.0) / 0.5).round() as usize;
            assert!((cl.get(r, c).unwrap() - p.tip.z).abs() < 1e-12);
        }
        // One way: a plunge per pass.
        let one_way = ZmapPathOptions {
            zigzag: false,
            ..opts
        };
        let tp = zmap_raster(&cl, DVec2::ZERO, 0.5, tool(), &one_way).unwrap();
        assert_eq!(
            tp.poses
                .iter()
                .filter(|p| p.kind == MoveKind::Plunge)
                .count(),
            6
        );
    }

    #[test]
    fn bad_options_are_errors() {
        let cl = Grid::from_fn(3, 3, |_, _| 0.0);
        for o in [
            ZmapPathOptions {
                stepover_mm: 0.0,
                ..ZmapPathOptions::default()
            },
            ZmapPathOptions {
                chord_tol_mm: f64::NAN,
                ..ZmapPathOptions::default()
            },
            ZmapPathOptions {
                clearance_mm: -1.0,
                ..ZmapPathOptions::default()
            },
        ] {
            assert!(zmap_raster(&cl, DVec2::ZERO, 1.0, tool(), &o).is_err());
        }
        let thin_grid = Grid::from_fn(3, 1, |_, _| 0.0);
        assert!(
            zmap_raster(
                &thin_grid,
                DVec2::ZERO,
                1.0,
                tool(),
                &ZmapPathOptions::default()
            )
            .is_err()
        );
    }
}
