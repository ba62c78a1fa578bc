//! Random-phase periodic surfaces whose radial PSD follows a tabulated one
//! (a measured or stitched PSD, [`TabulatedPsd`]; physics.md sections 8
//! and 11).

use std::f64::consts::PI;

use num_complex::Complex64;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{height_fft, BelowTable, HeightMap, SurfaceError, TabulatedPsd};

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
    /// Optional upper cut-off `q1` [1/m]: modes with `|q| > q1` get zero
    /// amplitude, every other mode is unchanged (same amplitude, same
    /// phase), so a surface cut at `q1` holds exactly the long waves of
    /// the uncut one (physics.md section 12). `None`: the table's whole
    /// range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q1: Option<f64>,
    /// What the modes below the table's first row get.
    #[serde(default)]
    pub below: BelowTable,
}

impl SynthParams {
    /// The largest wavenumber the synthesis of `table` gives an amplitude
    /// to (before the grid's Nyquist limit): the table's largest `q`, or
    /// the cut-off `q1` below it [1/m].
    pub fn highest_q(&self, table: &TabulatedPsd) -> f64 {
        table.q_max().min(self.q1.unwrap_or(f64::INFINITY))
    }
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
/// (log-log interpolated, zero outside its range and above the optional
/// cut-off [`SynthParams::q1`]): every mode
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
    if let Some(q1) = p.q1 {
        if !(q1.is_finite() && q1 > 0.0) {
            return Err(SurfaceError::param(
                "q1",
                q1,
                "must be a finite cut-off > 0 (1/m)",
            ));
        }
    }
    let cut = p.q1.unwrap_or(f64::INFINITY);
    let (nx, ny) = (p.nx, p.ny);
    let a = p.length / nx as f64;
    let dqx = 2.0 * PI / (nx as f64 * a);
    let dqy = 2.0 * PI / (ny as f64 * a);
    let sqrt_dq2 = (dqx * dqy).sqrt();
    let spec = random_phase_spectrum(nx, ny, dqx, dqy, p.seed, |qx, qy| {
        let q = (qx * qx + qy * qy).sqrt();
        if q > cut {
            0.0
        } else {
            table.eval_with(q, p.below).sqrt() * sqrt_dq2
        }
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

/// The lattice moments `(sum C dq^2, sum |q|^2 C dq^2)` over the modes
/// [`generate_from_table`] gives an amplitude on the grid of `p` (cut at
/// `p.q1` when set): the mean square height and the spectral mean square
/// slope of the surface it synthesises (Parseval; physics.md section 8).
pub fn table_lattice_moments(table: &TabulatedPsd, p: &SynthParams) -> (f64, f64) {
    let mut m = (0.0, 0.0);
    for_each_mode(p, |q, q2, dq2| {
        let c = table.eval_with(q, p.below) * dq2;
        m = (m.0 + c, m.1 + q2 * c);
    });
    m
}

/// The grid modes of `p` below the table's first row that
/// [`generate_from_table`] gives power to (by [`SynthParams::below`]):
/// their number and their share `sum C dq^2` of the mean square height.
pub fn below_table_modes(table: &TabulatedPsd, p: &SynthParams) -> (usize, f64) {
    let mut out = (0, 0.0);
    for_each_mode(p, |q, _, dq2| {
        if q > 0.0 && q < table.q_min() {
            let c = table.eval_with(q, p.below) * dq2;
            if c > 0.0 {
                out = (out.0 + 1, out.1 + c);
            }
        }
    });
    out
}

/// `f(|q|, |q|^2, dqx dqy)` for every mode of the grid of `p` at or below
/// its cut-off, with the synthesis's signed indices ((-n/2, n/2] for even
/// n).
fn for_each_mode(p: &SynthParams, mut f: impl FnMut(f64, f64, f64)) {
    let (nx, ny) = (p.nx, p.ny);
    let a = p.length / nx as f64;
    let dqx = 2.0 * PI / (nx as f64 * a);
    let dqy = 2.0 * PI / (ny as f64 * a);
    let cut = p.q1.unwrap_or(f64::INFINITY);
    let signed = |k: usize, n: usize| {
        if k <= n / 2 {
            k as f64
        } else {
            k as f64 - n as f64
        }
    };
    for ky in 0..ny {
        let qy = signed(ky, ny) * dqy;
        for kx in 0..nx {
            let qx = signed(kx, nx) * dqx;
            let q2 = qx * qx + qy * qy;
            let q = q2.sqrt();
            if q <= cut {
                f(q, q2, dqx * dqy);
            }
        }
    }
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
                q1: None,
                below: BelowTable::default(),
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
                q1: None,
                below: BelowTable::default(),
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

    fn table() -> TabulatedPsd {
        let q = vec![100.0, 1e3, 2e4];
        let c = vec![1e-20, 1e-20, 1e-20 * 20f64.powf(-3.6)];
        TabulatedPsd::new(q, c, "t").unwrap()
    }

    #[test]
    fn a_cut_keeps_the_lower_modes_and_removes_the_upper_ones() {
        let (n, ny, l) = (32, 24, 0.01);
        let p = SynthParams {
            nx: n,
            ny,
            length: l,
            seed: 9,
            q1: None,
            below: BelowTable::default(),
        };
        let q1 = 6.5 * 2.0 * PI / l;
        let full = generate_from_table(&table(), &p).unwrap();
        let cut = generate_from_table(&table(), &SynthParams { q1: Some(q1), ..p }).unwrap();
        let ff = height_fft::forward(&full.heights, n, ny).unwrap();
        let fc = height_fft::forward(&cut.heights, n, ny).unwrap();
        let big = ff.iter().map(|v| v.norm()).fold(0.0, f64::max);
        let (dqx, dqy) = (2.0 * PI / l, 2.0 * PI / (ny as f64 * l / n as f64));
        let (mut kept, mut removed) = (0, 0);
        for ky in 0..height_fft::half_len(ny) {
            for kx in 0..n {
                let sx = if kx <= n / 2 {
                    kx as f64
                } else {
                    kx as f64 - n as f64
                };
                let q = ((sx * dqx).powi(2) + (ky as f64 * dqy).powi(2)).sqrt();
                let (a, b) = (ff[ky * n + kx], fc[ky * n + kx]);
                // Same mode amplitudes and phases, through two inverse and
                // forward transforms: round-off only.
                if q <= q1 {
                    assert!((a - b).norm() <= 1e-12 * big, "({sx}, {ky}): {a} vs {b}");
                    kept += usize::from(a.norm() > 1e-6 * big);
                } else {
                    assert!(b.norm() <= 1e-12 * big, "({sx}, {ky}) not removed: {b}");
                    removed += usize::from(a.norm() > 1e-6 * big);
                }
            }
        }
        assert!(kept > 50 && removed > 50, "{kept} kept, {removed} removed");
        // The lattice moments are the mean square height (Parseval) and
        // slope of the cut surface.
        let (m0, _) = table_lattice_moments(&table(), &SynthParams { q1: Some(q1), ..p });
        let ms = cut.heights.iter().map(|h| h * h).sum::<f64>() / (n * ny) as f64;
        assert!((m0 - ms).abs() <= 1e-12 * ms, "{m0} vs {ms}");
        let bad = generate_from_table(
            &table(),
            &SynthParams {
                q1: Some(-1.0),
                ..p
            },
        );
        assert!(bad.is_err());
    }
}
