//! The stencil route (paper Eq. 9): `F_T = int p (e_v . grad u) dA`,
//! evaluated exactly for the piecewise-constant traction with the
//! cell-averaged derivative coefficients `D`: `F_T = a^2 sum_i p_i (D p)_i`.
//! On a non-periodic grid `D` is the derivative table of [`crate::kernel`],
//! whose elastic (`1/E_inf`) part is antisymmetric, so it contributes
//! exactly nothing; on a periodic cell it is the spectral slope
//! [`crate::operator::SpectralPeriodic::sliding_slope`].

use crate::operator::GridOperator;

/// `F_T = a^2 p . (D p)` \[N\] with `D` the cell-averaged derivative operator
/// along the sliding direction.
pub fn friction_force_stencil(derivative: &mut dyn GridOperator, pressure: &[f64], a: f64) -> f64 {
    friction_force_stencil_area(derivative, pressure, a * a)
}

/// [`friction_force_stencil`] on cells of area `cell_area = a_x a_y`
/// \[m^2\] (rectangular cells): `F_T = a_x a_y p . (D p)`.
pub fn friction_force_stencil_area(
    derivative: &mut dyn GridOperator,
    pressure: &[f64],
    cell_area: f64,
) -> f64 {
    let mut dp = vec![0.0; pressure.len()];
    derivative.apply(pressure, &mut dp);
    cell_area * pressure.iter().zip(&dp).map(|(p, d)| p * d).sum::<f64>()
}
