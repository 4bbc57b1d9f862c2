//! The remaining gouges and collisions of a computed path, listed under the operation's
//! summary ([`crate::project::finish_group::findings`]); clicking one makes that operation's
//! path the active one and picks its pose, which moves the playback and the camera there.

use super::command::Command;
use crate::project::finish_group::findings;
use crate::project::pipeline::Computed;

/// Rows shown before "… and N more".
const MAX_ROWS: usize = 50;

/// The list (nothing for a path without findings of a finishing operation).
pub fn findings_ui(
    ui: &mut egui::Ui,
    operation: usize,
    computed: &Computed,
    commands: &mut Vec<Command>,
) {
    let list = findings(computed);
    let Some(gouge) = &computed.toolpath.summary.gouge else {
        return;
    };
    if !gouge.part_checked && list.is_empty() {
        return;
    }
    ui.add_space(8.0);
    ui.label(
        egui::RichText::new("REMAINING GOUGES AND COLLISIONS")
            .small()
            .strong()
            .weak(),
    );
    if list.is_empty() {
        ui.label("None: the tool enters no face of the part.");
        return;
    }
    for (k, f) in list.iter().enumerate().take(MAX_ROWS) {
        if ui.link(f.label()).on_hover_text("Show this pose").clicked() {
            commands.push(Command::PickOperationPose {
                operation,
                pose: f.pose,
            });
        }
        if k + 1 == MAX_ROWS && list.len() > MAX_ROWS {
            ui.weak(format!("… and {} more", list.len() - MAX_ROWS));
        }
    }
}
