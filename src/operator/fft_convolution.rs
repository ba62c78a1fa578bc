//! The 2-D real-FFT convolution both FFT operators are built on: an
//! `nx x ny` block, embedded in an `mx x my` transform (zero-padded when
//! larger: [`super::ToeplitzFft`]; the same size: [`super::SpectralPeriodic`]),
//! multiplied mode by mode by a fixed spectrum.
//!
//! Layout: row r2c transforms (`my / 2 + 1` bins per row), then complex
//! column FFTs on a column-major copy, the pointwise product and the inverse
//! column FFTs in the same pass, then c2r on the first `nx` rows only. Rows
//! of the padding are zero and are neither transformed nor read back. Plans,
//! the multiplier and every work buffer are built once; `apply` allocates
//! nothing and runs its transforms with rayon. (The one-shot transforms of
//! height maps are the surface layer's, `surface/height_fft.rs`.)

use std::sync::Arc;

use num_complex::Complex64;
use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

/// Rows per rayon task when copying into the padded buffer.
const ROWS_PER_TASK: usize = 16;

/// `y = F^-1 [m F [x padded]]` restricted to the input block.
pub(crate) struct SpectralEngine {
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    /// `my / 2 + 1` complex bins per row after the real transform.
    myh: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    fwd: Arc<dyn Fft<f64>>,
    inv: Arc<dyn Fft<f64>>,
    /// Multiplier, column-major (`myh` columns of length `mx`), scaled by
    /// `1 / (mx my)` (the unnormalised inverse transforms).
    multiplier_t: Vec<Complex64>,
    /// Optional second multiplier with the same layout and scaling:
    /// the approximate inverse applied by [`SpectralEngine::apply_inverse`].
    inverse_t: Option<Vec<Complex64>>,
    rows: Vec<f64>,
    spec: Vec<Complex64>,
    spec_t: Vec<Complex64>,
    pool: Vec<Vec<Complex64>>,
}

impl SpectralEngine {
    /// Plans and buffers for an `nx x ny` block in an `mx x my` transform;
    /// the multiplier starts at zero ([`Self::set_multiplier`]).
    pub(crate) fn new(nx: usize, ny: usize, mx: usize, my: usize) -> Self {
        assert!(nx > 0 && ny > 0, "grid must be non-empty");
        assert!(mx >= nx && my >= ny, "the transform must hold the block");
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
        Self {
            nx,
            ny,
            mx,
            my,
            myh,
            r2c,
            c2r,
            fwd,
            inv,
            multiplier_t: vec![Complex64::default(); myh * mx],
            inverse_t: None,
            rows: vec![0.0; mx * my],
            spec: vec![Complex64::default(); mx * myh],
            spec_t: vec![Complex64::default(); myh * mx],
            pool: (0..groups)
                .map(|_| vec![Complex64::default(); scratch_len])
                .collect(),
        }
    }

    /// Block shape `(nx, ny)`.
    pub(crate) fn shape(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Transform sizes `(mx, my)`.
    pub(crate) fn padded_shape(&self) -> (usize, usize) {
        (self.mx, self.my)
    }

    /// The unnormalised half spectrum of a real `mx x my` array (row-major),
    /// column-major like the multiplier: e.g. a wrapped offset table.
    pub(crate) fn spectrum_of(&mut self, full: &[f64]) -> Vec<Complex64> {
        assert_eq!(full.len(), self.mx * self.my, "array of the transform size");
        self.rows.copy_from_slice(full);
        self.forward_rows(self.mx);
        let (mx, myh) = (self.mx, self.myh);
        let spec = &self.spec;
        let fwd = &self.fwd;
        let cols_per = myh.div_ceil(self.pool.len()).max(1);
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
        self.spec_t.clone()
    }

    /// Set the multiplier from its column-major half spectrum (`myh`
    /// columns of `mx` modes), unnormalised: the engine divides by `mx my`.
    pub(crate) fn set_multiplier(&mut self, mut multiplier_t: Vec<Complex64>) {
        assert_eq!(multiplier_t.len(), self.myh * self.mx, "one value per mode");
        let scale = 1.0 / (self.mx * self.my) as f64;
        multiplier_t.par_iter_mut().for_each(|m| *m *= scale);
        self.multiplier_t = multiplier_t;
    }

    /// Row r2c transforms of the first `count` rows of `rows` into `spec`.
    /// Set the second multiplier to the regularised inverse of the first:
    /// `1 / m` where `|m| > floor max |m|`; `1 / max |m|` where `m = 0` (a
    /// mode the operator does not see, e.g. `q = 0` of the periodic cell:
    /// the stiffness of the longest wave, so that the inverse stays
    /// positive definite); `1 / (floor max |m|)` in the direction of `m` in
    /// between.
    pub(crate) fn set_inverse_multiplier(&mut self, floor: f64) {
        let points = self.mx * self.my;
        self.inverse_t = Some(inverse_multiplier(&self.multiplier_t, points, floor));
    }

    /// Whether [`SpectralEngine::set_inverse_multiplier`] was called.
    pub(crate) fn has_inverse(&self) -> bool {
        self.inverse_t.is_some()
    }

    fn forward_rows(&mut self, count: usize) {
        let (my, myh) = (self.my, self.myh);
        let r2c = &self.r2c;
        let rows_per = count.div_ceil(self.pool.len()).max(1);
        self.rows[..count * my]
            .par_chunks_mut(rows_per * my)
            .zip(self.spec[..count * myh].par_chunks_mut(rows_per * myh))
            .zip(self.pool.par_iter_mut())
            .for_each(|((rin, sout), scratch)| {
                for (r, s) in rin.chunks_exact_mut(my).zip(sout.chunks_exact_mut(myh)) {
                    r2c.process_with_scratch(r, s, scratch)
                        .expect("buffer sizes match the plan");
                }
            });
    }

    /// `y = F^-1 [m F [x]]` on the `nx x ny` block (C order).
    pub(crate) fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.convolve(x, y, false);
    }

    /// `y = F^-1 [m^-1 F [x padded]]` with the inverse multiplier (panics
    /// when none was set).
    pub(crate) fn apply_inverse(&mut self, x: &[f64], y: &mut [f64]) {
        assert!(self.inverse_t.is_some(), "no inverse multiplier was set");
        self.convolve(x, y, true);
    }

    fn convolve(&mut self, x: &[f64], y: &mut [f64], inverse: bool) {
        let (nx, ny, mx, my, myh) = (self.nx, self.ny, self.mx, self.my, self.myh);
        assert_eq!(x.len(), nx * ny);
        assert_eq!(y.len(), nx * ny);
        let groups = self.pool.len();
        if my == ny {
            self.rows[..nx * ny].copy_from_slice(x);
        } else {
            self.rows[..nx * my]
                .par_chunks_mut(my)
                .zip(x.par_chunks(ny))
                .with_min_len(ROWS_PER_TASK)
                .for_each(|(r, xr)| {
                    r[..ny].copy_from_slice(xr);
                    r[ny..].fill(0.0);
                });
        }
        self.forward_rows(nx);
        // Column FFTs (padding rows are zero), multiplier, inverse column FFTs.
        let spec = &self.spec;
        let (fwd, inv) = (&self.fwd, &self.inv);
        let cols_per = myh.div_ceil(groups).max(1);
        self.spec_t
            .par_chunks_mut(cols_per * mx)
            .zip(
                if inverse {
                    self.inverse_t.as_deref().expect("checked by the caller")
                } else {
                    &self.multiplier_t
                }
                .par_chunks(cols_per * mx),
            )
            .enumerate()
            .zip(self.pool.par_iter_mut())
            .for_each(|((g, (cols, ms)), scratch)| {
                for (k, (col, m)) in cols
                    .chunks_exact_mut(mx)
                    .zip(ms.chunks_exact(mx))
                    .enumerate()
                {
                    let c = g * cols_per + k;
                    for (r, v) in col[..nx].iter_mut().enumerate() {
                        *v = spec[r * myh + c];
                    }
                    col[nx..].fill(Complex64::default());
                    fwd.process_with_scratch(col, scratch);
                    for (v, mv) in col.iter_mut().zip(m) {
                        *v *= mv;
                    }
                    inv.process_with_scratch(col, scratch);
                }
            });
        // Back to rows for the first nx rows only, then c2r.
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
                    // Without padding the row is the output row.
                    let out = if my == ny { &mut *yr } else { &mut *r };
                    c2r.process_with_scratch(s, out, scratch)
                        .expect("buffer sizes match the plan");
                    if my != ny {
                        yr.copy_from_slice(&r[..ny]);
                    }
                }
            });
    }
}

/// The regularised inverse of a multiplier stored times `1 / points` (the
/// unnormalised inverse transform's scale), stored the same way:
/// `conj(m) / |m|^2 / points^2`; modes below `floor` times the largest are
/// raised to it in the direction of `m`, zero modes get the largest's
/// inverse ([`SpectralEngine::set_inverse_multiplier`]; the GPU
/// preconditioner's spectrum too).
pub(crate) fn inverse_multiplier(
    multiplier: &[Complex64],
    points: usize,
    floor: f64,
) -> Vec<Complex64> {
    let scale = 1.0 / points as f64;
    let largest = multiplier.iter().map(|m| m.norm()).fold(0.0, f64::max);
    let cut = floor * largest;
    multiplier
        .par_iter()
        .map(|&m| {
            let r = m.norm();
            if r == 0.0 {
                Complex64::new(scale * scale / largest, 0.0)
            } else {
                let m = if r < cut { m * (cut / r) } else { m };
                m.conj() / m.norm_sqr() * (scale * scale)
            }
        })
        .collect()
}
