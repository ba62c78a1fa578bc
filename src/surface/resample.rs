//! Resampling a topography onto another grid (physics.md section 11): for
//! scans with non-square pixels whose users want square cells.
//!
//! Heights sit at pixel centres, `x_i = (i + 1/2) dx`, over the extent
//! `[0, nx dx] x [0, ny dy]`. Both methods are separable (one pass along
//! y for every row, then one along x for every column), which is exact for
//! tensor-product interpolants:
//!
//! - Spline ([`ResampleMethod::Spline`]): bicubic spline interpolation, a
//!   not-a-knot cubic spline along each axis (third derivative continuous
//!   at the second and the second-to-last sample), whose error on a smooth
//!   surface is `O(h^4)` up to the edges (a natural spline's is `O(h^2)`
//!   there). A requested pixel is kept exactly: the new grid has
//!   `floor(L / d)` pixels, centred on the old extent (the strip left over,
//!   less than one new pixel, is shared by both edges); a point up to half
//!   an old pixel outside the old centres is extrapolated by the end piece.
//! - Fourier ([`ResampleMethod::Fourier`]): band-limited (trigonometric)
//!   interpolation of a periodic map: the spectrum is zero-padded or
//!   truncated and shifted by the offset of the new pixel centres. The
//!   period is kept, so the new pixel is `L / round(L / d)`; an even
//!   map's Nyquist mode is split evenly between `+-q_N`. A surface whose
//!   modes lie below both grids' Nyquist wavenumbers is reproduced to
//!   round-off. A map whose opposite edges do not meet (a scan) rings
//!   near its edges: [`fourier_edge_warning`] says so.

use std::f64::consts::PI;

use num_complex::Complex64;
use rayon::prelude::*;
use rustfft::FftPlanner;
use serde::Serialize;

use super::{SurfaceError, Topography};

/// Largest number of cells a resampled map (or its intermediate after the
/// first pass) may have: 2^28 (2 GiB of heights).
pub const MAX_RESAMPLE_CELLS: usize = 1 << 28;

/// How the heights between the samples are interpolated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ResampleMethod {
    /// Not-a-knot bicubic spline (any map).
    Spline,
    /// Band-limited Fourier interpolation (periodic maps).
    Fourier,
}

impl std::str::FromStr for ResampleMethod {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "spline" => Ok(Self::Spline),
            "fourier" => Ok(Self::Fourier),
            _ => Err(format!("'{s}': use spline or fourier")),
        }
    }
}

/// Edge steps above this many neighbour steps make Fourier interpolation
/// ring ([`fourier_edge_warning`]).
pub(crate) const EDGE_STEP_RATIO: f64 = 2.0;

/// The warning for [`ResampleMethod::Fourier`] on a map that is not one
/// period of a periodic surface: band-limited interpolation takes the map
/// as a period, so where its opposite edges do not meet (an rms step
/// across them above [`EDGE_STEP_RATIO`] times that between neighbouring
/// cells, [`super::edge_steps`]) the jump is spread over the whole map as
/// oscillations that are largest at the edges. `None` for a map whose
/// edges meet like neighbouring cells.
pub(crate) fn fourier_edge_warning(topo: &Topography) -> Option<String> {
    let s = super::edge_steps(topo.nx, topo.ny, &topo.heights)?;
    let off = |edge: f64, cell: f64| edge > EDGE_STEP_RATIO * cell;
    (off(s.edge_x, s.cell_x) || off(s.edge_y, s.cell_y)).then(|| {
        format!(
            "Fourier interpolation takes the map as one period of a periodic surface, but its opposite edges do not meet: rms steps of {:.3} rms heights along x and {:.3} along y across them against {:.3} and {:.3} between neighbouring cells; the resampled heights ring near the edges. Use --method spline for a scan",
            s.edge_x, s.edge_y, s.cell_x, s.cell_y
        )
    })
}

/// The grid asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ResampleTarget {
    /// Pixel sides `(dx, dy)` \[m\].
    Pixel(f64, f64),
    /// Points `(nx, ny)` over the same extent.
    Shape(usize, usize),
}

/// The new grid: points, pixel sides and the position of the first new
/// pixel's lower corner in the old map's frame \[m\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ResampleGrid {
    pub nx: usize,
    pub ny: usize,
    pub dx: f64,
    pub dy: f64,
    pub offset_x: f64,
    pub offset_y: f64,
}

fn bad(what: impl Into<String>) -> SurfaceError {
    SurfaceError::Invalid(what.into())
}

/// The grid `target` gives for `topo` with `method` (see the module doc),
/// or a one-line error for a non-positive size, fewer than 2 points per
/// axis or more than [`MAX_RESAMPLE_CELLS`] cells.
pub fn resample_grid(
    topo: &Topography,
    target: ResampleTarget,
    method: ResampleMethod,
) -> Result<ResampleGrid, SurfaceError> {
    let (lx, ly) = (topo.length_x(), topo.length_y());
    let (nxf, nyf) = match target {
        ResampleTarget::Pixel(dx, dy) => {
            for (axis, d) in [("x", dx), ("y", dy)] {
                if !(d.is_finite() && d > 0.0) {
                    return Err(bad(format!(
                        "pixel size along {axis} is {d} m; it must be finite and > 0"
                    )));
                }
            }
            // A relative slack of 1e-9 keeps `L / d` that is an integer up
            // to round-off from losing a pixel.
            let count = |l: f64, d: f64| match method {
                ResampleMethod::Spline => (l / d * (1.0 + 1e-9)).floor(),
                ResampleMethod::Fourier => (l / d).round(),
            };
            (count(lx, dx), count(ly, dy))
        }
        ResampleTarget::Shape(nx, ny) => (nx as f64, ny as f64),
    };
    if nxf < 2.0 || nyf < 2.0 {
        return Err(bad(format!(
            "the new grid would have {nxf} x {nyf} points on a {lx:.6e} m x {ly:.6e} m map; \
             each axis needs at least 2 (a smaller pixel)"
        )));
    }
    let cells = nxf * nyf;
    let limit = MAX_RESAMPLE_CELLS as f64;
    if cells > limit {
        return Err(bad(format!(
            "the new grid would have {nxf} x {nyf} = {cells:.3e} cells, more than 2^28 = {limit:.3e}; \
             ask for a larger pixel"
        )));
    }
    let (nx, ny) = (nxf as usize, nyf as usize);
    // The first pass (along y) makes an nx_old x ny map.
    if (topo.nx * ny) as f64 > limit {
        return Err(bad(format!(
            "resampling would need an intermediate map of {} x {ny} cells, more than 2^28; \
             ask for a larger pixel along y",
            topo.nx
        )));
    }
    let (dx, dy) = match (target, method) {
        (ResampleTarget::Pixel(dx, dy), ResampleMethod::Spline) => (dx, dy),
        _ => (lx / nx as f64, ly / ny as f64),
    };
    Ok(ResampleGrid {
        nx,
        ny,
        dx,
        dy,
        offset_x: 0.5 * (lx - nx as f64 * dx),
        offset_y: 0.5 * (ly - ny as f64 * dy),
    })
}

/// `topo` resampled onto `grid` by `method`. Missing points (NaN) are an
/// error: fill them first ([`Topography::fill_missing`]).
pub fn resample(
    topo: &Topography,
    grid: &ResampleGrid,
    method: ResampleMethod,
) -> Result<Topography, SurfaceError> {
    if topo.heights.iter().any(|h| !h.is_finite()) {
        return Err(bad(format!(
            "{} of the {} heights are missing; fill them first (--fill-missing)",
            topo.heights.iter().filter(|h| !h.is_finite()).count(),
            topo.heights.len()
        )));
    }
    let along = |lines: &[f64], n_old: usize, d_old: f64, n_new: usize, d_new: f64, off: f64| {
        let start = off + 0.5 * d_new - 0.5 * d_old;
        match method {
            ResampleMethod::Spline => {
                let spline = SplineLine::new(n_old, d_old, n_new, d_new, start);
                map_lines(lines, n_old, n_new, |a, b| spline.apply(a, b))
            }
            ResampleMethod::Fourier => {
                let f = FourierLine::new(n_old, d_old, n_new, start);
                map_lines(lines, n_old, n_new, |a, b| f.apply(a, b))
            }
        }
    };
    // Along y (rows are contiguous), then along x on the transpose.
    let rows = along(
        &topo.heights,
        topo.ny,
        topo.dy,
        grid.ny,
        grid.dy,
        grid.offset_y,
    );
    let cols = transpose(&rows, topo.nx, grid.ny);
    let cols = along(&cols, topo.nx, topo.dx, grid.nx, grid.dx, grid.offset_x);
    let heights = transpose(&cols, grid.ny, grid.nx);
    let mut out = Topography::new(grid.nx, grid.ny, grid.dx, grid.dy, heights, "resampled map")?;
    out.filled = topo.filled;
    Ok(out)
}

/// Apply `f(old_line, new_line)` to every line of `data` (lines of `n_old`).
fn map_lines(
    data: &[f64],
    n_old: usize,
    n_new: usize,
    f: impl Fn(&[f64], &mut [f64]) + Sync,
) -> Vec<f64> {
    let lines = data.len() / n_old;
    let mut out = vec![0.0; lines * n_new];
    out.par_chunks_mut(n_new)
        .zip(data.par_chunks(n_old))
        .for_each(|(o, i)| f(i, o));
    out
}

/// The `c x r` transpose of an `r x c` C-order array.
fn transpose(a: &[f64], r: usize, c: usize) -> Vec<f64> {
    let mut t = vec![0.0; r * c];
    t.par_chunks_mut(r).enumerate().for_each(|(j, col)| {
        for (i, v) in col.iter_mut().enumerate() {
            *v = a[i * c + j];
        }
    });
    t
}

/// A not-a-knot cubic spline on `n` uniform samples of spacing `h`,
/// evaluated at fixed points: the tridiagonal factors and the evaluation
/// weights are shared by every line.
struct SplineLine {
    n: usize,
    h: f64,
    /// Thomas-algorithm multipliers of the interior system (rows 2..n-3).
    diag: Vec<f64>,
    /// Per new point: segment index `i` and `t = (x - x_i) / h`.
    at: Vec<(usize, f64)>,
}

impl SplineLine {
    /// Spline through samples at `x_i = i h`, evaluated at
    /// `start + k d_new`, `k < n_new`.
    fn new(n: usize, h: f64, n_new: usize, d_new: f64, start: f64) -> Self {
        // Interior system M_{i-1} + 4 M_i + M_{i+1} = r_i for i = 2..n-3
        // (M_1, M_{n-2} known): forward elimination of the constant matrix.
        let m = n.saturating_sub(4);
        let mut diag = vec![0.0; m];
        for k in 0..m {
            diag[k] = 4.0 - if k > 0 { 1.0 / diag[k - 1] } else { 0.0 };
        }
        let at = (0..n_new)
            .map(|k| {
                let u = (start + k as f64 * d_new) / h;
                let i = (u.floor().max(0.0) as usize).min(n - 2);
                (i, u - i as f64)
            })
            .collect();
        Self { n, h, diag, at }
    }

    /// Second derivatives `M` of the not-a-knot spline through `y`.
    fn second_derivatives(&self, y: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut mm = vec![0.0; n];
        if n < 3 {
            return mm;
        }
        let r = |i: usize| 6.0 / (self.h * self.h) * (y[i - 1] - 2.0 * y[i] + y[i + 1]);
        // Not-a-knot, M_0 - 2 M_1 + M_2 = 0, turns row 1 into 6 M_1 = r_1
        // (and likewise at the other end).
        mm[1] = r(1) / 6.0;
        mm[n - 2] = r(n - 2) / 6.0;
        if n >= 5 {
            // Unknowns M_2..M_{n-3}.
            let m = n - 4;
            let mut rhs: Vec<f64> = (2..n - 2).map(r).collect();
            rhs[0] -= mm[1];
            rhs[m - 1] -= mm[n - 2];
            for k in 1..m {
                rhs[k] -= rhs[k - 1] / self.diag[k - 1];
            }
            mm[n - 3] = rhs[m - 1] / self.diag[m - 1];
            for k in (0..m - 1).rev() {
                mm[k + 2] = (rhs[k] - mm[k + 3]) / self.diag[k];
            }
        }
        if n == 3 {
            // The parabola through the three samples.
            return vec![mm[1]; 3];
        }
        mm[0] = 2.0 * mm[1] - mm[2];
        mm[n - 1] = 2.0 * mm[n - 2] - mm[n - 3];
        mm
    }

    fn apply(&self, y: &[f64], out: &mut [f64]) {
        let mm = self.second_derivatives(y);
        let h2 = self.h * self.h / 6.0;
        for (o, &(i, t)) in out.iter_mut().zip(&self.at) {
            let s = 1.0 - t;
            *o = s * y[i]
                + t * y[i + 1]
                + h2 * ((s * s * s - s) * mm[i] + (t * t * t - t) * mm[i + 1]);
        }
    }
}

/// Band-limited interpolation of a periodic line of `n` samples at spacing
/// `h` onto `n_new` samples over the same period, the first at `start`
/// (relative to the first old sample).
struct FourierLine {
    n: usize,
    n_new: usize,
    forward: std::sync::Arc<dyn rustfft::Fft<f64>>,
    inverse: std::sync::Arc<dyn rustfft::Fft<f64>>,
    /// `(old bin, new bin, factor)` of every kept mode.
    map: Vec<(usize, usize, Complex64)>,
}

impl FourierLine {
    fn new(n: usize, h: f64, n_new: usize, start: f64) -> Self {
        let mut planner = FftPlanner::<f64>::new();
        let period = n as f64 * h;
        // Signed frequencies of the old spectrum; an even Nyquist bin is
        // split into +-n/2 with half its weight each.
        let mut map = Vec::new();
        let half_new = n_new as i64 / 2;
        let keep = |k: i64| {
            if n_new % 2 == 0 {
                k.abs() <= half_new
            } else {
                k.abs() < half_new + 1
            }
        };
        let mut push = |k: i64, bin: usize, w: f64| {
            if keep(k) {
                let phase = 2.0 * PI * k as f64 * start / period;
                map.push((
                    bin,
                    k.rem_euclid(n_new as i64) as usize,
                    Complex64::from_polar(w / n as f64, phase),
                ));
            }
        };
        for bin in 0..n {
            let k = if 2 * bin < n {
                bin as i64
            } else {
                bin as i64 - n as i64
            };
            if n % 2 == 0 && 2 * bin == n {
                push(k, bin, 0.5);
                push(-k, bin, 0.5);
            } else {
                push(k, bin, 1.0);
            }
        }
        Self {
            n,
            n_new,
            forward: planner.plan_fft_forward(n),
            inverse: planner.plan_fft_inverse(n_new),
            map,
        }
    }

    fn apply(&self, y: &[f64], out: &mut [f64]) {
        let mut a: Vec<Complex64> = y.iter().map(|&v| Complex64::new(v, 0.0)).collect();
        self.forward.process(&mut a);
        let mut b = vec![Complex64::default(); self.n_new];
        for &(i, j, f) in &self.map {
            b[j] += a[i] * f;
        }
        self.inverse.process(&mut b);
        debug_assert_eq!(a.len(), self.n);
        for (o, v) in out.iter_mut().zip(&b) {
            *o = v.re;
        }
    }
}

#[cfg(test)]
#[path = "resample_tests.rs"]
mod tests;
