//! The one path through a solve: the formulation and mesh
//! ([`Discretisation`]) give operator descriptions
//! ([`OperatorDescription`]), the executor ([`Executor`]) turns each into
//! its backend (`Executes`), and every grid's constrained iteration runs
//! through one function (`Problem::iterate`); the precision is one typed
//! choice both executors take ([`Problem::precision_on`]); the refinement
//! of an f32 device answer, the friction by both
//! routes, the finite pad's own friction, the contact statistics and the
//! timings are then computed once for all paths.

use std::sync::Arc;
use std::time::Instant;

use crate::backend::Backend;
use crate::config::{Formulation, MeshKind, Precision};
use crate::error::{Error, Result};
use crate::kernel::SlidingKernel;
use crate::operator::{LevelTables, OperatorDescription};
use crate::response::{Grid, SlidingResponse};
use crate::solver::{self, ContactSolution, Observer, SolveInfo, SolverError, WarmStart};

use super::adaptive::{solve_adaptive, AdaptiveError, AdaptiveParams, MeshReport};
use super::executor::{cpu_f32_refused, periodic_refused, CpuExecutor, Executes, GpuExecutor};
use super::gpu_refine::GpuRefinement;
use super::smooth_pad::SMOOTH_PAD_SHARE_LIMIT;
use super::{invalid, Executor, Problem, Solution, Timings};

/// The operator a problem is solved with: formulation x mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Discretisation {
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
    /// The stages of a GPU solve refined on the host.
    pub refinement: Option<GpuRefinement>,
}

impl Problem {
    /// The operator this problem is solved with.
    pub fn discretisation(&self) -> Discretisation {
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
        let kind = self.discretisation();
        if let Some(w) = &start {
            let n = self.surface.nx * self.surface.ny;
            if kind == Discretisation::Adaptive {
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
        }
        let precision = self.precision_on(executor)?;
        match executor {
            Executor::Cpu => {
                let raw = match precision {
                    Precision::F64 => {
                        self.run_in(&mut CpuExecutor::<f64>::new(), start, observer)?
                    }
                    Precision::Mixed => {
                        self.run_in(&mut CpuExecutor::<f32>::new(), start, observer)?
                    }
                    Precision::F32 => return Err(cpu_f32_refused()),
                };
                // The finite pad's reference in f64 whatever the rough
                // solve's precision.
                self.finish(raw, t0, &mut CpuExecutor::<f64>::new(), precision)
            }
            Executor::Gpu(ctx) => {
                match kind {
                    Discretisation::Periodic => return Err(periodic_refused()),
                    Discretisation::Adaptive if self.layer.is_some() => {
                        return Err(invalid(
                            "the GPU adaptive operator covers half-spaces only; use --backend cpu with [layer]",
                        ))
                    }
                    _ => {}
                }
                let mut gpu = GpuExecutor::new(ctx.clone(), self.params.precondition, precision)?;
                let raw = self.run_in(&mut gpu, start, observer)?;
                self.finish(raw, t0, &mut gpu, precision)
            }
        }
    }

    /// The iteration of this problem on `executor` in its precision:
    /// [`Problem::run`], then, for an executor
    /// whose mixed precision is refined afterwards
    /// ([`Executes::refined_on_host`]; a uniform grid), the f64 refinement
    /// on the host from its answer.
    fn run_in<X: Executes>(
        &self,
        executor: &mut X,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
        let raw = self.run(executor, start, observer)?;
        if executor.refined_on_host() && raw.mesh.is_none() {
            self.refined(raw, observer)
        } else {
            Ok(raw)
        }
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

    /// A device's answer refined in f64 on the host ([`super::gpu_refine`]).
    fn refined(&self, raw: Raw, observer: &mut dyn Observer) -> Result<Raw> {
        let device = (raw.solution, raw.info, raw.t_iter);
        let (solution, info, t_iter, report) = self.refine_on_host(device, observer)?;
        Ok(Raw {
            solution,
            info,
            backend: format!("{}, refined in f64 on the host", raw.backend),
            t_iter,
            refinement: Some(report),
            ..raw
        })
    }

    /// The solver's parameters for this problem: a layer on the thin-layer
    /// law (`kernel/thin_law.rs`, a bonded incompressible layer far below a
    /// cell) takes no preconditioner, whatever `solver.precondition` says:
    /// the law's coefficients sum to zero (no compliance to a uniform
    /// pressure), so the padded circulant's inverse at `q = 0` is its
    /// regularisation floor, 1e6 of the largest, and the preconditioned
    /// inner solves of a small contact set diverge (the set emptied on
    /// `configs/default.toml`-like pads at 32^2); plain GMRES solves them.
    pub(super) fn solver_params(&self) -> solver::SolverParams {
        let thin_law = self.formulation == crate::config::Formulation::NonPeriodic
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
    #[allow(clippy::too_many_arguments)]
    pub(super) fn iterate<B: Backend>(
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
    pub(super) fn advise(&self, e: SolverError) -> SolverError {
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
    pub(super) fn iterate_grid<B: Backend>(
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

    /// The operators of this problem's uniform grids: the Toeplitz
    /// operator of the non-periodic formulation or the periodic cell's
    /// multiplier.
    pub(super) fn uniform_operators(&self) -> Result<UniformOperators> {
        Ok(match self.formulation {
            Formulation::NonPeriodic => UniformOperators::Toeplitz(self.sliding_kernel()?),
            Formulation::Periodic => UniformOperators::Periodic(self.response()?),
        })
    }

    /// A uniform grid (Toeplitz or periodic) on `executor`: the fine
    /// grid's tables prepared once, then one grid or a coarse-to-fine
    /// cascade.
    fn uniform<X: Executes>(
        &self,
        executor: &mut X,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
        let t0 = Instant::now();
        let (nx, ny, cell) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let operators = self.uniform_operators()?;
        executor.prepare(&operators.on(nx, ny, cell)?)?;
        let t_coeff = t0.elapsed().as_secs_f64();
        let (solution, info, t_iter) = if self.cascades(start.as_ref()) {
            self.iterate_cascade(observer, |lx, ly, cell| {
                executor.build(&operators.on(lx, ly, cell)?, None)
            })?
        } else {
            let (mut backend, l00) = executor.build(&operators.on(nx, ny, cell)?, None)?;
            self.iterate_grid(&mut backend, l00, start, observer)?
        };
        Ok(Raw {
            solution,
            info,
            backend: executor.name(),
            mesh: None,
            t_coeff,
            t_setup: Some(0.0),
            t_iter,
            refinement: None,
        })
    }

    /// The adaptive quadtree ([`crate::mesh`]; physics.md section 7) on
    /// `executor`: level tables once (the host's f64 tables, also every
    /// round's certificate; the executor's own, prepared), then
    /// solve-certify-refine rounds. The fields come back on the fine grid.
    fn adaptive<X: Executes>(&self, executor: &mut X, observer: &mut dyn Observer) -> Result<Raw> {
        let t0 = Instant::now();
        let plan = AdaptivePlan::new(self)?;
        let description = OperatorDescription::Levels {
            kernel: &plan.kernel,
            tables: &plan.tables,
        };
        executor.prepare(&description)?;
        let t_coeff = t0.elapsed().as_secs_f64();
        self.adaptive_rounds(&plan, &description, t_coeff, executor, observer)
    }

    /// The solve-certify-refine rounds of [`solve_adaptive`] on the
    /// backends `executor` builds of `description` for each round's mesh
    /// (and takes back after it).
    fn adaptive_rounds<X: Executes>(
        &self,
        plan: &AdaptivePlan,
        description: &OperatorDescription<'_>,
        t_coeff: f64,
        executor: &mut X,
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
        let mut t_iter = 0.0;
        let mut failure: Option<Error> = None;
        let result = solve_adaptive(
            &self.gap_profile(),
            plan.tables.clone(),
            &plan.params,
            self.params.tolerance,
            |mesh, g_mesh, start, tol| {
                let t = Instant::now();
                let (mut backend, _) = executor.build(description, Some(mesh)).map_err(|e| {
                    let msg = e.to_string();
                    failure = Some(e);
                    SolverError::Invalid(msg)
                })?;
                let r = self.iterate(
                    &mut backend,
                    g_mesh.to_vec(),
                    plan.l00,
                    tol,
                    start.cloned(),
                    observer,
                );
                executor.release(backend);
                t_iter += t.elapsed().as_secs_f64();
                r
            },
        );
        let result = match (result, failure) {
            (Ok(r), _) => r,
            (Err(_), Some(e)) => return Err(e),
            (Err(AdaptiveError::Solver(SolverError::Cancelled)), None) => {
                return Err(SolverError::Cancelled.into())
            }
            (Err(e), None) => return Err(invalid(e.to_string())),
        };
        Ok(Raw {
            solution: result.solution,
            info: result.info,
            backend: format!("{} (adaptive mesh)", executor.name()),
            mesh: Some(result.report),
            t_coeff,
            t_setup: None,
            t_iter,
            refinement: None,
        })
    }

    /// Friction by both routes, contact statistics and timings of any path
    /// (solved in `precision`); a finite pad's own friction on `executor`
    /// (in its precision, as the rough solve).
    fn finish<X: Executes>(
        &self,
        raw: Raw,
        t0: Instant,
        executor: &mut X,
        precision: Precision,
    ) -> Result<Solution> {
        let t2 = Instant::now();
        let (mu, mu_d, stats) = self.friction_and_stats(&raw.solution)?;
        let unknowns = raw
            .mesh
            .as_ref()
            .map_or(self.surface.nx * self.surface.ny, |m| m.unknowns);
        let mut warnings = self.warnings(&stats, mu, mu_d);
        // A finite pad's own part of the friction (the same pad, flat): on
        // the uniform grid of the non-periodic formulation.
        let smooth_pad = if self.formulation == Formulation::NonPeriodic
            && raw.mesh.is_none()
            && stats.normal_load > 0.0
        {
            match self.smooth_pad(executor, stats.normal_load, mu, raw.info.matvecs) {
                Ok(pad) => Some(pad),
                Err(e) => {
                    warnings.push(format!("the finite pad's own friction (the same pad without roughness) was not computed: {e}"));
                    None
                }
            }
        } else {
            None
        };
        if let Some(pad) = &smooth_pad {
            if pad.share.abs() > SMOOTH_PAD_SHARE_LIMIT {
                warnings.push(format!(
                    "{:.0} % of the friction is the finite pad's own: the same pad without roughness gives mu = {:.4e} at this load and speed (its rim's hysteresis), the roughness part is {:.4e}; a rubber block on a large rough plate has no such rim: compare the roughness part (smooth_pad in summary.json) with experiments and Persson, or use formulation = \"periodic\" or a larger pad",
                    100.0 * pad.share,
                    pad.friction_coefficient,
                    pad.roughness_friction_coefficient
                ));
            }
        }
        let t_an = t2.elapsed().as_secs_f64();
        let total = t0.elapsed().as_secs_f64();
        let timings = Timings {
            coefficients_s: raw.t_coeff,
            operator_setup_s: raw
                .t_setup
                .unwrap_or(total - raw.t_coeff - raw.t_iter - t_an),
            iteration_s: raw.t_iter,
            analysis_s: t_an,
            total_s: total,
        };
        let mut solution = Solution::new(
            self,
            raw.solution,
            raw.info,
            stats,
            (mu, mu_d),
            raw.backend,
            timings,
            unknowns,
            raw.mesh,
            warnings,
        );
        solution.record_precision(precision);
        solution.gpu_refinement = raw.refinement;
        solution.smooth_pad = smooth_pad;
        Ok(solution)
    }
}

/// What a uniform grid's operator description is made of.
pub(super) enum UniformOperators {
    /// The non-periodic formulation's kernel (its coefficient tables).
    Toeplitz(SlidingKernel),
    /// The periodic cell's response (its multiplier).
    Periodic(SlidingResponse),
}

impl UniformOperators {
    /// The description of the `nx x ny` grid of cells `cell` \[m\].
    pub(super) fn on(
        &self,
        nx: usize,
        ny: usize,
        cell: (f64, f64),
    ) -> Result<OperatorDescription<'_>> {
        let grid = Grid::new(nx, ny, cell)?;
        Ok(match self {
            Self::Toeplitz(kernel) => OperatorDescription::Toeplitz { kernel, grid },
            Self::Periodic(response) => OperatorDescription::Periodic {
                response,
                grid: grid.periodic(),
            },
        })
    }
}

/// What both adaptive executors share: the kernel, the level tables of the
/// fine grid (also the certificate's), the self coefficient and the mesh
/// controls clamped to the grid.
struct AdaptivePlan {
    kernel: SlidingKernel,
    tables: Arc<LevelTables>,
    l00: f64,
    params: AdaptiveParams,
}

impl AdaptivePlan {
    fn new(problem: &Problem) -> Result<Self> {
        problem.check_adaptive_cells()?;
        let (nx, ny, a) = (
            problem.surface.nx,
            problem.surface.ny,
            problem.surface.cell_size,
        );
        let kernel = problem.sliding_kernel()?;
        let max_level = problem.adaptive.max_level.min(max_level_for(nx, ny));
        let tables = Arc::new(LevelTables::new(&kernel, nx, ny, a, max_level)?);
        let l00 = tables.coefficient(0, 0, 0);
        let params = AdaptiveParams {
            max_level,
            ..problem.adaptive
        };
        Ok(Self {
            kernel,
            tables,
            l00,
            params,
        })
    }
}

/// Coarsest useful level: blocks no larger than the grid.
fn max_level_for(nx: usize, ny: usize) -> u8 {
    let m = nx.min(ny).max(1);
    (usize::BITS - 1 - m.leading_zeros()) as u8
}
