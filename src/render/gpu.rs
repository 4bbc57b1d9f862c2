//! A wgpu device of our own, for offscreen rendering (tests, the `render` subcommand, benchmarks).
//! In the workstation the device comes from eframe instead.

use std::future::Future;
use std::pin::pin;
use std::task::{Context, Poll, Waker};

use super::RenderError;

/// A device and its queue, with a description of the adapter.
#[derive(Debug)]
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Adapter name, backend and kind, e.g. `llvmpipe (Vulkan, Cpu)`.
    pub adapter_description: String,
    /// MSAA samples the adapter supports for the scene formats (4 or 1).
    pub samples: u32,
}

impl GpuContext {
    /// Open the best adapter without a window (backends from `WGPU_BACKEND`, else all).
    /// Software adapters (lavapipe) are accepted.
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] when no adapter exists, [`RenderError::Device`] when the device
    /// cannot be opened.
    pub fn headless() -> Result<Self, RenderError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env()
                .unwrap_or(wgpu::PowerPreference::HighPerformance),
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        };
        let adapter = block_on(instance.request_adapter(&options))
            .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let adapter_description =
            format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type);
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("talas offscreen"),
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) = block_on(adapter.request_device(&descriptor))
            .map_err(|e| RenderError::Device(e.to_string()))?;
        let samples = super::target::supported_samples(&adapter);
        Ok(Self {
            device,
            queue,
            adapter_description,
            samples,
        })
    }
}

/// Run a future to completion on this thread (wgpu's native futures are ready at once or after
/// the device is polled).
pub(crate) fn block_on<F: Future>(future: F) -> F::Output {
    let mut future = pin!(future);
    let mut cx = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(v) = future.as_mut().poll(&mut cx) {
            return v;
        }
        std::thread::yield_now();
    }
}
