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

use super::fft_convolution::SpectralEngine;
use super::{GridOperator, OffsetTable};

/// `u = L p` by padded FFT convolution.
pub struct ToeplitzFft {
    engine: SpectralEngine,
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
        let spectrum = engine.spectrum_of(&wrapped);
        engine.set_multiplier(spectrum);
        Self { engine }
    }

    /// Also provide an approximate inverse as the operator's preconditioner
    /// ([`GridOperator::precondition`]): the inverse of the circulant of the
    /// padded transform, of which `L` is the leading block, restricted to the
    /// grid (`K = R C^-1 R^T`). Modes where the circulant's multiplier is
    /// below `1e-6` of its largest are clamped there.
    pub fn with_preconditioner(mut self) -> Self {
        self.engine.set_inverse_multiplier(1e-6);
        self
    }

    /// Padded transform sizes `(mx, my)`.
    pub fn padded_shape(&self) -> (usize, usize) {
        self.engine.padded_shape()
    }
}

impl GridOperator for ToeplitzFft {
    fn shape(&self) -> (usize, usize) {
        self.engine.shape()
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.engine.apply(x, y);
    }

    fn has_preconditioner(&self) -> bool {
        self.engine.has_inverse()
    }

    fn precondition(&mut self, x: &[f64], y: &mut [f64]) {
        if self.engine.has_inverse() {
            self.engine.apply_inverse(x, y);
        } else {
            y.copy_from_slice(x);
        }
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
