//! Iso-planar passes: the face cut by parallel planes `x cos θ + y sin θ = c` (vertical planes
//! at angle θ about z), each intersection traced in parameter space (predictor along the
//! contour tangent, Newton corrector back onto the plane) from where it enters the domain's
//! boundary to where it leaves. The plane spacing is the smallest over the face that keeps the
//! scallop within h: the surface distance between neighbouring contours is `Δc / |∇_S c|`,
//! `∇_S c = m − (m·n) n`. Closed contours that never touch the boundary are not traced.
//!
//! Edges: where a domain edge runs nearly along the planes no contour ends on it, and the strip
//! between the edge and the nearest contour can be up to a whole spacing wide (the half-step
//! levels only protect the global extremes of c). Edge points farther than half the local
//! spacing from every traced pass are collected into stretches, and each stretch becomes a
//! pass along the edge, ordered with the others by its mean level.

use glam::{DVec2, DVec3};

use super::PlanError;
use super::face::FacePatch;
use super::pass::Pass;
use super::setup::{Guide, Setup};
use crate::diagnostics::Diagnostic;

/// Samples whose surface gradient of the plane level is below this fraction of the largest
/// do not set the plane spacing.
const GRADIENT_FLOOR: f64 = 0.25;

/// Boundary samples per side when looking for contour ends.
const BOUNDARY_SAMPLES: usize = 400;

/// Iso-planar passes at plane-normal angle `angle` (rad from +x about +z).
///
/// # Errors
/// [`PlanError::Face`] when the face is parallel to the planes everywhere.
pub fn passes(
    setup: &Setup<'_>,
    angle: f64,
    diags: &mut Vec<Diagnostic>,
) -> Result<Vec<Pass>, PlanError> {
    let m = DVec3::new(angle.cos(), angle.sin(), 0.0);
    let patch = &setup.patch;
    let (mut cmin, mut cmax) = (f64::INFINITY, f64::NEG_INFINITY);
    // (side step w, |∇_S c|) at each sample.
    let mut steps: Vec<(f64, f64)> = Vec::new();
    for uv in patch.samples(40) {
        let Some(frame) = patch.frame(uv) else {
            continue;
        };
        let c = frame.p.dot(m);
        cmin = cmin.min(c);
        cmax = cmax.max(c);
        let grad = m - frame.n * m.dot(frame.n);
        let g = grad.length();
        let Some(tau) = grad.try_normalize() else {
            continue;
        };
        let f = frame.n.cross(tau);
        let guide = Guide { frame, f, tau };
        if let Some(sec) = setup.section(&guide, true) {
            steps.push((sec.step().0, g));
        }
    }
    // Where the face stands nearly square to the planes (|∇_S c| → 0 at critical points of c:
    // extremes and saddles) the contours spread apart and no finite spacing keeps the scallop
    // there; those samples would ask for spacings of micrometres. The spacing is taken over the
    // samples whose gradient is at least GRADIENT_FLOOR of the largest, and the local excess is
    // reported through the predicted scallop.
    let g_max = steps.iter().fold(0.0_f64, |a, s| a.max(s.1));
    let dc = steps
        .iter()
        .filter(|s| s.1 >= GRADIENT_FLOOR * g_max)
        .fold(f64::INFINITY, |a, s| a.min(s.0 * s.1));
    if steps.iter().any(|s| s.1 < GRADIENT_FLOOR * g_max) {
        diags.push(Diagnostic::info(
            None,
            "the face stands nearly square to the planes somewhere: the plane spacing ignores \
             those places, where the predicted scallop may exceed the target",
        ));
    }
    if !(dc.is_finite() && dc > 0.0 && cmax > cmin) {
        return Err(PlanError::Face(
            "the face is parallel to the iso-planar planes".into(),
        ));
    }
    let count = (((cmax - cmin) / dc).ceil() as usize).clamp(1, 100_000);
    let step = (cmax - cmin) / count as f64;
    let mut levelled: Vec<(f64, Pass)> = Vec::new();
    let keep = |uv: Vec<DVec2>| {
        let mut p = Pass::new(uv).resampled(patch, setup.guide_spacing);
        // Short contours cut the domain's corners: keep them (dropping them leaves the corner
        // uncut); only collapsed ones go.
        if p.length(patch) < 0.05 * setup.min_pass_length {
            return None;
        }
        predict(setup, &mut p, m, step);
        Some(p)
    };
    // Levels at half-steps from the extremes: the corners where c is extreme are then within
    // half a step of the nearest contour.
    for k in 0..count {
        let c = cmin + step * (k as f64 + 0.5);
        for uv in trace_level(patch, m, c, setup.guide_spacing) {
            levelled.extend(keep(uv).map(|p| (c, p)));
        }
    }
    // Boundary stretches the contours leave farther than half a pass spacing away (an edge
    // running nearly along the planes): a pass along the edge there.
    let traced: Vec<Pass> = levelled.iter().map(|(_, p)| p.clone()).collect();
    for (c, uv) in edge_stretches(setup, m, step, &traced) {
        levelled.extend(keep(uv).map(|p| (c, p)));
    }
    levelled.sort_by(|a, b| a.0.total_cmp(&b.0));
    let out: Vec<Pass> = levelled.into_iter().map(|(_, p)| p).collect();
    diags.push(Diagnostic::info(
        None,
        format!(
            "{} iso-planar passes, plane spacing {step:.4} mm",
            out.len()
        ),
    ));
    Ok(out)
}

fn predict(setup: &Setup<'_>, pass: &mut Pass, m: DVec3, dc: f64) {
    for i in 0..pass.uv.len() {
        let Some(uv) = pass.uv.get(i).copied() else {
            continue;
        };
        let Some(frame) = setup.patch.frame(uv) else {
            continue;
        };
        let grad = m - frame.n * m.dot(frame.n);
        let Some(tau) = grad.try_normalize() else {
            continue;
        };
        let guide = Guide {
            frame,
            f: frame.n.cross(tau),
            tau,
        };
        if let (Some(sec), Some(s)) = (setup.section(&guide, true), pass.scallop.get_mut(i)) {
            *s = sec.height(dc / grad.length());
        }
    }
}

/// Edge samples per side for the coverage of the boundary.
const EDGE_SAMPLES: usize = 100;

/// An edge point counts as covered within this fraction of half the pass spacing.
const EDGE_SLACK: f64 = 1.05;

/// Stretches of the domain's edges (as parameter polylines, with the mean level along them)
/// whose points are farther from every traced pass than half the local pass spacing
/// `step / |∇_S c|` (5 % slack; distances to the passes' polylines): there the strip between
/// the edge and the nearest contour is up to a whole spacing wide (the edge runs nearly along
/// the planes, so no contour ends on it). Each stretch is extended by one sample at both ends.
fn edge_stretches(
    setup: &Setup<'_>,
    m: DVec3,
    step: f64,
    passes: &[Pass],
) -> Vec<(f64, Vec<DVec2>)> {
    let patch = &setup.patch;
    let lines: Vec<Vec<DVec3>> = passes
        .iter()
        .map(|p| p.uv.iter().map(|q| patch.surface.point(q.x, q.y)).collect())
        .collect();
    let dist = |x: DVec3| {
        let mut d2 = f64::INFINITY;
        for l in &lines {
            for w in l.windows(2) {
                let (a, b) = (w[0], w[1]);
                let ab = b - a;
                let t = if ab.length_squared() > 0.0 {
                    ((x - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                d2 = d2.min((a + ab * t).distance_squared(x));
            }
        }
        d2.sqrt()
    };
    let mut out = Vec::new();
    for side in boundary_sides(patch) {
        let samples: Vec<(DVec2, bool)> = side
            .into_iter()
            .map(|uv| {
                let Some(frame) = patch.frame(uv) else {
                    return (uv, false);
                };
                let g = (m - frame.n * m.dot(frame.n)).length();
                if !(g > 1e-9) {
                    return (uv, false);
                }
                (uv, dist(frame.p) > EDGE_SLACK * 0.5 * step / g)
            })
            .collect();
        let mut k = 0;
        while k < samples.len() {
            if !samples.get(k).is_some_and(|x| x.1) {
                k += 1;
                continue;
            }
            let start = k;
            while samples.get(k).is_some_and(|x| x.1) {
                k += 1;
            }
            let (i0, i1) = (start.saturating_sub(1), k.min(samples.len() - 1));
            let uv: Vec<DVec2> = samples
                .get(i0..=i1)
                .unwrap_or_default()
                .iter()
                .map(|x| x.0)
                .collect();
            let c = uv
                .iter()
                .map(|q| patch.surface.point(q.x, q.y).dot(m))
                .sum::<f64>()
                / uv.len().max(1) as f64;
            if uv.len() >= 2 {
                out.push((c, uv));
            }
        }
    }
    out
}

/// The patch's boundary as polylines of samples: the rectangle's four sides
/// ([`EDGE_SAMPLES`] + 1 points each), or each loop of the trimmed region resampled to about
/// four times as many points (closed: the first point repeated at the end).
fn boundary_sides(patch: &FacePatch<'_>) -> Vec<Vec<DVec2>> {
    if patch.region.is_none() {
        let corners = [
            patch.at(0.0, 0.0),
            patch.at(1.0, 0.0),
            patch.at(1.0, 1.0),
            patch.at(0.0, 1.0),
        ];
        return (0..4)
            .map(|s| {
                let (a, b) = (corners[s], corners[(s + 1) % 4]);
                (0..=EDGE_SAMPLES)
                    .map(|k| a.lerp(b, k as f64 / EDGE_SAMPLES as f64))
                    .collect()
            })
            .collect();
    }
    patch
        .boundary_loops()
        .iter()
        .map(|l| resample_closed(l, 4 * EDGE_SAMPLES))
        .collect()
}

/// A closed polygon as a polyline of about `n` points evenly spaced in parameter length (every
/// vertex kept, long sides subdivided), ending on its first point.
fn resample_closed(l: &[DVec2], n: usize) -> Vec<DVec2> {
    let len: f64 = (0..l.len())
        .map(|k| l[k].distance(l[(k + 1) % l.len()]))
        .sum();
    let ds = len / n.max(1) as f64;
    let mut out = Vec::with_capacity(n + l.len() + 1);
    for k in 0..l.len() {
        let (a, b) = (l[k], l[(k + 1) % l.len()]);
        let pieces = if ds > 0.0 {
            ((a.distance(b) / ds).ceil() as usize).clamp(1, 10 * n.max(1))
        } else {
            1
        };
        for j in 0..pieces {
            out.push(a.lerp(b, j as f64 / pieces as f64));
        }
    }
    if let Some(&f) = out.first() {
        out.push(f);
    }
    out
}

/// All open contours of `S·m = c` that start on the domain boundary.
fn trace_level(patch: &FacePatch<'_>, m: DVec3, c: f64, spacing: f64) -> Vec<Vec<DVec2>> {
    let g = |uv: DVec2| patch.surface.point(uv.x, uv.y).dot(m) - c;
    // Boundary walk, sign changes → seeds.
    let sides: Vec<Vec<DVec2>> = if patch.region.is_none() {
        let corners = [
            patch.at(0.0, 0.0),
            patch.at(1.0, 0.0),
            patch.at(1.0, 1.0),
            patch.at(0.0, 1.0),
        ];
        (0..4)
            .map(|s| {
                let (a, b) = (corners[s], corners[(s + 1) % 4]);
                (0..=BOUNDARY_SAMPLES)
                    .map(|k| a.lerp(b, k as f64 / BOUNDARY_SAMPLES as f64))
                    .collect()
            })
            .collect()
    } else {
        patch
            .boundary_loops()
            .iter()
            .map(|l| resample_closed(l, 4 * BOUNDARY_SAMPLES))
            .collect()
    };
    let mut seeds: Vec<DVec2> = Vec::new();
    for side in &sides {
        let Some(&a) = side.first() else { continue };
        let mut prev = a;
        let mut gp = g(a);
        for &q in side.iter().skip(1) {
            let gq = g(q);
            if (gp <= 0.0) != (gq <= 0.0) {
                let (mut lo, mut hi) = (prev, q);
                for _ in 0..50 {
                    let mid = lo.lerp(hi, 0.5);
                    if (g(mid) <= 0.0) == (gp <= 0.0) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                seeds.push(lo.lerp(hi, 0.5));
            }
            prev = q;
            gp = gq;
        }
    }
    let mut used = vec![false; seeds.len()];
    let mut out = Vec::new();
    let scale = patch.domain.u.len().hypot(patch.domain.v.len());
    for s in 0..seeds.len() {
        if used.get(s).copied().unwrap_or(true) {
            continue;
        }
        if let Some(u) = used.get_mut(s) {
            *u = true;
        }
        let Some(&start) = seeds.get(s) else { continue };
        let curve = trace_from(patch, m, c, start, spacing);
        // Mark the seed the contour ended on.
        if let Some(end) = curve.last() {
            let hit = seeds
                .iter()
                .enumerate()
                .filter(|(k, _)| !used.get(*k).copied().unwrap_or(true))
                .map(|(k, q)| (k, q.distance(*end)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .filter(|(_, d)| *d < 1e-3 * scale);
            if let Some(u) = hit.and_then(|(k, _)| used.get_mut(k)) {
                *u = true;
            }
        }
        if curve.len() >= 2 {
            out.push(curve);
        }
    }
    out
}

/// Trace one contour from a boundary point into the domain until it leaves again.
fn trace_from(patch: &FacePatch<'_>, m: DVec3, c: f64, start: DVec2, spacing: f64) -> Vec<DVec2> {
    let mut pts = vec![start];
    let centre = patch.at(0.5, 0.5);
    let mut p = start;
    let mut sense = 0.0;
    for _ in 0..200_000 {
        let Some(frame) = patch.frame(p) else { break };
        let grad = m - frame.n * m.dot(frame.n);
        let Some(t) = frame.n.cross(grad).try_normalize() else {
            break;
        };
        let mut dp = FacePatch::param_dir(&frame.d, t);
        let speed = (frame.d.su * dp.x + frame.d.sv * dp.y).length();
        if !(speed > 0.0) {
            break;
        }
        dp /= speed;
        if sense == 0.0 {
            // Into the domain: the side where a step stays inside (toward the centre if both).
            let ins = |s: f64| patch.contains(p + dp * (spacing * s));
            sense = match (ins(1.0), ins(-1.0)) {
                (true, false) => 1.0,
                (false, true) => -1.0,
                _ if dp.dot(centre - p) >= 0.0 => 1.0,
                _ => -1.0,
            };
        }
        let mut q = p + dp * (spacing * sense);
        // Newton back onto the plane along the parametric gradient.
        for _ in 0..4 {
            let d = patch.surface.derivs(q.x, q.y);
            let r = d.p.dot(m) - c;
            let gp = DVec2::new(d.su.dot(m), d.sv.dot(m));
            let l2 = gp.length_squared();
            if l2 <= 0.0 {
                break;
            }
            q -= gp * (r / l2);
        }
        if !patch.contains(q) {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if patch.contains(p.lerp(q, mid)) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let end = patch.clamp(p.lerp(q, lo));
            if end.distance(p) > 0.0 {
                pts.push(end);
            }
            break;
        }
        pts.push(q);
        p = q;
    }
    pts
}
