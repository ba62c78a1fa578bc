//! Random-phase periodic surfaces whose radial PSD follows a tabulated one
//! (a measured or stitched PSD, [`TabulatedPsd`]; physics.md sections 8
//! and 11).

use std::f64::consts::PI;

use num_complex::Complex64;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{height_fft, HeightMap, SurfaceError, TabulatedPsd};

/// Grid and seed of [`generate_from_table`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SynthParams {
    /// Cells along x (>= 8).
    pub nx: usize,
    /// Cells along y (>= 8).
    pub ny: usize,
    /// Side along x \[m\]; cells are square.
    pub length: f64,
    /// Seed of the random phases.
    pub seed: u64,
}

/// The phase `2 pi u`, `u` uniform in `[0, 1)`, of the mode with signed
/// indices `(kx, ky)`, `ky >= 0`: word `2 zigzag(kx)` of the ChaCha8
/// stream `ky` seeded by `seed`. It depends on the mode only, not on the
/// grid, so the same seed gives the same Fourier modes at every
/// resolution.
pub(super) fn phase(seed: u64, kx: i64, ky: u64) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(ky);
    let zigzag = if kx >= 0 {
        2 * kx as u128
    } else {
        2 * (-kx) as u128 - 1
    };
    rng.set_word_pos(2 * zigzag);
    let u: f64 = rng.random();
    2.0 * PI * u
}

/// The half spectrum (`ny / 2 + 1` rows of `nx` modes, as
/// [`height_fft::inverse`] takes it) of a random-phase surface: the mode with
/// signed indices `(kx, ky)` gets `amplitude(qx, qy)` (already times
/// `sqrt(dqx dqy)`) and the phase of [`phase`]; on the self-conjugate rows
/// (`ky = 0`, `ky = ny / 2`) the modes `-kx` are the conjugates of `kx`
/// and the self-conjugate modes are real with the sign of their cosine, so
/// the heights are real. `amplitude` must be even: `a(-q) = a(q)`.
pub(super) fn random_phase_spectrum(
    nx: usize,
    ny: usize,
    dqx: f64,
    dqy: f64,
    seed: u64,
    amplitude: impl Fn(f64, f64) -> f64 + Sync,
) -> Vec<Complex64> {
    let nh = height_fft::half_len(ny);
    let signed = |k: usize| -> i64 {
        if k <= nx / 2 {
            k as i64
        } else {
            k as i64 - nx as i64
        }
    };
    let self_conj_row = |ky: usize| ky == 0 || (ny % 2 == 0 && ky == ny / 2);
    let mut spec = vec![Complex64::default(); nh * nx];
    spec.par_chunks_mut(nx).enumerate().for_each(|(ky, row)| {
        let qy = ky as f64 * dqy;
        for (kx, v) in row.iter_mut().enumerate() {
            let sx = signed(kx);
            let amp = amplitude(sx as f64 * dqx, qy);
            if amp != 0.0 {
                *v = Complex64::from_polar(amp, phase(seed, sx, ky as u64));
            }
        }
        if self_conj_row(ky) {
            // Hermitian along kx: H(-kx) = conj H(kx); self-conjugate modes real.
            for kx in 1..nx {
                let mirror = nx - kx;
                if kx < mirror {
                    row[mirror] = row[kx].conj();
                }
            }
            let mut real_mode = |kx: usize| {
                let v = row[kx];
                let sign = if v.re >= 0.0 { 1.0 } else { -1.0 };
                row[kx] = Complex64::new(sign * v.norm(), 0.0);
            };
            real_mode(0);
            if nx % 2 == 0 {
                real_mode(nx / 2);
            }
        }
    });
    spec
}

/// A random-phase periodic surface whose radial PSD follows `table`
/// (log-log interpolated, zero outside its range): every mode
/// `q = (2 pi kx / Lx, 2 pi ky / Ly)` gets the amplitude
/// `sqrt(C(|q|) dqx dqy)` and a phase that depends only on the seed and
/// the mode (see the phase rule above); `H(-q) = conj H(q)` (real
/// heights); the self-conjugate modes are real with the sign of the cosine
/// of their phase. No rescaling: the mean square height is
/// `sum C dq^2`, the lattice sum of the table over the grid's band, and a
/// coarser grid with the same side and seed holds exactly the same long
/// waves as a finer one.
pub fn generate_from_table(
    table: &TabulatedPsd,
    p: &SynthParams,
) -> Result<HeightMap, SurfaceError> {
    if p.nx < 8 || p.ny < 8 {
        return Err(SurfaceError::param(
            "n",
            format!("{} x {}", p.nx, p.ny),
            "grid needs at least 8 x 8 cells",
        ));
    }
    if !(p.length.is_finite() && p.length > 0.0) {
        return Err(SurfaceError::param(
            "length",
            p.length,
            "must be a finite length > 0 (m)",
        ));
    }
    let (nx, ny) = (p.nx, p.ny);
    let a = p.length / nx as f64;
    let dqx = 2.0 * PI / (nx as f64 * a);
    let dqy = 2.0 * PI / (ny as f64 * a);
    let sqrt_dq2 = (dqx * dqy).sqrt();
    let spec = random_phase_spectrum(nx, ny, dqx, dqy, p.seed, |qx, qy| {
        table.eval((qx * qx + qy * qy).sqrt()).sqrt() * sqrt_dq2
    });
    if spec.iter().all(|v| v.norm_sqr() == 0.0) {
        return Err(SurfaceError::Invalid(format!(
            "the tabulated PSD ({:.3e}..{:.3e} 1/m) has no Fourier mode on this grid \
             ({:.3e}..{:.3e} 1/m): change n or length",
            table.q_min(),
            table.q_max(),
            dqx.min(dqy),
            PI / a
        )));
    }
    let heights = height_fft::inverse(spec, nx, ny)?;
    Ok(HeightMap {
        nx,
        ny,
        cell_size: a,
        cell_size_y: a,
        heights,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_modes_at_every_resolution() {
        let q = vec![100.0, 1e3, 2e4];
        let c = vec![1e-20, 1e-20, 1e-20 * 20f64.powf(-3.6)];
        let t = TabulatedPsd::new(q, c, "t").unwrap();
        let l = 0.01;
        let coarse = generate_from_table(
            &t,
            &SynthParams {
                nx: 32,
                ny: 24,
                length: l,
                seed: 5,
            },
        )
        .unwrap();
        let fine = generate_from_table(
            &t,
            &SynthParams {
                nx: 64,
                ny: 48,
                length: l,
                seed: 5,
            },
        )
        .unwrap();
        let fc = height_fft::forward(&coarse.heights, 32, 24).unwrap();
        let ff = height_fft::forward(&fine.heights, 64, 48).unwrap();
        // Spectra of sums of modes: H_k = N * mode amplitude; compare
        // modes strictly inside the coarse band (|kx| < 16, ky < 12).
        let scale = |n: usize| 1.0 / n as f64;
        let big = ff.iter().map(|v| v.norm()).fold(0.0, f64::max) * scale(64 * 48);
        let mut checked = 0;
        for ky in 0..12usize {
            for kxs in -15i64..16 {
                let idx = |nx: usize| ky * nx + kxs.rem_euclid(nx as i64) as usize;
                let a = fc[idx(32)] * scale(32 * 24);
                let b = ff[idx(64)] * scale(64 * 48);
                assert!(
                    (a - b).norm() <= 1e-9 * big,
                    "mode ({kxs}, {ky}): {a} vs {b}"
                );
                checked += 1;
            }
        }
        assert!(checked > 300);
    }
}
