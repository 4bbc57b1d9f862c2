//! Feed scheduling for one engagement: the feed per tooth at which the peak resultant force
//! over a revolution reaches a target. The peak grows with the feed (chip thickness is
//! `f_t·sin φ`), so bisection on f_t finds it; the exponential model's coefficients follow the
//! mean chip thickness at each trial feed.

use super::cut::Engagement;
use super::mill::EndMill;
use super::revolution::{RevolutionOptions, revolution};
use super::{Coefficients, ForceError};

/// Smallest and largest feed per tooth searched, mm.
pub const FEED_RANGE_MM: (f64, f64) = (1e-4, 2.0);

/// The feed per tooth (mm) whose peak resultant over a revolution is `target_n` (N), to
/// 1e-9 mm.
///
/// # Errors
/// [`ForceError::Input`] for a target that is not positive and finite, one the edge forces
/// alone exceed at the smallest feed, or one not reached at the largest feed; the errors of
/// [`revolution`].
pub fn feed_for_peak_force(
    mill: &EndMill,
    coefficients: &Coefficients,
    engagement: &Engagement,
    target_n: f64,
    options: &RevolutionOptions,
) -> Result<f64, ForceError> {
    super::check_range("target force", target_n, 1e-6, 1e7, "N")?;
    let peak = |ft: f64| -> Result<f64, ForceError> {
        let e = Engagement {
            feed_per_tooth: ft,
            ..engagement.clone()
        };
        Ok(revolution(mill, coefficients, &e, options)?.peak_resultant_n)
    };
    let (mut lo, mut hi) = FEED_RANGE_MM;
    if peak(lo)? > target_n {
        return Err(ForceError::Input(format!(
            "the peak force exceeds {target_n} N already at {lo} mm per tooth"
        )));
    }
    if peak(hi)? < target_n {
        return Err(ForceError::Input(format!(
            "the peak force stays below {target_n} N up to {hi} mm per tooth"
        )));
    }
    while hi - lo > 1e-9 {
        let mid = 0.5 * (lo + hi);
        if peak(mid)? < target_n {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}
