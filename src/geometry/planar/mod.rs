//! Planar geometry (L0): bulge polylines of lines and circular arcs ([`Profile`], [`Vertex`],
//! [`Element`]), their exact offsets through `cavalier_contours` ([`offset_paths`]), regions
//! with islands ([`Region`]: offsets and booleans, exact arcs kept), and the CSV, DXF and SVG
//! readers and writers. Every strategy that works in a plane (pockets, contours, facing, the
//! EDM profile of [`crate::profile`]) builds on it.
//!
//! A [`Profile`] is an open or closed chain of lines and circular arcs (each vertex carries the
//! bulge of the element that leaves it, `tan(sweep / 4)`, positive counter-clockwise).

mod element;
mod index;
mod offset;
mod polish;
mod read;
mod read_svg;
mod region;
mod write;

pub(crate) use element::closest_on;
pub use element::{Element, distance_to_profile};
pub use index::{BoxTree, ElementIndex, box_distance};
pub use offset::{ClPath, ClVertex, Side, offset_paths};
pub use read::{ProfileFormat, parse_csv, parse_dxf, parse_svg, read_profile};
pub use region::{Area, BooleanOp, Region, RegionError, signed_area};
pub use write::{profile_to_csv, profile_to_dxf, profile_to_svg, write_profile};

use glam::DVec2;

/// Largest coordinate magnitude accepted, mm (1 km).
pub const MAX_COORD_MM: f64 = 1.0e6;

/// The most vertices a profile may have (a 100 MB CSV of points aborted on allocation; the
/// computation on this many takes seconds).
pub const MAX_PROFILE_POINTS: usize = 1_000_000;

/// One vertex of a profile: its position and the bulge of the element to the next vertex.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Vertex {
    /// x, mm.
    pub x: f64,
    /// y, mm.
    pub y: f64,
    /// `tan(sweep / 4)` of the arc to the next vertex (0: a line; positive: counter-clockwise).
    pub bulge: f64,
}

impl Vertex {
    /// A vertex followed by a line.
    #[must_use]
    pub fn point(x: f64, y: f64) -> Self {
        Self { x, y, bulge: 0.0 }
    }

    /// The position.
    #[must_use]
    pub fn pos(&self) -> DVec2 {
        DVec2::new(self.x, self.y)
    }
}

/// A 2D profile: vertices joined by lines and arcs, open or closed.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Profile {
    /// The vertices in order.
    pub vertices: Vec<Vertex>,
    /// The last vertex joins the first.
    pub closed: bool,
}

/// A profile error: the file (or `<memory>`), the place (`row N`, `line N`, `entity N`,
/// `vertex N`) and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{file}: {place}: {message}")]
pub struct ProfileError {
    /// The file or `<memory>`.
    pub file: String,
    /// Where in it.
    pub place: String,
    /// What is wrong.
    pub message: String,
}

impl ProfileError {
    pub(crate) fn new(file: &str, place: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            file: file.to_string(),
            place: place.into(),
            message: message.into(),
        }
    }
}

impl Profile {
    /// An open profile through points joined by lines.
    #[must_use]
    pub fn polyline(points: &[(f64, f64)]) -> Self {
        Self {
            vertices: points.iter().map(|&(x, y)| Vertex::point(x, y)).collect(),
            closed: false,
        }
    }

    /// Number of elements (lines and arcs).
    #[must_use]
    pub fn element_count(&self) -> usize {
        let n = self.vertices.len();
        if self.closed { n } else { n.saturating_sub(1) }
    }

    /// The elements in order.
    #[must_use]
    pub fn elements(&self) -> Vec<Element> {
        let n = self.vertices.len();
        (0..self.element_count())
            .filter_map(|i| {
                let a = self.vertices.get(i)?;
                let b = self.vertices.get((i + 1) % n)?;
                Some(Element::from_bulge(a.pos(), b.pos(), a.bulge))
            })
            .collect()
    }

    /// True when every element is a line (a point profile, as entered in the paper's program).
    #[must_use]
    pub fn is_point_profile(&self) -> bool {
        let m = self.element_count();
        self.vertices.iter().take(m).all(|v| v.bulge == 0.0)
    }

    /// The same profile traversed the other way.
    #[must_use]
    pub fn reversed(&self) -> Self {
        let n = self.vertices.len();
        let mut v: Vec<Vertex> = Vec::with_capacity(n);
        for i in (0..n).rev() {
            let Some(cur) = self.vertices.get(i) else {
                continue;
            };
            // The element from i-1 to i becomes the element from i to i-1.
            let prev_bulge = if i > 0 {
                self.vertices.get(i - 1).map_or(0.0, |p| p.bulge)
            } else if self.closed {
                self.vertices.last().map_or(0.0, |p| p.bulge)
            } else {
                0.0
            };
            v.push(Vertex {
                x: cur.x,
                y: cur.y,
                bulge: -prev_bulge,
            });
        }
        Self {
            vertices: v,
            closed: self.closed,
        }
    }

    /// Checks: at least two vertices (three for a closed profile), finite coordinates within
    /// ±[`MAX_COORD_MM`], no zero-length element, bulges within ±1 (at most a half circle per
    /// element; readers split larger arcs). `file` names the source in the error.
    ///
    /// # Errors
    /// [`ProfileError`] naming the vertex.
    pub fn validate(&self, file: &str) -> Result<(), ProfileError> {
        let n = self.vertices.len();
        if n > MAX_PROFILE_POINTS {
            return Err(ProfileError::new(
                file,
                "profile",
                format!("{n} points, more than the {MAX_PROFILE_POINTS} a profile may have"),
            ));
        }
        let need = if self.closed { 3 } else { 2 };
        if n < need {
            return Err(ProfileError::new(
                file,
                "profile",
                format!("a profile needs at least {need} points, found {n}"),
            ));
        }
        let scale = self.extent_mm().max(1e-300);
        for (i, v) in self.vertices.iter().enumerate() {
            let place = format!("vertex {}", i + 1);
            if !(v.x.is_finite() && v.y.is_finite() && v.bulge.is_finite()) {
                return Err(ProfileError::new(file, place, "non-finite number"));
            }
            if v.x.abs() > MAX_COORD_MM || v.y.abs() > MAX_COORD_MM {
                return Err(ProfileError::new(
                    file,
                    place,
                    format!("coordinate beyond ±{MAX_COORD_MM} mm"),
                ));
            }
            if v.bulge.abs() > 1.0 + 1e-12 {
                return Err(ProfileError::new(
                    file,
                    place,
                    format!("bulge {} beyond ±1 (more than a half circle)", v.bulge),
                ));
            }
        }
        for (i, e) in self.elements().iter().enumerate() {
            if e.chord_length() <= 1e-12 * scale {
                return Err(ProfileError::new(
                    file,
                    format!("vertex {}", (i + 1) % n + 1),
                    "repeats the previous point (zero-length element)",
                ));
            }
        }
        Ok(())
    }

    /// The largest side of the bounding box of the vertices, mm.
    #[must_use]
    pub fn extent_mm(&self) -> f64 {
        let (lo, hi) = self.bounds();
        (hi - lo).max_element()
    }

    /// Bounding box of the elements (arcs included), mm.
    #[must_use]
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for v in &self.vertices {
            lo = lo.min(v.pos());
            hi = hi.max(v.pos());
        }
        for e in self.elements() {
            let (a, b) = e.bounds();
            lo = lo.min(a);
            hi = hi.max(b);
        }
        (lo, hi)
    }

    /// Arc length of each element, mm.
    #[must_use]
    pub fn element_lengths(&self) -> Vec<f64> {
        self.elements().iter().map(Element::length).collect()
    }
}
