//! Feed scheduling: the feed per tooth at which the peak resultant force over a revolution
//! reaches a target, for one engagement ([`feed_for_peak_force`]) and for every piece of a
//! path ([`schedule_feeds`]); the spread of the peak force over the cutting time of a timed
//! motion ([`spread`]). The peak grows with the feed (chip thickness is `f_t·sin φ`), so
//! bisection on f_t finds it; the exponential model's coefficients follow the mean chip
//! thickness at each trial feed.

use super::cut::{Engagement, Mode};
use super::mill::EndMill;
use super::path::{ModeCoefficients, Piece};
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

/// The peak resultant over a revolution of one engagement as a function of the feed per
/// tooth. In the linear model every force sample is affine in f_t (`F(φ) = E(φ) + f_t·C(φ)`),
/// so two revolutions give the whole curve; the exponential model's coefficients follow the
/// mean chip thickness, so each feed is a fresh revolution.
#[derive(Clone, Debug)]
pub enum PeakCurve {
    /// Linear model: edge and cutting parts of the force at each rotation step.
    Affine {
        /// Force at f_t = 0 per rotation step, N.
        edge: Vec<[f64; 3]>,
        /// Force per mm of f_t per rotation step, N/mm.
        cut: Vec<[f64; 3]>,
    },
    /// Exponential model: the engagement and coefficients, sampled at each feed.
    General {
        /// The engagement.
        engagement: Engagement,
        /// The coefficients.
        coefficients: Coefficients,
        /// Rotation steps per revolution.
        steps: usize,
    },
}

fn forces_at(
    mill: &EndMill,
    c: &Coefficients,
    e: &Engagement,
    ft: f64,
    steps: usize,
) -> Result<Vec<[f64; 3]>, ForceError> {
    let e = Engagement {
        feed_per_tooth: ft,
        ..e.clone()
    };
    let rev = revolution(
        mill,
        c,
        &e,
        &RevolutionOptions {
            steps,
            spindle_rpm: None,
        },
    )?;
    Ok(rev
        .samples
        .iter()
        .map(|s| [s.force.fx, s.force.fy, s.force.fz])
        .collect())
}

impl PeakCurve {
    /// The curve of `engagement` (its feed per tooth is ignored).
    ///
    /// # Errors
    /// As [`revolution`].
    pub fn new(
        mill: &EndMill,
        coefficients: &Coefficients,
        engagement: &Engagement,
        steps: usize,
    ) -> Result<Self, ForceError> {
        if coefficients.is_exponential() {
            return Ok(Self::General {
                engagement: engagement.clone(),
                coefficients: *coefficients,
                steps,
            });
        }
        let edge = forces_at(mill, coefficients, engagement, 0.0, steps)?;
        let one = forces_at(mill, coefficients, engagement, 1.0, steps)?;
        let cut = one
            .iter()
            .zip(&edge)
            .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
            .collect();
        Ok(Self::Affine { edge, cut })
    }

    /// Peak resultant at feed per tooth `ft` (mm), N.
    ///
    /// # Errors
    /// As [`revolution`] (exponential model only).
    pub fn peak(&self, mill: &EndMill, ft: f64) -> Result<f64, ForceError> {
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        match self {
            Self::Affine { edge, cut } => Ok(edge
                .iter()
                .zip(cut)
                .map(|(e, c)| norm([e[0] + ft * c[0], e[1] + ft * c[1], e[2] + ft * c[2]]))
                .fold(0.0, f64::max)),
            Self::General {
                engagement,
                coefficients,
                steps,
            } => Ok(forces_at(mill, coefficients, engagement, ft, *steps)?
                .into_iter()
                .map(norm)
                .fold(0.0, f64::max)),
        }
    }

    /// The feed per tooth in `[lo, hi]` (mm) whose peak resultant is `target_n`: `lo` when
    /// even `lo` exceeds it, `hi` when even `hi` stays below it (bisection to 1e-7 relative).
    ///
    /// # Errors
    /// As [`PeakCurve::peak`].
    pub fn feed_for(
        &self,
        mill: &EndMill,
        target_n: f64,
        lo: f64,
        hi: f64,
    ) -> Result<f64, ForceError> {
        if self.peak(mill, hi)? <= target_n {
            return Ok(hi);
        }
        if self.peak(mill, lo)? >= target_n {
            return Ok(lo);
        }
        let (mut a, mut b) = (lo, hi);
        while b - a > 1e-7 * b {
            let m = 0.5 * (a + b);
            if self.peak(mill, m)? < target_n {
                a = m;
            } else {
                b = m;
            }
        }
        Ok(a)
    }
}

/// Limits of a path's feed schedule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScheduleOptions {
    /// Target peak resultant force, N.
    pub target_n: f64,
    /// Lowest feed the schedule may set, mm/min.
    pub min_feed_mm_per_min: f64,
    /// Highest feed the schedule may set (the machine's feed limit), mm/min.
    pub max_feed_mm_per_min: f64,
    /// Rotation steps per revolution.
    pub revolution_steps: usize,
}

/// A feed per piece of `pieces`: for an engaged piece, the feed whose peak resultant is the
/// target (clamped to the options' range), for a piece in air its move's programmed feed.
///
/// # Errors
/// [`ForceError::Input`] for a target or feed range out of range, a piece without a spindle
/// speed; the errors of [`revolution`].
pub fn schedule_feeds(
    mill: &EndMill,
    coefficients: &ModeCoefficients,
    pieces: &[Piece],
    programmed_feed: impl Fn(usize) -> f64,
    options: &ScheduleOptions,
) -> Result<Vec<f64>, ForceError> {
    super::check_range("target force", options.target_n, 1e-3, 1e7, "N")?;
    super::check_range(
        "lowest feed",
        options.min_feed_mm_per_min,
        1e-3,
        1e6,
        "mm/min",
    )?;
    super::check_range(
        "highest feed",
        options.max_feed_mm_per_min,
        options.min_feed_mm_per_min,
        1e6,
        "mm/min",
    )?;
    let teeth = mill.flutes() as f64;
    let mut last: Option<(&Engagement, Mode, f64, f64)> = None;
    let mut out = Vec::with_capacity(pieces.len());
    for p in pieces {
        let Some(mode) = p.mode else {
            out.push(programmed_feed(p.move_index));
            continue;
        };
        let per_tooth = p.spindle_rpm * teeth;
        if !(per_tooth > 0.0) {
            return Err(ForceError::Input(
                "a piece in material has no spindle speed".into(),
            ));
        }
        let (lo, hi) = (
            options.min_feed_mm_per_min / per_tooth,
            options.max_feed_mm_per_min / per_tooth,
        );
        let ft = match last {
            Some((e, m, rpm, ft)) if e == &p.engagement && m == mode && rpm == p.spindle_rpm => ft,
            _ => PeakCurve::new(
                mill,
                coefficients.get(mode),
                &p.engagement,
                options.revolution_steps,
            )?
            .feed_for(mill, options.target_n, lo, hi)?,
        };
        last = Some((&p.engagement, mode, p.spindle_rpm, ft));
        out.push(ft * per_tooth);
    }
    Ok(out)
}

/// How the peak force is spread over the cutting time.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Spread {
    /// Time in material, s.
    pub cutting_time_s: f64,
    /// Share of the cutting time with the peak resultant within ±5 % of the target.
    pub within_5_percent: f64,
    /// Share of the cutting time above 105 % of the target.
    pub above_5_percent: f64,
    /// Share of the cutting time below 95 % of the target while the machine runs more than
    /// 2 % below the programmed feed (accelerating, decelerating, slowing for a corner).
    pub below_while_slower: f64,
    /// Largest peak resultant, N.
    pub max_n: f64,
    /// Peak resultant exceeded during 95 % of the cutting time (5th percentile), N.
    pub p05_n: f64,
    /// Median peak resultant over the cutting time, N.
    pub p50_n: f64,
    /// 95th percentile of the peak resultant over the cutting time, N.
    pub p95_n: f64,
}

/// A moment of the planned motion: its duration, the piece the tool is in and the feed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeSample {
    /// Time this sample stands for, s.
    pub dt_s: f64,
    /// Index into the pieces.
    pub piece: usize,
    /// Path speed, mm/min.
    pub feed_mm_per_min: f64,
    /// Programmed feed of the block being run, mm/min.
    pub programmed_mm_per_min: f64,
}

/// The spread of the peak resultant over the cutting time of `samples` (in time order):
/// each sample in an engaged piece contributes the peak at the feed per tooth of its actual
/// speed.
///
/// # Errors
/// As [`PeakCurve::new`].
pub fn spread(
    mill: &EndMill,
    coefficients: &ModeCoefficients,
    pieces: &[Piece],
    target_n: f64,
    steps: usize,
    samples: impl IntoIterator<Item = TimeSample>,
) -> Result<Spread, ForceError> {
    let teeth = mill.flutes() as f64;
    let mut curve: Option<(usize, PeakCurve)> = None;
    let mut values: Vec<(f64, f64)> = Vec::new();
    let mut slower = 0.0;
    for s in samples {
        let Some(p) = pieces.get(s.piece) else {
            continue;
        };
        let Some(mode) = p.mode else {
            continue;
        };
        let same = curve.as_ref().is_some_and(|(k, _)| {
            pieces
                .get(*k)
                .is_some_and(|q| q.engagement == p.engagement && q.mode == p.mode)
        });
        if !same {
            curve = Some((
                s.piece,
                PeakCurve::new(mill, coefficients.get(mode), &p.engagement, steps)?,
            ));
        }
        let Some((_, c)) = &curve else {
            continue;
        };
        let ft = s.feed_mm_per_min / (p.spindle_rpm * teeth).max(1e-12);
        let peak = c.peak(mill, ft)?;
        if peak < 0.95 * target_n && s.feed_mm_per_min < 0.98 * s.programmed_mm_per_min {
            slower += s.dt_s;
        }
        values.push((peak, s.dt_s));
    }
    let mut out = summarise(values, target_n);
    if out.cutting_time_s > 0.0 {
        out.below_while_slower = slower / out.cutting_time_s;
    }
    Ok(out)
}

fn summarise(mut values: Vec<(f64, f64)>, target: f64) -> Spread {
    let total: f64 = values.iter().map(|v| v.1).sum();
    if !(total > 0.0) {
        return Spread::default();
    }
    let share = |pred: &dyn Fn(f64) -> bool| {
        values
            .iter()
            .filter(|v| pred(v.0))
            .map(|v| v.1)
            .sum::<f64>()
            / total
    };
    let within = share(&|f| (f - target).abs() <= 0.05 * target);
    let above = share(&|f| f > 1.05 * target);
    values.sort_by(|a, b| a.0.total_cmp(&b.0));
    let quantile = |q: f64| {
        let mut acc = 0.0;
        for v in &values {
            acc += v.1;
            if acc >= q * total {
                return v.0;
            }
        }
        values.last().map_or(0.0, |v| v.0)
    };
    Spread {
        cutting_time_s: total,
        within_5_percent: within,
        above_5_percent: above,
        below_while_slower: 0.0,
        max_n: values.last().map_or(0.0, |v| v.0),
        p05_n: quantile(0.05),
        p50_n: quantile(0.5),
        p95_n: quantile(0.95),
    }
}
