//! Units of a geometric representation context: the length unit (to mm) and the plane angle unit
//! (to rad), read from `GLOBAL_UNIT_ASSIGNED_CONTEXT`.

use super::entities::{Entity, Model, untyped};
use super::{BrepError, ErrorKind};
use crate::import::step::part21::Param;

/// Deepest chain of `CONVERSION_BASED_UNIT`s followed.
const MAX_UNIT_DEPTH: usize = 8;

/// Scale factors from file units to Talas units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Units {
    /// Millimetres per file length unit.
    pub length_mm: f64,
    /// Radians per file plane angle unit.
    pub angle_rad: f64,
}

impl Units {
    /// Millimetres and radians (no scaling).
    pub const MM_RAD: Self = Self {
        length_mm: 1.0,
        angle_rad: 1.0,
    };
}

/// What reading a context found.
pub(super) struct ContextUnits {
    /// The units.
    pub units: Units,
    /// Set when no length unit was declared (mm assumed).
    pub missing_length: bool,
}

/// The units of the representation context `#ctx`.
pub(super) fn context_units(model: &Model<'_>, ctx: Entity<'_>) -> Result<ContextUnits, BrepError> {
    let mut out = ContextUnits {
        units: Units::MM_RAD,
        missing_length: true,
    };
    let Some(rec) = ctx.record("GLOBAL_UNIT_ASSIGNED_CONTEXT") else {
        return Ok(out);
    };
    let Some(Param::List(units)) = rec.params.first().map(untyped) else {
        return Err(ctx.error(
            ErrorKind::BadParameter,
            "GLOBAL_UNIT_ASSIGNED_CONTEXT units: expected a list",
        ));
    };
    for p in units {
        let Param::Ref(id) = untyped(p) else { continue };
        let unit = model.entity(ctx, *id)?;
        if unit.has("LENGTH_UNIT") {
            out.units.length_mm = unit_size(model, unit, "METRE", 1000.0, 0)?;
            out.missing_length = false;
        } else if unit.has("PLANE_ANGLE_UNIT") {
            out.units.angle_rad = unit_size(model, unit, "RADIAN", 1.0, 0)?;
        }
    }
    Ok(out)
}

/// Size of `unit` in Talas units, where the SI base `si_name` is worth `si_size`.
fn unit_size(
    model: &Model<'_>,
    unit: Entity<'_>,
    si_name: &str,
    si_size: f64,
    depth: usize,
) -> Result<f64, BrepError> {
    if depth > MAX_UNIT_DEPTH {
        return Err(unit.error(
            ErrorKind::Cycle,
            "unit definitions nest too deeply (cycle?)",
        ));
    }
    if let Some(si) = unit.record("SI_UNIT") {
        let prefix = match si.params.first().map(untyped) {
            Some(Param::Enum(p)) => si_prefix(p).ok_or_else(|| {
                unit.error(ErrorKind::BadParameter, format!("unknown SI prefix .{p}."))
            })?,
            _ => 1.0,
        };
        return match si.params.get(1).map(untyped) {
            Some(Param::Enum(n)) if n == si_name => Ok(prefix * si_size),
            Some(Param::Enum(n)) => Err(unit.error(
                ErrorKind::BadParameter,
                format!("unit .{n}. is not a {si_name}-based unit"),
            )),
            _ => Err(unit.error(
                ErrorKind::BadParameter,
                "SI_UNIT name: expected an enumeration value",
            )),
        };
    }
    if let Some(conv) = unit.record("CONVERSION_BASED_UNIT") {
        let measure = match conv.params.get(1).map(untyped) {
            Some(Param::Ref(id)) => model.entity(unit, *id)?,
            _ => {
                return Err(unit.error(
                    ErrorKind::BadParameter,
                    "CONVERSION_BASED_UNIT: expected a measure reference",
                ));
            }
        };
        // LENGTH_MEASURE_WITH_UNIT / PLANE_ANGLE_MEASURE_WITH_UNIT / MEASURE_WITH_UNIT(value, unit)
        let rec = measure
            .inst
            .records
            .iter()
            .find(|r| r.name.ends_with("MEASURE_WITH_UNIT"))
            .ok_or_else(|| {
                measure.error(
                    ErrorKind::WrongType,
                    format!(
                        "expected a MEASURE_WITH_UNIT, found {}",
                        measure.type_name()
                    ),
                )
            })?;
        let value = rec
            .params
            .first()
            .and_then(super::entities::param_real)
            .ok_or_else(|| {
                measure.error(
                    ErrorKind::BadParameter,
                    "measure value: expected a finite number",
                )
            })?;
        let base = match rec.params.get(1).map(untyped) {
            Some(Param::Ref(id)) => model.entity(measure, *id)?,
            _ => {
                return Err(measure.error(
                    ErrorKind::BadParameter,
                    "measure unit: expected a reference",
                ));
            }
        };
        let size = value * unit_size(model, base, si_name, si_size, depth + 1)?;
        return if size.is_finite() && size > 0.0 {
            Ok(size)
        } else {
            Err(unit.error(
                ErrorKind::InvalidGeometry,
                "unit conversion factor must be positive",
            ))
        };
    }
    Err(unit.error(
        ErrorKind::WrongType,
        format!(
            "expected SI_UNIT or CONVERSION_BASED_UNIT, found {}",
            unit.type_name()
        ),
    ))
}

fn si_prefix(p: &str) -> Option<f64> {
    Some(match p {
        "EXA" => 1e18,
        "PETA" => 1e15,
        "TERA" => 1e12,
        "GIGA" => 1e9,
        "MEGA" => 1e6,
        "KILO" => 1e3,
        "HECTO" => 1e2,
        "DECA" => 1e1,
        "DECI" => 1e-1,
        "CENTI" => 1e-2,
        "MILLI" => 1e-3,
        "MICRO" => 1e-6,
        "NANO" => 1e-9,
        "PICO" => 1e-12,
        "FEMTO" => 1e-15,
        "ATTO" => 1e-18,
        _ => return None,
    })
}
