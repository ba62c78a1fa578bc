//! Adapter discovery and the device context (wgpu: Vulkan, Metal, DX12). On
//! machines without a GPU, Mesa's lavapipe provides a Vulkan adapter that
//! runs on the CPU.

use serde::Serialize;

/// What a user needs to know about an adapter.
#[derive(Debug, Clone, Serialize, PartialEq, Eq)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    /// Largest storage binding \[bytes\] (lavapipe: 128 MiB).
    pub max_storage_binding: u64,
    /// Largest buffer \[bytes\].
    pub max_buffer: u64,
}

impl AdapterSummary {
    /// The summary of an adapter from its info and `limits` (the
    /// adapter's own, or those a device is opened with).
    fn new(info: &wgpu::AdapterInfo, limits: &wgpu::Limits) -> Self {
        Self {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info)
                .trim()
                .to_string(),
            max_storage_binding: limits.max_storage_buffer_binding_size,
            max_buffer: limits.max_buffer_size,
        }
    }
}

impl std::fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ({}, {}, driver {}, max storage binding {} MiB)",
            self.name,
            self.backend,
            self.device_type,
            if self.driver.is_empty() {
                "?"
            } else {
                &self.driver
            },
            self.max_storage_binding >> 20
        )
    }
}

fn instance() -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
    wgpu::Instance::new(desc)
}

/// Every adapter wgpu can see, best first (discrete, integrated, virtual,
/// CPU).
pub fn list_adapters() -> Vec<AdapterSummary> {
    adapter_details().into_iter().map(|d| d.summary).collect()
}

/// An adapter's rank in [`list_adapters`] (discrete first) and its summary.
fn summarise(a: &wgpu::Adapter) -> (u8, AdapterSummary) {
    let info = a.get_info();
    let limits = a.limits();
    let rank = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    };
    (rank, AdapterSummary::new(&info, &limits))
}

/// An adapter as `viscoslide gpu --json` reports it: its summary, the
/// limits the engine's kernels depend on (workgroup storage and size,
/// bindings per stage, dispatch size, buffer and binding sizes) and the
/// features it offers, by wgpu's names.
#[derive(Debug, Clone, Serialize)]
pub struct AdapterDetails {
    #[serde(flatten)]
    pub summary: AdapterSummary,
    pub limits: AdapterLimits,
    pub features: Vec<String>,
}

/// The adapter limits that decide the engine's plans
/// ([`super::fft_plan`], [`super::split`]).
#[derive(Debug, Clone, Serialize)]
pub struct AdapterLimits {
    pub max_compute_workgroup_storage_size: u32,
    pub max_compute_invocations_per_workgroup: u32,
    pub max_compute_workgroup_size_x: u32,
    pub max_compute_workgroups_per_dimension: u32,
    pub max_storage_buffers_per_shader_stage: u32,
    pub max_storage_buffer_binding_size: u64,
    pub max_buffer_size: u64,
    pub min_storage_buffer_offset_alignment: u32,
    pub max_immediate_size: u32,
}

impl AdapterLimits {
    fn of(l: &wgpu::Limits) -> Self {
        Self {
            max_compute_workgroup_storage_size: l.max_compute_workgroup_storage_size,
            max_compute_invocations_per_workgroup: l.max_compute_invocations_per_workgroup,
            max_compute_workgroup_size_x: l.max_compute_workgroup_size_x,
            max_compute_workgroups_per_dimension: l.max_compute_workgroups_per_dimension,
            max_storage_buffers_per_shader_stage: l.max_storage_buffers_per_shader_stage,
            max_storage_buffer_binding_size: l.max_storage_buffer_binding_size,
            max_buffer_size: l.max_buffer_size,
            min_storage_buffer_offset_alignment: l.min_storage_buffer_offset_alignment,
            max_immediate_size: l.max_immediate_size,
        }
    }
}

/// [`list_adapters`] with each adapter's limits and features.
pub fn adapter_details() -> Vec<AdapterDetails> {
    let inst = instance();
    let mut out: Vec<(u8, AdapterDetails)> =
        pollster::block_on(inst.enumerate_adapters(wgpu::Backends::all()))
            .into_iter()
            .map(|a| {
                let (rank, summary) = summarise(&a);
                let features = a
                    .features()
                    .iter_names()
                    .map(|(name, _)| name.to_string())
                    .collect();
                let limits = AdapterLimits::of(&a.limits());
                (
                    rank,
                    AdapterDetails {
                        summary,
                        limits,
                        features,
                    },
                )
            })
            .collect();
    out.sort_by_key(|(r, _)| *r);
    out.into_iter().map(|(_, d)| d).collect()
}

/// Why no GPU could be used.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("no GPU adapter found ({0}); on CPU-only Linux install Mesa's lavapipe: apt-get install mesa-vulkan-drivers libvulkan1")]
    NoAdapter(String),
    #[error("cannot open a device on {adapter}: {what}")]
    Device { adapter: String, what: String },
    #[error("GPU readback failed: {0}")]
    Readback(String),
    #[error("{what} needs {need} bytes in one GPU buffer, but {adapter} allows {limit} {per}; use a smaller grid or --backend cpu")]
    TooLarge {
        what: String,
        need: u64,
        limit: u64,
        /// What the limit applies to ("per storage binding", "per buffer").
        per: &'static str,
        adapter: String,
    },
    #[error("{what} needs {need} storage bindings in one kernel (arrays larger than one binding count once per window), but {adapter} allows {limit}; use a smaller grid or --backend cpu")]
    TooManyBindings {
        what: String,
        need: u64,
        limit: u64,
        adapter: String,
    },
    #[error("invalid GPU input: {0}")]
    Invalid(String),
}

/// Fail with [`GpuError::TooManyBindings`] when a kernel that binds
/// `bindings` storage buffers (windows of split arrays included) exceeds
/// the storage buffers per shader stage of `limits` on `adapter` (`what`:
/// the kernel or array, for the message).
pub(crate) fn check_binding_count(
    what: &str,
    bindings: u64,
    limits: &wgpu::Limits,
    adapter: &str,
) -> Result<(), GpuError> {
    let limit = limits.max_storage_buffers_per_shader_stage as u64;
    if bindings > limit {
        return Err(GpuError::TooManyBindings {
            what: what.to_string(),
            need: bindings,
            limit,
            adapter: adapter.to_string(),
        });
    }
    Ok(())
}

/// An open device and its queue (cloning shares the device).
#[derive(Clone)]
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: AdapterSummary,
}

impl GpuContext {
    /// Open the best adapter (high-performance preference, fallback
    /// adapters such as lavapipe allowed) with the adapter's own limits.
    pub fn open() -> Result<Self, GpuError> {
        Self::open_with_limits(None, None)
    }

    /// As [`Self::open`], with the largest storage binding lowered to
    /// `binding` bytes and the largest buffer to `buffer` bytes when given
    /// (at most the adapter's; multiples of 4): the device then refuses
    /// larger bindings and buffers exactly as an adapter with those limits
    /// would, so arrays split into binding windows ([`super::split`]) and
    /// the refusals can be tested on small grids.
    pub fn open_with_limits(binding: Option<u64>, buffer: Option<u64>) -> Result<Self, GpuError> {
        let inst = instance();
        let adapter = pollster::block_on(inst.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let mut limits = adapter.limits();
        if let Some(b) = binding {
            let b = b.max(4) & !3;
            limits.max_storage_buffer_binding_size = limits.max_storage_buffer_binding_size.min(b);
        }
        if let Some(b) = buffer {
            let b = b.max(4) & !3;
            limits.max_buffer_size = limits.max_buffer_size.min(b);
        }
        let summary = AdapterSummary::new(&info, &limits);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("viscoslide device"),
            required_features: wgpu::Features::empty(),
            required_limits: limits,
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device {
            adapter: summary.name.clone(),
            what: e.to_string(),
        })?;
        Ok(Self {
            device,
            queue,
            adapter: summary,
        })
    }
}
