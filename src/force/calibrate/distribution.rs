//! The cutting-force-distribution (CFD) method of Aydın's thesis (§5.2, Eqs. 5.14–5.27): mean
//! forces measured per axial disk of a half-immersion cut are fitted by a quadratic in z
//! (as distributed loads, N/mm), integrated over the axial depth, and the integrals are equated
//! to the half-immersion mean-force formulas and inverted.
//!
//! - Linear edge-force model: per disk, the means over the feeds are regressed as
//!   `F = F_e + f_t·F_c` (Eq. 5.24); the cutting and edge parts are fitted along z (Eq. 5.25),
//!   integrated to V_xc, V_yc, V_xe, V_ye and inverted (Eq. 5.27).
//! - Exponential model: per feed, V_x and V_y give K_t and K_r (Eq. 5.20); ln K_t is regressed
//!   on ln h_a with `h_a = 2 f_t/π` (Eq. 5.5), and K_r likewise when all K_r share a sign
//!   (else K_r is their mean, with exponent 0).
//!
//! Only F_x and F_y enter, so the axial coefficients are not identified (set to 0).

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};

use crate::force::coefficients::{ExponentialCoefficients, PowerLaw};
use crate::force::{ForceError, LinearCoefficients, Mode};

/// The mean force measured on one disk element in one test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskMean {
    /// Mid-height of the disk above the tool tip, mm.
    pub z_mm: f64,
    /// Disk height, mm.
    pub height_mm: f64,
    /// Feed per tooth, mm.
    pub ft_mm: f64,
    /// Mean F_x on the disk, N.
    pub fx_n: f64,
    /// Mean F_y on the disk, N.
    pub fy_n: f64,
}

/// A CFD calibration test series: one tool, one mode, half immersion.
#[derive(Clone, Debug, PartialEq)]
pub struct DistributionTests {
    /// Flutes of the calibration tool (the thesis used single-flute tools).
    pub flutes: u32,
    /// Axial depth a_a, mm.
    pub axial_depth: f64,
    /// Up or down milling (half immersion).
    pub mode: Mode,
    /// Per-disk means, any order.
    pub disks: Vec<DiskMean>,
}

fn err(m: &str) -> ForceError {
    ForceError::Calibration(m.into())
}

/// Least-squares polynomial of degree ≤ 2 through (z, v), integrated over [0, a].
fn quadratic_integral(points: &[(f64, f64)], a: f64) -> Result<f64, ForceError> {
    let degree = points.len().saturating_sub(1).min(2);
    if points.is_empty() {
        return Err(err("no disks"));
    }
    let m = DMatrix::from_fn(points.len(), degree + 1, |i, j| points[i].0.powi(j as i32));
    let b = DVector::from_fn(points.len(), |i, _| points[i].1);
    let c = m
        .svd(true, true)
        .solve(&b, 1e-12)
        .map_err(|e| err(&format!("quadratic fit failed: {e}")))?;
    Ok((0..=degree)
        .map(|j| c[j] * a.powi(j as i32 + 1) / (j as f64 + 1.0))
        .sum())
}

/// Distinct values of `key` (to 1e-9).
fn distinct(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    v
}

fn check(t: &DistributionTests) -> Result<f64, ForceError> {
    if t.mode == Mode::Slot {
        return Err(err(
            "the CFD inversion is for half-immersion up or down milling",
        ));
    }
    if !(t.axial_depth > 0.0 && t.axial_depth.is_finite()) || t.flutes == 0 {
        return Err(err("axial depth and flutes must be positive"));
    }
    Ok(f64::from(t.flutes) * t.axial_depth)
}

/// Linear edge-force coefficients by the CFD method (Eq. 5.27).
///
/// # Errors
/// [`ForceError::Calibration`] for fewer than two feeds on a disk, no disks, or slotting.
pub fn linear(t: &DistributionTests) -> Result<LinearCoefficients, ForceError> {
    let na = check(t)?;
    let mut parts: [Vec<(f64, f64)>; 4] = Default::default(); // xc, yc, xe, ye
    for z in distinct(t.disks.iter().map(|d| d.z_mm)) {
        let on: Vec<&DiskMean> = t
            .disks
            .iter()
            .filter(|d| (d.z_mm - z).abs() < 1e-9)
            .collect();
        if distinct(on.iter().map(|d| d.ft_mm)).len() < 2 {
            return Err(err(&format!("disk at z = {z} mm needs two or more feeds")));
        }
        let m = DMatrix::from_fn(on.len(), 2, |i, j| if j == 0 { 1.0 } else { on[i].ft_mm });
        for (q, pick) in [|d: &DiskMean| d.fx_n, |d: &DiskMean| d.fy_n]
            .iter()
            .enumerate()
        {
            let b = DVector::from_fn(on.len(), |i, _| pick(on[i]) / on[i].height_mm);
            let c = m
                .clone()
                .svd(true, true)
                .solve(&b, 1e-12)
                .map_err(|e| err(&format!("feed regression failed: {e}")))?;
            parts[q].push((z, c[1]));
            parts[q + 2].push((z, c[0]));
        }
    }
    let a = t.axial_depth;
    let [vxc, vyc, vxe, vye] = [
        quadratic_integral(&parts[0], a)?,
        quadratic_integral(&parts[1], a)?,
        quadratic_integral(&parts[2], a)?,
        quadratic_integral(&parts[3], a)?,
    ];
    let (ktc, krc, kte, kre) = if t.mode == Mode::Up {
        let ktc = 8.0 * PI / na * (-2.0 * vxc + PI * vyc) / (PI * PI + 4.0);
        let kte = PI * (-vxe + vye) / na;
        (
            ktc,
            -2.0 * (ktc / PI + 4.0 * vxc / na),
            kte,
            -kte - 2.0 * PI * vxe / na,
        )
    } else {
        let ktc = 8.0 * PI / na * (2.0 * vxc + PI * vyc) / (PI * PI + 4.0);
        let kte = PI * (vxe + vye) / na;
        (
            ktc,
            2.0 * (ktc / PI - 4.0 * vxc / na),
            kte,
            kte - 2.0 * PI * vxe / na,
        )
    };
    Ok(LinearCoefficients {
        ktc,
        krc,
        kac: 0.0,
        kte,
        kre,
        kae: 0.0,
    })
}

/// Exponential-model coefficients by the CFD method (Eqs. 5.20, 5.5).
///
/// # Errors
/// [`ForceError::Calibration`] for fewer than two feeds, a degenerate inversion, or slotting.
pub fn exponential(t: &DistributionTests) -> Result<ExponentialCoefficients, ForceError> {
    let na = check(t)?;
    let feeds = distinct(t.disks.iter().map(|d| d.ft_mm));
    if feeds.len() < 2 {
        return Err(err("the exponential model needs two or more feeds"));
    }
    let mut kts = Vec::new();
    let mut krs = Vec::new();
    for &f in &feeds {
        let on: Vec<&DiskMean> = t
            .disks
            .iter()
            .filter(|d| (d.ft_mm - f).abs() < 1e-9)
            .collect();
        let px: Vec<(f64, f64)> = on.iter().map(|d| (d.z_mm, d.fx_n / d.height_mm)).collect();
        let py: Vec<(f64, f64)> = on.iter().map(|d| (d.z_mm, d.fy_n / d.height_mm)).collect();
        let (vx, vy) = (
            quadratic_integral(&px, t.axial_depth)?,
            quadratic_integral(&py, t.axial_depth)?,
        );
        let (kr, kt) = if t.mode == Mode::Up {
            let kr = (PI * vx + 2.0 * vy) / (2.0 * vx - PI * vy);
            (kr, -8.0 * PI * vx / (na * f * (2.0 + PI * kr)))
        } else {
            let kr = -(PI * vx - 2.0 * vy) / (2.0 * vx + PI * vy);
            (kr, 8.0 * PI * vx / (na * f * (2.0 - PI * kr)))
        };
        if !(kt > 0.0 && kt.is_finite() && kr.is_finite()) {
            return Err(err(&format!(
                "feed {f} mm: the mean forces give K_t = {kt}, K_r = {kr} (not a cutting force)"
            )));
        }
        let ln_h = (2.0 * f / PI).ln();
        kts.push((ln_h, kt.ln()));
        krs.push((ln_h, kr));
    }
    let kt = power_fit(&kts);
    let kr = if krs.iter().all(|p| p.1 > 0.0) || krs.iter().all(|p| p.1 < 0.0) {
        let sign = krs[0].1.signum();
        let logs: Vec<(f64, f64)> = krs.iter().map(|p| (p.0, (p.1 * sign).ln())).collect();
        let law = power_fit(&logs);
        PowerLaw {
            k: sign * law.k,
            p: law.p,
        }
    } else {
        PowerLaw::constant(krs.iter().map(|p| p.1).sum::<f64>() / krs.len() as f64)
    };
    Ok(ExponentialCoefficients {
        kt,
        kr,
        ka: PowerLaw::constant(0.0),
    })
}

/// `ln K = ln k − p·ln h` by linear regression over (ln h, ln K).
fn power_fit(points: &[(f64, f64)]) -> PowerLaw {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let slope = if sxx > 0.0 {
        points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / sxx
    } else {
        0.0
    };
    PowerLaw {
        k: (my - slope * mx).exp(),
        p: -slope,
    }
}
