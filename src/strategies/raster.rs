//! Raster (parallel) finishing on a triangle mesh with the drop-cutter, for ball, flat and
//! bull-nose cutters (any profile the drop-cutter handles).
//!
//! - **Passes** are parallel lines at `angle_rad` from +X, machined zig-zag or one-way.
//! - **Step-over** comes from the scallop height h with the local slope taken into account: the
//!   next pass is first placed at the step a plane inclined at the steepest cross slope met on
//!   the current pass allows (`stepover` explains the table; for a ball s = 2√(2Rh − h²)·cos φ),
//!   then the cusp between the two actual passes is measured at every grid point and the step
//!   is shrunk until every cusp is ≤ h. Where shrinking overshoots (the worst cusp below 0.9 h)
//!   the step is grown back once, to where the failing and the passing tries, on a log-log line
//!   of cusp against step, put the cusp at 0.95 h, and kept if it holds (on bicubic-hills 4 %
//!   fewer passes and less cut length). The cusp (`passes::cusps`) is the ridge of the lower
//!   envelope of the two volumes the tool sweeps moving along the passes (`envelope`), found
//!   between the two contact points (on a cross slope the ridge lies uphill of both axes once
//!   the step is small), as its distance to the mesh, less what a pass midway between the two
//!   would leave at the same point. That catches concave curvature across the passes, which the
//!   planar rule underestimates (by R_s/(R_s − R) on a fillet of radius R_s), and leaves out
//!   what no step-over removes: corners and valleys narrower than the tool, the foot of a wall
//!   met along the pass, the end of a pass where the tool stops on a slope (each reported in
//!   the diagnostics, not as scallop). Grid points whose cusp still does not shrink with the
//!   step stop counting too. Areas steeper than `max_slope_rad` are not held to h (a raster
//!   pass cannot control the scallop on walls; a Z-level finish does); their area is reported.
//!
//!   (The tool's profile at the grid point alone is no measure of the cusp: on a slope θ along
//!   the pass it hangs R·(sec θ − 1) above the surface, and between the two axes on a cross
//!   slope the downhill pass is lowest everywhere. Neither shrinks with the step, so a step cut
//!   to a third would still predict 0.12 mm for a 0.05 mm request on bicubic-hills.)
//! - **Sampling along a pass**: drop-cutter on a grid of step `sample_step_mm`, then chords are
//!   bisected until the CL polyline follows the true CL curve within the chord tolerance, lifted
//!   where a chord would dip under the true CL, and collinear points are dropped (`follow`).
//! - **Boundary**: the part's silhouette or a user polygon (the tool axis stays inside it; ends
//!   of runs found by bisection). On the silhouette the passes by default run on past the
//!   part's XY outline (the *contact boundary*, `contact_boundary`): the tool may stand up to
//!   its radius beyond the edge, and each run ends where its contact point reaches the edge's
//!   rim (found by bisection), so where the surface falls away toward the edge the strip
//!   between the contact and the edge is cut too (stopping with the axis over the edge left up
//!   to 0.12 mm on bicubic-hills for h = 0.05 mm). Beyond that point the tool would only roll
//!   over the rim. Passes alongside an edge that touch nothing but its rim are dropped, all but
//!   the innermost. `contact_boundary: false` keeps the axis over the outline, and so do flat
//!   and bull-nose cutters (their contact on a level area is any point under the flat bottom).
//! - **Links**: between runs closer than `max_link_mm` the tool stays down, following the CL
//!   surface along the straight XY link (a fed `Link`, gouge-free by construction); otherwise it
//!   retracts: rapid up to the clearance plane, rapid across, rapid down to 1 mm above the
//!   next start and plunge.
//!
//! Every pose carries its drop-cutter contact point and kind, and the predicted scallop toward
//! its neighbouring passes.

mod envelope;
mod follow;
mod passes;
mod stepover;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::diagnostics::{Diagnostic, Progress};
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::toolpath::{ContactKind, MoveKind, Pose, ToolRecord, Toolpath};
use crate::tools::dropcutter::{ClPoint, Contact, drop_cutter};
use crate::tools::{Cutter, CutterKind};
use follow::{ClSample, Follower};
use passes::{CoarsePass, Cusp, Region, coarse_pass, contact_normal, cusps};
use stepover::StepoverTable;

/// The order of passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RasterPattern {
    /// Alternate directions: every other pass is machined backwards.
    ZigZag,
    /// Every pass in the same direction (climb or conventional throughout); retract between.
    OneWay,
}

/// Where the passes run.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Boundary {
    /// The part's XY outline: the tool axis stays over the mesh.
    Silhouette,
    /// A closed XY polygon (mm, even-odd rule, at least 3 vertices).
    Polygon(Vec<DVec2>),
}

/// Options of [`raster`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RasterOptions {
    /// Pass direction, rad from +X.
    pub angle_rad: f64,
    /// Zig-zag or one-way.
    pub pattern: RasterPattern,
    /// Scallop height h, mm (> 0).
    pub scallop_mm: f64,
    /// Chord tolerance of the CL polyline against the true CL curve, mm (> 0).
    pub chord_tol_mm: f64,
    /// Where passes run.
    pub boundary: Boundary,
    /// Clearance plane height above the part's top, mm (≥ 0).
    pub clearance_mm: f64,
    /// Cutting (and link) feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed_mm_per_min: f64,
    /// Steepest cross slope held to the scallop, rad (0 < slope < 90°).
    pub max_slope_rad: f64,
    /// Longest XY link on which the tool stays down, mm.
    pub max_link_mm: f64,
    /// Grid step of the first drop-cutter samples along a pass, mm (None: R/2, within
    /// 0.05–2 mm).
    pub sample_step_mm: Option<f64>,
    /// With the silhouette boundary: run the passes on past the part's outline until the
    /// contact point reaches the edge (the tool rolls over it), so that the surface is finished
    /// up to the edge where it falls away under the tool (true, the default); false keeps the
    /// tool axis over the part, which leaves a strip uncut at edges on a slope. Ball end mills
    /// only (a flat bottom's contact on a level area is ambiguous; flat and bull-nose cutters
    /// keep the axis over the part). A polygon boundary always keeps the axis inside it.
    #[serde(default = "contact_boundary_default")]
    pub contact_boundary: bool,
}

fn contact_boundary_default() -> bool {
    true
}

impl Default for RasterOptions {
    fn default() -> Self {
        Self {
            angle_rad: 0.0,
            pattern: RasterPattern::ZigZag,
            scallop_mm: 0.01,
            chord_tol_mm: 0.01,
            boundary: Boundary::Silhouette,
            clearance_mm: 5.0,
            feed_mm_per_min: 1000.0,
            plunge_feed_mm_per_min: 300.0,
            max_slope_rad: 70f64.to_radians(),
            max_link_mm: 10.0,
            sample_step_mm: None,
            contact_boundary: true,
        }
    }
}

/// Why a raster path could not be planned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RasterError {
    /// An option is out of range.
    #[error("invalid raster option: {0}")]
    Option(String),
    /// The region holds no pass (the boundary misses the part).
    #[error("no pass lies inside the boundary over the part")]
    Empty,
    /// Cancelled through the progress handle.
    #[error("cancelled")]
    Cancelled,
}

/// A planned raster path and what the planner found.
#[derive(Clone, Debug, PartialEq)]
pub struct RasterPlan {
    /// The tool path.
    pub toolpath: Toolpath,
    /// Number of passes.
    pub passes: usize,
    /// Largest predicted cusp between neighbouring passes on slopes up to the limit, mm. Not
    /// counted: material in valleys narrower than the tool, at the ends of passes where the
    /// tool stops on a slope, and on walls steeper than the limit (each reported in
    /// `diagnostics` and in the fields below).
    pub max_predicted_scallop_mm: f64,
    /// Area of the surface inside the boundary steeper than `max_slope_rad`, mm² (not held to
    /// the scallop height).
    pub steep_area_mm2: f64,
    /// Plan-view area where material stays that no step-over removes (corners and valleys
    /// narrower than the tool, the foot of walls), mm²: grid step × pass gap per point.
    pub unreachable_area_mm2: f64,
    /// Notes (passes at the smallest step that still exceed h, ...).
    pub diagnostics: Vec<Diagnostic>,
}

/// The pass frame: t along the passes, w across.
pub(crate) struct Frame {
    u: DVec2,
    c: DVec2,
}

impl Frame {
    fn new(angle: f64) -> Self {
        let u = DVec2::new(angle.cos(), angle.sin());
        Self { u, c: u.perp() }
    }

    pub(crate) fn at(&self, t: f64, w: f64) -> DVec2 {
        self.u * t + self.c * w
    }
}

/// Plan raster finishing of `mesh` (with its hierarchy `bvh`) with `tool`.
///
/// # Errors
/// [`RasterError::Option`] for a bad option, [`RasterError::Empty`] when no pass lies over the
/// part inside the boundary.
pub fn raster(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &RasterOptions,
) -> Result<RasterPlan, RasterError> {
    raster_progress(mesh, bvh, tool, opts, &Progress::new())
}

fn check_options(opts: &RasterOptions) -> Result<(), RasterError> {
    let positive = [
        ("scallop height", opts.scallop_mm),
        ("chord tolerance", opts.chord_tol_mm),
        ("feed", opts.feed_mm_per_min),
        ("plunge feed", opts.plunge_feed_mm_per_min),
    ];
    for (what, v) in positive {
        if !(v > 0.0 && v.is_finite()) {
            return Err(RasterError::Option(format!(
                "{what} must be positive, got {v}"
            )));
        }
    }
    if !opts.angle_rad.is_finite() {
        return Err(RasterError::Option("angle must be finite".into()));
    }
    if !(opts.clearance_mm >= 0.0 && opts.clearance_mm.is_finite()) {
        return Err(RasterError::Option(format!(
            "clearance must be ≥ 0 mm, got {}",
            opts.clearance_mm
        )));
    }
    if !(opts.max_link_mm >= 0.0 && opts.max_link_mm.is_finite()) {
        return Err(RasterError::Option("max link length must be ≥ 0 mm".into()));
    }
    if !(opts.max_slope_rad > 0.0 && opts.max_slope_rad < 89.5f64.to_radians()) {
        return Err(RasterError::Option(
            "steepest slope must be between 0 and 89 degrees".into(),
        ));
    }
    if let Some(s) = opts.sample_step_mm
        && !(s > 0.0 && s.is_finite())
    {
        return Err(RasterError::Option(format!(
            "sample step must be positive, got {s}"
        )));
    }
    if let Boundary::Polygon(p) = &opts.boundary
        && (p.len() < 3 || p.iter().any(|v| !v.is_finite()))
    {
        return Err(RasterError::Option(
            "boundary polygon needs at least 3 finite vertices".into(),
        ));
    }
    Ok(())
}

/// [`raster`] reporting progress and stopping when cancelled.
///
/// # Errors
/// As [`raster`], plus [`RasterError::Cancelled`].
pub fn raster_progress(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &RasterOptions,
    progress: &Progress,
) -> Result<RasterPlan, RasterError> {
    check_options(opts)?;
    let cutter = &tool.cutter;
    cutter
        .validate()
        .map_err(|e| RasterError::Option(e.to_string()))?;
    let h = opts.scallop_mm;
    let frame = Frame::new(opts.angle_rad);
    let top = bvh.bbox().max.z;
    let PassLines {
        region,
        tmin,
        dt,
        grid,
        wmin,
        wmax,
    } = PassLines::new(opts, bvh, &frame, cutter)?;

    let table = StepoverTable::new(cutter, h, opts.max_slope_rad);
    let s0 = table.step(0.0);
    if !(s0 > 0.0) {
        return Err(RasterError::Option(format!(
            "scallop {h} mm gives no step-over for this cutter"
        )));
    }
    let s_min = (0.05 * s0).max(1.0e-3);
    let cos_max = opts.max_slope_rad.cos();
    let eps = 1.0e-3_f64.min(0.25 * (wmax - wmin));
    let (w_first, w_last) = (wmin + eps, wmax - eps);
    let mut diagnostics = Vec::new();
    let search = StepSearch {
        frame: &frame,
        grid: &grid,
        region: &region,
        bvh,
        mesh,
        cutter,
        cos_max,
        h,
        s_min,
        w_last,
    };

    // Passes, one after the other, each at the largest step that keeps its cusps ≤ h.
    let mut passes: Vec<CoarsePass> = Vec::new();
    let mut between: Vec<Vec<Option<f64>>> = Vec::new();
    let mut cur = coarse_pass(&frame, w_first, &grid, &region, bvh, mesh, cutter);
    let mut over = 0usize;
    let mut unreachable = Unscalloped::default();
    let mut run_ends = Unscalloped::default();
    let part_box = mesh.bbox();
    loop {
        progress.check().map_err(|_| RasterError::Cancelled)?;
        progress.set(0.5 * (cur.w - wmin) / (wmax - wmin).max(1e-12));
        if cur.w >= w_last - 1e-9 {
            passes.push(cur);
            break;
        }
        // Contacts on the rim (the tool rolling over the part's edge) say nothing of the slope.
        let steepest = cur
            .cl
            .iter()
            .zip(&cur.rim)
            .zip(&grid)
            .filter(|((_, rim), _)| !**rim)
            .filter_map(|((cl, _), t)| cl.as_ref().map(|cl| (cl, *t)))
            .map(|(cl, t)| {
                let tip = frame.at(t, cur.w).extend(cl.z);
                let n = contact_normal(cutter, mesh, tip, cl);
                let across = n.truncate().dot(frame.c).abs();
                across.atan2(n.z.max(0.0)).min(opts.max_slope_rad)
            })
            .fold(0.0_f64, f64::max);
        let (next, cusp, stuck, gave_up) = search.next_pass(&cur, table.step(steepest).max(s_min));
        if gave_up {
            over += 1;
        }
        // Only scallops proper stay attached to the poses; the rest is reported apart (not
        // between two passes that only touch the part's rim: those are dropped but the inner).
        let (mut run_ends_here, mut unreachable_here) = (&mut run_ends, &mut unreachable);
        let mut ignored = (Unscalloped::default(), Unscalloped::default());
        if rim_only(&cur) && rim_only(&next) {
            run_ends_here = &mut ignored.0;
            unreachable_here = &mut ignored.1;
        }
        let cell = dt * (next.w - cur.w).abs();
        // Beyond the part's plan-view box (passes running on past an open sheet's edge) the
        // material is in the air, not out of reach; on walls steeper than the limit it is in
        // the steep area, reported apart.
        let (lo, hi) = (part_box.min.truncate(), part_box.max.truncate());
        let over_part = |p: DVec2| p.cmpge(lo).all() && p.cmple(hi).all();
        let kept: Vec<Option<f64>> = cusp
            .iter()
            .zip(&stuck)
            .map(|(c, st)| {
                let c = (*c)?;
                // Material a midway pass would leave as well (or, at stuck points, whatever
                // stays) is not a scallop; at run ends it is bounded by where the tool stops.
                let rest = c.unreachable.max(if *st { c.height } else { 0.0 });
                if c.at_end {
                    run_ends_here.add(rest.max(c.height), h, cell);
                } else if over_part(c.at) && !c.steep {
                    unreachable_here.add(rest, h, cell);
                }
                let kept = !*st && (!c.at_end || c.height <= h);
                kept.then_some(c.height)
            })
            .collect();
        passes.push(std::mem::replace(&mut cur, next));
        between.push(kept);
    }
    let steep = steep_area_mm2(mesh, &region, opts.max_slope_rad);
    diagnostics.extend(leftover_diagnostics(
        over,
        s_min,
        &unreachable,
        &run_ends,
        steep,
        opts,
    ));
    let max_pred = between
        .iter()
        .flatten()
        .flatten()
        .fold(0.0_f64, |a, b| a.max(*b));
    drop_outer_rim_passes(&mut passes);

    // Follow every run of every pass (in parallel, results in order).
    let follower = Follower {
        bvh,
        mesh,
        cutter,
        chord_tol: opts.chord_tol_mm,
    };
    let followed: Vec<Vec<Vec<ClSample>>> = passes
        .par_iter()
        .map(|p| {
            // Cancel answers between passes here too (following is most of a large plan).
            if progress.is_cancelled() {
                return Vec::new();
            }
            p.runs
                .iter()
                .map(|run| follower.follow(frame.at(0.0, p.w), frame.u, run))
                .filter(|r| !r.is_empty())
                .collect()
        })
        .collect();
    progress.check().map_err(|_| RasterError::Cancelled)?;
    if followed.iter().all(Vec::is_empty) {
        return Err(RasterError::Empty);
    }

    // Order the runs, attach the predicted scallop, and link them.
    let runs = ordered_runs(&followed, &between, tmin, dt, opts);
    let clear_z = top + opts.clearance_mm;
    let poses = link_runs(&runs, &follower, opts, clear_z, dt);
    progress.set(1.0);
    Ok(RasterPlan {
        toolpath: Toolpath::new(tool.clone(), poses),
        passes: passes.iter().filter(|p| !p.runs.is_empty()).count(),
        max_predicted_scallop_mm: max_pred,
        steep_area_mm2: steep,
        unreachable_area_mm2: unreachable.area_mm2,
        diagnostics,
    })
}

/// Where and how densely the pass lines are sampled: the region passes run in, the extent of the
/// passes across (w) in the raster frame, and the sample grid along a line (from `tmin` at step
/// `dt`).
struct PassLines<'a> {
    region: Region<'a>,
    tmin: f64,
    dt: f64,
    grid: Vec<f64>,
    wmin: f64,
    wmax: f64,
}

impl<'a> PassLines<'a> {
    /// The lines over the boundary of `opts` (the part's box for the silhouette, widened by a
    /// tool radius for the contact boundary).
    fn new(
        opts: &'a RasterOptions,
        bvh: &'a MeshBvh,
        frame: &Frame,
        cutter: &Cutter,
    ) -> Result<Self, RasterError> {
        let big = cutter.radius();
        let bbox = bvh.bbox();
        let top = bbox.max.z;
        let outline: Vec<DVec2> = match &opts.boundary {
            Boundary::Silhouette => vec![
                bbox.min.truncate(),
                DVec2::new(bbox.max.x, bbox.min.y),
                bbox.max.truncate(),
                DVec2::new(bbox.min.x, bbox.max.y),
            ],
            Boundary::Polygon(p) => p.clone(),
        };
        let region = match &opts.boundary {
            // A flat bottom's contact on a level area is any point under it (often a rim vertex
            // with the axis well inside), so only ball end mills get the contact boundary.
            Boundary::Silhouette
                if opts.contact_boundary && matches!(cutter.kind, CutterKind::Ball) =>
            {
                Region::Contact(bvh, top + 1.0)
            }
            Boundary::Silhouette => Region::Silhouette(bvh, top + 1.0),
            Boundary::Polygon(p) => Region::Polygon(p),
        };
        // With the contact boundary the axis may stand up to a tool radius beyond the outline.
        let beyond = if matches!(region, Region::Contact(..)) {
            big
        } else {
            0.0
        };
        let (mut tmin, mut tmax, mut wmin, mut wmax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in &outline {
            let (t, w) = (p.dot(frame.u), p.dot(frame.c));
            tmin = tmin.min(t - beyond);
            tmax = tmax.max(t + beyond);
            wmin = wmin.min(w - beyond);
            wmax = wmax.max(w + beyond);
        }
        let dt_wanted = opts.sample_step_mm.unwrap_or((0.5 * big).clamp(0.05, 2.0));
        let count = ((tmax - tmin) / dt_wanted).ceil();
        if !(count.is_finite() && count <= 1.0e6) {
            return Err(RasterError::Option(format!(
                "sample step {dt_wanted} mm gives too many samples over {} mm",
                tmax - tmin
            )));
        }
        let count = (count as usize).max(1);
        let dt = (tmax - tmin) / count as f64;
        let grid: Vec<f64> = (0..=count).map(|j| tmin + dt * j as f64).collect();
        Ok(Self {
            region,
            tmin,
            dt,
            grid,
            wmin,
            wmax,
        })
    }
}

/// What the step search between two passes reads.
#[derive(Clone, Copy)]
struct StepSearch<'a> {
    frame: &'a Frame,
    grid: &'a [f64],
    region: &'a Region<'a>,
    bvh: &'a MeshBvh,
    mesh: &'a TriMesh,
    cutter: &'a Cutter,
    /// Cosine of the steepest slope held to the scallop height.
    cos_max: f64,
    /// Scallop height, mm.
    h: f64,
    /// Smallest step-over, mm.
    s_min: f64,
    /// Position of the last pass across, mm.
    w_last: f64,
}

impl StepSearch<'_> {
    /// The pass after `cur` at the largest step (from `s` down, mm) whose cusps stay within h,
    /// with its cusps, the grid points whose cusp did not shrink with the step (material the
    /// cutter cannot reach), and whether even the smallest step (or the eighth try) left a cusp
    /// above h.
    fn next_pass(
        &self,
        cur: &CoarsePass,
        mut s: f64,
    ) -> (CoarsePass, Vec<Option<Cusp>>, Vec<bool>, bool) {
        let Self {
            frame,
            grid,
            region,
            bvh,
            mesh,
            cutter,
            cos_max,
            h,
            s_min,
            w_last,
        } = *self;
        let mut tries = 0;
        // Grid points whose cusp does not shrink with the step hold material the cutter cannot
        // reach (a valley narrower than the tool), not a scallop: they stop counting.
        let mut stuck = vec![false; grid.len()];
        let mut last: Option<Vec<Option<Cusp>>> = None;
        // The last step that left a cusp above h, and the best step found within h (with its
        // pass and cusps), for one try at growing back a step that the shrinking overshot.
        let mut failed: Option<(f64, f64)> = None;
        let mut within: Option<(f64, CoarsePass, Vec<Option<Cusp>>)> = None;
        let mut gave_up = false;
        let (next, cusp) = loop {
            let w = (cur.w + s).min(w_last);
            let next = coarse_pass(frame, w, grid, region, bvh, mesh, cutter);
            let mid = coarse_pass(frame, 0.5 * (cur.w + w), grid, region, bvh, mesh, cutter);
            let cusp = cusps(frame, grid, cur, &next, &mid, cutter, bvh, cos_max);
            let growing = within.is_some();
            if let Some(prev) = &last
                && !growing
            {
                for ((st, new), old) in stuck.iter_mut().zip(&cusp).zip(prev) {
                    if let (Some(n), Some(o)) = (new, old)
                        && n.height > h
                        && n.height >= 0.8 * o.height
                    {
                        *st = true;
                    }
                }
            }
            // Run ends do not steer the step: the material there is bounded by where the tool
            // stops along the pass, which the step-over cannot change.
            let worst = cusp
                .iter()
                .zip(&stuck)
                .filter(|(_, st)| !**st)
                .filter_map(|(c, _)| c.filter(|c| !c.at_end))
                .fold(0.0_f64, |m, c| m.max(c.height));
            tries += 1;
            if growing {
                // The grown step either holds (take it) or not (back to the one that did).
                match within.take() {
                    Some((_, p, c)) if worst > h => break (p, c),
                    _ => break (next, cusp),
                }
            }
            if worst <= h {
                // Shrunk too far (the cusp grows about as s², so 0.8 h means a step 10 % short):
                // try once the step that the two tries bracketing h point to, on a log-log line.
                if let Some((sf, wf)) = failed
                    && worst > 0.0
                    && worst < GROW_BELOW * h
                    && w < w_last
                {
                    let k = (wf / worst).ln() / (sf / s).ln();
                    let grown = s * (GROW_TARGET * h / worst).powf(1.0 / k.max(1.0));
                    if grown.is_finite() && grown > 1.02 * s && grown < sf {
                        within = Some((s, next, cusp));
                        s = grown;
                        continue;
                    }
                }
                break (next, cusp);
            }
            if s <= s_min || tries >= 8 {
                gave_up = true;
                break (next, cusp);
            }
            failed = Some((s, worst));
            last = Some(cusp);
            let f = (0.95 * (h / worst).sqrt()).clamp(0.3, 0.9);
            s = (s * f).max(s_min);
        };
        (next, cusp, stuck, gave_up)
    }
}

/// What the passes leave beyond the scallop height: `over` gaps whose cusp stays above h at the
/// smallest step `s_min`, unreachable material, material at run ends, and the steep area
/// (mm²) not held to h.
fn leftover_diagnostics(
    over: usize,
    s_min: f64,
    unreachable: &Unscalloped,
    run_ends: &Unscalloped,
    steep: f64,
    opts: &RasterOptions,
) -> Vec<Diagnostic> {
    let h = opts.scallop_mm;
    let mut diagnostics = Vec::new();
    if over > 0 {
        diagnostics.push(Diagnostic::warning(
            None,
            format!(
                "{over} pass gaps keep a cusp above the scallop height {h} mm at the smallest step {s_min:.4} mm"
            ),
        ));
    }
    if unreachable.count > 0 {
        diagnostics.push(Diagnostic::warning(
            None,
            format!(
                "{} points (about {:.1} mm² in plan view) in corners or valleys narrower than the tool, or at the foot of walls, keep up to {:.4} mm of material no step-over removes (not counted as scallop)",
                unreachable.count, unreachable.area_mm2, unreachable.max
            ),
        ));
    }
    if run_ends.count > 0 {
        diagnostics.push(Diagnostic::warning(
            None,
            format!(
                "{} points at the ends of passes (the boundary) keep up to {:.4} mm where the tool stops on a slope (not counted as scallop)",
                run_ends.count, run_ends.max
            ),
        ));
    }
    if steep > 0.0 {
        diagnostics.push(Diagnostic::info(
            None,
            format!(
                "steep walls: {steep:.1} mm² of surface beyond {:.0}° is not held to the scallop height (finish it with a Z-level pass)",
                opts.max_slope_rad.to_degrees()
            ),
        ));
    }
    diagnostics
}

/// The followed runs of every pass as cutting poses, in cutting order (every other pass reversed
/// for zig-zag), each pose with the scallop predicted on either side of its pass (`between`:
/// per gap, per grid point from `tmin` at step `dt`).
fn ordered_runs(
    followed: &[Vec<Vec<ClSample>>],
    between: &[Vec<Option<f64>>],
    tmin: f64,
    dt: f64,
    opts: &RasterOptions,
) -> Vec<Vec<Pose>> {
    let mut runs: Vec<Vec<Pose>> = Vec::new();
    for (k, pass_runs) in followed.iter().enumerate() {
        let prev = k.checked_sub(1).and_then(|i| between.get(i));
        let next = between.get(k);
        let mut rs: Vec<Vec<Pose>> = pass_runs
            .iter()
            .map(|run| {
                run.iter()
                    .map(|s| {
                        let j = ((s.t - tmin) / dt).round().max(0.0) as usize;
                        let pick = |v: Option<&Vec<Option<f64>>>| {
                            v.and_then(|v| v.get(j)).copied().flatten()
                        };
                        let sc = match (pick(prev), pick(next)) {
                            (Some(a), Some(b)) => Some(a.max(b)),
                            (a, b) => a.or(b),
                        };
                        let pose = Pose::new(MoveKind::Cut, s.tip, DVec3::Z, opts.feed_mm_per_min)
                            .with_contact(s.cl.cc, contact_kind(s.cl.contact));
                        match sc {
                            Some(v) => pose.with_scallop(v),
                            None => pose,
                        }
                    })
                    .collect()
            })
            .collect();
        if opts.pattern == RasterPattern::ZigZag && k % 2 == 1 {
            rs.reverse();
            for r in &mut rs {
                r.reverse();
            }
        }
        runs.extend(rs);
    }
    runs
}

/// Whether the pass touches the part only on its rim (or not at all).
fn rim_only(p: &CoarsePass) -> bool {
    p.cl.iter().zip(&p.rim).all(|(c, rim)| c.is_none() || *rim)
}

/// With the contact boundary the first passes hang over the part's edge and touch only its
/// rim; of those, each touches the rim where the next one inward touches it as well, closer to
/// its axis, and cuts nothing that one does not: all but the innermost such pass on either
/// side lose their runs (the innermost one bounds the cusp at the rim that the step-over was
/// measured against).
fn drop_outer_rim_passes(passes: &mut [CoarsePass]) {
    let first = passes.iter().position(|p| !rim_only(p));
    let last = passes.iter().rposition(|p| !rim_only(p));
    let (Some(first), Some(last)) = (first, last) else {
        return;
    };
    for (k, p) in passes.iter_mut().enumerate() {
        if k + 1 < first || k > last + 1 {
            p.runs.clear();
        }
    }
}

/// A step whose worst cusp is below this fraction of h after shrinking is grown back once.
const GROW_BELOW: f64 = 0.9;
/// The cusp, as a fraction of h, that growing a step aims at.
const GROW_TARGET: f64 = 0.95;

/// Material above the scallop height that is not a scallop: how many grid points, how thick.
#[derive(Default)]
struct Unscalloped {
    count: usize,
    max: f64,
    /// Plan-view area of the grid cells counted, mm².
    area_mm2: f64,
}

impl Unscalloped {
    /// Count a grid point whose cell (step along the pass × gap between the passes) covers
    /// `cell_mm2`, when `height` exceeds `h`.
    fn add(&mut self, height: f64, h: f64, cell_mm2: f64) {
        if height > h {
            self.count += 1;
            self.max = self.max.max(height);
            self.area_mm2 += cell_mm2;
        }
    }
}

/// Area of the triangles steeper than `max_slope` (facing up or vertical) whose centroid lies
/// inside the region, mm².
fn steep_area_mm2(mesh: &TriMesh, region: &Region, max_slope: f64) -> f64 {
    let cos_max = max_slope.cos();
    (0..mesh.triangles.len())
        .into_par_iter()
        .filter_map(|t| {
            let [a, b, c] = mesh.triangle_corners(t)?;
            let n = (b - a).cross(c - a);
            let area = 0.5 * n.length();
            let n = n.try_normalize()?;
            // Steeper than the limit, and not a downward-facing overhang or underside.
            if n.z.abs() >= cos_max || n.z < -1.0e-3 {
                return None;
            }
            let centroid = ((a + b + c) / 3.0).truncate();
            region
                .contains(centroid + n.truncate() * 1.0e-3)
                .then_some(area)
        })
        .sum()
}

fn contact_kind(c: Contact) -> ContactKind {
    match c {
        Contact::Vertex => ContactKind::MeshVertex,
        Contact::Edge => ContactKind::MeshEdge,
        Contact::Facet => ContactKind::MeshFacet,
    }
}

/// Join the runs: stay down along the CL surface over short links, retract otherwise.
fn link_runs(
    runs: &[Vec<Pose>],
    follower: &Follower,
    opts: &RasterOptions,
    clear_z: f64,
    dt: f64,
) -> Vec<Pose> {
    let mut out: Vec<Pose> = Vec::new();
    let rapid = |p: DVec3| Pose::new(MoveKind::Rapid, p, DVec3::Z, opts.feed_mm_per_min);
    for run in runs {
        let (Some(first), Some(_)) = (run.first(), run.last()) else {
            continue;
        };
        let stay = out
            .last()
            .and_then(|p| stay_down(p, first, follower, opts, dt));
        let stayed = stay.is_some();
        match stay {
            Some(link) => out.extend(link),
            None => {
                if let Some(p) = out.last().copied() {
                    out.push(rapid(p.tip.truncate().extend(clear_z)));
                }
                out.push(rapid(first.tip.truncate().extend(clear_z)));
                let approach = (first.tip.z + 1.0).min(clear_z);
                out.push(rapid(first.tip.truncate().extend(approach)));
                let mut plunge = *first;
                plunge.kind = MoveKind::Plunge;
                plunge.feed_mm_per_min = opts.plunge_feed_mm_per_min;
                out.push(plunge);
            }
        }
        let skip = usize::from(!stayed);
        out.extend(run.iter().skip(skip).copied());
    }
    if let Some(p) = out.last().copied() {
        out.push(rapid(p.tip.truncate().extend(clear_z)));
    }
    out
}

/// The fed link from `from` to `to` along the CL surface, when short and over the part.
fn stay_down(
    from: &Pose,
    to: &Pose,
    follower: &Follower,
    opts: &RasterOptions,
    dt: f64,
) -> Option<Vec<Pose>> {
    let (a, b) = (from.tip.truncate(), to.tip.truncate());
    let len = a.distance(b);
    if len > opts.max_link_mm {
        return None;
    }
    if len < 1e-9 {
        return Some(Vec::new());
    }
    let dir = (b - a) / len;
    let n = (len / dt).ceil().max(1.0) as usize;
    let ts: Vec<f64> = (0..=n).map(|i| len * i as f64 / n as f64).collect();
    let xy: Vec<DVec2> = ts.iter().map(|t| a + dir * *t).collect();
    let cls = drop_cutter(follower.bvh, follower.mesh, follower.cutter, &xy);
    let samples: Option<Vec<(f64, ClPoint)>> = ts
        .iter()
        .zip(cls)
        .map(|(t, c)| c.map(|c| (*t, c)))
        .collect();
    let path = follower.follow(a, dir, &samples?);
    // The ends may sit at another height than the runs' own ends (each is lifted on its own):
    // the vertical moves between them stay above the CL at that XY.
    Some(
        path.iter()
            .map(|s| {
                Pose::new(MoveKind::Link, s.tip, DVec3::Z, opts.feed_mm_per_min)
                    .with_contact(s.cl.cc, contact_kind(s.cl.contact))
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::Cutter;

    /// A plane falling along +X at θ over [0, 40] × [0, 20] mm.
    fn tilted(theta: f64) -> (TriMesh, MeshBvh) {
        let z = |x: f64| -x * theta.tan();
        let p = |x: f64, y: f64| DVec3::new(x, y, z(x));
        let mesh = TriMesh::new(
            vec![p(0.0, 0.0), p(40.0, 0.0), p(40.0, 20.0), p(0.0, 20.0)],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        let bvh = MeshBvh::new(&mesh).unwrap();
        (mesh, bvh)
    }

    /// On a plane sloping at θ along the passes a ball touches it R·sin θ uphill of its axis:
    /// with the contact boundary each run starts with its axis R·sin θ inside the upper edge
    /// (x = 0) and ends R·sin θ beyond the lower one (x = 40), where the contact reaches it;
    /// with the axis held over the part the runs end at x = 40, the contact R·sin θ short.
    #[test]
    fn contact_boundary_runs_until_the_contact_reaches_the_edge() {
        let theta = 20f64.to_radians();
        let (mesh, bvh) = tilted(theta);
        let tool = ToolRecord {
            spec: "ball:d=6".into(),
            cutter: Cutter::new(CutterKind::Ball, 6.0).unwrap(),
        };
        let reach = 3.0 * theta.sin();
        for contact in [true, false] {
            let opts = RasterOptions {
                scallop_mm: 0.05,
                contact_boundary: contact,
                ..RasterOptions::default()
            };
            let plan = raster(&mesh, &bvh, &tool, &opts).unwrap();
            let cuts: Vec<&Pose> = plan
                .toolpath
                .poses
                .iter()
                .filter(|p| p.kind == MoveKind::Cut && p.tip.y > 0.1 && p.tip.y < 19.9)
                .collect();
            assert!(cuts.len() > 20);
            let (lo, hi) = cuts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                (lo.min(p.tip.x), hi.max(p.tip.x))
            });
            let (want_lo, want_hi) = if contact {
                (reach, 40.0 + reach)
            } else {
                (0.0, 40.0)
            };
            assert!(
                (lo - want_lo).abs() < 0.01 && (hi - want_hi).abs() < 0.01,
                "contact {contact}: runs over x {lo}..{hi}, want {want_lo}..{want_hi}"
            );
            // Where the contact is on the plane, the tip stands R(sec θ − 1) above it (a chord
            // next to the rim may be lifted by up to half the chord tolerance).
            for p in cuts
                .iter()
                .filter(|p| p.tip.x > reach + 0.01 && p.tip.x < 39.99)
            {
                let on_plane = -p.tip.x * theta.tan() + 3.0 * (1.0 / theta.cos() - 1.0);
                let above = p.tip.z - on_plane;
                assert!(
                    (-1e-6..=0.5 * opts.chord_tol_mm + 1e-6).contains(&above),
                    "{p:?}"
                );
            }
        }
    }
}
