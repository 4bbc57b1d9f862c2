//! Hole operations: the order of the holes (nearest neighbour, improved by 2-opt and Or-opt
//! moves until neither shortens the tour) and their tool paths as exact moves: canned cycles
//! (spot, drill, dwell, peck, chip-break, tap, bore) and helices (helical boring to a diameter
//! with a finishing pass, internal and external thread milling in climb, one helix turn per
//! pitch).
//!
//! Between two holes the tool stays at the R plane when nothing of the part (its mesh, widened
//! by the tool radius and a margin) stands within [`RETRACT_MARGIN_MM`] of that height along the
//! straight move, and the next hole's R plane is not above it; otherwise it goes up to the
//! clearance height. Heights are along the holes' common direction.

mod order;

pub use order::{order_holes, tour_length_mm};

use glam::DVec3;

use crate::geometry::mesh::TriMesh;
use crate::toolpath::{CycleKind, CycleMove, CycleRetract};
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

/// A part standing this close below a travel height counts as in the way, mm.
pub const RETRACT_MARGIN_MM: f64 = 0.5;

/// One hole to make: where its axis meets the top, its direction (out of the hole, toward the
/// spindle) and how deep to go below the top (the tool tip's depth), mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoleTarget {
    /// Centre of the entry, mm.
    pub top: DVec3,
    /// Unit direction out of the hole.
    pub direction: DVec3,
    /// Depth of the tool tip below the top, mm.
    pub depth_mm: f64,
    /// Hole diameter, mm (helical boring: the diameter to reach; thread milling: the thread's
    /// major diameter; external thread milling: the boss's thread's minor diameter, where the
    /// teeth reach).
    pub diameter_mm: f64,
}

/// The operation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HoleStrategy {
    /// A canned cycle per hole.
    Cycle(CycleKind),
    /// Helical boring with a flat-end tool smaller than the hole: a helix of `pitch_mm` per
    /// turn down at `finish_mm` inside the diameter, a full turn at the bottom, then a finishing
    /// helix up at the diameter.
    HelicalBore {
        /// Descent per turn, mm.
        pitch_mm: f64,
        /// Stock left by the roughing helix for the finishing one, mm (radial).
        finish_mm: f64,
    },
    /// Internal thread milling, climb (counter-clockwise seen from the spindle for a right-hand
    /// thread going up from the bottom), one turn per pitch. A single-tooth mill (`teeth` 1)
    /// climbs one continuous helix from the bottom to the top; a mill with N teeth at the pitch
    /// covers N·pitch per turn, so it cuts one turn per N·pitch of depth, from the bottom up:
    /// in from the axis, one helix turn rising a pitch, back to the axis, up N·pitch.
    ThreadMill {
        /// Pitch, mm.
        pitch_mm: f64,
        /// Teeth along the axis at the pitch (1 for a single-form mill; 0 reads as 1).
        teeth: u32,
    },
    /// External thread milling of a boss, climb: clockwise seen from the spindle, so a
    /// right-hand thread is cut going down. The target's top is the boss's top and its diameter
    /// the diameter the teeth reach (the thread's minor diameter). Each turn starts outside the
    /// boss ([`EXTERNAL_ENTRY_MM`] plus a pitch beyond the teeth's reach), goes in radially, cuts
    /// one turn falling a pitch and goes back out: a single-tooth mill one helix from the top to
    /// the depth, a mill with N teeth one turn per N·pitch from the top down, the last ending at
    /// the depth. Between bosses it always leaves at the clearance height (the R-plane test looks
    /// along the line between the tops, and this tool travels outside them).
    ExternalThreadMill {
        /// Pitch, mm.
        pitch_mm: f64,
        /// Teeth along the axis at the pitch (1 for a single-form mill; 0 reads as 1).
        teeth: u32,
    },
}

/// How far beyond a pitch outside the teeth's reach an external thread mill enters and leaves
/// each turn, mm (a 60° thread is at most 0.87 pitch deep, so the tool starts clear of the
/// boss's major diameter).
pub const EXTERNAL_ENTRY_MM: f64 = 0.5;

/// Heights, feeds and tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HolePlanOptions {
    /// R plane above each hole's top, mm.
    pub r_plane_mm: f64,
    /// Clearance height above the highest point of the part (or of the holes' tops without a
    /// mesh), mm.
    pub clearance_mm: f64,
    /// Feed, mm/min (a tap's feed is the pitch times `spindle_rpm` instead).
    pub feed_mm_per_min: f64,
    /// Spindle speed, rev/min.
    pub spindle_rpm: f64,
    /// Chord tolerance of the sampled helices, mm.
    pub chord_tol_mm: f64,
    /// Where the tool comes from (the tour starts at the hole nearest to it).
    pub start: DVec3,
}

impl Default for HolePlanOptions {
    fn default() -> Self {
        Self {
            r_plane_mm: 2.0,
            clearance_mm: 10.0,
            feed_mm_per_min: 200.0,
            spindle_rpm: 1000.0,
            chord_tol_mm: 0.005,
            start: DVec3::ZERO,
        }
    }
}

/// What the plan did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HolePlan {
    /// The tool path.
    pub toolpath: Option<Toolpath>,
    /// The holes in the order made (indices into the targets).
    pub order: Vec<usize>,
    /// Moves between holes kept at the R plane.
    pub r_plane_moves: usize,
    /// Moves between holes that went up to the clearance height.
    pub clearance_moves: usize,
    /// Length of the tour between the holes' tops, mm.
    pub tour_mm: f64,
}

/// Plan one hole operation for `targets` (one direction) with `tool`, avoiding `part` (its mesh)
/// between holes when given.
///
/// # Errors
/// No targets, directions that differ, a tool that does not fit (helical boring: tool not
/// smaller than the hole), or a bad number (see [`CycleMove::validate`]).
pub fn plan_holes(
    targets: &[HoleTarget],
    strategy: &HoleStrategy,
    tool: ToolRecord,
    part: Option<&TriMesh>,
    opts: &HolePlanOptions,
) -> Result<HolePlan, String> {
    let first = targets.first().ok_or("no holes to make")?;
    let dir = first
        .direction
        .try_normalize()
        .ok_or("a hole's direction is zero")?;
    if targets
        .iter()
        .any(|t| t.direction.normalize_or_zero().distance(dir) > 1e-6)
    {
        return Err("the holes of one operation must share one direction".into());
    }
    for (i, t) in targets.iter().enumerate() {
        if !(t.top.is_finite() && t.depth_mm.is_finite() && t.depth_mm > 0.0) {
            return Err(format!(
                "hole {i}: depth {} mm must be positive",
                t.depth_mm
            ));
        }
    }
    let points: Vec<DVec3> = targets
        .iter()
        .map(|t| t.top - dir * t.top.dot(dir))
        .collect();
    let start = opts.start - dir * opts.start.dot(dir);
    let order = order_holes(&points, Some(start));
    let tour_mm = tour_length_mm(&points, &order);
    // Clearance: above the part's highest point along `dir`.
    let part_top = part
        .map(|m| {
            m.positions
                .iter()
                .map(|p| p.dot(dir))
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .filter(|h| h.is_finite());
    let tops_max = targets
        .iter()
        .map(|t| t.top.dot(dir))
        .fold(f64::NEG_INFINITY, f64::max);
    let clear_h = part_top.unwrap_or(tops_max).max(tops_max) + opts.clearance_mm;
    let tool_r = 0.5 * tool.cutter.diameter;
    let mut tp = Toolpath::new(tool, Vec::new());
    let mut plan = HolePlan {
        order: order.clone(),
        tour_mm,
        ..HolePlan::default()
    };
    // The height the tool is at when it arrives over each hole.
    let mut arrive_h = clear_h;
    for (k, &i) in order.iter().enumerate() {
        let t = &targets[i];
        let top_h = t.top.dot(dir);
        let r_h = top_h + opts.r_plane_mm;
        let next = order.get(k + 1).map(|&j| &targets[j]);
        // Stay at this hole's R plane for the move to the next one?
        let external = matches!(strategy, HoleStrategy::ExternalThreadMill { .. });
        let stay = !external
            && next.is_some_and(|n| {
                let next_r = n.top.dot(dir) + opts.r_plane_mm;
                next_r <= r_h + 1e-9
                    && !in_the_way(
                        part,
                        dir,
                        t.top + dir * (r_h - top_h),
                        n.top + dir * (r_h - n.top.dot(dir)),
                        r_h,
                        tool_r,
                    )
            });
        if next.is_some() {
            if stay {
                plan.r_plane_moves += 1;
            } else {
                plan.clearance_moves += 1;
            }
        }
        let initial_mm = (arrive_h - top_h).max(opts.r_plane_mm);
        match strategy {
            HoleStrategy::Cycle(kind) => {
                arrive_h = if stay { r_h } else { clear_h };
                cycle_at(&mut tp, t, dir, *kind, stay, initial_mm, clear_h, opts)?;
            }
            HoleStrategy::HelicalBore {
                pitch_mm,
                finish_mm,
            } => {
                let path_r = 0.5 * (t.diameter_mm - 2.0 * tool_r);
                if path_r <= 0.0 {
                    return Err(format!(
                        "hole {i}: a {} mm tool cannot bore a {} mm hole helically (it must be smaller)",
                        2.0 * tool_r,
                        t.diameter_mm
                    ));
                }
                let leave_h = if stay { r_h } else { clear_h };
                helical_bore(
                    &mut tp,
                    t,
                    dir,
                    arrive_h,
                    r_h,
                    leave_h,
                    path_r,
                    *pitch_mm,
                    finish_mm.clamp(0.0, path_r),
                    opts,
                )?;
                arrive_h = leave_h;
            }
            HoleStrategy::ThreadMill { pitch_mm, teeth }
            | HoleStrategy::ExternalThreadMill { pitch_mm, teeth } => {
                // An external thread mill never stays (`stay` is false).
                let leave_h = if stay { r_h } else { clear_h };
                let mill = if external {
                    external_thread_mill
                } else {
                    thread_mill
                };
                mill(
                    &mut tp,
                    i,
                    t,
                    dir,
                    [arrive_h, r_h, leave_h],
                    tool_r,
                    *pitch_mm,
                    *teeth,
                    opts,
                )?;
                arrive_h = leave_h;
            }
        }
    }
    plan.toolpath = Some(tp);
    Ok(plan)
}

/// One canned cycle at `t`, started `initial_mm` above its top, ending at the R plane when
/// `stay`, else at the clearance height `clear_h`.
#[expect(
    clippy::too_many_arguments,
    reason = "the hole, its cycle, its heights and the options"
)]
fn cycle_at(
    tp: &mut Toolpath,
    t: &HoleTarget,
    dir: DVec3,
    kind: CycleKind,
    stay: bool,
    initial_mm: f64,
    clear_h: f64,
    opts: &HolePlanOptions,
) -> Result<(), String> {
    let top_h = t.top.dot(dir);
    let feed = match kind {
        CycleKind::Tap { pitch_mm } => pitch_mm * opts.spindle_rpm,
        _ => opts.feed_mm_per_min,
    };
    let cycle = CycleMove {
        cycle: kind,
        surface: t.top,
        axis: dir,
        depth_mm: t.depth_mm,
        clearance_mm: opts.r_plane_mm,
        retract_mm: initial_mm,
        retract: if stay {
            CycleRetract::RPlane
        } else {
            CycleRetract::Initial
        },
        feed_mm_per_min: feed,
    };
    tp.push_cycle(cycle).map_err(|e| e.message)?;
    // Leaving at the clearance height: the cycle's initial plane is where it started, so go up
    // from there when it is lower.
    if !stay && initial_mm + top_h < clear_h - 1e-9 {
        let p = t.top + dir * (clear_h - top_h);
        tp.push_pose(Pose::new(MoveKind::Rapid, p, dir, 0.0));
    }
    Ok(())
}

/// Whether the part stands within the margin of height `h` anywhere the tool passes moving
/// straight from `a` to `b` (both at height `h` along `dir`): any triangle reaching into the
/// corridor of the tool radius plus 1 mm whose highest vertex is that high. Conservative: the
/// triangle's highest vertex, not its height inside the corridor.
fn in_the_way(part: Option<&TriMesh>, dir: DVec3, a: DVec3, b: DVec3, h: f64, tool_r: f64) -> bool {
    let Some(mesh) = part else {
        return false;
    };
    // A frame with `dir` as z.
    let x = dir.any_orthonormal_vector();
    let y = dir.cross(x);
    let flat = |p: DVec3| glam::DVec2::new(p.dot(x), p.dot(y));
    let (a2, b2) = (flat(a), flat(b));
    let reach = tool_r + 1.0;
    mesh.triangles.iter().any(|t| {
        let v = t.map(|i| mesh.positions[i as usize]);
        let top = v
            .iter()
            .map(|p| p.dot(dir))
            .fold(f64::NEG_INFINITY, f64::max);
        if top < h - RETRACT_MARGIN_MM {
            return false;
        }
        let tri = v.map(flat);
        seg_tri_distance(a2, b2, tri) <= reach
    })
}

fn seg_seg_distance(p: glam::DVec2, q: glam::DVec2, a: glam::DVec2, b: glam::DVec2) -> f64 {
    let cross = |u: glam::DVec2, v: glam::DVec2| u.x * v.y - u.y * v.x;
    let (d1, d2, d3, d4) = (
        cross(b - a, p - a),
        cross(b - a, q - a),
        cross(q - p, a - p),
        cross(q - p, b - p),
    );
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return 0.0;
    }
    let pt_seg = |c: glam::DVec2, s: glam::DVec2, e: glam::DVec2| {
        let d = e - s;
        let l2 = d.length_squared();
        let t = if l2 > 0.0 {
            ((c - s).dot(d) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        c.distance(s + d * t)
    };
    pt_seg(p, a, b)
        .min(pt_seg(q, a, b))
        .min(pt_seg(a, p, q))
        .min(pt_seg(b, p, q))
}

fn seg_tri_distance(p: glam::DVec2, q: glam::DVec2, t: [glam::DVec2; 3]) -> f64 {
    let cross = |u: glam::DVec2, v: glam::DVec2| u.x * v.y - u.y * v.x;
    let inside = |c: glam::DVec2| {
        let s = [
            cross(t[1] - t[0], c - t[0]),
            cross(t[2] - t[1], c - t[1]),
            cross(t[0] - t[2], c - t[2]),
        ];
        s.iter().all(|v| *v >= 0.0) || s.iter().all(|v| *v <= 0.0)
    };
    if inside(p) || inside(q) {
        return 0.0;
    }
    (0..3)
        .map(|k| seg_seg_distance(p, q, t[k], t[(k + 1) % 3]))
        .fold(f64::INFINITY, f64::min)
}

/// Rapid to `arrive_h` over the hole when elsewhere, down to the R plane.
fn approach(tp: &mut Toolpath, at: DVec3, dir: DVec3, arrive_h: f64, r_h: f64) {
    let top_h = at.dot(dir);
    let above = at + dir * (arrive_h - top_h);
    if tp.poses.last().is_none_or(|p| p.tip.distance(above) > 1e-9) {
        tp.push_pose(Pose::new(MoveKind::Rapid, above, dir, 0.0));
    }
    let r = at + dir * (r_h - top_h);
    if above.distance(r) > 1e-9 {
        tp.push_pose(Pose::new(MoveKind::Rapid, r, dir, 0.0));
    }
}

/// Full turns (and the last part turn) of a helix descending (`rise` < 0) or rising `total`
/// mm at `pitch` mm per turn about `centre`, counter-clockwise about `dir`.
/// One full turn about `centre` in its own plane (no descent), at `feed`.
fn flat_turn(
    tp: &mut Toolpath,
    centre: DVec3,
    dir: DVec3,
    feed: f64,
    tol: f64,
) -> Result<(), String> {
    tp.push_helix(
        centre,
        dir,
        std::f64::consts::TAU,
        0.0,
        MoveKind::Cut,
        feed,
        tol,
    )
    .map_err(|e| e.message)
}

fn helix_turns(
    tp: &mut Toolpath,
    centre: DVec3,
    dir: DVec3,
    total: f64,
    pitch: f64,
    feed: f64,
    tol: f64,
) -> Result<(), String> {
    let turns = total.abs() / pitch;
    let full = turns.floor() as usize;
    let sign = total.signum();
    for _ in 0..full {
        tp.push_helix(
            centre,
            dir,
            std::f64::consts::TAU,
            sign * pitch,
            MoveKind::Cut,
            feed,
            tol,
        )
        .map_err(|e| e.message)?;
    }
    let rest = turns - full as f64;
    if rest > 1e-9 {
        tp.push_helix(
            centre,
            dir,
            std::f64::consts::TAU * rest,
            sign * pitch * rest,
            MoveKind::Cut,
            feed,
            tol,
        )
        .map_err(|e| e.message)?;
    }
    Ok(())
}

#[expect(
    clippy::too_many_arguments,
    reason = "the hole, its heights, the helix and the options"
)]
fn helical_bore(
    tp: &mut Toolpath,
    t: &HoleTarget,
    dir: DVec3,
    arrive_h: f64,
    r_h: f64,
    leave_h: f64,
    path_r: f64,
    pitch: f64,
    finish: f64,
    opts: &HolePlanOptions,
) -> Result<(), String> {
    if !(pitch > 0.0 && pitch.is_finite()) {
        return Err(format!("helix pitch {pitch} mm must be positive"));
    }
    let top_h = t.top.dot(dir);
    let x = dir.any_orthonormal_vector();
    let rough_r = path_r - finish;
    let f = opts.feed_mm_per_min;
    approach(tp, t.top + x * rough_r, dir, arrive_h, r_h);
    // Feed down to the top, then the roughing helix to depth and a full turn there.
    let at_top = t.top + x * rough_r;
    tp.push_pose(Pose::new(MoveKind::Plunge, at_top, dir, f));
    let bottom = t.top - dir * t.depth_mm;
    helix_turns(tp, t.top, dir, -t.depth_mm, pitch, f, opts.chord_tol_mm)?;
    flat_turn(tp, bottom, dir, f, opts.chord_tol_mm)?;
    // Out to the diameter, a full turn, and the finishing helix up.
    let last = tp.poses.last().map_or(bottom, |p| p.tip);
    let radial = (last - bottom).normalize_or(x);
    if finish > 0.0 {
        tp.push_pose(Pose::new(MoveKind::Cut, bottom + radial * path_r, dir, f));
        flat_turn(tp, bottom, dir, f, opts.chord_tol_mm)?;
        helix_turns(tp, bottom, dir, t.depth_mm, pitch, f, opts.chord_tol_mm)?;
    }
    // To the axis and out.
    let here = tp.poses.last().map_or(bottom, |p| p.tip);
    let h_here = here.dot(dir);
    let on_axis = t.top + dir * (h_here - top_h);
    tp.push_pose(Pose::new(MoveKind::Cut, on_axis, dir, f));
    tp.push_pose(Pose::new(
        MoveKind::Rapid,
        t.top + dir * (leave_h - top_h),
        dir,
        0.0,
    ));
    Ok(())
}

#[expect(
    clippy::too_many_arguments,
    reason = "the hole, its heights, the helix and the options"
)]
fn thread_mill(
    tp: &mut Toolpath,
    i: usize,
    t: &HoleTarget,
    dir: DVec3,
    [arrive_h, r_h, leave_h]: [f64; 3],
    tool_r: f64,
    pitch: f64,
    teeth: u32,
    opts: &HolePlanOptions,
) -> Result<(), String> {
    let path_r = 0.5 * t.diameter_mm - tool_r;
    if path_r <= 0.0 {
        return Err(format!(
            "hole {i}: a {} mm thread mill does not fit a {} mm thread",
            2.0 * tool_r,
            t.diameter_mm
        ));
    }
    if !(pitch > 0.0 && pitch.is_finite()) {
        return Err(format!("thread pitch {pitch} mm must be positive"));
    }
    let top_h = t.top.dot(dir);
    let x = dir.any_orthonormal_vector();
    let f = opts.feed_mm_per_min;
    approach(tp, t.top, dir, arrive_h, r_h);
    let bottom = t.top - dir * t.depth_mm;
    tp.push_pose(Pose::new(MoveKind::Plunge, bottom, dir, f));
    if teeth <= 1 {
        // Out to the thread's radius, then climb up one turn per pitch to the top.
        tp.push_pose(Pose::new(MoveKind::Cut, bottom + x * path_r, dir, f));
        helix_turns(tp, bottom, dir, t.depth_mm, pitch, f, opts.chord_tol_mm)?;
    } else {
        // One turn per N·pitch: the lowest tooth starts each turn a whole number of pitches
        // above the bottom, so every turn lies on the one thread.
        let span = f64::from(teeth) * pitch;
        let passes = (t.depth_mm / span - 1e-9).ceil().max(1.0) as usize;
        for k in 0..passes {
            let c = bottom + dir * (k as f64 * span);
            tp.push_pose(Pose::new(MoveKind::Cut, c, dir, f));
            tp.push_pose(Pose::new(MoveKind::Cut, c + x * path_r, dir, f));
            helix_turns(tp, c, dir, pitch, pitch, f, opts.chord_tol_mm)?;
            tp.push_pose(Pose::new(MoveKind::Cut, c + dir * pitch, dir, f));
        }
    }
    tp.push_pose(Pose::new(MoveKind::Cut, t.top, dir, f));
    tp.push_pose(Pose::new(
        MoveKind::Rapid,
        t.top + dir * (leave_h - top_h),
        dir,
        0.0,
    ));
    Ok(())
}

#[expect(
    clippy::too_many_arguments,
    reason = "the boss, its heights, the helix and the options"
)]
fn external_thread_mill(
    tp: &mut Toolpath,
    i: usize,
    t: &HoleTarget,
    dir: DVec3,
    [arrive_h, r_h, leave_h]: [f64; 3],
    tool_r: f64,
    pitch: f64,
    teeth: u32,
    opts: &HolePlanOptions,
) -> Result<(), String> {
    if !(t.diameter_mm > 0.0 && t.diameter_mm.is_finite()) {
        return Err(format!(
            "hole {i}: an external thread's minor diameter {} mm must be positive",
            t.diameter_mm
        ));
    }
    let path_r = 0.5 * t.diameter_mm + tool_r;
    if !(pitch > 0.0 && pitch.is_finite()) {
        return Err(format!("thread pitch {pitch} mm must be positive"));
    }
    let top_h = t.top.dot(dir);
    let x = dir.any_orthonormal_vector();
    let f = opts.feed_mm_per_min;
    let out_r = path_r + pitch + EXTERNAL_ENTRY_MM;
    let bottom = t.top - dir * t.depth_mm;
    // (start height above the bottom, fall) of each turn, from the top down.
    let turns: Vec<(f64, f64)> = if teeth <= 1 {
        vec![(t.depth_mm, t.depth_mm)]
    } else {
        let span = f64::from(teeth) * pitch;
        let passes = (t.depth_mm / span - 1e-9).ceil().max(1.0) as usize;
        (0..passes)
            .rev()
            .map(|k| (k as f64 * span + pitch, pitch))
            .collect()
    };
    approach(tp, t.top + x * out_r, dir, arrive_h, r_h);
    for (k, (start, fall)) in turns.into_iter().enumerate() {
        let c = bottom + dir * start;
        let kind = if k == 0 {
            MoveKind::Plunge
        } else {
            MoveKind::Cut
        };
        tp.push_pose(Pose::new(kind, c + x * out_r, dir, f));
        tp.push_pose(Pose::new(MoveKind::Cut, c + x * path_r, dir, f));
        // Clockwise about `dir`, a whole turn (or the rest) per helix.
        let mut left = fall;
        while left > 1e-9 {
            let piece = left.min(pitch);
            tp.push_helix(
                c - dir * (fall - left),
                dir,
                -std::f64::consts::TAU * piece / pitch,
                -piece,
                MoveKind::Cut,
                f,
                opts.chord_tol_mm,
            )
            .map_err(|e| e.message)?;
            left -= piece;
        }
        let end = c - dir * fall;
        tp.push_pose(Pose::new(MoveKind::Cut, end + x * out_r, dir, f));
    }
    tp.push_pose(Pose::new(MoveKind::Cut, t.top + x * out_r, dir, f));
    tp.push_pose(Pose::new(
        MoveKind::Rapid,
        t.top + x * out_r + dir * (leave_h - top_h),
        dir,
        0.0,
    ));
    Ok(())
}
