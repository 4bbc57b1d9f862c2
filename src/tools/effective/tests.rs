//! Effective radius and cross profiles against a brute-force envelope: sample the cutter's
//! surface, project it along the feed, take the lower outline per lateral bin.

use super::*;
use crate::tools::{Cutter, CutterKind};

/// Brute-force lower outline of the cutter projected along `f`: (x, y) bins of width `bin`
/// over [−span, span], relative to the projection of `cc`.
#[allow(
    clippy::too_many_arguments,
    reason = "a test helper naming every input"
)]
fn brute_outline(
    cutter: &Cutter,
    tip: DVec3,
    a: DVec3,
    n: DVec3,
    tau: DVec3,
    cc: DVec3,
    span: f64,
    bin: f64,
) -> Vec<(f64, f64)> {
    let (rf, rc) = torus_radii(cutter).expect("torus");
    let e1 = a.any_orthonormal_vector();
    let e2 = a.cross(e1);
    let c0 = tip + a * rc;
    let nb = (2.0 * span / bin).ceil() as usize + 1;
    let mut best = vec![f64::INFINITY; nb];
    let mut add = |p: DVec3| {
        let q = p - cc;
        let x = q.dot(tau);
        let y = q.dot(n);
        let k = ((x + span) / bin).round();
        if k >= 0.0 && (k as usize) < nb {
            let b = &mut best[k as usize];
            *b = b.min(y);
        }
    };
    let nt = 6000;
    for i in 0..nt {
        let th = std::f64::consts::TAU * i as f64 / nt as f64;
        let d = e1 * th.cos() + e2 * th.sin();
        // lower torus, ψ from the bottom (0) to the rim (π/2)
        for j in 0..=120 {
            let psi = std::f64::consts::FRAC_PI_2 * j as f64 / 120.0;
            add(c0 + d * (rf + rc * psi.sin()) - a * (rc * psi.cos()));
        }
        // flat bottom
        for j in 0..=40 {
            add(c0 - a * rc + d * (rf * j as f64 / 40.0));
        }
        // side cylinder
        for j in 0..=40 {
            add(c0 + d * (rf + rc) + a * (cutter.radius() * j as f64 / 40.0));
        }
    }
    best.iter()
        .enumerate()
        .filter(|(_, y)| y.is_finite())
        .map(|(k, y)| (k as f64 * bin - span, *y))
        .collect()
}

fn frame(lead_deg: f64, tilt_deg: f64) -> (DVec3, DVec3, DVec3, DVec3) {
    // A tilted contact frame (not axis-aligned) to exercise the general formula.
    let n = DVec3::new(0.2, -0.3, 1.0).normalize();
    let f = n.cross(DVec3::new(0.4, 1.0, 0.1)).normalize();
    let t = n.cross(f);
    let (l, s) = (lead_deg.to_radians(), tilt_deg.to_radians());
    let a = ((n * l.cos() + f * l.sin()) * s.cos() + t * s.sin()).normalize();
    (n, f, t, a)
}

#[test]
fn closed_forms_without_tilt() {
    let flat = Cutter::new(CutterKind::Flat, 10.0).expect("flat");
    let bull = Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0).expect("bull");
    for s in [5.0_f64, 14.4775, 20.0, 45.0] {
        let (n, f, _, a) = frame(s, 0.0);
        let sin = s.to_radians().sin();
        let rf = effective_radius(&flat, a, n, f).expect("flat");
        assert!((rf - 5.0 / sin).abs() < 1e-9 * rf, "flat {s}: {rf}");
        let rb = effective_radius(&bull, a, n, f).expect("bull");
        assert!((rb - (3.0 / sin + 2.0)).abs() < 1e-9 * rb, "bull {s}: {rb}");
    }
    // The thesis's worked example: ρ = 20, D = 10 → S = asin(5/20) = 14.4775°, r_e = ρ.
    let s = (5.0_f64 / 20.0).asin();
    assert!((s.to_degrees() - 14.4775).abs() < 1e-4);
    let (n, f, _, a) = frame(s.to_degrees(), 0.0);
    let re = effective_radius(&flat, a, n, f).expect("flat");
    assert!((re - 20.0).abs() < 1e-9);
}

#[test]
fn profile_and_radius_match_brute_force_envelope() {
    let tools = [
        Cutter::new(CutterKind::Ball, 6.0).expect("ball"),
        Cutter::new(CutterKind::Flat, 6.0).expect("flat"),
        Cutter::new(CutterKind::BullNose { corner_radius: 1.0 }, 6.0).expect("bull"),
    ];
    let cc = DVec3::new(3.0, -2.0, 1.5);
    for cutter in &tools {
        for (lead, tilt) in [(10.0, 0.0), (20.0, 5.0), (8.0, -3.0)] {
            let (n, f, t, a) = frame(lead, tilt);
            let tip = contact_to_tip(cutter, cc, n, a, f).expect("tip");
            let prof = CrossProfile::new(cutter, a, n, f, t).expect("profile");
            let bin = 0.004;
            let out = brute_outline(cutter, tip, a, n, t, cc, 2.5, bin);
            // The contact is the lowest point of the outline (tip placement is right).
            let ymin = out.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
            assert!(
                ymin > -2e-3,
                "{:?} {lead} {tilt}: lowest {ymin}",
                cutter.kind
            );
            // The tabulated outline agrees with the brute-force envelope.
            let mut worst: f64 = 0.0;
            for &(x, y) in &out {
                let h = prof.height(x);
                // Skip steep stretches (the rim of a flat end), where a bin's minimum differs
                // from the value at its centre by the slope times the bin width.
                let slope = (prof.height(x + bin) - prof.height(x - bin)).abs() / (2.0 * bin);
                if h.is_finite() && y < 1.0 && slope < 2.0 {
                    worst = worst.max((h - y).abs());
                }
            }
            assert!(
                worst < 4e-3,
                "{:?} lead {lead} tilt {tilt}: outline off by {worst}",
                cutter.kind
            );
            // Curvature at the contact: fit y = x²/(2 r) to the brute-force outline.
            let re = effective_radius(cutter, a, n, f).expect("re");
            let fitr = (0.15 * re).min(0.6);
            let (mut sxx, mut sxy) = (0.0, 0.0);
            for &(x, y) in out
                .iter()
                .filter(|p| p.0.abs() <= fitr && p.0.abs() > 0.2 * fitr)
            {
                let q = 0.5 * x * x;
                sxx += q * q;
                sxy += q * (y - cutter_outline_cubic(&prof, x));
            }
            let k_fit = sxy / sxx;
            let r_fit = 1.0 / k_fit;
            assert!(
                (r_fit - re).abs() < 0.03 * re,
                "{:?} lead {lead} tilt {tilt}: fitted {r_fit} vs exact {re}",
                cutter.kind
            );
        }
    }
}

/// The part of the outline beyond second order, estimated from the table itself (odd part):
/// removes the cubic term of a tilted cutter so the fit sees the curvature only.
fn cutter_outline_cubic(p: &CrossProfile, x: f64) -> f64 {
    0.5 * (p.height(x) - p.height(-x))
}

#[test]
fn tip_for_flat_with_sturz_is_thesis_form() {
    // The thesis's tip formula: TK = TT − r (cos S f − sin S n).
    let flat = Cutter::new(CutterKind::Flat, 10.0).expect("flat");
    let (n, f, _, a) = frame(17.88, 0.0);
    let s = 17.88_f64.to_radians();
    let cc = DVec3::new(1.0, 2.0, 3.0);
    let tip = contact_to_tip(&flat, cc, n, a, f).expect("tip");
    let want = cc - (f * s.cos() - n * s.sin()) * 5.0;
    assert!(tip.distance(want) < 1e-12);
}
