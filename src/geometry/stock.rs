//! The raw material: the one stock type every stage uses (the project, Z-level roughing, the
//! stock simulation, the force model and the virtual control), its one default around a part
//! ([`Stock::or_default_for`]) and the one text syntax of every `--stock` option
//! ([`StockSpec::parse`]).

use std::path::PathBuf;

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

    /// The upright cylinder of the default stock around `bounds`: its circle through the box's
    /// XY corners grown by [`DEFAULT_MARGIN_MM`], its bottom flush with the part's bottom, its
    /// top [`DEFAULT_MARGIN_MM`] above the part (as the default box).
    #[must_use]
    pub fn default_cylinder_for(bounds: &Aabb) -> Self {
        let m = DEFAULT_MARGIN_MM;
        let c = 0.5 * (bounds.min + bounds.max);
        let half = 0.5 * (bounds.max - bounds.min);
        Self::Cylinder {
            base_mm: [c.x, c.y, bounds.min.z],
            radius_mm: half.truncate().length() + m,
            height_mm: (bounds.max.z - bounds.min.z) + m,
        }
    }

    /// The stock's bounding box, mm (`None` for [`Stock::None`]).
    #[must_use]
    pub fn bounds(&self) -> Option<Aabb> {
        match *self {
            Self::None => None,
            Self::Box { min_mm, max_mm } => Some(Aabb {
                min: min_mm.into(),
                max: max_mm.into(),
            }),
            Self::Cylinder {
                base_mm,
                radius_mm,
                height_mm,
            } => {
                let base = glam::DVec3::from(base_mm);
                let r = glam::DVec3::new(radius_mm, radius_mm, 0.0);
                Some(Aabb {
                    min: base - r,
                    max: base + r + glam::DVec3::new(0.0, 0.0, height_mm),
                })
            }
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

/// A stock as given on a command line: a shape, or a closed STL mesh the caller reads.
#[derive(Clone, Debug, PartialEq)]
pub enum StockSpec {
    /// A box or an upright cylinder (already sized; never [`Stock::None`]).
    Shape(Stock),
    /// A closed triangle mesh in an STL file (the material is its inside).
    Mesh(PathBuf),
}

/// The syntax [`StockSpec::parse`] reads, for help texts and error messages.
pub const STOCK_SYNTAX: &str = "box (the default stock around the part: its box plus 2 mm on the \
     sides and the top), box:X0,Y0,Z0,X1,Y1,Z1, cylinder (the default cylinder around the part), \
     cylinder:CX,CY,R,Z0,Z1 or mesh:FILE.stl (mm)";

impl StockSpec {
    /// Read a `--stock` text: `box`, `box:X0,Y0,Z0,X1,Y1,Z1`, `cylinder`,
    /// `cylinder:CX,CY,R,Z0,Z1` (centre, radius, bottom and top) or `mesh:FILE.stl`, all mm.
    /// The bare `box` and `cylinder` are the default stock around `part` (the part's bounds),
    /// which they need. Corners and heights may come in either order.
    ///
    /// # Errors
    /// What is wrong, in words, naming the text.
    pub fn parse(spec: &str, part: Option<&Aabb>) -> Result<Self, String> {
        let spec = spec.trim();
        let (kind, rest) = spec.split_once(':').unwrap_or((spec, ""));
        let kind = kind.trim().to_ascii_lowercase();
        if kind == "mesh" {
            let path = rest.trim();
            if path.is_empty() {
                return Err(format!("stock '{spec}': mesh needs a file, mesh:FILE.stl"));
            }
            return Ok(Self::Mesh(PathBuf::from(path)));
        }
        let nums: Vec<f64> = if rest.trim().is_empty() {
            Vec::new()
        } else {
            rest.split(',')
                .map(|v| {
                    v.trim()
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| format!("stock '{spec}': '{}' is not a number", v.trim()))
                })
                .collect::<Result<_, _>>()?
        };
        let around = |what: &str| {
            part.copied().ok_or_else(|| {
                format!("stock '{spec}': the default {what} needs a part to size it around; give the sizes ({STOCK_SYNTAX})")
            })
        };
        let stock = match (kind.as_str(), nums.as_slice()) {
            ("box", []) => Stock::None.or_default_for(&around("box")?),
            ("box", [x0, y0, z0, x1, y1, z1]) => Stock::Box {
                min_mm: [x0.min(*x1), y0.min(*y1), z0.min(*z1)],
                max_mm: [x0.max(*x1), y0.max(*y1), z0.max(*z1)],
            },
            ("cylinder", []) => Stock::default_cylinder_for(&around("cylinder")?),
            ("cylinder", [cx, cy, r, z0, z1]) => Stock::Cylinder {
                base_mm: [*cx, *cy, z0.min(*z1)],
                radius_mm: *r,
                height_mm: (z1 - z0).abs(),
            },
            ("box", _) => {
                return Err(format!(
                    "stock '{spec}': a box needs six numbers X0,Y0,Z0,X1,Y1,Z1 (mm)"
                ));
            }
            ("cylinder", _) => {
                return Err(format!(
                    "stock '{spec}': a cylinder needs five numbers CX,CY,R,Z0,Z1 (centre, radius, bottom and top, mm)"
                ));
            }
            (other, _) => {
                return Err(format!(
                    "stock '{spec}': unknown kind '{other}'; write {STOCK_SYNTAX}"
                ));
            }
        };
        stock
            .validate()
            .map_err(|e| format!("stock '{spec}': {e}"))?;
        Ok(Self::Shape(stock))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn part() -> Aabb {
        Aabb {
            min: DVec3::new(0.0, 0.0, 0.0),
            max: DVec3::new(30.0, 40.0, 10.0),
        }
    }

    #[test]
    fn one_syntax_reads_every_kind() {
        let p = part();
        let shape = |s: &str| match StockSpec::parse(s, Some(&p)).unwrap() {
            StockSpec::Shape(s) => s,
            StockSpec::Mesh(_) => panic!("not a shape"),
        };
        assert_eq!(
            shape("box"),
            Stock::Box {
                min_mm: [-2.0, -2.0, 0.0],
                max_mm: [32.0, 42.0, 12.0]
            }
        );
        assert_eq!(
            shape(" Box : 1,2,3, 0,0,0 "),
            Stock::Box {
                min_mm: [0.0, 0.0, 0.0],
                max_mm: [1.0, 2.0, 3.0]
            }
        );
        // The circle through the corners (radius 25) plus the margin; bottom flush.
        assert_eq!(
            shape("cylinder"),
            Stock::Cylinder {
                base_mm: [15.0, 20.0, 0.0],
                radius_mm: 27.0,
                height_mm: 12.0
            }
        );
        assert_eq!(
            shape("cylinder:0,0,10,5,-1"),
            Stock::Cylinder {
                base_mm: [0.0, 0.0, -1.0],
                radius_mm: 10.0,
                height_mm: 6.0
            }
        );
        assert_eq!(
            StockSpec::parse("mesh:blank.stl", None).unwrap(),
            StockSpec::Mesh(PathBuf::from("blank.stl"))
        );
        let b = shape("cylinder:0,0,10,-1,5").bounds().unwrap();
        assert_eq!((b.min.z, b.max.z, b.max.x), (-1.0, 5.0, 10.0));
    }

    #[test]
    fn bad_stocks_are_refused_with_the_reason() {
        let p = part();
        for (spec, says) in [
            ("box:1,2,3", "six numbers"),
            ("cylinder:0,0,-1,0,5", "radius"),
            ("box:0,0,0,1,1,nan", "not a number"),
            ("box:0,0,0,1,1,0", "below maximum"),
            ("cone", "unknown kind 'cone'"),
            ("cyl:0,0,0,5,10", "unknown kind 'cyl'"),
            ("mesh:", "needs a file"),
        ] {
            let e = StockSpec::parse(spec, Some(&p)).unwrap_err();
            assert!(e.contains(says), "{spec}: {e}");
        }
        let e = StockSpec::parse("box", None).unwrap_err();
        assert!(e.contains("needs a part"), "{e}");
    }
}
