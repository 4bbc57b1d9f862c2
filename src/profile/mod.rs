//! 2D section profiles and the path of a ball-ended electrode (sinker EDM) or ball end mill
//! that finishes them.
//!
//! A [`Profile`] is an open or closed chain of lines and circular arcs (each vertex carries the
//! bulge of the element that leaves it, `tan(sweep / 4)`, positive counter-clockwise); a
//! function `y = f(x)` given as points is the simplest case. Profiles are read from and written
//! to CSV, DXF and SVG ([`read_profile`], [`write_profile`]).
//!
//! [`compute`] offsets the profile by the electrode radius R on its material-free side with
//! `cavalier_contours` (round joins at convex corners, self-intersections trimmed), so the
//! centre path never comes closer than R to the profile; every path vertex carries its contact
//! point and the electrode's lowest point. The same call evaluates the naïve path of the
//! per-point method (centre = point + R · normal, normal from the neighbouring points) and
//! measures every gouge it would make against the exact profile: a *plunge* where the profile
//! near the point turns concavely into the ball (a concave radius smaller than R), a *side
//! collision* where another part of the profile enters it. [`max_gouge_free_radius`] is the
//! largest electrode that touches every point of the profile from the free side (the
//! one-sided reach: the smallest concave radius, zero at a concave corner, and half the
//! narrowest bottleneck).
//!
//! Output: the CL table, G-code with G1 and G2/G3 through a post dialect in G17, G18 or G19
//! ([`write_gcode`], through the one post from the tool path of [`centre_toolpath`]), and a
//! [`crate::toolpath::Toolpath`] of the lowest points for the simulation ([`to_toolpath`]).

mod analysis;
mod gcode;
mod reach;
mod reach_tolerance;

pub use analysis::{
    Flag, FlagKind, NaivePoint, ProfileOptions, ProfileResult, compute, compute_opt,
};
pub use gcode::{GcodeOptions, ProfilePlane, centre_toolpath, to_toolpath, write_gcode};
pub use reach::max_gouge_free_radius;
pub use reach_tolerance::max_radius_within_tolerance;

// The 2D geometry lives in the geometry kernel (`geometry::planar`); re-exported here so that
// the EDM callers keep their paths.
pub use crate::geometry::planar::{
    ClPath, ClVertex, Element, MAX_COORD_MM, Profile, ProfileError, ProfileFormat, Side, Vertex,
    distance_to_profile, parse_csv, parse_dxf, parse_svg, profile_to_csv, profile_to_dxf,
    profile_to_svg, read_profile, write_profile,
};
