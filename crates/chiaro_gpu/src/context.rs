//! The wgpu adapter, device and queue the frame runs on.
//!
//! [`GpuContext::new_headless`] takes any adapter wgpu offers (Vulkan or GL: a discrete GPU is
//! preferred over an integrated one, a virtual one, then a CPU rasterizer such as lavapipe or
//! llvmpipe) and asks the device for exactly what chiaro needs ([`required_limits`]), plus
//! timestamp queries when the adapter has them. An adapter that falls short is refused with an
//! error naming it and each missing limit or capability.

use std::fmt::Write as _;

use thiserror::Error;

/// Storage buffers one shader stage binds: the scene's group(0) (6: instances, meshes, texture
/// atlas and table, instance extras, scene info; the BVH's arrays, the vertices, indices and
/// materials, the light tables and the environment are textures) plus a pass's own (the ray
/// passes: camera and parameters; parameters are storage buffers too, see
/// [`crate::passes::params`]).
pub const STORAGE_BUFFERS_PER_STAGE: u32 = 8;

/// Colour targets the G-buffer pass writes: position, surface, emission, motion and triangle
/// (one past WebGPU's downlevel 4).
pub const GBUFFER_TARGETS: u32 = 5;

/// Why no device could be made.
#[derive(Debug, Error)]
pub enum ContextError {
    /// wgpu found no adapter on the enabled backends.
    #[error(
        "no GPU adapter found on backends {backends:?} (install a Vulkan driver such as Mesa's lavapipe, or a GL driver)"
    )]
    NoAdapter {
        /// The backends searched.
        backends: wgpu::Backends,
    },
    /// Every adapter lacks something chiaro needs; the best-ranked one is named.
    #[error("adapter '{adapter}' ({backend:?}) cannot run chiaro: {missing}")]
    Unsupported {
        /// The adapter's name.
        adapter: String,
        /// Its backend.
        backend: wgpu::Backend,
        /// What it lacks, e.g. `max_storage_buffers_per_shader_stage: need 16, have 8`.
        missing: String,
    },
    /// The adapter refused the device request.
    #[error("adapter '{adapter}' refused the device: {source}")]
    Device {
        /// The adapter's name.
        adapter: String,
        /// wgpu's error.
        source: wgpu::RequestDeviceError,
    },
}

/// The limits chiaro asks for: WebGPU's downlevel defaults with more storage buffers per stage,
/// five colour targets and 64 bytes of them per sample (the G-buffer's use 56), and the
/// adapter's own buffer and texture sizes (large scenes need large storage buffers).
pub fn required_limits(adapter: &wgpu::Limits) -> wgpu::Limits {
    wgpu::Limits {
        max_storage_buffers_per_shader_stage: STORAGE_BUFFERS_PER_STAGE,
        // Five where the adapter has them: the traced G-buffer writes five targets.
        max_storage_textures_per_shader_stage: adapter.max_storage_textures_per_shader_stage.clamp(
            4,
            crate::passes::gbuffer_traced::TRACED_GBUFFER_STORAGE_TEXTURES,
        ),
        max_texture_dimension_2d: adapter.max_texture_dimension_2d.max(2048),
        max_color_attachments: GBUFFER_TARGETS,
        max_color_attachment_bytes_per_sample: 64,
        max_storage_buffer_binding_size: adapter
            .max_storage_buffer_binding_size
            .max(wgpu::Limits::downlevel_defaults().max_storage_buffer_binding_size),
        max_buffer_size: adapter
            .max_buffer_size
            .max(wgpu::Limits::downlevel_defaults().max_buffer_size),
        ..wgpu::Limits::downlevel_defaults()
    }
}

/// The downlevel capabilities chiaro's shaders use.
const REQUIRED_DOWNLEVEL: wgpu::DownlevelFlags = wgpu::DownlevelFlags::COMPUTE_SHADERS
    .union(wgpu::DownlevelFlags::VERTEX_STORAGE)
    .union(wgpu::DownlevelFlags::FRAGMENT_STORAGE)
    .union(wgpu::DownlevelFlags::INDIRECT_EXECUTION);

/// The texture formats the frame uses and how (see [`crate::targets`]).
fn required_formats() -> [(wgpu::TextureFormat, wgpu::TextureUsages); 6] {
    use crate::targets as t;
    use wgpu::TextureUsages as U;
    let attachment = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING;
    let storage = U::STORAGE_BINDING | U::TEXTURE_BINDING;
    [
        (t::POSITION_FORMAT, attachment),
        (t::SURFACE_FORMAT, attachment),
        (t::MOTION_FORMAT, attachment),
        (t::DEPTH_FORMAT, U::RENDER_ATTACHMENT),
        (t::HDR_FORMAT, storage),
        (t::LDR_FORMAT, storage),
    ]
}

/// What `adapter` lacks for chiaro, empty when nothing.
pub fn missing_capabilities(adapter: &wgpu::Adapter) -> String {
    let mut missing = String::new();
    let have = adapter.limits();
    required_limits(&have).check_limits_with_fail_fn(&have, false, |name, need, got| {
        let _ = write!(missing, "{}{name}: need {need}, have {got}", sep(&missing));
    });
    for (format, usages) in required_formats() {
        let allowed = adapter.get_texture_format_features(format).allowed_usages;
        let lacking = usages.difference(allowed);
        if !lacking.is_empty() {
            let _ = write!(missing, "{}{format:?} as {lacking:?}", sep(&missing));
        }
    }
    let flags = adapter.get_downlevel_capabilities().flags;
    let lacking = REQUIRED_DOWNLEVEL.difference(flags);
    if !lacking.is_empty() {
        let _ = write!(
            missing,
            "{}downlevel capabilities {lacking:?}",
            sep(&missing)
        );
    }
    missing
}

fn sep(text: &str) -> &'static str {
    if text.is_empty() { "" } else { "; " }
}

/// Preference of an adapter kind: lower is better.
fn rank(info: &wgpu::AdapterInfo) -> (u8, u8) {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    };
    let backend = u8::from(info.backend != wgpu::Backend::Vulkan);
    (kind, backend)
}

/// The device chiaro renders with.
pub struct GpuContext {
    /// The wgpu instance the adapter came from.
    pub instance: wgpu::Instance,
    /// The chosen adapter.
    pub adapter: wgpu::Adapter,
    /// The adapter's description (name, backend, driver).
    pub info: wgpu::AdapterInfo,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Whether the device has timestamp queries (passes are then timed on the GPU).
    pub timestamps: bool,
    /// Whether the device can trace the G-buffer
    /// ([`crate::passes::gbuffer_traced::traced_gbuffer_supported`]); its targets are then
    /// storage textures too.
    pub traced_gbuffer: bool,
    /// Tells this context's device from every other this process made (wgpu's handles of
    /// devices from different instances may compare equal).
    pub id: u64,
}

/// The next [`GpuContext::id`].
static NEXT_CONTEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

impl GpuContext {
    /// A context on the best adapter of the backends wgpu's environment variables allow
    /// (`WGPU_BACKEND`; Vulkan, then GL when Vulkan offers no usable adapter), without a
    /// surface.
    pub fn new_headless() -> Result<Self, ContextError> {
        let allowed =
            wgpu::Backends::from_env().unwrap_or(wgpu::Backends::VULKAN | wgpu::Backends::GL);
        let mut refusal = None;
        for backends in [wgpu::Backends::VULKAN, wgpu::Backends::GL] {
            let backends = backends & allowed;
            if backends.is_empty() {
                continue;
            }
            match Self::on_backends(backends) {
                Ok(context) => return Ok(context),
                Err(e @ ContextError::NoAdapter { .. }) => refusal = refusal.or(Some(e)),
                Err(e) => refusal = Some(e),
            }
        }
        Err(refusal.unwrap_or(ContextError::NoAdapter { backends: allowed }))
    }

    /// A context on the best usable adapter of `backends`.
    fn on_backends(backends: wgpu::Backends) -> Result<Self, ContextError> {
        let descriptor = wgpu::InstanceDescriptor {
            backends,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        }
        .with_env();
        let instance = wgpu::Instance::new(descriptor);
        let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
        adapters.sort_by_key(|a| rank(&a.get_info()));
        let Some(best) = adapters.first() else {
            return Err(ContextError::NoAdapter { backends });
        };
        let Some(adapter) = adapters
            .iter()
            .find(|a| missing_capabilities(a).is_empty())
            .cloned()
        else {
            let info = best.get_info();
            return Err(ContextError::Unsupported {
                adapter: info.name,
                backend: info.backend,
                missing: missing_capabilities(best),
            });
        };
        Self::from_adapter(instance, adapter)
    }

    /// A context on `adapter`, which must have what [`missing_capabilities`] checks.
    pub fn from_adapter(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
    ) -> Result<Self, ContextError> {
        let info = adapter.get_info();
        let missing = missing_capabilities(&adapter);
        if !missing.is_empty() {
            return Err(ContextError::Unsupported {
                adapter: info.name,
                backend: info.backend,
                missing,
            });
        }
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let traced_gbuffer = crate::passes::gbuffer_traced::traced_gbuffer_supported(&adapter);
        let required_features = if timestamps {
            wgpu::Features::TIMESTAMP_QUERY
        } else {
            wgpu::Features::empty()
        };
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("chiaro device"),
            required_features,
            required_limits: required_limits(&adapter.limits()),
            ..Default::default()
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|source| {
                ContextError::Device {
                    adapter: info.name.clone(),
                    source,
                }
            })?;
        log::info!(
            "GPU: {} ({:?}, {:?}, driver {} {}), timestamps {}, traced G-buffer {}",
            info.name,
            info.backend,
            info.device_type,
            info.driver,
            info.driver_info,
            timestamps,
            traced_gbuffer,
        );
        Ok(Self {
            instance,
            adapter,
            info,
            device,
            queue,
            timestamps,
            traced_gbuffer,
            id: NEXT_CONTEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        })
    }

    /// One line naming the adapter: name, backend, kind.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }

    /// Whether the adapter runs on the CPU (lavapipe, llvmpipe): its work takes the cores
    /// that anything else running beside it would.
    pub fn runs_on_cpu(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_gpus_rank_before_cpus_and_vulkan_before_gl() {
        let info = wgpu::AdapterInfo::new;
        let discrete = rank(&info(wgpu::DeviceType::DiscreteGpu, wgpu::Backend::Gl));
        let cpu_vk = rank(&info(wgpu::DeviceType::Cpu, wgpu::Backend::Vulkan));
        let cpu_gl = rank(&info(wgpu::DeviceType::Cpu, wgpu::Backend::Gl));
        assert!(discrete < cpu_vk && cpu_vk < cpu_gl);
    }

    #[test]
    fn required_limits_take_the_adapters_buffer_sizes() {
        let adapter = wgpu::Limits {
            max_storage_buffer_binding_size: 1 << 30,
            ..wgpu::Limits::default()
        };
        let limits = required_limits(&adapter);
        assert_eq!(limits.max_storage_buffer_binding_size, 1 << 30);
        assert_eq!(
            limits.max_storage_buffers_per_shader_stage,
            STORAGE_BUFFERS_PER_STAGE
        );
        // An adapter with WebGPU's default limits (8 storage buffers per stage) falls short of
        // the G-buffer's bytes per sample only.
        let mut failures = Vec::new();
        limits.check_limits_with_fail_fn(&adapter, false, |name, _, _| failures.push(name));
        assert_eq!(failures, ["max_color_attachment_bytes_per_sample"]);
    }
}
