//! Power spectral density and statistics of height maps (physics.md
//! sections 5 and 8).
//!
//! Normalisation (Persson's convention, the one of the paper's Eq. 11):
//! `C(q) = (2 pi)^-2 int <h(x) h(0)> e^{-i q.x} d2x`; on an `nx x ny` grid of
//! square cells `a` with `Lx = nx a`, `Ly = ny a`,
//! `C(q_k) = |a^2 H_k|^2 / ((2 pi)^2 Lx Ly)`, `H_k = sum_x h(x) e^{-i q_k.x}`,
//! so that `sum_k C(q_k) dqx dqy = <h^2>` exactly (Parseval), with
//! `dqx = 2 pi / Lx`, `dqy = 2 pi / Ly`.

use std::f64::consts::PI;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{height_fft, HeightMap, SurfaceError};

/// Taper applied before the FFT.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Window {
    /// No window: the map is treated as one period of a periodic surface
    /// (generated surfaces). `sum C dq^2 = <h^2>` holds to round-off, the
    /// `q = 0` mode carries the squared mean.
    #[default]
    None,
    /// Separable periodic Hann window `w(i) = (1 - cos(2 pi i / n)) / 2` on
    /// both axes, for measured, non-periodic maps (suppresses the leakage of
    /// the edge discontinuities into high `q`). The mean is removed first and
    /// the windowed map is divided by `sqrt(<w^2>)`, so `sum C dq^2 = <h^2>`
    /// holds on average over realisations, not exactly.
    Hann,
    /// Separable periodic 4-term Blackman-Harris window (Harris, Proc. IEEE
    /// 66, 51, 1978: `a = 0.35875, 0.48829, 0.14128, 0.01168`): lower side
    /// lobes than Hann for steep spectra, wider main lobe; same mean
    /// removal and mean-square rescaling.
    BlackmanHarris,
}

/// The 2-D PSD `C(q)` on the FFT grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Psd2d {
    pub nx: usize,
    pub ny: usize,
    /// `2 pi / Lx` [1/m].
    pub dqx: f64,
    /// `2 pi / Ly` [1/m].
    pub dqy: f64,
    /// `C` [m^4] at `values[kx * ny + ky]`, FFT order along both axes (index
    /// `k > n/2` stands for `k - n`).
    pub values: Vec<f64>,
}

fn signed(k: usize, n: usize) -> f64 {
    if k <= n / 2 {
        k as f64
    } else {
        k as f64 - n as f64
    }
}

impl Psd2d {
    /// Wavevector `(qx, qy)` [1/m] of the mode `(kx, ky)`.
    pub fn q(&self, kx: usize, ky: usize) -> (f64, f64) {
        (
            signed(kx, self.nx) * self.dqx,
            signed(ky, self.ny) * self.dqy,
        )
    }

    /// `sum_q f(qx, qy) C(q) dqx dqy`, parallel over rows.
    pub fn integrate(&self, f: impl Fn(f64, f64) -> f64 + Sync) -> f64 {
        let dq2 = self.dqx * self.dqy;
        height_fft::ordered_sum(&self.values, self.ny, |kx, row| {
            let qx = signed(kx, self.nx) * self.dqx;
            row.iter()
                .enumerate()
                .map(|(ky, c)| f(qx, signed(ky, self.ny) * self.dqy) * c)
                .sum::<f64>()
        }) * dq2
    }

    /// `sum C dq^2 = <h^2>` (including the squared mean at `q = 0`) [m^2].
    pub fn mean_square(&self) -> f64 {
        self.integrate(|_, _| 1.0)
    }

    /// The rms slope forward differences see in this PSD over the modes
    /// with `|q| >= q_lo`,
    /// `sqrt(sum (|2 sin(q_x a_x / 2)| / a_x)^2 + (|2 sin(q_y a_y / 2)| / a_y)^2) C dq^2)`
    /// with the pixel sides `a = 2 pi / (n dq)`: the transfer function of
    /// `(h[i+1] - h[i]) / a` replaces `q`. For a periodic map without a
    /// window and `q_lo = 0` this is the real-space value with wrap-around
    /// exactly (Parseval).
    pub fn rms_slope_fd(&self, q_lo: f64) -> f64 {
        let ax = 2.0 * PI / (self.nx as f64 * self.dqx);
        let ay = 2.0 * PI / (self.ny as f64 * self.dqy);
        let d = |q: f64, a: f64| (2.0 * (0.5 * q * a).sin() / a).powi(2);
        self.integrate(|qx, qy| {
            if qx * qx + qy * qy >= q_lo * q_lo {
                d(qx, ax) + d(qy, ay)
            } else {
                0.0
            }
        })
        .sqrt()
    }

    /// The PSD's side of the slope check ([`super::slope_warning`]): the
    /// rms slope forward differences see in it ([`Self::rms_slope_fd`]),
    /// like [`super::rms_slope_real`] of the same map. A windowed PSD (a
    /// scan) counts from the trusted band's lower end `2 pi / (L_min / 4)`
    /// ([`super::trusted_band`]): below, the window smears the longest
    /// waves, and a tilt left in the map sits there, which the check is
    /// there to catch; an unwindowed (periodic) PSD counts every mode.
    pub fn slope_check_value(&self, window: Window) -> f64 {
        let lmin = (2.0 * PI / self.dqx).min(2.0 * PI / self.dqy);
        let q_lo = match window {
            Window::None => 0.0,
            _ => 2.0 * PI / (lmin / 4.0),
        };
        self.rms_slope_fd(q_lo)
    }

    /// Slope tensor `M_ij = sum q_i q_j C(q) dq^2 = <d_i h d_j h>`
    /// (Eq. 11 of the paper over the whole band), `[[M_xx, M_xy], [M_xy, M_yy]]`.
    pub fn slope_tensor(&self) -> [[f64; 2]; 2] {
        let xx = self.integrate(|qx, _| qx * qx);
        let yy = self.integrate(|_, qy| qy * qy);
        let xy = self.integrate(|qx, qy| qx * qy);
        [[xx, xy], [xy, yy]]
    }
}

/// The taper `w(i)`, `i = 0..n`, of `window` (periodic form, length `n`);
/// `None` for [`Window::None`].
pub(crate) fn window_weights(window: Window, n: usize) -> Option<Vec<f64>> {
    let t = |i: usize| 2.0 * PI * i as f64 / n as f64;
    match window {
        Window::None => None,
        Window::Hann => Some((0..n).map(|i| 0.5 * (1.0 - t(i).cos())).collect()),
        Window::BlackmanHarris => Some(
            (0..n)
                .map(|i| {
                    let x = t(i);
                    0.35875 - 0.48829 * x.cos() + 0.14128 * (2.0 * x).cos()
                        - 0.01168 * (3.0 * x).cos()
                })
                .collect(),
        ),
    }
}

/// 2-D PSD of `map` (normalisation in the module doc).
pub fn psd_2d(map: &HeightMap, window: Window) -> Result<Psd2d, SurfaceError> {
    psd_grid(
        map.nx,
        map.ny,
        map.cell_size,
        map.cell_size_y,
        &map.heights,
        window,
    )
}

/// 2-D PSD of heights on an `nx x ny` grid of `dx x dy` pixels
/// (`heights[i * ny + j]`, i along x), normalisation of the module doc with
/// `a^2` replaced by `dx dy`: `C(q_k) = |dx dy H_k|^2 / ((2 pi)^2 Lx Ly)`.
/// With a window the mean is removed first and the tapered map is divided
/// by the root mean square of the separable window, so that
/// `sum C dq^2 = <h^2>` holds on average.
pub(crate) fn psd_grid(
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    heights: &[f64],
    window: Window,
) -> Result<Psd2d, SurfaceError> {
    let spec = match (window_weights(window, nx), window_weights(window, ny)) {
        (Some(wx), Some(wy)) => {
            let msq = |w: &[f64]| w.iter().map(|v| v * v).sum::<f64>() / w.len() as f64;
            let norm = 1.0 / (msq(&wx) * msq(&wy)).sqrt();
            let mean =
                height_fft::ordered_sum(heights, ny, |_, r| r.iter().sum()) / heights.len() as f64;
            let mut h = heights.to_vec();
            h.par_chunks_mut(ny).enumerate().for_each(|(i, row)| {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = (*v - mean) * wx[i] * wy[j] * norm;
                }
            });
            height_fft::forward(&h, nx, ny)?
        }
        _ => height_fft::forward(heights, nx, ny)?,
    };
    let (lx, ly) = (nx as f64 * dx, ny as f64 * dy);
    let factor = (dx * dy).powi(2) / ((2.0 * PI).powi(2) * lx * ly);
    let nh = height_fft::half_len(ny);
    let mut values = vec![0.0; nx * ny];
    values.par_chunks_mut(ny).enumerate().for_each(|(kx, row)| {
        for (ky, v) in row.iter_mut().enumerate() {
            // C(-q) = C(q): rows ky >= nh come from (-kx, ny - ky).
            *v = if ky < nh {
                spec[ky * nx + kx].norm_sqr() * factor
            } else {
                spec[(ny - ky) * nx + (nx - kx) % nx].norm_sqr() * factor
            };
        }
    });
    if let Some(c) = values.iter().find(|c| !c.is_finite()) {
        return Err(overflow("PSD", *c, heights));
    }
    Ok(Psd2d {
        nx,
        ny,
        dqx: 2.0 * PI / lx,
        dqy: 2.0 * PI / ly,
        values,
    })
}

/// The error for a statistic (`what` = `value`) that overflowed: the
/// squares of heights beyond about 1e154 (and sums of squares of smaller
/// ones) exceed f64. Names the largest height, usually a unit read wrong.
pub(crate) fn overflow(what: &str, value: f64, heights: &[f64]) -> SurfaceError {
    let scale = heights
        .iter()
        .filter(|h| h.is_finite())
        .fold(0.0f64, |m, h| m.max(h.abs()));
    SurfaceError::Invalid(format!(
        "the {what} of this map is {value} (floating-point overflow): its heights reach {scale:.3e} m, too large for sums of their squares; check the heights' unit and scale"
    ))
}

/// Radially averaged PSD `C(|q|)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RadialPsd {
    /// Bin width [1/m]: `max(dqx, dqy)`.
    pub dq: f64,
    /// Mean `|q|` of the modes in each bin [1/m].
    pub q: Vec<f64>,
    /// Mean `C` of the modes in each bin [m^4].
    pub c: Vec<f64>,
    /// Number of modes in each bin.
    pub count: Vec<usize>,
}

/// Average `C` over annuli `|q| in [(k - 1/2) dq, (k + 1/2) dq)`, `k >= 1`,
/// `dq = max(dqx, dqy)`, up to the largest circle inside the grid
/// (`|q| <= pi / a`); the `q = 0` mode and the corners are left out. Empty
/// bins are dropped.
pub fn radial_average(psd: &Psd2d) -> RadialPsd {
    let dq = psd.dqx.max(psd.dqy);
    let qmax = (psd.nx as f64 * psd.dqx).min(psd.ny as f64 * psd.dqy) / 2.0;
    let nbins = (qmax / dq + 0.5).floor() as usize + 1;
    // Fixed blocks of rows, partial histograms added in order: the result
    // does not depend on the number of threads.
    const ROWS: usize = 16;
    let parts: Vec<(Vec<f64>, Vec<f64>, Vec<usize>)> = psd
        .values
        .par_chunks(ROWS * psd.ny)
        .enumerate()
        .map(|(block, rows)| {
            let mut sq = vec![0.0; nbins];
            let mut sc = vec![0.0; nbins];
            let mut cnt = vec![0usize; nbins];
            for (r, row) in rows.chunks(psd.ny).enumerate() {
                let qx = signed(block * ROWS + r, psd.nx) * psd.dqx;
                for (ky, &c) in row.iter().enumerate() {
                    let qy = signed(ky, psd.ny) * psd.dqy;
                    let q = (qx * qx + qy * qy).sqrt();
                    if q > qmax * (1.0 + 1e-12) {
                        continue;
                    }
                    let b = (q / dq + 0.5).floor() as usize;
                    if b >= 1 && b < nbins {
                        sq[b] += q;
                        sc[b] += c;
                        cnt[b] += 1;
                    }
                }
            }
            (sq, sc, cnt)
        })
        .collect();
    let mut sq = vec![0.0; nbins];
    let mut sc = vec![0.0; nbins];
    let mut cnt = vec![0usize; nbins];
    for (a, b, c) in &parts {
        for i in 0..nbins {
            sq[i] += a[i];
            sc[i] += b[i];
            cnt[i] += c[i];
        }
    }
    let mut out = RadialPsd {
        dq,
        q: Vec::new(),
        c: Vec::new(),
        count: Vec::new(),
    };
    for b in 1..nbins {
        if cnt[b] > 0 {
            out.q.push(sq[b] / cnt[b] as f64);
            out.c.push(sc[b] / cnt[b] as f64);
            out.count.push(cnt[b]);
        }
    }
    out
}

/// Result of [`fit_hurst`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HurstFit {
    /// `H = -slope / 2 - 1`.
    pub hurst: f64,
    /// Least-squares slope of `ln C` against `ln q` (`-2 (H + 1)`).
    pub slope: f64,
    /// Intercept: `ln C = intercept + slope ln q` (`q` in 1/m, `C` in m^4).
    pub intercept: f64,
    /// Lower end of the band [1/m].
    pub q_min: f64,
    /// Upper end of the band [1/m].
    pub q_max: f64,
    /// Number of radial bins used.
    pub points: usize,
}

/// Hurst exponent from the radially averaged PSD over `q_min <= q <= q_max`:
/// least squares of `ln C` against `ln q`, slope `-2 (H + 1)` (physics.md
/// section 8). Needs at least 3 bins with `C > 0` in the band.
pub fn fit_hurst(radial: &RadialPsd, q_min: f64, q_max: f64) -> Result<HurstFit, SurfaceError> {
    if !(q_min.is_finite() && q_max.is_finite() && q_min > 0.0 && q_max > q_min) {
        return Err(SurfaceError::param(
            "fit band",
            format!("[{q_min}, {q_max}]"),
            "need 0 < q_min < q_max (1/m)",
        ));
    }
    let pts: Vec<(f64, f64)> = radial
        .q
        .iter()
        .zip(&radial.c)
        .filter(|(q, c)| **q >= q_min && **q <= q_max && **c > 0.0)
        .map(|(q, c)| (q.ln(), c.ln()))
        .collect();
    if pts.len() < 3 {
        return Err(SurfaceError::param(
            "fit band",
            format!("[{q_min:.4e}, {q_max:.4e}]"),
            format!("only {} PSD bins with C > 0 in the band, need 3", pts.len()),
        ));
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let slope = sxy / sxx;
    Ok(HurstFit {
        hurst: -slope / 2.0 - 1.0,
        slope,
        intercept: my - slope * mx,
        q_min,
        q_max,
        points: pts.len(),
    })
}

/// Statistics of a height map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SurfaceStats {
    pub nx: usize,
    pub ny: usize,
    /// Cell side along x \[m\].
    pub cell_size: f64,
    /// Cell side along y \[m\] (equal to `cell_size` for square cells).
    pub cell_size_y: f64,
    /// Sides \[m\].
    pub length_x: f64,
    pub length_y: f64,
    /// Mean, minimum and maximum height \[m\].
    pub mean: f64,
    pub min: f64,
    pub max: f64,
    /// `sqrt(<(h - mean)^2>)` from the heights \[m\].
    pub rms_height: f64,
    /// Spectral rms slope `sqrt(sum |q|^2 C dq^2) = sqrt(<|grad h|^2>)`.
    pub rms_slope: f64,
    /// Spectral rms slope components `sqrt(<(dh/dx)^2>)`, `sqrt(<(dh/dy)^2>)`.
    pub rms_slope_x: f64,
    pub rms_slope_y: f64,
    /// Finite-difference rms slope: `sqrt(<(dh/dx)^2 + (dh/dy)^2>)` with
    /// forward differences between neighbouring cells (no wrap-around,
    /// [`super::rms_slope_real`]); it underestimates the spectral value
    /// near the grid scale.
    pub rms_slope_fd: f64,
    /// The same differences seen in the PSD, the value the slope check
    /// compares with `rms_slope_fd` ([`Psd2d::slope_check_value`]).
    pub rms_slope_fd_psd: f64,
    /// Spectral rms Laplacian `sqrt(sum |q|^4 C dq^2) = sqrt(<(lap h)^2>)` [1/m]
    /// (twice the rms mean curvature).
    pub rms_curvature: f64,
    /// Window used for the spectral values.
    pub window: Window,
}

/// [`stats_with_window`] without a window (periodic maps).
pub fn stats(map: &HeightMap) -> Result<SurfaceStats, SurfaceError> {
    stats_with_window(map, Window::None)
}

/// Statistics of `map`; spectral values use the PSD with `window`.
pub fn stats_with_window(map: &HeightMap, window: Window) -> Result<SurfaceStats, SurfaceError> {
    let psd = psd_2d(map, window)?;
    let m = psd.slope_tensor();
    let m4 = psd.integrate(|qx, qy| (qx * qx + qy * qy).powi(2));
    let n = map.heights.len() as f64;
    // Row sums added in a fixed order: the same statistics from run to run
    // (a parallel reduction's order follows the thread scheduling).
    let ny = map.ny;
    let mean = height_fft::ordered_sum(&map.heights, ny, |_, r| r.iter().sum()) / n;
    let var = height_fft::ordered_sum(&map.heights, ny, |_, r| {
        r.iter().map(|h| (h - mean).powi(2)).sum()
    }) / n;
    let min = map.heights.iter().copied().fold(f64::INFINITY, f64::min);
    let max = map
        .heights
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let (nx, ny, (ax, ay)) = (map.nx, map.ny, map.cell());
    let fd = super::rms_slope_real(nx, ny, ax, ay, &map.heights);
    Ok(SurfaceStats {
        nx,
        ny,
        cell_size: ax,
        cell_size_y: ay,
        length_x: map.length_x(),
        length_y: map.length_y(),
        mean,
        min,
        max,
        rms_height: var.sqrt(),
        rms_slope: (m[0][0] + m[1][1]).sqrt(),
        rms_slope_x: m[0][0].sqrt(),
        rms_slope_y: m[1][1].sqrt(),
        rms_slope_fd: fd,
        rms_slope_fd_psd: psd.slope_check_value(window),
        rms_curvature: m4.sqrt(),
        window,
    })
}

impl std::fmt::Display for SurfaceStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let rows: [(&str, String, &str); 15] = [
            ("grid", format!("{} x {}", self.nx, self.ny), "cells"),
            ("cell size x", format!("{:.6e}", self.cell_size), "m"),
            ("cell size y", format!("{:.6e}", self.cell_size_y), "m"),
            ("length x", format!("{:.6e}", self.length_x), "m"),
            ("length y", format!("{:.6e}", self.length_y), "m"),
            ("mean", format!("{:.6e}", self.mean), "m"),
            ("min", format!("{:.6e}", self.min), "m"),
            ("max", format!("{:.6e}", self.max), "m"),
            ("rms height", format!("{:.6e}", self.rms_height), "m"),
            (
                "rms slope (spectral)",
                format!("{:.6e}", self.rms_slope),
                "-",
            ),
            (
                "rms slope x (spectral)",
                format!("{:.6e}", self.rms_slope_x),
                "-",
            ),
            (
                "rms slope y (spectral)",
                format!("{:.6e}", self.rms_slope_y),
                "-",
            ),
            (
                "rms slope (finite diff.)",
                format!("{:.6e}", self.rms_slope_fd),
                "-",
            ),
            (
                "rms curvature (spectral)",
                format!("{:.6e}", self.rms_curvature),
                "1/m",
            ),
            ("window", format!("{:?}", self.window).to_lowercase(), ""),
        ];
        for (k, v, u) in &rows {
            writeln!(f, "{k:<26} {v:>16} {u}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The statistics are the same bits on one thread and on four: every
    /// sum is added in a fixed order (a parallel reduction's order would
    /// follow the thread scheduling, and two runs of one surface could
    /// report rms heights a few ulps apart).
    #[test]
    fn stats_do_not_depend_on_the_thread_count() {
        let (nx, ny) = (256, 200);
        let heights: Vec<f64> = (0..nx * ny)
            .map(|k| ((k * 7919 % 1013) as f64 * 0.37).sin() * 1e-6 + 1e-9 * k as f64)
            .collect();
        let map = HeightMap::new(nx, ny, 1e-3, heights).unwrap();
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| stats(&map).unwrap())
        };
        let (one, four) = (on(1), on(4));
        assert_eq!(one.mean.to_bits(), four.mean.to_bits());
        assert_eq!(one.rms_height.to_bits(), four.rms_height.to_bits());
        assert_eq!(one.rms_slope.to_bits(), four.rms_slope.to_bits());
    }
}
