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
//! `Theta` is stored through the smooth function
//! `psi(rho) = (Theta(rho) - 1) / rho = int_0^inf (S(u) - 1) J0(rho u) du`
//! (even, analytic for `|Im rho| < 2`): Chebyshev pieces of length 1/2 in
//! `rho` from 0 until `|Theta| < 1e-13` over a whole unit of `rho`
//! (`rho ~ 20-30`), reproducing direct quadrature to ~1e-15; beyond,
//! `Theta = 0`. The same `psi` carries the cell integrals of the layer's
//! Green's function ([`super::cell`]). The curve depends only on the base
//! and `nu`, so it is computed once per process and shared by all
//! thicknesses.

use std::sync::{Arc, Mutex, OnceLock};

use super::quad::gauss_legendre_unit;
use super::KernelError;
use crate::response::layer::{compliance_ratio_minus_one, Layer, LayerBase};

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

/// `psi(rho) = (Theta(rho) - 1) / rho = int_0^inf (S(u) - 1) J0(rho u) du`
/// for one (base, nu) as Chebyshev pieces; independent of the thickness, so
/// it is computed once per process and shared.
///
/// `psi` is even and analytic in the strip `|Im rho| < 2` (`S - 1 ~ u^2
/// e^{-2u}`), so pieces of length [`PIECE`] (Bernstein parameter
/// `8 + sqrt 65 ~ 16` around each) of degree `CHEB - 1 = 13` reach
/// `16^-14 ~ 1e-17` relative to `max |psi|` on the ellipse: the pieces
/// reproduce direct quadrature to ~1e-15 (tests).
#[derive(Debug)]
struct ThetaCurve {
    /// Chebyshev coefficients of `psi` on `[k PIECE, (k+1) PIECE]`.
    pieces: Vec<[f64; CHEB]>,
    /// `rho` beyond which `|Theta| < THETA_FLOOR`: `Theta = 0` there.
    rho_end: f64,
    /// Chebyshev coefficients of the radial moments
    /// `T_k(rho) = int_0^rho s^k Theta(s) ds` (`k = 0, 1`) on each piece.
    moments: Vec<[[f64; MOMENT_CHEB]; 2]>,
    /// `T_0, T_1` at `rho_end` (constant beyond).
    moments_end: [f64; 2],
}

/// Length of one Chebyshev piece in `rho`.
const PIECE: f64 = 0.5;
/// Chebyshev coefficients per piece.
const CHEB: usize = 14;
/// Chebyshev coefficients per piece of the radial moments: on a piece
/// `Theta = 1 + rho psi` is a polynomial of degree `CHEB`, so `T_0` and
/// `T_1` are polynomials of degree `CHEB + 1` and `CHEB + 2`, held exactly.
const MOMENT_CHEB: usize = CHEB + 3;
const U_MAX: f64 = 20.0;
/// The curve ends once `|Theta|` stays below this over two pieces.
const THETA_FLOOR: f64 = 1e-13;
/// Pieces are computed this many at a time (rayon) until the floor.
const PIECES_PER_CHUNK: usize = 8;
/// Hard end of the curve (never reached for either base: `Theta` falls
/// below the floor near `rho ~ 20-30`).
const RHO_CAP: f64 = 200.0;

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
    1.0 + rho * psi_direct(base, nu, rho)
}

/// `psi(rho) = (Theta(rho) - 1) / rho = int_0^inf (S(u) - 1) J0(rho u) du`
/// by the quadrature of [`theta_direct`].
pub fn psi_direct(base: LayerBase, nu: f64, rho: f64) -> f64 {
    let gl = gauss_legendre_unit(16);
    psi_direct_with(base, nu, rho, &gl)
}

fn psi_direct_with(base: LayerBase, nu: f64, rho: f64, gl: &(Vec<f64>, Vec<f64>)) -> f64 {
    let width = (0.5f64).min(std::f64::consts::PI / rho.max(1e-300));
    integrate_u(
        |u| compliance_ratio_minus_one(base, nu, u) * bessel_j0(rho * u),
        width,
        gl,
    )
}

impl ThetaCurve {
    fn new(base: LayerBase, nu: f64) -> Self {
        use rayon::prelude::*;
        let gl = gauss_legendre_unit(16);
        // Chebyshev points of the first kind on [-1, 1].
        let t: [f64; CHEB] = chebyshev_nodes();
        let mut pieces: Vec<[f64; CHEB]> = Vec::new();
        let mut below = 0usize;
        let mut rho_end = RHO_CAP;
        'outer: loop {
            let start = pieces.len();
            let chunk: Vec<([f64; CHEB], bool)> = (start..start + PIECES_PER_CHUNK)
                .into_par_iter()
                .map(|k| {
                    let lo = k as f64 * PIECE;
                    let mut f = [0.0; CHEB];
                    for (fi, ti) in f.iter_mut().zip(&t) {
                        *fi = psi_direct_with(base, nu, lo + 0.5 * PIECE * (ti + 1.0), &gl);
                    }
                    let small = t.iter().zip(&f).all(|(ti, fi)| {
                        let rho = lo + 0.5 * PIECE * (ti + 1.0);
                        (1.0 + rho * fi).abs() < THETA_FLOOR
                    });
                    (chebyshev_fit(&f), small)
                })
                .collect();
            for (c, small) in chunk {
                pieces.push(c);
                below = if small { below + 1 } else { 0 };
                if below == 2 {
                    rho_end = (pieces.len() - 2) as f64 * PIECE;
                    pieces.truncate(pieces.len() - 2);
                    break 'outer;
                }
                if pieces.len() as f64 * PIECE >= RHO_CAP {
                    break 'outer;
                }
            }
        }
        let (moments, moments_end) = moment_pieces(&pieces, &gl);
        Self {
            pieces,
            rho_end,
            moments,
            moments_end,
        }
    }

    /// `psi(rho)`; `-1/rho` beyond the end of the curve.
    #[inline]
    fn psi(&self, rho: f64) -> f64 {
        let rho = rho.abs();
        if rho >= self.rho_end {
            return -1.0 / rho;
        }
        psi_on_pieces(&self.pieces, rho)
    }

    /// `(T_0(rho), T_1(rho))`, `T_k = int_0^rho s^k Theta(s) ds`, for
    /// `rho >= 0`; constant beyond the end of the curve.
    #[inline]
    fn moments(&self, rho: f64) -> [f64; 2] {
        if rho >= self.rho_end {
            return self.moments_end;
        }
        let (k, x) = piece_at(rho, self.moments.len());
        let [c0, c1] = &self.moments[k];
        [clenshaw(c0, x), clenshaw(c1, x)]
    }

    /// `Theta(rho) = 1 + rho psi(rho)`; exactly 0 beyond the end.
    #[inline]
    fn theta(&self, rho: f64) -> f64 {
        if rho >= self.rho_end {
            0.0
        } else {
            1.0 + rho * self.psi(rho)
        }
    }
}

/// The Chebyshev series `sum_j c_j T_j(x)` at `x` in `[-1, 1]` (Clenshaw).
#[inline]
fn clenshaw(c: &[f64], x: f64) -> f64 {
    let (mut b1, mut b2) = (0.0, 0.0);
    for &cj in c[1..].iter().rev() {
        let b0 = 2.0 * x * b1 - b2 + cj;
        b2 = b1;
        b1 = b0;
    }
    x * b1 - b2 + c[0]
}

/// `psi(rho)` from the pieces, for `0 <= rho` within them.
#[inline]
fn psi_on_pieces(pieces: &[[f64; CHEB]], rho: f64) -> f64 {
    let (k, x) = piece_at(rho, pieces.len());
    clenshaw(&pieces[k], x)
}

/// The piece of `0 <= rho` among `count` and the local coordinate in
/// `[-1, 1]` (the last piece is extended).
#[inline]
fn piece_at(rho: f64, count: usize) -> (usize, f64) {
    let k = ((rho / PIECE) as usize).min(count - 1);
    (k, 2.0 * (rho / PIECE - k as f64) - 1.0)
}

/// The `N` first-kind Chebyshev points `t_i = cos(pi (i + 1/2) / N)` on
/// `[-1, 1]`.
fn chebyshev_nodes<const N: usize>() -> [f64; N] {
    std::array::from_fn(|i| (std::f64::consts::PI * (i as f64 + 0.5) / N as f64).cos())
}

/// Chebyshev coefficients of `f` at the `N` first-kind Chebyshev points
/// ([`chebyshev_nodes`], values `f_i`), with the halved leading coefficient.
fn chebyshev_fit<const N: usize>(f: &[f64; N]) -> [f64; N] {
    let mut c = [0.0; N];
    for (j, cj) in c.iter_mut().enumerate() {
        let s: f64 = f
            .iter()
            .enumerate()
            .map(|(i, fi)| {
                fi * (std::f64::consts::PI * j as f64 * (i as f64 + 0.5) / N as f64).cos()
            })
            .sum();
        *cj = 2.0 * s / N as f64;
    }
    c[0] *= 0.5;
    c
}

/// The radial moments `T_k(rho) = int_0^rho s^k Theta(s) ds` (`k = 0, 1`)
/// of the curve's `Theta = 1 + rho psi` on each piece, and their values at
/// the end. On a piece the integrands are polynomials of degree at most
/// `CHEB + 1`, so 16-point Gauss-Legendre from the piece's start and a fit
/// at `MOMENT_CHEB` points reproduce them exactly (to round-off): the
/// moments are the exact integrals of the tabulated `Theta`.
#[allow(clippy::type_complexity)]
fn moment_pieces(
    pieces: &[[f64; CHEB]],
    gl: &(Vec<f64>, Vec<f64>),
) -> (Vec<[[f64; MOMENT_CHEB]; 2]>, [f64; 2]) {
    let theta = |rho: f64| 1.0 + rho * psi_on_pieces(pieces, rho);
    // [T_0, T_1] over [lo, hi].
    let integral = |lo: f64, hi: f64| -> [f64; 2] {
        let mut s = [0.0; 2];
        for (t, w) in gl.0.iter().zip(&gl.1) {
            let rho = lo + (hi - lo) * t;
            let f = w * (hi - lo) * theta(rho);
            s[0] += f;
            s[1] += f * rho;
        }
        s
    };
    let nodes: [f64; MOMENT_CHEB] = chebyshev_nodes();
    let mut start = [0.0; 2];
    let mut out = Vec::with_capacity(pieces.len());
    for k in 0..pieces.len() {
        let lo = k as f64 * PIECE;
        let (mut f0, mut f1) = ([0.0; MOMENT_CHEB], [0.0; MOMENT_CHEB]);
        for ((v0, v1), t) in f0.iter_mut().zip(f1.iter_mut()).zip(&nodes) {
            let part = integral(lo, lo + 0.5 * PIECE * (t + 1.0));
            *v0 = start[0] + part[0];
            *v1 = start[1] + part[1];
        }
        out.push([chebyshev_fit(&f0), chebyshev_fit(&f1)]);
        let whole = integral(lo, lo + PIECE);
        start = [start[0] + whole[0], start[1] + whole[1]];
    }
    (out, start)
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
    /// Tabulate `Theta` for `layer` and Poisson ratio `nu` (rayon over
    /// pieces; the curve for a given base and `nu` is computed once per
    /// process).
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
        self.curve.theta(r / self.layer.thickness)
    }

    /// `Theta(rho)`.
    pub fn eval(&self, rho: f64) -> f64 {
        self.curve.theta(rho)
    }

    /// `psi(rho) = (Theta(rho) - 1) / rho`, smooth (even and analytic in
    /// `|Im rho| < 2`); `-1/rho` beyond [`Self::rho_end`].
    #[inline]
    pub fn psi(&self, rho: f64) -> f64 {
        self.curve.psi(rho)
    }

    /// The radial moments of `Theta(s/h)` up to the distance `r >= 0` \[m\]:
    /// `(int_0^r Theta(s/h) ds [m], int_0^r s Theta(s/h) ds [m^2])`
    /// (exact integrals of the tabulated curve; constant beyond
    /// [`Self::reach`]).
    #[inline]
    pub fn radial_moments(&self, r: f64) -> (f64, f64) {
        let h = self.layer.thickness;
        let [t0, t1] = self.curve.moments(r / h);
        (h * t0, h * h * t1)
    }

    /// `rho = r/h` beyond which `Theta = 0` (`|Theta| < 1e-13` there).
    pub fn rho_end(&self) -> f64 {
        self.curve.rho_end
    }

    /// Distance \[m\] beyond which `Theta = 0`.
    pub fn reach(&self) -> f64 {
        self.curve.rho_end * self.layer.thickness
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::response::layer::compliance_ratio;

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

    /// The radial moments against 16-point Gauss-Legendre on panels of
    /// `h/8` of the tabulated `Theta`, inside and beyond the reach.
    #[test]
    fn radial_moments_are_integrals_of_theta() {
        let gl = gauss_legendre_unit(16);
        for base in [LayerBase::Bonded, LayerBase::Frictionless] {
            let h = 2e-6;
            let t = ThetaTable::new(Layer { thickness: h, base }, 0.5).unwrap();
            for rho in [
                0.1,
                0.77,
                1.0,
                3.3,
                12.0,
                t.rho_end() - 0.01,
                t.rho_end() + 5.0,
            ] {
                let r = rho * h;
                let n = (rho * 8.0).ceil() as usize;
                let b = r / n as f64;
                let (mut m0, mut m1) = (0.0, 0.0);
                for p in 0..n {
                    for (x, w) in gl.0.iter().zip(&gl.1) {
                        let s = (p as f64 + x) * b;
                        m0 += w * b * t.at_distance(s);
                        m1 += w * b * s * t.at_distance(s);
                    }
                }
                let (t0, t1) = t.radial_moments(r);
                assert!(
                    (t0 - m0).abs() < 1e-13 * h,
                    "{base:?} rho {rho}: {t0:e} vs {m0:e}"
                );
                assert!(
                    (t1 - m1).abs() < 1e-13 * h * h,
                    "{base:?} rho {rho}: {t1:e} vs {m1:e}"
                );
            }
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
