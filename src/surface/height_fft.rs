//! The 2-D FFT of height maps: the one-shot real <-> half-complex
//! transforms behind the spectral synthesis of surfaces (`inverse`: the
//! self-affine generator, the tabulated-PSD synthesis) and their spectral
//! analysis (`forward`: PSDs), for arbitrary grid sizes (rustfft / realfft
//! plan any length, not only powers of two), parallel over rows.
//! [`Forward`] and [`Inverse`] are the same transforms planned once for
//! many maps of one grid, on work space the caller keeps (the heat
//! problem's layers and depth nodes).
//!
//! Not the operators' transform: `operator/fft_convolution.rs` keeps plans,
//! a multiplier and work buffers alive for thousands of products on one
//! grid, which a one-shot transform of a map that may fill most of memory
//! must not hold.
//!
//! Layout of a half spectrum: `spec[ky * nx + kx]` for `ky = 0..=ny/2` and
//! `kx = 0..nx` (FFT order), i.e. transposed with respect to the heights so
//! that the complex transform along x runs over contiguous rows. The
//! transforms are unnormalised: `forward` computes `H_k = sum_x h(x) e^{-i q.x}`
//! and `inverse` computes `sum_k H_k e^{+i q.x}` over the full Hermitian
//! spectrum.

use std::sync::Arc;

use num_complex::Complex64;
use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

use super::SurfaceError;

/// `sum_k f(k, chunk_k)` over consecutive chunks of `chunk` elements,
/// evaluated in parallel but added in a fixed order, so the result does not
/// depend on the number of threads (bit-reproducible runs).
pub(crate) fn ordered_sum<T: Sync>(
    data: &[T],
    chunk: usize,
    f: impl Fn(usize, &[T]) -> f64 + Sync + Send,
) -> f64 {
    let parts: Vec<f64> = data
        .par_chunks(chunk.max(1))
        .enumerate()
        .map(|(k, c)| f(k, c))
        .collect();
    parts.iter().sum()
}

/// Number of stored `ky` rows of a half spectrum.
pub(crate) fn half_len(ny: usize) -> usize {
    ny / 2 + 1
}

fn rows_per_task(rows: usize) -> usize {
    (rows / (4 * rayon::current_num_threads())).max(1)
}

/// The `cols x rows` transpose of the `rows x cols` C-order matrix `src`
/// into `out` (`rows * cols` values), in blocks of 16 output rows.
pub(crate) fn transpose_into<T: Copy + Send + Sync>(
    src: &[T],
    rows: usize,
    cols: usize,
    out: &mut [T],
) {
    const BLOCK: usize = 16;
    debug_assert_eq!(out.len(), rows * cols);
    out.par_chunks_mut(rows * BLOCK)
        .enumerate()
        .for_each(|(b, chunk)| {
            let c0 = b * BLOCK;
            let nc = chunk.len() / rows;
            for r in 0..rows {
                let src_row = &src[r * cols + c0..r * cols + c0 + nc];
                for (dc, &v) in src_row.iter().enumerate() {
                    chunk[dc * rows + r] = v;
                }
            }
        });
}

/// `fft` in place on every contiguous row of `data` (rows of its length),
/// in parallel.
fn fft_rows(data: &mut [Complex64], fft: &dyn Fft<f64>) {
    let len = fft.len();
    data.par_chunks_mut(len * rows_per_task(data.len() / len))
        .for_each_init(
            || vec![Complex64::default(); fft.get_inplace_scratch_len()],
            |scratch, chunk| fft.process_with_scratch(chunk, scratch),
        );
}

/// Half spectrum (layout above) of a real `nx x ny` field in C order.
pub(crate) fn forward(
    heights: &[f64],
    nx: usize,
    ny: usize,
) -> Result<Vec<Complex64>, SurfaceError> {
    let mut spec = vec![Complex64::default(); nx * half_len(ny)];
    Forward::new(nx, ny).run(heights, &mut Vec::new(), &mut spec)?;
    Ok(spec)
}

/// [`forward`] planned once for many fields of one grid, into buffers the
/// caller keeps (a fresh spectrum and work space per field cost their
/// page faults on the largest grids).
pub(crate) struct Forward {
    nx: usize,
    ny: usize,
    along_y: Arc<dyn RealToComplex<f64>>,
    along_x: Arc<dyn Fft<f64>>,
}

impl Forward {
    pub(crate) fn new(nx: usize, ny: usize) -> Self {
        Self {
            nx,
            ny,
            along_y: RealFftPlanner::<f64>::new().plan_fft_forward(ny),
            along_x: FftPlanner::<f64>::new().plan_fft_forward(nx),
        }
    }

    /// `out` (`nx * half_len(ny)` values) the half spectrum of `heights`;
    /// `rows` is work space (resized as needed).
    pub(crate) fn run(
        &self,
        heights: &[f64],
        rows: &mut Vec<Complex64>,
        out: &mut [Complex64],
    ) -> Result<(), SurfaceError> {
        let (nx, ny) = (self.nx, self.ny);
        let nh = half_len(ny);
        debug_assert!(heights.len() == nx * ny && out.len() == nx * nh);
        rows.resize(nx * nh, Complex64::default());
        let r2c = &self.along_y;
        rows.par_chunks_mut(nh)
            .zip(heights.par_chunks(ny))
            .try_for_each_init(
                || (vec![0.0; ny], r2c.make_scratch_vec()),
                |(input, scratch), (out, h)| {
                    input.copy_from_slice(h);
                    r2c.process_with_scratch(input, out, scratch)
                },
            )
            .map_err(|e| SurfaceError::Invalid(format!("real FFT failed: {e}")))?;
        transpose_into(rows, nx, nh, out);
        fft_rows(out, self.along_x.as_ref());
        Ok(())
    }
}

/// Real `nx x ny` field (C order) whose full Hermitian spectrum has the given
/// half spectrum. The `ky = 0` and (even `ny`) `ky = ny/2` rows must already
/// be Hermitian along `kx`; their round-off imaginary parts after the x
/// transform are discarded.
pub(crate) fn inverse(
    mut spec: Vec<Complex64>,
    nx: usize,
    ny: usize,
) -> Result<Vec<f64>, SurfaceError> {
    let mut out = vec![0.0; nx * ny];
    Inverse::new(nx, ny).run(&mut spec, &mut Vec::new(), &mut out)?;
    Ok(out)
}

/// [`inverse`] planned once for many spectra of one grid, into buffers the
/// caller keeps.
pub(crate) struct Inverse {
    nx: usize,
    ny: usize,
    along_x: Arc<dyn Fft<f64>>,
    along_y: Arc<dyn ComplexToReal<f64>>,
}

impl Inverse {
    pub(crate) fn new(nx: usize, ny: usize) -> Self {
        Self {
            nx,
            ny,
            along_x: FftPlanner::<f64>::new().plan_fft_inverse(nx),
            along_y: RealFftPlanner::<f64>::new().plan_fft_inverse(ny),
        }
    }

    /// `out` (`nx * ny` values) the field of the half spectrum `spec`
    /// (transformed in place: work space afterwards); `rows` is work space
    /// (resized as needed).
    pub(crate) fn run(
        &self,
        spec: &mut [Complex64],
        rows: &mut Vec<Complex64>,
        out: &mut [f64],
    ) -> Result<(), SurfaceError> {
        let (nx, ny) = (self.nx, self.ny);
        let nh = half_len(ny);
        debug_assert!(spec.len() == nx * nh && out.len() == nx * ny);
        fft_rows(spec, self.along_x.as_ref());
        rows.resize(nx * nh, Complex64::default());
        transpose_into(spec, nh, nx, rows);
        let c2r = &self.along_y;
        out.par_chunks_mut(ny)
            .zip(rows.par_chunks_mut(nh))
            .try_for_each_init(
                || c2r.make_scratch_vec(),
                |scratch, (o, input)| real_row(c2r.as_ref(), input, o, scratch),
            )
    }
}

/// The real row `out` (`ny` values) of the half spectrum `input` (`ny / 2 +
/// 1` bins along y, used as work space): the imaginary parts of the `ky =
/// 0` and (even `ny`) Nyquist bins, round-off after the x transforms, are
/// discarded, as a real field has none.
fn real_row(
    c2r: &dyn realfft::ComplexToReal<f64>,
    input: &mut [Complex64],
    out: &mut [f64],
    scratch: &mut [Complex64],
) -> Result<(), SurfaceError> {
    input[0].im = 0.0;
    if out.len() % 2 == 0 {
        let last = input.len() - 1;
        input[last].im = 0.0;
    }
    c2r.process_with_scratch(input, out, scratch)
        .map_err(|e| SurfaceError::Invalid(format!("inverse real FFT failed: {e}")))
}

/// Many [`inverse`]s on one grid whose fields are wanted only through
/// their sum and largest value (a profile of maps): the plans and the two
/// spectrum buffers are kept between calls, each half spectrum is filled
/// row by row by the caller and transformed along x in the same pass (a
/// row the caller leaves empty is not transformed), and the real rows are
/// reduced as they come out of the y transforms, never stored.
pub(crate) struct ReducedInverse {
    nx: usize,
    ny: usize,
    rows: std::sync::Arc<dyn rustfft::Fft<f64>>,
    c2r: std::sync::Arc<dyn realfft::ComplexToReal<f64>>,
    /// The half spectrum, `ky` rows of `nx` modes (layout above).
    spec: Vec<Complex64>,
    /// Its transpose after the x transforms: `nx` rows of `ny / 2 + 1`.
    columns: Vec<Complex64>,
}

impl ReducedInverse {
    pub(crate) fn new(nx: usize, ny: usize) -> Self {
        let nh = half_len(ny);
        Self {
            nx,
            ny,
            rows: FftPlanner::<f64>::new().plan_fft_inverse(nx),
            c2r: RealFftPlanner::<f64>::new().plan_fft_inverse(ny),
            spec: vec![Complex64::default(); nx * nh],
            columns: vec![Complex64::default(); nx * nh],
        }
    }

    /// The sum and the largest value of the real field whose half spectrum
    /// is written by `fill(ky, state_row, spec_row)` (`spec_row` zeroed
    /// before; `state_row` the caller's `nx` values for that row of
    /// `state`, which it may update), which returns whether it wrote
    /// anything. The same field as [`inverse`]; the sum is added row by
    /// row in a fixed order.
    pub(crate) fn sum_and_max<S: Send>(
        &mut self,
        state: &mut [S],
        fill: impl Fn(usize, &mut [S], &mut [Complex64]) -> bool + Sync,
    ) -> Result<(f64, f64), SurfaceError> {
        let (nx, ny, nh) = (self.nx, self.ny, half_len(self.ny));
        assert_eq!(state.len(), nx * nh, "one state per mode");
        let rows = &self.rows;
        let scratch_len = rows.get_inplace_scratch_len();
        self.spec
            .par_chunks_mut(nx)
            .zip(state.par_chunks_mut(nx))
            .enumerate()
            .for_each_init(
                || vec![Complex64::default(); scratch_len],
                |scratch, (ky, (row, st))| {
                    row.fill(Complex64::default());
                    if fill(ky, st, row) {
                        rows.process_with_scratch(row, scratch);
                    }
                },
            );
        transpose_into(&self.spec, nh, nx, &mut self.columns);
        let c2r = &self.c2r;
        let parts: Vec<(f64, f64)> = self
            .columns
            .par_chunks_mut(nh)
            .map_init(
                || (vec![0.0; ny], c2r.make_scratch_vec()),
                |(out, scratch), input| {
                    real_row(c2r.as_ref(), input, out, scratch)?;
                    let max = out.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    Ok((out.iter().sum::<f64>(), max))
                },
            )
            .collect::<Result<_, SurfaceError>>()?;
        Ok(parts
            .iter()
            .fold((0.0, f64::NEG_INFINITY), |(s, m), &(rs, rm)| {
                (s + rs, m.max(rm))
            }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Naive 2-D DFT of a real field, full spectrum `[kx * ny + ky]`.
    fn naive_dft(h: &[f64], nx: usize, ny: usize) -> Vec<Complex64> {
        let mut out = vec![Complex64::default(); nx * ny];
        for kx in 0..nx {
            for ky in 0..ny {
                let mut s = Complex64::default();
                for i in 0..nx {
                    for j in 0..ny {
                        let ph = -2.0
                            * std::f64::consts::PI
                            * ((kx * i) as f64 / nx as f64 + (ky * j) as f64 / ny as f64);
                        s += h[i * ny + j] * Complex64::from_polar(1.0, ph);
                    }
                }
                out[kx * ny + ky] = s;
            }
        }
        out
    }

    #[test]
    fn forward_matches_naive_dft_and_inverse_round_trips() {
        for &(nx, ny) in &[(8, 8), (9, 7), (12, 10), (5, 16), (33, 20)] {
            let h: Vec<f64> = (0..nx * ny)
                .map(|k| ((k * 7919) % 101) as f64 / 50.0 - 1.0)
                .collect();
            let spec = forward(&h, nx, ny).unwrap();
            let full = naive_dft(&h, nx, ny);
            let nh = half_len(ny);
            for ky in 0..nh {
                for kx in 0..nx {
                    let d = (spec[ky * nx + kx] - full[kx * ny + ky]).norm();
                    assert!(d < 1e-10, "{nx}x{ny} mode ({kx},{ky}): {d}");
                }
            }
            let back = inverse(spec, nx, ny).unwrap();
            let n = (nx * ny) as f64;
            for (a, b) in back.iter().zip(&h) {
                assert!((a / n - b).abs() < 1e-13, "{nx}x{ny}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn transpose_is_exact() {
        let (r, c) = (37, 53);
        let a: Vec<u32> = (0..(r * c) as u32).collect();
        let mut t = vec![0; r * c];
        transpose_into(&a, r, c, &mut t);
        for i in 0..r {
            for j in 0..c {
                assert_eq!(t[j * r + i], a[i * c + j]);
            }
        }
    }
}
