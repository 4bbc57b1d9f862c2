//! # Talas: the planning engine
//!
//! Talas is a desktop CAM workstation. This library is its engine; the binary adds the egui
//! workstation (feature `gui`) and the command line (`cli`).
//!
//! ```text
//! file ─import::open─▶ Workpiece (B-rep, mesh, exact faces, one shared BVH)
//!                          │
//! Operation + Tool ────────┼─▶ project::pipeline::compute ─▶ strategy ─▶ Toolpath ─▶ checks
//!                          ▼
//! project::run::MachiningRun: post ─▶ G-code + line ↔ pose ─▶ gcode::interpret ─▶ Program
//!                          ─▶ feed::plan (jerk-limited) ─▶ TimedPath ─▶ pose ↔ line ↔ time
//!                          │
//!                          ├─▶ simulation (moves with planned times) ─▶ deviation
//!                          └─▶ force model (engagement from the stock) ─▶ forces, form error
//! ```
//!
//! Layers (a module may use only layers below it; `tests/architecture.rs` enforces this):
//!
//! | layer | modules | what lives there |
//! |---|---|---|
//! | L0 | [`units`], [`diagnostics`], [`storage`], [`geometry`] | mm/s/rad; warnings and the progress/cancel handle; atomic file writes; curves, surfaces, B-rep, meshes with a BVH, Z-maps |
//! | L1 | [`import`], [`features`], [`tools`], [`machine`], [`gcode`] | STEP and STL readers and the one `Workpiece`; machining features (holes, 2.5D regions) read from the B-rep; cutters and the drop-cutter; machine kinematics; G-code interpreter |
//! | L2 | [`toolpath`] | CL poses and tool paths |
//! | L3 | [`strategies`], [`checks`], [`reduce`] | path strategies (Z-map paths included); gouge and collision checks and test oracles; the SVD reduction of Z-maps |
//! | L4 | [`post`], [`feed`], [`simulation`], [`force`], [`profile`] | posting; jerk-limited feed planning; stock simulation; cutting forces; 2D profiles |
//! | L5 | [`project`], [`control`] | the document, the pipeline and the machining run; the virtual machine control |
//! | CLI | [`cli`] | thin shells over engine calls |
//! | GUI | `render`, `app` | feature `gui` only |
//!
//! Internal units are mm, s and rad everywhere; mm/min, rpm and degrees appear only at the
//! edges (UI, G-code, command line).

// `!(x > 0.0)` is the NaN-safe way to reject bad numbers (it is true for NaN, unlike `x <= 0.0`);
// the engine uses it on purpose wherever input may be non-finite.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

/// A uniform generator on [0, 1) for the unit tests of any module (the PCG multiplier's LCG,
/// top 53 bits) seeded by `seed`: the same sequence on every platform. At the crate root so
/// that modules of any layer may share it.
#[cfg(test)]
pub(crate) fn test_uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

pub mod checks;
pub mod control;
pub mod diagnostics;
pub mod features;
pub mod feed;
pub mod force;
pub mod gcode;
pub mod geometry;
pub mod import;
pub mod machine;
pub mod post;
pub mod profile;
pub mod project;
pub mod reduce;
pub mod simulation;
pub mod storage;
pub mod strategies;
pub mod toolpath;
pub mod tools;
pub mod units;

pub mod cli;

#[cfg(feature = "gui")]
pub mod app;
#[cfg(feature = "gui")]
pub mod render;
