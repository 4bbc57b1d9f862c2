//! Topology: shells of faces, faces bounded by loops, loops of oriented edges, edges between
//! vertices. Vertices and edges are shared by entity id within one placed representation, so an
//! `EDGE_CURVE` used by two faces becomes one [`Edge`].

use std::collections::BTreeMap;

use super::chains;
use super::curves::{curve, edge_params};
use super::entities::{Entity, Model};
use super::placement::Rigid;
use super::points::Geo;
use super::surfaces::surface;
use super::{BrepError, ErrorKind};
use crate::diagnostics::Diagnostic;
use crate::geometry::brep::{Edge, Face, Loop, OrientedEdge, Part, Shell, Vertex};
use crate::geometry::curve::{CurveGeom, Line};
use crate::geometry::surface::SurfaceGeom;

/// Deepest chain of oriented wrappers (`ORIENTED_EDGE` of `ORIENTED_EDGE`, ...) followed.
const MAX_WRAP_DEPTH: usize = 4;

/// The part being built, with what went wrong so far.
pub(super) struct Builder<'m, 'a> {
    /// The file.
    pub model: &'m Model<'a>,
    /// The result.
    pub part: Part,
    /// The first face that failed (returned when no face could be built at all).
    pub first_error: Option<BrepError>,
    /// Faces skipped so far.
    pub faces_skipped: usize,
}

/// One representation placed in the part: its units and placement, and the vertices and edges
/// already made from its entities.
pub(super) struct Placed<'m, 'a> {
    /// Geometry reader in the representation's units.
    pub geo: Geo<'m, 'a>,
    /// Placement of the representation in the part.
    pub xf: Rigid,
    vertices: BTreeMap<u64, usize>,
    edges: BTreeMap<u64, usize>,
}

impl<'m, 'a> Placed<'m, 'a> {
    /// A fresh placement (no vertices or edges shared with earlier ones).
    pub fn new(geo: Geo<'m, 'a>, xf: Rigid) -> Self {
        Self {
            geo,
            xf,
            vertices: BTreeMap::new(),
            edges: BTreeMap::new(),
        }
    }
}

impl<'m, 'a> Builder<'m, 'a> {
    /// An empty part.
    pub fn new(model: &'m Model<'a>) -> Self {
        Self {
            model,
            part: Part::default(),
            first_error: None,
            faces_skipped: 0,
        }
    }

    /// Note a face that could not be built; the part goes on without it.
    pub fn skip_face(&mut self, face_id: u64, err: BrepError) {
        self.part.diagnostics.push(Diagnostic::warning(
            Some(format!("#{face_id}")),
            format!("face skipped: {err}"),
        ));
        self.faces_skipped += 1;
        if self.first_error.is_none() {
            self.first_error = Some(err);
        }
    }

    /// Add a shell (`CLOSED_SHELL`, `OPEN_SHELL`, their `ORIENTED_` forms, `CONNECTED_FACE_SET`).
    pub fn shell(
        &mut self,
        pl: &mut Placed<'m, 'a>,
        from: Entity<'_>,
        id: u64,
        flip: bool,
        depth: usize,
    ) -> Result<(), BrepError> {
        let e = self.model.entity(from, id)?;
        if depth > MAX_WRAP_DEPTH {
            return Err(e.error(ErrorKind::Cycle, "shell wrappers nest too deeply"));
        }
        if let Ok(a) = e.args_any(&["ORIENTED_CLOSED_SHELL", "ORIENTED_OPEN_SHELL"]) {
            let element = a.reference(2, "shell_element")?;
            let orientation = a.boolean(3, "orientation")?;
            return self.shell(pl, e, element, flip ^ !orientation, depth + 1);
        }
        let a = e.args_any(&["CLOSED_SHELL", "OPEN_SHELL", "CONNECTED_FACE_SET"])?;
        let closed = a.rec.name == "CLOSED_SHELL";
        let face_ids = a.refs(1, "faces")?;
        let mut faces = Vec::with_capacity(face_ids.len());
        for fid in face_ids {
            match self.face(pl, e, fid, flip, 0) {
                Ok(face) => {
                    faces.push(self.part.faces.len());
                    self.part.faces.push(face);
                }
                Err(err) => self.skip_face(fid, err),
            }
        }
        self.part.shells.push(Shell {
            faces,
            closed,
            source_id: e.id(),
        });
        Ok(())
    }

    /// Add a lone face (a representation item that is a face) as a one-face open shell.
    pub fn lone_face(&mut self, pl: &mut Placed<'m, 'a>, from: Entity<'_>, id: u64) {
        match self.face(pl, from, id, false, 0) {
            Ok(face) => {
                self.part.shells.push(Shell {
                    faces: vec![self.part.faces.len()],
                    closed: false,
                    source_id: id,
                });
                self.part.faces.push(face);
            }
            Err(err) => self.skip_face(id, err),
        }
    }

    /// An element of a geometric set: a B-spline surface becomes a face over its whole domain;
    /// anything else (points, curves, unbounded surfaces) is passed over.
    pub fn set_surface(&mut self, pl: &mut Placed<'m, 'a>, from: Entity<'_>, id: u64) {
        let Some(e) = self.model.get(id) else {
            self.part.diagnostics.push(Diagnostic::warning(
                Some(format!("#{}", from.id())),
                format!("geometric set element #{id} is not in the file"),
            ));
            return;
        };
        let is_spline = [
            "B_SPLINE_SURFACE",
            "B_SPLINE_SURFACE_WITH_KNOTS",
            "BEZIER_SURFACE",
        ]
        .iter()
        .any(|n| e.has(n));
        if !is_spline {
            return;
        }
        match surface(&pl.geo, from, id, 0) {
            Ok(s) => {
                self.part.shells.push(Shell {
                    faces: vec![self.part.faces.len()],
                    closed: false,
                    source_id: id,
                });
                self.part.faces.push(Face {
                    surface: pl.xf.surface(&s),
                    same_sense: true,
                    loops: Vec::new(),
                    outer: None,
                    source_id: id,
                });
            }
            Err(err) => self.skip_face(id, err),
        }
    }

    /// Build one face (`ADVANCED_FACE`, `FACE_SURFACE`, `ORIENTED_FACE`).
    fn face(
        &mut self,
        pl: &mut Placed<'m, 'a>,
        from: Entity<'_>,
        id: u64,
        flip: bool,
        depth: usize,
    ) -> Result<Face, BrepError> {
        let e = self.model.entity(from, id)?;
        if depth > MAX_WRAP_DEPTH {
            return Err(e.error(ErrorKind::Cycle, "face wrappers nest too deeply"));
        }
        if e.has("ORIENTED_FACE") {
            let a = e.args("ORIENTED_FACE")?;
            let element = a.reference(2, "face_element")?;
            let orientation = a.boolean(3, "orientation")?;
            return self.face(pl, e, element, flip ^ !orientation, depth + 1);
        }
        let a = e.args_any(&["ADVANCED_FACE", "FACE_SURFACE"])?;
        let bounds = a.refs(1, "bounds")?;
        let surf = pl
            .xf
            .surface(&surface(&pl.geo, e, a.reference(2, "face_geometry")?, 0)?);
        let same_sense = a.boolean(3, "same_sense")? ^ flip;
        if bounds.is_empty()
            && !matches!(
                surf,
                SurfaceGeom::BSpline(_) | SurfaceGeom::Sphere(_) | SurfaceGeom::Torus(_)
            )
        {
            return Err(e.error(
                ErrorKind::BadParameter,
                "face has no bounds on an unbounded surface",
            ));
        }
        let mut loops = Vec::with_capacity(bounds.len());
        let mut outer = None;
        for bid in bounds {
            let (lp, is_outer) = self.bound(pl, e, bid)?;
            if is_outer && outer.is_none() {
                loops.insert(0, lp);
                outer = Some(0);
            } else {
                loops.push(lp);
            }
        }
        Ok(Face {
            surface: surf,
            same_sense,
            loops,
            outer,
            source_id: e.id(),
        })
    }

    /// A `FACE_OUTER_BOUND` / `FACE_BOUND`: the loop, oriented, and whether it is the outer one.
    fn bound(
        &mut self,
        pl: &mut Placed<'m, 'a>,
        from: Entity<'_>,
        id: u64,
    ) -> Result<(Loop, bool), BrepError> {
        let e = self.model.entity(from, id)?;
        let a = e.args_any(&["FACE_OUTER_BOUND", "FACE_BOUND"])?;
        let is_outer = a.rec.name == "FACE_OUTER_BOUND";
        let orientation = a.boolean(2, "orientation")?;
        let l = self.model.entity(e, a.reference(1, "bound")?)?;
        if l.has("VERTEX_LOOP") {
            let v = self.vertex(pl, l, l.args("VERTEX_LOOP")?.reference(1, "loop_vertex")?)?;
            return Ok((Loop::Vertex(v), is_outer));
        }
        let mut edges = if l.has("POLY_LOOP") {
            self.poly_loop(pl, l)?
        } else {
            let ids = l.args("EDGE_LOOP")?.refs(1, "edge_list")?;
            if ids.is_empty() {
                return Err(l.error(ErrorKind::BadParameter, "empty edge loop"));
            }
            ids.into_iter()
                .map(|oid| self.oriented_edge(pl, l, oid, 0))
                .collect::<Result<Vec<_>, _>>()?
        };
        if !orientation {
            edges.reverse();
            for oe in &mut edges {
                oe.forward = !oe.forward;
            }
        }
        if !chains::is_chain(&self.part, &edges) {
            let place = Some(format!("#{}", l.id()));
            if let Some(fixed) = chains::repair(&self.part, &edges) {
                edges = fixed;
                self.part.diagnostics.push(Diagnostic::warning(
                    place,
                    "loop edges reordered or reversed into a closed chain",
                ));
            } else {
                self.part.diagnostics.push(Diagnostic::warning(
                    place,
                    "loop edges do not form a closed chain",
                ));
            }
        }
        Ok((Loop::Edges(edges), is_outer))
    }

    /// An `ORIENTED_EDGE` (or a bare `EDGE_CURVE`, used forward).
    fn oriented_edge(
        &mut self,
        pl: &mut Placed<'m, 'a>,
        from: Entity<'_>,
        id: u64,
        depth: usize,
    ) -> Result<OrientedEdge, BrepError> {
        let e = self.model.entity(from, id)?;
        if depth > MAX_WRAP_DEPTH {
            return Err(e.error(ErrorKind::Cycle, "oriented edges nest too deeply"));
        }
        if e.has("EDGE_CURVE") {
            return Ok(OrientedEdge {
                edge: self.edge(pl, from, id)?,
                forward: true,
            });
        }
        let a = e.args("ORIENTED_EDGE")?;
        let inner = self.oriented_edge(pl, e, a.reference(3, "edge_element")?, depth + 1)?;
        let orientation = a.boolean(4, "orientation")?;
        Ok(OrientedEdge {
            edge: inner.edge,
            forward: inner.forward == orientation,
        })
    }

    /// The `EDGE_CURVE` `#id`, made once per placed representation.
    fn edge(
        &mut self,
        pl: &mut Placed<'m, 'a>,
        from: Entity<'_>,
        id: u64,
    ) -> Result<usize, BrepError> {
        if let Some(&i) = pl.edges.get(&id) {
            return Ok(i);
        }
        let e = self.model.entity(from, id)?;
        let a = e.args("EDGE_CURVE")?;
        let start = self.vertex(pl, e, a.reference(1, "edge_start")?)?;
        let end = self.vertex(pl, e, a.reference(2, "edge_end")?)?;
        let geom = pl
            .xf
            .curve(&curve(&pl.geo, e, a.reference(3, "edge_geometry")?, 0)?);
        let same_sense = a.boolean(4, "same_sense")?;
        let (ps, pe) = match (self.part.vertices.get(start), self.part.vertices.get(end)) {
            (Some(s), Some(t)) => (s.point, t.point),
            _ => return Err(e.error(ErrorKind::BadParameter, "edge vertices missing")),
        };
        let (t_start, t_end) = edge_params(&geom, ps, pe, start == end, same_sense);
        if !(t_start.is_finite() && t_end.is_finite()) {
            return Err(e.error(ErrorKind::InvalidGeometry, "edge parameters are not finite"));
        }
        let i = self.part.edges.len();
        self.part.edges.push(Edge {
            start,
            end,
            curve: geom,
            t_start,
            t_end,
            source_id: id,
        });
        pl.edges.insert(id, i);
        Ok(i)
    }

    /// The `VERTEX_POINT` `#id`, made once per placed representation.
    fn vertex(
        &mut self,
        pl: &mut Placed<'m, 'a>,
        from: Entity<'_>,
        id: u64,
    ) -> Result<usize, BrepError> {
        if let Some(&i) = pl.vertices.get(&id) {
            return Ok(i);
        }
        let e = self.model.entity(from, id)?;
        let p = pl
            .geo
            .point(e, e.args("VERTEX_POINT")?.reference(1, "vertex_geometry")?)?;
        let i = self.part.vertices.len();
        self.part.vertices.push(Vertex {
            point: pl.xf.point(p),
            source_id: id,
        });
        pl.vertices.insert(id, i);
        Ok(i)
    }

    /// A `POLY_LOOP` (faceted B-rep): straight edges between its points, keyed by point id.
    fn poly_loop(
        &mut self,
        pl: &mut Placed<'m, 'a>,
        l: Entity<'_>,
    ) -> Result<Vec<OrientedEdge>, BrepError> {
        let ids = l.args("POLY_LOOP")?.refs(1, "polygon")?;
        if ids.len() < 3 {
            return Err(l.error(
                ErrorKind::BadParameter,
                "a poly loop needs at least three points",
            ));
        }
        let mut verts = Vec::with_capacity(ids.len());
        for &pid in &ids {
            let v = match pl.vertices.get(&pid) {
                Some(&v) => v,
                None => {
                    let p = pl.xf.point(pl.geo.point(l, pid)?);
                    let v = self.part.vertices.len();
                    self.part.vertices.push(Vertex {
                        point: p,
                        source_id: pid,
                    });
                    pl.vertices.insert(pid, v);
                    v
                }
            };
            verts.push(v);
        }
        let mut out = Vec::with_capacity(verts.len());
        for (k, &a) in verts.iter().enumerate() {
            let b = verts.get((k + 1) % verts.len()).copied().unwrap_or(a);
            let (Some(pa), Some(pb)) = (self.part.vertices.get(a), self.part.vertices.get(b))
            else {
                continue;
            };
            let (pa, pb) = (pa.point, pb.point);
            let Some(dir) = (pb - pa).try_normalize() else {
                continue;
            };
            out.push(OrientedEdge {
                edge: self.part.edges.len(),
                forward: true,
            });
            self.part.edges.push(Edge {
                start: a,
                end: b,
                curve: CurveGeom::Line(Line { origin: pa, dir }),
                t_start: 0.0,
                t_end: pa.distance(pb),
                source_id: l.id(),
            });
        }
        if out.len() < 3 {
            return Err(l.error(ErrorKind::InvalidGeometry, "poly loop is degenerate"));
        }
        Ok(out)
    }
}
