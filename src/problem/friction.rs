//! Friction of a solved problem by both routes (paper Eq. 9 and the
//! dissipated power of Appendix A3-A4) and its contact statistics, for every
//! discretisation.

use crate::analysis::{self, ContactStatistics};
use crate::config::Formulation;
use crate::error::Result;
use crate::kernel::{Axis, SlidingKernel};
use crate::operator::{OffsetTable, PeriodicResponse, SpectralPeriodic, ToeplitzFft};
use crate::solver::ContactSolution;

use super::{invalid, Problem};

impl Problem {
    /// `mu = -F_T / F_N` by the exact-work stencil (paper Eq. 9) and by the
    /// dissipated power (Appendix A3-A4), and the contact statistics. The
    /// periodic formulation uses the spectral slope and the Fourier
    /// dissipation sum.
    pub fn friction_and_stats(
        &self,
        solution: &ContactSolution,
    ) -> Result<(f64, f64, ContactStatistics)> {
        let (nx, ny, cell) = (self.surface.nx, self.surface.ny, self.surface.cell());
        let (ax, ay) = cell;
        let stats =
            analysis::contact_statistics(&solution.pressure, &solution.contact, nx, ny, cell);
        let load = stats.normal_load;
        let (grid, response) = (self.grid()?, self.response()?);
        if self.formulation == Formulation::Periodic {
            // The slope operator goes before the dissipation route's spectra
            // are made (both are grid-size).
            let force = {
                let mut slope =
                    SpectralPeriodic::new(&grid, &response, PeriodicResponse::SlidingSlope);
                analysis::friction_force_stencil(&mut slope, &solution.pressure, grid.cell_area())
            };
            let force_d = analysis::friction_force_periodic(&solution.pressure, &grid, &response);
            return Ok((-force / load, -force_d / load, stats));
        }
        if load.is_nan() || load <= 0.0 {
            return Err(invalid(
                "the solution carries no load: the surfaces do not touch",
            ));
        }
        let kernel = SlidingKernel::new(&response)?;
        let force = self.friction_force_eq9(&kernel, &solution.pressure)?;
        let force_d = if self.layer.is_some() && kernel.is_thin_law(ax, ay) {
            analysis::friction::friction_force_dissipation_thin_law(
                &solution.pressure,
                &grid,
                &response,
            )
        } else {
            analysis::friction_force_dissipation(&solution.pressure, &grid, &response)
        };
        Ok((-force / load, -force_d / load, stats))
    }

    /// The friction force \[N\] of the pressure `pressure` on this
    /// non-periodic grid by the work of the contact pressure (paper Eq. 9):
    /// the cell-averaged derivative tables along the sliding direction.
    pub(super) fn friction_force_eq9(
        &self,
        kernel: &SlidingKernel,
        pressure: &[f64],
    ) -> Result<f64> {
        let grid = self.grid()?;
        let (nx, ny) = grid.size();
        let (ex, ey) = kernel.response().direction();
        let mut force = 0.0;
        for (axis, w) in [(Axis::X, ex), (Axis::Y, ey)] {
            if w == 0.0 {
                continue;
            }
            let d = kernel.derivative_table(&grid, axis)?;
            let mut op = ToeplitzFft::new(OffsetTable {
                nx,
                ny,
                values: &d.values,
            });
            force += w * analysis::friction_force_stencil(&mut op, pressure, grid.cell_area());
        }
        Ok(force)
    }
}
