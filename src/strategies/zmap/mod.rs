//! Tool paths on Z-maps: [`inverse_offset`] gives a cutter's CL Z-map (tip heights, the thesis's
//! Eqs. 4.7–4.10 generalised to every cutter profile; contacts at the nodes only), [`cl_zmap`] the
//! exact one of the triangulated Z-map (drop-cutter), and [`zmap_raster`] reads a raster
//! finishing path off either. Errors are [`crate::geometry::zmap::ZmapError`]s.

mod inverse_offset;
mod raster;

pub use inverse_offset::{cl_zmap, inverse_offset};
pub use raster::{ZmapPathOptions, zmap_raster};
