//! The cutting-forces window as a workstation [`Feature`]: Machining → "Cutting forces…" opens
//! it; its job is polled each frame, shown in the status bar and cancelled from there; a new part
//! or project forgets the result. While "Colour the path" is on, its scene is the path
//! coloured by force with the legend.

use std::any::Any;
use std::sync::Arc;

use glam::Mat4;

use super::ForcesWindow;
use crate::app::actions::{Action, Menu};
use crate::app::command::{Command, FeatureCommand};
use crate::app::feature::{Feature, FeatureContext, FeatureView, SceneParts, is_action};
use crate::app::job::JobStatus;
use crate::render::LineInstance;

impl ForcesWindow {
    /// The feature's id.
    pub const ID: &'static str = "forces";
}

impl Feature for ForcesWindow {
    fn id(&self) -> &'static str {
        Self::ID
    }

    fn actions(&self) -> Vec<Action> {
        let open = FeatureCommand {
            feature: Self::ID,
            action: "open",
        };
        vec![
            Action::new(
                Command::Feature(open),
                "Cutting forces…",
                Some((Menu::Machining, 2)),
            )
            .hint(
                "Forces, torque and power along the active operation's path; the coefficient library",
            ),
        ]
    }

    fn apply(&mut self, command: Command, _cx: &mut FeatureContext<'_>) -> Option<Command> {
        if is_action(&command, Self::ID, "open") {
            self.open = true;
            return None;
        }
        Some(command)
    }

    fn poll(&mut self, cx: &mut FeatureContext<'_>) {
        Self::poll(self, cx.egui);
    }

    fn job_status(&self) -> Option<JobStatus> {
        self.job.status().or_else(|| self.schedule.status())
    }

    fn cancel(&mut self) -> Option<String> {
        Self::cancel(self)
    }

    fn reset(&mut self) {
        let _ = self.job.cancel();
        self.schedule.reset();
        self.result = None;
        self.message = None;
        self.plot_transform = None;
        self.coloured = None;
        self.deflection = None;
    }

    fn ui(&mut self, ctx: &egui::Context, view: &FeatureView<'_>, commands: &mut Vec<Command>) {
        self.window(ctx, view, commands);
    }

    /// The path coloured by force, with its legend, while "Colour the path" is on and the
    /// result is current.
    fn scene(&self) -> SceneParts {
        let Some(c) = self.coloured_path() else {
            return SceneParts::default();
        };
        SceneParts {
            lines: vec![LineInstance {
                id: c.id,
                data: Arc::clone(&c.lines),
                world_from_lines: Mat4::IDENTITY,
                draw_segments: None,
            }],
            path_legend: Some(c.legend.clone()),
            ..SceneParts::default()
        }
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
