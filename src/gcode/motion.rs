//! Motion execution: end points in machine coordinates, feeds, and the emitted blocks.

use glam::DVec3;

use super::arc::{CentreSpec, arc_geometry};
use super::block::{Joints, MotionBlock, MotionKind};
use super::interpreter::{Block, Motion, State, u32_word};
use super::{GcodeError, InterpretOptions, Program};
use crate::diagnostics::Diagnostic;

/// The end point of a block. `machine`: coordinates are machine coordinates (G53, G28 home).
pub(super) fn target(
    b: &Block,
    s: &State,
    opts: &InterpretOptions,
    scale: f64,
    machine: bool,
) -> Joints {
    let offset = if machine {
        DVec3::ZERO
    } else {
        opts.work_offsets
            .get(s.work_offset)
            .copied()
            .unwrap_or(DVec3::ZERO)
    };
    let mut p = s.pos;
    let mut xyz = p.xyz.to_array();
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
        Some(f) => Ok(f),
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

pub(super) fn push(
    s: &mut State,
    out: &mut Program,
    b: &Block,
    kind: MotionKind,
    end: Joints,
    feed: f64,
) {
    let start = start_for(s.pos, end);
    out.blocks.push(MotionBlock {
        kind,
        start,
        end,
        feed_mm_per_min: feed,
        inverse_time: s.inverse_time && kind != MotionKind::Rapid,
        source_line: b.line,
        tool: s.tool,
        tool_length_h: s.tool_length_h,
        spindle_rpm: s.spindle_speed * s.spindle_dir,
        coolant: s.coolant,
        tcp: s.tcp,
    });
    s.pos = end;
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
    if start_for(s.pos, end) == end {
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

pub(super) fn emit_arc(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    ccw: bool,
    end: Joints,
    scale: f64,
) -> Result<(), GcodeError> {
    let (iu, iv, iw) = s.plane.axes();
    let letters = ['I', 'J', 'K'];
    let col = b.first_column();
    let spec = if let Some((r, rc)) = b.get('R') {
        if let Some((_, c)) = letters.iter().find_map(|l| b.get(*l)) {
            return Err(b.err(c, "an arc takes either R or I/J/K, not both"));
        }
        if !(r.abs() > 0.0) {
            return Err(b.err(rc, "arc radius R is zero"));
        }
        CentreSpec::Radius(r * scale)
    } else {
        let in_plane = [iu, iv]
            .iter()
            .any(|i| letters.get(*i).and_then(|l| b.get(*l)).is_some());
        if !in_plane {
            return Err(b.err(
                col,
                "an arc needs R or centre offsets I/J/K in the active plane",
            ));
        }
        if let Some((v, c)) = letters.get(iw).and_then(|l| b.get(*l))
            && v != 0.0
        {
            return Err(b.err(c, "centre offset along the plane normal is not allowed"));
        }
        let off = |i: usize| {
            letters
                .get(i)
                .and_then(|l| b.get(*l))
                .map_or(0.0, |(v, _)| v * scale)
        };
        let given = DVec3::new(off(0), off(1), off(2));
        let centre = if s.arc_absolute {
            given
                + opts
                    .work_offsets
                    .get(s.work_offset)
                    .copied()
                    .unwrap_or(DVec3::ZERO)
        } else {
            s.pos.xyz + given
        };
        CentreSpec::Centre(centre)
    };
    let turns = match b.get('P') {
        Some((p, pc)) => u32_word(p)
            .filter(|p| (1..=10_000).contains(p))
            .ok_or_else(|| b.err(pc, "P (turns) must be a positive integer"))?,
        None => 1,
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
    let via = target(b, s, opts, scale, false);
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
