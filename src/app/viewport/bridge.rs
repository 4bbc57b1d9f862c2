//! The bridge between egui and the renderer (rerun's `re_renderer` shape): a paint callback whose
//! `prepare` uploads data and records the scene into the renderer's own target, and whose `paint`
//! composites that target into egui's render pass.

use std::sync::{Arc, Mutex};

use crate::render::{Compositor, Renderer, Scene};

/// GPU state kept in egui-wgpu's callback resources for the life of the window.
pub struct ViewportResources {
    renderer: Renderer,
    compositor: Compositor,
    problems: Arc<Mutex<Vec<String>>>,
}

/// Install the renderer into eframe's wgpu state. Returns the shared list where draw problems
/// are reported, or `None` when eframe runs without wgpu.
pub fn install(render_state: &egui_wgpu::RenderState) -> Arc<Mutex<Vec<String>>> {
    let samples = crate::render::target::supported_samples(&render_state.adapter);
    let renderer = Renderer::new(&render_state.device, &render_state.queue, samples);
    // eframe's egui pass: the window's format, one sample, no depth (NativeOptions in app::run).
    let compositor = Compositor::new(&render_state.device, render_state.target_format, 1, None);
    let problems = Arc::new(Mutex::new(Vec::new()));
    let resources = ViewportResources {
        renderer,
        compositor,
        problems: Arc::clone(&problems),
    };
    render_state
        .renderer
        .write()
        .callback_resources
        .insert(resources);
    problems
}

/// One frame of the viewport: the scene and the size of the viewport in physical pixels.
pub struct ViewportCallback {
    /// What to draw.
    pub scene: Scene,
    /// Viewport size, physical pixels.
    pub size_px: [u32; 2],
}

impl egui_wgpu::CallbackTrait for ViewportCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen_descriptor: &egui_wgpu::ScreenDescriptor,
        egui_encoder: &mut wgpu::CommandEncoder,
        callback_resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        let Some(resources) = callback_resources.get_mut::<ViewportResources>() else {
            return Vec::new();
        };
        let ViewportResources {
            renderer,
            compositor,
            problems,
        } = resources;
        let found = renderer.prepare(device, queue, &self.scene, self.size_px);
        if !found.is_empty()
            && let Ok(mut list) = problems.lock()
        {
            list.extend(found);
        }
        renderer.record(egui_encoder);
        if let Some((target, generation)) = renderer.target() {
            compositor.set_source(device, target, generation);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        render_pass: &mut wgpu::RenderPass<'static>,
        callback_resources: &egui_wgpu::CallbackResources,
    ) {
        if let Some(resources) = callback_resources.get::<ViewportResources>() {
            resources.compositor.paint(render_pass);
        }
    }
}
