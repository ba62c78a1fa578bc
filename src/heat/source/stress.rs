//! The stress under one surface pressure mode (physics.md section 14): a
//! pressure `P exp(i q.x)` (compressive positive) on the half-space
//! `z >= 0` gives, in the frame `(xi, eta, z)` with `xi` along `q`,
//! `t = |q| z`, `f = exp(-t)` (Johnson, Contact Mechanics, sec. 2.9, the
//! plane-strain solution of a sinusoidal pressure, tension positive):
//!
//! `s_xixi = -(1 - t) f`, `s_zz = -(1 + t) f`, `s_xiz = i t f`,
//! `s_etaeta = nu (s_xixi + s_zz) = -2 nu f` (plane strain),
//!
//! times `P`. The in-plane stresses hold for any isotropic solid: they do
//! not depend on the modulus, so the viscoelastic solid with a constant
//! Poisson ratio (the Green's function of physics.md section 3) carries
//! them at every speed. The trace is `-2 (1 + nu) f`; for `nu = 0.5` the
//! deviator is `t f` times a fixed pattern and vanishes at the surface.

use num_complex::Complex64;

/// Deviatoric components `(xx, yy, xy, xz, yz)` (`zz = -xx - yy`) and the
/// trace of the stress of a unit mode `exp(i q.x)` at depth `z`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct ModeStress {
    pub dev: [Complex64; 5],
    pub trace: Complex64,
}

/// The stress of the unit pressure mode of wavevector `q` \[1/m\]
/// (`q != 0`) at depth `z` \[m\] in a solid of Poisson ratio `nu`.
pub(crate) fn mode_stress(q: (f64, f64), z: f64, nu: f64) -> ModeStress {
    let k = q.0.hypot(q.1);
    stress_at(q, k * z, (-k * z).exp(), nu)
}

/// The stress of the unit mode of wavevector `q` with `t = |q| z` and `f =
/// exp(-t)` given: `f` times [`unit_component`] of the direction `q / |q|`.
pub(crate) fn stress_at(q: (f64, f64), t: f64, f: f64, nu: f64) -> ModeStress {
    let k = q.0.hypot(q.1);
    let n = (q.0 / k, q.1 / k);
    let c = |i| unit_component(n, t, nu, i) * f;
    ModeStress {
        dev: [c(0), c(1), c(2), c(3), c(4)],
        trace: c(5),
    }
}

/// Component `c` (the deviatoric `xx, yy, xy, xz, yz`, then the trace) of
/// the stress of the unit mode of direction `n = q / |q|` at `t = |q| z`,
/// divided by `exp(-t)`: every component is `a + b t`.
pub(crate) fn unit_component(n: (f64, f64), t: f64, nu: f64, c: usize) -> Complex64 {
    // s_zz = -(1 + t) f enters through the trace: dev_zz = -dev_xx - dev_yy.
    let sxixi = -(1.0 - t);
    let see = -2.0 * nu;
    let trace = -2.0 * (1.0 + nu);
    let mean = trace / 3.0;
    let re = |v: f64| Complex64::new(v, 0.0);
    match c {
        0 => re(sxixi * n.0 * n.0 + see * n.1 * n.1 - mean),
        1 => re(sxixi * n.1 * n.1 + see * n.0 * n.0 - mean),
        2 => re((sxixi - see) * n.0 * n.1),
        3 => Complex64::new(0.0, t * n.0),
        4 => Complex64::new(0.0, t * n.1),
        _ => re(trace),
    }
}

/// The dissipation form `(1 + nu) |dev r|^2 + (1 - 2 nu) / 3 (tr r)^2` of
/// a real stress-rate field at one point, from its deviatoric components
/// `(xx, yy, xy, xz, yz)` and trace (physics.md section 14: for
/// `nu = 0.5`, `(3/2) |dev r|^2`). Non-negative for `-1 < nu <= 0.5`.
pub(crate) fn dissipation_form(dev: &[f64; 5], trace: f64, nu: f64) -> f64 {
    let [xx, yy, xy, xz, yz] = *dev;
    let zz = -(xx + yy);
    let dev2 = xx * xx + yy * yy + zz * zz + 2.0 * (xy * xy + xz * xz + yz * yz);
    (1.0 + nu) * dev2 + (1.0 - 2.0 * nu) / 3.0 * trace * trace
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The depth integral of the form over one mode is `2 (1 - nu^2) / |q|`
    /// (the mode's share of the friction, physics.md section 6, per unit
    /// `|c|^2`), by a midpoint sum (error `O(h^2)`, about 1e-9 here).
    #[test]
    fn one_mode_integrates_to_the_surface_compliance() {
        for nu in [0.5, 0.3, -0.2] {
            for q in [(3.0, 4.0), (-2.0, 0.5)] {
                let k = f64::hypot(q.0, q.1);
                let (h, n) = (1e-4 / k, 400_000);
                let mut sum = 0.0;
                for i in 0..n {
                    let s = mode_stress(q, (i as f64 + 0.5) * h, nu);
                    // The Hermitian form of a complex mode: the form of its
                    // real part plus that of its imaginary part.
                    let part = |f: fn(&Complex64) -> f64| {
                        let d = s.dev.map(|c| f(&c));
                        dissipation_form(&d, f(&s.trace), nu)
                    };
                    sum += h * (part(|c| c.re) + part(|c| c.im));
                }
                let want = 2.0 * (1.0 - nu * nu) / k;
                assert!((sum / want - 1.0).abs() < 1e-8, "{nu} {q:?}: {sum} {want}");
            }
        }
    }
}
