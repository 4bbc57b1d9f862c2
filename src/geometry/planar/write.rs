//! Profile writers: CSV (`x,y,bulge`), DXF (one LWPOLYLINE) and SVG (one `<path>`, y mirrored
//! to SVG's downward axis, arcs as `A`). What they write reads back to the same profile.

use std::fmt::Write as _;
use std::path::Path;

use super::element::Element;
use super::read::ProfileFormat;
use super::{Profile, ProfileError};

/// The profile as CSV text: a header, then `x,y,bulge` per vertex; a closed profile repeats
/// its first point at the end. Numbers are written with Rust's shortest round-trip form.
#[must_use]
pub fn profile_to_csv(profile: &Profile) -> String {
    let mut s = String::from(
        "# Talas profile, mm; bulge = tan(sweep/4) of the element to the next point\nx,y,bulge\n",
    );
    for v in &profile.vertices {
        let _ = writeln!(s, "{},{},{}", v.x, v.y, v.bulge);
    }
    if profile.closed
        && let Some(f) = profile.vertices.first()
    {
        let _ = writeln!(s, "{},{},0", f.x, f.y);
    }
    s
}

/// The profile as a DXF drawing holding one LWPOLYLINE.
///
/// # Errors
/// [`ProfileError`] when the DXF writer fails.
pub fn profile_to_dxf(profile: &Profile) -> Result<Vec<u8>, ProfileError> {
    let mut pl = dxf::entities::LwPolyline::default();
    for v in &profile.vertices {
        pl.vertices.push(dxf::LwPolylineVertex {
            x: v.x,
            y: v.y,
            bulge: v.bulge,
            ..Default::default()
        });
    }
    pl.set_is_closed(profile.closed);
    let mut drawing = dxf::Drawing::new();
    // LWPOLYLINE exists from R14 on.
    drawing.header.version = dxf::enums::AcadVersion::R2000;
    drawing.add_entity(dxf::entities::Entity::new(
        dxf::entities::EntityType::LwPolyline(pl),
    ));
    let mut out = Vec::new();
    drawing
        .save(&mut out)
        .map_err(|e| ProfileError::new("<memory>", "DXF", e.to_string()))?;
    Ok(out)
}

/// The profile as an SVG document with one `<path>` (y mirrored: SVG's axis points down).
#[must_use]
pub fn profile_to_svg(profile: &Profile) -> String {
    let (lo, hi) = profile.bounds();
    let pad = (hi - lo).max_element().max(1.0) * 0.05;
    let mut d = String::new();
    if let Some(f) = profile.vertices.first() {
        let _ = write!(d, "M {} {}", f.x, -f.y);
    }
    for e in profile.elements() {
        let b = e.end();
        match e {
            Element::Line { .. } => {
                let _ = write!(d, " L {} {}", b.x, -b.y);
            }
            Element::Arc {
                radius, sweep_rad, ..
            } => {
                let large = u8::from(sweep_rad.abs() > std::f64::consts::PI);
                // Counter-clockwise with y up is SVG's sweep flag 0 once y is mirrored.
                let sweep = u8::from(sweep_rad < 0.0);
                let _ = write!(d, " A {radius} {radius} 0 {large} {sweep} {} {}", b.x, -b.y);
            }
        }
    }
    if profile.closed {
        d.push_str(" Z");
    }
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{} {} {} {}\">\n  <path d=\"{d}\" fill=\"none\" stroke=\"black\" stroke-width=\"{}\"/>\n</svg>\n",
        lo.x - pad,
        -hi.y - pad,
        hi.x - lo.x + 2.0 * pad,
        hi.y - lo.y + 2.0 * pad,
        pad / 10.0
    )
}

/// Writes the profile in the format of the file's extension, atomically.
///
/// # Errors
/// [`ProfileError`] for an unknown extension or a failed write.
pub fn write_profile(profile: &Profile, path: &Path) -> Result<(), ProfileError> {
    let file = path.display().to_string();
    let bytes = match ProfileFormat::of_path(path) {
        Some(ProfileFormat::Csv) => profile_to_csv(profile).into_bytes(),
        Some(ProfileFormat::Svg) => profile_to_svg(profile).into_bytes(),
        Some(ProfileFormat::Dxf) => profile_to_dxf(profile)?,
        None => {
            return Err(ProfileError::new(
                &file,
                "name",
                "unknown extension (expected .csv, .dxf or .svg)",
            ));
        }
    };
    crate::storage::write_atomic(path, &bytes)
        .map_err(|e| ProfileError::new(&file, "file", e.to_string()))
}
