//! The arithmetic a problem is solved in (physics.md section 13): one typed
//! choice, [`Precision`], that both executors take. `[solver] precision`
//! where given; otherwise the executor's own: f64 on the CPU; on a GPU (f32
//! on the device) `Mixed` on a uniform grid, one iteration of f32 products
//! on the device and f64 residuals on the host (`gpu_refine = false`, the
//! older spelling of `F32`, keeps the device's f32 iteration), and `F32`
//! on the adaptive mesh, which has no mixed iteration. A combination the executor cannot run is refused in one
//! line before anything is solved.

use crate::config::{Formulation, MeshKind, Precision};
use crate::error::Result;

use super::executor::{cpu_f32_refused, gpu_f64_refused, periodic_refused};
use super::{Executor, Problem};

impl Problem {
    /// The precision this problem is solved in on `executor` (module
    /// docs), or the one-line refusal of a combination it cannot run:
    /// `"f32"` on the CPU (it has no f32-only iteration), `"f64"` on a GPU
    /// (the device computes in f32), and `gpu_refine = false` (the device's
    /// f32 iteration, non-periodic only) on a GPU with the periodic
    /// formulation. `"mixed"` on the adaptive mesh, and `"f32"` with the
    /// periodic formulation, are refused by [`Problem::check`] on every
    /// executor.
    pub fn precision_on(&self, executor: &Executor) -> Result<Precision> {
        match (executor, self.precision) {
            (Executor::Cpu, Some(Precision::F32)) => Err(cpu_f32_refused()),
            (Executor::Cpu, p) => Ok(p.unwrap_or(Precision::F64)),
            (Executor::Gpu(_), Some(Precision::F64)) => Err(gpu_f64_refused()),
            (Executor::Gpu(_), Some(p)) => Ok(p),
            (Executor::Gpu(_), None)
                if !self.gpu_refine && self.formulation == Formulation::Periodic =>
            {
                Err(periodic_refused())
            }
            (Executor::Gpu(_), None) => Ok(if self.gpu_refine && self.mesh == MeshKind::Uniform {
                Precision::Mixed
            } else {
                Precision::F32
            }),
        }
    }
}
