//! The renderer: keeps GPU copies of scene data (by id), and records a frame of a [`Scene`] into
//! a [`ViewTarget`]: gradient background, shaded meshes, lines, ground grid, then the axis triad
//! in a corner.

use std::collections::BTreeMap;
use std::collections::btree_map::Entry;

use glam::Mat4;
use glam::camera::rh::proj::directx::orthographic;
use glam::camera::rh::view::look_to_mat4;

use super::camera::Projection;
use super::colour_map::ColourMap;
use super::gpu_geometry::{GpuGeometry, colour_map_texture, upload_lines, upload_mesh};
use super::pipeline::{FrameUniform, ObjectUniform, Pipelines};
use super::scene::{DataId, Rgba8, Scene};
use super::target::ViewTarget;
use super::triad;

/// NDC depth by which lines are pulled toward the viewer so they show on surfaces.
const LINE_DEPTH_OFFSET: f32 = 2e-4;

struct ObjectSlot {
    buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

enum DrawKind {
    Mesh,
    Line,
}

struct Draw {
    kind: DrawKind,
    id: DataId,
    slot: usize,
    index_count: u32,
}

/// Draws [`Scene`]s. One per device; reuse it across frames so uploads are kept.
pub struct Renderer {
    samples: u32,
    pipelines: Pipelines,
    frame_buffer: wgpu::Buffer,
    frame_bind_group: wgpu::BindGroup,
    triad_frame_buffer: wgpu::Buffer,
    triad_frame_bind_group: wgpu::BindGroup,
    objects: Vec<ObjectSlot>,
    meshes: BTreeMap<DataId, GpuGeometry>,
    lines: BTreeMap<DataId, GpuGeometry>,
    triad_arrow: GpuGeometry,
    target: Option<ViewTarget>,
    target_generation: u64,
    draws: Vec<Draw>,
    triad_draws: Vec<usize>,
    triad_viewport: Option<[f32; 4]>,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("samples", &self.samples)
            .field("meshes", &self.meshes.len())
            .field("lines", &self.lines.len())
            .finish_non_exhaustive()
    }
}

impl Renderer {
    /// A renderer drawing with `samples` samples per pixel (4 for MSAA, or 1).
    #[must_use]
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, samples: u32) -> Self {
        let samples = samples.max(1);
        let pipelines = Pipelines::new(device, samples);
        let colour_map_view = colour_map_texture(device, queue);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("colour map"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let frame_pair = |label| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: std::mem::size_of::<FrameUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &pipelines.frame_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&colour_map_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&sampler),
                    },
                ],
            });
            (buffer, bind_group)
        };
        let (frame_buffer, frame_bind_group) = frame_pair("frame");
        let (triad_frame_buffer, triad_frame_bind_group) = frame_pair("triad frame");
        let arrow = triad::arrow_mesh(24);
        let triad_arrow = upload_mesh(device, &arrow);
        Self {
            samples,
            pipelines,
            frame_buffer,
            frame_bind_group,
            triad_frame_buffer,
            triad_frame_bind_group,
            objects: Vec::new(),
            meshes: BTreeMap::new(),
            lines: BTreeMap::new(),
            triad_arrow,
            target: None,
            target_generation: 0,
            draws: Vec::new(),
            triad_draws: Vec::new(),
            triad_viewport: None,
        }
    }

    /// Samples per pixel.
    #[must_use]
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The target of the last [`Renderer::prepare`], with a generation number that changes
    /// whenever the target is rebuilt (resize).
    #[must_use]
    pub fn target(&self) -> Option<(&ViewTarget, u64)> {
        self.target.as_ref().map(|t| (t, self.target_generation))
    }

    /// Upload what `scene` needs and is not on the GPU yet, drop what it no longer names, size the
    /// target to `size_px`, and write this frame's uniforms. Returns one line for each mesh or
    /// line set that cannot be drawn (it is skipped).
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        size_px: [u32; 2],
    ) -> Vec<String> {
        let mut problems = Vec::new();
        if self
            .target
            .as_ref()
            .is_none_or(|t| t.size != [size_px[0].max(1), size_px[1].max(1)])
        {
            self.target = Some(ViewTarget::new(device, size_px, self.samples));
            self.target_generation += 1;
        }
        let size = self.target.as_ref().map_or([1, 1], |t| t.size);
        let aspect = size[0] as f32 / size[1] as f32;

        // Keep GPU copies only of what the scene names.
        self.meshes
            .retain(|id, _| scene.meshes.iter().any(|m| m.id == *id));
        self.lines
            .retain(|id, _| scene.lines.iter().any(|l| l.id == *id));

        self.draws.clear();
        let mut slot = 0;
        self.prepare_meshes(device, queue, scene, &mut slot, &mut problems);
        self.prepare_lines(device, queue, scene, &mut slot, &mut problems);
        let frame = self.write_frame(queue, scene, aspect);
        self.prepare_triad(device, queue, scene, size, &frame, slot);
        problems
    }

    /// Upload the scene's meshes not on the GPU yet and queue their draws from object `slot` on.
    fn prepare_meshes(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        slot: &mut usize,
        problems: &mut Vec<String>,
    ) {
        for m in &scene.meshes {
            if let Entry::Vacant(vacant) = self.meshes.entry(m.id) {
                if let Some(p) = m.data.problem() {
                    problems.push(format!("mesh {}: {p}", m.id));
                    continue;
                }
                if m.data.indices.is_empty() {
                    continue;
                }
                vacant.insert(upload_mesh(device, &m.data));
            }
            let Some(index_count) = self.meshes.get(&m.id).map(|g| g.index_count) else {
                continue;
            };
            let (scalar, colour) = match m.scalar_map {
                Some(s) => {
                    let range = s.max - s.min;
                    let inv = if range.abs() > f32::EPSILON {
                        1.0 / range
                    } else {
                        0.0
                    };
                    let v = (s.map.row() as f32 + 0.5) / ColourMap::ALL.len() as f32;
                    ([s.min, inv, 1.0, v], m.colour)
                }
                None => ([0.0; 4], m.colour),
            };
            let uniform = object_uniform(m.world_from_mesh, colour, scalar);
            self.write_object(device, queue, *slot, &uniform);
            self.draws.push(Draw {
                kind: DrawKind::Mesh,
                id: m.id,
                slot: *slot,
                index_count,
            });
            *slot += 1;
        }
    }

    /// Upload the scene's line sets not on the GPU yet and queue their draws from object `slot`
    /// on (each up to its `draw_segments`).
    fn prepare_lines(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        slot: &mut usize,
        problems: &mut Vec<String>,
    ) {
        for l in &scene.lines {
            if let Entry::Vacant(vacant) = self.lines.entry(l.id) {
                if let Some(p) = l.data.problem() {
                    problems.push(format!("lines {}: {p}", l.id));
                    continue;
                }
                if l.data.indices.is_empty() {
                    continue;
                }
                vacant.insert(upload_lines(device, &l.data));
            }
            let Some(total) = self.lines.get(&l.id).map(|g| g.index_count) else {
                continue;
            };
            let count = l.draw_segments.map_or(total, |n| {
                u32::try_from(n.saturating_mul(2))
                    .unwrap_or(u32::MAX)
                    .min(total)
            });
            let uniform = object_uniform(l.world_from_lines, [255; 4], [0.0; 4]);
            self.write_object(device, queue, *slot, &uniform);
            self.draws.push(Draw {
                kind: DrawKind::Line,
                id: l.id,
                slot: *slot,
                index_count: count,
            });
            *slot += 1;
        }
    }

    /// Write the frame uniforms (camera, background, grid) and return them.
    fn write_frame(&self, queue: &wgpu::Queue, scene: &Scene, aspect: f32) -> FrameUniform {
        let camera = &scene.camera;
        let view = camera.view_from_world();
        let view_proj = camera.clip_from_view(aspect) * view;
        let o = &scene.options;
        let grid_major = o.grid_spacing * 10.0;
        let fade = if o.grid {
            (camera.scene.radius * 2.5).max(grid_major * 1.5)
        } else {
            0.0
        };
        let frame = FrameUniform {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            view: view.to_cols_array_2d(),
            eye: camera
                .eye()
                .extend(if camera.projection == Projection::Perspective {
                    1.0
                } else {
                    0.0
                })
                .to_array(),
            background_top: linear(o.background_top),
            background_bottom: linear(o.background_bottom),
            grid: [o.grid_z, o.grid_spacing, grid_major, fade],
            grid_minor_colour: [0.42, 0.46, 0.52, 0.16],
            grid_major_colour: [0.50, 0.55, 0.62, 0.42],
            params: [
                LINE_DEPTH_OFFSET,
                camera.scene.centre.x,
                camera.scene.centre.y,
                0.0,
            ],
        };
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&frame));

        frame
    }

    /// Triad: the camera's rotation about the origin, orthographic, in a corner viewport of a
    /// target of `size` (objects from `slot` on).
    fn prepare_triad(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        size: [u32; 2],
        frame: &FrameUniform,
        mut slot: usize,
    ) {
        let (camera, o) = (&scene.camera, &scene.options);
        self.triad_draws.clear();
        self.triad_viewport = None;
        if o.triad
            && let Some(rect) = triad::viewport_rect(size)
        {
            self.triad_viewport = Some(rect);
            let triad_view = look_to_mat4(camera.backward() * 3.0, -camera.backward(), camera.up());
            let triad_proj = {
                let e = triad::VIEW_HALF_EXTENT;
                orthographic(-e, e, -e, e, 0.5, 6.0)
            };
            let triad_view_proj = triad_proj * triad_view;
            let triad_frame = FrameUniform {
                view_proj: triad_view_proj.to_cols_array_2d(),
                inv_view_proj: triad_view_proj.inverse().to_cols_array_2d(),
                view: triad_view.to_cols_array_2d(),
                eye: [0.0; 4],
                grid: [0.0; 4],
                ..*frame
            };
            queue.write_buffer(
                &self.triad_frame_buffer,
                0,
                bytemuck::bytes_of(&triad_frame),
            );
            for (axis, model) in triad::axis_transforms().into_iter().enumerate() {
                let uniform = object_uniform(model, triad::AXIS_COLOURS[axis], [0.0; 4]);
                self.write_object(device, queue, slot, &uniform);
                self.triad_draws.push(slot);
                slot += 1;
            }
        }
    }

    /// Record the frame prepared by [`Renderer::prepare`] into `encoder`.
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder) {
        let Some(target) = &self.target else { return };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &[Some(
                    target.colour_attachment(wgpu::LoadOp::Clear(wgpu::Color::BLACK)),
                )],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.frame_bind_group, &[]);
            pass.set_pipeline(&self.pipelines.background);
            pass.draw(0..3, 0..1);
            pass.set_pipeline(&self.pipelines.mesh);
            for d in self
                .draws
                .iter()
                .filter(|d| matches!(d.kind, DrawKind::Mesh))
            {
                self.draw_geometry(&mut pass, self.meshes.get(&d.id), d.slot, d.index_count);
            }
            pass.set_pipeline(&self.pipelines.line);
            for d in self
                .draws
                .iter()
                .filter(|d| matches!(d.kind, DrawKind::Line))
            {
                self.draw_geometry(&mut pass, self.lines.get(&d.id), d.slot, d.index_count);
            }
            pass.set_pipeline(&self.pipelines.grid);
            pass.draw(0..3, 0..1);
        }
        if let Some([x, y, w, h]) = self.triad_viewport {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("triad"),
                color_attachments: &[Some(target.colour_attachment(wgpu::LoadOp::Load))],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_viewport(x, y, w, h, 0.0, 1.0);
            pass.set_bind_group(0, &self.triad_frame_bind_group, &[]);
            pass.set_pipeline(&self.pipelines.mesh);
            for &slot in &self.triad_draws {
                self.draw_geometry(
                    &mut pass,
                    Some(&self.triad_arrow),
                    slot,
                    self.triad_arrow.index_count,
                );
            }
        }
    }

    fn draw_geometry(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        gpu: Option<&GpuGeometry>,
        slot: usize,
        count: u32,
    ) {
        let (Some(gpu), Some(object)) = (gpu, self.objects.get(slot)) else {
            return;
        };
        pass.set_bind_group(1, &object.bind_group, &[]);
        pass.set_vertex_buffer(0, gpu.vertices.slice(..));
        pass.set_index_buffer(gpu.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..count, 0, 0..1);
    }

    fn write_object(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        slot: usize,
        uniform: &ObjectUniform,
    ) {
        while self.objects.len() <= slot {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("object"),
                size: std::mem::size_of::<ObjectUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("object"),
                layout: &self.pipelines.object_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                }],
            });
            self.objects.push(ObjectSlot { buffer, bind_group });
        }
        if let Some(object) = self.objects.get(slot) {
            queue.write_buffer(&object.buffer, 0, bytemuck::bytes_of(uniform));
        }
    }
}

fn object_uniform(model: Mat4, colour: Rgba8, scalar: [f32; 4]) -> ObjectUniform {
    ObjectUniform {
        model: model.to_cols_array_2d(),
        normal_matrix: model.inverse().transpose().to_cols_array_2d(),
        colour: linear(colour),
        scalar,
    }
}

/// sRGB bytes to linear floats (alpha stays linear).
fn linear(c: Rgba8) -> [f32; 4] {
    let f = |v: u8| {
        let s = f32::from(v) / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    [f(c[0]), f(c[1]), f(c[2]), f32::from(c[3]) / 255.0]
}
