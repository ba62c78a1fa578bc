//! The uniform grid's route through a solve on any executor: the
//! non-periodic formulation's Toeplitz operator (paper Eq. 6-7) or the
//! periodic cell's multiplier (paper Appendix, Eq. A1-A2), described once
//! per grid and solved on one grid or as a coarse-to-fine cascade.

use std::time::Instant;

use crate::config::Formulation;
use crate::error::Result;
use crate::kernel::SlidingKernel;
use crate::operator::OperatorDescription;
use crate::response::{Grid, SlidingResponse};
use crate::solver::{Observer, WarmStart};

use super::super::executor::Executes;
use super::super::Problem;
use super::Raw;

impl Problem {
    /// The operators of this problem's uniform grids: the Toeplitz
    /// operator of the non-periodic formulation or the periodic cell's
    /// multiplier.
    pub(in crate::problem) fn uniform_operators(&self) -> Result<UniformOperators> {
        Ok(match self.formulation {
            Formulation::NonPeriodic => UniformOperators::Toeplitz(self.sliding_kernel()?),
            Formulation::Periodic => UniformOperators::Periodic(self.response()?),
        })
    }

    /// A uniform grid (Toeplitz or periodic) on `executor`: the fine
    /// grid's tables prepared once, then one grid or a coarse-to-fine
    /// cascade.
    pub(super) fn uniform<X: Executes>(
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
        // The operators' set-up (every grid's backend: its tables beyond
        // the prepared fine one, transforms, preconditioner, device
        // buffers), timed apart from the iteration it is built within.
        let mut t_setup = 0.0;
        let mut build = |lx: usize, ly: usize, cell: (f64, f64)| {
            let t = Instant::now();
            let built = executor.build(&operators.on(lx, ly, cell)?, None);
            t_setup += t.elapsed().as_secs_f64();
            built
        };
        let (solution, info, t_iter) = if self.cascades(start.as_ref()) {
            // The cascade's time holds its levels' builds.
            let (solution, info, t) = self.iterate_cascade(observer, &mut build)?;
            (solution, info, (t - t_setup).max(0.0))
        } else {
            let (mut backend, l00) = build(nx, ny, cell)?;
            self.iterate_grid(&mut backend, l00, start, observer)?
        };
        Ok(Raw {
            solution,
            info,
            backend: executor.name(),
            mesh: None,
            t_coeff,
            t_setup: Some(t_setup),
            t_iter,
        })
    }
}

/// What a uniform grid's operator description is made of.
pub(in crate::problem) enum UniformOperators {
    /// The non-periodic formulation's kernel (its coefficient tables).
    Toeplitz(SlidingKernel),
    /// The periodic cell's response (its multiplier).
    Periodic(SlidingResponse),
}

impl UniformOperators {
    /// The description of the `nx x ny` grid of cells `cell` \[m\].
    pub(in crate::problem) fn on(
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
