//! The simulation job's work with stock keyframes: a whole run keeps keyframes of the stock
//! ([`crate::project::keyframes`]); "Stock here" at a pose starts from them when they were cut
//! from the same paths, tools, stock and settings, and otherwise simulates from the start.

use std::sync::{Arc, Mutex};

use crate::diagnostics::Progress;
use crate::geometry::mesh::TriMesh;
use crate::project::Stock;
use crate::project::keyframes::{
    DEFAULT_KEYFRAME_BYTES, StockKeyframes, simulate_with_keyframes, stock_here,
};
use crate::project::simulate::{Simulated, SimulationSettings, simulate_toolpaths};
use crate::simulation::SimError;
use crate::toolpath::Toolpath;
use crate::tools::Cutter;

/// The keyframes of the latest whole simulation, shared with its job.
pub(crate) type KeyframeSlot = Arc<Mutex<Option<Arc<StockKeyframes>>>>;

/// What one simulation job cuts.
pub(crate) struct SimInputs {
    pub(crate) stock: Stock,
    pub(crate) part: TriMesh,
    /// Whole paths with their tools, in order.
    pub(crate) paths: Vec<(Toolpath, Cutter)>,
    /// Cut the last path only up to this pose.
    pub(crate) upto: Option<usize>,
    pub(crate) settings: SimulationSettings,
}

/// Simulate `inputs`: whole (keeping keyframes in `slot`) or up to a pose (from the keyframes
/// in `slot` when they match).
pub(crate) fn run_simulation(
    inputs: &SimInputs,
    slot: &KeyframeSlot,
    progress: &Progress,
) -> Result<Simulated, SimError> {
    let SimInputs {
        stock,
        part,
        paths,
        upto,
        settings,
    } = inputs;
    let refs: Vec<(&Toolpath, &Cutter)> = paths.iter().map(|(t, c)| (t, c)).collect();
    let Some(pose) = *upto else {
        let (simulated, frames) = simulate_with_keyframes(
            stock,
            part,
            &refs,
            settings,
            DEFAULT_KEYFRAME_BYTES,
            progress,
        )?;
        if let Ok(mut kept) = slot.lock() {
            *kept = Some(Arc::new(frames));
        }
        return Ok(simulated);
    };
    let frames = slot.lock().ok().and_then(|kept| kept.clone());
    if let Some(frames) = frames.filter(|f| f.matches(stock, part, &refs, settings)) {
        return stock_here(&frames, part, pose, progress);
    }
    let mut cut = refs.clone();
    let short;
    if let Some(last) = cut.last_mut() {
        short = Toolpath::new(
            last.0.tool.clone(),
            last.0.poses.iter().take(pose + 1).copied().collect(),
        );
        last.0 = &short;
    }
    simulate_toolpaths(stock, part, &cut, settings, progress)
}
