//! The render pipelines and the uniform blocks they share. Layout of every uniform struct here
//! matches its WGSL twin in `shaders/`.

pub mod composite;

use bytemuck::{Pod, Zeroable};

use super::shaders::Shader;
use super::target::{DEPTH_FORMAT, SCENE_FORMAT};

/// The per-frame uniform (`Frame` in `common.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniform {
    /// Clip from world.
    pub view_proj: [[f32; 4]; 4],
    /// World from clip.
    pub inv_view_proj: [[f32; 4]; 4],
    /// View from world.
    pub view: [[f32; 4]; 4],
    /// Eye position; w = 1 perspective, 0 orthographic.
    pub eye: [f32; 4],
    /// Background top colour (linear).
    pub background_top: [f32; 4],
    /// Background bottom colour (linear).
    pub background_bottom: [f32; 4],
    /// Grid plane z, minor spacing, major spacing, fade distance (0: no grid).
    pub grid: [f32; 4],
    /// Minor grid line colour (linear, alpha).
    pub grid_minor_colour: [f32; 4],
    /// Major grid line colour (linear, alpha).
    pub grid_major_colour: [f32; 4],
    /// Line depth offset (NDC), grid fade centre x and y.
    pub params: [f32; 4],
}

/// The per-object uniform (`Object` in `mesh.wgsl` and `line.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ObjectUniform {
    /// World from object.
    pub model: [[f32; 4]; 4],
    /// Inverse transpose of `model` (for normals).
    pub normal_matrix: [[f32; 4]; 4],
    /// Base colour (linear RGBA).
    pub colour: [f32; 4],
    /// Scalar start, 1 / range, use-scalar flag, colour-map row v coordinate.
    pub scalar: [f32; 4],
}

/// One mesh vertex: position, normal, scalar.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MeshVertex {
    /// Position.
    pub position: [f32; 3],
    /// Normal.
    pub normal: [f32; 3],
    /// Scalar for the colour map.
    pub scalar: f32,
}

/// One line vertex: position and sRGB colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LineVertex {
    /// Position.
    pub position: [f32; 3],
    /// sRGB colour.
    pub colour: [u8; 4],
}

/// The scene pipelines and their bind-group layouts.
#[derive(Debug)]
pub struct Pipelines {
    /// Group 0: frame uniform, colour-map texture and sampler.
    pub frame_layout: wgpu::BindGroupLayout,
    /// Group 1: object uniform.
    pub object_layout: wgpu::BindGroupLayout,
    /// Gradient background.
    pub background: wgpu::RenderPipeline,
    /// Shaded meshes.
    pub mesh: wgpu::RenderPipeline,
    /// Lines.
    pub line: wgpu::RenderPipeline,
    /// Ground grid.
    pub grid: wgpu::RenderPipeline,
}

impl Pipelines {
    /// Build every scene pipeline for `samples` samples per pixel.
    #[must_use]
    pub fn new(device: &wgpu::Device, samples: u32) -> Self {
        let uniform = |binding, visibility| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[
                uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let object_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("object"),
            entries: &[uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT)],
        });
        let frame_only = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("frame only"),
            bind_group_layouts: &[Some(&frame_layout)],
            immediate_size: 0,
        });
        let with_object = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("frame and object"),
            bind_group_layouts: &[Some(&frame_layout), Some(&object_layout)],
            immediate_size: 0,
        });
        let builder = PipelineBuilder { device, samples };
        let background = builder.build(
            &frame_only,
            Shader::Background,
            &[],
            Topology::Fullscreen,
            Depth::Ignore,
            false,
        );
        let mesh_attributes =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32];
        let mesh_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &mesh_attributes,
        })];
        let mesh = builder.build(
            &with_object,
            Shader::Mesh,
            &mesh_buffers,
            Topology::Triangles,
            Depth::TestAndWrite,
            false,
        );
        let line_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4];
        let line_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &line_attributes,
        })];
        let line = builder.build(
            &with_object,
            Shader::Line,
            &line_buffers,
            Topology::Lines,
            Depth::TestAndWrite,
            true,
        );
        let grid = builder.build(
            &frame_only,
            Shader::Grid,
            &[],
            Topology::Fullscreen,
            Depth::TestAndWrite,
            true,
        );
        Self {
            frame_layout,
            object_layout,
            background,
            mesh,
            line,
            grid,
        }
    }
}

#[derive(Clone, Copy)]
enum Topology {
    Fullscreen,
    Triangles,
    Lines,
}

#[derive(Clone, Copy)]
enum Depth {
    Ignore,
    TestAndWrite,
}

struct PipelineBuilder<'a> {
    device: &'a wgpu::Device,
    samples: u32,
}

impl PipelineBuilder<'_> {
    fn build(
        &self,
        layout: &wgpu::PipelineLayout,
        shader: Shader,
        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
        topology: Topology,
        depth: Depth,
        blend: bool,
    ) -> wgpu::RenderPipeline {
        let module = shader.module(self.device);
        let topology = match topology {
            Topology::Fullscreen | Topology::Triangles => wgpu::PrimitiveTopology::TriangleList,
            Topology::Lines => wgpu::PrimitiveTopology::LineList,
        };
        let depth_stencil = wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(matches!(depth, Depth::TestAndWrite)),
            depth_compare: Some(match depth {
                Depth::Ignore => wgpu::CompareFunction::Always,
                Depth::TestAndWrite => wgpu::CompareFunction::LessEqual,
            }),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        };
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(shader.file_name()),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(depth_stencil),
                multisample: wgpu::MultisampleState {
                    count: self.samples,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: SCENE_FORMAT,
                        blend: blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
    }
}
