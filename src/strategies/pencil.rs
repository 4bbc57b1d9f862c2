//! Pencil finishing on a triangle mesh with a ball end mill: one pass along every valley and
//! inner corner where the ball touches the part at two places at once (double contact), the
//! lines a raster or waterline pass of the same ball leaves material in.
//!
//! - **Lines** (`crease`): drop-cutter on a regular XY grid over the part (`sampling_mm`, by
//!   default a quarter of the tool radius within 0.05–1 mm); on every grid edge where the
//!   contact normal turns by at least `min_angle_rad` the crease is found by bisection to
//!   0.1 µm. The angle between the two contact normals (the bitangency angle) is what tells a
//!   real valley from the facets of a tessellated concave surface the ball fits into (their
//!   normals differ by about 2·√(2·tol/ρ)); 20° by default.
//! - **Chaining**: crossings on the edges of one grid cell are joined (where creases meet,
//!   the nearest pairs first); a join the tool cannot travel straight without going below the
//!   drop-cutter surface by more than the chord tolerance is left out. Between two points of
//!   a chain a crease point is searched across the chord's middle and inserted while it lies
//!   farther than the chord tolerance from the chord (up to six halvings). Chains shorter than
//!   `min_length_mm` are dropped.
//! - **Order and links**: from the origin, the nearest chain next, entered at its nearer end
//!   (a closed loop at its nearest point); a chain that starts where the last one ended
//!   follows without a link; otherwise the tool retracts to the clearance plane, rapids
//!   across, rapids down to 1 mm above the start and plunges.
//!
//! Every cutting pose is an exact drop-cutter location and carries its contact point.

mod crease;

pub use crease::CreasePoint;

use glam::{DVec2, DVec3};

use crate::diagnostics::Diagnostic;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::toolpath::{ContactKind, MoveKind, Pose, ToolRecord, Toolpath};
use crate::tools::CutterKind;
use crease::{Ctx, Grid, chains, connections, crossings};

/// Options of [`pencil`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PencilOptions {
    /// Smallest angle between the two contact normals that makes a pencil line, rad
    /// (1°–170°).
    pub min_angle_rad: f64,
    /// Grid step of the drop-cutter search, mm (None: R/4 within 0.05–1 mm).
    pub sampling_mm: Option<f64>,
    /// Chord tolerance of the pencil polylines, mm (> 0).
    pub chord_tol_mm: f64,
    /// Shortest pencil line kept, mm (≥ 0).
    pub min_length_mm: f64,
    /// Clearance plane height above the part's top, mm (≥ 0).
    pub clearance_mm: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed_mm_per_min: f64,
}

/// Default smallest angle between the two contact normals of a pencil line, degrees.
pub const PENCIL_DEFAULT_ANGLE_DEG: f64 = 20.0;

impl Default for PencilOptions {
    fn default() -> Self {
        Self {
            min_angle_rad: PENCIL_DEFAULT_ANGLE_DEG.to_radians(),
            sampling_mm: None,
            chord_tol_mm: 0.01,
            min_length_mm: 0.5,
            clearance_mm: 5.0,
            feed_mm_per_min: 1000.0,
            plunge_feed_mm_per_min: 300.0,
        }
    }
}

/// Why a pencil path could not be planned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PencilError {
    /// An option or the cutter is out of range.
    #[error("invalid pencil option: {0}")]
    Option(String),
    /// The part has no valley or corner the ball touches twice.
    #[error(
        "no pencil line: the ball touches the part at two places nowhere (bitangency angle {0:.1} degrees)"
    )]
    Empty(f64),
}

/// A planned pencil path.
#[derive(Clone, Debug, PartialEq)]
pub struct PencilPlan {
    /// The tool path.
    pub toolpath: Toolpath,
    /// The pencil lines in machining order (closed loops repeat their first point).
    pub lines: Vec<Vec<CreasePoint>>,
    /// Cutting length along the lines, mm.
    pub length_mm: f64,
    /// Notes.
    pub diagnostics: Vec<Diagnostic>,
}

fn check_options(tool: &ToolRecord, o: &PencilOptions) -> Result<(), PencilError> {
    let bad = |m: String| Err(PencilError::Option(m));
    if tool.cutter.kind != CutterKind::Ball {
        return bad("pencil finishing needs a ball end mill (ball:d=...)".into());
    }
    let deg = o.min_angle_rad.to_degrees();
    if !(1.0..=170.0).contains(&deg) {
        return bad(format!(
            "bitangency angle must be 1 to 170 degrees, got {deg} degrees"
        ));
    }
    if let Some(s) = o.sampling_mm
        && !(s > 1e-3 && s <= 10.0)
    {
        return bad(format!("sampling must be 0.001 to 10 mm, got {s} mm"));
    }
    for (what, v) in [
        ("chord tolerance", o.chord_tol_mm),
        ("feed", o.feed_mm_per_min),
        ("plunge feed", o.plunge_feed_mm_per_min),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return bad(format!("{what} must be positive, got {v}"));
        }
    }
    for (what, v) in [
        ("shortest line (mm)", o.min_length_mm),
        ("clearance (mm)", o.clearance_mm),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            return bad(format!("{what} must be at least 0, got {v}"));
        }
    }
    Ok(())
}

/// The pencil lines of `tool` (a ball) on `mesh`, unordered; each line's points in order,
/// a closed loop with its first point repeated.
///
/// # Errors
/// [`PencilError::Option`] for a bad option or a cutter other than a ball.
pub fn pencil_lines(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &PencilOptions,
) -> Result<Vec<Vec<CreasePoint>>, PencilError> {
    check_options(tool, opts)?;
    let r = tool.cutter.radius();
    let step = opts.sampling_mm.unwrap_or((0.25 * r).clamp(0.05, 1.0));
    let bb = mesh.bbox();
    let grid = Grid::over(bb.min.truncate(), bb.max.truncate(), step);
    let ctx = Ctx {
        mesh,
        bvh,
        cutter: &tool.cutter,
        min_angle: opts.min_angle_rad,
        tol: opts.chord_tol_mm,
    };
    let cross = crossings(&ctx, &grid);
    let links = connections(&ctx, &grid, &cross);
    let mut lines = Vec::new();
    for keys in chains(&cross, &links) {
        let pts: Vec<CreasePoint> = keys.iter().map(|k| cross[k]).collect();
        for piece in refine_split(&ctx, &pts) {
            if line_length(&piece) >= opts.min_length_mm.max(1e-9) {
                lines.push(piece);
            }
        }
    }
    Ok(lines)
}

/// Refine every chord of `pts` to the tolerance and split the line where a chord would take
/// the tool below the drop-cutter surface.
fn refine_split(ctx: &Ctx, pts: &[CreasePoint]) -> Vec<Vec<CreasePoint>> {
    let mut fine = Vec::with_capacity(pts.len());
    for w in pts.windows(2) {
        fine.push(w[0]);
        ctx.refine(&w[0], &w[1], 6, &mut fine);
    }
    fine.extend(pts.last().copied());
    let mut out = vec![Vec::new()];
    for (k, p) in fine.iter().enumerate() {
        if k > 0 && !ctx.chord_clear(fine[k - 1].tip, p.tip) {
            out.push(Vec::new());
        }
        if let Some(cur) = out.last_mut() {
            cur.push(*p);
        }
    }
    out.retain(|l| l.len() > 1);
    out
}

fn line_length(line: &[CreasePoint]) -> f64 {
    line.windows(2).map(|w| w[0].tip.distance(w[1].tip)).sum()
}

/// Plan pencil finishing of `mesh` (with its hierarchy `bvh`) with `tool`, a ball end mill.
///
/// # Errors
/// [`PencilError::Option`] for a bad option or cutter, [`PencilError::Empty`] when the part
/// has no pencil line.
pub fn pencil(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &PencilOptions,
) -> Result<PencilPlan, PencilError> {
    let mut pending = pencil_lines(mesh, bvh, tool, opts)?;
    if pending.is_empty() {
        return Err(PencilError::Empty(opts.min_angle_rad.to_degrees()));
    }
    let top = mesh.bbox().max.z;
    let clear = top + opts.clearance_mm;
    let mut poses: Vec<Pose> = Vec::new();
    let mut lines = Vec::with_capacity(pending.len());
    let feed = opts.feed_mm_per_min;
    while !pending.is_empty() {
        let here = poses.last().map_or(DVec3::ZERO, |p| p.tip);
        let line = take_nearest(&mut pending, here);
        enter(&mut poses, line[0].tip, clear, opts);
        for p in &line[1..] {
            poses.push(
                Pose::new(MoveKind::Cut, p.tip, DVec3::Z, feed)
                    .with_contact(p.cc, ContactKind::Ball),
            );
        }
        lines.push(line);
    }
    if let Some(last) = poses.last() {
        let up = last.tip.truncate().extend(clear);
        poses.push(Pose::new(MoveKind::Rapid, up, DVec3::Z, feed));
    }
    let length_mm = lines.iter().map(|l| line_length(l)).sum();
    let diagnostics = vec![Diagnostic::info(
        None,
        format!(
            "pencil: {} lines, {:.1} mm along valleys and corners where the ball touches twice",
            lines.len(),
            length_mm
        ),
    )];
    Ok(PencilPlan {
        toolpath: Toolpath::new(tool.clone(), poses),
        lines,
        length_mm,
        diagnostics,
    })
}

/// Remove and return the line nearest to `here`, turned to start at its nearest end (a closed
/// loop rotated to start at its nearest point).
fn take_nearest(pending: &mut Vec<Vec<CreasePoint>>, here: DVec3) -> Vec<CreasePoint> {
    let mut best = (0, 0, f64::MAX);
    for (k, line) in pending.iter().enumerate() {
        let closed = line.len() > 2 && line[0].tip == line[line.len() - 1].tip;
        let idx: Vec<usize> = if closed {
            (0..line.len() - 1).collect()
        } else {
            vec![0, line.len() - 1]
        };
        for i in idx {
            let d = line[i].tip.distance_squared(here);
            if d < best.2 {
                best = (k, i, d);
            }
        }
    }
    let mut line = pending.remove(best.0);
    let closed = line.len() > 2 && line[0].tip == line[line.len() - 1].tip;
    if closed && best.1 > 0 {
        line.pop();
        line.rotate_left(best.1);
        let first = line[0];
        line.push(first);
    } else if !closed && best.1 > 0 {
        line.reverse();
    }
    line
}

/// Move from the last pose to `to`: straight on when it is there already, else retract, rapid
/// across and plunge.
fn enter(poses: &mut Vec<Pose>, to: DVec3, clear: f64, opts: &PencilOptions) {
    let axis = DVec3::Z;
    let feed = opts.feed_mm_per_min;
    if let Some(last) = poses.last().copied() {
        if last.tip.distance(to) < 1e-9 {
            return;
        }
        poses.push(Pose::new(
            MoveKind::Rapid,
            last.tip.truncate().extend(clear),
            axis,
            feed,
        ));
    }
    let b: DVec2 = to.truncate();
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
        opts.plunge_feed_mm_per_min,
    ));
}
