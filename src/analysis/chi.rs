//! Anisotropy of the contact area from the PSD `C_chi(q)` of the
//! characteristic function `chi` (1 in contact, 0 elsewhere): contours of
//! `C_chi(q) / C_chi(0)` and least-squares ellipses through them
//! (Carbone & Putignano 2014, Section IV and Fig. 10; physics.md section 5).
//!
//! # Estimator
//!
//! The periodogram `|FT chi|^2` of a single map fluctuates by 100 % from one
//! Fourier mode to the next (the phases of the spots add at random) and
//! carries the squared mean `<chi>^2` as a spike at `q = 0`. The contours are
//! therefore taken on the Blackman-Tukey estimate
//!
//! `C_chi(q) = a^4 / ((2 pi)^2 Lx Ly) sum_r w(|r|) (R(r) - R_b) cos(q.r)`,
//!
//! with `R(r) = sum_x chi(x) chi(x + r)` the non-periodic (zero-padded)
//! autocorrelation of `chi`, `w` a flat-top window (`w = 1` for
//! `|r| <= r_flat`, a cosine taper to zero at `r_c = 1.5 r_flat`) and `R_b`
//! the mean of `R` over the taper ring `r_flat < |r| < r_c`. Without the
//! window and background (`r_c -> infinity`, periodic map) this is exactly
//! the periodogram in the normalisation of [`crate::surface::psd_2d`].
//! Within `r_flat`, `R` is the sum of the self-correlations of the spots
//! (each supported on its own shape dilated by two) plus the pair terms of
//! neighbouring spots, which tend to the uniform level `<chi>^2` per cell
//! pair beyond the correlation length of the spot positions. The window
//! keeps the shape information of every spot and drops the random
//! far-field phases; `R_b` removes the uniform level, which would otherwise
//! add the isotropic term `R_b W(q)` to every contour (dense maps). For
//! spots farther apart than `r_c` the ring holds no pair term, `R_b = 0`,
//! and the estimate is the exact sum of the spots' `|FT|^2`. `C_chi(0)` is
//! the estimate at `q = 0` (the largest value when `R_b = 0`, since
//! `w R >= 0`).
//!
//! The default `r_flat` is `4 sqrt(v)`, with `v` the area-weighted mean
//! over the spots of the largest eigenvalue of their second-moment tensor
//! (`4 sqrt(v) = 2 A` for ellipses of semi-major axis `A`: the full extent of
//! their self-correlation), at least 2 cells, with `r_c` capped below half
//! the shorter side of the map. A window sized on the largest spot instead
//! keeps more neighbour pairs, whose random arrangement makes the contours
//! of a single contact map ragged.
//!
//! # Contours and ellipse fit
//!
//! For each level `l` the contour `C_chi(q) = l C_chi(0)` is sampled along
//! `rays` directions `theta_k = pi k / rays` from `q = 0`: the first crossing
//! is bracketed on the FFT grid (bilinear interpolation), then refined by
//! bisection on the exact trigonometric sum. `C_chi(-q) = C_chi(q)`, so every
//! crossing `q` gives the point `-q` too and the contour's centre is the
//! origin: the ellipse `A qx^2 + B qx qy + C qy^2 = 1` (centre fixed at 0)
//! is fitted by linear least squares to the points (in units of `q0`), and
//! accepted when `4AC - B^2 > 0`, `A > 0`. `lambda` is the ratio of the minor
//! to the major semi-axis; `ellipse_angle_deg` the direction of the major
//! axis from `+q_x`, in (-90, 90]. Spots elongated along `e` give contours
//! elongated along the perpendicular of `e` (reciprocal lengths).
//!
//! The ellipse fit itself, which knows nothing of `chi`, is
//! [`super::ellipse`].

use std::f64::consts::PI;

use num_complex::Complex64;
use rayon::prelude::*;
use rustfft::FftPlanner;
use serde::Serialize;

use super::ellipse::{fit_centred_ellipse, EllipseFit, FitFailure};

/// Smoothed `C_chi(q)` of one contact map (see the module doc).
#[derive(Debug, Clone)]
pub struct ChiSpectrum {
    pub nx: usize,
    pub ny: usize,
    /// `2 pi / Lx` [1/m].
    pub dqx: f64,
    /// `2 pi / Ly` [1/m].
    pub dqy: f64,
    /// `C_chi` on the FFT grid, `values[kx * ny + ky]`, FFT order [m^4].
    pub values: Vec<f64>,
    /// `C_chi(0)` [m^4].
    pub c0: f64,
    /// Window radius `r_c` \[cells\].
    pub window_radius_cells: f64,
    /// Flat part of the window `r_flat` \[cells\].
    pub flat_radius_cells: f64,
    /// Background `R_b` subtracted from `R` \[cells\] (see the module doc).
    pub background_cells: f64,
    /// The cosine sum's coefficients `v = w (R - R_b) a^4 / ((2 pi)^2 Lx Ly)`
    /// folded onto the half plane (`v(-r) = v(r)` and the cosine is even):
    /// row `rx` in `0..=rmax_x` of `2 rmax_y + 1` columns `ry + rmax_y`, holding
    /// `2 v` for `rx > 0` or `ry > 0`, `v` at `r = 0` and nothing for
    /// `rx = 0, ry < 0`.
    lags: Vec<f64>,
    /// Lags per axis on either side of 0.
    rmax_x: usize,
    rmax_y: usize,
    /// Sides of a cell \[m\].
    cell: (f64, f64),
}

impl ChiSpectrum {
    /// Exact `C_chi(q)` [m^4] at any wavevector: the cosine sum of the
    /// module doc, separated along the axes,
    /// `sum_rx [cos(qx rx) sum_ry v cos(qy ry) - sin(qx rx) sum_ry v sin(qy ry)]`,
    /// two multiply-adds per lag and `rmax_x + 2 rmax_y + 2` sines and cosines
    /// instead of one cosine per lag.
    pub fn eval(&self, qx: f64, qy: f64) -> f64 {
        let m = 2 * self.rmax_y + 1;
        let trig = |q: f64, n: usize, shift: usize, a: f64| -> (Vec<f64>, Vec<f64>) {
            (0..n)
                .map(|k| (q * (k as f64 - shift as f64) * a).sin_cos())
                .map(|(s, c)| (c, s))
                .unzip()
        };
        let (cx, sx) = trig(qx, self.rmax_x + 1, 0, self.cell.0);
        let (cy, sy) = trig(qy, m, self.rmax_y, self.cell.1);
        let mut total = 0.0;
        for (i, row) in self.lags.chunks_exact(m).enumerate() {
            let (mut rc, mut rs) = (0.0, 0.0);
            for ((v, c), s) in row.iter().zip(&cy).zip(&sy) {
                rc += v * c;
                rs += v * s;
            }
            total += cx[i] * rc - sx[i] * rs;
        }
        total
    }

    /// Bilinear interpolation of the grid values at `(qx, qy)` [1/m] (the
    /// grid is periodic in `q`).
    fn interp(&self, qx: f64, qy: f64) -> f64 {
        let fx = qx / self.dqx;
        let fy = qy / self.dqy;
        let (ix, iy) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - ix, fy - iy);
        let wrap = |k: f64, n: usize| (k as i64).rem_euclid(n as i64) as usize;
        let (x0, x1) = (wrap(ix, self.nx), wrap(ix + 1.0, self.nx));
        let (y0, y1) = (wrap(iy, self.ny), wrap(iy + 1.0, self.ny));
        let v = |x: usize, y: usize| self.values[x * self.ny + y];
        (1.0 - tx) * ((1.0 - ty) * v(x0, y0) + ty * v(x0, y1))
            + tx * ((1.0 - ty) * v(x1, y0) + ty * v(x1, y1))
    }
}

/// In-place 2-D complex FFT of an `n0 x n1` C-order array (unnormalised;
/// `inverse` uses `e^{+i}`).
fn fft2(data: &mut [Complex64], n0: usize, n1: usize, inverse: bool) {
    let mut planner = FftPlanner::<f64>::new();
    let (p1, p0) = if inverse {
        (planner.plan_fft_inverse(n1), planner.plan_fft_inverse(n0))
    } else {
        (planner.plan_fft_forward(n1), planner.plan_fft_forward(n0))
    };
    data.par_chunks_mut(n1).for_each(|row| p1.process(row));
    let mut t = vec![Complex64::default(); n0 * n1];
    t.par_chunks_mut(n0).enumerate().for_each(|(j, col)| {
        for (i, v) in col.iter_mut().enumerate() {
            *v = data[i * n1 + j];
        }
    });
    t.par_chunks_mut(n0).for_each(|col| p0.process(col));
    data.par_chunks_mut(n1).enumerate().for_each(|(i, row)| {
        for (j, v) in row.iter_mut().enumerate() {
            *v = t[j * n0 + i];
        }
    });
}

/// The flat-top window: 1 up to `flat`, cosine taper to 0 at `radius`.
fn window(r: f64, flat: f64, radius: f64) -> f64 {
    if r <= flat {
        1.0
    } else if r >= radius {
        0.0
    } else {
        0.5 * (1.0 + (PI * (r - flat) / (radius - flat)).cos())
    }
}

/// Largest usable window radius \[cells\] on an `nx x ny` map: the windowed
/// autocorrelation must fit on the FFT grid without aliasing.
pub fn max_window_radius(nx: usize, ny: usize) -> f64 {
    (nx.min(ny) / 2) as f64 - 1.0
}

/// Smoothed `C_chi` of `contact` (`> 0.5` in contact) with window radius
/// `radius` cells (flat part `2/3` of it), capped at [`max_window_radius`],
/// on cells of sides `(a_x, a_y)` \[m\]: the window is round in physical
/// space, its radius counted in cells of the mean side `c = sqrt(a_x a_y)`
/// (`radius c / a_x` cells along x, `radius c / a_y` along y), and capped
/// so that it fits the grid both ways.
pub fn chi_spectrum(
    contact: &[f64],
    nx: usize,
    ny: usize,
    (ax, ay): (f64, f64),
    radius: f64,
) -> ChiSpectrum {
    let c = (ax * ay).sqrt();
    // Lag (dx, dy) in cells of side c.
    let (sx, sy) = (ax / c, ay / c);
    let cap = ((nx / 2) as f64 - 1.0) * sx;
    let cap = cap.min(((ny / 2) as f64 - 1.0) * sy);
    let radius = radius.min(cap).max(1.0);
    let flat = radius / 1.5;
    let (px, py) = (2 * nx, 2 * ny);
    let mut buf = vec![Complex64::default(); px * py];
    for i in 0..nx {
        for j in 0..ny {
            if contact[i * ny + j] > 0.5 {
                buf[i * py + j] = Complex64::new(1.0, 0.0);
            }
        }
    }
    fft2(&mut buf, px, py, false);
    buf.par_iter_mut()
        .for_each(|v| *v = Complex64::new(v.norm_sqr(), 0.0));
    fft2(&mut buf, px, py, true);
    let inv = 1.0 / (px * py) as f64;
    let (lx, ly) = (nx as f64 * ax, ny as f64 * ay);
    let factor = (ax * ay).powi(2) / ((2.0 * PI).powi(2) * lx * ly);
    let (rmax_x, rmax_y) = ((radius / sx).ceil() as i64, (radius / sy).ceil() as i64);
    let dist = |dx: i64, dy: i64| (dx as f64 * sx).hypot(dy as f64 * sy);
    let lag = |dx: i64, dy: i64| {
        // R counts overlapping cells: an integer up to round-off.
        (buf[dx.rem_euclid(px as i64) as usize * py + dy.rem_euclid(py as i64) as usize].re * inv)
            .round()
    };
    // Background: mean of R over the taper ring.
    let (mut ring_sum, mut ring_count) = (0.0, 0usize);
    for dx in -rmax_x..=rmax_x {
        for dy in -rmax_y..=rmax_y {
            let d = dist(dx, dy);
            if d > flat && d < radius {
                ring_sum += lag(dx, dy);
                ring_count += 1;
            }
        }
    }
    let background = if ring_count > 0 {
        ring_sum / ring_count as f64
    } else {
        0.0
    };
    let m = 2 * rmax_y as usize + 1;
    let mut lags = vec![0.0; (rmax_x as usize + 1) * m];
    let mut grid = vec![0.0; nx * ny];
    for dx in -rmax_x..=rmax_x {
        for dy in -rmax_y..=rmax_y {
            let w = window(dist(dx, dy), flat, radius);
            if w == 0.0 {
                continue;
            }
            let r = lag(dx, dy) - background;
            if r == 0.0 {
                continue;
            }
            let v = w * r * factor;
            let fold = match (dx, dy) {
                (0, 0) => 1.0,
                (0, y) if y < 0 => 0.0,
                (x, _) if x < 0 => 0.0,
                _ => 2.0,
            };
            if fold > 0.0 {
                lags[dx as usize * m + (dy + rmax_y) as usize] = fold * v;
            }
            grid[dx.rem_euclid(nx as i64) as usize * ny + dy.rem_euclid(ny as i64) as usize] += v;
        }
    }
    let mut g: Vec<Complex64> = grid.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    fft2(&mut g, nx, ny, false);
    let values: Vec<f64> = g.iter().map(|v| v.re).collect();
    // C(0) is the sum of the coefficients, folded or not.
    let c0 = lags.iter().sum();
    ChiSpectrum {
        nx,
        ny,
        dqx: 2.0 * PI / lx,
        dqy: 2.0 * PI / ly,
        values,
        c0,
        window_radius_cells: radius,
        flat_radius_cells: flat,
        background_cells: background,
        lags,
        rmax_x: rmax_x as usize,
        rmax_y: rmax_y as usize,
        cell: (ax, ay),
    }
}

/// First crossing of `C_chi = level C_chi(0)` along the ray `e(theta)` from
/// `q = 0`, as a distance [1/m]; `None` when the ray leaves the grid's
/// `q` range first.
pub fn ray_crossing(spec: &ChiSpectrum, theta: f64, level: f64) -> Option<f64> {
    crossing_with(spec, theta, level, |qx, qy| spec.eval(qx, qy))
}

/// [`ray_crossing`] with the exact `C_chi` given by `eval`.
fn crossing_with(
    spec: &ChiSpectrum,
    theta: f64,
    level: f64,
    eval: impl Fn(f64, f64) -> f64,
) -> Option<f64> {
    let target = level * spec.c0;
    let (s, c) = theta.sin_cos();
    let qxmax = (spec.nx / 2) as f64 * spec.dqx;
    let qymax = (spec.ny / 2) as f64 * spec.dqy;
    let tmax = (if c.abs() > 1e-12 {
        qxmax / c.abs()
    } else {
        f64::INFINITY
    })
    .min(if s.abs() > 1e-12 {
        qymax / s.abs()
    } else {
        f64::INFINITY
    });
    let step = 0.25 * spec.dqx.min(spec.dqy);
    let exact = |t: f64| eval(t * c, t * s) - target;
    let bisect = |mut lo: f64, mut hi: f64| {
        for _ in 0..50 {
            let mid = 0.5 * (lo + hi);
            if exact(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-10 * hi {
                break;
            }
        }
        0.5 * (lo + hi)
    };
    // Bracket on the grid, confirm with the exact sum.
    let mut t = 0.0;
    while t < tmax {
        let t1 = (t + step).min(tmax);
        if spec.interp(t1 * c, t1 * s) <= target {
            if exact(t) > 0.0 && exact(t1) <= 0.0 {
                return Some(bisect(t, t1));
            }
            break;
        }
        t = t1;
    }
    // Fallback: march on the exact sum.
    let mut t = 0.0;
    while t < tmax {
        let t1 = (t + step).min(tmax);
        if exact(t1) <= 0.0 {
            return Some(bisect(t, t1));
        }
        t = t1;
    }
    None
}

/// One contour level of `C_chi / C_chi(0)` and its ellipse.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChiLevel {
    /// `C_chi(q) / C_chi(0)` on the contour.
    pub level: f64,
    /// Contour points found (two per ray that crosses the level).
    pub points: usize,
    /// The fitted ellipse, if any.
    pub ellipse: Option<EllipseFit>,
    /// Why there is no ellipse, if none.
    pub failure: Option<FitFailure>,
    /// The contour points `(qx, qy)` in units of `q0` (for figures).
    #[serde(skip)]
    pub contour: Vec<[f64; 2]>,
}

/// Contour of `spec` at `level` sampled along `rays` directions, and its
/// ellipse; points are in units of `q0 = dqx`.
pub fn contour_level(spec: &ChiSpectrum, level: f64, rays: usize) -> ChiLevel {
    let q0 = spec.dqx;
    if spec.c0.is_nan() || spec.c0 <= 0.0 {
        return ChiLevel {
            level,
            points: 0,
            ellipse: None,
            failure: Some(FitFailure::NonPositiveC0),
            contour: Vec::new(),
        };
    }
    let found: Vec<Option<f64>> = (0..rays)
        .into_par_iter()
        .map(|k| ray_crossing(spec, PI * k as f64 / rays as f64, level))
        .collect();
    let mut contour = Vec::with_capacity(2 * rays);
    for (k, t) in found.iter().enumerate() {
        if let Some(t) = t {
            let (s, c) = (PI * k as f64 / rays as f64).sin_cos();
            contour.push([t * c / q0, t * s / q0]);
            contour.push([-t * c / q0, -t * s / q0]);
        }
    }
    let fit = fit_centred_ellipse(&contour);
    ChiLevel {
        level,
        points: contour.len(),
        ellipse: fit.ok(),
        failure: fit.err(),
        contour,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cosine sum as first written: one term `(rx, ry, v)` per lag,
    /// with `R` counted cell by cell (the reference of the fast paths).
    fn reference_terms(
        chi: &[f64],
        nx: usize,
        ny: usize,
        a: f64,
        spec: &ChiSpectrum,
    ) -> Vec<(f64, f64, f64)> {
        let (radius, flat) = (spec.window_radius_cells, spec.flat_radius_cells);
        let rmax = radius.ceil() as i64;
        let on = |i: i64, j: i64| {
            i >= 0
                && j >= 0
                && i < nx as i64
                && j < ny as i64
                && chi[(i * ny as i64 + j) as usize] > 0.5
        };
        let r = |dx: i64, dy: i64| {
            let mut n = 0.0;
            for i in 0..nx as i64 {
                for j in 0..ny as i64 {
                    if on(i, j) && on(i + dx, j + dy) {
                        n += 1.0;
                    }
                }
            }
            n
        };
        let factor = a.powi(4) / ((2.0 * PI).powi(2) * nx as f64 * a * ny as f64 * a);
        let mut terms = Vec::new();
        for dx in -rmax..=rmax {
            for dy in -rmax..=rmax {
                let w = window(((dx * dx + dy * dy) as f64).sqrt(), flat, radius);
                if w > 0.0 {
                    let v = w * (r(dx, dy) - spec.background_cells) * factor;
                    terms.push((dx as f64 * a, dy as f64 * a, v));
                }
            }
        }
        terms
    }

    #[test]
    fn separable_sum_and_contours_match_the_term_by_term_sum() {
        // A dense map (most cells in contact, irregular holes): the case
        // where the window is widest and the background largest.
        let (nx, ny, a) = (36, 28, 1e-6);
        let chi: Vec<f64> = (0..nx * ny)
            .map(|k| {
                let (i, j) = ((k / ny) as f64, (k % ny) as f64);
                let f = (0.9 * i).sin() + (0.55 * j + 0.3 * i).cos() + (0.31 * i * j).sin();
                if f > -1.2 {
                    1.0
                } else {
                    0.0
                }
            })
            .collect();
        for radius in [5.0, 13.0] {
            let spec = chi_spectrum(&chi, nx, ny, (a, a), radius);
            let terms = reference_terms(&chi, nx, ny, a, &spec);
            let direct = |qx: f64, qy: f64| -> f64 {
                terms
                    .iter()
                    .map(|&(rx, ry, v)| v * (qx * rx + qy * ry).cos())
                    .sum()
            };
            let scale: f64 = terms.iter().map(|t| t.2.abs()).sum();
            let c0: f64 = terms.iter().map(|t| t.2).sum();
            assert!((spec.c0 - c0).abs() < 1e-13 * scale, "{} {c0}", spec.c0);
            for k in 0..50 {
                let (qx, qy) = (
                    spec.dqx * (0.37 * k as f64 - 7.0),
                    spec.dqy * (0.23 * k as f64 * (k % 3) as f64 - 5.0),
                );
                // Both sums add the same terms in another order and by
                // angle addition: round-off relative to sum |v|.
                let (fast, slow) = (spec.eval(qx, qy), direct(qx, qy));
                assert!(
                    (fast - slow).abs() < 1e-13 * scale,
                    "{qx} {qy}: {fast} {slow}"
                );
            }
            for level in [0.5, 0.3] {
                for k in 0..12 {
                    let th = PI * k as f64 / 12.0;
                    let fast = ray_crossing(&spec, th, level);
                    let slow = crossing_with(&spec, th, level, direct);
                    match (fast, slow) {
                        // Bisection to 1e-10 relative on functions equal to
                        // round-off.
                        (Some(f), Some(s)) => assert!((f / s - 1.0).abs() < 1e-9, "{f} {s}"),
                        (None, None) => {}
                        other => panic!("{radius} {level} {th}: {other:?}"),
                    }
                }
            }
        }
    }

    #[test]
    fn unwindowed_limit_is_the_periodogram_at_zero() {
        // C_chi(0) = a^4 (sum chi)^2 / ((2 pi)^2 Lx Ly) when the window holds
        // every pair of cells.
        let (nx, ny) = (16, 16);
        let mut chi = vec![0.0; nx * ny];
        for (i, j) in [(2, 3), (2, 4), (3, 3), (4, 4)] {
            chi[i * ny + j] = 1.0;
        }
        let s = chi_spectrum(&chi, nx, ny, (0.5, 0.5), 7.0);
        let want = 0.5f64.powi(4) * 16.0 / ((2.0 * PI).powi(2) * 64.0);
        assert!((s.c0 / want - 1.0).abs() < 1e-12, "{} {}", s.c0, want);
        assert!((s.eval(0.0, 0.0) - s.values[0]).abs() < 1e-12 * want);
    }
}
