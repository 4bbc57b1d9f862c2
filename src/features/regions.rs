//! Machinable regions of a B-rep seen from +Z: flat floors with their walls (closed pockets,
//! open pockets, steps, slots), the part's top faces and its outer profile.
//!
//! A face is a *floor* when it is flat and horizontal, whatever its surface type (a plane, or a
//! B-spline or extrusion whose tessellation lies in one height within 1e-6 mm, as some CAD
//! systems write flat faces): its height is the mean of its B-rep vertices (exact as the file
//! gives them). Whether it faces up, and is reachable from +Z, is decided by the part's mesh,
//! not by the file's normals (which some writers reverse): a vertical ray from just above a
//! point inside the floor crosses no triangle when the floor is open to +Z, an odd number of
//! triangles when the floor is a ceiling. Floors at one height that share an edge form one
//! region. Each boundary edge of a region is a *wall* when the face across it rises above
//! the floor, an *open side* otherwise (it falls away: the part's outline, a step's edge).
//! The region itself is built from the exact edges (lines, arcs about Z), so its area and
//! corner radii are exact; other edges are sampled (64 chords).

use glam::{DVec2, DVec3};

use super::holes::{Hole, HoleBottom, HoleOptions, recognize_holes};
use crate::geometry::brep::{Loop, Part, face_adjacency};
use crate::geometry::curve::CurveGeom;
use crate::geometry::planar::{BooleanOp, Element, Profile, Region, Vertex, signed_area};
use crate::geometry::tessellate::{PartMesh, TessellationOptions, tessellate_part};

/// Heights within this are one height, mm.
const Z_TOL_MM: f64 = 1e-6;
/// A face across a boundary edge is a wall when it rises this far above the floor, mm.
const WALL_RISE_MM: f64 = 1e-4;

/// What a region is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RegionKind {
    /// A floor at the part's top height (a face to face, no walls above it).
    Top,
    /// A floor walled on every side.
    ClosedPocket,
    /// A floor with open sides that is neither a step nor a slot (walls on most sides, or
    /// several runs of wall).
    OpenPocket,
    /// A floor with one run of wall that turns less than 135° and the rest open: a step.
    Step,
    /// A floor between two runs of wall with two open ends, no islands.
    Slot,
    /// The outline of the part seen from +Z (its lowest down-facing flat face).
    OuterProfile,
}

/// One machinable region.
#[derive(Clone, Debug, serde::Serialize)]
pub struct MachinableRegion {
    /// What it is.
    pub kind: RegionKind,
    /// The B-rep faces of its floor (indices into `Part::faces`).
    pub faces: Vec<usize>,
    /// Floor height, mm.
    pub floor_z_mm: f64,
    /// Height of the highest wall around it (the part's top for the outer profile), mm.
    pub top_z_mm: f64,
    /// `top_z_mm − floor_z_mm`, mm.
    pub depth_mm: f64,
    /// Floor area, islands taken out, mm².
    pub area_mm2: f64,
    /// Smallest radius of a corner between walls that a tool in the region must turn inside
    /// (0 at a sharp corner), mm; `None` when there is no such corner.
    pub smallest_corner_radius_mm: Option<f64>,
    /// Number of islands (inner boundaries of the floor).
    pub islands: usize,
    /// Number of open runs along the boundary.
    pub open_sides: usize,
    /// Bounding box of the floor in x, y: `[x0, y0, x1, y1]`, mm.
    pub bbox_mm: [f64; 4],
    /// The floor as a region (exact lines and arcs).
    pub region: Region,
}

/// The regions found and what was skipped.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct RegionReport {
    /// Regions, by kind then floor height (highest first) then position.
    pub regions: Vec<MachinableRegion>,
    /// Faces that are flat and horizontal but not reachable from +Z (under an overhang), or
    /// whose boundary could not be built, with the reason.
    pub skipped: Vec<String>,
}

/// One edge of a floor loop projected to XY: its vertices (bulges set) and whether the face
/// across it is a wall.
struct LoopEdge {
    verts: Vec<Vertex>,
    wall: bool,
    /// The edge is shared with another floor face of the same region.
    internal: bool,
}

/// Finds the regions of `part` seen from +Z.
#[must_use]
pub fn find_regions(part: &Part) -> RegionReport {
    let mesh = tessellate_part(
        part,
        &TessellationOptions {
            chord_tol_mm: 0.05,
            ..TessellationOptions::default()
        },
    );
    find_regions_with_mesh(part, &mesh)
}

/// As [`find_regions`] with the part's mesh already made.
#[must_use]
pub fn find_regions_with_mesh(part: &Part, mesh: &PartMesh) -> RegionReport {
    let mut report = RegionReport::default();
    let n = part.faces.len();
    let z_range: Vec<(f64, f64)> = (0..n).map(|f| face_z_range(mesh, f)).collect();
    let Some(top) = z_range
        .iter()
        .map(|r| r.1)
        .filter(|z| z.is_finite())
        .max_by(f64::total_cmp)
    else {
        return report;
    };
    // Flat horizontal faces and which way they face.
    let mut floor_z: Vec<Option<f64>> = vec![None; n];
    let mut bottom: Option<(usize, f64, f64)> = None; // (face, z, area)
    for (f, &(lo, hi)) in z_range.iter().enumerate() {
        if !(lo.is_finite() && hi - lo <= Z_TOL_MM.max(1e-9 * hi.abs())) {
            continue;
        }
        let z = vertex_mean_z(part, f).unwrap_or(0.5 * (lo + hi));
        let Some(probe) = probe_point(mesh, f) else {
            continue;
        };
        // Off the mesh's edges and vertices by an amount no drawn geometry has.
        let q = probe + DVec2::new(1.234_567e-7, 2.718_281e-7);
        let above = crossings(mesh, DVec3::new(q.x, q.y, z + 1e-3), f, true);
        let below = crossings(mesh, DVec3::new(q.x, q.y, z - 1e-3), f, false);
        if above == 0 && below % 2 == 1 {
            if let Some(slot) = floor_z.get_mut(f) {
                *slot = Some(z);
            }
        } else if below == 0 && above % 2 == 1 {
            let a = mesh.faces.get(f).map_or(0.0, |r| r.area_mm2);
            if bottom
                .is_none_or(|(_, bz, ba)| z < bz - Z_TOL_MM || (z - bz).abs() <= Z_TOL_MM && a > ba)
            {
                bottom = Some((f, z, a));
            }
        } else if above.is_multiple_of(2) && below % 2 == 1 {
            report.skipped.push(format!(
                "face {} (#{}): flat floor at z = {z:.6} mm under material, not reachable from +Z",
                f + 1,
                part.faces.get(f).map_or(0, |x| x.source_id)
            ));
        }
    }
    // Edge → the faces using it.
    let adjacency = face_adjacency(part);
    let mut across: std::collections::HashMap<(usize, usize), usize> =
        std::collections::HashMap::new();
    for &(e, a, b) in &adjacency {
        across.insert((e, a), b);
        across.insert((e, b), a);
    }
    // Group floors of one height joined by an edge.
    let mut group: Vec<Option<usize>> = vec![None; n];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for f in 0..n {
        let Some(z) = floor_z.get(f).copied().flatten() else {
            continue;
        };
        if group.get(f).copied().flatten().is_some() {
            continue;
        }
        let gi = groups.len();
        let mut members = vec![f];
        if let Some(g) = group.get_mut(f) {
            *g = Some(gi);
        }
        let mut k = 0;
        while let Some(&cur) = members.get(k) {
            k += 1;
            for &(_, a, b) in &adjacency {
                let other = if a == cur {
                    b
                } else if b == cur {
                    a
                } else {
                    continue;
                };
                if group.get(other).copied().flatten().is_none()
                    && floor_z
                        .get(other)
                        .copied()
                        .flatten()
                        .is_some_and(|oz| (oz - z).abs() <= Z_TOL_MM)
                {
                    if let Some(g) = group.get_mut(other) {
                        *g = Some(gi);
                    }
                    members.push(other);
                }
            }
        }
        groups.push(members);
    }
    // Flat-bottomed holes (a disc floor walled by one full cylinder) are hole making's, not
    // pockets: their floors are left out with a note.
    let holes = recognize_holes(part, Some(mesh), &HoleOptions::default()).holes;
    for members in &groups {
        let Some(&first) = members.first() else {
            continue;
        };
        let Some(z) = floor_z.get(first).copied().flatten() else {
            continue;
        };
        match floor_region(part, mesh, members, z, &z_range, &across) {
            Ok(r) => match drilled_hole(&r, &holes) {
                Some(h) => report.skipped.push(format!(
                    "face {}: the floor of a flat-bottomed hole Ø{:.4} mm at ({:.4}, {:.4}) mm, \
                     {:.4} mm deep (hole making, not a pocket)",
                    first + 1,
                    h.diameter_mm,
                    h.top.x,
                    h.top.y,
                    h.depth_mm
                )),
                None => report.regions.push(r),
            },
            Err(e) => report.skipped.push(format!("face {}: {e}", first + 1)),
        }
    }
    for r in &mut report.regions {
        if (r.floor_z_mm - top).abs() <= 1e-3
            && r.open_sides > 0
            && r.top_z_mm <= r.floor_z_mm + WALL_RISE_MM
        {
            r.kind = RegionKind::Top;
        }
    }
    if let Some((f, z, _)) = bottom {
        match outer_profile(part, f, z, top) {
            Ok(r) => report.regions.push(r),
            Err(e) => report
                .skipped
                .push(format!("outer profile (face {}): {e}", f + 1)),
        }
    }
    report.regions.sort_by(|a, b| {
        (a.kind as u8)
            .cmp(&(b.kind as u8))
            .then(b.floor_z_mm.total_cmp(&a.floor_z_mm))
            .then(a.bbox_mm[0].total_cmp(&b.bbox_mm[0]))
            .then(a.bbox_mm[1].total_cmp(&b.bbox_mm[1]))
    });
    report
}

fn face_z_range(mesh: &PartMesh, f: usize) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    if let Some(r) = mesh.faces.get(f) {
        for t in r.first..r.first + r.count {
            if let Some(c) = mesh.mesh.triangle_corners(t) {
                for p in c {
                    lo = lo.min(p.z);
                    hi = hi.max(p.z);
                }
            }
        }
    }
    (lo, hi)
}

fn vertex_mean_z(part: &Part, f: usize) -> Option<f64> {
    let face = part.faces.get(f)?;
    let mut sum = 0.0;
    let mut k = 0usize;
    for l in &face.loops {
        if let Loop::Edges(es) = l {
            for oe in es {
                let e = part.edges.get(oe.edge)?;
                let v = part
                    .vertices
                    .get(if oe.forward { e.start } else { e.end })?;
                sum += v.point.z;
                k += 1;
            }
        }
    }
    (k > 0).then(|| sum / k as f64)
}

/// The centroid of the face's largest triangle.
fn probe_point(mesh: &PartMesh, f: usize) -> Option<DVec2> {
    let r = mesh.faces.get(f)?;
    let mut best: Option<(f64, DVec2)> = None;
    for t in r.first..r.first + r.count {
        let c = mesh.mesh.triangle_corners(t)?;
        let a = (c[1] - c[0]).cross(c[2] - c[0]).length();
        if best.is_none_or(|(ba, _)| a > ba) {
            let m = (c[0] + c[1] + c[2]) / 3.0;
            best = Some((a, DVec2::new(m.x, m.y)));
        }
    }
    best.map(|b| b.1)
}

/// Triangles (not of face `skip`) that a vertical ray from `p` crosses, upward or downward.
fn crossings(mesh: &PartMesh, p: DVec3, skip: usize, up: bool) -> usize {
    let mut count = 0;
    for (t, tri) in mesh.mesh.triangles.iter().enumerate() {
        if mesh.face_of_triangle.get(t).copied() == Some(skip as u32) {
            continue;
        }
        let _ = tri;
        let Some(c) = mesh.mesh.triangle_corners(t) else {
            continue;
        };
        let (a, b, cc) = (c[0].truncate(), c[1].truncate(), c[2].truncate());
        let q = p.truncate();
        let area = (b - a).perp_dot(cc - a);
        if area.abs() < 1e-12 {
            continue;
        }
        let w0 = (b - q).perp_dot(cc - q) / area;
        let w1 = (cc - q).perp_dot(a - q) / area;
        let w2 = 1.0 - w0 - w1;
        // The probe is moved off the mesh's edges (below), so strict insideness counts a
        // crossing once.
        if !(w0 > 0.0 && w1 > 0.0 && w2 > 0.0) {
            continue;
        }
        let z = w0 * c[0].z + w1 * c[1].z + w2 * c[2].z;
        if (up && z > p.z) || (!up && z < p.z) {
            count += 1;
        }
    }
    count
}

/// One edge of a loop in XY: the edge, its vertices (bulges set), its midpoint (3D) and unit
/// tangent (XY) in the loop's direction.
type EdgeXy = (usize, Vec<Vertex>, DVec3, DVec2);

/// True when the side of a floor edge away from the floor is material just above the floor:
/// a point 0.1 mm beside the edge's midpoint, outside the floor region, and 0.1 mm above the
/// floor lies inside the solid (an odd number of mesh crossings on a vertical ray). 0.1 mm is
/// twice the mesh's chord tolerance, so a wall's chords never put the point on the wrong side.
fn side_is_material(mesh: &PartMesh, floor: &Region, mid: DVec3, tangent: DVec2, z: f64) -> bool {
    let n = tangent.perp();
    let a = mid.truncate() + n * 0.1;
    let b = mid.truncate() - n * 0.1;
    let out = if floor.contains(a) && !floor.contains(b) {
        b
    } else if floor.contains(b) && !floor.contains(a) {
        a
    } else {
        return false;
    };
    let q = out + DVec2::new(1.234_567e-7, 2.718_281e-7);
    crossings(mesh, DVec3::new(q.x, q.y, z + 0.1), usize::MAX, true) % 2 == 1
}

/// The edges of a loop projected to XY.
fn loop_edges(part: &Part, l: &Loop) -> Option<Vec<EdgeXy>> {
    let Loop::Edges(es) = l else {
        return None;
    };
    let mut out = Vec::with_capacity(es.len());
    for oe in es {
        let e = part.edges.get(oe.edge)?;
        let (t0, t1) = if oe.forward {
            (e.t_start, e.t_end)
        } else {
            (e.t_end, e.t_start)
        };
        let start = part
            .vertices
            .get(if oe.forward { e.start } else { e.end })?
            .point;
        let mut verts = Vec::new();
        match &e.curve {
            CurveGeom::Line(_) => verts.push(Vertex::point(start.x, start.y)),
            CurveGeom::Circle(c) if c.frame.z.z.abs() > 1.0 - 1e-9 => {
                let sweep = (t1 - t0) * c.frame.z.z.signum();
                let pieces = ((sweep.abs() / std::f64::consts::PI) - 1e-9)
                    .ceil()
                    .max(1.0) as usize;
                let bulge = (sweep / pieces as f64 / 4.0).tan();
                for k in 0..pieces {
                    let t = t0 + (t1 - t0) * k as f64 / pieces as f64;
                    let p = if k == 0 { start } else { e.curve.point(t) };
                    verts.push(Vertex {
                        x: p.x,
                        y: p.y,
                        bulge,
                    });
                }
            }
            curve => {
                let m = 64;
                for k in 0..m {
                    let p = if k == 0 {
                        start
                    } else {
                        curve.point(t0 + (t1 - t0) * k as f64 / m as f64)
                    };
                    verts.push(Vertex::point(p.x, p.y));
                }
            }
        }
        let tm = 0.5 * (t0 + t1);
        let h = 1e-4 * (t1 - t0);
        let mid = e.curve.point(tm);
        let d = (e.curve.point(tm + h) - e.curve.point(tm - h)).truncate();
        out.push((oe.edge, verts, mid, d.normalize_or_zero()));
    }
    Some(out)
}

fn floor_region(
    part: &Part,
    mesh: &PartMesh,
    members: &[usize],
    z: f64,
    z_range: &[(f64, f64)],
    across: &std::collections::HashMap<(usize, usize), usize>,
) -> Result<MachinableRegion, String> {
    let mut region = Region::empty();
    let mut loops: Vec<Vec<LoopEdge>> = Vec::new();
    let mut top = z;
    for &f in members {
        let face = part.faces.get(f).ok_or("no face")?;
        let all: Vec<Vec<EdgeXy>> = face
            .loops
            .iter()
            .filter_map(|l| loop_edges(part, l))
            .collect();
        let boundaries: Vec<Profile> = all
            .iter()
            .map(|edges| Profile {
                vertices: edges.iter().flat_map(|x| x.1.iter().copied()).collect(),
                closed: true,
            })
            .collect();
        let face_region = Region::from_boundaries(&boundaries).map_err(|e| e.to_string())?;
        for edges in all {
            let mut les = Vec::new();
            for (e, verts, mid, tangent) in edges {
                let other = across.get(&(e, f)).copied();
                let internal = other.is_some_and(|o| members.contains(&o));
                let wall = !internal && side_is_material(mesh, &face_region, mid, tangent, z);
                if wall {
                    let rise = other.and_then(|o| z_range.get(o)).map_or(z, |r| r.1);
                    top = top.max(rise);
                }
                les.push(LoopEdge {
                    verts,
                    wall,
                    internal,
                });
            }
            loops.push(les);
        }
        region = region.boolean(&face_region, BooleanOp::Union);
    }
    // Runs of open and wall edges along each loop (internal edges skipped).
    let mut open_runs = 0;
    let mut wall_runs = 0;
    let mut max_wall_turn: f64 = 0.0;
    let mut corner: Option<f64> = None;
    for les in &loops {
        let kinds: Vec<(bool, &LoopEdge)> = les
            .iter()
            .filter(|e| !e.internal)
            .map(|e| (e.wall, e))
            .collect();
        let m = kinds.len();
        if m == 0 {
            continue;
        }
        // The loop's orientation: face on the left when its signed area is positive.
        let p = Profile {
            vertices: les.iter().flat_map(|le| le.verts.iter().copied()).collect(),
            closed: true,
        };
        let sign = signed_area(&p).signum();
        let all_wall = kinds.iter().all(|k| k.0);
        let all_open = kinds.iter().all(|k| !k.0);
        if all_wall {
            wall_runs += 1;
        } else if all_open {
            open_runs += 1;
        } else {
            for i in 0..m {
                let (a, _) = kinds[i];
                let (b, _) = kinds[(i + 1) % m];
                if a != b {
                    if b {
                        wall_runs += 1;
                    } else {
                        open_runs += 1;
                    }
                }
            }
        }
        // Turning along walls, and corner radii between walls.
        let els = p.elements();
        let mut run_turn = 0.0f64;
        let mut edge_of_el = Vec::new();
        for (k, le) in les.iter().enumerate() {
            for _ in &le.verts {
                edge_of_el.push(k);
            }
        }
        let ne = els.len();
        for (i, el) in els.iter().enumerate() {
            let k = edge_of_el.get(i).copied().unwrap_or(0);
            let wall = les.get(k).is_some_and(|l| l.wall);
            if wall {
                let sweep = match *el {
                    Element::Arc {
                        sweep_rad, radius, ..
                    } => {
                        if sweep_rad * sign > 0.0 && les.get(k).is_some_and(|l| l.wall) {
                            corner = Some(corner.map_or(radius, |c| c.min(radius)));
                        }
                        sweep_rad
                    }
                    Element::Line { .. } => 0.0,
                };
                run_turn += sweep;
                let next_i = (i + 1) % ne;
                let nk = edge_of_el.get(next_i).copied().unwrap_or(0);
                let next_wall = les.get(nk).is_some_and(|l| l.wall);
                if let Some(next) = els.get(next_i) {
                    let t0 = el.tangent_at(1.0);
                    let t1 = next.tangent_at(0.0);
                    let turn = t0.perp_dot(t1).atan2(t0.dot(t1));
                    if next_wall {
                        run_turn += turn;
                        if turn * sign > 1e-3 {
                            corner = Some(0.0);
                        }
                    }
                }
            } else {
                max_wall_turn = max_wall_turn.max(run_turn.abs());
                run_turn = 0.0;
            }
        }
        max_wall_turn = max_wall_turn.max(run_turn.abs());
    }
    let islands = islands_of(&region);
    let kind = if open_runs == 0 {
        RegionKind::ClosedPocket
    } else if wall_runs == 0 {
        RegionKind::Top
    } else if wall_runs == 2 && open_runs == 2 && islands_of(&region) == 0 {
        RegionKind::Slot
    } else if wall_runs == 1 && max_wall_turn < 135f64.to_radians() {
        RegionKind::Step
    } else {
        RegionKind::OpenPocket
    };
    let (lo, hi) = region.bounds();
    let top = if wall_runs == 0 { z } else { top };
    Ok(MachinableRegion {
        kind,
        faces: members.to_vec(),
        floor_z_mm: z,
        top_z_mm: top,
        depth_mm: top - z,
        area_mm2: region.area_mm2(),
        smallest_corner_radius_mm: corner,
        islands,
        open_sides: open_runs,
        bbox_mm: [lo.x, lo.y, hi.x, hi.y],
        region,
    })
}

/// The recognised hole whose flat floor `r` is: a closed region without islands, its floor
/// faces among the hole's faces, the hole's axis vertical (entered from +Z), and the region a
/// full disc of the hole's diameter (area within 1e-6 relative, or 1e-6 mm²).
fn drilled_hole<'a>(r: &MachinableRegion, holes: &'a [Hole]) -> Option<&'a Hole> {
    if r.kind != RegionKind::ClosedPocket || r.islands > 0 || r.region.areas.len() != 1 {
        return None;
    }
    holes.iter().find(|h| {
        let disc = std::f64::consts::PI * 0.25 * h.diameter_mm * h.diameter_mm;
        h.direction.z > 1.0 - 1e-9
            && matches!(h.bottom, HoleBottom::Flat)
            && r.faces.iter().all(|f| h.faces.contains(f))
            && (r.area_mm2 - disc).abs() <= (1e-6 * disc).max(1e-6)
    })
}

fn islands_of(region: &Region) -> usize {
    region.areas.iter().map(|a| a.islands.len()).sum()
}

fn outer_profile(part: &Part, f: usize, z: f64, top: f64) -> Result<MachinableRegion, String> {
    let face = part.faces.get(f).ok_or("no face")?;
    let mut boundaries = Vec::new();
    for l in &face.loops {
        if let Some(edges) = loop_edges(part, l) {
            boundaries.push(Profile {
                vertices: edges.into_iter().flat_map(|x| x.1).collect(),
                closed: true,
            });
        }
    }
    // The outline is the largest boundary of the bottom face.
    let outline = boundaries
        .into_iter()
        .max_by(|a, b| signed_area(a).abs().total_cmp(&signed_area(b).abs()))
        .ok_or("the bottom face has no boundary")?;
    let region = Region::from_outline(&outline).map_err(|e| e.to_string())?;
    // Concave corners of the outline seen from outside: right turns of the ccw outline.
    let mut corner: Option<f64> = None;
    if let Some(a) = region.areas.first() {
        let els = a.outer.elements();
        let ne = els.len();
        for (i, el) in els.iter().enumerate() {
            if let Element::Arc {
                sweep_rad, radius, ..
            } = *el
                && sweep_rad < 0.0
            {
                corner = Some(corner.map_or(radius, |c| c.min(radius)));
            }
            if let Some(next) = els.get((i + 1) % ne) {
                let t0 = el.tangent_at(1.0);
                let t1 = next.tangent_at(0.0);
                if t0.perp_dot(t1) < -1e-6 {
                    corner = Some(0.0);
                }
            }
        }
    }
    let (lo, hi) = region.bounds();
    Ok(MachinableRegion {
        kind: RegionKind::OuterProfile,
        faces: vec![f],
        floor_z_mm: z,
        top_z_mm: top,
        depth_mm: top - z,
        area_mm2: region.area_mm2(),
        smallest_corner_radius_mm: corner,
        islands: 0,
        open_sides: 0,
        bbox_mm: [lo.x, lo.y, hi.x, hi.y],
        region,
    })
}
