//! The one path through a solve: the operator is chosen by formulation x
//! mesh ([`Discretisation`]), the executor by backend ([`Executor`]), and
//! every path runs the constrained iteration through one function
//! (`Problem::iterate`, the only caller of the solver); the
//! friction by both routes, the contact statistics and the timings are then
//! computed once for all paths.
//!
//! Over 600 lines while it holds the {uniform, periodic, adaptive} x {CPU, GPU} paths, until they become one operator description each executor turns into a backend.

use std::sync::Arc;
use std::time::Instant;

use crate::backend::gpu::engine::Engine;
use crate::backend::gpu::{coefficients, GpuBackend, GpuContext, GpuLevelTables, GpuOptions};
use crate::backend::{Backend, CpuBackend};
use crate::config::{Formulation, MeshKind, Precision};
use crate::error::{Error, Result};
use crate::kernel::SlidingKernel;
use crate::operator::{
    AdaptiveOperator, LevelTables, OffsetTable, PeriodicResponse, Real, SpectralPeriodic,
};
use crate::response::Grid;
use crate::solver::{self, ContactSolution, Observer, SolveInfo, SolverError, WarmStart};

use super::adaptive::{solve_adaptive, AdaptiveError, AdaptiveParams, MeshReport};
use super::executor::toeplitz_backend;
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
        let raw = match (kind, executor) {
            (Discretisation::Periodic, Executor::Cpu) => self.periodic_cpu(start, observer)?,
            (Discretisation::Periodic, Executor::Gpu(_)) => {
                return Err(invalid(
                    "the GPU path solves the non-periodic formulation; use --backend cpu for formulation = \"periodic\"",
                ))
            }
            (Discretisation::Uniform, Executor::Cpu) => self.uniform_cpu(start, observer)?,
            (Discretisation::Uniform, Executor::Gpu(ctx)) => {
                self.uniform_gpu(ctx.clone(), start, observer)?
            }
            (Discretisation::Adaptive, Executor::Cpu) => self.adaptive_cpu(observer)?,
            (Discretisation::Adaptive, Executor::Gpu(ctx)) => {
                self.adaptive_gpu(ctx.clone(), observer)?
            }
        };
        self.finish(raw, t0)
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

    /// Uniform grid on the CPU in the precision of `[solver] precision`.
    fn uniform_cpu(&self, start: Option<WarmStart>, observer: &mut dyn Observer) -> Result<Raw> {
        match self.params.precision {
            Precision::F64 => self.uniform_cpu_in::<f64>(start, observer),
            Precision::Mixed => self.uniform_cpu_in::<f32>(start, observer),
        }
    }

    /// Uniform grid on the CPU: the host coefficient table, Toeplitz-FFT
    /// with its spectra and transforms in `T` (f32: with f64 products for
    /// the refinement, [`Backend::refines`]).
    fn uniform_cpu_in<T: Real>(
        &self,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
        let t0 = Instant::now();
        let (nx, ny, cell) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let kernel = self.sliding_kernel()?;
        let table = kernel.table(&self.grid()?)?;
        let t_coeff = t0.elapsed().as_secs_f64();
        let mut fine = Some(table);
        // The fine grid's table is computed once; coarse grids' on demand.
        let mut build = |nx: usize, ny: usize, cell: (f64, f64)| {
            let table = match fine.take() {
                Some(t) if t.nx == nx && t.ny == ny => t,
                _ => kernel.table(&Grid::new(nx, ny, cell)?)?,
            };
            Ok(toeplitz_backend::<T>(nx, ny, &table.values))
        };
        let (solution, info, t_iter) = if self.cascades(start.as_ref()) {
            self.iterate_cascade(observer, build)?
        } else {
            let (mut backend, l00) = build(nx, ny, cell)?;
            self.iterate_grid(&mut backend, l00, start, observer)?
        };
        let t_setup = 0.0;
        Ok(Raw {
            solution,
            info,
            backend: "cpu".into(),
            mesh: None,
            t_coeff,
            t_setup: Some(t_setup),
            t_iter,
            refinement: None,
        })
    }

    /// Uniform grid on the GPU (f32 on the device): the coefficient table
    /// of a half-space computed on the device (`shaders/coefficients.wgsl`,
    /// about 4e-7 relative to the host table; a finite layer's table on the
    /// host), its spectrum on the host in f64; then, unless
    /// `gpu_refine = false`, the f64 refinement on the host from the
    /// device's answer ([`super::gpu_refine`]).
    fn uniform_gpu(
        &self,
        ctx: GpuContext,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
        let t0 = Instant::now();
        let (nx, ny, cell) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let kernel = self.sliding_kernel()?;
        // The coefficient table of an nx x ny grid: a half-space's on the
        // device, a finite layer's on the host.
        let table_of = |engine: &mut Engine, nx: usize, ny: usize, cell: (f64, f64)| {
            let grid = Grid::new(nx, ny, cell)?;
            Ok::<_, Error>(match self.layer {
                None => coefficients::coefficient_table(engine, kernel.response(), &grid)?,
                Some(_) => kernel.table(&grid)?.values,
            })
        };
        let mut engine = Engine::new(ctx.clone());
        let table = table_of(&mut engine, nx, ny, cell)?;
        let t_coeff = t0.elapsed().as_secs_f64();
        let self_coefficient = |table: &[f64], nx: usize, ny: usize| {
            OffsetTable {
                nx,
                ny,
                values: table,
            }
            .get(0, 0)
        };
        // As `Backend::name` of the GPU backend.
        let name = format!("gpu: {}", ctx.adapter);
        let mut fine = Some((engine, table));
        // The fine grid's engine and table are made once; the coarse grids'
        // on demand, each level on an engine of its own.
        let mut build = |lx: usize, ly: usize, cell: (f64, f64)| -> Result<(GpuBackend, f64)> {
            let (engine, table) = match fine.take() {
                Some((engine, table)) if (lx, ly) == (nx, ny) => (engine, table),
                other => {
                    fine = other;
                    let mut engine = Engine::new(ctx.clone());
                    let table = table_of(&mut engine, lx, ly, cell)?;
                    (engine, table)
                }
            };
            let l00 = self_coefficient(&table, lx, ly);
            let options = GpuOptions {
                preconditioner: self.params.precondition,
                ..GpuOptions::default()
            };
            let backend = GpuBackend::with_engine(engine, lx, ly, &table, options)?;
            Ok((backend, l00))
        };
        let t_setup = t0.elapsed().as_secs_f64() - t_coeff;
        let device = if self.cascades(start.as_ref()) {
            self.iterate_cascade(observer, build)?
        } else {
            let (mut backend, l00) = build(nx, ny, cell)?;
            self.iterate_grid(&mut backend, l00, start, observer)?
        };
        // The f64 refinement on the host (physics.md section 13), unless
        // the device's f32 answer was asked for.
        let (solution, info, t_iter, refinement) = if self.gpu_refine {
            let (s, i, t, r) = self.refine_on_host(device, observer)?;
            (s, i, t, Some(r))
        } else {
            let (s, i, t) = device;
            (s, i, t, None)
        };
        let backend = match refinement {
            Some(_) => format!("{name}, refined in f64 on the host"),
            None => name,
        };
        Ok(Raw {
            solution,
            info,
            backend,
            mesh: None,
            t_coeff,
            t_setup: Some(t_setup),
            t_iter,
            refinement,
        })
    }

    /// A periodic cell solved spectrally (paper Appendix, Eq. A1-A2) on the
    /// CPU: the same iteration on the [`SpectralPeriodic`] operator.
    fn periodic_cpu(&self, start: Option<WarmStart>, observer: &mut dyn Observer) -> Result<Raw> {
        match self.params.precision {
            Precision::F64 => self.periodic_cpu_in::<f64>(start, observer),
            Precision::Mixed => self.periodic_cpu_in::<f32>(start, observer),
        }
    }

    /// [`Problem::periodic_cpu`] with the multiplier and transforms in `T`.
    fn periodic_cpu_in<T: Real>(
        &self,
        start: Option<WarmStart>,
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
        let t0 = Instant::now();
        let (nx, ny, cell) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let response = self.response()?;
        let build = |nx, ny, cell| {
            let grid = Grid::new(nx, ny, cell)?.periodic();
            let op = SpectralPeriodic::<T>::in_precision(
                &grid,
                &response,
                PeriodicResponse::Displacement,
            )
            .with_preconditioner()
            .with_exact();
            let l00 = op.self_coefficient();
            Ok((CpuBackend::new(op), l00))
        };
        let t_setup = t0.elapsed().as_secs_f64();
        let (solution, info, t_iter) = if self.cascades(start.as_ref()) {
            self.iterate_cascade(observer, build)?
        } else {
            let (mut backend, l00) = build(nx, ny, cell)?;
            self.iterate_grid(&mut backend, l00, start, observer)?
        };
        Ok(Raw {
            solution,
            info,
            backend: "cpu".into(),
            mesh: None,
            t_coeff: 0.0,
            t_setup: Some(t_setup),
            t_iter,
            refinement: None,
        })
    }

    /// The adaptive quadtree ([`crate::mesh`]; physics.md section 7) with the
    /// pairwise CPU operator: level tables once, then solve-certify-refine
    /// rounds. The fields come back on the fine grid.
    fn adaptive_cpu(&self, observer: &mut dyn Observer) -> Result<Raw> {
        let t0 = Instant::now();
        let plan = AdaptivePlan::new(self)?;
        let t_coeff = t0.elapsed().as_secs_f64();
        let raw = self.adaptive_rounds(
            &plan,
            t_coeff,
            |mesh| {
                Ok(CpuBackend::new(AdaptiveOperator::new(
                    plan.tables.clone(),
                    mesh,
                )))
            },
            drop,
            observer,
        )?;
        // The uniform CPU path reports "cpu" too, without the thread count.
        Ok(Raw {
            backend: "cpu (adaptive mesh)".into(),
            ..raw
        })
    }

    /// The adaptive mesh on the GPU: the level tables computed on the device
    /// once (`shaders/level_table.wgsl`, `shaders/level_box_sum.wgsl`, f32)
    /// and each round's iteration there with the pairwise operator that
    /// reads them (`shaders/level_matvec.wgsl`); each round's certificate
    /// uses the host's f64 level tables. Half-spaces only.
    fn adaptive_gpu(&self, ctx: GpuContext, observer: &mut dyn Observer) -> Result<Raw> {
        if self.layer.is_some() {
            return Err(invalid(
                "the GPU adaptive operator covers half-spaces only; use --backend cpu with [layer]",
            ));
        }
        let t0 = Instant::now();
        let plan = AdaptivePlan::new(self)?;
        let mut eng = Engine::new(ctx);
        let (nx, ny) = plan.tables.shape();
        let tables = GpuLevelTables::new(
            &mut eng,
            plan.kernel.response(),
            nx,
            ny,
            plan.tables.cell_size(),
            plan.tables.max_level(),
        )?;
        let t_coeff = t0.elapsed().as_secs_f64();
        // The device's engine goes into each round's backend and back.
        let engine = std::cell::RefCell::new(Some(eng));
        self.adaptive_rounds(
            &plan,
            t_coeff,
            |mesh| {
                let eng = engine
                    .borrow_mut()
                    .take()
                    .expect("engine returned after each round");
                Ok(GpuBackend::with_level_tables(eng, &tables, mesh)?)
            },
            |backend: GpuBackend| *engine.borrow_mut() = Some(backend.into_engine()),
            observer,
        )
    }

    /// The solve-certify-refine rounds of [`solve_adaptive`] on backends made
    /// by `backend_for` for each round's mesh (and handed to `give_back`
    /// after it): the one adaptive path of both executors.
    fn adaptive_rounds<B: Backend>(
        &self,
        plan: &AdaptivePlan,
        t_coeff: f64,
        mut backend_for: impl FnMut(&crate::mesh::QuadMesh) -> Result<B>,
        mut give_back: impl FnMut(B),
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
        let mut name = String::new();
        let mut t_iter = 0.0;
        let mut failure: Option<Error> = None;
        let result = solve_adaptive(
            &self.gap_profile(),
            plan.tables.clone(),
            &plan.params,
            self.params.tolerance,
            |mesh, g_mesh, start, tol| {
                let t = Instant::now();
                let mut backend = backend_for(mesh).map_err(|e| {
                    let msg = e.to_string();
                    failure = Some(e);
                    SolverError::Invalid(msg)
                })?;
                name = backend.name();
                let r = self.iterate(
                    &mut backend,
                    g_mesh.to_vec(),
                    plan.l00,
                    tol,
                    start.cloned(),
                    observer,
                );
                give_back(backend);
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
            backend: format!("{name} (adaptive mesh)"),
            mesh: Some(result.report),
            t_coeff,
            t_setup: None,
            t_iter,
            refinement: None,
        })
    }

    /// Friction by both routes, contact statistics and timings of any path.
    fn finish(&self, raw: Raw, t0: Instant) -> Result<Solution> {
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
            match self.smooth_pad(stats.normal_load, mu, raw.info.matvecs) {
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
        solution.gpu_refinement = raw.refinement;
        solution.smooth_pad = smooth_pad;
        Ok(solution)
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
