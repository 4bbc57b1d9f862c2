//! Helical end mills for the force model: the profile's local radius r(z) and axial immersion
//! angle κ(z) (the angle between the tool axis and the surface normal; π/2 on the cylinder),
//! the helix lag ψ(z) and the flutes' angular positions.
//!
//! The helix has a constant lead, so the lag is `ψ(z) = z·tan β / R` along the whole flute,
//! on the cylinder and on a ball or torus nose alike (Engin & Altintas' constant-lead ball end
//! mill); on the cylinder this is the thesis's `k_β z` (Eq. 5.1). The tip leads: a point at
//! height z reaches a given angle ψ(z) later than the tip.

use std::f64::consts::TAU;

use super::ForceError;
use crate::tools::{Cutter, CutterKind};

/// The cutting end's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Profile {
    /// Cylindrical flat end mill.
    Flat,
    /// Ball end mill (hemisphere of the tool radius).
    Ball,
    /// Bull-nose end mill with this corner radius, mm.
    Bull {
        /// Corner radius, mm.
        corner_radius: f64,
    },
}

/// The profile at one height: local radius and axial immersion angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Local {
    /// Distance of the edge from the axis, mm.
    pub radius: f64,
    /// sin κ: 1 on the cylinder, → 0 at a ball's tip.
    pub sin_kappa: f64,
    /// cos κ: 0 on the cylinder, → 1 at a ball's tip.
    pub cos_kappa: f64,
}

/// A helical end mill.
#[derive(Clone, Debug, PartialEq)]
pub struct EndMill {
    /// Shape of the cutting end.
    pub profile: Profile,
    /// Tool radius R, mm.
    pub radius: f64,
    /// Helix angle β, rad.
    pub helix: f64,
    /// Normal rake angle, rad (the coefficients depend on it; the geometry does not).
    pub rake: f64,
    /// Angular position of each flute's tip relative to flute 0, rad (θ_0 = 0, increasing).
    pub flute_angles: Vec<f64>,
}

impl EndMill {
    /// An end mill with `flutes` evenly pitched flutes.
    ///
    /// # Errors
    /// [`ForceError::Input`] for a diameter outside (0, 1000] mm, 0 or more than 16 flutes, a
    /// helix outside [0°, 60°), a rake outside [−30°, 45°] or a corner radius outside
    /// (0, R].
    pub fn new(
        profile: Profile,
        diameter: f64,
        flutes: u32,
        helix: f64,
        rake: f64,
    ) -> Result<Self, ForceError> {
        if !(1..=16).contains(&flutes) {
            return Err(ForceError::Input(format!(
                "flute count must be 1 to 16, got {flutes}"
            )));
        }
        let pitch = TAU / f64::from(flutes);
        Self::with_flute_angles(
            profile,
            diameter,
            (0..flutes).map(|j| f64::from(j) * pitch).collect(),
            helix,
            rake,
        )
    }

    /// An end mill with the given flute positions (variable pitch): `angles[0]` must be 0 and
    /// the angles increasing and below 2π.
    ///
    /// # Errors
    /// As [`EndMill::new`], and for flute angles that are not increasing in [0, 2π).
    pub fn with_flute_angles(
        profile: Profile,
        diameter: f64,
        angles: Vec<f64>,
        helix: f64,
        rake: f64,
    ) -> Result<Self, ForceError> {
        super::check_range("tool diameter", diameter, 1e-3, 1000.0, "mm")?;
        super::check_range("helix angle", helix.to_degrees(), 0.0, 59.999, "degrees")?;
        super::check_range("rake angle", rake.to_degrees(), -30.0, 45.0, "degrees")?;
        let ok = !angles.is_empty()
            && angles.len() <= 16
            && angles[0] == 0.0
            && angles.windows(2).all(|w| w[1] > w[0])
            && angles.iter().all(|a| a.is_finite() && *a < TAU);
        if !ok {
            return Err(ForceError::Input(
                "flute angles must start at 0 and increase below 360 degrees (1 to 16 flutes)"
                    .into(),
            ));
        }
        let radius = 0.5 * diameter;
        if let Profile::Bull { corner_radius } = profile {
            super::check_range("corner radius", corner_radius, 1e-6, radius, "mm")?;
        }
        Ok(Self {
            profile,
            radius,
            helix,
            rake,
            flute_angles: angles,
        })
    }

    /// The force model's end mill for a cutter from the tool library or a tool SPEC.
    ///
    /// # Errors
    /// [`ForceError::Tool`] for a cone cutter or a cutter without `flutes=N`.
    pub fn from_cutter(cutter: &Cutter) -> Result<Self, ForceError> {
        let flutes = cutter.flutes.ok_or_else(|| {
            ForceError::Tool(
                "the tool SPEC needs flutes=N (and helix=DEG, rake=DEG) for cutting forces".into(),
            )
        })?;
        let profile = match cutter.kind {
            CutterKind::Flat => Profile::Flat,
            CutterKind::Ball => Profile::Ball,
            CutterKind::BullNose { corner_radius } => Profile::Bull { corner_radius },
            CutterKind::Cone { .. } => {
                return Err(ForceError::Tool(
                    "cone cutters have no helical-end-mill force model".into(),
                ));
            }
        };
        Self::new(
            profile,
            cutter.diameter,
            flutes.count,
            flutes.helix,
            flutes.rake,
        )
    }

    /// Number of flutes.
    #[must_use]
    pub fn flutes(&self) -> usize {
        self.flute_angles.len()
    }

    /// Diameter, mm.
    #[must_use]
    pub fn diameter(&self) -> f64 {
        2.0 * self.radius
    }

    /// k_β = tan β / R, rad/mm: the lag per unit height.
    #[must_use]
    pub fn k_beta(&self) -> f64 {
        self.helix.tan() / self.radius
    }

    /// Critical axial depth for even pitch, mm: `R·φ_p / tan β` (∞ for straight flutes). Below
    /// it one point of the flutes generates the wall at a time.
    #[must_use]
    pub fn critical_depth(&self) -> f64 {
        let pitch = TAU / self.flutes() as f64;
        let k = self.k_beta();
        if k > 0.0 { pitch / k } else { f64::INFINITY }
    }

    /// Height of the nose (where the profile reaches the full radius), mm.
    #[must_use]
    pub fn nose_height(&self) -> f64 {
        match self.profile {
            Profile::Flat => 0.0,
            Profile::Ball => self.radius,
            Profile::Bull { corner_radius } => corner_radius,
        }
    }

    /// The profile at height `z` above the tip (mm).
    #[must_use]
    pub fn local(&self, z: f64) -> Local {
        let cylinder = Local {
            radius: self.radius,
            sin_kappa: 1.0,
            cos_kappa: 0.0,
        };
        let (rc, inner) = match self.profile {
            Profile::Flat => return cylinder,
            Profile::Ball => (self.radius, 0.0),
            Profile::Bull { corner_radius } => (corner_radius, self.radius - corner_radius),
        };
        if z >= rc {
            return cylinder;
        }
        let cos_kappa = ((rc - z) / rc).clamp(0.0, 1.0);
        let sin_kappa = (1.0 - cos_kappa * cos_kappa).max(0.0).sqrt();
        Local {
            radius: inner + rc * sin_kappa,
            sin_kappa,
            cos_kappa,
        }
    }
}

/// `a` wrapped into [0, 2π).
#[must_use]
pub fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w >= TAU { 0.0 } else { w }
}
