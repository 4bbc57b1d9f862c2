//! An interpreter that keeps its modal state between calls: a control's MDI line and its
//! program run line by line go through the same execution as [`super::interpret`], so a line
//! typed now sees the units, plane, distance mode, feed, work offset and tool that the lines
//! before it left. Parameters and expressions work line by line too (a parameter set on one
//! line is seen by the next); O-word lines (subroutines, loops, conditionals) need the whole
//! program and are refused here. A cutter-compensated move is held until the next move is
//! known, so it comes out with the line after it (or with `M2`/`M30`), as in LinuxCNC.

use super::arc::Plane;
use super::block::Joints;
use super::interpreter::{blocks_of_line, program_frame, run_block};
use super::state::{Motion, State};
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
    /// Active work offset, 0 = G54 … 5 = G59, 6..8 = G59.1..G59.3.
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
        v.push(match self.work_offset {
            n @ 0..=5 => format!("G{}", 54 + n),
            n => format!("G59.{}", n - 5),
        });
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
    /// The first line with anything on it was `%`.
    opened_percent: bool,
    /// A line with words has been run.
    seen_words: bool,
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
            opened_percent: false,
            seen_words: false,
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
            self.state.place(pos);
        }
    }

    /// Set the spindle as an operator's button does (`M3`/`M4`/`M5` without a program).
    pub fn set_spindle_direction(&mut self, direction: f64) {
        self.state.spindle_dir = direction.signum() * f64::from(u8::from(direction != 0.0));
    }

    /// The modal state.
    #[must_use]
    pub fn modal(&self) -> Modal {
        modal_of(&self.state)
    }

    /// Execute one line (numbered `line` in messages and blocks). On an error the modal state
    /// may hold what the line's words before the error set, as on a control.
    ///
    /// # Errors
    /// The line's [`GcodeError`].
    pub fn run_line(&mut self, text: &str, line: usize) -> Result<LineResult, GcodeError> {
        let mut out = LineResult::default();
        let (raw, frame_inch) = program_frame(text, self.opts.syntax);
        if let Some(inch) = frame_inch {
            self.state.inch = inch;
        }
        let separator = if self.opts.semicolon_ends_block {
            Some(';')
        } else {
            self.opts.syntax.block_end()
        };
        for parsed in blocks_of_line(raw, line, separator, self.opts.syntax)? {
            if parsed.percent {
                if self.opened_percent || self.seen_words {
                    // The closing `%` ends the program.
                    super::compensation::flush(&mut self.state, &mut out.program, line)?;
                    out.program_end = true;
                } else {
                    self.opened_percent = true;
                }
                continue;
            }
            if parsed.block_delete && self.opts.block_delete {
                out.deleted = true;
                continue;
            }
            if let Some(o) = &parsed.oword {
                return Err(GcodeError {
                    line,
                    column: o.column,
                    message: format!(
                        "{}: O-word subroutines, loops and conditionals are read in whole \
                         programs, not line by line",
                        o.label()
                    ),
                });
            }
            if parsed.is_empty() {
                continue;
            }
            self.seen_words = true;
            let ran = run_block(&parsed, line, &mut self.state, &self.opts, &mut out.program)?;
            out.program_stop |= ran.m.contains(&0);
            out.optional_stop |= ran.m.contains(&10);
            out.program_end |= ran.ends;
        }
        Ok(out)
    }
}

/// The modal state of an interpreter state.
pub(super) fn modal_of(s: &State) -> Modal {
    Modal {
        motion: match s.motion {
            Some(Motion::Rapid) => "G0",
            Some(Motion::Linear) => "G1",
            Some(Motion::Cw) => "G2",
            Some(Motion::Ccw) => "G3",
            Some(Motion::Cycle(c)) => c.name(),
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
