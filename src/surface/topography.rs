//! Measured topographies: a height map with its physical pixel sizes along
//! both axes, missing points (NaN) and where it came from (physics.md
//! section 11).
//!
//! A [`Topography`] is what the file readers return ([`super::read_topography`]):
//! heights in metres, `heights[i * ny + j]` with `i` the x index (axis 0,
//! the sliding direction), pixel sides `dx`, `dy` in metres, and `NaN` where
//! the instrument gave no value (an x3p invalid-point mask, a NaN in a map).
//! Missing points are an error by default ([`MissingData::Error`]); with
//! [`MissingData::Fill`] they are filled by harmonic interpolation
//! ([`Topography::fill_missing`]) and the count is kept in
//! [`Topography::filled`] so every output can say so.

use serde::{Deserialize, Serialize};

use super::{HeightMap, SurfaceError};

/// What to do with missing points when a file is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MissingData {
    /// Refuse the file, naming the fraction of missing points.
    #[default]
    Error,
    /// Fill them by harmonic (Laplace) interpolation.
    Fill,
}

/// A height map with physical pixel sizes and possibly missing points.
#[derive(Debug, Clone, PartialEq)]
pub struct Topography {
    /// Points along x (axis 0).
    pub nx: usize,
    /// Points along y (axis 1).
    pub ny: usize,
    /// Pixel side along x \[m\].
    pub dx: f64,
    /// Pixel side along y \[m\].
    pub dy: f64,
    /// Heights \[m\], `heights[i * ny + j]`; `NaN` marks a missing point.
    pub heights: Vec<f64>,
    /// Number of points filled by [`Topography::fill_missing`] (0: none).
    pub filled: usize,
}

impl Topography {
    /// A topography from its parts; checks the shape (at least 2 x 2), the
    /// sizes (finite, > 0) and that no height is infinite (NaN is missing).
    pub fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        heights: Vec<f64>,
        name: &str,
    ) -> Result<Self, SurfaceError> {
        if nx < 2 || ny < 2 || heights.len() != nx * ny {
            return Err(SurfaceError::Shape {
                path: name.to_string(),
                shape: vec![nx, ny],
            });
        }
        for (what, v) in [("pixel size along x", dx), ("pixel size along y", dy)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(SurfaceError::Invalid(format!(
                    "{name}: {what} is {v} m; it must be finite and > 0"
                )));
            }
        }
        if let Some(k) = heights.iter().position(|h| h.is_infinite()) {
            return Err(SurfaceError::NonFinite {
                path: name.to_string(),
                row: k / ny,
                col: k % ny,
                value: heights[k],
            });
        }
        Ok(Self {
            nx,
            ny,
            dx,
            dy,
            heights,
            filled: 0,
        })
    }

    /// The topography of a height map (nothing missing).
    pub fn from_height_map(map: &HeightMap) -> Self {
        Self {
            nx: map.nx,
            ny: map.ny,
            dx: map.cell_size,
            dy: map.cell_size_y,
            heights: map.heights.clone(),
            filled: 0,
        }
    }

    /// Side along x \[m\].
    pub fn length_x(&self) -> f64 {
        self.nx as f64 * self.dx
    }
    /// Side along y \[m\].
    pub fn length_y(&self) -> f64 {
        self.ny as f64 * self.dy
    }

    /// Number of missing (NaN) points.
    pub fn missing(&self) -> usize {
        self.heights.iter().filter(|h| h.is_nan()).count()
    }

    /// Fraction of missing points, in `[0, 1]`.
    pub fn missing_fraction(&self) -> f64 {
        self.missing() as f64 / self.heights.len() as f64
    }

    /// Apply `policy` to the missing points: `Error` refuses a map with any
    /// (the message names the fraction), `Fill` fills them. `name` labels
    /// the error.
    pub fn handle_missing(&mut self, policy: MissingData, name: &str) -> Result<(), SurfaceError> {
        let m = self.missing();
        if m == 0 {
            return Ok(());
        }
        match policy {
            MissingData::Error => Err(SurfaceError::Invalid(format!(
                "{name}: {:.3} % of the points ({m} of {}) are missing (NaN or masked invalid); \
                 fill them by harmonic interpolation with [surface] fill_missing = true (the surface commands' --fill-missing, Python's fill_missing=True)",
                100.0 * m as f64 / self.heights.len() as f64,
                self.heights.len()
            ))),
            MissingData::Fill => self.fill_missing(name),
        }
    }

    /// Fill the missing points by harmonic interpolation: the filled heights
    /// solve the discrete Laplace equation (5-point stencil, pixel sizes
    /// `dx`, `dy`) with the measured points as Dirichlet values and no flux
    /// through the map's edges; solved by conjugate gradients. Needs at least
    /// one measured point.
    pub fn fill_missing(&mut self, name: &str) -> Result<(), SurfaceError> {
        let (nx, ny) = (self.nx, self.ny);
        let unknown: Vec<usize> = (0..nx * ny).filter(|&k| self.heights[k].is_nan()).collect();
        if unknown.is_empty() {
            return Ok(());
        }
        if unknown.len() == nx * ny {
            return Err(SurfaceError::Invalid(format!(
                "{name}: every point is missing; nothing to interpolate from"
            )));
        }
        let mut index = vec![usize::MAX; nx * ny];
        for (u, &k) in unknown.iter().enumerate() {
            index[k] = u;
        }
        let (wx, wy) = (1.0 / (self.dx * self.dx), 1.0 / (self.dy * self.dy));
        let neighbours = |k: usize| {
            let (i, j) = (k / ny, k % ny);
            let mut out = [(usize::MAX, 0.0); 4];
            if i > 0 {
                out[0] = (k - ny, wx);
            }
            if i + 1 < nx {
                out[1] = (k + ny, wx);
            }
            if j > 0 {
                out[2] = (k - 1, wy);
            }
            if j + 1 < ny {
                out[3] = (k + 1, wy);
            }
            out
        };
        // A x = b: sum_n w (x_p - x_n) = 0 over the neighbours n of p.
        let h = &self.heights;
        let n = unknown.len();
        let mut b = vec![0.0; n];
        let mut diag = vec![0.0; n];
        for (u, &k) in unknown.iter().enumerate() {
            for (m, w) in neighbours(k) {
                if m == usize::MAX {
                    continue;
                }
                diag[u] += w;
                if index[m] == usize::MAX {
                    b[u] += w * h[m];
                }
            }
        }
        let apply = |x: &[f64], y: &mut [f64]| {
            for (u, &k) in unknown.iter().enumerate() {
                let mut s = diag[u] * x[u];
                for (m, w) in neighbours(k) {
                    if m != usize::MAX && index[m] != usize::MAX {
                        s -= w * x[index[m]];
                    }
                }
                y[u] = s;
            }
        };
        // Start from the mean of the measured points; Jacobi-preconditioned CG.
        let known: Vec<f64> = h.iter().copied().filter(|v| !v.is_nan()).collect();
        let mean = known.iter().sum::<f64>() / known.len() as f64;
        let mut x = vec![mean; n];
        let mut ax = vec![0.0; n];
        apply(&x, &mut ax);
        let mut r: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
        let mut z: Vec<f64> = r.iter().zip(&diag).map(|(r, d)| r / d).collect();
        let mut p = z.clone();
        let mut rz: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
        let bnorm = b
            .iter()
            .zip(&diag)
            .map(|(b, d)| (b / d).powi(2))
            .sum::<f64>()
            .sqrt()
            .max(known.iter().map(|v| v.abs()).fold(0.0, f64::max) * (n as f64).sqrt())
            .max(f64::MIN_POSITIVE);
        let mut ap = vec![0.0; n];
        let max_iter = 20 * n + 100;
        for _ in 0..max_iter {
            let rn = r
                .iter()
                .zip(&diag)
                .map(|(r, d)| (r / d).powi(2))
                .sum::<f64>()
                .sqrt();
            if rn <= 1e-12 * bnorm {
                break;
            }
            apply(&p, &mut ap);
            let pap: f64 = p.iter().zip(&ap).map(|(a, b)| a * b).sum();
            if pap <= 0.0 {
                break;
            }
            let alpha = rz / pap;
            for u in 0..n {
                x[u] += alpha * p[u];
                r[u] -= alpha * ap[u];
                z[u] = r[u] / diag[u];
            }
            let rz_new: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
            let beta = rz_new / rz;
            rz = rz_new;
            for u in 0..n {
                p[u] = z[u] + beta * p[u];
            }
        }
        for (u, &k) in unknown.iter().enumerate() {
            self.heights[k] = x[u];
        }
        self.filled += n;
        Ok(())
    }

    /// The height map the solver uses: the topography's own pixels as cells
    /// (`dx x dy`, rectangular where they differ; pixels equal to 1e-6
    /// relative are taken as square), nothing missing. `name` labels errors.
    pub fn to_height_map(&self, name: &str) -> Result<HeightMap, SurfaceError> {
        let dy = if ((self.dx - self.dy) / self.dx).abs() > 1e-6 {
            self.dy
        } else {
            self.dx
        };
        let m = self.missing();
        if m > 0 {
            return Err(SurfaceError::Invalid(format!(
                "{name}: {m} missing points; fill them first (--fill-missing)"
            )));
        }
        // Shape and finiteness were checked by `new` and just above.
        Ok(HeightMap {
            nx: self.nx,
            ny: self.ny,
            cell_size: self.dx,
            cell_size_y: dy,
            heights: self.heights.clone(),
        })
    }
}
