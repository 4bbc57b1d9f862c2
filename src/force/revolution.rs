//! Forces over one revolution: F_x, F_y, F_z, resultant, torque and spindle power against the
//! rotation angle (disk sums), the exact mean per revolution (closed form in φ) and the peaks
//! (the sampled value of largest magnitude, with its sign).

use std::f64::consts::TAU;

use super::closed_form::{Load, mean_load};
use super::cut::Engagement;
use super::disks::DiskForces;
use super::mill::EndMill;
use super::{Coefficients, Force, ForceError};

/// How a revolution is sampled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RevolutionOptions {
    /// Rotation steps per revolution (default 720: 0.5°).
    pub steps: usize,
    /// Spindle speed, rev/min, for the power (none: no power).
    pub spindle_rpm: Option<f64>,
}

impl Default for RevolutionOptions {
    fn default() -> Self {
        Self {
            steps: 720,
            spindle_rpm: None,
        }
    }
}

/// One rotation angle's result.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Sample {
    /// Rotation angle of flute 0's tip, rad.
    pub phi_rad: f64,
    /// Force on the tool, N.
    pub force: Force,
    /// |F|, N.
    pub resultant_n: f64,
    /// Cutting torque, N·m.
    pub torque_nm: f64,
    /// Spindle power, W (when the speed is known).
    pub power_w: Option<f64>,
}

/// Forces over one revolution.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Revolution {
    /// Samples at `steps` equal rotation steps from φ = 0.
    pub samples: Vec<Sample>,
    /// Mean force per revolution (exact in φ), N.
    pub mean: Force,
    /// Mean resultant of the samples, N.
    pub mean_resultant_n: f64,
    /// Mean torque, N·m.
    pub mean_torque_nm: f64,
    /// Mean spindle power, W.
    pub mean_power_w: Option<f64>,
    /// Per component, the sampled value of largest magnitude with its sign, N.
    pub peak: Force,
    /// Largest resultant, N.
    pub peak_resultant_n: f64,
    /// Largest torque, N·m.
    pub peak_torque_nm: f64,
    /// Largest spindle power, W.
    pub peak_power_w: Option<f64>,
}

/// The value of larger magnitude.
fn signed_max(a: f64, b: f64) -> f64 {
    if b.abs() > a.abs() { b } else { a }
}

/// Sample one revolution of `mill` in `engagement`.
///
/// # Errors
/// [`ForceError::Input`] for fewer than 8 or more than 10⁶ steps, a spindle speed outside
/// (0, 200 000] rpm, or coefficients out of range.
pub fn revolution(
    mill: &EndMill,
    coefficients: &Coefficients,
    engagement: &Engagement,
    options: &RevolutionOptions,
) -> Result<Revolution, ForceError> {
    coefficients.validate()?;
    if !(8..=1_000_000).contains(&options.steps) {
        return Err(ForceError::Input(format!(
            "steps per revolution must be 8 to 1000000, got {}",
            options.steps
        )));
    }
    let omega = match options.spindle_rpm {
        Some(n) => {
            super::check_range("spindle speed", n, 1e-6, 200_000.0, "rpm")?;
            Some(n * TAU / 60.0)
        }
        None => None,
    };
    let model = DiskForces::new(mill, coefficients, engagement);
    let mut samples = Vec::with_capacity(options.steps);
    let mut peak = Force::default();
    let (mut peak_res, mut peak_t, mut sum_res) = (0.0_f64, 0.0_f64, 0.0);
    for i in 0..options.steps {
        let phi = TAU * i as f64 / options.steps as f64;
        let l = model.load(phi, None);
        let f = l.force;
        let torque_nm = l.torque * 1e-3;
        peak = Force {
            fx: signed_max(peak.fx, f.fx),
            fy: signed_max(peak.fy, f.fy),
            fz: signed_max(peak.fz, f.fz),
        };
        let res = f.resultant();
        peak_res = peak_res.max(res);
        peak_t = signed_max(peak_t, torque_nm);
        sum_res += res;
        samples.push(Sample {
            phi_rad: phi,
            force: f,
            resultant_n: res,
            torque_nm,
            power_w: omega.map(|w| torque_nm * w),
        });
    }
    let Load {
        force: mean,
        torque,
    } = mean_load(mill, coefficients, engagement);
    let mean_torque_nm = torque * 1e-3;
    Ok(Revolution {
        samples,
        mean,
        mean_resultant_n: sum_res / options.steps as f64,
        mean_torque_nm,
        mean_power_w: omega.map(|w| mean_torque_nm * w),
        peak,
        peak_resultant_n: peak_res,
        peak_torque_nm: peak_t,
        peak_power_w: omega.map(|w| peak_t * w),
    })
}
