//! Stitching the PSDs of several scans of one surface, taken at different
//! sizes and resolutions, into one PSD over the union of their trusted
//! bands (physics.md section 11; the paper's Fig. 5; contact.engineering).
//!
//! Rule: each map scan is trusted over [`super::trusted_band`]
//! (`2 pi / (L_min / 4) <= q <= (2/3) pi / max(dx, dy)`); a PSD given as a
//! table is trusted over its whole range. The trusted radial bins of all
//! scans are gathered into log-spaced bins (`bins_per_decade`) and averaged
//! with weights equal to their number of Fourier modes, so a scan
//! contributes in proportion to the statistical information it holds at
//! that wavenumber. The stitched `q` of a bin is the mode-weighted mean.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::measured::{detrend, psd_topography, trusted_band, Detrend};
use super::{radial_average, SurfaceError, TabulatedPsd, Topography, Window};

/// One scan's radial PSD and the band it is trusted in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScanPsd {
    /// Label (file name).
    pub name: String,
    /// Radial wavenumbers \[1/m\].
    pub q: Vec<f64>,
    /// PSD \[m^4\].
    pub c: Vec<f64>,
    /// Modes per bin (weights).
    pub modes: Vec<f64>,
    /// Trusted band \[1/m\].
    pub q_lo: f64,
    pub q_hi: f64,
}

impl ScanPsd {
    /// The radial PSD of a map after `trend` and `window`, trusted over
    /// [`trusted_band`].
    pub fn from_topography(
        name: &str,
        topo: &Topography,
        trend: Detrend,
        window: Window,
    ) -> Result<Self, SurfaceError> {
        let t = detrend(topo, trend);
        if let Some(why) = super::empty_band_reason(&t) {
            return Err(SurfaceError::Invalid(format!(
                "{name}: {why}, so it adds nothing to the stitched PSD; leave it out"
            )));
        }
        let radial = radial_average(&psd_topography(&t, window)?);
        let (q_lo, q_hi) = trusted_band(&t);
        Ok(Self {
            name: name.to_string(),
            modes: radial.count.iter().map(|&n| n as f64).collect(),
            q: radial.q,
            c: radial.c,
            q_lo,
            q_hi,
        })
    }

    /// A PSD table (`q, C` columns, see [`TabulatedPsd::parse_csv`]),
    /// trusted over its whole range. A column headed `modes` or `count`
    /// gives the weights; without one each row weighs 1.
    pub fn from_csv(path: &Path) -> Result<Self, SurfaceError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SurfaceError::Io {
            path: name.clone(),
            source,
        })?;
        let table = TabulatedPsd::parse_csv(&text, &name)?;
        let mut modes = vec![1.0; table.q().len()];
        let mut lines = text
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with('#'));
        if let Some(header) = lines.next() {
            let cols: Vec<&str> = header.split([',', ';', '\t']).map(str::trim).collect();
            if let Some(k) = cols
                .iter()
                .position(|c| c.starts_with("modes") || c.starts_with("count"))
            {
                let mut w = Vec::new();
                for (row, line) in lines.enumerate() {
                    let v = line
                        .split([',', ';', '\t'])
                        .nth(k)
                        .and_then(|s| s.trim().parse::<f64>().ok())
                        .filter(|v| v.is_finite() && *v > 0.0)
                        .ok_or_else(|| {
                            SurfaceError::Invalid(format!(
                                "{name}: row {}: column '{}' must be a positive number",
                                row + 1,
                                cols[k]
                            ))
                        })?;
                    w.push(v);
                }
                if w.len() == modes.len() {
                    modes = w;
                }
            }
        }
        Ok(Self {
            name,
            q: table.q().to_vec(),
            c: table.c().to_vec(),
            modes,
            q_lo: table.q_min(),
            q_hi: table.q_max(),
        })
    }
}

/// The stitched PSD.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StitchedPsd {
    /// Mode-weighted mean wavenumber per bin \[1/m\].
    pub q: Vec<f64>,
    /// Mode-weighted mean PSD \[m^4\].
    pub c: Vec<f64>,
    /// Modes in the bin (sum over scans).
    pub modes: Vec<f64>,
    /// Scans contributing to the bin.
    pub scans: Vec<usize>,
    pub bins_per_decade: usize,
}

impl StitchedPsd {
    /// `q_per_m,c_m4,modes,scans`; [`TabulatedPsd::parse_csv`] reads it.
    pub fn to_csv(&self) -> String {
        let mut s = String::from("q_per_m,c_m4,modes,scans\n");
        for i in 0..self.q.len() {
            s.push_str(&format!(
                "{:.10e},{:.10e},{},{}\n",
                self.q[i], self.c[i], self.modes[i], self.scans[i]
            ));
        }
        s
    }
}

/// Stitch `scans` in log-spaced bins (see the module doc).
pub fn stitch(scans: &[ScanPsd], bins_per_decade: usize) -> Result<StitchedPsd, SurfaceError> {
    if scans.is_empty() {
        return Err(SurfaceError::Invalid(
            "psd-stitch needs at least one scan".into(),
        ));
    }
    if bins_per_decade == 0 {
        return Err(SurfaceError::param("bins_per_decade", 0, "must be >= 1"));
    }
    for s in scans {
        if !s
            .q
            .iter()
            .zip(&s.c)
            .any(|(q, _)| *q >= s.q_lo && *q <= s.q_hi)
        {
            return Err(SurfaceError::Invalid(format!(
                "{}: no PSD bin inside its trusted band {:.3e}..{:.3e} 1/m (scan too small?)",
                s.name, s.q_lo, s.q_hi
            )));
        }
    }
    let q0 = scans.iter().map(|s| s.q_lo).fold(f64::INFINITY, f64::min);
    let q1 = scans.iter().map(|s| s.q_hi).fold(0.0, f64::max);
    let nb = ((q1 / q0).log10() * bins_per_decade as f64).floor() as usize + 1;
    let mut wq = vec![0.0; nb];
    let mut wc = vec![0.0; nb];
    let mut w = vec![0.0; nb];
    let mut who = vec![Vec::<usize>::new(); nb];
    for (k, s) in scans.iter().enumerate() {
        for i in 0..s.q.len() {
            let (q, c, m) = (s.q[i], s.c[i], s.modes[i]);
            if q < s.q_lo || q > s.q_hi || c.is_nan() || c <= 0.0 {
                continue;
            }
            let b = (((q / q0).log10() * bins_per_decade as f64).floor() as usize).min(nb - 1);
            wq[b] += m * q;
            wc[b] += m * c;
            w[b] += m;
            if who[b].last() != Some(&k) {
                who[b].push(k);
            }
        }
    }
    let mut out = StitchedPsd {
        q: Vec::new(),
        c: Vec::new(),
        modes: Vec::new(),
        scans: Vec::new(),
        bins_per_decade,
    };
    for b in 0..nb {
        if w[b] > 0.0 {
            out.q.push(wq[b] / w[b]);
            out.c.push(wc[b] / w[b]);
            out.modes.push(w[b]);
            out.scans.push(who[b].len());
        }
    }
    if out.q.len() < 2 {
        return Err(SurfaceError::Invalid(
            "the stitched PSD has fewer than 2 bins: use larger scans or more bins per decade"
                .into(),
        ));
    }
    Ok(out)
}
