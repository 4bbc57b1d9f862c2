//! Rest finishing on a triangle mesh with a ball end mill: parallel passes only where a larger
//! reference tool (the one an earlier operation used) left material.
//!
//! - **What is left**: by default where the reference tool leaves it ([`rest`]); [`rest_where`]
//!   takes the thickness from elsewhere (the simulated stock of the earlier operations).
//! - **Reference surface**: the reference tool is dropped on a regular XY grid (step
//!   `sampling_mm`, over the part grown by its radius); what it leaves is bounded by the lower
//!   envelope of its bodies at those locations.
//! - **Rest thickness** at a contact point c of the finishing ball (normal n, from the contact
//!   toward the ball's centre): for a ball reference, the distance from c to the nearest
//!   reference ball less its radius, the grid's locations and the one where the reference would
//!   touch c with the same normal (the thickness is 0 wherever it does); for other cutters, the
//!   height of the reference envelope above c (the profile's height at the radial distance,
//!   lowest over the locations in reach) times n_z, the normal thickness of a layer on a plane
//!   of that slope. A contact with more than `threshold_mm` left is in the rest area.
//! - **Passes** run along +X, `2·√(2Rh − h²)` apart (the scallop rule on a level floor),
//!   sampled at the grid step; the runs of samples whose contact is in the rest area, grown by
//!   `overlap_mm` along the pass and by one pass across, are cut. A chord of a run is halved
//!   while the drop-cutter location at its middle lies farther than the chord tolerance from
//!   it (up to six times). Passes zig-zag; between runs the tool moves fed and straight when the
//!   run starts within two step-overs and that move stays above the drop-cutter surface,
//!   otherwise it retracts to the clearance plane, rapids across and plunges.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::diagnostics::Diagnostic;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::toolpath::{ContactKind, MoveKind, Pose, ToolRecord, Toolpath};
use crate::tools::dropcutter::{ClPoint, drop_cutter, drop_cutter_at};
use crate::tools::{Cutter, CutterKind};

/// Options of [`rest`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RestOptions {
    /// The earlier, larger tool whose leftovers are finished.
    pub reference: Cutter,
    /// Rest thickness below which a contact counts as finished, mm (> 0).
    pub threshold_mm: f64,
    /// Scallop height between the passes on a level floor, mm (> 0).
    pub scallop_mm: f64,
    /// Chord tolerance along the passes, mm (> 0).
    pub chord_tol_mm: f64,
    /// Grid step of the reference tool and of the samples along a pass, mm (None: the
    /// finishing radius / 4 within 0.05–1 mm).
    pub sampling_mm: Option<f64>,
    /// How far the runs are grown past the rest area along the pass, mm (≥ 0).
    pub overlap_mm: f64,
    /// Clearance plane height above the part's top, mm (≥ 0).
    pub clearance_mm: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed_mm_per_min: f64,
}

/// Why a rest path could not be planned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RestError {
    /// An option or a cutter is out of range.
    #[error("invalid rest option: {0}")]
    Option(String),
    /// The reference tool leaves nothing the finishing tool reaches.
    #[error(
        "no rest area: the reference tool leaves less than {0} mm wherever the finishing tool touches"
    )]
    Empty(f64),
}

/// A planned rest path.
#[derive(Clone, Debug, PartialEq)]
pub struct RestPlan {
    /// The tool path.
    pub toolpath: Toolpath,
    /// Number of cut runs.
    pub runs: usize,
    /// Largest rest thickness met at a finishing contact, mm.
    pub max_rest_mm: f64,
    /// Notes.
    pub diagnostics: Vec<Diagnostic>,
}

fn check_reference(tool: &ToolRecord, o: &RestOptions) -> Result<(), RestError> {
    if o.reference.validate().is_err() || o.reference.radius() <= tool.cutter.radius() {
        return Err(RestError::Option(format!(
            "the reference tool must be a valid cutter larger than the finishing tool ({} mm), got {} mm",
            tool.cutter.diameter, o.reference.diameter
        )));
    }
    Ok(())
}

fn check(tool: &ToolRecord, o: &RestOptions) -> Result<(), RestError> {
    let bad = |m: String| Err(RestError::Option(m));
    if tool.cutter.kind != CutterKind::Ball {
        return bad("rest finishing needs a ball end mill (ball:d=...)".into());
    }
    for (what, v) in [
        ("rest threshold (mm)", o.threshold_mm),
        ("scallop height (mm)", o.scallop_mm),
        ("chord tolerance (mm)", o.chord_tol_mm),
        ("feed (mm/min)", o.feed_mm_per_min),
        ("plunge feed (mm/min)", o.plunge_feed_mm_per_min),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return bad(format!("{what} must be positive, got {v}"));
        }
    }
    if o.scallop_mm >= tool.cutter.radius() {
        return bad(format!(
            "scallop height must be below the tool radius, got {} mm",
            o.scallop_mm
        ));
    }
    for (what, v) in [
        ("overlap (mm)", o.overlap_mm),
        ("clearance (mm)", o.clearance_mm),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            return bad(format!("{what} must be at least 0, got {v}"));
        }
    }
    if let Some(s) = o.sampling_mm
        && !(s > 1e-3 && s <= 10.0)
    {
        return bad(format!("sampling must be 0.001 to 10 mm, got {s} mm"));
    }
    Ok(())
}

/// The reference tool's locations on a grid, and how thick a layer it leaves at a point.
pub struct ReferenceSurface {
    cutter: Cutter,
    origin: DVec2,
    step: f64,
    nx: usize,
    ny: usize,
    cl: Vec<Option<f64>>,
}

impl ReferenceSurface {
    /// Drop `cutter` on `mesh` on a grid of `step` mm over the part grown by its radius.
    #[must_use]
    pub fn new(mesh: &TriMesh, bvh: &MeshBvh, cutter: &Cutter, step: f64) -> Self {
        let bb = mesh.bbox();
        let grow = DVec2::splat(cutter.radius());
        let (lo, hi) = (bb.min.truncate() - grow, bb.max.truncate() + grow);
        let nx = ((hi.x - lo.x) / step).ceil() as usize + 1;
        let ny = ((hi.y - lo.y) / step).ceil() as usize + 1;
        let pts: Vec<DVec2> = (0..ny)
            .flat_map(|j| (0..nx).map(move |i| lo + DVec2::new(i as f64, j as f64) * step))
            .collect();
        let cl = drop_cutter(bvh, mesh, cutter, &pts)
            .into_iter()
            .map(|c| c.map(|c| c.z))
            .collect();
        Self {
            cutter: cutter.clone(),
            origin: lo,
            step,
            nx,
            ny,
            cl,
        }
    }

    /// The layer the reference leaves at contact `c` with unit normal `n` (see the module
    /// documentation), mm; 0 where no reference location reaches.
    #[must_use]
    pub fn thickness(&self, c: DVec3, n: DVec3) -> f64 {
        let r = self.cutter.radius();
        let rel = (c.truncate() - self.origin) / self.step;
        let span = (r / self.step).ceil() as i64 + 1;
        let (ci, cj) = (rel.x.round() as i64, rel.y.round() as i64);
        let ball = self.cutter.kind == CutterKind::Ball;
        let mut best = f64::MAX;
        for j in (cj - span).max(0)..=(cj + span).min(self.ny as i64 - 1) {
            for i in (ci - span).max(0)..=(ci + span).min(self.nx as i64 - 1) {
                let Some(z) = self.cl[j as usize * self.nx + i as usize] else {
                    continue;
                };
                let q = self.origin + DVec2::new(i as f64, j as f64) * self.step;
                let d = if ball {
                    c.distance(q.extend(z + r)) - r
                } else {
                    match self.cutter.height_at_radius(q.distance(c.truncate())) {
                        Some(h) => (z + h - c.z) * n.z.max(0.0),
                        None => continue,
                    }
                };
                best = best.min(d);
            }
        }
        if best == f64::MAX { 0.0 } else { best.max(0.0) }
    }

    /// [`Self::thickness`], for a ball reference also tried at the one location where it
    /// would touch `c` with the same normal (centre c + R·n): dropped there, it reaches `c`
    /// when nothing holds it up, which the grid locations around it only approximate.
    #[must_use]
    pub fn thickness_directed(&self, mesh: &TriMesh, bvh: &MeshBvh, c: DVec3, n: DVec3) -> f64 {
        let grid = self.thickness(c, n);
        if self.cutter.kind != CutterKind::Ball {
            return grid;
        }
        let r = self.cutter.radius();
        let q = c.truncate() + r * n.truncate();
        match drop_cutter_at(bvh, mesh, &self.cutter, q) {
            Some(cl) => grid.min((c.distance(q.extend(cl.z + r)) - r).max(0.0)),
            None => grid,
        }
    }
}

/// One sample along a pass: tool tip, contact, rest thickness there.
#[derive(Clone, Copy)]
struct Sample {
    tip: DVec3,
    cc: DVec3,
    rest: f64,
}

/// Plan rest finishing of `mesh` with `tool` (a ball) where `opts.reference` left material.
///
/// # Errors
/// [`RestError::Option`] for a bad option or cutter, [`RestError::Empty`] when nothing is left
/// to finish.
pub fn rest(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &RestOptions,
) -> Result<RestPlan, RestError> {
    check(tool, opts)?;
    check_reference(tool, opts)?;
    let reference = ReferenceSurface::new(mesh, bvh, &opts.reference, sampling(tool, opts));
    let source = format!("the reference tool ({} mm)", opts.reference.diameter);
    let leftover = |c: DVec3, n: DVec3| reference.thickness_directed(mesh, bvh, c, n);
    rest_where(mesh, bvh, tool, opts, &leftover, &source)
}

/// The grid step of the reference tool and of the samples along a pass, mm.
fn sampling(tool: &ToolRecord, opts: &RestOptions) -> f64 {
    opts.sampling_mm
        .unwrap_or((0.25 * tool.cutter.radius()).clamp(0.05, 1.0))
}

/// Plan rest finishing of `mesh` with `tool` (a ball) where `leftover(c, n)`, the thickness of
/// the layer an earlier operation left at the finishing contact `c` along its unit normal `n`
/// (mm), exceeds `opts.threshold_mm`; `source` names what left it in the diagnostics. Used
/// with the simulated stock of the earlier operations; `opts.reference` is not used here.
///
/// # Errors
/// As [`rest`].
pub fn rest_where(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &RestOptions,
    leftover: &(dyn Fn(DVec3, DVec3) -> f64 + Sync),
    source: &str,
) -> Result<RestPlan, RestError> {
    check(tool, opts)?;
    let rf = tool.cutter.radius();
    let step = sampling(tool, opts);
    let h = opts.scallop_mm;
    let across = 2.0 * (2.0 * rf * h - h * h).sqrt();
    let bb = mesh.bbox();
    let (lo, hi) = (bb.min.truncate(), bb.max.truncate());
    let nrow = ((hi.y - lo.y) / across).ceil().max(1.0) as usize + 1;
    let ncol = ((hi.x - lo.x) / step).ceil().max(1.0) as usize + 1;
    let y0 = 0.5 * (lo.y + hi.y) - 0.5 * (nrow - 1) as f64 * across;
    let x0 = 0.5 * (lo.x + hi.x) - 0.5 * (ncol - 1) as f64 * step;
    let rows: Vec<Vec<Option<Sample>>> = (0..nrow)
        .into_par_iter()
        .map(|k| {
            let pts: Vec<DVec2> = (0..ncol)
                .map(|i| DVec2::new(x0 + i as f64 * step, y0 + k as f64 * across))
                .collect();
            pts.iter()
                .map(|p| {
                    let c = drop_cutter_at(bvh, mesh, &tool.cutter, *p)?;
                    Some(sample(leftover, rf, *p, &c))
                })
                .collect()
        })
        .collect();
    let max_rest = rows
        .iter()
        .flatten()
        .flatten()
        .map(|s| s.rest)
        .fold(0.0, f64::max);
    let grow = (opts.overlap_mm / step).ceil() as usize;
    let marks = rest_marks(&rows, opts.threshold_mm, grow);
    let ctx = Follow {
        mesh,
        bvh,
        cutter: &tool.cutter,
        tol: opts.chord_tol_mm,
    };
    let mut runs: Vec<Vec<Sample>> = Vec::new();
    for (k, row) in rows.iter().enumerate() {
        let mut row_runs = row_runs(row, &marks[k]);
        if k % 2 == 1 {
            row_runs.reverse();
            row_runs.iter_mut().for_each(|r| r.reverse());
        }
        runs.extend(row_runs.into_iter().map(|r| ctx.refine_run(&r)));
    }
    if runs.is_empty() {
        return Err(RestError::Empty(opts.threshold_mm));
    }
    let clear = bb.max.z + opts.clearance_mm;
    let poses = link(&ctx, &runs, clear, 2.0 * across, opts);
    let diagnostics = vec![Diagnostic::info(
        None,
        format!(
            "rest: {} runs where {source} leaves more than {} mm; up to {:.3} mm left",
            runs.len(),
            opts.threshold_mm,
            max_rest
        ),
    )];
    Ok(RestPlan {
        toolpath: Toolpath::new(tool.clone(), poses),
        runs: runs.len(),
        max_rest_mm: max_rest,
        diagnostics,
    })
}

fn sample(
    leftover: &(dyn Fn(DVec3, DVec3) -> f64 + Sync),
    rf: f64,
    p: DVec2,
    c: &ClPoint,
) -> Sample {
    let n = (p.extend(c.z + rf) - c.cc).normalize_or(DVec3::Z);
    Sample {
        tip: p.extend(c.z),
        cc: c.cc,
        rest: leftover(c.cc, n),
    }
}

/// Which samples to cut: in the rest area, grown by `grow` samples along the row and by one
/// row across.
fn rest_marks(rows: &[Vec<Option<Sample>>], thr: f64, grow: usize) -> Vec<Vec<bool>> {
    let raw: Vec<Vec<bool>> = rows
        .iter()
        .map(|r| r.iter().map(|s| s.is_some_and(|s| s.rest > thr)).collect())
        .collect();
    let n = raw.len();
    (0..n)
        .map(|k| {
            let m = raw[k].len();
            (0..m)
                .map(|i| {
                    let (a, b) = (i.saturating_sub(grow), (i + grow).min(m - 1));
                    rows[k][i].is_some()
                        && (k.saturating_sub(1)..=(k + 1).min(n - 1))
                            .any(|kk| raw[kk][a..=b].iter().any(|x| *x))
                })
                .collect()
        })
        .collect()
}

fn row_runs(row: &[Option<Sample>], marks: &[bool]) -> Vec<Vec<Sample>> {
    let mut out: Vec<Vec<Sample>> = vec![Vec::new()];
    for (s, m) in row.iter().zip(marks) {
        match (s, m) {
            (Some(s), true) => {
                if let Some(cur) = out.last_mut() {
                    cur.push(*s);
                }
            }
            _ => {
                if out.last().is_some_and(|c| !c.is_empty()) {
                    out.push(Vec::new());
                }
            }
        }
    }
    out.retain(|r| r.len() > 1);
    out
}

/// The finishing tool and the chord tolerance, for refining runs and checking links.
struct Follow<'a> {
    mesh: &'a TriMesh,
    bvh: &'a MeshBvh,
    cutter: &'a Cutter,
    tol: f64,
}

impl Follow<'_> {
    fn drop(&self, p: DVec2) -> Option<ClPoint> {
        drop_cutter_at(self.bvh, self.mesh, self.cutter, p)
    }

    fn refine_run(&self, run: &[Sample]) -> Vec<Sample> {
        let mut out = Vec::with_capacity(run.len());
        for w in run.windows(2) {
            out.push(w[0]);
            self.halve(w[0], w[1], 6, &mut out);
        }
        out.extend(run.last().copied());
        out
    }

    fn halve(&self, a: Sample, b: Sample, depth: u32, out: &mut Vec<Sample>) {
        if depth == 0 {
            return;
        }
        let m = 0.5 * (a.tip + b.tip);
        let Some(c) = self.drop(m.truncate()) else {
            return;
        };
        if (c.z - m.z).abs() <= self.tol {
            return;
        }
        let s = Sample {
            tip: m.truncate().extend(c.z),
            cc: c.cc,
            rest: 0.0,
        };
        self.halve(a, s, depth - 1, out);
        out.push(s);
        self.halve(s, b, depth - 1, out);
    }

    /// Whether a straight move from `a` to `b` stays above the drop-cutter surface.
    fn clear(&self, a: DVec3, b: DVec3) -> bool {
        let n = ((a.truncate().distance(b.truncate()) / (0.1 * self.cutter.radius())).ceil()
            as usize)
            .clamp(2, 64);
        (1..n).all(|i| {
            let p = a.lerp(b, i as f64 / n as f64);
            self.drop(p.truncate())
                .is_none_or(|c| c.z <= p.z + self.tol)
        })
    }
}

fn link(
    ctx: &Follow,
    runs: &[Vec<Sample>],
    clear: f64,
    max_link: f64,
    o: &RestOptions,
) -> Vec<Pose> {
    let (axis, feed) = (DVec3::Z, o.feed_mm_per_min);
    let mut poses: Vec<Pose> = Vec::new();
    for run in runs {
        let to = run[0].tip;
        match poses.last().copied() {
            Some(last)
                if last.tip.truncate().distance(to.truncate()) <= max_link
                    && ctx.clear(last.tip, to) =>
            {
                poses.push(Pose::new(MoveKind::Link, to, axis, feed));
            }
            last => {
                if let Some(l) = last {
                    poses.push(Pose::new(
                        MoveKind::Rapid,
                        l.tip.truncate().extend(clear),
                        axis,
                        feed,
                    ));
                }
                let b = to.truncate();
                poses.push(Pose::new(MoveKind::Rapid, b.extend(clear), axis, feed));
                poses.push(Pose::new(
                    MoveKind::Rapid,
                    b.extend((to.z + 1.0).min(clear)),
                    axis,
                    feed,
                ));
                poses.push(Pose::new(
                    MoveKind::Plunge,
                    to,
                    axis,
                    o.plunge_feed_mm_per_min,
                ));
            }
        }
        for s in &run[1..] {
            poses.push(
                Pose::new(MoveKind::Cut, s.tip, axis, feed).with_contact(s.cc, ContactKind::Ball),
            );
        }
    }
    if let Some(last) = poses.last() {
        poses.push(Pose::new(
            MoveKind::Rapid,
            last.tip.truncate().extend(clear),
            axis,
            feed,
        ));
    }
    poses
}
