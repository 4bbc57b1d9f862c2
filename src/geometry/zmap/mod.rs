//! Z-maps: regular grids of heights (row index ↔ y, column index ↔ x, as in the thesis) and the
//! thesis's XY-dependent Z-map, built from meshes, parametric surfaces and scattered points, and
//! turned back into triangle meshes.
//!
//! A regular Z-map comes from a mesh ([`zmap_from_mesh`], vertical ray casts) or from a
//! parametric surface ([`zmap_from_surface`], Newton on x(u,v), y(u,v)); irregular data (mesh
//! vertices, point clouds) gives the XY-dependent Z-map ([`xy_zmap_from_points`]). Their SVD
//! reduction is [`crate::reduce`]; tool paths read off them are [`crate::strategies::zmap`].

mod error;
mod grid;
mod mesh_zmap;
mod surface_zmap;
mod xy_zmap;

pub use error::ZmapError;
pub use grid::Grid;
pub use mesh_zmap::{grid_mesh, zmap_from_mesh};
pub(crate) use surface_zmap::invert_xy;
pub use surface_zmap::{SurfaceZmap, zmap_from_surface};
pub use xy_zmap::{EmptyCellFill, XyZmap, xy_mesh, xy_zmap_from_points};
