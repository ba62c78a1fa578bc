//! Finite thickness correction `Theta(r/h)` of the paper's Eq. 5 (physics.md
//! section 3, "Finite thickness").
//!
//! `Theta(rho) = int_0^inf S(w / rho) J0(w) dw = 1 + rho int_0^inf (S(u) - 1) J0(rho u) du`
//! with `rho = r/h` and `S(qh)` the ratio of the layer's Fourier surface
//! compliance to the half-space's (`S -> 1` for `qh -> inf`). `S(u) - 1`
//! decays like `u e^{-2u}`, so the second form converges absolutely.
//!
//! Two base conditions:
//! * bonded to a rigid base:
//!   `1/S = [(3-4nu) cosh 2u + 2u^2 + 5 - 12nu + 8nu^2] / [(3-4nu) sinh 2u - 2u]`;
//!   for `u -> 0`, `S ~ u (1-2nu) / (2 (1-nu)^2)`, the oedometric limit
//!   `w = p h (1+nu)(1-2nu) / ((1-nu) E)`. At `nu = 0.5` the leading term
//!   vanishes: a thin bonded incompressible layer has zero compliance to
//!   leading order (`S = O(u^3)`).
//! * sliding frictionlessly on a rigid base (plane-strain layer with zero
//!   shear traction and zero normal displacement at the base):
//!   `S = (cosh 2u - 1) / (sinh 2u + 2u)`, independent of `nu`; for
//!   `u -> 0`, `S ~ u/2`, i.e. `w = p h (1-nu^2)/E` (uniaxial strain with free
//!   lateral expansion in plane strain).
//!
//! Both `S` are odd in `u`, so `Theta` decays faster than any power of
//! `rho` for `r >> h`; for `r << h`, `Theta = 1 + c1 rho + c3 rho^3 + c5 rho^5 + ...`
//! with `c1 = int (S-1) du`, `c3 = -1/4 int u^2 (S-1) du`,
//! `c5 = 1/64 int u^4 (S-1) du` (from the series of `J0`).
//!
//! `Theta` is tabulated on a log grid of `rho` (256 nodes per decade, from
//! `1e-2` until `|Theta| < 1e-13` for a quarter decade, i.e. `rho ~ 30` for
//! the bonded base) and interpolated with cubic Lagrange polynomials in
//! `ln rho` (interpolation error ~1e-9 absolute, largest near `rho ~ 1-2`
//! where `Theta` turns over); below the grid the series is used, above it
//! `Theta = 0`. The curve depends only on the base and `nu`, so it is
//! computed once per process and shared by all thicknesses.

use std::sync::{Arc, Mutex, OnceLock};

use serde::{Deserialize, Serialize};

use super::quad::gauss_legendre_unit;
use super::KernelError;
pub use crate::config::{LayerBase, LayerConfig};

/// A viscoelastic layer of finite thickness on a rigid base (Eq. 5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Layer {
    /// Thickness `h` \[m\].
    pub thickness: f64,
    pub base: LayerBase,
}

impl LayerConfig {
    /// The layer, after checking the thickness.
    pub fn build(&self) -> Result<Layer, KernelError> {
        let l = Layer {
            thickness: self.thickness,
            base: self.base,
        };
        l.validate()?;
        Ok(l)
    }
}

impl Layer {
    /// Thickness must be positive and finite.
    pub fn validate(&self) -> Result<(), KernelError> {
        if !(self.thickness.is_finite() && self.thickness > 0.0) {
            return Err(KernelError::Invalid(format!(
                "[layer] thickness = {} m must be positive and finite",
                self.thickness
            )));
        }
        Ok(())
    }
}

/// Compliance ratio `S(qh)` of the layer to the half-space (Eq. 5).
pub fn compliance_ratio(base: LayerBase, nu: f64, u: f64) -> f64 {
    if u > 30.0 {
        return 1.0 + compliance_ratio_minus_one(base, nu, u);
    }
    let u = u.abs();
    match base {
        LayerBase::Bonded => {
            let k = 3.0 - 4.0 * nu;
            let num = k * (2.0 * u).sinh() - 2.0 * u;
            let den = k * (2.0 * u).cosh() + 2.0 * u * u + 5.0 - 12.0 * nu + 8.0 * nu * nu;
            num / den
        }
        LayerBase::Frictionless => {
            if u < 1e-4 {
                // (cosh 2u - 1)/(sinh 2u + 2u) = u/2 - u^3/6 + ...
                return u / 2.0 - u * u * u / 6.0;
            }
            ((2.0 * u).cosh() - 1.0) / ((2.0 * u).sinh() + 2.0 * u)
        }
    }
}

/// `S(u) - 1` without cancellation for large `u` (written with `e^{-2u}`).
pub fn compliance_ratio_minus_one(base: LayerBase, nu: f64, u: f64) -> f64 {
    if u < 2.0 {
        return compliance_ratio(base, nu, u) - 1.0;
    }
    let e = (-2.0 * u).exp();
    match base {
        LayerBase::Bonded => {
            // num - den over den, multiplied through by 2 e^{-2u}.
            let k = 3.0 - 4.0 * nu;
            let c = 5.0 - 12.0 * nu + 8.0 * nu * nu;
            // sinh - cosh = -e^{-2u}.
            let diff = -2.0 * k * e * e - 2.0 * (2.0 * u + 2.0 * u * u + c) * e;
            let den = k * (1.0 + e * e) + 2.0 * (2.0 * u * u + c) * e;
            diff / den
        }
        LayerBase::Frictionless => {
            // (cosh - 1 - sinh - 2u) / (sinh + 2u), times 2 e^{-2u}.
            let diff = 2.0 * e * e - 2.0 * e - 4.0 * u * e;
            let den = 1.0 - e * e + 4.0 * u * e;
            diff / den
        }
    }
}

/// Bessel function `J0(x)` to ~1e-16 absolute: for `|x| <= 25` the midpoint
/// rule on `J0(x) = (1/pi) int_0^pi cos(x sin t) dt` (periodic analytic
/// integrand: error ~ `2 J_{2N}(x)`, negligible for `N = 16 + 0.8 x`), beyond it the
/// Hankel asymptotic expansion (smallest term ~ `e^{-2x}`).
pub fn bessel_j0(x: f64) -> f64 {
    let x = x.abs();
    if x <= 25.0 {
        // N >= 16 + 0.8 x keeps 2 J_{2N}(x) below 1e-19.
        let n = 16 + (0.8 * x) as usize;
        let mut s = 0.0;
        for j in 0..n {
            let t = std::f64::consts::PI * (j as f64 + 0.5) / n as f64;
            s += (x * t.sin()).cos();
        }
        return s / n as f64;
    }
    // P, Q series: a_k = prod_{m=1..k} (2m-1)^2 / (k! 8^k), alternating.
    let mut p = 1.0;
    let mut q = 0.0;
    let mut term = 1.0;
    let mut k = 1;
    loop {
        let m = (2 * k - 1) as f64;
        term *= m * m / (k as f64 * 8.0 * x);
        if term < 1e-17 || k > 60 {
            break;
        }
        // k odd -> Q gets (-1)^((k-1)/2) term, k even -> P gets (-1)^(k/2) term.
        if k % 2 == 1 {
            let sign = if (k / 2) % 2 == 0 { -1.0 } else { 1.0 };
            q += sign * term;
        } else {
            let sign = if (k / 2) % 2 == 0 { 1.0 } else { -1.0 };
            p += sign * term;
        }
        k += 1;
    }
    let phase = x - std::f64::consts::FRAC_PI_4;
    (2.0 / (std::f64::consts::PI * x)).sqrt() * (p * phase.cos() - q * phase.sin())
}

/// Tabulated `Theta(r/h)` for one layer (thickness, base) and Poisson ratio.
#[derive(Debug, Clone)]
pub struct ThetaTable {
    pub layer: Layer,
    pub poisson: f64,
    curve: Arc<ThetaCurve>,
}

/// `Theta(rho)` samples for one (base, nu); independent of the thickness,
/// so it is computed once per process and shared.
#[derive(Debug)]
struct ThetaCurve {
    /// `ln rho` of the first node.
    ln_rho0: f64,
    /// Node spacing in `ln rho`.
    step: f64,
    values: Vec<f64>,
    /// Series coefficients `c1, c3, c5` for `rho < RHO_MIN`.
    series: [f64; 3],
}

const RHO_MIN: f64 = 1e-2;
const PER_DECADE: f64 = 256.0;
const U_MAX: f64 = 20.0;
/// The table ends once `|Theta|` stays below this for a quarter decade.
const THETA_FLOOR: f64 = 1e-13;

/// `int_0^U_MAX g(u) du` by 16-point Gauss-Legendre panels of width `<= width`.
fn integrate_u(mut g: impl FnMut(f64) -> f64, width: f64, gl: &(Vec<f64>, Vec<f64>)) -> f64 {
    let n = (U_MAX / width).ceil() as usize;
    let h = U_MAX / n as f64;
    let mut s = 0.0;
    for p in 0..n {
        let a = p as f64 * h;
        for (t, w) in gl.0.iter().zip(&gl.1) {
            s += w * h * g(a + h * t);
        }
    }
    s
}

/// `Theta(rho)` by direct quadrature of Eq. 5 (second form): 16-point
/// Gauss-Legendre panels of at most half a period of `J0(rho u)` and at most
/// 0.5 in `u`, up to `u = 20` (`|S - 1| < 1e-14` beyond).
pub fn theta_direct(base: LayerBase, nu: f64, rho: f64) -> f64 {
    let gl = gauss_legendre_unit(16);
    theta_direct_with(base, nu, rho, &gl)
}

fn theta_direct_with(base: LayerBase, nu: f64, rho: f64, gl: &(Vec<f64>, Vec<f64>)) -> f64 {
    let width = (0.5f64).min(std::f64::consts::PI / rho);
    1.0 + rho
        * integrate_u(
            |u| compliance_ratio_minus_one(base, nu, u) * bessel_j0(rho * u),
            width,
            gl,
        )
}

impl ThetaCurve {
    fn new(base: LayerBase, nu: f64) -> Self {
        use rayon::prelude::*;
        let gl = gauss_legendre_unit(16);
        let m = |p: i32, c: f64| {
            c * integrate_u(
                |u| u.powi(p) * compliance_ratio_minus_one(base, nu, u),
                0.25,
                &gl,
            )
        };
        let series = [m(0, 1.0), m(2, -0.25), m(4, 1.0 / 64.0)];
        let step = std::f64::consts::LN_10 / PER_DECADE;
        let ln_rho0 = RHO_MIN.ln() - step; // one node below for the cubic stencil
        let mut values: Vec<f64> = Vec::new();
        let chunk = (PER_DECADE / 4.0) as usize;
        loop {
            let start = values.len();
            let new: Vec<f64> = (start..start + chunk)
                .into_par_iter()
                .map(|i| theta_direct_with(base, nu, (ln_rho0 + step * i as f64).exp(), &gl))
                .collect();
            values.extend(new);
            let tail = &values[values.len().saturating_sub(chunk)..];
            let rho_end = (ln_rho0 + step * values.len() as f64).exp();
            if tail.iter().all(|v| v.abs() < THETA_FLOOR) || rho_end > 1e3 {
                break;
            }
        }
        Self {
            ln_rho0,
            step,
            values,
            series,
        }
    }

    fn eval(&self, rho: f64) -> f64 {
        if rho < RHO_MIN {
            let r2 = rho * rho;
            return 1.0 + rho * (self.series[0] + r2 * (self.series[1] + r2 * self.series[2]));
        }
        let t = (rho.ln() - self.ln_rho0) / self.step;
        let i = t.floor() as isize;
        let n = self.values.len() as isize;
        if i + 2 >= n {
            return 0.0;
        }
        let i0 = (i - 1).max(0) as usize;
        let f = t - i0 as f64; // position relative to node i0, in [1, 2)
        let v = &self.values[i0..i0 + 4];
        // Cubic Lagrange through nodes 0..3 at f.
        let (a, b, c, d) = (f, f - 1.0, f - 2.0, f - 3.0);
        -v[0] * b * c * d / 6.0 + v[1] * a * c * d / 2.0 - v[2] * a * b * d / 2.0
            + v[3] * a * b * c / 6.0
    }
}

type CurveCache = Mutex<Vec<((LayerBase, u64), Arc<ThetaCurve>)>>;

fn cached_curve(base: LayerBase, nu: f64) -> Arc<ThetaCurve> {
    static CACHE: OnceLock<CurveCache> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(Vec::new()));
    let key = (base, nu.to_bits());
    if let Some((_, c)) = cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .find(|(k, _)| *k == key)
    {
        return c.clone();
    }
    let curve = Arc::new(ThetaCurve::new(base, nu));
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push((key, curve.clone()));
    curve
}

impl ThetaTable {
    /// Tabulate `Theta` for `layer` and Poisson ratio `nu` (rayon over nodes;
    /// the curve for a given base and `nu` is computed once per process).
    pub fn new(layer: Layer, nu: f64) -> Result<Self, KernelError> {
        layer.validate()?;
        Ok(Self {
            layer,
            poisson: nu,
            curve: cached_curve(layer.base, nu),
        })
    }

    /// `Theta(r / h)` at distance `r` \[m\].
    #[inline]
    pub fn at_distance(&self, r: f64) -> f64 {
        self.curve.eval(r / self.layer.thickness)
    }

    /// `Theta(rho)`.
    pub fn eval(&self, rho: f64) -> f64 {
        self.curve.eval(rho)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn j0_reference_values() {
        // Reference values from mpmath (30 digits); 25 and 25.000001 straddle
        // the switch between the two methods.
        let cases = [
            (0.0, 1.0),
            (1.0, 0.765_197_686_557_966_6),
            (2.404_825_557_695_773, 0.0),
            (5.0, -0.177_596_771_314_338_3),
            (10.0, -0.245_935_764_451_348_3),
            (25.0, 0.096_266_783_275_958_12),
            (25.000_001, 0.096_266_908_626_157_06),
            (26.0, 0.155_999_315_522_421_13),
            (30.0, -0.086_367_983_581_040_21),
            (100.0, 0.019_985_850_304_223_12),
        ];
        for (x, v) in cases {
            assert!(
                (bessel_j0(x) - v).abs() < 2e-15,
                "J0({x}) = {} vs {v}",
                bessel_j0(x)
            );
        }
    }

    #[test]
    fn minus_one_forms_agree() {
        for base in [LayerBase::Bonded, LayerBase::Frictionless] {
            for u in [2.0, 3.0, 5.0, 10.0] {
                let a = compliance_ratio(base, 0.3, u) - 1.0;
                let b = compliance_ratio_minus_one(base, 0.3, u);
                assert!((a - b).abs() < 1e-14, "{base:?} {u} {a} {b}");
            }
        }
    }
}
