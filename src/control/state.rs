//! The control's state machine: actions in, motion on the simulated clock, snapshots out.

use std::collections::{BTreeMap, VecDeque};

use glam::DVec3;

use super::motion::Run;
use super::{
    Action, Alarm, ControlConfig, Mode, OverrideKind, Peak, RunState, Snapshot, Spindle, codes,
};
use crate::feed::path::{JointVector, SLOTS, joint_vector, slot_of};
use crate::feed::{AxisLimit, machine_limits, travel_violations};
use crate::gcode::{InterpretOptions, Joints, Modal, MotionBlock, MotionKind, Session};

mod cut;

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

/// One interpreted program line.
struct Item {
    blocks: Vec<MotionBlock>,
    dwell_s: f64,
    stop: bool,
    optional_stop: bool,
    end: bool,
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
        super::collide::cutter_cylinders(&s.cutter)
    });
    crate::machine::collision::CollisionModel::new(&cfg.machine, &tool, &extras)
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
            cfg,
        };
        control.session = Session::new(control.interp_options())
            .map_err(|e| ControlError::Refused(e.to_string()))?;
        Ok(control)
    }

    fn interp_options(&self) -> InterpretOptions {
        InterpretOptions {
            start: self.joints(&self.pos),
            work_offsets: self.cfg.work_offsets,
            block_delete: self.block_delete,
            ..InterpretOptions::default()
        }
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

    fn home(&mut self) -> Result<(), ControlError> {
        self.can_move()?;
        if self.busy() {
            return refuse("homing needs the machine at rest");
        }
        self.mode = Mode::Ref;
        self.home_queue = self.cfg.home_order.iter().copied().collect();
        self.next_home_axis();
        Ok(())
    }

    fn next_home_axis(&mut self) {
        let Some(axis) = self.home_queue.pop_front() else {
            return;
        };
        let Some(k) = slot_of(axis) else {
            return;
        };
        let mut target = self.pos;
        target[k] = self.cfg.home_position[k];
        let feed = self.axis_feed(axis, self.cfg.home_feed_mm_per_min);
        let block = self.line_block(&target, feed, 0);
        self.start_run(vec![block], Kind::Home(axis), None);
    }

    /// A jog-style feed in the block's units: mm/min, or rad/min on a rotary axis (the
    /// planner measures a rotary-only block in rad).
    fn axis_feed(&self, axis: char, feed_mm_per_min: f64) -> f64 {
        if matches!(axis, 'A' | 'B' | 'C') {
            feed_mm_per_min.to_radians()
        } else {
            feed_mm_per_min
        }
    }

    fn line_block(&self, target: &JointVector, feed: f64, line: usize) -> MotionBlock {
        MotionBlock {
            kind: MotionKind::Linear,
            start: self.joints(&self.pos),
            end: self.joints(target),
            feed_mm_per_min: feed,
            inverse_time: false,
            source_line: line,
            tool: 0,
            tool_length_h: None,
            spindle_rpm: 0.0,
            coolant: false,
            tcp: false,
        }
    }

    /// The target of a jog by `d` (mm or deg) clamped to the travel, and the limit it stops at.
    fn jog_target(
        &self,
        axis: char,
        d: f64,
    ) -> Result<(JointVector, Option<(char, f64)>), ControlError> {
        if !d.is_finite() {
            return refuse(format!("jog distance {d} is not a number"));
        }
        if axis == super::tool_axis::TOOL_AXIS {
            return Ok(super::tool_axis::tool_axis_target(
                &self.cfg.machine,
                &self.pos,
                d,
            ));
        }
        let (Some(ax), Some(k)) = (self.cfg.machine.axis(axis), slot_of(axis)) else {
            return refuse(format!("the machine has no axis {axis}"));
        };
        let d = if ax.is_rotary() { d.to_radians() } else { d };
        let mut target = self.pos;
        let want = self.pos[k] + d;
        target[k] = want.clamp(ax.min, ax.max);
        let scale = if ax.is_rotary() {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        };
        let limit = (target[k] != want).then_some((axis, target[k] * scale));
        Ok((target, limit))
    }

    fn jog_by(&mut self, axis: char, d: f64, kind: Kind) -> Result<(), ControlError> {
        self.can_move()?;
        if !matches!(self.mode, Mode::Jog | Mode::Mpg) {
            return refuse("jogging needs JOG or MPG mode");
        }
        if self.busy() {
            // A key pressed again while the axis moves does not queue a move.
            return Ok(());
        }
        let (target, limit) = self.jog_target(axis, d)?;
        self.start_jog(axis, target, limit, kind);
        Ok(())
    }

    fn start_jog(
        &mut self,
        axis: char,
        target: JointVector,
        limit: Option<(char, f64)>,
        kind: Kind,
    ) {
        let still = target
            .iter()
            .zip(&self.pos)
            .all(|(t, p)| (t - p).abs() <= 1e-12);
        if still {
            if let Some((axis, lim)) = limit {
                self.soft_limit_alarm(axis, lim);
            }
            return;
        }
        let feed = self.axis_feed(axis, self.jog_feed);
        let block = self.line_block(&target, feed, 0);
        self.start_run(vec![block], kind, limit);
    }

    fn soft_limit_alarm(&mut self, axis: char, limit: f64) {
        let unit = if matches!(axis, 'A' | 'B' | 'C') {
            "°"
        } else {
            " mm"
        };
        let p = self.position();
        let a = self.alarm(
            codes::SOFT_LIMIT,
            format!("axis {axis} stopped at its soft limit {limit:.4}{unit}"),
        );
        a.axis = Some(axis);
        a.position = Some([p[0], p[1], p[2]]);
    }

    fn jog_start(&mut self, axis: char, direction: f64) -> Result<(), ControlError> {
        self.can_move()?;
        if self.mode != Mode::Jog {
            return refuse("continuous jog needs JOG mode");
        }
        if self.busy() {
            // Held keys and auto-repeat never queue moves.
            return Ok(());
        }
        // Planned to the boundary: the whole travel in the jog direction.
        let (target, limit) = self.jog_target(axis, direction.signum() * 1e9)?;
        self.start_jog(axis, target, limit, Kind::Jog { continuous: true });
        Ok(())
    }

    fn mpg(&mut self, axis: char, detents: i32) -> Result<(), ControlError> {
        self.can_move()?;
        if self.mode != Mode::Mpg {
            return refuse("the handwheel needs MPG mode");
        }
        let d = f64::from(detents) * self.increment;
        let moving_this = self
            .active
            .as_ref()
            .is_some_and(|a| a.kind == Kind::Mpg(axis) && !a.run.braking());
        if moving_this {
            // Position mode: detents turned while the axis moves are added to its target.
            match &mut self.mpg_pending {
                Some((pa, pd)) if *pa == axis => *pd += d,
                Some(_) => {}
                None => self.mpg_pending = Some((axis, d)),
            }
            return Ok(());
        }
        if self.busy() {
            return Ok(());
        }
        let (target, limit) = self.jog_target(axis, d)?;
        self.start_jog(axis, target, limit, Kind::Mpg(axis));
        Ok(())
    }

    fn homed_all(&self) -> bool {
        self.cfg
            .machine
            .axes
            .iter()
            .all(|a| slot_of(a.name).is_some_and(|k| self.homed[k]))
    }

    fn mdi(&mut self, line: &str) -> Result<(), ControlError> {
        self.can_move()?;
        if self.mode != Mode::Mdi {
            return refuse("MDI lines need MDI mode");
        }
        if self.busy() {
            return refuse("an MDI line waits for the machine to come to rest");
        }
        if !self.homed_all() {
            self.alarm(codes::NOT_HOMED, "home the machine before MDI".into());
            return Ok(());
        }
        self.mdi_count += 1;
        let n = self.mdi_count;
        self.session.set_position(self.joints(&self.pos));
        let result = match self.session.run_line(line, n) {
            Ok(r) => r,
            Err(e) => {
                self.alarm(codes::GCODE, format!("MDI {e}")).line = Some(n);
                return Ok(());
            }
        };
        self.spindle_dir = self.session.modal().spindle_direction;
        if !self.travel_ok(&result.program.blocks) {
            self.session.set_position(self.joints(&self.pos));
            return Ok(());
        }
        let dwell: f64 = result.program.dwells.iter().map(|d| d.seconds).sum();
        self.dwell_left += dwell;
        if !result.program.blocks.is_empty() {
            self.start_run(result.program.blocks, Kind::Mdi, None);
        }
        Ok(())
    }

    /// Refuse motion leaving the travel with an alarm naming the first block and axis.
    fn travel_ok(&mut self, blocks: &[MotionBlock]) -> bool {
        let (v, _) = travel_violations(blocks, &self.cfg.machine, 1);
        let Some(v) = v.first() else {
            return true;
        };
        let unit = if matches!(v.axis, 'A' | 'B' | 'C') {
            "°"
        } else {
            " mm"
        };
        let a = self.alarm(
            codes::TRAVEL,
            format!(
                "line {}: axis {} would reach {:.4}{unit}, beyond its travel limit {:.4}{unit}; \
                 refused before it started",
                v.line, v.axis, v.value, v.limit
            ),
        );
        a.axis = Some(v.axis);
        a.line = Some(v.line);
        false
    }

    fn cycle_start(&mut self, from_line: usize) -> Result<(), ControlError> {
        self.can_move()?;
        if let Some(h) = self.held.take() {
            if self.active.is_some() {
                self.held = Some(h);
                return refuse("still braking");
            }
            if h.by_override && (self.overrides[0] <= 0.0 || self.overrides[1] <= 0.0) {
                self.held = Some(h);
                return refuse("a 0 % override holds the motion: raise it to resume");
            }
            self.start_run(h.blocks, h.kind, None);
            return Ok(());
        }
        if self.mode != Mode::Auto {
            return refuse("cycle start runs a program in AUTO mode (or resumes a hold)");
        }
        if self.auto.is_some() {
            if self.stopped && self.is_idle() {
                self.stopped = false;
                self.auto_next();
            }
            return Ok(());
        }
        if !self.is_idle() {
            return refuse("the machine is moving");
        }
        if !self.homed_all() {
            self.alarm(codes::NOT_HOMED, "home the machine before AUTO".into());
            return Ok(());
        }
        let Some((name, text)) = self.program.clone() else {
            return refuse("no program loaded");
        };
        if let Some(run) = self.interpret_program(&name, &text, from_line.max(1)) {
            self.auto = Some(run);
            self.stopped = false;
            self.auto_next();
        }
        Ok(())
    }

    /// The whole program interpreted from the present position, checked against the travel.
    ///
    /// Run from line: the lines before `from_line` are interpreted for their modal state only
    /// (units, plane, distance mode, offsets, feed, spindle, tool, TCP), without motion; the
    /// first block from `from_line` on starts at the present position.
    fn interpret_program(&mut self, name: &str, text: &str, from_line: usize) -> Option<AutoRun> {
        let Ok(mut session) = Session::new(self.interp_options()) else {
            return None;
        };
        let mut run = AutoRun {
            items: VecDeque::new(),
            modal: BTreeMap::new(),
            stop_after_run: false,
        };
        let mut all = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let r = match session.run_line(raw, i + 1) {
                Ok(r) => r,
                Err(e) => {
                    self.alarm(codes::GCODE, format!("{name}: {e}")).line = Some(e.line);
                    return None;
                }
            };
            if i + 2 == from_line {
                session.set_position(self.joints(&self.pos));
            }
            if r.program_end && i + 1 < from_line {
                let text = format!(
                    "{name}: the program ends at line {} before line {from_line}",
                    i + 1
                );
                self.alarm(codes::GCODE, text).line = Some(from_line);
                return None;
            }
            if i + 1 < from_line {
                continue;
            }
            run.modal.insert(i + 1, session.modal());
            all.extend(r.program.blocks.iter().cloned());
            run.items.push_back(Item {
                blocks: r.program.blocks,
                dwell_s: r.program.dwells.iter().map(|d| d.seconds).sum(),
                stop: r.program_stop,
                optional_stop: r.optional_stop,
                end: r.program_end,
            });
            if r.program_end {
                break;
            }
        }
        self.travel_ok(&all).then_some(run)
    }

    /// Start the next stretch of the program: blocks up to a stop, a dwell or the end.
    fn auto_next(&mut self) {
        let single = self.single_block;
        let optional = self.optional_stop;
        let Some(auto) = &mut self.auto else {
            return;
        };
        let mut chunk: Vec<MotionBlock> = Vec::new();
        let mut stop_after = false;
        let mut dwell = 0.0;
        while let Some(item) = auto.items.front() {
            if item.dwell_s > 0.0 && !chunk.is_empty() {
                break;
            }
            let Some(item) = auto.items.pop_front() else {
                break;
            };
            if item.dwell_s > 0.0 {
                dwell = item.dwell_s;
                break;
            }
            let moved = !item.blocks.is_empty();
            chunk.extend(item.blocks);
            if item.stop || (item.optional_stop && optional) || (single && moved) {
                stop_after = true;
                break;
            }
            if item.end {
                auto.items.clear();
                break;
            }
        }
        auto.stop_after_run = stop_after;
        let finished = auto.items.is_empty() && !stop_after && dwell <= 0.0;
        if dwell > 0.0 {
            self.dwell_left = dwell;
            return;
        }
        if chunk.is_empty() {
            if stop_after {
                self.stopped = true;
            } else if finished {
                self.auto = None;
            }
            return;
        }
        if finished {
            auto.stop_after_run = false;
        }
        self.start_run(chunk, Kind::Auto, None);
    }

    fn set_override(&mut self, kind: OverrideKind, pct: f64) -> Result<(), ControlError> {
        let ok = match kind {
            OverrideKind::Feed => (0.0..=150.0).contains(&pct),
            OverrideKind::Rapid => [0.0, 25.0, 50.0, 100.0].contains(&pct),
            OverrideKind::Spindle => (50.0..=120.0).contains(&pct),
        };
        if !ok {
            return refuse(match kind {
                OverrideKind::Feed => format!("feed override {pct} % must lie in 0–150 %"),
                OverrideKind::Rapid => format!("rapid override {pct} % must be 0, 25, 50 or 100 %"),
                OverrideKind::Spindle => format!("spindle override {pct} % must lie in 50–120 %"),
            });
        }
        let i = match kind {
            OverrideKind::Feed => 0,
            OverrideKind::Rapid => 1,
            OverrideKind::Spindle => 2,
        };
        let changed = self.overrides[i] != pct;
        self.overrides[i] = pct;
        if let Some(a) = &mut self.active
            && i < 2
            && pct > 0.0
            && changed
            && matches!(a.kind, Kind::Auto | Kind::Mdi)
            && !a.run.braking()
        {
            a.retime = true;
        }
        if i < 2 && pct <= 0.0 {
            self.hold(true);
        } else if i < 2
            && self.overrides[0] > 0.0
            && self.overrides[1] > 0.0
            && let Some(h) = self.held.take()
        {
            if h.by_override && self.active.is_none() {
                self.start_run(h.blocks, h.kind, None);
            } else {
                self.held = Some(h);
            }
        }
        Ok(())
    }

    /// Feed hold: AUTO and MDI motion brakes and waits for a resume; jogs and homing stop.
    fn hold(&mut self, by_override: bool) {
        let Some(a) = &mut self.active else {
            return;
        };
        if a.run.braking() {
            return;
        }
        a.after_brake = match a.kind {
            Kind::Auto | Kind::Mdi => AfterBrake::Hold { by_override },
            _ => AfterBrake::Discard,
        };
        if a.after_brake == AfterBrake::Discard {
            self.home_queue.clear();
            self.mpg_pending = None;
        }
        a.run.start_brake();
    }

    /// Brake whatever moves and abandon it, the program and everything queued.
    fn stop_all(&mut self) {
        if let Some(a) = &mut self.active {
            a.after_brake = AfterBrake::Discard;
            a.run.start_brake();
        }
        self.auto = None;
        self.held = None;
        self.stopped = false;
        self.dwell_left = 0.0;
        self.home_queue.clear();
        self.mpg_pending = None;
    }

    /// The blocks as the planner gets them: feeds scaled by the overrides, rapids slowed by
    /// the rapid override (as a fed move at that fraction of the fastest the axes allow).
    fn planned_copy(&self, blocks: &[MotionBlock], kind: Kind) -> Vec<MotionBlock> {
        let program = matches!(kind, Kind::Auto | Kind::Mdi);
        let (feed, rapid) = (self.overrides[0] / 100.0, self.overrides[1] / 100.0);
        blocks
            .iter()
            .map(|b| {
                let mut c = b.clone();
                if !program {
                    return c;
                }
                if matches!(b.kind, MotionKind::Rapid) {
                    if rapid < 1.0 {
                        c.kind = MotionKind::Linear;
                        c.inverse_time = false;
                        c.feed_mm_per_min = rapid * self.fastest_mm_per_min(b);
                    }
                } else {
                    c.feed_mm_per_min *= feed;
                }
                c
            })
            .collect()
    }

    /// The fastest path feed of a straight block that keeps every axis within its velocity.
    fn fastest_mm_per_min(&self, b: &MotionBlock) -> f64 {
        let (s, e) = (joint_vector(&b.start), joint_vector(&b.end));
        let xyz = b.length_mm();
        let rot = (3..SLOTS)
            .map(|k| (e[k] - s[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let len = if xyz > 1e-12 { xyz } else { rot };
        let mut v = f64::INFINITY;
        for (name, lim) in &self.axes {
            if let Some(k) = slot_of(*name) {
                let d1 = (e[k] - s[k]).abs() / len.max(1e-300);
                if d1 > 0.0 {
                    v = v.min(lim.velocity / d1);
                }
            }
        }
        if v.is_finite() { v * 60.0 } else { 1.0 }
    }

    fn start_run(&mut self, blocks: Vec<MotionBlock>, kind: Kind, limit: Option<(char, f64)>) {
        let program = matches!(kind, Kind::Auto | Kind::Mdi);
        if program && (self.overrides[0] <= 0.0 || self.overrides[1] <= 0.0) {
            self.held = Some(Held {
                blocks,
                kind,
                by_override: true,
            });
            return;
        }
        let planned = self.planned_copy(&blocks, kind);
        match Run::plan(blocks, &planned, &self.axes) {
            Ok(run) => {
                self.active = Some(Active {
                    run,
                    kind,
                    after_brake: AfterBrake::Discard,
                    limit_alarm: limit,
                    cut_s: 0.0,
                    since_cut: 0.0,
                    check_s: 0.0,
                    check_pos: self.pos,
                    retime: false,
                    start_contacts: self.collide.as_ref().map_or_else(Vec::new, |m| {
                        let j = super::collide::machine_joints(&self.cfg.machine, &self.pos);
                        m.contacts(&self.cfg.machine, &j)
                    }),
                });
            }
            Err(e) => {
                self.alarm(codes::PLAN, format!("the motion cannot be planned: {e}"));
                self.auto = None;
                self.home_queue.clear();
            }
        }
    }

    /// Run the simulated clock on by `dt` seconds (motion, dwells, cutting).
    pub fn advance(&mut self, dt: f64) {
        if !(dt > 0.0) || !dt.is_finite() {
            return;
        }
        let mut left = dt;
        while left > 1e-12 {
            if self.active.is_some() && !self.cutting_keeps_up() {
                // The motion waits for the cutting worker.
                return;
            }
            if self.active.as_ref().is_some_and(|a| a.run.finished()) {
                self.finish_active();
                continue;
            }
            let Some(a) = &mut self.active else {
                if self.dwell_left > 0.0 {
                    let h = left.min(self.dwell_left);
                    self.dwell_left -= h;
                    self.clock += h;
                    left -= h;
                    if self.dwell_left <= 1e-12 {
                        self.dwell_left = 0.0;
                        self.auto_next();
                    }
                    continue;
                }
                self.clock += left;
                break;
            };
            let retime = a.retime;
            let used = if retime {
                a.run.step_within_segment(left.min(SUB_STEP_S))
            } else {
                a.run.step(left.min(SUB_STEP_S))
            };
            a.since_cut += used;
            self.clock += used;
            left -= used;
            let k = a.run.kinematics();
            let cut_due = a.since_cut >= CUT_PERIOD_S;
            let check_due = super::collide::due(&a.check_pos, &k.position);
            for i in 0..SLOTS {
                let p = &mut self.peaks[i];
                p[0] = p[0].max(k.velocity[i].abs());
                p[1] = p[1].max(k.acceleration[i].abs());
                p[2] = p[2].max(k.jerk[i].abs());
            }
            if check_due {
                self.check_machine();
            }
            if cut_due {
                self.cut_pending();
            }
            if retime
                && self
                    .active
                    .as_ref()
                    .is_some_and(|a| a.run.at_segment_boundary())
            {
                self.retime_rest();
            }
        }
        if self.active.as_ref().is_some_and(|a| a.run.finished()) {
            self.finish_active();
        }
        self.poll_cutting();
    }

    /// Run the clock in steps of a millisecond until the control is idle (or `max_s` has
    /// passed); returns the time run.
    pub fn advance_until_idle(&mut self, max_s: f64) -> f64 {
        let t0 = self.clock;
        while !self.is_idle() && self.clock - t0 < max_s {
            self.advance(SUB_STEP_S);
        }
        self.clock - t0
    }

    /// Cut whatever motion has not been cut into the stock yet (the stock is otherwise cut
    /// every 20 ms of motion and at the end of each motion).
    pub fn flush_cutting(&mut self) {
        self.cut_pending();
        self.wait_for_cutting();
    }

    /// Test the motion played since the last test for machine collisions; the first contact
    /// becomes an alarm and stops the machine.
    fn check_machine(&mut self) {
        let (Some(a), Some(model)) = (&mut self.active, &self.collide) else {
            return;
        };
        if self.blocked {
            return;
        }
        let s1 = a.run.path_position();
        let s0 = a.check_s.min(s1);
        a.check_s = s1;
        a.check_pos = a.run.position_at(s1);
        let machine = &self.cfg.machine;
        let run = &a.run;
        let Some((s, contacts)) = super::collide::first_contact_along(
            model,
            machine,
            |u| run.position_at(u),
            (s0, s1),
            &a.start_contacts,
        ) else {
            return;
        };
        let p = run.position_at(s);
        let line = run
            .block_at(s)
            .and_then(|i| run.blocks().get(i))
            .map(|b| b.source_line)
            .filter(|&l| l > 0);
        let pairs: Vec<String> = contacts
            .iter()
            .map(|c| format!("{} against {}", c.bodies[0], c.bodies[1]))
            .collect();
        let where_ = line.map_or(String::new(), |l| format!("line {l}: "));
        let text = format!(
            "{where_}collision: {} at {}",
            pairs.join(", "),
            super::collide::describe_position(machine, &p)
        );
        let bodies = contacts
            .first()
            .map(|c| c.bodies.to_vec())
            .unwrap_or_default();
        let al = self.alarm(codes::COLLISION_MACHINE, text);
        al.bodies = bodies;
        al.position = Some([p[0], p[1], p[2]]);
        al.line = line;
        self.blocked = true;
        self.stop_all();
    }

    /// At rest between two blocks after an override change: the rest of the motion is
    /// planned again with the overrides now set.
    fn retime_rest(&mut self) {
        self.check_machine();
        self.cut_pending();
        self.wait_for_cutting();
        let Some(a) = self.active.take() else {
            return;
        };
        self.pos = a.run.kinematics().position;
        self.session.set_position(self.joints(&self.pos));
        let blocks = a.run.remaining_blocks();
        if blocks.is_empty() || self.blocked {
            self.active = Some(a);
            return;
        }
        self.start_run(blocks, a.kind, a.limit_alarm);
    }

    /// The motion has ended (or braked to rest): settle the position and go on.
    fn finish_active(&mut self) {
        self.check_machine();
        self.cut_pending();
        self.wait_for_cutting();
        let Some(a) = self.active.take() else {
            return;
        };
        self.pos = a.run.kinematics().position;
        self.session.set_position(self.joints(&self.pos));
        if a.run.braking() {
            if let AfterBrake::Hold { by_override } = a.after_brake {
                let blocks = a.run.remaining_blocks();
                if !blocks.is_empty() {
                    self.held = Some(Held {
                        blocks,
                        kind: a.kind,
                        by_override,
                    });
                    return;
                }
            } else {
                if a.kind == Kind::Auto {
                    self.auto = None;
                }
                return;
            }
        }
        if let Some((axis, limit)) = a.limit_alarm {
            self.soft_limit_alarm(axis, limit);
        }
        match a.kind {
            Kind::Home(axis) => {
                if let Some(k) = slot_of(axis) {
                    self.homed[k] = true;
                }
                self.next_home_axis();
            }
            Kind::Auto => {
                if self.auto.as_ref().is_some_and(|r| r.stop_after_run) {
                    self.stopped = true;
                } else {
                    self.auto_next();
                }
            }
            Kind::Mpg(axis) => {
                if let Some((_, d)) = self.mpg_pending.take()
                    && let Ok((target, limit)) = self.jog_target(axis, d)
                {
                    self.start_jog(axis, target, limit, Kind::Mpg(axis));
                }
            }
            Kind::Jog { .. } | Kind::Mdi => {}
        }
    }

    /// What a panel shows now.
    #[must_use]
    pub fn snapshot(&self) -> Snapshot {
        let p = self.position();
        let running = self.active.as_ref();
        let block = running.and_then(|a| a.run.current_block().and_then(|i| a.run.blocks().get(i)));
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
