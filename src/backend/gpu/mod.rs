//! GPU executor (wgpu). In the f32 iteration ([`GpuBackend`]) every vector
//! lives on the device in f32; the host sees only the scalars each step
//! needs (reduction partials finished in f64) and the size of each new
//! contact set. In mixed precision ([`mixed`]) the vectors are the host's
//! and the device computes the f32 products.
//!
//! - [`context`]: adapter discovery and the device.
//! - [`shaders`]: the WGSL kernels of `shaders/` and their validation.
//! - [`engine`]: pipeline and bind-group caches, the parameter ring, command
//!   recording, submission and readback.
//! - [`split`]: arrays larger than one storage binding, bound as windows.
//! - [`pool`]: grid-sized storage buffers, recycled.
//! - [`fft`]: the Toeplitz matvec (paper Eq. 7) by a padded FFT: its
//!   buffers, kernel spectrum and recording.
//! - [`fft_plan`]: the dispatches of that matvec (workgroup-memory Stockham
//!   passes over real rows, or the radix-2 fallback) and their memory
//!   traffic.
//! - [`fft_twin`]: the CPU twin of the shared-memory FFT kernels.
//! - [`plan`]: what the coefficient kernels share: the creep-term plan, the
//!   workgroup grid of large dispatches and the scaled f32 read-back.
//! - [`coefficients`]: the influence-coefficient table computed on the device.
//! - [`adaptive`]: coefficients between cells of different sizes and the
//!   matrix-free operator of a non-uniform mesh.
//! - [`level_tables`]: the same operator on a quadtree mesh from per-level
//!   coefficient tables computed on the device.
//! - [`backend`]: [`GpuBackend`], the [`crate::backend::Backend`] implementation.
//! - [`mixed`]: the operator of a GPU's mixed precision, f32 products on
//!   the device and f64 ones on the host, for the CPU backend's iteration.

pub mod adaptive;
pub mod backend;
pub mod coefficients;
pub mod context;
pub mod engine;
pub mod fft;
pub mod fft_plan;
pub mod fft_twin;
pub mod level_tables;
pub mod mixed;
pub mod plan;
pub mod pool;
pub mod shaders;
pub mod split;

pub use adaptive::{AdaptiveMatvec, MeshCells};
pub use backend::{FftChoice, GpuBackend, GpuIndex, GpuOptions, GpuVector, SpectrumPrecision};
pub use context::{
    adapter_details, list_adapters, AdapterDetails, AdapterLimits, AdapterSummary, GpuContext,
    GpuError,
};
pub use level_tables::{GpuLevelTables, LevelMatvec};
