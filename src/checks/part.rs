//! The whole part as check: the tool (cutting end, flutes, and with `whole_tool` the shank and
//! holder) against every face of the part, through the part's triangle mesh and its hierarchy.
//! The drive faces are left out (the exact checks in [`super::gouge`] test them against the
//! exact surface); every other face counts, so a neighbouring wall or fillet that the tool
//! enters is found and named.
//!
//! The tool is a union of convex solids of revolution: the cutting solid (cutting end plus
//! flute cylinder, convex for every cutter kind) and one cylinder per shank and holder section.
//! The signed distance to a convex solid is a convex function of the point, so its minimum over
//! a (flat) triangle is found exactly by nested golden-section searches over the triangle's
//! parameters `p(s, t) = (1 − s)·a + s·((1 − t)·b + t·c)` (for fixed `s` the point runs on a
//! segment; the minimum over that segment is convex in `s`). A triangle is skipped first where
//! a lower bound of the signed distance over it rules out a depth beyond the tolerance (or
//! beyond the deepest found): its bounding sphere's distance (the distance is 1-Lipschitz) or
//! its distance to the axis segment of a capsule holding the piece less the capsule's radius
//! (a ball end's capsule starts at its centre). The rest are searched by that bound, most promising first.
//! Depth = −(minimum signed distance).
//!
//! The mesh is the exact faces within the tessellation's chord tolerance, so depths up to that
//! tolerance are not reported (give it as [`PartCheck::tolerance_mm`]). Along a move,
//! placements are checked at steps in which no tool point moves more than `step_mm`: a gouge
//! missed between them is at most `step_mm / 2` deep.

use glam::DVec3;
use rayon::prelude::*;

use super::motion::{Placement, cutting_moves, interpolate, motion_bound};
use crate::geometry::Aabb;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::geometry::tessellate::TessellationOptions;
use crate::import::Workpiece;
use crate::toolpath::Pose;
use crate::tools::Cutter;
use crate::tools::solid::{ToolPart, ToolSolid};

/// The part to check against: its mesh, hierarchy and face of each triangle, the faces left
/// out, and the depth below which nothing is reported.
#[derive(Clone, Copy, Debug)]
pub struct PartCheck<'a> {
    /// The part's triangles, mm.
    pub mesh: &'a TriMesh,
    /// Their hierarchy.
    pub bvh: &'a MeshBvh,
    /// For each triangle, its face index.
    pub face_of_triangle: &'a [u32],
    /// Faces not checked here (the drive faces, checked exactly elsewhere).
    pub skip_faces: &'a [usize],
    /// Depths up to this are not reported, mm (at least the tessellation's chord tolerance).
    pub tolerance_mm: f64,
    /// Along moves: largest motion of any tool point between checked placements, mm.
    pub step_mm: f64,
    /// Check the shank and holder as well as the fluted part.
    pub whole_tool: bool,
}

impl<'a> PartCheck<'a> {
    /// The check of a workpiece (its mesh and `bvh`), leaving out `skip_faces`: whole tool,
    /// 0.25 mm motion steps, tolerance = the chord tolerance `talas` tessellates a part of
    /// this size with, plus 1 µm.
    #[must_use]
    pub fn of_workpiece(wp: &'a Workpiece, bvh: &'a MeshBvh, skip_faces: &'a [usize]) -> Self {
        let diagonal = wp
            .part
            .as_ref()
            .map_or_else(|| bvh.bbox().diagonal(), |p| p.rough_bbox().diagonal());
        Self {
            mesh: &wp.mesh,
            bvh,
            face_of_triangle: &wp.face_of_triangle,
            skip_faces,
            tolerance_mm: TessellationOptions::for_size(diagonal).chord_tol_mm + 1e-3,
            step_mm: 0.25,
            whole_tool: true,
        }
    }
}

/// The deepest entry at one placement: (point, depth mm, face, tool part).
pub type PlacementHit = (DVec3, f64, usize, ToolPart);

/// Where the tool enters another face of the part.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PartHit {
    /// Index of the pose (the move into it when `move_param` < 1).
    pub pose: usize,
    /// Parameter along the move into the pose where it is deepest (1 = at the pose).
    pub move_param: f64,
    /// Deepest point of the part inside the tool, mm.
    pub point: DVec3,
    /// Depth, mm (> tolerance).
    pub depth_mm: f64,
    /// The face it lies on.
    pub face: usize,
    /// The tool part it is in.
    pub tool_part: ToolPart,
}

/// The hits of a whole path.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct PartReport {
    /// One entry per pose whose move (or the pose itself) enters another face: the deepest.
    pub hits: Vec<PartHit>,
    /// Largest depth, mm (0 when none).
    pub max_depth_mm: f64,
    /// Placements checked.
    pub placements: usize,
    /// Bound on a hit missed between checked placements, mm (`step_mm / 2`).
    pub bound_mm: f64,
}

/// One convex piece of the tool, in the tool frame (tip at the origin, axis +z).
#[derive(Clone, Debug)]
enum Convex {
    /// The cutting solid, and the height from which the capsule holding it starts (a ball
    /// end: its centre; else the tip).
    Cutting(ToolSolid, f64),
    /// A cylinder of `radius` from `z0` to `z1`.
    Cylinder { z0: f64, z1: f64, radius: f64 },
}

impl Convex {
    fn signed_distance(&self, rho: f64, z: f64) -> f64 {
        match self {
            Self::Cutting(s, _) => s.signed_distance_rz(rho, z),
            Self::Cylinder { z0, z1, radius } => {
                let dx = rho - radius;
                let dz = (z0 - z).max(z - z1);
                if dx <= 0.0 && dz <= 0.0 {
                    dx.max(dz)
                } else {
                    dx.max(0.0).hypot(dz.max(0.0))
                }
            }
        }
    }

    /// Height range and radius bounding the piece.
    fn extent(&self) -> (f64, f64, f64) {
        match self {
            Self::Cutting(s, _) => (0.0, s.top(), s.max_radius()),
            Self::Cylinder { z0, z1, radius } => (*z0, *z1, *radius),
        }
    }

    /// A capsule holding the piece: the segment of the axis (heights) and the radius.
    fn capsule(&self) -> (f64, f64, f64) {
        match self {
            Self::Cutting(s, start) => (*start, s.top(), s.max_radius()),
            Self::Cylinder { z0, z1, radius } => (*z0, *z1, *radius),
        }
    }
}

/// The tool as convex pieces, each with the tool part it is.
#[derive(Clone, Debug)]
pub struct ToolPieces {
    pieces: Vec<(Convex, ToolPart)>,
    top: f64,
    radius: f64,
}

impl ToolPieces {
    /// The pieces of `cutter`: the cutting solid, then (with `whole_tool`) the shank and every
    /// holder section as cylinders.
    #[must_use]
    pub fn of(cutter: &Cutter, whole_tool: bool) -> Self {
        let cutting = cutter.cutting_solid();
        let mut top = cutting.top();
        let mut radius = cutting.max_radius();
        // A ball end below its centre lies within its radius of the centre.
        let start = if cutter.kind == crate::tools::CutterKind::Ball {
            cutter.radius().clamp(0.0, top)
        } else {
            0.0
        };
        let mut pieces = vec![(Convex::Cutting(cutting, start), ToolPart::CuttingEnd)];
        if whole_tool {
            let mut z = cutter.flute_length;
            let mut push = |z0: f64, z1: f64, r: f64, part: ToolPart| {
                if z1 > z0 && r > 0.0 {
                    pieces.push((Convex::Cylinder { z0, z1, radius: r }, part));
                    top = top.max(z1);
                    radius = radius.max(r);
                }
            };
            push(
                z,
                cutter.overall_length,
                0.5 * cutter.shank_diameter,
                ToolPart::Shank,
            );
            z = z.max(cutter.overall_length);
            for (i, h) in cutter.holder.iter().enumerate() {
                push(z, z + h.length, 0.5 * h.diameter, ToolPart::Holder(i));
                z += h.length;
            }
        }
        Self {
            pieces,
            top,
            radius,
        }
    }

    /// Height of the top of the tool above the tip, mm.
    #[must_use]
    pub fn top(&self) -> f64 {
        self.top
    }

    /// Largest radius of the tool's pieces, mm.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }
}

/// Signed distance of part-space `p` to `piece` placed at (`tip`, unit `axis`).
fn sd_at(piece: &Convex, p: DVec3, tip: DVec3, axis: DVec3) -> f64 {
    let d = p - tip;
    let z = d.dot(axis);
    let rho = (d - axis * z).length();
    piece.signed_distance(rho, z)
}

/// World box of a piece placed at (`tip`, `axis`), grown by `margin`.
fn piece_box(piece: &Convex, tip: DVec3, axis: DVec3, margin: f64) -> Aabb {
    let (z0, z1, r) = piece.extent();
    let a = tip + axis * z0;
    let b = tip + axis * z1;
    let grow = DVec3::new(
        (1.0 - axis.x * axis.x).max(0.0).sqrt(),
        (1.0 - axis.y * axis.y).max(0.0).sqrt(),
        (1.0 - axis.z * axis.z).max(0.0).sqrt(),
    ) * r
        + DVec3::splat(margin);
    Aabb {
        min: a.min(b) - grow,
        max: a.max(b) + grow,
    }
}

/// A lower bound of `piece`'s signed distance over triangle `tri` (the piece placed at
/// (`tip`, `axis`)): the distance from the triangle to the axis segment of a capsule holding
/// the piece ([`Convex::capsule`]), less the capsule's radius. A convex solid's signed distance
/// is never below that of a convex solid holding it.
fn capsule_bound(piece: &Convex, tip: DVec3, axis: DVec3, tri: [DVec3; 3]) -> f64 {
    let (z0, z1, r) = piece.capsule();
    let d = segment_triangle_distance(tip + axis * z0, tip + axis * z1, tri);
    // Rounding of the closest-point arithmetic: a margin far below any tolerance.
    if d.is_finite() {
        d - r - 1e-7
    } else {
        f64::NEG_INFINITY
    }
}

/// Distance between segment `[p, q]` and triangle `tri`: 0 where the segment crosses it, else
/// the least of the ends' distances to the triangle and the segment's distances to its edges.
fn segment_triangle_distance(p: DVec3, q: DVec3, tri: [DVec3; 3]) -> f64 {
    let [a, b, c] = tri;
    let n = (b - a).cross(c - a);
    let (dp, dq) = ((p - a).dot(n), (q - a).dot(n));
    let mut best = point_triangle_distance(p, tri).min(point_triangle_distance(q, tri));
    if dp * dq < 0.0 {
        let x = p + (q - p) * (dp / (dp - dq));
        best = best.min(point_triangle_distance(x, tri));
    }
    for (e0, e1) in [(a, b), (b, c), (c, a)] {
        best = best.min(segment_distance(p, q, e0, e1));
    }
    best
}

/// Distance from `p` to triangle `[a, b, c]` (closest point by the triangle's Voronoi regions);
/// NaN-free for a degenerate triangle only through its edges, so `+∞` is returned there and the
/// edges decide.
fn point_triangle_distance(p: DVec3, [a, b, c]: [DVec3; 3]) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return p.distance(a);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return p.distance(b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return p.distance(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return p.distance(c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return p.distance(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return p.distance(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let sum = va + vb + vc;
    if sum.abs() < 1e-300 {
        return f64::INFINITY;
    }
    let d = p.distance(a + ab * (vb / sum) + ac * (vc / sum));
    if d.is_finite() { d } else { f64::INFINITY }
}

/// Distance between segments `[p1, q1]` and `[p2, q2]` (closest points by clamped parameters).
fn segment_distance(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(r));
    let tiny = 1e-30;
    let (s, t) = if a <= tiny && e <= tiny {
        (0.0, 0.0)
    } else if a <= tiny {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= tiny {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let s = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t = (b * s + f) / e;
            if t < 0.0 {
                ((-c / a).clamp(0.0, 1.0), 0.0)
            } else if t > 1.0 {
                (((b - c) / a).clamp(0.0, 1.0), 1.0)
            } else {
                (s, t)
            }
        }
    };
    (p1 + d1 * s).distance(p2 + d2 * t)
}

/// A candidate triangle of [`PartCheck::placement`]: the lower bound of the signed distance
/// over it, its key (piece, place in the piece's candidates), corners and face.
struct Bounded {
    bound: f64,
    key: (usize, usize),
    tri: [DVec3; 3],
    face: usize,
}

/// Minimum of a convex `f` on [0, 1] by golden section to `tol`: (argmin, min).
fn golden(f: impl Fn(f64) -> f64, tol: f64) -> (f64, f64) {
    let steps = crate::geometry::minimize::golden_iterations(1.0, tol, 200);
    crate::geometry::minimize::golden_point(0.0, 1.0, steps, f)
}

/// Least signed distance of triangle `[a, b, c]` to a convex `sd`: (point, distance). Exact for
/// a convex function up to 1e-5 of the triangle's size.
fn triangle_min(tri: [DVec3; 3], sd: impl Fn(DVec3) -> f64) -> (DVec3, f64) {
    let [a, b, c] = tri;
    let size = (b - a).length().max((c - a).length()).max(1e-12);
    let tol = (1e-5 / size).clamp(1e-9, 1e-3);
    let at = |s: f64, t: f64| a * (1.0 - s) + (b * (1.0 - t) + c * t) * s;
    let inner = |s: f64| golden(|t| sd(at(s, t)), tol);
    let (s, _) = golden(|s| inner(s).1, tol);
    let (t, v) = inner(s);
    (at(s, t), v)
}

impl PartCheck<'_> {
    /// The triangles (source index, corners, face) near `piece` placed at (`tip`, `axis`),
    /// outside the skipped faces.
    fn candidates(
        &self,
        piece: &Convex,
        tip: DVec3,
        axis: DVec3,
    ) -> impl Iterator<Item = ([DVec3; 3], usize)> + '_ {
        let bx = piece_box(piece, tip, axis, self.tolerance_mm.max(0.0));
        self.bvh.triangles_in_aabb(&bx).into_iter().filter_map(|t| {
            let face = self.face_of_triangle.get(t).map_or(0, |&f| f as usize);
            if self.skip_faces.contains(&face) {
                return None;
            }
            Some((self.mesh.triangle_corners(t)?, face))
        })
    }

    /// The deepest point of the part (outside the skipped faces) inside the tool placed at
    /// (`tip`, unit `axis`), when deeper than the tolerance: (point, depth, face, tool part).
    /// The triangles are searched in the order of their lower bounds (most promising first), so
    /// the deepest found early skips the rest; of equal depths the first piece's, lowest
    /// triangle's wins, so the result does not depend on that order.
    #[must_use]
    pub fn placement(&self, tool: &ToolPieces, tip: DVec3, axis: DVec3) -> Option<PlacementHit> {
        let tol = self.tolerance_mm.max(0.0);
        let mut order = self.bounded(tool, tip, axis, tol);
        order.sort_by(|a, b| a.bound.total_cmp(&b.bound));
        let mut best: Option<(PlacementHit, (usize, usize))> = None;
        for c in &order {
            // Lower bound of the distance over the triangle (1-Lipschitz): it cannot be deeper
            // than the tolerance or than the deepest found (nor can any later one).
            let floor = tol.max(best.map_or(0.0, |b| b.0.1));
            if c.bound > -floor {
                break;
            }
            let (piece, part) = &tool.pieces[c.key.0];
            let (p, d) = triangle_min(c.tri, |q| sd_at(piece, q, tip, axis));
            let depth = -d;
            let wins = best.is_none_or(|(b, key)| depth > b.1 || (depth == b.1 && c.key < key));
            if depth > tol && wins {
                best = Some(((p, depth, c.face, *part), c.key));
            }
        }
        best.map(|b| b.0)
    }

    /// Every candidate triangle of every piece whose lower bound (the larger of `sd(centre) −
    /// reach`, the distance being 1-Lipschitz, and [`capsule_bound`]) does not rule out a depth
    /// beyond `tol`.
    fn bounded(&self, tool: &ToolPieces, tip: DVec3, axis: DVec3, tol: f64) -> Vec<Bounded> {
        let mut out = Vec::new();
        for (k, (piece, _)) in tool.pieces.iter().enumerate() {
            for (i, (tri, face)) in self.candidates(piece, tip, axis).enumerate() {
                let centre = (tri[0] + tri[1] + tri[2]) / 3.0;
                let reach = tri.iter().fold(0.0_f64, |m, v| m.max(v.distance(centre)));
                let bound = sd_at(piece, centre, tip, axis) - reach;
                let bound = if bound <= -tol {
                    bound.max(capsule_bound(piece, tip, axis, tri))
                } else {
                    bound
                };
                if bound <= -tol {
                    out.push(Bounded {
                        bound,
                        key: (k, i),
                        tri,
                        face,
                    });
                }
            }
        }
        out
    }

    /// Whether the tool placed at (`tip`, unit `axis`) enters the part (outside the skipped
    /// faces) deeper than the tolerance: as [`Self::placement`] is `Some`, faster where the
    /// tool is deep in the part (a triangle's corner or centre inside answers at once, and the
    /// search ends at the first triangle found deeper than the tolerance).
    #[must_use]
    pub fn enters(&self, tool: &ToolPieces, tip: DVec3, axis: DVec3) -> bool {
        let tol = self.tolerance_mm.max(0.0);
        let mut doubtful = Vec::new();
        for (k, (piece, _)) in tool.pieces.iter().enumerate() {
            for (tri, _) in self.candidates(piece, tip, axis) {
                let centre = (tri[0] + tri[1] + tri[2]) / 3.0;
                let c = sd_at(piece, centre, tip, axis);
                if c < -tol || tri.iter().any(|&v| sd_at(piece, v, tip, axis) < -tol) {
                    return true;
                }
                let reach = tri.iter().fold(0.0_f64, |m, v| m.max(v.distance(centre)));
                if c - reach <= -tol {
                    let bound = (c - reach).max(capsule_bound(piece, tip, axis, tri));
                    if bound <= -tol {
                        doubtful.push((bound, k, tri));
                    }
                }
            }
        }
        // `placement` is `Some` exactly when one of these triangles' minimum is below −tol.
        doubtful.sort_by(|a, b| a.0.total_cmp(&b.0));
        doubtful.iter().any(|&(_, k, tri)| {
            let piece = &tool.pieces[k].0;
            triangle_min(tri, |q| sd_at(piece, q, tip, axis)).1 < -tol
        })
    }

    /// Check every cutting pose and move of `poses` (in parallel): the deepest hit per pose.
    #[must_use]
    pub fn check_path(&self, cutter: &Cutter, poses: &[Pose]) -> PartReport {
        let tool = ToolPieces::of(cutter, self.whole_tool);
        let step = if self.step_mm.is_finite() && self.step_mm > 0.0 {
            self.step_mm
        } else {
            0.1
        };
        let moves = cutting_moves(poses);
        let results: Vec<(Option<PartHit>, usize)> = moves
            .par_iter()
            .map(|&(i0, i1)| {
                let (Some(a), Some(b)) = (poses.get(i0), poses.get(i1)) else {
                    return (None, 0);
                };
                self.move_hits(&tool, a, b, i1, step, i0 == i1)
            })
            .collect();
        let placements = results.iter().map(|r| r.1).sum();
        let hits: Vec<PartHit> = results.into_iter().filter_map(|r| r.0).collect();
        let max_depth_mm = hits.iter().fold(0.0_f64, |m, h| m.max(h.depth_mm));
        PartReport {
            hits,
            max_depth_mm,
            placements,
            bound_mm: 0.5 * step,
        }
    }

    fn move_hits(
        &self,
        tool: &ToolPieces,
        a: &Pose,
        b: &Pose,
        index: usize,
        step: f64,
        single: bool,
    ) -> (Option<PartHit>, usize) {
        let (Some(aa), Some(ba)) = (a.axis.try_normalize(), b.axis.try_normalize()) else {
            return (None, 0);
        };
        let pa = Placement {
            tip: a.tip,
            axis: aa,
        };
        let pb = Placement {
            tip: b.tip,
            axis: ba,
        };
        let steps = if single {
            1
        } else {
            (motion_bound(pa, pb, tool.top, tool.radius) / step)
                .ceil()
                .clamp(1.0, 1e5) as usize
        };
        let mut best: Option<PartHit> = None;
        for k in 1..=steps {
            let s = k as f64 / steps as f64;
            let q = interpolate(pa, pb, s);
            if let Some((point, depth_mm, face, tool_part)) = self.placement(tool, q.tip, q.axis)
                && best.is_none_or(|h| depth_mm > h.depth_mm)
            {
                best = Some(PartHit {
                    pose: index,
                    move_param: s,
                    point,
                    depth_mm,
                    face,
                    tool_part,
                });
            }
        }
        (best, steps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::CutterKind;

    #[test]
    fn cylinder_distance_is_the_box_distance_in_the_meridian() {
        let c = Convex::Cylinder {
            z0: 10.0,
            z1: 20.0,
            radius: 3.0,
        };
        assert!((c.signed_distance(0.0, 15.0) + 3.0).abs() < 1e-12);
        assert!((c.signed_distance(2.0, 11.0) + 1.0).abs() < 1e-12);
        assert!((c.signed_distance(7.0, 15.0) - 4.0).abs() < 1e-12);
        assert!((c.signed_distance(6.0, 24.0) - 5.0).abs() < 1e-12);
        assert!((c.signed_distance(1.0, 8.0) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn triangle_minimum_of_a_ball_is_the_closed_form() {
        // A ball of radius 3 (centre at z = 3) above the plane z = 0.5: depth 0.5 at (0, 0).
        let cutter = Cutter::new(CutterKind::Ball, 6.0).expect("valid");
        let tool = ToolPieces::of(&cutter, false);
        let piece = &tool.pieces[0].0;
        let tri = [
            DVec3::new(-20.0, -10.0, 0.5),
            DVec3::new(30.0, -7.0, 0.5),
            DVec3::new(1.0, 25.0, 0.5),
        ];
        let (p, d) = triangle_min(tri, |q| sd_at(piece, q, DVec3::ZERO, DVec3::Z));
        assert!((d + 0.5).abs() < 1e-6, "{d}");
        assert!(p.truncate().length() < 1e-3, "{p}");
        // Tilted 30° about x: the ball centre moves, the depth is measured from it.
        let axis = DVec3::new(0.0, -0.5, 3f64.sqrt() / 2.0);
        let centre = axis * 3.0;
        let (_, d) = triangle_min(tri, |q| sd_at(piece, q, DVec3::ZERO, axis));
        let want = -(3.0 - (centre.z - 0.5));
        assert!((d - want).abs() < 1e-6, "{d} {want}");
    }

    #[test]
    fn segment_triangle_distance_matches_sampling() {
        // Independent: the least distance between sample points of the segment and of the
        // triangle (an upper bound, within the sampling's spacing of the true distance).
        let mut seed = 12_345_u64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 10.0 - 5.0
        };
        for _ in 0..40 {
            let mut v = || DVec3::new(next(), next(), next());
            let tri = [v(), v(), v()];
            let (p, q) = (v(), v());
            let d = segment_triangle_distance(p, q, tri);
            let n = 60;
            let mut sampled = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=n - i {
                    let (u, w) = (i as f64 / n as f64, j as f64 / n as f64);
                    let x = tri[0] + (tri[1] - tri[0]) * u + (tri[2] - tri[0]) * w;
                    for k in 0..=n {
                        let y = p.lerp(q, k as f64 / n as f64);
                        sampled = sampled.min(x.distance(y));
                    }
                }
            }
            assert!(d <= sampled + 1e-9, "{d} above sampled {sampled}");
            assert!(d >= sampled - 0.5, "{d} far below sampled {sampled}");
        }
        // A segment through the triangle: 0; one above it: the height.
        let tri = [DVec3::ZERO, DVec3::X * 4.0, DVec3::Y * 4.0];
        let through =
            segment_triangle_distance(DVec3::new(1.0, 1.0, -1.0), DVec3::new(1.0, 1.0, 1.0), tri);
        assert!(through.abs() < 1e-12, "{through}");
        let above =
            segment_triangle_distance(DVec3::new(1.0, 1.0, 2.0), DVec3::new(3.0, -1.0, 2.5), tri);
        assert!((above - 2.0).abs() < 1e-12, "{above}");
    }
}
