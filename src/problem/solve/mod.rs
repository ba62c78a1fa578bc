//! The one path through a solve: the formulation and mesh
//! (`Discretisation`) choose the route (`uniform.rs`: one grid or the
//! cascade, Toeplitz or periodic; `rounds.rs`: the adaptive mesh's
//! rounds), each route describes its operators
//! ([`OperatorDescription`](crate::operator::OperatorDescription)) and the
//! executor ([`Executor`]) turns each into its backend (`Executes`); every
//! grid's constrained iteration runs through one function
//! (`Problem::iterate`, `iterate.rs`); the precision is one typed choice
//! both executors take ([`Problem::precision_on`]; `"mixed"` is one
//! iteration on either, its f32 products on the CPU's f32 transforms or on
//! a device). The friction by both routes, the finite pad's own friction,
//! the contact statistics and the timings (`finish.rs`) are computed once
//! for all routes.

mod finish;
mod iterate;
mod rounds;
mod uniform;

pub(super) use uniform::UniformOperators;

use std::time::Instant;

use crate::config::{Formulation, MeshKind, Precision};
use crate::error::Result;
use crate::solver::{ContactSolution, Observer, SolveInfo, WarmStart};

use super::adaptive::MeshReport;
use super::executor::{
    cpu_f32_refused, gpu_f64_refused, CpuExecutor, Executes, GpuExecutor, GpuMixedExecutor,
};
use super::{invalid, Executor, Problem, Solution};

/// The operator a problem is solved with: formulation x mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Discretisation {
    /// Non-periodic, uniform grid: Toeplitz operator, FFT matvec (paper Eq. 6-7).
    Uniform,
    /// Periodic cell, spectral operator (paper Appendix, Eq. A1-A2).
    Periodic,
    /// Non-periodic on an adaptive quadtree: pairwise level-table operator.
    Adaptive,
}

/// What every path hands to the common finish.
pub(super) struct Raw {
    pub solution: ContactSolution,
    pub info: SolveInfo,
    pub backend: String,
    pub mesh: Option<MeshReport>,
    /// Coefficient tables \[s\].
    pub t_coeff: f64,
    /// Operator set-up \[s\]; `None`: the time not accounted for otherwise
    /// (the adaptive mesh's rounds).
    pub t_setup: Option<f64>,
    /// Iteration \[s\].
    pub t_iter: f64,
}

impl Problem {
    /// The operator this problem is solved with.
    pub(crate) fn discretisation(&self) -> Discretisation {
        match (self.formulation, self.mesh) {
            (Formulation::Periodic, _) => Discretisation::Periodic,
            (Formulation::NonPeriodic, MeshKind::Uniform) => Discretisation::Uniform,
            (Formulation::NonPeriodic, MeshKind::Adaptive) => Discretisation::Adaptive,
        }
    }

    /// Solve on `executor`; `observer` sees every outer iteration.
    pub fn solve(&self, executor: &Executor, observer: &mut dyn Observer) -> Result<Solution> {
        self.solve_from(executor, None, observer)
    }

    /// [`Problem::solve`] from a warm start (a previous solution's contact
    /// set, pressure and approach on this grid, e.g. from
    /// [`Solution::warm_start`] of a neighbouring speed or load); the start
    /// changes the path, not the solution. The adaptive mesh warm-starts
    /// each round from the previous one and takes no outside start.
    pub fn solve_from(
        &self,
        executor: &Executor,
        start: Option<&WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<Solution> {
        self.solve_warm(executor, start.cloned(), observer)
    }

    /// [`Problem::solve_from`] taking the start by value: its vectors are
    /// freed as soon as the iteration holds them (16 bytes per cell that a
    /// refinement study's finest grid does not keep twice).
    pub fn solve_warm(
        &self,
        executor: &Executor,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<Solution> {
        self.check()?;
        let t0 = Instant::now();
        if let Some(w) = &start {
            self.check_start(w)?;
        }
        let precision = self.precision_on(executor)?;
        match executor {
            Executor::Cpu => {
                let raw = match precision {
                    Precision::F64 => self.run(&mut CpuExecutor::<f64>::new(), start, observer)?,
                    Precision::Mixed => {
                        self.run(&mut CpuExecutor::<f32>::new(), start, observer)?
                    }
                    Precision::F32 => return Err(cpu_f32_refused()),
                };
                // The finite pad's reference in f64 whatever the rough
                // solve's precision.
                self.finish(raw, t0, &mut CpuExecutor::<f64>::new(), precision)
            }
            Executor::Gpu(ctx) => match precision {
                // The CPU's mixed iteration with the device's f32 products.
                Precision::Mixed => {
                    let mut gpu = GpuMixedExecutor::for_problem(ctx, self)?;
                    let raw = self.run(&mut gpu, start, observer)?;
                    self.finish(raw, t0, &mut gpu, precision)
                }
                Precision::F32 => {
                    let mut gpu = GpuExecutor::for_problem(ctx, self)?;
                    let raw = self.run(&mut gpu, start, observer)?;
                    self.finish(raw, t0, &mut gpu, precision)
                }
                Precision::F64 => Err(gpu_f64_refused()),
            },
        }
    }

    /// A warm start's refusal where it does not fit this problem: the
    /// adaptive mesh takes none, and its vectors must cover the grid.
    fn check_start(&self, w: &WarmStart) -> Result<()> {
        let n = self.surface.nx * self.surface.ny;
        if self.discretisation() == Discretisation::Adaptive {
            return Err(invalid(
                "the adaptive mesh takes no warm start (its rounds warm-start each other); use mesh = \"uniform\"",
            ));
        }
        if w.pressure.len() != n || w.contact.len() != n {
            return Err(invalid(format!(
                "the warm start has {} cells, the {} x {} grid needs {n}",
                w.pressure.len(),
                self.surface.nx,
                self.surface.ny
            )));
        }
        Ok(())
    }

    /// The iteration of this problem on `executor`: a uniform grid (one
    /// grid or the cascade) or the adaptive mesh's rounds.
    fn run<X: Executes>(
        &self,
        executor: &mut X,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
        match self.discretisation() {
            Discretisation::Adaptive => self.adaptive(executor, observer),
            Discretisation::Uniform | Discretisation::Periodic => {
                self.uniform(executor, start, observer)
            }
        }
    }
}
