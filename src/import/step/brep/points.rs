//! Points, directions, vectors and placements (`CARTESIAN_POINT`, `DIRECTION`, `VECTOR`,
//! `AXIS1_PLACEMENT`, `AXIS2_PLACEMENT_3D`), scaled to mm.

use glam::DVec3;

use super::entities::{Entity, Model};
use super::units::Units;
use super::{BrepError, ErrorKind};
use crate::geometry::frame::Frame;

/// Reads geometry in one representation context.
#[derive(Clone, Copy)]
pub(super) struct Geo<'m, 'a> {
    /// The file.
    pub model: &'m Model<'a>,
    /// The context's units.
    pub units: Units,
}

impl<'a> Geo<'_, 'a> {
    /// The instance `#id` referred to by `from`.
    pub fn entity(&self, from: Entity<'_>, id: u64) -> Result<Entity<'a>, BrepError> {
        self.model.entity(from, id)
    }

    /// A length in file units → mm.
    pub fn length(&self, x: f64) -> f64 {
        x * self.units.length_mm
    }

    /// `CARTESIAN_POINT` `#id` in mm (2D points get z = 0).
    pub fn point(&self, from: Entity<'_>, id: u64) -> Result<DVec3, BrepError> {
        let a = self.model.typed(from, id, "CARTESIAN_POINT")?;
        let e = a.ent;
        let c = a.reals(1, "coordinates")?;
        let v = match c.as_slice() {
            [x, y, z] => DVec3::new(*x, *y, *z),
            [x, y] => DVec3::new(*x, *y, 0.0),
            _ => {
                return Err(e.error(
                    ErrorKind::BadParameter,
                    format!("point has {} coordinates", c.len()),
                ));
            }
        };
        finite(e, v * self.units.length_mm)
    }

    /// `DIRECTION` `#id`, normalised; a zero direction is an error.
    pub fn direction(&self, from: Entity<'_>, id: u64) -> Result<DVec3, BrepError> {
        let a = self.model.typed(from, id, "DIRECTION")?;
        let e = a.ent;
        let c = a.reals(1, "direction ratios")?;
        let v = match c.as_slice() {
            [x, y, z] => DVec3::new(*x, *y, *z),
            [x, y] => DVec3::new(*x, *y, 0.0),
            _ => {
                return Err(e.error(
                    ErrorKind::BadParameter,
                    format!("direction has {} components", c.len()),
                ));
            }
        };
        finite(e, v)?
            .try_normalize()
            .ok_or_else(|| e.error(ErrorKind::InvalidGeometry, "zero-length direction"))
    }

    /// `VECTOR` `#id`: its unit direction (the magnitude only has to be finite and non-zero).
    pub fn vector_dir(&self, from: Entity<'_>, id: u64) -> Result<DVec3, BrepError> {
        let a = self.model.typed(from, id, "VECTOR")?;
        let e = a.ent;
        let dir = self.direction(e, a.reference(1, "orientation")?)?;
        let magnitude = a.real(2, "magnitude")?;
        if magnitude == 0.0 {
            return Err(e.error(ErrorKind::InvalidGeometry, "zero-length vector"));
        }
        Ok(if magnitude < 0.0 { -dir } else { dir })
    }

    /// `AXIS2_PLACEMENT_3D` `#id` as a frame (mm).
    pub fn placement(&self, from: Entity<'_>, id: u64) -> Result<Frame, BrepError> {
        let a = self.model.typed(from, id, "AXIS2_PLACEMENT_3D")?;
        let e = a.ent;
        let origin = self.point(e, a.reference(1, "location")?)?;
        let axis = if a.is_unset(2) {
            DVec3::Z
        } else {
            self.direction(e, a.reference(2, "axis")?)?
        };
        let ref_dir = if a.is_unset(3) {
            None
        } else {
            Some(self.direction(e, a.reference(3, "ref_direction")?)?)
        };
        Frame::from_axis_ref(origin, axis, ref_dir)
            .map_err(|err| e.error(ErrorKind::InvalidGeometry, err.to_string()))
    }

    /// `AXIS1_PLACEMENT` `#id`: a point and a unit axis (default +Z).
    pub fn axis1(&self, from: Entity<'_>, id: u64) -> Result<(DVec3, DVec3), BrepError> {
        let a = self.model.typed(from, id, "AXIS1_PLACEMENT")?;
        let e = a.ent;
        let origin = self.point(e, a.reference(1, "location")?)?;
        let axis = if a.is_unset(2) {
            DVec3::Z
        } else {
            self.direction(e, a.reference(2, "axis")?)?
        };
        Ok((origin, axis))
    }

    /// A positive finite length parameter (radius, semi-axis), mm.
    pub fn positive_length(&self, e: Entity<'_>, x: f64, what: &str) -> Result<f64, BrepError> {
        let mm = self.length(x);
        if mm.is_finite() && mm > 0.0 {
            Ok(mm)
        } else {
            Err(e.error(
                ErrorKind::InvalidGeometry,
                format!("{what} must be positive, got {x}"),
            ))
        }
    }
}

fn finite(e: Entity<'_>, v: DVec3) -> Result<DVec3, BrepError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(e.error(ErrorKind::InvalidGeometry, "non-finite coordinates"))
    }
}
