//! The wgpu renderer: pipelines, camera, meshes, lines, colour maps. Knows wgpu, never the engine.
//!
//! A frame is a [`Scene`] (camera, meshes and line sets with stable ids, display options). The
//! [`Renderer`] keeps GPU copies of the data by id, and records a frame into a [`ViewTarget`]
//! (4× MSAA colour and depth, resolved to an sRGB texture). The workstation composites that
//! texture into egui with a [`Compositor`]; [`render_to_image`] reads it back instead.
//!
//! Shaders live in `shaders/*.wgsl` and are compiled in with `include_str!` ([`shaders`]).

pub mod camera;
pub mod colour_map;
pub mod glyphs;
pub mod gpu;
pub mod gpu_geometry;
pub mod offscreen;
pub mod pipeline;
pub mod renderer;
pub mod scene;
pub mod shaders;
pub mod target;
pub mod triad;

pub use camera::{BoundingSphere, Camera, Projection, StandardView};
pub use colour_map::ColourMap;
pub use gpu::GpuContext;
pub use offscreen::{OffscreenRenderer, RgbaImage, render_to_image};
pub use pipeline::composite::Compositor;
pub use renderer::Renderer;
pub use scene::{
    DataId, DisplayOptions, LineData, LineInstance, MeshData, MeshInstance, Rgba8, ScalarMapping,
    Scene,
};
pub use target::ViewTarget;

/// A failure to render.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RenderError {
    /// No graphics adapter (install a driver, or Mesa's lavapipe for software rendering).
    #[error("no graphics adapter: {0}")]
    NoAdapter(String),
    /// The device could not be opened or failed.
    #[error("graphics device: {0}")]
    Device(String),
    /// Scene data that cannot be drawn (mismatched lengths, index out of range).
    #[error("cannot draw: {0}")]
    BadData(String),
}
