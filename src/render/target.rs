//! The textures a frame is drawn into: multisampled colour and depth, resolved to a single-sample
//! sRGB texture that the compositor samples or the offscreen path reads back.

/// Colour format of the scene (sRGB, so lighting is computed in linear space).
pub const SCENE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Depth format of the scene.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Render targets of one size.
#[derive(Debug)]
pub struct ViewTarget {
    /// Size in pixels.
    pub size: [u32; 2],
    /// Samples per pixel (4, or 1 where the adapter cannot multisample).
    pub samples: u32,
    /// Multisampled colour (absent when `samples == 1`).
    pub msaa_view: Option<wgpu::TextureView>,
    /// Single-sample resolved colour.
    pub resolved: wgpu::Texture,
    /// View of `resolved`.
    pub resolved_view: wgpu::TextureView,
    /// Depth (with `samples` samples).
    pub depth_view: wgpu::TextureView,
}

impl ViewTarget {
    /// Targets of `size` pixels (each side at least 1) with `samples` samples.
    #[must_use]
    pub fn new(device: &wgpu::Device, size: [u32; 2], samples: u32) -> Self {
        let max = device.limits().max_texture_dimension_2d;
        let size = [size[0].clamp(1, max), size[1].clamp(1, max)];
        let extent = wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        };
        let texture = |label, format, sample_count, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let resolved = texture(
            "scene colour",
            SCENE_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let msaa_view = (samples > 1).then(|| {
            texture(
                "scene colour msaa",
                SCENE_FORMAT,
                samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&wgpu::TextureViewDescriptor::default())
        });
        let depth_view = texture(
            "scene depth",
            DEPTH_FORMAT,
            samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&wgpu::TextureViewDescriptor::default());
        let resolved_view = resolved.create_view(&wgpu::TextureViewDescriptor::default());
        Self {
            size,
            samples,
            msaa_view,
            resolved,
            resolved_view,
            depth_view,
        }
    }

    /// Width / height.
    #[must_use]
    pub fn aspect(&self) -> f32 {
        self.size[0] as f32 / self.size[1] as f32
    }

    /// The colour attachment: the multisampled texture resolving into `resolved`, or `resolved`.
    #[must_use]
    pub fn colour_attachment(
        &self,
        load: wgpu::LoadOp<wgpu::Color>,
    ) -> wgpu::RenderPassColorAttachment<'_> {
        let ops = wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        };
        match &self.msaa_view {
            Some(msaa) => wgpu::RenderPassColorAttachment {
                view: msaa,
                depth_slice: None,
                resolve_target: Some(&self.resolved_view),
                ops,
            },
            None => wgpu::RenderPassColorAttachment {
                view: &self.resolved_view,
                depth_slice: None,
                resolve_target: None,
                ops,
            },
        }
    }
}

/// The sample count to use on `adapter`-backed devices: 4 when the scene formats support it.
#[must_use]
pub fn supported_samples(adapter: &wgpu::Adapter) -> u32 {
    let ok = |f: wgpu::TextureFormat| {
        adapter
            .get_texture_format_features(f)
            .flags
            .contains(wgpu::TextureFormatFeatureFlags::MULTISAMPLE_X4)
    };
    if ok(SCENE_FORMAT) && ok(DEPTH_FORMAT) {
        4
    } else {
        1
    }
}
