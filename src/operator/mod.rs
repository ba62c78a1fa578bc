//! The linear map `u = L p` of the discretised Green's function (paper Eq. 7,
//! `u_i = L_ik(v) sigma_k`) on a uniform grid.
//!
//! On a uniform grid `L_ik` depends only on the cell offset, so `L` is
//! block-Toeplitz: [`ToeplitzFft`] applies it as an exact linear
//! (non-periodic) convolution through zero-padded real FFTs; [`DenseOperator`]
//! stores every entry (faer) and is the naive control; [`SpectralPeriodic`]
//! is the periodic-cell formulation of the paper's Appendix;
//! [`AdaptiveOperator`] applies the pairwise operator of a quadtree mesh.

mod adaptive;
mod dense;
mod description;
mod fft_convolution;
mod field;
mod real;
mod real_rows;
pub(crate) use fft_convolution::inverse_multiplier;
mod periodic;
mod toeplitz;

pub use adaptive::{AdaptiveOperator, LevelTables};
pub use dense::DenseOperator;
pub use description::OperatorDescription;
pub(crate) use fft_convolution::half_spectrum;
pub use fft_convolution::Real;
pub(crate) use fft_convolution::SpectralEngine;
pub(crate) use periodic::{column_weight, multiplier_half_spectrum, nyquist_signs, signed_index};
pub use periodic::{periodic_multiplier, PeriodicResponse, SpectralPeriodic};
pub(crate) use toeplitz::chan_inverse_table;
pub use toeplitz::{chan_kernel, fast_size, ToeplitzFft, CHAN_FRACTION};

/// A square linear map on grid vectors (C order, axis 0 = x).
pub trait GridOperator: Send + Sync {
    /// `(nx, ny)` of the grid.
    fn shape(&self) -> (usize, usize);
    /// `y = L x`, in the operator's working precision
    /// ([`GridOperator::epsilon`]).
    fn apply(&mut self, x: &[f64], y: &mut [f64]);
    /// `y = L x` to f64 rounding, for the outer residuals of iterative
    /// refinement (physics.md section 13); the default is
    /// [`GridOperator::apply`], which is exact for f64 operators.
    fn apply_exact(&mut self, x: &[f64], y: &mut [f64]) {
        self.apply(x, y);
    }
    /// Relative rounding unit of [`GridOperator::apply`] and
    /// [`GridOperator::precondition`] (`f64::EPSILON` unless the transforms
    /// run in f32).
    fn epsilon(&self) -> f64 {
        f64::EPSILON
    }
    /// `out[k] = (L x)[rows[k]]`. The default applies `L` on the whole grid
    /// into `scratch` and picks the rows; pairwise operators evaluate only
    /// the rows asked for.
    fn apply_rows(&mut self, x: &[f64], rows: &[usize], scratch: &mut [f64], out: &mut [f64]) {
        self.apply(x, scratch);
        for (o, &r) in out.iter_mut().zip(rows) {
            *o = scratch[r];
        }
    }
    /// `out = (L x)[cells]` for `x` zero off `cells` (`x[k]` on
    /// `cells[k]`, sorted), in the working precision. The default scatters
    /// into grid-size work vectors of `work`; operators that transform row
    /// by row read and write the set's values directly (module `field`).
    fn apply_set(&mut self, cells: &[usize], x: &[f64], out: &mut [f64], work: &mut GridWork) {
        let (full, product) = work.scatter(self.shape(), cells, x);
        self.apply_rows(full, cells, product, out);
    }
    /// [`GridOperator::apply_set`] to f64 rounding
    /// ([`GridOperator::apply_exact`]).
    fn apply_set_exact(
        &mut self,
        cells: &[usize],
        x: &[f64],
        out: &mut [f64],
        work: &mut GridWork,
    ) {
        through_grid(self, Self::apply_exact, cells, x, out, work);
    }
    /// `out = (K x)[cells]` for `x` zero off `cells`
    /// ([`GridOperator::precondition`]).
    fn precondition_set(
        &mut self,
        cells: &[usize],
        x: &[f64],
        out: &mut [f64],
        work: &mut GridWork,
    ) {
        through_grid(self, Self::precondition, cells, x, out, work);
    }
    /// Whether [`GridOperator::precondition`] applies an approximate
    /// inverse (default: no).
    fn has_preconditioner(&self) -> bool {
        false
    }
    /// The fraction of the grid's cells in the contact set that the next
    /// preconditioner applications serve: an operator with more than one
    /// approximate inverse picks the one for it (default: nothing to pick).
    fn set_contact_fraction(&mut self, _fraction: f64) {}
    /// `y = K x` with `K` an approximate inverse of `L` on the whole grid
    /// (the identity unless [`GridOperator::has_preconditioner`]).
    fn precondition(&mut self, x: &[f64], y: &mut [f64]) {
        y.copy_from_slice(x);
    }
}

/// A boxed operator is the operator it holds (every method forwarded, the
/// set products included): an executor holds the operator of any
/// [`OperatorDescription`] behind one type.
impl<O: GridOperator + ?Sized> GridOperator for Box<O> {
    fn shape(&self) -> (usize, usize) {
        (**self).shape()
    }
    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        (**self).apply(x, y);
    }
    fn apply_exact(&mut self, x: &[f64], y: &mut [f64]) {
        (**self).apply_exact(x, y);
    }
    fn epsilon(&self) -> f64 {
        (**self).epsilon()
    }
    fn apply_rows(&mut self, x: &[f64], rows: &[usize], scratch: &mut [f64], out: &mut [f64]) {
        (**self).apply_rows(x, rows, scratch, out);
    }
    fn apply_set(&mut self, cells: &[usize], x: &[f64], out: &mut [f64], work: &mut GridWork) {
        (**self).apply_set(cells, x, out, work);
    }
    fn apply_set_exact(
        &mut self,
        cells: &[usize],
        x: &[f64],
        out: &mut [f64],
        work: &mut GridWork,
    ) {
        (**self).apply_set_exact(cells, x, out, work);
    }
    fn precondition_set(
        &mut self,
        cells: &[usize],
        x: &[f64],
        out: &mut [f64],
        work: &mut GridWork,
    ) {
        (**self).precondition_set(cells, x, out, work);
    }
    fn has_preconditioner(&self) -> bool {
        (**self).has_preconditioner()
    }
    fn set_contact_fraction(&mut self, fraction: f64) {
        (**self).set_contact_fraction(fraction);
    }
    fn precondition(&mut self, x: &[f64], y: &mut [f64]) {
        (**self).precondition(x, y);
    }
}

/// Grid-size work vectors for the set products of operators that need the
/// whole field ([`GridOperator::apply_set`]'s default): allocated at the
/// first such product, never by the FFT operators.
#[derive(Debug, Default)]
pub struct GridWork {
    full: Vec<f64>,
    product: Vec<f64>,
}

impl GridWork {
    /// The set's values scattered into a zeroed grid vector of `shape`, and
    /// a second grid vector for the product.
    fn scatter(
        &mut self,
        shape: (usize, usize),
        cells: &[usize],
        x: &[f64],
    ) -> (&mut [f64], &mut [f64]) {
        let n = shape.0 * shape.1;
        self.full.clear();
        self.full.resize(n, 0.0);
        self.product.resize(n, 0.0);
        for (&c, &v) in cells.iter().zip(x) {
            self.full[c] = v;
        }
        (&mut self.full, &mut self.product)
    }
}

/// `out = (f x)[cells]` for `x` zero off `cells`, through the grid-size
/// work vectors of `work`: the set products' default for an operator that
/// has only whole-grid products.
fn through_grid<O: GridOperator + ?Sized>(
    op: &mut O,
    f: fn(&mut O, &[f64], &mut [f64]),
    cells: &[usize],
    x: &[f64],
    out: &mut [f64],
    work: &mut GridWork,
) {
    let (full, product) = work.scatter(op.shape(), cells, x);
    f(op, full, product);
    gather(cells, product, out);
}

/// `out[k] = full[cells[k]]`.
fn gather(cells: &[usize], full: &[f64], out: &mut [f64]) {
    for (o, &c) in out.iter_mut().zip(cells) {
        *o = full[c];
    }
}

/// Entries of a block-Toeplitz operator: `table(di, dj)` is the response at
/// cell `(i, j)` to a unit input at `(i - di, j - dj)`, stored as in
/// [`crate::kernel::CoefficientTable`]: `values[(di + nx - 1) * (2 ny - 1) + dj + ny - 1]`.
#[derive(Debug, Clone, Copy)]
pub struct OffsetTable<'a> {
    pub nx: usize,
    pub ny: usize,
    pub values: &'a [f64],
}

impl OffsetTable<'_> {
    /// The entry for offset `(di, dj)`.
    #[inline]
    pub fn get(&self, di: isize, dj: isize) -> f64 {
        let w = 2 * self.ny - 1;
        self.values[(di + self.nx as isize - 1) as usize * w + (dj + self.ny as isize - 1) as usize]
    }

    pub(crate) fn check(&self) {
        assert_eq!(
            self.values.len(),
            (2 * self.nx - 1) * (2 * self.ny - 1),
            "offset table must hold (2nx-1)(2ny-1) entries"
        );
    }
}
