//! Anisotropy of the deformed surface (Carbone & Putignano 2014, Section IV,
//! Eq. 11-13; physics.md section 5).
//!
//! The deformed surface `u(x)` is band-filtered to
//! `zeta1 q0 <= |q| <= zeta2 q0` (`q0 = 2 pi / L`, `L` the side of the map
//! along x) with a sharp spectral filter. The PSD of the filtered surface is
//! the PSD of `u` restricted to the band, so the filter is applied as a mask
//! on [`crate::surface::psd_2d`] (normalisation `sum C dq^2 = <u^2>`). The
//! band edges are inclusive: with `zeta1 = 1` the longest wavelength of the
//! map, `|q| = q0`, belongs to the band.

use std::f64::consts::PI;

use serde::Serialize;

use crate::surface::Psd2d;

/// Relative tolerance of the band edges (modes on a band edge are kept).
const EDGE_TOL: f64 = 1e-9;

/// Hurst exponent of the reference field of [`ZetaBand::grid_gamma`]: the
/// roughness of the paper's surfaces and of the shipped configurations.
pub const REFERENCE_HURST: f64 = 0.8;

/// [`ZetaBand::grid_gamma`] below which the band is warned to sample
/// directions too unevenly for `gamma` and `theta_P` (see [`ZetaBand`]).
pub const MIN_GRID_GAMMA: f64 = 0.9;

/// The wavevector band `zeta1 q0 <= |q| <= zeta2 q0` of Eq. 11.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ZetaBand {
    /// Lower factor `zeta1`.
    pub zeta1: f64,
    /// Upper factor `zeta2`.
    pub zeta2: f64,
    /// `q0 = 2 pi / L` [1/m].
    pub q0: f64,
    /// Fourier modes of the grid inside the band (both halves of the plane).
    pub modes: usize,
    /// `gamma` of Eq. 11 that an isotropic self-affine field
    /// (`C ~ |q|^-2(1+H)`, `H` = [`REFERENCE_HURST`]) has on this grid and
    /// band: 1 where the band's modes sample every direction evenly.
    ///
    /// The grid's modes lie on a lattice of spacings `2 pi / Lx` and
    /// `2 pi / Ly`; the band's edges are in units of `q0 = 2 pi / Lx`. On a
    /// map much shorter along y than x the y spacing is several `q0`, and
    /// the band holds mostly (or only) modes along `q_x`: `gamma` and
    /// `theta_P` then describe the map's shape, not the surface. The
    /// expected Eq. 11 tensor of an isotropic field is the sum of
    /// `q_i q_j C(|q|)` over the band's modes, so its `gamma` measures that
    /// bias directly, with the weight the analysis gives each mode (the
    /// low-`q` modes, where the lattice is coarsest, weigh most for a
    /// self-affine spectrum). It is exactly 1 on a square map (a tensor
    /// unchanged by quarter turns is isotropic), whatever the band, and
    /// below [`MIN_GRID_GAMMA`] the analysis warns: the map's shape alone
    /// would then bias `gamma` by more than 10 %. Counting modes per
    /// direction sector would instead flag narrow bands on square maps,
    /// whose few modes still give an isotropic tensor.
    pub grid_gamma: f64,
}

impl ZetaBand {
    /// Whether `|q|` lies in the band (edges included).
    pub fn contains(&self, q: f64) -> bool {
        q >= self.zeta1 * self.q0 * (1.0 - EDGE_TOL) && q <= self.zeta2 * self.q0 * (1.0 + EDGE_TOL)
    }
}

/// A symmetric 2 x 2 anisotropy tensor and its principal values
/// (paper Eq. 11 or 12 and Eq. 13).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AnisotropyTensor {
    /// `M11 = m20` (`<u_x^2>` for Eq. 11).
    pub m20: f64,
    /// `M22 = m02` (`<u_y^2>` for Eq. 11).
    pub m02: f64,
    /// `M12 = m11` (`<u_x u_y>` for Eq. 11).
    pub m11: f64,
    /// Smallest eigenvalue `m2_min`.
    pub m2_min: f64,
    /// Largest eigenvalue `m2_max`.
    pub m2_max: f64,
    /// Degree of isotropy `gamma = m2_min / m2_max` (1: isotropic).
    pub gamma: f64,
    /// Principal direction `theta_P` [degrees, in (-90, 90]] from +x (the
    /// sliding direction) towards +y: the direction maximising `m2(theta)`.
    pub theta_p_deg: f64,
}

impl AnisotropyTensor {
    /// Principal values and direction of `[[m20, m11], [m11, m02]]`.
    pub fn from_components(m20: f64, m02: f64, m11: f64) -> Self {
        let mean = 0.5 * (m20 + m02);
        let half_diff = 0.5 * (m20 - m02);
        let r = half_diff.hypot(m11);
        let (m2_min, m2_max) = (mean - r, mean + r);
        let gamma = if m2_max > 0.0 { m2_min / m2_max } else { 1.0 };
        // m2(theta) = mean + half_diff cos 2 theta + m11 sin 2 theta is
        // largest at 2 theta = atan2(m11, half_diff).
        let theta_p_deg = if r > 0.0 {
            wrap_axis_deg(0.5 * m11.atan2(half_diff).to_degrees())
        } else {
            0.0
        };
        Self {
            m20,
            m02,
            m11,
            m2_min,
            m2_max,
            gamma,
            theta_p_deg,
        }
    }

    /// `m2(theta) = m20 cos^2 + 2 m11 sin cos + m02 sin^2` (Eq. 13), the mean
    /// square slope of a profile cut along `e(theta)`; `theta` in radians.
    pub fn m2(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        self.m20 * c * c + 2.0 * self.m11 * s * c + self.m02 * s * s
    }
}

/// An axial angle (degrees) mapped into (-90, 90].
pub fn wrap_axis_deg(theta: f64) -> f64 {
    let mut t = theta % 180.0;
    if t <= -90.0 {
        t += 180.0;
    }
    if t > 90.0 {
        t -= 180.0;
    }
    t
}

/// Both tensors of Section IV over one band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DeformedAnisotropy {
    pub band: ZetaBand,
    /// Eq. 11: `M_ij = sum q_i q_j C(q) dq^2` [dimensionless when `u` is in m].
    pub tensor: AnisotropyTensor,
    /// Eq. 12: `M_ij = sum q_i q_j / |q|^2 C(q) dq^2` [m^2], which weighs
    /// every scale by its share of `<u^2>` instead of its slope.
    pub normalised: AnisotropyTensor,
    /// `<u^2>` of the filtered surface, `sum C dq^2` over the band [m^2].
    pub mean_square: f64,
}

/// Eq. 11-13 on the PSD `psd` of the deformed surface, over the band
/// `zeta1 q0 <= |q| <= zeta2 q0` with `q0 = 2 pi / (nx dx)`
/// (`dx = 2 pi / (nx dqx)`, i.e. `q0 = psd.dqx`).
///
/// The sums run over the full FFT grid (both half planes), so `M` is exactly
/// `<d_i u_f d_j u_f>` of the filtered surface `u_f` by Parseval.
pub fn deformed_anisotropy(psd: &Psd2d, zeta1: f64, zeta2: f64) -> DeformedAnisotropy {
    let q0 = psd.dqx;
    let mut band = ZetaBand {
        zeta1,
        zeta2,
        q0,
        modes: 0,
        grid_gamma: 1.0,
    };
    let dq2 = psd.dqx * psd.dqy;
    // Accumulate per row and add rows in order (deterministic).
    let mut acc = [0.0f64; 10];
    let mut modes = 0usize;
    for kx in 0..psd.nx {
        let mut row = [0.0f64; 10];
        for ky in 0..psd.ny {
            let (qx, qy) = psd.q(kx, ky);
            let q2 = qx * qx + qy * qy;
            if q2 == 0.0 || !band.contains(q2.sqrt()) {
                continue;
            }
            modes += 1;
            let c = psd.values[kx * psd.ny + ky];
            row[0] += qx * qx * c;
            row[1] += qy * qy * c;
            row[2] += qx * qy * c;
            row[3] += qx * qx / q2 * c;
            row[4] += qy * qy / q2 * c;
            row[5] += qx * qy / q2 * c;
            row[6] += c;
            // The reference field: q_i q_j |q|^-2(1+H).
            let w = q2.powf(-(1.0 + REFERENCE_HURST));
            row[7] += qx * qx * w;
            row[8] += qy * qy * w;
            row[9] += qx * qy * w;
        }
        for (a, r) in acc.iter_mut().zip(row) {
            *a += r;
        }
    }
    band.modes = modes;
    band.grid_gamma = AnisotropyTensor::from_components(acc[7], acc[8], acc[9]).gamma;
    let m: Vec<f64> = acc.iter().map(|v| v * dq2).collect();
    DeformedAnisotropy {
        band,
        tensor: AnisotropyTensor::from_components(m[0], m[1], m[2]),
        normalised: AnisotropyTensor::from_components(m[3], m[4], m[5]),
        mean_square: m[6],
    }
}

/// `m2(theta)` sampled at `n` angles over `[0, 2 pi)` for a polar diagram
/// (paper Fig. 9): `(theta \[rad\], m2)`.
pub fn polar_samples(t: &AnisotropyTensor, n: usize) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|k| {
            let th = 2.0 * PI * k as f64 / n as f64;
            (th, t.m2(th))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn principal_values_of_a_rotated_tensor() {
        // diag(4, 1) rotated by 35 degrees.
        let th = 35f64.to_radians();
        let (s, c) = th.sin_cos();
        let (a, b) = (4.0, 1.0);
        let m20 = a * c * c + b * s * s;
        let m02 = a * s * s + b * c * c;
        let m11 = (a - b) * s * c;
        let t = AnisotropyTensor::from_components(m20, m02, m11);
        assert!((t.m2_max - 4.0).abs() < 1e-12 && (t.m2_min - 1.0).abs() < 1e-12);
        assert!((t.gamma - 0.25).abs() < 1e-12);
        assert!((t.theta_p_deg - 35.0).abs() < 1e-9, "{}", t.theta_p_deg);
        assert!((t.m2(th) - 4.0).abs() < 1e-12);
        // Transpose (x <-> y): theta -> 90 - theta.
        let t2 = AnisotropyTensor::from_components(m02, m20, m11);
        assert!((t2.theta_p_deg - 55.0).abs() < 1e-9, "{}", t2.theta_p_deg);
        // Rotation by 90 degrees: theta -> theta + 90 = -55 (axial).
        let t3 = AnisotropyTensor::from_components(m02, m20, -m11);
        assert!((t3.theta_p_deg + 55.0).abs() < 1e-9, "{}", t3.theta_p_deg);
    }

    #[test]
    fn axial_angles_wrap_into_half_open_interval() {
        assert_eq!(wrap_axis_deg(90.0), 90.0);
        assert_eq!(wrap_axis_deg(-90.0), 90.0);
        assert!((wrap_axis_deg(120.0) + 60.0).abs() < 1e-12);
        assert!((wrap_axis_deg(-100.0) - 80.0).abs() < 1e-12);
    }
}
