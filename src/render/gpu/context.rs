//! The wgpu instance, adapter and device, found without a display, and the float render-target
//! format the adapter can blend.

use anyhow::{anyhow, Result};

/// The render target's texel format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TargetFormat {
    /// Rgba32Float: blending in f32, as the CPU path composites.
    Rgba32Float,
    /// Rgba16Float, where the adapter cannot blend 32-bit float targets.
    Rgba16Float,
}

impl TargetFormat {
    pub fn wgpu(self) -> wgpu::TextureFormat {
        match self {
            TargetFormat::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
            TargetFormat::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
        }
    }

    /// Bytes per texel.
    pub fn texel_bytes(self) -> u32 {
        match self {
            TargetFormat::Rgba32Float => 16,
            TargetFormat::Rgba16Float => 8,
        }
    }
}

/// A device ready for rendering.
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    pub format: TargetFormat,
}

impl GpuContext {
    /// The adapter wgpu prefers (backends from `WGPU_BACKEND`, power preference from
    /// `WGPU_POWER_PREF` when set), with its own limits and FLOAT32_BLENDABLE when offered.
    /// Needs no window system.
    pub fn new() -> Result<GpuContext> {
        let power =
            wgpu::PowerPreference::from_env().unwrap_or(wgpu::PowerPreference::HighPerformance);
        let find = |backends: Option<wgpu::Backends>| {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
            if let Some(b) = backends {
                desc.backends = b;
            }
            let instance = wgpu::Instance::new(desc);
            pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: power,
                ..Default::default()
            }))
        };
        // Without WGPU_BACKEND, Vulkan alone first: probing GL on a machine with no display
        // makes EGL print errors even when a Vulkan adapter exists.
        let adapter = if std::env::var_os("WGPU_BACKEND").is_some() {
            find(None)
        } else {
            find(Some(wgpu::Backends::VULKAN)).or_else(|_| find(Some(wgpu::Backends::GL)))
        }
        .map_err(|e| anyhow!("no GPU adapter: {e}"))?;
        let info = adapter.get_info();
        let features = adapter.features();
        let format = if features.contains(wgpu::Features::FLOAT32_BLENDABLE) {
            TargetFormat::Rgba32Float
        } else {
            TargetFormat::Rgba16Float
        };
        let required_features = if format == TargetFormat::Rgba32Float {
            wgpu::Features::FLOAT32_BLENDABLE
        } else {
            wgpu::Features::empty()
        };
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("tetkit"),
            required_features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| anyhow!("GPU adapter '{}': no device: {e}", info.name))?;
        Ok(GpuContext {
            device,
            queue,
            info,
            limits,
            format,
        })
    }

    /// One line naming the adapter, backend and target format.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?}, driver {} {}), target {:?}",
            self.info.name,
            self.info.backend,
            self.info.device_type,
            self.info.driver,
            self.info.driver_info,
            self.format
        )
    }
}
