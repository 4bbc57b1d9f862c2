//! The machining run of a tool path: the program posted for a machine and dialect, its
//! interpreted motion blocks, the jerk-limited motion plan (the true cycle time), and the maps
//! between G-code lines, tool-path poses and planned time. Playback, the motion plots, the
//! stock simulation, the force model and the virtual control all read the run, so they agree
//! on where the tool is at a time and which line moved it there.
//!
//! ```text
//! Toolpath ─post_mapped─▶ text + pose_of_line ─interpret─▶ Program ─feed::plan─▶ TimedPath
//!     ▲                                                                   │
//!     └──── pose_time_s, pose_feed_mm_min ◀── line spans (start, end, length) ◀┘
//! ```

use crate::feed::{
    CornerPolicy, FeedError, PlanInput, PlanOptions, TimedPath, machine_limits, plan,
};
use crate::gcode::{InterpretOptions, Program, Syntax, interpret};
use crate::machine::Machine;
use crate::post::{Dialect, PostError, PostOptions, Posted, post_mapped};
use crate::simulation::{MovePlan, SimError, StepOptions, plan_program};
use crate::toolpath::Toolpath;

/// Why a run could not be made (grouped by the stage that refused).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RunError {
    /// The machine cannot be found or read.
    #[error("machine '{name}': {message}")]
    Machine {
        /// The name or file asked for.
        name: String,
        /// Why it cannot be used.
        message: String,
    },
    /// The dialect cannot be found or read.
    #[error("dialect '{name}': {message}")]
    Dialect {
        /// The name or file asked for.
        name: String,
        /// Why it cannot be used.
        message: String,
    },
    /// The post refused the tool path.
    #[error("post ({machine}, {dialect}): {source}")]
    Post {
        /// The machine's name.
        machine: String,
        /// The dialect's name.
        dialect: String,
        /// The post's error.
        source: PostError,
    },
    /// The interpreter refused a line of the posted program.
    #[error("posted program, line {line}: {message}")]
    Interpret {
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The feed planner refused the program.
    #[error("feed planning: {0}")]
    Feed(#[from] FeedError),
}

/// When one G-code line runs, and how far it moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSpan {
    /// Planned time at which the line's first block starts, s.
    pub start_s: f64,
    /// Planned time at which its last block ends, s.
    pub end_s: f64,
    /// Path length of its blocks (corner blends included), mm (rad for rotary-only blocks).
    pub length_mm: f64,
}

impl LineSpan {
    /// Mean path speed over the line, mm/min (NaN when it takes no time).
    #[must_use]
    pub fn mean_feed_mm_min(&self) -> f64 {
        let dt = self.end_s - self.start_s;
        if dt > 0.0 {
            60.0 * self.length_mm / dt
        } else {
            f64::NAN
        }
    }
}

/// The planned motion of a run: the interpreted program, its jerk-limited plan and the time
/// maps derived from it.
#[derive(Clone, Debug)]
pub struct RunMotion {
    /// The interpreted posted program (machine-axis blocks).
    pub program: Program,
    /// The jerk-limited plan of the program's blocks on the machine's axes.
    pub timed: TimedPath,
    /// `(start time s, 0-based line)` each time the running line changes, in time order.
    pub line_starts: Vec<(f64, usize)>,
    /// Per 0-based line of the text, when it runs (`None` for lines without motion).
    pub line_spans: Vec<Option<LineSpan>>,
    /// Planned time at which each pose of the tool path is reached, s (non-decreasing; a pose
    /// no line writes keeps the time of the pose before it).
    pub pose_time_s: Vec<f64>,
    /// Mean planned path speed of the line that reaches each pose, mm/min (NaN where none).
    pub pose_feed_mm_min: Vec<f32>,
}

impl RunMotion {
    /// Plan `program` (interpreted from a text of `line_count` lines) on `machine`'s axes with
    /// corners blended within `corner_tolerance_mm`, and derive the time maps for a tool path
    /// whose poses are written by `line_of_pose`.
    ///
    /// # Errors
    /// [`RunError::Feed`] when the planner refuses the program.
    pub fn plan(
        program: Program,
        machine: &Machine,
        corner_tolerance_mm: f64,
        line_count: usize,
        line_of_pose: &[Option<usize>],
    ) -> Result<Self, RunError> {
        let input = PlanInput {
            blocks: program.blocks.as_slice().into(),
            axes: machine_limits(machine),
            options: PlanOptions {
                corner: CornerPolicy::Blend {
                    tolerance_mm: corner_tolerance_mm,
                },
                ..PlanOptions::default()
            },
        };
        let timed = plan(&input)?;
        let (line_starts, line_spans) = line_timing(&timed, line_count);
        let mut last = 0.0f64;
        let mut pose_time_s = Vec::with_capacity(line_of_pose.len());
        let mut pose_feed_mm_min = Vec::with_capacity(line_of_pose.len());
        for line in line_of_pose {
            let span = line.and_then(|l| line_spans.get(l).copied().flatten());
            if let Some(s) = span {
                last = last.max(s.end_s);
            }
            pose_time_s.push(last);
            pose_feed_mm_min.push(span.map_or(f32::NAN, |s| s.mean_feed_mm_min() as f32));
        }
        Ok(Self {
            program,
            timed,
            line_starts,
            line_spans,
            pose_time_s,
            pose_feed_mm_min,
        })
    }

    /// The planned cycle time, s.
    #[must_use]
    pub fn cycle_time_s(&self) -> f64 {
        self.timed.cycle_time_s
    }

    /// The 0-based line running at time `t_s` (the last line started at or before it).
    #[must_use]
    pub fn line_at_time(&self, t_s: f64) -> Option<usize> {
        let k = self.line_starts.partition_point(|(s, _)| *s <= t_s);
        self.line_starts.get(k.checked_sub(1)?).map(|(_, l)| *l)
    }

    /// The planned time at which 0-based `line` starts.
    #[must_use]
    pub fn line_start_s(&self, line: usize) -> Option<f64> {
        self.line_spans
            .get(line)
            .copied()
            .flatten()
            .map(|s| s.start_s)
    }

    /// The program's moves for the stock simulation, each with its planned duration (the time
    /// the jerk-limited plan gives its line, shared evenly among the moves of that line),
    /// instead of the time at the programmed feed.
    ///
    /// # Errors
    /// As [`plan_program`].
    pub fn move_plan(&self, machine: &Machine, opts: &StepOptions) -> Result<MovePlan, SimError> {
        let mut plan = plan_program(&self.program, Some(machine), opts)?;
        let mut per_line = std::collections::HashMap::<usize, usize>::new();
        for m in &plan.moves {
            *per_line.entry(m.block).or_default() += 1;
        }
        for m in &mut plan.moves {
            let span = m
                .block
                .checked_sub(1)
                .and_then(|l| self.line_spans.get(l).copied().flatten());
            let n = per_line.get(&m.block).copied().unwrap_or(1).max(1);
            m.duration_s = span.map_or(0.0, |s| (s.end_s - s.start_s) / n as f64);
        }
        Ok(plan)
    }
}

/// Line changes in time order and per-line spans, from the planned segments.
fn line_timing(timed: &TimedPath, line_count: usize) -> (Vec<(f64, usize)>, Vec<Option<LineSpan>>) {
    let mut starts: Vec<(f64, usize)> = Vec::new();
    let mut spans: Vec<Option<LineSpan>> = vec![None; line_count];
    for (index, (t0, t1), length) in timed.block_pieces() {
        let Some(block) = timed.blocks().get(index) else {
            continue;
        };
        let line = block.source_line.saturating_sub(1);
        if starts.last().is_none_or(|(_, l)| *l != line) {
            starts.push((t0, line));
        }
        if let Some(slot) = spans.get_mut(line) {
            let span = slot.get_or_insert(LineSpan {
                start_s: t0,
                end_s: t1,
                length_mm: 0.0,
            });
            span.start_s = span.start_s.min(t0);
            span.end_s = span.end_s.max(t1);
            span.length_mm += length;
        }
    }
    (starts, spans)
}

/// A posted tool path and, where the program could be interpreted and planned, its motion.
#[derive(Clone, Debug)]
pub struct MachiningRun {
    /// The program text, one block per line.
    pub text: String,
    /// For each line (0-based), the pose its block moves to (see [`Posted::pose_of_line`]).
    pub pose_of_line: Vec<Option<usize>>,
    /// For each pose, the line of the block that reaches it.
    pub line_of_pose: Vec<Option<usize>>,
    /// The motion plan, or why the program could not be planned (the text is still valid).
    pub motion: Result<RunMotion, RunError>,
}

impl MachiningRun {
    /// Post `toolpath` for `machine` in `dialect` and plan its motion with corners blended
    /// within `corner_tolerance_mm`.
    ///
    /// # Errors
    /// [`RunError::Post`] when the post refuses the path; interpretation and planning errors
    /// are kept in [`MachiningRun::motion`].
    pub fn new(
        toolpath: &Toolpath,
        machine: &Machine,
        dialect: &Dialect,
        options: &PostOptions,
        corner_tolerance_mm: f64,
    ) -> Result<Self, RunError> {
        let posted =
            post_mapped(toolpath, machine, dialect, options).map_err(|source| RunError::Post {
                machine: machine.name.clone(),
                dialect: dialect.name.clone(),
                source,
            })?;
        Ok(Self::from_posted(
            posted,
            toolpath.poses.len(),
            machine,
            corner_tolerance_mm,
        ))
    }

    /// The run of an already posted program of a `pose_count`-pose tool path.
    #[must_use]
    pub fn from_posted(
        posted: Posted,
        pose_count: usize,
        machine: &Machine,
        corner_tolerance_mm: f64,
    ) -> Self {
        let line_of_pose = posted.line_of_each_pose(pose_count);
        // The machine's kinematics read a tilted work plane (G68.2, CYCLE800, PLANE SPATIAL).
        let options = InterpretOptions {
            machine: Some(machine.clone()),
            ..InterpretOptions::for_syntax(Syntax::detect(&posted.text))
        };
        let line_count = posted.text.lines().count();
        let motion = interpret(&posted.text, &options)
            .map_err(|e| RunError::Interpret {
                line: e.line,
                message: e.message,
            })
            .and_then(|program| {
                RunMotion::plan(
                    program,
                    machine,
                    corner_tolerance_mm,
                    line_count,
                    &line_of_pose,
                )
            });
        Self {
            text: posted.text,
            pose_of_line: posted.pose_of_line,
            line_of_pose,
            motion,
        }
    }

    /// How many leading blocks of the interpreted program run from wherever the machine stood
    /// before it: the blocks up to the first position the program commands in every one of X,
    /// Y and Z, the move into it included (0 when the motion could not be planned, or the
    /// program never commands an absolute position).
    ///
    /// Found as `talas simulate` finds them: the text interpreted again from another start; a
    /// block whose end does not depend on the start is commanded.
    #[must_use]
    pub fn lead_in_blocks(&self) -> usize {
        let Ok(motion) = &self.motion else {
            return 0;
        };
        let mut options = InterpretOptions::for_syntax(Syntax::detect(&self.text));
        let base = options.start.xyz;
        options.start.xyz = base + glam::DVec3::new(1234.5, -2345.25, 3456.125);
        let Ok(moved) = interpret(&self.text, &options) else {
            return 0;
        };
        if moved.blocks.len() != motion.program.blocks.len() {
            return 0;
        }
        motion
            .program
            .blocks
            .iter()
            .zip(&moved.blocks)
            .position(|(a, b)| a.end.xyz == b.end.xyz)
            .map_or(0, |i| i + 1)
    }

    /// The run's moves for the stock simulation ([`RunMotion::move_plan`]) without its lead-in
    /// ([`MachiningRun::lead_in_blocks`]): a position the program did not command is never
    /// cut, as `talas simulate` leaves it out.
    ///
    /// # Errors
    /// The run's planning error, or the move plan's ([`crate::simulation::plan_program`]).
    pub fn commanded_move_plan(
        &self,
        machine: &Machine,
        opts: &StepOptions,
    ) -> Result<MovePlan, String> {
        let motion = self.motion.as_ref().map_err(ToString::to_string)?;
        let mut plan = motion.move_plan(machine, opts).map_err(|e| e.to_string())?;
        let lead = self.lead_in_blocks().min(plan.moves.len());
        let first = plan
            .moves
            .get(lead)
            .map_or(plan.steps.len(), |m| m.first_step);
        plan.moves.drain(..lead);
        plan.steps.drain(..first);
        for m in &mut plan.moves {
            m.first_step -= first;
        }
        // Each step names its move by index: the moves left shifted down by `lead`.
        for s in &mut plan.steps {
            s.move_index = s.move_index.saturating_sub(lead);
        }
        Ok(plan)
    }

    /// The pose (of the tool path) that the line running at time `t_s` moves to.
    #[must_use]
    pub fn pose_at_time(&self, t_s: f64) -> Option<usize> {
        let line = self.motion.as_ref().ok()?.line_at_time(t_s)?;
        self.pose_of_line.get(line).copied().flatten()
    }
}
