//! Stock simulation (L4): dexel stock, material removal by the swept volume of the cutter,
//! surface extraction, deviation from the design part, collisions.
//!
//! ```text
//! Program (G-code) ─plan_program (machine kinematics)─┐
//! Toolpath ─────────plan_toolpath─────────────────────┴▶ MovePlan (moves → straight steps)
//! StockShape(s) ─DexelStock::new (memory checked first)─▶ DexelStock
//! simulate(stock, cutter, plan, options, progress) ─▶ SimReport (removed volume, collisions)
//! DexelStock ─▶ height_field_mesh / closed_mesh (STL) / surface_points ─deviation(part)─▶ stats
//! ```
//!
//! The stock is a set of dexels: rays on a square grid of the chosen resolution, each holding
//! its material as sorted intervals. 3-axis programs need only Z rays; a tilted tool gets X, Y
//! and Z rays (tri-dexel) so walls and undercuts keep the resolution. Removal of one straight
//! step is exact per ray (the ray's interval inside the swept tool body, see `sweep`); arcs
//! and axis changes are cut into steps with stated bounds (see [`StepOptions`]).

mod ballrow;
mod batch;
mod deviation;
mod dexel;
mod engine;
mod exact;
mod motion;
mod prepared;
mod stock;
mod surface;
mod sweep;

pub use deviation::{
    DeviationOptions, DeviationReport, Histogram, TopDeviation, deviation, is_closed,
    signed_distance, top_deviation,
};
pub use dexel::{Dexel, DexelFamily, RayAxis};
pub use engine::{Collision, CollisionKind, SimOptions, SimReport, simulate, simulate_moves};
pub(crate) use engine::{Continued, StockCache, run_moves, run_moves_cached};
pub use motion::{MovePlan, SimMove, Step, StepOptions, plan_program, plan_toolpath};
pub use stock::{
    DEFAULT_MEMORY_LIMIT_BYTES, DexelMode, DexelStock, MeshStock, StockShape, estimate_bytes,
};
pub use surface::{MESH_HEIGHT_STEP_MM, SurfacePoint};

/// Errors of the simulation.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SimError {
    /// The stock shape is invalid.
    #[error("stock: {0}")]
    Stock(String),
    /// The resolution is not a positive length.
    #[error("resolution must be a positive length in mm, got {0}")]
    Resolution(f64),
    /// The stock would need more memory than allowed.
    #[error(
        "stock at {resolution_mm} mm needs about {} MiB, more than the limit of {} MiB: use a \
         coarser resolution or a higher limit",
        need_bytes / (1 << 20),
        limit_bytes / (1 << 20)
    )]
    Memory {
        /// Estimated bytes.
        need_bytes: u64,
        /// The limit.
        limit_bytes: u64,
        /// The resolution asked for.
        resolution_mm: f64,
    },
    /// The tool is invalid.
    #[error("tool: {0}")]
    Tool(String),
    /// A block of the program (or a pose of the tool path) cannot be simulated.
    #[error("block {block}: {message}")]
    Program {
        /// G-code line or pose index.
        block: usize,
        /// What is wrong.
        message: String,
    },
    /// Options are out of range.
    #[error("options: {0}")]
    Options(String),
    /// The design part cannot be used for deviation.
    #[error("part: {0}")]
    Part(String),
    /// Someone cancelled the run.
    #[error("cancelled")]
    Cancelled,
}
