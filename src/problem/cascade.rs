//! The coarse-to-fine cascade of the uniform paths (CPU and GPU, Toeplitz
//! and periodic): the problem's gap
//! restricted to grids halved down to [`CASCADE_COARSEST`] cells a side, each
//! solved from the coarser one ([`solver::solve_cascade`]).

use std::time::Instant;

use crate::backend::Backend;
use crate::error::Result;
use crate::solver::{self, ContactSolution, Control, Observer, SolveInfo, WarmStart};

use super::Problem;

/// Grids of the coarse-to-fine cascade: the fine grid halved while even,
/// down to this many cells a side at least.
pub(super) const CASCADE_COARSEST: usize = 64;

/// Grids of the cascade at most by default, the fine one included
/// (`[solver] cascade_levels`).
pub(super) const DEFAULT_CASCADE_LEVELS: usize = 8;

impl Problem {
    /// Whether a solve without an outside start runs as a coarse-to-fine
    /// cascade (uniform grids, `cascade_levels > 1`, a grid side that
    /// halves at least once to 64 cells or more). An outside start (a
    /// neighbouring speed, or a coarser grid's solution prolonged with
    /// [`WarmStart::prolonged`]) replaces the coarse grids.
    pub(super) fn cascades(&self, start: Option<&WarmStart>) -> bool {
        let (nx, ny) = (self.surface.nx, self.surface.ny);
        start.is_none()
            && solver::cascade::cascade_shapes(nx, ny, CASCADE_COARSEST, self.cascade_levels).len()
                > 1
    }

    /// The constrained iteration as a coarse-to-fine cascade
    /// ([`solver::solve_cascade`]) on backends built by
    /// `build(nx, ny, (a_x, a_y))` (the backend and its self coefficient;
    /// both sides halve together, so every level keeps the fine grid's cell
    /// aspect ratio);
    /// the coarse grids' gap profiles are the fine one's 2 x 2 block means
    /// (any surface, files included, and no band limit to meet). Returns
    /// the solution, its report (fine-grid-equivalent matvecs) and the
    /// iteration's wall time \[s\], the coarse grids' set-up included.
    pub(super) fn iterate_cascade<B, F>(
        &self,
        observer: &mut dyn Observer,
        build: F,
    ) -> Result<(ContactSolution, SolveInfo, f64)>
    where
        B: Backend,
        F: FnMut(usize, usize, (f64, f64)) -> Result<(B, f64)>,
    {
        let (nx, ny) = (self.surface.nx, self.surface.ny);
        let t = Instant::now();
        let shapes = solver::cascade::cascade_shapes(nx, ny, CASCADE_COARSEST, self.cascade_levels);
        let (solution, info) = cascade_of(
            &shapes,
            self.surface.cell(),
            self.gap_profile(),
            self.control,
            &self.solver_params(),
            observer,
            build,
        )?
        .map_err(|e| self.advise(e))?;
        Ok((solution, info, t.elapsed().as_secs_f64()))
    }
}

/// The constrained iteration of the fine gap `gap` on the grids `shapes`
/// (the last the fine one, of cells `(a_x, a_y)`) as a coarse-to-fine
/// cascade ([`solver::solve_cascade`]) on backends built by
/// `build(nx, ny, (a_x, a_y))`; the coarse grids' gaps are the fine one's
/// 2 x 2 block means. A level that cannot be built (e.g. a device error)
/// is the outer error, its own; the iteration's outcome is the inner
/// result.
pub(super) fn cascade_of<B, F>(
    shapes: &[(usize, usize)],
    (ax, ay): (f64, f64),
    gap: Vec<f64>,
    control: Control,
    params: &solver::SolverParams,
    observer: &mut dyn Observer,
    mut build: F,
) -> Result<std::result::Result<(ContactSolution, SolveInfo), solver::SolverError>>
where
    B: Backend,
    F: FnMut(usize, usize, (f64, f64)) -> Result<(B, f64)>,
{
    let &(nx, ny) = shapes.last().expect("the fine grid");
    let mut gaps = vec![gap];
    for w in shapes.windows(2).rev() {
        let (fx, fy) = w[1];
        let coarse = solver::cascade::restrict_mean(gaps.last().expect("fine gap"), fx, fy);
        gaps.push(coarse);
    }
    gaps.reverse();
    let mut failure = None;
    let result = solver::solve_cascade(
        shapes,
        |k, (lx, ly)| {
            let cell = (ax * (nx / lx) as f64, ay * (ny / ly) as f64);
            let (backend, l00) = build(lx, ly, cell).map_err(|e| {
                let message = format!("the {lx} x {ly} grid of the cascade: {e}");
                failure = Some(e);
                solver::SolverError::Invalid(message)
            })?;
            Ok(solver::CascadeLevel {
                backend,
                gap: std::mem::take(&mut gaps[k]),
                cell_area: cell.0 * cell.1,
                self_coefficient: l00,
            })
        },
        control,
        params,
        None,
        observer,
    );
    match (result, failure) {
        (Err(_), Some(e)) => Err(e),
        (result, _) => Ok(result),
    }
}
