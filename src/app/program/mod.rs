//! The posted program of the active operation, a workstation feature: the engine's machining
//! run (posting and jerk-limited motion planning, [`crate::project::run`]) made on a worker
//! thread, the G-code pane ([`gcode_view`]) and the motion plots ([`motion_plots`]) in the
//! bottom dock, export through a save dialog, and the links between a G-code line, a path pose,
//! the playback and a plot time (read off the run's maps).
//!
//! The run is lent to the workstation and the other features as a [`Posted`] snapshot (see
//! [`crate::app::posted`] (an
//! `Rc`, see [`crate::app::feature::Lent`]): the operator panel loads its text, the forces and
//! the playback read its planned clock, the path colouring its planned feed. A new program
//! asks the workstation to restart the playback (its clock changed) and to show the G-code tab.

mod dock;
mod feature;
pub mod gcode_view;
pub mod motion_plots;

use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::feature::{FeatureContext, FeatureView, ViewSwitch};
use super::job::{Job, JobSlot};
use super::posted::{Posted, ProgramKey};
use crate::diagnostics::Severity;
use crate::project::MachiningRun;
use crate::project::posting::run_operation;
use gcode_view::GcodeView;
use motion_plots::MotionPlots;

/// Corner blending tolerance of the motion plan, mm.
const CORNER_TOLERANCE_MM: f64 = 0.01;

/// The bottom dock's tab with the G-code pane.
const GCODE_TAB: &str = "G-code";
/// The bottom dock's tab with the motion plots.
const MOTION_TAB: &str = "Motion";

/// What the worker produces: the run and, when its motion is planned, the plots of it.
struct ProgramOutput {
    run: MachiningRun,
    plots: Result<MotionPlots, String>,
}

/// The program posted last and its views.
struct Program {
    /// The operation it was posted for.
    index: usize,
    /// The run, shared with the workstation and the other features.
    posted: Rc<Posted>,
    view: GcodeView,
    /// The motion plots, or why the program has no motion plan.
    plots: Result<MotionPlots, String>,
    elapsed_s: f64,
}

/// A running post, keyed by what it posts and the operation index.
type PostJob = JobSlot<Result<ProgramOutput, String>, (ProgramKey, usize)>;

/// The posted-program feature: the post job, the program posted last with its G-code pane and
/// motion plots.
#[derive(Default)]
pub struct PostedProgram {
    job: PostJob,
    current: Option<Program>,
    /// The pose under the pointer in a motion plot (this frame): the tool is drawn there.
    hover_pose: Option<usize>,
}

impl PostedProgram {
    /// The feature's id.
    pub const ID: &'static str = "program";

    /// Is a program being posted?
    #[must_use]
    pub fn is_posting(&self) -> bool {
        self.job.is_running()
    }

    /// The program posted last, when it is operation `index`'s current one (see `view`).
    #[must_use]
    pub fn posted_for(&self, index: usize, view: &FeatureView<'_>) -> Option<&Posted> {
        let p = &self.current.as_ref()?.posted;
        p.is_current(view.project, view.document, index)
            .then_some(p.as_ref())
    }

    /// The G-code pane: its selected line and the lines it drew in the last frame.
    #[must_use]
    pub fn gcode_pane(&self) -> Option<(Option<usize>, std::ops::Range<usize>)> {
        let p = self.current.as_ref()?;
        Some((p.view.selected_line(), p.view.visible_lines()))
    }

    /// The G-code line (0-based) that moves the tool to pose `pose` of the posted program.
    #[must_use]
    pub fn gcode_line_of_pose(&self, pose: usize) -> Option<usize> {
        let run = &self.current.as_ref()?.posted.run;
        run.line_of_pose.get(pose).copied().flatten()
    }

    /// The pose the G-code line `line` (0-based) of the posted program moves the tool to.
    #[must_use]
    pub fn pose_of_line(&self, line: usize) -> Option<usize> {
        let run = &self.current.as_ref()?.posted.run;
        run.pose_of_line.get(line).copied().flatten()
    }

    /// Post operation `index`'s computed path and plan its motion in the background.
    fn start(&mut self, index: usize, cx: &mut FeatureContext<'_>) {
        let view = cx.view;
        let Some(key) = ProgramKey::of(view.project, view.document, index) else {
            return;
        };
        let Some((result, true)) = view.results.operation_result(index) else {
            cx.notify(
                Severity::Warning,
                "Calculate the operation before posting it",
            );
            return;
        };
        let toolpath = result.toolpath().clone();
        let project = view.project.clone();
        let tool_number = u32::try_from(key.operation.tool() + 1).unwrap_or(1);
        let label = format!("Posting {}", key.operation.name());
        cx.log(
            Severity::Info,
            format!("{label} for {} ({})", project.machine, project.post.dialect),
        );
        let job = Job::start(label, cx.egui, move |progress| {
            let run = run_operation(&project, index, &toolpath, tool_number, CORNER_TOLERANCE_MM)
                .map_err(|e| e.to_string())?;
            progress.set(0.8);
            let plots = match &run.motion {
                Ok(m) => Ok(MotionPlots::new(&m.timed)),
                Err(e) => Err(e.to_string()),
            };
            Ok(ProgramOutput { run, plots })
        });
        self.job.start((key, index), job);
    }

    /// Collect a finished post: it becomes the current program, the playback restarts on its
    /// clock and the dock shows its G-code.
    fn poll_job(&mut self, cx: &mut FeatureContext<'_>) {
        let Some(done) = self.job.poll() else {
            return;
        };
        let ((key, index), elapsed_s) = (done.key, done.elapsed_s);
        match done.result {
            Some(Ok(out)) => {
                let lines = out.run.text.lines().count();
                let name = key.operation.name();
                match &out.plots {
                    Ok(plots) => cx.log(
                        Severity::Info,
                        format!("Posted '{name}': {lines} lines; {}", plots.summary()),
                    ),
                    Err(e) => cx.log(
                        Severity::Warning,
                        format!("Posted '{name}': {lines} lines; no motion plan: {e}"),
                    ),
                }
                let view = GcodeView::new(out.run.text.clone());
                let posted = Posted::new(key, out.run, cx.next_id());
                self.current = Some(Program {
                    index,
                    posted: Rc::new(posted),
                    view,
                    plots: out.plots,
                    elapsed_s,
                });
                // The playback now runs on the planned clock.
                cx.switch(ViewSwitch::RestartPlayback);
                cx.switch(ViewSwitch::DockTab(GCODE_TAB));
            }
            Some(Err(e)) => cx.notify(Severity::Error, e),
            None => cx.notify(
                Severity::Error,
                "Posting failed: the worker stopped unexpectedly",
            ),
        }
    }

    /// Bring the G-code line and the plot cursor to pose `pose` of the `active` operation's path.
    fn follow(&mut self, pose: usize, active: Option<usize>) {
        let Some(p) = self.current.as_mut() else {
            return;
        };
        if Some(p.index) != active {
            return;
        }
        let run = &p.posted.run;
        let Some(line) = run.line_of_pose.get(pose).copied().flatten() else {
            return;
        };
        p.view.scroll_to_line(line);
        if let (Ok(plots), Ok(m)) = (&mut p.plots, &run.motion)
            && let Some(t) = m.line_start_s(line)
        {
            plots.set_cursor_time(Some(t));
        }
    }

    /// Save the current program to `path` (atomically).
    fn export(&self, path: &Path, cx: &mut FeatureContext<'_>) {
        let Some(p) = &self.current else {
            cx.notify(Severity::Warning, "Post an operation before exporting");
            return;
        };
        match crate::storage::write_atomic(path, p.view.text().as_bytes()) {
            Ok(()) => cx.log(
                Severity::Info,
                format!(
                    "Exported {} lines to {}",
                    p.view.line_count(),
                    path.display()
                ),
            ),
            Err(e) => cx.notify(
                Severity::Error,
                format!("Not exported: {}: {e}", path.display()),
            ),
        }
    }
}

/// A file name for the exported program: next to the project, named after it and the active
/// operation, with the dialect's usual extension.
fn export_suggestion(view: &FeatureView<'_>) -> PathBuf {
    let project = view.project;
    let dir = view
        .project_path
        .and_then(|p| p.parent().map(Path::to_path_buf))
        .or_else(|| std::env::current_dir().ok())
        .unwrap_or_default();
    let op = view
        .active_operation
        .and_then(|i| project.operations.get(i))
        .map_or("program", |o| o.name());
    let stem: String = format!("{}-{op}", project.name)
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let ext = match project.post.dialect.as_str() {
        "linuxcnc" => "ngc",
        "siemens" => "mpf",
        "heidenhain" => "i",
        _ => "nc",
    };
    dir.join(format!("{stem}.{ext}"))
}
