//! Canned cycles G73, G74, G81–G86, G89, expanded into traverses, feeds and dwells exactly as
//! LinuxCNC's interpreter expands them (`interp_cycles.cc`), in any of the three planes (the
//! cycle axis is the plane's normal: Z in G17, Y in G18, X in G19).
//!
//! One cycle block, for each of its `L` repeats (default 1):
//! 1. if the tool is below the R plane, rapid up to it first (once);
//! 2. rapid to the hole in the plane (at the tool's height on the first repeat, at the
//!    clearance height after that), then down to R;
//! 3. the cycle's own moves, from R to the bottom and back to the clearance height: R (G99,
//!    the default as in LinuxCNC) or the height the cycle started at (G98, the "initial
//!    level" kept from the first cycle block after another motion mode).
//!
//! | cycle | down | at the bottom | out |
//! |---|---|---|---|
//! | G81 drill | feed | | rapid |
//! | G82 drill, dwell | feed | dwell P s | rapid |
//! | G83 peck | feed by Q, rapid back to R, rapid down to 0.254 mm (0.010 in) above the last depth, repeat | | rapid |
//! | G73 chip break | feed by Q, rapid back up 0.254 mm (0.010 in), repeat | | rapid |
//! | G84 right-hand tap (M3) | feed | spindle reversed, dwell P | feed, spindle forward again |
//! | G74 left-hand tap (M4) | feed | spindle reversed, dwell P | feed, spindle reversed back |
//! | G85 bore | feed | | feed to R, rapid |
//! | G86 bore | feed | dwell P, spindle stop | rapid, spindle restarts |
//! | G89 bore, dwell | feed | dwell P | feed |
//!
//! In G90 the X Y (plane) words, R and the depth word are positions; in G91 the plane words
//! are increments per repeat, R is an increment from the initial level and the depth word an
//! increment from R. A block in a cycle mode that has plane words repeats the cycle at the new
//! position; R, the depth, P and Q carry over from the last cycle block. G80 or any other motion
//! mode ends the cycle. Cycles need a feed rate, units-per-minute feed (not G93) and cutter
//! compensation off; they do not move rotary axes.

use glam::{DVec2, DVec3};

use super::block::{CyclePhase, CycleStep, Joints};
use super::motion::{dwell, emit_line, total_offset};
use super::state::{Block, Cycle, Motion, State, u32_word};
use super::{GcodeError, InterpretOptions, Program};

/// LinuxCNC's `G83_RAPID_DELTA` (0.010 in), in the program's units.
pub(super) const PECK_CLEARANCE_INCH: f64 = 0.010;
pub(super) const PECK_CLEARANCE_MM: f64 = 0.254;

/// The place of one move of a cycle: plane coordinates and height, program units.
pub(super) struct Cursor<'a> {
    pub(super) b: &'a Block,
    pub(super) opts: &'a InterpretOptions,
    pub(super) scale: f64,
    pub(super) offset: DVec3,
    pub(super) rotary: Joints,
}

impl Cursor<'_> {
    pub(super) fn go(
        &self,
        s: &mut State,
        out: &mut Program,
        rapid: bool,
        uv: DVec2,
        w: f64,
    ) -> Result<(), GcodeError> {
        let program = s.plane.join(uv, w);
        let end = Joints {
            xyz: program * self.scale + self.offset,
            ..self.rotary
        };
        let m = if rapid { Motion::Rapid } else { Motion::Linear };
        emit_line(self.b, s, self.opts, out, m, end)
    }
}

/// The words a cycle block gives, resolved against what earlier cycle blocks left.
struct Words {
    r: f64,
    depth: f64,
    repeats: u32,
    p: f64,
    q: f64,
}

fn words(
    b: &Block,
    s: &State,
    cycle: Cycle,
    col: usize,
    same: bool,
    p_ms: bool,
) -> Result<Words, GcodeError> {
    let name = cycle.name();
    let (_, _, iw) = s.plane.axes();
    let lw = ['X', 'Y', 'Z'].get(iw).copied().unwrap_or('Z');
    let r = match b.get('R') {
        Some((v, _)) => v,
        None if same => s.cycle.r,
        None => return Err(b.err(col, format!("{name}: R (the retract plane) is missing"))),
    };
    let repeats = match b.get('L') {
        Some((l, lc)) => u32_word(l)
            .filter(|l| (1..=100_000).contains(l))
            .ok_or_else(|| b.err(lc, "L (cycle repeats) must be a positive integer"))?,
        None => 1,
    };
    if !same && b.get(lw).is_none() {
        return Err(b.err(
            col,
            format!("{name}: {lw} (the bottom of the cycle) is missing"),
        ));
    }
    let depth = b.get(lw).map_or(s.cycle.depth, |(v, _)| v);
    let mut p = s.cycle.p;
    if let Some((v, pc)) = b.get('P') {
        if !(v >= 0.0) {
            return Err(b.err(pc, "P (dwell seconds) must not be negative"));
        }
        p = if p_ms { v / 1000.0 } else { v };
    } else if cycle.needs_dwell() && !same {
        return Err(b.err(col, format!("{name}: P (the dwell time, s) is missing")));
    }
    let mut q = s.cycle.q;
    if let Some((v, qc)) = b.get('Q') {
        if !(v > 0.0) {
            return Err(b.err(qc, format!("{name}: Q (the peck depth) must be positive")));
        }
        q = v;
    } else if cycle.pecks() && (!same || !(q > 0.0)) {
        return Err(b.err(col, format!("{name}: Q (the peck depth) is missing")));
    }
    Ok(Words {
        r,
        depth,
        repeats,
        p,
        q,
    })
}

/// Run one cycle block. `col`: the column of the block's motion word (or its first word);
/// `same`: the cycle was already the motion mode before this block.
///
/// # Errors
/// A [`GcodeError`] for a missing R, depth, P or Q word, an R plane below the bottom, a cycle
/// in G93, with compensation on or without a feed, or a tap without the spindle turning the
/// right way.
pub(super) fn run(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    cycle: Cycle,
    col: usize,
    same: bool,
) -> Result<(), GcodeError> {
    let name = cycle.name();
    let scale = if s.inch {
        crate::units::MM_PER_INCH
    } else {
        1.0
    };
    if s.inverse_time {
        return Err(b.err(
            col,
            format!("{name}: canned cycles cannot use inverse-time feed (G93)"),
        ));
    }
    if s.comp.side.is_some() {
        return Err(b.err(
            col,
            format!("{name}: canned cycles cannot run with cutter compensation on (G41/G42)"),
        ));
    }
    if !s.feed.is_some_and(|f| f > 0.0) {
        return Err(b.err(
            col,
            format!("{name} cannot feed with zero feed rate (no F word set)"),
        ));
    }
    for l in ['A', 'B', 'C'] {
        if let Some((_, c)) = b.get(l) {
            return Err(b.err(c, format!("{l}: rotary axes cannot move in a canned cycle")));
        }
    }
    let w = words(b, s, cycle, col, same, opts.cycle_dwell_ms)?;
    match cycle {
        Cycle::G84 | Cycle::G74 if s.spindle_dir == 0.0 || s.spindle_speed == 0.0 => {
            return Err(b.err(col, format!("{name}: the spindle is not turning")));
        }
        Cycle::G84 if s.spindle_dir < 0.0 => {
            return Err(b.err(
                col,
                "G84: the spindle turns counterclockwise (M4); G84 taps with M3",
            ));
        }
        Cycle::G74 if s.spindle_dir > 0.0 => {
            return Err(b.err(
                col,
                "G74: the spindle turns clockwise (M3); G74 taps with M4",
            ));
        }
        Cycle::G86 if s.spindle_dir == 0.0 => {
            return Err(b.err(col, "G86: the spindle is not turning"));
        }
        _ => {}
    }
    let (iu, iv, iw) = s.plane.axes();
    let letter = |i: usize| ['X', 'Y', 'Z'].get(i).copied().unwrap_or('X');
    let offset = total_offset(s);
    let prog = |i: usize, m: DVec3| {
        (m.to_array().get(i).copied().unwrap_or(0.0)
            - offset.to_array().get(i).copied().unwrap_or(0.0))
            / scale
    };
    let here = s.pos.xyz;
    let current_w = prog(iw, here);
    let mut old = *s.cycle.initial.get_or_insert(current_w);
    let word = |i: usize| b.get(letter(i)).map(|(v, _)| v);
    let (mut uv, step, r, bottom) = if s.absolute {
        let uv = DVec2::new(
            word(iu).unwrap_or_else(|| prog(iu, here)),
            word(iv).unwrap_or_else(|| prog(iv, here)),
        );
        (uv, DVec2::ZERO, w.r, w.depth)
    } else {
        let step = DVec2::new(word(iu).unwrap_or(0.0), word(iv).unwrap_or(0.0));
        let r = w.r + old;
        (
            DVec2::new(prog(iu, here), prog(iv, here)),
            step,
            r,
            r + w.depth,
        )
    };
    if r < bottom {
        return Err(b.err(
            col,
            format!(
                "{name}: the R plane ({r}) is below the bottom of the cycle ({}{bottom})",
                letter(iw)
            ),
        ));
    }
    let cur = Cursor {
        b,
        opts,
        scale,
        offset,
        rotary: s.pos,
    };
    let peck_clearance = if s.inch {
        PECK_CLEARANCE_INCH
    } else {
        PECK_CLEARANCE_MM
    };
    let mut phase = Phase {
        cycle: name,
        hole: 1,
        holes: w.repeats,
        pecks: pecks(cycle, r, bottom, w.q),
        r,
        bottom,
        scale,
    };
    let mut current = current_w;
    phase.set(s, CycleStep::Position, 0, r);
    if old < r {
        let start = DVec2::new(prog(iu, here), prog(iv, here));
        cur.go(s, out, true, start, r)?;
        old = r;
        current = old;
    }
    let clear = if s.retract_r_plane { r } else { old };
    for repeat in 0..w.repeats {
        phase.hole = repeat + 1;
        phase.set(s, CycleStep::Position, 0, r);
        uv += step;
        if repeat == 0 && current > r {
            cur.go(s, out, true, uv, current)?;
            cur.go(s, out, true, uv, r)?;
        } else {
            cur.go(s, out, true, uv, clear)?;
            if clear > r {
                cur.go(s, out, true, uv, r)?;
            }
        }
        body(&cur, s, out, cycle, &w, &phase, uv, clear, peck_clearance)?;
    }
    s.cycle_phase = None;
    s.cycle.r = w.r;
    s.cycle.depth = w.depth;
    s.cycle.p = w.p;
    s.cycle.q = w.q;
    Ok(())
}

/// The number of infeeds of a cycle from `r` to `bottom` by `q` (program units).
fn pecks(cycle: Cycle, r: f64, bottom: f64, q: f64) -> u32 {
    if !cycle.pecks() || !(q > 0.0) {
        return 1;
    }
    let mut n = 1;
    let mut depth = r - q;
    while depth > bottom && n < u32::MAX {
        n += 1;
        depth -= q;
    }
    n
}

/// The phase of the cycle being emitted, set on the state before each of its moves.
struct Phase {
    cycle: &'static str,
    hole: u32,
    holes: u32,
    pecks: u32,
    /// R plane and bottom along the cycle axis, program units.
    r: f64,
    bottom: f64,
    /// mm per program unit.
    scale: f64,
}

impl Phase {
    /// Set the phase for the next moves: `peck` (0 while positioning) reaching `to`.
    fn set(&self, s: &mut State, step: CycleStep, peck: u32, to: f64) {
        s.cycle_phase = Some(CyclePhase {
            cycle: self.cycle,
            hole: self.hole,
            holes: self.holes,
            peck,
            pecks: self.pecks,
            step,
            depth_mm: (self.r - to) * self.scale,
            bottom_mm: (self.r - self.bottom) * self.scale,
            dwell_s: 0.0,
        });
    }

    /// Dwell `seconds` at the bottom, shown as the cycle's dwell phase; then the way out.
    fn dwell_at_bottom(&self, s: &mut State, out: &mut Program, line: usize, seconds: f64) {
        self.set(s, CycleStep::Dwell, self.pecks, self.bottom);
        if let Some(p) = s.cycle_phase.as_mut() {
            p.dwell_s = seconds;
        }
        dwell(s, out, line, seconds);
        self.set(s, CycleStep::Retract, self.pecks, self.bottom);
    }
}

#[allow(clippy::too_many_arguments)]
fn body(
    cur: &Cursor,
    s: &mut State,
    out: &mut Program,
    cycle: Cycle,
    w: &Words,
    phase: &Phase,
    uv: DVec2,
    clear: f64,
    peck_clearance: f64,
) -> Result<(), GcodeError> {
    let line = cur.b.line;
    let (r, bottom) = (phase.r, phase.bottom);
    let last = phase.pecks;
    // Down to the bottom (the last infeed), and the way out after it.
    let down = |s: &mut State, out: &mut Program| {
        phase.set(s, CycleStep::Feed, last, bottom);
        cur.go(s, out, false, uv, bottom)?;
        phase.set(s, CycleStep::Retract, last, bottom);
        Ok::<(), GcodeError>(())
    };
    match cycle {
        Cycle::G81 => {
            down(s, out)?;
            cur.go(s, out, true, uv, clear)
        }
        Cycle::G82 => {
            down(s, out)?;
            if w.p > 0.0 {
                phase.dwell_at_bottom(s, out, line, w.p);
            }
            cur.go(s, out, true, uv, clear)
        }
        Cycle::G83 | Cycle::G73 => {
            let mut depth = r - w.q;
            let mut k = 1;
            while depth > bottom {
                phase.set(s, CycleStep::Feed, k, depth);
                cur.go(s, out, false, uv, depth)?;
                phase.set(s, CycleStep::Retract, k, depth);
                if cycle == Cycle::G83 {
                    cur.go(s, out, true, uv, r)?;
                    phase.set(s, CycleStep::Reenter, k, depth);
                }
                cur.go(s, out, true, uv, depth + peck_clearance)?;
                depth -= w.q;
                k += 1;
            }
            down(s, out)?;
            cur.go(s, out, true, uv, clear)
        }
        Cycle::G84 | Cycle::G74 => {
            down(s, out)?;
            let turning = s.spindle_dir;
            s.spindle_dir = -turning;
            if w.p > 0.0 {
                phase.dwell_at_bottom(s, out, line, w.p);
            }
            let back = cur.go(s, out, false, uv, clear);
            s.spindle_dir = turning;
            back
        }
        Cycle::G85 => {
            down(s, out)?;
            cur.go(s, out, false, uv, r)?;
            cur.go(s, out, true, uv, clear)
        }
        Cycle::G86 => {
            down(s, out)?;
            if w.p > 0.0 {
                phase.dwell_at_bottom(s, out, line, w.p);
            }
            let turning = s.spindle_dir;
            s.spindle_dir = 0.0;
            let back = cur.go(s, out, true, uv, clear);
            s.spindle_dir = turning;
            back
        }
        Cycle::G89 => {
            down(s, out)?;
            if w.p > 0.0 {
                phase.dwell_at_bottom(s, out, line, w.p);
            }
            cur.go(s, out, false, uv, clear)
        }
    }
}
