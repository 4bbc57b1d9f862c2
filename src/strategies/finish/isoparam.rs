//! Iso-parametric passes: zig-zag two-way and one-way at a constant
//! parametric side step, and the rectangular spiral. The thesis takes the step from the chord
//! at the minimum convex radius; here it is the smallest step, over a grid of the face, that
//! keeps the scallop (from the same cross-feed section as iso-scallop) within h everywhere, so
//! both strategies meet the same maximum scallop. On a trimmed face every iso-line is clipped
//! to the region: a line that leaves and re-enters it (a hole, a notch) gives several runs,
//! each ending on the boundary, and the step is chosen over the runs only; passes along the
//! region's loops finish its edges.

use super::pass::Pass;
use super::setup::Setup;
use super::{Direction, Pattern, PlanError};
use crate::diagnostics::Diagnostic;

/// Iso-lines sampled to choose the step.
const GRID_LINES: usize = 41;

/// Smallest safe across-step over the face, as a fraction of the across domain, and the
/// worst predicted scallop at that step.
fn across_step(setup: &Setup<'_>, reversed_next: bool) -> Option<f64> {
    let len = if setup.across() == 0 {
        setup.patch.domain.u.len()
    } else {
        setup.patch.domain.v.len()
    };
    let mut best = f64::INFINITY;
    for k in 0..GRID_LINES {
        for pass in setup.iso_runs(k as f64 / (GRID_LINES - 1) as f64) {
            for i in 0..pass.uv.len() {
                let Some(g) = setup.guide(&pass, i) else {
                    continue;
                };
                let Some(sec) = setup.section(&g, reversed_next) else {
                    continue;
                };
                let (w, _) = sec.step();
                let perp = across_speed(setup, &g);
                if perp > 0.0 {
                    best = best.min(w / perp / len);
                }
            }
        }
    }
    (best.is_finite() && best > 0.0).then_some(best)
}

/// |∂S/∂(across)| without its component along the feed: the distance between neighbouring
/// iso-lines per unit parameter.
fn across_speed(setup: &Setup<'_>, g: &super::setup::Guide) -> f64 {
    let d = &g.frame.d;
    let s = if setup.across() == 0 { d.su } else { d.sv };
    (s - g.f * s.dot(g.f)).length()
}

/// Fill each guide's predicted scallop for a spacing of `step` (fraction) to the neighbour.
fn predict(setup: &Setup<'_>, pass: &mut Pass, step: f64, reversed_next: bool) {
    let len = if setup.across() == 0 {
        setup.patch.domain.u.len()
    } else {
        setup.patch.domain.v.len()
    };
    for i in 0..pass.uv.len() {
        let h = setup.guide(pass, i).and_then(|g| {
            let sec = setup.section(&g, reversed_next)?;
            Some(sec.height(step * len * across_speed(setup, &g)))
        });
        if let (Some(s), Some(h)) = (pass.scallop.get_mut(i), h) {
            *s = h;
        }
    }
}

/// Iso-parametric passes in machining order (all in the same parametric direction; the
/// linking reverses every other one for the zig-zag).
///
/// # Errors
/// [`PlanError::Face`] when no side step can be computed on the face.
pub fn passes(
    setup: &Setup<'_>,
    pattern: Pattern,
    diags: &mut Vec<Diagnostic>,
) -> Result<Vec<Pass>, PlanError> {
    let reversed = pattern == Pattern::Zigzag;
    if pattern == Pattern::Spiral {
        return spiral(setup, diags);
    }
    let step = across_step(setup, reversed)
        .ok_or_else(|| PlanError::Face("no side step could be computed on the face".into()))?;
    let count = ((1.0 / step).ceil() as usize).clamp(1, 100_000);
    let actual = 1.0 / count as f64;
    let mut out = Vec::with_capacity(count + 1);
    for k in 0..=count {
        for mut p in setup.iso_runs(k as f64 * actual) {
            if p.length(&setup.patch) < 0.05 * setup.min_pass_length {
                continue;
            }
            predict(setup, &mut p, actual, reversed);
            out.push(p);
        }
    }
    // A trimmed face's edges: an iso-line along an edge can fall just outside the region and be
    // clipped away, and the nearest kept one can then be a whole step inside it.
    out.extend(
        super::isoscallop::boundary_passes(setup)
            .into_iter()
            .filter(|p| p.length(&setup.patch) >= 0.05 * setup.min_pass_length),
    );
    diags.push(Diagnostic::info(
        None,
        format!(
            "{} iso-parametric passes, parametric step {:.6}",
            count + 1,
            actual
        ),
    ));
    Ok(out)
}

/// Rectangular spiral: concentric iso-parametric rings stepping inward by the safe step in
/// each direction.
fn spiral(setup: &Setup<'_>, diags: &mut Vec<Diagnostic>) -> Result<Vec<Pass>, PlanError> {
    let mut su = setup.clone();
    su.opts.direction = Direction::V;
    let mut sv = setup.clone();
    sv.opts.direction = Direction::U;
    let err = || PlanError::Face("no side step could be computed on the face".into());
    let du = across_step(&su, false).ok_or_else(err)?;
    let dv = across_step(&sv, false).ok_or_else(err)?;
    let mut out = Vec::new();
    let mut k = 0usize;
    loop {
        let (u0, u1) = (k as f64 * du, 1.0 - k as f64 * du);
        let (v0, v1) = (k as f64 * dv, 1.0 - k as f64 * dv);
        if u0 >= u1 || v0 >= v1 {
            break;
        }
        let ring = [(u0, v0), (u0, v1), (u1, v1), (u1, v0), (u0, v0)];
        let uv = ring.iter().map(|&(a, b)| setup.patch.at(a, b)).collect();
        let mut p = Pass::new(uv).resampled(&setup.patch, setup.guide_spacing);
        p.closed = true;
        let h = setup.opts.scallop;
        p.scallop.iter_mut().for_each(|s| *s = h);
        for run in p.clipped(&setup.patch) {
            out.push(run.resampled(&setup.patch, setup.guide_spacing));
        }
        k += 1;
        if k > 100_000 {
            break;
        }
    }
    // The core left inside the last ring: one iso-line through its middle.
    if !out.is_empty() {
        let last = k.saturating_sub(1) as f64;
        let (a, b) = ((last * du).min(0.5), (last * dv).min(0.5));
        let uv = if k as f64 * du >= 0.5 {
            vec![setup.patch.at(0.5, b), setup.patch.at(0.5, 1.0 - b)]
        } else {
            vec![setup.patch.at(a, 0.5), setup.patch.at(1.0 - a, 0.5)]
        };
        let p = Pass::new(uv).resampled(&setup.patch, setup.guide_spacing);
        for run in p.clipped(&setup.patch) {
            if run.length(&setup.patch) >= setup.min_pass_length {
                out.push(run.resampled(&setup.patch, setup.guide_spacing));
            }
        }
    }
    diags.push(Diagnostic::info(
        None,
        format!(
            "{} spiral rings, parametric steps {du:.6} (u), {dv:.6} (v)",
            k
        ),
    ));
    Ok(out)
}
