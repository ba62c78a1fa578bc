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
        let stats = self.contact_stats(solution);
        let (mu, mu_d, _) = self.friction_with(solution, &stats, None)?;
        Ok((mu, mu_d, stats))
    }

    /// The contact statistics of `solution` on this problem's grid.
    pub(super) fn contact_stats(&self, solution: &ContactSolution) -> ContactStatistics {
        let (nx, ny, cell) = (self.surface.nx, self.surface.ny, self.surface.cell());
        analysis::contact_statistics(&solution.pressure, &solution.contact, nx, ny, cell)
    }

    /// The two friction coefficients of [`Self::friction_and_stats`] from
    /// the solution's statistics `stats` ([`Self::contact_stats`]), and for
    /// the non-periodic formulation the Eq. 9 friction force \[N\] of a
    /// second pressure `other` on the same grid (the finite pad's flat
    /// twin) from the same derivative operators, built once for both.
    pub(super) fn friction_with(
        &self,
        solution: &ContactSolution,
        stats: &ContactStatistics,
        other: Option<&[f64]>,
    ) -> Result<(f64, f64, Option<f64>)> {
        let (ax, ay) = self.surface.cell();
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
            return Ok((-force / load, -force_d / load, None));
        }
        if load.is_nan() || load <= 0.0 {
            return Err(invalid(
                "the solution carries no load: the surfaces do not touch",
            ));
        }
        let kernel = SlidingKernel::new(&response)?;
        let mut pressures = vec![solution.pressure.as_slice()];
        pressures.extend(other);
        let forces = self.friction_forces_eq9(&kernel, &pressures)?;
        let force = forces[0];
        let force_d = if self.layer.is_some() && kernel.is_thin_law(ax, ay) {
            analysis::friction::friction_force_dissipation_thin_law(
                &solution.pressure,
                &grid,
                &response,
            )
        } else {
            analysis::friction_force_dissipation(&solution.pressure, &grid, &response)
        };
        Ok((-force / load, -force_d / load, forces.get(1).copied()))
    }

    /// The friction force \[N\] of each pressure of `pressures` on this
    /// non-periodic grid by the work of the contact pressure (paper Eq. 9):
    /// the cell-averaged derivative tables along the sliding direction,
    /// each table and its transform built once for all of them.
    fn friction_forces_eq9(
        &self,
        kernel: &SlidingKernel,
        pressures: &[&[f64]],
    ) -> Result<Vec<f64>> {
        let grid = self.grid()?;
        let (nx, ny) = grid.size();
        let (ex, ey) = kernel.response().direction();
        let mut forces = vec![0.0; pressures.len()];
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
            for (force, pressure) in forces.iter_mut().zip(pressures) {
                *force += w * analysis::friction_force_stencil(&mut op, pressure, grid.cell_area());
            }
        }
        Ok(forces)
    }
}
