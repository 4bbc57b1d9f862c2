//! Engagement: which angles of each axial disk are in the material. For a straight cut the
//! entry and exit angles follow from the radial depth (Eq. 5.11): up milling
//! `[0, arccos(1 − a_r/R)]`, down milling `[π − arccos(1 − a_r/R), π]`, slotting `[0, π]`; on a
//! ball or bull nose the disk's local radius r replaces R in `arccos((R − a_r)/r)`.

use std::f64::consts::{PI, TAU};

use super::ForceError;
use super::mill::EndMill;

/// Milling mode of a straight cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Up (conventional) milling: the chip starts thin.
    Up,
    /// Down (climb) milling: the chip ends thin.
    Down,
    /// Full-width slot.
    Slot,
}

impl Mode {
    /// `up`, `down` or `slot`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Up => "up",
            Self::Down => "down",
            Self::Slot => "slot",
        }
    }

    /// Parse `up`, `down` or `slot` (also `conventional`, `climb`).
    #[must_use]
    pub fn parse(text: &str) -> Option<Self> {
        match text.trim().to_ascii_lowercase().as_str() {
            "up" | "conventional" => Some(Self::Up),
            "down" | "climb" => Some(Self::Down),
            "slot" => Some(Self::Slot),
            _ => None,
        }
    }
}

/// Up to four engaged angle intervals `[start, end]` within [0, 2π], start < end.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Arcs {
    len: usize,
    arcs: [(f64, f64); 4],
}

impl Arcs {
    /// No engagement.
    #[must_use]
    pub fn empty() -> Self {
        Self::default()
    }

    /// One interval (empty if `end <= start`); clamped to [0, 2π].
    #[must_use]
    pub fn single(start: f64, end: f64) -> Self {
        let mut a = Self::default();
        a.push(start, end);
        a
    }

    /// Add an interval; ignored when empty or when four are held already. Returns whether it
    /// was kept.
    pub fn push(&mut self, start: f64, end: f64) -> bool {
        let (s, e) = (start.max(0.0), end.min(TAU));
        if !(e > s) || self.len == self.arcs.len() {
            return false;
        }
        self.arcs[self.len] = (s, e);
        self.len += 1;
        true
    }

    /// The intervals.
    #[must_use]
    pub fn as_slice(&self) -> &[(f64, f64)] {
        &self.arcs[..self.len]
    }

    /// Whether nothing is engaged.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether angle `a` (in [0, 2π)) lies in an interval.
    #[must_use]
    pub fn contains(&self, a: f64) -> bool {
        self.as_slice().iter().any(|&(s, e)| a >= s && a <= e)
    }

    /// Mean of sin φ over the intervals (0 when empty): the mean chip thickness is
    /// `f_t·sin κ` times this (Eq. 5.6).
    #[must_use]
    pub fn mean_sin(&self) -> f64 {
        let (mut num, mut den) = (0.0, 0.0);
        for &(s, e) in self.as_slice() {
            num += s.cos() - e.cos();
            den += e - s;
        }
        if den > 0.0 { num / den } else { 0.0 }
    }
}

/// One axial disk: its height range and its engaged angles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskEngagement {
    /// Bottom of the disk above the tool tip, mm.
    pub z0: f64,
    /// Top of the disk above the tool tip, mm.
    pub z1: f64,
    /// Engaged angles.
    pub arcs: Arcs,
}

/// The engagement of a whole tool: disks from the tip up and the feed per tooth.
#[derive(Clone, Debug, PartialEq)]
pub struct Engagement {
    /// Disks from the tip up, contiguous.
    pub disks: Vec<DiskEngagement>,
    /// Feed per tooth f_t, mm.
    pub feed_per_tooth: f64,
}

/// A straight cut of constant radial and axial depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StraightCut {
    /// Radial depth a_r (width of cut), mm.
    pub radial_depth: f64,
    /// Axial depth a_a, mm.
    pub axial_depth: f64,
    /// Feed per tooth f_t, mm.
    pub feed_per_tooth: f64,
    /// Up, down or slot.
    pub mode: Mode,
}

/// Default disk height, mm.
pub const DEFAULT_DISK_HEIGHT: f64 = 0.5;

impl StraightCut {
    /// Check the cut against the tool: f_t in (0, 2] mm, a_a in (0, 500] mm, a_r in
    /// (0, D] (a slot's a_r is D).
    ///
    /// # Errors
    /// [`ForceError::Input`] naming the bad value.
    pub fn validate(&self, mill: &EndMill) -> Result<(), ForceError> {
        super::check_range("feed per tooth", self.feed_per_tooth, 1e-6, 2.0, "mm")?;
        super::check_range("axial depth", self.axial_depth, 1e-6, 500.0, "mm")?;
        super::check_range(
            "radial depth",
            self.radial_depth,
            1e-6,
            mill.diameter(),
            "mm",
        )?;
        if self.mode == Mode::Slot && (self.radial_depth - mill.diameter()).abs() > 1e-9 {
            return Err(ForceError::Input(format!(
                "a slot is cut at a radial depth equal to the diameter {} mm, got {} mm",
                mill.diameter(),
                self.radial_depth
            )));
        }
        Ok(())
    }

    /// Entry and exit angles on the full radius `R` (Eq. 5.11).
    #[must_use]
    pub fn immersion(&self, radius: f64) -> (f64, f64) {
        let a = self.arcs_at(radius, radius);
        a.as_slice().first().copied().unwrap_or((0.0, 0.0))
    }

    /// Engaged angles of an edge at local radius `r` of a tool of radius `radius`.
    #[must_use]
    pub fn arcs_at(&self, radius: f64, r: f64) -> Arcs {
        if self.mode == Mode::Slot {
            return Arcs::single(0.0, PI);
        }
        let c = (radius - self.radial_depth) / r;
        if c >= 1.0 {
            return Arcs::empty();
        }
        let sweep = c.max(-1.0).acos();
        match self.mode {
            Mode::Up => Arcs::single(0.0, sweep),
            _ => Arcs::single(PI - sweep, PI),
        }
    }

    /// The disk engagement of this cut: disks of at most `disk_height` mm (at least 8 disks,
    /// and disk boundaries at the nose height so no disk straddles the nose and the cylinder),
    /// each with the angles engaged at its mid-height radius.
    ///
    /// # Errors
    /// As [`StraightCut::validate`], and for a disk height outside (0, 100] mm.
    pub fn engagement(&self, mill: &EndMill, disk_height: f64) -> Result<Engagement, ForceError> {
        self.validate(mill)?;
        super::check_range("disk height", disk_height, 1e-4, 100.0, "mm")?;
        let nose = mill.nose_height().min(self.axial_depth);
        let mut disks = Vec::new();
        for (lo, hi) in [(0.0, nose), (nose, self.axial_depth)] {
            if hi - lo <= 1e-12 {
                continue;
            }
            let min_disks = if nose > 0.0 { 4.0 } else { 8.0 };
            // A count of disks: small, positive and finite by the checks above.
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let n = ((hi - lo) / disk_height).ceil().max(min_disks) as usize;
            let dz = (hi - lo) / n as f64;
            for i in 0..n {
                let z0 = lo + dz * i as f64;
                let z1 = if i + 1 == n { hi } else { z0 + dz };
                let r = mill.local(0.5 * (z0 + z1)).radius;
                disks.push(DiskEngagement {
                    z0,
                    z1,
                    arcs: self.arcs_at(mill.radius, r),
                });
            }
        }
        Ok(Engagement {
            disks,
            feed_per_tooth: self.feed_per_tooth,
        })
    }
}
