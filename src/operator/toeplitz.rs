//! Block-Toeplitz operator applied by zero-padded real FFTs: the exact linear
//! (non-periodic) 2-D convolution of the pressure with the influence
//! coefficients, in O(N log N) (physics.md section 3, "Discretisation").
//!
//! The `(2nx-1) x (2ny-1)` offset table is wrapped into a circular kernel of
//! size `mx x my` with `mx >= 2nx - 1`, `my >= 2ny - 1` (sizes with factors
//! 2, 3, 5, 7 only), so circular and linear convolution coincide on the
//! `nx x ny` output block. The transforms are [`SpectralEngine`]'s: plans,
//! the kernel spectrum and all work buffers are built once; `apply`
//! allocates nothing.
//!
//! Two approximate inverses serve as preconditioners: the restriction of the
//! padded circulant's inverse (good on small contact sets, whose spots lie
//! far inside the grid), and the inverse of T. Chan's optimal circulant of
//! the grid's own two-level Toeplitz matrix (good where contact covers most
//! of the grid; BENCHMARKS.md, "Near-full contact").

use rayon::prelude::*;

use super::fft_convolution::{half_spectrum, Product, Real, SpectralEngine};
use super::{GridOperator, GridWork, OffsetTable};

/// `u = L p` by padded FFT convolution, the transforms in precision `T`
/// (f64, or f32 for the inner solves of mixed precision).
pub struct ToeplitzFft<T: Real = f64> {
    engine: SpectralEngine<T>,
    /// First row of T. Chan's optimal circulant ([`chan_kernel`]), kept
    /// until its inverse is first needed (one value per cell).
    chan_kernel: Option<Vec<f64>>,
    /// The `nx x ny` circulant engine holding the inverse of T. Chan's
    /// circulant, built on demand.
    chan: Option<SpectralEngine<T>>,
    /// Whether [`GridOperator::precondition`] applies the optimal
    /// circulant's inverse (set by [`GridOperator::set_contact_fraction`]).
    use_chan: bool,
}

/// Contact-set fraction of the grid above which the preconditioner is the
/// inverse of T. Chan's optimal circulant instead of the restricted inverse
/// of the padded circulant (measured in BENCHMARKS.md, "Near-full contact":
/// 140 against 281 matvecs at 82 % contact, 90 against 82 at 5 %). Strictly
/// above: the bearing-area start, capped at half the grid, keeps the padded
/// one.
pub const CHAN_FRACTION: f64 = 0.5;

/// Modes of T. Chan's circulant below this fraction of its largest
/// multiplier are clamped there in its inverse.
const CHAN_FLOOR: f64 = 1e-6;

/// First row (an `nx x ny` array, C order) of T. Chan's optimal circulant of
/// the two-level Toeplitz matrix of `table` (T. F. Chan, SIAM J. Sci. Stat.
/// Comput. 9, 766, 1988; two-level form of Chan & Olkin): the circulant
/// nearest in the Frobenius norm, `c(i) = ((n - i) t(i) + i t(i - n)) / n`
/// along each axis. Its eigenvalues are the Rayleigh quotients `f* L f` of
/// the Fourier vectors, so its symmetric part is positive definite where
/// `L`'s is.
pub fn chan_kernel(table: OffsetTable<'_>) -> Vec<f64> {
    table.check();
    let (nx, ny) = (table.nx, table.ny);
    let pairs = |i: usize, n: usize| -> [(isize, f64); 2] {
        let w = i as f64 / n as f64;
        [(i as isize, 1.0 - w), (i as isize - n as isize, w)]
    };
    let mut kernel = vec![0.0; nx * ny];
    kernel.par_chunks_mut(ny).enumerate().for_each(|(i, row)| {
        let px = pairs(i, nx);
        for (j, c) in row.iter_mut().enumerate() {
            let py = pairs(j, ny);
            let mut sum = 0.0;
            for &(sx, wx) in &px {
                for &(sy, wy) in &py {
                    // Weight 0 at offset -n (outside the table).
                    if wx != 0.0 && wy != 0.0 {
                        sum += wx * wy * table.get(sx, sy);
                    }
                }
            }
            *c = sum;
        }
    });
    kernel
}

/// The `nx x ny` circulant engine of T. Chan's circulant whose first row is
/// `kernel` ([`chan_kernel`]), with its inverse (modes below [`CHAN_FLOOR`]
/// of the largest clamped there), in precision `T`.
fn chan_engine<T: Real>(kernel: &[f64], nx: usize, ny: usize) -> SpectralEngine<T> {
    let mut chan = SpectralEngine::<T>::new(nx, ny, nx, ny);
    chan.set_multiplier(half_spectrum(kernel, nx, ny));
    chan.set_inverse_multiplier(CHAN_FLOOR);
    chan
}

/// The offset table (`(2nx-1) x (2ny-1)`, layout of [`OffsetTable`]) of
/// the inverse of T. Chan's optimal circulant whose first row is `kernel`
/// ([`chan_kernel`], `nx x ny`): the inverse of a circulant is the
/// circulant of `c_inv = C^-1 e_0`, and on the grid `(C^-1 x)_i = sum_k
/// c_inv((i - k) mod n) x_k`, so the table holds `c_inv(d mod n)` at offset
/// `d`. The preconditioner [`ToeplitzFft`] applies above [`CHAN_FRACTION`],
/// for an executor whose only product is the padded convolution of a table
/// (the GPU's): `c_inv` comes from the same transform and the same floor.
pub(crate) fn chan_inverse_table(kernel: &[f64], nx: usize, ny: usize) -> Vec<f64> {
    assert_eq!(kernel.len(), nx * ny, "one value per cell");
    let mut chan = chan_engine::<f64>(kernel, nx, ny);
    let mut impulse = vec![0.0; nx * ny];
    impulse[0] = 1.0;
    let mut column = vec![0.0; nx * ny];
    chan.apply_inverse(&impulse, &mut column);
    let w = 2 * ny - 1;
    let mut table = vec![0.0; (2 * nx - 1) * w];
    table.par_chunks_mut(w).enumerate().for_each(|(r, row)| {
        let i = (r as isize - (nx as isize - 1)).rem_euclid(nx as isize) as usize;
        for (c, t) in row.iter_mut().enumerate() {
            let j = (c as isize - (ny as isize - 1)).rem_euclid(ny as isize) as usize;
            *t = column[i * ny + j];
        }
    });
    table
}

/// Smallest `m >= n` whose prime factors are 2, 3, 5 and 7 (fast FFT sizes).
pub fn fast_size(n: usize) -> usize {
    let mut m = n.max(1);
    loop {
        let mut r = m;
        for p in [2, 3, 5, 7] {
            while r % p == 0 {
                r /= p;
            }
        }
        if r == 1 {
            return m;
        }
        m += 1;
    }
}

impl ToeplitzFft {
    /// Plan the transforms and transform the kernel once (f64).
    pub fn new(table: OffsetTable<'_>) -> Self {
        Self::in_precision(table)
    }
}

impl<T: Real> ToeplitzFft<T> {
    /// [`ToeplitzFft::new`] with transforms and spectra in precision `T`
    /// (the kernel spectrum is computed in f64, then rounded).
    pub fn in_precision(table: OffsetTable<'_>) -> Self {
        table.check();
        let (nx, ny) = (table.nx, table.ny);
        let (mx, my) = (fast_size(2 * nx - 1), fast_size(2 * ny - 1));
        let mut engine = SpectralEngine::new(nx, ny, mx, my);
        // Wrap the offset table into the circular kernel.
        let mut wrapped = vec![0.0; mx * my];
        for di in -(nx as isize - 1)..=(nx as isize - 1) {
            let r = di.rem_euclid(mx as isize) as usize;
            for dj in -(ny as isize - 1)..=(ny as isize - 1) {
                let c = dj.rem_euclid(my as isize) as usize;
                wrapped[r * my + c] = table.get(di, dj);
            }
        }
        let spectrum = half_spectrum(&wrapped, mx, my);
        drop(wrapped);
        engine.set_multiplier(spectrum);
        Self {
            engine,
            chan_kernel: Some(chan_kernel(table)),
            chan: None,
            use_chan: false,
        }
    }

    /// Also provide an approximate inverse as the operator's preconditioner
    /// ([`GridOperator::precondition`]): the inverse of the circulant of the
    /// padded transform, of which `L` is the leading block, restricted to the
    /// grid (`K = R C^-1 R^T`); and, for contact sets covering more than
    /// [`CHAN_FRACTION`] of the grid, the inverse of T. Chan's optimal
    /// circulant ([`chan_kernel`], transformed when first needed). Modes
    /// where a circulant's multiplier is below `1e-6` of its largest are
    /// clamped there.
    pub fn with_preconditioner(mut self) -> Self {
        self.engine.set_inverse_multiplier(1e-6);
        self
    }

    /// Also plan f64 transforms for [`GridOperator::apply_exact`]: the
    /// product with the stored (rounded) spectrum to f64 rounding.
    pub fn with_exact(mut self) -> Self {
        self.engine = self.engine.with_exact();
        self
    }

    /// Padded transform sizes `(mx, my)`.
    pub fn padded_shape(&self) -> (usize, usize) {
        self.engine.padded_shape()
    }

    /// Bytes held by the spectra and the spectrum buffers.
    pub fn bytes(&self) -> usize {
        self.engine.bytes()
            + self.chan.as_ref().map_or(0, SpectralEngine::bytes)
            + 8 * self.chan_kernel.as_ref().map_or(0, Vec::len)
    }
}

impl<T: Real> GridOperator for ToeplitzFft<T> {
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
        if let (true, Some(chan)) = (self.use_chan, self.chan.as_mut()) {
            chan.set_product(Product::Inverse, cells, x, out);
        } else {
            self.engine.precondition_set(cells, x, out);
        }
    }

    fn has_preconditioner(&self) -> bool {
        self.engine.has_inverse()
    }

    fn set_contact_fraction(&mut self, fraction: f64) {
        self.use_chan = fraction > CHAN_FRACTION && self.engine.has_inverse();
        if self.use_chan && self.chan.is_none() {
            let kernel = self.chan_kernel.take().expect("kept by new");
            let (nx, ny) = self.engine.shape();
            self.chan = Some(chan_engine(&kernel, nx, ny));
        }
    }

    fn precondition(&mut self, x: &[f64], y: &mut [f64]) {
        if let (true, Some(chan)) = (self.use_chan, self.chan.as_mut()) {
            chan.apply_inverse(x, y);
        } else {
            self.engine.precondition(x, y);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seeded pseudo-random value in [-1, 1).
    fn noise(k: usize) -> f64 {
        let x = (k as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// The set products read and write the set's values row by row; they
    /// must equal the grid products scattered and gathered, bit for bit
    /// (the same transforms of the same rows; an empty row's transform is
    /// zero either way), for every product, both precisions, a set with
    /// empty rows and the empty set.
    fn set_products_match<T: Real>() {
        let (nx, ny) = (13, 10);
        let values: Vec<f64> = (0..(2 * nx - 1) * (2 * ny - 1))
            .map(|k| 1.0 + 0.3 * noise(k))
            .collect();
        let tab = OffsetTable {
            nx,
            ny,
            values: &values,
        };
        let mut op = ToeplitzFft::<T>::in_precision(tab)
            .with_preconditioner()
            .with_exact();
        // Rows 0, 4..6 and 12 hold cells; the others are empty.
        let cells: Vec<usize> = (0..nx * ny)
            .filter(|&c| {
                let r = c / ny;
                (r == 0 || (4..=6).contains(&r) || r == 12) && noise(c + 7) > -0.2
            })
            .collect();
        let x: Vec<f64> = (0..cells.len()).map(|k| noise(k + 100)).collect();
        let mut full = vec![0.0; nx * ny];
        for (&c, &v) in cells.iter().zip(&x) {
            full[c] = v;
        }
        let mut work = GridWork::default();
        for fraction in [0.0, 1.0] {
            op.set_contact_fraction(fraction);
            let mut grid = vec![0.0; nx * ny];
            let mut short = vec![0.0; cells.len()];
            let pick = |g: &[f64]| cells.iter().map(|&c| g[c]).collect::<Vec<f64>>();
            op.apply(&full, &mut grid);
            op.apply_set(&cells, &x, &mut short, &mut work);
            assert_eq!(short, pick(&grid), "working product");
            op.apply_exact(&full, &mut grid);
            op.apply_set_exact(&cells, &x, &mut short, &mut work);
            assert_eq!(short, pick(&grid), "exact product");
            op.precondition(&full, &mut grid);
            op.precondition_set(&cells, &x, &mut short, &mut work);
            assert_eq!(short, pick(&grid), "preconditioner (fraction {fraction})");
        }
        let mut none: Vec<f64> = vec![];
        op.apply_set(&[], &[], &mut none, &mut work);
        assert!(none.is_empty());
    }

    #[test]
    fn set_products_equal_grid_products() {
        set_products_match::<f64>();
        set_products_match::<f32>();
    }

    /// The table of Chan's inverse, applied as the direct sum `y_i = sum_k
    /// t(i - k) x_k`, is the operator's own preconditioner above
    /// [`CHAN_FRACTION`] (the executors that convolve tables apply it so),
    /// to 1e-12 of the largest value: both come from one f64 transform, the
    /// sum is O(n) additions of f64 terms. Odd and even sides, a
    /// non-symmetric table.
    #[test]
    fn chan_inverse_table_is_the_chan_preconditioner() {
        let (nx, ny) = (9, 6);
        let values: Vec<f64> = (0..(2 * nx - 1) * (2 * ny - 1))
            .map(|k| {
                let (di, dj) = (
                    (k / (2 * ny - 1)) as f64 - 8.0,
                    (k % (2 * ny - 1)) as f64 - 5.0,
                );
                1.0 / (1.0 + di * di + dj * dj).sqrt() + 0.05 * noise(k)
            })
            .collect();
        let tab = OffsetTable {
            nx,
            ny,
            values: &values,
        };
        let mut op = ToeplitzFft::new(tab).with_preconditioner();
        op.set_contact_fraction(1.0);
        let x: Vec<f64> = (0..nx * ny).map(|k| noise(k + 31)).collect();
        let mut expected = vec![0.0; nx * ny];
        op.precondition(&x, &mut expected);
        let table = chan_inverse_table(&chan_kernel(tab), nx, ny);
        let inverse = OffsetTable {
            nx,
            ny,
            values: &table,
        };
        let largest = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for i in 0..nx {
            for j in 0..ny {
                let mut sum = 0.0;
                for k in 0..nx {
                    for l in 0..ny {
                        sum += inverse.get(i as isize - k as isize, j as isize - l as isize)
                            * x[k * ny + l];
                    }
                }
                let e = expected[i * ny + j];
                assert!(
                    (sum - e).abs() <= 1e-12 * largest,
                    "({i}, {j}): {sum} against {e}"
                );
            }
        }
    }

    #[test]
    fn fast_sizes() {
        assert_eq!(fast_size(1023), 1024);
        assert_eq!(fast_size(11), 12);
        assert_eq!(fast_size(13), 14);
        assert_eq!(fast_size(127), 128);
    }
}
