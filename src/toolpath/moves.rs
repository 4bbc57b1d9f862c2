//! Exact moves: arcs, helices and canned cycles beside the sampled poses.
//!
//! A [`Toolpath`](super::Toolpath) keeps its poses as the sampled view every consumer reads
//! (simulation, playback, checks); [`ExactSegment`]s say that the poses `from..=to` sample one
//! exact move that starts at pose `from` and ends at pose `to`. Poses not covered by a segment
//! are reached by straight moves (rapid or line, by the pose's kind), as before. The post writes
//! an exact move as G2/G3 or a canned cycle where the dialect and machine allow it, and its
//! poses as lines otherwise.
//!
//! Cycle motion follows LinuxCNC's interpreter (`interp_cycles.cc`, checked with `rs274 -g`):
//! pecks come back down to 0.254 mm above the last depth (G83) or back off 0.254 mm (G73), a tap
//! feeds out to the clear plane, a bore feeds out to the R plane (G85) or to the clear plane
//! after its dwell (G89).

use glam::DVec3;

/// LinuxCNC's `G83_RAPID_DELTA` and `G73_PECK_CLEARANCE` (0.010 in), mm.
pub const PECK_CLEARANCE_MM: f64 = 0.254;

/// Most samples one exact move may take (a guard against a tolerance far below the size).
pub const MAX_SAMPLES: usize = 1_000_000;

/// A circular arc or helix that starts at its segment's first pose.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct ArcMove {
    /// Centre, mm, in the plane through the start point normal to `normal`.
    #[schemars(with = "[f64; 3]")]
    pub centre: DVec3,
    /// Unit normal of the arc's plane (any direction; +Z, +Y, +X are G17, G18, G19).
    #[schemars(with = "[f64; 3]")]
    pub normal: DVec3,
    /// Swept angle, rad: positive counter-clockwise about `normal` (right-hand rule), negative
    /// clockwise; more than one turn for a helix of several turns.
    pub sweep_rad: f64,
    /// Travel along `normal` from start to end, mm (0 for a planar arc).
    #[serde(default)]
    pub helix_mm: f64,
}

impl ArcMove {
    /// The point at parameter `t` in [0, 1] of the move that starts at `start`.
    #[must_use]
    pub fn point_at(&self, start: DVec3, t: f64) -> DVec3 {
        let r0 = start - self.centre;
        let r0 = r0 - self.normal * r0.dot(self.normal);
        let (s, c) = (self.sweep_rad * t).sin_cos();
        // Rodrigues' rotation of the in-plane radius about the normal.
        let rotated = r0 * c + self.normal.cross(r0) * s;
        let base = start - r0;
        base + rotated + self.normal * (self.helix_mm * t)
    }

    /// The end point of the move that starts at `start`.
    #[must_use]
    pub fn end(&self, start: DVec3) -> DVec3 {
        self.point_at(start, 1.0)
    }

    /// Radius, mm, for the start point `start`.
    #[must_use]
    pub fn radius_mm(&self, start: DVec3) -> f64 {
        let r0 = start - self.centre;
        (r0 - self.normal * r0.dot(self.normal)).length()
    }

    /// Tip path length, mm.
    #[must_use]
    pub fn length_mm(&self, start: DVec3) -> f64 {
        (self.radius_mm(start) * self.sweep_rad).hypot(self.helix_mm)
    }

    /// The number of equal-angle pieces whose chords stay within `chord_tol_mm` of the arc.
    ///
    /// # Errors
    /// A tolerance that is not positive, or more than [`MAX_SAMPLES`] pieces.
    pub fn pieces(&self, start: DVec3, chord_tol_mm: f64) -> Result<usize, String> {
        if !(chord_tol_mm > 0.0 && chord_tol_mm.is_finite()) {
            return Err(format!(
                "chord tolerance {chord_tol_mm} mm must be positive"
            ));
        }
        let r = self.radius_mm(start);
        let tol = chord_tol_mm.min(r);
        let step = 2.0 * (1.0 - tol / r).clamp(-1.0, 1.0).acos();
        let n = (self.sweep_rad.abs() / step.max(1e-12)).ceil();
        if !(n <= MAX_SAMPLES as f64) {
            return Err(format!(
                "an arc of radius {r} mm sweeping {} rad needs more than {MAX_SAMPLES} chords at {chord_tol_mm} mm",
                self.sweep_rad
            ));
        }
        Ok((n as usize).max(1))
    }

    /// Checks: finite numbers, unit normal (within 1e-6), centre in the start point's plane
    /// (within 1e-6 mm), radius at least 1 µm, sweep non-zero and at most 1000 turns.
    ///
    /// # Errors
    /// What is wrong, in words.
    pub fn validate(&self, start: DVec3) -> Result<(), String> {
        if !(self.centre.is_finite()
            && self.normal.is_finite()
            && self.sweep_rad.is_finite()
            && self.helix_mm.is_finite())
        {
            return Err("arc: non-finite number".into());
        }
        if (self.normal.length() - 1.0).abs() > 1e-6 {
            return Err(format!(
                "arc: normal length {} is not 1",
                self.normal.length()
            ));
        }
        let off = (start - self.centre).dot(self.normal);
        if off.abs() > 1e-6 * (1.0 + self.centre.abs().max_element()) {
            return Err(format!(
                "arc: centre is {off} mm off the start point's plane along the normal"
            ));
        }
        if self.radius_mm(start) < 1e-3 {
            return Err(format!(
                "arc: radius {} mm is below 1 µm",
                self.radius_mm(start)
            ));
        }
        if self.sweep_rad == 0.0 || self.sweep_rad.abs() > 1000.0 * std::f64::consts::TAU {
            return Err(format!(
                "arc: sweep {} rad must be non-zero and at most 1000 turns",
                self.sweep_rad
            ));
        }
        Ok(())
    }
}

/// Where a cycle leaves the tool after the hole (G98 / G99).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum CycleRetract {
    /// Back to the initial plane, where the cycle started (G98).
    #[default]
    Initial,
    /// Back to the R plane (G99).
    RPlane,
}

/// The kind of hole-making cycle and its own parameters.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum CycleKind {
    /// Feed to depth, rapid out (G81, CYCLE81, Heidenhain 200).
    Drill,
    /// Feed to depth, dwell, rapid out (G82, CYCLE82, Heidenhain 200 with Q211).
    Dwell {
        /// Dwell at the bottom, s.
        dwell_s: f64,
    },
    /// Deep-hole peck: feed `peck_mm`, rapid out to the R plane, rapid back down (G83,
    /// CYCLE83 with VARI=1, Heidenhain 200 with Q202).
    Peck {
        /// Depth of each peck, mm.
        peck_mm: f64,
    },
    /// Chip-breaking peck: feed `peck_mm`, back off 0.254 mm (G73, CYCLE83 with VARI=0,
    /// Heidenhain 203).
    ChipBreak {
        /// Depth of each peck, mm.
        peck_mm: f64,
    },
    /// Right-hand tapping: feed in, spindle reversed, feed out (G84, CYCLE84, Heidenhain 207).
    /// The cycle's feed must be the pitch times the spindle speed.
    Tap {
        /// Thread pitch, mm per turn.
        pitch_mm: f64,
    },
    /// Boring or reaming, fed out (G85 without dwell, G89 with; CYCLE85 / CYCLE89;
    /// Heidenhain 201).
    Bore {
        /// Dwell at the bottom, s (0: G85, fed out to the R plane then rapid).
        dwell_s: f64,
    },
    /// Boring with the spindle stopped at the bottom and a rapid out (G86, CYCLE86).
    BoreSpindleStop {
        /// Dwell at the bottom, s.
        dwell_s: f64,
    },
}

/// A canned cycle for one hole along a tool axis, in part coordinates.
///
/// Heights are measured along `axis` from `surface`: the tool starts at the initial plane
/// (`retract_mm` above the surface), rapids to the R plane (`clearance_mm`), works down to
/// `depth_mm` below the surface and leaves to the plane `retract` names.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct CycleMove {
    /// What the cycle does, with its own parameters.
    pub cycle: CycleKind,
    /// Where the hole's axis meets the top surface, mm.
    #[schemars(with = "[f64; 3]")]
    pub surface: DVec3,
    /// Unit tool axis (from the hole toward the spindle).
    #[schemars(with = "[f64; 3]")]
    pub axis: DVec3,
    /// Depth of the hole below the surface, mm (> 0).
    pub depth_mm: f64,
    /// R plane above the surface, mm (≥ 0).
    pub clearance_mm: f64,
    /// Initial plane above the surface, mm (≥ `clearance_mm`): where the tool starts.
    pub retract_mm: f64,
    /// Where the tool goes after the hole.
    #[serde(default)]
    pub retract: CycleRetract,
    /// Feed into the hole, mm/min.
    pub feed_mm_per_min: f64,
}

/// A spindle switch inside a cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpindleSwitch {
    /// Stop the spindle.
    Stop,
    /// Run it clockwise (M3).
    Forward,
    /// Run it counter-clockwise (M4).
    Reverse,
}

/// One step of a cycle's motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CycleStep {
    /// Rapid to the point.
    Rapid(DVec3),
    /// Feed to the point at the cycle's feed.
    Feed(DVec3),
    /// Stand still, s.
    Dwell(f64),
    /// Switch the spindle.
    Spindle(SpindleSwitch),
}

impl CycleMove {
    /// The point `h` mm above the surface on the hole's axis.
    #[must_use]
    pub fn at(&self, h: f64) -> DVec3 {
        self.surface + self.axis * h
    }

    /// Where the cycle starts: the initial plane.
    #[must_use]
    pub fn start(&self) -> DVec3 {
        self.at(self.retract_mm)
    }

    /// The bottom of the hole.
    #[must_use]
    pub fn bottom(&self) -> DVec3 {
        self.at(-self.depth_mm)
    }

    /// The plane the cycle leaves the tool at (height above the surface, mm).
    #[must_use]
    pub fn clear_mm(&self) -> f64 {
        match self.retract {
            CycleRetract::Initial => self.retract_mm,
            CycleRetract::RPlane => self.clearance_mm,
        }
    }

    /// Checks: finite numbers, unit axis, depth and feed positive, `0 ≤ clearance ≤ retract`,
    /// pecks and pitch positive, dwells not negative, at most [`MAX_SAMPLES`] pecks.
    ///
    /// # Errors
    /// What is wrong, in words.
    pub fn validate(&self) -> Result<(), String> {
        let finite = [
            self.depth_mm,
            self.clearance_mm,
            self.retract_mm,
            self.feed_mm_per_min,
        ]
        .iter()
        .all(|v| v.is_finite())
            && self.surface.is_finite()
            && self.axis.is_finite();
        if !finite {
            return Err("cycle: non-finite number".into());
        }
        if (self.axis.length() - 1.0).abs() > 1e-6 {
            return Err(format!(
                "cycle: axis length {} is not 1",
                self.axis.length()
            ));
        }
        if !(self.depth_mm > 0.0) {
            return Err(format!(
                "cycle: depth {} mm must be positive",
                self.depth_mm
            ));
        }
        if !(self.feed_mm_per_min > 0.0) {
            return Err(format!(
                "cycle: feed {} mm/min must be positive",
                self.feed_mm_per_min
            ));
        }
        if !(self.clearance_mm >= 0.0 && self.retract_mm >= self.clearance_mm) {
            return Err(format!(
                "cycle: need 0 <= clearance ({} mm) <= retract ({} mm)",
                self.clearance_mm, self.retract_mm
            ));
        }
        match self.cycle {
            CycleKind::Drill => Ok(()),
            CycleKind::Dwell { dwell_s }
            | CycleKind::Bore { dwell_s }
            | CycleKind::BoreSpindleStop { dwell_s } => {
                if dwell_s >= 0.0 && dwell_s.is_finite() {
                    Ok(())
                } else {
                    Err(format!("cycle: dwell {dwell_s} s must be finite and >= 0"))
                }
            }
            CycleKind::Peck { peck_mm } | CycleKind::ChipBreak { peck_mm } => {
                let total = self.depth_mm + self.clearance_mm;
                if !(peck_mm > 0.0 && peck_mm.is_finite()) {
                    Err(format!("cycle: peck {peck_mm} mm must be positive"))
                } else if total / peck_mm > MAX_SAMPLES as f64 / 4.0 {
                    Err(format!(
                        "cycle: peck {peck_mm} mm makes more than {} pecks",
                        MAX_SAMPLES / 4
                    ))
                } else {
                    Ok(())
                }
            }
            CycleKind::Tap { pitch_mm } => {
                if pitch_mm > 0.0 && pitch_mm.is_finite() {
                    Ok(())
                } else {
                    Err(format!("cycle: pitch {pitch_mm} mm must be positive"))
                }
            }
        }
    }

    /// The cycle's motion from its start (the initial plane), as LinuxCNC runs it.
    #[must_use]
    pub fn steps(&self) -> Vec<CycleStep> {
        use CycleStep::{Dwell, Feed, Rapid, Spindle};
        let r = self.clearance_mm;
        let bottom = -self.depth_mm;
        let clear = self.at(self.clear_mm());
        let mut s = vec![Rapid(self.at(r))];
        let pecks = |s: &mut Vec<CycleStep>, peck: f64, full_retract: bool| {
            let mut depth = r;
            while depth > bottom {
                let next = (depth - peck).max(bottom);
                s.push(Feed(self.at(next)));
                depth = next;
                if depth > bottom {
                    if full_retract {
                        s.push(Rapid(self.at(r)));
                        s.push(Rapid(self.at(depth + PECK_CLEARANCE_MM)));
                    } else {
                        s.push(Rapid(self.at(depth + PECK_CLEARANCE_MM)));
                    }
                }
            }
        };
        match self.cycle {
            CycleKind::Drill => s.extend([Feed(self.bottom()), Rapid(clear)]),
            CycleKind::Dwell { dwell_s } => {
                s.extend([Feed(self.bottom()), Dwell(dwell_s), Rapid(clear)]);
            }
            CycleKind::Peck { peck_mm } => {
                pecks(&mut s, peck_mm, true);
                s.push(Rapid(clear));
            }
            CycleKind::ChipBreak { peck_mm } => {
                pecks(&mut s, peck_mm, false);
                s.push(Rapid(clear));
            }
            CycleKind::Tap { .. } => s.extend([
                Feed(self.bottom()),
                Spindle(SpindleSwitch::Reverse),
                Feed(clear),
                Spindle(SpindleSwitch::Forward),
            ]),
            CycleKind::Bore { dwell_s } if dwell_s > 0.0 => {
                s.extend([Feed(self.bottom()), Dwell(dwell_s), Feed(clear)]);
            }
            CycleKind::Bore { .. } => {
                s.extend([Feed(self.bottom()), Feed(self.at(r)), Rapid(clear)]);
            }
            CycleKind::BoreSpindleStop { dwell_s } => {
                s.push(Feed(self.bottom()));
                if dwell_s > 0.0 {
                    s.push(Dwell(dwell_s));
                }
                s.extend([
                    Spindle(SpindleSwitch::Stop),
                    Rapid(clear),
                    Spindle(SpindleSwitch::Forward),
                ]);
            }
        }
        // A rapid to where the tool already is (R plane = initial plane) moves nothing.
        let mut here = self.start();
        s.retain(|step| match step {
            Rapid(p) | Feed(p) => {
                let moved = p.distance(here) > 1e-12;
                here = *p;
                moved
            }
            _ => true,
        });
        s
    }

    /// Total dwell time of the cycle, s.
    #[must_use]
    pub fn dwell_s(&self) -> f64 {
        match self.cycle {
            CycleKind::Dwell { dwell_s }
            | CycleKind::Bore { dwell_s }
            | CycleKind::BoreSpindleStop { dwell_s } => dwell_s,
            _ => 0.0,
        }
    }

    /// This cycle moved by `offset` (program coordinates).
    #[must_use]
    pub fn translated(mut self, offset: DVec3) -> Self {
        self.surface += offset;
        self
    }
}

/// An exact move.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(tag = "move", rename_all = "snake_case")]
pub enum ExactMove {
    /// Arc or helix (helix when `helix_mm` is not 0).
    Arc(ArcMove),
    /// Canned cycle.
    Cycle(CycleMove),
}

/// Poses `from..=to` sample one exact move from pose `from` to pose `to`.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct ExactSegment {
    /// The pose the move starts at.
    pub from: usize,
    /// The pose the move ends at (> `from`).
    pub to: usize,
    /// The move.
    #[serde(flatten)]
    pub exact: ExactMove,
}

/// A move of a tool path, as the post reads it: straight to a pose, or an exact move over a
/// range of poses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Move<'a> {
    /// Rapid to pose `to`.
    Rapid {
        /// Index of the pose reached.
        to: usize,
    },
    /// Straight feed to pose `to` (cut, link or plunge).
    Line {
        /// Index of the pose reached.
        to: usize,
    },
    /// An arc, helix or cycle with its segment.
    Exact(&'a ExactSegment),
}
