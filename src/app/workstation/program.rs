//! The posted program of the active operation: the engine's machining run (posting and
//! jerk-limited motion planning, [`crate::project::run`]) made on a worker thread, the G-code
//! pane and the motion plots in the bottom dock, export through a save dialog, and the links
//! between a G-code line, a path pose, the playback and a plot time (read off the run's maps).

use std::path::PathBuf;
use std::sync::Arc;

use super::super::command::Command;
use super::super::job::{Job, JobSlot};
use super::super::panels::gcode_view::{GcodeEvent, GcodeView};
use super::super::panels::motion_plots::{MotionPlots, PlotEvent};
use super::Workstation;
use crate::diagnostics::Severity;
use crate::project::MachiningRun;
use crate::project::posting::run_operation;
use crate::project::{Operation, PostConfig, Setup};
use crate::render::{ColourMap, DataId, LineData, ScalarMapping};
use crate::tools::Cutter;

/// Corner blending tolerance of the motion plan, mm.
const CORNER_TOLERANCE_MM: f64 = 0.01;

pub use super::super::state::DockTab;

/// What a program was posted from (it is shown as current while these are unchanged).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ProgramKey {
    operation: Operation,
    cutter: Cutter,
    part_id: DataId,
    machine: String,
    setup: Setup,
    post: PostConfig,
}

/// What the worker produces: the run and, when its motion is planned, the plots of it.
pub(super) struct ProgramOutput {
    run: MachiningRun,
    plots: Result<MotionPlots, String>,
}

/// A posted program and its views.
pub(super) struct Program {
    key: ProgramKey,
    index: usize,
    view: GcodeView,
    /// The engine's run: line ↔ pose ↔ planned time.
    run: MachiningRun,
    /// The motion plots, or why the program has no motion plan.
    plots: Result<MotionPlots, String>,
    elapsed_s: f64,
    /// The path coloured by planned feed (render id, lines, mapping in mm/min), built once.
    feed_lines: Option<(DataId, Arc<LineData>, ScalarMapping)>,
}

/// A running post, keyed by what it posts and the operation index.
type PostJob = JobSlot<Result<ProgramOutput, String>, (ProgramKey, usize)>;

/// The program state of the workstation.
#[derive(Default)]
pub(super) struct Programs {
    pub(super) job: PostJob,
    pub current: Option<Program>,
    pub dock: DockTab,
}

impl Workstation {
    fn program_key(&self, index: usize) -> Option<ProgramKey> {
        let project = &self.saved.session.project;
        let operation = project.operations.get(index)?.clone();
        Some(ProgramKey {
            cutter: project.tools.get(operation.tool())?.cutter.clone(),
            operation,
            part_id: self.document.as_ref()?.ids[0],
            machine: project.machine.clone(),
            setup: project.setup,
            post: project.post.clone(),
        })
    }

    /// Post operation `index`'s computed path and plan its motion in the background.
    pub(super) fn start_post(&mut self, index: usize) {
        let t = self.now_s();
        let Some(key) = self.program_key(index) else {
            return;
        };
        let Some((result, true)) = self.operation_result(index) else {
            self.log.notify(
                t,
                Severity::Warning,
                "Calculate the operation before posting it",
            );
            return;
        };
        let toolpath = result.toolpath().clone();
        let project = self.saved.session.project.clone();
        let tool_number = u32::try_from(key.operation.tool() + 1).unwrap_or(1);
        let label = format!("Posting {}", key.operation.name());
        self.log_info(format!(
            "{label} for {} ({})",
            project.machine, project.post.dialect
        ));
        let job = Job::start(label, &self.run.ctx, move |progress| {
            let run = run_operation(&project, &toolpath, tool_number, CORNER_TOLERANCE_MM)
                .map_err(|e| e.to_string())?;
            progress.set(0.8);
            let plots = match &run.motion {
                Ok(m) => Ok(MotionPlots::new(&m.timed)),
                Err(e) => Err(e.to_string()),
            };
            Ok(ProgramOutput { run, plots })
        });
        self.programs.job.start((key, index), job);
    }

    /// Is a program being posted?
    #[must_use]
    pub fn is_posting(&self) -> bool {
        self.programs.job.is_running()
    }

    /// The posted G-code of operation `index`, when it is current.
    #[must_use]
    pub fn program_text(&self, index: usize) -> Option<&str> {
        let key = self.program_key(index)?;
        self.programs
            .current
            .as_ref()
            .filter(|p| p.key == key)
            .map(|p| p.view.text())
    }

    /// The planned clock of operation `index`'s path (time each pose is reached, s), when its
    /// posted program is current and planned.
    pub(crate) fn planned_clock(&self, index: usize) -> Option<&[f64]> {
        let key = self.program_key(index)?;
        self.programs
            .current
            .as_ref()
            .filter(|p| p.key == key)
            .and_then(|p| p.run.motion.as_ref().ok())
            .map(|m| m.pose_time_s.as_slice())
    }

    /// The planned feed at each pose of operation `index`'s path, mm/min (NaN where unknown),
    /// when its posted program is current.
    #[must_use]
    pub fn planned_feed(&self, index: usize) -> Option<&[f32]> {
        let key = self.program_key(index)?;
        self.programs
            .current
            .as_ref()
            .filter(|p| p.key == key)
            .and_then(|p| p.run.motion.as_ref().ok())
            .map(|m| m.pose_feed_mm_min.as_slice())
    }

    /// Collect a finished post.
    pub(super) fn poll_post_job(&mut self) {
        let Some(done) = self.programs.job.poll() else {
            return;
        };
        let ((key, index), elapsed_s) = (done.key, done.elapsed_s);
        let t = self.now_s();
        match done.result {
            Some(Ok(out)) => {
                let lines = out.run.text.lines().count();
                match &out.plots {
                    Ok(plots) => self.log.push(
                        t,
                        Severity::Info,
                        format!(
                            "Posted '{}': {lines} lines; {}",
                            key.operation.name(),
                            plots.summary()
                        ),
                    ),
                    Err(e) => self.log.push(
                        t,
                        Severity::Warning,
                        format!(
                            "Posted '{}': {lines} lines; no motion plan: {e}",
                            key.operation.name()
                        ),
                    ),
                }
                self.programs.current = Some(Program {
                    key,
                    index,
                    view: GcodeView::new(out.run.text.clone()),
                    run: out.run,
                    plots: out.plots,
                    elapsed_s,
                    feed_lines: None,
                });
                // The playback now runs on the planned clock.
                self.ops.t_s = None;
                self.ops.playing = false;
                self.programs.dock = DockTab::Gcode;
            }
            Some(Err(e)) => self.log.notify(t, Severity::Error, e),
            None => self.log.notify(
                t,
                Severity::Error,
                "Posting failed: the worker stopped unexpectedly",
            ),
        }
    }

    /// The posted program's pane: its selected line and the lines it drew in the last frame.
    #[must_use]
    pub fn gcode_pane(&self) -> Option<(Option<usize>, std::ops::Range<usize>)> {
        let p = self.programs.current.as_ref()?;
        Some((p.view.selected_line(), p.view.visible_lines()))
    }

    /// The G-code line (0-based) that moves the tool to pose `pose` of the posted program.
    #[must_use]
    pub fn gcode_line_of_pose(&self, pose: usize) -> Option<usize> {
        self.programs
            .current
            .as_ref()?
            .run
            .line_of_pose
            .get(pose)
            .copied()
            .flatten()
    }

    /// Bring the G-code line and the plot cursor to pose `pose` of the active path.
    pub(super) fn follow_pose(&mut self, pose: usize) {
        let active = self.ops.active;
        let Some(p) = self.programs.current.as_mut() else {
            return;
        };
        if Some(p.index) != active {
            return;
        }
        let Some(line) = p.run.line_of_pose.get(pose).copied().flatten() else {
            return;
        };
        p.view.scroll_to_line(line);
        if let (Ok(plots), Ok(m)) = (&mut p.plots, &p.run.motion)
            && let Some(t) = m.line_start_s(line)
        {
            plots.set_cursor_time(Some(t));
        }
    }

    /// Save the current program to `path` (atomically).
    pub(super) fn export_program(&mut self, path: PathBuf) {
        let t = self.now_s();
        let Some(p) = &self.programs.current else {
            self.log
                .notify(t, Severity::Warning, "Post an operation before exporting");
            return;
        };
        match crate::storage::write_atomic(&path, p.view.text().as_bytes()) {
            Ok(()) => self.log.push(
                t,
                Severity::Info,
                format!(
                    "Exported {} lines to {}",
                    p.view.line_count(),
                    path.display()
                ),
            ),
            Err(e) => self.log.notify(
                t,
                Severity::Error,
                format!("Not exported: {}: {e}", path.display()),
            ),
        }
    }

    /// The G-code tab.
    pub(super) fn gcode_tab_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        let index = self.ops.active;
        let current_key = index.and_then(|i| self.program_key(i));
        ui.horizontal(|ui| {
            let can_post = index.is_some_and(|i| self.operation_result(i).is_some_and(|r| r.1));
            if ui
                .add_enabled(can_post, egui::Button::new("Post").shortcut_text("F7"))
                .on_hover_text(format!(
                    "Write the active operation's program for {} ({})",
                    self.saved.session.project.machine, self.saved.session.project.post.dialect
                ))
                .on_disabled_hover_text("Calculate the active operation first")
                .clicked()
            {
                commands.push(Command::PostActive);
            }
            let has = self.programs.current.is_some();
            if ui.add_enabled(has, egui::Button::new("Export…")).clicked() {
                commands.push(Command::ExportProgramDialog);
            }
            if let Some(p) = &self.programs.current {
                let stale = current_key.as_ref() != Some(&p.key);
                ui.label(format!(
                    "{} · {} · {} · {:.2} s",
                    p.key.operation.name(),
                    p.key.machine,
                    p.key.post.dialect,
                    p.elapsed_s
                ));
                if stale {
                    ui.colored_label(
                        super::super::theme::WARNING,
                        "stale: the operation or the post settings changed",
                    );
                }
            }
        });
        let Some(p) = self.programs.current.as_mut() else {
            ui.weak("No program yet: calculate an operation, then Post (F7).");
            return;
        };
        if let Some(GcodeEvent::LineClicked(line)) = p.view.ui(ui)
            && let Some(pose) = p.run.pose_of_line.get(line).copied().flatten()
        {
            if let (Ok(plots), Ok(m)) = (&mut p.plots, &p.run.motion)
                && let Some(t) = m.line_start_s(line)
            {
                plots.set_cursor_time(Some(t));
            }
            if Some(p.index) == self.ops.active {
                commands.push(Command::PickPose(Some(pose)));
            }
        }
    }

    /// The motion tab.
    pub(super) fn motion_tab_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        let Some(p) = self.programs.current.as_mut() else {
            ui.weak("No program yet: calculate an operation, then Post (F7).");
            return;
        };
        match &mut p.plots {
            Err(e) => {
                ui.colored_label(super::super::theme::WARNING, format!("No motion plan: {e}"));
            }
            Ok(plots) => {
                let event = plots.ui(ui);
                let (t, clicked) = match event {
                    Some(PlotEvent::TimeClicked(t)) => (t, true),
                    Some(PlotEvent::TimeHovered(t)) => (t, false),
                    None => return,
                };
                let pose = p
                    .run
                    .pose_at_time(t)
                    .filter(|_| Some(p.index) == self.ops.active);
                if clicked {
                    plots.set_cursor_time(Some(t));
                    if let Some(pose) = pose {
                        commands.push(Command::PickPose(Some(pose)));
                    }
                } else {
                    // Hovering a plot shows the place on the path: the tool stands there.
                    self.ops.hover_pose = pose;
                }
            }
        }
    }

    /// The active path coloured by planned feed, when its program is posted and current.
    pub(super) fn feed_coloured_path(&mut self) -> Option<(DataId, Arc<LineData>, ScalarMapping)> {
        let index = self.ops.active?;
        let key = self.program_key(index)?;
        let (k, true) = self.result_index(index)? else {
            return None;
        };
        let mut next_id = self.ops.next_id;
        let store = &self.ops.store;
        let p = self.programs.current.as_mut().filter(|p| p.key == key)?;
        if p.feed_lines.is_none() {
            let r = store.get(k)?;
            let pose_feed = &p.run.motion.as_ref().ok()?.pose_feed_mm_min;
            let max = pose_feed
                .iter()
                .copied()
                .filter(|f| f.is_finite())
                .fold(0.0f32, f32::max)
                .max(1.0);
            let mapping = ScalarMapping {
                map: ColourMap::Turbo,
                min: 0.0,
                max,
            };
            next_id += 1;
            let lines = crate::app::toolpaths::path_lines_by(r.toolpath(), pose_feed, mapping);
            p.feed_lines = Some((next_id, Arc::new(lines), mapping));
        }
        self.ops.next_id = next_id;
        p.feed_lines
            .as_ref()
            .map(|(id, l, m)| (*id, Arc::clone(l), *m))
    }
}
