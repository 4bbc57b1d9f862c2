//! Tool-path strategies (L3): iso-parametric, iso-planar and iso-scallop finishing on exact
//! surfaces, raster finishing and Z-level roughing on meshes and Z-maps. Each strategy takes a
//! part (or face), a cutter and its parameters, and returns a [`crate::toolpath::Toolpath`] plus
//! diagnostics.

pub mod raster;
pub mod raster_check;
pub mod zlevel;
