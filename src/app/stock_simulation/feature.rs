//! The stock simulation as a workstation feature: the simulation commands (Simulate, "Stock
//! here", the stock shown or not, the tolerance band), its job, its section of the operation
//! editor, the "Simulated stock" check box and the stock drawn instead of the part.

use std::any::Any;

use super::StockSimulation;
use crate::app::command::Command;
use crate::app::feature::{Feature, FeatureContext, FeatureView, SceneParts, Toggle};
use crate::app::job::JobStatus;
use crate::diagnostics::Severity;

impl Feature for StockSimulation {
    fn id(&self) -> &'static str {
        Self::ID
    }

    fn apply(&mut self, command: Command, cx: &mut FeatureContext<'_>) -> Option<Command> {
        match command {
            Command::Simulate(index) => self.start(index, None, cx),
            Command::SimulateActive => match cx.view.target_operation {
                Some(i) => self.start(i, None, cx),
                None => cx.log(Severity::Info, "Select an operation to simulate"),
            },
            Command::SimulateToPlayback => {
                match (cx.view.active_operation, cx.view.playback_pose) {
                    (Some(i), Some(p)) => self.start(i, Some(p), cx),
                    _ => cx.log(Severity::Info, "Play back or step the path to a pose first"),
                }
            }
            Command::SetStockVisible(on) => self.visible = on,
            Command::SetDeviationBand(band_mm) => self.set_deviation_band(band_mm),
            // A replaced path (a feed schedule applied) is not what the keyframes were cut
            // from; the workstation applies the command itself.
            Command::ReplacePath(..) => {
                self.drop_keyframes();
                return Some(command);
            }
            other => return Some(other),
        }
        None
    }

    fn poll(&mut self, cx: &mut FeatureContext<'_>) {
        self.poll_job(cx);
        self.follow_active(cx);
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

    fn operation_ui(
        &self,
        ui: &mut egui::Ui,
        index: usize,
        view: &FeatureView<'_>,
        commands: &mut Vec<Command>,
    ) {
        super::editor::section_ui(self, ui, index, view, commands);
    }

    fn toggles(&self) -> Vec<Toggle> {
        vec![Toggle {
            label: "Simulated stock",
            on: self.visible,
            enabled: self.shown.is_some(),
            set: Command::SetStockVisible,
        }]
    }

    fn scene(&self) -> SceneParts {
        let stock = self.stock_instance();
        SceneParts {
            // Over the simulated stock the path would hide the deviation map.
            hide_paths: stock.is_some(),
            instead_of_part: stock,
            lines: self.collision_instance().into_iter().collect(),
            ..SceneParts::default()
        }
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
