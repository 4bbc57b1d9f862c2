//! Posting: a [`Toolpath`] through a [`Machine`]'s kinematics into the text of a G-code
//! dialect.
//!
//! Joint-space output (the default) runs the inverse kinematics with continuity (least rotary
//! travel, C kept at the singular pose), linearises every fed move within
//! [`PostOptions::tolerance_mm`] ([`Machine::linearise`]) and writes machine joints. The rotary
//! angles are rounded to the dialect's resolution first and the linear axes computed for the
//! rounded angles, so the tip lands on the pose to within the linear resolution. Fed moves
//! that turn a rotary axis are written in inverse time (G93), the others in G94.
//!
//! Tool-centre-point output (`tcp`) writes the tip in part coordinates and the rotary angles,
//! after the dialect's TCP code (G43.4, TRAORI, M128); the controller does the rest.
//!
//! The output holds no date or path: the same input gives the same bytes.

mod dialect;
mod exact;
mod probe;
mod workplane;
mod writer;

pub use dialect::{ArcCentre, CycleStyle, Dialect};
pub use workplane::{WorkPlaneStyle, euler_zxz, fixed_xyz, turned_xyz};

/// The read-back check every loaded dialect passes (see the module docs of `probe`).
pub use probe::check_reads_back as check_dialect_reads_back;

use crate::machine::{KinematicsKind, Machine, MachineError, MachineJoints, ToolPose};
use crate::toolpath::{Move, MoveKind, Toolpath};
use writer::Writer;

/// Errors of posting.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PostError {
    /// A dialect file is malformed or unknown.
    #[error("dialect: {0}")]
    Dialect(String),
    /// The machine and dialect (or options) do not go together.
    #[error("{0}")]
    Unsupported(String),
    /// A pose cannot be posted (kinematics).
    #[error("pose {pose}: {source}")]
    Pose {
        /// Index of the pose in the tool path.
        pose: usize,
        /// The kinematic failure.
        source: MachineError,
    },
    /// Bad options.
    #[error("options: {0}")]
    Options(String),
}

/// Settings of one post run.
#[derive(Clone, Debug, PartialEq)]
pub struct PostOptions {
    /// Tool-centre-point output instead of joint positions.
    pub tcp: bool,
    /// Largest tip deviation of a linearised move from its straight line, mm.
    pub tolerance_mm: f64,
    /// Program name for the header.
    pub program_name: String,
    /// Tool (and length offset) number.
    pub tool_number: u32,
    /// Spindle speed, rpm.
    pub spindle_rpm: f64,
    /// Coolant on during the program.
    pub coolant: bool,
    /// Z (program coordinates, mm) of the safe retract at start and end.
    pub clearance_z_mm: f64,
    /// Line numbers on or off (`None`: the dialect's default).
    pub line_numbers: Option<bool>,
    /// Work offset word written by the dialect's `{work_offset}` (`G54` … `G59`).
    pub work_offset: String,
    /// A 3+2 setup's tilted work plane: its axes (columns X, Y, Z; Z the tool axis) in
    /// program coordinates. A dialect with its own plane ([`Dialect::work_plane`]) writes it
    /// and the moves in its coordinates; every pose's axis must then be the plane's Z.
    pub work_plane: Option<glam::DMat3>,
    /// Comment lines written after the dialect's header comments (what the program is).
    pub comments: Vec<String>,
    /// The plane the program's setup selects: the `G17` of the dialect's setup blocks becomes
    /// this plane's code (or the code is a block of its own after the setup when no setup
    /// block names `G17`), and an arc in the plane last named by the setup or tool change
    /// blocks is written without a plane word. `None`: the setup as the dialect writes it,
    /// and the first arc or cycle names its plane.
    pub setup_plane: Option<crate::gcode::Plane>,
}

impl Default for PostOptions {
    fn default() -> Self {
        Self {
            tcp: false,
            tolerance_mm: 0.01,
            program_name: "TALAS".into(),
            tool_number: 1,
            spindle_rpm: 10_000.0,
            coolant: true,
            clearance_z_mm: 100.0,
            line_numbers: None,
            work_offset: "G54".into(),
            work_plane: None,
            comments: Vec::new(),
            setup_plane: None,
        }
    }
}

/// The joints written for one block, with the tip they put in part coordinates.
#[derive(Clone, Copy, Debug)]
struct Target {
    joints: MachineJoints,
    tip: glam::DVec3,
}

/// A posted program with the tool-path pose behind every line.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Posted {
    /// The program text, one block per line, ending with a newline.
    pub text: String,
    /// For each line of `text` (0-based), the index of the tool-path pose whose motion the
    /// line writes: the block reaching the pose or, for a linearised move, every block on the
    /// way from the previous pose to it. `None` for the header, comments, tool change, the
    /// approach at clearance, the retracts of a safe flip and the end.
    pub pose_of_line: Vec<Option<usize>>,
}

impl Posted {
    /// For each of `pose_count` poses, the line of the block that reaches it (the last line
    /// tagged with it); `None` for a pose no block writes (a repeat of the previous pose).
    /// The inverse of [`Posted::pose_of_line`], for selecting the line of a picked pose.
    #[must_use]
    pub fn line_of_each_pose(&self, pose_count: usize) -> Vec<Option<usize>> {
        let mut lines = vec![None; pose_count];
        for (line, pose) in self.pose_of_line.iter().enumerate() {
            if let Some(slot) = pose.and_then(|k| lines.get_mut(k)) {
                *slot = Some(line);
            }
        }
        lines
    }
}

/// Post a tool path.
///
/// # Errors
/// As [`post_mapped`].
pub fn post(
    toolpath: &Toolpath,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
) -> Result<String, PostError> {
    post_mapped(toolpath, machine, dialect, options).map(|p| p.text)
}

/// Post a tool path and map every output line to the pose it moves to.
///
/// # Errors
/// [`PostError::Unsupported`] for a 5-axis machine with a 3-axis dialect, TCP on a dialect or
/// machine without it, or a tilted pose on a 3-axis machine; [`PostError::Pose`] for poses the
/// kinematics cannot reach; [`PostError::Options`] for bad options.
pub fn post_mapped(
    toolpath: &Toolpath,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
) -> Result<Posted, PostError> {
    let op = Operation {
        toolpath,
        tool_number: options.tool_number,
        spindle_rpm: options.spindle_rpm,
        coolant: options.coolant,
    };
    let p = post_program(&[op], machine, dialect, options)?;
    Ok(Posted {
        text: p.text,
        pose_of_line: p.source_of_line.into_iter().map(|s| s.pose).collect(),
    })
}

/// One operation of a program: its tool path, tool number (and length offset), spindle speed
/// and coolant.
#[derive(Clone, Copy, Debug)]
pub struct Operation<'a> {
    /// The tool path.
    pub toolpath: &'a Toolpath,
    /// Tool number (`T n M6`, `G43 H n` where the dialect has them).
    pub tool_number: u32,
    /// Spindle speed, rpm (0: spindle off).
    pub spindle_rpm: f64,
    /// Coolant on.
    pub coolant: bool,
}

/// Where a line of a program comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineSource {
    /// Index of the operation.
    pub operation: usize,
    /// Index of the pose in that operation's tool path whose motion the line writes (as
    /// [`Posted::pose_of_line`]); `None` for the operation's tool change and approach.
    pub pose: Option<usize>,
}

/// A posted program of several operations.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PostedProgram {
    /// The program text, one block per line, ending with a newline.
    pub text: String,
    /// For each line, its operation (the one being written: the header and setup belong to
    /// the first, the end to the last) and pose.
    pub source_of_line: Vec<LineSource>,
}

/// Post several operations in order into one program: the header and setup once, then per
/// operation its tool change, spindle and coolant (after a retract and the dialect's blocks
/// between operations, e.g. `M9 M5 M1`) and its moves, then the end. With one operation this
/// is [`post_mapped`]. `options` gives everything but the tool, spindle and coolant, which
/// each operation sets.
///
/// # Errors
/// As [`post_mapped`] (the pose of a [`PostError::Pose`] is in its operation's path), and
/// [`PostError::Options`] for an empty list.
pub fn post_program(
    operations: &[Operation<'_>],
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
) -> Result<PostedProgram, PostError> {
    let Some(first) = operations.first() else {
        return Err(PostError::Options("a program needs an operation".into()));
    };
    let per_op: Vec<PostOptions> = operations
        .iter()
        .map(|op| PostOptions {
            tool_number: op.tool_number,
            spindle_rpm: op.spindle_rpm,
            coolant: op.coolant,
            ..options.clone()
        })
        .collect();
    for (op, o) in operations.iter().zip(&per_op) {
        check(op.toolpath, machine, dialect, o)?;
    }
    let Some(first_options) = per_op.first() else {
        return Err(PostError::Options("a program needs an operation".into()));
    };
    let mut w = Writer::new(dialect, machine, first.toolpath, first_options);
    w.preamble();
    for (i, (op, o)) in operations.iter().zip(&per_op).enumerate() {
        if i > 0 {
            w.next_operation(i, op.toolpath, o);
        }
        operation_body(&mut w, machine, dialect, o, op.toolpath)?;
    }
    w.postamble();
    let (text, poses, ops) = w.finish();
    let source_of_line = poses
        .into_iter()
        .zip(ops)
        .map(|(pose, operation)| LineSource { operation, pose })
        .collect();
    Ok(PostedProgram {
        text,
        source_of_line,
    })
}

/// The approach and every move of one operation.
fn operation_body(
    w: &mut Writer<'_>,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
    toolpath: &Toolpath,
) -> Result<(), PostError> {
    let Some(first) = toolpath.poses.first() else {
        return Ok(());
    };
    let start = ToolPose {
        tip: first.tip,
        axis: first.axis,
    };
    let mut prev = machine
        .inverse(&start, &MachineJoints::default())
        .map_err(|source| PostError::Pose { pose: 0, source })?;
    w.approach(&target(dialect, machine, &prev, options.tcp));
    w.motion(
        &target(dialect, machine, &prev, options.tcp),
        first.kind,
        first.feed_mm_per_min,
        0.0,
        0,
    );
    for mv in toolpath.moves() {
        match mv {
            Move::Rapid { to } | Move::Line { to } => {
                straight(w, machine, dialect, options, toolpath, to, &mut prev)?;
            }
            Move::Exact(seg) => {
                exact::segment(w, machine, dialect, options, toolpath, seg, &mut prev)?;
            }
        }
    }
    Ok(())
}

/// A rapid whose rotary axes turn by more than this goes up to the clearance height first,
/// rad (0.001°: any turn a machine would make).
pub const ROTARY_RETRACT_RAD: f64 = 1.745_329_251_994_33e-5;

/// The straight move reaching pose `to` from pose `to - 1`: one block for a rapid or under
/// TCP, else the linearised joints (with a safe flip where the joints jump).
fn straight(
    w: &mut Writer<'_>,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
    toolpath: &Toolpath,
    to: usize,
    prev: &mut MachineJoints,
) -> Result<(), PostError> {
    let (Some(a), Some(b)) = (
        to.checked_sub(1).and_then(|i| toolpath.poses.get(i)),
        toolpath.poses.get(to),
    ) else {
        return Ok(());
    };
    straight_between(w, machine, dialect, options, a, b, to, prev)
}

/// The straight move from `a` to `b`, its blocks tagged with pose `to`.
#[expect(
    clippy::too_many_arguments,
    reason = "the writer, the three posting inputs, the two poses, the tag and the joints"
)]
fn straight_between(
    w: &mut Writer<'_>,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
    a: &crate::toolpath::Pose,
    b: &crate::toolpath::Pose,
    to: usize,
    prev: &mut MachineJoints,
) -> Result<(), PostError> {
    let k = to.saturating_sub(1);
    let pose_err = |pose: usize| move |source| PostError::Pose { pose, source };
    let from = ToolPose {
        tip: a.tip,
        axis: a.axis,
    };
    let to_pose = ToolPose {
        tip: b.tip,
        axis: b.axis,
    };
    if b.kind == MoveKind::Rapid || options.tcp {
        let j = machine.inverse(&to_pose, prev).map_err(pose_err(k + 1))?;
        let turns = (j.tilt_rad - prev.tilt_rad).abs() > ROTARY_RETRACT_RAD
            || (j.rotary_rad - prev.rotary_rad).abs() > ROTARY_RETRACT_RAD;
        if b.kind == MoveKind::Rapid && turns && !options.tcp {
            // A rapid that turns the table swings the part under the tool along an arc the
            // tool path never planned: turn only at the clearance height (retract, turn,
            // position X Y, rapid down to the pose).
            w.turn_at_clearance(&target(dialect, machine, &j, false), k + 1);
            *prev = j;
            return Ok(());
        }
        let len = a.tip.distance(b.tip);
        w.motion(
            &target(dialect, machine, &j, options.tcp),
            b.kind,
            b.feed_mm_per_min,
            len,
            k + 1,
        );
        *prev = j;
        return Ok(());
    }
    let js = match machine.linearise(&from, &to_pose, prev, options.tolerance_mm) {
        Ok(js) => js,
        Err(MachineError::Unreachable(first_error)) => {
            // The joints jump inside the move (a limit forces the other branch): flip over
            // a safe move (retract, turn, re-enter at `from`), then cut on that branch.
            let (j0, js) = flipped(machine, &from, &to_pose, prev, options.tolerance_mm)
                .ok_or_else(|| PostError::Pose {
                    pose: k + 1,
                    source: MachineError::Unreachable(first_error),
                })?;
            w.reposition(&target(dialect, machine, &j0, false), b.feed_mm_per_min, k);
            js
        }
        Err(e) => return Err(pose_err(k + 1)(e)),
    };
    let mut last_tip = a.tip;
    for (i, j) in js.iter().enumerate() {
        if i == 0 && joints_equal(j, prev) {
            continue;
        }
        let t = target(dialect, machine, j, false);
        w.motion(
            &t,
            b.kind,
            b.feed_mm_per_min,
            last_tip.distance(t.tip),
            k + 1,
        );
        last_tip = t.tip;
    }
    if let Some(j) = js.last() {
        *prev = *j;
    }
    Ok(())
}

fn check(
    toolpath: &Toolpath,
    machine: &Machine,
    dialect: &Dialect,
    options: &PostOptions,
) -> Result<(), PostError> {
    let five = machine.kinematics != KinematicsKind::ThreeAxis;
    if five && !dialect.five_axis {
        return Err(PostError::Unsupported(format!(
            "dialect {} is for 3-axis machines; machine {} has rotary axes",
            dialect.name, machine.name
        )));
    }
    if options.tcp && !(five && dialect.supports_tcp()) {
        return Err(PostError::Unsupported(format!(
            "tool-centre-point output needs a 5-axis machine and dialect (machine {}, dialect {})",
            machine.name, dialect.name
        )));
    }
    if !(options.tolerance_mm > 0.0 && options.tolerance_mm.is_finite()) {
        return Err(PostError::Options("tolerance must be positive".into()));
    }
    if !(options.spindle_rpm >= 0.0
        && options.spindle_rpm.is_finite()
        && options.clearance_z_mm.is_finite())
    {
        return Err(PostError::Options(
            "spindle speed and clearance must be finite (speed >= 0)".into(),
        ));
    }
    check_program_name(&options.program_name)?;
    if !matches!(
        options.work_offset.as_str(),
        "G54" | "G55" | "G56" | "G57" | "G58" | "G59"
    ) {
        return Err(PostError::Options(format!(
            "work offset {:?} is not one of G54 … G59",
            options.work_offset
        )));
    }
    if let Some(w) = options
        .work_plane
        .filter(|_| dialect.work_plane != WorkPlaneStyle::Explicit)
    {
        if options.tcp || !five {
            return Err(PostError::Unsupported(format!(
                "a tilted work plane ({:?}) needs joint-space output on a 5-axis machine",
                dialect.work_plane
            )));
        }
        let z = workplane::tool_axis(&w);
        if let Some(k) = toolpath
            .poses
            .iter()
            .position(|p| p.axis.angle_between(z) > 1e-9)
        {
            return Err(PostError::Unsupported(format!(
                "pose {k}: its tool axis is not the tilted work plane's Z (a 3+2 setup keeps one axis)"
            )));
        }
    }
    toolpath
        .validate("<tool path>")
        .map_err(|e| PostError::Options(e.to_string()))
}

/// A program name goes into headers (`%NAME G71 *`, `O` comments, `PROGRAM NAME`) as it is, so
/// it must not be able to end a block or a comment: 1–32 letters, digits, `_` or `-`.
fn check_program_name(name: &str) -> Result<(), PostError> {
    let ok = !name.is_empty()
        && name.len() <= 32
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if ok {
        Ok(())
    } else {
        Err(PostError::Options(format!(
            "program name {name:?} must be 1 to 32 letters, digits, '_' or '-'"
        )))
    }
}

/// The move on another solution branch at `from`: its first joints and the linearised joints.
fn flipped(
    machine: &Machine,
    from: &ToolPose,
    to: &ToolPose,
    prev: &MachineJoints,
    tolerance_mm: f64,
) -> Option<(MachineJoints, Vec<MachineJoints>)> {
    let mut candidates = machine.inverse_candidates(from, prev).ok()?;
    let cost = |j: &MachineJoints| {
        (j.tilt_rad - prev.tilt_rad).abs() + (j.rotary_rad - prev.rotary_rad).abs()
    };
    candidates.sort_by(|a, b| cost(a).total_cmp(&cost(b)));
    candidates
        .into_iter()
        .filter(|c| {
            (c.tilt_rad - prev.tilt_rad).abs() > 1e-9
                || (c.rotary_rad - prev.rotary_rad).abs() > 1e-9
        })
        .find_map(|c| {
            let js = machine.linearise(from, to, &c, tolerance_mm).ok()?;
            Some((*js.first()?, js))
        })
}

fn joints_equal(a: &MachineJoints, b: &MachineJoints) -> bool {
    a.xyz.distance(b.xyz) < 1e-12
        && (a.tilt_rad - b.tilt_rad).abs() < 1e-15
        && (a.rotary_rad - b.rotary_rad).abs() < 1e-15
}

/// The block target for exact joints: rotary angles rounded to the dialect's resolution, the
/// linear axes recomputed for them so the tip stays put (joint space), or the tip itself (TCP).
fn target(dialect: &Dialect, machine: &Machine, j: &MachineJoints, tcp: bool) -> Target {
    let tip = machine.forward(j).tip;
    let (mut q, r, t) = rounded_frame(dialect, machine, j);
    q.xyz = if tcp { tip } else { r * tip + t };
    Target { joints: q, tip }
}

/// The joints with their rotary angles rounded as the dialect writes them, and the rigid map
/// from part to machine coordinates at those angles (`machine = r · part + t`).
fn rounded_frame(
    dialect: &Dialect,
    machine: &Machine,
    j: &MachineJoints,
) -> (MachineJoints, glam::DMat3, glam::DVec3) {
    let round = |rad: f64| Dialect::rounded(rad.to_degrees(), dialect.decimals_angle).to_radians();
    let q = MachineJoints {
        xyz: j.xyz,
        tilt_rad: round(j.tilt_rad),
        rotary_rad: round(j.rotary_rad),
    };
    let (r, t) = machine.machine_from_table(&q);
    (q, r, t)
}

#[cfg(test)]
mod tests;
