//! The host f64 refinement of a uniform-grid GPU solve (physics.md
//! section 13, iterative refinement): the device's f32 iteration does the
//! bulk of the work and stops at its rounding floor (residual about 1e-5 to
//! 1e-4); its contact set, pressure and approach then warm-start the same
//! problem on the CPU's f64 Toeplitz operator (the operator of
//! `--backend cpu`), which reaches the requested tolerance in a few outer
//! iterations. The answer is then the f64 answer of the CPU path; the
//! report ([`GpuRefinement`], `summary.json` `gpu_refinement`) states both
//! stages. `[solver] gpu_refine = false` keeps the device's f32 answer.

use std::time::Instant;

use serde::Serialize;

use crate::error::Result;
use crate::operator::OperatorDescription;
use crate::solver::{ContactSolution, Observer, SolveInfo, WarmStart};

use super::executor::{CpuExecutor, Executes};
use super::Problem;

/// One stage of a refined GPU solve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StageReport {
    /// Active-set iterations (the fine grid's for a cascade).
    pub iterations: usize,
    /// Operator applications (fine-grid equivalent for a cascade).
    pub matvecs: usize,
    /// Preconditioner applications.
    pub preconditioner_applications: usize,
    /// Complementarity residual at the end of the stage.
    pub residual: f64,
    /// Wall time \[s\] (the host stage's includes its f64 coefficient
    /// table and operator set-up).
    pub time_s: f64,
}

impl StageReport {
    fn of(info: &SolveInfo, time_s: f64) -> Self {
        Self {
            iterations: info.iterations,
            matvecs: info.matvecs,
            preconditioner_applications: info.preconditioner_applications,
            residual: info.residual,
            time_s,
        }
    }
}

/// The two stages of a GPU solve refined on the host.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GpuRefinement {
    /// The f32 iteration on the device.
    pub device: StageReport,
    /// The f64 iteration on the host from the device's answer.
    pub host: StageReport,
}

impl Problem {
    /// Refine the device's answer `(solution, info, seconds)` of this
    /// problem's uniform grid in f64 on the host: the CPU path's operator
    /// (host coefficient table, Toeplitz-FFT, its preconditioner)
    /// warm-started from the device's contact set, pressure and approach,
    /// at the problem's tolerance. Returns the refined solution, the
    /// combined report (iterations and matvecs of both stages summed;
    /// residual, load error of the host stage; histories one after the
    /// other), the total iteration time and the per-stage report.
    pub(super) fn refine_on_host(
        &self,
        device: (ContactSolution, SolveInfo, f64),
        observer: &mut dyn Observer,
    ) -> Result<(ContactSolution, SolveInfo, f64, GpuRefinement)> {
        let (solution, info, t_device) = device;
        let t = Instant::now();
        let kernel = self.sliding_kernel()?;
        let description = OperatorDescription::Toeplitz {
            kernel: &kernel,
            grid: self.grid()?,
        };
        let (mut backend, l00) = CpuExecutor::<f64>::new().build(&description, None)?;
        let start = WarmStart {
            contact: solution.contact,
            pressure: solution.pressure,
            approach: solution.approach,
        };
        let (refined, host, _) = self.iterate_grid(&mut backend, l00, Some(start), observer)?;
        let t_host = t.elapsed().as_secs_f64();
        let report = GpuRefinement {
            device: StageReport::of(&info, t_device),
            host: StageReport::of(&host, t_host),
        };
        let combined = SolveInfo {
            iterations: info.iterations + host.iterations,
            matvecs: info.matvecs + host.matvecs,
            preconditioner_applications: info.preconditioner_applications
                + host.preconditioner_applications,
            exact_matvecs: info.exact_matvecs + host.exact_matvecs,
            levels: info.levels,
            residual: host.residual,
            load_error: host.load_error,
            history: info.history.into_iter().chain(host.history).collect(),
            contact_history: info
                .contact_history
                .into_iter()
                .chain(host.contact_history)
                .collect(),
        };
        Ok((refined, combined, t_device + t_host, report))
    }
}
