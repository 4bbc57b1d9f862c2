//! Step-over from the scallop height, with the local slope taken into account.
//!
//! **Method.** On a plane inclined at φ across the passes, two passes at XY distance s put the
//! cutter at the same height above the plane, shifted by s/cos φ along it, so the cusp between
//! them grows with φ. For a cutter profile g(ρ) (height of the lower surface above the tip at
//! radius ρ) the cusp is computed in the vertical section across the passes: the tools resting
//! on the line z = x·tan φ at x = i·s (i = −1…2) form the envelope min_i(T_i + g(|x − i·s|)), and
//! the cusp is the largest height of that envelope above the line on [0, s], measured along the
//! plane's normal (× cos φ). The XY step-over for a scallop h is the largest s whose cusp is ≤ h
//! (bisection; the cusp grows with s). For a ball this reproduces the closed form
//! s = 2·√(2Rh − h²)·cos φ; for flat and bull-nose cutters it includes the flat bottom's tilt.
//! The table is tabulated per degree and read conservatively (the smaller step of the two
//! neighbouring entries). Curvature across the passes is handled afterwards by the planner,
//! which measures the cusp between actual neighbouring passes and shrinks the step until it
//! holds.

use crate::tools::Cutter;

/// XY step-over per degree of cross slope, 0° up to the steepest slope honoured.
#[derive(Clone, Debug)]
pub(crate) struct StepoverTable {
    steps: Vec<f64>,
    /// The step on a level floor (no cross slope at all): the table's first entry is the
    /// smallest over 0°–1°, which for a flat end mill is the step a 1° slope allows (0.57 mm
    /// for Ø50 at 0.01 mm) where the floor itself leaves no cusp at any step.
    level: f64,
}

/// The largest step-over, as a share of the cutter's diameter: passes always overlap a
/// little, whatever the scallop allows (a flat end mill on a level floor leaves no cusp at
/// any step up to its diameter).
pub(crate) const MAX_STEP_OF_DIAMETER: f64 = 0.9;

/// Height of the cutter's lower surface at radius `rho`; beyond the rim a steep wall (the
/// cutter's side), which keeps the envelope finite and monotone.
pub(crate) fn profile(cutter: &Cutter, rho: f64) -> f64 {
    let big = cutter.radius();
    let r = rho.abs();
    if r <= big {
        cutter.height_at_radius(r).unwrap_or(0.0)
    } else {
        cutter.height_at_radius(big).unwrap_or(0.0) + (r - big) * 1.0e6
    }
}

/// Cusp height (along the plane's normal) between passes at XY distance `s` on a plane of slope
/// `phi` across the passes.
pub(crate) fn planar_cusp(cutter: &Cutter, phi: f64, s: f64) -> f64 {
    let k = phi.tan().abs();
    let big = cutter.radius();
    // Tip height above the line at the tool's own x: max over ρ of kρ − g(ρ) (concave in ρ for
    // convex profiles): ternary search on [0, R].
    let (mut lo, mut hi) = (0.0, big);
    for _ in 0..100 {
        let a = lo + (hi - lo) / 3.0;
        let b = hi - (hi - lo) / 3.0;
        if k * a - profile(cutter, a) < k * b - profile(cutter, b) {
            lo = a;
        } else {
            hi = b;
        }
    }
    let rho = 0.5 * (lo + hi);
    let lift = (k * rho - profile(cutter, rho)).max(0.0);
    if !(s > 0.0) {
        return 0.0;
    }
    // Every tool whose footprint covers x can be the lowest there (a flat bottom on a slope is
    // undercut by the passes downhill of it), so take them all (at most a few hundred).
    let reach = (big / s).ceil().min(400.0) as i32 + 1;
    let env = |x: f64| {
        (-reach..=reach + 1)
            .map(|i| {
                let xc = f64::from(i) * s;
                k * xc + lift + profile(cutter, x - xc)
            })
            .fold(f64::INFINITY, f64::min)
            - k * x
    };
    let n = 120;
    let (mut best, mut at) = (f64::NEG_INFINITY, 0.0);
    for i in 0..=n {
        let x = s * f64::from(i) / f64::from(n);
        let e = env(x);
        if e > best {
            (best, at) = (e, x);
        }
    }
    // Refine around the best sample (the envelope is unimodal near its cusp).
    let dx = s / f64::from(n);
    let (mut lo, mut hi) = ((at - dx).max(0.0), (at + dx).min(s));
    for _ in 0..60 {
        let a = lo + (hi - lo) / 3.0;
        let b = hi - (hi - lo) / 3.0;
        if env(a) < env(b) {
            lo = a;
        } else {
            hi = b;
        }
    }
    best.max(env(0.5 * (lo + hi))).max(0.0) * phi.cos()
}

/// A cross slope below this is a level floor, rad (the normals of a plane's triangles).
const LEVEL_RAD: f64 = 1e-6;

impl StepoverTable {
    /// The table for `cutter` and scallop `h` (mm), slopes 0 ..= `max_slope` (rad).
    pub(crate) fn new(cutter: &Cutter, h: f64, max_slope: f64) -> Self {
        let last = max_slope.to_degrees().ceil().clamp(0.0, 89.0) as usize;
        let raw: Vec<f64> = (0..=last + 1)
            .map(|deg| {
                let phi = (deg as f64).min(89.5).to_radians();
                let (mut lo, mut hi) = (0.0, 2.0 * cutter.radius());
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    if planar_cusp(cutter, phi, mid) <= h {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            })
            .collect();
        let cap = MAX_STEP_OF_DIAMETER * 2.0 * cutter.radius();
        let steps = raw.windows(2).map(|w| w[0].min(w[1]).min(cap)).collect();
        Self {
            steps,
            level: raw.first().copied().unwrap_or(0.0).min(cap),
        }
    }

    /// The XY step-over for a cross slope `phi` (rad); slopes past the table use its last entry.
    pub(crate) fn step(&self, phi: f64) -> f64 {
        if phi.abs() <= LEVEL_RAD {
            return self.level;
        }
        let deg = phi.abs().to_degrees();
        let i = if deg.is_finite() {
            deg.floor() as usize
        } else {
            usize::MAX
        };
        self.steps
            .get(i)
            .or_else(|| self.steps.last())
            .copied()
            .unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::CutterKind;

    #[test]
    fn ball_matches_the_closed_form() {
        let c = Cutter::new(CutterKind::Ball, 6.0).unwrap();
        let h = 0.01;
        let t = StepoverTable::new(&c, h, 70f64.to_radians());
        for deg in [0.0_f64, 10.0, 30.0, 60.0] {
            let want = 2.0 * (2.0 * 3.0 * h - h * h).sqrt() * (deg + 1.0).to_radians().cos();
            let got = t.step((deg + 0.5).to_radians());
            assert!((got - want).abs() < 2e-3, "{deg}°: {got} vs {want}");
        }
    }

    /// On a level floor a flat end mill leaves no cusp at any step: the step is the cap
    /// (0.9 of Ø50 = 45 mm), not the 0.57 mm that a 1° slope would allow at 0.01 mm
    /// (0.01 / tan 1°); on a 1° slope it is that.
    #[test]
    fn a_flat_end_mill_on_a_level_floor_steps_by_the_cap() {
        let c = Cutter::new(CutterKind::Flat, 50.0).unwrap();
        let t = StepoverTable::new(&c, 0.01, 70f64.to_radians());
        assert!((t.step(0.0) - 45.0).abs() < 1e-9, "{}", t.step(0.0));
        let one = t.step(0.5f64.to_radians());
        let want = 0.01 / 1f64.to_radians().tan();
        assert!((one - want).abs() < 0.01 * want, "{one} vs {want}");
        // A ball's level step is its closed form, under the cap.
        let b = Cutter::new(CutterKind::Ball, 6.0).unwrap();
        let tb = StepoverTable::new(&b, 0.01, 70f64.to_radians());
        let closed = 2.0 * (2.0 * 3.0 * 0.01 - 1e-4_f64).sqrt();
        assert!((tb.step(0.0) - closed).abs() < 1e-6, "{}", tb.step(0.0));
    }

    #[test]
    fn flat_end_on_a_slope_is_bounded_by_the_tilt() {
        let c = Cutter::new(CutterKind::Flat, 10.0).unwrap();
        // On a slope φ the flat bottom leaves a wedge of normal height s·sin φ.
        let phi = 20f64.to_radians();
        let s = 0.5;
        let cusp = planar_cusp(&c, phi, s);
        assert!((cusp - s * phi.sin()).abs() < 1e-3, "{cusp}");
    }
}
