//! The machine file (serde) and its validation into a [`Machine`].

use glam::DVec3;

use super::{KinematicsKind, Machine, MachineError};

/// One axis as written in a file (linear: mm, mm/s, mm/s², mm/s³; rotary: deg, deg/s, ...).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisFile {
    /// `X`, `Y`, `Z`, `A`, `B` or `C`.
    pub name: char,
    /// Lower travel limit.
    pub min: f64,
    /// Upper travel limit.
    pub max: f64,
    /// Velocity limit (per s).
    pub velocity: f64,
    /// Acceleration limit (per s²).
    pub acceleration: f64,
    /// Jerk limit (per s³).
    pub jerk: f64,
    /// Rotary axes: +1 when a positive joint angle turns the table positively (right hand)
    /// about its axis, −1 for the ISO table convention (the part turns opposite to the
    /// tool's nominal rotation). Ignored for linear axes.
    #[serde(default = "one")]
    pub direction: f64,
}

fn one() -> f64 {
    1.0
}

/// Simple geometry for pictures of the machine (mm).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Drawing {
    /// Rotary table (or fixed table) diameter.
    pub table_diameter_mm: f64,
    /// Table thickness.
    pub table_thickness_mm: f64,
    /// Trunnion (tilting cradle) width along the tilt axis; 0 for none.
    #[serde(default)]
    pub trunnion_width_mm: f64,
}

impl Default for Drawing {
    fn default() -> Self {
        Self {
            table_diameter_mm: 400.0,
            table_thickness_mm: 40.0,
            trunnion_width_mm: 0.0,
        }
    }
}

/// A machine file as written.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MachineFile {
    /// Short name.
    pub name: String,
    /// One line for people.
    #[serde(default)]
    pub description: String,
    /// `xyz`, `xyzac-trt` or `xyzbc-trt`.
    pub kinematics: KinematicsKind,
    /// The axes.
    pub axes: Vec<AxisFile>,
    /// C-axis centre (mm), machine coordinates.
    #[serde(default)]
    pub rot_point_mm: [f64; 3],
    /// From the C-axis centre to the tilt axis (mm).
    #[serde(default)]
    pub tilt_offset_mm: [f64; 3],
    /// Drawing geometry.
    #[serde(default)]
    pub drawing: Drawing,
    /// Solid bodies and which axes carry them (optional).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub structure: Option<super::StructureFile>,
    /// Rated spindle power, W (optional: the cutting-force model flags moves above it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spindle_power_w: Option<f64>,
    /// Homing order: every axis letter once, first homed first (`"ZXY"`, `"ZYXAC"`); optional,
    /// the control's default (Z, the other linear axes, the rotaries) when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub home_order: Option<String>,
}

/// A validated axis in internal units (mm or rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    /// Name letter.
    pub name: char,
    /// Lower limit (mm or rad).
    pub min: f64,
    /// Upper limit (mm or rad).
    pub max: f64,
    /// Velocity limit (mm/s or rad/s).
    pub velocity: f64,
    /// Acceleration limit (mm/s² or rad/s²).
    pub acceleration: f64,
    /// Jerk limit (mm/s³ or rad/s³).
    pub jerk: f64,
    /// +1 or −1 (rotary axes; +1 for linear ones).
    pub direction: f64,
}

impl Axis {
    /// Is `v` within the travel (with a tolerance of 1e-9 of the unit)?
    #[must_use]
    pub fn contains(&self, v: f64) -> bool {
        v >= self.min - 1e-9 && v <= self.max + 1e-9
    }

    /// Is this a rotary axis?
    #[must_use]
    pub fn is_rotary(&self) -> bool {
        matches!(self.name, 'A' | 'B' | 'C')
    }
}

impl MachineFile {
    /// Check the definition and convert to internal units.
    ///
    /// # Errors
    /// [`MachineError::Invalid`] naming the problem.
    pub fn validate(&self) -> Result<Machine, MachineError> {
        let bad = |m: String| Err(MachineError::Invalid(format!("{}: {m}", self.name)));
        let wanted: &[char] = match self.kinematics {
            KinematicsKind::ThreeAxis => &['X', 'Y', 'Z'],
            KinematicsKind::TableAc => &['X', 'Y', 'Z', 'A', 'C'],
            KinematicsKind::TableBc => &['X', 'Y', 'Z', 'B', 'C'],
        };
        let mut axes = Vec::new();
        for &name in wanted {
            let found: Vec<&AxisFile> = self.axes.iter().filter(|a| a.name == name).collect();
            let [a] = found.as_slice() else {
                return bad(format!(
                    "needs exactly one axis {name}, found {}",
                    found.len()
                ));
            };
            let nums = [
                a.min,
                a.max,
                a.velocity,
                a.acceleration,
                a.jerk,
                a.direction,
            ];
            if nums.iter().any(|v| !v.is_finite()) {
                return bad(format!("axis {name} has a non-finite number"));
            }
            if !(a.min <= a.max) {
                return bad(format!("axis {name}: min {} > max {}", a.min, a.max));
            }
            if !(a.velocity > 0.0 && a.acceleration > 0.0 && a.jerk > 0.0) {
                return bad(format!(
                    "axis {name}: velocity, acceleration and jerk must be positive"
                ));
            }
            if a.direction != 1.0 && a.direction != -1.0 {
                return bad(format!("axis {name}: direction must be 1 or -1"));
            }
            let k = if matches!(name, 'A' | 'B' | 'C') {
                1f64.to_radians()
            } else {
                1.0
            };
            axes.push(Axis {
                name,
                min: a.min * k,
                max: a.max * k,
                velocity: a.velocity * k,
                acceleration: a.acceleration * k,
                jerk: a.jerk * k,
                direction: a.direction,
            });
        }
        if let Some(extra) = self.axes.iter().find(|a| !wanted.contains(&a.name)) {
            return bad(format!(
                "axis {} does not belong to {:?} kinematics",
                extra.name, self.kinematics
            ));
        }
        let rot = DVec3::from_array(self.rot_point_mm);
        let off = DVec3::from_array(self.tilt_offset_mm);
        if !rot.is_finite() || !off.is_finite() {
            return bad("pivot parameters must be finite".into());
        }
        if let Some(p) = self.spindle_power_w
            && !(p.is_finite() && p > 0.0 && p <= 1e7)
        {
            return bad(format!(
                "spindle_power_w must be above 0 and at most 1e7 W, got {p}"
            ));
        }
        let mut machine = Machine {
            name: self.name.clone(),
            description: self.description.clone(),
            kinematics: self.kinematics,
            axes,
            rot_point_mm: rot,
            tilt_offset_mm: off,
            drawing: self.drawing.clone(),
            spindle_power_w: self.spindle_power_w,
            structure: None,
            home_order: Vec::new(),
        };
        if let Some(order) = &self.home_order {
            machine.home_order = validate_home_order(order, &machine)
                .map_err(|m| MachineError::Invalid(format!("{}: {m}", self.name)))?;
        }
        if let Some(s) = &self.structure {
            machine.structure = Some(
                s.validate(&machine)
                    .map_err(|m| super::bodies::structure_error(&self.name, &m))?,
            );
        }
        Ok(machine)
    }
}

/// The homing order of a file: each axis of the machine exactly once.
fn validate_home_order(order: &str, machine: &Machine) -> Result<Vec<char>, String> {
    let letters: Vec<char> = order.chars().filter(|c| !c.is_whitespace()).collect();
    for (i, c) in letters.iter().enumerate() {
        if machine.axis(*c).is_none() {
            return Err(format!(
                "home_order \"{order}\": {c} is not an axis of the machine"
            ));
        }
        if letters[..i].contains(c) {
            return Err(format!("home_order \"{order}\": axis {c} is named twice"));
        }
    }
    if let Some(missing) = machine.axes.iter().find(|a| !letters.contains(&a.name)) {
        return Err(format!(
            "home_order \"{order}\" leaves out axis {}",
            missing.name
        ));
    }
    Ok(letters)
}
