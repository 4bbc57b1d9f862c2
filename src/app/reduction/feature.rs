//! Data reduction as a workstation feature: its menu entry, its commands, job and scene.

use std::any::Any;

use super::DataReduction;
use crate::app::actions::{Action, Menu};
use crate::app::command::Command;
use crate::app::feature::{
    Feature, FeatureContext, FeatureSave, FeatureView, SceneParts, chosen_file, is_action,
};
use crate::app::job::JobStatus;

/// The reduced surface's save dialog.
const STL_FILE: FeatureSave = FeatureSave {
    feature: DataReduction::ID,
    title: "Export reduced surface (STL)",
    types: &[("STL (.stl)", &["stl"])],
};

impl Feature for DataReduction {
    fn id(&self) -> &'static str {
        Self::ID
    }

    fn actions(&self) -> Vec<Action> {
        vec![
            Action::new(
                Self::command("open"),
                "Data reduction (Z-map SVD)…",
                Some((Menu::Machining, 2)),
            )
            .hint("Sample the part's Z-map and reduce it by singular value decomposition"),
        ]
    }

    fn apply(&mut self, command: Command, cx: &mut FeatureContext<'_>) -> Option<Command> {
        if let Some(path) = chosen_file(&command, Self::ID) {
            self.export(path, cx);
            return None;
        }
        let Some(action) = ["open", "reduce", "show", "hide", "export"]
            .into_iter()
            .find(|a| is_action(&command, Self::ID, a))
        else {
            return Some(command);
        };
        match action {
            "open" => self.open = true,
            "reduce" => self.start(cx),
            "show" | "hide" => self.set_visible(action == "show", cx),
            _ => {
                let suggestion = Self::export_suggestion(&cx.view);
                cx.ask_save_path(STL_FILE, suggestion);
            }
        }
        None
    }

    fn poll(&mut self, cx: &mut FeatureContext<'_>) {
        self.poll_job(cx);
    }

    fn job_status(&self) -> Option<JobStatus> {
        self.job.status()
    }

    fn cancel(&mut self) -> Option<String> {
        self.job.cancel()
    }

    fn reset(&mut self) {
        self.forget();
    }

    fn ui(&mut self, ctx: &egui::Context, view: &FeatureView<'_>, commands: &mut Vec<Command>) {
        self.window(ctx, view, commands);
    }

    fn scene(&self) -> SceneParts {
        SceneParts {
            instead_of_part: self.instead_of_part(),
            ..SceneParts::default()
        }
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
