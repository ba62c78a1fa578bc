//! The Fourier side of the heat problem on a periodic cell (physics.md
//! section 14): for the mode `exp(i k.x)` (forward transform
//! `exp(-i k.x)`, as rustfft/realfft), `theta'' - m^2 theta = -Q / lam`
//! with `m^2 = |k|^2 - i v (k.e_v) / kappa`, `Re m > 0`; the response of
//! every mode to a surface flux and to a source constant within a depth
//! layer, in closed form.
//!
//! The grid's modes are treated as the periodic elastic formulation treats
//! them (`operator/periodic.rs`): the continuous multiplier is sampled at
//! the grid wavevectors `k = 2 pi (k_i / L_x, k_j / L_y)` (the source as
//! band-limited, not piecewise constant), and a Nyquist mode gets the
//! average over the signs of its Nyquist components, which keeps the
//! operator real. `k = 0` has no steady state and is left to the caller.

use num_complex::Complex64;

use crate::operator::{nyquist_signs, signed_index};

/// `m` of the wavevector `(kx, ky)` \[1/m\]: the root of
/// `m^2 = |k|^2 - i rate (k.e)` with `Re m > 0` (`rate = v / kappa`);
/// `m(-k) = conj m(k)`.
pub fn decay_rate(k: (f64, f64), e: (f64, f64), rate: f64) -> Complex64 {
    let k2 = k.0 * k.0 + k.1 * k.1;
    Complex64::new(k2, -rate * (k.0 * e.0 + k.1 * e.1)).sqrt()
}

/// `(1 - exp(-w)) / w` (1 at `w = 0`) without cancellation, `Re w >= 0`.
pub fn phi1(w: Complex64) -> Complex64 {
    if w.norm() < 1e-4 {
        // Error below |w|^5 / 720 < 2e-23.
        let w2 = w * w;
        return Complex64::new(1.0, 0.0) - w / 2.0 + w2 / 6.0 - w2 * w / 24.0 + w2 * w2 / 120.0;
    }
    -expm1(-w) / w
}

/// `phi1(w)` from `e = exp(-w)` (already at hand): `(1 - e) / w` where
/// `|w| >= 1/8`, whose cancellation costs at most a factor `1 / (1 -
/// exp(-1/8)) < 9` on the rounding of `e` (about 1e-15 relative); the
/// series or `expm1` of [`phi1`] below.
pub fn phi1_with(w: Complex64, e: Complex64) -> Complex64 {
    if w.norm() >= 0.125 {
        (1.0 - e) / w
    } else {
        phi1(w)
    }
}

/// `exp(w) - 1` accurate for small `|w|`: `(e^x - 1) cos y - 2 sin^2(y/2)
/// + i e^x sin y`.
fn expm1(w: Complex64) -> Complex64 {
    let (x, y) = (w.re, w.im);
    let half = (0.5 * y).sin();
    Complex64::new(x.exp_m1() * y.cos() - 2.0 * half * half, x.exp() * y.sin())
}

/// `Int_a^b [exp(-m |z - z'|) + exp(-m (z + z'))] dz'` \[m\], the depth
/// integral of a source constant on the layer `[a, b]` seen at depth `z`
/// (all `>= 0`), in closed form.
pub fn layer_integral(m: Complex64, (a, b): (f64, f64), z: f64) -> Complex64 {
    let h = b - a;
    let whole = h * phi1(m * h);
    let image = (-m * (z + a)).exp() * whole;
    let direct = if z <= a {
        (-m * (a - z)).exp() * whole
    } else if z >= b {
        (-m * (z - b)).exp() * whole
    } else {
        (z - a) * phi1(m * (z - a)) + (b - z) * phi1(m * (b - z))
    };
    direct + image
}

/// The grid's modes: wavevectors of a periodic cell, with the sliding
/// direction and `v / kappa`.
#[derive(Debug, Clone, Copy)]
pub struct Modes {
    pub nx: usize,
    pub ny: usize,
    /// Period along x and y \[m\].
    pub length: (f64, f64),
    /// `e_v`.
    pub e: (f64, f64),
    /// `v / kappa` \[1/m\].
    pub rate: f64,
}

impl Modes {
    /// The average of `f(m(k))` over the signs of the Nyquist components
    /// of mode `(i, j)` (`i < nx`, `j <= ny / 2`); `None` for `k = 0`.
    pub fn average(
        &self,
        i: usize,
        j: usize,
        mut f: impl FnMut(Complex64) -> Complex64,
    ) -> Option<Complex64> {
        if i == 0 && j == 0 {
            return None;
        }
        let (kx, nyq_x) = signed_index(i, self.nx);
        let (ky, nyq_y) = signed_index(j, self.ny);
        let tau = std::f64::consts::TAU;
        let (qx, qy) = (tau * kx / self.length.0, tau * ky / self.length.1);
        let sx = nyquist_signs(nyq_x);
        let sy = nyquist_signs(nyq_y);
        let mut acc = Complex64::default();
        for &s in sx {
            for &t in sy {
                acc += f(decay_rate((s * qx, t * qy), self.e, self.rate));
            }
        }
        Some(acc / (sx.len() * sy.len()) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `phi1` and `layer_integral` against direct sums: the series and the
    /// closed form agree with a 64-point Gauss rule of the integrand.
    #[test]
    fn closed_forms_match_quadrature() {
        let (x, w) = crate::gauss::gauss_legendre(64);
        for m in [
            Complex64::new(3.0, -2.0),
            Complex64::new(0.01, 0.02),
            Complex64::new(40.0, -35.0),
        ] {
            for (a, b) in [(0.0, 0.1), (0.05, 0.2)] {
                for z in [0.0, 0.03, 0.07, 0.12, 0.5] {
                    // Split at z so the kink of |z - z'| falls on a node edge.
                    let mut pieces = vec![a, b];
                    if a < z && z < b {
                        pieces.insert(1, z);
                    }
                    let mut quad = Complex64::default();
                    for p in pieces.windows(2) {
                        let (c, h) = (0.5 * (p[0] + p[1]), 0.5 * (p[1] - p[0]));
                        for (xi, wi) in x.iter().zip(&w) {
                            let zp = c + h * xi;
                            quad += h * wi * ((-m * (z - zp).abs()).exp() + (-m * (z + zp)).exp());
                        }
                    }
                    let exact = layer_integral(m, (a, b), z);
                    assert!(
                        (exact - quad).norm() <= 1e-12 * quad.norm(),
                        "{m} {a} {b} {z}"
                    );
                }
            }
        }
        for w in [1e-3, 0.124, 0.126, 0.5, 3.0, 40.0] {
            for arg in [0.0f64, 1.0, -1.5] {
                let z = Complex64::from_polar(w, arg);
                let reference = phi1(z);
                let fast = phi1_with(z, (-z).exp());
                assert!((fast - reference).norm() <= 2e-15 * reference.norm(), "{z}");
            }
        }
        for w in [1e-6, 9e-5, 1.1e-4, 0.3] {
            for arg in [0.0f64, 1.0, -1.2] {
                let z = Complex64::from_polar(w, arg);
                let direct = (Complex64::new(1.0, 0.0) - (-z).exp()) / z;
                let tol = if w < 1e-3 { 1e-9 } else { 1e-14 };
                assert!((phi1(z) - direct).norm() < tol, "{z}");
            }
        }
    }
}
