//! Real-to-complex and complex-to-real FFTs of the FFT engine's rows
//! ([`super::fft_convolution`]).
//!
//! A real row of even length `n` is transformed as a complex one of length
//! `m = n / 2` (`z_j = x_{2j} + i x_{2j+1}`, rustfft), then split into the
//! `m + 1` bins of the real transform,
//! `X_k = (Z_k + conj Z_{m-k}) / 2 - (i / 2) w^k (Z_k - conj Z_{m-k})`,
//! `w = exp(-2 pi i / n)`; the inverse merges the bins into `Z` first
//! (the standard packing of a real FFT into a half-length complex one).
//!
//! This is what the `realfft` crate (3.5) does, with the same operations in
//! the same order and the inner FFT its planner picks, so the bins equal
//! `realfft`'s bit for bit (unit tests). Only the split and merge loops are
//! written differently: they index both ends of the row instead of zipping
//! a reversed iterator. On the 2-core test machine (one thread, 2048 rows
//! of 2048) the f32 split takes 1.6 ms against `realfft`'s 3.8 (f64: 2.9
//! against 3.4), so an f32 row transform takes 8.3 ms instead of 10.4
//! (BENCHMARKS.md, "Where an f32 product's time goes"). (Explicit SIMD of
//! the same loops was tried: on that machine, an AMD Zen 1, 128-bit SSE
//! was no faster than this scalar loop and 256-bit AVX slower.) Odd
//! lengths, which have no split step, are `realfft`'s own transforms.

use std::sync::Arc;

use num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

use super::real::Real;

/// Forward and inverse real transforms of rows of one length.
pub(crate) struct RealRows<U: Real> {
    kind: Kind<U>,
}

enum Kind<U: Real> {
    /// Even length: the half-length complex FFTs and the split/merge
    /// twiddles.
    Even(Box<EvenRows<U>>),
    /// Odd length: `realfft`'s transforms.
    Odd {
        r2c: Arc<dyn RealToComplex<U>>,
        c2r: Arc<dyn ComplexToReal<U>>,
    },
}

struct EvenRows<U: Real> {
    /// Half length `m = n / 2`.
    m: usize,
    fwd: Arc<dyn Fft<U>>,
    inv: Arc<dyn Fft<U>>,
    /// `w^k / 2` for `k = 1 ..`: the split's twiddles.
    split: Vec<Complex<U>>,
    /// `conj w^k`: the merge's twiddles.
    merge: Vec<Complex<U>>,
}

/// `exp(-2 pi i k / n)`, the angle in f64 and rounded to `U` (as `realfft`
/// computes its twiddles).
fn twiddle<U: Real>(k: usize, n: usize) -> Complex<U> {
    let angle = -2.0 * std::f64::consts::PI / n as f64 * k as f64;
    Complex::new(U::of(angle.cos()), U::of(angle.sin()))
}

impl<U: Real> RealRows<U> {
    /// Plans for rows of `n` reals (`n / 2 + 1` bins).
    pub(crate) fn new(n: usize) -> Self {
        assert!(n > 0, "rows must be non-empty");
        if n % 2 == 1 {
            let mut planner = RealFftPlanner::<U>::new();
            return Self {
                kind: Kind::Odd {
                    r2c: planner.plan_fft_forward(n),
                    c2r: planner.plan_fft_inverse(n),
                },
            };
        }
        let m = n / 2;
        let mut planner = FftPlanner::<U>::new();
        // Pairs (k, m - k) for 0 < k < m - k.
        let pairs = m.div_ceil(2) - 1;
        let half = U::of(0.5);
        Self {
            kind: Kind::Even(Box::new(EvenRows {
                m,
                fwd: planner.plan_fft_forward(m),
                inv: planner.plan_fft_inverse(m),
                split: (1..=pairs).map(|k| twiddle::<U>(k, n) * half).collect(),
                merge: (1..=pairs).map(|k| twiddle::<U>(k, n).conj()).collect(),
            })),
        }
    }

    /// Complex values of scratch that [`Self::forward`] and
    /// [`Self::inverse`] need.
    pub(crate) fn scratch_len(&self) -> usize {
        match &self.kind {
            Kind::Even(e) => e
                .fwd
                .get_outofplace_scratch_len()
                .max(e.inv.get_outofplace_scratch_len()),
            Kind::Odd { r2c, c2r } => r2c.get_scratch_len().max(c2r.get_scratch_len()),
        }
    }

    /// The `n / 2 + 1` bins of the real row `input` into `output`
    /// (unnormalised; `input` is used as work space).
    pub(crate) fn forward(
        &self,
        input: &mut [U],
        output: &mut [Complex<U>],
        scratch: &mut [Complex<U>],
    ) {
        match &self.kind {
            Kind::Even(e) => {
                let m = e.m;
                assert!(input.len() == 2 * m && output.len() == m + 1);
                let z: &mut [Complex<U>] = bytemuck::cast_slice_mut(input);
                e.fwd
                    .process_outofplace_with_scratch(z, &mut output[..m], scratch);
                split(output, &e.split);
            }
            Kind::Odd { r2c, .. } => r2c
                .process_with_scratch(input, output, scratch)
                .expect("buffer sizes match the plan"),
        }
    }

    /// The real row of the bins `input` into `output` (unnormalised:
    /// `n` times the inverse DFT). The imaginary parts of the first bin
    /// (and of the last for even `n`), round-off for a real row, are set
    /// to zero first; `input` is used as work space.
    pub(crate) fn inverse(
        &self,
        input: &mut [Complex<U>],
        output: &mut [U],
        scratch: &mut [Complex<U>],
    ) {
        input[0].im = U::zero();
        if output.len() % 2 == 0 {
            input[output.len() / 2].im = U::zero();
        }
        match &self.kind {
            Kind::Even(e) => {
                let m = e.m;
                assert!(input.len() == m + 1 && output.len() == 2 * m);
                merge(input, &e.merge);
                let z: &mut [Complex<U>] = bytemuck::cast_slice_mut(output);
                e.inv
                    .process_outofplace_with_scratch(&mut input[..m], z, scratch);
            }
            Kind::Odd { c2r, .. } => c2r
                .process_with_scratch(input, output, scratch)
                .expect("buffer sizes match the plan"),
        }
    }
}

/// The split step on `Z` (bins `0 .. m` of `bins`) into the `m + 1` bins of
/// the real transform, in place; `tw` holds `w^k / 2` for the pairs.
fn split<U: Real>(bins: &mut [Complex<U>], tw: &[Complex<U>]) {
    let m = bins.len() - 1;
    let first = bins[0];
    bins[0] = Complex::new(first.re + first.im, U::zero());
    bins[m] = Complex::new(first.re - first.im, U::zero());
    let (left, right) = pair_runs(bins, tw.len());
    split_pairs(left, right, tw);
    if m % 2 == 0 {
        // The middle bin pairs with itself: conj Z_{m/2}.
        bins[m / 2].im = -bins[m / 2].im;
    }
}

/// The merge step, the inverse of [`split`]: the `m + 1` bins into `Z`
/// (bins `0 .. m`), in place; `tw` holds `conj w^k` for the pairs.
fn merge<U: Real>(bins: &mut [Complex<U>], tw: &[Complex<U>]) {
    let m = bins.len() - 1;
    let (first, last) = (bins[0], bins[m]);
    let (sum, diff) = (first + last, first - last);
    bins[0] = Complex::new(sum.re - sum.im, diff.re - diff.im);
    let (left, right) = pair_runs(bins, tw.len());
    merge_pairs(left, right, tw);
    if m % 2 == 0 {
        let c = bins[m / 2];
        bins[m / 2] = (c + c).conj();
    }
}

/// Bins `1 ..= pairs` and `m - pairs .. m` of `bins` (`m + 1` of them): the
/// partner of `left[k]` (bin `k + 1`) is `right[pairs - 1 - k]`.
fn pair_runs<U>(bins: &mut [U], pairs: usize) -> (&mut [U], &mut [U]) {
    let m = bins.len() - 1;
    let (head, tail) = bins.split_at_mut(m - pairs);
    (&mut head[1..=pairs], &mut tail[..pairs])
}

/// The split of the pairs (`realfft`'s arithmetic).
fn split_pairs<U: Real>(left: &mut [Complex<U>], right: &mut [Complex<U>], tw: &[Complex<U>]) {
    let pairs = tw.len();
    let half = U::of(0.5);
    for k in 0..pairs {
        let (a, b, w) = (left[k], right[pairs - 1 - k], tw[k]);
        let (sum, diff) = (a + b, a - b);
        let half_sum_re = half * sum.re;
        let half_diff_im = half * diff.im;
        let re = sum.im * w.re + diff.re * w.im;
        let im = sum.im * w.im - diff.re * w.re;
        left[k] = Complex::new(half_sum_re + re, half_diff_im + im);
        right[pairs - 1 - k] = Complex::new(half_sum_re - re, im - half_diff_im);
    }
}

/// The merge of the pairs (`realfft`'s arithmetic).
fn merge_pairs<U: Real>(left: &mut [Complex<U>], right: &mut [Complex<U>], tw: &[Complex<U>]) {
    let pairs = tw.len();
    for k in 0..pairs {
        let (a, b, w) = (left[k], right[pairs - 1 - k], tw[k]);
        let (sum, diff) = (a + b, a - b);
        let re = sum.im * w.re + diff.re * w.im;
        let im = sum.im * w.im - diff.re * w.re;
        left[k] = Complex::new(sum.re - re, diff.im - im);
        right[pairs - 1 - k] = Complex::new(sum.re + re, -im - diff.im);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic real row.
    fn row<U: Real>(n: usize, seed: usize) -> Vec<U> {
        (0..n)
            .map(|k| U::of((((k + seed) * 7919) % 1013) as f64 / 1013.0 - 0.37))
            .collect()
    }

    fn realfft_forward<U: Real>(x: &[U]) -> Vec<Complex<U>> {
        let plan = RealFftPlanner::<U>::new().plan_fft_forward(x.len());
        let mut input = x.to_vec();
        let mut out = plan.make_output_vec();
        plan.process(&mut input, &mut out).unwrap();
        out
    }

    fn realfft_inverse<U: Real>(bins: &[Complex<U>], n: usize) -> Vec<U> {
        let plan = RealFftPlanner::<U>::new().plan_fft_inverse(n);
        let mut input = bins.to_vec();
        let mut out = plan.make_output_vec();
        plan.process(&mut input, &mut out).unwrap();
        out
    }

    fn ours<U: Real>(n: usize) -> (Vec<Complex<U>>, Vec<U>, Vec<Complex<U>>) {
        let rows = RealRows::<U>::new(n);
        let mut scratch = vec![Complex::<U>::default(); rows.scratch_len()];
        let mut x = row::<U>(n, n);
        let mut bins = vec![Complex::<U>::default(); n / 2 + 1];
        rows.forward(&mut x, &mut bins, &mut scratch);
        let forward = bins.clone();
        // Inverse of a spectrum that is not the forward one's (so the merge
        // sees arbitrary bins), with round-off in the imaginary parts of
        // the first and (even n) last bins, which the inverse drops.
        let mut spectrum: Vec<Complex<U>> = (0..=n / 2)
            .map(|k| {
                let v = row::<U>(2, 3 * k + 1);
                Complex::new(v[0], v[1])
            })
            .collect();
        let mut input = spectrum.clone();
        spectrum[0].im = U::zero();
        if n % 2 == 0 {
            spectrum[n / 2].im = U::zero();
        }
        let mut out = vec![U::zero(); n];
        rows.inverse(&mut input, &mut out, &mut scratch);
        (forward, out, spectrum)
    }

    /// Both transforms equal `realfft`'s bit for bit, for lengths 2 and 4
    /// (no pairs), `n / 2` odd and even (with and without a middle bin), odd
    /// lengths (`realfft`'s own) and the engine's sizes.
    fn equals_realfft<U: Real>() {
        for n in [
            1, 2, 3, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 30, 34, 64, 100, 126, 1000, 2048,
        ] {
            let x = row::<U>(n, n);
            let (forward, inverse, spectrum) = ours::<U>(n);
            assert_eq!(forward, realfft_forward(&x), "forward, n = {n}");
            assert_eq!(inverse, realfft_inverse(&spectrum, n), "inverse, n = {n}");
        }
    }

    #[test]
    fn f64_rows_equal_realfft_bit_for_bit() {
        equals_realfft::<f64>();
    }

    #[test]
    fn f32_rows_equal_realfft_bit_for_bit() {
        equals_realfft::<f32>();
    }
}
