//! The graphics adapter and device, opened once per process and shared.
//!
//! Adapter choice: among the adapters of the enabled backends (all native
//! backends, or those named by `WGPU_BACKEND`), prefer a discrete GPU, then an
//! integrated one, then a virtual one, then anything else, and a software
//! rasteriser last. Among hardware adapters Vulkan/Metal/DX12 come before GL;
//! among software ones GL comes first, so a GPU-less machine renders with
//! Mesa llvmpipe through EGL whether or not Vulkan's lavapipe is also
//! installed (it often arrives with ffmpeg), and reference images stay
//! comparable from machine to machine. The device asks for the
//! WebGL2-level downlevel limits with the adapter's own texture size limits,
//! each clamped to what the adapter has.
//!
//! [`check_scope`] turns the device's error scopes into
//! [`RenderError::Gpu`] naming what the renderer was doing.

use super::RenderError;
use std::sync::{Arc, Mutex};

/// An open device with its queue and what callers may want to print about it.
pub(crate) struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// "name (backend, driver, device type)".
    pub description: String,
    /// Largest texture side the device accepts, in pixels.
    pub max_texture_side: u32,
    /// MSAA sample count used for colour and depth (4 when supported, else 1).
    pub sample_count: u32,
}

static SHARED: Mutex<Option<Arc<Gpu>>> = Mutex::new(None);

/// The process-wide device, opened on first use.
pub(crate) fn shared_gpu() -> Result<Arc<Gpu>, RenderError> {
    let mut shared = SHARED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(gpu) = shared.as_ref() {
        return Ok(gpu.clone());
    }
    let gpu = Arc::new(pollster::block_on(open_gpu())?);
    *shared = Some(gpu.clone());
    Ok(gpu)
}

/// Describes the graphics adapter the renderer uses: name, backend, driver
/// and device type, e.g. `llvmpipe (LLVM 19.1.7, 256 bits) (backend gl,
/// driver "…", Cpu, 4x MSAA)`.
pub fn adapter_description() -> Result<String, RenderError> {
    Ok(shared_gpu()?.description.clone())
}

/// The largest image the device renders: its largest texture side in
/// pixels and its largest buffer in bytes (an image is read back through one).
pub fn max_image_size() -> Result<(u32, u64), RenderError> {
    let gpu = shared_gpu()?;
    Ok((gpu.max_texture_side, gpu.device.limits().max_buffer_size))
}

/// The variable wgpu reads for the backends to try.
pub const BACKEND_VARIABLE: &str = "WGPU_BACKEND";

/// The backend names wgpu accepts in [`BACKEND_VARIABLE`] (its own list,
/// `wgpu::Backends::from_comma_list`, without `noop`, which renders nothing).
const BACKEND_NAMES: [&str; 10] = [
    "vulkan", "vk", "dx12", "d3d12", "metal", "mtl", "opengl", "gles", "gl", "webgpu",
];

/// Why [`BACKEND_VARIABLE`] cannot select a backend (`None` when it is unset
/// or names only backends wgpu knows): wgpu skips a name it does not know
/// with a log line nobody sees, and a list of only such names left no backend
/// to try, found only when the first frame was to be drawn.
pub fn backend_variable_problem() -> Option<String> {
    let value = std::env::var_os(BACKEND_VARIABLE)?;
    let Some(text) = value.to_str() else {
        return Some("is not valid UTF-8".to_owned());
    };
    let unknown: Vec<&str> = text
        .split(',')
        .map(str::trim)
        .filter(|name| !BACKEND_NAMES.contains(&name.to_lowercase().as_str()))
        .collect();
    (!unknown.is_empty()).then(|| {
        format!(
            "names no graphics backend wgpu knows: `{}`; give a comma-separated list of {}",
            unknown.join("`, `"),
            BACKEND_NAMES.join(", ")
        )
    })
}

fn backends() -> wgpu::Backends {
    wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY | wgpu::Backends::GL)
}

/// Lower is better.
fn device_type_rank(device_type: wgpu::DeviceType) -> u8 {
    match device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    }
}

async fn open_gpu() -> Result<Gpu, RenderError> {
    let backends = backends();
    let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle().with_env();
    descriptor.backends = backends;
    let instance = wgpu::Instance::new(descriptor);
    let adapter = instance
        .enumerate_adapters(backends)
        .await
        .into_iter()
        .filter(|adapter| adapter.get_info().backend != wgpu::Backend::Noop)
        .min_by_key(|adapter| {
            let info = adapter.get_info();
            let software = info.device_type == wgpu::DeviceType::Cpu;
            (
                device_type_rank(info.device_type),
                (info.backend == wgpu::Backend::Gl) != software,
            )
        })
        .ok_or_else(|| RenderError::NoAdapter {
            backends: backend_names(backends),
        })?;

    open_device(adapter).await
}

/// Opens `adapter`'s device with the limits and sample count the renderer uses.
async fn open_device(adapter: wgpu::Adapter) -> Result<Gpu, RenderError> {
    let info = adapter.get_info();
    let adapter_limits = adapter.limits();
    let limits = wgpu::Limits::downlevel_webgl2_defaults()
        .using_resolution(adapter_limits.clone())
        .or_worse_values_from(&adapter_limits);
    let max_texture_side = limits.max_texture_dimension_2d;

    let msaa = [
        wgpu::TextureFormat::Rgba8UnormSrgb,
        wgpu::TextureFormat::Depth32Float,
    ]
    .iter()
    .all(|&format| {
        adapter
            .get_texture_format_features(format)
            .flags
            .sample_count_supported(4)
    });
    let sample_count = if msaa { 4 } else { 1 };

    let description = format!(
        "{} (backend {}, driver \"{}{}{}\", {:?}, {}x MSAA)",
        info.name,
        info.backend,
        info.driver,
        if info.driver.is_empty() || info.driver_info.is_empty() {
            ""
        } else {
            " "
        },
        info.driver_info,
        info.device_type,
        sample_count
    );

    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("elasto render device"),
            required_features: wgpu::Features::empty(),
            required_limits: limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        })
        .await
        .map_err(|error| RenderError::Device {
            adapter: description.clone(),
            message: error.to_string(),
        })?;

    Ok(Gpu {
        device,
        queue,
        description,
        max_texture_side,
        sample_count,
    })
}

fn backend_names(backends: wgpu::Backends) -> String {
    let names: Vec<&str> = wgpu::Backend::ALL
        .iter()
        .filter(|&&backend| backends.contains(backend.into()))
        .map(|backend| backend.to_str())
        .collect();
    if names.is_empty() {
        "none".to_owned()
    } else {
        names.join(", ")
    }
}

/// Turns the error an error scope caught, if any, into a [`RenderError::Gpu`].
pub(crate) fn check_scope(
    scope: wgpu::ErrorScopeGuard,
    during: &'static str,
) -> Result<(), RenderError> {
    match pollster::block_on(scope.pop()) {
        None => Ok(()),
        Some(error) => Err(RenderError::Gpu {
            during,
            message: error.to_string(),
        }),
    }
}
