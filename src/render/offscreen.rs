//! Offscreen rendering: draw a [`Scene`] into an image in memory (tests, `talas render`,
//! benchmarks), through the same [`Renderer`] as the viewport.

use std::sync::mpsc;

use super::RenderError;
use super::gpu::GpuContext;
use super::renderer::Renderer;
use super::scene::Scene;

/// An 8-bit RGBA image (sRGB), rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

impl RgbaImage {
    /// The pixel at (`x`, `y`) from the top-left, if inside.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize * self.width as usize + x as usize) * 4;
        let p = self.pixels.get(i..i + 4)?;
        Some([p[0], p[1], p[2], p[3]])
    }
}

/// A headless device with a renderer, reused across frames.
#[derive(Debug)]
pub struct OffscreenRenderer {
    /// The device.
    pub gpu: GpuContext,
    renderer: Renderer,
}

impl OffscreenRenderer {
    /// Open a headless device and build the renderer.
    ///
    /// # Errors
    /// When no adapter or device is available.
    pub fn new() -> Result<Self, RenderError> {
        let gpu = GpuContext::headless()?;
        let renderer = Renderer::new(&gpu.device, &gpu.queue, gpu.samples);
        Ok(Self { gpu, renderer })
    }

    /// Draw `scene` at `width` × `height` without reading it back (for timing); waits until the
    /// GPU has finished.
    ///
    /// # Errors
    /// When the scene names data that cannot be drawn, or the device fails.
    pub fn draw(&mut self, width: u32, height: u32, scene: &Scene) -> Result<(), RenderError> {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let problems = self.renderer.prepare(device, queue, scene, [width, height]);
        if let Some(p) = problems.into_iter().next() {
            return Err(RenderError::BadData(p));
        }
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("offscreen"),
        });
        self.renderer.record(&mut encoder);
        queue.submit([encoder.finish()]);
        device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(())
    }

    /// Draw `scene` at `width` × `height` and read the picture back.
    ///
    /// # Errors
    /// When the scene names data that cannot be drawn, or the device fails.
    pub fn render(
        &mut self,
        width: u32,
        height: u32,
        scene: &Scene,
    ) -> Result<RgbaImage, RenderError> {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let problems = self.renderer.prepare(device, queue, scene, [width, height]);
        if let Some(p) = problems.into_iter().next() {
            return Err(RenderError::BadData(p));
        }
        let Some((target, _)) = self.renderer.target() else {
            return Err(RenderError::Device("no render target".into()));
        };
        let [w, h] = target.size;
        let unpadded = w * 4;
        let padded = unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded) * u64::from(h),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("offscreen"),
        });
        self.renderer.record(&mut encoder);
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &target.resolved,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(h),
                },
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([encoder.finish()]);
        let (tx, rx) = mpsc::channel();
        readback.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map_err(|e| RenderError::Device(e.to_string()))?;
        rx.recv()
            .map_err(|e| RenderError::Device(e.to_string()))?
            .map_err(|e| RenderError::Device(e.to_string()))?;
        let mapped = readback
            .get_mapped_range(..)
            .map_err(|e| RenderError::Device(e.to_string()))?;
        let mut pixels = Vec::with_capacity((unpadded * h) as usize);
        for row in mapped.chunks(padded as usize).take(h as usize) {
            pixels.extend_from_slice(row.get(..unpadded as usize).unwrap_or(row));
        }
        drop(mapped);
        readback.unmap();
        Ok(RgbaImage {
            width: w,
            height: h,
            pixels,
        })
    }
}

/// Render `scene` at `width` × `height` on a fresh headless device (about half a second of set-up
/// on a software adapter; keep an [`OffscreenRenderer`] for repeated frames).
///
/// # Errors
/// When no adapter is available, the device fails, or the scene's data cannot be drawn.
pub fn render_to_image(width: u32, height: u32, scene: &Scene) -> Result<RgbaImage, RenderError> {
    OffscreenRenderer::new()?.render(width, height, scene)
}
