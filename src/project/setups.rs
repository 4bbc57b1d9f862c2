//! Setups: the job's ordered list of how the part is held and machined. A setup has a name, an
//! optional machine (else the project's), a frame (work offset G54–G59, program origin and the
//! part's orientation on the table), its stock, its workholding, an optional 3+2 tilt (tool
//! orientation) and its operations in order (indices into [`Project::operations`]).
//!
//! Coordinates: a point `p` of the part is at `R·(p − o)` in the setup frame, where `R` is the
//! orientation and `o` the program origin in part coordinates; the setup frame is the program's
//! frame (the work offset's zero, +Z up the spindle). A tilted setup plans its 3-axis operations
//! in the work plane's frame `W` (its +Z the tool axis): a setup-frame point `s` is at `Wᵀ·s`
//! there. [`Placement`] holds the whole chain.

use std::path::Path;

use glam::{DMat3, DVec3};

use super::workholding::Workholding;
use super::{Project, Stock};
use crate::geometry::Aabb;
use crate::geometry::mesh::TriMesh;
use crate::import::Workpiece;
use crate::toolpath::{ExactMove, Toolpath};

/// How the part is turned onto the table.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Orientation {
    /// As modelled: the part's axes are the table's.
    #[default]
    AsModelled,
    /// Typed as angles: turned about the table's X, then Y, then Z (`R = Rz·Ry·Rx`), rad.
    Angles {
        /// Turn about X, rad.
        #[serde(default)]
        rx_rad: f64,
        /// Turn about Y, rad.
        #[serde(default)]
        ry_rad: f64,
        /// Turn about Z, rad.
        #[serde(default)]
        rz_rad: f64,
    },
    /// A planar face of the part lies on the table (its outward normal points down, −Z), then
    /// a straight edge is turned onto +X (when given), then the part is turned about Z.
    FaceOnTable {
        /// The face (index in the part's STEP order).
        face: usize,
        /// A straight edge (index in the part's edge order) to align with +X.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        x_edge: Option<usize>,
        /// A further turn about +Z, rad.
        #[serde(default)]
        rz_rad: f64,
    },
}

/// Where the setup's frame sits: the work offset, the program origin and the orientation.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Frame {
    /// Work offset number: 1 = G54 … 6 = G59.
    #[serde(default = "first_offset")]
    pub work_offset: u8,
    /// The program origin in part coordinates, mm.
    #[serde(default)]
    pub origin_mm: [f64; 3],
    /// The part's orientation on the table.
    #[serde(default)]
    pub orientation: Orientation,
}

fn first_offset() -> u8 {
    1
}

impl Default for Frame {
    fn default() -> Self {
        Self {
            work_offset: 1,
            origin_mm: [0.0; 3],
            orientation: Orientation::AsModelled,
        }
    }
}

impl Frame {
    /// The work offset's G-code word (`G54` … `G59`).
    #[must_use]
    pub fn work_offset_code(&self) -> String {
        format!("G{}", 53 + u32::from(self.work_offset.clamp(1, 6)))
    }

    /// Check the values (faces and edges are checked against the part by [`Frame::rotation`]).
    ///
    /// # Errors
    /// What is wrong, in words.
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=6).contains(&self.work_offset) {
            return Err(format!(
                "work offset {} is not one of G54…G59 (1…6)",
                self.work_offset
            ));
        }
        if self.origin_mm.iter().any(|v| !v.is_finite()) {
            return Err("the origin must be finite (mm)".into());
        }
        let angles = match self.orientation {
            Orientation::AsModelled => vec![],
            Orientation::Angles {
                rx_rad,
                ry_rad,
                rz_rad,
            } => vec![rx_rad, ry_rad, rz_rad],
            Orientation::FaceOnTable { rz_rad, .. } => vec![rz_rad],
        };
        if angles.iter().any(|a| !a.is_finite()) {
            return Err("the orientation's angles must be finite (rad)".into());
        }
        Ok(())
    }

    /// The orientation as a rotation matrix (part → setup frame), reading faces and edges from
    /// `part` where the orientation names them.
    ///
    /// # Errors
    /// A face or edge the part lacks, a face that is not planar, an edge that is not straight
    /// or stands upright after the face is laid down, or no part given when one is needed.
    pub fn rotation(&self, part: Option<&Workpiece>) -> Result<DMat3, String> {
        match self.orientation {
            Orientation::AsModelled => Ok(DMat3::IDENTITY),
            Orientation::Angles {
                rx_rad,
                ry_rad,
                rz_rad,
            } => Ok(DMat3::from_rotation_z(rz_rad)
                * DMat3::from_rotation_y(ry_rad)
                * DMat3::from_rotation_x(rx_rad)),
            Orientation::FaceOnTable {
                face,
                x_edge,
                rz_rad,
            } => {
                let part = part.ok_or("the orientation names a face but no part is loaded")?;
                let n = planar_face_normal(part, face)?;
                let down = rotation_between(n, -DVec3::Z);
                let mut r = down;
                if let Some(e) = x_edge {
                    let d = down * straight_edge_direction(part, e)?;
                    let flat = DVec3::new(d.x, d.y, 0.0);
                    if flat.length() < 1e-6 * d.length() {
                        return Err(format!(
                            "edge {} stands upright when face {} lies on the table",
                            e + 1,
                            face + 1
                        ));
                    }
                    r = DMat3::from_rotation_z(-flat.y.atan2(flat.x)) * r;
                }
                Ok(DMat3::from_rotation_z(rz_rad) * r)
            }
        }
    }
}

/// The outward unit normal of planar face `face` from the part's triangles (counter-clockwise
/// seen from outside), checked flat within 1e-6 rad.
fn planar_face_normal(part: &Workpiece, face: usize) -> Result<DVec3, String> {
    let mut sum = DVec3::ZERO;
    let mut normals = Vec::new();
    for (t, &f) in part.face_of_triangle.iter().enumerate() {
        if f as usize != face {
            continue;
        }
        if let Some([a, b, c]) = part.mesh.triangle_corners(t) {
            let n = (b - a).cross(c - a);
            sum += n;
            if n.length() > 0.0 {
                normals.push(n.normalize());
            }
        }
    }
    if part.part.is_none() {
        return Err(format!(
            "face {}: the part is a mesh without faces (pick the orientation by angles)",
            face + 1
        ));
    }
    let n = sum.normalize_or_zero();
    if normals.is_empty() || n == DVec3::ZERO {
        return Err(format!("the part has no face {}", face + 1));
    }
    if normals.iter().any(|m| m.dot(n) < 1.0 - 1e-9) {
        return Err(format!(
            "face {} is not planar: it cannot lie on the table",
            face + 1
        ));
    }
    Ok(n)
}

/// The unit direction of straight edge `edge` of the part's B-rep (start to end vertex).
fn straight_edge_direction(part: &Workpiece, edge: usize) -> Result<DVec3, String> {
    let brep = part
        .part
        .as_ref()
        .ok_or("the part is a mesh without edges")?;
    let e = brep.edges.get(edge).ok_or_else(|| {
        format!(
            "the part has no edge {} ({} edges)",
            edge + 1,
            brep.edges.len()
        )
    })?;
    if !matches!(e.curve, crate::geometry::curve::CurveGeom::Line(_)) {
        return Err(format!("edge {} is not straight", edge + 1));
    }
    let (a, b) = (
        brep.vertices.get(e.start).map(|v| v.point),
        brep.vertices.get(e.end).map(|v| v.point),
    );
    match (a, b) {
        (Some(a), Some(b)) if (b - a).length() > 1e-9 => Ok((b - a).normalize()),
        _ => Err(format!("edge {} has no length", edge + 1)),
    }
}

/// The rotation turning unit `a` onto unit `b` (about `a × b`; a half turn about X or Y when
/// they are opposite).
fn rotation_between(a: DVec3, b: DVec3) -> DMat3 {
    let c = a.dot(b);
    if c < -1.0 + 1e-12 {
        let axis = if a.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
        let axis = (axis - a * a.dot(axis)).normalize();
        return DMat3::from_axis_angle(axis, std::f64::consts::PI);
    }
    let v = a.cross(b);
    if v.length() < 1e-15 {
        return DMat3::IDENTITY;
    }
    DMat3::from_axis_angle(v.normalize(), v.length().atan2(c))
}

/// A 3+2 setup's fixed tool orientation: the tool axis in the setup frame, and the work
/// plane's X (projected square to the axis; +X of the setup frame, or +Y when the axis is
/// close to X, when not given).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tilt {
    /// The tool axis (tip → spindle) in the setup frame, any length > 0.
    pub tool_axis: [f64; 3],
    /// The work plane's X direction in the setup frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_axis: Option<[f64; 3]>,
}

impl Tilt {
    /// The work plane's frame: columns X, Y, Z (Z the tool axis) in the setup frame.
    ///
    /// # Errors
    /// A zero or non-finite axis, or an X along the tool axis.
    pub fn work_plane(&self) -> Result<DMat3, String> {
        let z = DVec3::from_array(self.tool_axis);
        if !z.is_finite() || z.length() < 1e-9 {
            return Err("tilt: the tool axis must be a finite, non-zero direction".into());
        }
        let z = z.normalize();
        let x0 = match self.x_axis {
            Some(x) => DVec3::from_array(x),
            None if z.x.abs() > 0.9 => DVec3::Y,
            None => DVec3::X,
        };
        let x = x0 - z * z.dot(x0);
        if !x.is_finite() || x.length() < 1e-6 * x0.length().max(1e-300) {
            return Err("tilt: the work plane's X lies along the tool axis".into());
        }
        let x = x.normalize();
        Ok(DMat3::from_cols(x, z.cross(x), z))
    }
}

/// The stock a setup starts from.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SetupStock {
    /// The project's stock ([`Project::stock`], in part coordinates; its default box around
    /// the part when none), carried into the setup's frame.
    #[default]
    Project,
    /// A box around the part as it lies in this setup, grown by `margin_mm` on the sides and
    /// the top (its bottom flush with the part's).
    Around {
        /// Margin, mm.
        margin_mm: f64,
    },
    /// A box given in the setup frame, mm.
    Box {
        /// Minimum corner, mm.
        min_mm: [f64; 3],
        /// Maximum corner, mm.
        max_mm: [f64; 3],
    },
    /// What the previous setup left, carried through the part's motion between the two frames.
    Previous,
}

/// One setup of the job.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Setup {
    /// Name (unique in the project).
    pub name: String,
    /// Machine name or file; `None`: the project's [`Project::machine`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine: Option<String>,
    /// Work offset, program origin and orientation.
    #[serde(default)]
    pub frame: Frame,
    /// The stock it starts from.
    #[serde(default)]
    pub stock: SetupStock,
    /// What holds the stock, in the setup frame.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub workholding: Vec<Workholding>,
    /// A fixed tool orientation (3+2 on a 5-axis machine).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt: Option<Tilt>,
    /// Its operations in machining order: indices into [`Project::operations`].
    #[serde(default)]
    pub operations: Vec<usize>,
}

impl Setup {
    /// A setup named `name` as modelled, under G54, with the project's stock and no operation.
    #[must_use]
    pub fn named(name: &str) -> Self {
        Self {
            name: name.to_string(),
            machine: None,
            frame: Frame::default(),
            stock: SetupStock::Project,
            workholding: Vec::new(),
            tilt: None,
            operations: Vec::new(),
        }
    }

    /// Check the setup's own values.
    ///
    /// # Errors
    /// What is wrong, in words.
    pub fn validate(&self) -> Result<(), String> {
        if self.name.trim().is_empty() {
            return Err("the name is empty".into());
        }
        if let Some(m) = &self.machine
            && m.trim().is_empty()
        {
            return Err("the machine name is empty".into());
        }
        self.frame.validate()?;
        match self.stock {
            SetupStock::Around { margin_mm } if !(margin_mm.is_finite() && margin_mm >= 0.0) => {
                return Err(format!(
                    "stock: the margin must be 0 mm or more, got {margin_mm}"
                ));
            }
            SetupStock::Box { min_mm, max_mm } => Stock::Box { min_mm, max_mm }
                .validate()
                .map_err(|e| format!("stock: {e}"))?,
            _ => {}
        }
        for (i, w) in self.workholding.iter().enumerate() {
            w.validate()
                .map_err(|e| format!("workholding {}: {e}", i + 1))?;
        }
        if let Some(t) = &self.tilt {
            t.work_plane()?;
        }
        Ok(())
    }

    /// The machine this setup runs on: its own, else the project's.
    #[must_use]
    pub fn machine_name<'a>(&'a self, project: &'a Project) -> &'a str {
        self.machine.as_deref().unwrap_or(&project.machine)
    }
}

/// Check the job: at least one setup, unique names, each setup's values and machine, the
/// first setup not starting from a previous one, a tilt only on a 5-axis machine, and every
/// operation in exactly one setup.
///
/// # Errors
/// What is wrong and in which setup.
pub fn check(project: &Project) -> Result<(), String> {
    if project.setups.is_empty() {
        return Err("the project has no setup".into());
    }
    let mut owner: Vec<Option<usize>> = vec![None; project.operations.len()];
    for (i, s) in project.setups.iter().enumerate() {
        let place = format!("setup {} ('{}')", i + 1, s.name);
        s.validate().map_err(|e| format!("{place}: {e}"))?;
        if project.setups[..i].iter().any(|o| o.name == s.name) {
            return Err(format!("{place}: another setup has the same name"));
        }
        if i == 0 && s.stock == SetupStock::Previous {
            return Err(format!(
                "{place}: the first setup has no previous setup to take its stock from"
            ));
        }
        let machine = crate::machine::Machine::resolve(s.machine_name(project))
            .map_err(|e| format!("{place}: machine {:?}: {e}", s.machine_name(project)))?;
        if s.tilt.is_some() && machine.rotary_names().is_none() {
            return Err(format!(
                "{place}: a tilted (3+2) setup needs a 5-axis machine, '{}' has no rotary axes",
                machine.name
            ));
        }
        for &op in &s.operations {
            let slot = owner.get_mut(op).ok_or_else(|| {
                format!(
                    "{place}: operation {} but there are {}",
                    op + 1,
                    project.operations.len()
                )
            })?;
            if let Some(other) = slot {
                return Err(format!(
                    "{place}: operation {} is already in setup {}",
                    op + 1,
                    *other + 1
                ));
            }
            *slot = Some(i);
        }
    }
    if let Some(op) = owner.iter().position(Option::is_none) {
        return Err(format!("operation {} is in no setup", op + 1));
    }
    Ok(())
}

/// The whole chain from the part to a setup's planning frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Part → setup frame rotation.
    pub rotation: DMat3,
    /// Program origin in part coordinates, mm.
    pub origin: DVec3,
    /// The work plane (columns X, Y, Z in the setup frame; identity unless tilted).
    pub work_plane: DMat3,
}

impl Placement {
    /// The placement of `setup` (faces and edges read from `part`).
    ///
    /// # Errors
    /// As [`Frame::rotation`] and [`Tilt::work_plane`].
    pub fn of(setup: &Setup, part: Option<&Workpiece>) -> Result<Self, String> {
        Ok(Self {
            rotation: setup.frame.rotation(part)?,
            origin: DVec3::from_array(setup.frame.origin_mm),
            work_plane: setup
                .tilt
                .as_ref()
                .map_or(Ok(DMat3::IDENTITY), Tilt::work_plane)?,
        })
    }

    /// A part point in the setup frame.
    #[must_use]
    pub fn to_setup(&self, p: DVec3) -> DVec3 {
        self.rotation * (p - self.origin)
    }

    /// A setup-frame point in part coordinates.
    #[must_use]
    pub fn to_part(&self, s: DVec3) -> DVec3 {
        self.rotation.transpose() * s + self.origin
    }

    /// A setup-frame point in the work plane's frame.
    #[must_use]
    pub fn setup_to_plane(&self, s: DVec3) -> DVec3 {
        self.work_plane.transpose() * s
    }

    /// A part point in the work plane's frame.
    #[must_use]
    pub fn to_plane(&self, p: DVec3) -> DVec3 {
        self.setup_to_plane(self.to_setup(p))
    }

    /// The part → work plane rotation.
    #[must_use]
    pub fn plane_rotation(&self) -> DMat3 {
        self.work_plane.transpose() * self.rotation
    }

    /// The tool axis in the setup frame (+Z unless tilted).
    #[must_use]
    pub fn tool_axis(&self) -> DVec3 {
        self.work_plane.z_axis
    }
}

/// `toolpath` moved rigidly: every point `p` to `rotation·p + offset`, every direction (tool
/// axes, arc normals, cycle axes) to `rotation·d`.
#[must_use]
pub fn transform_toolpath(toolpath: &Toolpath, rotation: DMat3, offset: DVec3) -> Toolpath {
    let mut out = toolpath.clone();
    let point = |p: DVec3| rotation * p + offset;
    for p in &mut out.poses {
        p.tip = point(p.tip);
        p.axis = rotation * p.axis;
        if let Some(cc) = p.cc.as_mut() {
            *cc = point(*cc);
        }
    }
    for s in &mut out.exact {
        match &mut s.exact {
            ExactMove::Arc(a) => {
                a.centre = point(a.centre);
                a.normal = rotation * a.normal;
            }
            ExactMove::Cycle(c) => {
                c.surface = point(c.surface);
                c.axis = rotation * c.axis;
            }
        }
    }
    out.resummarise();
    out
}

/// `mesh` moved rigidly: points to `rotation·p + offset`, normals turned.
#[must_use]
pub fn transform_mesh(mesh: &TriMesh, rotation: DMat3, offset: DVec3) -> TriMesh {
    let mut out = mesh.clone();
    for p in &mut out.positions {
        *p = rotation * *p + offset;
    }
    for n in &mut out.normals {
        *n = rotation * *n;
    }
    out
}

/// The part as a setup's 3-axis planners see it: its triangles (with their faces) in the work
/// plane's frame, so that the planners' +Z is the setup's tool axis. The exact surfaces are
/// left out (they stay in part coordinates: face finishing plans in the part frame and its
/// poses are moved with [`Placement`]).
#[must_use]
pub fn workpiece_in_plane(part: &Workpiece, placement: &Placement) -> Workpiece {
    let r = placement.plane_rotation();
    let mesh = transform_mesh(&part.mesh, r, -(r * placement.origin));
    let mut out = Workpiece::from_mesh(&part.source, mesh, part.diagnostics.clone());
    out.face_of_triangle = part.face_of_triangle.clone();
    out
}

/// A box's corners.
fn corners(min: DVec3, max: DVec3) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        DVec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    })
}

/// The solid a setup's stock starts as, a closed mesh in the setup frame (for
/// [`SetupStock::Previous`], the previous setup's starting solid carried through the part's
/// motion; the material the previous setup removed is the in-process stock's business).
/// `parts` holds each setup's placement in order; `part_bounds` the part's box in part
/// coordinates.
///
/// # Errors
/// A setup index past the end, or a stock that cannot be built.
pub fn stock_solid(
    project: &Project,
    index: usize,
    placements: &[Placement],
    part_bounds: &Aabb,
) -> Result<TriMesh, String> {
    let setup = project.setups.get(index).ok_or_else(|| {
        format!(
            "no setup {} (there are {})",
            index + 1,
            project.setups.len()
        )
    })?;
    let here = placements
        .get(index)
        .ok_or_else(|| format!("setup {}: no placement", index + 1))?;
    let boxed = |min: DVec3, max: DVec3| super::workholding::box_mesh(min, max);
    match setup.stock {
        SetupStock::Project => {
            let solid = match project.stock.or_default_for(part_bounds) {
                Stock::Box { min_mm, max_mm } => {
                    boxed(DVec3::from_array(min_mm), DVec3::from_array(max_mm))
                }
                Stock::Cylinder {
                    base_mm,
                    radius_mm,
                    height_mm,
                } => cylinder_mesh(DVec3::from_array(base_mm), radius_mm, height_mm, 128),
                Stock::None => return Err("the project's stock is empty".into()),
            };
            Ok(transform_mesh(
                &solid,
                here.rotation,
                -(here.rotation * here.origin),
            ))
        }
        SetupStock::Around { margin_mm } => {
            let b = Aabb::from_points(
                &corners(part_bounds.min, part_bounds.max)
                    .iter()
                    .map(|&c| here.to_setup(c))
                    .collect::<Vec<_>>(),
            );
            let m = DVec3::new(margin_mm, margin_mm, 0.0);
            Ok(boxed(
                b.min - m,
                b.max + DVec3::new(margin_mm, margin_mm, margin_mm),
            ))
        }
        SetupStock::Box { min_mm, max_mm } => {
            Ok(boxed(DVec3::from_array(min_mm), DVec3::from_array(max_mm)))
        }
        SetupStock::Previous => {
            let Some(prev_index) = index.checked_sub(1) else {
                return Err("the first setup has no previous setup".into());
            };
            let before = stock_solid(project, prev_index, placements, part_bounds)?;
            let (r, t) = motion_between(&placements[prev_index], here);
            Ok(transform_mesh(&before, r, t))
        }
    }
}

/// The rigid motion `(R, t)` taking setup-frame points of `from` to setup-frame points of `to`
/// (`s_to = R·s_from + t`): the part's motion between the two frames.
#[must_use]
pub fn motion_between(from: &Placement, to: &Placement) -> (DMat3, DVec3) {
    let r = to.rotation * from.rotation.transpose();
    // s_to = R_to·(R_fromᵀ·s_from + o_from − o_to)
    let t = to.rotation * (from.origin - to.origin);
    (r, t)
}

/// An upright closed cylinder (base centre, radius, height) of `n` sides.
fn cylinder_mesh(base: DVec3, radius: f64, height: f64, n: u32) -> TriMesh {
    let mut positions = vec![base, base + DVec3::Z * height];
    for i in 0..n {
        let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
        let p = base + DVec3::new(radius * a.cos(), radius * a.sin(), 0.0);
        positions.push(p);
        positions.push(p + DVec3::Z * height);
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        let (b0, t0, b1, t1) = (2 + 2 * i, 3 + 2 * i, 2 + 2 * j, 3 + 2 * j);
        triangles.push([0, b1, b0]);
        triangles.push([1, t0, t1]);
        triangles.push([b0, b1, t1]);
        triangles.push([b0, t1, t0]);
    }
    TriMesh::new(positions, triangles)
}

/// The stock box a setup's planners use, in the work plane's frame: the box around the
/// setup's starting solid there, as a [`Stock::Box`].
///
/// # Errors
/// As [`stock_solid`].
pub fn planning_stock(
    project: &Project,
    index: usize,
    placements: &[Placement],
    part_bounds: &Aabb,
) -> Result<Stock, String> {
    let solid = stock_solid(project, index, placements, part_bounds)?;
    let here = placements
        .get(index)
        .ok_or_else(|| format!("setup {}: no placement", index + 1))?;
    let b = Aabb::from_points(
        &solid
            .positions
            .iter()
            .map(|&s| here.setup_to_plane(s))
            .collect::<Vec<_>>(),
    );
    Ok(Stock::Box {
        min_mm: b.min.to_array(),
        max_mm: b.max.to_array(),
    })
}

/// The workholding meshes of setup `index` in its frame, placed around the box of its starting
/// stock; body files are read relative to `base`.
///
/// # Errors
/// As [`stock_solid`] and [`Workholding::mesh`].
pub fn workholding_meshes(
    project: &Project,
    index: usize,
    placements: &[Placement],
    part_bounds: &Aabb,
    base: &Path,
) -> Result<Vec<TriMesh>, String> {
    let setup = project
        .setups
        .get(index)
        .ok_or_else(|| format!("no setup {}", index + 1))?;
    if setup.workholding.is_empty() {
        return Ok(Vec::new());
    }
    let solid = stock_solid(project, index, placements, part_bounds)?;
    super::workholding::meshes(&setup.workholding, &solid.bbox(), base)
}

/// Every setup's placement, in order.
///
/// # Errors
/// The first setup whose frame cannot be resolved, named.
pub fn placements(project: &Project, part: Option<&Workpiece>) -> Result<Vec<Placement>, String> {
    project
        .setups
        .iter()
        .enumerate()
        .map(|(i, s)| {
            Placement::of(s, part).map_err(|e| format!("setup {} ('{}'): {e}", i + 1, s.name))
        })
        .collect()
}

/// The index of the setup holding operation `op`, if any.
#[must_use]
pub fn setup_of(project: &Project, op: usize) -> Option<usize> {
    project
        .setups
        .iter()
        .position(|s| s.operations.contains(&op))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::project::{Edit, Operation, OperationKind};
    use std::f64::consts::{FRAC_PI_2, PI};

    fn data(name: &str) -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(name)
    }

    fn plate() -> Workpiece {
        crate::import::open(
            &data("plate-hole.stp"),
            &crate::import::OpenOptions::default(),
            &crate::diagnostics::Progress::new(),
        )
        .expect("plate-hole.stp")
    }

    fn two_op_project() -> Project {
        let text = std::fs::read_to_string(data("job/old-format.talas")).expect("old file");
        Project::from_toml(&text, Path::new("old-format.talas")).expect("reads")
    }

    #[test]
    fn an_old_project_opens_as_one_setup_holding_every_operation() {
        let p = two_op_project();
        assert_eq!(p.setups.len(), 1);
        let s = &p.setups[0];
        assert_eq!(s.name, "Setup 1");
        assert_eq!(s.frame.work_offset, 2);
        assert_eq!(s.frame.origin_mm, [1.5, -2.0, 20.0]);
        assert_eq!(s.frame.orientation, Orientation::AsModelled);
        assert_eq!(s.operations, vec![0, 1]);
        assert_eq!(p.legacy_setup, None);
        // Written strictly: only `[[setups]]`, and it reads back the same.
        let text = p.to_toml().expect("writes");
        assert!(
            text.contains("[[setups]]") && !text.contains("[setup]"),
            "{text}"
        );
        let back = Project::from_toml(&text, Path::new("new.talas")).expect("reads back");
        assert_eq!(back, p);
        // Posting it still subtracts the old origin (program = part − origin) under G55.
        let record = crate::toolpath::ToolRecord {
            spec: crate::tools::tool_spec(&p.tools[0].cutter),
            cutter: p.tools[0].cutter.clone(),
        };
        let mut tp = Toolpath::new(record, Vec::new());
        tp.poses.push(crate::toolpath::Pose::new(
            crate::toolpath::MoveKind::Cut,
            DVec3::new(10.0, 10.0, 21.0),
            DVec3::Z,
            1000.0,
        ));
        let posted = crate::project::posting::post_operation(&p, 0, &tp, 1).expect("posts");
        assert!(posted.text.contains("G55"), "{}", posted.text);
        assert!(
            posted.text.contains("X8.5") && posted.text.contains("Y12"),
            "{}",
            posted.text
        );
    }

    #[test]
    fn the_job_is_checked_with_clear_messages() {
        let p = two_op_project();
        let err = |f: &dyn Fn(&mut Project)| {
            let mut q = p.clone();
            f(&mut q);
            q.check().unwrap_err()
        };
        let mut second = Setup::named("Flip");
        second.stock = SetupStock::Previous;
        let e = err(&|q| {
            q.setups.push(second.clone());
            q.setups[1].operations = vec![1];
        });
        assert_eq!(e, "setup 2 ('Flip'): operation 2 is already in setup 1");
        let e = err(&|q| q.setups[0].operations = vec![0]);
        assert_eq!(e, "operation 2 is in no setup");
        let e = err(&|q| q.setups[0].operations.push(7));
        assert_eq!(e, "setup 1 ('Setup 1'): operation 8 but there are 2");
        let e = err(&|q| q.setups[0].stock = SetupStock::Previous);
        assert!(e.contains("no previous setup"), "{e}");
        let e = err(&|q| q.setups.push(Setup::named("Setup 1")));
        assert!(e.contains("same name"), "{e}");
        let e = err(&|q| {
            q.setups[0].tilt = Some(Tilt {
                tool_axis: [0.0, -1.0, 1.0],
                x_axis: None,
            });
        });
        assert!(e.contains("needs a 5-axis machine"), "{e}");
        let e = err(&|q| q.setups[0].frame.work_offset = 9);
        assert!(e.contains("G54…G59"), "{e}");
        // Both the old and the new field in one file.
        let text = std::fs::read_to_string(data("job/old-format.talas")).unwrap()
            + "\n[[setups]]\nname = \"A\"\noperations = [0, 1]\n";
        let e = Project::from_toml(&text, Path::new("both.talas")).unwrap_err();
        assert!(
            e.to_string().starts_with("both.talas: the file gives both"),
            "{e}"
        );
    }

    #[test]
    fn typed_angles_turn_the_part_as_the_closed_forms_say() {
        let mut s = Setup::named("A");
        s.frame.orientation = Orientation::Angles {
            rx_rad: FRAC_PI_2,
            ry_rad: 0.0,
            rz_rad: FRAC_PI_2,
        };
        s.frame.origin_mm = [1.0, 2.0, 3.0];
        let pl = Placement::of(&s, None).unwrap();
        // Rx(90°): (x, y, z) → (x, −z, y); then Rz(90°): (x, y, z) → (−y, x, z).
        let p = DVec3::new(5.0, 7.0, 11.0);
        let d = p - DVec3::new(1.0, 2.0, 3.0);
        let want = DVec3::new(d.z, d.x, d.y);
        assert!((pl.to_setup(p) - want).length() < 1e-12);
        assert!((pl.to_part(pl.to_setup(p)) - p).length() < 1e-12);
    }

    #[test]
    fn a_face_laid_on_the_table_faces_down_and_an_edge_lines_up_with_x() {
        let part = plate();
        // The plate's top face (z = 5, outward normal +Z): which face index it is, found from
        // the triangles' heights (independent of the normal computation).
        let top = (0..7)
            .find(|&f| {
                let zs: Vec<f64> = part
                    .face_of_triangle
                    .iter()
                    .enumerate()
                    .filter(|(_, ff)| **ff as usize == f)
                    .flat_map(|(t, _)| part.mesh.triangle_corners(t).unwrap())
                    .map(|c| c.z)
                    .collect();
                !zs.is_empty() && zs.iter().all(|z| (z - 5.0).abs() < 1e-9)
            })
            .expect("a top face");
        let mut s = Setup::named("Flip");
        s.frame.orientation = Orientation::FaceOnTable {
            face: top,
            x_edge: None,
            rz_rad: 0.0,
        };
        let pl = Placement::of(&s, Some(&part)).unwrap();
        // Turned over: the top (z = 5) goes to the bottom, the bottom (z = 0) above it, by 5 mm.
        let a = pl.to_setup(DVec3::new(3.0, 4.0, 5.0));
        let b = pl.to_setup(DVec3::new(3.0, 4.0, 0.0));
        assert!((b.z - a.z - 5.0).abs() < 1e-9, "{a} {b}");
        // An edge of the top face along part Y (x = 15) turned onto +X.
        let brep = part.part.as_ref().unwrap();
        let edge = brep
            .edges
            .iter()
            .position(|e| {
                let (p, q) = (brep.vertices[e.start].point, brep.vertices[e.end].point);
                (p.x - 15.0).abs() < 1e-9
                    && (q.x - 15.0).abs() < 1e-9
                    && (p.z - 5.0).abs() < 1e-9
                    && (q.z - 5.0).abs() < 1e-9
            })
            .expect("edge x = 15 on top");
        s.frame.orientation = Orientation::FaceOnTable {
            face: top,
            x_edge: Some(edge),
            rz_rad: 0.0,
        };
        let pl = Placement::of(&s, Some(&part)).unwrap();
        let (p, q) = (
            brep.vertices[brep.edges[edge].start].point,
            brep.vertices[brep.edges[edge].end].point,
        );
        let d = (pl.to_setup(q) - pl.to_setup(p)).normalize();
        assert!((d - DVec3::X).length() < 1e-9, "{d}");
        assert!((pl.rotation * DVec3::Z + DVec3::Z).length() < 1e-9);
        // The hole's wall is not planar; a face past the end is named.
        s.frame.orientation = Orientation::FaceOnTable {
            face: 99,
            x_edge: None,
            rz_rad: 0.0,
        };
        assert_eq!(
            Placement::of(&s, Some(&part)).unwrap_err(),
            "the part has no face 100"
        );
        let cyl = (0..7)
            .find(|&f| {
                matches!(
                    part.surfaces[f].as_deref(),
                    Some(crate::geometry::surface::SurfaceGeom::Cylinder(_))
                )
            })
            .unwrap();
        s.frame.orientation = Orientation::FaceOnTable {
            face: cyl,
            x_edge: None,
            rz_rad: 0.0,
        };
        assert!(
            Placement::of(&s, Some(&part))
                .unwrap_err()
                .contains("not planar")
        );
    }

    #[test]
    fn the_stock_is_carried_through_the_flip_with_its_volume() {
        let mut p = two_op_project();
        let mut flip = Setup::named("Flip");
        flip.frame.work_offset = 2;
        flip.frame.origin_mm = [25.0, 20.0, 22.0];
        flip.frame.orientation = Orientation::Angles {
            rx_rad: PI,
            ry_rad: 0.0,
            rz_rad: 0.0,
        };
        flip.stock = SetupStock::Previous;
        p.setups.push(flip);
        p.check().unwrap();
        let bounds = Aabb::from_points(&[DVec3::ZERO, DVec3::new(50.0, 40.0, 20.0)]);
        let pl = placements(&p, None).unwrap();
        let s1 = stock_solid(&p, 0, &pl, &bounds).unwrap();
        let s2 = stock_solid(&p, 1, &pl, &bounds).unwrap();
        // 54 × 44 × 22 mm in both frames.
        let v = 54.0 * 44.0 * 22.0;
        assert!((s1.signed_volume() - v).abs() < 1e-9 * v);
        assert!((s2.signed_volume() - v).abs() < 1e-9 * v);
        // Turned over about X, (x, y, z) → (x, −y, −z) about the origin (25, 20, 22): the old
        // top (z = 22) lies on the table at z = 0, the old bottom is the new top at z = 22;
        // x −27…27 and y −22…22 about the origin.
        let b = s2.bbox();
        assert!(
            b.min.z.abs() < 1e-9 && (b.max.z - 22.0).abs() < 1e-9,
            "{b:?}"
        );
        assert!(
            (b.min.x + 27.0).abs() < 1e-9 && (b.max.x - 27.0).abs() < 1e-9,
            "{b:?}"
        );
        assert!(
            (b.min.y + 22.0).abs() < 1e-9 && (b.max.y - 22.0).abs() < 1e-9,
            "{b:?}"
        );
        // The planning box of the flipped setup is the same box.
        let Stock::Box { min_mm, max_mm } = planning_stock(&p, 1, &pl, &bounds).unwrap() else {
            panic!("a box")
        };
        assert!(min_mm[2].abs() < 1e-9 && (max_mm[2] - 22.0).abs() < 1e-9);
        // Every part point goes to the same place by the motion as by the frame.
        let (r, t) = motion_between(&pl[0], &pl[1]);
        let q = DVec3::new(3.0, -7.0, 12.0);
        assert!((r * pl[0].to_setup(q) + t - pl[1].to_setup(q)).length() < 1e-12);
    }

    #[test]
    fn a_tilted_setup_plans_on_the_part_in_its_work_plane() {
        let part = plate();
        let mut s = Setup::named("Tilt");
        s.tilt = Some(Tilt {
            tool_axis: [0.0, -1.0, 1.0],
            x_axis: None,
        });
        let pl = Placement::of(&s, None).unwrap();
        let w = workpiece_in_plane(&part, &pl);
        // A 45° tilt about X: the work plane's Z is (0, −1, 1)/√2, so part (0, −15, 0) is at
        // height 15/√2 and (0, 15, 5) at (−15 + 5)/√2.
        let h = |p: DVec3| pl.to_plane(p).z;
        let r = std::f64::consts::FRAC_1_SQRT_2;
        assert!((h(DVec3::new(0.0, -15.0, 0.0)) - 15.0 * r).abs() < 1e-12);
        assert!((h(DVec3::new(0.0, 15.0, 5.0)) + 10.0 * r).abs() < 1e-12);
        let top = w.mesh.bbox().max.z;
        assert!((top - (15.0 + 5.0) * r).abs() < 1e-9, "{top}");
        assert_eq!(w.face_of_triangle, part.face_of_triangle);
        assert!((pl.tool_axis() - DVec3::new(0.0, -r, r)).length() < 1e-12);
    }

    #[test]
    fn editing_operations_keeps_every_one_in_its_setup_and_undoes_exactly() {
        let mut p = two_op_project();
        p.setups.push(Setup::named("Flip"));
        let start = p.clone();
        let inv_move = p
            .apply(Edit::MoveOperation {
                operation: 1,
                setup: 1,
                position: 0,
            })
            .unwrap();
        assert_eq!(p.setups[0].operations, vec![0]);
        assert_eq!(p.setups[1].operations, vec![1]);
        let after_move = p.clone();
        // A new operation after operation 2 goes to its setup; the old indices shift.
        let op = Operation::new(OperationKind::Raster, 0, 0);
        let inv_add = p
            .apply(Edit::AddOperation {
                index: 0,
                operation: op,
            })
            .unwrap();
        assert_eq!(p.setups[0].operations, vec![0, 1]);
        assert_eq!(p.setups[1].operations, vec![2]);
        p.check().unwrap();
        p.apply(inv_add).unwrap();
        assert_eq!(p, after_move);
        let inv_remove = p.apply(Edit::RemoveOperation { index: 1 }).unwrap();
        assert_eq!(p.setups[1].operations, Vec::<usize>::new());
        p.check().unwrap();
        p.apply(inv_remove).unwrap();
        assert_eq!(p, after_move);
        p.apply(inv_move).unwrap();
        assert_eq!(p, start);
        // A setup holding operations is not removed.
        assert!(p.apply(Edit::RemoveSetup { index: 0 }).is_err());
        let inv = p.apply(Edit::RemoveSetup { index: 1 }).unwrap();
        assert_eq!(p.setups.len(), 1);
        p.apply(inv).unwrap();
        assert_eq!(p, start);
    }
}
