//! The WGSL sources in `shaders/`, compiled into the binary. Every shader except the compositor
//! starts with the shared prelude `common.wgsl` (the per-frame uniform block).

/// The shared prelude: the `Frame` uniform and small helpers.
const COMMON: &str = include_str!("../../shaders/common.wgsl");

/// One shader of the renderer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shader {
    /// Gradient background.
    Background,
    /// Shaded triangle meshes.
    Mesh,
    /// Lines with per-vertex colour.
    Line,
    /// Infinite ground grid.
    Grid,
    /// Copies the scene texture into egui's render pass.
    Composite,
}

impl Shader {
    /// Every shader, for validation.
    pub const ALL: [Self; 5] = [
        Self::Background,
        Self::Mesh,
        Self::Line,
        Self::Grid,
        Self::Composite,
    ];

    /// The file name under `shaders/`.
    #[must_use]
    pub fn file_name(self) -> &'static str {
        match self {
            Self::Background => "background.wgsl",
            Self::Mesh => "mesh.wgsl",
            Self::Line => "line.wgsl",
            Self::Grid => "grid.wgsl",
            Self::Composite => "composite.wgsl",
        }
    }

    /// The complete WGSL source (prelude included where the shader uses it).
    #[must_use]
    pub fn source(self) -> String {
        let body = match self {
            Self::Background => include_str!("../../shaders/background.wgsl"),
            Self::Mesh => include_str!("../../shaders/mesh.wgsl"),
            Self::Line => include_str!("../../shaders/line.wgsl"),
            Self::Grid => include_str!("../../shaders/grid.wgsl"),
            Self::Composite => return include_str!("../../shaders/composite.wgsl").to_string(),
        };
        format!("{COMMON}\n{body}")
    }

    /// Compile the shader on `device`.
    #[must_use]
    pub fn module(self, device: &wgpu::Device) -> wgpu::ShaderModule {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.file_name()),
            source: wgpu::ShaderSource::Wgsl(self.source().into()),
        })
    }
}
