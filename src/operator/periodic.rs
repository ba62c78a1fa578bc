//! Periodic (spectral) influence operator: the paper's Appendix (Eq. A1-A2)
//! and physics.md section 6.
//!
//! On a periodic cell of `nx x ny` cells of sides `a_x x a_y`, a pressure mode
//! `exp(i q.x)` produces the displacement mode
//! `u(q) = 2 (1 - nu^2) J*(omega) / |q| p(q)`, where `omega = -q.v` is the
//! frequency the material sees (time factor `exp(+i w t)`, physics.md
//! section 2). With the forward transform `exp(-i q.x)` of rustfft/realfft
//! the multiplier of the discrete mode `(i, j)` is therefore
//! `m(q) = 2 (1 - nu^2) J*(-q.v) / |q|` at the grid wavevector
//! `q = 2 pi (k_i / L_x, k_j / L_y)`, `L_x = nx a_x`, `L_y = ny a_y`, `k`
//! the signed FFT index (rectangular cells: physics.md section 11).
//!
//! On a layer of thickness `h` (physics.md section 3, "Finite thickness")
//! the multiplier is exact: the half-space's times the layer's compliance
//! ratio, `m(q) = S(|q| h) 2 (1 - nu^2) J*(-q.v) / |q|`, for either base
//! ([`crate::response::layer::compliance_ratio`]). Unlike the
//! non-periodic kernel (the paper's Eq. 5, `Theta` times the viscoelastic
//! Green's function), this holds for the sliding viscoelastic layer.
//!
//! The multiplier of every mode is built once, by [`multiplier_half_spectrum`], for
//! the operator and for the Fourier dissipation sum of
//! [`crate::analysis::friction_force_periodic`] alike.
//!
//! Choices (documented because they change results at the grid scale):
//! - The continuous multiplier is sampled at the grid wavevectors (the usual
//!   spectral formulation of Stanley & Kato, J. Tribol. 119, 481, 1997, and
//!   Tamaas): the pressure is treated as band-limited, not as
//!   piecewise-constant cells. The non-periodic [`super::ToeplitzFft`]
//!   integrates over cells instead; the two differ at wavelengths of a few
//!   cells even on a domain much longer than `v tau`.
//! - `q = 0` carries the load but gets multiplier 0: the mean displacement is
//!   absorbed in the rigid approach `delta`, which the solver's bordered
//!   system determines. Displacements therefore have zero mean.
//! - Nyquist modes (`k = n/2` for even `n`) are real grid functions that
//!   sample both `+pi/a` and `-pi/a`; their multiplier is the average over
//!   the signs of the Nyquist components. This keeps the operator real (a
//!   Hermitian multiplier). For the slope operator the average of
//!   `i q_x m(q)` over `+-q_x` is the real `-q_x Im m(q)`: the derivative of
//!   the Nyquist mode itself vanishes (as a spectral derivative must) and
//!   only its dissipative, out-of-phase response is kept.
//!
//! The transforms are [`SpectralEngine`]'s at the grid's own size: plans,
//! the multiplier and all work buffers are built once; `apply` allocates
//! nothing.

use num_complex::Complex64;
use rayon::prelude::*;

use super::fft_convolution::{Product, Real, SpectralEngine};
use super::{GridOperator, GridWork};
use crate::response::{Grid, SlidingResponse};

/// Which field the operator returns for a pressure field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PeriodicResponse {
    /// Normal displacement `u = L p` (multiplier `m(q)`).
    Displacement,
    /// Slope of the displacement along the sliding direction,
    /// `e_v . grad u` (multiplier `i (q.e_v) m(q)`): the derivative
    /// operator of the friction stencil `F_T = a^2 p . (D p)` (paper Eq. 9).
    SlidingSlope,
}

/// Periodic viscoelastic half-space operator applied by real FFTs, the
/// transforms in precision `T` (f64, or f32 for the inner solves of mixed
/// precision).
pub struct SpectralPeriodic<T: Real = f64> {
    engine: SpectralEngine<T>,
    /// Diagonal entry of the operator.
    diagonal: f64,
}

/// Signed FFT index of bin `i` of an `n`-point transform, and whether it is
/// the Nyquist bin.
pub(crate) fn signed_index(i: usize, n: usize) -> (f64, bool) {
    if 2 * i == n {
        (i as f64, true)
    } else if i <= n / 2 {
        (i as f64, false)
    } else {
        (i as f64 - n as f64, false)
    }
}

/// The signs a component of a mode is sampled with: both for a Nyquist
/// bin (its multiplier is averaged over them), one otherwise.
pub(crate) fn nyquist_signs(nyquist: bool) -> &'static [f64] {
    if nyquist {
        &[1.0, -1.0]
    } else {
        &[1.0]
    }
}

/// The discrete multiplier of mode `(i, j)` of `grid`: the continuous
/// multiplier of `response` ([`SlidingResponse::surface_multiplier_with`];
/// for the slope times `i q.e_v`) at the grid wavevector
/// `2 pi (k_i / L_x, k_j / L_y)`, averaged over the signs of Nyquist
/// components (module docs).
pub fn periodic_multiplier(
    response: &SlidingResponse,
    grid: &Grid,
    i: usize,
    j: usize,
    field: PeriodicResponse,
) -> Complex64 {
    let modes = Modes::new(response, grid);
    modes.multiplier(i, j, field, |qv, _| response.compliance_along(qv))
}

/// What the multiplier of every mode of one grid shares: the response and
/// the periodic cell's sides.
struct Modes<'a> {
    response: &'a SlidingResponse,
    nx: usize,
    ny: usize,
    /// `L_x = nx a_x`, `L_y = ny a_y` \[m\].
    length: (f64, f64),
}

impl<'a> Modes<'a> {
    fn new(response: &'a SlidingResponse, grid: &Grid) -> Self {
        Self {
            response,
            nx: grid.nx(),
            ny: grid.ny(),
            length: grid.lengths(),
        }
    }

    /// Whether `q.e_v` depends on the row index `i` alone (sliding exactly
    /// along x, or no sliding): then the compliance of a grid can be
    /// evaluated once per row and sign of `q_x` ([`Self::row_compliances`]).
    fn rows_suffice(&self) -> bool {
        self.response.direction().1 == 0.0 || self.response.speed() == 0.0
    }

    /// `q_x` of row `i` with the sign `s` of a Nyquist alias.
    fn qx(&self, i: usize, s: f64) -> f64 {
        let (kx, _) = signed_index(i, self.nx);
        s * (std::f64::consts::TAU * kx / self.length.0)
    }

    /// The compliance of every row `i` for `q_x` and, on the Nyquist row,
    /// `-q_x`: `[i][0]` and `[i][1]`. Equal, bit for bit, to the compliance
    /// each mode would evaluate: `q.e_v = q_x e_x + q_y e_y` with
    /// `e_y = 0` (or `speed = 0`, where the frequency is zero anyway).
    fn row_compliances(&self) -> Vec<[Complex64; 2]> {
        (0..self.nx)
            .into_par_iter()
            .map(|i| {
                let (_, nyq) = signed_index(i, self.nx);
                let at = |s: f64| {
                    let qv = self.response.along((self.qx(i, s), 0.0));
                    self.response.compliance_along(qv)
                };
                [at(1.0), if nyq { at(-1.0) } else { Complex64::default() }]
            })
            .collect()
    }

    /// The discrete multiplier of mode `(i, j)`: the continuous one at the
    /// grid wavevector, averaged over the signs of its Nyquist components;
    /// `compliance(qv, s)` gives `J*(-q.v)` for `q_x`'s sign index `s`
    /// (0: `+`, 1: `-`).
    fn multiplier(
        &self,
        i: usize,
        j: usize,
        field: PeriodicResponse,
        compliance: impl Fn(f64, usize) -> Complex64,
    ) -> Complex64 {
        let (_, nyq_x) = signed_index(i, self.nx);
        let (ky, nyq_y) = signed_index(j, self.ny);
        let qy = std::f64::consts::TAU * ky / self.length.1;
        let sx = nyquist_signs(nyq_x);
        let sy = nyquist_signs(nyq_y);
        let mut acc = Complex64::default();
        for (si, &s) in sx.iter().enumerate() {
            for &t in sy {
                let q = (self.qx(i, s), t * qy);
                let m = self
                    .response
                    .surface_multiplier_with(q, |qv| compliance(qv, si));
                acc += match field {
                    PeriodicResponse::Displacement => m,
                    PeriodicResponse::SlidingSlope => {
                        Complex64::new(0.0, self.response.along(q)) * m
                    }
                };
            }
        }
        acc / (sx.len() * sy.len()) as f64
    }
}

impl SpectralPeriodic {
    /// The operator of `response` on the periodic `grid` (paper Eq. A2,
    /// physics.md section 6; a layer exact in Fourier space): the
    /// displacement `u = L p`, or for [`PeriodicResponse::SlidingSlope`] the
    /// derivative operator `D p = e_v . grad (L p)` of the friction stencil
    /// (paper Eq. 9 on a periodic cell). Plans the transforms and evaluates
    /// the multiplier once, in f64.
    pub fn new(grid: &Grid, response: &SlidingResponse, field: PeriodicResponse) -> Self {
        Self::in_precision(grid, response, field)
    }
}

impl<T: Real> SpectralPeriodic<T> {
    /// [`SpectralPeriodic::new`] with transforms and multiplier in
    /// precision `T` (the multiplier is evaluated in f64, then rounded; the
    /// diagonal is the f64 one).
    pub fn in_precision(grid: &Grid, response: &SlidingResponse, field: PeriodicResponse) -> Self {
        let (nx, ny) = grid.size();
        let mut engine = SpectralEngine::<T>::new(nx, ny, nx, ny);
        let multiplier_t = multiplier_half_spectrum(response, grid, field);
        // Diagonal: (1/N) sum over all modes.
        let diag: f64 = multiplier_t
            .chunks_exact(nx)
            .enumerate()
            .map(|(j, col)| column_weight(j, ny) * col.iter().map(|m| m.re).sum::<f64>())
            .sum();
        engine.set_multiplier(multiplier_t);
        Self {
            engine,
            diagonal: diag / (nx * ny) as f64,
        }
    }

    /// The diagonal entry `L_00` (displacement of a cell under unit pressure
    /// on itself, mean removed) [m/Pa]: the `self_coefficient` the solver
    /// scales gaps with.
    pub fn self_coefficient(&self) -> f64 {
        self.diagonal
    }

    /// Also provide the stiffness `K ~ L^-1` (multiplier `1 / m(q)`,
    /// `|q| E(-q.v) / (2 (1 - nu^2))`; at `q = 0`, where `L` has none, that
    /// of the longest wave) as the operator's
    /// preconditioner ([`GridOperator::precondition`]): operator
    /// preconditioning of the first-kind equation on the contact set
    /// (Steinbach & Wendland, Adv. Comput. Math. 9, 191, 1998).
    pub fn with_preconditioner(mut self) -> Self {
        self.engine.set_inverse_multiplier(0.0);
        self
    }

    /// Also plan f64 transforms for [`GridOperator::apply_exact`]: the
    /// product with the stored (rounded) multiplier to f64 rounding.
    pub fn with_exact(mut self) -> Self {
        self.engine = self.engine.with_exact();
        self
    }

    /// Bytes held by the multipliers and the spectrum buffer.
    pub fn bytes(&self) -> usize {
        self.engine.bytes()
    }
}

/// The discrete multiplier of every mode of the half spectrum of `grid`
/// (`ny / 2 + 1` columns of `nx` modes, column-major, as the transforms
/// hold them).
pub(crate) fn multiplier_half_spectrum(
    response: &SlidingResponse,
    grid: &Grid,
    field: PeriodicResponse,
) -> Vec<Complex64> {
    let (nx, ny) = grid.size();
    let nyh = ny / 2 + 1;
    let modes = Modes::new(response, grid);
    // The material's compliance (a sum over its creep spectrum) is most of
    // a mode's cost; sliding along x it depends on the row alone.
    let rows = modes.rows_suffice().then(|| modes.row_compliances());
    let mut multiplier_t = vec![Complex64::default(); nyh * nx];
    multiplier_t
        .par_chunks_mut(nx)
        .enumerate()
        .for_each(|(j, col)| {
            for (i, m) in col.iter_mut().enumerate() {
                *m = modes.multiplier(i, j, field, |qv, s| match &rows {
                    Some(rows) => rows[i][s],
                    None => response.compliance_along(qv),
                });
            }
        });
    multiplier_t
}

/// Weight of column `j` of the half spectrum in a sum over all modes: the
/// columns other than DC and Nyquist stand for their Hermitian partners too.
pub(crate) fn column_weight(j: usize, ny: usize) -> f64 {
    if j == 0 || (ny % 2 == 0 && j == ny / 2) {
        1.0
    } else {
        2.0
    }
}

impl<T: Real> GridOperator for SpectralPeriodic<T> {
    fn shape(&self) -> (usize, usize) {
        self.engine.shape()
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.engine.apply(x, y);
    }

    fn apply_exact(&mut self, x: &[f64], y: &mut [f64]) {
        self.engine.apply_exact(x, y);
    }

    fn epsilon(&self) -> f64 {
        T::ROUNDING
    }

    fn apply_set(&mut self, cells: &[usize], x: &[f64], out: &mut [f64], _: &mut GridWork) {
        self.engine.set_product(Product::Working, cells, x, out);
    }

    fn apply_set_exact(&mut self, cells: &[usize], x: &[f64], out: &mut [f64], _: &mut GridWork) {
        self.engine.set_product(Product::Exact, cells, x, out);
    }

    fn precondition_set(&mut self, cells: &[usize], x: &[f64], out: &mut [f64], _: &mut GridWork) {
        self.engine.precondition_set(cells, x, out);
    }

    fn has_preconditioner(&self) -> bool {
        self.engine.has_inverse()
    }

    fn precondition(&mut self, x: &[f64], y: &mut [f64]) {
        self.engine.precondition(x, y);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{CreepSpectrum, Material};

    fn material() -> Material {
        Material::new(
            CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
            0.5,
        )
        .unwrap()
    }

    /// The periodic operator's set products equal its grid products
    /// scattered and gathered, bit for bit, in both precisions (a set with
    /// empty rows; odd and even sizes).
    #[test]
    fn set_products_equal_grid_products() {
        fn check<T: Real>(nx: usize, ny: usize) {
            let response = SlidingResponse::new(&material(), 0.013, 0.4, None).unwrap();
            let grid = Grid::new(nx, ny, (1e-4, 1.5e-4)).unwrap();
            let mut op = SpectralPeriodic::<T>::in_precision(
                &grid,
                &response,
                PeriodicResponse::Displacement,
            )
            .with_preconditioner()
            .with_exact();
            let cells: Vec<usize> = (0..nx * ny)
                .filter(|&c| (c / ny) % 3 != 1 && (c * 7) % 5 != 0)
                .collect();
            let x: Vec<f64> = (0..cells.len())
                .map(|k| ((k * 37 % 11) as f64) - 4.3)
                .collect();
            let mut full = vec![0.0; nx * ny];
            for (&c, &v) in cells.iter().zip(&x) {
                full[c] = v;
            }
            let pick = |g: &[f64]| cells.iter().map(|&c| g[c]).collect::<Vec<f64>>();
            let (mut grid, mut short) = (vec![0.0; nx * ny], vec![0.0; cells.len()]);
            let mut work = GridWork::default();
            op.apply(&full, &mut grid);
            op.apply_set(&cells, &x, &mut short, &mut work);
            assert_eq!(short, pick(&grid), "working product");
            op.apply_exact(&full, &mut grid);
            op.apply_set_exact(&cells, &x, &mut short, &mut work);
            assert_eq!(short, pick(&grid), "exact product");
            op.precondition(&full, &mut grid);
            op.precondition_set(&cells, &x, &mut short, &mut work);
            assert_eq!(short, pick(&grid), "preconditioner");
        }
        for (nx, ny) in [(9, 8), (10, 7)] {
            check::<f64>(nx, ny);
            check::<f32>(nx, ny);
        }
    }

    /// Sliding along x (or not sliding), the half spectrum takes each row's
    /// compliance from one evaluation per row; it equals the multiplier
    /// evaluated mode by mode, bit for bit, for both responses, odd and
    /// even sizes (Nyquist rows and columns), rectangular cells and a layer.
    /// Along another direction every mode evaluates its own.
    #[test]
    fn row_compliances_equal_the_modes_own() {
        use crate::response::{Layer, LayerBase};
        let mat = material();
        let layer = Some(Layer {
            thickness: 3e-4,
            base: LayerBase::Bonded,
        });
        for (speed, dir, layer) in [(0.013, 0.0, None), (0.0, 0.7, None), (0.013, 0.0, layer)] {
            let response = SlidingResponse::new(&mat, speed, dir, layer).unwrap();
            let unit = Grid::square(4, 4, 1.0).unwrap();
            assert!(Modes::new(&response, &unit).rows_suffice());
            for &(nx, ny) in &[(6usize, 8usize), (7, 5), (8, 9)] {
                let grid = Grid::new(nx, ny, (1e-4, 1.5e-4)).unwrap();
                for resp in [
                    PeriodicResponse::Displacement,
                    PeriodicResponse::SlidingSlope,
                ] {
                    let half = multiplier_half_spectrum(&response, &grid, resp);
                    for j in 0..ny / 2 + 1 {
                        for i in 0..nx {
                            let own = periodic_multiplier(&response, &grid, i, j, resp);
                            let m = half[j * nx + i];
                            assert!(
                                m.re.to_bits() == own.re.to_bits()
                                    && m.im.to_bits() == own.im.to_bits(),
                                "{nx}x{ny} {resp:?} mode ({i}, {j}): {m} vs {own}"
                            );
                        }
                    }
                }
            }
        }
        let oblique = SlidingResponse::new(&mat, 0.013, 0.4, None).unwrap();
        let unit = Grid::square(4, 4, 1.0).unwrap();
        assert!(!Modes::new(&oblique, &unit).rows_suffice());
    }

    /// The FFT operator equals the naive double sum over modes,
    /// `u_n = (1/N) sum_k m_k sum_l p_l exp(i q_k (x_n - x_l))`, on odd and
    /// even sizes, and its diagonal matches `self_coefficient`.
    #[test]
    fn matches_naive_mode_sum() {
        let mat = material();
        for &(nx, ny) in &[(4usize, 6usize), (5, 3), (6, 7), (8, 8)] {
            let a = 1e-4;
            let (speed, dir) = (0.013, 0.4);
            for resp in [
                PeriodicResponse::Displacement,
                PeriodicResponse::SlidingSlope,
            ] {
                let response = SlidingResponse::new(&mat, speed, dir, None).unwrap();
                let grid = Grid::square(nx, ny, a).unwrap();
                let mut op = SpectralPeriodic::new(&grid, &response, resp);
                let n = nx * ny;
                let p: Vec<f64> = (0..n).map(|k| ((k * 37 % 11) as f64) - 4.3).collect();
                let mut u = vec![0.0; n];
                op.apply(&p, &mut u);
                let mut naive = vec![0.0; n];
                let mut dense = vec![0.0; n * n];
                for kx in 0..nx {
                    for ky in 0..ny {
                        let m = periodic_multiplier(&response, &grid, kx, ky, resp);
                        for s in 0..n {
                            for t in 0..n {
                                let (di, dj) = (
                                    (s / ny) as f64 - (t / ny) as f64,
                                    (s % ny) as f64 - (t % ny) as f64,
                                );
                                let ph = std::f64::consts::TAU
                                    * (kx as f64 * di / nx as f64 + ky as f64 * dj / ny as f64);
                                let e = (m * Complex64::from_polar(1.0, ph)).re / n as f64;
                                dense[s * n + t] += e;
                            }
                        }
                    }
                }
                for s in 0..n {
                    for t in 0..n {
                        naive[s] += dense[s * n + t] * p[t];
                    }
                }
                let scale = naive.iter().map(|v| v.abs()).fold(0.0, f64::max);
                for (x, y) in u.iter().zip(&naive) {
                    assert!(
                        (x - y).abs() <= 1e-12 * scale,
                        "{nx}x{ny} {resp:?}: {x} vs {y}"
                    );
                }
                if resp == PeriodicResponse::Displacement {
                    let d = op.self_coefficient();
                    assert!(
                        (d - dense[0]).abs() <= 1e-12 * d.abs(),
                        "{d} vs {}",
                        dense[0]
                    );
                }
            }
        }
    }
}
