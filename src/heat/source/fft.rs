//! The inverse transform of a half spectrum to a real grid field, planned
//! once and run on one thread (many small transforms run side by side on
//! the pool's threads): the steps of `surface/height_fft.rs`'s inverse
//! (complex transforms along x of every `ky` column, then real
//! transforms along y), on buffers the caller keeps.

use std::sync::Arc;

use num_complex::Complex64;
use realfft::{ComplexToReal, RealFftPlanner};
use rustfft::{Fft, FftPlanner};

use super::super::error::HeatError;

/// The plans of an `nx x ny` grid.
pub(crate) struct InverseFft {
    nx: usize,
    ny: usize,
    along_x: Arc<dyn Fft<f64>>,
    along_y: Arc<dyn ComplexToReal<f64>>,
}

/// One thread's buffers for [`InverseFft::run`].
pub(crate) struct Buffers {
    rows: Vec<Complex64>,
    scratch_x: Vec<Complex64>,
    scratch_y: Vec<Complex64>,
}

impl InverseFft {
    pub fn new(nx: usize, ny: usize) -> Self {
        Self {
            nx,
            ny,
            along_x: FftPlanner::<f64>::new().plan_fft_inverse(nx),
            along_y: RealFftPlanner::<f64>::new().plan_fft_inverse(ny),
        }
    }

    pub fn buffers(&self) -> Buffers {
        Buffers {
            rows: vec![Complex64::default(); self.nx * (self.ny / 2 + 1)],
            scratch_x: vec![Complex64::default(); self.along_x.get_inplace_scratch_len()],
            scratch_y: self.along_y.make_scratch_vec(),
        }
    }

    /// `out` (C order, axis 0 = x) the unnormalised inverse of the half
    /// spectrum `spec` (`ny / 2 + 1` columns of `nx` modes, consumed).
    pub fn run(
        &self,
        spec: &mut [Complex64],
        out: &mut [f64],
        buf: &mut Buffers,
    ) -> Result<(), HeatError> {
        let (nx, ny) = (self.nx, self.ny);
        let nh = ny / 2 + 1;
        for col in spec.chunks_mut(nx) {
            self.along_x.process_with_scratch(col, &mut buf.scratch_x);
        }
        for (j, col) in spec.chunks(nx).enumerate() {
            for (i, v) in col.iter().enumerate() {
                buf.rows[i * nh + j] = *v;
            }
        }
        for (row, o) in buf.rows.chunks_mut(nh).zip(out.chunks_mut(ny)) {
            row[0].im = 0.0;
            if ny % 2 == 0 {
                row[nh - 1].im = 0.0;
            }
            self.along_y
                .process_with_scratch(row, o, &mut buf.scratch_y)
                .map_err(|e| HeatError::Transform(format!("inverse real FFT failed: {e}")))?;
        }
        Ok(())
    }
}
