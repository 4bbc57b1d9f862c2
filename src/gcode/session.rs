//! An interpreter that keeps its modal state between calls: a control's MDI line and its
//! program run line by line go through the same execution as [`super::interpret`], so a line
//! typed now sees the units, plane, distance mode, feed, work offset and tool that the lines
//! before it left.

use super::arc::Plane;
use super::block::Joints;
use super::interpreter::{Motion, State, blocks_of_line, execute, program_frame, sort_words};
use super::{GcodeError, InterpretOptions, Program};

/// What one line did besides its motion.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineResult {
    /// The line's motion blocks, dwells and warnings.
    pub program: Program,
    /// The line holds `M0` (program stop).
    pub program_stop: bool,
    /// The line holds `M1` (optional stop).
    pub optional_stop: bool,
    /// The line ends the program (`M2`, `M30`).
    pub program_end: bool,
    /// The line was skipped by block delete (`/` with the switch on).
    pub deleted: bool,
}

/// The modal state as a control shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct Modal {
    /// Motion mode: `G0`, `G1`, `G2`, `G3`, or `G80` (none).
    pub motion: &'static str,
    /// `G17`, `G18` or `G19`.
    pub plane: &'static str,
    /// `G20` (inch) or `G21` (mm).
    pub units: &'static str,
    /// `G90` or `G91`.
    pub distance: &'static str,
    /// `G93` (inverse time) or `G94`.
    pub feed_mode: &'static str,
    /// Active work offset, 0 = G54 … 5 = G59.
    pub work_offset: usize,
    /// Programmed feed (mm/min, or 1/min under G93), if any.
    pub feed: Option<f64>,
    /// Programmed spindle speed (rpm).
    pub spindle_rpm: f64,
    /// +1 `M3`, −1 `M4`, 0 `M5`.
    pub spindle_direction: f64,
    /// Coolant on (`M7`/`M8`).
    pub coolant: bool,
    /// Selected tool.
    pub tool: u32,
    /// Tool length offset register (`G43 Hn`), if active.
    pub tool_length_h: Option<u32>,
    /// Tool-centre-point mode.
    pub tcp: bool,
}

impl Modal {
    /// The active codes as a control lists them (`G1 G17 G21 G90 G94 G54 G49 M5 M9 T1 F600 S0`).
    #[must_use]
    pub fn codes(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            self.motion,
            self.plane,
            self.units,
            self.distance,
            self.feed_mode,
        ]
        .iter()
        .map(ToString::to_string)
        .collect();
        v.push(format!("G{}", 54 + self.work_offset));
        v.push(match self.tool_length_h {
            Some(h) if self.tcp => format!("G43.4 H{h}"),
            Some(h) => format!("G43 H{h}"),
            None => "G49".into(),
        });
        v.push(
            match self.spindle_direction {
                d if d > 0.0 => "M3",
                d if d < 0.0 => "M4",
                _ => "M5",
            }
            .into(),
        );
        v.push(if self.coolant { "M8" } else { "M9" }.into());
        v.push(format!("T{}", self.tool));
        if let Some(f) = self.feed {
            v.push(format!("F{f}"));
        }
        v.push(format!("S{}", self.spindle_rpm));
        v
    }
}

/// A stateful interpreter: one line at a time, modal state kept.
pub struct Session {
    state: State,
    opts: InterpretOptions,
}

impl Session {
    /// A session at the program start (modal defaults, position `opts.start`).
    ///
    /// # Errors
    /// A [`GcodeError`] at line 0 when the start position is not finite.
    pub fn new(opts: InterpretOptions) -> Result<Self, GcodeError> {
        if !opts.start.is_finite() {
            return Err(GcodeError {
                line: 0,
                column: 0,
                message: "the start position is not finite".into(),
            });
        }
        Ok(Self {
            state: State::new(&opts),
            opts,
        })
    }

    /// The options the session runs with.
    #[must_use]
    pub fn options(&self) -> &InterpretOptions {
        &self.opts
    }

    /// Switch block delete on or off for the lines to come.
    pub fn set_block_delete(&mut self, on: bool) {
        self.opts.block_delete = on;
    }

    /// The position the next block starts from (machine coordinates, mm and rad).
    #[must_use]
    pub fn position(&self) -> Joints {
        self.state.pos
    }

    /// Tell the session where the machine is (after a jog, homing or an interrupted move).
    pub fn set_position(&mut self, pos: Joints) {
        if pos.is_finite() {
            self.state.pos = pos;
        }
    }

    /// Set the spindle as an operator's button does (`M3`/`M4`/`M5` without a program).
    pub fn set_spindle_direction(&mut self, direction: f64) {
        self.state.spindle_dir = direction.signum() * f64::from(u8::from(direction != 0.0));
    }

    /// The modal state.
    #[must_use]
    pub fn modal(&self) -> Modal {
        let s = &self.state;
        Modal {
            motion: match s.motion {
                Some(Motion::Rapid) => "G0",
                Some(Motion::Linear) => "G1",
                Some(Motion::Cw) => "G2",
                Some(Motion::Ccw) => "G3",
                None => "G80",
            },
            plane: match s.plane {
                Plane::Xy => "G17",
                Plane::Zx => "G18",
                Plane::Yz => "G19",
            },
            units: if s.inch { "G20" } else { "G21" },
            distance: if s.absolute { "G90" } else { "G91" },
            feed_mode: if s.inverse_time { "G93" } else { "G94" },
            work_offset: s.work_offset,
            feed: s.feed,
            spindle_rpm: s.spindle_speed,
            spindle_direction: s.spindle_dir,
            coolant: s.coolant,
            tool: s.tool,
            tool_length_h: s.tool_length_h,
            tcp: s.tcp,
        }
    }

    /// Execute one line (numbered `line` in messages and blocks). On an error the modal state
    /// may hold what the line's words before the error set, as on a control.
    ///
    /// # Errors
    /// The line's [`GcodeError`].
    pub fn run_line(&mut self, text: &str, line: usize) -> Result<LineResult, GcodeError> {
        let mut out = LineResult::default();
        let raw = program_frame(text, self.opts.syntax, &mut self.state);
        let separator = if self.opts.semicolon_ends_block {
            Some(';')
        } else {
            self.opts.syntax.block_end()
        };
        for lexed in blocks_of_line(raw, line, separator)? {
            if lexed.block_delete && self.opts.block_delete {
                out.deleted = true;
                continue;
            }
            if lexed.words.is_empty() && lexed.keywords.is_empty() {
                continue;
            }
            let mut block = sort_words(&lexed.words, line, self.opts.syntax)?;
            block.keywords = lexed.keywords;
            out.program_stop |= block.m.iter().any(|(m, _)| *m == 0);
            out.optional_stop |= block.m.iter().any(|(m, _)| *m == 10);
            if execute(&block, &mut self.state, &self.opts, &mut out.program)? {
                out.program_end = true;
            }
        }
        Ok(out)
    }
}
