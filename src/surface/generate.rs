//! Self-affine random surfaces by the spectral method (physics.md section 8;
//! Carbone & Putignano 2014, Section III: `L = 0.01 m`, `q1 = N q_L`, `N = 64`).

use std::f64::consts::PI;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{height_fft, HeightMap, SurfaceError};

/// How the generated surface is scaled: exactly one of a prescribed rms
/// height or rms slope.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normalisation {
    /// `sqrt(<h^2>)` \[m\] (heights have zero mean).
    RmsHeight(f64),
    /// `sqrt(<|grad h|^2>)`, dimensionless (the rms slope of physics.md
    /// section 5, Eq. 10), computed spectrally: `sqrt(sum q^2 C(q) dq^2)`.
    RmsSlope(f64),
}

/// Upper cut-off of the self-affine band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UpperCutoff {
    /// Number of scales `N`: `q1 = N q_L`.
    Scales(f64),
    /// `q1` directly [1/m].
    Q1(f64),
}

/// Anisotropic stretch for testing anisotropy analysis.
///
/// The surface is stretched by the factor `ratio = s` along the in-plane unit
/// vector `e = (cos theta, sin theta)`, `theta = angle_deg` measured from +x
/// towards +y: `h(x) = h_iso(x.e / s, x.e_perp)` with
/// `e_perp = (-sin theta, cos theta)`. In Fourier space the isotropic PSD is
/// evaluated at `q_eff = sqrt((s q.e)^2 + (q.e_perp)^2)`. Then
/// `<(dh/de)^2> / <(dh/de_perp)^2> = 1/s^2` exactly for the continuous PSD
/// (substitute `u = s q.e` in `int (q.e)^2 C d2q`); on the grid the lattice sum
/// agrees up to the discretisation of the cut-offs. `s > 1` gives long
/// correlation along `e` (smaller slopes along `e`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Anisotropy {
    /// Stretch factor `s > 0` along `e(theta)`.
    pub ratio: f64,
    /// `theta` \[degrees\] from +x.
    pub angle_deg: f64,
}

/// Parameters of [`generate`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GenerateParams {
    /// Cells along x (axis 0, sliding direction), `>= 8`; any size, FFTs of
    /// arbitrary length are used.
    pub nx: usize,
    /// Cells along y, `>= 8`.
    pub ny: usize,
    /// Side `L` of the map along x \[m\]; cells are square, `a = L / nx`.
    pub length: f64,
    /// Hurst exponent `H` (`0 < H <= 1`), `H = 3 - D_f`.
    pub hurst: f64,
    /// Upper cut-off `q1` of the self-affine band.
    pub upper: UpperCutoff,
    /// Lower cut-off `q_L` [1/m]; `None`: `2 pi / L`.
    pub ql: Option<f64>,
    /// Roll-off wavenumber `q0` [1/m] (`q_L <= q0 < q1`): the PSD is flat for
    /// `q_L <= q < q0`. `None`: `q0 = q_L` (no roll-off).
    pub rolloff_q0: Option<f64>,
    /// Prescribed rms height or rms slope.
    pub normalisation: Normalisation,
    /// Seed of the random phases (`ChaCha8Rng::seed_from_u64`).
    pub seed: u64,
    /// Optional anisotropic stretch.
    pub anisotropy: Option<Anisotropy>,
}

/// The side lengths accepted \[m\].
pub const LENGTH_RANGE: (f64, f64) = (1e-9, 1e3);

impl Default for GenerateParams {
    /// The paper's surface (Section III): `L = 0.01 m`, `N = 64` scales,
    /// `H = 0.8`, on a 512 x 512 grid; rms height 10 um (the paper does not
    /// give one).
    fn default() -> Self {
        Self {
            nx: 512,
            ny: 512,
            length: 0.01,
            hurst: 0.8,
            upper: UpperCutoff::Scales(64.0),
            ql: None,
            rolloff_q0: None,
            normalisation: Normalisation::RmsHeight(1e-5),
            seed: 0,
            anisotropy: None,
        }
    }
}

/// The target PSD of physics.md section 8:
/// `C(q) = C0 (q/q0)^(-2(H+1))` for `q0 <= q <= q1`, `C(q) = C0` for
/// `q_L <= q < q0`, zero elsewhere; with anisotropy, `q` is replaced by
/// `q_eff` (see [`Anisotropy`]). Normalisation: `sum_q C(q) dqx dqy = <h^2>`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SelfAffinePsd {
    /// Lower cut-off `q_L` [1/m].
    pub ql: f64,
    /// Roll-off `q0` [1/m].
    pub q0: f64,
    /// Upper cut-off `q1` [1/m].
    pub q1: f64,
    /// Hurst exponent.
    pub hurst: f64,
    /// Plateau value `C0` [m^4].
    pub c0: f64,
    /// Optional stretch.
    pub anisotropy: Option<Anisotropy>,
}

impl SelfAffinePsd {
    /// `C` at the isotropic wavenumber `q` (no stretch applied) [m^4].
    pub fn eval_isotropic(&self, q: f64) -> f64 {
        const TOL: f64 = 1e-12;
        if q < self.ql * (1.0 - TOL) || q > self.q1 * (1.0 + TOL) {
            0.0
        } else if q < self.q0 {
            self.c0
        } else {
            self.c0 * (q / self.q0).powf(-2.0 * (self.hurst + 1.0))
        }
    }

    /// `sqrt(C)` at `|q|^2 = q2` (no stretch applied) [m^2]: one `powf` on
    /// `q^2`, no square roots, for the generator's inner loop.
    fn sqrt_eval_isotropic_sq(&self, q2: f64) -> f64 {
        const TOL: f64 = 1e-12;
        let lo = self.ql * (1.0 - TOL);
        let hi = self.q1 * (1.0 + TOL);
        if q2 < lo * lo || q2 > hi * hi {
            0.0
        } else if q2 < self.q0 * self.q0 {
            self.c0.sqrt()
        } else {
            self.c0.sqrt() * (q2 / (self.q0 * self.q0)).powf(-0.5 * (self.hurst + 1.0))
        }
    }

    /// `sqrt(C(qx, qy))` [m^2], with the stretch if any.
    fn sqrt_eval(&self, qx: f64, qy: f64) -> f64 {
        match self.anisotropy {
            None => self.sqrt_eval_isotropic_sq(qx * qx + qy * qy),
            Some(a) => {
                let (s, c) = a.angle_deg.to_radians().sin_cos();
                let qe = a.ratio * (qx * c + qy * s);
                let qp = -qx * s + qy * c;
                self.sqrt_eval_isotropic_sq(qe * qe + qp * qp)
            }
        }
    }

    /// `C(qx, qy)` [m^4], with the stretch if any.
    pub fn eval(&self, qx: f64, qy: f64) -> f64 {
        match self.anisotropy {
            None => self.eval_isotropic(qx.hypot(qy)),
            Some(a) => {
                let (s, c) = a.angle_deg.to_radians().sin_cos();
                let qe = qx * c + qy * s;
                let qp = -qx * s + qy * c;
                self.eval_isotropic((a.ratio * qe).hypot(qp))
            }
        }
    }

    /// Angular average of `C` over the circle `|q| = q` (equal to `C(q)` for
    /// an isotropic PSD; 720-point midpoint rule otherwise).
    pub fn eval_radial(&self, q: f64) -> f64 {
        match self.anisotropy {
            None => self.eval_isotropic(q),
            Some(_) => {
                const M: usize = 720;
                (0..M)
                    .map(|k| {
                        let phi = 2.0 * PI * (k as f64 + 0.5) / M as f64;
                        self.eval(q * phi.cos(), q * phi.sin())
                    })
                    .sum::<f64>()
                    / M as f64
            }
        }
    }
}

impl GenerateParams {
    /// Check the parameters and resolve the cut-offs (with `C0 = 1`).
    pub fn resolve(&self) -> Result<SelfAffinePsd, SurfaceError> {
        let p = self;
        if p.nx < 8 {
            return Err(SurfaceError::param(
                "n",
                p.nx,
                "grid needs at least 8 cells along x",
            ));
        }
        if p.ny < 8 {
            return Err(SurfaceError::param(
                "ny",
                p.ny,
                "grid needs at least 8 cells along y",
            ));
        }
        if !(p.length.is_finite() && p.length > 0.0) {
            return Err(SurfaceError::param(
                "length",
                p.length,
                "must be a finite length > 0 (m)",
            ));
        }
        let (lo, hi) = LENGTH_RANGE;
        if !(lo..=hi).contains(&p.length) {
            return Err(SurfaceError::param(
                "length",
                format!("{:e}", p.length),
                format!("must lie in [{lo:e}, {hi:e}] m (a nanometre to a kilometre: beyond, the heights, gaps and loads leave double precision's useful range)"),
            ));
        }
        if !(p.hurst.is_finite() && p.hurst > 0.0 && p.hurst <= 1.0) {
            return Err(SurfaceError::param(
                "hurst",
                p.hurst,
                "Hurst exponent must satisfy 0 < H <= 1",
            ));
        }
        let ql = match p.ql {
            None => 2.0 * PI / p.length,
            Some(q) if q.is_finite() && q > 0.0 => q,
            Some(q) => {
                return Err(SurfaceError::param(
                    "ql",
                    q,
                    "must be a finite wavenumber > 0 (1/m)",
                ))
            }
        };
        let q1 = match p.upper {
            UpperCutoff::Scales(n) => {
                if !(n.is_finite() && n > 1.0) {
                    return Err(SurfaceError::param(
                        "scales",
                        n,
                        "number of scales N = q1/q_L must be > 1",
                    ));
                }
                n * ql
            }
            UpperCutoff::Q1(q1) => {
                if !(q1.is_finite() && q1 > ql) {
                    return Err(SurfaceError::param(
                        "q1",
                        q1,
                        format!("must exceed q_L = {ql:.6e} 1/m"),
                    ));
                }
                q1
            }
        };
        let q0 = match p.rolloff_q0 {
            None => ql,
            Some(q0) if q0.is_finite() && q0 >= ql && q0 < q1 => q0,
            Some(q0) => {
                return Err(SurfaceError::param(
                    "rolloff_q0",
                    q0,
                    format!("must satisfy q_L = {ql:.6e} <= q0 < q1 = {q1:.6e} (1/m)"),
                ))
            }
        };
        let mut reach = 1.0;
        if let Some(a) = p.anisotropy {
            if !(a.ratio.is_finite() && a.ratio > 0.0) {
                return Err(SurfaceError::param(
                    "anisotropy.ratio",
                    a.ratio,
                    "stretch factor must be finite and > 0",
                ));
            }
            if !a.angle_deg.is_finite() {
                return Err(SurfaceError::param(
                    "anisotropy.angle_deg",
                    a.angle_deg,
                    "angle must be finite",
                ));
            }
            reach = (1.0 / a.ratio).max(1.0);
        }
        let a = p.length / p.nx as f64;
        let nyquist = PI / a;
        if q1 * reach > nyquist * (1.0 + 1e-12) {
            // Within the grid unstretched: the stretch carries the band
            // beyond it, and is what to change.
            if reach > 1.0 && q1 <= nyquist * (1.0 + 1e-12) {
                return Err(SurfaceError::param(
                    "anisotropy.ratio",
                    format!("{:e}", 1.0 / reach),
                    format!(
                        "stretching the band by 1 / ratio = {reach:.3e} carries q1 = {q1:.6e} 1/m to {:.6e} 1/m, beyond the grid's Nyquist wavenumber pi/a = {nyquist:.6e} 1/m; use a ratio of at least {:.3e}, or more cells",
                        q1 * reach,
                        q1 / nyquist
                    ),
                ));
            }
            return Err(SurfaceError::param(
                "q1",
                format!("{:.6e}", q1),
                format!(
                    "the band reaches {:.6e} 1/m, beyond the grid's Nyquist wavenumber pi/a = {nyquist:.6e} 1/m; use more cells (n >= 2 q1 L / (2 pi)) or fewer scales",
                    q1 * reach
                ),
            ));
        }
        match p.normalisation {
            Normalisation::RmsHeight(v) if !(v.is_finite() && v > 0.0) => {
                return Err(SurfaceError::param(
                    "rms_height",
                    v,
                    "must be finite and > 0 (m)",
                ))
            }
            Normalisation::RmsSlope(v) if !(v.is_finite() && v > 0.0) => {
                return Err(SurfaceError::param(
                    "rms_slope",
                    v,
                    "must be finite and > 0",
                ))
            }
            _ => {}
        }
        Ok(SelfAffinePsd {
            ql,
            q0,
            q1,
            hurst: p.hurst,
            c0: 1.0,
            anisotropy: p.anisotropy,
        })
    }
}

/// The spectral moments `(sum C dq^2, sum |q|^2 C dq^2)` over the Fourier
/// modes of the grid of `params` for the PSD with `C0 = 1`: the sums
/// [`generate`] normalises with, from the amplitudes alone (no phases, no
/// transform). A surface whose PSD has the plateau `C0` has the spectral
/// rms height `sqrt(C0 m0)` and rms slope `sqrt(C0 m2)`, so generating it
/// with `rms_slope = sqrt(C0 m2)` reproduces exactly that `C0`: how a
/// magnification study holds `C(q)` fixed while it cuts the band at
/// several `q1` (physics.md section 12).
pub fn lattice_moments(params: &GenerateParams) -> Result<(f64, f64), SurfaceError> {
    let [m0, m2] = lattice_sums(params, |qx, qy| [1.0, qx * qx + qy * qy])?;
    Ok((m0, m2))
}

/// Relative departure of the generated surface's rms-slope ratio from its
/// stretch's `1/s` above which [`anisotropy_warning`] warns.
const ANISOTROPY_RATIO_TOLERANCE: f64 = 0.1;

/// The rms-slope ratio `sqrt(<(dh/de)^2> / <(dh/de_perp)^2>)` of the
/// surface [`generate`] makes from `params` ([`Anisotropy`]: `1/s` for the
/// continuous PSD), from the amplitudes alone as [`lattice_moments`]
/// sums them (the phases do not enter a mean square slope); `None`
/// without a stretch. Infinite where no mode varies across `e`, zero where
/// none varies along it.
pub(crate) fn lattice_slope_ratio(params: &GenerateParams) -> Result<Option<f64>, SurfaceError> {
    let Some(a) = params.anisotropy else {
        return Ok(None);
    };
    let (s, c) = a.angle_deg.to_radians().sin_cos();
    let [along, across] = lattice_sums(params, |qx, qy| {
        let (qe, qp) = (qx * c + qy * s, -qx * s + qy * c);
        [qe * qe, qp * qp]
    })?;
    Ok(Some((along / across).sqrt()))
}

/// A one-line warning where the generated surface's rms-slope ratio along
/// and across the stretch departs from the asked `1/s` by more than 10 %
/// (its modes' sum, the ratio the heights have): the grid holds too few modes along the
/// stretched direction (`s |q.e| <= q1` keeps about `q1 / (s q_L)` of
/// them; above `s = q1 / q_L` only the modes across it, a ridged surface
/// whatever the ratio).
pub fn anisotropy_warning(params: &GenerateParams) -> Result<Option<String>, SurfaceError> {
    match lattice_slope_ratio(params)? {
        Some(got) => slope_ratio_warning(params, got),
        None => Ok(None),
    }
}

/// [`anisotropy_warning`] for the ratio `got` the grid's modes give
/// ([`lattice_slope_ratio`], summed once by a caller that reports it
/// too).
pub(crate) fn slope_ratio_warning(
    params: &GenerateParams,
    got: f64,
) -> Result<Option<String>, SurfaceError> {
    let Some(a) = params.anisotropy else {
        return Ok(None);
    };
    let want = 1.0 / a.ratio;
    if (got / want - 1.0).abs() <= ANISOTROPY_RATIO_TOLERANCE {
        return Ok(None);
    }
    let target = params.resolve()?;
    // Below 1e-9 of the asked ratio (or above 1e9 times it) what is left
    // is the round-off of `cos` and `sin` at a grid axis.
    let realised = if got <= 1e-9 * want || got >= 1e9 * want {
        format!(
            "{got:.1e}, heights that do not vary {} it (a ridged, one-dimensional surface)",
            if got < want { "along" } else { "across" }
        )
    } else {
        format!("{got:.4}")
    };
    Ok(Some(format!(
        "anisotropy.ratio = {} along {} deg asks for an rms-slope ratio (along / across) of {want:.4}; the grid's modes give {realised} (more than {:.0} % off): the stretched band holds about q1 / (ratio q_L) = {:.2} modes along it; bring the ratio closer to 1 or raise q1 / q_L = {:.3}",
        a.ratio,
        a.angle_deg,
        100.0 * ANISOTROPY_RATIO_TOLERANCE,
        target.q1 / (a.ratio * target.ql),
        target.q1 / target.ql
    )))
}

/// `sum_q f(q) C(q) dqx dqy` over the Fourier modes of the grid of
/// `params` for the PSD with `C0 = 1`, `K` weights at once.
fn lattice_sums<const K: usize>(
    params: &GenerateParams,
    f: impl Fn(f64, f64) -> [f64; K] + Sync,
) -> Result<[f64; K], SurfaceError> {
    let target = params.resolve()?;
    let (nx, ny) = (params.nx, params.ny);
    let a = params.length / nx as f64;
    let dqx = 2.0 * PI / (nx as f64 * a);
    let dqy = 2.0 * PI / (ny as f64 * a);
    // Signed indices as the generator uses them: (-n/2, n/2] for even n.
    let signed = |k: usize, n: usize| {
        if k <= n / 2 {
            k as f64
        } else {
            k as f64 - n as f64
        }
    };
    // Row sums in parallel, added in row order: the same bits on any
    // number of threads.
    let add = |mut sum: [f64; K], terms: [f64; K], c: f64| {
        sum.iter_mut().zip(terms).for_each(|(m, t)| *m += t * c);
        sum
    };
    let rows: Vec<[f64; K]> = (0..ny)
        .into_par_iter()
        .map(|ky| {
            let qy = signed(ky, ny) * dqy;
            (0..nx).fold([0.0; K], |sum, kx| {
                let qx = signed(kx, nx) * dqx;
                let s = target.sqrt_eval(qx, qy);
                add(sum, f(qx, qy), s * s * dqx * dqy)
            })
        })
        .collect();
    Ok(rows.iter().fold([0.0; K], |sum, r| add(sum, *r, 1.0)))
}

/// Bytes per cell [`generate`] needs at its peak, roughly: the heights (8),
/// the half spectrum (about 8) and the FFT's work space (about 32).
pub const GENERATE_BYTES_PER_CELL: u64 = 48;

/// Generate a self-affine random surface (physics.md section 8).
///
/// Every Fourier mode `q = (2 pi kx / Lx, 2 pi ky / Ly)` gets the
/// deterministic amplitude `sqrt(C(q) dqx dqy)` (`dqx = 2 pi / Lx`,
/// `dqy = 2 pi / Ly`) and a uniformly random phase; the spectrum is Hermitian
/// (`H(-q) = conj H(q)`; the self-conjugate modes `kx in {0, nx/2}`,
/// `ky in {0, ny/2}` are real with a random sign), so the heights are real.
/// The phase of every mode depends only on the seed and the mode's signed
/// indices (the rule of the table synthesis, `surface::synth`), not on the grid
/// or the number of threads: the same seed gives the same Fourier modes at
/// every resolution, so a refinement study compares discretisations of one
/// surface, not different realisations. The surface is then scaled so that the spectral
/// rms height `sqrt(sum C dq^2)` or rms slope `sqrt(sum |q|^2 C dq^2)` equals
/// the target, and its mean (zero up to round-off, `C(0) = 0`) is removed.
pub fn generate(params: &GenerateParams) -> Result<HeightMap, SurfaceError> {
    generate_with_target(params).map(|(m, _)| m)
}

/// [`generate`], also returning the target PSD with its scaled `C0`.
pub fn generate_with_target(
    params: &GenerateParams,
) -> Result<(HeightMap, SelfAffinePsd), SurfaceError> {
    let mut target = params.resolve()?;
    let (nx, ny) = (params.nx, params.ny);
    // Heights, half spectrum and FFT work space: refuse what cannot fit
    // instead of aborting in an allocation.
    let need = (nx as u64)
        .saturating_mul(ny as u64)
        .saturating_mul(GENERATE_BYTES_PER_CELL);
    crate::io::memory::check_fits(|| format!("{nx} x {ny} surface"), need)
        .map_err(|e| SurfaceError::Invalid(e.to_string()))?;
    let a = params.length / nx as f64;
    let dqx = 2.0 * PI / (nx as f64 * a);
    let dqy = 2.0 * PI / (ny as f64 * a);
    let sqrt_dq2 = (dqx * dqy).sqrt();
    let signed = |k: usize, n: usize| {
        if k <= n / 2 {
            k as f64
        } else {
            k as f64 - n as f64
        }
    };
    let self_conj_row = |ky: usize| ky == 0 || (ny % 2 == 0 && ky == ny / 2);
    let spec = super::synth::random_phase_spectrum(nx, ny, dqx, dqy, params.seed, |qx, qy| {
        target.sqrt_eval(qx, qy) * sqrt_dq2
    });

    // Spectral moments of the unscaled surface: sum C dq^2 and sum |q|^2 C dq^2
    // over the full plane (rows 0 < ky < ny/2 stand for themselves and -ky).
    let moment = |power: i32| {
        height_fft::ordered_sum(&spec, nx, |ky, row| {
            let w = if self_conj_row(ky) { 1.0 } else { 2.0 };
            let qy = ky as f64 * dqy;
            row.iter()
                .enumerate()
                .map(|(kx, v)| {
                    let qx = signed(kx, nx) * dqx;
                    w * (qx * qx + qy * qy).powi(power) * v.norm_sqr()
                })
                .sum()
        })
    };
    let (m0, m2) = (moment(0), moment(1));
    if m0.is_nan() || m0 <= 0.0 {
        let cause = match params.anisotropy {
            // Stretched by `s`, a mode keeps a band wavenumber only where
            // `s |q.e| <= q1`: a large stretch leaves the modes with
            // `q.e = 0` alone, and off the grid's axes there are none.
            Some(a) => format!(
                "anisotropy.ratio = {} stretches every mode's component along {} deg beyond q1 = {:.6e} 1/m; give a smaller ratio (every ratio above q1 / q_L = {:.3} leaves at most the modes across that direction)",
                a.ratio,
                a.angle_deg,
                target.q1,
                target.q1 / target.ql
            ),
            None => "check ql, q1 and the grid size".into(),
        };
        return Err(SurfaceError::Invalid(format!(
            "the prescribed PSD has no Fourier mode on this grid: {cause}"
        )));
    }
    let scale = match params.normalisation {
        Normalisation::RmsHeight(h) => h / m0.sqrt(),
        Normalisation::RmsSlope(s) => s / m2.sqrt(),
    };
    target.c0 = scale * scale;

    let mut heights = height_fft::inverse(spec, nx, ny)?;
    let mean = height_fft::ordered_sum(&heights, ny, |_, r| r.iter().sum()) / heights.len() as f64;
    heights
        .par_iter_mut()
        .for_each(|h| *h = (*h - mean) * scale);
    let map = HeightMap {
        nx,
        ny,
        cell_size: a,
        cell_size_y: a,
        heights,
    };
    Ok((map, target))
}
