//! Hole recognition: the holes of a part from its B-rep faces.
//!
//! Method: every cylinder and cone face whose material lies outside it (the face normal points
//! at the axis) is a candidate wall. Walls on one axis line are merged where they are pieces of
//! one surface of revolution (a cylinder split in halves, or in bands along its length) and
//! kept where they go all the way round (2π). Walls that meet end to end along the axis form a
//! hole's profile; each end of the profile is open (the hole runs out of the material), closed
//! by a disc face (a flat bottom) or by a cone that closes at the axis (a drill point). A hole is
//! entered from an open end: the end with the wider profile when both are open, else the one
//! facing up (+z, then +y, then +x). From the entry down: the deepest cylinder is the main bore
//! (its diameter and depth are the hole's), the wider parts above it are steps (counterbores,
//! countersinks, spot faces).
//!
//! B-spline faces are not examined (a B-spline approximation of a cylinder is reported, not
//! guessed at); partial cylinders (slots, fillets) are not holes. Lengths mm, angles rad.

use std::f64::consts::TAU;

use crate::diagnostics::Diagnostic;
use crate::geometry::DVec3;
use crate::geometry::brep::{Loop, Part};
use crate::geometry::surface::SurfaceGeom;
use crate::geometry::tessellate::{PartMesh, TessellationOptions, face_param_loops};

/// How a hole ends at the far side from its entry.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum HoleBottom {
    /// The hole runs out of the material at both ends.
    Through,
    /// A flat floor (a disc face across the bore).
    Flat,
    /// A cone closing at the axis (a drill point).
    Point {
        /// Included angle of the cone, rad (118° for a standard twist drill).
        angle_rad: f64,
        /// Depth of the point's tip below the entry, mm.
        tip_depth_mm: f64,
    },
    /// Closed by some other face within the bore (a ball end, a rounded corner, a B-spline).
    Other {
        /// Depth of the deepest point found on the closing face below the entry, mm.
        tip_depth_mm: f64,
    },
}

/// A wider part of a hole above its main bore.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum HoleStep {
    /// A cylinder (a counterbore or spot face): its diameter and the depth of its floor below
    /// the entry, mm.
    Cylinder {
        /// Diameter, mm.
        diameter_mm: f64,
        /// Depth of its lower end below the entry, mm.
        depth_mm: f64,
    },
    /// A cone (a countersink or chamfer): diameters at its upper and lower ends, included
    /// angle, and the depth of its lower end below the entry.
    Cone {
        /// Diameter at the upper end, mm.
        top_diameter_mm: f64,
        /// Diameter at the lower end, mm.
        bottom_diameter_mm: f64,
        /// Included angle, rad.
        angle_rad: f64,
        /// Depth of its lower end below the entry, mm.
        depth_mm: f64,
    },
}

/// What kind of hole it is, from its steps.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum HoleKind {
    /// One bore.
    Simple,
    /// A wider cylinder above the bore (possibly chamfered).
    Counterbore,
    /// A shallow wider cylinder (depth at most 0.15 of its diameter).
    SpotFace,
    /// A cone above the bore.
    Countersink,
    /// Several wider cylinders.
    Stepped,
}

/// A thread whose tap drill matches a hole's diameter: a suggestion, not a fact.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ThreadSuggestion {
    /// ISO metric coarse designation, e.g. `M6`.
    pub name: &'static str,
    /// Nominal (major) diameter, mm.
    pub major_diameter_mm: f64,
    /// Pitch, mm.
    pub pitch_mm: f64,
}

/// One hole.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Hole {
    /// Centre of the entry (on the axis, at the top of the hole), mm.
    pub top: DVec3,
    /// Unit axis pointing out of the hole through its entry: the tool comes from this side and
    /// feeds along `-direction`.
    pub direction: DVec3,
    /// Diameter of the main (deepest) bore, mm.
    pub diameter_mm: f64,
    /// Depth from the entry to the lower end of the main bore's cylinder, mm.
    pub depth_mm: f64,
    /// The far end.
    pub bottom: HoleBottom,
    /// Wider parts above the main bore, from the entry down.
    pub steps: Vec<HoleStep>,
    /// Kind, from the steps.
    pub kind: HoleKind,
    /// The faces of the hole (walls, point, floor), indices into [`Part::faces`].
    pub faces: Vec<usize>,
    /// True when a wall of the hole is made of more than one face around the axis (a cylinder
    /// split in halves).
    pub split: bool,
    /// A metric coarse thread whose tap drill is this diameter (within 0.02 mm), if any.
    pub thread_suggestion: Option<ThreadSuggestion>,
}

impl Hole {
    /// Depth of the deepest point of the hole below the entry (the drill point's tip, the floor,
    /// or the exit), mm.
    #[must_use]
    pub fn full_depth_mm(&self) -> f64 {
        match self.bottom {
            HoleBottom::Point { tip_depth_mm, .. } | HoleBottom::Other { tip_depth_mm } => {
                tip_depth_mm
            }
            _ => self.depth_mm,
        }
    }
}

/// Holes of one diameter and direction.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct HoleGroup {
    /// Main-bore diameter, mm.
    pub diameter_mm: f64,
    /// Common direction (see [`Hole::direction`]).
    pub direction: DVec3,
    /// Indices into [`HoleReport::holes`].
    pub holes: Vec<usize>,
}

/// The holes of a part.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct HoleReport {
    /// Holes, ordered by direction, then entry height (highest first), then x, then y.
    pub holes: Vec<Hole>,
    /// Holes grouped by diameter and direction.
    pub groups: Vec<HoleGroup>,
    /// Walls left out and why (B-spline faces, faces that could not be read, closed cavities).
    pub diagnostics: Vec<Diagnostic>,
}

/// ISO metric coarse threads: (name, major diameter, pitch, tap drill), mm.
const METRIC_COARSE: [(&str, f64, f64, f64); 13] = [
    ("M2", 2.0, 0.4, 1.6),
    ("M2.5", 2.5, 0.45, 2.05),
    ("M3", 3.0, 0.5, 2.5),
    ("M4", 4.0, 0.7, 3.3),
    ("M5", 5.0, 0.8, 4.2),
    ("M6", 6.0, 1.0, 5.0),
    ("M8", 8.0, 1.25, 6.8),
    ("M10", 10.0, 1.5, 8.5),
    ("M12", 12.0, 1.75, 10.2),
    ("M14", 14.0, 2.0, 12.0),
    ("M16", 16.0, 2.0, 14.0),
    ("M20", 20.0, 2.5, 17.5),
    ("M24", 24.0, 3.0, 21.0),
];

/// The metric coarse thread whose tap drill is `diameter_mm` (within 0.02 mm).
#[must_use]
pub fn thread_for_tap_drill(diameter_mm: f64) -> Option<ThreadSuggestion> {
    METRIC_COARSE
        .iter()
        .find(|t| (t.3 - diameter_mm).abs() <= 0.02)
        .map(|t| ThreadSuggestion {
            name: t.0,
            major_diameter_mm: t.1,
            pitch_mm: t.2,
        })
}

/// The metric coarse thread called `name` (e.g. `M6`).
#[must_use]
pub fn metric_thread(name: &str) -> Option<ThreadSuggestion> {
    METRIC_COARSE
        .iter()
        .find(|t| t.0.eq_ignore_ascii_case(name))
        .map(|t| ThreadSuggestion {
            name: t.0,
            major_diameter_mm: t.1,
            pitch_mm: t.2,
        })
}

/// Tolerances of the recognition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoleOptions {
    /// Two lengths (radii, axis offsets, axial positions) this close are the same, mm (CAD
    /// tolerances run from 1e-7 to 1e-3 mm).
    pub length_tol_mm: f64,
    /// Two directions this close are the same, rad.
    pub angle_tol_rad: f64,
    /// Holes of a main diameter above this are left out (they are bores or pockets), mm.
    pub max_diameter_mm: f64,
}

impl Default for HoleOptions {
    fn default() -> Self {
        Self {
            length_tol_mm: 1e-4,
            angle_tol_rad: 1e-6,
            max_diameter_mm: f64::INFINITY,
        }
    }
}

/// An axis line: a point on it (the one nearest the origin) and a unit direction with its
/// largest component positive.
#[derive(Clone, Copy, Debug)]
struct AxisLine {
    origin: DVec3,
    dir: DVec3,
}

impl AxisLine {
    fn new(origin: DVec3, dir: DVec3) -> Option<Self> {
        let mut d = dir.try_normalize()?;
        let a = d.abs();
        let lead = if a.x >= a.y && a.x >= a.z {
            d.x
        } else if a.y >= a.z {
            d.y
        } else {
            d.z
        };
        if lead < 0.0 {
            d = -d;
        }
        let o = origin - d * origin.dot(d);
        (o.is_finite() && d.is_finite()).then_some(Self { origin: o, dir: d })
    }

    fn same(&self, other: &Self, opts: &HoleOptions) -> bool {
        self.dir.cross(other.dir).length() <= opts.angle_tol_rad
            && (self.origin - other.origin).length() <= opts.length_tol_mm
    }

    /// Axial coordinate and distance from the axis.
    fn coords(&self, p: DVec3) -> (f64, f64) {
        let w = p - self.origin;
        let t = w.dot(self.dir);
        (t, (w - self.dir * t).length())
    }
}

/// A wall: a piece of a cylinder or cone between two axial positions.
#[derive(Clone, Debug)]
struct Wall {
    faces: Vec<usize>,
    /// Axial range, `t0 < t1`, and radius at each end.
    t0: f64,
    t1: f64,
    r0: f64,
    r1: f64,
    /// Semi-angle for a cone (exact, from the surface), None for a cylinder.
    cone_semi_angle: Option<f64>,
    /// Angle covered around the axis, rad.
    coverage: f64,
    /// More than one face around.
    split: bool,
}

/// A plane face with one loop: its normal and boundary sample points (a flat-bottom candidate).
struct Disc {
    face: usize,
    normal: DVec3,
    points: Vec<DVec3>,
}

/// Recognise the holes of `part`. `mesh` (the part's tessellation, when the caller has it)
/// tells which shells are inside out (their faces' volumes sum negative), so that a part with
/// reversed normals is still read right; without it the normals are taken as written.
#[must_use]
pub fn recognize_holes(part: &Part, mesh: Option<&PartMesh>, opts: &HoleOptions) -> HoleReport {
    let mut report = HoleReport::default();
    let flip = shell_flips(part, mesh);
    let topts = TessellationOptions::for_size(part.rough_bbox().diagonal());
    let mut walls: Vec<(AxisLine, Wall)> = Vec::new();
    let mut discs: Vec<Disc> = Vec::new();
    let mut bspline = 0usize;
    for (fi, face) in part.faces.iter().enumerate() {
        match &face.surface {
            SurfaceGeom::Cylinder(_) | SurfaceGeom::Cone(_) => {
                match wall_of(part, fi, flip[fi], &topts) {
                    Ok(Some(w)) => walls.push(w),
                    Ok(None) => {}
                    Err(msg) => report.diagnostics.push(Diagnostic::warning(
                        Some(format!("#{}", face.source_id)),
                        format!("face not examined for holes: {msg}"),
                    )),
                }
            }
            SurfaceGeom::Plane(p) => {
                let edge_loops: Vec<_> = face
                    .loops
                    .iter()
                    .filter(|l| matches!(l, Loop::Edges(_)))
                    .collect();
                if let [Loop::Edges(oes)] = edge_loops.as_slice() {
                    let mut points = Vec::new();
                    for oe in oes {
                        if let Some(e) = part.edges.get(oe.edge) {
                            for k in 0..=8 {
                                let t = e.t_start + (e.t_end - e.t_start) * f64::from(k) / 8.0;
                                let q = e.curve.point(t);
                                if q.is_finite() {
                                    points.push(q);
                                }
                            }
                        }
                    }
                    if let Some(normal) = p.frame.z.try_normalize() {
                        discs.push(Disc {
                            face: fi,
                            normal,
                            points,
                        });
                    }
                }
            }
            SurfaceGeom::BSpline(_) | SurfaceGeom::Revolution(_) | SurfaceGeom::Extrusion(_) => {
                bspline += 1;
            }
            SurfaceGeom::Sphere(_) | SurfaceGeom::Torus(_) => {}
        }
    }
    if bspline > 0 {
        report.diagnostics.push(Diagnostic::info(
            None,
            format!(
                "{bspline} B-spline, revolved or extruded faces not examined for holes (a hole \
                 whose wall is a B-spline approximation of a cylinder is not recognised)"
            ),
        ));
    }
    // Walls by axis line.
    let mut axes: Vec<(AxisLine, Vec<Wall>)> = Vec::new();
    for (ax, w) in walls {
        match axes.iter_mut().find(|(a, _)| a.same(&ax, opts)) {
            Some((a, ws)) => {
                // Re-express the wall on the group's axis.
                let shift = (ax.origin - a.origin).dot(a.dir);
                let mut w = w;
                w.t0 += shift;
                w.t1 += shift;
                ws.push(w);
            }
            None => axes.push((ax, vec![w])),
        }
    }
    let topo = Topology::new(part);
    let mut holes = Vec::new();
    for (ax, ws) in axes {
        let ws = merge_walls(ws, opts);
        for chain in chains(ws, opts) {
            match hole_of(part, &topo, &ax, &chain, &discs, opts) {
                Ok(Some(h)) if h.diameter_mm <= opts.max_diameter_mm => holes.push(h),
                Ok(_) => {}
                Err(msg) => report.diagnostics.push(Diagnostic::info(None, msg)),
            }
        }
    }
    holes.sort_by(|a, b| {
        dir_key(a.direction)
            .partial_cmp(&dir_key(b.direction))
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(b.top.z.total_cmp(&a.top.z))
            .then(a.top.x.total_cmp(&b.top.x))
            .then(a.top.y.total_cmp(&b.top.y))
    });
    let mut groups: Vec<HoleGroup> = Vec::new();
    for (i, h) in holes.iter().enumerate() {
        match groups.iter_mut().find(|g| {
            (g.diameter_mm - h.diameter_mm).abs() <= opts.length_tol_mm
                && g.direction.cross(h.direction).length() <= 1e-6
                && g.direction.dot(h.direction) > 0.0
        }) {
            Some(g) => g.holes.push(i),
            None => groups.push(HoleGroup {
                diameter_mm: h.diameter_mm,
                direction: h.direction,
                holes: vec![i],
            }),
        }
    }
    report.holes = holes;
    report.groups = groups;
    report
}

/// A sort key for directions: +z first, then the others in a fixed order.
fn dir_key(d: DVec3) -> (f64, f64, f64) {
    (-d.z, -d.y, -d.x)
}

/// For each face, whether its shell is inside out (per the mesh's signed face volumes).
fn shell_flips(part: &Part, mesh: Option<&PartMesh>) -> Vec<bool> {
    let mut flip = vec![false; part.faces.len()];
    let Some(mesh) = mesh else {
        return flip;
    };
    for shell in &part.shells {
        let v: f64 = shell
            .faces
            .iter()
            .filter_map(|&f| mesh.faces.get(f))
            .map(|r| r.volume_mm3)
            .sum();
        if shell.closed && v < 0.0 {
            for &f in &shell.faces {
                if let Some(x) = flip.get_mut(f) {
                    *x = true;
                }
            }
        }
    }
    flip
}

/// The wall of a cylinder or cone face, when its material lies outside it.
fn wall_of(
    part: &Part,
    fi: usize,
    flip: bool,
    topts: &TessellationOptions,
) -> Result<Option<(AxisLine, Wall)>, String> {
    let face = &part.faces[fi];
    let (frame, semi) = match &face.surface {
        SurfaceGeom::Cylinder(c) => (c.frame, None),
        SurfaceGeom::Cone(c) => (c.frame, Some(c.semi_angle)),
        _ => return Ok(None),
    };
    let ax = AxisLine::new(frame.origin, frame.z).ok_or("degenerate axis")?;
    let loops = face_param_loops(face, part, topts)?;
    let (mut umin, mut umax, mut vmin, mut vmax) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in loops.iter().flatten() {
        umin = umin.min(p.x);
        umax = umax.max(p.x);
        vmin = vmin.min(p.y);
        vmax = vmax.max(p.y);
    }
    if !(umin.is_finite() && umax.is_finite() && vmin.is_finite() && vmax.is_finite()) {
        return Err("no boundary".into());
    }
    let coverage = (umax - umin).min(TAU);
    let um = 0.5 * (umin + umax);
    let vm = 0.5 * (vmin + vmax);
    // Concave (a hole's wall) when the face normal points at the axis.
    let d = face.surface.derivs(um, vm);
    let mut n = d.su.cross(d.sv);
    if !face.same_sense {
        n = -n;
    }
    if flip {
        n = -n;
    }
    let (tm, _) = ax.coords(d.p);
    let radial = d.p - (ax.origin + ax.dir * tm);
    if n.dot(radial) >= 0.0 {
        return Ok(None);
    }
    let (ta, ra) = ax.coords(face.surface.point(um, vmin));
    let (tb, rb) = ax.coords(face.surface.point(um, vmax));
    let (t0, r0, t1, r1) = if ta <= tb {
        (ta, ra, tb, rb)
    } else {
        (tb, rb, ta, ra)
    };
    let cone_semi_angle = semi.map(f64::abs);
    Ok(Some((
        ax,
        Wall {
            faces: vec![fi],
            t0,
            t1,
            r0,
            r1,
            cone_semi_angle,
            coverage,
            split: false,
        },
    )))
}

/// Merge the pieces of one surface around the axis (halves) and along it (bands), and keep the
/// walls that go all the way round.
fn merge_walls(mut ws: Vec<Wall>, opts: &HoleOptions) -> Vec<Wall> {
    let tol = opts.length_tol_mm;
    ws.sort_by(|a, b| a.t0.total_cmp(&b.t0).then(a.r0.total_cmp(&b.r0)));
    // Around: same range and radii.
    let mut around: Vec<Wall> = Vec::new();
    for w in ws {
        match around.iter_mut().find(|m| {
            (m.t0 - w.t0).abs() <= tol
                && (m.t1 - w.t1).abs() <= tol
                && (m.r0 - w.r0).abs() <= tol
                && (m.r1 - w.r1).abs() <= tol
                && m.cone_semi_angle.is_some() == w.cone_semi_angle.is_some()
        }) {
            Some(m) => {
                m.faces.extend(&w.faces);
                m.coverage += w.coverage;
                m.split = true;
            }
            None => around.push(w),
        }
    }
    let full: Vec<Wall> = around
        .into_iter()
        .filter(|w| w.coverage >= TAU * (1.0 - 1e-6))
        .collect();
    // Along: consecutive cylinders of one radius.
    let mut out: Vec<Wall> = Vec::new();
    for w in full {
        if let Some(last) = out.last_mut()
            && last.cone_semi_angle.is_none()
            && w.cone_semi_angle.is_none()
            && (last.t1 - w.t0).abs() <= tol
            && (last.r1 - w.r0).abs() <= tol
        {
            last.t1 = w.t1;
            last.faces.extend(&w.faces);
            last.split |= w.split;
            continue;
        }
        out.push(w);
    }
    out
}

/// Runs of walls that meet end to end along the axis.
fn chains(ws: Vec<Wall>, opts: &HoleOptions) -> Vec<Vec<Wall>> {
    let mut out: Vec<Vec<Wall>> = Vec::new();
    for w in ws {
        if let Some(last) = out.last_mut()
            && let Some(prev) = last.last()
            && (prev.t1 - w.t0).abs() <= opts.length_tol_mm
        {
            last.push(w);
            continue;
        }
        out.push(vec![w]);
    }
    out
}

/// How one end of a profile is closed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum End {
    Open,
    Flat(usize),
    Point,
    /// Closed by this face, reaching this far beyond the wall's end.
    Other(usize, f64),
}

/// What the end tests need about the part's edges and faces.
struct Topology {
    /// Sample points of each edge.
    edge_points: Vec<Vec<DVec3>>,
    /// The faces that use each edge.
    edge_faces: Vec<Vec<usize>>,
    /// The edges each face uses.
    face_edges: Vec<Vec<usize>>,
}

impl Topology {
    fn new(part: &Part) -> Self {
        let edge_points = part
            .edges
            .iter()
            .map(|e| {
                (0..=8)
                    .map(|k| {
                        e.curve
                            .point(e.t_start + (e.t_end - e.t_start) * f64::from(k) / 8.0)
                    })
                    .filter(|p| p.is_finite())
                    .collect()
            })
            .collect();
        let mut edge_faces = vec![Vec::new(); part.edges.len()];
        let mut face_edges = vec![Vec::new(); part.faces.len()];
        for (fi, f) in part.faces.iter().enumerate() {
            for l in &f.loops {
                if let Loop::Edges(oes) = l {
                    for oe in oes {
                        if let Some(ef) = edge_faces.get_mut(oe.edge) {
                            if !ef.contains(&fi) {
                                ef.push(fi);
                            }
                            face_edges[fi].push(oe.edge);
                        }
                    }
                }
            }
        }
        Self {
            edge_points,
            edge_faces,
            face_edges,
        }
    }

    /// A face next to `wall` across an edge at its end `t` (radius `r`; `outward` +1 at the
    /// high end, −1 at the low end) whose boundary lies within the bore and beyond the end: it
    /// closes the hole. Returns it and how far beyond the end its surface reaches.
    #[expect(
        clippy::too_many_arguments,
        reason = "the wall, its axis, the end's position, radius and side, and the tolerance"
    )]
    fn cap(
        &self,
        part: &Part,
        ax: &AxisLine,
        wall: &Wall,
        t: f64,
        r: f64,
        outward: f64,
        tol: f64,
    ) -> Option<(usize, f64)> {
        for &f in &wall.faces {
            for &e in self.face_edges.get(f)? {
                let pts = self.edge_points.get(e)?;
                if pts.is_empty() || !pts.iter().all(|&p| (ax.coords(p).0 - t).abs() <= tol) {
                    continue;
                }
                for &g in self.edge_faces.get(e)? {
                    if wall.faces.contains(&g) {
                        continue;
                    }
                    let inside = self.face_edges[g].iter().all(|&ge| {
                        self.edge_points[ge].iter().all(|&p| {
                            let (tp, rp) = ax.coords(p);
                            rp <= r + tol && outward * (tp - t) >= -tol
                        })
                    });
                    if !inside {
                        continue;
                    }
                    // How deep: the surface over its boundary's parameter box.
                    let face = &part.faces[g];
                    let topts = TessellationOptions::for_size(2.0 * r.max(tol));
                    let mut beyond = 0.0f64;
                    if let Ok(loops) = face_param_loops(face, part, &topts) {
                        let (mut lo, mut hi) = (
                            crate::geometry::DVec2::splat(f64::INFINITY),
                            crate::geometry::DVec2::splat(f64::NEG_INFINITY),
                        );
                        for p in loops.iter().flatten() {
                            lo = lo.min(*p);
                            hi = hi.max(*p);
                        }
                        if lo.is_finite() && hi.is_finite() {
                            for i in 0..=16 {
                                for j in 0..=16 {
                                    let u = lo.x + (hi.x - lo.x) * f64::from(i) / 16.0;
                                    let v = lo.y + (hi.y - lo.y) * f64::from(j) / 16.0;
                                    let (tp, rp) = ax.coords(face.surface.point(u, v));
                                    if rp <= r + tol {
                                        beyond = beyond.max(outward * (tp - t));
                                    }
                                }
                            }
                        }
                    }
                    return Some((g, beyond));
                }
            }
        }
        None
    }
}

/// The disc face closing the profile at axial position `t` with radius `r`, if any.
fn disc_at(ax: &AxisLine, t: f64, r: f64, discs: &[Disc], opts: &HoleOptions) -> Option<usize> {
    let tol = opts.length_tol_mm.max(1e-9 * (1.0 + r));
    discs
        .iter()
        .find(|d| {
            d.normal.cross(ax.dir).length() <= opts.angle_tol_rad.max(1e-9)
                && !d.points.is_empty()
                && d.points.iter().all(|&p| {
                    let (tp, rp) = ax.coords(p);
                    (tp - t).abs() <= tol && (rp - r).abs() <= tol
                })
        })
        .map(|d| d.face)
}

fn hole_of(
    part: &Part,
    topo: &Topology,
    ax: &AxisLine,
    chain: &[Wall],
    discs: &[Disc],
    opts: &HoleOptions,
) -> Result<Option<Hole>, String> {
    let (Some(first), Some(last)) = (chain.first(), chain.last()) else {
        return Ok(None);
    };
    if !chain.iter().any(|w| w.cone_semi_angle.is_none()) {
        return Ok(None);
    }
    let tol = opts.length_tol_mm;
    let end_kind = |w: &Wall, low: bool| -> End {
        let (t, r) = if low { (w.t0, w.r0) } else { (w.t1, w.r1) };
        if w.cone_semi_angle.is_some() && r <= tol {
            End::Point
        } else if let Some(f) = disc_at(ax, t, r, discs, opts) {
            End::Flat(f)
        } else if let Some((f, beyond)) = topo.cap(
            part,
            ax,
            w,
            t,
            r,
            if low { -1.0 } else { 1.0 },
            tol.max(1e-9 * (1.0 + r)),
        ) {
            End::Other(f, beyond)
        } else {
            End::Open
        }
    };
    let lo = end_kind(first, true);
    let hi = end_kind(last, false);
    // Entry at the high end (direction +axis) or the low end.
    let entry_high = match (lo, hi) {
        (End::Open, End::Open) => {
            if (last.r1 - first.r0).abs() > tol {
                last.r1 > first.r0
            } else {
                dir_key(ax.dir) <= dir_key(-ax.dir)
            }
        }
        (_, End::Open) => true,
        (End::Open, _) => false,
        _ => {
            return Err(format!(
                "a closed cavity of diameter {:.4} mm on the axis through ({:.4}, {:.4}, {:.4}) mm is not a hole",
                2.0 * first.r0.max(last.r1),
                ax.origin.x,
                ax.origin.y,
                ax.origin.z
            ));
        }
    };
    let (direction, t_top, far) = if entry_high {
        (ax.dir, last.t1, lo)
    } else {
        (-ax.dir, first.t0, hi)
    };
    // Walls from the entry down, each as (depth of its upper end, depth of its lower end,
    // radius at its upper end, radius at its lower end).
    let mut ordered: Vec<&Wall> = chain.iter().collect();
    if entry_high {
        ordered.reverse();
    }
    let depth = |t: f64| (t_top - t).abs();
    let ends = |w: &Wall| {
        if entry_high {
            (depth(w.t1), depth(w.t0), w.r1, w.r0)
        } else {
            (depth(w.t0), depth(w.t1), w.r0, w.r1)
        }
    };
    let Some(main_idx) = ordered.iter().rposition(|w| w.cone_semi_angle.is_none()) else {
        return Ok(None);
    };
    let main = ordered[main_idx];
    let (_, main_depth, main_r, _) = ends(main);
    let after = &ordered[main_idx + 1..];
    let bottom = match far {
        End::Open => HoleBottom::Through,
        End::Flat(_) => HoleBottom::Flat,
        End::Other(_, beyond) => HoleBottom::Other {
            tip_depth_mm: after.last().map_or(main_depth, |w| ends(w).1) + beyond,
        },
        End::Point => {
            // The cone(s) below the main bore down to the tip.
            let tip = after.last().map_or(main_depth, |w| ends(w).1);
            let semi = after.last().and_then(|w| w.cone_semi_angle).unwrap_or(0.0);
            HoleBottom::Point {
                angle_rad: 2.0 * cone_half_angle_to_axis(semi),
                tip_depth_mm: tip,
            }
        }
    };
    let depth_mm = main_depth;
    let mut steps = Vec::new();
    for w in &ordered[..main_idx] {
        let (_, d1, r0, r1) = ends(w);
        match w.cone_semi_angle {
            None => steps.push(HoleStep::Cylinder {
                diameter_mm: 2.0 * r0,
                depth_mm: d1,
            }),
            Some(semi) => steps.push(HoleStep::Cone {
                top_diameter_mm: 2.0 * r0,
                bottom_diameter_mm: 2.0 * r1,
                angle_rad: 2.0 * cone_half_angle_to_axis(semi),
                depth_mm: d1,
            }),
        }
    }
    let cylinders = steps
        .iter()
        .filter(|s| matches!(s, HoleStep::Cylinder { .. }))
        .count();
    let kind = match (steps.len(), cylinders) {
        (0, _) => HoleKind::Simple,
        (_, 0) => HoleKind::Countersink,
        (_, 1) => {
            let spot = steps.iter().any(|s| {
                matches!(s, HoleStep::Cylinder { diameter_mm, depth_mm } if *depth_mm <= 0.15 * diameter_mm)
            });
            if spot {
                HoleKind::SpotFace
            } else {
                HoleKind::Counterbore
            }
        }
        _ => HoleKind::Stepped,
    };
    let mut faces: Vec<usize> = chain.iter().flat_map(|w| w.faces.iter().copied()).collect();
    for e in [lo, hi] {
        if let End::Flat(f) | End::Other(f, _) = e {
            faces.push(f);
        }
    }
    faces.sort_unstable();
    let diameter_mm = 2.0 * main_r;
    let thread_suggestion = if !matches!(bottom, HoleBottom::Through) || steps.is_empty() {
        thread_for_tap_drill(diameter_mm)
    } else {
        None
    };
    Ok(Some(Hole {
        top: ax.origin + ax.dir * t_top,
        direction,
        diameter_mm,
        depth_mm,
        bottom,
        steps,
        kind,
        faces,
        split: chain.iter().any(|w| w.split),
        thread_suggestion,
    }))
}

/// Open CASCADE's cone semi-angle is measured from the axis (`ElSLib::ConeValue`: radius grows
/// by `sin a` per unit of v, the height by `cos a`), which is the half included angle.
fn cone_half_angle_to_axis(semi: f64) -> f64 {
    semi.abs()
}
