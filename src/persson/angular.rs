//! The two angular integrals of Persson's theory. Both depend on the
//! wavenumber `q` and the speed `v` only through `Q = q v` (rad/s):
//!
//! `F(Q) = Int_0^2pi dphi cos(phi) Im E(Q cos phi)`,
//! `K(Q) = Int_0^2pi dphi |E(Q cos phi)|^2`.
//!
//! With `E(-w) = conj E(w)` (physics.md section 2) the integrands are even
//! under `phi -> pi - phi` and `phi -> -phi`, and
//! `cos(phi) Im E(Q cos phi) = |cos phi| E2(Q |cos phi|) >= 0`; so
//! `F = 4 Int_0^{pi/2} dpsi sin(psi) E2(Q sin psi)` and
//! `K = 4 Int_0^{pi/2} dpsi |E(Q sin psi)|^2` with `psi = pi/2 - phi`.
//!
//! Quadrature: `E` varies on a logarithmic frequency scale, so near
//! `psi = 0` (sliding perpendicular to the wavevector, `w -> 0`) the
//! integrand has structure at every `psi ~ 1 / (Q tau_k)`. `[0, pi/2]` is
//! cut into the geometric panels `[pi/2^(k+1), pi/2^k]`, `k = 1..N`, and the
//! remainder `[0, pi/2^(N+1)]`, with `N` chosen so that
//! `Q tau_max pi / 2^(N+1) <= 0.05` (below that frequency `E` is a low-order
//! polynomial in `w`); each panel gets a Gauss-Legendre rule. A pole of
//! `E(w)` at `w = i / theta` (theta a relaxation time) is at least a panel's
//! length away from the panel in the complex `psi` plane, so the error of an
//! `n`-point rule falls like `5.8^(-2n)` (about `1e-12` for the default
//! `n = 8`).

use std::f64::consts::FRAC_PI_2;

use crate::material::CreepSpectrum;

use super::quad::GaussRule;

/// `[F(Q), K(Q)]` \[Pa, Pa^2\] by direct quadrature (module docs), for `Q >= 0`.
pub(crate) fn angular_integrals(spectrum: &CreepSpectrum, q_v: f64, rule: &GaussRule) -> [f64; 2] {
    let tau_max = spectrum.terms.iter().map(|t| t.time).fold(0.0, f64::max);
    let reach = q_v * tau_max * FRAC_PI_2 / 0.05;
    let levels = if reach > 2.0 {
        (reach.log2().ceil() as usize).min(1000)
    } else {
        1
    };
    let mut f = 0.0;
    let mut k = 0.0;
    let mut panel = |a: f64, b: f64| {
        let half = 0.5 * (b - a);
        let (mut pf, mut pk) = (0.0, 0.0);
        for (t, w) in rule.nodes.iter().zip(&rule.weights) {
            let s = (a + half * (t + 1.0)).sin();
            let e = spectrum.modulus(q_v * s);
            pf += w * s * e.im;
            pk += w * e.norm_sqr();
        }
        f += half * pf;
        k += half * pk;
    };
    let mut hi = FRAC_PI_2;
    for _ in 0..levels {
        let lo = 0.5 * hi;
        panel(lo, hi);
        hi = lo;
    }
    panel(0.0, hi);
    [4.0 * f, 4.0 * k]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn elastic_constant_modulus_gives_closed_forms() {
        let s = CreepSpectrum::new(2e6, vec![]).unwrap();
        let r = GaussRule::new(8);
        for q_v in [0.0, 1e-3, 1.0, 1e9] {
            let [f, k] = angular_integrals(&s, q_v, &r);
            assert_eq!(f, 0.0);
            assert!((k / (2.0 * PI * 4e12) - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn sls_matches_a_fine_trapezoidal_rule() {
        // Over a full period the trapezoidal rule converges geometrically.
        let s = CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap();
        let r = GaussRule::new(8);
        for q_v in [1.0, 100.0, 1e4] {
            let m = 200_000;
            let (mut f, mut k) = (0.0, 0.0);
            for i in 0..m {
                let phi = 2.0 * PI * i as f64 / m as f64;
                let e = s.modulus(q_v * phi.cos());
                f += phi.cos() * e.im;
                k += e.norm_sqr();
            }
            let h = 2.0 * PI / m as f64;
            let [fa, ka] = angular_integrals(&s, q_v, &r);
            assert!((fa / (f * h) - 1.0).abs() < 1e-10, "F at Q = {q_v}");
            assert!((ka / (k * h) - 1.0).abs() < 1e-12, "K at Q = {q_v}");
            assert!(fa > 0.0);
        }
    }
}
