//! Dynamic mechanical analysis (DMA) data: CSV input, time-temperature
//! superposition by the WLF shift, and the non-negative least-squares fit of a
//! relaxation spectrum with characteristic times in geometric progression
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

use std::path::Path;

use num_complex::Complex64;

use super::nnls::{nnls, ColMajor, NnlsParams};
use super::{CreepSpectrum, MaterialError, PronySeries, PronyTerm};

/// WLF time-temperature shift
/// `log10 a_T = -C1 (T - T_ref) / (C2 + T - T_ref)`, with
/// `E(w, T) = E(w a_T, T_ref)` (physics.md section 2). Temperatures in C
/// (only differences enter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wlf {
    /// `C1` (dimensionless).
    pub c1: f64,
    /// `C2` \[K\].
    pub c2: f64,
    /// Reference temperature `T_ref` \[C\].
    pub reference_temperature: f64,
}

impl Wlf {
    /// Check the constants are finite and `C2 > 0`.
    pub fn new(c1: f64, c2: f64, reference_temperature: f64) -> Result<Self, MaterialError> {
        if !(c1.is_finite() && c2.is_finite() && c2 > 0.0 && reference_temperature.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "WLF constants C1 = {c1}, C2 = {c2} K, T_ref = {reference_temperature} C must be finite with C2 > 0"
            )));
        }
        Ok(Self {
            c1,
            c2,
            reference_temperature,
        })
    }

    /// `log10 a_T` at temperature `t` \[C\]; an error where `C2 + T - T_ref <= 0`
    /// (the WLF form has its pole there and is meaningless below it).
    pub fn log10_shift(&self, t: f64) -> Result<f64, MaterialError> {
        let dt = t - self.reference_temperature;
        let den = self.c2 + dt;
        if !(t.is_finite() && den > 0.0) {
            return Err(MaterialError::Invalid(format!(
                "temperature {t} C is outside the WLF range T > T_ref - C2 = {} C",
                self.reference_temperature - self.c2
            )));
        }
        Ok(-self.c1 * dt / den)
    }

    /// Shift factor `a_T` at temperature `t` \[C\].
    pub fn shift_factor(&self, t: f64) -> Result<f64, MaterialError> {
        Ok(10f64.powf(self.log10_shift(t)?))
    }

    /// The frequency at temperature `to` with the same response as `omega` at
    /// temperature `from`: `omega a_T(from) / a_T(to)`.
    pub fn shift_frequency(&self, omega: f64, from: f64, to: f64) -> Result<f64, MaterialError> {
        Ok(omega * 10f64.powf(self.log10_shift(from)? - self.log10_shift(to)?))
    }
}

/// One DMA measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DmaPoint {
    /// Angular frequency `w` [rad/s].
    pub omega: f64,
    /// Storage modulus `E1` \[Pa\].
    pub storage: f64,
    /// Loss modulus `E2` \[Pa\].
    pub loss: f64,
    /// Test temperature \[C\], when the file has a `temperature_c` column.
    pub temperature: Option<f64>,
}

/// A DMA data set read from CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct DmaData {
    /// Where it came from (for messages and provenance).
    pub source: String,
    pub points: Vec<DmaPoint>,
}

/// Accepted column names (lower case) and their meaning.
const FREQ_HZ: &[&str] = &["frequency_hz", "f_hz"];
const FREQ_RAD: &[&str] = &["omega_rad_s", "frequency_rad_s", "angular_frequency_rad_s"];
const STORAGE: &[&str] = &["e1_pa", "storage_modulus_pa"];
const LOSS: &[&str] = &["e2_pa", "loss_modulus_pa"];
const TEMP: &[&str] = &["temperature_c"];

impl DmaData {
    /// Read a CSV file (see [`DmaData::parse`]).
    pub fn read(path: &Path) -> Result<Self, MaterialError> {
        let text = std::fs::read_to_string(path).map_err(|e| MaterialError::Data {
            source_name: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parse CSV text. Lines starting with `#` and blank lines are skipped; the
    /// first other line is the header. Columns (case-insensitive): frequency as
    /// `frequency_hz` \[Hz\] or `omega_rad_s` [rad/s] (exactly one), `e1_pa` and
    /// `e2_pa` \[Pa\], optional `temperature_c` \[C\]; other columns are ignored.
    /// Every frequency, `E1` and `E2` must be positive and finite.
    pub fn parse(text: &str, source: &str) -> Result<Self, MaterialError> {
        let err = |line: usize, message: String| MaterialError::Data {
            source_name: if line > 0 {
                format!("{source} line {line}")
            } else {
                source.to_string()
            },
            message,
        };
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (hline, header) = lines.next().ok_or_else(|| {
            err(
                0,
                "no header line (expected e.g. frequency_hz,e1_pa,e2_pa)".into(),
            )
        })?;
        let names: Vec<String> = header
            .split(',')
            .map(|s| s.trim().trim_matches('"').to_ascii_lowercase())
            .collect();
        let find = |aliases: &[&str]| -> Result<Option<usize>, MaterialError> {
            let hits: Vec<usize> = names
                .iter()
                .enumerate()
                .filter(|(_, n)| aliases.contains(&n.as_str()))
                .map(|(i, _)| i)
                .collect();
            match hits.len() {
                0 => Ok(None),
                1 => Ok(Some(hits[0])),
                _ => Err(err(
                    hline,
                    format!("more than one column named {}", aliases.join(" / ")),
                )),
            }
        };
        let hz = find(FREQ_HZ)?;
        let rad = find(FREQ_RAD)?;
        let (fcol, to_rad) = match (hz, rad) {
            (Some(c), None) => (c, 2.0 * std::f64::consts::PI),
            (None, Some(c)) => (c, 1.0),
            (Some(_), Some(_)) => {
                return Err(err(
                    hline,
                    "both frequency_hz and omega_rad_s columns given; keep one".into(),
                ))
            }
            (None, None) => {
                return Err(err(
                    hline,
                    "missing frequency column: frequency_hz (Hz) or omega_rad_s (rad/s)".into(),
                ))
            }
        };
        let e1col = find(STORAGE)?.ok_or_else(|| {
            err(
                hline,
                "missing column e1_pa (storage modulus E1, Pa)".into(),
            )
        })?;
        let e2col = find(LOSS)?
            .ok_or_else(|| err(hline, "missing column e2_pa (loss modulus E2, Pa)".into()))?;
        let tcol = find(TEMP)?;
        let mut points = Vec::new();
        for (ln, line) in lines {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let cell = |c: usize| -> Result<f64, MaterialError> {
                let raw = cells.get(c).copied().ok_or_else(|| {
                    err(
                        ln,
                        format!("has {} cells, column {} is missing", cells.len(), names[c]),
                    )
                })?;
                let v: f64 = raw.trim_matches('"').parse().map_err(|_| {
                    err(ln, format!("column {}: '{raw}' is not a number", names[c]))
                })?;
                if !v.is_finite() {
                    return Err(err(
                        ln,
                        format!("column {}: '{raw}' is not finite", names[c]),
                    ));
                }
                Ok(v)
            };
            let f = cell(fcol)?;
            let e1 = cell(e1col)?;
            let e2 = cell(e2col)?;
            let t = tcol.map(cell).transpose()?;
            for (v, c, what) in [(f, fcol, "frequency"), (e1, e1col, "E1"), (e2, e2col, "E2")] {
                if v <= 0.0 {
                    return Err(err(
                        ln,
                        format!("column {}: {what} = {v} must be positive", names[c]),
                    ));
                }
            }
            points.push(DmaPoint {
                omega: f * to_rad,
                storage: e1,
                loss: e2,
                temperature: t,
            });
        }
        if points.len() < 3 {
            return Err(err(
                0,
                format!("{} data rows; at least 3 are needed", points.len()),
            ));
        }
        Ok(Self {
            source: source.to_string(),
            points,
        })
    }

    /// The distinct test temperatures, ascending (empty without a
    /// `temperature_c` column).
    pub fn temperatures(&self) -> Vec<f64> {
        let mut t: Vec<f64> = self.points.iter().filter_map(|p| p.temperature).collect();
        t.sort_by(f64::total_cmp);
        t.dedup();
        t
    }

    /// The data as a master curve at temperature `target` \[C\]:
    /// each frequency is shifted by `a_T(T) / a_T(target)` (WLF). Without WLF
    /// constants the data must be at one temperature, which must equal
    /// `target` if one is given. Returns the points and the temperature they
    /// now describe (None if unknown).
    pub fn reduced(
        &self,
        wlf: Option<&Wlf>,
        target: Option<f64>,
    ) -> Result<(Vec<DmaPoint>, Option<f64>), MaterialError> {
        let temps = self.temperatures();
        let src = || self.source.clone();
        match wlf {
            None => {
                if temps.len() > 1 {
                    return Err(MaterialError::Data {
                        source_name: src(),
                        message: format!(
                            "data at {} temperatures need WLF constants (--wlf C1,C2,TREF) to build a master curve",
                            temps.len()
                        ),
                    });
                }
                let data_t = temps.first().copied();
                match (target, data_t) {
                    (Some(t), Some(d)) if t != d => Err(MaterialError::Data {
                        source_name: src(),
                        message: format!(
                            "data are at {d} C; shifting to {t} C needs WLF constants (--wlf C1,C2,TREF)"
                        ),
                    }),
                    (Some(t), None) => Err(MaterialError::Data {
                        source_name: src(),
                        message: format!(
                            "no temperature_c column: cannot shift to {t} C"
                        ),
                    }),
                    _ => Ok((self.points.clone(), data_t)),
                }
            }
            Some(w) => {
                if self.points.iter().any(|p| p.temperature.is_none()) {
                    return Err(MaterialError::Data {
                        source_name: src(),
                        message: "WLF shift needs a temperature_c column".into(),
                    });
                }
                let to = target.unwrap_or(w.reference_temperature);
                let mut out = Vec::with_capacity(self.points.len());
                for p in &self.points {
                    let from = p.temperature.unwrap_or(to);
                    out.push(DmaPoint {
                        omega: w.shift_frequency(p.omega, from, to)?,
                        ..*p
                    });
                }
                Ok((out, Some(to)))
            }
        }
    }
}

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
    /// Loss tangent of the fit at the lowest data frequency. When it is not
    /// small the data do not reach the rubbery plateau and the relaxed modulus
    /// `E0` is an extrapolation (the fit may place relaxation below the data).
    pub tan_delta_at_lowest_frequency: f64,
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
        tan_delta_at_lowest_frequency: {
            let e = creep.modulus(wmin);
            e.im / e.re
        },
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_units_and_comments() {
        let text = "# comment\nomega_rad_s, E1_Pa ,e2_pa\n1,2,3\n\n# x\n10,20,30\n100,200,300\n";
        let d = DmaData::parse(text, "t").unwrap();
        assert_eq!(d.points.len(), 3);
        assert_eq!(d.points[1].omega, 10.0);
        let hz = DmaData::parse("frequency_hz,e1_pa,e2_pa\n1,2,3\n2,2,3\n3,2,3\n", "t").unwrap();
        assert!((hz.points[0].omega - 2.0 * std::f64::consts::PI).abs() < 1e-15);
    }

    #[test]
    fn wlf_is_zero_at_reference_and_composes() {
        let w = Wlf::new(8.86, 101.6, 17.0).unwrap();
        assert_eq!(w.log10_shift(17.0).unwrap(), 0.0);
        assert!(w.log10_shift(0.0).unwrap() > 0.0, "colder is slower");
        assert!(w.log10_shift(17.0 - 101.6).is_err());
    }
}
