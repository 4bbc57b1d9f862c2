//! Tool choice against local gouging (thesis §2.8 and its worked examples).
//!
//! - Ball end mill: no local gouge while the ball radius stays below the smallest concave radius
//!   ρ (both parametric directions, or principal): D < 2ρ.
//! - Flat end mill tilted by the lead ("Sturz") S in the feed plane: the bottom's effective
//!   radius across the feed is r/sin S, so no local gouge needs r/sin S ≤ ρ: S = asin(r/ρ).
//! - Bull-nose with flat radius R_f = D/2 − r_c and corner radius r_c at lead S: effective
//!   radius R_f/sin S + r_c (Rao 1997), so S = asin(R_f/(ρ − r_c)).
//!
//! Procedure 1 (small ρ): r = ρ·sin S_max, D = 2r, take the next smaller standard diameter and
//! recompute S. Procedure 2 (large ρ, the user's D): S = asin(r/ρ).

use crate::tools::{Cutter, CutterKind};

/// Standard cutter diameters, mm, used by the suggestions. The thesis does not print its list;
/// its worked examples fix part of it: ρ = 20 mm at S_max = 20° gives D ≤ 13.68 and the thesis
/// takes **10** (so neither 12 nor 13 is on its list), and ρ = 26.0545 gives D ≤ 17.82 → **16**.
/// This list (a preferred-number series of end-mill sizes without 12 and 14) reproduces both;
/// pass your own list to the `_with` functions for a different catalogue.
pub const STANDARD_DIAMETERS_MM: [f64; 17] = [
    0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 16.0, 20.0, 25.0, 32.0, 40.0, 50.0,
];

/// The largest standard diameter strictly below `limit_mm` (`None` when there is none).
#[must_use]
pub fn standard_below(limit_mm: f64, standards: &[f64]) -> Option<f64> {
    standards
        .iter()
        .copied()
        .filter(|d| d.is_finite() && *d > 0.0 && *d < limit_mm)
        .max_by(f64::total_cmp)
}

/// Ball end mill for the smallest concave radius `rho_mm`: `(diameter bound 2ρ, largest standard
/// diameter below it)`. `None` for a non-positive or non-finite ρ (no concave region: any ball).
#[must_use]
pub fn ball_for_radius(rho_mm: f64) -> Option<(f64, Option<f64>)> {
    (rho_mm.is_finite() && rho_mm > 0.0).then(|| {
        let bound = 2.0 * rho_mm;
        (bound, standard_below(bound, &STANDARD_DIAMETERS_MM))
    })
}

/// A flat end mill suggestion (procedure 1).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FlatChoice {
    /// Largest diameter at the maximum lead: 2ρ·sin S_max, mm.
    pub max_diameter_mm: f64,
    /// The standard diameter chosen (next smaller), mm.
    pub diameter_mm: f64,
    /// The minimum lead for it: asin((D/2)/ρ), rad.
    pub lead_rad: f64,
}

/// Procedure 1 with [`STANDARD_DIAMETERS_MM`]: flat end mill for concave radius `rho_mm` and
/// maximum lead `max_lead_rad` (the thesis uses 20°).
#[must_use]
pub fn flat_for_radius(rho_mm: f64, max_lead_rad: f64) -> Option<FlatChoice> {
    flat_for_radius_with(rho_mm, max_lead_rad, &STANDARD_DIAMETERS_MM)
}

/// Procedure 1 with your own standard diameters. `None` for bad inputs or no standard size.
#[must_use]
pub fn flat_for_radius_with(
    rho_mm: f64,
    max_lead_rad: f64,
    standards: &[f64],
) -> Option<FlatChoice> {
    let ok = rho_mm.is_finite()
        && rho_mm > 0.0
        && max_lead_rad > 0.0
        && max_lead_rad < std::f64::consts::FRAC_PI_2;
    if !ok {
        return None;
    }
    let max_d = 2.0 * rho_mm * max_lead_rad.sin();
    // "Next smaller": a standard diameter equal to the bound is also gouge-free.
    let d = standards
        .iter()
        .copied()
        .filter(|d| d.is_finite() && *d > 0.0 && *d <= max_d)
        .max_by(f64::total_cmp)?;
    Some(FlatChoice {
        max_diameter_mm: max_d,
        diameter_mm: d,
        lead_rad: (0.5 * d / rho_mm).asin(),
    })
}

/// Procedure 2: the smallest lead (rad) at which `cutter` has no local gouge on a concave radius
/// `rho_mm` across the feed: 0 when its effective radius at zero lead already fits (a ball with
/// r ≤ ρ), `None` when no lead below 90° does (flat: r ≥ ρ... ball: r > ρ; bull-nose: ρ ≤ r_c
/// or R_f ≥ ρ − r_c). A non-positive or infinite ρ (convex or flat across the feed) needs no
/// lead: `Some(0)`.
#[must_use]
pub fn min_lead_for_radius(cutter: &Cutter, rho_mm: f64) -> Option<f64> {
    if rho_mm.is_nan() {
        return None;
    }
    if !(rho_mm > 0.0) || rho_mm.is_infinite() {
        return Some(0.0);
    }
    let (flat, corner) = match cutter.kind {
        CutterKind::Ball => {
            return (cutter.radius() <= rho_mm).then_some(0.0);
        }
        CutterKind::Flat => (cutter.radius(), 0.0),
        CutterKind::BullNose { corner_radius } => (cutter.radius() - corner_radius, corner_radius),
        // A cone touches with its apex or a straight generator: no curvature to match.
        CutterKind::Cone { .. } => return Some(0.0),
    };
    let room = rho_mm - corner;
    if !(room > 0.0) {
        return None;
    }
    if flat <= 0.0 {
        return Some(0.0);
    }
    let s = flat / room;
    (s < 1.0).then(|| s.asin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_ek_b_numbers() {
        // The thesis's worked example: ρ_min concave (u) = 26.0544985816258.
        let rho = 26.054_498_581_625_8;
        let (bound, ball) = ball_for_radius(rho).expect("concave");
        assert!((bound - 52.108_997_163_251_6).abs() < 1e-12);
        assert_eq!(ball, Some(50.0));
        let flat = flat_for_radius(rho, 20f64.to_radians()).expect("choice");
        assert!((flat.max_diameter_mm - 17.8223).abs() < 1e-4);
        assert_eq!(flat.diameter_mm, 16.0);
        assert!((flat.lead_rad.to_degrees() - 17.881_461_334_930).abs() < 1e-9);
        let c = Cutter::new(CutterKind::Flat, 16.0).expect("valid");
        let s = min_lead_for_radius(&c, rho).expect("fits");
        assert!((s.to_degrees() - 17.881_461_334_9).abs() < 1e-9);
    }

    #[test]
    fn thesis_worked_examples() {
        // The thesis's worked example: ρ = 20 → D = 13.68 at 20°, standard 10, S = 14.4775°.
        let f = flat_for_radius(20.0, 20f64.to_radians()).expect("choice");
        assert!((f.max_diameter_mm - 13.68).abs() < 5e-3);
        assert_eq!(f.diameter_mm, 10.0);
        assert!((f.lead_rad.to_degrees() - 14.4775).abs() < 5e-5);
        // ρ = 100 at 20° → r = 34.2, D ≈ 68.
        let big = flat_for_radius(100.0, 20f64.to_radians()).expect("choice");
        assert!((big.max_diameter_mm - 68.404).abs() < 1e-3);
    }

    #[test]
    fn bull_nose_uses_its_effective_radius() {
        let c = Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0).expect("valid");
        let s = min_lead_for_radius(&c, 20.0).expect("fits");
        // R_f / sin S + r_c = ρ.
        assert!((3.0 / s.sin() + 2.0 - 20.0).abs() < 1e-12);
        assert_eq!(min_lead_for_radius(&c, 1.5), None);
        let ball = Cutter::new(CutterKind::Ball, 10.0).expect("valid");
        assert_eq!(min_lead_for_radius(&ball, 6.0), Some(0.0));
        assert_eq!(min_lead_for_radius(&ball, 4.0), None);
    }
}
