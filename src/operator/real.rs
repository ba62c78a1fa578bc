//! The storage precision of the FFT engine's spectra and transforms
//! (physics.md section 13): f64, or f32 for mixed precision.

use rustfft::num_traits::NumAssign;
use rustfft::FftNum;

/// The storage precision of the FFT engine's spectra and transforms: f64 or f32.
pub trait Real: FftNum + NumAssign + Default + bytemuck::Pod {
    /// Bytes of one value.
    const BYTES: usize;
    /// Relative rounding unit.
    const ROUNDING: f64;
    /// `v` rounded to this precision.
    fn of(v: f64) -> Self;
    /// The value in f64.
    fn wide(self) -> f64;
}

impl Real for f64 {
    const BYTES: usize = 8;
    const ROUNDING: f64 = f64::EPSILON;
    #[inline]
    fn of(v: f64) -> Self {
        v
    }
    #[inline]
    fn wide(self) -> f64 {
        self
    }
}

impl Real for f32 {
    const BYTES: usize = 4;
    const ROUNDING: f64 = f32::EPSILON as f64;
    #[inline]
    fn of(v: f64) -> Self {
        v as f32
    }
    #[inline]
    fn wide(self) -> f64 {
        f64::from(self)
    }
}
