//! The program's tabs of the bottom dock: the G-code pane (Post and Export buttons, the
//! program's origin, its lines) and the motion plots. A clicked line or plot time picks the
//! pose it reaches on the active path; hovering a plot stands the tool there.

use super::PostedProgram;
use super::gcode_view::GcodeEvent;
use super::motion_plots::PlotEvent;
use super::{GCODE_TAB, MOTION_TAB, ProgramKey};
use crate::app::command::Command;
use crate::app::feature::FeatureView;
use crate::app::theme;

impl PostedProgram {
    /// The dock tab `tab` (one of [`GCODE_TAB`], [`MOTION_TAB`]).
    pub(super) fn dock_tab_ui(
        &mut self,
        tab: &str,
        ui: &mut egui::Ui,
        view: &FeatureView<'_>,
        commands: &mut Vec<Command>,
    ) {
        match tab {
            GCODE_TAB => self.gcode_tab_ui(ui, view, commands),
            MOTION_TAB => self.motion_tab_ui(ui, view, commands),
            _ => {}
        }
    }

    /// The G-code tab.
    fn gcode_tab_ui(
        &mut self,
        ui: &mut egui::Ui,
        view: &FeatureView<'_>,
        commands: &mut Vec<Command>,
    ) {
        let index = view.active_operation;
        let current_key = index.and_then(|i| ProgramKey::of(view.project, view.document, i));
        ui.horizontal(|ui| {
            let can_post =
                index.is_some_and(|i| view.results.operation_result(i).is_some_and(|r| r.1));
            if ui
                .add_enabled(can_post, egui::Button::new("Post").shortcut_text("F7"))
                .on_hover_text(format!(
                    "Write the active operation's program for {} ({})",
                    view.project.machine, view.project.post.dialect
                ))
                .on_disabled_hover_text("Calculate the active operation first")
                .clicked()
            {
                commands.push(Command::PostActive);
            }
            let has = self.current.is_some();
            if ui.add_enabled(has, egui::Button::new("Export…")).clicked() {
                commands.push(Command::ExportProgramDialog);
            }
            if let Some(p) = &self.current {
                let key = p.posted.key();
                ui.label(format!(
                    "{} · {} · {} · {:.2} s",
                    key.operation.name(),
                    key.machine,
                    key.post.dialect,
                    p.elapsed_s
                ));
                if current_key.as_ref() != Some(key) {
                    ui.colored_label(
                        theme::WARNING,
                        "stale: the operation or the post settings changed",
                    );
                }
            }
        });
        let Some(p) = self.current.as_mut() else {
            ui.weak("No program yet: calculate an operation, then Post (F7).");
            return;
        };
        let run = &p.posted.run;
        if let Some(GcodeEvent::LineClicked(line)) = p.view.ui(ui)
            && let Some(pose) = run.pose_of_line.get(line).copied().flatten()
        {
            if let (Ok(plots), Ok(m)) = (&mut p.plots, &run.motion)
                && let Some(t) = m.line_start_s(line)
            {
                plots.set_cursor_time(Some(t));
            }
            if Some(p.index) == index {
                commands.push(Command::PickPose(Some(pose)));
            }
        }
    }

    /// The motion tab.
    fn motion_tab_ui(
        &mut self,
        ui: &mut egui::Ui,
        view: &FeatureView<'_>,
        commands: &mut Vec<Command>,
    ) {
        let Some(p) = self.current.as_mut() else {
            ui.weak("No program yet: calculate an operation, then Post (F7).");
            return;
        };
        match &mut p.plots {
            Err(e) => {
                ui.colored_label(theme::WARNING, format!("No motion plan: {e}"));
            }
            Ok(plots) => {
                let event = plots.ui(ui);
                let (t, clicked) = match event {
                    Some(PlotEvent::TimeClicked(t)) => (t, true),
                    Some(PlotEvent::TimeHovered(t)) => (t, false),
                    None => return,
                };
                let pose = p
                    .posted
                    .run
                    .pose_at_time(t)
                    .filter(|_| Some(p.index) == view.active_operation);
                if clicked {
                    plots.set_cursor_time(Some(t));
                    if let Some(pose) = pose {
                        commands.push(Command::PickPose(Some(pose)));
                    }
                } else {
                    // Hovering a plot shows the place on the path: the tool stands there.
                    self.hover_pose = pose;
                }
            }
        }
    }
}
