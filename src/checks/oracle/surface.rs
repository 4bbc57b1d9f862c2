//! Independent verification of a tool path against the exact surface: sample the surface on a
//! uv grid and, for each sample, measure the remaining height (distance along the tool-side
//! normal up to the union of the tool envelopes swept along the cutting moves) and the
//! penetration (how far that union reaches below the sample along the normal). See [`crate::checks::sweep`] for the move
//! model and the error bound of the sweep.
//!
//! Which samples count:
//! - the grid covers `rect` (default: the patch's rectangle) with `nu × nv` samples, ends
//!   included;
//! - samples closer than `margin_mm` to the rectangle's edge (measured with the local metric:
//!   `Δu·|S_u|`, `Δv·|S_v|`) are skipped (`outside_margin`);
//! - samples failing the optional mask (e.g. outside a trimmed face) are skipped (`masked`);
//! - samples whose normal ray meets no tool within `max_height_mm` are not machined by this
//!   path (`uncovered`): reported, not counted in the statistics.
//!
//! Sampling error: the maxima are maxima over the samples; between samples the deviation is
//! 1-Lipschitz in the sample position, so the true maximum exceeds the sampled one by at most
//! half the sample spacing diagonal in the worst case, and by O(spacing²) at a smooth extremum.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::checks::sweep::SweptTool;
use crate::checks::{CheckError, FacePatch};
use crate::geometry::surface::ParamRect;
use crate::toolpath::Pose;
use crate::tools::Cutter;

/// Options of [`verify`]. `VerifyOptions::default()` then adjust.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerifyOptions {
    /// Samples along u (≥ 2).
    pub nu: usize,
    /// Samples along v (≥ 2).
    pub nv: usize,
    /// Sampled rectangle; `None` = the patch's rectangle.
    pub rect: Option<ParamRect>,
    /// Distance from the rectangle's edge within which samples are skipped, mm (≥ 0).
    pub margin_mm: f64,
    /// Largest remaining height looked for (and largest penetration measured), mm; a sample
    /// whose normal ray meets no tool within it counts as uncovered. `None` = half the cutter
    /// radius.
    pub max_height_mm: Option<f64>,
    /// Ball end mills: largest chord error of the swept ball centre, mm.
    pub ball_tolerance_mm: f64,
    /// Other cutters: largest motion of any tool point within one swept piece, mm (the
    /// distance error is at most half of it, and nil for a constant axis).
    pub piece_mm: f64,
    /// Threshold for [`VerifyReport::within_threshold`], mm.
    pub threshold_mm: f64,
}

impl Default for VerifyOptions {
    fn default() -> Self {
        Self {
            nu: 200,
            nv: 200,
            rect: None,
            margin_mm: 0.0,
            max_height_mm: None,
            ball_tolerance_mm: 1e-5,
            piece_mm: 0.25,
            threshold_mm: 0.01,
        }
    }
}

/// A sample singled out in the report.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SampleAt {
    /// Parameters.
    pub uv: DVec2,
    /// Surface point, mm.
    pub point: DVec3,
    /// The value there, mm (remaining height or penetration depth).
    pub value_mm: f64,
    /// Index of the pose ending the move nearest to it.
    pub pose: usize,
}

/// Result of [`verify`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct VerifyReport {
    /// Grid samples in total.
    pub samples: usize,
    /// Samples counted in the statistics.
    pub counted: usize,
    /// Skipped within the margin.
    pub outside_margin: usize,
    /// Skipped by the mask.
    pub masked: usize,
    /// Skipped where the normal is undefined.
    pub degenerate: usize,
    /// Not reached by the tool within the maximum height.
    pub uncovered: usize,
    /// Largest remaining height, mm (0 when nothing was counted).
    pub max_remaining_mm: f64,
    /// Where it is.
    pub max_remaining_at: Option<SampleAt>,
    /// Remaining height percentiles (50, 90, 99, 99.9 %), mm.
    pub remaining_percentiles_mm: [f64; 4],
    /// The threshold used for `within_threshold`, mm.
    pub threshold_mm: f64,
    /// Fraction of counted samples with remaining height ≤ the threshold.
    pub within_threshold: f64,
    /// Largest penetration depth, mm (0 when none).
    pub max_penetration_mm: f64,
    /// Where it is.
    pub max_penetration_at: Option<SampleAt>,
    /// Samples with any penetration deeper than the sweep's error bound.
    pub penetrating: usize,
    /// Bound on the sweep's distance error, mm.
    pub sweep_bound_mm: f64,
}

enum Outcome {
    Margin,
    Masked,
    Degenerate,
    Uncovered,
    Value(SampleAt, f64),
}

/// Verify `poses` of `cutter` on `patch` (see the module doc).
///
/// # Errors
/// [`CheckError`] for bad options, poses or cutter.
pub fn verify(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    poses: &[Pose],
    opts: &VerifyOptions,
) -> Result<VerifyReport, CheckError> {
    verify_masked(patch, cutter, poses, opts, &|_| true)
}

/// [`verify`] counting only samples for which `mask(uv)` is true (a trimmed face's inside test).
///
/// # Errors
/// As [`verify`].
pub fn verify_masked(
    patch: &FacePatch<'_>,
    cutter: &Cutter,
    poses: &[Pose],
    opts: &VerifyOptions,
    mask: &(dyn Fn(DVec2) -> bool + Sync),
) -> Result<VerifyReport, CheckError> {
    if opts.nu < 2 || opts.nv < 2 || opts.nu.saturating_mul(opts.nv) > 50_000_000 {
        return Err(CheckError::BadOption {
            name: "nu/nv",
            message: format!(
                "need 2..=50e6 samples per side product, got {}×{}",
                opts.nu, opts.nv
            ),
        });
    }
    if !(opts.margin_mm.is_finite() && opts.margin_mm >= 0.0) {
        return Err(CheckError::BadOption {
            name: "margin_mm",
            message: format!("must be ≥ 0, got {}", opts.margin_mm),
        });
    }
    let rect = match opts.rect {
        Some(r) => FacePatch::new(patch.surface, r, patch.flip)?.rect,
        None => patch.rect,
    };
    let max_h = opts.max_height_mm.unwrap_or_else(|| 0.5 * cutter.radius());
    let sweep = SweptTool::new(cutter, poses, opts.ball_tolerance_mm, opts.piece_mm, max_h)?;
    let (nu, nv) = (opts.nu, opts.nv);
    let outcomes: Vec<Outcome> = (0..nu * nv)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k / nv, k % nv);
            let uv = DVec2::new(
                rect.u.lerp(i as f64 / (nu - 1) as f64),
                rect.v.lerp(j as f64 / (nv - 1) as f64),
            );
            sample(patch, &rect, &sweep, uv, opts.margin_mm, mask)
        })
        .collect();
    Ok(summarise(
        outcomes,
        nu * nv,
        opts.threshold_mm,
        sweep.bound_mm(),
    ))
}

fn sample(
    patch: &FacePatch<'_>,
    rect: &ParamRect,
    sweep: &SweptTool,
    uv: DVec2,
    margin: f64,
    mask: &(dyn Fn(DVec2) -> bool + Sync),
) -> Outcome {
    let d = patch.derivs(uv);
    let Some(n) = d.normal() else {
        return Outcome::Degenerate;
    };
    let n = n * patch.sign();
    if margin > 0.0 {
        let (su, sv) = (d.su.length(), d.sv.length());
        let du = (uv.x - rect.u.t0).min(rect.u.t1 - uv.x) * su;
        let dv = (uv.y - rect.v.t0).min(rect.v.t1 - uv.y) * sv;
        if du < margin || dv < margin {
            return Outcome::Margin;
        }
    }
    if !mask(uv) {
        return Outcome::Masked;
    }
    match sweep.deviation(d.p, n) {
        None => Outcome::Uncovered,
        Some(s) => Outcome::Value(
            SampleAt {
                uv,
                point: d.p,
                value_mm: s.distance_mm.abs(),
                pose: s.pose,
            },
            s.distance_mm,
        ),
    }
}

fn summarise(outcomes: Vec<Outcome>, samples: usize, threshold: f64, bound: f64) -> VerifyReport {
    let mut r = VerifyReport {
        samples,
        counted: 0,
        outside_margin: 0,
        masked: 0,
        degenerate: 0,
        uncovered: 0,
        max_remaining_mm: 0.0,
        max_remaining_at: None,
        remaining_percentiles_mm: [0.0; 4],
        threshold_mm: threshold,
        within_threshold: 0.0,
        max_penetration_mm: 0.0,
        max_penetration_at: None,
        penetrating: 0,
        sweep_bound_mm: bound,
    };
    let mut remaining = Vec::new();
    for o in outcomes {
        match o {
            Outcome::Margin => r.outside_margin += 1,
            Outcome::Masked => r.masked += 1,
            Outcome::Degenerate => r.degenerate += 1,
            Outcome::Uncovered => r.uncovered += 1,
            Outcome::Value(at, signed) => {
                r.counted += 1;
                let rem = signed.max(0.0);
                remaining.push(rem);
                if rem > r.max_remaining_mm || (r.max_remaining_at.is_none() && signed >= 0.0) {
                    r.max_remaining_mm = rem;
                    r.max_remaining_at = Some(at);
                }
                if signed < 0.0 {
                    let depth = -signed;
                    if depth > bound {
                        r.penetrating += 1;
                    }
                    if depth > r.max_penetration_mm {
                        r.max_penetration_mm = depth;
                        r.max_penetration_at = Some(at);
                    }
                }
            }
        }
    }
    if !remaining.is_empty() {
        remaining.sort_unstable_by(f64::total_cmp);
        let pick = |q: f64| {
            let idx = ((remaining.len() - 1) as f64 * q).round() as usize;
            remaining.get(idx).copied().unwrap_or(0.0)
        };
        r.remaining_percentiles_mm = [pick(0.5), pick(0.9), pick(0.99), pick(0.999)];
        let ok = remaining.iter().filter(|&&x| x <= threshold).count();
        r.within_threshold = ok as f64 / remaining.len() as f64;
    }
    r
}
