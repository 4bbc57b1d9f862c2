//! The virtual controller: modal state and the execution of one block after another.

use super::arc::Plane;
use super::compensation;
use super::cycles;
use super::expr::ParamSource;
use super::lexer::{ParsedLine, Target, Word, parse_line};
use super::modal::{GCodes, MotionCode, classify};
use super::motion::{arc_words, dwell, emit_arc, emit_line, g28, target};
use super::offsets;
use super::siemens;
use super::siemens_call::SiemensCycle;
use super::state::{Block, Cycle, Motion, Side, State, u32_word};
use super::{GcodeError, InterpretOptions, Program, Syntax};
use crate::diagnostics::Diagnostic;
use crate::units::MM_PER_INCH;

/// Letters accepted besides G and M (which are collected separately).
const LETTERS: &str = "ABCDFHIJKLNOPQRSTXYZ";

/// The parameters as expressions read them: the store, and the controller's own values.
pub(super) struct View<'a> {
    pub(super) s: &'a State,
}

impl ParamSource for View<'_> {
    fn numbered(&self, index: usize) -> Result<f64, String> {
        super::sysparams::numbered(self.s, index)
    }
    fn named(&self, name: &str) -> Option<f64> {
        super::sysparams::named(self.s, name).or_else(|| self.s.params.named(name))
    }
}

/// Heidenhain's program frame `%NAME G71 *` (start) and `N99999999 %NAME G71 *` (end): the
/// unit code in it (`Some(true)` for G70, inch) and the line without the frame; other
/// syntaxes keep the line as it is.
pub(super) fn program_frame(raw: &str, syntax: Syntax) -> (&str, Option<bool>) {
    if syntax != Syntax::HeidenhainIso {
        return (raw, None);
    }
    let Some(at) = raw.find('%') else {
        return (raw, None);
    };
    let frame = raw.get(at..).unwrap_or("").to_ascii_uppercase();
    let words: Vec<&str> = frame
        .split(|c: char| c.is_whitespace() || c == '*')
        .collect();
    let inch = if words.contains(&"G70") {
        Some(true)
    } else if words.contains(&"G71") {
        Some(false)
    } else {
        None
    };
    (raw.get(..at).unwrap_or(""), inch)
}

/// The blocks of one line: one, or with a block-end character (`;` in the thesis's samples,
/// Heidenhain's `*`), one per separated piece (columns stay those of the whole line).
pub(super) fn blocks_of_line(
    raw: &str,
    line: usize,
    separator: Option<char>,
    syntax: Syntax,
) -> Result<Vec<ParsedLine>, GcodeError> {
    // Heidenhain's `Q200=2` cycle parameters are taken out as keywords before the lexer.
    let parse = |piece: &str| {
        if syntax != Syntax::HeidenhainIso {
            return parse_line(piece, line, false);
        }
        let (rest, plane) = super::workplane::take_plane(piece);
        let (rest, q) = super::heidenhain::take_q_assignments(&rest);
        let mut parsed = parse_line(&rest, line, false)?;
        parsed.keywords.extend(q);
        parsed.keywords.extend(plane);
        parsed.keywords.sort_by_key(|k| k.1);
        Ok(parsed)
    };
    let Some(separator) = separator else {
        return Ok(vec![parse(raw)?]);
    };
    let mut out = Vec::new();
    let mut offset = 0usize;
    for piece in raw.split(separator) {
        let mut parsed = parse(piece).map_err(|mut e: GcodeError| {
            e.column += offset;
            e
        })?;
        parsed.shift(offset);
        out.push(parsed);
        offset += piece.chars().count() + 1;
    }
    Ok(out)
}

/// What a block did besides its motion.
#[derive(Clone, Debug, Default)]
pub(super) struct Ran {
    /// The block ends the program (M2, M30).
    pub(super) ends: bool,
    /// Its M codes (× 10).
    pub(super) m: Vec<i32>,
}

/// Evaluate one parsed block against the parameters, set its parameters, and execute it.
/// O-word lines are the caller's.
///
/// # Errors
/// The block's [`GcodeError`].
pub(super) fn run_block(
    parsed: &ParsedLine,
    line: usize,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
) -> Result<Ran, GcodeError> {
    s.line = line;
    let evaluated = parsed.evaluate(line, &View { s })?;
    for (target, value, column) in evaluated.assignments {
        match target {
            Target::Numbered(i) => s.params.set(i, value).map_err(|message| GcodeError {
                line,
                column,
                message,
            })?,
            Target::Named(n) => {
                if super::sysparams::named(s, &n).is_some() {
                    return Err(GcodeError {
                        line,
                        column,
                        message: format!("#<{n}> is read-only (set by the controller)"),
                    });
                }
                s.params.set_named(&n, value);
            }
        }
    }
    if evaluated.words.is_empty() && parsed.keywords.is_empty() {
        return Ok(Ran::default());
    }
    let mut block = sort_words(&evaluated.words, line, opts.syntax)?;
    block.keywords.clone_from(&parsed.keywords);
    // A cycle that stopped on an error leaves no phase on the blocks after it.
    s.cycle_phase = None;
    let ends = execute(&block, s, opts, out)?;
    Ok(Ran {
        ends,
        m: block.m.iter().map(|(m, _)| *m).collect(),
    })
}

pub(super) fn sort_words(words: &[Word], line: usize, syntax: Syntax) -> Result<Block, GcodeError> {
    let mut block = Block {
        line,
        g: Vec::new(),
        m: Vec::new(),
        keywords: Vec::new(),
        words: [None; 26],
    };
    let d_allowed = matches!(syntax, Syntax::Siemens | Syntax::Rs274);
    for w in words {
        let code = || {
            let x10 = (w.value * 10.0).round();
            ((w.value * 10.0 - x10).abs() < 1e-6 && x10.abs() < 1e6).then_some(x10 as i32)
        };
        match w.letter {
            'G' | 'M' => {
                let c = code().ok_or_else(|| {
                    block.err(w.column, format!("bad code {}{}", w.letter, w.value))
                })?;
                if w.letter == 'G' {
                    block.g.push((c, w.column));
                } else {
                    block.m.push((c, w.column));
                }
            }
            l if LETTERS.contains(l) && (l != 'D' || d_allowed) => {
                let i = (l as usize).saturating_sub('A' as usize);
                match block.words.get_mut(i) {
                    Some(Some(_)) => {
                        return Err(
                            block.err(w.column, format!("word {l} appears twice in one block"))
                        );
                    }
                    Some(slot) => *slot = Some((w.value, w.column)),
                    None => return Err(block.err(w.column, format!("unsupported word {l}"))),
                }
            }
            l => {
                return Err(block.err(
                    w.column,
                    format!(
                        "unsupported word {l}{} (not an axis or code this interpreter knows)",
                        w.value
                    ),
                ));
            }
        }
    }
    Ok(block)
}

/// Sinumerik keywords that only set messages, dynamics or compressor modes: read with a warning.
const SIEMENS_NO_GEOMETRY: &[&str] = &[
    "MSG", "CYCLE832", "SOFT", "BRISK", "FFWON", "FFWOF", "COMPCAD", "COMPCURV", "COMPOF",
    "COMPON", "FGROUP", "DIAMOF", "WAITM", "STOPRE",
];

/// Sinumerik keywords that move, turn, mirror or scale the coordinate system, or run a cycle that
/// moves the tool: refused, since ignoring them would change where the tool goes.
const SIEMENS_GEOMETRY: &[&str] = &[
    "SUPA", "TRANS", "ATRANS", "ROT", "AROT", "MIRROR", "AMIRROR", "SCALE", "ASCALE", "TRAORI2",
    "TRANSMIT", "TRACYL", "CYCLE87", "CYCLE88", "CYCLE89", "HOLES1", "HOLES2", "CYCLE801",
    "CYCLE802", "CYCLE61", "CYCLE71", "POCKET3", "POCKET4", "SLOT1", "SLOT2",
];

/// The block's keywords; returns a Sinumerik drilling cycle called on this block (not `MCALL`)
/// with its column.
fn keywords(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
) -> Result<Option<(SiemensCycle, usize)>, GcodeError> {
    let mut call = None;
    let mut mcall = None;
    for (keyword, col) in &b.keywords {
        let (name, args) = match keyword.split_once('(') {
            Some((n, a)) => (n, Some(a.strip_suffix(')').unwrap_or(a))),
            None => (keyword.as_str(), None),
        };
        match (opts.syntax, name) {
            (Syntax::Siemens, "MCALL") => mcall = Some(*col),
            (Syntax::Siemens, k) if siemens::is_cycle(k) => {
                if call.is_some() {
                    return Err(b.err(*col, format!("{k}: one cycle call per block")));
                }
                call = Some((siemens::parse(b, k, args, *col)?, *col));
            }
            (Syntax::Siemens, "TRAORI") => s.tcp = true,
            (Syntax::Siemens, "TRAFOOF") => s.tcp = false,
            (Syntax::Siemens, k) if SIEMENS_NO_GEOMETRY.contains(&k) => {
                out.diagnostics.push(Diagnostic::warning(
                    format!("line {}, column {col}", b.line),
                    format!("{k} ignored (it does not change the tool's path here)"),
                ));
            }
            (Syntax::HeidenhainIso, k) if super::heidenhain::is_q_assignment(k) => {}
            (Syntax::HeidenhainIso, k) if k.starts_with("PLANE") => {
                no_axis(b, *col, "PLANE")?;
                super::workplane::plane(b, *col, s, opts, out, k)?;
            }
            (Syntax::Siemens, "CYCLE800") => {
                no_axis(b, *col, "CYCLE800")?;
                super::workplane::cycle800(b, *col, s, opts, out, args)?;
            }
            (Syntax::Siemens, k) if SIEMENS_GEOMETRY.contains(&k) => {
                return Err(b.err(
                    *col,
                    format!(
                        "{k} is not supported: it moves or turns the coordinate system, or runs a \
                         cycle, and ignoring it would put the tool somewhere else"
                    ),
                ));
            }
            (syntax, _) => {
                return Err(b.err(
                    *col,
                    format!(
                        "unknown word {name} (not a {} keyword)",
                        syntax_name(syntax)
                    ),
                ));
            }
        }
    }
    if let Some(col) = mcall {
        // `MCALL CYCLE81(…)` calls the cycle after each following move; a bare `MCALL` ends it.
        s.modal_call = call.take().map(|(c, _)| c);
        if b.has_axis() && s.modal_call.is_some() {
            return Err(b.err(
                col,
                "MCALL with a cycle: put the positions on the blocks after it",
            ));
        }
    }
    Ok(call)
}

/// A block that sets a work plane has no axis words.
fn no_axis(b: &Block, col: usize, what: &str) -> Result<(), GcodeError> {
    if b.has_axis() {
        return Err(b.err(col, format!("{what} stands in a block without axis words")));
    }
    Ok(())
}

/// Fanuc `G68.2 X Y Z I J K` (set the plane), `G53.1` (turn the tool onto it), `G69`
/// (cancel); true when the block was one of the first two (no motion of its own follows).
fn fanuc_plane(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    scale: f64,
) -> Result<bool, GcodeError> {
    use super::workplane::{Turn, euler_zxz, orient, reset, set};
    let mut handled = false;
    for &(g, col) in &b.g {
        match g {
            690 => reset(s),
            682 => {
                let w = |l: char| b.get(l).map_or(0.0, |v| v.0);
                let origin = glam::DVec3::new(w('X'), w('Y'), w('Z')) * scale;
                let r = euler_zxz(w('I'), w('J'), w('K'));
                set(b, col, s, opts, out, r, origin, Turn::Stay, "G68.2")?;
                handled = true;
            }
            531 => {
                if b.has_axis() {
                    return Err(b.err(col, "G53.1 stands in a block without axis words"));
                }
                orient(b, col, s, opts, out, Turn::Nearest, "G53.1")?;
                handled = true;
            }
            _ => {}
        }
    }
    Ok(handled)
}

/// Units, feed mode, F, S and T, in LinuxCNC's order (before M and the other G codes).
fn settings(
    b: &Block,
    g: &GCodes,
    s: &mut State,
    opts: &InterpretOptions,
) -> Result<(), GcodeError> {
    if let Some((inch, col)) = g.inch {
        if inch != s.inch && s.comp.side.is_some() {
            return Err(b.err(col, "units cannot change with cutter compensation on"));
        }
        s.inch = inch;
    }
    if let Some((inverse, _)) = g.inverse_time {
        s.inverse_time = inverse;
    }
    let scale = if s.inch { MM_PER_INCH } else { 1.0 };
    // Sinumerik's `G4 F2` dwells 2 s and leaves the feed alone.
    // Heidenhain's `G04 F2` too.
    let siemens_dwell = matches!(opts.syntax, Syntax::Siemens | Syntax::HeidenhainIso)
        && matches!(g.non_modal, Some((40, _)));
    if let Some((f, col)) = b.get('F').filter(|_| !siemens_dwell) {
        if !(f >= 0.0) {
            return Err(b.err(col, "F must not be negative"));
        }
        s.feed = Some(if s.inverse_time { f } else { f * scale });
    }
    if let Some((v, col)) = b.get('S') {
        if !(v >= 0.0) {
            return Err(b.err(col, "S must not be negative"));
        }
        s.spindle_speed = v;
    }
    // The tool is selected before G43 reads its default H (RS274NGC order of execution).
    if let Some((t, col)) = b.get('T') {
        let t = u32_word(t).ok_or_else(|| b.err(col, "T must be a non-negative integer"))?;
        if t != 0
            && let Some(table) = &opts.tool_table
            && table.get(t).is_none()
        {
            return Err(b.err(col, format!("requested tool {t} is not in the tool table")));
        }
        s.tool = t;
    }
    Ok(())
}

/// M codes; returns (program end, stop: M0 M1 M2 M30 M60).
fn m_codes(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
) -> Result<(bool, bool), GcodeError> {
    let mut ends = false;
    let mut stops = false;
    for &(m, col) in &b.m {
        match m {
            0 | 10 | 600 => stops = true,
            30 => s.spindle_dir = 1.0,
            40 => s.spindle_dir = -1.0,
            50 => s.spindle_dir = 0.0,
            60 => {
                if s.comp.side.is_some() {
                    return Err(b.err(col, "M6 cannot change the tool with cutter compensation on"));
                }
                s.loaded_tool = s.tool;
            }
            610 => {
                let q = b.get('Q').and_then(|(q, _)| u32_word(q));
                s.loaded_tool = q.ok_or_else(|| b.err(col, "M61 needs Q, the tool number"))?;
                s.tool = s.loaded_tool;
            }
            70 | 80 => s.coolant = true,
            90 => s.coolant = false,
            20 | 300 => {
                ends = true;
                stops = true;
            }
            980 => {
                return Err(b.err(
                    col,
                    "M98 (a Fanuc subprogram call) is not supported: use o-word subroutines \
                     (o100 call)",
                ));
            }
            // Heidenhain's cycle calls: read by `heidenhain`.
            890 | 990 if opts.syntax == Syntax::HeidenhainIso => {}
            990 => out.diagnostics.push(Diagnostic::warning(
                format!("line {}, column {col}", b.line),
                "M99 (subprogram return, or repeat the main program) ignored: the program runs \
                 once",
            )),
            1280 if opts.syntax == Syntax::HeidenhainIso => s.tcp = true,
            1290 if opts.syntax == Syntax::HeidenhainIso => s.tcp = false,
            _ => out.diagnostics.push(Diagnostic::warning(
                format!("line {}, column {col}", b.line),
                format!("unknown M code M{} ignored", f64::from(m) / 10.0),
            )),
        }
    }
    Ok((ends, stops))
}

/// Plane, compensation, tool length, coordinate system, distance modes, retract mode (the
/// modal G codes after units and feed mode).
fn modal_g(
    b: &Block,
    g: &GCodes,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    scale: f64,
) -> Result<(), GcodeError> {
    if let Some((plane, col)) = g.plane {
        if plane != s.plane && s.comp.side.is_some() {
            return Err(b.err(col, "the plane cannot change with cutter compensation on"));
        }
        s.plane = plane;
    }
    if let Some((code, col)) = g.comp {
        if code == 400 {
            compensation::off(s, out, b.line)?;
        } else {
            comp_on(b, s, opts, out, code, col, scale)?;
        }
    }
    if let Some((code, col)) = g.length {
        offsets::tool_length(b, s, opts, code, col, scale)?;
    }
    if let Some((system, col)) = g.coord {
        if s.comp.side.is_some() && system != s.work_offset {
            return Err(b.err(
                col,
                "the coordinate system cannot change with cutter compensation on",
            ));
        }
        s.work_offset = system;
    }
    if let Some((absolute, _)) = g.absolute {
        s.absolute = absolute;
    }
    if let Some((absolute, _)) = g.arc_absolute {
        s.arc_absolute = absolute;
    }
    if let Some((r_plane, _)) = g.retract_r {
        s.retract_r_plane = r_plane;
    }
    Ok(())
}

/// G41/G42 (D: a tool number) and G41.1/G42.1 (D: a diameter in program units).
fn comp_on(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    code: i32,
    col: usize,
    scale: f64,
) -> Result<(), GcodeError> {
    let name = if code % 10 == 0 {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    };
    if !matches!(s.plane, Plane::Xy | Plane::Zx) {
        return Err(b.err(
            col,
            format!("{name}: cutter compensation works in G17 or G18 only"),
        ));
    }
    if s.comp.side.is_some() {
        return Err(b.err(col, format!("{name}: cutter compensation is already on")));
    }
    let mut side = if code / 10 == 41 {
        Side::Left
    } else {
        Side::Right
    };
    let diameter = if code % 10 == 1 {
        let (d, _) = b
            .get('D')
            .ok_or_else(|| b.err(col, format!("{name} needs D, the tool diameter")))?;
        d * scale
    } else {
        let number = match b.get('D') {
            Some((d, dc)) => {
                u32_word(d).ok_or_else(|| b.err(dc, format!("{name}: D must be a tool number")))?
            }
            None => 0,
        };
        let dc = b.get('D').map_or(col, |(_, c)| c);
        match offsets::tool_entry(b, s, opts, number, dc)? {
            Some((_, d)) => {
                if d == 0.0 {
                    out.diagnostics.push(Diagnostic::warning(
                        format!("line {}, column {col}", b.line),
                        format!("{name} with a tool of diameter 0: nothing is offset"),
                    ));
                }
                d
            }
            None => {
                return Err(b.err(
                    col,
                    format!(
                        "cutter radius compensation {name} needs the tool's radius: give a tool \
                         table (--tool-table) or use {name}.1 D<diameter>"
                    ),
                ));
            }
        }
    };
    let mut radius = diameter / 2.0;
    if radius < 0.0 {
        radius = -radius;
        side = if side == Side::Left {
            Side::Right
        } else {
            Side::Left
        };
    }
    s.comp.side = Some(side);
    s.comp.radius_mm = radius;
    s.comp.first_move = true;
    Ok(())
}

/// Execute one block; returns true at a program end (M2/M30).
pub(super) fn execute(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
) -> Result<bool, GcodeError> {
    let g = classify(b, opts.syntax)?;
    let call = keywords(b, s, opts, out)?;
    let heidenhain_call = if opts.syntax == Syntax::HeidenhainIso {
        super::heidenhain::block(b, s)?
    } else {
        None
    };
    if b.get('H').is_some() && !matches!(g.length, Some((430 | 434, _))) {
        return Err(b.err(b.get('H').map_or(1, |h| h.1), "H word without G43"));
    }
    settings(b, &g, s, opts)?;
    let (ends, stops) = m_codes(b, s, opts, out)?;
    if s.work_plane.is_some() {
        let moving = |m: Motion| matches!(m, Motion::Cw | Motion::Ccw | Motion::Cycle(_));
        let col = match g.motion {
            Some((MotionCode::Move(m), c)) if moving(m) => Some(c),
            None if b.has_axis() && s.motion.is_some_and(moving) => Some(b.first_column()),
            _ => heidenhain_call.or(call.as_ref().map(|c| c.1)),
        };
        let col = col.or(g.comp.filter(|c| c.0 != 400).map(|c| c.1));
        super::workplane::check_block(b, s, col)?;
    }
    let scale = if s.inch { MM_PER_INCH } else { 1.0 };
    modal_g(b, &g, s, opts, out, scale)?;
    if opts.syntax == Syntax::Rs274 && fanuc_plane(b, s, opts, out, scale)? {
        return Ok(ends);
    }
    if let Some((40, _)) = g.non_modal {
        g4(b, &g, s, out, opts.syntax)?;
    } else {
        non_modal_and_motion(b, &g, s, opts, out, scale)?;
    }
    if let Some(col) = heidenhain_call {
        super::heidenhain::run(b, col, s, opts, out)?;
    }
    if let Some((c, col)) = call {
        siemens::run(b, col, s, opts, out, &c)?;
    } else if let Some(c) = s.modal_call.clone().filter(|_| b.has_axis()) {
        siemens::run(b, b.first_column(), s, opts, out, &c)?;
    }
    if stops {
        compensation::flush(s, out, b.line)?;
    }
    Ok(ends)
}

fn g4(
    b: &Block,
    g: &GCodes,
    s: &mut State,
    out: &mut Program,
    syntax: Syntax,
) -> Result<(), GcodeError> {
    if b.has_axis() || g.motion.is_some() {
        return Err(b.err(
            b.first_column(),
            "G4 dwell cannot share a block with motion",
        ));
    }
    let word = match syntax {
        Syntax::Siemens | Syntax::HeidenhainIso => b.get('F').or_else(|| b.get('P')),
        _ => b.get('P'),
    };
    let Some((seconds, col)) = word else {
        return Err(b.err(b.first_column(), "G4 needs a P word (seconds)"));
    };
    if !(seconds >= 0.0) {
        return Err(b.err(col, "G4 P (seconds) must not be negative"));
    }
    dwell(s, out, b.line, seconds);
    Ok(())
}

/// Group 0 codes that use the axis words (G10, G28, G52, G92*, G43.1 too), then the motion.
fn non_modal_and_motion(
    b: &Block,
    g: &GCodes,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    scale: f64,
) -> Result<(), GcodeError> {
    let previous = s.motion;
    let mut cycle_run = false;
    let mut arc_run = false;
    match g.motion {
        Some((MotionCode::Move(m), _)) => s.motion = Some(m),
        Some((MotionCode::Cancel, _)) => {
            s.motion = None;
            s.cycle.initial = None;
        }
        None => {}
    }
    let axes_taken = matches!(g.non_modal, Some((100 | 280 | 520 | 920..=923, _)))
        || matches!(g.length, Some((431, _)));
    match g.non_modal {
        Some((280, col)) if s.comp.side.is_some() => {
            return Err(b.err(col, "G28 cannot be used with cutter compensation on"));
        }
        Some((280, _)) => g28(b, s, opts, out, scale)?,
        Some((100, col)) => offsets::g10(b, s, col, scale)?,
        Some((code @ (520 | 920..=923), col)) => offsets::axis_offset(b, s, code, col, scale)?,
        Some((_, col)) if !s.absolute => {
            return Err(b.err(col, "G53 is not allowed in incremental mode (G91)"));
        }
        Some((_, col)) => {
            let m = s
                .motion
                .filter(|m| matches!(m, Motion::Rapid | Motion::Linear));
            let m = m.ok_or_else(|| b.err(col, "G53 needs G0 or G1"))?;
            if s.comp.side.is_some() {
                return Err(b.err(col, "G53 cannot be used with cutter compensation on"));
            }
            let t = target(b, s, scale, true);
            emit_line(b, s, opts, out, m, t)?;
        }
        None if axes_taken => {}
        None if b.has_axis()
            || matches!(g.motion, Some((MotionCode::Move(Motion::Cycle(_)), _))) =>
        {
            let m = s.motion.ok_or_else(|| {
                b.err(
                    b.first_column(),
                    "axis words without a motion mode (G0, G1, G2, G3)",
                )
            })?;
            let col = g.motion.map_or_else(|| b.first_column(), |(_, c)| c);
            if let Motion::Cycle(c) = m {
                if !b.has_axis() {
                    return Err(b.err(col, format!("{}: all axis words are missing", c.name())));
                }
                let same = previous == Some(m);
                cycles::run(b, s, opts, out, c, col, same)?;
                cycle_run = true;
            } else {
                s.cycle.initial = None;
                let t = target(b, s, scale, false);
                match m {
                    Motion::Cw | Motion::Ccw => {
                        if s.comp.arc_not_allowed {
                            return Err(b.err(
                                col,
                                "the move just after cutter compensation is turned off (G40) \
                                 must be straight, not an arc",
                            ));
                        }
                        let ccw = m == Motion::Ccw;
                        let (centre, turns) = arc_words(b, s, scale)?;
                        if s.comp.active() {
                            compensation::arc(b, s, opts, out, ccw, t, centre, turns)?;
                        } else {
                            emit_arc(b, s, opts, out, ccw, t, centre, turns)?;
                        }
                        arc_run = true;
                    }
                    _ if s.comp.active() => {
                        compensation::straight(b, s, opts, out, m == Motion::Rapid, t)?;
                    }
                    _ => emit_line(b, s, opts, out, m, t)?,
                }
            }
        }
        None => {
            if let Some((MotionCode::Move(Motion::Cw | Motion::Ccw), col)) = g.motion {
                return Err(b.err(col, "an arc needs end point words"));
            }
            if g.motion.is_some() {
                s.cycle.initial = None;
            }
        }
    }
    check_letters(b, g, s, (arc_run, cycle_run), opts.syntax)
}

/// Words that only some codes use, refused where nothing in the block uses them.
fn check_letters(
    b: &Block,
    g: &GCodes,
    s: &State,
    (arc, cycle): (bool, bool),
    syntax: Syntax,
) -> Result<(), GcodeError> {
    let non_modal = g.non_modal.map(|(c, _)| c);
    let g10 = non_modal == Some(100);
    for l in ['I', 'J', 'K', 'R', 'P'] {
        let used = arc || (cycle && matches!(l, 'R' | 'P')) || (g10 && matches!(l, 'P' | 'R'));
        if let (Some((_, col)), false) = (b.get(l), used) {
            return Err(b.err(
                col,
                format!("{l} word used outside an arc or a canned cycle"),
            ));
        }
    }
    let pecking = matches!(s.motion, Some(Motion::Cycle(Cycle::G73 | Cycle::G83)));
    let m61 = b.m.iter().any(|(m, _)| *m == 610);
    if let (Some((_, col)), false) = (b.get('Q'), (cycle && pecking) || m61) {
        return Err(b.err(
            col,
            "Q word used outside a peck drilling cycle (G73, G83) or M61",
        ));
    }
    if let (Some((_, col)), false) = (b.get('L'), cycle || g10) {
        return Err(b.err(col, "L word used outside a canned cycle or G10"));
    }
    let comp_on = matches!(g.comp, Some((410 | 411 | 420 | 421, _)));
    // Sinumerik's D is the tool edge (T1 D1); in RS274 it belongs to G41/G42.
    if let (Some((_, col)), false) = (b.get('D'), comp_on || syntax == Syntax::Siemens) {
        return Err(b.err(col, "D word used outside G41/G42 (G41.1/G42.1)"));
    }
    Ok(())
}

pub(super) fn syntax_name(syntax: Syntax) -> &'static str {
    match syntax {
        Syntax::Rs274 => "RS274",
        Syntax::Siemens => "Sinumerik",
        Syntax::HeidenhainIso => "Heidenhain ISO",
    }
}
