//! The control's state machine: actions in, motion on the simulated clock, snapshots out.
//! This file holds the state, the action dispatch and the snapshot; `manual` the homing, jog,
//! handwheel and MDI motions, `auto` the program run, `clock` the motion on the clock (plan,
//! advance, overrides and holds, collisions), `cut` the stock's cutting worker.

use std::collections::{BTreeMap, VecDeque};

use glam::DVec3;

use super::motion::Run;
use super::{Action, Alarm, ControlConfig, Mode, Peak, RunState, Snapshot, Spindle, codes};
use crate::feed::path::{JointVector, SLOTS, joint_vector, slot_of};
use crate::feed::{AxisLimit, machine_limits};
use crate::gcode::{CyclePhase, InterpretOptions, Joints, Modal, MotionBlock, Session};

mod auto;
mod clock;
mod cut;
mod manual;

/// An action the control refuses (wrong mode, busy, value out of range).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ControlError {
    /// Refused, with the reason.
    #[error("{0}")]
    Refused(String),
}

fn refuse<T>(msg: impl Into<String>) -> Result<T, ControlError> {
    Err(ControlError::Refused(msg.into()))
}

/// What a motion is for.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Jog { continuous: bool },
    Mpg(char),
    Home(char),
    Mdi,
    Auto,
}

/// What happens when a brake comes to rest.
#[derive(Clone, Copy, Debug, PartialEq)]
enum AfterBrake {
    /// Keep the rest of the motion for a resume.
    Hold { by_override: bool },
    /// Drop it.
    Discard,
    /// Plan the rest again at once (an override changed while blending through).
    Resume,
}

struct Active {
    run: Run,
    kind: Kind,
    after_brake: AfterBrake,
    /// Soft-limit alarm to raise when the motion ends at its target: (axis, limit in mm/deg).
    limit_alarm: Option<(char, f64)>,
    /// Path position up to which the stock has been cut.
    cut_s: f64,
    /// Simulated time since the last cut.
    since_cut: f64,
    /// Path position and joints of the last machine-collision test.
    check_s: f64,
    check_pos: JointVector,
    /// Bodies in contact where the motion started (it may separate them).
    start_contacts: Vec<crate::machine::collision::Contact>,
    /// An override changed while this motion runs: replan the rest at the next block
    /// boundary (where the exact-stop plan is at rest).
    retime: bool,
}

struct Held {
    blocks: Vec<MotionBlock>,
    kind: Kind,
    by_override: bool,
}

/// One executed program block's motion (or one of its dwells).
struct Item {
    blocks: Vec<MotionBlock>,
    dwell_s: f64,
    /// A canned cycle's dwell at the bottom: its phase, shown while it stands still.
    dwell_cycle: Option<CyclePhase>,
    stop: bool,
    optional_stop: bool,
    end: bool,
}

impl Item {
    fn motion(blocks: Vec<MotionBlock>) -> Self {
        Self {
            blocks,
            dwell_s: 0.0,
            dwell_cycle: None,
            stop: false,
            optional_stop: false,
            end: false,
        }
    }
}

struct AutoRun {
    items: VecDeque<Item>,
    /// Modal state after each line (for the active codes while running).
    modal: BTreeMap<usize, Modal>,
    stop_after_run: bool,
}

/// Longest motion played between two cuts of the stock (s): collisions stop the motion
/// within this time of simulated motion.
const CUT_PERIOD_S: f64 = 0.02;
/// The collision model of a configuration: the machine's bodies, the tool of the live stock
/// and the stock's bounding box, the fixtures.
fn collision_model(cfg: &ControlConfig) -> Option<crate::machine::collision::CollisionModel> {
    if !cfg.machine_collisions {
        return None;
    }
    let mut extras = cfg.fixtures.clone();
    let tool = cfg.stock.as_ref().map_or_else(Vec::new, |s| {
        let b = &s.stock.bounds;
        extras.extend(super::collide::stock_extra(b.min, b.max));
        crate::checks::collide::assembly(&s.cutter)
    });
    crate::machine::collision::CollisionModel::new(&cfg.machine, &tool, &extras)
}

/// How a program is read on a machine (the control's AUTO and MDI, `talas interpret`, `feed`
/// and `simulate` with `--machine`): the machine's kinematics for tilted work planes, `G28`
/// to its home switches, and the start at its home (where a homed control stands).
#[must_use]
pub fn machine_interpret_options(
    machine: &crate::machine::Machine,
    syntax: crate::gcode::Syntax,
) -> InterpretOptions {
    let cfg = ControlConfig::new(machine.clone());
    let home = cfg.home_position;
    let has = |c: char| machine.axis(c).is_some();
    InterpretOptions {
        start: Joints {
            xyz: DVec3::new(home[0], home[1], home[2]),
            a: has('A').then_some(home[3]),
            b: has('B').then_some(home[4]),
            c: has('C').then_some(home[5]),
        },
        g28_position: DVec3::new(home[0], home[1], home[2]),
        machine: Some(machine.clone()),
        ..InterpretOptions::for_syntax(syntax)
    }
}

/// Longest clock step inside [`Control::advance`] (s): peaks are recorded at this period.
const SUB_STEP_S: f64 = 1e-3;

/// The virtual control.
pub struct Control {
    cfg: ControlConfig,
    axes: Vec<(char, AxisLimit)>,
    clock: f64,
    mode: Mode,
    estop: bool,
    /// A collision stops all motion until reset.
    blocked: bool,
    homed: [bool; SLOTS],
    pos: JointVector,
    active: Option<Active>,
    held: Option<Held>,
    auto: Option<AutoRun>,
    stopped: bool,
    dwell_left: f64,
    /// The canned cycle's phase of the dwell under way (`None` for a `G4`).
    dwell_phase: Option<CyclePhase>,
    program: Option<(String, String)>,
    session: Session,
    mdi_count: usize,
    overrides: [f64; 3],
    increment: f64,
    jog_feed: f64,
    single_block: bool,
    optional_stop: bool,
    block_delete: bool,
    spindle_dir: f64,
    alarms: Vec<Alarm>,
    peaks: [[f64; 3]; SLOTS],
    home_queue: VecDeque<char>,
    mpg_pending: Option<(char, f64)>,
    /// Machine bodies, tool and table extras (when the machine has bodies).
    collide: Option<crate::machine::collision::CollisionModel>,
    /// The stock's cutting thread, when the stock is cut off this thread.
    worker: Option<cut::WorkerLink>,
    /// Steps the clock has taken in [`Control::advance`] (see [`Control::clock_steps`]).
    clock_steps: u64,
    /// The program and MDI blocks run to their end, when logged ([`Control::log_played`]).
    played: Option<Vec<MotionBlock>>,
}

impl Control {
    /// A control at power-on: position `cfg.start`, nothing homed, JOG mode.
    ///
    /// # Errors
    /// [`ControlError::Refused`] when the start position is not finite.
    pub fn new(cfg: ControlConfig) -> Result<Self, ControlError> {
        let axes = machine_limits(&cfg.machine);
        let pos = cfg.start;
        let mut control = Self {
            axes,
            clock: 0.0,
            mode: Mode::Jog,
            estop: false,
            blocked: false,
            homed: [false; SLOTS],
            pos,
            active: None,
            held: None,
            auto: None,
            stopped: false,
            dwell_left: 0.0,
            dwell_phase: None,
            program: None,
            session: Session::new(InterpretOptions::default())
                .map_err(|e| ControlError::Refused(e.to_string()))?,
            mdi_count: 0,
            overrides: [100.0; 3],
            increment: 1.0,
            jog_feed: cfg.jog_feed_mm_per_min,
            single_block: false,
            optional_stop: false,
            block_delete: true,
            spindle_dir: 0.0,
            alarms: Vec::new(),
            peaks: [[0.0; 3]; SLOTS],
            home_queue: VecDeque::new(),
            mpg_pending: None,
            collide: collision_model(&cfg),
            worker: None,
            clock_steps: 0,
            played: None,
            cfg,
        };
        control.session = Session::new(control.interp_options())
            .map_err(|e| ControlError::Refused(e.to_string()))?;
        Ok(control)
    }

    /// The interpreter's settings on this control: its work offsets, tool table, machine
    /// (tilted work planes) and home (`G28`), the syntax of the loaded program (detected from
    /// its text) — the same as `talas interpret --machine` reads a program with.
    fn interp_options(&self) -> InterpretOptions {
        let syntax = self
            .program
            .as_ref()
            .map_or(crate::gcode::Syntax::Rs274, |(_, t)| {
                crate::gcode::Syntax::detect(t)
            });
        let mut o = machine_interpret_options(&self.cfg.machine, syntax);
        o.start = self.joints(&self.pos);
        o.work_offsets = self.cfg.work_offsets;
        o.block_delete = self.block_delete;
        o.tool_table.clone_from(&self.cfg.tool_table);
        o
    }

    /// The machine.
    #[must_use]
    pub fn machine(&self) -> &crate::machine::Machine {
        &self.cfg.machine
    }

    /// The live stock, if any, when it is cut on this thread (`None` while a worker cuts it:
    /// see [`Control::start_cutting_worker`]).
    #[must_use]
    pub fn stock(&self) -> Option<&super::LiveStock> {
        self.cfg.stock.as_ref()
    }

    /// The fixtures and other solids on the table (table coordinates).
    #[must_use]
    pub fn fixtures(&self) -> &[crate::machine::collision::TableExtra] {
        &self.cfg.fixtures
    }

    /// Simulated time, s.
    #[must_use]
    pub fn time_s(&self) -> f64 {
        self.clock
    }

    /// Steps the simulated clock has taken so far: one per millisecond (at most) of motion
    /// played, one per dwell or stretch of standing still however long (the work a run did,
    /// for tests and benches: waiting costs nothing).
    #[must_use]
    pub fn clock_steps(&self) -> u64 {
        self.clock_steps
    }

    /// Machine position now (slots X Y Z A B C, mm and rad).
    #[must_use]
    pub fn position(&self) -> JointVector {
        self.active
            .as_ref()
            .map_or(self.pos, |a| a.run.kinematics().position)
    }

    /// Axis state now (zero velocities when standing).
    #[must_use]
    pub fn kinematics(&self) -> super::Kinematics {
        self.active.as_ref().map_or(
            super::Kinematics {
                position: self.pos,
                ..super::Kinematics::default()
            },
            |a| a.run.kinematics(),
        )
    }

    /// Alarms since the last reset.
    #[must_use]
    pub fn alarms(&self) -> &[Alarm] {
        &self.alarms
    }

    /// Whether nothing moves and nothing waits to move by itself (a dwell, the next homing
    /// axis, the next AUTO stretch) or to be cut by the worker.
    #[must_use]
    pub fn is_idle(&self) -> bool {
        self.active.is_none()
            && self.cuts_pending() == 0
            && self.dwell_left <= 0.0
            && self.home_queue.is_empty()
            && self.mpg_pending.is_none()
    }

    /// The run state.
    #[must_use]
    pub fn run_state(&self) -> RunState {
        if self.estop {
            return RunState::EStop;
        }
        match &self.active {
            Some(a) if a.run.braking() => RunState::Braking,
            Some(_) => RunState::Moving,
            None if self.held.is_some() => RunState::Held,
            None if self.dwell_left > 0.0 => RunState::Dwell,
            None if self.stopped => RunState::Stopped,
            None => RunState::Idle,
        }
    }

    /// Highest |velocity|, |acceleration|, |jerk| reached per axis (mm, deg).
    #[must_use]
    pub fn peaks(&self) -> Vec<Peak> {
        self.cfg
            .machine
            .axes
            .iter()
            .filter_map(|a| {
                let k = slot_of(a.name)?;
                let s = if a.is_rotary() {
                    180.0 / std::f64::consts::PI
                } else {
                    1.0
                };
                let p = self.peaks.get(k)?;
                Some(Peak {
                    axis: a.name,
                    velocity: p[0] * s,
                    acceleration: p[1] * s,
                    jerk: p[2] * s,
                })
            })
            .collect()
    }

    fn joints(&self, p: &JointVector) -> Joints {
        let has = |c: char| self.cfg.machine.axis(c).is_some();
        Joints {
            xyz: DVec3::new(p[0], p[1], p[2]),
            a: has('A').then_some(p[3]),
            b: has('B').then_some(p[4]),
            c: has('C').then_some(p[5]),
        }
    }

    fn alarm(&mut self, code: u32, text: String) -> &mut Alarm {
        self.alarms.push(Alarm {
            code,
            text,
            axis: None,
            bodies: Vec::new(),
            position: None,
            line: None,
            t_s: self.clock,
        });
        let last = self.alarms.len() - 1;
        &mut self.alarms[last]
    }

    /// Apply one operator action.
    ///
    /// # Errors
    /// [`ControlError::Refused`] when the action does not fit the mode or state, or a value is
    /// out of range (nothing changes then). Problems of the machine or the program (soft
    /// limits, travel, G-code errors, collisions) are alarms, not errors.
    pub fn apply(&mut self, action: Action) -> Result<(), ControlError> {
        match action {
            Action::SetMode(m) => self.set_mode(m),
            Action::Home => self.home(),
            Action::JogStart { axis, direction } => self.jog_start(axis, direction),
            Action::JogStop => {
                if let Some(a) = &mut self.active
                    && a.kind == (Kind::Jog { continuous: true })
                {
                    a.after_brake = AfterBrake::Discard;
                    a.run.start_brake();
                }
                Ok(())
            }
            Action::JogIncrement { axis, direction } => {
                let d = self.increment * direction.signum();
                self.jog_by(axis, d, Kind::Jog { continuous: false })
            }
            Action::JogDistance { axis, distance } => {
                self.jog_by(axis, distance, Kind::Jog { continuous: false })
            }
            Action::SetIncrement(v) => {
                if !(v > 0.0 && v <= 1000.0) {
                    return refuse(format!("increment {v} must lie in (0, 1000] mm or deg"));
                }
                self.increment = v;
                Ok(())
            }
            Action::Mpg { axis, detents } => self.mpg(axis, detents),
            Action::Mdi(line) => self.mdi(&line),
            Action::LoadProgram { name, text } => {
                if self.auto.is_some() || self.active.is_some() {
                    return refuse("a program cannot be loaded while one runs");
                }
                self.program = Some((name, text));
                Ok(())
            }
            Action::CycleStart | Action::Resume => self.cycle_start(1),
            Action::RunFromLine(line) => {
                if self.auto.is_some() || self.held.is_some() {
                    return refuse(
                        "run from line starts a program at rest: stop the one running first",
                    );
                }
                self.cycle_start(line)
            }
            Action::FeedHold => {
                self.hold(false);
                Ok(())
            }
            Action::Stop => {
                self.stop_all();
                Ok(())
            }
            Action::Reset => {
                self.wait_for_cutting();
                self.resume_cutting();
                self.stop_all();
                self.alarms.clear();
                self.estop = false;
                self.blocked = false;
                Ok(())
            }
            Action::EStop => {
                self.stop_all();
                self.estop = true;
                let p = self.position();
                self.alarm(codes::ESTOP, "emergency stop".into()).position =
                    Some([p[0], p[1], p[2]]);
                Ok(())
            }
            Action::Override(kind, pct) => self.set_override(kind, pct),
            Action::Spindle(s) => {
                if self.estop {
                    return refuse("emergency stop is latched: reset first");
                }
                self.spindle_dir = match s {
                    Spindle::Cw => 1.0,
                    Spindle::Ccw => -1.0,
                    Spindle::Stop => 0.0,
                };
                self.session.set_spindle_direction(self.spindle_dir);
                Ok(())
            }
            Action::SingleBlock(on) => {
                self.single_block = on;
                Ok(())
            }
            Action::OptionalStop(on) => {
                self.optional_stop = on;
                Ok(())
            }
            Action::BlockDelete(on) => {
                self.block_delete = on;
                self.session.set_block_delete(on);
                Ok(())
            }
            Action::JogFeed(f) => {
                if !(f > 0.0 && f <= 1e6) {
                    return refuse(format!("jog feed {f} mm/min must lie in (0, 1e6]"));
                }
                self.jog_feed = f;
                Ok(())
            }
        }
    }

    fn busy(&self) -> bool {
        !self.is_idle() || self.held.is_some() || self.auto.is_some()
    }

    fn can_move(&self) -> Result<(), ControlError> {
        if self.estop {
            return refuse("emergency stop is latched: reset first");
        }
        if self.blocked {
            return refuse("a collision alarm stops all motion: reset first");
        }
        Ok(())
    }

    fn set_mode(&mut self, m: Mode) -> Result<(), ControlError> {
        if m != self.mode && self.busy() {
            return refuse("the mode cannot change while a motion or program is active");
        }
        self.mode = m;
        Ok(())
    }

    /// What a panel shows now.
    #[must_use]
    pub fn snapshot(&self) -> Snapshot {
        let p = self.position();
        let running = self.active.as_ref();
        // The block being run, or during a feed hold the one it stopped in (the first left):
        // the active codes and the line are the program's there, not the MDI session's.
        let block = running
            .and_then(|a| a.run.current_block().and_then(|i| a.run.blocks().get(i)))
            .or_else(|| self.held.as_ref().and_then(|h| h.blocks.first()));
        let line = match (block, self.mode) {
            (Some(b), _) if b.source_line > 0 => Some(b.source_line),
            (_, Mode::Mdi) if self.mdi_count > 0 => Some(self.mdi_count),
            _ => None,
        };
        let modal = match (&self.auto, line) {
            (Some(run), Some(l)) => run.modal.range(..=l).next_back().map(|(_, m)| m.clone()),
            _ => None,
        }
        .unwrap_or_else(|| self.session.modal());
        let offset = self
            .cfg
            .work_offsets
            .get(modal.work_offset)
            .copied()
            .unwrap_or(DVec3::ZERO);
        let end = running
            .and_then(|a| a.run.blocks().last())
            .or_else(|| self.held.as_ref().and_then(|h| h.blocks.last()))
            .map_or(p, |b| joint_vector(&b.end));
        let mut snap = Snapshot {
            time_s: self.clock,
            mode: self.mode,
            state: self.run_state(),
            axes: Vec::new(),
            machine_position: Vec::new(),
            work_position: Vec::new(),
            distance_to_go: Vec::new(),
            homed: Vec::new(),
            active_codes: modal.codes(),
            feed_programmed_mm_per_min: block
                .map_or(modal.feed.unwrap_or(0.0), |b| b.feed_mm_per_min),
            feed_actual_mm_per_min: self.kinematics().feed * 60.0,
            spindle_programmed_rpm: modal.spindle_rpm,
            spindle_actual_rpm: modal.spindle_rpm * self.overrides[2] / 100.0
                * if self.auto.is_some() {
                    modal.spindle_direction
                } else {
                    self.spindle_dir
                },
            overrides_pct: self.overrides,
            line,
            alarms: self.alarms.clone(),
            increment: self.increment,
            removed_volume_mm3: self.removed_mm3(),
            // A move's phase, or while the machine stands still in a cycle's dwell, the dwell.
            cycle: block
                .and_then(|b| b.cycle)
                .or(if running.is_none() && self.dwell_left > 0.0 {
                    self.dwell_phase
                } else {
                    None
                }),
        };
        for a in &self.cfg.machine.axes {
            let Some(k) = slot_of(a.name) else {
                continue;
            };
            let s = if a.is_rotary() {
                180.0 / std::f64::consts::PI
            } else {
                1.0
            };
            let off = if k < 3 { offset[k] } else { 0.0 };
            snap.axes.push(a.name);
            snap.machine_position.push(p[k] * s);
            snap.work_position.push((p[k] - off) * s);
            snap.distance_to_go.push((end[k] - p[k]) * s);
            snap.homed.push(self.homed[k]);
        }
        snap
    }
}
