//! Motion execution: end points in machine coordinates, feeds, and the emitted blocks.

use glam::{DVec2, DVec3};

use super::arc::{CentreSpec, arc_geometry};
use super::block::{Joints, MotionBlock, MotionKind};
use super::state::{Block, Motion, Snapshot, State, u32_word};
use super::{Dwell, GcodeError, InterpretOptions, Program};
use crate::diagnostics::Diagnostic;

/// The sum of the offsets between program and machine coordinates: the active work offset,
/// the G92/G52 offset and the G43 tool length offset, mm.
pub(super) fn total_offset(s: &State) -> DVec3 {
    s.total_offset()
}

/// The end point of a block. `machine`: coordinates are machine coordinates (G53, G28 home).
/// Coordinates a block leaves out, and the base of incremental ones, are where the program
/// is: the tool's position, or the programmed point while cutter compensation offsets the
/// tool from it.
pub(super) fn target(b: &Block, s: &State, scale: f64, machine: bool) -> Joints {
    if let Some(plane) = s.work_plane.as_ref().filter(|_| !machine) {
        // Under a tilted plane X Y Z are plane coordinates (rotary words are refused there).
        let offset = total_offset(s);
        let mut p = plane.point(&s.pos, offset).to_array();
        for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if let (Some((v, _)), Some(slot)) = (b.get(l), p.get_mut(i)) {
                *slot = if s.absolute {
                    v * scale
                } else {
                    *slot + v * scale
                };
            }
        }
        return plane.joints(DVec3::from_array(p), &s.pos, offset);
    }
    let offset = if machine {
        DVec3::ZERO
    } else {
        total_offset(s)
    };
    let mut p = s.pos;
    let base = s.comp.programmed.unwrap_or(s.pos.xyz).to_array();
    let mut xyz = base;
    for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if let (Some((v, _)), Some(slot)) = (b.get(l), xyz.get_mut(i)) {
            let off = offset.to_array().get(i).copied().unwrap_or(0.0);
            *slot = if s.absolute {
                v * scale + off
            } else {
                *slot + v * scale
            };
        }
    }
    p.xyz = DVec3::from_array(xyz);
    for (l, slot) in [('A', &mut p.a), ('B', &mut p.b), ('C', &mut p.c)] {
        if let Some((v, _)) = b.get(l) {
            let v = v.to_radians();
            *slot = Some(if s.absolute {
                v
            } else {
                slot.unwrap_or(0.0) + v
            });
        }
    }
    p
}

/// Start of a block: an axis the block moves that was never set starts at 0.
pub(super) fn start_for(pos: Joints, end: Joints) -> Joints {
    let fill = |s: Option<f64>, e: Option<f64>| s.or(e.map(|_| 0.0));
    Joints {
        xyz: pos.xyz,
        a: fill(pos.a, end.a),
        b: fill(pos.b, end.b),
        c: fill(pos.c, end.c),
    }
}

/// The feed of a move: the rapid rate, the G93 F word, or the modal feed.
///
/// # Errors
/// A [`GcodeError`] for a G93 move without F, or a feed move with an F of zero (LinuxCNC:
/// "cannot do G1 with zero feed rate").
pub(super) fn feed_for(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    rapid: bool,
) -> Result<f64, GcodeError> {
    if rapid {
        return Ok(opts.rapid_mm_per_min);
    }
    if s.inverse_time {
        return match b.get('F') {
            Some((f, _)) if f > 0.0 => Ok(f),
            Some((_, col)) => Err(b.err(col, "inverse-time F must be positive")),
            None => Err(b.err(
                b.first_column(),
                "inverse-time feed (G93) needs an F word on every feed move",
            )),
        };
    }
    match s.feed {
        Some(f) if f > 0.0 => Ok(f),
        Some(_) => {
            let col = b.get('F').map_or_else(|| b.first_column(), |(_, c)| c);
            Err(b.err(
                col,
                "a feed move with zero feed rate (F0): give the feed with F",
            ))
        }
        None => {
            if !s.warned_no_feed {
                s.warned_no_feed = true;
                out.diagnostics.push(Diagnostic::warning(
                    format!("line {}", b.line),
                    "feed move before any F word: feed 0 recorded",
                ));
            }
            Ok(0.0)
        }
    }
}

/// How an arc's centre is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum ArcCentre {
    /// R word, mm (negative: the long way round).
    Radius(f64),
    /// Incremental I J K, mm, in plane coordinates (from the arc's start).
    Offset(DVec2),
    /// G90.1 centre, machine mm, in plane coordinates.
    Absolute(DVec2),
}

/// Emit a block from the end of the last emitted one.
pub(super) fn push_block(
    s: &mut State,
    out: &mut Program,
    kind: MotionKind,
    end: Joints,
    feed: f64,
    snap: &Snapshot,
) {
    let start = start_for(s.emitted, end);
    out.blocks.push(MotionBlock {
        kind,
        start,
        end,
        feed_mm_per_min: feed,
        inverse_time: snap.inverse_time,
        source_line: snap.line,
        tool: snap.tool,
        tool_length_h: snap.tool_length_h,
        spindle_rpm: snap.spindle_rpm,
        coolant: snap.coolant,
        tcp: snap.tcp,
        cycle: snap.cycle,
    });
    s.emitted = end;
}

pub(super) fn push(
    s: &mut State,
    out: &mut Program,
    b: &Block,
    kind: MotionKind,
    end: Joints,
    feed: f64,
) {
    let snap = Snapshot::of(s, b.line, kind == MotionKind::Rapid);
    push_block(s, out, kind, end, feed, &snap);
    s.pos = end;
    s.comp.programmed = None;
}

/// A dwell before the next block (held behind a compensated move that is still held).
pub(super) fn dwell(s: &mut State, out: &mut Program, line: usize, seconds: f64) {
    if s.comp.holding() {
        s.comp.hold_dwell(line, seconds);
    } else {
        out.dwells.push(Dwell {
            line,
            before_block: out.blocks.len(),
            seconds,
            cycle: s
                .cycle_phase
                .filter(|c| c.step == super::block::CycleStep::Dwell),
        });
    }
}

pub(super) fn emit_line(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    m: Motion,
    end: Joints,
) -> Result<(), GcodeError> {
    let rapid = m == Motion::Rapid;
    s.comp.arc_not_allowed = false;
    if start_for(s.pos, end) == end {
        s.comp.programmed = None;
        return Ok(()); // no movement
    }
    let feed = feed_for(b, s, opts, out, rapid)?;
    let kind = if rapid {
        MotionKind::Rapid
    } else {
        MotionKind::Linear
    };
    push(s, out, b, kind, end, feed);
    Ok(())
}

/// The centre of an arc block: R, or I J K (incremental from the start, or G90.1 absolute).
fn arc_centre(b: &Block, s: &State, scale: f64) -> Result<ArcCentre, GcodeError> {
    let (iu, iv, iw) = s.plane.axes();
    let letters = ['I', 'J', 'K'];
    let col = b.first_column();
    if let Some((r, rc)) = b.get('R') {
        if let Some((_, c)) = letters.iter().find_map(|l| b.get(*l)) {
            return Err(b.err(c, "an arc takes either R or I/J/K, not both"));
        }
        if !(r.abs() > 0.0) {
            return Err(b.err(rc, "arc radius R is zero"));
        }
        return Ok(ArcCentre::Radius(r * scale));
    }
    let word = |i: usize| letters.get(i).and_then(|l| b.get(*l));
    if word(iu).is_none() && word(iv).is_none() {
        return Err(b.err(
            col,
            "an arc needs R or centre offsets I/J/K in the active plane",
        ));
    }
    if let Some((v, c)) = word(iw)
        && v != 0.0
    {
        return Err(b.err(c, "centre offset along the plane normal is not allowed"));
    }
    let off = |i: usize| word(i).map_or(0.0, |(v, _)| v * scale);
    let given = DVec2::new(off(iu), off(iv));
    if s.arc_absolute {
        for i in [iu, iv] {
            if word(i).is_none() {
                let l = letters.get(i).copied().unwrap_or('I');
                return Err(b.err(
                    col,
                    format!("{l} word missing in an absolute-centre arc (G90.1)"),
                ));
            }
        }
        let (o, _) = s.plane.split(total_offset(s));
        Ok(ArcCentre::Absolute(given + o))
    } else {
        Ok(ArcCentre::Offset(given))
    }
}

/// The centre and the turns (`P`, default 1) of an arc block.
///
/// # Errors
/// A [`GcodeError`] for R with I/J/K, a zero R, no centre in the plane, a centre off the
/// plane, a missing absolute centre word, or a P that is not a positive integer.
pub(super) fn arc_words(b: &Block, s: &State, scale: f64) -> Result<(ArcCentre, u32), GcodeError> {
    let centre = arc_centre(b, s, scale)?;
    let turns = match b.get('P') {
        Some((p, pc)) => u32_word(p)
            .filter(|p| (1..=10_000).contains(p))
            .ok_or_else(|| b.err(pc, "P (turns) must be a positive integer"))?,
        None => 1,
    };
    Ok((centre, turns))
}

/// An arc without cutter compensation.
///
/// # Errors
/// A [`GcodeError`] for impossible geometry.
#[allow(clippy::too_many_arguments)]
pub(super) fn emit_arc(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    ccw: bool,
    end: Joints,
    centre: ArcCentre,
    turns: u32,
) -> Result<(), GcodeError> {
    let col = b.first_column();
    let spec = match centre {
        ArcCentre::Radius(r) => CentreSpec::Radius(r),
        ArcCentre::Offset(o) => {
            let (p, w) = s.plane.split(s.pos.xyz);
            CentreSpec::Centre(s.plane.join(p + o, w))
        }
        ArcCentre::Absolute(c) => {
            let (_, w) = s.plane.split(s.pos.xyz);
            CentreSpec::Centre(s.plane.join(c, w))
        }
    };
    let arc =
        arc_geometry(s.pos.xyz, end.xyz, s.plane, ccw, spec, turns).map_err(|m| b.err(col, m))?;
    let feed = feed_for(b, s, opts, out, false)?;
    let kind = if ccw {
        MotionKind::ArcCcw(arc)
    } else {
        MotionKind::ArcCw(arc)
    };
    push(s, out, b, kind, end, feed);
    Ok(())
}

/// G28: rapid through the optional intermediate point to the home position.
pub(super) fn g28(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    scale: f64,
) -> Result<(), GcodeError> {
    let has_axis = "XYZABC".chars().any(|l| b.get(l).is_some());
    if !has_axis {
        let mut home = s.pos;
        home.xyz = opts.g28_position;
        return emit_line(b, s, opts, out, Motion::Rapid, home);
    }
    let via = target(b, s, scale, false);
    emit_line(b, s, opts, out, Motion::Rapid, via)?;
    let mut home = s.pos;
    let mut xyz = home.xyz.to_array();
    let g28 = opts.g28_position.to_array();
    for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if b.get(l).is_some()
            && let (Some(slot), Some(h)) = (xyz.get_mut(i), g28.get(i))
        {
            *slot = *h;
        }
    }
    home.xyz = DVec3::from_array(xyz);
    for (l, slot) in [('A', &mut home.a), ('B', &mut home.b), ('C', &mut home.c)] {
        if b.get(l).is_some() {
            *slot = Some(0.0);
        }
    }
    emit_line(b, s, opts, out, Motion::Rapid, home)
}
