//! Units. Internally Talas works in millimetres, seconds and radians; conversions happen only at
//! the edges (file import, UI, G-code), with the constants here. Names carry their unit
//! (`feed_mm_per_min`, `angle_rad`).

/// Millimetres per inch (exact).
pub const MM_PER_INCH: f64 = 25.4;

/// The rapid rate assumed where a machine's own is not known (time estimates, playback, G-code
/// interpretation and simulation defaults), mm/min: a typical mill's. One value for every stage.
pub const DEFAULT_RAPID_MM_PER_MIN: f64 = 10_000.0;
