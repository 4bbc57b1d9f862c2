//! 2.5D strategies on planar regions ([`crate::geometry::planar::Region`]): offset pocketing
//! with step-downs, ramp entry and a finishing level, adaptive clearing at a constant engagement, contours with leads and tabs, and facing; lines stay lines and arcs are written as
//! exact arcs (`ExactSegment`), sloped arcs of a ramp as helices.

mod adaptive;
mod contour;
mod facing;
mod pocket;

pub use adaptive::{AdaptiveOptions, adaptive};
pub use contour::{ContourOptions, ContourSide, contour};
pub use facing::{FacingOptions, facing};
pub use pocket::{PocketOptions, pocket};

/// Why a 2.5D path could not be planned.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct PlanarError(pub String);
