//! The posted program as a workstation feature: it takes the workstation's commands Post and
//! Export (the menu entries "Post G-code F7" and "Export G-code…" stay in the actions table),
//! watches `ReplacePath` go by to drop a program made from the old path, owns the G-code and
//! Motion tabs of the bottom dock, follows the tool's pose into them and lends its run.

use std::any::Any;
use std::rc::Rc;

use super::{GCODE_TAB, MOTION_TAB, PostedProgram, export_suggestion};
use crate::app::command::Command;
use crate::app::feature::{Feature, FeatureContext, FeatureSave, FeatureView, Lent, chosen_file};
use crate::app::job::JobStatus;
use crate::diagnostics::Severity;

/// The posted program's save dialog (Heidenhain's `.h`/`.i`, Siemens' `.mpf`, LinuxCNC's `.ngc`).
const GCODE_FILE: FeatureSave = FeatureSave {
    feature: PostedProgram::ID,
    title: "Export G-code",
    types: &[
        (
            "G-code (.ngc, .nc, .tap, .mpf, .h, .i, .gcode)",
            &["ngc", "nc", "tap", "mpf", "h", "i", "gcode"],
        ),
        ("All files", &[]),
    ],
};

impl Feature for PostedProgram {
    fn id(&self) -> &'static str {
        Self::ID
    }

    fn apply(&mut self, command: Command, cx: &mut FeatureContext<'_>) -> Option<Command> {
        if let Some(path) = chosen_file(&command, Self::ID) {
            self.export(path, cx);
            return None;
        }
        match command {
            Command::PostActive => match cx.view.target_operation {
                Some(i) => self.start(i, cx),
                None => cx.log(Severity::Info, "Select an operation to post"),
            },
            Command::ExportProgramDialog => {
                let suggestion = export_suggestion(&cx.view);
                cx.ask_save_path(GCODE_FILE, suggestion);
            }
            // A program posted from the path being replaced (a feed schedule applied) is not the
            // path's any more; the workstation applies the command itself.
            Command::ReplacePath(index, _) => {
                if cx
                    .view
                    .results
                    .operation_result(index)
                    .is_some_and(|(_, fresh)| fresh)
                {
                    self.current = None;
                }
                return Some(command);
            }
            other => return Some(other),
        }
        None
    }

    fn poll(&mut self, cx: &mut FeatureContext<'_>) {
        // The pointer is over a plot only in the frame it is drawn.
        self.hover_pose = None;
        self.poll_job(cx);
    }

    fn job_status(&self) -> Option<JobStatus> {
        self.job.status()
    }

    fn cancel(&mut self) -> Option<String> {
        self.job.cancel()
    }

    fn reset(&mut self) {
        // Replacing the job slot drops its job, which cancels it without a word.
        *self = Self::default();
    }

    fn ui(&mut self, _ctx: &egui::Context, _view: &FeatureView<'_>, _commands: &mut Vec<Command>) {}

    fn dock_tabs(&self) -> &'static [&'static str] {
        &[GCODE_TAB, MOTION_TAB]
    }

    fn dock_ui(
        &mut self,
        tab: &str,
        ui: &mut egui::Ui,
        view: &FeatureView<'_>,
        commands: &mut Vec<Command>,
    ) {
        self.dock_tab_ui(tab, ui, view, commands);
    }

    fn follow_pose(&mut self, pose: usize, view: &FeatureView<'_>) {
        self.follow(pose, view.active_operation);
    }

    fn lend(&self, lent: &mut Lent) {
        if let Some(p) = &self.current {
            lent.lend(Rc::clone(&p.posted));
        }
        lent.hover_pose = lent.hover_pose.or(self.hover_pose);
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
