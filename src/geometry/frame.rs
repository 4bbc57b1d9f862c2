//! Right-handed orthonormal frames (STEP `AXIS2_PLACEMENT_3D`, OCCT `gp_Ax3` with direct sense).

use super::{DVec3, GeometryError};

/// A placement: origin plus orthonormal axes `x`, `y`, `z` (`z = x × y`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Frame {
    /// Origin in mm.
    pub origin: DVec3,
    /// Unit X axis (the reference direction).
    pub x: DVec3,
    /// Unit Y axis.
    pub y: DVec3,
    /// Unit Z axis (the main axis).
    pub z: DVec3,
}

impl Frame {
    /// The world frame.
    pub const WORLD: Self = Self {
        origin: DVec3::ZERO,
        x: DVec3::X,
        y: DVec3::Y,
        z: DVec3::Z,
    };

    /// Build from an origin, a main axis and an optional reference direction, as STEP does: the
    /// reference direction is projected perpendicular to the axis; when absent or parallel to the
    /// axis, an arbitrary perpendicular is chosen (the same one OCCT's `gp_Ax2(P, V)` picks).
    ///
    /// # Errors
    /// [`GeometryError::ZeroVector`] when the axis has zero length, `NonFinite` on NaN/inf input.
    pub fn from_axis_ref(
        origin: DVec3,
        axis: DVec3,
        ref_dir: Option<DVec3>,
    ) -> Result<Self, GeometryError> {
        if !origin.is_finite() || !axis.is_finite() || ref_dir.is_some_and(|r| !r.is_finite()) {
            return Err(GeometryError::NonFinite("placement".into()));
        }
        let z = axis.try_normalize().ok_or(GeometryError::ZeroVector)?;
        let x = ref_dir
            .and_then(|r| (r - z * r.dot(z)).try_normalize())
            .filter(|x| x.is_finite())
            .unwrap_or_else(|| default_perpendicular(z));
        let y = z.cross(x);
        Ok(Self { origin, x, y, z })
    }

    /// Map local coordinates to world coordinates.
    #[must_use]
    pub fn to_world(&self, local: DVec3) -> DVec3 {
        self.origin + self.x * local.x + self.y * local.y + self.z * local.z
    }

    /// Map a world point to local coordinates.
    #[must_use]
    pub fn to_local(&self, world: DVec3) -> DVec3 {
        let d = world - self.origin;
        DVec3::new(d.dot(self.x), d.dot(self.y), d.dot(self.z))
    }
}

/// OCCT's choice of X direction for `gp_Ax2(P, N)` with no reference: the perpendicular built from
/// the smallest components of N (see `gp_Ax2` constructor).
#[must_use]
pub fn default_perpendicular(n: DVec3) -> DVec3 {
    let (a, b, c) = (n.x, n.y, n.z);
    let (aa, ab, ac) = (a.abs(), b.abs(), c.abs());
    let v = if ab <= aa && ab <= ac {
        if aa > ac {
            DVec3::new(-c, 0.0, a)
        } else {
            DVec3::new(c, 0.0, -a)
        }
    } else if aa <= ab && aa <= ac {
        if ab > ac {
            DVec3::new(0.0, -c, b)
        } else {
            DVec3::new(0.0, c, -b)
        }
    } else if aa > ab {
        DVec3::new(-b, a, 0.0)
    } else {
        DVec3::new(b, -a, 0.0)
    };
    v.normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_and_inverts() {
        let f = Frame::from_axis_ref(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(0.0, 0.0, 2.0),
            Some(DVec3::new(1.0, 1.0, 1.0)),
        )
        .unwrap();
        assert!((f.x.dot(f.z)).abs() < 1e-15);
        assert!((f.x.cross(f.y) - f.z).length() < 1e-15);
        let p = DVec3::new(4.0, -5.0, 6.0);
        assert!((f.to_world(f.to_local(p)) - p).length() < 1e-12);
        assert!(Frame::from_axis_ref(DVec3::ZERO, DVec3::ZERO, None).is_err());
        let g = Frame::from_axis_ref(DVec3::ZERO, DVec3::Z, Some(DVec3::Z)).unwrap();
        assert!((g.x.dot(g.z)).abs() < 1e-15 && (g.x.length() - 1.0).abs() < 1e-15);
        assert!(Frame::from_axis_ref(DVec3::splat(f64::NAN), DVec3::Z, None).is_err());
    }
}
