//! Heidenhain TNC drilling cycles in ISO programs: a cycle is defined by `G200`…`G209` with its
//! Q parameters (`G200 Q200=2 Q201=-15 Q206=150 Q202=5 Q210=0 Q203=0 Q204=50 Q211=0`) and run
//! by a call: `G79` (at the tool's position), `M99` (at the end point of its block) or `M89`
//! (modal: at the end of every later block that moves an axis, until `M99` or a new
//! definition).
//!
//! The parameters follow the TNC 320/426/430/640 user manuals for ISO programming ("Cycles for
//! drilling, tapping and thread milling"; e.g. cycle 209's parameter list on page 238 of the
//! TNC 320 manual, <https://www.manualsdir.com/manuals/798411/heidenhain-tnc-320-340-55x-03.html?page=238>):
//! Q200 set-up clearance (above Q203), Q201 depth (incremental from Q203, negative), Q203 the
//! workpiece surface coordinate (absolute), Q204 the 2nd set-up clearance (above Q203), Q206
//! the plunging feed, Q202 the plunging depth per cut (from the surface), Q210 the dwell at the
//! top, Q211 the dwell at the bottom (s), Q208 the retraction feed (0: the plunging feed; `FMAX`
//! a rapid), Q212 the decrement per cut, Q205 the least plunging depth, Q213 the chip breaks
//! before a full retract, Q256 the back-off of a chip break, Q258 the advanced stop distance
//! (how far above the last depth a rapid comes back down), Q239 the thread pitch (its sign the
//! hand), Q257 the depth per chip break of cycle 209, Q214 cycle 202's lift-off direction,
//! Q336 a spindle angle.
//!
//! | cycle | down | after a cut | at the bottom | out |
//! |---|---|---|---|---|
//! | 200 drilling | feed Q206 by Q202 | rapid to Q200, dwell Q210, rapid to Q200 above the depth | dwell Q211 | rapid |
//! | 201 reaming | feed Q206 | | dwell Q211 | feed Q208 to Q200, rapid |
//! | 202 boring | feed Q206 | | dwell Q211, spindle stop | feed Q208 to Q200, rapid, spindle on |
//! | 203 universal drilling | feed Q206 by Q202 − k·Q212 (≥ Q205) | Q213 times a rapid back-off Q256, then rapid to Q200, dwell Q210, rapid to Q200 above the depth | dwell Q211 | feed Q208 to Q200, rapid |
//! | 205 universal pecking | feed Q206 by Q202 − k·Q212 (≥ Q205) | rapid to Q200, rapid to Q258 above the depth | dwell Q211 | rapid |
//! | 207 rigid tapping | feed pitch × S | | spindle reversed | feed to Q200, spindle back, rapid |
//! | 209 tapping with chip breaking | as 207, by Q257 | spindle reversed, back Q256 (0: out to Q200), spindle back | spindle reversed | feed to Q200, rapid |
//!
//! Every cycle first rapids along the tool axis to Q200 above the surface and ends at the 2nd
//! set-up clearance (Q204, or Q200 when that is higher); a retract at `FMAX` goes there in one
//! rapid. What is not read is refused by name: a parameter a cycle does not have, cycle 205's
//! chip breaking inside a cut (Q257) and deepened start (Q379), differing advanced stop
//! distances (Q258 ≠ Q259), cycle 202's lift-off (Q214 ≠ 0), a positive depth.

use glam::DVec2;

use super::cycles::Cursor;
use super::heidenhain_call::HeidenhainCycle;
use super::motion::{dwell, total_offset};
use super::state::{Block, State};
use super::{GcodeError, InterpretOptions, Program};

/// The cycles this module reads (G code × 10).
const DEFINITIONS: [i32; 7] = [2000, 2010, 2020, 2030, 2050, 2070, 2090];

/// Is G code `code` (× 10) a cycle definition this module reads?
pub(super) fn is_definition(code: i32) -> bool {
    DEFINITIONS.contains(&code)
}

/// Is keyword `k` a Q parameter assignment (`Q200=2`) taken out of the line by
/// [`take_q_assignments`]?
pub(super) fn is_q_assignment(k: &str) -> bool {
    k.strip_prefix('Q')
        .and_then(|r| r.split_once('='))
        .is_some_and(|(n, _)| !n.is_empty() && n.chars().all(|c| c.is_ascii_digit()))
}

/// Take the Q parameter assignments (`Q200=2`, `Q201 = -15`, `Q208=FMAX`) out of one block's
/// text: the text with them blanked (columns kept) and each as a keyword `Q200=2` with its
/// 1-based column. A `;` or `(` ends the search (a comment).
pub(super) fn take_q_assignments(text: &str) -> (String, Vec<(String, usize)>) {
    let mut chars: Vec<char> = text.chars().collect();
    let mut found = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars.get(i).copied().unwrap_or(' ');
        if c == ';' || c == '(' {
            break;
        }
        let starts = (c == 'Q' || c == 'q')
            && i.checked_sub(1)
                .and_then(|p| chars.get(p))
                .is_none_or(|p| !p.is_ascii_alphanumeric());
        if !starts {
            i += 1;
            continue;
        }
        let mut j = i + 1;
        let digits = j;
        while chars.get(j).is_some_and(char::is_ascii_digit) {
            j += 1;
        }
        let number: String = chars.get(digits..j).unwrap_or_default().iter().collect();
        while chars.get(j).is_some_and(|c| c.is_whitespace()) {
            j += 1;
        }
        if number.is_empty() || chars.get(j) != Some(&'=') {
            i += 1;
            continue;
        }
        j += 1;
        while chars.get(j).is_some_and(|c| c.is_whitespace()) {
            j += 1;
        }
        let v0 = j;
        while chars
            .get(j)
            .is_some_and(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
        {
            j += 1;
        }
        let value: String = chars.get(v0..j).unwrap_or_default().iter().collect();
        found.push((format!("Q{number}={}", value.to_ascii_uppercase()), i + 1));
        for slot in chars.get_mut(i..j).unwrap_or_default() {
            *slot = ' ';
        }
        i = j;
    }
    (chars.into_iter().collect(), found)
}

/// The Q parameters each cycle reads: required, then optional (default 0).
fn parameters(number: u32) -> (&'static [u32], &'static [u32]) {
    match number {
        200 => (&[200, 201, 206, 202, 203, 204], &[210, 211]),
        201 => (&[200, 201, 206, 203, 204], &[211, 208]),
        202 => (&[200, 201, 206, 203, 204], &[211, 208, 214, 336]),
        203 => (
            &[200, 201, 206, 202, 203, 204],
            &[210, 212, 213, 205, 211, 208, 256],
        ),
        205 => (
            &[200, 201, 206, 202, 203, 204],
            &[212, 205, 258, 259, 257, 256, 211, 379, 253, 208],
        ),
        _ => (&[200, 201, 239, 203, 204], &[257, 256, 336, 403]),
    }
}

/// What a Q parameter is, for errors.
fn meaning(q: u32) -> &'static str {
    match q {
        200 => "the set-up clearance",
        201 => "the depth",
        202 => "the plunging depth",
        203 => "the workpiece surface coordinate",
        204 => "the 2nd set-up clearance",
        206 => "the plunging feed",
        239 => "the thread pitch",
        _ => "a parameter",
    }
}

/// Read a cycle definition `G2xx Q…=…` (`code` × 10 at column `col`).
fn define(b: &Block, code: i32, col: usize) -> Result<HeidenhainCycle, GcodeError> {
    let number = u32::try_from(code / 10).unwrap_or(200);
    let name = format!("G{number}");
    let (required, optional) = parameters(number);
    let mut q: Vec<(u32, f64)> = Vec::new();
    for (k, kc) in &b.keywords {
        let Some((n, v)) = k.strip_prefix('Q').and_then(|r| r.split_once('=')) else {
            continue;
        };
        let n: u32 = n.parse().unwrap_or(0);
        if !required.contains(&n) && !optional.contains(&n) {
            return Err(b.err(
                *kc,
                format!("{name}: Q{n} is not a parameter of cycle {number} that Talas reads"),
            ));
        }
        let value = if v == "FMAX" && matches!(n, 206 | 208 | 253) {
            f64::INFINITY
        } else {
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    b.err(
                        *kc,
                        format!("{name}: Q{n}={v} is not a number (FMAX only for a feed)"),
                    )
                })?
        };
        if q.iter().any(|(m, _)| *m == n) {
            return Err(b.err(*kc, format!("{name}: Q{n} is given twice")));
        }
        q.push((n, value));
    }
    let c = HeidenhainCycle { number, q };
    for &n in required {
        if c.get(n).is_none() {
            return Err(b.err(col, format!("{name}: Q{n} ({}) is missing", meaning(n))));
        }
    }
    check(b, &c, col)?;
    Ok(c)
}

/// The values' own bounds.
fn check(b: &Block, c: &HeidenhainCycle, col: usize) -> Result<(), GcodeError> {
    let name = c.name();
    let q = |n: u32| c.get(n).unwrap_or(0.0);
    let bad = |m: String| Err(b.err(col, format!("{name}: {m}")));
    if !(q(201) < 0.0) {
        return bad(format!(
            "Q201 (the depth) must be negative (into the material), got {}",
            q(201)
        ));
    }
    if q(200) < 0.0 || q(204) < 0.0 {
        return bad("Q200 and Q204 (the set-up clearances) must not be negative".into());
    }
    if c.get(206).is_some_and(|f| !(f > 0.0)) {
        return bad("Q206 (the plunging feed) must be positive".into());
    }
    if c.get(208).is_some_and(|f| f < 0.0) {
        return bad("Q208 (the retraction feed) must not be negative".into());
    }
    if c.get(202).is_some_and(|p| !(p > 0.0)) {
        return bad("Q202 (the plunging depth) must be positive".into());
    }
    if [210, 211].iter().any(|&n| q(n) < 0.0) {
        return bad("Q210 and Q211 (dwells, s) must not be negative".into());
    }
    if [212, 205, 256, 257, 258, 259].iter().any(|&n| q(n) < 0.0) {
        return bad("Q205, Q212, Q256, Q257, Q258 and Q259 must not be negative".into());
    }
    if c.get(239).is_some_and(|p| p == 0.0) {
        return bad("Q239 (the thread pitch) must not be 0".into());
    }
    match c.number {
        202 if q(214) != 0.0 => bad(
            "the lift-off Q214 is not read (it moves the tool sideways out of the bore); give Q214=0"
                .into(),
        ),
        205 if q(257) != 0.0 || q(379) != 0.0 => {
            bad("chip breaking inside a cut (Q257) and a deepened start (Q379) are not read".into())
        }
        205 if c.get(259).is_some_and(|v| Some(v) != c.get(258)) => {
            bad("advanced stop distances that change from cut to cut (Q258 ≠ Q259) are not read".into())
        }
        _ => Ok(()),
    }
}

/// The block's cycle words: a definition (stored in the state), `M89` (modal call on), and the
/// column of a call to run after the block's motion (`G79`, `M99`, or a move under `M89`).
///
/// # Errors
/// A definition that cannot be read, Q parameters without a definition, a call with no cycle
/// defined.
pub(super) fn block(b: &Block, s: &mut State) -> Result<Option<usize>, GcodeError> {
    let mut definition = None;
    let mut call = None;
    for &(g, col) in &b.g {
        if is_definition(g) {
            if definition.is_some() {
                return Err(b.err(col, "one cycle definition per block"));
            }
            definition = Some((g, col));
        } else if g == 790 {
            call = Some(col);
        }
    }
    if let Some((g, col)) = definition {
        if call.is_some() || b.has_axis() {
            return Err(b.err(
                col,
                "a cycle definition stands in a block of its own (call it with G79 or M99)",
            ));
        }
        s.heidenhain_cycle = Some(define(b, g, col)?);
        s.heidenhain_modal = false;
    } else if let Some((_, kc)) = b.keywords.iter().find(|(k, _)| is_q_assignment(k)) {
        return Err(b.err(
            *kc,
            "Q parameters outside a cycle definition (G200…G209) are not read",
        ));
    }
    for &(m, col) in &b.m {
        match m {
            990 => {
                call = Some(col);
                s.heidenhain_modal = false;
            }
            890 => s.heidenhain_modal = true,
            _ => {}
        }
    }
    if call.is_none() && s.heidenhain_modal && b.has_axis() {
        call = Some(b.first_column());
    }
    if let Some(col) = call
        && s.heidenhain_cycle.is_none()
    {
        return Err(b.err(col, "cycle call without a cycle defined (G200…G209 first)"));
    }
    Ok(call)
}

/// The moves of one cycle at the tool's place: heights along the plane normal, program units.
struct Hole<'a> {
    cur: Cursor<'a>,
    uv: DVec2,
    line: usize,
    /// Program units to mm, for feeds.
    scale: f64,
}

impl Hole<'_> {
    /// Rapid (`feed` infinite) or feed (`Some`, program units per minute; `None` the modal
    /// feed) to height `w`.
    fn go(
        &self,
        s: &mut State,
        out: &mut Program,
        feed: Option<f64>,
        w: f64,
    ) -> Result<(), GcodeError> {
        match feed {
            Some(f) if f.is_infinite() => self.cur.go(s, out, true, self.uv, w),
            Some(f) => {
                let modal = s.feed;
                s.feed = Some(f * self.scale);
                let r = self.cur.go(s, out, false, self.uv, w);
                s.feed = modal;
                r
            }
            None => self.cur.go(s, out, false, self.uv, w),
        }
    }
    fn rapid(&self, s: &mut State, out: &mut Program, w: f64) -> Result<(), GcodeError> {
        self.cur.go(s, out, true, self.uv, w)
    }
    fn wait(&self, s: &mut State, out: &mut Program, seconds: f64) {
        if seconds > 0.0 {
            dwell(s, out, self.line, seconds);
        }
    }
}

/// Run the defined cycle once at the tool's place in the plane.
///
/// # Errors
/// A [`GcodeError`] at `col` for cutter compensation on, inverse-time feed, a tap without the
/// spindle turning, or a move the interpreter refuses.
pub(super) fn run(
    b: &Block,
    col: usize,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
) -> Result<(), GcodeError> {
    let Some(c) = s.heidenhain_cycle.clone() else {
        return Err(b.err(col, "cycle call without a cycle defined (G200…G209 first)"));
    };
    let name = c.name();
    if s.comp.side.is_some() {
        return Err(b.err(
            col,
            format!("{name}: drilling cycles cannot run with cutter compensation on"),
        ));
    }
    if s.inverse_time {
        return Err(b.err(
            col,
            format!("{name}: cycles cannot run in inverse time (G93)"),
        ));
    }
    let tapping = matches!(c.number, 207 | 209);
    if (tapping || c.number == 202) && (s.spindle_dir == 0.0 || s.spindle_speed == 0.0) {
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
    let hole = Hole {
        cur: Cursor {
            b,
            opts,
            scale,
            offset,
            rotary: s.pos,
        },
        uv: DVec2::new(prog(iu), prog(iv)),
        line: b.line,
        scale,
    };
    let q = |n: u32| c.get(n).unwrap_or(0.0);
    let top = q(203);
    let r = top + q(200);
    let clear = top + q(204).max(q(200));
    let bottom = top + q(201);
    let plunge = Some(q(206));
    // Q208 = 0 retracts at the plunging feed.
    let retract = c.get(208).filter(|f| *f > 0.0).or(plunge);
    hole.rapid(s, out, r)?;
    match c.number {
        200 | 203 | 205 => {
            let breaks = if c.number == 203 { q(213) } else { 0.0 };
            let back = c.get(256).unwrap_or(0.2);
            let advance = match c.number {
                205 => c.get(258).unwrap_or(0.2),
                _ => q(200),
            };
            let (first, decrement, least) = (q(202), q(212), q(205));
            let mut depth = top;
            let mut cuts = 0.0f64;
            let mut broken = 0.0;
            loop {
                let step = if c.number == 200 {
                    first
                } else {
                    // Smaller by Q212 each cut, never below Q205 (nor a thousandth of Q202).
                    (first - cuts * decrement).max(least).max(first * 1e-3)
                };
                let next = (depth - step).max(bottom);
                hole.go(s, out, plunge, next)?;
                depth = next;
                cuts += 1.0;
                if depth <= bottom {
                    break;
                }
                if broken < breaks {
                    hole.rapid(s, out, depth + back)?;
                    broken += 1.0;
                } else {
                    hole.rapid(s, out, r)?;
                    hole.wait(s, out, q(210));
                    hole.rapid(s, out, depth + advance)?;
                    broken = 0.0;
                }
            }
            hole.wait(s, out, q(211));
            if c.number == 203 && !retract.is_some_and(f64::is_infinite) {
                hole.go(s, out, retract, r)?;
            }
            hole.rapid(s, out, clear)?;
        }
        201 => {
            hole.go(s, out, plunge, bottom)?;
            hole.wait(s, out, q(211));
            if retract.is_some_and(f64::is_infinite) {
                hole.rapid(s, out, clear)?;
            } else {
                hole.go(s, out, retract, r)?;
                if clear > r {
                    hole.rapid(s, out, clear)?;
                }
            }
        }
        202 => {
            hole.go(s, out, plunge, bottom)?;
            hole.wait(s, out, q(211));
            let turning = s.spindle_dir;
            s.spindle_dir = 0.0;
            let up = if retract.is_some_and(f64::is_infinite) {
                hole.rapid(s, out, clear)
            } else {
                hole.go(s, out, retract, r).and_then(|()| {
                    if clear > r {
                        hole.rapid(s, out, clear)
                    } else {
                        Ok(())
                    }
                })
            };
            s.spindle_dir = turning;
            up?;
        }
        _ => tap(&hole, s, out, &c, (top, r, bottom, clear))?,
    }
    Ok(())
}

/// Cycles 207 and 209: synchronised feed (pitch × speed), reversed out.
fn tap(
    hole: &Hole<'_>,
    s: &mut State,
    out: &mut Program,
    c: &HeidenhainCycle,
    (top, r, bottom, clear): (f64, f64, f64, f64),
) -> Result<(), GcodeError> {
    let q = |n: u32| c.get(n).unwrap_or(0.0);
    let pitch = q(239);
    let feed = Some(pitch.abs() * s.spindle_speed);
    let turning = s.spindle_dir;
    // The hand of the thread turns the spindle in (Q239 > 0: clockwise).
    let inward = pitch.signum();
    let step = if c.number == 209 { q(257) } else { 0.0 };
    let back = q(256);
    let result = (|| {
        // Cuts of Q257 counted from the surface, as the drilling cycles count Q202.
        let mut depth = r.min(top);
        loop {
            let next = if step > 0.0 {
                (depth - step).max(bottom)
            } else {
                bottom
            };
            s.spindle_dir = inward;
            hole.go(s, out, feed, next)?;
            depth = next;
            if depth <= bottom {
                break;
            }
            s.spindle_dir = -inward;
            if back > 0.0 {
                hole.go(s, out, feed, (depth + back).min(r))?;
            } else {
                hole.go(s, out, feed, r)?;
            }
        }
        s.spindle_dir = -inward;
        hole.go(s, out, feed, r)
    })();
    s.spindle_dir = turning;
    result?;
    if clear > r {
        hole.rapid(s, out, clear)?;
    }
    Ok(())
}
