//! The stencil route (paper Eq. 9): `F_T = int p (e_v . grad u) dA`,
//! evaluated exactly for the piecewise-constant traction with the
//! cell-averaged derivative coefficients `D`: `F_T = a^2 sum_i p_i (D p)_i`.
//! On a non-periodic grid `D` is the derivative table of [`crate::kernel`],
//! whose elastic (`1/E_inf`) part is antisymmetric, so it contributes
//! exactly nothing; on a periodic cell it is the spectral slope
//! [`crate::operator::SpectralPeriodic`] with [`crate::operator::PeriodicResponse::SlidingSlope`].

use crate::operator::{GridOperator, GridWork};

/// `F_T = a_x a_y p . (D p)` \[N\] with `D` the cell-averaged derivative
/// operator along the sliding direction, on cells of area
/// `cell_area = a_x a_y` \[m^2\]. Only the loaded cells
/// contribute, so `D p` is evaluated on them alone
/// ([`GridOperator::apply_set`]: no grid-size vector beside the pressure
/// for the FFT operators); the sum is that over every cell, bit for bit.
pub fn friction_force_stencil(
    derivative: &mut dyn GridOperator,
    pressure: &[f64],
    cell_area: f64,
) -> f64 {
    let cells: Vec<usize> = (0..pressure.len())
        .filter(|&i| pressure[i] != 0.0)
        .collect();
    let loads: Vec<f64> = cells.iter().map(|&i| pressure[i]).collect();
    let mut dp = vec![0.0; cells.len()];
    derivative.apply_set(&cells, &loads, &mut dp, &mut GridWork::default());
    cell_area * loads.iter().zip(&dp).map(|(p, d)| p * d).sum::<f64>()
}
