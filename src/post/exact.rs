//! Exact moves in the program: arcs and helices as G2/G3, canned cycles in the dialect's
//! style, and both as straight moves where the dialect, machine or mode cannot write them.
//!
//! An arc is written as G2/G3 when the post is in joint space, the dialect writes arcs (and
//! helices, for a helix), the rotary axes stand still over it, its plane maps onto G17, G18 or
//! G19 in machine coordinates and is one the dialect allows, and its radius is within the
//! dialect's limit; it is split into blocks of at most the dialect's largest sweep. Otherwise
//! it is sampled again at the post tolerance and written as lines.
//!
//! A cycle is written as one cycle call when the post is in joint space, the dialect has a
//! cycle style (not `expand`) with that kind of cycle, the rotary axes stand still and the
//! hole's axis is machine +Z; otherwise its motion (the poses that sample it, dwells and
//! spindle switches) is written as G0/G1 moves.

use glam::{DMat3, DVec3};

use super::dialect::{ArcCentre, CycleStyle};
use super::writer::plane_code;
use super::{
    Dialect, MachineJoints, PostError, PostOptions, Writer, rounded_frame, straight_between,
};
use crate::gcode::Plane;
use crate::machine::{Machine, ToolPose};
use crate::toolpath::{
    ArcMove, CycleKind, CycleMove, CycleRetract, CycleStep, ExactMove, ExactSegment, Pose,
    SpindleSwitch, Toolpath,
};

/// Write one exact segment.
pub(super) fn segment(
    w: &mut Writer<'_>,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
    tp: &Toolpath,
    seg: &ExactSegment,
    prev: &mut MachineJoints,
) -> Result<(), PostError> {
    match seg.exact {
        ExactMove::Arc(a) => {
            if !arc(w, machine, dialect, options, tp, seg, &a, prev)? {
                arc_as_lines(w, machine, dialect, options, tp, seg, &a, prev)?;
            }
        }
        ExactMove::Cycle(c) => {
            if !cycle(w, machine, dialect, options, tp, seg, &c, prev)? {
                expand(w, machine, dialect, options, tp, seg, &c, prev)?;
            }
        }
    }
    Ok(())
}

/// The joints at the end pose when the rotary axes do not turn from `prev`; the map to machine
/// coordinates there.
fn steady_frame(
    machine: &Machine,
    dialect: &Dialect,
    end: &Pose,
    prev: &MachineJoints,
) -> Result<Option<(MachineJoints, DMat3, DVec3)>, PostError> {
    let j = machine
        .inverse(
            &ToolPose {
                tip: end.tip,
                axis: end.axis,
            },
            prev,
        )
        .map_err(|source| PostError::Pose { pose: 0, source })?;
    if (j.tilt_rad - prev.tilt_rad).abs() > 1e-12 || (j.rotary_rad - prev.rotary_rad).abs() > 1e-12
    {
        return Ok(None);
    }
    let (_, r, t) = rounded_frame(dialect, machine, prev);
    Ok(Some((j, r, t)))
}

/// The G17/G18/G19 plane a machine-frame normal lies along, and +1 or −1 for its sense.
fn plane_of(normal: DVec3) -> Option<(Plane, f64)> {
    [Plane::Xy, Plane::Zx, Plane::Yz].into_iter().find_map(|p| {
        let d = normal.dot(p.normal());
        (d.abs() > 1.0 - 1e-9).then_some((p, d.signum()))
    })
}

/// The pose tag of the piece ending at parameter `t` of a segment.
fn tag(seg: &ExactSegment, t: f64) -> usize {
    let span = (seg.to - seg.from) as f64;
    (seg.from + (t * span).ceil() as usize).clamp(seg.from + 1, seg.to)
}

#[expect(
    clippy::too_many_arguments,
    reason = "the writer, the three posting inputs, the path, the segment, its arc and the joints"
)]
fn arc(
    w: &mut Writer<'_>,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
    tp: &Toolpath,
    seg: &ExactSegment,
    a: &ArcMove,
    prev: &mut MachineJoints,
) -> Result<bool, PostError> {
    let (Some(first), Some(last)) = (tp.poses.get(seg.from), tp.poses.get(seg.to)) else {
        return Ok(false);
    };
    if options.tcp || w.tilted() || !dialect.arcs || (a.helix_mm != 0.0 && !dialect.helix) {
        return Ok(false);
    }
    let Some((j_end, r, t)) =
        steady_frame(machine, dialect, last, prev).map_err(|e| with_pose(e, seg.to))?
    else {
        return Ok(false);
    };
    let Some((plane, sense)) = plane_of(r * a.normal) else {
        return Ok(false);
    };
    if !dialect.arc_planes.iter().any(|p| p == plane_code(plane))
        || a.radius_mm(first.tip) > dialect.arc_max_radius_mm
    {
        return Ok(false);
    }
    let mut max_sweep = dialect.arc_max_sweep_deg.to_radians();
    if dialect.arc_centre == ArcCentre::Radius {
        max_sweep = max_sweep.min(150f64.to_radians());
    }
    let n = ((a.sweep_rad.abs() / max_sweep).ceil() as usize).max(1);
    let piece_sweep = a.sweep_rad.abs() / n as f64;
    let ccw = a.sweep_rad * sense > 0.0;
    for i in 1..=n {
        let t0 = (i - 1) as f64 / n as f64;
        let t1 = i as f64 / n as f64;
        let end = r * a.point_at(first.tip, t1) + t;
        let centre = r * (a.centre + a.normal * (a.helix_mm * t0)) + t;
        if !w.arc(
            plane,
            ccw,
            end,
            centre,
            piece_sweep,
            last.feed_mm_per_min,
            tag(seg, t1),
        ) {
            return Ok(false);
        }
    }
    *prev = j_end;
    Ok(true)
}

fn with_pose(e: PostError, pose: usize) -> PostError {
    match e {
        PostError::Pose { source, .. } => PostError::Pose { pose, source },
        other => other,
    }
}

/// The arc sampled again at the post tolerance, written as lines.
#[expect(
    clippy::too_many_arguments,
    reason = "the writer, the three posting inputs, the path, the segment, its arc and the joints"
)]
fn arc_as_lines(
    w: &mut Writer<'_>,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
    tp: &Toolpath,
    seg: &ExactSegment,
    a: &ArcMove,
    prev: &mut MachineJoints,
) -> Result<(), PostError> {
    let (Some(first), Some(last)) = (tp.poses.get(seg.from), tp.poses.get(seg.to)) else {
        return Ok(());
    };
    let n = a
        .pieces(first.tip, options.tolerance_mm)
        .map_err(|m| PostError::Options(format!("exact move at pose {}: {m}", seg.from)))?;
    let mut from = *first;
    for i in 1..=n {
        let t = i as f64 / n as f64;
        let mut to = *last;
        to.tip = if i == n {
            last.tip
        } else {
            a.point_at(first.tip, t)
        };
        straight_between(w, machine, dialect, options, &from, &to, tag(seg, t), prev)?;
        from = to;
    }
    Ok(())
}

#[expect(
    clippy::too_many_arguments,
    reason = "the writer, the three posting inputs, the path, the segment, its cycle and the joints"
)]
fn cycle(
    w: &mut Writer<'_>,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
    tp: &Toolpath,
    seg: &ExactSegment,
    c: &CycleMove,
    prev: &mut MachineJoints,
) -> Result<bool, PostError> {
    let Some(last) = tp.poses.get(seg.to) else {
        return Ok(false);
    };
    // Under a tilted work plane arcs and cycles are written as moves (not read back there).
    if options.tcp || w.tilted() || dialect.cycles == CycleStyle::Expand {
        return Ok(false);
    }
    let Some((j_end, r, t)) =
        steady_frame(machine, dialect, last, prev).map_err(|e| with_pose(e, seg.to))?
    else {
        return Ok(false);
    };
    if (r * c.axis).z < 1.0 - 1e-9 {
        return Ok(false);
    }
    let surface = r * c.surface + t;
    let text = match dialect.cycles {
        CycleStyle::Rs274 => rs274(dialect, c, surface),
        CycleStyle::Siemens => siemens(dialect, c, surface, options.spindle_rpm),
        CycleStyle::HeidenhainIso => heidenhain(dialect, c, surface),
        CycleStyle::Expand => None,
    };
    let Some(blocks) = text else {
        return Ok(false);
    };
    let mut first = true;
    for b in blocks {
        let mut words: Vec<String> = Vec::new();
        if first {
            words.extend(w.plane_word("G17"));
            let (mode, _) = w.per_minute_words(c.feed_mm_per_min);
            words.extend(mode);
            first = false;
        }
        words.push(b);
        w.tagged_block(&words.join(" "), Some(seg.to));
    }
    w.moved_to(r * c.at(c.clear_mm()) + t);
    w.forget_feed();
    *prev = j_end;
    Ok(true)
}

fn z_word(d: &Dialect, letter: char, v: f64) -> String {
    format!("{letter}{}", d.number(v, d.decimals_linear))
}

/// `G98 G83 X Y Z R Q F` and `G80`.
fn rs274(d: &Dialect, c: &CycleMove, surface: DVec3) -> Option<Vec<String>> {
    let dl = d.decimals_linear;
    let dwell = |s: f64| {
        if d.cycle_dwell_ms {
            format!("P{:.0}", s * 1000.0)
        } else {
            format!("P{}", d.number(s, 3))
        }
    };
    let (code, extra) = match c.cycle {
        CycleKind::Drill => ("G81", None),
        CycleKind::Dwell { dwell_s } => ("G82", Some(dwell(dwell_s))),
        CycleKind::Peck { peck_mm } => ("G83", Some(z_word(d, 'Q', peck_mm))),
        CycleKind::ChipBreak { peck_mm } => ("G73", Some(z_word(d, 'Q', peck_mm))),
        // G84 and G86 dwell P at the bottom, and P is sticky (LinuxCNC's `cycle_p`, checked with
        // `rs274`): a P left by an earlier G82 would dwell there, so they always say P0.
        CycleKind::Tap { .. } => ("G84", Some(dwell(0.0))),
        CycleKind::Bore { dwell_s } if dwell_s > 0.0 => ("G89", Some(dwell(dwell_s))),
        CycleKind::Bore { .. } => ("G85", None),
        CycleKind::BoreSpindleStop { dwell_s } => ("G86", Some(dwell(dwell_s.max(0.0)))),
    };
    let retract = match c.retract {
        CycleRetract::Initial => "G98",
        CycleRetract::RPlane => "G99",
    };
    let mut words = vec![
        retract.to_string(),
        code.to_string(),
        format!("X{}", d.number(surface.x, dl)),
        format!("Y{}", d.number(surface.y, dl)),
        z_word(d, 'Z', surface.z - c.depth_mm),
        z_word(d, 'R', surface.z + c.clearance_mm),
    ];
    words.extend(extra);
    words.push(format!("F{}", d.number(c.feed_mm_per_min, d.decimals_feed)));
    Some(vec![words.join(" "), "G80".into()])
}

/// `F..` then `CYCLE8x(RTP, RFP, SDIS, DP, DPR, …)`.
fn siemens(d: &Dialect, c: &CycleMove, surface: DVec3, rpm: f64) -> Option<Vec<String>> {
    let n = |v: f64| d.number(v, d.decimals_linear);
    let rtp = n(surface.z + c.clear_mm());
    let rfp = n(surface.z);
    let sdis = n(c.clearance_mm);
    let dp = n(surface.z - c.depth_mm);
    let head = format!("{rtp}, {rfp}, {sdis}, {dp}, ");
    // CYCLE84 and CYCLE85 feed out only to RFP + SDIS and rapid on to RTP; a tap or a dwelling
    // bore fed out to the initial plane (G84 / G89 with G98) is written as plain moves.
    let fed_out_past_r = match c.cycle {
        CycleKind::Tap { .. } => true,
        CycleKind::Bore { dwell_s } => dwell_s > 0.0,
        _ => false,
    };
    if fed_out_past_r && c.clear_mm() > c.clearance_mm {
        return None;
    }
    let call = match c.cycle {
        CycleKind::Drill => format!("CYCLE81({head})"),
        CycleKind::Dwell { dwell_s } => format!("CYCLE82({head}, {})", d.number(dwell_s, 3)),
        CycleKind::Peck { peck_mm } | CycleKind::ChipBreak { peck_mm } => {
            let vari = if matches!(c.cycle, CycleKind::Peck { .. }) {
                1
            } else {
                0
            };
            let fdep = n(surface.z + c.clearance_mm - peck_mm);
            format!("CYCLE83({head}, {fdep}, , {}, 0, 0, 1, {vari})", n(peck_mm))
        }
        CycleKind::Tap { pitch_mm } => format!(
            "CYCLE84({head}, 0, 3, , {}, 0, {rpm:.0}, {rpm:.0})",
            n(pitch_mm)
        ),
        CycleKind::Bore { dwell_s } => {
            let f = d.number(c.feed_mm_per_min, d.decimals_feed);
            format!("CYCLE85({head}, {}, {f}, {f})", d.number(dwell_s, 3))
        }
        CycleKind::BoreSpindleStop { .. } => return None,
    };
    Some(vec![
        format!("F{}", d.number(c.feed_mm_per_min, d.decimals_feed)),
        call,
    ])
}

/// `G2xx Q200=… …` then `G79` (the cycle call), as `gcode::heidenhain` reads them (the TNC
/// ISO manuals' cycles 200, 201, 203, 205, 207). The pecking cycles count their cuts from
/// the surface Q203 where G83/G73 count from the R plane, so they are written with Q203 at the
/// R plane and Q200=0 (the same moves); a peck comes back down to 0.254 mm above the last depth
/// (205's advanced stop Q258), a chip break backs off 0.254 mm (203's Q256), as G83/G73 do.
/// Cycles 207 and 201 feed out only to the set-up clearance: a tap or a dwelling bore that
/// goes back to the initial plane is written as moves. Cycle 202 (spindle-stop bore) always
/// is: it orients the spindle, which G86 does not.
fn heidenhain(d: &Dialect, c: &CycleMove, surface: DVec3) -> Option<Vec<String>> {
    let n = |v: f64| d.number(v, d.decimals_linear);
    let f = d.number(c.feed_mm_per_min, d.decimals_feed);
    let fed_out_past_r = match c.cycle {
        CycleKind::Tap { .. } => true,
        CycleKind::Bore { dwell_s } => dwell_s > 0.0,
        _ => false,
    };
    if fed_out_past_r && c.clear_mm() > c.clearance_mm {
        return None;
    }
    let common = format!("Q200={} Q201={}", n(c.clearance_mm), n(-c.depth_mm));
    let tail = format!("Q203={} Q204={}", n(surface.z), n(c.clear_mm()));
    // From the R plane (Q200 = 0): the pecking cycles.
    let r_plane = format!("Q200=0 Q201={}", n(-(c.depth_mm + c.clearance_mm)));
    let r_tail = format!(
        "Q203={} Q204={}",
        n(surface.z + c.clearance_mm),
        n(c.clear_mm() - c.clearance_mm)
    );
    let clearance = n(crate::toolpath::PECK_CLEARANCE_MM);
    let def = match c.cycle {
        CycleKind::Drill => format!(
            "G200 {common} Q206={f} Q202={} Q210=0 {tail} Q211=0",
            n(c.depth_mm)
        ),
        CycleKind::Dwell { dwell_s } => format!(
            "G200 {common} Q206={f} Q202={} Q210=0 {tail} Q211={}",
            n(c.depth_mm),
            d.number(dwell_s, 3)
        ),
        CycleKind::Peck { peck_mm } => format!(
            "G205 {r_plane} Q206={f} Q202={} {r_tail} Q212=0 Q205=0 Q258={clearance} Q259={clearance} Q257=0 Q211=0",
            n(peck_mm)
        ),
        CycleKind::ChipBreak { peck_mm } => format!(
            "G203 {r_plane} Q206={f} Q202={} Q210=0 {r_tail} Q212=0 Q213=99 Q205=0 Q211=0 Q208=FMAX Q256={clearance}",
            n(peck_mm)
        ),
        CycleKind::Tap { pitch_mm } => format!("G207 {common} Q239={} {tail}", n(pitch_mm)),
        CycleKind::Bore { dwell_s } => format!(
            "G201 {common} Q206={f} Q211={} Q208={f} {tail}",
            d.number(dwell_s, 3)
        ),
        CycleKind::BoreSpindleStop { .. } => return None,
    };
    Some(vec![def, "G79".into()])
}

/// The cycle's motion as straight moves through its poses, with dwells and spindle switches.
#[expect(
    clippy::too_many_arguments,
    reason = "the writer, the three posting inputs, the path, the segment, its cycle and the joints"
)]
fn expand(
    w: &mut Writer<'_>,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
    tp: &Toolpath,
    seg: &ExactSegment,
    c: &CycleMove,
    prev: &mut MachineJoints,
) -> Result<(), PostError> {
    let mut k = seg.from;
    for step in c.steps() {
        match step {
            CycleStep::Rapid(_) | CycleStep::Feed(_) => {
                let (Some(a), Some(b)) = (tp.poses.get(k), tp.poses.get(k + 1)) else {
                    break;
                };
                straight_between(w, machine, dialect, options, a, b, k + 1, prev)?;
                k += 1;
            }
            CycleStep::Dwell(s) => {
                let text = dialect
                    .dwell
                    .replace("{seconds}", &dialect.number(s, 3))
                    .replace("{ms}", &format!("{:.0}", s * 1000.0));
                w.tagged_block(&text, Some(k));
            }
            CycleStep::Spindle(switch) if options.spindle_rpm > 0.0 => {
                let code = match switch {
                    SpindleSwitch::Stop => &dialect.spindle_stop,
                    SpindleSwitch::Forward => &dialect.spindle_forward,
                    SpindleSwitch::Reverse => &dialect.spindle_reverse,
                };
                w.tagged_block(code, Some(k));
            }
            CycleStep::Spindle(_) => {}
        }
    }
    Ok(())
}
