//! The virtual machine control (L5): one state machine that an operator panel, the command
//! line and the tests drive alike.
//!
//! ```text
//! Action ─apply─▶ Control ─advance(dt)─▶ motion on the simulated clock ─▶ Snapshot (DRO, codes,
//!                   │                      (feed planner, jerk-limited)     alarms, peaks)
//!                   └─ gcode::Session (MDI, AUTO) ── live cutting (simulation) ─┘
//! ```
//!
//! - Modes: REF (homing each axis to its switch in the homing order), JOG (continuous and
//!   incremental), MPG (handwheel detents × increment), MDI (lines through
//!   [`crate::gcode::Session`], modal state kept between lines), AUTO (a loaded program; single
//!   block, optional stop `M1`, block delete).
//! - Every motion is a set of motion blocks planned by [`crate::feed::plan`] (exact stop at
//!   corners) and played on the simulated clock; feed hold, stop, jog release and e-stop brake
//!   on the jerk-limited stop along the path ([`motion`]), so no axis leaves its velocity,
//!   acceleration and jerk limits; e-stop is a category-1 stop (controlled braking, then the
//!   latch).
//! - Continuous jog is one move planned to the soft limit: released, it brakes; held, it ends
//!   exactly at the limit with alarm [`codes::SOFT_LIMIT`]. A jog key pressed while a jog is
//!   running is ignored (nothing queues). Incremental jogs beyond the travel end at the limit
//!   with the same alarm. MPG detents turned while the axis moves are added to its target
//!   (position mode: no count is lost).
//! - Jogs along the tool axis use the pseudo-axis [`tool_axis::TOOL_AXIS`] (`T`) in the jog
//!   actions: the tool tip moves along the tool's axis with the rotaries standing.
//! - MDI and AUTO motion is checked against the travel before it starts
//!   ([`crate::feed::travel_violations`]); a block that would leave it is refused with alarm
//!   [`codes::TRAVEL`] naming the line and axis.
//! - Overrides: feed 0–150 % (fed moves), rapid 0/25/50/100 % (rapids), spindle 50–120 %.
//!   They are applied when a motion is planned (each AUTO stretch between stops, each MDI
//!   line, each resume); a change while a program or MDI motion runs replans the rest of it
//!   at the next block boundary (where the exact-stop plan is at rest), so the block under
//!   way keeps its speed. 0 % holds the motion and a non-zero value resumes it.
//! - A fed move that removes material while the spindle stands (M5, never started, 0 rpm;
//!   jogs: the spindle buttons) raises [`codes::SPINDLE_STOPPED`] naming the line and stops.
//! - With a stock and a tool, every piece of motion played is cut into the dexel stock
//!   ([`cutting`]); a rapid through material or a holder/shank in material stops the motion
//!   with a collision alarm naming the bodies, the line and the position. The pieces continue
//!   each other (arcs and rotary moves in their own simulation steps), so a whole program cut
//!   live leaves the stock of one `talas simulate` run, bit for bit. The cutting runs on the
//!   caller's thread or, after [`Control::start_cutting_worker`], on a worker thread that owns
//!   the stock (the operator panel: frames do not wait for the removal); the same pieces go to
//!   it in the same order, so the stock is the same.
//! - When the machine file has bodies, every motion is tested against machine collisions
//!   ([`collide`]): head, spindle, tool and holder against the bed, the table side (table,
//!   trunnion, cradle, rotary table), the stock's bounding box and the fixtures; the first
//!   contact (found by bisection along the path) raises [`codes::COLLISION_MACHINE`] naming
//!   the two bodies, the line and the position, and the machine brakes.

pub mod collide;
pub mod cutting;
pub mod motion;
mod state;
pub mod tool_axis;

pub use cutting::LiveStock;
pub use motion::{CutPiece, Kinematics, Run, sub_block};
pub use state::{Control, ControlError, machine_interpret_options};

use glam::DVec3;

use crate::machine::Machine;

/// Alarm codes.
pub mod codes {
    /// Emergency stop pressed.
    pub const ESTOP: u32 = 1;
    /// A jog reached the soft limit of its axis and stopped there.
    pub const SOFT_LIMIT: u32 = 10;
    /// An MDI or program block would leave the travel; refused before it started.
    pub const TRAVEL: u32 = 11;
    /// MDI or AUTO asked before the machine was homed.
    pub const NOT_HOMED: u32 = 20;
    /// The G-code line or program could not be interpreted.
    pub const GCODE: u32 = 30;
    /// The motion could not be planned.
    pub const PLAN: u32 = 31;
    /// The cutting end went through material on a rapid move.
    pub const COLLISION_RAPID: u32 = 40;
    /// The shank met material.
    pub const COLLISION_SHANK: u32 = 41;
    /// The holder met material.
    pub const COLLISION_HOLDER: u32 = 42;
    /// Two machine bodies (head, spindle, tool or holder against the table side, the bed, the
    /// stock or a fixture) touched.
    pub const COLLISION_MACHINE: u32 = 43;
    /// A fed move cut the stock while the spindle stood (M5, never started, or 0 rpm).
    pub const SPINDLE_STOPPED: u32 = 44;
    /// The stock simulation failed on a piece of motion.
    pub const SIMULATION: u32 = 50;
}

/// Operating mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Reference (homing).
    Ref,
    /// Manual jog, continuous and incremental.
    Jog,
    /// Handwheel.
    Mpg,
    /// Manual data input.
    Mdi,
    /// Program run.
    Auto,
}

/// Which override.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverrideKind {
    /// Feed override, 0–150 %.
    Feed,
    /// Rapid override, 0, 25, 50 or 100 %.
    Rapid,
    /// Spindle override, 50–120 %.
    Spindle,
}

/// Spindle buttons.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spindle {
    /// Clockwise (M3).
    Cw,
    /// Counter-clockwise (M4).
    Ccw,
    /// Stop (M5).
    Stop,
}

/// One operator action.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Select a mode (only while nothing moves).
    SetMode(Mode),
    /// Home all axes in the homing order (switches to REF).
    Home,
    /// Continuous jog key pressed: axis, direction (+1/−1).
    JogStart {
        /// Axis letter.
        axis: char,
        /// +1 or −1.
        direction: f64,
    },
    /// Continuous jog key released.
    JogStop,
    /// Incremental jog by the selected increment: axis, direction (+1/−1).
    JogIncrement {
        /// Axis letter.
        axis: char,
        /// +1 or −1.
        direction: f64,
    },
    /// Jog by a distance (mm, or degrees for a rotary axis).
    JogDistance {
        /// Axis letter.
        axis: char,
        /// Signed distance, mm or degrees.
        distance: f64,
    },
    /// Select the increment (mm; the same number is degrees on rotary axes).
    SetIncrement(f64),
    /// Handwheel detents on an axis (each moves the selected increment).
    Mpg {
        /// Axis letter.
        axis: char,
        /// Signed detent count.
        detents: i32,
    },
    /// Execute one MDI line.
    Mdi(String),
    /// Load a program for AUTO (name for messages, text).
    LoadProgram {
        /// Name shown in messages.
        name: String,
        /// The program text.
        text: String,
    },
    /// Cycle start (AUTO: run or continue; after a hold: resume).
    CycleStart,
    /// Cycle start of the loaded program from a line (1-based), with the modal state the lines
    /// before it leave; its first block starts at the present position.
    RunFromLine(usize),
    /// Feed hold.
    FeedHold,
    /// Resume after a feed hold.
    Resume,
    /// Stop: brake and abandon the motion (the program rewinds).
    Stop,
    /// Reset: clear alarms and the e-stop latch, abandon motion and program.
    Reset,
    /// Emergency stop (category 1: braking within the limits, then latched).
    EStop,
    /// Set an override (percent).
    Override(OverrideKind, f64),
    /// Spindle buttons.
    Spindle(Spindle),
    /// Single block switch.
    SingleBlock(bool),
    /// Optional stop (M1) switch.
    OptionalStop(bool),
    /// Block delete (`/`) switch.
    BlockDelete(bool),
    /// Jog feed of linear axes, mm/min (rotary axes: the same number in deg/min).
    JogFeed(f64),
}

/// One alarm.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Alarm {
    /// Code (see [`codes`]).
    pub code: u32,
    /// What happened, one sentence with units.
    pub text: String,
    /// The axis concerned.
    pub axis: Option<char>,
    /// The bodies concerned (collisions).
    pub bodies: Vec<String>,
    /// Where (machine X Y Z, mm).
    pub position: Option<[f64; 3]>,
    /// Program or MDI line.
    pub line: Option<usize>,
    /// Simulated time it was raised, s.
    pub t_s: f64,
}

/// What the control is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RunState {
    /// Nothing moves.
    Idle,
    /// A motion is played.
    Moving,
    /// Braking (hold, stop, jog release).
    Braking,
    /// Held (feed hold or 0 % override), resumable.
    Held,
    /// AUTO stopped at M0, M1 or the end of a single block; cycle start continues.
    Stopped,
    /// AUTO in a dwell.
    Dwell,
    /// Emergency stop latched.
    EStop,
}

/// Per-axis peaks reached (mm or deg per s, s², s³).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Peak {
    /// Axis letter.
    pub axis: char,
    /// Highest |velocity|.
    pub velocity: f64,
    /// Highest |acceleration|.
    pub acceleration: f64,
    /// Highest |jerk|.
    pub jerk: f64,
}

/// What a panel shows.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Snapshot {
    /// Simulated time, s.
    pub time_s: f64,
    /// Mode.
    pub mode: Mode,
    /// Run state.
    pub state: RunState,
    /// Axis letters in machine order.
    pub axes: Vec<char>,
    /// Machine position per axis (mm, deg).
    pub machine_position: Vec<f64>,
    /// Work position per axis (mm, deg): machine position less the active work offset.
    pub work_position: Vec<f64>,
    /// Distance to go in the present motion per axis (mm, deg).
    pub distance_to_go: Vec<f64>,
    /// Axes homed.
    pub homed: Vec<bool>,
    /// Active G/M codes.
    pub active_codes: Vec<String>,
    /// Programmed feed, mm/min.
    pub feed_programmed_mm_per_min: f64,
    /// Path speed now, mm/min (deg/min on rotary-only moves).
    pub feed_actual_mm_per_min: f64,
    /// Programmed spindle speed, rpm.
    pub spindle_programmed_rpm: f64,
    /// Spindle speed now (programmed × override, 0 when stopped), rpm; signed by direction.
    pub spindle_actual_rpm: f64,
    /// Feed, rapid, spindle override, %.
    pub overrides_pct: [f64; 3],
    /// Line of the program (AUTO) or MDI line being run.
    pub line: Option<usize>,
    /// Alarms since the last reset.
    pub alarms: Vec<Alarm>,
    /// Selected increment (mm or deg).
    pub increment: f64,
    /// Removed stock volume, mm³ (0 without a stock).
    pub removed_volume_mm3: f64,
    /// The canned-cycle move being run (hole, peck k of n, its depth), while a cycle runs.
    pub cycle: Option<crate::gcode::CyclePhase>,
}

/// How the control is set up.
pub struct ControlConfig {
    /// The machine.
    pub machine: Machine,
    /// The stock and tool, when cutting is simulated.
    pub stock: Option<LiveStock>,
    /// Work offsets G54–G59, mm.
    pub work_offsets: [DVec3; 6],
    /// Position at power-on (slots X Y Z A B C, mm and rad).
    pub start: [f64; 6],
    /// Homing order (axis letters).
    pub home_order: Vec<char>,
    /// Home switch position per slot (mm, rad).
    pub home_position: [f64; 6],
    /// Jog feed, mm/min (rotary: deg/min).
    pub jog_feed_mm_per_min: f64,
    /// Homing feed, mm/min (rotary: deg/min).
    pub home_feed_mm_per_min: f64,
    /// Test machine collisions (when the machine has bodies).
    pub machine_collisions: bool,
    /// Fixtures and other solids on the table (table coordinates).
    pub fixtures: Vec<crate::machine::collision::TableExtra>,
    /// The tool table (LinuxCNC `.tbl`): lengths for `G43`, radii for `G41`/`G42` in MDI
    /// and AUTO.
    pub tool_table: Option<crate::gcode::ToolTable>,
}

impl ControlConfig {
    /// Defaults for a machine: power-on at machine zero (clamped into the travel) with Z at
    /// the top of its travel (the spindle clear of the table and its bodies), homing in the
    /// machine file's `home_order` (when it has none: Z first, then the other linear axes,
    /// then the rotaries), each axis to its switch at the top of the travel (linear) or 0
    /// (rotary); jog 1000 mm/min, homing 2000 mm/min.
    #[must_use]
    pub fn new(machine: Machine) -> Self {
        let mut start = [0.0; 6];
        let mut home_position = [0.0; 6];
        let mut home_order = Vec::new();
        if machine.axis('Z').is_some() {
            home_order.push('Z');
        }
        for a in &machine.axes {
            let Some(k) = crate::feed::path::slot_of(a.name) else {
                continue;
            };
            // Z at the top: the spindle clear of the table, as a machine is switched off.
            start[k] = if a.name == 'Z' {
                a.max
            } else {
                0.0_f64.clamp(a.min, a.max)
            };
            home_position[k] = if a.is_rotary() {
                0.0_f64.clamp(a.min, a.max)
            } else {
                a.max
            };
            if a.name != 'Z' && !a.is_rotary() {
                home_order.push(a.name);
            }
        }
        home_order.extend(
            machine
                .axes
                .iter()
                .filter(|a| a.is_rotary())
                .map(|a| a.name),
        );
        if !machine.home_order.is_empty() {
            home_order.clone_from(&machine.home_order);
        }
        Self {
            machine,
            stock: None,
            work_offsets: [DVec3::ZERO; 6],
            start,
            home_order,
            home_position,
            jog_feed_mm_per_min: 1000.0,
            home_feed_mm_per_min: 2000.0,
            machine_collisions: true,
            fixtures: Vec::new(),
            tool_table: None,
        }
    }
}
