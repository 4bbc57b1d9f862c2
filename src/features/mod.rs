//! Machining features read from the B-rep: what a part asks to be made, in the terms a shop uses,
//! found from the faces' exact surfaces rather than from triangles. Strategies plan operations
//! from these.
//! - [`holes`]: holes with their diameters, depths and bottoms, compound holes, groups.
//! - [`regions`]: the regions a 2.5D strategy machines (pockets, steps, slots, the top and the
//!   outer profile seen from +Z).

pub mod holes;
pub mod regions;
