//! Independent references for the tests: checks that measure a finished tool path without the
//! planners' own contact computations, so a test compares the planner against something else.
//!
//! - [`surface`]: dense samples of an exact surface against the union of the tool envelopes
//!   swept along the cutting moves: remaining height (scallop) and penetration (gouge).
//! - [`raster`]: 3-axis ball-end paths on a mesh against the closed-form lower envelope of the
//!   swept ball (no drop-cutter): remaining height and gouge.
//!
//! They ship in the library (the integration tests link it) but nothing in the library calls them.

pub mod raster;
pub mod surface;
