//! Live cutting: the motion the control has played since the last cut, as blocks, is cut into
//! the dexel stock through the simulation's own move planner and removal (`plan_program`,
//! `simulate_moves`), so jogging, MDI and AUTO cut as `talas simulate` does; collisions the
//! removal reports (the cutting end through material on a rapid, shank or holder in the
//! material) come back for the control to raise as alarms.

use crate::diagnostics::Progress;
use crate::gcode::{MotionBlock, Program};
use crate::machine::Machine;
use crate::simulation::{
    Collision, DexelStock, SimError, SimOptions, StepOptions, plan_program, simulate_moves,
};
use crate::tools::Cutter;

/// The stock and the tool cutting it.
pub struct LiveStock {
    /// The stock.
    pub stock: DexelStock,
    /// The tool in the spindle.
    pub cutter: Cutter,
    /// Step bounds (from the resolution, as `talas simulate` sets them).
    pub steps: StepOptions,
    /// Volume at the start, mm³.
    pub initial_volume_mm3: f64,
}

impl LiveStock {
    /// A stock cut by `cutter`, with step bounds from the stock's resolution `resolution_mm`.
    #[must_use]
    pub fn new(stock: DexelStock, cutter: Cutter, resolution_mm: f64) -> Self {
        let steps = StepOptions::for_resolution(resolution_mm, cutter.flute_length);
        let initial_volume_mm3 = stock.volume_mm3();
        Self {
            stock,
            cutter,
            steps,
            initial_volume_mm3,
        }
    }

    /// Removed volume so far, mm³.
    #[must_use]
    pub fn removed_mm3(&self) -> f64 {
        self.initial_volume_mm3 - self.stock.volume_mm3()
    }

    /// Cut the motion `blocks` (pieces of programmed blocks, in order); the collisions found.
    ///
    /// # Errors
    /// The simulation's [`SimError`] (a piece that needs more steps than allowed).
    pub fn cut(
        &mut self,
        blocks: Vec<MotionBlock>,
        machine: &Machine,
    ) -> Result<Vec<Collision>, SimError> {
        if blocks.is_empty() {
            return Ok(Vec::new());
        }
        let program = Program {
            blocks,
            ..Program::default()
        };
        let plan = plan_program(&program, Some(machine), &self.steps)?;
        let report = simulate_moves(
            &mut self.stock,
            &self.cutter,
            &plan,
            0..plan.moves.len(),
            &SimOptions::default(),
            &Progress::new(),
        )?;
        Ok(report.collisions)
    }
}
