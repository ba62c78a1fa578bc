//! Spectral analysis of measured, non-periodic maps (physics.md section 11):
//! detrending, windowed 2-D and 1-D line PSDs, rms height, slope and
//! curvature from the PSD and from the real-space map, the Hurst exponent,
//! and the band of wavenumbers a scan can be trusted in.

use std::f64::consts::PI;

use num_complex::Complex64;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::psd::{fit_hurst, psd_grid, radial_average, window_weights};
use super::{HurstFit, Psd2d, RadialPsd, SurfaceError, Topography, Window};

/// Polynomial removed from the heights before the PSD.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Detrend {
    /// Keep the heights as they are.
    #[default]
    None,
    /// Remove the mean.
    Mean,
    /// Remove the least-squares plane (tilt of the sample).
    Plane,
    /// Remove the least-squares quadratic `1, x, y, x^2, xy, y^2`
    /// (tilt and bow / curvature from mounting).
    Quadratic,
}

impl Detrend {
    /// The name configs and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Mean => "mean",
            Self::Plane => "plane",
            Self::Quadratic => "quadratic",
        }
    }
}

/// Remove the least-squares polynomial `detrend` from `topo` (missing
/// points are left out of the fit and stay missing). Coordinates are the
/// pixel centres, scaled to `[-1, 1]` for conditioning.
pub fn detrend(topo: &Topography, detrend: Detrend) -> Topography {
    let mut out = topo.clone();
    let terms = match detrend {
        Detrend::None => return out,
        Detrend::Mean => 1,
        Detrend::Plane => 3,
        Detrend::Quadratic => 6,
    };
    let (nx, ny) = (topo.nx, topo.ny);
    let sx = |i: usize| 2.0 * (i as f64 + 0.5) / nx as f64 - 1.0;
    let sy = |j: usize| 2.0 * (j as f64 + 0.5) / ny as f64 - 1.0;
    let basis = |i: usize, j: usize| {
        let (x, y) = (sx(i), sy(j));
        [1.0, x, y, x * x, x * y, y * y]
    };
    // Normal equations, accumulated per row in order (deterministic).
    let parts: Vec<([[f64; 6]; 6], [f64; 6])> = (0..nx)
        .into_par_iter()
        .map(|i| {
            let mut a = [[0.0; 6]; 6];
            let mut b = [0.0; 6];
            for j in 0..ny {
                let h = topo.heights[i * ny + j];
                if h.is_nan() {
                    continue;
                }
                let f = basis(i, j);
                for r in 0..terms {
                    b[r] += f[r] * h;
                    for c in 0..terms {
                        a[r][c] += f[r] * f[c];
                    }
                }
            }
            (a, b)
        })
        .collect();
    let mut a = [[0.0; 6]; 6];
    let mut b = [0.0; 6];
    for (pa, pb) in &parts {
        for r in 0..terms {
            b[r] += pb[r];
            for c in 0..terms {
                a[r][c] += pa[r][c];
            }
        }
    }
    let coef = solve_small(a, b, terms);
    out.heights
        .par_chunks_mut(ny)
        .enumerate()
        .for_each(|(i, row)| {
            for (j, h) in row.iter_mut().enumerate() {
                let f = basis(i, j);
                let p: f64 = (0..terms).map(|r| coef[r] * f[r]).sum();
                *h -= p;
            }
        });
    out
}

/// Gaussian elimination with partial pivoting on the leading `n x n` block;
/// a singular direction gets coefficient 0.
fn solve_small(mut a: [[f64; 6]; 6], mut b: [f64; 6], n: usize) -> [f64; 6] {
    let scale = (0..n).map(|r| a[r][r].abs()).fold(0.0, f64::max);
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))
            .unwrap_or(col);
        a.swap(col, piv);
        b.swap(col, piv);
        if a[col][col].abs() <= 1e-14 * scale {
            continue;
        }
        let pivot_row = a[col];
        for r in col + 1..n {
            let f = a[r][col] / pivot_row[col];
            for (v, p) in a[r][col..n].iter_mut().zip(&pivot_row[col..n]) {
                *v -= f * p;
            }
            b[r] -= f * b[col];
        }
    }
    let mut x = [0.0; 6];
    for r in (0..n).rev() {
        if a[r][r].abs() <= 1e-14 * scale {
            continue;
        }
        let s: f64 = (r + 1..n).map(|c| a[r][c] * x[c]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x
}

/// 2-D PSD of a topography (pixel sizes `dx`, `dy`; see `psd_grid`).
/// Missing points must have been filled.
pub fn psd_topography(topo: &Topography, window: Window) -> Result<Psd2d, SurfaceError> {
    if topo.missing() > 0 {
        return Err(SurfaceError::Invalid(format!(
            "{} missing points: fill them before taking a PSD",
            topo.missing()
        )));
    }
    psd_grid(topo.nx, topo.ny, topo.dx, topo.dy, &topo.heights, window)
}

/// Direction of a line PSD.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// Lines along x (axis 0, the sliding direction), one per y index.
    X,
    /// Lines along y, one per x index.
    Y,
}

/// The 1-D PSD of the lines of a map along one axis, averaged over the
/// lines. Convention: `C1(q) = dx^2 |H(q)|^2 / (2 pi L)` for a line of
/// length `L` sampled every `dx`, so that `Int_{-inf}^{inf} C1 dq =
/// 2 Int_0^inf C1 dq = <h^2>` (listed for `q > 0` only).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinePsd {
    pub axis: Axis,
    /// `2 pi / L` \[1/m\].
    pub dq: f64,
    /// Wavenumbers `k dq`, `k = 1..n/2` \[1/m\].
    pub q: Vec<f64>,
    /// `C1` \[m^3\].
    pub c: Vec<f64>,
    /// Number of lines averaged.
    pub lines: usize,
}

/// Line PSD of `topo` along `axis` with a 1-D `window` per line (mean
/// removed and mean-square rescaled when windowed).
pub fn line_psd(topo: &Topography, axis: Axis, window: Window) -> LinePsd {
    let (n, lines, d) = match axis {
        Axis::X => (topo.nx, topo.ny, topo.dx),
        Axis::Y => (topo.ny, topo.nx, topo.dy),
    };
    let get = |line: usize, k: usize| match axis {
        Axis::X => topo.heights[k * topo.ny + line],
        Axis::Y => topo.heights[line * topo.ny + k],
    };
    let w = window_weights(window, n);
    let norm = w
        .as_ref()
        .map(|w| 1.0 / (w.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt());
    let fft = rustfft::FftPlanner::<f64>::new().plan_fft_forward(n);
    let half = n / 2;
    let length = n as f64 * d;
    let factor = d * d / (2.0 * PI * length);
    let sums: Vec<f64> = (0..lines)
        .into_par_iter()
        .map(|line| {
            let mut buf: Vec<Complex64> =
                (0..n).map(|k| Complex64::new(get(line, k), 0.0)).collect();
            if let (Some(w), Some(norm)) = (&w, norm) {
                let mean = buf.iter().map(|c| c.re).sum::<f64>() / n as f64;
                for (k, c) in buf.iter_mut().enumerate() {
                    c.re = (c.re - mean) * w[k] * norm;
                }
            }
            fft.process(&mut buf);
            buf
        })
        .collect::<Vec<_>>()
        .into_iter()
        .fold(vec![0.0; half + 1], |mut acc, spec| {
            for k in 1..=half {
                acc[k] += spec[k].norm_sqr();
            }
            acc
        });
    let dq = 2.0 * PI / length;
    LinePsd {
        axis,
        dq,
        q: (1..=half).map(|k| k as f64 * dq).collect(),
        c: (1..=half)
            .map(|k| sums[k] * factor / lines as f64)
            .collect(),
        lines,
    }
}

/// The band `[q_lo, q_hi]` \[1/m\] in which a scan's PSD is trusted:
/// `q_lo = 2 pi / (L_min / 4)` (at least four wavelengths in the shorter
/// side: below, few modes, and the window and detrending distort the
/// spectrum) and `q_hi = (2/3) pi / max(dx, dy)` (the last third of the
/// Nyquist range is dropped: tip and optics blur the shortest waves and
/// the finite-difference and aliasing errors are largest there). This is
/// the rule of physics.md section 11, after Jacobs, Junge & Pastewka,
/// Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), Sec. 4 and the
/// reliability cut-offs of contact.engineering.
pub fn trusted_band(topo: &Topography) -> (f64, f64) {
    let lmin = topo.length_x().min(topo.length_y());
    (
        2.0 * PI / (lmin / 4.0),
        2.0 / 3.0 * PI / topo.dx.max(topo.dy),
    )
}

/// Why a scan's PSD has no trusted band ([`trusted_band`] empty: its
/// shorter side holds fewer than 12 of its coarser pixels, four
/// wavelengths of at least three pixels), naming both sides in pixels;
/// `None` when the band is not empty.
pub(crate) fn empty_band_reason(topo: &Topography) -> Option<String> {
    let (lo, hi) = trusted_band(topo);
    (lo >= hi).then(|| {
        format!(
            "the {} x {} map's shorter side is too short for a trusted band of its PSD ({:.3e} to {:.3e} 1/m: four wavelengths across it need at least 12 of its coarser pixels)",
            topo.nx, topo.ny, lo, hi
        )
    })
}

/// Statistics of a measured map, from its PSD and from real space.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeasuredStats {
    pub nx: usize,
    pub ny: usize,
    /// Pixel sides \[m\].
    pub dx: f64,
    pub dy: f64,
    /// Sides \[m\].
    pub length_x: f64,
    pub length_y: f64,
    pub detrend: Detrend,
    pub window: Window,
    /// Points filled by harmonic interpolation (0: none).
    pub filled_points: usize,
    /// `sqrt(<h^2>)` of the detrended map (mean removed) \[m\].
    pub rms_height_real: f64,
    /// `sqrt(sum_{q != 0} C dq^2)` of the windowed PSD \[m\].
    pub rms_height_psd: f64,
    /// `sqrt(<(dh/dx)^2 + (dh/dy)^2>)` by forward differences
    /// ([`super::rms_slope_real`], SurfaceTopography's `rms_gradient`).
    pub rms_slope_real: f64,
    /// `sqrt(sum |q|^2 C dq^2)`.
    pub rms_slope_psd: f64,
    /// The rms slope forward differences see in the PSD, the value the
    /// slope check compares with `rms_slope_real`
    /// ([`super::Psd2d::slope_check_value`]).
    pub rms_slope_fd_psd: f64,
    /// Components along x and y, from the PSD.
    pub rms_slope_x_psd: f64,
    pub rms_slope_y_psd: f64,
    /// rms of the 5-point Laplacian (interior) \[1/m\].
    pub rms_curvature_real: f64,
    /// `sqrt(sum |q|^4 C dq^2)` \[1/m\].
    pub rms_curvature_psd: f64,
    /// Trusted band of this scan \[1/m\] (see [`trusted_band`]).
    pub trusted_q_min: f64,
    pub trusted_q_max: f64,
}

/// Everything `surface stats` reports for a map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Analysis {
    pub stats: MeasuredStats,
    pub radial: RadialPsd,
    pub line_x: LinePsd,
    pub line_y: LinePsd,
    /// Hurst exponent over the given band, or by default over the trusted
    /// band where `C` is above 1e-8 of its peak; `None` if fewer than 3
    /// bins are there.
    pub hurst: Option<HurstFit>,
}

/// Detrend, window, and analyse `topo` (missing points must be filled).
pub fn analyse(
    topo: &Topography,
    trend: Detrend,
    window: Window,
    fit: Option<(f64, f64)>,
) -> Result<Analysis, SurfaceError> {
    let t = detrend(topo, trend);
    let psd = psd_topography(&t, window)?;
    let radial = radial_average(&psd);
    let m0 = psd.integrate(|qx, qy| if qx == 0.0 && qy == 0.0 { 0.0 } else { 1.0 });
    let m2 = psd.slope_tensor();
    let m4 = psd.integrate(|qx, qy| (qx * qx + qy * qy).powi(2));
    let (nx, ny, dx, dy) = (t.nx, t.ny, t.dx, t.dy);
    let h = |i: usize, j: usize| t.heights[i * ny + j];
    let n = (nx * ny) as f64;
    let mean = t.heights.iter().sum::<f64>() / n;
    let var = t.heights.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let (mut c2, mut cnt) = (0.0, 0usize);
    for i in 1..nx.saturating_sub(1) {
        for j in 1..ny.saturating_sub(1) {
            let lap = (h(i + 1, j) - 2.0 * h(i, j) + h(i - 1, j)) / (dx * dx)
                + (h(i, j + 1) - 2.0 * h(i, j) + h(i, j - 1)) / (dy * dy);
            c2 += lap * lap;
            cnt += 1;
        }
    }
    let cnt = cnt.max(1) as f64;
    let (q_lo, q_hi) = trusted_band(&t);
    let hurst = match fit {
        Some((a, b)) => Some(fit_hurst(&radial, a, b)?),
        None => {
            let peak = radial.c.iter().copied().fold(0.0, f64::max);
            let hi = radial
                .q
                .iter()
                .zip(&radial.c)
                .filter(|(q, c)| **q >= q_lo && **q <= q_hi && **c > 1e-8 * peak)
                .map(|(q, _)| *q)
                .fold(q_lo, f64::max);
            fit_hurst(&radial, q_lo, hi).ok()
        }
    };
    let stats = MeasuredStats {
        nx,
        ny,
        dx,
        dy,
        length_x: t.length_x(),
        length_y: t.length_y(),
        detrend: trend,
        window,
        filled_points: topo.filled,
        rms_height_real: var.sqrt(),
        rms_height_psd: m0.sqrt(),
        rms_slope_real: super::rms_slope_real(nx, ny, dx, dy, &t.heights),
        rms_slope_psd: (m2[0][0] + m2[1][1]).sqrt(),
        rms_slope_fd_psd: psd.slope_check_value(window),
        rms_slope_x_psd: m2[0][0].sqrt(),
        rms_slope_y_psd: m2[1][1].sqrt(),
        rms_curvature_real: (c2 / cnt).sqrt(),
        rms_curvature_psd: m4.sqrt(),
        trusted_q_min: q_lo,
        trusted_q_max: q_hi,
    };
    for (what, v) in [
        ("rms height", stats.rms_height_real),
        ("rms height (PSD)", stats.rms_height_psd),
        ("rms slope", stats.rms_slope_real),
        ("rms slope (PSD)", stats.rms_slope_psd),
        ("rms slope of the PSD's differences", stats.rms_slope_fd_psd),
        ("rms curvature", stats.rms_curvature_real),
        ("rms curvature (PSD)", stats.rms_curvature_psd),
    ] {
        if !v.is_finite() {
            return Err(super::psd::overflow(what, v, &t.heights));
        }
    }
    Ok(Analysis {
        stats,
        line_x: line_psd(&t, Axis::X, window),
        line_y: line_psd(&t, Axis::Y, window),
        radial,
        hurst,
    })
}

impl std::fmt::Display for MeasuredStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let e = |v: f64| format!("{v:.6e}");
        let rows: Vec<(&str, String, &str)> = vec![
            ("grid", format!("{} x {}", self.nx, self.ny), "points"),
            ("pixel size x", e(self.dx), "m"),
            ("pixel size y", e(self.dy), "m"),
            ("length x", e(self.length_x), "m"),
            ("length y", e(self.length_y), "m"),
            ("detrend", format!("{:?}", self.detrend).to_lowercase(), ""),
            ("window", format!("{:?}", self.window).to_lowercase(), ""),
            ("filled points", self.filled_points.to_string(), ""),
            ("rms height (real space)", e(self.rms_height_real), "m"),
            ("rms height (PSD)", e(self.rms_height_psd), "m"),
            ("rms slope (real space)", e(self.rms_slope_real), "-"),
            ("rms slope (PSD)", e(self.rms_slope_psd), "-"),
            ("rms slope x (PSD)", e(self.rms_slope_x_psd), "-"),
            ("rms slope y (PSD)", e(self.rms_slope_y_psd), "-"),
            ("rms curvature (real)", e(self.rms_curvature_real), "1/m"),
            ("rms curvature (PSD)", e(self.rms_curvature_psd), "1/m"),
            (
                "trusted band",
                format!("{:.3e}..{:.3e}", self.trusted_q_min, self.trusted_q_max),
                "1/m",
            ),
        ];
        for (k, v, u) in &rows {
            writeln!(f, "{k:<26} {v:>22} {u}")?;
        }
        Ok(())
    }
}
