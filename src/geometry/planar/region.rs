//! Regions with islands: closed areas bounded by lines and arcs, as a machinist's pocket floor
//! or a stock outline. A [`Region`] is a list of [`Area`]s, each an outer boundary
//! (counter-clockwise) less its islands (clockwise), the layout of `cavalier_contours`'
//! `Shape`. Offsets go through `Shape::parallel_offset`, booleans through the polyline booleans
//! of `cavalier_contours`: both keep arcs exact (see ARCHITECTURE.md, "2D geometry").
//!
//! The library's tolerances are absolute (1e-5 on positions), fit for coordinates in mm from
//! about 0.01 to 10 000: regions are kept in mm and not rescaled.

use cavalier_contours::polyline::{
    BooleanOp as PlineOp, BooleanResultInfo, PlineCreation, PlineSource, PlineSourceMut, Polyline,
};
use cavalier_contours::shape_algorithms::{Shape, ShapeOffsetOptions};
use glam::DVec2;

use super::{Element, MAX_COORD_MM, Profile, Vertex};

/// A boolean operation between two regions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BooleanOp {
    /// Points in either.
    Union,
    /// Points in both.
    Intersection,
    /// Points in the first and not in the second.
    Difference,
}

/// Why a region could not be built.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("region: {0}")]
pub struct RegionError(pub String);

/// One connected area: an outer boundary (counter-clockwise, closed) less its islands
/// (clockwise, closed, inside the outer boundary, disjoint from each other).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Area {
    /// The outer boundary, counter-clockwise.
    pub outer: Profile,
    /// The islands, clockwise.
    pub islands: Vec<Profile>,
}

/// A planar region: disjoint [`Area`]s.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Region {
    /// The areas.
    pub areas: Vec<Area>,
}

fn to_pline(p: &Profile) -> Polyline<f64> {
    let mut pl = Polyline::with_capacity(p.vertices.len(), true);
    for v in &p.vertices {
        pl.add(v.x, v.y, v.bulge);
    }
    pl
}

fn from_pline<P: PlineSource<Num = f64>>(pl: &P) -> Profile {
    Profile {
        vertices: pl
            .iter_vertexes()
            .map(|v| Vertex {
                x: v.x,
                y: v.y,
                bulge: v.bulge,
            })
            .collect(),
        closed: true,
    }
}

/// Signed area of a closed profile (positive counter-clockwise), arcs included, mm².
#[must_use]
pub fn signed_area(p: &Profile) -> f64 {
    if p.vertices.len() < 2 {
        return 0.0;
    }
    to_pline(p).area()
}

fn oriented(p: &Profile, ccw: bool) -> Profile {
    if (signed_area(p) > 0.0) == ccw {
        p.clone()
    } else {
        p.reversed()
    }
}

/// True when `p` is a usable closed boundary: at least two vertices (a two-arc circle),
/// finite coordinates within range, a non-zero area.
fn usable(p: &Profile) -> bool {
    p.vertices.len() >= 2
        && p.vertices.iter().all(|v| {
            v.x.is_finite()
                && v.y.is_finite()
                && v.bulge.is_finite()
                && v.x.abs() <= MAX_COORD_MM
                && v.y.abs() <= MAX_COORD_MM
                && v.bulge.abs() <= 1.0 + 1e-12
        })
        && signed_area(p).abs() > 1e-12
}

impl Area {
    /// Area of the region, islands taken out, mm².
    #[must_use]
    pub fn area_mm2(&self) -> f64 {
        signed_area(&self.outer).abs()
            - self
                .islands
                .iter()
                .map(|i| signed_area(i).abs())
                .sum::<f64>()
    }

    /// True when `p` lies inside the outer boundary and outside every island.
    #[must_use]
    pub fn contains(&self, p: DVec2) -> bool {
        winding(&self.outer, p) != 0 && self.islands.iter().all(|i| winding(i, p) == 0)
    }
}

fn winding(p: &Profile, q: DVec2) -> i32 {
    to_pline(p).winding_number(cavalier_contours::core::math::Vector2::new(q.x, q.y))
}

impl Region {
    /// The empty region.
    #[must_use]
    pub fn empty() -> Self {
        Self::default()
    }

    /// A region from closed boundaries in any orientation and order: each boundary's nesting
    /// depth decides whether it bounds material (even depth: an outer boundary) or a hole (odd:
    /// an island), as a DXF drawing of a pocket with islands gives them.
    ///
    /// # Errors
    /// A boundary that is open, has fewer than two vertices, non-finite or out-of-range
    /// coordinates, bulges beyond ±1 or no area.
    pub fn from_boundaries(boundaries: &[Profile]) -> Result<Self, RegionError> {
        for (i, b) in boundaries.iter().enumerate() {
            if !b.closed || !usable(b) {
                return Err(RegionError(format!(
                    "boundary {} is not a closed boundary with an area (open, degenerate or out of range)",
                    i + 1
                )));
            }
        }
        // Nesting depth by a point of each boundary tested against the others.
        let depth: Vec<usize> = boundaries
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let q = interior_probe(b);
                boundaries
                    .iter()
                    .enumerate()
                    .filter(|&(j, o)| {
                        j != i && winding(o, q) != 0 && signed_area(o).abs() > signed_area(b).abs()
                    })
                    .count()
            })
            .collect();
        let mut areas: Vec<(usize, Area)> = Vec::new();
        for (i, b) in boundaries.iter().enumerate() {
            if depth.get(i).copied().unwrap_or(0) % 2 == 0 {
                areas.push((
                    i,
                    Area {
                        outer: oriented(b, true),
                        islands: Vec::new(),
                    },
                ));
            }
        }
        for (i, b) in boundaries.iter().enumerate() {
            let d = depth.get(i).copied().unwrap_or(0);
            if d % 2 == 1 {
                let q = interior_probe(b);
                // The innermost outer boundary around it: depth d − 1.
                if let Some((_, a)) = areas.iter_mut().find(|(j, a)| {
                    depth.get(*j).copied().unwrap_or(0) + 1 == d && winding(&a.outer, q) != 0
                }) {
                    a.islands.push(oriented(b, false));
                }
            }
        }
        Ok(Self {
            areas: areas.into_iter().map(|(_, a)| a).collect(),
        })
    }

    /// A region of one closed boundary.
    ///
    /// # Errors
    /// As [`Region::from_boundaries`].
    pub fn from_outline(outline: &Profile) -> Result<Self, RegionError> {
        Self::from_boundaries(std::slice::from_ref(outline))
    }

    /// An axis-aligned rectangle.
    #[must_use]
    pub fn rectangle(lo: DVec2, hi: DVec2) -> Self {
        let outer = Profile {
            vertices: vec![
                Vertex::point(lo.x, lo.y),
                Vertex::point(hi.x, lo.y),
                Vertex::point(hi.x, hi.y),
                Vertex::point(lo.x, hi.y),
            ],
            closed: true,
        };
        Self {
            areas: vec![Area {
                outer,
                islands: Vec::new(),
            }],
        }
    }

    /// A circle of radius `r` about `c` (two half-circle arcs).
    #[must_use]
    pub fn circle(c: DVec2, r: f64) -> Self {
        let outer = Profile {
            vertices: vec![
                Vertex {
                    x: c.x - r,
                    y: c.y,
                    bulge: 1.0,
                },
                Vertex {
                    x: c.x + r,
                    y: c.y,
                    bulge: 1.0,
                },
            ],
            closed: true,
        };
        Self {
            areas: vec![Area {
                outer,
                islands: Vec::new(),
            }],
        }
    }

    /// True when the region has no area.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.areas.is_empty()
    }

    /// Total area, mm².
    #[must_use]
    pub fn area_mm2(&self) -> f64 {
        self.areas.iter().map(Area::area_mm2).sum()
    }

    /// Every boundary: outer ones counter-clockwise, islands clockwise.
    #[must_use]
    pub fn boundaries(&self) -> Vec<&Profile> {
        self.areas
            .iter()
            .flat_map(|a| std::iter::once(&a.outer).chain(a.islands.iter()))
            .collect()
    }

    /// True when `p` is inside the region.
    #[must_use]
    pub fn contains(&self, p: DVec2) -> bool {
        self.areas.iter().any(|a| a.contains(p))
    }

    /// Bounding box of the region, mm (infinite when empty).
    #[must_use]
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for a in &self.areas {
            let (l, h) = a.outer.bounds();
            lo = lo.min(l);
            hi = hi.max(h);
        }
        (lo, hi)
    }

    /// The smallest radius of a concave corner of material around the region (a corner of
    /// the outer boundary the tool must turn inside, or of an island), mm: `None` when the
    /// region's boundaries have no arcs turning into the region; `Some(0)` at a sharp inside
    /// corner.
    #[must_use]
    pub fn smallest_corner_radius_mm(&self) -> Option<f64> {
        let mut best: Option<f64> = None;
        for p in self.boundaries() {
            let els = p.elements();
            let n = els.len();
            for (i, e) in els.iter().enumerate() {
                // Arcs turning left on a ccw outer (or on a cw island, which turns right
                // overall) bound the region from the outside: the tool must fit in them.
                if let Element::Arc {
                    radius, sweep_rad, ..
                } = *e
                    && sweep_rad > 0.0
                {
                    best = Some(best.map_or(radius, |b: f64| b.min(radius)));
                }
                // A sharp corner the region sees as convex toward the material: a left turn.
                let Some(next) = els.get((i + 1) % n) else {
                    continue;
                };
                let t0 = e.tangent_at(1.0);
                let t1 = next.tangent_at(0.0);
                let cross = t0.perp_dot(t1);
                if cross > 1e-6 && t0.dot(t1) < 1.0 - 1e-9 {
                    best = Some(0.0);
                }
            }
        }
        best
    }

    fn to_shape(&self) -> Shape<f64> {
        Shape::from_plines(self.boundaries().into_iter().map(to_pline))
    }

    fn from_shape(shape: &Shape<f64>) -> Self {
        let outers: Vec<Profile> = shape
            .ccw_plines
            .iter()
            .map(|p| from_pline(&p.polyline))
            .collect();
        let holes: Vec<Profile> = shape
            .cw_plines
            .iter()
            .map(|p| from_pline(&p.polyline))
            .collect();
        assemble(outers, holes)
    }

    /// The region offset inward by `distance_mm` (outward when negative): every boundary moves
    /// by the distance, arcs round the convex corners, pieces that vanish are dropped.
    #[must_use]
    pub fn offset(&self, distance_mm: f64) -> Self {
        if self.is_empty() || !distance_mm.is_finite() {
            return Self::empty();
        }
        if distance_mm == 0.0 {
            return self.clone();
        }
        let opts = ShapeOffsetOptions::new();
        Self::from_shape(&self.to_shape().parallel_offset(distance_mm, &opts))
    }

    /// A boolean of two regions.
    #[must_use]
    pub fn boolean(&self, other: &Self, op: BooleanOp) -> Self {
        match op {
            BooleanOp::Difference => self.minus(other),
            BooleanOp::Intersection => self.minus(&self.minus(other)),
            BooleanOp::Union => {
                if self.is_empty() {
                    return other.clone();
                }
                if other.is_empty() {
                    return self.clone();
                }
                // Complements in a box around both: A ∪ B = box − ((box − A) − B).
                let (la, ha) = self.bounds();
                let (lb, hb) = other.bounds();
                let lo = la.min(lb) - DVec2::splat(10.0);
                let hi = ha.max(hb) + DVec2::splat(10.0);
                let frame = Self::rectangle(lo, hi);
                frame.minus(&frame.minus(self).minus(other))
            }
        }
    }

    /// `self − other`: `A − (O − H) = (A − O) ∪ (A ∩ H)` for each area `O − H` of `other`.
    fn minus(&self, other: &Self) -> Self {
        let mut out = self.clone();
        for b in &other.areas {
            let before = out.clone();
            out = out.minus_boundary(&b.outer);
            for h in &b.islands {
                out.areas.extend(before.intersect_boundary(h).areas);
            }
        }
        out
    }

    /// `self ∩ P` for one closed boundary `P`: each outer boundary clipped to `P`, then its
    /// islands taken out again.
    fn intersect_boundary(&self, p: &Profile) -> Self {
        let p = oriented(p, true);
        let pp = to_pline(&p);
        let mut out = Vec::new();
        for a in &self.areas {
            let r = to_pline(&a.outer).boolean(&pp, PlineOp::And);
            let pieces = match r.result_info {
                BooleanResultInfo::Pline1InsidePline2 | BooleanResultInfo::Overlapping => {
                    vec![a.outer.clone()]
                }
                BooleanResultInfo::Pline2InsidePline1 => vec![p.clone()],
                BooleanResultInfo::Disjoint | BooleanResultInfo::InvalidInput => Vec::new(),
                BooleanResultInfo::Intersected => {
                    r.pos_plines.iter().map(|q| from_pline(&q.pline)).collect()
                }
            };
            let mut clipped = assemble(pieces, Vec::new());
            for isl in &a.islands {
                clipped = clipped.minus_boundary(isl);
            }
            out.extend(clipped.areas);
        }
        Self { areas: out }
    }

    /// `self − P` for one closed boundary `P`: for every area `O − ∪H`, the result is
    /// `O − (∪H ∪ P)`.
    fn minus_boundary(&self, p: &Profile) -> Self {
        let p = oriented(p, true);
        let mut out = Vec::new();
        for a in &self.areas {
            // The holes united with P.
            let mut holes: Vec<Profile> = a.islands.iter().map(|h| oriented(h, true)).collect();
            let mut extra_outers = Vec::new();
            holes = union_into(holes, p.clone(), &mut extra_outers);
            // O less each hole in turn (holes are disjoint).
            let mut pieces: Vec<Area> = vec![Area {
                outer: a.outer.clone(),
                islands: Vec::new(),
            }];
            for h in &holes {
                let hp = to_pline(h);
                let mut next = Vec::new();
                for piece in pieces {
                    let r = to_pline(&piece.outer).boolean(&hp, PlineOp::Not);
                    match r.result_info {
                        BooleanResultInfo::Pline2InsidePline1 => {
                            let mut piece = piece;
                            piece.islands.push(oriented(h, false));
                            next.push(piece);
                        }
                        BooleanResultInfo::Disjoint => next.push(piece),
                        BooleanResultInfo::InvalidInput => next.push(piece),
                        BooleanResultInfo::Pline1InsidePline2 | BooleanResultInfo::Overlapping => {}
                        BooleanResultInfo::Intersected => {
                            let outers: Vec<Profile> =
                                r.pos_plines.iter().map(|q| from_pline(&q.pline)).collect();
                            let holes: Vec<Profile> =
                                r.neg_plines.iter().map(|q| from_pline(&q.pline)).collect();
                            let mut parts = assemble(outers, holes).areas;
                            for part in &mut parts {
                                for isl in &piece.islands {
                                    if !part.outer.vertices.is_empty()
                                        && winding(&part.outer, interior_probe(isl)) != 0
                                    {
                                        part.islands.push(isl.clone());
                                    }
                                }
                            }
                            next.extend(parts);
                        }
                    }
                }
                pieces = next;
            }
            out.extend(pieces);
            // Material enclosed by the united holes but inside O (rare): its own areas.
            out.extend(extra_outers.into_iter().map(|e| Area {
                outer: e,
                islands: Vec::new(),
            }));
        }
        Self {
            areas: out.into_iter().filter(|a| usable(&a.outer)).collect(),
        }
    }
}

/// Adds `p` to a set of disjoint counter-clockwise boundaries, merging it with those it
/// overlaps; gaps the merge encloses go to `enclosed`.
fn union_into(set: Vec<Profile>, p: Profile, enclosed: &mut Vec<Profile>) -> Vec<Profile> {
    let mut cur = p;
    let mut rest = Vec::new();
    let mut pending = set;
    loop {
        let mut merged = false;
        let mut keep = Vec::new();
        for h in pending {
            if merged {
                keep.push(h);
                continue;
            }
            let r = to_pline(&cur).boolean(&to_pline(&h), PlineOp::Or);
            match r.result_info {
                BooleanResultInfo::Disjoint | BooleanResultInfo::InvalidInput => keep.push(h),
                BooleanResultInfo::Pline1InsidePline2 => {
                    cur = h;
                    merged = true;
                }
                BooleanResultInfo::Pline2InsidePline1 | BooleanResultInfo::Overlapping => {
                    merged = true;
                }
                BooleanResultInfo::Intersected => {
                    if let Some(first) = r.pos_plines.first() {
                        cur = oriented(&from_pline(&first.pline), true);
                    }
                    enclosed.extend(
                        r.neg_plines
                            .iter()
                            .map(|q| oriented(&from_pline(&q.pline), true)),
                    );
                    merged = true;
                }
            }
        }
        pending = keep;
        if !merged {
            rest.append(&mut pending);
            break;
        }
    }
    rest.push(cur);
    rest
}

/// Areas from counter-clockwise outer boundaries and holes (any orientation): each hole goes
/// to the smallest outer boundary around it.
fn assemble(outers: Vec<Profile>, holes: Vec<Profile>) -> Region {
    let mut areas: Vec<Area> = outers
        .into_iter()
        .filter(usable)
        .map(|o| Area {
            outer: oriented(&o, true),
            islands: Vec::new(),
        })
        .collect();
    for h in holes.into_iter().filter(usable) {
        let q = interior_probe(&h);
        let mut best: Option<(usize, f64)> = None;
        for (i, a) in areas.iter().enumerate() {
            if winding(&a.outer, q) != 0 {
                let s = signed_area(&a.outer).abs();
                if best.is_none_or(|(_, b)| s < b) {
                    best = Some((i, s));
                }
            }
        }
        if let Some((i, _)) = best
            && let Some(a) = areas.get_mut(i)
        {
            a.islands.push(oriented(&h, false));
        }
    }
    Region { areas }
}

/// A point of the boundary `p` (the midpoint of its first element): used to test nesting of
/// boundaries that do not cross.
fn interior_probe(p: &Profile) -> DVec2 {
    p.elements()
        .first()
        .map_or(DVec2::ZERO, |e| e.point_at(0.5))
}
