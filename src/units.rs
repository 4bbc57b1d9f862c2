//! Units. Internally Talas works in millimetres, seconds and radians; conversions happen only at
//! the edges (file import, UI, G-code), with the constants here. Names carry their unit
//! (`feed_mm_per_min`, `angle_rad`).

/// Millimetres per inch (exact).
pub const MM_PER_INCH: f64 = 25.4;

/// The rapid rate assumed where a machine's own is not known (time estimates, playback, G-code
/// interpretation and simulation defaults), mm/min: a typical mill's. One value for every stage.
pub const DEFAULT_RAPID_MM_PER_MIN: f64 = 10_000.0;

/// The bounds every length a file or an option gives must lie in (issue 36: a chord tolerance
/// of 1e-300 mm hung the planner, a step-down of 1e-300 mm aborted on allocation). A range
/// with the name of the value in the error, so a bad number is refused before any loop whose
/// length it decides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LengthBounds {
    /// Smallest value accepted, mm.
    pub min_mm: f64,
    /// Largest value accepted, mm.
    pub max_mm: f64,
}

/// Chord tolerances and scallop heights: 0.01 µm to 100 mm.
pub const TOLERANCE_BOUNDS: LengthBounds = LengthBounds {
    min_mm: 1e-5,
    max_mm: 100.0,
};
/// Step-downs and step sizes: 1 µm to 1 m.
pub const STEP_BOUNDS: LengthBounds = LengthBounds {
    min_mm: 1e-3,
    max_mm: 1000.0,
};
/// Allowances (stock to leave): 0 to 100 mm.
pub const ALLOWANCE_BOUNDS: LengthBounds = LengthBounds {
    min_mm: 0.0,
    max_mm: 100.0,
};
/// Heights and clearances: 0 to 10 m.
pub const CLEARANCE_BOUNDS: LengthBounds = LengthBounds {
    min_mm: 0.0,
    max_mm: 10_000.0,
};
/// Coordinates of a stock or a work piece: within ±10 m.
pub const MAX_COORDINATE_MM: f64 = 10_000.0;
/// Feeds, mm/min: 0.001 to 1 000 000.
pub const FEED_BOUNDS: LengthBounds = LengthBounds {
    min_mm: 1e-3,
    max_mm: 1e6,
};

/// `v` as an error message shows it: plain between 10⁻⁴ and 10⁹, else in exponent form (a
/// hostile 1e-300 is not 300 digits).
#[must_use]
pub fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e9).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

impl LengthBounds {
    /// `Ok` when `v` is finite and lies in the bounds; else the error naming `what`.
    ///
    /// # Errors
    /// "WHAT must lie in [MIN, MAX] mm, got V".
    pub fn check(self, what: &str, v: f64) -> Result<(), String> {
        if v.is_finite() && (self.min_mm..=self.max_mm).contains(&v) {
            Ok(())
        } else {
            Err(format!(
                "{what} must lie in [{:e}, {:e}], got {}",
                self.min_mm,
                self.max_mm,
                short(v)
            ))
        }
    }
}
