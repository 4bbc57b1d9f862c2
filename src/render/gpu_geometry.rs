//! GPU copies of scene data: vertex and index buffers for meshes and line sets, and the
//! colour-map texture.

use wgpu::util::DeviceExt;

use super::colour_map::{COLOUR_MAP_TEXELS, ColourMap};
use super::pipeline::{LineVertex, MeshVertex};
use super::scene::{LineData, MeshData};

/// Vertex and index buffers of one mesh or line set.
pub struct GpuGeometry {
    /// Interleaved vertices ([`MeshVertex`] or [`LineVertex`]).
    pub vertices: wgpu::Buffer,
    /// `u32` indices.
    pub indices: wgpu::Buffer,
    /// Number of indices.
    pub index_count: u32,
}

/// Upload a mesh (the caller has checked [`MeshData::problem`]).
pub fn upload_mesh(device: &wgpu::Device, data: &MeshData) -> GpuGeometry {
    let vertices: Vec<MeshVertex> = data
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| MeshVertex {
            position: *p,
            normal: data.normals.get(i).copied().unwrap_or([0.0, 0.0, 1.0]),
            scalar: data.scalars.get(i).copied().unwrap_or(0.0),
        })
        .collect();
    upload(
        device,
        bytemuck::cast_slice(&vertices),
        &data.indices,
        "mesh",
    )
}

/// Upload a line set (the caller has checked [`LineData::problem`]).
pub fn upload_lines(device: &wgpu::Device, data: &LineData) -> GpuGeometry {
    let vertices: Vec<LineVertex> = data
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| LineVertex {
            position: *p,
            colour: data.colours.get(i).copied().unwrap_or([255; 4]),
        })
        .collect();
    upload(
        device,
        bytemuck::cast_slice(&vertices),
        &data.indices,
        "lines",
    )
}

fn upload(device: &wgpu::Device, vertex_bytes: &[u8], indices: &[u32], label: &str) -> GpuGeometry {
    let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: vertex_bytes,
        usage: wgpu::BufferUsages::VERTEX,
    });
    let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(indices),
        usage: wgpu::BufferUsages::INDEX,
    });
    GpuGeometry {
        vertices,
        indices: index_buffer,
        index_count: u32::try_from(indices.len()).unwrap_or(u32::MAX),
    }
}

/// The colour-map texture: one 256-texel row per [`ColourMap`], in [`ColourMap::row`] order.
pub fn colour_map_texture(device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::TextureView {
    let texels: Vec<u8> = ColourMap::ALL.iter().flat_map(|m| m.texels()).collect();
    let width = u32::try_from(COLOUR_MAP_TEXELS).unwrap_or(256);
    let rows = u32::try_from(ColourMap::ALL.len()).unwrap_or(1);
    let texture = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("colour maps"),
            size: wgpu::Extent3d {
                width,
                height: rows,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &texels,
    );
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}
