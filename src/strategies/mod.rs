//! Tool-path strategies (L3): iso-parametric, iso-planar and iso-scallop finishing on exact
//! surfaces ([`finish`]), raster, waterline, steep-and-shallow, pencil and rest finishing and
//! Z-level roughing on meshes and Z-maps. Each strategy takes a part (or face), a cutter and its
//! parameters, and returns a [`crate::toolpath::Toolpath`] plus diagnostics.

pub mod boundary;
pub mod finish;
pub mod holes;
pub mod pencil;
pub mod planar;
pub mod raster;
pub mod rest;
pub mod steep_shallow;
pub mod waterline;
pub mod zlevel;
pub mod zmap;
