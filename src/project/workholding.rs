//! Workholding: what holds the stock on the table in a setup (a vise, a plate or fixture plate,
//! parallels, a riser, clamps, or any closed STL/STEP body). Each item gives a closed triangle
//! mesh placed in the setup's frame ([`super::setups`]), built around the setup's stock box, so
//! that the collision checks, the simulation and the viewport see the same bodies.

use std::path::{Path, PathBuf};

use glam::{DMat3, DVec3};

use crate::geometry::Aabb;
use crate::geometry::mesh::TriMesh;

/// One workholding item of a setup. Sizes in mm, angles in rad; every item is placed relative
/// to the setup's stock box in the setup frame (X, Y on the table, +Z up the spindle).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Workholding {
    /// A machine vise: two jaws gripping the stock's two faces across the closing axis (X, or
    /// Y with `along_y`), centred on the stock, their tops `grip_mm` above the stock's bottom.
    Vise {
        /// Jaw width (across the closing axis), mm.
        jaw_width_mm: f64,
        /// Jaw height, mm.
        jaw_height_mm: f64,
        /// Jaw thickness (along the closing axis), mm.
        jaw_thickness_mm: f64,
        /// How far the jaws reach up the stock from its bottom, mm.
        grip_mm: f64,
        /// Opening between the jaws, mm (`None`: the stock's size along the closing axis).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        opening_mm: Option<f64>,
        /// The jaws close along Y instead of X.
        #[serde(default)]
        along_y: bool,
    },
    /// A plate (or fixture plate) under the stock, centred on it, its top at the stock's bottom.
    Plate {
        /// Size along X and Y, mm.
        size_mm: [f64; 2],
        /// Thickness, mm.
        thickness_mm: f64,
    },
    /// Two parallels under the stock along X, flush with its front and back faces.
    Parallels {
        /// Height, mm.
        height_mm: f64,
        /// Thickness (along Y), mm.
        thickness_mm: f64,
    },
    /// A riser block under the stock, centred on it, its top at the stock's bottom.
    Riser {
        /// Size along X and Y, mm.
        size_mm: [f64; 2],
        /// Height, mm.
        height_mm: f64,
    },
    /// A strap clamp: a block whose bottom centre sits at `at_mm`, turned about Z.
    Clamp {
        /// Bottom centre of the clamp in the setup frame, mm.
        at_mm: [f64; 3],
        /// Length (along its own X), width and height, mm.
        size_mm: [f64; 3],
        /// Turn about +Z, rad.
        #[serde(default)]
        angle_rad: f64,
    },
    /// Any closed body from an STL or STEP file, in its own coordinates turned about Z by
    /// `angle_rad` then moved by `offset_mm` into the setup frame.
    Body {
        /// The file (relative paths are read from the project's folder).
        path: PathBuf,
        /// Translation into the setup frame, mm.
        #[serde(default)]
        offset_mm: [f64; 3],
        /// Turn about +Z, rad.
        #[serde(default)]
        angle_rad: f64,
    },
}

fn positive(what: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{what} must be a positive number of mm, got {v}"))
    }
}

fn finite(what: &str, v: &[f64]) -> Result<(), String> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(format!("{what} must be finite"))
    }
}

impl Workholding {
    /// The item's kind in words (`vise`, `plate`, …).
    #[must_use]
    pub fn kind_name(&self) -> &'static str {
        match self {
            Self::Vise { .. } => "vise",
            Self::Plate { .. } => "plate",
            Self::Parallels { .. } => "parallels",
            Self::Riser { .. } => "riser",
            Self::Clamp { .. } => "clamp",
            Self::Body { .. } => "body",
        }
    }

    /// Check the values (a body's file is read by [`Workholding::mesh`]).
    ///
    /// # Errors
    /// What is wrong, in words.
    pub fn validate(&self) -> Result<(), String> {
        match self {
            Self::Vise {
                jaw_width_mm,
                jaw_height_mm,
                jaw_thickness_mm,
                grip_mm,
                opening_mm,
                ..
            } => {
                positive("vise: jaw width", *jaw_width_mm)?;
                positive("vise: jaw height", *jaw_height_mm)?;
                positive("vise: jaw thickness", *jaw_thickness_mm)?;
                positive("vise: grip", *grip_mm)?;
                if grip_mm > jaw_height_mm {
                    return Err(format!(
                        "vise: the grip ({grip_mm} mm) is more than the jaw height ({jaw_height_mm} mm)"
                    ));
                }
                if let Some(o) = opening_mm {
                    positive("vise: opening", *o)?;
                }
                Ok(())
            }
            Self::Plate {
                size_mm,
                thickness_mm,
            } => {
                positive("plate: size X", size_mm[0])?;
                positive("plate: size Y", size_mm[1])?;
                positive("plate: thickness", *thickness_mm)
            }
            Self::Parallels {
                height_mm,
                thickness_mm,
            } => {
                positive("parallels: height", *height_mm)?;
                positive("parallels: thickness", *thickness_mm)
            }
            Self::Riser { size_mm, height_mm } => {
                positive("riser: size X", size_mm[0])?;
                positive("riser: size Y", size_mm[1])?;
                positive("riser: height", *height_mm)
            }
            Self::Clamp {
                at_mm,
                size_mm,
                angle_rad,
            } => {
                finite("clamp: position", at_mm)?;
                for (v, n) in size_mm.iter().zip(["length", "width", "height"]) {
                    positive(&format!("clamp: {n}"), *v)?;
                }
                finite("clamp: angle", &[*angle_rad])
            }
            Self::Body {
                path,
                offset_mm,
                angle_rad,
            } => {
                if path.as_os_str().is_empty() {
                    return Err("body: the file path is empty".into());
                }
                finite("body: offset", offset_mm)?;
                finite("body: angle", &[*angle_rad])
            }
        }
    }

    /// The item's closed triangle mesh in the setup frame, placed around `stock` (the setup's
    /// stock box in the setup frame); a body's file is read relative to `base` (the project's
    /// folder).
    ///
    /// # Errors
    /// Bad values, a vise opening narrower than the stock, an empty stock box, or a body file
    /// that cannot be read or is not closed (naming the file).
    pub fn mesh(&self, stock: &Aabb, base: &Path) -> Result<TriMesh, String> {
        self.validate()?;
        if stock.is_empty() && !matches!(self, Self::Clamp { .. } | Self::Body { .. }) {
            return Err(format!(
                "{}: the setup has no stock to place it around",
                self.kind_name()
            ));
        }
        let (lo, hi) = (stock.min, stock.max);
        let c = 0.5 * (lo + hi);
        let mut mesh = TriMesh::default();
        match self {
            Self::Vise {
                jaw_width_mm,
                jaw_height_mm,
                jaw_thickness_mm,
                grip_mm,
                opening_mm,
                along_y,
            } => {
                // Work along the closing axis `a`, the jaw width along `b`.
                let (a, b) = if *along_y { (1, 0) } else { (0, 1) };
                let size = hi[a] - lo[a];
                let opening = opening_mm.unwrap_or(size);
                if opening < size - 1e-9 {
                    return Err(format!(
                        "vise: the opening ({opening} mm) is narrower than the stock ({size} mm)"
                    ));
                }
                let top = lo.z + grip_mm;
                for side in [-1.0, 1.0] {
                    let inner = c[a] + side * 0.5 * opening;
                    let outer = inner + side * jaw_thickness_mm;
                    let mut min = DVec3::ZERO;
                    let mut max = DVec3::ZERO;
                    min[a] = inner.min(outer);
                    max[a] = inner.max(outer);
                    min[b] = c[b] - 0.5 * jaw_width_mm;
                    max[b] = c[b] + 0.5 * jaw_width_mm;
                    min.z = top - jaw_height_mm;
                    max.z = top;
                    mesh.append(&box_mesh(min, max));
                }
            }
            Self::Plate {
                size_mm,
                thickness_mm,
            } => mesh = under(c, lo.z, *size_mm, *thickness_mm),
            Self::Riser { size_mm, height_mm } => mesh = under(c, lo.z, *size_mm, *height_mm),
            Self::Parallels {
                height_mm,
                thickness_mm,
            } => {
                let t = thickness_mm.min(0.5 * (hi.y - lo.y));
                for (y0, y1) in [(lo.y, lo.y + t), (hi.y - t, hi.y)] {
                    mesh.append(&box_mesh(
                        DVec3::new(lo.x, y0, lo.z - height_mm),
                        DVec3::new(hi.x, y1, lo.z),
                    ));
                }
            }
            Self::Clamp {
                at_mm,
                size_mm,
                angle_rad,
            } => {
                let h = DVec3::new(0.5 * size_mm[0], 0.5 * size_mm[1], 0.0);
                let mut m = box_mesh(-h, h + DVec3::Z * size_mm[2]);
                place(&mut m, *angle_rad, DVec3::from_array(*at_mm));
                mesh = m;
            }
            Self::Body {
                path,
                offset_mm,
                angle_rad,
            } => {
                let file = if path.is_absolute() {
                    path.clone()
                } else {
                    base.join(path)
                };
                let wp = crate::import::open(
                    &file,
                    &crate::import::OpenOptions::default(),
                    &crate::diagnostics::Progress::new(),
                )
                .map_err(|e| format!("body: {e}"))?;
                let mut m = wp.mesh;
                if m.triangles.is_empty() || !m.is_closed() {
                    return Err(format!(
                        "body: {}: the mesh is not closed ({} open or shared edges)",
                        file.display(),
                        m.bad_edges().len()
                    ));
                }
                place(&mut m, *angle_rad, DVec3::from_array(*offset_mm));
                mesh = m;
            }
        }
        Ok(mesh)
    }
}

/// A block under the stock: centred on `c` in X and Y, its top at `top`.
fn under(c: DVec3, top: f64, size: [f64; 2], height: f64) -> TriMesh {
    box_mesh(
        DVec3::new(c.x - 0.5 * size[0], c.y - 0.5 * size[1], top - height),
        DVec3::new(c.x + 0.5 * size[0], c.y + 0.5 * size[1], top),
    )
}

/// Turn `mesh` about +Z by `angle` then move it by `offset`.
fn place(mesh: &mut TriMesh, angle: f64, offset: DVec3) {
    let r = DMat3::from_rotation_z(angle);
    for p in &mut mesh.positions {
        *p = r * *p + offset;
    }
    for n in &mut mesh.normals {
        *n = r * *n;
    }
}

/// A closed box, triangles counter-clockwise seen from outside.
#[must_use]
pub fn box_mesh(min: DVec3, max: DVec3) -> TriMesh {
    let corner = |i: u32| {
        DVec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    let positions = (0..8).map(corner).collect();
    // Each face as a quad seen from outside (corners counter-clockwise).
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1], // -Z
        [4, 5, 7, 6], // +Z
        [0, 1, 5, 4], // -Y
        [2, 6, 7, 3], // +Y
        [0, 4, 6, 2], // -X
        [1, 3, 7, 5], // +X
    ];
    let triangles = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    TriMesh::new(positions, triangles)
}

/// All items' meshes of a setup, one per item, in the setup frame.
///
/// # Errors
/// The first item that cannot be built, numbered from 1.
pub fn meshes(items: &[Workholding], stock: &Aabb, base: &Path) -> Result<Vec<TriMesh>, String> {
    items
        .iter()
        .enumerate()
        .map(|(i, w)| {
            w.mesh(stock, base)
                .map_err(|e| format!("workholding {}: {e}", i + 1))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stock() -> Aabb {
        Aabb::from_points(&[DVec3::new(-40.0, -25.0, 0.0), DVec3::new(40.0, 25.0, 30.0)])
    }

    fn vise() -> Workholding {
        Workholding::Vise {
            jaw_width_mm: 150.0,
            jaw_height_mm: 40.0,
            jaw_thickness_mm: 20.0,
            grip_mm: 8.0,
            opening_mm: None,
            along_y: false,
        }
    }

    #[test]
    fn box_is_closed_with_its_volume() {
        let m = box_mesh(DVec3::new(1.0, 2.0, 3.0), DVec3::new(4.0, 7.0, 11.0));
        assert!(m.is_closed());
        // 3 × 5 × 8 mm: positive (outward) orientation.
        assert!((m.signed_volume() - 120.0).abs() < 1e-9);
    }

    #[test]
    fn vise_jaws_touch_the_stock_sides_and_grip_its_bottom() {
        let m = vise().mesh(&stock(), Path::new(".")).unwrap();
        assert!(m.is_closed());
        let b = m.bbox();
        // Jaws from −60 to −40 and 40 to 60 along X, 150 mm wide, top 8 mm above the bottom.
        assert!((b.min.x + 60.0).abs() < 1e-12 && (b.max.x - 60.0).abs() < 1e-12);
        assert!((b.max.y - 75.0).abs() < 1e-12 && (b.min.y + 75.0).abs() < 1e-12);
        assert!((b.max.z - 8.0).abs() < 1e-12 && (b.min.z + 32.0).abs() < 1e-12);
        // Two jaws of 20 × 150 × 40 mm.
        assert!((m.signed_volume() - 2.0 * 20.0 * 150.0 * 40.0).abs() < 1e-6);
        // No jaw point inside the stock.
        let s = stock();
        assert!(
            m.positions
                .iter()
                .all(|p| p.x <= s.min.x + 1e-12 || p.x >= s.max.x - 1e-12)
        );
    }

    #[test]
    fn a_vise_narrower_than_the_stock_is_refused() {
        let mut v = vise();
        if let Workholding::Vise { opening_mm, .. } = &mut v {
            *opening_mm = Some(70.0);
        }
        let e = v.mesh(&stock(), Path::new(".")).unwrap_err();
        assert!(e.contains("narrower than the stock (80 mm)"), "{e}");
    }

    #[test]
    fn plate_parallels_and_clamp_sit_where_said() {
        let s = stock();
        let plate = Workholding::Plate {
            size_mm: [200.0, 100.0],
            thickness_mm: 12.0,
        }
        .mesh(&s, Path::new("."))
        .unwrap();
        let b = plate.bbox();
        assert!((b.max.z).abs() < 1e-12 && (b.min.z + 12.0).abs() < 1e-12);
        assert!((plate.signed_volume() - 200.0 * 100.0 * 12.0).abs() < 1e-6);
        let par = Workholding::Parallels {
            height_mm: 20.0,
            thickness_mm: 5.0,
        }
        .mesh(&s, Path::new("."))
        .unwrap();
        assert!((par.signed_volume() - 2.0 * 80.0 * 5.0 * 20.0).abs() < 1e-6);
        let clamp = Workholding::Clamp {
            at_mm: [10.0, 0.0, 30.0],
            size_mm: [40.0, 10.0, 6.0],
            angle_rad: std::f64::consts::FRAC_PI_2,
        }
        .mesh(&s, Path::new("."))
        .unwrap();
        let b = clamp.bbox();
        // Turned a quarter: 10 mm along X, 40 along Y.
        assert!((b.max.x - b.min.x - 10.0).abs() < 1e-9 && (b.max.y - b.min.y - 40.0).abs() < 1e-9);
        assert!((b.min.z - 30.0).abs() < 1e-12);
    }

    #[test]
    fn bad_values_and_open_bodies_are_named() {
        let v = Workholding::Vise {
            jaw_width_mm: 150.0,
            jaw_height_mm: 5.0,
            jaw_thickness_mm: 20.0,
            grip_mm: 8.0,
            opening_mm: None,
            along_y: false,
        };
        assert!(v.validate().unwrap_err().contains("grip"));
        let body = Workholding::Body {
            path: "no-such-fixture.stl".into(),
            offset_mm: [0.0; 3],
            angle_rad: 0.0,
        };
        let e = body.mesh(&stock(), Path::new("/nonexistent")).unwrap_err();
        assert!(e.contains("no-such-fixture.stl"), "{e}");
    }
}
