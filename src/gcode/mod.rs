//! G-code (RS274NGC / ISO 6983) reading: lexer, expressions, modal state and an interpreter
//! that turns a program into [`MotionBlock`]s in machine coordinates (mm, rad), read as
//! LinuxCNC's interpreter reads it (checked against its `rs274 -g` on a corpus of programs:
//! `tests/gcode_linuxcnc.rs`).
//!
//! ```text
//! text ─lexer─▶ items per line (words with expression values, parameter settings, O-words)
//!      ─program (%, O-word structure, loops, calls)─▶ blocks ─interpreter (modal state,
//!      offsets, cycles, cutter compensation)─▶ Program { blocks, dwells, diagnostics }
//! ```
//!
//! The syntax of LinuxCNC/Fanuc/GRBL (RS274), Siemens 840D and Heidenhain ISO programs is read
//! ([`Syntax`], [`InterpretOptions::syntax`]; [`Syntax::detect`] picks it from the text),
//! including their tool-centre-point modes (`G43.4`/`G49`, `TRAORI`/`TRAFOOF`,
//! `M128`/`M129`): blocks programmed under TCP carry [`MotionBlock::tcp`], their X Y Z being
//! the tool tip in part coordinates.
//!
//! What is understood:
//! - motion: `G0 G1 G2 G3` (arcs with `I J K` or `R`, full circles, helices, `P` turns),
//!   `G4` dwell, `G17 G18 G19`, `G20 G21`, `G28` (through an optional intermediate point to
//!   [`InterpretOptions::g28_position`]), `G53`, `G90 G91`, `G90.1 G91.1`, `G93 G94`,
//!   `G61 G61.1 G64` (accepted, no effect); `F S T`; `M0 M1 M2 M3 M4 M5 M6 M7 M8 M9 M30 M60`,
//!   `M61 Q`;
//! - canned cycles `G73 G74 G81 G82 G83 G84 G85 G86 G89` with `G98`/`G99`, `R Q P L`, in any
//!   plane and in G90 or G91, repeated on later blocks, `G80` ([`cycles`]);
//! - cutter radius compensation `G41 G42` (radius from the tool table, `D` a tool number) and
//!   `G41.1 G42.1` (`D` the diameter), `G40`, in G17 and G18 ([`compensation`]);
//! - offsets: `G54`–`G59.3` (from [`InterpretOptions::work_offsets`] and `G10 L2`/`L20`),
//!   `G52`, `G92 G92.1 G92.2 G92.3`, tool lengths `G43 Hn`/`G43`/`G43.1`/`G49` from
//!   [`InterpretOptions::tool_table`] ([`offsets`], [`tooltable`]);
//! - parameters `#1`..`#5601`, `#<local>`, `#<_global>` and expressions `[ ]` with LinuxCNC's
//!   operators and functions ([`expr`], [`params`]);
//! - LinuxCNC O-words: `sub`/`endsub`/`call` with arguments, `return`, `if`/`elseif`/`else`,
//!   `while`, `do`/`while`, `repeat`, `break`/`continue`, bounded so that a loop that never
//!   ends is an error ([`oword`]);
//! - Heidenhain ISO drilling cycles `G200 G201 G202 G203 G205 G207 G209` with their `Q`
//!   parameters, called by `G79`, `M99` and modal `M89` (`heidenhain`), and `G04 F` dwells;
//! - tilted work planes with the machine's kinematics ([`InterpretOptions::machine`]): Fanuc
//!   `G68.2`/`G53.1`/`G69`, Sinumerik `CYCLE800`/`CYCLE800()`, Heidenhain `PLANE SPATIAL`/
//!   `PLANE RESET` (`workplane`);
//! - `N` numbers, `O` program numbers, `%` lines (a closing `%` ends the program), `/` block
//!   delete, comments `( )` and `;` (or `;` as the ISO end of block with
//!   [`InterpretOptions::semicolon_ends_block`]).
//!
//! Policy for what is not understood (never skipped silently):
//! - errors, naming the code: `G5.x` splines, `G7`/`G8`, `G10 L1/L10/L11` and rotations,
//!   `G28.1 G30 G30.1`, `G33 G33.1 G38.x G76 G87 G88` and the lathe cycles `G70`–`G72`,
//!   `G43.2`, `G95 G96 G97`, the UVW planes, `M98`, offsets of rotary axes, any other
//!   G code, any letter that is not listed above (`U`, `V`, `W`, `E`, `$`, ...: it might be an
//!   axis, and ignoring it would move the tool somewhere else), a word given twice in one
//!   block, two codes of one modal group in one block, a fed move at a zero feed (`F0`),
//!   a corner that compensation cannot reach without gouging, a subroutine that is not in the
//!   file;
//! - warnings (in [`Program::diagnostics`]): unknown M codes (they switch machine functions,
//!   not geometry; `M99` too: the program runs once), feed moves before any F word
//!   (LinuxCNC refuses those too; Talas keeps reading feed-less listings, feed 0 recorded),
//!   text after `M2`/`M30`.

mod arc;
mod block;
pub mod compensation;
pub mod cycles;
pub mod expr;
mod heidenhain;
mod heidenhain_call;
mod interpreter;
mod lexer;
mod modal;
mod motion;
pub mod offsets;
pub mod oword;
pub mod params;
mod program;
mod session;
mod siemens;
mod siemens_call;
mod state;
mod syntax;
mod sysparams;
pub mod tooltable;
mod workplane;
mod workplane_frame;

pub use arc::{CentreSpec, Plane, arc_geometry};
pub use block::{Arc, CyclePhase, CycleStep, Joints, MotionBlock, MotionKind};
pub use lexer::{LexedLine, Word, lex_line};
pub use program::interpret;
pub use program::interpret_partial;
pub use program::{TraceStep, Traced, interpret_traced};
pub use session::{LineResult, Modal, Session};
pub use syntax::Syntax;
pub use tooltable::{LengthUnit, ToolEntry, ToolTable};

use glam::DVec3;

use crate::diagnostics::Diagnostic;

/// The one error of the G-code reader: where (1-based line and column) and what.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("line {line}, column {column}: {message}")]
pub struct GcodeError {
    /// 1-based line.
    pub line: usize,
    /// 1-based column (characters) of the offending word or character.
    pub column: usize,
    /// What is wrong, one sentence.
    pub message: String,
}

/// Settings of the virtual controller.
#[derive(Clone, Debug, PartialEq)]
pub struct InterpretOptions {
    /// Machine position before the first block.
    pub start: Joints,
    /// Work offsets G54..G59 (index 0 = G54), in mm, added to program coordinates.
    pub work_offsets: [DVec3; 6],
    /// Work offset active at the start (0 = G54).
    pub initial_work_offset: usize,
    /// The G28 home position in machine coordinates (mm).
    pub g28_position: DVec3,
    /// Feed recorded on rapid (G0) blocks, mm/min.
    pub rapid_mm_per_min: f64,
    /// Skip lines that start with `/` (the operator's block-delete switch).
    pub block_delete: bool,
    /// Read `;` as the ISO end-of-block character, so one line may hold several blocks
    /// (`T1; M3 S1250;`, as in the Can 2010 thesis samples), instead of as the start of a
    /// comment (RS274NGC, the default).
    pub semicolon_ends_block: bool,
    /// The controller family whose syntax is read (block ends, units codes, TCP codes).
    pub syntax: Syntax,
    /// The tool table (LinuxCNC `.tbl`): lengths for G43 and radii for G41/G42. Without one,
    /// G43 records its H without moving the tool, and G41/G42 are refused (G41.1/G42.1 with
    /// a D diameter need no table).
    pub tool_table: Option<ToolTable>,
    /// Read a canned cycle's P (G82, G84, G86, G89 dwell) in milliseconds, as Fanuc does
    /// (`P500` is 0.5 s), instead of seconds (LinuxCNC, the default).
    pub cycle_dwell_ms: bool,
    /// The machine whose kinematics turn a tilted work plane (`G68.2`, `CYCLE800`,
    /// `PLANE SPATIAL`) into joints; without one those are refused.
    pub machine: Option<crate::machine::Machine>,
}

impl Default for InterpretOptions {
    fn default() -> Self {
        Self {
            start: Joints::default(),
            work_offsets: [DVec3::ZERO; 6],
            initial_work_offset: 0,
            g28_position: DVec3::ZERO,
            rapid_mm_per_min: crate::units::DEFAULT_RAPID_MM_PER_MIN,
            block_delete: true,
            semicolon_ends_block: false,
            syntax: Syntax::Rs274,
            cycle_dwell_ms: false,
            tool_table: None,
            machine: None,
        }
    }
}

impl InterpretOptions {
    /// Default options for a controller family's syntax.
    #[must_use]
    pub fn for_syntax(syntax: Syntax) -> Self {
        Self {
            syntax,
            ..Self::default()
        }
    }

    /// Default options starting at a given position.
    #[must_use]
    pub fn starting_at(start: Joints) -> Self {
        Self {
            start,
            ..Self::default()
        }
    }
}

/// An interpreted program.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    /// Motions in program order.
    pub blocks: Vec<MotionBlock>,
    /// Warnings and notes (place = `line N, column C`).
    pub diagnostics: Vec<Diagnostic>,
    /// `G4` dwells in program order: the machine stands still for their time between blocks.
    pub dwells: Vec<Dwell>,
}

/// A `G4` dwell: the machine stands still before block `before_block` (or at the end of the
/// program when that is the block count).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dwell {
    /// 1-based line of the `G4` block.
    pub line: usize,
    /// Index of the motion block the dwell comes before.
    pub before_block: usize,
    /// Time standing still, s.
    pub seconds: f64,
    /// The canned cycle's dwell at a hole's bottom (G82, G84, G86, G89 with `P`), what the
    /// control's panel shows while it stands still; `None` for a `G4`.
    pub cycle: Option<CyclePhase>,
}

impl Program {
    /// Sum of [`MotionBlock::length_mm`] over all blocks.
    #[must_use]
    pub fn length_mm(&self) -> f64 {
        self.blocks.iter().map(MotionBlock::length_mm).sum()
    }

    /// Sum of the `G4` dwell times, s.
    #[must_use]
    pub fn dwell_s(&self) -> f64 {
        self.dwells.iter().map(|d| d.seconds).sum()
    }
}
