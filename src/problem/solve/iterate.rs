//! The one call of the solver: the constrained iteration (paper Eq. 6-7
//! with `p >= 0`) of a problem on any backend, with the solver's
//! parameters for that problem and the advice a stalled solve gets.

use std::time::Instant;

use crate::backend::Backend;
use crate::config::Formulation;
use crate::error::Result;
use crate::solver::{self, ContactSolution, Observer, SolveInfo, SolverError, WarmStart};

use super::super::Problem;

impl Problem {
    /// The solver's parameters for this problem: a layer on the thin-layer
    /// law (`kernel/thin_law.rs`, a bonded incompressible layer far below a
    /// cell) takes no preconditioner, whatever `solver.precondition` says:
    /// the law's coefficients sum to zero (no compliance to a uniform
    /// pressure), so the padded circulant's inverse at `q = 0` is its
    /// regularisation floor, 1e6 of the largest, and the preconditioned
    /// inner solves of a small contact set diverge (the set emptied on
    /// `configs/default.toml`-like pads at 32^2); plain GMRES solves them.
    pub(in crate::problem) fn solver_params(&self) -> solver::SolverParams {
        let thin_law = self.formulation == Formulation::NonPeriodic
            && self.layer.is_some()
            && self.sliding_kernel().is_ok_and(|k| {
                let (ax, ay) = self.surface.cell();
                k.is_thin_law(ax, ay)
            });
        solver::SolverParams {
            precondition: self.params.precondition && !thin_law,
            ..self.params.clone()
        }
    }

    /// The constrained iteration (paper Eq. 6-7 with `p >= 0`) of this
    /// problem on `backend` (`l00` the self coefficient, `g` the gap profile
    /// over the backend's unknowns, handed to the iteration: on the CPU it
    /// becomes the iteration's own vector) at the relative tolerance
    /// `tolerance`: the one call of the solver for every discretisation and
    /// executor.
    pub(in crate::problem) fn iterate<B: Backend>(
        &self,
        backend: &mut B,
        g: Vec<f64>,
        l00: f64,
        tolerance: f64,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> std::result::Result<(ContactSolution, SolveInfo), SolverError> {
        let params = solver::SolverParams {
            tolerance,
            ..self.solver_params()
        };
        solver::solve(
            backend,
            solver::ContactProblem::new(g, self.surface.cell_area(), l00, self.control),
            &params,
            start,
            observer,
        )
        .map_err(|e| self.advise(e))
    }

    /// A stalled solve's error with what to do for this problem: the
    /// non-periodic formulation where the periodic one stalled (it
    /// converged on every stalled periodic case of the robustness study,
    /// BENCHMARKS.md).
    pub(in crate::problem) fn advise(&self, e: SolverError) -> SolverError {
        match e {
            SolverError::NoConvergence {
                iterations,
                matvecs,
                residual,
                history,
                mut cause,
            } if cause.contains("stalled") => {
                cause.push_str(match self.formulation {
                    Formulation::Periodic => "; try formulation = \"non_periodic\" (it converged on every stalled periodic problem measured: BENCHMARKS.md, \"Stalled solves and sub-cell layers\") or a larger solver.restart",
                    Formulation::NonPeriodic => "; try a finer grid, a lower load or a larger solver.restart",
                });
                SolverError::NoConvergence {
                    iterations,
                    matvecs,
                    residual,
                    history,
                    cause,
                }
            }
            e => e,
        }
    }

    /// [`Problem::iterate`] over the whole grid at the problem's tolerance,
    /// timed.
    pub(in crate::problem) fn iterate_grid<B: Backend>(
        &self,
        backend: &mut B,
        l00: f64,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<(ContactSolution, SolveInfo, f64)> {
        let t = Instant::now();
        let g = self.gap_profile();
        let (solution, info) =
            self.iterate(backend, g, l00, self.params.tolerance, start, observer)?;
        Ok((solution, info, t.elapsed().as_secs_f64()))
    }
}
