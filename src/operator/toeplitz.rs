//! Block-Toeplitz operator applied by zero-padded real FFTs: the exact linear
//! (non-periodic) 2-D convolution of the pressure with the influence
//! coefficients, in O(N log N) (physics.md section 3, "Discretisation").
//!
//! The `(2nx-1) x (2ny-1)` offset table is wrapped into a circular kernel of
//! size `mx x my` with `mx >= 2nx - 1`, `my >= 2ny - 1` (sizes with factors
//! 2, 3, 5, 7 only), so circular and linear convolution coincide on the
//! `nx x ny` output block. Plans, the kernel spectrum and all work buffers are
//! built once; `apply` allocates nothing.

use std::sync::Arc;

use num_complex::Complex64;
use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

use super::{GridOperator, OffsetTable};

/// `u = L p` by padded FFT convolution.
pub struct ToeplitzFft {
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    /// `my / 2 + 1` complex entries per row after the real transform.
    myh: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    fwd: Arc<dyn Fft<f64>>,
    inv: Arc<dyn Fft<f64>>,
    /// Kernel spectrum, column-major (`myh` columns of length `mx`), scaled by `1/(mx my)`.
    kernel_t: Vec<Complex64>,
    rows: Vec<f64>,
    spec: Vec<Complex64>,
    spec_t: Vec<Complex64>,
    pool: Vec<Vec<Complex64>>,
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
    /// Plan the transforms and transform the kernel once.
    pub fn new(table: OffsetTable<'_>) -> Self {
        table.check();
        let (nx, ny) = (table.nx, table.ny);
        let mx = fast_size(2 * nx - 1);
        let my = fast_size(2 * ny - 1);
        let myh = my / 2 + 1;
        let mut rp = RealFftPlanner::<f64>::new();
        let r2c = rp.plan_fft_forward(my);
        let c2r = rp.plan_fft_inverse(my);
        let mut cp = FftPlanner::<f64>::new();
        let fwd = cp.plan_fft_forward(mx);
        let inv = cp.plan_fft_inverse(mx);
        let groups = 4 * rayon::current_num_threads().max(1);
        let scratch_len = r2c
            .get_scratch_len()
            .max(c2r.get_scratch_len())
            .max(fwd.get_inplace_scratch_len())
            .max(inv.get_inplace_scratch_len())
            .max(1);
        let mut op = Self {
            nx,
            ny,
            mx,
            my,
            myh,
            r2c,
            c2r,
            fwd,
            inv,
            kernel_t: vec![Complex64::default(); myh * mx],
            rows: vec![0.0; mx * my],
            spec: vec![Complex64::default(); mx * myh],
            spec_t: vec![Complex64::default(); myh * mx],
            pool: (0..groups)
                .map(|_| vec![Complex64::default(); scratch_len])
                .collect(),
        };
        // Wrap the offset table into the circular kernel.
        op.rows.fill(0.0);
        for di in -(nx as isize - 1)..=(nx as isize - 1) {
            let r = di.rem_euclid(mx as isize) as usize;
            for dj in -(ny as isize - 1)..=(ny as isize - 1) {
                let c = dj.rem_euclid(my as isize) as usize;
                op.rows[r * my + c] = table.get(di, dj);
            }
        }
        op.forward_all_rows();
        let scale = 1.0 / (mx * my) as f64;
        let kernel_t: Vec<Complex64> = op.spec_t.iter().map(|z| z * scale).collect();
        op.kernel_t = kernel_t;
        op
    }

    /// Padded transform sizes `(mx, my)`.
    pub fn padded_shape(&self) -> (usize, usize) {
        (self.mx, self.my)
    }

    /// Row r2c transforms of all `mx` rows of `self.rows`, then column FFTs
    /// into `spec_t` (column-major).
    fn forward_all_rows(&mut self) {
        self.forward_rows(self.mx);
        self.forward_columns();
    }

    fn forward_rows(&mut self, nonzero_rows: usize) {
        let (my, myh) = (self.my, self.myh);
        let r2c = &self.r2c;
        let groups = self.pool.len();
        let rows_per = nonzero_rows.div_ceil(groups).max(1);
        self.rows[..nonzero_rows * my]
            .par_chunks_mut(rows_per * my)
            .zip(self.spec[..nonzero_rows * myh].par_chunks_mut(rows_per * myh))
            .zip(self.pool.par_iter_mut())
            .for_each(|((rin, sout), scratch)| {
                for (r, s) in rin.chunks_exact_mut(my).zip(sout.chunks_exact_mut(myh)) {
                    r2c.process_with_scratch(r, s, scratch)
                        .expect("buffer sizes match the plan");
                }
            });
        self.spec[nonzero_rows * myh..].fill(Complex64::default());
    }

    fn forward_columns(&mut self) {
        let (mx, myh) = (self.mx, self.myh);
        let spec = &self.spec;
        let fwd = &self.fwd;
        let groups = self.pool.len();
        let cols_per = myh.div_ceil(groups).max(1);
        self.spec_t
            .par_chunks_mut(cols_per * mx)
            .enumerate()
            .zip(self.pool.par_iter_mut())
            .for_each(|((g, cols), scratch)| {
                for (k, col) in cols.chunks_exact_mut(mx).enumerate() {
                    let c = g * cols_per + k;
                    for (r, v) in col.iter_mut().enumerate() {
                        *v = spec[r * myh + c];
                    }
                    fwd.process_with_scratch(col, scratch);
                }
            });
    }
}

impl GridOperator for ToeplitzFft {
    fn shape(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        let (nx, ny, mx, my, myh) = (self.nx, self.ny, self.mx, self.my, self.myh);
        assert_eq!(x.len(), nx * ny);
        assert_eq!(y.len(), nx * ny);
        // Zero-padded input: rows beyond nx stay zero and are not transformed.
        self.rows[..nx * my]
            .par_chunks_mut(my)
            .zip(x.par_chunks(ny))
            .for_each(|(r, xr)| {
                r[..ny].copy_from_slice(xr);
                r[ny..].fill(0.0);
            });
        self.forward_rows(nx);
        self.forward_columns();
        // Pointwise product with the kernel spectrum and inverse column FFTs.
        let inv = &self.inv;
        let kernel_t = &self.kernel_t;
        let groups = self.pool.len();
        let cols_per = myh.div_ceil(groups).max(1);
        self.spec_t
            .par_chunks_mut(cols_per * mx)
            .zip(kernel_t.par_chunks(cols_per * mx))
            .zip(self.pool.par_iter_mut())
            .for_each(|((cols, ks), scratch)| {
                for (col, k) in cols.chunks_exact_mut(mx).zip(ks.chunks_exact(mx)) {
                    for (v, kv) in col.iter_mut().zip(k) {
                        *v *= kv;
                    }
                    inv.process_with_scratch(col, scratch);
                }
            });
        // Back to row-major for the first nx rows only, then c2r.
        let spec_t = &self.spec_t;
        let c2r = &self.c2r;
        let rows_per = nx.div_ceil(groups).max(1);
        self.spec[..nx * myh]
            .par_chunks_mut(rows_per * myh)
            .enumerate()
            .zip(self.rows[..nx * my].par_chunks_mut(rows_per * my))
            .zip(self.pool.par_iter_mut())
            .zip(y.par_chunks_mut(rows_per * ny))
            .for_each(|((((g, srows), rrows), scratch), yrows)| {
                for (k, ((s, r), yr)) in srows
                    .chunks_exact_mut(myh)
                    .zip(rrows.chunks_exact_mut(my))
                    .zip(yrows.chunks_exact_mut(ny))
                    .enumerate()
                {
                    let row = g * rows_per + k;
                    for (c, v) in s.iter_mut().enumerate() {
                        *v = spec_t[c * mx + row];
                    }
                    // The imaginary parts of the DC and Nyquist bins are
                    // round-off for a real signal; c2r requires them zero.
                    s[0].im = 0.0;
                    if my % 2 == 0 {
                        s[myh - 1].im = 0.0;
                    }
                    c2r.process_with_scratch(s, r, scratch)
                        .expect("buffer sizes match the plan");
                    yr.copy_from_slice(&r[..ny]);
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_sizes() {
        assert_eq!(fast_size(1023), 1024);
        assert_eq!(fast_size(11), 12);
        assert_eq!(fast_size(13), 14);
        assert_eq!(fast_size(127), 128);
    }
}
