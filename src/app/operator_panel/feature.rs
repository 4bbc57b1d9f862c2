//! The operator panel as a workstation [`Feature`]: Machining → "Operator panel…" opens its
//! window, which drives a virtual control built from the project (machine, stock, the active
//! operation's tool, work offset and posted program).

use std::any::Any;

use super::camera::MACHINE_VIEWS;
use super::{OperatorPanel, PanelSource, SetupSource};
use crate::app::actions::{Action, Menu};
use crate::app::command::{Command, FeatureCommand};
use crate::app::feature::{Feature, FeatureContext, FeatureView, RenderIds, is_action};
use crate::app::viewport::ViewportState;
use crate::project::Operation;
use crate::render::MeshInstance;

impl OperatorPanel {
    /// The feature's id.
    pub const ID: &'static str = "operator_panel";
}

/// What the panel's control is built from, read off the workstation.
fn source<'a>(view: &FeatureView<'a>) -> PanelSource<'a> {
    let project = view.project;
    let operation = view
        .active_operation
        .and_then(|i| project.operations.get(i));
    let tool = operation.map_or(0, Operation::tool);
    // The active operation's setup (else the first): its work offset and its workholding.
    let index = view
        .active_operation
        .and_then(|op| crate::project::setups::setup_of(project, op))
        .unwrap_or(0)
        .min(project.setups.len().saturating_sub(1));
    let frame = project
        .setups
        .get(index)
        .map_or_else(|| project.first_setup().frame, |s| s.frame);
    PanelSource {
        machine: project.machine.clone(),
        stock: view
            .document
            .map(|d| crate::simulation::StockShape::of(&project.stock, &d.bounds)),
        cutter: project.tools.get(tool).map(|t| t.cutter.clone()),
        work_offset: (frame.work_offset, frame.origin_mm),
        posted: view.posted,
        setup: view.document.map(|d| SetupSource {
            project,
            index,
            part: &d.part.workpiece,
            base: view
                .project_path
                .and_then(std::path::Path::parent)
                .unwrap_or(std::path::Path::new(".")),
        }),
    }
}

impl Feature for OperatorPanel {
    fn id(&self) -> &'static str {
        Self::ID
    }

    fn actions(&self) -> Vec<Action> {
        let open = FeatureCommand {
            feature: Self::ID,
            action: "open",
        };
        let mut out = vec![
            Action::new(
                Command::Feature(open),
                "Operator panel…",
                Some((Menu::Machining, 2)),
            )
            .hint("Jog, MDI and AUTO on the virtual control of the project's machine"),
        ];
        out.extend(MACHINE_VIEWS.map(|(_, action, label)| {
            let command = Command::Feature(FeatureCommand {
                feature: Self::ID,
                action,
            });
            Action::new(command, format!("Machine {label}"), Some((Menu::View, 1)))
                .hint("The whole machine (opens the operator panel)")
        }));
        out
    }

    fn apply(&mut self, command: Command, _cx: &mut FeatureContext<'_>) -> Option<Command> {
        if is_action(&command, Self::ID, "open") {
            self.open = true;
            return None;
        }
        if let Some((view, _, _)) = MACHINE_VIEWS
            .iter()
            .find(|(_, action, _)| is_action(&command, Self::ID, action))
        {
            self.request_machine_view(*view);
            return None;
        }
        Some(command)
    }

    fn ui(&mut self, ctx: &egui::Context, view: &FeatureView<'_>, _commands: &mut Vec<Command>) {
        if self.open {
            self.window(ctx, &source(view));
        }
    }

    fn steer_view(&mut self, viewport: &mut ViewportState, ids: &RenderIds) -> Vec<MeshInstance> {
        super::machine_view::panel_machine(self, viewport, ids)
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
