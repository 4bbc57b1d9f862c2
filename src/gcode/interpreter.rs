//! The virtual controller: modal state and the execution of one block after another.

use super::block::Joints;

use super::arc::Plane;
use super::lexer::{LexedLine, Word, lex_line};
use super::motion::{emit_arc, emit_line, g28, target};
use super::{Dwell, GcodeError, InterpretOptions, Program, Syntax};
use crate::diagnostics::Diagnostic;
use crate::units::MM_PER_INCH;

/// Letters accepted besides G and M (which are collected separately).
const LETTERS: &str = "ABCFHIJKNOPRSTXYZ";
/// Motion modes (modal group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Motion {
    Rapid,
    Linear,
    Cw,
    Ccw,
}

/// The modal state of the controller.
pub(super) struct State {
    pub(super) pos: Joints,
    pub(super) motion: Option<Motion>,
    pub(super) plane: Plane,
    pub(super) inch: bool,
    pub(super) absolute: bool,
    pub(super) arc_absolute: bool,
    pub(super) inverse_time: bool,
    pub(super) feed: Option<f64>,
    pub(super) work_offset: usize,
    pub(super) tool: u32,
    pub(super) tool_length_h: Option<u32>,
    pub(super) spindle_speed: f64,
    pub(super) spindle_dir: f64,
    pub(super) coolant: bool,
    pub(super) warned_no_feed: bool,
    /// Tool-centre-point mode (G43.4, TRAORI, M128).
    pub(super) tcp: bool,
}

/// Words of one block, sorted by kind.
pub(super) struct Block {
    pub(super) line: usize,
    pub(super) g: Vec<(i32, usize)>,
    pub(super) m: Vec<(i32, usize)>,
    /// Keywords (`TRAORI`), upper case, with their columns.
    pub(super) keywords: Vec<(String, usize)>,
    /// Other letters A..Z: value and column.
    pub(super) words: [Option<(f64, usize)>; 26],
}

impl Block {
    pub(super) fn get(&self, letter: char) -> Option<(f64, usize)> {
        let i = (letter as usize).checked_sub('A' as usize)?;
        self.words.get(i).copied().flatten()
    }
    pub(super) fn err(&self, column: usize, message: impl Into<String>) -> GcodeError {
        GcodeError {
            line: self.line,
            column,
            message: message.into(),
        }
    }
    pub(super) fn first_column(&self) -> usize {
        self.g
            .iter()
            .chain(&self.m)
            .map(|(_, c)| *c)
            .chain(self.words.iter().flatten().map(|(_, c)| *c))
            .min()
            .unwrap_or(1)
    }
}

/// Interpret a whole program.
///
/// # Errors
/// The first [`GcodeError`] met (line and column of the offending word). Warnings go to
/// [`Program::diagnostics`].
pub fn interpret(text: &str, opts: &InterpretOptions) -> Result<Program, GcodeError> {
    let mut state = State::new(opts);
    if !opts.start.is_finite() {
        return Err(GcodeError {
            line: 0,
            column: 0,
            message: "the start position is not finite".into(),
        });
    }
    let mut program = Program::default();
    let mut ended_at: Option<usize> = None;
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let raw = program_frame(raw, opts.syntax, &mut state);
        let separator = if opts.semicolon_ends_block {
            Some(';')
        } else {
            opts.syntax.block_end()
        };
        for lexed in blocks_of_line(raw, line, separator)? {
            if lexed.block_delete && opts.block_delete {
                continue;
            }
            // A line of keywords alone (`TRAORI`, `MSG("...")`, a mistyped `TRAFOF`) is a
            // block too: skipping it would drop a mode change or an unknown word silently.
            if lexed.words.is_empty() && lexed.keywords.is_empty() {
                continue;
            }
            if let Some(end) = ended_at {
                program.diagnostics.push(Diagnostic::warning(
                    format!("line {line}"),
                    format!("words after the program end (line {end}) are ignored"),
                ));
                return Ok(program);
            }
            let mut block = sort_words(&lexed.words, line, opts.syntax)?;
            block.keywords = lexed.keywords;
            if execute(&block, &mut state, opts, &mut program)? {
                ended_at = Some(line);
            }
        }
    }
    Ok(program)
}

impl State {
    /// The state at the start of a program.
    pub(super) fn new(opts: &InterpretOptions) -> Self {
        Self {
            pos: opts.start,
            motion: None,
            plane: Plane::Xy,
            inch: false,
            absolute: true,
            arc_absolute: false,
            inverse_time: false,
            feed: None,
            work_offset: opts.initial_work_offset.min(5),
            tool: 0,
            tool_length_h: None,
            spindle_speed: 0.0,
            spindle_dir: 0.0,
            coolant: false,
            warned_no_feed: false,
            tcp: false,
        }
    }
}

/// Heidenhain's program frame `%NAME G71 *` (start) and `N99999999 %NAME G71 *` (end): the
/// unit code in it is applied and the frame is removed from the line; other syntaxes keep the
/// line as it is.
pub(super) fn program_frame<'a>(raw: &'a str, syntax: Syntax, state: &mut State) -> &'a str {
    if syntax != Syntax::HeidenhainIso {
        return raw;
    }
    let Some(at) = raw.find('%') else {
        return raw;
    };
    let frame = raw.get(at..).unwrap_or("").to_ascii_uppercase();
    let words: Vec<&str> = frame
        .split(|c: char| c.is_whitespace() || c == '*')
        .collect();
    if words.contains(&"G70") {
        state.inch = true;
    } else if words.contains(&"G71") {
        state.inch = false;
    }
    raw.get(..at).unwrap_or("")
}

/// The blocks of one line: one, or with a block-end character (`;` in the thesis's samples,
/// Heidenhain's `*`), one per separated piece (columns stay those of the whole line).
pub(super) fn blocks_of_line(
    raw: &str,
    line: usize,
    separator: Option<char>,
) -> Result<Vec<LexedLine>, GcodeError> {
    let Some(separator) = separator else {
        return Ok(vec![lex_line(raw, line)?]);
    };
    let mut out = Vec::new();
    let mut offset = 0usize;
    for piece in raw.split(separator) {
        let mut lexed = lex_line(piece, line).map_err(|mut e| {
            e.column += offset;
            e
        })?;
        for w in &mut lexed.words {
            w.column += offset;
        }
        out.push(lexed);
        offset += piece.chars().count() + 1;
    }
    Ok(out)
}

pub(super) fn sort_words(words: &[Word], line: usize, syntax: Syntax) -> Result<Block, GcodeError> {
    let mut block = Block {
        line,
        g: Vec::new(),
        m: Vec::new(),
        keywords: Vec::new(),
        words: [None; 26],
    };
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
            l if LETTERS.contains(l) || (l == 'D' && syntax == Syntax::Siemens) => {
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

/// The G words of a block that act later (motion, G28/G53, G4).
struct GWords {
    motion: Option<(Motion, usize)>,
    non_modal: Option<(i32, usize)>,
    dwell: bool,
}

/// Apply the modal G codes of a block and classify the rest, rejecting unknown codes and
/// conflicts within a modal group.
fn g_words(b: &Block, s: &mut State, syntax: Syntax) -> Result<GWords, GcodeError> {
    let mut motion: Option<(Motion, usize)> = None;
    let mut non_modal: Option<(i32, usize)> = None;
    let mut dwell = false;
    let set_motion = |m: Motion, col: usize, motion: &mut Option<(Motion, usize)>| {
        if motion.is_some() {
            return Err(b.err(col, "two motion codes in one block"));
        }
        *motion = Some((m, col));
        Ok(())
    };
    for &(g, col) in &b.g {
        match g {
            0 => set_motion(Motion::Rapid, col, &mut motion)?,
            10 => set_motion(Motion::Linear, col, &mut motion)?,
            20 => set_motion(Motion::Cw, col, &mut motion)?,
            30 => set_motion(Motion::Ccw, col, &mut motion)?,
            40 => dwell = true,
            170 => s.plane = Plane::Xy,
            180 => s.plane = Plane::Zx,
            190 => s.plane = Plane::Yz,
            200 => s.inch = true,
            210 => s.inch = false,
            280 | 530 => {
                if non_modal.is_some() {
                    return Err(b.err(col, "G28 and G53 cannot share a block"));
                }
                non_modal = Some((g, col));
            }
            400 | 610 | 611 | 640 => {}
            410 | 420 => {
                return Err(b.err(
                    col,
                    format!("cutter radius compensation G{} is not supported (program the tool centre path)", g / 10),
                ));
            }
            430 | 434 => {
                let h = match b.get('H') {
                    Some((h, hc)) => {
                        u32_word(h).ok_or_else(|| b.err(hc, "H must be a non-negative integer"))?
                    }
                    None => s.tool,
                };
                s.tool_length_h = Some(h);
                if g == 434 {
                    s.tcp = true;
                }
            }
            490 => {
                s.tool_length_h = None;
                s.tcp = false;
            }
            700 | 7000 if syntax.g70_g71_are_units() => s.inch = true,
            710 | 7100 if syntax.g70_g71_are_units() => s.inch = false,
            540..=590 if g % 10 == 0 => s.work_offset = ((g - 540) / 10) as usize,
            800 => s.motion = None,
            900 => s.absolute = true,
            910 => s.absolute = false,
            901 => s.arc_absolute = true,
            911 => s.arc_absolute = false,
            930 => s.inverse_time = true,
            940 => s.inverse_time = false,
            _ => {
                let name = if g % 10 == 0 {
                    format!("G{}", g / 10)
                } else {
                    format!("G{}.{}", g / 10, g % 10)
                };
                return Err(b.err(col, format!("unsupported G code {name}")));
            }
        }
    }
    Ok(GWords {
        motion,
        non_modal,
        dwell,
    })
}

/// Execute one block; returns true at a program end (M2/M30).
/// Sinumerik keywords that only set messages, dynamics or compressor modes: read with a warning.
const SIEMENS_NO_GEOMETRY: &[&str] = &[
    "MSG", "CYCLE832", "SOFT", "BRISK", "FFWON", "FFWOF", "COMPCAD", "COMPCURV", "COMPOF",
    "COMPON", "FGROUP", "DIAMOF", "WAITM", "STOPRE",
];

/// Sinumerik keywords that move, turn, mirror or scale the coordinate system, or run a cycle that
/// moves the tool: refused, since ignoring them would change where the tool goes.
const SIEMENS_GEOMETRY: &[&str] = &[
    "CYCLE800", "SUPA", "TRANS", "ATRANS", "ROT", "AROT", "MIRROR", "AMIRROR", "SCALE", "ASCALE",
    "TRAORI2", "TRANSMIT", "TRACYL", "CYCLE81", "CYCLE82", "CYCLE83", "CYCLE84", "CYCLE61",
    "CYCLE71", "POCKET3", "POCKET4", "SLOT1", "SLOT2",
];

pub(super) fn execute(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
) -> Result<bool, GcodeError> {
    // The tool is selected before G43 reads its default H (RS274NGC order of execution).
    if let Some((t, col)) = b.get('T') {
        s.tool = u32_word(t).ok_or_else(|| b.err(col, "T must be a non-negative integer"))?;
    }
    let GWords {
        motion,
        non_modal,
        dwell,
    } = g_words(b, s, opts.syntax)?;
    for (keyword, col) in &b.keywords {
        match (opts.syntax, keyword.as_str()) {
            (Syntax::Siemens, "TRAORI") => s.tcp = true,
            (Syntax::Siemens, "TRAFOOF") => s.tcp = false,
            (Syntax::Siemens, k) if SIEMENS_NO_GEOMETRY.contains(&k) => {
                out.diagnostics.push(Diagnostic::warning(
                    format!("line {}, column {col}", b.line),
                    format!("{k} ignored (it does not change the tool's path here)"),
                ));
            }
            (Syntax::Siemens, k) if SIEMENS_GEOMETRY.contains(&k) => {
                return Err(b.err(
                    *col,
                    format!(
                        "{k} is not supported: it moves or turns the coordinate system, and \
                         ignoring it would put the tool somewhere else"
                    ),
                ));
            }
            (syntax, _) => {
                return Err(b.err(
                    *col,
                    format!(
                        "unknown word {keyword} (not a {} keyword)",
                        syntax_name(syntax)
                    ),
                ));
            }
        }
    }
    if b.get('H').is_some() && !b.g.iter().any(|(g, _)| *g == 430 || *g == 434) {
        return Err(b.err(b.get('H').map_or(1, |h| h.1), "H word without G43"));
    }
    let scale = if s.inch { MM_PER_INCH } else { 1.0 };
    if let Some((f, col)) = b.get('F') {
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
    let mut ends = false;
    for &(m, col) in &b.m {
        match m {
            0 | 10 | 60 => {}
            30 => s.spindle_dir = 1.0,
            40 => s.spindle_dir = -1.0,
            50 => s.spindle_dir = 0.0,
            70 | 80 => s.coolant = true,
            90 => s.coolant = false,
            20 | 300 => ends = true,
            1280 if opts.syntax == Syntax::HeidenhainIso => s.tcp = true,
            1290 if opts.syntax == Syntax::HeidenhainIso => s.tcp = false,
            _ => out.diagnostics.push(Diagnostic::warning(
                format!("line {}, column {col}", b.line),
                format!("unknown M code M{} ignored", f64::from(m) / 10.0),
            )),
        }
    }
    if let Some((m, _)) = motion {
        s.motion = Some(m);
    }
    let has_axis = "XYZABC".chars().any(|l| b.get(l).is_some());
    if dwell {
        if has_axis || motion.is_some() {
            return Err(b.err(
                b.first_column(),
                "G4 dwell cannot share a block with motion",
            ));
        }
        let Some((seconds, col)) = b.get('P') else {
            return Err(b.err(b.first_column(), "G4 needs a P word (seconds)"));
        };
        if !(seconds >= 0.0) {
            return Err(b.err(col, "G4 P (seconds) must not be negative"));
        }
        out.dwells.push(Dwell {
            line: b.line,
            before_block: out.blocks.len(),
            seconds,
        });
        return Ok(ends);
    }
    match non_modal {
        Some((280, _)) => g28(b, s, opts, out, scale)?,
        Some((_, col)) => {
            if s.absolute {
                let m = s
                    .motion
                    .filter(|m| matches!(m, Motion::Rapid | Motion::Linear));
                let m = m.ok_or_else(|| b.err(col, "G53 needs G0 or G1"))?;
                let target = target(b, s, opts, scale, true);
                emit_line(b, s, opts, out, m, target)?;
            } else {
                return Err(b.err(col, "G53 is not allowed in incremental mode (G91)"));
            }
        }
        None if has_axis => {
            let m = s.motion.ok_or_else(|| {
                b.err(
                    b.first_column(),
                    "axis words without a motion mode (G0, G1, G2, G3)",
                )
            })?;
            let t = target(b, s, opts, scale, false);
            match m {
                Motion::Rapid | Motion::Linear => emit_line(b, s, opts, out, m, t)?,
                Motion::Cw | Motion::Ccw => emit_arc(b, s, opts, out, m == Motion::Ccw, t, scale)?,
            }
        }
        None => {
            if let Some((_, col)) = motion.filter(|(m, _)| matches!(m, Motion::Cw | Motion::Ccw)) {
                return Err(b.err(col, "an arc needs end point words"));
            }
        }
    }
    let arc_words = s
        .motion
        .is_some_and(|m| matches!(m, Motion::Cw | Motion::Ccw))
        && has_axis
        && non_modal.is_none();
    if !arc_words {
        for l in ['I', 'J', 'K', 'R', 'P'] {
            if let Some((_, col)) = b.get(l) {
                return Err(b.err(col, format!("{l} word used outside an arc")));
            }
        }
    }
    Ok(ends)
}

fn syntax_name(syntax: Syntax) -> &'static str {
    match syntax {
        Syntax::Rs274 => "RS274",
        Syntax::Siemens => "Sinumerik",
        Syntax::HeidenhainIso => "Heidenhain ISO",
    }
}

pub(super) fn u32_word(v: f64) -> Option<u32> {
    (v >= 0.0 && v <= f64::from(u32::MAX) && v.fract() == 0.0).then_some(v as u32)
}
