//! Cutter radius compensation G41/G42 (G41.1/G42.1 with a D diameter), ported from LinuxCNC's
//! interpreter (`convert_straight_comp1/2`, `convert_arc_comp1/2`, `interp_queue.cc`), in the
//! XY plane (G17) and the ZX plane (G18).
//!
//! - The entry move (the first after G41/G42) ends one tool radius to the side of its
//!   programmed end, perpendicular to the move (lines) or along the arc's radius (arcs); it
//!   must be longer than the radius.
//! - Every later move is offset by the radius along its own normal. Each compensated move is
//!   held back until the next one is known, so its end can be moved:
//!   - on an outside (convex) corner the tool goes around the programmed corner point on an
//!     arc of the tool radius (a traverse straight across for G0),
//!   - on an inside (concave) corner the held move is shortened to the intersection of the
//!     two offset paths (line–line, line–arc, arc–line, arc–arc); a corner the tool cannot
//!     reach without cutting into the part is an error naming the line;
//!   - within 0.05 rad of straight on, nothing is inserted.
//! - G40 ends the held move at its offset end; the next move leaves from there to its
//!   programmed end (it must be a line). M0, M1, M2, M30 and the end of the program flush the
//!   held move too.
//!
//! Positions here are machine coordinates in mm, split into the plane's (first, second)
//! coordinates and the normal one ([`Plane::split`]); LinuxCNC computes the same in program
//! coordinates, which differ by a translation and the unit scale only.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::DVec2;

use super::arc::{CentreSpec, Plane, arc_geometry};
use super::block::{Joints, MotionKind};
use super::motion::{ArcCentre, feed_for, push_block, start_for};
use super::state::{Block, Held, Queued, Side, Snapshot, State};
use super::{Dwell, GcodeError, InterpretOptions, Program};

/// LinuxCNC's `TOLERANCE_CONCAVE_CORNER`, rad.
const SMALL: f64 = 0.05;
/// LinuxCNC's `TOLERANCE_EQUAL`.
const TOLERANCE_EQUAL: f64 = 0.0001;
/// `RADIUS_TOLERANCE_MM`: radii below this are zero, a chord may exceed 2R by this.
const RADIUS_TOLERANCE_MM: f64 = 0.00005 * 25.4;
/// `CENTER_ARC_RADIUS_TOLERANCE_MM` and `_INCH` (in mm).
const SPIRAL_ABS_MM: f64 = 2.0 * 0.01 * std::f64::consts::SQRT_2;
const SPIRAL_ABS_INCH_MM: f64 = 2.0 * 0.001 * std::f64::consts::SQRT_2 * 25.4;
const SPIRAL_REL: f64 = 0.001;

fn inside(side: Side, turn: i32) -> bool {
    (side == Side::Left && turn > 0) || (side == Side::Right && turn < 0)
}

fn dir(a: f64) -> DVec2 {
    DVec2::new(a.cos(), a.sin())
}

fn angle(v: DVec2) -> f64 {
    v.y.atan2(v.x)
}

/// LinuxCNC's `find_turn`: the signed sweep from `p1` to `p2` about `c`.
fn find_turn(p1: DVec2, c: DVec2, turn: i32, p2: DVec2) -> f64 {
    if turn == 0 {
        return 0.0;
    }
    let mut alpha = angle(p1 - c);
    let mut beta = angle(p2 - c);
    if turn > 0 {
        if beta <= alpha {
            beta += TAU;
        }
        (beta - alpha) + f64::from(turn - 1) * TAU
    } else {
        if alpha <= beta {
            alpha += TAU;
        }
        (beta - alpha) + f64::from(turn + 1) * TAU
    }
}

/// The plane coordinates of an arc's end in a held move (plane split of its end).
fn plane_end(plane: Plane, j: &Joints) -> DVec2 {
    plane.split(j.xyz).0
}

fn with_plane(plane: Plane, mut j: Joints, uv: DVec2, w: f64) -> Joints {
    j.xyz = plane.join(uv, w);
    j
}

/// Emit the held moves in order (LinuxCNC's `dequeue_canons`).
fn dequeue(s: &mut State, out: &mut Program) -> Result<(), GcodeError> {
    s.comp.endpoint = None;
    let plane = s.plane;
    for q in std::mem::take(&mut s.comp.queue) {
        match q {
            Queued::Dwell { line, seconds } => out.dwells.push(Dwell {
                line,
                before_block: out.blocks.len(),
                seconds,
                cycle: None,
            }),
            Queued::Move {
                held,
                end,
                feed,
                snap,
            } => {
                let kind = match held {
                    Held::Straight { rapid, .. } => {
                        if start_for(s.emitted, end) == end {
                            continue;
                        }
                        if rapid {
                            MotionKind::Rapid
                        } else {
                            MotionKind::Linear
                        }
                    }
                    Held::Arc { centre, turn, .. } => {
                        let (_, w) = plane.split(s.emitted.xyz);
                        let c = plane.join(centre, w);
                        let arc = arc_geometry(
                            s.emitted.xyz,
                            end.xyz,
                            plane,
                            turn > 0,
                            CentreSpec::Centre(c),
                            turn.unsigned_abs().max(1),
                        )
                        .map_err(|m| GcodeError {
                            line: snap.line,
                            column: 1,
                            message: format!("cutter compensation made an arc that fails: {m}"),
                        })?;
                        if turn > 0 {
                            MotionKind::ArcCcw(arc)
                        } else {
                            MotionKind::ArcCw(arc)
                        }
                    }
                };
                push_block(s, out, kind, end, feed, &snap);
            }
        }
    }
    Ok(())
}

fn set_endpoint(s: &mut State, p: DVec2) {
    s.comp.endpoint = Some(p);
}

/// Move the end of the held move to `p`, checking that this does not reverse it, then emit it
/// (LinuxCNC's `move_endpoint_and_flush`).
fn move_endpoint_and_flush(
    s: &mut State,
    out: &mut Program,
    line: usize,
    p: DVec2,
) -> Result<(), GcodeError> {
    if s.comp.queue.is_empty() {
        return Ok(());
    }
    let plane = s.plane;
    let err = |message: &str| GcodeError {
        line,
        column: 1,
        message: message.to_string(),
    };
    let endpoint = s.comp.endpoint;
    let turn_slack = if s.inch { 0.001 } else { 0.0254 };
    for q in &mut s.comp.queue {
        let Queued::Move { held, end, .. } = q else {
            continue;
        };
        let (_, w) = plane.split(end.xyz);
        match held {
            Held::Arc {
                centre,
                turn,
                original_sweep,
            } => {
                let r1 = (plane_end(plane, end) - *centre).length();
                let r2 = (p - *centre).length();
                if (r1 - r2).abs() > 0.01 {
                    return Err(err(
                        "cutter compensation made an arc whose start and end radii differ",
                    ));
                }
                if let Some(e) = endpoint {
                    let l2 = find_turn(e, *centre, *turn, p);
                    if *original_sweep != 0.0 && l2.abs() > original_sweep.abs() + turn_slack {
                        return Err(err(
                            "arc move in a concave corner cannot be reached by the tool without \
                             gouging",
                        ));
                    }
                }
            }
            Held::Straight { rapid, dir } => {
                if let Some(e) = endpoint
                    && dir.dot(p - e) < 0.0
                {
                    let what = if *rapid { "traverse" } else { "feed" };
                    return Err(err(&format!(
                        "straight {what} in a concave corner cannot be reached by the tool \
                         without gouging"
                    )));
                }
            }
        }
        *end = with_plane(plane, *end, p, w);
    }
    dequeue(s, out)?;
    set_endpoint(s, p);
    Ok(())
}

fn hold(s: &mut State, b: &Block, held: Held, end: Joints, feed: f64, rapid: bool) {
    let snap = Snapshot::of(s, b.line, rapid);
    s.comp.queue.push(Queued::Move {
        held,
        end,
        feed,
        snap,
    });
}

/// A straight move (G0 `rapid`, or G1) to the programmed `end` with compensation active.
///
/// # Errors
/// A [`GcodeError`] for an entry move not longer than the radius, or a corner the tool
/// cannot reach.
pub(super) fn straight(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    rapid: bool,
    end: Joints,
) -> Result<(), GcodeError> {
    s.comp.arc_not_allowed = false;
    let feed = feed_for(b, s, opts, out, rapid)?;
    let plane = s.plane;
    let side = s.comp.side.unwrap_or(Side::Left);
    let radius = s.comp.radius_mm;
    let (c, cz) = plane.split(s.pos.xyz);
    let (p, pz) = plane.split(end.xyz);
    let normal = if side == Side::Left {
        FRAC_PI_2
    } else {
        -FRAC_PI_2
    };
    if s.comp.first_move {
        if (p - c).length() <= radius {
            return Err(b.err(
                b.first_column(),
                "length of cutter compensation entry move is not greater than the tool radius",
            ));
        }
        let alpha = angle(p - c) + normal;
        let e = p + radius * dir(alpha);
        set_endpoint(s, c);
        let moved = with_plane(plane, end, e, pz);
        hold(
            s,
            b,
            Held::Straight {
                rapid,
                dir: dir(alpha),
            },
            moved,
            feed,
            rapid,
        );
        s.comp.first_move = false;
        s.pos = moved;
        s.comp.programmed = Some(end.xyz);
        return Ok(());
    }
    let (op, _) = plane.split(s.comp.programmed.unwrap_or(s.pos.xyz));
    let mut e = c;
    if p == op {
        // No motion in the plane.
        let moved = with_plane(plane, end, c, pz);
        hold(
            s,
            b,
            Held::Straight { rapid, dir: p - op },
            moved,
            feed,
            rapid,
        );
    } else {
        let mut theta = angle(c - op);
        let mut alpha = angle(p - op);
        let (beta, gamma) = if side == Side::Left {
            if theta < alpha {
                theta += TAU;
            }
            (theta - alpha - FRAC_PI_2, FRAC_PI_2)
        } else {
            if alpha < theta {
                alpha += TAU;
            }
            (alpha - theta - FRAC_PI_2, -FRAC_PI_2)
        };
        e = p + radius * dir(alpha + gamma);
        let mid = op + radius * dir(alpha + gamma);
        let concave = !(-SMALL..=PI + SMALL).contains(&beta)
            || (beta > PI - SMALL
                && s.comp
                    .front_arc_plane(plane)
                    .is_some_and(|(_, _, turn)| !inside(side, turn)));
        if !concave && beta > SMALL {
            // Outside corner: around the programmed corner point (straight across for G0).
            move_endpoint_and_flush(s, out, b.line, c)?;
            let corner = with_plane(plane, end, mid, cz);
            let held = if rapid {
                Held::Straight {
                    rapid,
                    dir: DVec2::ZERO,
                }
            } else {
                Held::Arc {
                    centre: op,
                    turn: if side == Side::Left { -1 } else { 1 },
                    original_sweep: 0.0,
                }
            };
            hold(s, b, held, corner, feed, rapid);
            dequeue(s, out)?;
            set_endpoint(s, mid);
        } else if concave {
            let mid = if let Some((centre, prev_end, turn)) = s.comp.front_arc_plane(plane) {
                arc_to_straight(b, side, radius, (centre, prev_end, turn), op, p)?
            } else {
                let halfcorner = (beta + PI) / 2.0;
                if halfcorner == 0.0 {
                    return Err(b.err(
                        b.first_column(),
                        "zero degree inside corner is invalid for cutter compensation",
                    ));
                }
                let retreat = radius / halfcorner.tan();
                c + retreat * dir(theta + gamma)
            };
            move_endpoint_and_flush(s, out, b.line, mid)?;
        } else {
            dequeue(s, out)?;
            set_endpoint(s, c);
        }
        let moved = with_plane(plane, end, e, pz);
        hold(
            s,
            b,
            Held::Straight { rapid, dir: p - op },
            moved,
            feed,
            rapid,
        );
    }
    s.pos = with_plane(plane, end, e, pz);
    s.comp.programmed = Some(end.xyz);
    Ok(())
}

/// The end of a held arc followed by a line into an inside corner.
fn arc_to_straight(
    b: &Block,
    side: Side,
    radius: f64,
    (centre, prev_end, turn): (DVec2, DVec2, i32),
    op: DVec2,
    p: DVec2,
) -> Result<DVec2, GcodeError> {
    let oldrad = (centre - prev_end).length();
    let base_dir = angle(p - op);
    let theta = if turn > 0 {
        base_dir + FRAC_PI_2
    } else {
        base_dir - FRAC_PI_2
    };
    let phi = angle(centre - op);
    let oldrad_uncomp = if inside(side, turn) {
        oldrad + radius
    } else {
        oldrad - radius
    };
    let d = oldrad_uncomp * (theta - phi).cos();
    let gouge = || {
        b.err(
            b.first_column(),
            "arc to straight motion makes a corner the compensated tool can't fit in without \
             gouging",
        )
    };
    let angle_from_centre = if inside(side, turn) {
        let l = (d - radius) / oldrad;
        if !(-1.0..=1.0).contains(&l) {
            return Err(gouge());
        }
        if turn > 0 {
            -l.acos() + theta + PI
        } else {
            l.acos() + theta + PI
        }
    } else {
        let l = (d + radius) / oldrad;
        if !(-1.0..=1.0).contains(&l) {
            return Err(gouge());
        }
        if turn > 0 {
            l.acos() + theta + PI
        } else {
            -l.acos() + theta + PI
        }
    };
    Ok(centre + oldrad * dir(angle_from_centre))
}

/// LinuxCNC's `arc_data_r`: the centre of an R arc from `start` to `end`.
fn arc_data_r(
    b: &Block,
    ccw: bool,
    start: DVec2,
    end: DVec2,
    radius: f64,
) -> Result<DVec2, GcodeError> {
    let col = b.first_column();
    if start == end {
        return Err(b.err(col, "an R-format arc cannot end where it starts"));
    }
    let abs_radius = radius.abs();
    let mid = (start + end) / 2.0;
    let mut half = (mid - end).length();
    if half - abs_radius > RADIUS_TOLERANCE_MM {
        return Err(b.err(col, "arc radius R is too small to reach the end point"));
    }
    if half / abs_radius > 1.0 - 1e-12 {
        half = abs_radius;
    }
    let theta = if (!ccw && radius > 0.0) || (ccw && radius < 0.0) {
        angle(end - start) - FRAC_PI_2
    } else {
        angle(end - start) + FRAC_PI_2
    };
    let offset = abs_radius * (half / abs_radius).asin().cos();
    Ok(mid + offset * dir(theta))
}

/// LinuxCNC's `arc_data_ijk`: the centre from I J K, radii checked.
fn arc_data_ijk(
    b: &Block,
    s: &State,
    start: DVec2,
    end: DVec2,
    centre: ArcCentre,
) -> Result<DVec2, GcodeError> {
    let col = b.first_column();
    let c = match centre {
        ArcCentre::Absolute(c) => c,
        ArcCentre::Offset(o) => start + o,
        ArcCentre::Radius(_) => start,
    };
    let r1 = (c - start).length();
    let r2 = (c - end).length();
    if r1 < RADIUS_TOLERANCE_MM || r2 < RADIUS_TOLERANCE_MM {
        return Err(b.err(col, "zero-radius arc"));
    }
    let abs_err = (r1 - r2).abs();
    let rel_err = abs_err / r1.max(r2);
    let spiral = if s.inch {
        SPIRAL_ABS_INCH_MM
    } else {
        SPIRAL_ABS_MM
    };
    if abs_err > spiral * 100.0 || (rel_err > SPIRAL_REL && abs_err > spiral) {
        return Err(b.err(
            col,
            format!("arc start radius {r1:.4} mm and end radius {r2:.4} mm differ"),
        ));
    }
    Ok(c)
}

fn centre_of(
    b: &Block,
    s: &State,
    ccw: bool,
    start: DVec2,
    end: DVec2,
    centre: ArcCentre,
) -> Result<DVec2, GcodeError> {
    match centre {
        ArcCentre::Radius(r) => arc_data_r(b, ccw, start, end, r),
        _ => arc_data_ijk(b, s, start, end, centre),
    }
}

/// One compensated arc block: what every step of it needs.
struct ArcBlock<'a> {
    b: &'a Block,
    ccw: bool,
    /// LinuxCNC's turn: ±P.
    turn: i32,
    end: Joints,
    feed: f64,
    side: Side,
    radius: f64,
}

impl ArcBlock<'_> {
    /// The tool runs inside the arc (G41 with G3, G42 with G2).
    fn tool_inside(&self) -> bool {
        (self.side == Side::Left && self.ccw) || (self.side == Side::Right && !self.ccw)
    }

    fn too_small(&self) -> GcodeError {
        self.b.err(
            self.b.first_column(),
            "the tool radius is not less than the arc radius with compensation",
        )
    }
}

/// An arc (G3 `ccw`, or G2) to the programmed `end` with compensation active; `turns` is P.
///
/// # Errors
/// A [`GcodeError`] for an entry arc not longer than the radius, an arc too small for the
/// tool, or a corner the tool cannot reach.
#[allow(clippy::too_many_arguments)]
pub(super) fn arc(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    ccw: bool,
    end: Joints,
    centre: ArcCentre,
    turns: u32,
) -> Result<(), GcodeError> {
    let turns = i32::try_from(turns).unwrap_or(1);
    let a = ArcBlock {
        b,
        ccw,
        turn: if ccw { turns } else { -turns },
        end,
        feed: feed_for(b, s, opts, out, false)?,
        side: s.comp.side.unwrap_or(Side::Left),
        radius: s.comp.radius_mm,
    };
    if s.comp.first_move {
        arc_entry(s, &a, centre)
    } else {
        arc_next(s, out, &a, centre)
    }
}

/// The entry arc (LinuxCNC's `convert_arc_comp1`): it ends a radius from its programmed
/// end, on a circle through the tool's start.
fn arc_entry(s: &mut State, a: &ArcBlock, centre: ArcCentre) -> Result<(), GcodeError> {
    let (b, plane, radius, turn) = (a.b, s.plane, a.radius, a.turn);
    let col = b.first_column();
    let (c, _) = plane.split(s.pos.xyz);
    let (e, ez) = plane.split(a.end.xyz);
    if (e - c).length() <= radius {
        return Err(b.err(
            col,
            "radius of cutter compensation entry arc is not greater than the tool radius",
        ));
    }
    let centre = centre_of(b, s, a.ccw, c, e, centre)?;
    if (centre - c).length() <= radius && a.tool_inside() {
        return Err(a.too_small());
    }
    let gamma = if inside(a.side, turn) {
        angle(centre - e)
    } else {
        angle(e - centre)
    };
    s.comp.first_move = false;
    s.comp.programmed = Some(a.end.xyz);
    let e2 = e + radius * dir(gamma);
    let b_len = (c - e2).length() / 2.0;
    let ab_ang = angle(centre - e2);
    let a_ang = angle(c - e2) - ab_ang;
    if a_ang.cos().abs() < TOLERANCE_EQUAL {
        return Err(a.too_small());
    }
    let centre2 = e2 + b_len / a_ang.cos() * dir(ab_ang);
    let spiral = if s.inch {
        SPIRAL_ABS_INCH_MM
    } else {
        SPIRAL_ABS_MM
    };
    if ((centre2 - e2).length() - (centre2 - c).length()).abs() > spiral {
        return Err(b.err(col, "cutter compensation could not place the entry arc"));
    }
    let moved = with_plane(plane, a.end, e2, ez);
    let held = Held::Arc {
        centre: centre2,
        turn,
        original_sweep: find_turn(c, centre2, turn, e2),
    };
    hold(s, b, held, moved, a.feed, false);
    s.pos = moved;
    Ok(())
}

/// A later arc (LinuxCNC's `convert_arc_comp2`): the corner with the held move first.
fn arc_next(
    s: &mut State,
    out: &mut Program,
    a: &ArcBlock,
    centre: ArcCentre,
) -> Result<(), GcodeError> {
    let (b, plane, radius, side, turn) = (a.b, s.plane, a.radius, a.side, a.turn);
    let (c, cz) = plane.split(s.pos.xyz);
    let (e, ez) = plane.split(a.end.xyz);
    let (op, _) = plane.split(s.comp.programmed.unwrap_or(s.pos.xyz));
    let centre = centre_of(b, s, a.ccw, op, e, centre)?;
    let arc_radius = (centre - e).length();
    let normal = if side == Side::Left {
        -FRAC_PI_2
    } else {
        FRAC_PI_2
    };
    let theta = angle(c - op) + normal;
    let mut delta = angle(centre - op);
    let alpha = if a.ccw {
        delta - FRAC_PI_2
    } else {
        delta + FRAC_PI_2
    };
    let mut beta = if side == Side::Left {
        theta - alpha
    } else {
        alpha - theta
    };
    if beta > 1.5 * PI {
        beta -= TAU;
    } else if beta < -FRAC_PI_2 {
        beta += TAU;
    }
    let gamma = if a.tool_inside() {
        if arc_radius <= radius {
            return Err(a.too_small());
        }
        angle(centre - e)
    } else {
        delta += PI;
        angle(e - centre)
    };
    let new_end = e + radius * dir(gamma);
    let main = Held::Arc {
        centre,
        turn,
        original_sweep: find_turn(op, centre, turn, e),
    };
    let concave = !(-SMALL..=PI + SMALL).contains(&beta)
        || ((beta - PI).abs() < SMALL && !inside(side, turn));
    if concave {
        let mid = concave_arc_corner(s, a, centre, arc_radius, theta, beta)?;
        move_endpoint_and_flush(s, out, b.line, mid)?;
    } else if beta > SMALL {
        // Outside corner: an arc around the programmed corner, then the arc itself.
        let mid = op + radius * dir(delta);
        dequeue(s, out)?;
        let corner = with_plane(plane, a.end, mid, cz);
        let corner_arc = Held::Arc {
            centre: op,
            turn: if side == Side::Left { -1 } else { 1 },
            original_sweep: 0.0,
        };
        hold(s, b, corner_arc, corner, a.feed, false);
        dequeue(s, out)?;
        set_endpoint(s, mid);
    } else {
        dequeue(s, out)?;
        set_endpoint(s, c);
    }
    let moved = with_plane(plane, a.end, new_end, ez);
    hold(s, b, main, moved, a.feed, false);
    s.comp.programmed = Some(a.end.xyz);
    s.pos = moved;
    Ok(())
}

/// Where the held move must end before an arc into an inside corner: on the arc's offset
/// circle, meeting the held line or arc.
fn concave_arc_corner(
    s: &State,
    a: &ArcBlock,
    centre: DVec2,
    arc_radius: f64,
    theta: f64,
    beta: f64,
) -> Result<DVec2, GcodeError> {
    let (b, radius, side, turn) = (a.b, a.radius, a.side, a.turn);
    let col = b.first_column();
    if let Some((prev_c, prev_end, prev_turn)) = s.comp.front_arc_plane(s.plane) {
        let oldrad = (prev_c - prev_end).length();
        let newrad = if inside(side, turn) {
            arc_radius - radius
        } else {
            arc_radius + radius
        };
        let arc_cc = (prev_c - centre).length();
        if oldrad == 0.0 || arc_cc == 0.0 {
            return Err(b.err(
                col,
                "arc to arc motion is invalid because the arcs have the same centre",
            ));
        }
        let k = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2.0 * oldrad * arc_cc);
        if !(-1.0..=1.0).contains(&k) {
            return Err(b.err(
                col,
                "arc to arc motion makes a corner the compensated tool can't fit in without \
                 gouging",
            ));
        }
        let pullback = k.acos();
        let cc_dir = angle(centre - prev_c);
        let d = if inside(side, prev_turn) == (turn > 0) {
            cc_dir + pullback
        } else {
            cc_dir - pullback
        };
        return Ok(prev_c + oldrad * dir(d));
    }
    let cy = arc_radius * (beta - FRAC_PI_2).sin();
    let gouge = || {
        b.err(
            col,
            "arc move in a concave corner cannot be reached by the tool without gouging",
        )
    };
    let (dist, l) = if inside(side, turn) {
        (arc_radius - radius, (cy + radius) / (arc_radius - radius))
    } else {
        (arc_radius + radius, (cy - radius) / (arc_radius + radius))
    };
    if !(-1.0..=1.0).contains(&l) {
        return Err(gouge());
    }
    let at = match (inside(side, turn), turn > 0) {
        (true, true) => theta + l.asin(),
        (true, false) => theta - l.asin(),
        (false, true) => theta + PI - l.asin(),
        (false, false) => theta + PI + l.asin(),
    };
    Ok(centre + dist * dir(at))
}

/// G40: end the held move at its offset end (LinuxCNC's `convert_cutter_compensation_off`).
///
/// # Errors
/// A [`GcodeError`] when the held move cannot end there.
pub(super) fn off(s: &mut State, out: &mut Program, line: usize) -> Result<(), GcodeError> {
    if s.comp.active() && !s.comp.first_move {
        let (c, _) = s.plane.split(s.pos.xyz);
        move_endpoint_and_flush(s, out, line, c)?;
        dequeue(s, out)?;
        s.comp.arc_not_allowed = true;
    }
    s.comp.side = None;
    s.comp.first_move = true;
    Ok(())
}

/// Emit what is held (at M0, M1, M2, M30 and the end of the program).
///
/// # Errors
/// A [`GcodeError`] when the held move cannot end at its offset end.
pub(super) fn flush(s: &mut State, out: &mut Program, line: usize) -> Result<(), GcodeError> {
    if s.comp.holding() {
        let (c, _) = s.plane.split(s.pos.xyz);
        move_endpoint_and_flush(s, out, line, c)?;
        dequeue(s, out)?;
    }
    Ok(())
}
