//! Workstation test helpers (GUI builds only): the stock-simulation feature and what it shows.

use talas::app::Workstation;
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
