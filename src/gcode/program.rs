//! A whole program: its lines read once, its `%` frame, its O-word structure, and the run
//! from the first line to the program end.
//!
//! The program ends at `M2`/`M30` (words after it, outside subroutine definitions, are
//! ignored with a warning), at the end of the text, or at a closing `%`: when the first
//! non-blank line is `%` the program runs to the next `%` line and the lines after it are not
//! read, as in LinuxCNC (a `%` line without an opening one also ends the program, the end of
//! a Fanuc tape).

use super::expr::eval;
use super::interpreter::{View, blocks_of_line, program_frame, run_block};
use super::lexer::{Item, ParsedLine};
use super::oword::{Flow, MAX_ITERATIONS, OLine, Step, Structure};
use super::state::State;
use super::{GcodeError, InterpretOptions, Program};
use crate::diagnostics::Diagnostic;

/// One source line, parsed.
struct SourceLine {
    /// 1-based line number.
    number: usize,
    /// The unit code of a Heidenhain program frame on this line (`Some(true)`: inch).
    frame_inch: Option<bool>,
    /// Its blocks, or the parse error (reported when the line runs).
    blocks: Result<Vec<ParsedLine>, GcodeError>,
    /// Skipped by block delete (`/` with the switch on).
    deleted: bool,
}

impl SourceLine {
    /// The O-word of a line that is one (and is not block-deleted).
    fn oline(&self) -> Option<&OLine> {
        match &self.blocks {
            Ok(blocks) if blocks.len() == 1 && !self.deleted => {
                blocks.first().and_then(|b| b.oword.as_ref())
            }
            _ => None,
        }
    }

    fn percent(&self) -> bool {
        matches!(&self.blocks, Ok(blocks) if blocks.iter().any(|b| b.percent))
    }

    /// Only `N` words (what is left of Heidenhain's end frame `N99999999 %NAME G71 *`).
    fn numbers_only(&self) -> bool {
        matches!(&self.blocks, Ok(blocks) if blocks.iter().all(|b| {
            b.keywords.is_empty()
                && b.oword.is_none()
                && b.items.iter().all(|i| matches!(i, Item::Word { letter: 'N', .. }))
        }))
    }

    fn blank(&self) -> bool {
        self.frame_inch.is_none()
            && matches!(&self.blocks, Ok(blocks) if blocks.iter().all(|b| b.is_empty() && !b.percent))
    }
}

fn read_lines(text: &str, opts: &InterpretOptions) -> Vec<SourceLine> {
    let separator = if opts.semicolon_ends_block {
        Some(';')
    } else {
        opts.syntax.block_end()
    };
    let mut lines: Vec<SourceLine> = Vec::new();
    let mut opened = false;
    for (index, raw) in text.lines().enumerate() {
        let number = index + 1;
        let (raw, frame_inch) = program_frame(raw, opts.syntax);
        let blocks = blocks_of_line(raw, number, separator, opts.syntax);
        let deleted = opts.block_delete
            && matches!(&blocks, Ok(b) if b.first().is_some_and(|b| b.block_delete));
        let line = SourceLine {
            number,
            frame_inch,
            blocks,
            deleted,
        };
        if line.percent() {
            let first = lines.iter().all(SourceLine::blank);
            if first && !opened {
                opened = true;
                lines.push(line);
                continue;
            }
            // The closing `%`: nothing after it is read.
            break;
        }
        lines.push(line);
    }
    lines
}

/// Interpret a whole program.
///
/// # Errors
/// The first [`GcodeError`] met (line and column of the offending word). Warnings go to
/// [`Program::diagnostics`].
pub fn interpret(text: &str, opts: &InterpretOptions) -> Result<Program, GcodeError> {
    let mut program = Program::default();
    run_into(text, opts, &mut program)?;
    Ok(program)
}

/// Interpret a program as far as it reads: the motion up to the first error, and the error.
/// [`interpret`] gives the same program when there is no error.
#[must_use]
pub fn interpret_partial(text: &str, opts: &InterpretOptions) -> (Program, Option<GcodeError>) {
    let mut program = Program::default();
    let e = run_into(text, opts, &mut program).err();
    (program, e)
}

/// One executed block of a program, in execution order (a subroutine's lines once per call, a
/// loop's once per pass): where its motion and dwells end in the program, what it stops on,
/// and the modal state it leaves.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceStep {
    /// 1-based line of the block.
    pub line: usize,
    /// [`Program::blocks`] up to this index have been emitted after this block (a
    /// compensated move comes out with the block after it).
    pub blocks_end: usize,
    /// [`Program::dwells`] up to this index have been emitted after this block.
    pub dwells_end: usize,
    /// The block holds `M0`.
    pub program_stop: bool,
    /// The block holds `M1`.
    pub optional_stop: bool,
    /// The block ends the program (`M2`, `M30`; also the last step, where the text ends).
    pub program_end: bool,
    /// The modal state after the block.
    pub modal: super::Modal,
}

/// A program interpreted whole ([`interpret`]'s motion) with its execution steps: what a
/// control's program run plays (`control`'s AUTO), so that it runs exactly the interpreter's
/// motion, canned cycles, compensation, subroutines and loops included.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Traced {
    /// The motion, dwells and warnings, as [`interpret`] gives them.
    pub program: Program,
    /// The executed blocks in order.
    pub steps: Vec<TraceStep>,
}

/// Interpret a whole program and record its execution steps ([`Traced`]). With `restart`
/// `(line, position)`, the machine is placed at `position` before the first block executed
/// on or after `line` (a control's run from a line: the blocks before it set the modal state,
/// their motion is the caller's to drop).
///
/// # Errors
/// The first [`GcodeError`] met; the steps and motion before it are not returned.
pub fn interpret_traced(
    text: &str,
    opts: &InterpretOptions,
    restart: Option<(usize, super::Joints)>,
) -> Result<Traced, GcodeError> {
    let mut traced = Traced::default();
    let mut trace = Trace {
        steps: Vec::new(),
        restart,
    };
    run_traced(text, opts, &mut traced.program, Some(&mut trace))?;
    let last_line = trace.steps.last().map_or(0, |s| s.line);
    let (blocks, dwells) = (traced.program.blocks.len(), traced.program.dwells.len());
    let tail = trace
        .steps
        .last()
        .is_none_or(|s| s.blocks_end < blocks || s.dwells_end < dwells || !s.program_end);
    if tail {
        // The end of the text (or a closing `%`) ends the program; a move compensation held
        // comes out there.
        let modal = trace.steps.last().map(|s| s.modal.clone());
        if let Some(modal) = modal {
            trace.steps.push(TraceStep {
                line: last_line,
                blocks_end: blocks,
                dwells_end: dwells,
                program_stop: false,
                optional_stop: false,
                program_end: true,
                modal,
            });
        }
    }
    traced.steps = trace.steps;
    Ok(traced)
}

/// What [`interpret_traced`] records while the program runs.
struct Trace {
    steps: Vec<TraceStep>,
    restart: Option<(usize, super::Joints)>,
}

fn run_into(text: &str, opts: &InterpretOptions, out: &mut Program) -> Result<(), GcodeError> {
    run_traced(text, opts, out, None)
}

fn run_traced(
    text: &str,
    opts: &InterpretOptions,
    out: &mut Program,
    mut trace: Option<&mut Trace>,
) -> Result<(), GcodeError> {
    if !opts.start.is_finite() {
        return Err(GcodeError {
            line: 0,
            column: 0,
            message: "the start position is not finite".into(),
        });
    }
    let lines = read_lines(text, opts);
    let olines: Vec<(usize, usize, &OLine)> = lines
        .iter()
        .enumerate()
        .filter_map(|(i, l)| l.oline().map(|o| (i, l.number, o)))
        .collect();
    let structure = Structure::build(&olines)?;
    let mut state = State::new(opts);
    let program = out;
    let mut flow = Flow::default();
    let mut ended_at: Option<usize> = None;
    let mut idx = 0;
    let budget = lines.len() as u64 + MAX_ITERATIONS;
    let mut executed = 0u64;
    while let Some(line) = lines.get(idx) {
        executed += 1;
        if executed > budget {
            return Err(GcodeError {
                line: line.number,
                column: 1,
                message: format!(
                    "the program ran {MAX_ITERATIONS} lines more than it has (its loops and \
                     calls never end?); stopped here"
                ),
            });
        }
        if let Some(end) = ended_at {
            // After the end only subroutine definitions (and a Heidenhain end frame, an N
            // number alone) may follow quietly.
            if !line.blank() && !line.numbers_only() && !structure.in_definition(idx) {
                program.diagnostics.push(Diagnostic::warning(
                    format!("line {}", line.number),
                    format!("words after the program end (line {end}) are ignored"),
                ));
                break;
            }
            idx += 1;
            continue;
        }
        if let Some(inch) = line.frame_inch {
            state.inch = inch;
        }
        let blocks = line.blocks.as_ref().map_err(Clone::clone)?;
        if line.deleted && blocks.first().is_some_and(|b| b.oword.is_some()) {
            idx += 1;
            continue;
        }
        if let Some(o) = line.oline() {
            idx = oline(&mut flow, &mut state, &structure, idx, line.number, o)?;
            continue;
        }
        for block in blocks {
            if block.block_delete && opts.block_delete {
                continue;
            }
            if block.oword.is_some() {
                return Err(GcodeError {
                    line: line.number,
                    column: 1,
                    message: "an O-word must be alone on its line".into(),
                });
            }
            if let Some(t) = trace.as_deref_mut()
                && let Some((from, at)) = t.restart
                && line.number >= from
            {
                state.place(at);
                t.restart = None;
            }
            let ran = run_block(block, line.number, &mut state, opts, program)?;
            if let Some(t) = trace.as_deref_mut() {
                t.steps.push(TraceStep {
                    line: line.number,
                    blocks_end: program.blocks.len(),
                    dwells_end: program.dwells.len(),
                    program_stop: ran.m.contains(&0),
                    optional_stop: ran.m.contains(&10),
                    program_end: ran.ends,
                    modal: super::session::modal_of(&state),
                });
            }
            if ran.ends {
                ended_at = Some(line.number);
                break;
            }
        }
        idx += 1;
    }
    let last = lines.last().map_or(0, |l| l.number);
    super::compensation::flush(&mut state, program, last)
}

/// Execute an O-word line; returns the index of the next line to run.
fn oline(
    flow: &mut Flow,
    state: &mut State,
    structure: &Structure,
    idx: usize,
    number: usize,
    o: &OLine,
) -> Result<usize, GcodeError> {
    let err = |message: String| GcodeError {
        line: number,
        column: o.column,
        message,
    };
    let in_call = state.params.depth() > 0;
    let (step, args) = {
        let view = View { s: state };
        let values = || -> Result<Vec<f64>, GcodeError> {
            o.args
                .iter()
                .map(|e| eval(e, &view).map_err(|m| err(format!("{}: {m}", o.label()))))
                .collect()
        };
        let mut first = || values().map(|v| v.first().copied());
        let step = flow.step(idx, number, o, structure, &mut first, in_call)?;
        let args = if matches!(step, Step::Call(_)) {
            values()?
        } else {
            Vec::new()
        };
        (step, args)
    };
    match step {
        Step::Goto(next) => Ok(next),
        Step::Call(at) => {
            state.params.call(&args).map_err(err)?;
            Ok(at)
        }
        Step::Return(back, v) => {
            state.params.ret(v);
            Ok(back)
        }
    }
}
