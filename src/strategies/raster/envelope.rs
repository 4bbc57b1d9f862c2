//! The lower envelope of the volume one pass sweeps, in the vertical section across the passes.
//!
//! The cusp between two passes is the highest point of the lower envelope of the two swept
//! volumes there. Taking only the tool resting at the section's own grid point (its
//! instantaneous profile) overestimates that envelope wherever the surface slopes along the
//! pass: the ball's bottom then hangs R·(sec θ − 1) above the surface under its axis (0.13 mm for
//! R = 3 mm at θ = 17°), while the tool a little uphill or downhill reaches lower. That error is
//! not a scallop, it does not shrink with the step, and it drove the step down and the
//! predicted scallop up. Here the tool moves along the pass: the envelope over a section point
//! at lateral offset d from the pass is min over t' of z(t') + g(√((t − t')² + d²)), z the CL
//! height along the pass and g the cutter's profile.
//!
//! **CL between grid points.** z(t') comes from the CL samples on the pass's grid: on each grid
//! interval the larger of the chord and the Catmull–Rom cubic through the four nearest samples,
//! on four sub-chords. Where the true CL bulges above the chord (convex along the pass) the
//! cubic follows it (error O(dt⁴) instead of the chord's dt²/8κ); where the CL has a V-shaped
//! kink (the tool touching two sides of a valley) the cubic could dip below the true CL and the
//! chord, which lies above it there, is used (conservative). The followed path lies on or above
//! the true CL within the chord tolerance, so its cusps are those predicted here plus at most
//! the chord tolerance.
//!
//! **Minimum over one sub-chord.** For a ball the centre moves on a straight segment and the
//! minimum has the closed form of `checks::oracle::raster` (the function is convex in t'). For other
//! profiles g is convex and non-decreasing and ρ(t') is convex, so the function is convex and
//! a ternary search finds it.

use super::passes::CoarsePass;
use super::stepover::profile;
use crate::tools::{Cutter, CutterKind};

/// Sub-chords per grid interval.
const SUB: usize = 4;

/// CL height on the pass at the fraction `s` of the way from grid point `k` to `k + 1` (a
/// uniform grid); None where either end has no CL point.
fn cl_height(pass: &CoarsePass, k: usize, s: f64) -> Option<f64> {
    let z = |i: usize| pass.cl.get(i).copied().flatten().map(|c| c.z);
    let (z1, z2) = (z(k)?, z(k + 1)?);
    let chord = z1 + (z2 - z1) * s;
    // Neighbours for the cubic's tangents; missing ones fall back to the chord's slope.
    let z0 = k.checked_sub(1).and_then(z).unwrap_or(2.0 * z1 - z2);
    let z3 = z(k + 2).unwrap_or(2.0 * z2 - z1);
    let (m1, m2) = (0.5 * (z2 - z0), 0.5 * (z3 - z1));
    let (s2, s3) = (s * s, s * s * s);
    let cubic = (2.0 * s3 - 3.0 * s2 + 1.0) * z1
        + (s3 - 2.0 * s2 + s) * m1
        + (-2.0 * s3 + 3.0 * s2) * z2
        + (s3 - s2) * m2;
    Some(chord.max(cubic))
}

/// The lowest point over the section point (t, offset `d` from the pass) of the tool moving
/// from (t_a, z_a) to (t_b, z_b) along the pass.
fn segment_lower(cutter: &Cutter, t: f64, d: f64, a: (f64, f64), b: (f64, f64)) -> f64 {
    let big = cutter.radius();
    let (ta, za) = a;
    let (tb, zb) = b;
    let len = tb - ta;
    if matches!(cutter.kind, CutterKind::Ball) {
        let s2 = big * big - d * d;
        if s2 < 0.0 || !(len > 0.0) {
            return f64::INFINITY;
        }
        let s = s2.sqrt();
        let (lo, hi) = ((t - s).max(ta), (t + s).min(tb));
        if lo > hi {
            return f64::INFINITY;
        }
        let slope = (zb - za) / len;
        let tc = (t - slope * s / (1.0 + slope * slope).sqrt()).clamp(lo, hi);
        let dt = tc - t;
        // Centre height minus the ball's depth below it.
        return za + slope * (tc - ta) + big - (s2 - dt * dt).max(0.0).sqrt();
    }
    if d.abs() > big || !(len > 0.0) {
        return f64::INFINITY;
    }
    let f = |tp: f64| {
        let z = za + (zb - za) * (tp - ta) / len;
        z + profile(cutter, ((t - tp).powi(2) + d * d).sqrt())
    };
    let (mut lo, mut hi) = (ta, tb);
    for _ in 0..40 {
        let m1 = lo + (hi - lo) / 3.0;
        let m2 = hi - (hi - lo) / 3.0;
        if f(m1) < f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(0.5 * (lo + hi)).min(f(ta)).min(f(tb))
}

/// The lower envelope of the volume swept by `cutter` along `pass`, over the section point at
/// grid index `j` and lateral offset `d` from the pass (+∞ where the tool never reaches).
pub(crate) fn swept_lower(
    cutter: &Cutter,
    grid: &[f64],
    pass: &CoarsePass,
    j: usize,
    d: f64,
) -> f64 {
    let Some(&t) = grid.get(j) else {
        return f64::INFINITY;
    };
    let big = cutter.radius();
    // The tool resting at the grid point itself (also where its neighbours have no CL point).
    let mut best = pass
        .cl
        .get(j)
        .copied()
        .flatten()
        .map_or(f64::INFINITY, |c| {
            if d.abs() <= big {
                c.z + profile(cutter, d)
            } else {
                f64::INFINITY
            }
        });
    let lo = grid.partition_point(|&g| g < t - big).saturating_sub(1);
    let hi = grid
        .partition_point(|&g| g <= t + big)
        .min(grid.len().saturating_sub(1));
    for k in lo..hi {
        let (Some(&ta), Some(&tb)) = (grid.get(k), grid.get(k + 1)) else {
            continue;
        };
        let mut prev: Option<(f64, f64)> = None;
        for i in 0..=SUB {
            let s = i as f64 / SUB as f64;
            let Some(z) = cl_height(pass, k, s) else {
                break;
            };
            let cur = (ta + (tb - ta) * s, z);
            if let Some(p) = prev {
                best = best.min(segment_lower(cutter, t, d, p, cur));
            }
            prev = Some(cur);
        }
    }
    // The moves from the last grid points to the runs' ends off the grid.
    for [a, b] in &pass.ends {
        if a.0 <= t + big && b.0 >= t - big {
            best = best.min(segment_lower(cutter, t, d, *a, *b));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::dropcutter::{ClPoint, Contact};
    use glam::DVec3;

    fn pass(grid: &[f64], z: impl Fn(f64) -> f64) -> CoarsePass {
        CoarsePass {
            w: 0.0,
            cl: grid
                .iter()
                .map(|&t| {
                    Some(ClPoint {
                        z: z(t),
                        cc: DVec3::ZERO,
                        contact: Contact::Facet,
                        triangle: 0,
                    })
                })
                .collect(),
            rim: vec![false; grid.len()],
            ends: Vec::new(),
            runs: Vec::new(),
        }
    }

    /// On a plane sloping along the pass at θ, the ball swept along it touches the plane
    /// everywhere under its path: the envelope at offset d is the plane's height there plus
    /// the cusp of a ball at offset d on the plane, (R − √(R² − d²))/cos θ measured vertically,
    /// whereas the instantaneous profile at the grid point stands R(sec θ − 1) higher at d = 0.
    #[test]
    fn ball_swept_down_a_slope_reaches_the_plane() {
        let c = Cutter::new(CutterKind::Ball, 6.0).unwrap();
        let big = 3.0_f64;
        let theta = 20f64.to_radians();
        let grid: Vec<f64> = (0..=20).map(|i| f64::from(i) * 1.5).collect();
        // CL of a ball on the plane z = t·tan θ: the tip sits R(sec θ − 1) above it.
        let lift = big * (1.0 / theta.cos() - 1.0);
        let p = pass(&grid, |t| t * theta.tan() + lift);
        for d in [0.0, 0.5, 1.0] {
            let got = swept_lower(&c, &grid, &p, 10, d);
            let want = 15.0 * theta.tan() + (big - (big * big - d * d).sqrt()) / theta.cos();
            assert!((got - want).abs() < 1e-9, "d {d}: {got} vs {want}");
        }
        let instantaneous = p.cl[10].unwrap().z;
        assert!(instantaneous - 15.0 * theta.tan() > 0.18);
    }

    /// Over a horizontal CL a flat end mill's envelope is its own bottom within its radius.
    #[test]
    fn flat_over_a_level_cl_is_its_bottom() {
        let c = Cutter::new(CutterKind::Flat, 10.0).unwrap();
        let grid: Vec<f64> = (0..=10).map(f64::from).collect();
        let p = pass(&grid, |_| 2.0);
        assert!((swept_lower(&c, &grid, &p, 5, 4.9) - 2.0).abs() < 1e-9);
        assert!(swept_lower(&c, &grid, &p, 5, 5.1) > 2.0 + 1.0);
    }
}
