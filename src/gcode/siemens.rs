//! Sinumerik 840D drilling cycles, `CYCLE81`–`CYCLE86` and `CYCLE840`, called once
//! (`CYCLE81(…)` on its own block, at the tool's position) or modally (`MCALL CYCLE81(…)`: after
//! every following block that moves an axis, at its end point, until a bare `MCALL`).
//!
//! Parameters in the order of the 840D cycles manual (empty places take the defaults):
//!
//! | cycle | parameters |
//! |---|---|
//! | CYCLE81 drill | RTP, RFP, SDIS, DP, DPR |
//! | CYCLE82 drill, dwell | RTP, RFP, SDIS, DP, DPR, DTB |
//! | CYCLE83 deep hole | RTP, RFP, SDIS, DP, DPR, FDEP, FDPR, DAM, DTB, DTS, FRF, VARI |
//! | CYCLE84 rigid tap | RTP, RFP, SDIS, DP, DPR, DTB, SDAC, MPIT, PIT, POSS, SST, SST1 |
//! | CYCLE840 tap, compensating chuck | RTP, RFP, SDIS, DP, DPR, DTB, SDR, SDAC, ENC, MPIT, PIT |
//! | CYCLE85 bore, fed out | RTP, RFP, SDIS, DP, DPR, DTB, FFR, RFF |
//! | CYCLE86 bore, spindle stop | RTP, RFP, SDIS, DP, DPR, DTB, SDIR, RPA, RPO, RPAP, POSS |
//!
//! RTP is the retract plane, RFP the reference (top) plane, SDIS the safety distance (the R
//! plane is RFP + SDIS), DP the final depth (or DPR below RFP), along the plane's normal. Each
//! cycle rapids to RFP + SDIS, works to DP and leaves to RTP: with one rapid (81, 82, 83, 86), or
//! fed back to RFP + SDIS first (84 and 840 with the spindle reversed, 85 at RFF). CYCLE83's
//! pecks are FDEP (or FDPR below RFP) first, then DAM each; VARI=1 rapids back to RFP + SDIS
//! between pecks (dwell DTS there), VARI=0 backs off to break the chip. Both come back down to
//! (or back off) 0.254 mm (0.010 in) above the last depth, the clearance of G83/G73, so a
//! CYCLE83 reads as the G83/G73 Talas posts for other controls; a real Sinumerik takes its own
//! anticipation and retraction distances. CYCLE86's lift-off (RPA, RPO, RPAP) and position
//! lists with `HOLES1`/`HOLES2` are refused by name.

use glam::DVec2;

use super::cycles::{Cursor, PECK_CLEARANCE_INCH, PECK_CLEARANCE_MM};
use super::motion::{dwell, total_offset};
use super::siemens_call::{Kind, SiemensCycle};
use super::state::{Block, State};
use super::{GcodeError, InterpretOptions, Program};

/// Is `name` (upper case, without arguments) a drilling cycle this module reads?
pub(super) fn is_cycle(name: &str) -> bool {
    matches!(
        name,
        "CYCLE81" | "CYCLE82" | "CYCLE83" | "CYCLE84" | "CYCLE840" | "CYCLE85" | "CYCLE86"
    )
}

/// Read `CYCLE8x(args)`: `args` is the text between the brackets, `col` the name's column.
///
/// # Errors
/// A [`GcodeError`] at the call for a missing bracket, a parameter that is not a number, a
/// missing RTP, RFP or depth, or a CYCLE86 lift-off.
pub(super) fn parse(
    b: &Block,
    name: &str,
    args: Option<&str>,
    col: usize,
) -> Result<SiemensCycle, GcodeError> {
    let Some(args) = args else {
        return Err(b.err(
            col,
            format!("{name} needs its parameters in brackets: {name}(RTP, RFP, SDIS, DP, …)"),
        ));
    };
    let mut values: Vec<Option<f64>> = Vec::new();
    for (i, a) in args.split(',').enumerate() {
        let a = a.trim();
        if a.is_empty() {
            values.push(None);
            continue;
        }
        let v: f64 = a.parse().map_err(|_| {
            b.err(
                col,
                format!("{name}: parameter {} ({a:?}) is not a number (expressions and variables in cycle calls are not read)", i + 1),
            )
        })?;
        if !v.is_finite() {
            return Err(b.err(col, format!("{name}: parameter {} is not finite", i + 1)));
        }
        values.push(Some(v));
    }
    let at = |i: usize| values.get(i).copied().flatten();
    let need = |i: usize, what: &str| {
        at(i).ok_or_else(|| {
            b.err(
                col,
                format!("{name}: {what} (parameter {}) is missing", i + 1),
            )
        })
    };
    let rtp = need(0, "RTP, the retract plane")?;
    let rfp = need(1, "RFP, the reference plane")?;
    let sdis = at(2).unwrap_or(0.0);
    let dp = match (at(3), at(4)) {
        (Some(dp), _) => dp,
        (None, Some(dpr)) => rfp - dpr.abs(),
        (None, None) => {
            return Err(b.err(
                col,
                format!("{name}: DP or DPR, the final depth (parameter 4 or 5), is missing"),
            ));
        }
    };
    let kind = match name {
        "CYCLE81" => Kind::Drill,
        "CYCLE82" => Kind::Dwell,
        "CYCLE83" => Kind::Deep,
        "CYCLE84" | "CYCLE840" => Kind::Tap,
        "CYCLE85" => Kind::Bore,
        _ => Kind::BoreStop,
    };
    let mut c = SiemensCycle {
        name: name.to_string(),
        kind,
        rtp,
        rfp,
        sdis,
        dp,
        dtb: 0.0,
        fdep: None,
        dam: 0.0,
        dts: 0.0,
        chip_break: false,
        ffr: None,
        rff: None,
    };
    let dwell_at = |i: usize| -> Result<f64, GcodeError> {
        let v = at(i).unwrap_or(0.0);
        if v < 0.0 {
            // Negative DTB is revolutions on a Sinumerik; Talas times seconds only.
            return Err(b.err(col, format!("{name}: DTB/DTS (parameter {}) in spindle revolutions (negative) is not read; give seconds", i + 1)));
        }
        Ok(v)
    };
    match kind {
        Kind::Drill => {}
        Kind::Dwell | Kind::Tap => c.dtb = dwell_at(5)?,
        Kind::Deep => {
            c.fdep = at(5).or_else(|| at(6).map(|r| rfp - r.abs()));
            c.dam = at(7).unwrap_or(0.0).abs();
            c.dtb = dwell_at(8)?;
            c.dts = dwell_at(9)?;
            c.chip_break = at(11).unwrap_or(0.0) == 0.0;
        }
        Kind::Bore => {
            c.dtb = dwell_at(5)?;
            c.ffr = at(6);
            c.rff = at(7);
        }
        Kind::BoreStop => {
            c.dtb = dwell_at(5)?;
            if [7, 8, 9].iter().any(|&i| at(i).is_some_and(|v| v != 0.0)) {
                return Err(b.err(col, format!("{name}: the lift-off RPA, RPO, RPAP (parameters 8–10) is not read; it moves the tool sideways out of the bore")));
            }
        }
    }
    if c.sdis < 0.0 {
        return Err(b.err(
            col,
            format!("{name}: SDIS (the safety distance) must not be negative"),
        ));
    }
    if c.rfp + c.sdis < c.dp {
        return Err(b.err(
            col,
            format!(
                "{name}: the final depth DP ({}) is above RFP + SDIS ({})",
                c.dp,
                c.rfp + c.sdis
            ),
        ));
    }
    if c.rtp < c.rfp + c.sdis {
        return Err(b.err(
            col,
            format!(
                "{name}: the retract plane RTP ({}) is below RFP + SDIS ({})",
                c.rtp,
                c.rfp + c.sdis
            ),
        ));
    }
    Ok(c)
}

/// Run one call of `c` at the tool's place in the plane.
///
/// # Errors
/// A [`GcodeError`] for a cycle without a feed, with compensation on, or a tap without the
/// spindle turning.
pub(super) fn run(
    b: &Block,
    col: usize,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    c: &SiemensCycle,
) -> Result<(), GcodeError> {
    let name = c.name.as_str();
    if s.comp.side.is_some() {
        return Err(b.err(
            col,
            format!("{name}: drilling cycles cannot run with cutter compensation on"),
        ));
    }
    let feed = s.feed.filter(|f| *f > 0.0);
    if feed.is_none() && !(c.kind == Kind::Bore && c.ffr.is_some() && c.rff.is_some()) {
        return Err(b.err(
            col,
            format!("{name} cannot feed with zero feed rate (no F word set)"),
        ));
    }
    if matches!(c.kind, Kind::Tap | Kind::BoreStop)
        && (s.spindle_dir == 0.0 || s.spindle_speed == 0.0)
    {
        return Err(b.err(col, format!("{name}: the spindle is not turning")));
    }
    let scale = if s.inch {
        crate::units::MM_PER_INCH
    } else {
        1.0
    };
    let offset = total_offset(s);
    let (iu, iv, _) = s.plane.axes();
    let here = s.pos.xyz;
    let prog = |i: usize| {
        (here.to_array().get(i).copied().unwrap_or(0.0)
            - offset.to_array().get(i).copied().unwrap_or(0.0))
            / scale
    };
    let uv = DVec2::new(prog(iu), prog(iv));
    let cur = Cursor {
        b,
        opts,
        scale,
        offset,
        rotary: s.pos,
    };
    let r = c.rfp + c.sdis;
    let line = b.line;
    cur.go(s, out, true, uv, r)?;
    match c.kind {
        Kind::Drill | Kind::Dwell => {
            cur.go(s, out, false, uv, c.dp)?;
            if c.dtb > 0.0 {
                dwell(s, out, line, c.dtb);
            }
        }
        Kind::Deep => {
            let clearance = if s.inch {
                PECK_CLEARANCE_INCH
            } else {
                PECK_CLEARANCE_MM
            };
            let mut depth = c.fdep.unwrap_or(c.dp);
            while depth > c.dp {
                cur.go(s, out, false, uv, depth)?;
                if !c.chip_break {
                    cur.go(s, out, true, uv, r)?;
                    if c.dts > 0.0 {
                        dwell(s, out, line, c.dts);
                    }
                }
                cur.go(s, out, true, uv, depth + clearance)?;
                if c.dam <= 0.0 {
                    break;
                }
                depth -= c.dam;
            }
            cur.go(s, out, false, uv, c.dp)?;
            if c.dtb > 0.0 {
                dwell(s, out, line, c.dtb);
            }
        }
        Kind::Tap => {
            cur.go(s, out, false, uv, c.dp)?;
            if c.dtb > 0.0 {
                dwell(s, out, line, c.dtb);
            }
            let turning = s.spindle_dir;
            s.spindle_dir = -turning;
            let back = cur.go(s, out, false, uv, r);
            s.spindle_dir = turning;
            back?;
        }
        Kind::Bore => {
            let modal = s.feed;
            s.feed = c.ffr.or(modal);
            let down = cur.go(s, out, false, uv, c.dp);
            if down.is_ok() && c.dtb > 0.0 {
                dwell(s, out, line, c.dtb);
            }
            s.feed = c.rff.or(modal);
            let up = down.and_then(|()| cur.go(s, out, false, uv, r));
            s.feed = modal;
            up?;
        }
        Kind::BoreStop => {
            cur.go(s, out, false, uv, c.dp)?;
            if c.dtb > 0.0 {
                dwell(s, out, line, c.dtb);
            }
            // Out with the spindle stopped, one rapid through RFP + SDIS to RTP.
            let turning = s.spindle_dir;
            s.spindle_dir = 0.0;
            let up = cur.go(s, out, true, uv, c.rtp);
            s.spindle_dir = turning;
            up?;
        }
    }
    if matches!(c.kind, Kind::Tap | Kind::Bore) && c.rtp > r
        || matches!(c.kind, Kind::Drill | Kind::Dwell | Kind::Deep)
    {
        cur.go(s, out, true, uv, c.rtp)?;
    }
    Ok(())
}
