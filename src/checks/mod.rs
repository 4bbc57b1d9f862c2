//! Checks on tool paths (L3): surface analysis for tool choice, local and rear gouge detection
//! against the exact surface, and the independent references used by the tests ([`oracle`]).
//!
//! Every check works on a [`FacePatch`]: a surface, the parameter rectangle of interest and the
//! side the tool is on. Curvatures here are signed with respect to the **tool-side** normal, so
//! a positive normal curvature is concave as the tool sees it (the surface bends toward the
//! tool) and a negative one convex.
//!
//! - [`oracle`]: independent references the tests check tool paths against (dense samples
//!   against the swept tool, without the planners' own contact computations).
//! - [`analysis`]: minimum concave/convex radii per parametric direction and principal; per-point
//!   curvatures for colour maps.
//! - [`choice`]: largest gouge-free ball end mill, standard flat diameter and minimum lead
//!   ("Sturz") against local gouging (thesis §2.8).
//! - [`gouge`]: local (curvature) and rear (tool solid against the surface under the footprint)
//!   gouge checks at poses and along moves, and the lead that fixes a gouge.
//! - [`collide`]: the tool assembly against fixed obstacles (a setup's workholding) along a
//!   motion: the first contact.
//! - [`part`]: the whole part as check: the tool (shank and holder too) against every other face
//!   of the part through its triangle mesh.

pub mod analysis;
pub mod choice;
pub mod collide;
mod contact;
mod footprint;
pub mod gouge;
pub(crate) mod motion;
pub mod oracle;
pub mod part;
pub mod sweep;

use glam::{DVec2, DVec3};

use crate::geometry::diffgeom::SurfaceDerivs;
use crate::geometry::surface::{ParamRect, SurfaceGeom};

pub use analysis::{CurvatureSample, RadiusExtreme, SurfaceAnalysis, analyze, curvature_at};
pub use choice::{
    FlatChoice, STANDARD_DIAMETERS_MM, ball_for_radius, flat_for_radius, flat_for_radius_with,
    min_lead_for_radius, standard_below,
};
pub use gouge::{
    Gouge, GougeKind, GougeOptions, GougeReport, check_move, check_path, check_pose,
    curvature_margin, effective_radius, pose_from_contact, required_lead,
};
pub use sweep::{SweptDistance, SweptTool};

/// Why a check could not run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CheckError {
    /// The parameter rectangle is empty, inverted or not finite.
    #[error("parameter rectangle must be finite and non-empty, got u {u0}..{u1}, v {v0}..{v1}")]
    BadRect {
        /// u start.
        u0: f64,
        /// u end.
        u1: f64,
        /// v start.
        v0: f64,
        /// v end.
        v1: f64,
    },
    /// An option is out of range (named, with the reason).
    #[error("invalid option {name}: {message}")]
    BadOption {
        /// The option.
        name: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A pose has a non-finite tip or a zero/non-finite axis.
    #[error("pose {index}: non-finite tip or axis")]
    BadPose {
        /// Index of the pose.
        index: usize,
    },
    /// The cutter's sizes are invalid.
    #[error(transparent)]
    Tool(#[from] crate::tools::ToolError),
}

/// A surface region to check: the surface, its parameter rectangle, and the side the tool is on.
#[derive(Clone, Copy, Debug)]
pub struct FacePatch<'a> {
    /// The exact surface.
    pub surface: &'a SurfaceGeom,
    /// Parameter rectangle (finite).
    pub rect: ParamRect,
    /// True when the tool is on the side opposite to `S_u × S_v` (a face with `same_sense ==
    /// false`, or a surface seen from below).
    pub flip: bool,
}

impl<'a> FacePatch<'a> {
    /// A patch; the rectangle must be finite and non-empty.
    ///
    /// # Errors
    /// [`CheckError::BadRect`].
    pub fn new(surface: &'a SurfaceGeom, rect: ParamRect, flip: bool) -> Result<Self, CheckError> {
        let ok =
            rect.u.is_finite() && rect.v.is_finite() && !rect.u.is_empty() && !rect.v.is_empty();
        if !ok {
            return Err(CheckError::BadRect {
                u0: rect.u.t0,
                u1: rect.u.t1,
                v0: rect.v.t0,
                v1: rect.v.t1,
            });
        }
        Ok(Self {
            surface,
            rect,
            flip,
        })
    }

    /// The whole (finite) domain of a surface, tool on the `S_u × S_v` side unless `flip`.
    ///
    /// # Errors
    /// [`CheckError::BadRect`] for unbounded surfaces (planes, cylinders: give a rectangle).
    pub fn whole(surface: &'a SurfaceGeom, flip: bool) -> Result<Self, CheckError> {
        Self::new(surface, surface.domain(), flip)
    }

    /// Derivatives at `uv`.
    #[must_use]
    pub fn derivs(&self, uv: DVec2) -> SurfaceDerivs {
        self.surface.derivs(uv.x, uv.y)
    }

    /// Point and tool-side unit normal at `uv` (`None` where the normal is undefined).
    #[must_use]
    pub fn point_normal(&self, uv: DVec2) -> Option<(DVec3, DVec3)> {
        let d = self.derivs(uv);
        let n = d.normal()?;
        Some((d.p, if self.flip { -n } else { n }))
    }

    /// Sign that turns curvatures with respect to `S_u × S_v` into tool-side curvatures
    /// (positive = concave as the tool sees it).
    #[must_use]
    pub fn sign(&self) -> f64 {
        if self.flip { -1.0 } else { 1.0 }
    }

    /// Clamp `uv` into the rectangle.
    #[must_use]
    pub fn clamp(&self, uv: DVec2) -> DVec2 {
        DVec2::new(self.rect.u.clamp(uv.x), self.rect.v.clamp(uv.y))
    }
}
