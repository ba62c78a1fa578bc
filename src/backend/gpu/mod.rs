//! GPU discovery through wgpu (Vulkan, Metal, DX12). On machines without a
//! GPU, Mesa's lavapipe provides a Vulkan adapter that runs on the CPU.

use serde::Serialize;

/// What a user needs to know about an adapter.
#[derive(Debug, Clone, Serialize, PartialEq, Eq)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    /// Largest storage binding [bytes] (lavapipe: 128 MiB).
    pub max_storage_binding: u64,
    /// Largest buffer [bytes].
    pub max_buffer: u64,
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
    let inst = instance();
    let mut out: Vec<(u8, AdapterSummary)> =
        pollster::block_on(inst.enumerate_adapters(wgpu::Backends::all()))
            .into_iter()
            .map(|a| {
                let info = a.get_info();
                let limits = a.limits();
                let rank = match info.device_type {
                    wgpu::DeviceType::DiscreteGpu => 0,
                    wgpu::DeviceType::IntegratedGpu => 1,
                    wgpu::DeviceType::VirtualGpu => 2,
                    wgpu::DeviceType::Cpu => 3,
                    wgpu::DeviceType::Other => 4,
                };
                (
                    rank,
                    AdapterSummary {
                        name: info.name,
                        backend: format!("{:?}", info.backend),
                        device_type: format!("{:?}", info.device_type),
                        driver: format!("{} {}", info.driver, info.driver_info)
                            .trim()
                            .to_string(),
                        max_storage_binding: limits.max_storage_buffer_binding_size,
                        max_buffer: limits.max_buffer_size,
                    },
                )
            })
            .collect();
    out.sort_by_key(|(r, _)| *r);
    out.into_iter().map(|(_, s)| s).collect()
}
