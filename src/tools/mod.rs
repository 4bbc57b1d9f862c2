//! Cutters as profiles, in OpenCAMLib's style: a rotationally symmetric lower surface described by
//! [`Cutter::height_at_radius`] and [`Cutter::radius_at_height`], plus shank and holder cylinders.
//! The drop-cutter ([`dropcutter`]) works on any profile through the same vertex, facet and edge
//! tests.
//!
//! All lengths in mm, angles in rad. The tool tip (the lowest point on the axis) is the origin of
//! the profile: height 0 at radius 0.

pub mod dropcutter;
pub mod effective;
pub mod hole_tool;
pub mod solid;
mod spec;

pub use spec::{parse_tool_spec, tool_spec};

/// The shape of a cutter's cutting end.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum CutterKind {
    /// Ball end mill: a hemisphere of radius d/2.
    Ball,
    /// Flat (cylindrical) end mill.
    Flat,
    /// Bull-nose (toroidal) end mill: flat bottom of radius d/2 − r, then a quarter torus of
    /// corner radius r.
    BullNose {
        /// Corner radius r, mm (0 < r ≤ d/2; r = d/2 is a ball).
        corner_radius: f64,
    },
    /// Cone (taper, engraving or chamfer tool) with its apex at the tip.
    Cone {
        /// Angle between the axis and the flank, rad (0 < α < π/2).
        half_angle: f64,
    },
}

/// One cylinder of a tool holder, from the bottom up.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct HolderSection {
    /// Diameter, mm.
    pub diameter: f64,
    /// Length along the axis, mm.
    pub length: f64,
}

/// A cutter: cutting-end profile, flutes, shank and holder. Build it with [`Cutter::new`] or
/// [`parse_tool_spec`], which validate the sizes.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cutter {
    /// The shape of the cutting end.
    pub kind: CutterKind,
    /// Cutting diameter, mm.
    pub diameter: f64,
    /// Length of the fluted (cutting) part from the tip, mm.
    pub flute_length: f64,
    /// Shank diameter, mm.
    pub shank_diameter: f64,
    /// Overall length of the tool out of the holder (tip to holder face), mm.
    pub overall_length: f64,
    /// Holder cylinders from the holder face upward (may be empty).
    pub holder: Vec<HolderSection>,
    /// Flute count, helix and rake (what the cutting-force model needs); `None` when the spec
    /// did not give them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flutes: Option<Flutes>,
    /// Load limits of the tool (cutting-force checks); all absent when not given.
    #[serde(default, skip_serializing_if = "ToolLimits::is_empty")]
    pub limits: ToolLimits,
}

/// The loads a tool may carry, checked by the cutting-force model (each optional).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(deny_unknown_fields)]
pub struct ToolLimits {
    /// Largest resultant cutting force on the tool, N.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_force_n: Option<f64>,
    /// Largest cutting torque, N·m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_torque_nm: Option<f64>,
    /// Largest cutting power, W.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_power_w: Option<f64>,
}

impl ToolLimits {
    /// No limit given.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.max_force_n.is_none() && self.max_torque_nm.is_none() && self.max_power_w.is_none()
    }

    /// Check the ranges: each given limit positive and finite, force ≤ 10⁶ N, torque ≤ 10⁵ N·m,
    /// power ≤ 10⁷ W.
    ///
    /// # Errors
    /// [`ToolError::Dimension`] naming the limit out of range.
    pub fn validate(&self) -> Result<(), ToolError> {
        let checks = [
            ("max_force_n", self.max_force_n, 1e6, "N"),
            ("max_torque_nm", self.max_torque_nm, 1e5, "N·m"),
            ("max_power_w", self.max_power_w, 1e7, "W"),
        ];
        for (name, v, hi, unit) in checks {
            if let Some(v) = v
                && !(v.is_finite() && v > 0.0 && v <= hi)
            {
                return Err(ToolError::Dimension(format!(
                    "{name} must be above 0 and at most {hi:e} {unit}, got {v}"
                )));
            }
        }
        Ok(())
    }
}

/// The cutting edges of a helical end mill: what the cutting-force model needs beyond the
/// profile.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct Flutes {
    /// Number of flutes (1 to 16), evenly pitched.
    pub count: u32,
    /// Helix angle, rad (0 ≤ β < 60°).
    pub helix: f64,
    /// Normal rake angle, rad (−30° to 45°).
    pub rake: f64,
}

impl Flutes {
    /// Default helix when a spec gives `flutes=` but no `helix=`, rad (30°).
    pub const DEFAULT_HELIX: f64 = std::f64::consts::FRAC_PI_6;

    /// Check the ranges: 1–16 flutes, helix in [0°, 60°), rake in [−30°, 45°].
    ///
    /// # Errors
    /// [`ToolError::Dimension`] naming the value out of range.
    pub fn validate(&self) -> Result<(), ToolError> {
        if !(1..=16).contains(&self.count) {
            return Err(ToolError::Dimension(format!(
                "flute count must be 1 to 16, got {}",
                self.count
            )));
        }
        if !(self.helix >= 0.0 && self.helix < 60f64.to_radians()) {
            return Err(ToolError::Dimension(format!(
                "helix must be at least 0 and below 60 degrees, got {} degrees",
                self.helix.to_degrees()
            )));
        }
        if !(self.rake >= -30f64.to_radians() && self.rake <= 45f64.to_radians()) {
            return Err(ToolError::Dimension(format!(
                "rake must be between -30 and 45 degrees, got {} degrees",
                self.rake.to_degrees()
            )));
        }
        Ok(())
    }
}

/// Why a cutter or a tool spec is invalid.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ToolError {
    /// The spec string is malformed (unknown kind, key or syntax).
    #[error("bad tool spec '{spec}': {message}")]
    Spec {
        /// The spec as given.
        spec: String,
        /// What is wrong.
        message: String,
    },
    /// A size is not a positive finite number, or sizes contradict each other.
    #[error("invalid tool dimension: {0}")]
    Dimension(String),
}

impl Cutter {
    /// A cutter with default flute length (3·d, at least the profile height), shank (= d),
    /// overall length (flute + 2·d) and no holder.
    ///
    /// # Errors
    /// [`ToolError::Dimension`] for a non-positive or non-finite diameter, a corner radius outside
    /// (0, d/2], or a cone half-angle outside (0, π/2).
    pub fn new(kind: CutterKind, diameter: f64) -> Result<Self, ToolError> {
        let mut c = Self {
            kind,
            diameter,
            flute_length: 0.0,
            shank_diameter: diameter,
            overall_length: 0.0,
            holder: Vec::new(),
            flutes: None,
            limits: ToolLimits::default(),
        };
        c.validate_profile()?;
        c.flute_length = (3.0 * diameter).max(c.profile_height());
        c.overall_length = c.flute_length + 2.0 * diameter;
        c.validate()?;
        Ok(c)
    }

    /// Check every size: positive and finite, corner radius ≤ d/2, cone angle in (0, π/2), flute
    /// length at least the profile height, overall length at least the flute length.
    ///
    /// # Errors
    /// [`ToolError::Dimension`] naming the first bad size.
    pub fn validate(&self) -> Result<(), ToolError> {
        self.validate_profile()?;
        length("flute length", self.flute_length)?;
        positive("shank diameter", self.shank_diameter)?;
        length("overall length", self.overall_length)?;
        if self.flute_length < self.profile_height() {
            return Err(ToolError::Dimension(format!(
                "flute length {} mm is shorter than the cutting end's height {} mm",
                self.flute_length,
                self.profile_height()
            )));
        }
        if self.overall_length < self.flute_length {
            return Err(ToolError::Dimension(format!(
                "overall length {} mm is shorter than the flute length {} mm",
                self.overall_length, self.flute_length
            )));
        }
        for (i, h) in self.holder.iter().enumerate() {
            positive(&format!("holder section {} diameter", i + 1), h.diameter)?;
            length(&format!("holder section {} length", i + 1), h.length)?;
        }
        if let Some(f) = &self.flutes {
            f.validate()?;
        }
        self.limits.validate()?;
        Ok(())
    }

    fn validate_profile(&self) -> Result<(), ToolError> {
        positive("diameter", self.diameter)?;
        match self.kind {
            CutterKind::BullNose { corner_radius } => {
                positive("corner radius", corner_radius)?;
                if corner_radius > self.radius() {
                    return Err(ToolError::Dimension(format!(
                        "corner radius {corner_radius} mm exceeds half the diameter {} mm",
                        self.radius()
                    )));
                }
            }
            CutterKind::Cone { half_angle } => {
                if !(half_angle > 0.0 && half_angle < std::f64::consts::FRAC_PI_2) {
                    return Err(ToolError::Dimension(format!(
                        "cone half-angle must be between 0 and 90 degrees, got {} degrees",
                        half_angle.to_degrees()
                    )));
                }
            }
            CutterKind::Ball | CutterKind::Flat => {}
        }
        Ok(())
    }

    /// Cutting radius d/2, mm.
    #[must_use]
    pub fn radius(&self) -> f64 {
        0.5 * self.diameter
    }

    /// Radius of the flat bottom, mm (0 for ball and cone).
    #[must_use]
    pub fn flat_radius(&self) -> f64 {
        match self.kind {
            CutterKind::Flat => self.radius(),
            CutterKind::BullNose { corner_radius } => self.radius() - corner_radius,
            CutterKind::Ball | CutterKind::Cone { .. } => 0.0,
        }
    }

    /// Height above the tip where the profile reaches the full radius, mm (ball: d/2, flat: 0,
    /// bull-nose: r, cone: (d/2)/tan α).
    #[must_use]
    pub fn profile_height(&self) -> f64 {
        match self.kind {
            CutterKind::Ball => self.radius(),
            CutterKind::Flat => 0.0,
            CutterKind::BullNose { corner_radius } => corner_radius,
            CutterKind::Cone { half_angle } => self.radius() / half_angle.tan(),
        }
    }

    /// Height of the lower surface above the tip at distance `r` from the axis, mm; `None` for
    /// r outside [0, d/2] or not finite.
    #[must_use]
    pub fn height_at_radius(&self, r: f64) -> Option<f64> {
        let big = self.radius();
        if !(r >= 0.0 && r <= big) {
            return None;
        }
        Some(match self.kind {
            CutterKind::Ball => big - (big * big - r * r).max(0.0).sqrt(),
            CutterKind::Flat => 0.0,
            CutterKind::BullNose { corner_radius } => {
                let a = big - corner_radius;
                if r <= a {
                    0.0
                } else {
                    let q = r - a;
                    corner_radius - (corner_radius * corner_radius - q * q).max(0.0).sqrt()
                }
            }
            CutterKind::Cone { half_angle } => r / half_angle.tan(),
        })
    }

    /// Radius of the tool at height `h` above the tip, mm: the profile below
    /// [`Cutter::profile_height`], the cutting diameter up to the flute length, the shank up to
    /// the overall length, then the holder sections; `None` for negative, non-finite heights or
    /// heights above the holder.
    #[must_use]
    pub fn radius_at_height(&self, h: f64) -> Option<f64> {
        if !(h >= 0.0) || !h.is_finite() {
            return None;
        }
        let big = self.radius();
        if h < self.profile_height() {
            return Some(match self.kind {
                CutterKind::Ball => (big * big - (big - h) * (big - h)).max(0.0).sqrt(),
                CutterKind::Flat => big,
                CutterKind::BullNose { corner_radius } => {
                    let q = corner_radius - h;
                    big - corner_radius + (corner_radius * corner_radius - q * q).max(0.0).sqrt()
                }
                CutterKind::Cone { half_angle } => h * half_angle.tan(),
            });
        }
        if h <= self.flute_length {
            return Some(big);
        }
        if h <= self.overall_length {
            return Some(0.5 * self.shank_diameter);
        }
        let mut top = self.overall_length;
        for s in &self.holder {
            top += s.length;
            if h <= top {
                return Some(0.5 * s.diameter);
            }
        }
        None
    }
}

/// The smallest tool size accepted (diameters, radii, lengths), mm.
pub const MIN_TOOL_SIZE_MM: f64 = 1e-3;
/// The largest diameter (cutter, shank, holder section) or corner radius accepted, mm: beyond
/// it a number is a typing error or hostile (a ball of 10³⁰⁰ mm removed nothing, one of 10²⁰ mm
/// exactly half the stock).
pub const MAX_TOOL_DIAMETER_MM: f64 = 1000.0;
/// The largest length (flutes, overall, a holder section) accepted, mm: five of the largest
/// diameters, the default overall length of such a cutter.
pub const MAX_TOOL_LENGTH_MM: f64 = 5.0 * MAX_TOOL_DIAMETER_MM;

/// A diameter or radius in [`MIN_TOOL_SIZE_MM`], [`MAX_TOOL_DIAMETER_MM`].
fn positive(what: &str, v: f64) -> Result<(), ToolError> {
    bounded(what, v, MAX_TOOL_DIAMETER_MM)
}

/// A length in [`MIN_TOOL_SIZE_MM`], [`MAX_TOOL_LENGTH_MM`].
fn length(what: &str, v: f64) -> Result<(), ToolError> {
    bounded(what, v, MAX_TOOL_LENGTH_MM)
}

fn bounded(what: &str, v: f64, max: f64) -> Result<(), ToolError> {
    if v.is_finite() && (MIN_TOOL_SIZE_MM..=max).contains(&v) {
        Ok(())
    } else {
        Err(ToolError::Dimension(format!(
            "{what} must be a length from {MIN_TOOL_SIZE_MM} to {max} mm, got {}",
            crate::units::short(v)
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_invert() {
        let cutters = [
            Cutter::new(CutterKind::Ball, 6.0),
            Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0),
            Cutter::new(CutterKind::Cone { half_angle: 0.5 }, 10.0),
        ];
        for c in cutters {
            let c = c.expect("valid");
            for i in 1..20 {
                let h = c.profile_height() * f64::from(i) / 20.0;
                let r = c.radius_at_height(h).expect("inside");
                let h2 = c.height_at_radius(r).expect("inside");
                assert!((h - h2).abs() < 1e-9, "{c:?} h {h} r {r} h2 {h2}");
            }
        }
    }

    #[test]
    fn bad_sizes_are_errors() {
        assert!(Cutter::new(CutterKind::Ball, -1.0).is_err());
        assert!(Cutter::new(CutterKind::Ball, f64::NAN).is_err());
        assert!(Cutter::new(CutterKind::BullNose { corner_radius: 6.0 }, 10.0).is_err());
        assert!(Cutter::new(CutterKind::Cone { half_angle: 1.6 }, 10.0).is_err());
    }
}
