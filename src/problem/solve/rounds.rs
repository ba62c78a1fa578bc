//! The adaptive mesh's route through a solve on any executor
//! ([`crate::mesh`]; physics.md section 7): the level tables described
//! once, then the solve-certify-refine rounds of
//! [`super::super::adaptive`], each round's backend built by the executor.

use std::sync::Arc;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::kernel::SlidingKernel;
use crate::operator::{LevelTables, OperatorDescription};
use crate::solver::{Observer, SolverError};

use super::super::adaptive::{solve_adaptive, AdaptiveError, AdaptiveParams};
use super::super::executor::Executes;
use super::super::{invalid, Problem};
use super::Raw;

impl Problem {
    /// The adaptive quadtree ([`crate::mesh`]; physics.md section 7) on
    /// `executor`: level tables once (the host's f64 tables, also every
    /// round's certificate; the executor's own, prepared), then
    /// solve-certify-refine rounds. The fields come back on the fine grid.
    pub(super) fn adaptive<X: Executes>(
        &self,
        executor: &mut X,
        observer: &mut dyn Observer,
    ) -> Result<Raw> {
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
