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

/// `Re w` beyond which [`exp_phi1`] takes `exp(-w)` as 0: `exp(-40) =
/// 4e-18`, below the rounding of the 1 it is subtracted from and of every
/// sum it enters (`exp(-w)` multiplies what the layers above carry down).
const EXP_CUT: f64 = 40.0;

/// `(exp(-w), phi1(w))` for `Re w >= 0`, with as few transcendental calls
/// as the range allows:
/// - `|w| < 1/8`: [`phi1`]'s Taylor series to `w^12` (remainder below
///   `(1/8)^13 / 14! = 2e-23`) and `exp(-w) = 1 - w phi1(w)`, exact to
///   a few units of rounding of 1; no exponential at all;
/// - `Re w > EXP_CUT`: `exp(-w)` below `4e-18`, taken as 0, and `phi1 =
///   1 / w`;
/// - otherwise one complex exponential and `(1 - e) / w`, whose
///   cancellation costs at most a factor `1 / (1 - exp(-1/8)) < 9` on the
///   rounding of `e` (about 1e-15 relative).
pub fn exp_phi1(w: Complex64) -> (Complex64, Complex64) {
    const ONE: Complex64 = Complex64::new(1.0, 0.0);
    if w.norm_sqr() < 1.0 / 64.0 {
        // 1 / (n + 1)! for n = 12 down to 0.
        const C: [f64; 13] = [
            1.0 / 6_227_020_800.0,
            1.0 / 479_001_600.0,
            1.0 / 39_916_800.0,
            1.0 / 3_628_800.0,
            1.0 / 362_880.0,
            1.0 / 40_320.0,
            1.0 / 5_040.0,
            1.0 / 720.0,
            1.0 / 120.0,
            1.0 / 24.0,
            1.0 / 6.0,
            1.0 / 2.0,
            1.0,
        ];
        let x = -w;
        let p = C[1..]
            .iter()
            .fold(Complex64::new(C[0], 0.0), |p, &c| p * x + c);
        return (ONE - w * p, p);
    }
    if w.re > EXP_CUT {
        return (Complex64::default(), w.inv());
    }
    let e = (-w).exp();
    (e, (ONE - e) / w)
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

    /// `exp_phi1` against `exp` and `phi1` on each side of its two
    /// switches and in between: `exp(-w)` within 2.5e-16 relative (4.5e-18
    /// absolute where it is cut to 0), `phi1` within 2e-15 relative (`(1 -
    /// e) / w` just above `|w| = 1/8` loses up to a factor 9 on the
    /// rounding of `e`; the expm1 form of `phi1` is itself a few 1e-16 off
    /// below it).
    #[test]
    fn exp_phi1_matches_exp_and_phi1() {
        for r in [
            1e-9, 1e-5, 0.01, 0.1, 0.124999, 0.125001, 0.5, 3.0, 39.9, 40.1, 300.0,
        ] {
            for angle in [-1.2, -0.5, 0.0, 0.7, 1.5] {
                let w = Complex64::from_polar(r, angle);
                let (e, p) = exp_phi1(w);
                let (e_ref, p_ref) = ((-w).exp(), phi1(w));
                assert!(
                    (e - e_ref).norm() <= 4.5e-18_f64.max(2.5e-16 * e_ref.norm()),
                    "exp at {w}: {e} {e_ref}"
                );
                assert!(
                    (p - p_ref).norm() <= 2e-15 * p_ref.norm(),
                    "phi1 at {w}: {p} {p_ref}"
                );
            }
        }
        // Against the series summed in exact rational arithmetic (30
        // terms, rounded once), where `phi1`'s expm1 form is 2.3e-16 off.
        let w = Complex64::new(0.008775825618903728, -0.00479425538604203);
        let exact = Complex64::new(0.9956210892470281, 0.002383144663206966);
        assert!((exp_phi1(w).1 - exact).norm() <= 1.2e-16 * exact.norm());
    }

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
