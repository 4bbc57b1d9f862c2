//! The interpreter's output: motion blocks in machine coordinates.

use glam::DVec3;

/// A machine position: X Y Z in mm, and the rotary axes A B C in rad where the program uses
/// them (`None` for an axis the program never mentioned).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Joints {
    /// X, Y, Z in mm (machine coordinates: program coordinates plus the active work offset).
    pub xyz: DVec3,
    /// A axis in rad.
    pub a: Option<f64>,
    /// B axis in rad.
    pub b: Option<f64>,
    /// C axis in rad.
    pub c: Option<f64>,
}

impl Joints {
    /// A position with only linear axes.
    #[must_use]
    pub fn xyz(x: f64, y: f64, z: f64) -> Self {
        Self {
            xyz: DVec3::new(x, y, z),
            ..Self::default()
        }
    }

    /// Every coordinate is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.xyz.is_finite()
            && [self.a, self.b, self.c]
                .iter()
                .flatten()
                .all(|v| v.is_finite())
    }
}

/// The circular part of an arc block.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Arc {
    /// Centre in machine coordinates, at the start point's height along the plane normal.
    pub centre: DVec3,
    /// Unit plane normal: +Z for G17, +Y for G18 (the ZX plane), +X for G19 (the YZ plane).
    /// The sense (CW/CCW) is seen looking down this normal, as in ISO 6983 / RS274NGC.
    pub normal: DVec3,
    /// Radius in mm (distance from the centre to the start point, in the plane).
    pub radius_mm: f64,
    /// Swept angle in rad, always positive (the direction is the block's kind); up to 2π per
    /// turn, more with a `P` turn count.
    pub sweep_rad: f64,
    /// Travel along the normal from start to end in mm (signed; 0 for a planar arc).
    pub helix_mm: f64,
}

impl Arc {
    /// Length of the helix (or planar arc) in mm.
    #[must_use]
    pub fn length_mm(&self) -> f64 {
        (self.radius_mm * self.sweep_rad).hypot(self.helix_mm)
    }
}

/// What a block does.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum MotionKind {
    /// G0: rapid positioning (straight line in joint space).
    Rapid,
    /// G1: straight feed move.
    Linear,
    /// G2: clockwise arc (seen from the plane normal).
    ArcCw(Arc),
    /// G3: counter-clockwise arc (seen from the plane normal).
    ArcCcw(Arc),
}

impl MotionKind {
    /// The arc, for G2/G3.
    #[must_use]
    pub fn arc(&self) -> Option<&Arc> {
        match self {
            Self::ArcCw(a) | Self::ArcCcw(a) => Some(a),
            Self::Rapid | Self::Linear => None,
        }
    }
}

/// One motion of the program, in machine coordinates (mm, rad).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MotionBlock {
    /// Rapid, line or arc.
    pub kind: MotionKind,
    /// Position before the move.
    pub start: Joints,
    /// Position after the move.
    pub end: Joints,
    /// With `inverse_time == false` (G94): the programmed feed in mm/min (rapids carry
    /// [`super::InterpretOptions::rapid_mm_per_min`]; 0 when no F was ever given, with a
    /// warning). With `inverse_time == true` (G93): the F word itself in 1/min, i.e. the block
    /// takes 1/F minutes.
    pub feed_mm_per_min: f64,
    /// G93 inverse-time feed mode was active for this block.
    pub inverse_time: bool,
    /// 1-based line of the block in the source text.
    pub source_line: usize,
    /// Active tool number (`T` word, last one selected; 0 before any).
    pub tool: u32,
    /// `H` number of active tool length compensation (G43), `None` after G49 or before any.
    pub tool_length_h: Option<u32>,
    /// Spindle speed in rpm, signed: positive for M3 (CW), negative for M4, 0 when stopped.
    pub spindle_rpm: f64,
    /// Coolant on (M7/M8 until M9).
    pub coolant: bool,
    /// Tool-centre-point mode (G43.4, TRAORI, M128) was active: X Y Z are the tool tip in
    /// part coordinates and the controller keeps it there while the rotary axes move, instead
    /// of being joint positions.
    #[serde(default)]
    pub tcp: bool,
    /// The canned-cycle move this block is, when a drilling, peck, tap or bore cycle made it
    /// (what the control's panel shows while it runs). Not part of the block's file form.
    #[serde(skip)]
    pub cycle: Option<CyclePhase>,
}

/// What one move of a canned cycle does: the control shows it while the move runs
/// ("G83 hole 2 of 4, peck 3 of 5, to 7.500 mm below R").
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CyclePhase {
    /// The cycle as programmed: `G83`, `CYCLE83`, `CYCL DEF 203`.
    pub cycle: &'static str,
    /// The hole (repeat) of the cycle block, 1-based.
    pub hole: u32,
    /// Holes of the cycle block (its `L`/`K` repeats).
    pub holes: u32,
    /// The peck (infeed) this move belongs to, 1-based; 0 while positioning to the hole.
    pub peck: u32,
    /// Pecks to the bottom (1 for a cycle without pecks).
    pub pecks: u32,
    /// What the move does.
    pub step: CycleStep,
    /// Depth this peck reaches, below the R plane, mm (0 while positioning).
    pub depth_mm: f64,
    /// Depth of the hole's bottom below the R plane, mm.
    pub bottom_mm: f64,
    /// The dwell's time, s, while the step is [`CycleStep::Dwell`] (0 otherwise).
    pub dwell_s: f64,
}

/// The kind of move inside a canned cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CycleStep {
    /// Rapid to the hole, or down to the R plane.
    Position,
    /// Feeding into the material.
    Feed,
    /// Back out (to R, to the clearance plane, or the chip-break lift).
    Retract,
    /// Rapid back down to just above the last peck's depth.
    Reenter,
    /// Standing still at the bottom (`P` of G82, G84, G86, G89): carried by the dwell
    /// ([`crate::gcode::Dwell::cycle`]), not by a move.
    Dwell,
}

impl CycleStep {
    /// The step as the panel words it.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Position => "positioning",
            Self::Feed => "feeding",
            Self::Retract => "retracting",
            Self::Reenter => "re-entering",
            Self::Dwell => "dwell",
        }
    }
}

impl CyclePhase {
    /// One line for a panel: `G83 hole 1/4, peck 3/5 feeding to 7.500 mm of 15.000 mm below R`,
    /// or while it dwells `G82 hole 2/6 dwell 0.5 s at 5.000 mm below R`.
    #[must_use]
    pub fn describe(&self) -> String {
        if self.step == CycleStep::Dwell {
            return format!(
                "{} hole {}/{} dwell {} s at {:.3} mm below R",
                self.cycle, self.hole, self.holes, self.dwell_s, self.depth_mm
            );
        }
        let peck = if self.peck == 0 {
            String::new()
        } else {
            format!(", peck {}/{}", self.peck, self.pecks)
        };
        format!(
            "{} hole {}/{}{peck} {} to {:.3} mm of {:.3} mm below R",
            self.cycle,
            self.hole,
            self.holes,
            self.step.label(),
            self.depth_mm,
            self.bottom_mm
        )
    }
}

impl MotionBlock {
    /// Cartesian length of the tool's linear-axis path in mm (helix length for arcs). Rotary
    /// axis travel is not included; see [`MotionBlock::rotary_travel_rad`].
    #[must_use]
    pub fn length_mm(&self) -> f64 {
        match self.kind.arc() {
            Some(arc) => arc.length_mm(),
            None => self.start.xyz.distance(self.end.xyz),
        }
    }

    /// Total absolute rotary travel |ΔA| + |ΔB| + |ΔC| in rad.
    #[must_use]
    pub fn rotary_travel_rad(&self) -> f64 {
        let d = |s: Option<f64>, e: Option<f64>| match (s, e) {
            (Some(s), Some(e)) => (e - s).abs(),
            (None, Some(e)) => e.abs(),
            _ => 0.0,
        };
        d(self.start.a, self.end.a) + d(self.start.b, self.end.b) + d(self.start.c, self.end.c)
    }

    /// Programmed duration in s for inverse-time (G93) blocks, `None` otherwise.
    #[must_use]
    pub fn inverse_time_duration_s(&self) -> Option<f64> {
        (self.inverse_time && self.feed_mm_per_min > 0.0).then(|| 60.0 / self.feed_mm_per_min)
    }

    /// The position at fraction `t` ∈ [0, 1] of the move (arcs follow the helix; rotary axes
    /// are interpolated linearly, as a controller does in joint space).
    #[must_use]
    pub fn point_at(&self, t: f64) -> Joints {
        let t = t.clamp(0.0, 1.0);
        let lerp = |s: Option<f64>, e: Option<f64>| match (s, e) {
            (Some(s), Some(e)) => Some(s + (e - s) * t),
            (None, Some(e)) => Some(e * t),
            (s, None) => s,
        };
        let xyz = match self.kind {
            MotionKind::Rapid | MotionKind::Linear => self.start.xyz.lerp(self.end.xyz, t),
            MotionKind::ArcCw(a) | MotionKind::ArcCcw(a) => {
                let sign = if matches!(self.kind, MotionKind::ArcCw(_)) {
                    -1.0
                } else {
                    1.0
                };
                let r0 = self.start.xyz - a.centre;
                let r0 = r0 - a.normal * r0.dot(a.normal);
                let angle = sign * a.sweep_rad * t;
                let rotated = r0 * angle.cos() + a.normal.cross(r0) * angle.sin();
                a.centre + rotated + a.normal * (a.helix_mm * t)
            }
        };
        Joints {
            xyz,
            a: lerp(self.start.a, self.end.a),
            b: lerp(self.start.b, self.end.b),
            c: lerp(self.start.c, self.end.c),
        }
    }
}
