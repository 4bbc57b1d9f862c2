//! Machining features read from the B-rep: what a part asks to be made, in the terms a shop uses,
//! found from the faces' exact surfaces rather than from triangles. Strategies plan operations
//! from these.
//! - [`holes`]: holes with their diameters, depths and bottoms, compound holes, groups.
//! - [`regions`]: the regions a 2.5D strategy machines (pockets, steps, slots, the top and the
//!   outer profile seen from +Z).

pub mod holes;
pub mod regions;

use crate::geometry::brep::Part;

/// One recognised feature, summarised for a list: what it is (kind, heights, sizes in mm) and
/// the faces it is made of (the first is its floor or its main bore).
#[derive(Clone, Debug, PartialEq)]
pub struct FeatureSummary {
    /// One line in words with units.
    pub text: String,
    /// Its faces (indices into the part's faces).
    pub faces: Vec<usize>,
}

/// The holes of `part`, recognised from its B-rep on a mesh fine enough to tell reversed
/// shells (chord 1e-3 of the part's diagonal).
#[must_use]
pub fn holes_of(part: &Part) -> holes::HoleReport {
    use crate::geometry::tessellate::{TessellationOptions, tessellate_part};
    let mesh = tessellate_part(
        part,
        &TessellationOptions::with_chord_tol(1e-3 * part.rough_bbox().diagonal().max(1e-3)),
    );
    holes::recognize_holes(part, Some(&mesh), &holes::HoleOptions::default())
}

/// The regions (seen from +Z) and the holes of `part`, each as one line: what the
/// workstation's feature list shows (the same recognition as `talas features`).
#[must_use]
pub fn summaries(part: &Part) -> Vec<FeatureSummary> {
    let mut out = Vec::new();
    for r in regions::find_regions(part).regions {
        let kind = match r.kind {
            regions::RegionKind::Top => "Top face",
            regions::RegionKind::ClosedPocket => "Closed pocket",
            regions::RegionKind::OpenPocket => "Open pocket",
            regions::RegionKind::Step => "Step",
            regions::RegionKind::Slot => "Slot",
            regions::RegionKind::OuterProfile => "Outer profile",
        };
        let mut text = format!(
            "{kind} · floor {:.3} mm · depth {:.3} mm · {:.0} mm²",
            r.floor_z_mm, r.depth_mm, r.area_mm2
        );
        if let Some(c) = r.smallest_corner_radius_mm {
            text.push_str(&format!(" · corners R{c:.3} mm"));
        }
        if r.islands > 0 {
            text.push_str(&format!(" · {} islands", r.islands));
        }
        if r.open_sides > 0 {
            text.push_str(&format!(" · {} open sides", r.open_sides));
        }
        out.push(FeatureSummary {
            text,
            faces: r.faces,
        });
    }
    for h in holes_of(part).holes {
        let kind = match h.kind {
            holes::HoleKind::Simple => "Hole",
            holes::HoleKind::Counterbore => "Counterbored hole",
            holes::HoleKind::SpotFace => "Spot-faced hole",
            holes::HoleKind::Countersink => "Countersunk hole",
            holes::HoleKind::Stepped => "Stepped hole",
        };
        let bottom = match h.bottom {
            holes::HoleBottom::Through => "through".to_string(),
            holes::HoleBottom::Flat => "flat bottom".to_string(),
            holes::HoleBottom::Point { angle_rad, .. } => {
                format!("{:.0}° drill point", angle_rad.to_degrees())
            }
            holes::HoleBottom::Other { .. } => "closed".to_string(),
        };
        out.push(FeatureSummary {
            text: format!(
                "{kind} Ø{:.3} mm · depth {:.3} mm · {bottom} · top ({:.3}, {:.3}, {:.3}) mm",
                h.diameter_mm, h.depth_mm, h.top.x, h.top.y, h.top.z
            ),
            faces: h.faces,
        });
    }
    out
}
