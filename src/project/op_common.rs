//! The settings every 2.5D and hole operation shares ([`Common`], flattened into
//! [`super::Operation::Face`], [`super::Operation::Pocket`], [`super::Operation::Contour`] and
//! [`super::Operation::Holes`]): heights, feeds, spindle speed, coolant and stock to leave.
//! Applied after planning by [`apply_feeds`] and [`apply_feed_from`], which work on any tool
//! path, and read by the strategies through [`Levels`].

use crate::toolpath::{ExactMove, MoveKind, Pose, Toolpath};

/// What a height is measured from (in the setup's planning frame, +Z the tool axis).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HeightFrom {
    /// The top of the setup's stock.
    #[default]
    StockTop,
    /// The top of the part as it lies in the setup.
    PartTop,
    /// The setup's origin (the program zero): an absolute height.
    Origin,
}

/// A height: `mm` above the reference `from`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Height {
    /// Distance above the reference, mm (negative: below it).
    pub mm: f64,
    /// The reference.
    #[serde(default)]
    pub from: HeightFrom,
}

impl Height {
    /// `mm` above the stock top.
    #[must_use]
    pub const fn above_stock(mm: f64) -> Self {
        Self {
            mm,
            from: HeightFrom::StockTop,
        }
    }

    /// The height as a Z in the planning frame.
    #[must_use]
    pub fn z(&self, levels: &Levels) -> f64 {
        self.mm
            + match self.from {
                HeightFrom::StockTop => levels.stock_top_z,
                HeightFrom::PartTop => levels.part_top_z,
                HeightFrom::Origin => 0.0,
            }
    }
}

/// The reference heights of one plan, in the planning frame (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Levels {
    /// Top of the stock (the part's top when no stock is set).
    pub stock_top_z: f64,
    /// Top of the part.
    pub part_top_z: f64,
}

/// Settings shared by the 2.5D and hole operations.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Common {
    /// Clearance height: rapids between regions and holes (default 5 mm above the stock).
    #[serde(default = "default_clearance")]
    pub clearance: Height,
    /// Retract height: the R plane of hole cycles (default 2 mm above the part's top).
    #[serde(default = "default_retract")]
    pub retract: Height,
    /// Feed-from height: rapids going down stop here and the tool feeds on at the plunge feed
    /// (default 1 mm above the stock).
    #[serde(default = "default_feed_from")]
    pub feed_from: Height,
    /// Cutting feed, mm/min.
    #[serde(default = "default_feed")]
    pub feed_mm_per_min: f64,
    /// Feed of plunges along the tool axis, mm/min (default: a third of the cutting feed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plunge_feed_mm_per_min: Option<f64>,
    /// Feed of ramping cuts (cuts going down), mm/min (default: half the cutting feed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ramp_feed_mm_per_min: Option<f64>,
    /// Spindle speed, rev/min (default: the project's post setting).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spindle_rpm: Option<f64>,
    /// Flood coolant on.
    #[serde(default = "yes")]
    pub coolant: bool,
    /// Material left on walls, mm.
    #[serde(default)]
    pub stock_to_leave_walls_mm: f64,
    /// Material left on floors, mm.
    #[serde(default)]
    pub stock_to_leave_floors_mm: f64,
}

fn default_clearance() -> Height {
    Height::above_stock(5.0)
}

fn default_retract() -> Height {
    Height {
        mm: 2.0,
        from: HeightFrom::PartTop,
    }
}

fn default_feed_from() -> Height {
    Height::above_stock(1.0)
}

fn default_feed() -> f64 {
    600.0
}

fn yes() -> bool {
    true
}

impl Default for Common {
    fn default() -> Self {
        Self {
            clearance: default_clearance(),
            retract: default_retract(),
            feed_from: default_feed_from(),
            feed_mm_per_min: default_feed(),
            plunge_feed_mm_per_min: None,
            ramp_feed_mm_per_min: None,
            spindle_rpm: None,
            coolant: true,
            stock_to_leave_walls_mm: 0.0,
            stock_to_leave_floors_mm: 0.0,
        }
    }
}

impl Common {
    /// The plunge feed, mm/min.
    #[must_use]
    pub fn plunge_feed(&self) -> f64 {
        self.plunge_feed_mm_per_min
            .unwrap_or(self.feed_mm_per_min / 3.0)
    }

    /// The ramp feed, mm/min.
    #[must_use]
    pub fn ramp_feed(&self) -> f64 {
        self.ramp_feed_mm_per_min
            .unwrap_or(self.feed_mm_per_min / 2.0)
    }

    /// Check the numbers, in words with units.
    ///
    /// # Errors
    /// What is wrong.
    pub fn validate(&self) -> Result<(), String> {
        for (what, h) in [
            ("clearance", self.clearance),
            ("retract", self.retract),
            ("feed-from", self.feed_from),
        ] {
            if !(h.mm.is_finite() && h.mm.abs() <= crate::units::MAX_COORDINATE_MM) {
                return Err(format!(
                    "the {what} height must lie within ±{} mm, got {}",
                    crate::units::MAX_COORDINATE_MM,
                    h.mm
                ));
            }
        }
        for (what, v) in [
            ("feed (mm/min)", Some(self.feed_mm_per_min)),
            ("plunge feed (mm/min)", self.plunge_feed_mm_per_min),
            ("ramp feed (mm/min)", self.ramp_feed_mm_per_min),
            ("spindle speed (rev/min)", self.spindle_rpm),
        ] {
            if let Some(v) = v {
                crate::units::FEED_BOUNDS.check(what, v)?;
            }
        }
        for (what, v) in [
            ("on walls", self.stock_to_leave_walls_mm),
            ("on floors", self.stock_to_leave_floors_mm),
        ] {
            crate::units::ALLOWANCE_BOUNDS.check(&format!("stock to leave {what} (mm)"), v)?;
        }
        Ok(())
    }
}

/// Sets the feeds of `tp` from `common`: plunges at the plunge feed, cuts whose tip goes down
/// at the ramp feed, other cuts at the cutting feed (rapids and links untouched). Canned cycles
/// keep their own feed.
pub fn apply_feeds(tp: &mut Toolpath, common: &Common) {
    let mut in_cycle = vec![false; tp.poses.len()];
    for s in &tp.exact {
        if matches!(s.exact, ExactMove::Cycle(_)) {
            for f in in_cycle.iter_mut().take(s.to + 1).skip(s.from) {
                *f = true;
            }
        }
    }
    let mut prev: Option<glam::DVec3> = None;
    for (i, p) in tp.poses.iter_mut().enumerate() {
        let before = prev.replace(p.tip);
        if in_cycle.get(i).copied().unwrap_or(false) {
            continue;
        }
        match p.kind {
            MoveKind::Plunge => p.feed_mm_per_min = common.plunge_feed(),
            MoveKind::Cut => {
                let down = before.is_some_and(|b| {
                    let d = p.tip - b;
                    d.dot(p.axis) < -1e-6 && d.length() > 1e-9
                });
                p.feed_mm_per_min = if down {
                    common.ramp_feed()
                } else {
                    common.feed_mm_per_min
                };
            }
            MoveKind::Rapid | MoveKind::Link => {}
        }
    }
}

/// Splits every rapid that goes down along the tool axis through the feed-from height `z` (in
/// the frame of `tp`, +Z the tool axis): a rapid to `z`, then a plunge at `plunge_feed` on to
/// the rapid's end. Rapids inside exact moves (canned cycles) are left as they are.
pub fn apply_feed_from(tp: &mut Toolpath, z: f64, plunge_feed: f64) {
    let inside = |i: usize, tp: &Toolpath| tp.exact.iter().any(|s| s.from < i && i <= s.to);
    let mut i = 1;
    while i < tp.poses.len() {
        let (a, b) = (tp.poses[i - 1], tp.poses[i]);
        let d = b.tip - a.tip;
        let vertical = d.truncate().length() <= 1e-9;
        if b.kind == MoveKind::Rapid
            && vertical
            && a.tip.z > z + 1e-9
            && b.tip.z < z - 1e-9
            && !inside(i, tp)
        {
            let mut mid: Pose = b;
            mid.tip.z = z;
            tp.poses[i].kind = MoveKind::Plunge;
            tp.poses[i].feed_mm_per_min = plunge_feed;
            tp.poses.insert(i, mid);
            for s in &mut tp.exact {
                if s.from >= i {
                    s.from += 1;
                    s.to += 1;
                }
            }
            i += 2;
        } else {
            i += 1;
        }
    }
    tp.resummarise();
}

/// The reference heights of `part` (as it lies in the planning frame) under a stock whose top
/// is `stock_top_z` (`None`: the part's top).
#[must_use]
pub fn levels(part: &crate::import::Workpiece, stock_top_z: Option<f64>) -> Levels {
    let top = part.mesh.bbox().max.z;
    Levels {
        stock_top_z: stock_top_z.unwrap_or(top),
        part_top_z: top,
    }
}

/// The top of `stock` (`None` when no stock is set).
#[must_use]
pub fn stock_top(stock: &crate::geometry::stock::Stock) -> Option<f64> {
    stock.bounds().map(|b| b.max.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::{Pose, ToolRecord};
    use glam::DVec3;

    fn record() -> ToolRecord {
        let cutter = crate::tools::parse_tool_spec("flat:d=6").expect("a flat end mill");
        ToolRecord {
            spec: "flat:d=6".into(),
            cutter,
        }
    }

    #[test]
    fn a_rapid_down_through_the_feed_from_height_becomes_rapid_then_plunge() {
        let p = |z: f64, kind| Pose::new(kind, DVec3::new(1.0, 2.0, z), DVec3::Z, 0.0);
        let mut tp = Toolpath::new(
            record(),
            vec![
                p(20.0, MoveKind::Rapid),
                p(-3.0, MoveKind::Rapid),
                p(-3.0, MoveKind::Cut),
            ],
        );
        apply_feed_from(&mut tp, 1.0, 123.0);
        let z: Vec<f64> = tp.poses.iter().map(|p| p.tip.z).collect();
        assert_eq!(z, vec![20.0, 1.0, -3.0, -3.0]);
        assert_eq!(tp.poses[1].kind, MoveKind::Rapid);
        assert_eq!(tp.poses[2].kind, MoveKind::Plunge);
        assert!((tp.poses[2].feed_mm_per_min - 123.0).abs() < 1e-12);
    }

    #[test]
    fn heights_resolve_from_their_reference() {
        let l = Levels {
            stock_top_z: 26.0,
            part_top_z: 25.0,
        };
        assert!((Height::above_stock(5.0).z(&l) - 31.0).abs() < 1e-12);
        let h = Height {
            mm: 2.0,
            from: HeightFrom::PartTop,
        };
        assert!((h.z(&l) - 27.0).abs() < 1e-12);
        let o = Height {
            mm: 40.0,
            from: HeightFrom::Origin,
        };
        assert!((o.z(&l) - 40.0).abs() < 1e-12);
    }
}
