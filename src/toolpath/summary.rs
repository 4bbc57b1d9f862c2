//! The summary of a tool path: lengths, counts, estimated time, extent.

use glam::DVec3;

use super::{MoveKind, Pose};

/// Rapid rate assumed by the time estimate, mm/min (the one default of [`crate::units`]).
pub const ESTIMATE_RAPID_MM_PER_MIN: f64 = crate::units::DEFAULT_RAPID_MM_PER_MIN;

/// A predicted scallop at least this high means the neighbouring pass does not reach (the
/// scallop model's stand-in for "no intersection" is 1e9 mm), mm.
pub const SCALLOP_NOT_REACHED_MM: f64 = 1e6;

/// Lengths, counts, time and extent of a tool path.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Summary {
    /// Number of poses.
    pub pose_count: usize,
    /// Tip path length of cut and plunge moves, mm.
    pub cut_length_mm: f64,
    /// Tip path length of link and rapid moves, mm.
    pub other_length_mm: f64,
    /// Length / feed summed over moves (rapids at 10 m/min), s; no acceleration.
    pub estimated_time_s: f64,
    /// Smallest tip coordinates (zero when empty).
    pub bbox_min: DVec3,
    /// Largest tip coordinates (zero when empty).
    pub bbox_max: DVec3,
    /// Largest predicted scallop height over the poses that carry one, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted_max_scallop_mm: Option<f64>,
    /// Cutting poses where the neighbouring pass's envelope does not reach this pass's (the
    /// scallop there is not predicted; e.g. a vertical wall between iso-planar planes); they
    /// are left out of `predicted_max_scallop_mm`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scallop_not_reached_poses: Option<usize>,
    /// What the planner found about gouging (kept across save and load).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gouge: Option<GougeReport>,
}

/// The planner's gouge report.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
pub struct GougeReport {
    /// Poses checked.
    pub checked_poses: usize,
    /// Poses found gouging (after fixes), by the gouge checks.
    pub gouging_poses: usize,
    /// Deepest gouge found, mm (0 when none).
    pub max_depth_mm: f64,
    /// Where the deepest gouge is (contact point), when any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<[f64; 3]>")]
    pub worst_at: Option<DVec3>,
    /// The lead (Sturz) was raised to this many degrees to avoid local gouging.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lead_raised_deg: Option<f64>,
    /// Local gouging somewhere that no lead fixes (the surface is more curved than the cutter
    /// allows, or a ball larger than the smallest concave radius).
    #[serde(default)]
    pub local_gouge: bool,
    /// True when the poses were checked against the exact surface (the checks module).
    #[serde(default)]
    pub exact_check: bool,
    /// Gouges the exact check found on the cutting passes as first stepped, before the repair
    /// (lead raised locally, poses inserted); what is left is `gouging_poses`.
    #[serde(default)]
    pub found_before_repair: usize,
    /// The largest lead the repair raised to, degrees, when it raised any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub repair_lead_deg: Option<f64>,
    /// True when the path was checked against the part's other faces (whole-part check).
    #[serde(default)]
    pub part_checked: bool,
    /// Poses whose tool (shank and holder included) enters another face of the part.
    #[serde(default)]
    pub part_hits: usize,
    /// Deepest entry into another face, mm (0 when none).
    #[serde(default)]
    pub part_max_depth_mm: f64,
}

impl Summary {
    /// The summary of these poses (the first pose is reached from nowhere: no length).
    #[must_use]
    pub fn of(poses: &[Pose]) -> Self {
        let mut s = Self {
            pose_count: poses.len(),
            ..Self::default()
        };
        if let Some(first) = poses.first() {
            s.bbox_min = first.tip;
            s.bbox_max = first.tip;
        }
        for p in poses {
            match p.scallop_mm {
                Some(h) if h >= SCALLOP_NOT_REACHED_MM => {
                    *s.scallop_not_reached_poses.get_or_insert(0) += 1;
                }
                Some(h) => {
                    let m = s.predicted_max_scallop_mm.get_or_insert(h);
                    *m = m.max(h);
                }
                None => {}
            }
        }
        for w in poses.windows(2) {
            let [a, b] = w else { continue };
            let len = a.tip.distance(b.tip);
            s.bbox_min = s.bbox_min.min(b.tip);
            s.bbox_max = s.bbox_max.max(b.tip);
            match b.kind {
                MoveKind::Cut | MoveKind::Plunge => s.cut_length_mm += len,
                MoveKind::Link | MoveKind::Rapid => s.other_length_mm += len,
            }
            s.estimated_time_s += move_time_at_feed_s(a.tip, b);
        }
        s
    }
}

/// Time of the move from `from` to the pose `to` at its feed, s: length / feed, rapids (and
/// moves without a usable feed) at [`crate::units::DEFAULT_RAPID_MM_PER_MIN`], no
/// acceleration. The one "time at feed" rule of the summary and the playback clock.
#[must_use]
pub fn move_time_at_feed_s(from: DVec3, to: &Pose) -> f64 {
    let feed = match to.kind {
        MoveKind::Rapid => ESTIMATE_RAPID_MM_PER_MIN,
        _ if to.feed_mm_per_min.is_finite() && to.feed_mm_per_min > 0.0 => to.feed_mm_per_min,
        _ => ESTIMATE_RAPID_MM_PER_MIN,
    };
    from.distance(to.tip) / feed * 60.0
}

/// Time at feed when each pose is reached, s ([`move_time_at_feed_s`] summed; the first pose at
/// 0). Its last value is the summary's `estimated_time_s`.
#[must_use]
pub fn pose_times_at_feed(poses: &[Pose]) -> Vec<f64> {
    let mut t = 0.0;
    let mut out = Vec::with_capacity(poses.len());
    let mut prev: Option<DVec3> = None;
    for p in poses {
        if let Some(a) = prev {
            t += move_time_at_feed_s(a, p);
        }
        out.push(t);
        prev = Some(p.tip);
    }
    out
}
