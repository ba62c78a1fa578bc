//! The host f64 refinement of a uniform-grid GPU solve in mixed precision
//! (physics.md section 13, iterative refinement, `solver::refine`): the
//! device's f32 iteration does the
//! bulk of the work and stops at its rounding floor (residual about 1e-5 to
//! 1e-4); its contact set, pressure and approach then warm-start the same
//! problem on the CPU's f64 Toeplitz operator (the operator of
//! `--backend cpu`), which reaches the requested tolerance in a few outer
//! iterations. The answer is then the f64 answer of the CPU path; the
//! report ([`GpuRefinement`], `summary.json` `gpu_refinement`) states both
//! stages. `[solver] precision = "f32"` (or its older spelling
//! `gpu_refine = false`) keeps the device's f32 answer.

use std::time::Instant;

use serde::Serialize;

use crate::error::Result;
use crate::solver::{self, ContactSolution, Observer, SolveInfo};

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
    /// problem's uniform grid in f64 on the host (`solver::refine`): the
    /// CPU path's f64 operator of the same description (host coefficient
    /// table, Toeplitz-FFT, its preconditioner) warm-started from the
    /// device's contact set, pressure and approach, at the problem's
    /// tolerance. Returns the refined solution, the combined report
    /// (iterations and matvecs of both stages summed; residual, load error
    /// of the host stage; histories one after the other), the total
    /// iteration time and the per-stage report.
    pub(super) fn refine_on_host(
        &self,
        device: (ContactSolution, SolveInfo, f64),
        observer: &mut dyn Observer,
    ) -> Result<(ContactSolution, SolveInfo, f64, GpuRefinement)> {
        let (solution, info, t_device) = device;
        let t = Instant::now();
        let (nx, ny, cell) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let operators = self.uniform_operators()?;
        let (mut backend, l00) =
            CpuExecutor::<f64>::new().build(&operators.on(nx, ny, cell)?, None)?;
        let problem = solver::ContactProblem::new(
            self.gap_profile(),
            self.surface.cell_area(),
            l00,
            self.control,
        );
        let device_report = StageReport::of(&info, t_device);
        let refined = solver::refine(
            &mut backend,
            problem,
            &self.solver_params(),
            (solution, info),
            observer,
        )
        .map_err(|e| self.advise(e))?;
        let t_host = t.elapsed().as_secs_f64();
        let report = GpuRefinement {
            device: device_report,
            host: StageReport::of(&refined.stage, t_host),
        };
        Ok((refined.solution, refined.info, t_device + t_host, report))
    }
}
