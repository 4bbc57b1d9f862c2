//! The machine drawn in the viewport: every body of the machine file (bed, column, saddle,
//! table, trunnion, cradle, rotary table, head, spindle) placed by the machine's forward
//! kinematics at the control's axis values, in the viewport's world frame, which is the part's
//! (table) frame: the part, the stock and the tool stay where the viewport draws them and the
//! machine moves around them as it does seen from the workpiece.

use std::sync::Arc;

use glam::{DMat4, Mat4, Vec3};

use crate::app::feature::RenderIds;
use crate::control::Control;
use crate::control::collide::machine_joints;
use crate::machine::{Link, Machine, MachineJoints, Placement, Side};
use crate::render::{BoundingSphere, DataId, MeshData, MeshInstance, Rgba8};

/// Sides of a cylinder body.
const SEGMENTS: usize = 40;

/// Colours by link kind (sRGB): cast iron grey for the bed, steel for what carries the part,
/// the cradle orange, the head a blue grey, the spindle a light metal.
fn colour(side: Side, link: Link, name: &str) -> Rgba8 {
    match (side, link) {
        (_, Link::Tilt) => [212, 140, 62, 255],
        (_, Link::Rotary) => [176, 180, 188, 255],
        (Side::Bed, _) => [120, 124, 130, 255],
        (Side::Table, _) => [148, 152, 160, 255],
        (Side::Head, _) if name.contains("spindle") => [196, 200, 206, 255],
        (Side::Head, _) => [88, 104, 138, 255],
    }
}

/// One body's mesh, cached.
#[derive(Debug)]
struct BodyDraw {
    id: DataId,
    data: Arc<MeshData>,
    link: Link,
    colour: Rgba8,
}

/// The machine's meshes, built once per machine.
#[derive(Debug, Default)]
pub struct MachineView {
    machine: Option<String>,
    bodies: Vec<BodyDraw>,
    /// The camera was fitted to this machine already.
    fitted: Option<String>,
    /// The fixtures drawn, and their meshes (table frame = world).
    fixtures: Vec<crate::machine::collision::TableExtra>,
    fixture_draws: Vec<(DataId, Arc<MeshData>)>,
    /// The live stock as last meshed (table frame = world), and when a mesh was last taken.
    stock_draw: Option<(DataId, Arc<MeshData>)>,
    stock_taken: Option<std::time::Instant>,
}

/// Colour of the live stock (sRGB), as the simulation draws it.
const STOCK_COLOUR: Rgba8 = [196, 170, 120, 255];
/// Shortest time between two stock meshes in the machine view, s (meshing the stock costs
/// the cutting worker a few milliseconds each time).
const STOCK_MESH_EVERY_S: f64 = 0.25;

/// Colour of fixtures (risers, vices): aluminium.
const FIXTURE_COLOUR: Rgba8 = [200, 186, 150, 255];

/// Flat-shaded mesh data of a body (each triangle its own vertices and face normal).
fn mesh_data(mesh: &crate::machine::BodyMesh) -> MeshData {
    MeshData::flat(&mesh.vertices, &mesh.triangles)
}

/// Flat-shaded mesh data of a triangle mesh (the live stock).
fn flat_mesh_data(mesh: &crate::geometry::mesh::TriMesh) -> MeshData {
    MeshData::flat(&mesh.positions, &mesh.triangles)
}

fn mat4(p: &Placement) -> Mat4 {
    let m = DMat4::from_cols(
        p.rotation.x_axis.extend(0.0),
        p.rotation.y_axis.extend(0.0),
        p.rotation.z_axis.extend(0.0),
        p.translation.extend(1.0),
    );
    m.as_mat4()
}

/// The inverse of a rigid placement.
fn inverse(p: &Placement) -> Placement {
    let r = p.rotation.transpose();
    Placement {
        rotation: r,
        translation: -(r * p.translation),
    }
}

impl MachineView {
    fn rebuild(&mut self, machine: &Machine, ids: &RenderIds) {
        self.bodies.clear();
        self.machine = Some(machine.name.clone());
        let Some(s) = &machine.structure else {
            return;
        };
        for b in &s.bodies {
            self.bodies.push(BodyDraw {
                id: ids.next(),
                data: Arc::new(mesh_data(&b.shape.mesh(SEGMENTS))),
                link: b.link,
                colour: colour(s.side(b.link), b.link, &b.name),
            });
        }
    }

    /// The machine's bodies at `joints` with a tool of gauge length `gauge_mm`, in the part
    /// (table) frame; empty when the machine has no bodies.
    pub fn instances(
        &mut self,
        machine: &Machine,
        joints: &MachineJoints,
        gauge_mm: f64,
        ids: &RenderIds,
    ) -> Vec<MeshInstance> {
        if self.machine.as_deref() != Some(machine.name.as_str()) {
            self.rebuild(machine, ids);
        }
        let Some(links) = machine.link_placements(joints, gauge_mm) else {
            return Vec::new();
        };
        let view = inverse(&links.table);
        self.bodies
            .iter()
            .map(|b| MeshInstance {
                id: b.id,
                data: Arc::clone(&b.data),
                world_from_mesh: mat4(&view.then_inner(&links.of(b.link))),
                colour: b.colour,
                scalar_map: None,
            })
            .collect()
    }

    /// The machine at the control's position, with the gauge length of the control's tool
    /// (0 without one).
    pub fn instances_for(&mut self, control: &Control, ids: &RenderIds) -> Vec<MeshInstance> {
        let machine = control.machine();
        let joints = machine_joints(machine, &control.position());
        let gauge = control.cutter().map_or(0.0, |c| {
            c.overall_length + c.holder.iter().map(|h| h.length).sum::<f64>()
        });
        let mut out = self.instances(machine, &joints, gauge, ids);
        out.extend(self.fixture_meshes(control.fixtures(), ids));
        out
    }

    /// The live stock as it is cut, meshed at most every `STOCK_MESH_EVERY_S` (the
    /// latest mesh is drawn meanwhile; none before the first arrives or without a stock).
    pub fn stock_instance(
        &mut self,
        control: &mut Control,
        ids: &RenderIds,
    ) -> Option<MeshInstance> {
        let due = self
            .stock_taken
            .is_none_or(|t| t.elapsed().as_secs_f64() >= STOCK_MESH_EVERY_S);
        if due {
            if let Some(mesh) = control.stock_mesh() {
                self.stock_draw = Some((ids.next(), Arc::new(flat_mesh_data(&mesh))));
                self.stock_taken = Some(std::time::Instant::now());
            } else if control.cutter().is_none() {
                self.stock_draw = None;
            }
        }
        self.stock_draw.as_ref().map(|(id, data)| MeshInstance {
            id: *id,
            data: Arc::clone(data),
            world_from_mesh: Mat4::IDENTITY,
            colour: STOCK_COLOUR,
            scalar_map: None,
        })
    }

    /// The fixtures on the table (table coordinates, which are the world's).
    pub fn fixture_meshes(
        &mut self,
        fixtures: &[crate::machine::collision::TableExtra],
        ids: &RenderIds,
    ) -> Vec<MeshInstance> {
        if self.fixtures != fixtures {
            self.fixtures = fixtures.to_vec();
            self.fixture_draws.clear();
            for f in fixtures {
                let data = Arc::new(mesh_data(&f.shape.mesh(SEGMENTS)));
                self.fixture_draws.push((ids.next(), data));
            }
        }
        self.fixture_draws
            .iter()
            .map(|(id, data)| MeshInstance {
                id: *id,
                data: Arc::clone(data),
                world_from_mesh: Mat4::IDENTITY,
                colour: FIXTURE_COLOUR,
                scalar_map: None,
            })
            .collect()
    }

    /// A sphere around the instances (for the machine camera preset), once per machine: `Some`
    /// the first time a machine is shown, `None` afterwards.
    pub fn fit_once(&mut self, instances: &[MeshInstance]) -> Option<BoundingSphere> {
        if self.fitted == self.machine || instances.is_empty() {
            return None;
        }
        self.fitted.clone_from(&self.machine);
        machine_sphere(instances)
    }
}

/// The bounding sphere of placed meshes.
#[must_use]
pub fn machine_sphere(instances: &[MeshInstance]) -> Option<BoundingSphere> {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for m in instances {
        let (a, b) = m.data.bounds()?;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { a.x } else { b.x },
                if i & 2 == 0 { a.y } else { b.y },
                if i & 4 == 0 { a.z } else { b.z },
            );
            let w = m.world_from_mesh.transform_point3(c);
            lo = lo.min(w);
            hi = hi.max(w);
        }
    }
    lo.is_finite().then(|| BoundingSphere::from_box(lo, hi))
}

/// The panel's part of the 3D view: while it is open and its control exists, the machine's
/// bodies at the control's axis values and the fixtures on its table (to add to the viewport's
/// meshes), the control's tool drawn at its tip, and the camera fitted to the machine the first
/// time it is shown or when a machine camera preset is asked for. Empty otherwise.
pub fn panel_machine(
    panel: &mut crate::app::operator_panel::OperatorPanel,
    viewport: &mut crate::app::viewport::ViewportState,
    ids: &RenderIds,
) -> Vec<MeshInstance> {
    if !panel.open || panel.control().is_none() {
        return Vec::new();
    }
    let preset = panel.take_machine_view();
    viewport.machine_shown = true;
    viewport.camera.frame = glam::Mat3::IDENTITY;
    let mut view = std::mem::take(&mut panel.machine_view);
    let stock = panel
        .control_mut()
        .and_then(|c| view.stock_instance(c, ids));
    let meshes = match panel.control() {
        Some(control) => place_machine(&mut view, control, stock, preset, viewport, ids),
        None => Vec::new(),
    };
    panel.machine_view = view;
    meshes
}

/// The machine's meshes for `control` with the live `stock`; fits the camera (first showing or
/// `preset`) and draws the control's tool.
fn place_machine(
    view: &mut MachineView,
    control: &Control,
    stock: Option<MeshInstance>,
    preset: Option<crate::render::StandardView>,
    viewport: &mut crate::app::viewport::ViewportState,
    ids: &RenderIds,
) -> Vec<MeshInstance> {
    let mut meshes = view.instances_for(control, ids);
    let first = view
        .fit_once(&meshes)
        .map(|s| (crate::render::StandardView::Iso, s));
    let asked = preset.and_then(|v| machine_sphere(&meshes).map(|s| (v, s)));
    if let Some((v, sphere)) = asked.or(first) {
        viewport.camera.set_view(v);
        viewport.camera.fit(sphere, viewport.aspect);
    }
    if let Some(cutter) = control.cutter() {
        let machine = control.machine();
        let pose = machine.forward(&machine_joints(machine, &control.position()));
        viewport.tool_pose = Some(crate::app::viewport::ToolPose {
            tip: pose.tip,
            axis: pose.axis,
            cutter: cutter.clone(),
        });
    }
    // After the camera fit: the stock is inside the machine's sphere anyway.
    meshes.extend(stock);
    meshes
}
