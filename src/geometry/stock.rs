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

    /// The upright cylinder around `points` (a part's mesh vertices, mm): the smallest circle
    /// that holds their XY projections grown by `margin_mm`, its bottom flush with the lowest
    /// point and its top `margin_mm` above the highest (as the default box: the part sits on
    /// its bottom). `None` without a finite point.
    #[must_use]
    pub fn cylinder_enclosing(points: &[glam::DVec3], margin_mm: f64) -> Option<Self> {
        let finite: Vec<glam::DVec3> = points.iter().copied().filter(|p| p.is_finite()).collect();
        let xy: Vec<glam::DVec2> = finite.iter().map(|p| p.truncate()).collect();
        let (centre, radius) = smallest_enclosing_circle(&xy)?;
        let (lo, hi) = finite
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.z), hi.max(p.z))
            });
        Some(Self::Cylinder {
            base_mm: [centre.x, centre.y, lo],
            radius_mm: radius + margin_mm,
            height_mm: (hi - lo) + margin_mm,
        })
    }

    /// Check the sizes: finite, min < max, positive radius and height.
    ///
    /// # Errors
    /// What is wrong, in words with units.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            Self::None => Ok(()),
            Self::Box { min_mm, max_mm } => {
                let far = crate::units::MAX_COORDINATE_MM;
                for (axis, (lo, hi)) in ["X", "Y", "Z"].iter().zip(min_mm.iter().zip(max_mm)) {
                    if !(lo.is_finite() && hi.is_finite() && *lo < hi) {
                        return Err(format!(
                            "stock box {axis}: minimum {lo} mm must be below maximum {hi} mm"
                        ));
                    }
                    if lo.abs() > far || hi.abs() > far {
                        return Err(format!(
                            "stock box {axis}: {lo}..{hi} mm must lie within ±{far} mm"
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
                let far = crate::units::MAX_COORDINATE_MM;
                if !base_mm.iter().all(|v| v.is_finite() && v.abs() <= far) {
                    return Err(format!("stock cylinder base must lie within ±{far} mm"));
                }
                if !(radius_mm.is_finite() && radius_mm > 0.0 && radius_mm <= far) {
                    return Err(format!(
                        "stock cylinder radius {radius_mm} mm must be positive, at most {far} mm"
                    ));
                }
                if !(height_mm.is_finite() && height_mm > 0.0 && height_mm <= 2.0 * far) {
                    return Err(format!(
                        "stock cylinder height {height_mm} mm must be positive, at most {} mm",
                        2.0 * far
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

/// The smallest circle holding every point (centre, radius), by Welzl's algorithm in its
/// iterative form (expected linear time) over the points in a fixed pseudo-random order, so the
/// result does not depend on the input order's worst case and is the same on every run.
/// `None` for no points. Written here: it is some 40 lines, and the crates that offer it are
/// small and unmaintained (see ARCHITECTURE.md).
#[must_use]
pub fn smallest_enclosing_circle(points: &[glam::DVec2]) -> Option<(glam::DVec2, f64)> {
    use glam::DVec2;
    let first = *points.first()?;
    let mut pts: Vec<DVec2> = points.to_vec();
    // Fisher–Yates with a fixed 64-bit LCG: deterministic, and no adversarial order.
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    for i in (1..pts.len()).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let j = ((state >> 33) % (i as u64 + 1)) as usize;
        pts.swap(i, j);
    }
    // Points within this relative slack of the circle count as inside (rounding).
    let inside = |c: DVec2, r: f64, p: DVec2| p.distance(c) <= r * (1.0 + 1e-12) + 1e-12;
    let two = |a: DVec2, b: DVec2| (0.5 * (a + b), 0.5 * a.distance(b));
    let three = |a: DVec2, b: DVec2, c: DVec2| {
        let (ab, ac) = (b - a, c - a);
        let d = 2.0 * ab.perp_dot(ac);
        if d.abs() <= 1e-18 * ab.length_squared().max(ac.length_squared()).max(1e-300) {
            // Collinear: the circle on the two farthest apart.
            let cands = [two(a, b), two(a, c), two(b, c)];
            return cands
                .into_iter()
                .fold((a, -1.0), |best, c| if c.1 > best.1 { c } else { best });
        }
        let o = DVec2::new(
            ac.y * ab.length_squared() - ab.y * ac.length_squared(),
            ab.x * ac.length_squared() - ac.x * ab.length_squared(),
        ) / d;
        (a + o, o.length())
    };
    let (mut c, mut r) = (first, 0.0);
    for i in 0..pts.len() {
        if inside(c, r, pts[i]) {
            continue;
        }
        (c, r) = (pts[i], 0.0);
        for j in 0..i {
            if inside(c, r, pts[j]) {
                continue;
            }
            (c, r) = two(pts[i], pts[j]);
            for k in 0..j {
                if !inside(c, r, pts[k]) {
                    (c, r) = three(pts[i], pts[j], pts[k]);
                }
            }
        }
    }
    Some((c, r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    /// The smallest circle against brute force: the least circle through two or three of the
    /// points that holds them all, on seeded random sets (clustered, on a circle, collinear).
    #[test]
    fn smallest_circle_is_the_least_of_all_circles_through_two_or_three_points() {
        let mut state: u64 = 7;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..60 {
            let n = 3 + case % 10;
            let pts: Vec<DVec2> = (0..n)
                .map(|_| match case % 3 {
                    0 => DVec2::new(next() * 50.0 - 20.0, next() * 30.0 + 5.0),
                    1 => {
                        let a = next() * std::f64::consts::TAU;
                        DVec2::new(3.0 + 40.0 * a.cos(), -7.0 + 40.0 * a.sin())
                    }
                    _ => {
                        let t = next();
                        DVec2::new(10.0 * t, 4.0 * t - 1.0)
                    }
                })
                .collect();
            let holds = |c: DVec2, r: f64| pts.iter().all(|p| p.distance(c) <= r + 1e-9);
            let mut best = f64::INFINITY;
            for i in 0..n {
                for j in i + 1..n {
                    let (c, r) = (0.5 * (pts[i] + pts[j]), 0.5 * pts[i].distance(pts[j]));
                    if holds(c, r) {
                        best = best.min(r);
                    }
                    for k in j + 1..n {
                        let (a, b, q) = (pts[i], pts[j], pts[k]);
                        let (ab, aq) = (b - a, q - a);
                        let d = 2.0 * ab.perp_dot(aq);
                        if d.abs() < 1e-9 {
                            continue;
                        }
                        let o = DVec2::new(
                            aq.y * ab.length_squared() - ab.y * aq.length_squared(),
                            ab.x * aq.length_squared() - aq.x * ab.length_squared(),
                        ) / d;
                        if holds(a + o, o.length()) {
                            best = best.min(o.length());
                        }
                    }
                }
            }
            let (c, r) = smallest_enclosing_circle(&pts).unwrap();
            assert!(holds(c, r), "case {case}: a point lies outside");
            assert!(
                (r - best).abs() < 1e-7,
                "case {case}: {r} vs brute force {best}"
            );
        }
        assert_eq!(smallest_enclosing_circle(&[]), None);
        let one = DVec2::new(1.0, 2.0);
        assert_eq!(smallest_enclosing_circle(&[one]), Some((one, 0.0)));
    }

    /// "Cylinder around part" on an Ø80 part is Ø80 + 2·margin, not the circle through its
    /// bounding box's corners (Ø117.1 for Ø80 + 2 mm), bottom flush, top + margin.
    #[test]
    fn cylinder_around_a_round_part_fits_the_part_not_its_box() {
        let pts: Vec<DVec3> = (0..360)
            .flat_map(|i| {
                let a = (i as f64).to_radians();
                let p = DVec3::new(12.0 + 40.0 * a.cos(), -5.0 + 40.0 * a.sin(), 0.0);
                [p, p + DVec3::Z * 25.0]
            })
            .collect();
        let Some(Stock::Cylinder {
            base_mm,
            radius_mm,
            height_mm,
        }) = Stock::cylinder_enclosing(&pts, 2.0)
        else {
            panic!("a cylinder");
        };
        assert!((radius_mm - 42.0).abs() < 1e-9, "{radius_mm}");
        assert!((base_mm[0] - 12.0).abs() < 1e-9 && (base_mm[1] + 5.0).abs() < 1e-9);
        assert!(base_mm[2].abs() < 1e-12 && (height_mm - 27.0).abs() < 1e-12);
        let bounds = Aabb {
            min: DVec3::new(-28.0, -45.0, 0.0),
            max: DVec3::new(52.0, 35.0, 25.0),
        };
        let Stock::Cylinder { radius_mm: old, .. } = Stock::cylinder_around(&bounds, 2.0) else {
            panic!("a cylinder");
        };
        assert!(
            (2.0 * old - 117.137).abs() < 1e-3,
            "the box rule gives {}",
            2.0 * old
        );
        assert_eq!(Stock::cylinder_enclosing(&[DVec3::NAN], 2.0), None);
    }

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
