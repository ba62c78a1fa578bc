//! Who runs the iteration: the CPU reference path or a GPU device, and the
//! choice between them for `--backend auto | gpu | cpu`; the CPU backend of
//! a uniform grid.

use crate::backend::gpu::{GpuBackend, GpuContext};
use crate::backend::{BackendChoice, CpuBackend};
use crate::error::Result;
use crate::operator::{OffsetTable, Real, ToeplitzFft};

use super::Problem;

/// Who runs the iteration.
#[derive(Clone)]
pub enum Executor {
    /// The CPU reference path (rayon, rustfft), f64.
    Cpu,
    /// A GPU device (wgpu), f32 vectors.
    Gpu(GpuContext),
}

impl std::fmt::Debug for Executor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Executor::Cpu => write!(f, "Executor::Cpu"),
            Executor::Gpu(ctx) => write!(f, "Executor::Gpu({})", ctx.adapter),
        }
    }
}

impl Executor {
    /// Resolve a backend choice for `problem`: `auto` takes a GPU when one
    /// exists, the problem fits on it and it is not emulated on the CPU.
    /// Returns the executor and a line saying which was picked and why.
    pub fn select(choice: BackendChoice, problem: &Problem) -> Result<(Executor, String)> {
        let (nx, ny) = (problem.surface.nx, problem.surface.ny);
        Ok(match choice {
            BackendChoice::Cpu => (Executor::Cpu, "backend: cpu".into()),
            BackendChoice::Gpu => {
                let ctx = GpuContext::open()?;
                let line = format!("backend: gpu, adapter {}", ctx.adapter);
                (Executor::Gpu(ctx), line)
            }
            BackendChoice::Auto => match GpuContext::open()
                .and_then(|ctx| GpuBackend::check_fits(&ctx, nx, ny).map(|()| ctx))
            {
                Ok(ctx) if ctx.adapter.device_type == "Cpu" => (
                    Executor::Cpu,
                    format!(
                        "backend: cpu (auto: the only adapter, {}, is emulated on the CPU and slower than the CPU backend; --backend gpu forces it)",
                        ctx.adapter
                    ),
                ),
                Ok(ctx) => {
                    let line = format!("backend: gpu (auto), adapter {}", ctx.adapter);
                    (Executor::Gpu(ctx), line)
                }
                Err(e) => (Executor::Cpu, format!("backend: cpu (auto: {e})")),
            },
        })
    }
}

/// The CPU backend of a uniform `nx x ny` grid from its offset table
/// (`values` as in [`OffsetTable`]): the Toeplitz-FFT operator with its
/// preconditioners and exact products in precision `T`, and the self
/// coefficient `L_00`.
pub(super) fn toeplitz_backend<T: Real>(
    nx: usize,
    ny: usize,
    values: &[f64],
) -> (CpuBackend<ToeplitzFft<T>>, f64) {
    let tab = OffsetTable { nx, ny, values };
    let op = ToeplitzFft::<T>::in_precision(tab)
        .with_preconditioner()
        .with_exact();
    (CpuBackend::new(op), tab.get(0, 0))
}
