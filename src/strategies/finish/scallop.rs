//! Scallop height between two neighbouring passes and the side step that gives a requested
//! height (the thesis's ball-on-plane formula, generalised to any cutter and curvature).
//!
//! In the cross-feed normal section, the surface is taken to second order (normal curvature κ
//! across the feed, positive where it bends toward the tool) and each pass's envelope is the
//! cutter's exact projected outline ([`CrossProfile`]). To second order the rotation between the
//! two contact frames cancels, so the material left above the surface at lateral offset `x`
//! from pass A's contact is `min(g_A(x), g_B(x − w))` with `g(ξ) = profile(ξ) − κ ξ²/2` and `w`
//! the arc length between the contacts. The scallop is the maximum of that over `0 ≤ x ≤ w`.
//!
//! For a ball and circular sections this is eq. 3.69: `h = w²/8 · (1/r − κ)`, i.e.
//! `ω = √(8|ρ| r h / (|ρ| + r·sign ρ))` (convex +), with the exact circle of the cutter instead
//! of its parabola. The ω singularity (a concave radius equal to the effective radius, where the
//! formula's denominator vanishes) cannot occur here: the step is bounded by the cutters'
//! lateral reach, which caps it at the footprint width.

use crate::tools::effective::CrossProfile;

/// Cross-feed section of two neighbouring passes.
#[derive(Clone, Copy, Debug)]
pub struct Section<'a> {
    /// Profile of pass A (lateral axis toward pass B).
    pub a: &'a CrossProfile,
    /// Profile of pass B in the same lateral axis (its near side is `x < 0`).
    pub b: &'a CrossProfile,
    /// Surface normal curvature across the feed (positive: concave toward the tool), 1/mm.
    pub kappa: f64,
    /// Both profiles are the same and mirror-symmetric (no sideways tilt): the cusp is midway.
    pub symmetric: bool,
}

/// Large stand-in for "the cutter does not reach", mm.
const FAR: f64 = 1e9;

impl Section<'_> {
    fn ga(&self, x: f64) -> f64 {
        let h = self.a.height(x);
        if h.is_finite() {
            h - 0.5 * self.kappa * x * x
        } else {
            FAR
        }
    }

    fn gb(&self, x: f64) -> f64 {
        let h = self.b.height(x);
        if h.is_finite() {
            h - 0.5 * self.kappa * x * x
        } else {
            FAR
        }
    }

    /// Scallop height for contacts `w` mm apart (arc length), mm (≥ 0; `FAR` when the two
    /// envelopes do not meet).
    #[must_use]
    pub fn height(&self, w: f64) -> f64 {
        if !(w > 0.0) {
            return 0.0;
        }
        if self.symmetric {
            return self.ga(0.5 * w).max(0.0);
        }
        // F(x) = g_A(x) − g_B(x − w) rises from ≤ 0 at x = 0 to ≥ 0 at x = w.
        let (mut lo, mut hi) = (0.0, w);
        for _ in 0..34 {
            let m = 0.5 * (lo + hi);
            if self.ga(m) < self.gb(m - w) {
                lo = m;
            } else {
                hi = m;
            }
        }
        let x = 0.5 * (lo + hi);
        self.ga(x).min(self.gb(x - w)).max(0.0)
    }

    /// Largest reach `w` at which the two cutters still overlap, mm.
    #[must_use]
    pub fn max_step(&self) -> f64 {
        self.a.reach().0 + self.b.reach().1
    }

    /// The side step (arc length between contacts) giving scallop height `h`, capped at
    /// 95 % of the cutters' combined reach (the footprint), mm; with the predicted height.
    #[must_use]
    pub fn step_for(&self, h: f64) -> (f64, f64) {
        let cap = 0.95 * self.max_step();
        let at_cap = self.height(cap);
        if at_cap <= h {
            return (cap, at_cap);
        }
        let (mut lo, mut hi) = (0.0, cap);
        for _ in 0..34 {
            let m = 0.5 * (lo + hi);
            if self.height(m) <= h {
                lo = m;
            } else {
                hi = m;
            }
        }
        (lo, self.height(lo))
    }
}

/// Thesis eq. 3.69 (Lo 1999): side step for scallop `h`, cutter (effective) radius `r` and
/// signed surface radius `rho` (convex > 0, concave < 0; infinite for a plane), mm. Returns
/// `None` at or beyond the singularity `|ρ| ≤ r` on concave surfaces.
#[must_use]
pub fn thesis_side_step(h: f64, r: f64, rho: f64) -> Option<f64> {
    if rho.is_infinite() {
        return Some((8.0 * r * h).sqrt());
    }
    let den = rho.abs() + r * rho.signum();
    (den > 0.0).then(|| (8.0 * rho.abs() * r * h / den).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::{Cutter, CutterKind};
    use glam::DVec3;

    fn ball(r: f64) -> CrossProfile {
        let c = Cutter::new(CutterKind::Ball, 2.0 * r).expect("ball");
        CrossProfile::new(&c, DVec3::Z, DVec3::Z, DVec3::X, DVec3::Y).expect("profile")
    }

    #[test]
    fn ball_on_plane_is_exact_circle_form() {
        // Lin & Koren 2000 (eq. 3.61): ω = 2√(r² − (r − h)²).
        let p = ball(3.0);
        let s = Section {
            a: &p,
            b: &p,
            kappa: 0.0,
            symmetric: false,
        };
        for h in [0.001, 0.01, 0.05, 0.2] {
            let (w, hp) = s.step_for(h);
            let exact = 2.0 * (9.0 - (3.0 - h) * (3.0 - h)).sqrt();
            assert!((w - exact).abs() < 1e-9, "h {h}: {w} vs {exact}");
            assert!((hp - h).abs() < 1e-9);
        }
    }

    #[test]
    fn ball_on_curved_matches_eq_3_69() {
        // Vickers & Quan: r = 20, ω = 4 on a plane gives h = 0.1003.
        let big = ball(20.0);
        let s = Section {
            a: &big,
            b: &big,
            kappa: 0.0,
            symmetric: false,
        };
        assert!((s.height(4.0) - (20.0 - 396f64.sqrt())).abs() < 1e-9);
        let p = ball(3.0);
        for rho in [-60.0, -20.0, 20.0, 60.0, 200.0] {
            // thesis sign: convex +; here κ > 0 is concave.
            let s = Section {
                a: &p,
                b: &p,
                kappa: -1.0 / rho,
                symmetric: false,
            };
            let h = 0.01;
            let (w, _) = s.step_for(h);
            let want = thesis_side_step(h, 3.0, rho).expect("regular");
            assert!((w - want).abs() < 2e-3 * want, "ρ {rho}: {w} vs {want}");
        }
    }

    #[test]
    fn concave_singularity_is_capped_at_footprint() {
        let p = ball(3.0);
        let s = Section {
            a: &p,
            b: &p,
            kappa: 1.0 / 3.0,
            symmetric: false,
        };
        assert!(thesis_side_step(0.01, 3.0, -3.0).is_none());
        let (w, _) = s.step_for(0.01);
        assert!(w.is_finite() && w <= 6.0 && w > 0.0);
    }
}
