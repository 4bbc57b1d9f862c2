//! One face: interior points on a curvature-driven grid, constrained Delaunay triangulation in
//! the (arc-length scaled) parameter plane, even-odd classification against the loops.

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::TessellationOptions;
use super::loops::{UvLoop, face_uv_loops};
use crate::diagnostics::Diagnostic;
use crate::geometry::brep::{Face, Part};
use crate::geometry::surface::SurfaceGeom;
use crate::geometry::{DVec2, DVec3};

/// A tessellated face. The first `boundary_vertex_count` vertices are boundary points (exact edge
/// points); the rest are interior points on the surface.
#[derive(Clone, Debug, Default)]
pub struct FaceMesh {
    /// Vertex positions, mm.
    pub positions: Vec<DVec3>,
    /// Unit normals (pointing out of the face, i.e. flipped where the face is reversed).
    pub normals: Vec<DVec3>,
    /// Parameters of each vertex.
    pub uv: Vec<DVec2>,
    /// Triangles, counter-clockwise about the face normal.
    pub triangles: Vec<[u32; 3]>,
    /// How many leading vertices are boundary points.
    pub boundary_vertex_count: usize,
    /// The face's area on the exact surface, mm²: the surface's area element integrated over
    /// every triangle's parameter-plane image (a degree-2 rule), plus, for each boundary chord,
    /// the parabolic segment between the chord and the edge curve. Unlike the triangles' own
    /// area it does not shrink with the chord tolerance.
    pub area_mm2: f64,
    /// This face's share of the enclosed volume, mm³: `⅓∫ p·n dA` over the exact surface with
    /// the face's outward normal, integrated as `area_mm2`. Summed over a closed shell it is the
    /// solid's volume (divergence theorem).
    pub volume_mm3: f64,
    /// Notes about this face.
    pub diagnostics: Vec<Diagnostic>,
}

/// Tessellate one face given the shared edge polylines (see [`super::discretize_edge`]).
///
/// # Errors
/// A message when the face's loops cannot be mapped to the parameter plane or triangulated.
pub fn tessellate_face(
    face: &Face,
    part: &Part,
    edge_polylines: &[Vec<DVec3>],
    opts: &TessellationOptions,
) -> Result<FaceMesh, String> {
    let surface = &face.surface;
    let mut loops = face_uv_loops(face, part, edge_polylines, opts.chord_tol_mm)?;
    if loops.is_empty() {
        loops.push(domain_loop(surface)?);
    }
    let (lo, hi) = uv_bounds(&loops).ok_or("face has no boundary points")?;
    let grid = Grid::new(surface, lo, hi, opts);
    // Coordinates below 1e-30 are flushed to zero: the triangulator refuses non-zero values
    // under about 1e-38 ("TooSmall"), which a boundary point a rounding error from the corner of
    // the bounds gives.
    let flush = |x: f64| if x.abs() < 1e-30 { 0.0 } else { x };
    let to_xy = |uv: DVec2| {
        Point2::new(
            flush((uv.x - lo.x) * grid.scale.x),
            flush((uv.y - lo.y) * grid.scale.y),
        )
    };
    let polys: Vec<Vec<Point2<f64>>> = loops
        .iter()
        .map(|l| l.uv.iter().map(|&uv| to_xy(uv)).collect())
        .collect();

    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    let mut out = FaceMesh::default();
    // Output vertex of each CDT vertex (by handle index).
    let mut out_of_handle: Vec<u32> = Vec::new();
    let mut conflicts = 0usize;
    // Output vertex of every loop point, for the boundary segments' curve corrections.
    let mut loop_out: Vec<Vec<u32>> = Vec::with_capacity(loops.len());
    for (l, poly) in loops.iter().zip(&polys) {
        let mut handles = Vec::with_capacity(poly.len());
        let mut lo_out = Vec::with_capacity(poly.len());
        for (k, &xy) in poly.iter().enumerate() {
            let h = cdt
                .insert(xy)
                .map_err(|e| format!("boundary point not triangulable: {e:?}"))?;
            if h.index() >= out_of_handle.len() {
                out_of_handle.resize(h.index() + 1, u32::MAX);
            }
            if out_of_handle[h.index()] == u32::MAX {
                out_of_handle[h.index()] =
                    push(&mut out, surface, l.uv[k], l.p3[k], face.same_sense);
            }
            handles.push(h);
            lo_out.push(out_of_handle[h.index()]);
        }
        for k in 0..handles.len() {
            let (a, b) = (handles[k], handles[(k + 1) % handles.len()]);
            if a != b && cdt.try_add_constraint(a, b).is_empty() && !cdt.exists_constraint(a, b) {
                conflicts += 1;
            }
        }
        loop_out.push(lo_out);
    }
    out.boundary_vertex_count = out.positions.len();
    if conflicts > 0 {
        out.diagnostics.push(Diagnostic::warning(
            Some(format!("#{}", face.source_id)),
            format!("{conflicts} boundary segments cross others in the parameter plane"),
        ));
    }

    // Interior grid points, away from the boundary.
    let segs = SegmentIndex::new(&polys, &grid);
    for i in 1..grid.n.0 {
        for j in 1..grid.n.1 {
            let uv = DVec2::new(lo.x + grid.step.x * i as f64, lo.y + grid.step.y * j as f64);
            let xy = to_xy(uv);
            if !inside(&polys, xy) || segs.near_boundary(xy, &polys, 0.3 * grid.min_step_xy()) {
                continue;
            }
            let Ok(h) = cdt.insert(xy) else { continue };
            if h.index() >= out_of_handle.len() {
                out_of_handle.resize(h.index() + 1, u32::MAX);
            }
            if out_of_handle[h.index()] == u32::MAX {
                let p = surface.point(uv.x, uv.y);
                out_of_handle[h.index()] = push(&mut out, surface, uv, p, face.same_sense);
            }
        }
    }

    let unscale =
        |xy: Point2<f64>| DVec2::new(lo.x + xy.x / grid.scale.x, lo.y + xy.y / grid.scale.y);
    // Refinement may grow the grid some times over (a face whose curvature the grid step
    // underestimated), not without bound: a pathological surface (kilometres of wild B-spline)
    // would otherwise refine to the whole per-face budget, for seconds per face.
    let budget = opts
        .max_grid_points_per_face
        .min(out.positions.len() * REFINE_GROWTH + REFINE_EXTRA_POINTS);
    // A grid already at half the per-face budget was capped by it: checking its triangles
    // (seconds on such a face) could add little, so the face is taken as it is, with a warning.
    let stopped = out.positions.len() * 2 >= opts.max_grid_points_per_face
        || refine(
            &mut cdt,
            &mut out,
            &mut out_of_handle,
            &Refine {
                surface,
                same_sense: face.same_sense,
                tol: opts.chord_tol_mm,
                budget,
                parity: conflicts == 0,
                polys: &polys,
                unscale: &unscale,
            },
        );
    if stopped {
        out.diagnostics.push(Diagnostic::warning(
            None,
            format!(
                "refinement stopped at {budget} points: parts of the face may lie farther than \
                 {} mm from its mesh",
                opts.chord_tol_mm
            ),
        ));
    }

    let parity = if conflicts == 0 {
        Some(inside_by_parity(&cdt))
    } else {
        None
    };
    for f in cdt.inner_faces() {
        let vs = f.vertices();
        let keep = match &parity {
            Some(p) => p.get(f.fix().index()).copied().flatten().unwrap_or(false),
            None => {
                let [a, b, c] = vs.map(|v| v.position());
                inside(
                    &polys,
                    Point2::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0),
                )
            }
        };
        if !keep {
            continue;
        }
        let idx = vs.map(|v| {
            out_of_handle
                .get(v.fix().index())
                .copied()
                .unwrap_or(u32::MAX)
        });
        if idx.contains(&u32::MAX) {
            continue;
        }
        out.triangles.push(if face.same_sense {
            idx
        } else {
            [idx[0], idx[2], idx[1]]
        });
    }
    fill_missing_normals(&mut out);
    let (area, volume) = integrate(&out, face, part, &loops, &loop_out);
    out.area_mm2 = area;
    out.volume_mm3 = volume;
    Ok(out)
}

/// The exact area and volume share of a triangulated face (see [`FaceMesh::area_mm2`]).
fn integrate(
    out: &FaceMesh,
    face: &Face,
    part: &Part,
    loops: &[UvLoop],
    loop_out: &[Vec<u32>],
) -> (f64, f64) {
    let surface = &face.surface;
    let sign = if face.same_sense { 1.0 } else { -1.0 };
    // Area element and volume integrand at (u, v).
    let element = |uv: DVec2| -> (f64, f64) {
        let d = surface.derivs(uv.x, uv.y);
        let n = d.su.cross(d.sv);
        let (j, w) = (n.length(), d.p.dot(n) * sign / 3.0);
        if j.is_finite() && w.is_finite() {
            (j, w)
        } else {
            (0.0, 0.0)
        }
    };
    let cross = |a: DVec2, b: DVec2| a.x * b.y - a.y * b.x;
    let (mut area, mut volume) = (0.0, 0.0);
    for t in &out.triangles {
        let [a, b, c] = t.map(|i| out.uv[i as usize]);
        let a_uv = 0.5 * cross(b - a, c - a).abs();
        if !(a_uv > 0.0 && a_uv.is_finite()) {
            continue;
        }
        for (wa, wb, wc) in [
            (4.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0),
            (1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0),
            (1.0 / 6.0, 1.0 / 6.0, 4.0 / 6.0),
        ] {
            let (j, w) = element(a * wa + b * wb + c * wc);
            area += a_uv * j / 3.0;
            volume += a_uv * w / 3.0;
        }
    }
    // Boundary chords: the third vertex of the triangle on each side says where the face is.
    let mut third: std::collections::HashMap<(u32, u32), u32> = std::collections::HashMap::new();
    // Only edges between two boundary vertices can be boundary chords.
    let nb = u32::try_from(out.boundary_vertex_count).unwrap_or(u32::MAX);
    for t in &out.triangles {
        for k in 0..3 {
            let (i, j, w) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            if i < nb && j < nb {
                third.insert((i.min(j), i.max(j)), w);
            }
        }
    }
    let rect = surface.domain();
    let (pu, pv) = surface.periods();
    for (l, outs) in loops.iter().zip(loop_out) {
        let n = l.uv.len().min(outs.len());
        for k in 0..n {
            let (Some(Some(ei)), k1) = (l.edge.get(k), (k + 1) % n) else {
                continue;
            };
            let (oi, oj) = (outs[k], outs[k1]);
            let (Some(&w), Some(edge)) =
                (third.get(&(oi.min(oj), oi.max(oj))), part.edges.get(*ei))
            else {
                continue;
            };
            let (pa, pb) = (l.p3[k], l.p3[k1]);
            let range = crate::geometry::Interval::new(
                edge.t_start.min(edge.t_end),
                edge.t_start.max(edge.t_end),
            );
            let on_curve = edge
                .curve
                .point(edge.curve.closest_param(0.5 * (pa + pb), range));
            if !on_curve.is_finite() {
                continue;
            }
            let (ua, ub) = (out.uv[oi as usize], out.uv[oj as usize]);
            let guess = 0.5 * (ua + ub);
            let mut mid = surface.closest_point_near(on_curve, rect, guess).uv;
            // Into the loop's period window (the inversion may answer in another period).
            for (axis, per) in [(0, pu), (1, pv)] {
                if let Some(per) = per.filter(|p| *p > 0.0 && p.is_finite()) {
                    mid[axis] += ((guess[axis] - mid[axis]) / per).round() * per;
                }
            }
            let bulge = cross(ub - ua, mid - ua);
            // A sagitta as long as half the chord is no chord of a curve within tolerance: an
            // inversion that landed elsewhere; leave that segment uncorrected.
            if bulge.abs() > 0.5 * (ub - ua).length_squared() {
                continue;
            }
            let side = cross(ub - ua, out.uv[w as usize] - ua);
            if !(bulge.is_finite() && side != 0.0) {
                continue;
            }
            // The parabolic segment between chord and curve: ⅔ · chord · sagitta.
            let seg = 2.0 / 3.0 * bulge.abs();
            let seg = if bulge.signum() == side.signum() {
                -seg
            } else {
                seg
            };
            let (j, wv) = element(mid);
            area += seg * j;
            volume += seg * wv;
        }
    }
    (area, volume)
}

/// What [`refine`] needs besides the triangulation.
struct Refine<'a> {
    surface: &'a SurfaceGeom,
    same_sense: bool,
    /// Chord tolerance, mm.
    tol: f64,
    /// Most vertices the face may get.
    budget: usize,
    /// Inside/outside by crossing parity (the boundary constraints are consistent).
    parity: bool,
    polys: &'a [Vec<Point2<f64>>],
    unscale: &'a dyn Fn(Point2<f64>) -> DVec2,
}

/// Most refinement rounds: each round at least halves the offending triangles' size, so 40
/// rounds reach 1e-12 of the face; the vertex budget stops runaway cases first.
const MAX_REFINE_ROUNDS: usize = 40;
/// Refinement adds at most this many times the grid's points ...
const REFINE_GROWTH: usize = 2;
/// ... plus this many.
const REFINE_EXTRA_POINTS: usize = 20_000;

/// Insert vertices until every kept triangle lies within the chord tolerance of the surface:
/// the triangle's centroid and the midpoints of its interior (unconstrained) edges are compared
/// with the surface point at the same parameters and, where that differs by more than the
/// tolerance, with the closest surface point; an edge midpoint that strays is inserted (so both
/// triangles on the edge are split), else the centroid. Boundary segments are chords of the edge
/// curves, already within tolerance, and are left as they are so that neighbouring faces keep
/// sharing them.
/// Returns whether it stopped at the vertex budget with triangles still out of tolerance.
fn refine(
    cdt: &mut ConstrainedDelaunayTriangulation<Point2<f64>>,
    out: &mut FaceMesh,
    out_of_handle: &mut Vec<u32>,
    r: &Refine<'_>,
) -> bool {
    let rect = r.surface.domain();
    let strays = |uv: DVec2, p: DVec3| -> bool {
        let q = r.surface.point(uv.x, uv.y);
        if !q.is_finite() || q.distance(p) <= r.tol {
            return false;
        }
        r.surface.closest_point_near(p, rect, uv).distance > r.tol
    };
    // After the first round only the triangles around the vertices just inserted are new.
    let mut fresh: Option<Vec<spade::handles::FixedVertexHandle>> = None;
    for _ in 0..MAX_REFINE_ROUNDS {
        let parity = r.parity.then(|| inside_by_parity(cdt));
        let mut inserts: Vec<Point2<f64>> = Vec::new();
        let faces: Vec<spade::handles::FixedFaceHandle<spade::handles::InnerTag>> = match &fresh {
            None => cdt.inner_faces().map(|f| f.fix()).collect(),
            Some(vs) => {
                let mut set = std::collections::BTreeSet::new();
                for &v in vs {
                    for e in cdt.vertex(v).out_edges() {
                        if let Some(f) = e.face().as_inner() {
                            set.insert(f.fix());
                        }
                    }
                }
                set.into_iter().collect()
            }
        };
        for fh in faces {
            let f = cdt.face(fh);
            let vs = f.vertices();
            let xy = vs.map(|v| v.position());
            let keep = match &parity {
                Some(p) => p.get(f.fix().index()).copied().flatten().unwrap_or(false),
                None => inside(
                    r.polys,
                    Point2::new(
                        (xy[0].x + xy[1].x + xy[2].x) / 3.0,
                        (xy[0].y + xy[1].y + xy[2].y) / 3.0,
                    ),
                ),
            };
            if !keep {
                continue;
            }
            let idx = vs.map(|v| {
                out_of_handle
                    .get(v.fix().index())
                    .copied()
                    .unwrap_or(u32::MAX)
            });
            if idx.contains(&u32::MAX) {
                continue;
            }
            let [a, b, c] = idx.map(|i| i as usize);
            // Degenerate in the plane: nothing to gain by splitting.
            let area2 = ((xy[1].x - xy[0].x) * (xy[2].y - xy[0].y)
                - (xy[2].x - xy[0].x) * (xy[1].y - xy[0].y))
                .abs();
            let size2 = [(0, 1), (1, 2), (2, 0)]
                .iter()
                .map(|&(i, j)| (xy[i].x - xy[j].x).powi(2) + (xy[i].y - xy[j].y).powi(2))
                .fold(0.0f64, f64::max);
            if area2 <= 1e-24 * size2.max(1e-300) || size2.sqrt() < 0.01 * r.tol {
                continue;
            }
            let mut split = None;
            for (e, (i, j)) in f
                .adjacent_edges()
                .iter()
                .zip([(0usize, 1usize), (1, 2), (2, 0)])
            {
                if e.is_constraint_edge() && r.parity {
                    continue;
                }
                let (oi, oj) = ([a, b, c][i], [a, b, c][j]);
                let uv = 0.5 * (out.uv[oi] + out.uv[oj]);
                let p = 0.5 * (out.positions[oi] + out.positions[oj]);
                if !e.is_constraint_edge() && strays(uv, p) {
                    split = Some(Point2::new(
                        0.5 * (xy[i].x + xy[j].x),
                        0.5 * (xy[i].y + xy[j].y),
                    ));
                    break;
                }
            }
            if split.is_none() {
                let uv = (out.uv[a] + out.uv[b] + out.uv[c]) / 3.0;
                let p = (out.positions[a] + out.positions[b] + out.positions[c]) / 3.0;
                if strays(uv, p) {
                    split = Some(Point2::new(
                        (xy[0].x + xy[1].x + xy[2].x) / 3.0,
                        (xy[0].y + xy[1].y + xy[2].y) / 3.0,
                    ));
                }
            }
            if let Some(s) = split {
                inserts.push(s);
            }
        }
        if inserts.is_empty() {
            return false;
        }
        if out.positions.len() >= r.budget {
            return true;
        }
        let mut added = Vec::new();
        for xy in inserts {
            if out.positions.len() >= r.budget {
                break;
            }
            let Ok(h) = cdt.insert(xy) else { continue };
            if h.index() >= out_of_handle.len() {
                out_of_handle.resize(h.index() + 1, u32::MAX);
            }
            if out_of_handle[h.index()] == u32::MAX {
                let uv = (r.unscale)(xy);
                let p = r.surface.point(uv.x, uv.y);
                out_of_handle[h.index()] = push(out, r.surface, uv, p, r.same_sense);
                added.push(h);
            }
        }
        // Points that fell on existing vertices change nothing: another round would find the
        // same triangles.
        if added.is_empty() {
            return false;
        }
        fresh = Some(added);
    }
    false
}

fn push(out: &mut FaceMesh, surface: &SurfaceGeom, uv: DVec2, p: DVec3, same_sense: bool) -> u32 {
    let n = surface
        .derivs(uv.x, uv.y)
        .normal()
        .map_or(DVec3::ZERO, |n| if same_sense { n } else { -n });
    out.positions.push(p);
    out.normals.push(n);
    out.uv.push(uv);
    u32::try_from(out.positions.len() - 1).unwrap_or(u32::MAX)
}

/// Inside/outside of every triangle by crossing parity: start outside at the convex hull and
/// flip at every constraint (boundary) edge crossed. Unlike a point-in-polygon test this is
/// immune to slivers between nearly collinear boundary points.
fn inside_by_parity(cdt: &ConstrainedDelaunayTriangulation<Point2<f64>>) -> Vec<Option<bool>> {
    let mut state: Vec<Option<bool>> = vec![None; cdt.num_all_faces()];
    let mut stack = Vec::new();
    for e in cdt.convex_hull() {
        if let Some(f) = e.face().as_inner().or_else(|| e.rev().face().as_inner()) {
            stack.push((f.fix(), e.is_constraint_edge()));
        }
    }
    while let Some((f, inside)) = stack.pop() {
        let Some(slot) = state.get_mut(f.index()) else {
            continue;
        };
        if slot.is_some() {
            continue;
        }
        *slot = Some(inside);
        for e in cdt.face(f).adjacent_edges() {
            if let Some(nb) = e.rev().face().as_inner()
                && state.get(nb.fix().index()).is_some_and(Option::is_none)
            {
                stack.push((nb.fix(), inside ^ e.is_constraint_edge()));
            }
        }
    }
    state
}

/// Vertices where the surface normal is undefined (poles, apexes) take the mean of their
/// triangles' normals.
fn fill_missing_normals(out: &mut FaceMesh) {
    if !out.normals.contains(&DVec3::ZERO) {
        return;
    }
    let mut acc = vec![DVec3::ZERO; out.positions.len()];
    for t in &out.triangles {
        let [a, b, c] = t.map(|i| out.positions[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in t {
            acc[i as usize] += n;
        }
    }
    for (n, a) in out.normals.iter_mut().zip(acc) {
        if *n == DVec3::ZERO {
            *n = a.normalize_or_zero();
        }
    }
}

/// The whole (finite) parameter domain as a loop, for a face with no bounds.
fn domain_loop(surface: &SurfaceGeom) -> Result<UvLoop, String> {
    let r = surface.domain();
    if !r.u.is_finite() || !r.v.is_finite() || r.u.is_empty() || r.v.is_empty() {
        return Err("face has no bounds and its surface is unbounded".into());
    }
    let n = 16;
    let mut l = UvLoop::default();
    let corners = [
        DVec2::new(r.u.t0, r.v.t0),
        DVec2::new(r.u.t1, r.v.t0),
        DVec2::new(r.u.t1, r.v.t1),
        DVec2::new(r.u.t0, r.v.t1),
    ];
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        for s in 0..n {
            let uv = a.lerp(b, s as f64 / n as f64);
            l.uv.push(uv);
            l.p3.push(surface.point(uv.x, uv.y));
            l.edge.push(None);
        }
    }
    Ok(l)
}

fn uv_bounds(loops: &[UvLoop]) -> Option<(DVec2, DVec2)> {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for p in loops.iter().flat_map(|l| &l.uv) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

/// The interior sampling grid: parameter steps that keep the chord error and the normal's turn
/// per step within tolerance (from the largest second derivatives over the face's bounds), and
/// scale factors that make the parameter plane approximate arc length.
struct Grid {
    /// Parameter steps.
    step: DVec2,
    /// Cell counts in u and v.
    n: (usize, usize),
    /// mm per unit of u and of v (mean |S_u|, |S_v|).
    scale: DVec2,
}

impl Grid {
    fn new(surface: &SurfaceGeom, lo: DVec2, hi: DVec2, opts: &TessellationOptions) -> Self {
        const SAMPLES: usize = 9;
        let (mut su, mut sv) = (0.0, 0.0);
        // Largest turn of the normal per unit parameter (|S_uu·n| / |S_u|), over the samples.
        let (mut rate_u, mut rate_v) = (0.0f64, 0.0f64);
        let (mut a_uu, mut a_uv, mut a_vv) = (0.0f64, 0.0f64, 0.0f64);
        let mut count = 0.0;
        for i in 0..SAMPLES {
            for j in 0..SAMPLES {
                let u = lo.x + (hi.x - lo.x) * i as f64 / (SAMPLES - 1) as f64;
                let v = lo.y + (hi.y - lo.y) * j as f64 / (SAMPLES - 1) as f64;
                let d = surface.derivs(u, v);
                let (lu, lv) = (d.su.length(), d.sv.length());
                if !(lu.is_finite() && lv.is_finite()) {
                    continue;
                }
                su += lu;
                sv += lv;
                count += 1.0;
                // Only the normal components bend the surface away from a flat triangle.
                let n = d.normal().unwrap_or(DVec3::ZERO);
                let (b_uu, b_uv, b_vv) =
                    (d.suu.dot(n).abs(), d.suv.dot(n).abs(), d.svv.dot(n).abs());
                a_uu = a_uu.max(b_uu);
                a_uv = a_uv.max(b_uv);
                a_vv = a_vv.max(b_vv);
                if lu > 1e-9 * (lu + lv) {
                    rate_u = rate_u.max(b_uu.max(b_uv) / lu);
                }
                if lv > 1e-9 * (lu + lv) {
                    rate_v = rate_v.max(b_vv.max(b_uv) / lv);
                }
            }
        }
        let scale = if count > 0.0 {
            DVec2::new((su / count).max(1e-12), (sv / count).max(1e-12))
        } else {
            DVec2::ONE
        };
        let range = (hi - lo).max(DVec2::splat(1e-300));
        let tol = opts.chord_tol_mm;
        let step_for = |a: f64, rate: f64, full: f64| -> f64 {
            if a <= 0.0 || !a.is_finite() {
                return full;
            }
            let by_chord = (8.0 * tol / a).sqrt();
            let by_angle = if rate > 0.0 && rate.is_finite() {
                opts.angle_tol_rad / rate
            } else {
                full
            };
            by_chord.min(by_angle).min(full)
        };
        let hu = step_for(a_uu.max(a_uv), rate_u, range.x);
        let hv = step_for(a_vv.max(a_uv), rate_v, range.y);
        let mut nu = (range.x / hu).ceil().max(1.0);
        let mut nv = (range.y / hv).ceil().max(1.0);
        let cap = opts.max_grid_points_per_face as f64;
        if nu * nv > cap {
            let f = (cap / (nu * nv)).sqrt();
            nu = (nu * f).floor().max(1.0);
            nv = (nv * f).floor().max(1.0);
        }
        Self {
            step: DVec2::new(range.x / nu, range.y / nv),
            n: (nu as usize, nv as usize),
            scale,
        }
    }

    fn min_step_xy(&self) -> f64 {
        (self.step.x * self.scale.x).min(self.step.y * self.scale.y)
    }
}

/// Boundary segments bucketed by grid cell, for the "too close to the boundary" test.
struct SegmentIndex {
    cells: Vec<Vec<(u32, u32)>>,
    n: (usize, usize),
    cell: (f64, f64),
}

impl SegmentIndex {
    fn new(polys: &[Vec<Point2<f64>>], grid: &Grid) -> Self {
        let n = (grid.n.0.max(1), grid.n.1.max(1));
        let cell = (
            (grid.step.x * grid.scale.x).max(1e-300),
            (grid.step.y * grid.scale.y).max(1e-300),
        );
        let mut cells = vec![Vec::new(); n.0 * n.1];
        for (li, poly) in polys.iter().enumerate() {
            for k in 0..poly.len() {
                let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                let (i0, i1) = ordered(a.x / cell.0, b.x / cell.0);
                let (j0, j1) = ordered(a.y / cell.1, b.y / cell.1);
                let (i0, i1) = (clamp_idx(i0 - 1.0, n.0), clamp_idx(i1 + 1.0, n.0));
                let (j0, j1) = (clamp_idx(j0 - 1.0, n.1), clamp_idx(j1 + 1.0, n.1));
                if (i1 - i0 + 1) * (j1 - j0 + 1) > 4096 {
                    continue; // a huge segment: the even-odd test still guards it
                }
                for i in i0..=i1 {
                    for j in j0..=j1 {
                        cells[i * n.1 + j].push((li as u32, k as u32));
                    }
                }
            }
        }
        Self { cells, n, cell }
    }

    fn near_boundary(&self, p: Point2<f64>, polys: &[Vec<Point2<f64>>], dist: f64) -> bool {
        let i = clamp_idx(p.x / self.cell.0, self.n.0);
        let j = clamp_idx(p.y / self.cell.1, self.n.1);
        self.cells[i * self.n.1 + j].iter().any(|&(li, k)| {
            let poly = &polys[li as usize];
            let (a, b) = (poly[k as usize], poly[(k as usize + 1) % poly.len()]);
            segment_distance(p, a, b) < dist
        })
    }
}

fn ordered(a: f64, b: f64) -> (f64, f64) {
    if a <= b { (a, b) } else { (b, a) }
}

fn clamp_idx(x: f64, n: usize) -> usize {
    if x.is_nan() || x < 0.0 {
        0
    } else {
        (x as usize).min(n - 1)
    }
}

fn segment_distance(p: Point2<f64>, a: Point2<f64>, b: Point2<f64>) -> f64 {
    let (abx, aby) = (b.x - a.x, b.y - a.y);
    let (apx, apy) = (p.x - a.x, p.y - a.y);
    let len2 = abx * abx + aby * aby;
    let t = if len2 > 0.0 {
        ((apx * abx + apy * aby) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (dx, dy) = (apx - t * abx, apy - t * aby);
    (dx * dx + dy * dy).sqrt()
}

/// Even-odd point-in-polygons test (loop orientation does not matter).
fn inside(polys: &[Vec<Point2<f64>>], p: Point2<f64>) -> bool {
    let mut odd = false;
    for poly in polys {
        let n = poly.len();
        for k in 0..n {
            let (a, b) = (poly[k], poly[(k + 1) % n]);
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if p.x < x {
                    odd = !odd;
                }
            }
        }
    }
    odd
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn even_odd_handles_holes() {
        let sq = |s: f64| {
            vec![
                Point2::new(-s, -s),
                Point2::new(s, -s),
                Point2::new(s, s),
                Point2::new(-s, s),
            ]
        };
        let polys = vec![sq(2.0), sq(1.0)];
        assert!(inside(&polys, Point2::new(1.5, 0.0)));
        assert!(!inside(&polys, Point2::new(0.0, 0.0)));
        assert!(!inside(&polys, Point2::new(3.0, 0.0)));
        assert!(
            (segment_distance(
                Point2::new(0.0, 1.0),
                Point2::new(-1.0, 0.0),
                Point2::new(1.0, 0.0)
            ) - 1.0)
                .abs()
                < 1e-15
        );
    }
}
