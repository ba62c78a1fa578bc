//! The surface work flux (physics.md sections 5 and 14): the power the
//! contact pressure puts into the solid per unit area, `q_s = -v p (e_v .
//! grad w)` \[W/m^2\] (in the indenter's frame a material point moves with
//! `-v e_v`, so `dw/dt = -v e_v . grad w`; `w` into the solid). The slope
//! is the friction stencil's own (paper Eq. 9): the cell-averaged
//! derivative tables on a pad, the spectral slope on a periodic cell, so
//! that `a_x a_y sum q_s = -F_T v = mu F_N v` with the stencil route's
//! `mu`, to round-off. Locally `q_s` may be negative (the surface rises
//! back where it leaves the contact); only its total is the dissipation.

use super::super::error::HeatError;
use crate::kernel::{Axis, SlidingKernel};
use crate::operator::{GridOperator, OffsetTable, PeriodicResponse, SpectralPeriodic, ToeplitzFft};
use crate::response::{Grid, SlidingResponse};

/// `e_v . grad w` at every cell of `grid` for the cell pressures
/// `pressure` \[Pa\].
fn sliding_slope(
    pressure: &[f64],
    grid: &Grid,
    response: &SlidingResponse,
) -> Result<Vec<f64>, HeatError> {
    let n = grid.cells();
    let mut slope = vec![0.0; n];
    if grid.is_periodic() {
        SpectralPeriodic::new(grid, response, PeriodicResponse::SlidingSlope)
            .apply(pressure, &mut slope);
        return Ok(slope);
    }
    let kernel = SlidingKernel::new(response).map_err(|e| HeatError::Transform(e.to_string()))?;
    let (ex, ey) = response.direction();
    let mut part = vec![0.0; n];
    for (axis, weight) in [(Axis::X, ex), (Axis::Y, ey)] {
        if weight == 0.0 {
            continue;
        }
        let table = kernel
            .derivative_table(grid, axis)
            .map_err(|e| HeatError::Transform(e.to_string()))?;
        ToeplitzFft::new(OffsetTable {
            nx: grid.nx(),
            ny: grid.ny(),
            values: &table.values,
        })
        .apply(pressure, &mut part);
        slope
            .iter_mut()
            .zip(&part)
            .for_each(|(s, d)| *s += weight * d);
    }
    Ok(slope)
}

/// `q_s = -v p (e_v . grad w)` \[W/m^2\] at every cell.
pub(crate) fn surface_work_flux(
    pressure: &[f64],
    grid: &Grid,
    response: &SlidingResponse,
) -> Result<Vec<f64>, HeatError> {
    let v = response.speed();
    let slope = sliding_slope(pressure, grid, response)?;
    Ok(pressure
        .iter()
        .zip(&slope)
        .map(|(p, s)| if *p == 0.0 { 0.0 } else { -v * p * s })
        .collect())
}
