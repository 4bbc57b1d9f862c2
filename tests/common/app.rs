//! Workstation test helpers (GUI builds only): the stock-simulation and posted-program features
//! and what they show.

use talas::app::Workstation;
use talas::app::posted::Posted;
use talas::app::program::PostedProgram;
use talas::app::stock_simulation::{ShownSimulation, StockSimulation};

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
