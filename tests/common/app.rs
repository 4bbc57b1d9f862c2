//! Workstation test helpers (GUI builds only): a headless harness of the real workstation,
//! stepping it while its background jobs run, typing into its number fields, and the
//! stock-simulation and posted-program features and what they show.

use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use talas::app::posted::Posted;
use talas::app::program::PostedProgram;
use talas::app::stock_simulation::{ShownSimulation, StockSimulation};
use talas::app::{Workstation, WorkstationConfig};

/// The workstation in a headless harness 1400 px wide and `height` px tall (editor rows and
/// lists lie below the fold of a short window, and a click goes where a widget is drawn).
pub fn harness(config: WorkstationConfig, height: f32) -> Harness<'static, Workstation> {
    let ws = Workstation::new(&egui::Context::default(), None, config);
    Harness::builder()
        .with_size(egui::vec2(1400.0, height))
        .with_accessibility_check(false)
        .build_ui_state(|ui, ws: &mut Workstation| ws.frame_ui(ui), ws)
}

/// How long a test waits for a background job before it fails.
const SETTLE_LIMIT: Duration = Duration::from_secs(180);

/// Steps frames while `busy` says a background job runs (at most 180 s of wall time), then
/// one more frame; panics naming `what` when the job never ends.
pub fn settle_while(
    h: &mut Harness<'static, Workstation>,
    what: &str,
    busy: fn(&Workstation) -> bool,
) {
    settle_while_mut(h, what, |ws| busy(ws));
}

/// [`settle_while`] for a test whose check needs the workstation mutably (a feature lookup).
pub fn settle_while_mut(
    h: &mut Harness<'static, Workstation>,
    what: &str,
    mut busy: impl FnMut(&mut Workstation) -> bool,
) {
    let start = Instant::now();
    while start.elapsed() < SETTLE_LIMIT {
        h.step();
        if !busy(h.state_mut()) {
            h.step();
            return;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    panic!("the {what} never finished");
}

/// Steps frames until the part is loaded and its scalar field computed.
pub fn settle_load(h: &mut Harness<'static, Workstation>) {
    settle_while(h, "load", |ws| ws.is_loading() || ws.is_computing_field());
}

/// Steps frames until the calculation ends.
pub fn settle_calculation(h: &mut Harness<'static, Workstation>) {
    settle_while(h, "calculation", Workstation::is_calculating);
}

/// Types `text` into the number field labelled `label` and confirms it with Enter.
pub fn type_number(h: &mut Harness<'static, Workstation>, label: &str, text: &str) {
    h.get_by_label(label).focus();
    h.step();
    h.get_by_label(label).set_text_value_accesskit(text);
    h.step();
    h.key_press_modifiers(egui::Modifiers::NONE, egui::Key::Enter);
    h.step();
    h.step();
}

/// The stock-simulation feature.
pub fn simulation(ws: &Workstation) -> &StockSimulation {
    ws.feature_ref()
        .expect("the stock simulation is registered")
}

/// Is a simulation running?
pub fn is_simulating(ws: &Workstation) -> bool {
    simulation(ws).is_running()
}

/// The simulation shown for operation `index`, when it matches the project as it is now.
pub fn simulation_of(ws: &Workstation, index: usize) -> Option<&ShownSimulation> {
    simulation(ws).simulation_of(index, &ws.feature_view())
}

/// The posted-program feature.
pub fn program(ws: &Workstation) -> &PostedProgram {
    ws.feature_ref().expect("the posted program is registered")
}

/// Is a program being posted?
pub fn is_posting(ws: &Workstation) -> bool {
    program(ws).is_posting()
}

/// The posted G-code of operation `index`, when it is current.
pub fn program_text(ws: &Workstation, index: usize) -> Option<&str> {
    program(ws)
        .posted_for(index, &ws.feature_view())
        .map(Posted::text)
}

/// The planned feed at each pose of operation `index`'s path (mm/min), when its posted
/// program is current.
pub fn planned_feed(ws: &Workstation, index: usize) -> Option<&[f32]> {
    program(ws)
        .posted_for(index, &ws.feature_view())
        .and_then(Posted::planned_feed)
}

/// The G-code pane: its selected line and the lines it drew in the last frame.
pub fn gcode_pane(ws: &Workstation) -> Option<(Option<usize>, std::ops::Range<usize>)> {
    program(ws).gcode_pane()
}

/// The G-code line (0-based) that moves the tool to pose `pose` of the posted program.
pub fn gcode_line_of_pose(ws: &Workstation, pose: usize) -> Option<usize> {
    program(ws).gcode_line_of_pose(pose)
}
