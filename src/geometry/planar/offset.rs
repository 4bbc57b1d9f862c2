//! The exact electrode-centre path: the profile offset by R on its material-free side with
//! `cavalier_contours` (arcs at convex corners, self-intersections trimmed).
//!
//! The library's tolerances are absolute (positions equal within 1e-5, slices kept within
//! 1e-4 of the offset distance), tuned for coordinates of order 1 to 1000. The profile is
//! therefore moved to its bounding-box centre and scaled to a 100-unit extent before offsetting
//! and the result mapped back, so the result does not depend on where the profile lies or on
//! its size.

use cavalier_contours::polyline::{
    PlineCreation, PlineOffsetOptions, PlineOrientation, PlineSource, PlineSourceMut, Polyline,
};
use glam::DVec2;

use super::Profile;
use super::element::Element;
use super::index::ElementIndex;
use super::polish::polish;

/// Extent the profile is scaled to before offsetting.
const NORMALISED_EXTENT: f64 = 100.0;

/// Where the material-free side of the profile is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// Left of the direction of travel.
    Left,
    /// Right of the direction of travel.
    Right,
    /// Above (+y): for an open profile the left side when it runs toward +x overall, the right
    /// side when it runs toward −x; for a closed profile the outside.
    #[default]
    Above,
    /// Outside a closed profile.
    Outside,
    /// Inside a closed profile.
    Inside,
}

impl Side {
    /// The side as left (true) or right (false) of the direction of travel.
    ///
    /// # Errors
    /// A sentence when the side does not fit the profile (inside/outside of an open profile,
    /// above for an open profile whose ends have the same x).
    pub fn is_left(self, profile: &Profile) -> Result<bool, String> {
        let ccw = || orientation_ccw(profile);
        match self {
            Self::Left => Ok(true),
            Self::Right => Ok(false),
            Self::Outside | Self::Above if profile.closed => Ok(!ccw()),
            Self::Inside if profile.closed => Ok(ccw()),
            Self::Outside | Self::Inside => {
                Err("inside/outside needs a closed profile; say left, right or above".into())
            }
            Self::Above => {
                let (Some(first), Some(last)) = (profile.vertices.first(), profile.vertices.last())
                else {
                    return Err("empty profile".into());
                };
                let dx = last.x - first.x;
                if dx > 0.0 {
                    Ok(true)
                } else if dx < 0.0 {
                    Ok(false)
                } else {
                    Err("the profile's ends have the same x, so 'above' is ambiguous; say left or right".into())
                }
            }
        }
    }
}

/// True when a closed profile runs counter-clockwise (positive signed area, arcs included).
fn orientation_ccw(profile: &Profile) -> bool {
    let pl = to_pline(profile, DVec2::ZERO, 1.0);
    pl.orientation() == PlineOrientation::CounterClockwise
}

/// One vertex of the electrode-centre path.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ClVertex {
    /// Electrode centre, mm.
    pub centre: DVec2,
    /// Bulge of the path element to the next vertex.
    pub bulge: f64,
    /// The profile point the electrode touches here (the closest point), mm.
    pub contact: DVec2,
    /// The electrode's lowest point (centre − R in y), mm.
    pub lowest: DVec2,
}

/// One connected piece of the electrode-centre path.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct ClPath {
    /// Vertices in the profile's direction.
    pub vertices: Vec<ClVertex>,
    /// The piece closes on itself.
    pub closed: bool,
}

impl ClPath {
    /// The path's elements (lines and arcs of the centre).
    #[must_use]
    pub fn elements(&self) -> Vec<Element> {
        let n = self.vertices.len();
        let m = if self.closed { n } else { n.saturating_sub(1) };
        (0..m)
            .filter_map(|i| {
                let a = self.vertices.get(i)?;
                let b = self.vertices.get((i + 1) % n)?;
                Some(Element::from_bulge(a.centre, b.centre, a.bulge))
            })
            .collect()
    }

    /// Length of the centre path, mm.
    #[must_use]
    pub fn length_mm(&self) -> f64 {
        self.elements().iter().map(Element::length).sum()
    }
}

fn to_pline(profile: &Profile, origin: DVec2, scale: f64) -> Polyline<f64> {
    let mut pl = Polyline::with_capacity(profile.vertices.len(), profile.closed);
    let m = profile.element_count();
    for (i, v) in profile.vertices.iter().enumerate() {
        let p = (v.pos() - origin) * scale;
        let bulge = if i < m { v.bulge } else { 0.0 };
        pl.add(p.x, p.y, bulge);
    }
    pl
}

/// The exact centre path of an electrode of radius `radius_mm` on the left (`left`) or right
/// side, in pieces ordered along the profile. Empty when the electrode fits nowhere (a closed
/// profile offset inward by more than its inradius).
#[must_use]
pub fn offset_paths(profile: &Profile, radius_mm: f64, left: bool) -> Vec<ClPath> {
    let (lo, hi) = profile.bounds();
    let origin = (lo + hi) / 2.0;
    let extent = (hi - lo).max_element();
    let scale = if extent > 0.0 {
        NORMALISED_EXTENT / extent
    } else {
        1.0
    };
    let pl = to_pline(profile, origin, scale);
    let opts = PlineOffsetOptions {
        handle_self_intersects: true,
        ..PlineOffsetOptions::default()
    };
    let signed = if left { radius_mm } else { -radius_mm } * scale;
    let results = pl.parallel_offset_opt(signed, &opts);
    let elements = profile.elements();
    let index = ElementIndex::new(&elements);
    let ends = end_offsets(profile, &elements, radius_mm, left);
    let eps = 1e-6 * extent.max(radius_mm).max(1e-300);
    let lengths: Vec<f64> = elements.iter().map(Element::length).collect();
    let mut keyed: Vec<(f64, ClPath)> = results
        .iter()
        .filter(|r| r.vertex_count() >= 2)
        .map(|r| {
            let path = from_pline(r, origin, scale, radius_mm, &index, ends, eps);
            let key = path
                .vertices
                .first()
                .map_or(0.0, |v| profile_position(&index, &lengths, v.centre));
            (key, path)
        })
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    keyed.into_iter().map(|(_, p)| p).collect()
}

/// The exact offsets of an open profile's end points (none for a closed profile).
fn end_offsets(
    profile: &Profile,
    elements: &[Element],
    radius: f64,
    left: bool,
) -> [Option<DVec2>; 2] {
    if profile.closed {
        return [None, None];
    }
    let off = |e: Option<&Element>, t: f64| {
        e.map(|e| {
            let tan = e.tangent_at(t);
            let n = if left { tan.perp() } else { -tan.perp() };
            e.point_at(t) + n * radius
        })
    };
    [off(elements.first(), 0.0), off(elements.last(), 1.0)]
}

fn from_pline(
    r: &Polyline<f64>,
    origin: DVec2,
    scale: f64,
    radius_mm: f64,
    index: &ElementIndex,
    ends: [Option<DVec2>; 2],
    eps: f64,
) -> ClPath {
    let mut raw: Vec<(DVec2, f64)> = r
        .iter_vertexes()
        .map(|v| (DVec2::new(v.x, v.y) / scale + origin, v.bulge))
        .collect();
    // Elements shorter than the matching tolerance are slivers the library left where slices
    // meet (a few 1e-6 of the size): the vertex after one is dropped.
    // The kept vertex takes the dropped one's bulge: the element leaving it is the real one.
    raw.dedup_by(|b, a| {
        let close = (b.0 - a.0).length() <= eps;
        if close {
            a.1 = b.1;
        }
        close
    });
    if r.is_closed()
        && raw.len() > 1
        && raw
            .first()
            .zip(raw.last())
            .is_some_and(|(f, l)| (f.0 - l.0).length() <= eps)
    {
        raw.pop();
    }
    polish(&mut raw, r.is_closed(), index, radius_mm, ends, eps);
    let vertices = raw
        .into_iter()
        .map(|(centre, bulge)| {
            let contact = index.closest(centre).map_or(centre, |c| c.2);
            ClVertex {
                centre,
                bulge,
                contact,
                lowest: centre - DVec2::new(0.0, radius_mm),
            }
        })
        .collect();
    ClPath {
        vertices,
        closed: r.is_closed(),
    }
}

/// Arc-length position along the profile of the point closest to `p`, mm.
pub(crate) fn profile_position(index: &ElementIndex, lengths: &[f64], p: DVec2) -> f64 {
    let elements = index.elements();
    let Some((_, i, _)) = index.closest(p) else {
        return 0.0;
    };
    let before: f64 = lengths.iter().take(i).sum();
    let (t, len) = elements
        .get(i)
        .map_or((0.0, 0.0), |e| (e.closest(p).1, e.length()));
    before + t * len
}
