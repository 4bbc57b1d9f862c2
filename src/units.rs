//! Units. Internally Talas works in millimetres, seconds and radians; conversions happen only at
//! the edges (file import, UI, G-code). Names carry their unit (`feed_mm_per_min`, `angle_rad`).

/// Millimetres per inch (exact).
pub const MM_PER_INCH: f64 = 25.4;
/// Millimetres per metre.
pub const MM_PER_M: f64 = 1000.0;

/// The rapid rate assumed where a machine's own is not known (time estimates, playback, G-code
/// interpretation and simulation defaults), mm/min: a typical mill's. One value for every stage.
pub const DEFAULT_RAPID_MM_PER_MIN: f64 = 10_000.0;

/// Degrees to radians.
#[must_use]
pub fn deg_to_rad(deg: f64) -> f64 {
    deg.to_radians()
}

/// Radians to degrees.
#[must_use]
pub fn rad_to_deg(rad: f64) -> f64 {
    rad.to_degrees()
}

/// Feed in mm/min to mm/s.
#[must_use]
pub fn mm_per_min_to_mm_per_s(feed_mm_per_min: f64) -> f64 {
    feed_mm_per_min / 60.0
}

/// Feed in mm/s to mm/min.
#[must_use]
pub fn mm_per_s_to_mm_per_min(feed_mm_per_s: f64) -> f64 {
    feed_mm_per_s * 60.0
}

/// A length unit a file may declare.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum LengthUnit {
    /// Millimetre (Talas's internal unit).
    Millimetre,
    /// Centimetre.
    Centimetre,
    /// Metre.
    Metre,
    /// Inch (25.4 mm).
    Inch,
    /// Foot (304.8 mm).
    Foot,
    /// Micrometre.
    Micrometre,
    /// Any other unit, given by its size in mm.
    Other(f64),
}

impl LengthUnit {
    /// Size of one unit in millimetres.
    #[must_use]
    pub fn to_mm(self) -> f64 {
        match self {
            Self::Millimetre => 1.0,
            Self::Centimetre => 10.0,
            Self::Metre => MM_PER_M,
            Self::Inch => MM_PER_INCH,
            Self::Foot => 12.0 * MM_PER_INCH,
            Self::Micrometre => 1e-3,
            Self::Other(mm) => mm,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_trip() {
        assert!((rad_to_deg(deg_to_rad(37.5)) - 37.5).abs() < 1e-12);
        assert!((mm_per_min_to_mm_per_s(1200.0) - 20.0).abs() < 1e-12);
        assert!((mm_per_s_to_mm_per_min(20.0) - 1200.0).abs() < 1e-12);
        assert!((LengthUnit::Inch.to_mm() - 25.4).abs() < 1e-15);
        assert!((LengthUnit::Foot.to_mm() - 304.8).abs() < 1e-12);
        assert!((LengthUnit::Other(2.5).to_mm() - 2.5).abs() < 1e-15);
    }
}
