//! The non-negative least-squares fit of a relaxation spectrum to DMA data
//! (`dma`, shifted to one temperature by WLF) with characteristic times in geometric progression
//! (the paper fits SBR with 34 times of ratio e, Fig. 2; physics.md section 2).
//!
//! The fit uses route (b) of physics.md section 2: the generalized Maxwell
//! form `E(w) = E0 + sum_j E_j i w theta_j / (1 + i w theta_j)` is linear in
//! the non-negative unknowns `(E0, E_j)` at fixed `theta_j`; the result is
//! converted exactly to the creep spectrum of Eq. 2 ([`PronySeries::to_creep`]).
//!
//! Weighting: every residual is relative to the measured value of the same
//! component, `(E1_fit - E1) / E1` and `(E2_fit - E2) / E2`. DMA instruments
//! report storage and loss moduli each with a roughly constant relative
//! uncertainty, so this is the maximum-likelihood weighting for such noise, and
//! it keeps the small loss modulus of the rubbery and glassy plateaus (where
//! `E2 << |E|`) from being ignored, which a weighting by `|E|` would do.

use num_complex::Complex64;

use super::nnls::{nnls, ColMajor, NnlsParams};
use super::{CreepSpectrum, MaterialError, PronySeries, PronyTerm};

/// Options of the spectrum fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitParams {
    /// Number of characteristic times (the paper: 34).
    pub terms: usize,
    /// Ratio of consecutive times (the paper: e).
    pub ratio: f64,
    /// Shortest relaxation time \[s\]; `None` centres the geometric grid
    /// (in log scale) on the data's frequency range, so that the margin beyond
    /// the data is the same at both ends.
    pub shortest_time: Option<f64>,
}

impl Default for FitParams {
    fn default() -> Self {
        Self {
            terms: 34,
            ratio: std::f64::consts::E,
            shortest_time: None,
        }
    }
}

/// Quality and shape of a fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitInfo {
    /// Data points used.
    pub points: usize,
    /// RMS of `(E1_fit - E1) / E1` over the data.
    pub rms_relative_storage: f64,
    /// RMS of `(E2_fit - E2) / E2` over the data.
    pub rms_relative_loss: f64,
    /// Largest `|E1_fit - E1| / E1`.
    pub max_relative_storage: f64,
    /// Largest `|E2_fit - E2| / E2`.
    pub max_relative_loss: f64,
    /// Shortest and longest relaxation time of the grid \[s\].
    pub shortest_time: f64,
    pub longest_time: f64,
    /// Decades of margin of the time grid beyond the data, at the high- and
    /// low-frequency ends: `log10(1 / (w_max theta_min))` and
    /// `log10(w_min theta_max)`; negative means the data reach past the grid.
    pub margin_decades: (f64, f64),
    /// The lowest and highest angular frequency of the data \[rad/s\]:
    /// beyond them the spectrum's moduli are extrapolated.
    pub frequency_range: [f64; 2],
    /// Loss tangent of the fit at the lowest data frequency. When it is not
    /// small the data do not reach the rubbery plateau and the relaxed modulus
    /// `E0` is an extrapolation (the fit may place relaxation below the data).
    pub tan_delta_at_lowest_frequency: f64,
    /// Loss tangent of the fit at the highest data frequency. When it is
    /// not small the data do not reach the glassy plateau and the glassy
    /// modulus `E_inf` is an extrapolation.
    pub tan_delta_at_highest_frequency: f64,
    /// The fit's storage modulus `E1` at the highest data frequency \[Pa\]:
    /// how far `E_inf` lies beyond the data.
    pub storage_at_highest_frequency: f64,
    /// Relaxation terms with a positive weight.
    pub nonzero_terms: usize,
    /// NNLS outer iterations.
    pub nnls_iterations: usize,
}

/// A fitted material: the relaxation series, its exact creep equivalent,
/// and the fit quality.
#[derive(Debug, Clone, PartialEq)]
pub struct SpectrumFit {
    /// Generalized Maxwell form as fitted (zero-weight terms removed).
    pub prony: PronySeries,
    /// Creep spectrum of Eq. 2, converted exactly from `prony`.
    pub creep: CreepSpectrum,
    pub info: FitInfo,
}

/// Fit a generalized Maxwell spectrum with `params.terms` relaxation times in
/// geometric progression and non-negative weights (Lawson-Hanson NNLS) to
/// complex moduli `measured[i] = E1 + i E2` at `omega[i]` [rad/s], with the
/// relative weighting described in the module documentation; then convert it
/// exactly to the creep spectrum of Eq. 2.
pub fn fit_spectrum(
    omega: &[f64],
    measured: &[Complex64],
    params: &FitParams,
) -> Result<SpectrumFit, MaterialError> {
    let m = omega.len();
    if m != measured.len() || m < 3 {
        return Err(MaterialError::Fit(format!(
            "need at least 3 matching frequencies and moduli, got {} and {}",
            m,
            measured.len()
        )));
    }
    if params.terms == 0 || params.terms > 1000 {
        return Err(MaterialError::Fit(format!(
            "terms = {} must be between 1 and 1000",
            params.terms
        )));
    }
    if !(params.ratio.is_finite() && params.ratio > 1.0) {
        return Err(MaterialError::Fit(format!(
            "ratio = {} must be a finite number > 1",
            params.ratio
        )));
    }
    for (w, e) in omega.iter().zip(measured) {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !(ok(*w) && ok(e.re) && ok(e.im)) {
            return Err(MaterialError::Fit(format!(
                "data point w = {w} rad/s, E = {} + {} i Pa: frequency, E1 and E2 must be positive and finite",
                e.re, e.im
            )));
        }
    }
    let n = params.terms;
    let wmin = omega.iter().copied().fold(f64::INFINITY, f64::min);
    let wmax = omega.iter().copied().fold(0.0, f64::max);
    let ln_r = params.ratio.ln();
    let first = match params.shortest_time {
        Some(t) if t.is_finite() && t > 0.0 => t,
        Some(t) => {
            return Err(MaterialError::Fit(format!(
                "shortest time {t} s must be positive and finite"
            )))
        }
        None => (-(wmin * wmax).sqrt().ln() - 0.5 * (n - 1) as f64 * ln_r).exp(),
    };
    let times: Vec<f64> = (0..n).map(|j| first * (j as f64 * ln_r).exp()).collect();
    // Every `w tau` and its square must be finite and nonzero for the
    // columns: the grid's span, `ratio^(terms - 1)`, against the data's.
    let reach = |t: f64| {
        let (lo, hi) = (wmin * t, wmax * t);
        lo * lo > 0.0 && (hi * hi).is_finite()
    };
    if !times.iter().all(|&t| reach(t)) {
        return Err(MaterialError::Fit(format!(
            "terms = {n} with ratio = {} spans {:.0} decades of creep times, which with the data's {:.1} decades of frequency leaves double precision; use fewer terms or a smaller ratio",
            if params.ratio < 1e6 {
                params.ratio.to_string()
            } else {
                format!("{:e}", params.ratio)
            },
            (n - 1) as f64 * params.ratio.log10(),
            (wmax / wmin).log10()
        )));
    }

    // Columns: E0, then E_j; rows: real parts / E1, imaginary parts / E2.
    let cols = n + 1;
    let rows = 2 * m;
    let mut a = vec![0.0; rows * cols];
    let b = vec![1.0; rows];
    for (i, (&w, e)) in omega.iter().zip(measured).enumerate() {
        a[i] = 1.0 / e.re;
        for (j, &th) in times.iter().enumerate() {
            let x = w * th;
            let d = 1.0 + x * x;
            a[(j + 1) * rows + i] = x * x / d / e.re;
            a[(j + 1) * rows + m + i] = x / d / e.im;
        }
    }
    // Scale columns to unit norm (positive scaling keeps x >= 0 equivalent).
    let mut scale = vec![1.0; cols];
    for (j, s) in scale.iter_mut().enumerate() {
        let c = &mut a[j * rows..(j + 1) * rows];
        let norm = c.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > 0.0 {
            c.iter_mut().for_each(|v| *v /= norm);
            *s = norm;
        }
    }
    let (x, nn) = nnls(
        ColMajor {
            rows,
            cols,
            data: &a,
        },
        &b,
        NnlsParams::default(),
    )
    .map_err(|e| MaterialError::Fit(e.to_string()))?;
    let coef: Vec<f64> = x.iter().zip(&scale).map(|(v, s)| v / s).collect();
    let e0 = coef[0];
    if e0 <= 0.0 {
        return Err(MaterialError::Fit(
            "the fit gives no relaxed modulus E0: the data must reach the rubbery (low-frequency) plateau"
                .into(),
        ));
    }
    let terms: Vec<PronyTerm> = coef[1..]
        .iter()
        .zip(&times)
        .filter(|(c, _)| **c > 0.0)
        .map(|(&c, &t)| PronyTerm {
            modulus: c,
            time: t,
        })
        .collect();
    let nonzero_terms = terms.len();
    let prony = PronySeries::new(e0, terms)?;
    let creep = prony.to_creep()?;
    let stats = relative_errors(&creep, omega, measured);
    let info = FitInfo {
        points: m,
        rms_relative_storage: stats.0,
        rms_relative_loss: stats.1,
        max_relative_storage: stats.2,
        max_relative_loss: stats.3,
        shortest_time: times[0],
        longest_time: times[n - 1],
        margin_decades: (-(wmax * times[0]).log10(), (wmin * times[n - 1]).log10()),
        frequency_range: [wmin, wmax],
        tan_delta_at_lowest_frequency: {
            let e = creep.modulus(wmin);
            e.im / e.re
        },
        tan_delta_at_highest_frequency: {
            let e = creep.modulus(wmax);
            e.im / e.re
        },
        storage_at_highest_frequency: creep.modulus(wmax).re,
        nonzero_terms,
        nnls_iterations: nn.iterations,
    };
    Ok(SpectrumFit { prony, creep, info })
}

/// `(rms E1, rms E2, max E1, max E2)` relative errors of `model` against data.
fn relative_errors(
    model: &CreepSpectrum,
    omega: &[f64],
    measured: &[Complex64],
) -> (f64, f64, f64, f64) {
    let (mut s1, mut s2, mut m1, mut m2) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (&w, e) in omega.iter().zip(measured) {
        let f = model.modulus(w);
        let r1 = (f.re - e.re) / e.re;
        let r2 = (f.im - e.im) / e.im;
        s1 += r1 * r1;
        s2 += r2 * r2;
        m1 = m1.max(r1.abs());
        m2 = m2.max(r2.abs());
    }
    let k = omega.len().max(1) as f64;
    ((s1 / k).sqrt(), (s2 / k).sqrt(), m1, m2)
}
