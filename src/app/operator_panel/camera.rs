//! Machine camera presets: the whole machine seen from the front, the side, the top and in
//! iso, as menu entries (View menu, from the feature's actions) and as buttons on the panel.
//! A preset is a request the machine view carries out on the next frame: the standard view
//! direction, the camera fitted to the machine's bodies at their present position.

use crate::render::StandardView;

use super::OperatorPanel;

/// The presets: view, feature action name, label.
pub const MACHINE_VIEWS: [(StandardView, &str, &str); 4] = [
    (StandardView::Front, "machine-front", "Front"),
    (StandardView::Right, "machine-side", "Side"),
    (StandardView::Top, "machine-top", "Top"),
    (StandardView::Iso, "machine-iso", "Iso"),
];

impl OperatorPanel {
    /// Ask for a machine camera preset (opens the panel, whose control the machine follows).
    pub fn request_machine_view(&mut self, view: StandardView) {
        self.open = true;
        self.camera_request = Some(view);
    }

    /// The preset asked for and not yet carried out.
    pub fn take_machine_view(&mut self) -> Option<StandardView> {
        self.camera_request.take()
    }

    /// The preset buttons.
    pub(super) fn camera_buttons(&mut self, ui: &mut egui::Ui) {
        ui.label("Machine view");
        for (view, _, label) in MACHINE_VIEWS {
            if ui
                .button(label)
                .on_hover_text("Show the whole machine from this side")
                .clicked()
            {
                self.request_machine_view(view);
            }
        }
    }
}
