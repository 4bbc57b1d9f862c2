//! Iso-scallop passes (the thesis's ISC-II, "dual iterative scan in parameter space"), with the
//! side step taken on the surface rather than by a parameter crawl: the first pass is the boundary
//! iso-curve; at every guide point of pass k the cross-feed direction `t = ±n × f` is taken on
//! the surface, the side step `w` comes from the local normal curvature across the feed and the
//! cutter's exact cross profile (see [`super::scallop`]), and the next pass's point is reached by
//! marching `w` along the surface (arc length, not the thesis's 0.0001 parameter crawl).
//!
//! Boundaries: a march that leaves the domain ends on the boundary; if the boundary is within
//! half a step the strip is already within the scallop limit and the point is dropped, else the
//! point is kept on the boundary (a pass along the edge). Runs of kept points become the next
//! passes; their ends are extended to the domain boundary along their own direction (so passes
//! can end on adjacent boundaries, as the thesis observes). Back-tracking points (the front
//! folding over on the concave side of a curved pass) are removed, passes are resampled to a
//! fixed guide spacing and passes shorter than the cutter radius are dropped. Every kept point
//! is at least `w_min > 0` beyond its source, and the number of passes is bounded, so the scan
//! terminates. Each new front is trimmed of its swallowtails and smoothed (see `successors`),
//! and the scan is closed by passes along the far edge and the two edges where passes start
//! and end, which the fronts meet obliquely.
//!
//! Trimmed faces: the scan runs over the rectangle that bounds the face's region (so the
//! fronts stay smooth across holes and notches) and every pass is clipped to the region: a pass
//! that leaves and re-enters it gives several runs, each ending on the boundary. Passes along
//! the region's loops (outline and holes, less any stretch on a periodic seam) then finish the
//! edge strips that the clipped passes, running alongside an edge, leave up to a side step wide.

use glam::DVec2;

use super::PlanError;
use super::pass::Pass;
use super::setup::Setup;
use crate::diagnostics::Diagnostic;

/// Most passes before the scan stops with a diagnostic.
const MAX_PASSES: usize = 20_000;

/// A next-pass candidate closer than this fraction of another source guide's step to that
/// guide is inside the front's swallowtail (3D chords slightly under-estimate the arc length,
/// hence a margin below 1).
const SWALLOWTAIL: f64 = 0.98;

/// Iso-scallop passes over the setup's face, in machining order.
///
/// # Errors
/// [`PlanError`] when the face has no usable normal at the start.
pub fn passes(setup: &Setup<'_>, diags: &mut Vec<Diagnostic>) -> Result<Vec<Pass>, PlanError> {
    if setup.patch.region.is_none() {
        return scan(setup, diags);
    }
    // A trimmed face: the fronts march over the rectangle that bounds the region, and each
    // pass is clipped to the region.
    let mut open = setup.clone();
    open.patch = setup.patch.untrimmed();
    let mut out = Vec::new();
    for p in scan(&open, diags)? {
        for run in p.clipped(&setup.patch) {
            let run = run.resampled(&setup.patch, setup.guide_spacing);
            if run.uv.len() >= 2 && run.length(&setup.patch) >= 0.05 * setup.min_pass_length {
                out.push(run);
            }
        }
    }
    for run in boundary_passes(setup) {
        if run.uv.len() >= 2 && run.length(&setup.patch) >= 0.05 * setup.min_pass_length {
            out.push(run);
        }
    }
    Ok(out)
}

/// Passes along the trimmed region's loops, resampled to the guide spacing. The clipped scan
/// passes end on the boundary where they cross it, but where the boundary runs along the
/// passes the nearest one can lie up to a side step `w` inside it, leaving up to `w²/(2R)` on
/// the edge strip; a pass with its contact on the loop finishes it. Stretches of a loop that
/// lie on a periodic seam (a line inside the face) are left out.
pub(super) fn boundary_passes(setup: &Setup<'_>) -> Vec<Pass> {
    let Some(region) = setup.patch.region else {
        return Vec::new();
    };
    let surface = setup.patch.surface;
    let (pu, pv) = surface.periods();
    let dom = surface.domain();
    let on_seam = |a: f64, b: f64, period: Option<f64>, t0: f64| {
        period.is_some_and(|p| {
            let tol = 1e-9 * p.max(1.0);
            let k = ((a - t0) / p).round();
            (a - b).abs() <= tol && (a - t0 - k * p).abs() <= 1e-7 * p.max(1.0)
        })
    };
    let t0 = |i: crate::geometry::Interval| {
        if i.t0.is_finite() { i.t0 } else { 0.0 }
    };
    let (u0, v0) = (t0(dom.u), t0(dom.v));
    let mut out = Vec::new();
    for l in region.loops() {
        let mut run: Vec<DVec2> = Vec::new();
        for k in 0..l.len() {
            let (a, b) = (l[k], l[(k + 1) % l.len()]);
            let seam = on_seam(a.x, b.x, pu, u0) || on_seam(a.y, b.y, pv, v0);
            if seam {
                if run.len() >= 2 {
                    out.push(Pass::new(std::mem::take(&mut run)));
                }
                run.clear();
                continue;
            }
            // A corner of the loop (the face's vertex) ends the run: each side is its own
            // pass, so the tilt-away treats the sides apart.
            if let Some(&prev) = run.iter().rev().nth(1)
                && corner(surface, prev, a, b)
            {
                out.push(Pass::new(std::mem::take(&mut run)));
            }
            if run.is_empty() {
                run.push(a);
            }
            run.push(b);
        }
        if run.len() >= 2 {
            out.push(Pass::new(run));
        }
    }
    out.into_iter()
        .map(|p| p.resampled(&setup.patch, setup.guide_spacing))
        .collect()
}

/// Does the boundary turn by more than 30° at `b` (between the chords `a b` and `b c` on the
/// surface)?
fn corner(surface: &crate::geometry::surface::SurfaceGeom, a: DVec2, b: DVec2, c: DVec2) -> bool {
    let (pa, pb, pc) = (
        surface.point(a.x, a.y),
        surface.point(b.x, b.y),
        surface.point(c.x, c.y),
    );
    match ((pb - pa).try_normalize(), (pc - pb).try_normalize()) {
        (Some(d0), Some(d1)) => d0.dot(d1) < 30f64.to_radians().cos(),
        _ => false,
    }
}

/// The scan over the whole patch.
fn scan(setup: &Setup<'_>, diags: &mut Vec<Diagnostic>) -> Result<Vec<Pass>, PlanError> {
    let first = setup.iso_pass(0.0);
    if first.uv.len() < 2 {
        return Err(PlanError::Face(
            "the first boundary pass is degenerate".into(),
        ));
    }
    let mut out: Vec<Pass> = Vec::new();
    let mut fronts = vec![first];
    let mut count = 0usize;
    while let Some(mut pass) = fronts.pop() {
        count += 1;
        if count > MAX_PASSES {
            diags.push(Diagnostic::warning(
                None,
                format!("iso-scallop stopped after {MAX_PASSES} passes"),
            ));
            break;
        }
        // Zig-zag: every other pass runs the other way.
        let next_reversed = true;
        let next = successors(setup, &mut pass, next_reversed);
        out.push(pass);
        // Depth-first keeps neighbouring passes adjacent in the output.
        for p in next.into_iter().rev() {
            fronts.push(p);
        }
    }
    // Edge passes. The far boundary iso-curve closes the scan. The last fronts, tilted by the varying side
    // step, meet that boundary obliquely; between their ends the edge lies ahead of one pass's
    // last contact and behind the next one's first, where a tilted flat or bull-nose cutter
    // leaves material (up to 0.3 mm at h = 0.05 on bicubic-hills). A pass along the edge
    // covers it, as the boundary iso-curve that starts the scan covers the near edge.
    // The same holds at the two other edges, where the passes start and end: the fronts cross
    // them obliquely, and behind a first contact (or ahead of a last one) the tilted flat
    // bottom stands higher by the lead's slope. Passes along those edges (iso-curves across
    // the scan) cover them.
    let dom = setup.patch.domain;
    let (lo, hi) = if setup.across() == 0 {
        (dom.u.t0, dom.u.t1)
    } else {
        (dom.v.t0, dom.v.t1)
    };
    let on_far = |p: &Pass| {
        p.uv.iter().all(|q| {
            let a = if setup.across() == 0 { q.x } else { q.y };
            a >= hi - 1e-9 * (hi - lo).abs().max(1.0)
        })
    };
    let mut edges = Vec::with_capacity(3);
    if !out.iter().any(on_far) {
        edges.push(setup.iso_pass(1.0));
    }
    edges.push(setup.edge_pass(1.0));
    edges.push(setup.edge_pass(0.0));
    for e in edges {
        if e.uv.len() >= 2 && out.len() < MAX_PASSES {
            out.push(e);
        }
    }
    Ok(out)
}

/// A candidate point of the next pass.
#[derive(Clone, Copy, Debug)]
enum Next {
    /// No point (no guide or section, or dropped at the boundary): the front breaks here.
    Gap,
    /// A point of the next pass.
    Point(DVec2),
    /// A point inside the swallowtail of the offset front: skipped without breaking it.
    Trimmed,
}

/// The passes that follow `pass`; fills `pass.scallop` with the predicted heights.
///
/// Two corrections against the front folding over itself (which, for flat and bull-nose
/// cutters whose large effective radius gives side steps of several mm that vary by ×2 with
/// the cross curvature, produced passes that curled into loops up to 1.6 m long, ten times the
/// passes of iso-parametric and, through the jittering feed of a tilted cutter, five times the
/// poses per mm):
/// - the cross direction at a guide comes from a chord spanning about the side step (not the
///   neighbouring guides 0.5 mm apart): a direction error θ moves the next point by w·θ along
///   the front, so with w ≫ the guide spacing short wiggles were amplified into back-tracking;
/// - the next front is the boundary of the union of the step discs (the trimmed variable-radius
///   offset): a candidate closer than its step to another source guide lies in a swallowtail
///   and is skipped (the neighbouring points, at their full steps, still bound the scallop).
fn successors(setup: &Setup<'_>, pass: &mut Pass, next_reversed: bool) -> Vec<Pass> {
    let n = pass.uv.len();
    let spacing = setup.guide_spacing.max(1e-9);
    let mut kept: Vec<Next> = Vec::with_capacity(n);
    // Source points and their steps (3D), for the swallowtail test.
    let mut discs: Vec<(glam::DVec3, f64)> = Vec::with_capacity(n);
    for i in 0..n {
        let Some((g, sec)) = setup
            .guide(pass, i)
            .and_then(|g| Some((g, setup.section(&g, next_reversed)?)))
        else {
            kept.push(Next::Gap);
            continue;
        };
        // Re-take the guide with a chord about the side step wide, then its section.
        let (w0, _) = sec.step();
        let k = ((0.5 * w0 / spacing).ceil() as usize).clamp(1, 64);
        let (g, sec) = if k > 1 {
            match setup
                .guide_spanning(pass, i, k)
                .and_then(|g2| Some((g2, setup.section(&g2, next_reversed)?)))
            {
                Some(gs) => gs,
                None => (g, sec),
            }
        } else {
            (g, sec)
        };
        let (w, h_pred) = sec.step();
        discs.push((g.frame.p, w));
        let along = 1 - setup.across();
        let m = setup
            .patch
            .march(g.frame.uv, g.tau, w, setup.march_substep, Some(along));
        let (point, h) = if m.hit_boundary {
            if m.travelled <= 0.5 * w {
                (None, sec.boundary_height(m.travelled))
            } else {
                (Some(m.uv), sec.height(m.travelled))
            }
        } else {
            (Some(m.uv), h_pred)
        };
        if let Some(s) = pass.scallop.get_mut(i) {
            *s = h;
        }
        kept.push(point.map_or(Next::Gap, Next::Point));
    }
    // Swallowtails: candidates strictly inside another source guide's step disc.
    for c in &mut kept {
        if let Next::Point(q) = *c {
            let qp = setup.patch.surface.point(q.x, q.y);
            if discs
                .iter()
                .any(|&(p, w)| qp.distance_squared(p) < (SWALLOWTAIL * w).powi(2))
            {
                *c = Next::Trimmed;
            }
        }
    }
    let mut runs: Vec<Pass> = Vec::new();
    let mut i = 0;
    while i < n {
        if !matches!(kept.get(i), Some(Next::Point(_))) {
            i += 1;
            continue;
        }
        let start = i;
        let mut pts: Vec<DVec2> = Vec::new();
        while let Some(&c) = kept.get(i) {
            let q = match c {
                Next::Gap => break,
                Next::Trimmed => {
                    i += 1;
                    continue;
                }
                Next::Point(q) => q,
            };
            // Drop points that run backwards against the source pass (a folded front).
            let forward = match (
                pts.last(),
                pass.uv.get(i),
                i.checked_sub(1).and_then(|j| pass.uv.get(j)),
            ) {
                (Some(last), Some(a), Some(b)) => (q - *last).dot(*a - *b) > 0.0,
                _ => true,
            };
            if forward {
                pts.push(q);
            }
            i += 1;
        }
        let end = i - 1;
        if pts.len() < 2 {
            continue;
        }
        if start == 0 {
            extend_to_boundary(setup, &mut pts, true);
        }
        if end + 1 == n {
            extend_to_boundary(setup, &mut pts, false);
        }
        smooth(&mut pts);
        let run = Pass::new(pts).resampled(&setup.patch, setup.guide_spacing);
        if run.length(&setup.patch) >= setup.min_pass_length && run.uv.len() >= 2 {
            runs.push(run);
        }
    }
    runs
}

/// Binomial smoothing passes over a new front.
const SMOOTHING_PASSES: usize = 3;

/// Smooth a new front's interior points in parameter space with the binomial filter
/// `(1, 2, 1)/4` ([`SMOOTHING_PASSES`] times; the ends stay). Without it, the front carried
/// sub-micrometre jitter from the marches (steps from a piecewise-linear outline table, kinks
/// where swallowtails were trimmed); harmless for a ball, but a tilted flat or bull-nose cutter
/// puts its tip R_f behind the contact along the feed, so the jitter of the feed direction
/// reappears ×R_f on the tip path and the chord check stepped at 0.6 mm instead of 1.2 mm (1.7
/// poses per mm against 0.8 for iso-parametric passes). The filter moves a smooth front by
/// about `s²κ/4` per pass (`s` the guide spacing), far below the side step.
fn smooth(pts: &mut [DVec2]) {
    for _ in 0..SMOOTHING_PASSES {
        let prev = pts.to_vec();
        for (j, q) in pts.iter_mut().enumerate().skip(1) {
            if let (Some(a), Some(b), Some(c)) = (prev.get(j - 1), prev.get(j), prev.get(j + 1)) {
                *q = (*a + *b * 2.0 + *c) * 0.25;
            }
        }
    }
}

/// Extend a run at its start (or end) along its own parametric direction to the domain
/// boundary, by at most a quarter of the domain.
fn extend_to_boundary(setup: &Setup<'_>, pts: &mut Vec<DVec2>, at_start: bool) {
    let (a, b) = if at_start {
        (pts.first().copied(), pts.get(1).copied())
    } else {
        (
            pts.last().copied(),
            pts.len().checked_sub(2).and_then(|j| pts.get(j).copied()),
        )
    };
    let (Some(a), Some(b)) = (a, b) else { return };
    let dir = a - b;
    if dir.length_squared() <= 0.0 {
        return;
    }
    let dom = setup.patch.domain;
    let reach = 0.25 * dom.u.len().hypot(dom.v.len()) / dir.length();
    if setup.patch.contains(a + dir * reach) {
        return;
    }
    let (mut lo, mut hi) = (0.0, reach);
    for _ in 0..50 {
        let m = 0.5 * (lo + hi);
        if setup.patch.contains(a + dir * m) {
            lo = m;
        } else {
            hi = m;
        }
    }
    let q = setup.patch.clamp(a + dir * lo);
    if q.distance(a) > 1e-12 {
        if at_start {
            pts.insert(0, q);
        } else {
            pts.push(q);
        }
    }
}
