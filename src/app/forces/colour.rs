//! The path coloured by the computed forces: every cutting move takes the largest value of the
//! quantity the plot shows (resultant force in N, torque in N·m or cutting power in W, peak or
//! mean per revolution) over the pieces of that move; a cutting move that never meets material
//! gets 0; rapids, links and plunges keep their move-kind colours. The colour bar runs from 0 to
//! the larger of the largest value and the limit, and the limit is marked on it.

use std::sync::Arc;

use super::Shown;
use crate::project::forces::{ForceSample, ForceTimeline};
use crate::render::{ColourMap, DataId, LineData, ScalarMapping};
use crate::toolpath::{MoveKind, Toolpath};

/// The value of `shown` (peak or `mean` per revolution) for one sample: the resultant force
/// (N), the torque (N·m) or the cutting power (W).
#[must_use]
pub fn sample_value(s: &ForceSample, shown: Shown, mean: bool) -> f64 {
    match shown {
        Shown::Force if mean => s.mean.iter().map(|v| v * v).sum::<f64>().sqrt(),
        Shown::Force => s.peak_resultant_n,
        Shown::Torque => s.torque_nm[usize::from(mean)],
        Shown::Power => s.power_w[usize::from(mean)],
    }
}

/// One value per pose of `toolpath`: for the pose a cutting move goes to, the largest value of
/// `shown` over that move's samples (0 for a cutting move in air); NaN for other poses.
#[must_use]
pub fn pose_values(toolpath: &Toolpath, r: &ForceTimeline, shown: Shown, mean: bool) -> Vec<f32> {
    let mut out: Vec<f32> = toolpath
        .poses
        .iter()
        .map(|p| {
            if p.kind == MoveKind::Cut {
                0.0
            } else {
                f32::NAN
            }
        })
        .collect();
    for s in &r.samples {
        if let Some(v) = out.get_mut(s.pose)
            && v.is_finite()
        {
            *v = v.max(sample_value(s, shown, mean) as f32);
        }
    }
    out
}

/// The legend title (with the unit) and the limit of `shown`.
#[must_use]
pub fn title_and_limit(shown: Shown, mean: bool, r: &ForceTimeline) -> (String, Option<f64>) {
    let per_rev = if mean { "mean" } else { "peak" };
    match shown {
        Shown::Force => (
            format!("Resultant force, {per_rev} per move (N)"),
            r.limits.max_force_n,
        ),
        Shown::Torque => (
            format!("Torque, {per_rev} per move (N·m)"),
            r.limits.max_torque_nm,
        ),
        Shown::Power => (
            format!("Cutting power, {per_rev} per move (W)"),
            r.limits.max_power_w,
        ),
    }
}

/// The colour bar: Turbo from 0 to the larger of the largest finite value and the limit.
#[must_use]
pub fn mapping(values: &[f32], limit: Option<f64>) -> ScalarMapping {
    let top = values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max)
        .max(limit.map_or(0.0, |l| l as f32));
    ScalarMapping {
        map: ColourMap::Turbo,
        min: 0.0,
        max: top.max(1e-6),
    }
}

/// The legend of the coloured path.
pub type PathLegend = crate::app::feature::SceneLegend;

/// What the coloured path was built for (rebuilt when it changes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColourKey {
    /// The result it shows (a counter bumped per new result).
    pub result: u64,
    /// The quantity.
    pub shown: Shown,
    /// Mean instead of peak.
    pub mean: bool,
}

/// The coloured path in render form, with its legend.
#[derive(Clone, Debug)]
pub struct ColouredPath {
    /// What it was built for.
    pub key: ColourKey,
    /// Render id.
    pub id: DataId,
    /// The line segments (segment `i` is the move into pose `i + 1`).
    pub lines: Arc<LineData>,
    /// The legend.
    pub legend: PathLegend,
}

/// Build the coloured path of `toolpath` for the result `r`.
#[must_use]
pub fn coloured_path(
    toolpath: &Toolpath,
    r: &ForceTimeline,
    key: ColourKey,
    id: DataId,
) -> ColouredPath {
    let values = pose_values(toolpath, r, key.shown, key.mean);
    let (title, limit) = title_and_limit(key.shown, key.mean, r);
    let mapping = mapping(&values, limit);
    let unit = match key.shown {
        Shown::Force => "N",
        Shown::Torque => "N·m",
        Shown::Power => "W",
    };
    let lines = crate::app::toolpaths::path_lines_by(toolpath, &values, mapping);
    ColouredPath {
        key,
        id,
        lines: Arc::new(lines),
        legend: PathLegend {
            title,
            mapping,
            mark: limit.map(|l| (l as f32, format!("limit {l:.0} {unit}"))),
        },
    }
}
