//! The 3D viewport: turns the document into a [`Scene`], handles navigation and picking, and
//! hands the scene to the renderer through an egui-wgpu paint callback ([`bridge`]). Over the
//! part: the tool at its pose and the work-offset marker ([`tool_model`]); in the upper-right
//! corner, the view cube ([`view_cube`]).

pub mod bridge;
pub mod legend;
pub mod navigation;
pub mod picking;
pub mod tool_model;
pub mod view_cube;

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};

use super::command::Command;
use super::document::{Document, Selection};
use super::scalar_field::ScalarField;
use crate::render::triad::{AXIS_COLOURS, label_positions};
use crate::render::{
    BoundingSphere, Camera, DataId, DisplayOptions, LineInstance, MeshData, MeshInstance,
    Projection, ScalarMapping, Scene, StandardView,
};
use crate::toolpath::Toolpath;
pub use tool_model::ToolPose;

/// Colour of the part (sRGB): a light steel grey-blue.
const PART_COLOUR: [u8; 4] = [176, 186, 200, 255];
/// Colour of the selected face: green, a colour no move kind of a tool path has.
const SELECTED_COLOUR: [u8; 4] = [90, 215, 120, 255];

/// The viewport's own state (view settings; not part of the document).
#[derive(Debug)]
pub struct ViewportState {
    /// The camera.
    pub camera: Camera,
    /// Background, grid and triad settings.
    pub options: DisplayOptions,
    /// Draw the part's feature edges.
    pub show_edges: bool,
    /// The point of the part under the cursor (mm), if any.
    pub hover_point: Option<DVec3>,
    /// Fit the view at the next frame (the viewport's aspect is known only then).
    pub fit_requested: bool,
    /// Aspect of the last frame (width / height).
    pub aspect: f32,
    /// The scalar field shown on the part, if any.
    pub scalar_field: Option<ScalarField>,
    /// The tool drawn at its pose (playback, simulation), if any.
    pub tool_pose: Option<ToolPose>,
    /// The work offset marked by coloured axes, if any: world from the program's frame (its
    /// origin, mm, and its X, Y, Z: the active setup's).
    pub work_offset: Option<Mat4>,
    /// The camera orbits in the active setup's frame, so the part is seen as it lies on that
    /// setup's table ("Top" looks down its spindle); off, it orbits the part's own Z.
    pub orient_to_setup: bool,
    /// The operator panel's machine is drawn this frame (machine coordinates: the setup's frame
    /// and work offset do not apply). Cleared before the features steer the view.
    pub machine_shown: bool,
    tool_mesh: Option<tool_model::ToolMesh>,
    marker_lines: Option<tool_model::MarkerLines>,
    /// The part's mesh with the shown field: ((document id, field), render id, mesh, mapping).
    field_mesh: Option<FieldMesh>,
    /// The selected face's triangles: ((document id, face), render id, mesh).
    highlight: Option<((DataId, usize), DataId, Arc<MeshData>)>,
    next_id: DataId,
}

/// The part's mesh carrying a scalar field, cached per (document, field).
#[derive(Debug)]
struct FieldMesh {
    key: (DataId, ScalarField),
    id: DataId,
    data: Arc<MeshData>,
    mapping: ScalarMapping,
}

impl Default for ViewportState {
    fn default() -> Self {
        Self {
            camera: Camera::default(),
            options: DisplayOptions::default(),
            show_edges: true,
            hover_point: None,
            fit_requested: true,
            aspect: 1.5,
            scalar_field: None,
            tool_pose: None,
            work_offset: None,
            orient_to_setup: true,
            machine_shown: false,
            tool_mesh: None,
            marker_lines: None,
            field_mesh: None,
            highlight: None,
            // Document ids count up from 1; highlight ids live far above them.
            next_id: 1 << 40,
        }
    }
}

impl ViewportState {
    /// Fit the camera to the document (or to a default box when there is none).
    pub fn fit(&mut self, document: Option<&Document>) {
        let sphere = document.filter(|d| !d.bounds.is_empty()).map_or(
            BoundingSphere {
                centre: Vec3::ZERO,
                radius: 50.0,
            },
            |d| BoundingSphere::from_box(d.bounds.min.as_vec3(), d.bounds.max.as_vec3()),
        );
        self.camera.fit(sphere, self.aspect);
        self.fit_requested = false;
    }

    /// Snap to a standard view and fit.
    pub fn set_view(&mut self, view: StandardView, document: Option<&Document>) {
        self.camera.set_view(view);
        self.fit(document);
    }

    /// Switch projection.
    pub fn set_projection(&mut self, projection: Projection) {
        self.camera.projection = projection;
    }

    /// The scene for this frame.
    #[must_use]
    pub fn scene(&mut self, document: Option<&Document>) -> Scene {
        let mut options = self.options;
        let mut meshes = Vec::new();
        let mut lines = Vec::new();
        if let Some(doc) = document {
            if !doc.bounds.is_empty() {
                let size = (doc.bounds.max - doc.bounds.min).max_element() as f32;
                options.grid_z = doc.bounds.min.z as f32;
                options.grid_spacing = DisplayOptions::grid_spacing_for(size);
                self.camera.scene =
                    BoundingSphere::from_box(doc.bounds.min.as_vec3(), doc.bounds.max.as_vec3());
            }
            let field = self.field_mesh(doc);
            meshes.push(match field {
                Some((id, data, mapping)) => MeshInstance {
                    id,
                    data,
                    world_from_mesh: Mat4::IDENTITY,
                    colour: PART_COLOUR,
                    scalar_map: Some(mapping),
                },
                None => MeshInstance {
                    id: doc.ids[0],
                    data: Arc::clone(&doc.render_mesh),
                    world_from_mesh: Mat4::IDENTITY,
                    colour: PART_COLOUR,
                    scalar_map: None,
                },
            });
            if let Selection::Face(face) = doc.selection {
                let key = (doc.ids[0], face);
                if self.highlight.as_ref().is_none_or(|(k, _, _)| *k != key) {
                    self.next_id += 1;
                    self.highlight = Some((key, self.next_id, Arc::new(doc.face_mesh(face))));
                }
                if let Some((_, id, data)) = &self.highlight {
                    meshes.push(MeshInstance {
                        id: *id,
                        data: Arc::clone(data),
                        world_from_mesh: Mat4::IDENTITY,
                        colour: SELECTED_COLOUR,
                        scalar_map: None,
                    });
                }
            }
            if self.show_edges {
                lines.push(LineInstance {
                    id: doc.ids[1],
                    data: Arc::clone(&doc.render_edges),
                    world_from_lines: Mat4::IDENTITY,
                    draw_segments: None,
                });
            }
        }
        let mut camera = self.camera;
        let part_size = document
            .filter(|d| !d.bounds.is_empty())
            .map_or(0.0, |d| (d.bounds.max - d.bounds.min).max_element() as f32);
        let (tool, marker) = self.tool_and_marker(part_size);
        let extra = Scene {
            meshes: tool.into_iter().collect(),
            lines: marker.into_iter().collect(),
            ..Scene::default()
        };
        if let Some((lo, hi)) = extra.bounds() {
            camera.scene = tool_model::enclose(camera.scene, lo, hi);
        }
        meshes.extend(extra.meshes);
        lines.extend(extra.lines);
        Scene {
            camera,
            meshes,
            lines,
            options,
        }
    }
}

/// What the viewport draws besides the part: tool paths, their legend, and the path whose poses
/// can be picked.
#[derive(Default)]
pub struct ViewportExtras<'a> {
    /// Tool paths (drawn over the part).
    pub paths: Vec<LineInstance>,
    /// Legend of the path colouring, when it maps a scalar (title with unit, mapping).
    pub path_legend: Option<(String, ScalarMapping)>,
    /// A value marked on the path legend's bar (a limit) and its label.
    pub path_legend_mark: Option<(f32, String)>,
    /// More meshes (the simulated stock).
    pub meshes: Vec<MeshInstance>,
    /// Legend of the stock's deviation colouring.
    pub stock_legend: Option<(String, ScalarMapping)>,
    /// Draw the part's edges only (the simulated stock stands in for its faces).
    pub hide_part: bool,
    /// The active path and how far playback has drawn it (poses beyond are not pickable).
    pub pick_path: Option<(&'a Toolpath, Option<usize>)>,
}

/// Pick radius around a path pose, points.
const POSE_PICK_RADIUS: f32 = 7.0;

/// Over the part, a plain click picks a path pose only when it stands at least this much in
/// front of the surface under the pointer (along the view ray), mm; else the face.
const POSE_IN_FRONT_MM: f64 = 1.0;

/// Draw the viewport into the rest of `ui`; navigation changes the camera, clicks on the part
/// become selection commands, clicks on a pose of the active path pick it.
pub fn viewport_ui(
    ui: &mut egui::Ui,
    state: &mut ViewportState,
    document: Option<&Document>,
    extras: ViewportExtras<'_>,
    commands: &mut Vec<Command>,
) {
    let rect = ui.available_rect_before_wrap();
    let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
    state.aspect = rect.aspect_ratio().max(1e-3);
    if state.fit_requested {
        state.fit(document);
    }
    navigation::navigate(ui, &response, &mut state.camera);

    // Hover and click picking.
    let pointer = response.hover_pos();
    let hit = pointer.zip(document).and_then(|(pos, doc)| {
        let (origin, dir) = state.camera.ray(navigation::ndc(rect, pos), state.aspect);
        picking::ray_cast(doc.bvh.as_ref()?, origin.as_dvec3(), dir.as_dvec3())
    });
    state.hover_point = hit.map(|h| h.point);
    let ray = pointer.map(|pos| state.camera.ray(navigation::ndc(rect, pos), state.aspect));
    let alt = ui.input(|i| i.modifiers.alt);
    let pose_hit = if response.clicked() {
        pointer
            .zip(extras.pick_path)
            .and_then(|(pos, (path, up_to))| {
                let local = pos - rect.min;
                super::toolpaths::pick_pose(
                    path,
                    state.camera.clip_from_world(state.aspect),
                    glam::Vec2::new(rect.width(), rect.height()),
                    glam::Vec2::new(local.x, local.y),
                    POSE_PICK_RADIUS,
                    up_to,
                )
                .filter(|&i| {
                    // Over the part, a click picks the face unless the pose stands clear in
                    // front of it (a retract, a rapid): a path lying on the surface would
                    // otherwise hide every face under it. Alt+click always picks the pose.
                    let (Some(h), Some((origin, dir)), Some(p)) = (hit, ray, path.poses.get(i))
                    else {
                        return true;
                    };
                    let (origin, dir) = (origin.as_dvec3(), dir.as_dvec3().normalize_or_zero());
                    alt || (p.tip - origin).dot(dir)
                        < (h.point - origin).dot(dir) - POSE_IN_FRONT_MM
                })
            })
    } else {
        None
    };
    if let Some(i) = pose_hit {
        commands.push(Command::PickPose(Some(i)));
    } else if response.clicked() {
        commands.push(Command::PickPose(None));
        let (selection, pick) = match (hit, document) {
            (Some(h), Some(doc)) if !doc.part.faces.is_empty() => {
                let face = doc
                    .part
                    .face_of_triangle()
                    .get(h.triangle)
                    .map(|&f| f as usize);
                let pick =
                    face.and_then(|f| picking::surface_pick(f, doc.part.faces.get(f)?, h.point));
                if let Some(f) = face {
                    super::face_group::click(ui.ctx(), f);
                }
                (face.map_or(Selection::Part, Selection::Face), pick)
            }
            (Some(_), Some(_)) => (Selection::Part, None),
            _ => (Selection::None, None),
        };
        commands.push(Command::Select(selection));
        commands.push(Command::SetPick(pick));
    }
    if response.double_clicked() {
        commands.push(Command::FitAll);
    }

    let ppp = ui.ctx().pixels_per_point();
    let size_px = [
        (rect.width() * ppp).round().max(1.0) as u32,
        (rect.height() * ppp).round().max(1.0) as u32,
    ];
    let mut scene = state.scene(document);
    if extras.hide_part {
        scene.meshes.clear();
    }
    // Extra meshes (stock, machine bodies) widen the near and far planes.
    let more = Scene {
        meshes: extras.meshes,
        ..Scene::default()
    };
    if let Some((lo, hi)) = more.bounds() {
        scene.camera.scene = tool_model::enclose(scene.camera.scene, lo, hi);
    }
    scene.meshes.extend(more.meshes);
    scene.lines.extend(extras.paths);
    ui.painter().add(egui_wgpu::Callback::new_paint_callback(
        rect,
        bridge::ViewportCallback { scene, size_px },
    ));

    // Axis labels next to the triad's arrow tips.
    if state.options.triad
        && let Some(labels) = label_positions(size_px, state.camera.right(), state.camera.up())
    {
        for (k, (name, at)) in ["X", "Y", "Z"].iter().zip(labels).enumerate() {
            let [r, g, b, _] = AXIS_COLOURS[k];
            ui.painter().text(
                rect.min + egui::vec2(at[0] / ppp, at[1] / ppp),
                egui::Align2::CENTER_CENTER,
                *name,
                egui::FontId::proportional(12.0),
                egui::Color32::from_rgb(r, g, b),
            );
        }
    }
    let projection = match state.camera.projection {
        Projection::Perspective => "Perspective",
        Projection::Orthographic => "Orthographic",
    };
    if let Some((field, mapping)) = state.legend() {
        let title = format!("{} ({})", field.name(), field.unit());
        legend::legend_ui(ui, rect, &title, mapping, 0);
    }
    let first = usize::from(state.legend().is_some());
    let legends = extras.path_legend.iter().chain(&extras.stock_legend);
    for (slot, (title, mapping)) in (first..).zip(legends) {
        legend::legend_ui(ui, rect, title, *mapping, slot);
    }
    if let (Some((_, mapping)), Some((value, label))) =
        (&extras.path_legend, &extras.path_legend_mark)
    {
        legend::legend_mark_ui(ui, rect, *mapping, first, *value, label);
    }
    if let Some(view) = view_cube::view_cube_ui(ui, rect, &state.camera) {
        commands.push(Command::StandardView(view));
    }
    ui.painter().text(
        rect.right_bottom() + egui::vec2(-10.0, -8.0),
        egui::Align2::RIGHT_BOTTOM,
        format!(
            "{projection} · grid {} mm",
            state.options_grid_label(document)
        ),
        egui::FontId::proportional(11.0),
        egui::Color32::from_gray(150),
    );
}

impl ViewportState {
    /// The part's mesh with the chosen scalar field and its mapping, when a field is chosen and
    /// the document has it.
    fn field_mesh(&mut self, doc: &Document) -> Option<(DataId, Arc<MeshData>, ScalarMapping)> {
        let field = self.scalar_field?;
        let values = doc.curvature.as_ref()?.values(field);
        if values.len() != doc.render_mesh.positions.len() {
            return None;
        }
        let key = (doc.ids[0], field);
        if self.field_mesh.as_ref().is_none_or(|f| f.key != key) {
            self.next_id += 1;
            let mut data = (*doc.render_mesh).clone();
            data.scalars = values.to_vec();
            self.field_mesh = Some(FieldMesh {
                key,
                id: self.next_id,
                data: Arc::new(data),
                mapping: super::scalar_field::mapping_for(values),
            });
        }
        self.field_mesh
            .as_ref()
            .map(|f| (f.id, Arc::clone(&f.data), f.mapping))
    }

    /// The shown field and its mapping (for the legend).
    #[must_use]
    pub fn legend(&self) -> Option<(ScalarField, ScalarMapping)> {
        let f = self.field_mesh.as_ref()?;
        (Some(f.key.1) == self.scalar_field).then_some((f.key.1, f.mapping))
    }

    fn options_grid_label(&self, document: Option<&Document>) -> String {
        let spacing = document
            .filter(|d| !d.bounds.is_empty())
            .map_or(self.options.grid_spacing, |d| {
                DisplayOptions::grid_spacing_for((d.bounds.max - d.bounds.min).max_element() as f32)
            });
        format!("{spacing}")
    }
}
