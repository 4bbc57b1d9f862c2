//! Cutting forces of helical end mills, the tool's static deflection and the wall (form) error
//! it leaves, and the calibration of the force coefficients from measured mean forces.
//!
//! The model is the mechanistic one of Altintas and of Aydın's thesis (2014): the flute is cut
//! into axial disks, each disk element carries a tangential, radial and axial force
//! proportional to its chip thickness `h = f_t·sin φ·sin κ` plus an edge force
//! ([`coefficients::LinearCoefficients`]), or, in the exponential model, coefficients that are
//! power laws of the mean chip thickness ([`coefficients::ExponentialCoefficients`]).
//!
//! - [`mill`]: flat, ball and bull-nose end mills: local radius and axial immersion angle along
//!   the profile, constant-lead helix lag, per-flute pitch angles.
//! - [`cut`]: entry/exit angles of up, down and slot milling, per disk; the disk layout.
//! - [`closed_form`]: the integrals of the elemental forces along the engaged flute (flat end
//!   mills) and the closed-form mean forces per revolution (any profile, exact in the rotation
//!   angle).
//! - [`disks`]: the numerical disk sums (Gauss–Legendre inside each disk, split where the edge
//!   enters or leaves the cut) for any profile and any per-disk engagement.
//! - [`mod@revolution`]: forces, resultant, torque and power against the rotation angle over one
//!   revolution; peak (signed value of largest magnitude) and mean.
//! - [`deflection`]: the tool as a stepped cantilever and the wall error at the
//!   surface-generation points.
//! - [`path`]: forces along a tool path or program, move by move, with the engagement read
//!   from the material before each move and the move then removed from it.
//! - [`schedule`]: the feed per tooth that holds the peak resultant force at a target.
//! - [`stock`]: engagement read from the material (the Z-dexel stock) for a tool at a position
//!   moving in a direction: per disk, the front-half angles whose edge points are in material.
//! - [`calibrate`]: mean-force regression (linear model, `nalgebra`), nonlinear least squares
//!   for the exponential model (`levenberg-marquardt`), and the thesis's cutting-force
//!   distribution method; [`measurements`] reads FORCES.csv; [`library`] the TOML coefficient
//!   library.
//!
//! Frame (Altintas): x is the feed direction, y the normal to it in the tool's plane, z the tool
//! axis up from the tip; forces act on the tool, in N. The rotation angle φ of flute 0's tip is
//! measured clockwise from +y. Lengths in mm, angles in rad, coefficients in N/mm² (cutting)
//! and N/mm (edge).

pub mod calibrate;
pub mod closed_form;
pub mod coefficients;
pub mod cut;
pub mod cutting_data;
pub mod deflection;
pub mod disks;
pub mod library;
pub mod measurements;
pub mod mill;
pub mod path;
pub mod revolution;
pub mod schedule;
pub mod stock;

pub use coefficients::{Coefficients, ExponentialCoefficients, LinearCoefficients};
pub use cut::{Arcs, Engagement, Mode, StraightCut};
pub use mill::{EndMill, Profile};
pub use revolution::{Revolution, RevolutionOptions, revolution};

/// Why a force computation or a calibration cannot be done.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ForceError {
    /// A number outside its sane range (the message says which and why).
    #[error("{0}")]
    Input(String),
    /// The tool cannot be modelled (no flute geometry, cone cutter, ...).
    #[error("tool: {0}")]
    Tool(String),
    /// A move of a path cannot be modelled (`block`: its G-code line or tool-path pose).
    #[error("block {block}: {message}")]
    Move {
        /// G-code line or tool-path pose index.
        block: usize,
        /// What is wrong.
        message: String,
    },
    /// The measurements do not determine the coefficients.
    #[error("calibration: {0}")]
    Calibration(String),
}

/// `Err(ForceError::Input)` unless `v` is finite and in `[lo, hi]`.
pub(crate) fn check_range(
    what: &str,
    v: f64,
    lo: f64,
    hi: f64,
    unit: &str,
) -> Result<(), ForceError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(ForceError::Input(format!(
            "{what} must be between {lo} and {hi} {unit}, got {v}"
        )))
    }
}

/// A force vector in the feed frame, N.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Force {
    /// Along the feed, N.
    pub fx: f64,
    /// Normal to the feed, N.
    pub fy: f64,
    /// Along the tool axis (up), N.
    pub fz: f64,
}

impl Force {
    /// Euclidean norm, N.
    #[must_use]
    pub fn resultant(&self) -> f64 {
        (self.fx * self.fx + self.fy * self.fy + self.fz * self.fz).sqrt()
    }
}

impl std::ops::AddAssign for Force {
    fn add_assign(&mut self, o: Self) {
        self.fx += o.fx;
        self.fy += o.fy;
        self.fz += o.fz;
    }
}
