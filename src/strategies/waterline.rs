//! Waterline (Z-level finishing) on a triangle mesh for ball, flat, bull-nose and cone cutters.
//!
//! - **Contours** at each level are exact cutter locations: fibres in x and y on a regular
//!   grid are pushed against the mesh (`push`: exact vertex, edge and facet contacts for any
//!   profile of [`crate::tools::Cutter`]) and the closed loops are read off the grid
//!   (`contour`). The grid step comes from the chord tolerance: a chord of length c on a
//!   contour of radius ρ sags c²/(8ρ), so c = √(8·ρ_min·tol) with ρ_min = half the cutter
//!   radius (contours around convex features are at least the cutter's radius of curvature
//!   where the contact is on its rim), clamped to [0.005, 1] mm (or `sampling_mm`).
//! - **Levels** run from the top of the part down to its lowest point. The step-down is set by
//!   the scallop height on the local wall slope θ of every contact on the level (and on the next
//!   level; when that asks for less, the next level is moved up, up to eight times): ball and bull-nose cutters
//!   leave a cusp of height h between levels whose contacts lie s = 2√(2ρh − h²) apart along
//!   the wall (ρ the ball or corner radius), so Δz = s·sin θ; flat and cone cutters touch a
//!   slope with a sharp rim or tip, which leaves steps of height Δz·cos θ, so Δz = h / cos θ.
//!   Contacts flatter than `min_slope_rad` set no limit (a raster pass finishes them); the
//!   step-down is at most `max_step_down_mm`.
//! - **Direction**: climb (the part on the right of the travel, spindle clockwise) or
//!   conventional (loops reversed).
//! - **Order and links**: levels from the top down; within a level the nearest loop next, each
//!   loop entered at its point nearest to where the tool is, closed back to it and cut on
//!   past it by `loop_overlap_mm` (0.5 mm by default) so the entry leaves no mark. A link at
//!   the same level or downward whose straight XY path the cutter can travel at the lower of
//!   the two heights without meeting the mesh (checked with the same push-cutter) and shorter
//!   than `max_link_mm` is a fed move; otherwise the tool retracts to the clearance plane,
//!   rapids across, rapids down to 1 mm above the loop and plunges.
//! - **Entry** (`entry`): a plunge onto the loop's start, a tangential arc lead-in and
//!   lead-out in the level's plane on the free side, or a ramp down along the loop; an arc or
//!   ramp that the push-cutter finds not clear falls back to the plunge, counted in the plan
//!   (`entry`).
//! - **Steep parts only** (`steep_only`): with a threshold, only the runs of each loop whose
//!   contacts are at least `min_slope_rad` steep are cut (less an overlap band), each as an
//!   open pass; that is the waterline half of steep-and-shallow finishing.
//! - **Points a line carries are dropped**: a contour point within 1 % of the chord tolerance
//!   ([`COLLINEAR_FRACTION`]) of the line from the last kept point to a later one is left out,
//!   so a straight wall is one move, not one pose per fibre.

mod contour;
mod entry;
mod gaps;
mod push;

use glam::{DVec2, DVec3};

use crate::diagnostics::{Diagnostic, Progress};
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::toolpath::{ContactKind, MoveKind, Pose, ToolRecord, Toolpath};
use crate::tools::CutterKind;
pub use contour::ContourPoint;
use contour::{Grid, fibre_intervals, level_contours};
pub use entry::{
    ARC_RADIUS_RANGE_MM, Entry, RAMP_ANGLE_RANGE_DEG, RAMP_DEFAULT_ANGLE_DEG, RAMP_HEIGHT_MM,
};
use push::{Fibre, Profile};

/// Climb or conventional milling along the contours.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Cut {
    /// The part on the right of the travel (spindle clockwise, M3).
    #[default]
    Climb,
    /// The part on the left of the travel.
    Conventional,
}

/// Options of [`waterline`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WaterlineOptions {
    /// Scallop height h between levels, mm (> 0).
    pub scallop_mm: f64,
    /// Chord tolerance of the contours, mm (> 0).
    pub chord_tol_mm: f64,
    /// Fibre spacing, mm (None: from the chord tolerance).
    pub sampling_mm: Option<f64>,
    /// Contacts flatter than this set no limit on the step-down, rad from horizontal.
    pub min_slope_rad: f64,
    /// Cut only the runs of contours whose contacts are at least `min_slope_rad` steep
    /// (less `overlap_rad`).
    pub steep_only: bool,
    /// With `steep_only`: runs reach this much flatter than the threshold, rad.
    pub overlap_rad: f64,
    /// Largest step-down, mm (> 0).
    pub max_step_down_mm: f64,
    /// Climb or conventional.
    pub cut: Cut,
    /// Clearance plane above the part's top, mm (≥ 0).
    pub clearance_mm: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed_mm_per_min: f64,
    /// Longest link on which the tool stays down, mm (≥ 0).
    pub max_link_mm: f64,
    /// How each loop (or steep run) is entered.
    #[serde(default)]
    pub entry: Entry,
    /// How far a closed loop is cut on past its start, mm (≥ 0), so the entry leaves no
    /// witness mark; at most the loop's length.
    #[serde(default = "default_loop_overlap_mm")]
    pub loop_overlap_mm: f64,
}

/// The default overlap of a closed loop past its start, mm.
pub const DEFAULT_LOOP_OVERLAP_MM: f64 = 0.5;

fn default_loop_overlap_mm() -> f64 {
    DEFAULT_LOOP_OVERLAP_MM
}

/// Contour points within this fraction of the chord tolerance of the line through their
/// neighbours are dropped: the line already carries them.
pub const COLLINEAR_FRACTION: f64 = 0.01;

impl Default for WaterlineOptions {
    fn default() -> Self {
        Self {
            scallop_mm: 0.01,
            chord_tol_mm: 0.01,
            sampling_mm: None,
            min_slope_rad: 30f64.to_radians(),
            steep_only: false,
            overlap_rad: 5f64.to_radians(),
            max_step_down_mm: 2.0,
            cut: Cut::Climb,
            clearance_mm: 5.0,
            feed_mm_per_min: 1000.0,
            plunge_feed_mm_per_min: 300.0,
            max_link_mm: 10.0,
            entry: Entry::Plunge,
            loop_overlap_mm: DEFAULT_LOOP_OVERLAP_MM,
        }
    }
}

/// Why a waterline path could not be planned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WaterlineError {
    /// An option is out of range.
    #[error("invalid waterline option: {0}")]
    Option(String),
    /// No level holds a contour.
    #[error("no waterline contour lies on the part")]
    Empty,
    /// Cancelled through the progress handle.
    #[error("cancelled")]
    Cancelled,
}

/// A planned waterline path.
#[derive(Clone, Debug, PartialEq)]
pub struct WaterlinePlan {
    /// The tool path.
    pub toolpath: Toolpath,
    /// Tool-tip heights of the levels, from the top down, mm.
    pub levels: Vec<f64>,
    /// Number of loops (or steep runs) cut.
    pub loops: usize,
    /// Loops whose arc or ramp entry was not clear of the part (or a ramp on an open run) and
    /// that are entered by a plunge instead.
    pub entry_fallbacks: usize,
    /// Notes.
    pub diagnostics: Vec<Diagnostic>,
}

fn check_options(o: &WaterlineOptions) -> Result<(), WaterlineError> {
    let positive = [
        ("scallop height", o.scallop_mm),
        ("chord tolerance", o.chord_tol_mm),
        ("largest step-down", o.max_step_down_mm),
        ("feed", o.feed_mm_per_min),
        ("plunge feed", o.plunge_feed_mm_per_min),
    ];
    for (what, v) in positive {
        if !(v > 0.0 && v.is_finite()) {
            return Err(WaterlineError::Option(format!(
                "{what} must be positive, got {v}"
            )));
        }
    }
    if let Some(s) = o.sampling_mm
        && !(1e-3..=10.0).contains(&s)
    {
        return Err(WaterlineError::Option(format!(
            "fibre spacing must be 0.001 to 10 mm, got {s} mm"
        )));
    }
    let angles = [
        ("threshold angle", o.min_slope_rad),
        ("overlap", o.overlap_rad),
    ];
    for (what, a) in angles {
        if !(a >= 0.0 && a < 89.5f64.to_radians()) {
            return Err(WaterlineError::Option(format!(
                "{what} must be 0 to 89 degrees, got {} degrees",
                a.to_degrees()
            )));
        }
    }
    o.entry.validate().map_err(WaterlineError::Option)?;
    for (what, v) in [
        ("clearance", o.clearance_mm),
        ("max link", o.max_link_mm),
        ("loop overlap", o.loop_overlap_mm),
    ] {
        if !(0.0..1e6).contains(&v) {
            return Err(WaterlineError::Option(format!(
                "{what} must be 0 to 1000000 mm, got {v}"
            )));
        }
    }
    Ok(())
}

/// The fibre spacing for a cutter of radius `big` and chord tolerance `tol`, mm.
#[must_use]
pub fn default_sampling_mm(big: f64, tol: f64) -> f64 {
    (8.0 * 0.5 * big * tol).sqrt().clamp(0.005, 1.0)
}

/// The closed contours of `tool` at tip height `z` on `mesh`, the part on the right of each
/// loop, with fibres `sampling_mm` apart.
#[must_use]
pub fn contours_at(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &crate::tools::Cutter,
    z: f64,
    sampling_mm: f64,
) -> Vec<Vec<ContourPoint>> {
    let prof = Profile::new(tool);
    let grid = Grid::around(&bvh.bbox(), prof.radius(), sampling_mm);
    level_contours(mesh, bvh, &prof, &grid, z)
}

/// Largest step-down for a contact of slope `theta` (rad) at scallop `h`.
fn step_for_slope(kind: CutterKind, big: f64, h: f64, theta: f64) -> f64 {
    let rho = match kind {
        CutterKind::Ball => big,
        CutterKind::BullNose { corner_radius } => corner_radius,
        CutterKind::Flat | CutterKind::Cone { .. } => return h / theta.cos().max(1e-9),
    };
    let h = h.min(rho);
    2.0 * (2.0 * rho * h - h * h).max(0.0).sqrt() * theta.sin()
}

/// Plan waterline finishing of `mesh` (with its hierarchy `bvh`) with `tool`.
///
/// # Errors
/// [`WaterlineError::Option`] for a bad option or cutter, [`WaterlineError::Empty`] when no
/// contour is found.
pub fn waterline(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &WaterlineOptions,
) -> Result<WaterlinePlan, WaterlineError> {
    waterline_progress(mesh, bvh, tool, opts, &Progress::new())
}

struct Level {
    z: f64,
    loops: Vec<Vec<ContourPoint>>,
    step: f64,
}

/// [`waterline`] reporting progress and stopping when cancelled.
///
/// # Errors
/// As [`waterline`], plus [`WaterlineError::Cancelled`].
pub fn waterline_progress(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &WaterlineOptions,
    progress: &Progress,
) -> Result<WaterlinePlan, WaterlineError> {
    check_options(opts)?;
    let cutter = &tool.cutter;
    cutter
        .validate()
        .map_err(|e| WaterlineError::Option(e.to_string()))?;
    let prof = Profile::new(cutter);
    let sampling = opts
        .sampling_mm
        .unwrap_or_else(|| default_sampling_mm(cutter.radius(), opts.chord_tol_mm));
    let bbox = bvh.bbox();
    let grid = Grid::around(&bbox, prof.radius(), sampling);
    if (grid.nx as f64) * (grid.ny as f64) > 4.0e7 {
        return Err(WaterlineError::Option(format!(
            "fibre spacing {sampling} mm gives too fine a grid over the part"
        )));
    }
    let (top, bottom) = (bbox.max.z, bbox.min.z);
    let level = |z: f64| -> Level {
        let loops = level_contours(mesh, bvh, &prof, &grid, z);
        let step = loops
            .iter()
            .flatten()
            .filter(|p| p.slope >= opts.min_slope_rad)
            .map(|p| step_for_slope(cutter.kind, cutter.radius(), opts.scallop_mm, p.slope))
            .fold(opts.max_step_down_mm, f64::min)
            .max(1e-3);
        Level { z, loops, step }
    };
    let mut levels: Vec<Level> = Vec::new();
    // The first level lies one step below the top, the step of the flattest slope that
    // counts (a rounded rim under the top is steep within that depth).
    let first = step_for_slope(
        cutter.kind,
        cutter.radius(),
        opts.scallop_mm,
        opts.min_slope_rad.max(5f64.to_radians()),
    )
    .min(opts.max_step_down_mm)
    .min(0.5 * (top - bottom));
    let mut cur = level((top - first).max(bottom));
    loop {
        progress.check().map_err(|_| WaterlineError::Cancelled)?;
        progress.set(((top - cur.z) / (top - bottom).max(1e-9)).clamp(0.0, 1.0));
        let z = cur.z;
        let step = cur.step;
        levels.push(cur);
        if z <= bottom {
            break;
        }
        let mut nz = (z - step).max(bottom);
        let mut nxt = level(nz);
        // Move the next level up until its own slopes allow the step (a few tries).
        for _ in 0..8 {
            if nxt.step >= 0.999 * (z - nz) {
                break;
            }
            nz = (z - nxt.step).max(bottom);
            nxt = level(nz);
        }
        cur = nxt;
    }
    if opts.steep_only {
        let limit = (opts.min_slope_rad - opts.overlap_rad).max(0.0);
        levels = gaps::fill(&level, levels, limit, sampling);
    }
    let mut diagnostics = Vec::new();
    let ctx = entry::Ctx {
        mesh,
        bvh,
        prof: &prof,
        contact: contact_kind(cutter.kind),
    };
    let plan = link(&ctx, opts, &levels, top + opts.clearance_mm);
    if plan.1 == 0 {
        return Err(WaterlineError::Empty);
    }
    if plan.2 > 0 {
        let what = match opts.entry {
            Entry::Ramp { .. } => "ramp",
            _ => "arc",
        };
        diagnostics.push(Diagnostic::warning(
            None,
            format!(
                "{} of {} loops are entered by a plunge: their {what} entry would meet the part{}",
                plan.2,
                plan.1,
                if what == "ramp" {
                    " or they are open runs"
                } else {
                    ""
                }
            ),
        ));
    }
    diagnostics.push(Diagnostic::info(
        None,
        format!(
            "{} levels from z = {:.3} mm to {:.3} mm, {} loops, fibres {:.4} mm apart",
            levels.len(),
            levels.first().map_or(top, |l| l.z),
            levels.last().map_or(bottom, |l| l.z),
            plan.1,
            sampling
        ),
    ));
    Ok(WaterlinePlan {
        toolpath: Toolpath::new(tool.clone(), plan.0),
        levels: levels.iter().map(|l| l.z).collect(),
        loops: plan.1,
        entry_fallbacks: plan.2,
        diagnostics,
    })
}

/// The runs to cut on one loop: the whole loop closed back to its start, or with `steep_only`
/// the open runs of steep contacts.
fn runs(lp: &[ContourPoint], opts: &WaterlineOptions) -> Vec<Vec<ContourPoint>> {
    let mut pts: Vec<ContourPoint> = lp.to_vec();
    if opts.cut == Cut::Conventional {
        pts.reverse();
    }
    let limit = (opts.min_slope_rad - opts.overlap_rad).max(0.0);
    let steep: Vec<bool> = pts.iter().map(|p| p.slope >= limit).collect();
    if !opts.steep_only || steep.iter().all(|s| *s) {
        let first = pts[0];
        pts.push(first);
        return vec![pts];
    }
    // Start right after a shallow point so no run is split across the loop's start.
    let n = pts.len();
    let start = steep.iter().position(|s| !s).unwrap_or(0);
    let mut out = Vec::new();
    let mut run: Vec<ContourPoint> = Vec::new();
    for k in 1..=n {
        let i = (start + k) % n;
        if steep[i] {
            if run.is_empty() {
                // Begin at the shallow neighbour so the run covers the whole steep stretch.
                run.push(pts[(i + n - 1) % n]);
            }
            run.push(pts[i]);
        } else if !run.is_empty() {
            run.push(pts[i]);
            out.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        out.push(run);
    }
    out
}

/// The indices of the points of `pts` to keep: a point within `eps` of the straight line from
/// the last kept point to a later one is left out (the line carries it); the first and last
/// points are kept.
fn kept_points(pts: &[ContourPoint], eps: f64) -> Vec<usize> {
    /// The most points one line may carry before a point is kept anyway (bounds the work).
    const WINDOW: usize = 4096;
    if pts.len() <= 2 {
        return (0..pts.len()).collect();
    }
    let mut out = vec![0];
    let mut anchor = 0;
    for j in 2..pts.len() {
        let (a, b) = (pts[anchor].tip, pts[j].tip);
        let carried = j - anchor <= WINDOW
            && pts[anchor + 1..j]
                .iter()
                .all(|p| distance_to_segment(p.tip, a, b) <= eps);
        if !carried {
            anchor = j - 1;
            out.push(anchor);
        }
    }
    out.push(pts.len() - 1);
    out
}

/// Distance from `p` to the segment `a`–`b`.
fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 <= 1e-24 {
        return p.distance(a);
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

/// Whether the cutter at tip height `z` travels from `a` to `b` without meeting the mesh.
fn link_free(mesh: &TriMesh, bvh: &MeshBvh, prof: &Profile, a: DVec2, b: DVec2, z: f64) -> bool {
    let d = b - a;
    let len = d.length();
    if len < 1e-9 {
        return true;
    }
    let f = Fibre {
        origin: a,
        dir: d / len,
        z,
    };
    // Touching the contour at either end is allowed: shrink by a hair.
    let iv = fibre_intervals(mesh, bvh, prof, &f, len);
    iv.iter()
        .all(|(lo, hi)| hi.s <= 1e-7 || lo.s >= len - 1e-7 || hi.s - lo.s < 1e-7)
}

fn contact_kind(kind: CutterKind) -> ContactKind {
    match kind {
        CutterKind::Ball => ContactKind::Ball,
        CutterKind::Flat | CutterKind::BullNose { .. } => ContactKind::Corner,
        CutterKind::Cone { .. } => ContactKind::Flank,
    }
}

/// Order the runs of every level, link them and make the poses; returns the poses, the
/// number of runs and the number of entries that fell back to a plunge.
fn link(
    ctx: &entry::Ctx,
    opts: &WaterlineOptions,
    levels: &[Level],
    clear: f64,
) -> (Vec<Pose>, usize, usize) {
    let axis = DVec3::Z;
    let feed = opts.feed_mm_per_min;
    let mut poses: Vec<Pose> = Vec::new();
    let (mut count, mut fallbacks) = (0, 0);
    for lv in levels {
        let mut pending: Vec<Vec<ContourPoint>> =
            lv.loops.iter().flat_map(|lp| runs(lp, opts)).collect();
        let closed = !opts.steep_only;
        while !pending.is_empty() {
            let here = poses.last().map_or(DVec2::ZERO, |p| p.tip.truncate());
            let (k, start) = nearest_run(&pending, here, closed);
            let mut run = pending.swap_remove(k);
            if closed && start > 0 {
                run.pop();
                run.rotate_left(start);
                let first = run[0];
                run.push(first);
            }
            let z = run[0].tip.z;
            let ramp_h = entry::RAMP_HEIGHT_MM.min(clear - z);
            let mut ap = entry::approach(ctx, &run, opts, ramp_h);
            let fed = poses
                .last()
                .copied()
                .filter(|last| fed_link(ctx, opts, last.tip, ap.start.truncate().extend(z)));
            if let Some(last) = fed
                && matches!(opts.entry, Entry::Ramp { .. })
            {
                // A fed link arrives at its own height: the ramp starts there (at most 1 mm up).
                ap = entry::approach(ctx, &run, opts, ramp_h.min(last.tip.z - z));
            }
            fallbacks += usize::from(ap.fell_back);
            arrive(&mut poses, fed.is_some(), &ap, clear, opts);
            poses.extend(ap.moves);
            count += 1;
        }
    }
    if let Some(last) = poses.last() {
        let up = last.tip.truncate().extend(clear);
        poses.push(Pose::new(MoveKind::Rapid, up, axis, feed));
    }
    (poses, count, fallbacks)
}

/// The run nearest to `here` and the index of its point to start at (a closed loop may start
/// anywhere; an open run at its first point).
fn nearest_run(pending: &[Vec<ContourPoint>], here: DVec2, closed: bool) -> (usize, usize) {
    let mut best = (0, 0, f64::MAX);
    for (k, run) in pending.iter().enumerate() {
        let cands: &[ContourPoint] = if closed {
            &run[..run.len() - 1]
        } else {
            &run[..1]
        };
        for (i, p) in cands.iter().enumerate() {
            let d = p.tip.truncate().distance_squared(here);
            if d < best.2 {
                best = (k, i, d);
            }
        }
    }
    (best.0, best.1)
}

/// Whether the tool at `from` may link fed to `to` (at `to`'s level or below `from`): short,
/// and the straight XY path clear at the lower of the two heights.
fn fed_link(ctx: &entry::Ctx, opts: &WaterlineOptions, from: DVec3, to: DVec3) -> bool {
    let (a, b) = (from.truncate(), to.truncate());
    a.distance(b) <= opts.max_link_mm
        && to.z <= from.z + 1e-9
        && link_free(ctx.mesh, ctx.bvh, ctx.prof, a, b, to.z.min(from.z))
}

/// Move from the last pose to the approach's start: a fed link (`fed`) across at the old
/// height and down, else retract, rapid across and down, and plunge the last `gap`.
fn arrive(
    poses: &mut Vec<Pose>,
    fed: bool,
    ap: &entry::Approach,
    clear: f64,
    opts: &WaterlineOptions,
) {
    let axis = DVec3::Z;
    let feed = opts.feed_mm_per_min;
    let to = ap.start;
    if let Some(last) = poses.last().copied() {
        let (a, b) = (last.tip.truncate(), to.truncate());
        if fed {
            // Across at the old height, then down (the vertical is free: it is above `to`).
            if a.distance(b) > 1e-9 {
                poses.push(Pose::new(MoveKind::Link, b.extend(last.tip.z), axis, feed));
            }
            if last.tip.z - to.z > 1e-9 {
                poses.push(Pose::new(
                    MoveKind::Link,
                    to,
                    axis,
                    opts.plunge_feed_mm_per_min,
                ));
            }
            return;
        }
        poses.push(Pose::new(MoveKind::Rapid, a.extend(clear), axis, feed));
    }
    let b = to.truncate();
    poses.push(Pose::new(MoveKind::Rapid, b.extend(clear), axis, feed));
    if ap.gap > 0.0 {
        let above = (to.z + ap.gap).min(clear);
        poses.push(Pose::new(MoveKind::Rapid, b.extend(above), axis, feed));
        poses.push(Pose::new(
            MoveKind::Plunge,
            to,
            axis,
            opts.plunge_feed_mm_per_min,
        ));
    } else if clear - to.z > 1e-9 {
        poses.push(Pose::new(MoveKind::Rapid, to, axis, feed));
    }
}
