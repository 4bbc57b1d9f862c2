//! The profile editor as a workstation [`Feature`]: Machining → "2D profile / EDM electrode…"
//! opens its window; its computation runs on its own [`crate::app::job::JobSlot`].

use std::any::Any;

use super::ProfileEditor;
use crate::app::actions::{Action, Menu};
use crate::app::command::{Command, FeatureCommand};
use crate::app::feature::{Feature, FeatureContext, FeatureView, is_action};

impl ProfileEditor {
    /// The feature's id.
    pub const ID: &'static str = "profile_editor";
}

impl Feature for ProfileEditor {
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
                "2D profile / EDM electrode…",
                Some((Menu::Machining, 2)),
            )
            .hint("Profile editor: the path of a ball electrode along a 2D section"),
        ]
    }

    fn apply(&mut self, command: Command, _cx: &mut FeatureContext<'_>) -> Option<Command> {
        if is_action(&command, Self::ID, "open") {
            self.open = true;
            return None;
        }
        Some(command)
    }

    fn ui(&mut self, ctx: &egui::Context, _view: &FeatureView<'_>, _commands: &mut Vec<Command>) {
        self.window(ctx);
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
