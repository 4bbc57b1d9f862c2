//! The controller's modal state: what every part of the interpreter reads and sets (the
//! motion mode, plane, units, feed, tool, offsets, the compensation and cycle state and the
//! parameters), and the sorted words of one block. Data only: the execution lives in the
//! modules that use it.

use glam::{DVec2, DVec3};

use super::arc::Plane;
use super::block::Joints;
use super::params::Params;
use super::{GcodeError, InterpretOptions};

/// Motion modes (modal group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Motion {
    Rapid,
    Linear,
    Cw,
    Ccw,
    Cycle(Cycle),
}

/// The modal state of the controller.
pub(super) struct State {
    /// Where the tool is (machine coordinates), after every move made or held back.
    pub(super) pos: Joints,
    /// The end of the last emitted block: the start of the next.
    pub(super) emitted: Joints,
    pub(super) motion: Option<Motion>,
    pub(super) plane: Plane,
    pub(super) inch: bool,
    pub(super) absolute: bool,
    pub(super) arc_absolute: bool,
    pub(super) inverse_time: bool,
    pub(super) feed: Option<f64>,
    /// Active coordinate system, 0 = G54 .. 8 = G59.3.
    pub(super) work_offset: usize,
    /// The tool selected by the last T word.
    pub(super) tool: u32,
    /// The tool in the spindle (M6 loads the selected tool, M61 Q sets it).
    pub(super) loaded_tool: u32,
    pub(super) tool_length_h: Option<u32>,
    pub(super) spindle_speed: f64,
    pub(super) spindle_dir: f64,
    pub(super) coolant: bool,
    pub(super) warned_no_feed: bool,
    /// Tool-centre-point mode (G43.4, TRAORI, M128).
    pub(super) tcp: bool,
    /// G99 (retract to R, LinuxCNC's default) rather than G98.
    pub(super) retract_r_plane: bool,
    pub(super) params: Params,
    pub(super) offsets: Offsets,
    pub(super) comp: Compensation,
    pub(super) cycle: CycleState,
    /// A Sinumerik `MCALL CYCLE8x(…)`: run after every block that moves an axis.
    pub(super) modal_call: Option<super::siemens_call::SiemensCycle>,
    /// The Heidenhain cycle last defined (`G200 Q…`), run by `G79`, `M99`, `M89`.
    pub(super) heidenhain_cycle: Option<super::heidenhain_call::HeidenhainCycle>,
    /// Heidenhain `M89`: the defined cycle runs after every block that moves an axis.
    pub(super) heidenhain_modal: bool,
    /// The active tilted work plane (`G68.2`, `CYCLE800`, `PLANE SPATIAL`).
    pub(super) work_plane: Option<super::workplane_frame::WorkPlane>,
    /// The line being executed (`#<_line>`).
    pub(super) line: usize,
    /// The canned-cycle move being emitted (copied into its blocks).
    pub(super) cycle_phase: Option<super::block::CyclePhase>,
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
    /// The block has an axis word.
    pub(super) fn has_axis(&self) -> bool {
        "XYZABC".chars().any(|l| self.get(l).is_some())
    }
}

impl State {
    /// The state at the start of a program.
    pub(super) fn new(opts: &InterpretOptions) -> Self {
        Self {
            pos: opts.start,
            emitted: opts.start,
            motion: None,
            plane: Plane::Xy,
            inch: false,
            absolute: true,
            arc_absolute: false,
            inverse_time: false,
            feed: None,
            work_offset: opts.initial_work_offset.min(5),
            tool: 0,
            loaded_tool: 0,
            tool_length_h: None,
            spindle_speed: 0.0,
            spindle_dir: 0.0,
            coolant: false,
            warned_no_feed: false,
            tcp: false,
            retract_r_plane: true,
            params: Params::default(),
            offsets: Offsets::new(opts),
            comp: Compensation::default(),
            cycle: CycleState::default(),
            modal_call: None,
            heidenhain_cycle: None,
            heidenhain_modal: false,
            work_plane: None,
            line: 0,
            cycle_phase: None,
        }
    }

    /// Set the position (a jog, homing, an interrupted move): nothing is held back any more.
    pub(super) fn place(&mut self, pos: Joints) {
        self.pos = pos;
        self.emitted = pos;
        self.comp.programmed = None;
    }
}

impl State {
    /// Machine minus program coordinates: the active work offset, the G92/G52 offset and the
    /// G43 tool length offset, mm.
    pub(super) fn total_offset(&self) -> DVec3 {
        self.offsets.total(self.work_offset)
    }
}

/// A canned cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Cycle {
    G73,
    G74,
    G81,
    G82,
    G83,
    G84,
    G85,
    G86,
    G89,
}

impl Cycle {
    /// The cycle of a G code × 10.
    pub(super) fn from_code(g: i32) -> Option<Self> {
        Some(match g {
            730 => Self::G73,
            740 => Self::G74,
            810 => Self::G81,
            820 => Self::G82,
            830 => Self::G83,
            840 => Self::G84,
            850 => Self::G85,
            860 => Self::G86,
            890 => Self::G89,
            _ => return None,
        })
    }

    /// `G81`.
    pub(super) fn name(self) -> &'static str {
        match self {
            Self::G73 => "G73",
            Self::G74 => "G74",
            Self::G81 => "G81",
            Self::G82 => "G82",
            Self::G83 => "G83",
            Self::G84 => "G84",
            Self::G85 => "G85",
            Self::G86 => "G86",
            Self::G89 => "G89",
        }
    }

    pub(super) fn needs_dwell(self) -> bool {
        matches!(self, Self::G82 | Self::G86 | Self::G89)
    }

    pub(super) fn pecks(self) -> bool {
        matches!(self, Self::G73 | Self::G83)
    }
}

/// What cycle blocks carry over to the next (LinuxCNC's `cycle_r`, `cycle_cc`, `cycle_p`,
/// `cycle_q`, `cycle_il`), in program units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct CycleState {
    pub(super) r: f64,
    pub(super) depth: f64,
    pub(super) p: f64,
    pub(super) q: f64,
    /// The initial level along the cycle axis, kept from the first cycle block after another
    /// motion (G98 retracts to it).
    pub(super) initial: Option<f64>,
}

/// The offsets between program and machine coordinates, mm.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Offsets {
    /// G54 .. G59.3.
    pub(super) work: [DVec3; 9],
    /// The G92/G52 axis offset.
    pub(super) axis: DVec3,
    /// The axis offset parameters `#5211`..`#5213` (kept by G92.2, applied by G92.3).
    pub(super) axis_params: DVec3,
    /// `#5210`: an axis offset is applied.
    pub(super) axis_applied: bool,
    /// The G43 tool length offset.
    pub(super) tool: DVec3,
}

impl Offsets {
    /// From the options' G54..G59.
    pub(super) fn new(opts: &InterpretOptions) -> Self {
        let mut work = [DVec3::ZERO; 9];
        for (slot, o) in work.iter_mut().zip(opts.work_offsets) {
            *slot = o;
        }
        Self {
            work,
            ..Self::default()
        }
    }

    /// Machine minus program coordinates in work system `system` (0 = G54).
    pub(super) fn total(&self, system: usize) -> DVec3 {
        self.work.get(system).copied().unwrap_or(DVec3::ZERO) + self.axis + self.tool
    }
}

/// Which side of the programmed path the tool runs on, looking along the motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Side {
    Left,
    Right,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) enum Held {
    Straight {
        rapid: bool,
        /// Direction of the programmed motion (not normalised).
        dir: DVec2,
    },
    Arc {
        centre: DVec2,
        /// LinuxCNC's turn: ±(1 + full turns), positive counter-clockwise.
        turn: i32,
        /// The sweep before the end was moved (0: a corner arc whose end never moves).
        original_sweep: f64,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub(super) enum Queued {
    Move {
        held: Held,
        end: Joints,
        feed: f64,
        snap: Snapshot,
    },
    Dwell {
        line: usize,
        seconds: f64,
    },
}

/// The compensation state (LinuxCNC's `cutter_comp_*` settings and the canon queue).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Compensation {
    /// G41 / G42 on (after a negative radius swapped the side).
    pub(super) side: Option<Side>,
    /// Tool radius, mm (0: on, but nothing to offset).
    pub(super) radius_mm: f64,
    /// The next move is the entry move.
    pub(super) first_move: bool,
    /// The programmed point while it differs from the tool's position (compensated moves,
    /// and after G40 until the next move): the base of incremental and missing coordinates.
    pub(super) programmed: Option<DVec3>,
    /// After G40 the next move must be straight.
    pub(super) arc_not_allowed: bool,
    pub(super) queue: Vec<Queued>,
    /// The start of the held move (LinuxCNC's `endpoint`), plane coordinates.
    pub(super) endpoint: Option<DVec2>,
}

impl Default for Compensation {
    fn default() -> Self {
        Self {
            side: None,
            radius_mm: 0.0,
            first_move: true,
            programmed: None,
            arc_not_allowed: false,
            queue: Vec::new(),
            endpoint: None,
        }
    }
}

impl Compensation {
    /// Moves are offset (on, with a radius).
    pub(super) fn active(&self) -> bool {
        self.side.is_some() && self.radius_mm > 0.0
    }

    /// Moves or dwells are held back.
    pub(super) fn holding(&self) -> bool {
        !self.queue.is_empty()
    }

    /// Hold a dwell back behind the held move.
    pub(super) fn hold_dwell(&mut self, line: usize, seconds: f64) {
        self.queue.push(Queued::Dwell { line, seconds });
    }
}

impl Compensation {
    /// The held arc at the front of the queue: centre, end and turn, in plane coordinates.
    pub(super) fn front_arc_plane(&self, plane: Plane) -> Option<(DVec2, DVec2, i32)> {
        match self.queue.first() {
            Some(Queued::Move {
                held: Held::Arc { centre, turn, .. },
                end,
                ..
            }) => Some((*centre, plane.split(end.xyz).0, *turn)),
            _ => None,
        }
    }
}

/// What a motion block carries besides its path, taken when the move is made (a held
/// compensated move keeps the state of its own block).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Snapshot {
    pub(super) line: usize,
    pub(super) tool: u32,
    pub(super) tool_length_h: Option<u32>,
    pub(super) spindle_rpm: f64,
    pub(super) coolant: bool,
    pub(super) tcp: bool,
    pub(super) inverse_time: bool,
    pub(super) cycle: Option<super::block::CyclePhase>,
}

impl Snapshot {
    pub(super) fn of(s: &State, line: usize, rapid: bool) -> Self {
        Self {
            line,
            tool: s.tool,
            tool_length_h: s.tool_length_h,
            spindle_rpm: s.spindle_speed * s.spindle_dir,
            coolant: s.coolant,
            tcp: s.tcp,
            inverse_time: s.inverse_time && !rapid,
            cycle: s.cycle_phase,
        }
    }
}

pub(super) fn u32_word(v: f64) -> Option<u32> {
    (v >= 0.0 && v <= f64::from(u32::MAX) && v.fract() == 0.0).then_some(v as u32)
}
