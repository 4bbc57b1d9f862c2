//! Stock: the raw material, a box or a cylinder, usually the part's bounding box with margins.

use crate::geometry::Aabb;

/// The raw material the part is cut from (mm).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Stock {
    /// No stock defined.
    #[default]
    None,
    /// An axis-aligned box.
    Box {
        /// Minimum corner, mm.
        min_mm: [f64; 3],
        /// Maximum corner, mm.
        max_mm: [f64; 3],
    },
    /// An upright cylinder (axis +Z).
    Cylinder {
        /// Centre of the bottom face, mm.
        base_mm: [f64; 3],
        /// Radius, mm.
        radius_mm: f64,
        /// Height, mm.
        height_mm: f64,
    },
}

/// Margin of the default stock around the part's box on the sides and the top, mm (see
/// [`Stock::or_default_for`]).
pub const DEFAULT_MARGIN_MM: f64 = 2.0;

impl Stock {
    /// This stock, or, when none is defined, the one default every stage uses (roughing clears
    /// it, the simulation starts from it): the part's box (`part_bounds`) grown by
    /// [`DEFAULT_MARGIN_MM`] on the four sides and the top, its bottom flush with the part's
    /// bottom (where the part sits on the fixture: no tool reaches below it).
    #[must_use]
    pub fn or_default_for(&self, part_bounds: &Aabb) -> Self {
        match self {
            Self::None => {
                let m = DEFAULT_MARGIN_MM;
                Self::Box {
                    min_mm: [
                        part_bounds.min.x - m,
                        part_bounds.min.y - m,
                        part_bounds.min.z,
                    ],
                    max_mm: (part_bounds.max + glam::DVec3::splat(m)).to_array(),
                }
            }
            other => *other,
        }
    }

    /// The box around `bounds` grown by `margin_mm` on every side (the top included).
    #[must_use]
    pub fn box_around(bounds: &Aabb, margin_mm: f64) -> Self {
        let m = glam::DVec3::splat(margin_mm);
        Self::Box {
            min_mm: (bounds.min - m).to_array(),
            max_mm: (bounds.max + m).to_array(),
        }
    }

    /// The upright cylinder around `bounds` (its XY corners on the circle plus `margin_mm`), with
    /// `margin_mm` below and above.
    #[must_use]
    pub fn cylinder_around(bounds: &Aabb, margin_mm: f64) -> Self {
        let c = 0.5 * (bounds.min + bounds.max);
        let half = 0.5 * (bounds.max - bounds.min);
        Self::Cylinder {
            base_mm: [c.x, c.y, bounds.min.z - margin_mm],
            radius_mm: half.truncate().length() + margin_mm,
            height_mm: (bounds.max.z - bounds.min.z) + 2.0 * margin_mm,
        }
    }

    /// Check the sizes: finite, min < max, positive radius and height.
    ///
    /// # Errors
    /// What is wrong, in words with units.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            Self::None => Ok(()),
            Self::Box { min_mm, max_mm } => {
                for (axis, (lo, hi)) in ["X", "Y", "Z"].iter().zip(min_mm.iter().zip(max_mm)) {
                    if !(lo.is_finite() && hi.is_finite() && *lo < hi) {
                        return Err(format!(
                            "stock box {axis}: minimum {lo} mm must be below maximum {hi} mm"
                        ));
                    }
                }
                Ok(())
            }
            Self::Cylinder {
                base_mm,
                radius_mm,
                height_mm,
            } => {
                if !base_mm.iter().all(|v| v.is_finite()) {
                    return Err("stock cylinder base must be finite".into());
                }
                if !(radius_mm.is_finite() && radius_mm > 0.0) {
                    return Err(format!(
                        "stock cylinder radius {radius_mm} mm must be positive"
                    ));
                }
                if !(height_mm.is_finite() && height_mm > 0.0) {
                    return Err(format!(
                        "stock cylinder height {height_mm} mm must be positive"
                    ));
                }
                Ok(())
            }
        }
    }
}
