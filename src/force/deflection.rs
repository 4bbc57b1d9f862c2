//! Static deflection of the tool and the wall (form) error it leaves (thesis §6.2.1).
//!
//! The tool is a cantilever clamped at the holder face, `overhang` above the tip, with a
//! stepped section: the fluted part as a round bar of an equivalent diameter (by default
//! 0.8·D, the common rule for two- to four-flute end mills) and the shank above it. The
//! deflection at height z_s under a load W at height z_m (both from the tip) comes from the
//! unit-load method, `δ = W·∫_{max(z_s,z_m)}^{L} (z − z_m)(z − z_s) / EI(z) dz`, exact per
//! segment; for a uniform beam it is the textbook `W·u_m²(3u_s − u_m)/(6EI)` (u measured from
//! the clamp). Forces are the rigid tool's (no feedback into the chip thickness), applied per
//! disk at the disk's mid-height.
//!
//! The wall is generated where the edge passes φ = 0 (up milling) or φ = π (down milling). At
//! the rotation where a flute's edge point at height z_s passes that angle, the wall error is
//! the tool's y-deflection there projected on the wall normal from material to air (−y for up
//! milling, +y for down milling): up milling overcuts (negative), down milling undercuts
//! (positive), as in Table 8.8. With several flutes the wall keeps the deepest pass.

use std::f64::consts::PI;

use super::closed_form::Load;
use super::cut::{Engagement, Mode};
use super::disks::DiskForces;
use super::mill::EndMill;
use super::{Coefficients, ForceError};

/// Young's modulus of cemented carbide assumed by default, N/mm² (600 GPa; handbooks give
/// 550–650 GPa).
pub const CARBIDE_E: f64 = 600_000.0;

/// Equivalent diameter of the fluted section over the tool diameter, assumed by default.
pub const FLUTE_DIAMETER_RATIO: f64 = 0.8;

/// A stepped cantilever: segments from the tip up, each with its bending stiffness EI.
#[derive(Clone, Debug, PartialEq)]
pub struct Cantilever {
    /// Gauge length from the tip to the clamp, mm.
    pub length: f64,
    /// `(top of the segment above the tip in mm, EI in N·mm²)`, from the tip up; the last
    /// segment ends at `length`.
    pub segments: Vec<(f64, f64)>,
}

/// The beam of an end mill.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamSpec {
    /// Tool diameter, mm.
    pub diameter: f64,
    /// Fluted length from the tip, mm.
    pub flute_length: f64,
    /// Shank diameter, mm.
    pub shank_diameter: f64,
    /// Overhang: tip to holder face, mm.
    pub overhang: f64,
    /// Young's modulus, N/mm².
    pub youngs_modulus: f64,
    /// Equivalent diameter of the fluted section over the tool diameter.
    pub flute_diameter_ratio: f64,
}

impl Cantilever {
    /// The cantilever of an end mill.
    ///
    /// # Errors
    /// [`ForceError::Input`] for sizes that are not positive, an overhang above 2000 mm, a
    /// modulus outside [1 000, 2 000 000] N/mm² or a diameter ratio outside (0.3, 1].
    pub fn end_mill(spec: &BeamSpec) -> Result<Self, ForceError> {
        use super::check_range;
        check_range("overhang", spec.overhang, 1e-3, 2000.0, "mm")?;
        check_range("tool diameter", spec.diameter, 1e-3, 1000.0, "mm")?;
        check_range("flute length", spec.flute_length, 1e-3, 2000.0, "mm")?;
        check_range("shank diameter", spec.shank_diameter, 1e-3, 1000.0, "mm")?;
        check_range("Young's modulus", spec.youngs_modulus, 1e3, 2e6, "N/mm²")?;
        check_range(
            "flute diameter ratio",
            spec.flute_diameter_ratio,
            0.3,
            1.0,
            "",
        )?;
        let ei = |d: f64| spec.youngs_modulus * PI * d.powi(4) / 64.0;
        let flute_top = spec.flute_length.min(spec.overhang);
        let mut segments = vec![(flute_top, ei(spec.flute_diameter_ratio * spec.diameter))];
        if flute_top < spec.overhang {
            segments.push((spec.overhang, ei(spec.shank_diameter)));
        }
        Ok(Self {
            length: spec.overhang,
            segments,
        })
    }

    /// Deflection at height `zs` per unit load at height `zm` (both above the tip), mm/N.
    #[must_use]
    pub fn influence(&self, zs: f64, zm: f64) -> f64 {
        let lo = zs.max(zm);
        let prim = |z: f64| z * z * z / 3.0 - 0.5 * (zm + zs) * z * z + zm * zs * z;
        let mut bottom = 0.0_f64;
        let mut total = 0.0;
        for &(top, ei) in &self.segments {
            let (a, b) = (bottom.max(lo), top.min(self.length));
            if b > a {
                total += (prim(b) - prim(a)) / ei;
            }
            bottom = top;
        }
        total
    }
}

/// One point of a wall-error profile.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct WallPoint {
    /// Height above the tool tip, mm.
    pub z_mm: f64,
    /// Wall error, µm (negative: overcut; positive: undercut).
    pub error_um: f64,
}

/// The wall error along the depth of cut for a wall generated at angle `phi_wall` (0 for up
/// milling, π for down milling), at `points` heights from the tip to the top of the cut.
///
/// # Errors
/// [`ForceError::Input`] for fewer than 2 or more than 10 000 points.
pub fn wall_profile(
    mill: &EndMill,
    coefficients: &Coefficients,
    engagement: &Engagement,
    beam: &Cantilever,
    mode: Mode,
    points: usize,
) -> Result<Vec<WallPoint>, ForceError> {
    if !(2..=10_000).contains(&points) {
        return Err(ForceError::Input(format!(
            "wall profile points must be 2 to 10000, got {points}"
        )));
    }
    let walls: &[(f64, f64)] = match mode {
        Mode::Up => &[(0.0, -1.0)],
        Mode::Down => &[(PI, 1.0)],
        Mode::Slot => &[(0.0, -1.0), (PI, 1.0)],
    };
    let top = engagement.disks.last().map_or(0.0, |d| d.z1);
    let model = DiskForces::new(mill, coefficients, engagement);
    let mids: Vec<f64> = (0..model.len()).map(|i| model.disk_mid(i)).collect();
    let mut per_disk = vec![Load::default(); model.len()];
    let kb = mill.k_beta();
    let mut out = Vec::with_capacity(points);
    for p in 0..points {
        let zs = top * p as f64 / (points - 1) as f64;
        // Per wall the deepest pass (most negative error) of any flute leaves the surface; of
        // a slot's two walls the one with the larger error is reported.
        let mut error = 0.0_f64;
        for &(phi_wall, normal) in walls {
            let mut wall = f64::INFINITY;
            for &theta in &mill.flute_angles {
                // Rotation at which this flute's edge point at zs passes the wall angle.
                let phi = phi_wall - theta + kb * zs;
                model.load(phi, Some(&mut per_disk));
                let dy: f64 = per_disk
                    .iter()
                    .zip(&mids)
                    .map(|(l, &zm)| l.force.fy * beam.influence(zs, zm))
                    .sum();
                wall = wall.min(normal * dy * 1e3);
            }
            if wall.abs() > error.abs() {
                error = wall;
            }
        }
        out.push(WallPoint {
            z_mm: zs,
            error_um: error,
        });
    }
    Ok(out)
}

/// One point of the tool's deflection profile.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct DeflectionPoint {
    /// Height above the tool tip, mm.
    pub z_mm: f64,
    /// Deflection along x (the feed direction in the cut's frame), µm.
    pub dx_um: f64,
    /// Deflection along y (normal to the feed, towards the material side of up milling), µm.
    pub dy_um: f64,
}

/// A point load on the tool: height above the tip (mm) and the force's x and y parts (N).
pub type PointLoad = (f64, f64, f64);

/// The deflection of `beam` at `points` heights evenly from the tip to `top_mm` under the
/// point `loads` (superposed through [`Cantilever::influence`]).
///
/// # Errors
/// [`ForceError::Input`] for fewer than 2 or more than 10 000 points, or a top outside the
/// beam.
pub fn deflection_profile(
    beam: &Cantilever,
    loads: &[PointLoad],
    top_mm: f64,
    points: usize,
) -> Result<Vec<DeflectionPoint>, ForceError> {
    if !(2..=10_000).contains(&points) {
        return Err(ForceError::Input(format!(
            "deflection profile points must be 2 to 10000, got {points}"
        )));
    }
    super::check_range("profile top", top_mm, 0.0, beam.length, "mm")?;
    Ok((0..points)
        .map(|p| {
            let zs = top_mm * p as f64 / (points - 1) as f64;
            let (mut dx, mut dy) = (0.0, 0.0);
            for &(zm, fx, fy) in loads {
                let c = beam.influence(zs, zm);
                dx += fx * c;
                dy += fy * c;
            }
            DeflectionPoint {
                z_mm: zs,
                dx_um: dx * 1e3,
                dy_um: dy * 1e3,
            }
        })
        .collect())
}

/// The per-disk loads (disk mid-height, F_x, F_y) at the rotation angle, of `steps` per
/// revolution, where the tool's resultant force is largest, with that angle (rad).
#[must_use]
pub fn peak_disk_loads(
    mill: &EndMill,
    coefficients: &Coefficients,
    engagement: &Engagement,
    steps: usize,
) -> (f64, Vec<PointLoad>) {
    let model = DiskForces::new(mill, coefficients, engagement);
    let steps = steps.max(1);
    let mut best = (0.0, f64::NEG_INFINITY);
    for k in 0..steps {
        let phi = 2.0 * PI * k as f64 / steps as f64;
        let f = model.load(phi, None).force;
        let r = (f.fx * f.fx + f.fy * f.fy + f.fz * f.fz).sqrt();
        if r > best.1 {
            best = (phi, r);
        }
    }
    let mut per_disk = vec![Load::default(); model.len()];
    model.load(best.0, Some(&mut per_disk));
    let loads = per_disk
        .iter()
        .enumerate()
        .map(|(i, l)| (model.disk_mid(i), l.force.fx, l.force.fy))
        .collect();
    (best.0, loads)
}
