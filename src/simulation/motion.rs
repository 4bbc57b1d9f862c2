//! What the simulator cuts with: moves (one per G-code block or tool-path pose) cut into
//! straight steps with a fixed tool axis.
//!
//! Error bounds of the steps (stated, and set by [`StepOptions`]):
//! - arcs and helices are replaced by chords whose sagitta is at most
//!   `chord_tolerance_mm` (the tool follows the chord, so it stays inside the arc by at most
//!   that much);
//! - where the axis turns (5-axis moves), each step keeps the axis at its mid value, which is at
//!   most half a step's turn δ away from the true one; a tool point at height ≤ `reach_mm`
//!   above the tip is then off by at most `reach_mm · δ / 2`, kept ≤ `axis_tolerance_mm`;
//! - rotary moves of a table-tilting machine bend the tip path in part coordinates; the joint
//!   step is also bounded so that the chord sagitta of a point `arm` mm from the rotary axes
//!   stays below `chord_tolerance_mm`.
//!
//! The number of steps is bounded per move (`max_steps_per_move`) and over the whole program
//! (`max_steps_total`): past either, an error naming the block before anything is simulated, so a program that turns a rotary axis thousands of times fails at once with
//! the block named instead of running for hours.

use glam::DVec3;

use super::SimError;
use crate::diagnostics::Diagnostic;
use crate::gcode::{MotionBlock, MotionKind, Program};
use crate::machine::{KinematicsKind, Machine, MachineJoints, ToolPose};
use crate::toolpath::{MoveKind, Toolpath};

/// Step sizes (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOptions {
    /// Largest sagitta of a chord replacing an arc or a curved rotary tip path, mm.
    pub chord_tolerance_mm: f64,
    /// Largest displacement of a tool point within `reach_mm` of the tip caused by keeping
    /// the axis fixed during one step, mm.
    pub axis_tolerance_mm: f64,
    /// Height above the tip up to which the axis bound holds (the flute length), mm.
    pub reach_mm: f64,
    /// Feed of rapid moves in a tool path (G-code rapids carry the interpreter's), mm/min.
    pub rapid_mm_per_min: f64,
    /// At most this many steps per move (more: an error naming the block, before anything is
    /// simulated).
    pub max_steps_per_move: usize,
    /// At most this many steps over the whole program (more: an error naming the block where
    /// the budget ran out, before anything is simulated).
    pub max_steps_total: usize,
}

impl StepOptions {
    /// The step bounds for a stock of `resolution_mm` dexel spacing cut by a cutter whose flutes
    /// reach `reach_mm`: chords within 5 % of the spacing (0.1 µm … 0.01 mm) and axis changes
    /// within 10 % (0.1 µm … 0.02 mm), so the steps never show at the stock's resolution.
    #[must_use]
    pub fn for_resolution(resolution_mm: f64, reach_mm: f64) -> Self {
        Self {
            reach_mm,
            chord_tolerance_mm: (0.05 * resolution_mm).clamp(1e-4, 0.01),
            axis_tolerance_mm: (0.1 * resolution_mm).clamp(1e-4, 0.02),
            ..Self::default()
        }
    }
}

impl Default for StepOptions {
    fn default() -> Self {
        Self {
            chord_tolerance_mm: 0.002,
            axis_tolerance_mm: 0.005,
            reach_mm: 30.0,
            rapid_mm_per_min: crate::units::DEFAULT_RAPID_MM_PER_MIN,
            max_steps_per_move: 100_000,
            max_steps_total: 2_000_000,
        }
    }
}

/// One move: a G-code block or the way to one tool-path pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimMove {
    /// 1-based G-code line, or the index of the pose reached in a tool path.
    pub block: usize,
    /// A rapid (G0) move.
    pub rapid: bool,
    /// Tool pose at the start, part coordinates.
    pub start: ToolPose,
    /// Tool pose at the end, part coordinates.
    pub end: ToolPose,
    /// Path length of the tip, mm (as the controller measures it).
    pub length_mm: f64,
    /// Time the move takes at its programmed feed, s (0 without a feed).
    pub duration_s: f64,
    /// Index of the move's first step in [`MovePlan::steps`].
    pub first_step: usize,
}

/// A straight piece of a move with a fixed axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// Tip at the start, mm.
    pub from: DVec3,
    /// Tip at the end, mm.
    pub to: DVec3,
    /// Unit tool axis (tip toward spindle).
    pub axis: DVec3,
    /// Index of the move in [`MovePlan::moves`].
    pub move_index: usize,
}

/// Moves and their steps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MovePlan {
    /// Moves in order.
    pub moves: Vec<SimMove>,
    /// Steps in order.
    pub steps: Vec<Step>,
    /// Notes and warnings (moves without feed, coarse moves).
    pub diagnostics: Vec<Diagnostic>,
}

impl MovePlan {
    /// Whether any step's axis is not +Z (then the stock should keep three ray families).
    #[must_use]
    pub fn tilted(&self) -> bool {
        self.steps
            .iter()
            .any(|s| (s.axis - DVec3::Z).length_squared() > 1e-24)
    }

    /// Sum of the moves' durations, s.
    #[must_use]
    pub fn duration_s(&self) -> f64 {
        self.moves.iter().map(|m| m.duration_s).sum()
    }

    fn push_move(
        &mut self,
        mut m: SimMove,
        n: usize,
        opts: &StepOptions,
        pose_at: impl Fn(f64) -> ToolPose,
    ) -> Result<(), SimError> {
        if n > opts.max_steps_per_move {
            // Cutting it coarser would leave the sweep's chord error far beyond the stated
            // tolerances without a word (a rotary turned thousands of times in one move).
            return Err(SimError::Program {
                block: m.block,
                message: format!(
                    "this move needs {n} simulation steps for the stated tolerances, more than \
                     the {} a move may take (a rotary turned many times, or a very long arc)",
                    opts.max_steps_per_move
                ),
            });
        }
        let n = n.max(1);
        if self.steps.len().saturating_add(n) > opts.max_steps_total {
            return Err(SimError::Program {
                block: m.block,
                message: format!(
                    "the program needs more than {} simulation steps in total (this move \
                     alone {n}: rotary turns and arcs are cut into steps of the stated \
                     tolerances); simulate a coarser resolution or a shorter program",
                    opts.max_steps_total
                ),
            });
        }
        m.first_step = self.steps.len();
        let index = self.moves.len();
        let mut prev = m.start;
        for k in 1..=n {
            #[allow(clippy::cast_precision_loss)]
            let t = k as f64 / n as f64;
            let next = if k == n { m.end } else { pose_at(t) };
            let axis = (prev.axis + next.axis).try_normalize().unwrap_or(next.axis);
            self.steps.push(Step {
                from: prev.tip,
                to: next.tip,
                axis,
                move_index: index,
            });
            prev = next;
        }
        self.moves.push(m);
        Ok(())
    }
}

/// The largest `|sin θ|` for θ between `a` and `b` (rad): 1 where a multiple of π/2 that is odd
/// lies between them (or an angle is not finite), else the larger at the two ends.
///
/// On a table-tilting machine at tilt θ, the tool axis stands θ from the C axis, so a C turn
/// by Δ moves it along a circle of radius `|sin θ|` by at most `Δ · |sin θ|`.
fn max_abs_sin(a: f64, b: f64) -> f64 {
    let (lo, hi) = (a.min(b), a.max(b));
    if !(lo.is_finite() && hi.is_finite()) {
        return 1.0;
    }
    use std::f64::consts::{FRAC_PI_2, PI};
    // The first odd multiple of π/2 at or above `lo`.
    let peak = FRAC_PI_2 + ((lo - FRAC_PI_2) / PI).ceil() * PI;
    if peak <= hi {
        return 1.0;
    }
    lo.sin().abs().max(hi.sin().abs()).min(1.0)
}

/// Steps needed so each turns the axis by at most the bound, for a total turn `angle`.
fn axis_steps(angle: f64, opts: &StepOptions) -> usize {
    let max_turn = 2.0 * opts.axis_tolerance_mm / opts.reach_mm.max(1e-9);
    count(angle / max_turn)
}

/// Steps so a chord of a circle of radius `radius` swept by `angle` has sagitta ≤ tolerance.
fn chord_steps(angle: f64, radius: f64, opts: &StepOptions) -> usize {
    if !(radius > opts.chord_tolerance_mm) {
        return count(angle / std::f64::consts::FRAC_PI_2);
    }
    let max_turn = 2.0 * (1.0 - opts.chord_tolerance_mm / radius).acos();
    count(angle / max_turn)
}

fn count(x: f64) -> usize {
    if !(x > 1.0) {
        return 1;
    }
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let n = x.ceil().min(1e12) as usize;
    n
}

fn check_options(opts: &StepOptions) -> Result<(), SimError> {
    for (what, v) in [
        ("chord tolerance", opts.chord_tolerance_mm),
        ("axis tolerance", opts.axis_tolerance_mm),
        ("reach", opts.reach_mm),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(SimError::Options(format!(
                "{what} must be a positive length in mm, got {v}"
            )));
        }
    }
    Ok(())
}

/// The joints of a 5-axis machine from a block position (tilt = A or B, rotary = C).
fn machine_joints(j: &crate::gcode::Joints, kind: KinematicsKind) -> MachineJoints {
    let tilt = match kind {
        KinematicsKind::TableBc => j.b,
        KinematicsKind::TableAc | KinematicsKind::ThreeAxis => j.a,
    };
    MachineJoints {
        xyz: j.xyz,
        tilt_rad: tilt.unwrap_or(0.0),
        rotary_rad: j.c.unwrap_or(0.0),
    }
}

/// Moves of an interpreted program. Without a machine (or with a 3-axis one) the tool axis is
/// +Z and coordinates are taken as part coordinates; with a table-tilting machine every
/// position goes through its forward kinematics (joint-linear interpolation, as the
/// controller moves), except blocks programmed in tool-centre-point mode
/// ([`crate::gcode::MotionBlock::tcp`]), whose X Y Z are the tip itself.
///
/// # Errors
/// [`SimError::Program`] naming the line of a block that moves a rotary axis the machine does
/// not have (or when no 5-axis machine was given) or where the program runs past
/// `max_steps_total`, [`SimError::Options`] for bad tolerances.
pub fn plan_program(
    program: &Program,
    machine: Option<&Machine>,
    opts: &StepOptions,
) -> Result<MovePlan, SimError> {
    check_options(opts)?;
    let five = machine.filter(|m| m.kinematics != KinematicsKind::ThreeAxis);
    let mut plan = MovePlan {
        diagnostics: program.diagnostics.clone(),
        ..MovePlan::default()
    };
    let mut warned_feed = false;
    for b in &program.blocks {
        let rotary = [b.start.a, b.start.b, b.start.c, b.end.a, b.end.b, b.end.c]
            .iter()
            .flatten()
            .any(|v| *v != 0.0);
        let pose_at = |t: f64| -> ToolPose {
            let j = b.point_at(t);
            match five {
                // Tool-centre-point mode: the controller keeps the tip on the programmed
                // X Y Z (part coordinates); the rotary axes give only the orientation.
                Some(m) if b.tcp => ToolPose {
                    tip: j.xyz,
                    axis: m.forward(&machine_joints(&j, m.kinematics)).axis,
                },
                Some(m) => m.forward(&machine_joints(&j, m.kinematics)),
                None => ToolPose {
                    tip: j.xyz,
                    axis: DVec3::Z,
                },
            }
        };
        let mut n = 1;
        if rotary {
            let Some(m) = five else {
                return Err(SimError::Program {
                    block: b.source_line,
                    message: "the block moves a rotary axis: give a 5-axis machine".into(),
                });
            };
            let letter = match m.kinematics {
                KinematicsKind::TableBc => 'A',
                _ => 'B',
            };
            let other = if letter == 'A' {
                [b.start.a, b.end.a]
            } else {
                [b.start.b, b.end.b]
            };
            if other.iter().flatten().any(|v| *v != 0.0) {
                return Err(SimError::Program {
                    block: b.source_line,
                    message: format!("machine {} has no {letter} axis", m.name),
                });
            }
            let (j0, j1) = (
                machine_joints(&b.start, m.kinematics),
                machine_joints(&b.end, m.kinematics),
            );
            let (tilt, rotary) = (
                (j1.tilt_rad - j0.tilt_rad).abs(),
                (j1.rotary_rad - j0.rotary_rad).abs(),
            );
            let arm = [j0.xyz, j1.xyz]
                .iter()
                .map(|p| p.distance(m.rot_point_mm) + m.tilt_offset_mm.length())
                .fold(0.0, f64::max);
            // The table turns by at most tilt + rotary about axes within `arm` of the tip
            // (the chord bound); the tool axis, at the tilt's angle from C, turns by at most
            // tilt + rotary · |sin(tilt angle)| (the axis bound): a C turn near the vertical
            // barely moves the axis, as the tool path's great-circle angle says.
            let axis_turn = tilt + rotary * max_abs_sin(j0.tilt_rad, j1.tilt_rad);
            n = axis_steps(axis_turn, opts).max(chord_steps(tilt + rotary, arm, opts));
        }
        if let Some(arc) = b.kind.arc() {
            n = n.max(chord_steps(arc.sweep_rad, arc.radius_mm, opts));
        }
        let duration_s = block_duration(b);
        if duration_s.is_none() && !warned_feed {
            warned_feed = true;
            plan.diagnostics.push(Diagnostic::warning(
                format!("line {}", b.source_line),
                "feed move without a feed: its time counts as 0",
            ));
        }
        let m = SimMove {
            block: b.source_line,
            rapid: b.kind == MotionKind::Rapid,
            start: pose_at(0.0),
            end: pose_at(1.0),
            length_mm: b.length_mm(),
            duration_s: duration_s.unwrap_or(0.0),
            first_step: 0,
        };
        plan.push_move(m, n, opts, pose_at)?;
    }
    Ok(plan)
}

fn block_duration(b: &MotionBlock) -> Option<f64> {
    if let Some(t) = b.inverse_time_duration_s() {
        return Some(t);
    }
    (b.feed_mm_per_min > 0.0).then(|| b.length_mm() / (b.feed_mm_per_min / 60.0))
}

/// Moves of a tool path: from each pose to the next, the tip along a line and the axis turning
/// on the great circle between the two axes. The move's `block` is the index of the pose it
/// reaches.
///
/// # Errors
/// [`SimError::Options`] for bad tolerances, [`SimError::Program`] for a pose with a
/// non-finite position or a zero axis, or where the path runs past `max_steps_total`.
pub fn plan_toolpath(tp: &Toolpath, opts: &StepOptions) -> Result<MovePlan, SimError> {
    check_options(opts)?;
    let mut plan = MovePlan::default();
    let poses: Vec<ToolPose> = tp
        .poses
        .iter()
        .enumerate()
        .map(|(k, p)| match p.axis.try_normalize() {
            Some(axis) if p.tip.is_finite() => Ok(ToolPose { tip: p.tip, axis }),
            _ => Err(SimError::Program {
                block: k,
                message: "pose with a non-finite tip or a zero axis".into(),
            }),
        })
        .collect::<Result<_, _>>()?;
    for (k, pair) in poses.windows(2).enumerate() {
        let (Some(a), Some(b), Some(pose)) = (pair.first(), pair.get(1), tp.poses.get(k + 1))
        else {
            continue;
        };
        let (a, b) = (*a, *b);
        let rapid = pose.kind == MoveKind::Rapid;
        let length_mm = a.tip.distance(b.tip);
        let feed = if rapid {
            opts.rapid_mm_per_min
        } else {
            pose.feed_mm_per_min
        };
        let duration_s = if feed > 0.0 {
            length_mm / (feed / 60.0)
        } else {
            0.0
        };
        let turn = a.axis.angle_between(b.axis);
        let n = axis_steps(turn, opts);
        let m = SimMove {
            block: k + 1,
            rapid,
            start: a,
            end: b,
            length_mm,
            duration_s,
            first_step: 0,
        };
        plan.push_move(m, n, opts, |t| ToolPose {
            tip: a.tip.lerp(b.tip, t),
            axis: a.axis.slerp(b.axis, t),
        })?;
    }
    Ok(plan)
}
