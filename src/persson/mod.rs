//! Persson's theory of rubber friction and contact area, the analytic
//! reference beside the simulations (physics.md section 10; B. N. J. Persson,
//! J. Chem. Phys. 115, 3840 (2001); J. Phys.: Condens. Matter 18, 7789
//! (2006)).
//!
//! A rigid, isotropically rough surface with radial PSD `C(q)` slides at
//! speed `v` over a viscoelastic half-space under the nominal pressure
//! `sigma0`. With `E*(w) = E(w) / (1 - nu^2)`:
//!
//! ```text
//! mu   = 1/2 Int_{qL}^{q1} dq q^3 C(q) P(q) Int_0^2pi dphi cos(phi) Im E*(q v cos phi) / sigma0
//! P(q) = erf(1 / (2 sqrt(G(q))))
//! G(q) = 1/8 Int_{qL}^{q} dq' q'^3 C(q') Int_0^2pi dphi |E*(q' v cos phi) / sigma0|^2
//! A/A0 = P(q1)
//! ```
//!
//! `qL` and `q1` are the ends of the PSD's support (for the self-affine
//! surfaces of `[surface.generate]`, the lower cut-off `q_L`, not the
//! roll-off `q0`). The contact area is Persson's original `P(q)` (no
//! correction of the small-load area, which is known to come out about 20 %
//! below boundary-element results for self-affine surfaces).
//!
//! # Conventions
//!
//! * PSD: the project's isotropic radial PSD, `<h^2> = 2 pi Int q C(q) dq`,
//!   `<|grad h|^2> = 2 pi Int q^3 C(q) dq` ([`crate::surface::psd_2d`]).
//! * `E(w)` is the project's complex modulus ([`crate::material`]; `exp(+i w t)`,
//!   `E2 >= 0` for `w > 0`, `E(-w) = conj E(w)`), so any material the
//!   project accepts (SLS, creep spectrum, Prony series, fitted DMA data
//!   with its WLF shift) enters as its [`CreepSpectrum`].
//! * Sign: the wavevector `q` at angle `phi` to the sliding direction sees
//!   the frequency `q v cos(phi)` (physically `-q.v` in this project's
//!   convention, physics.md section 6; the sign does not matter below).
//!   Because `E(-w) = conj E(w)`, `cos(phi) Im E(q v cos phi)` equals
//!   `|cos phi| E2(q v |cos phi|) >= 0` for every `phi`: the two half-planes
//!   `cos phi > 0` and `cos phi < 0` contribute the same positive amount,
//!   so `mu >= 0` with no extra sign, whichever sign of the frequency is
//!   used. The angular integrals are computed over `[0, pi/2]` and
//!   multiplied by 4.
//!
//! # Quadrature (accuracy target 1e-6 relative)
//!
//! * Angle: the integrals `F(Q) = Int_0^2pi dphi cos(phi) Im E(Q cos phi)`
//!   and `K(Q) = Int_0^2pi dphi |E(Q cos phi)|^2` depend on `q` and `v`
//!   only through `Q = q v` ([`Persson::angular_integrals`]): geometric
//!   panels of ratio 2 towards `phi = pi/2` (where the frequency goes to 0
//!   and `E` has structure at every `1 / (Q tau_k)`) down to
//!   `Q tau_max phi <= 0.05`, [`PerssonParams::phi_nodes`] Gauss-Legendre
//!   nodes on each (a pole of `E` is at least a panel's length away in the
//!   complex plane: error about `5.8^(-2n)`).
//! * `F` and `K` are tabulated once per curve as functions of `ln Q` over
//!   the range the curve needs: piecewise Chebyshev interpolation,
//!   [`PerssonParams::table_points`] points on panels of width
//!   [`PerssonParams::table_width`] (`E` is analytic in `ln w` within
//!   `|Im ln w| < pi/2`, so 16 points on unit panels interpolate to about
//!   `1e-12`).
//! * Wavenumber: Gauss-Legendre in `ln q` on panels no wider than
//!   [`PerssonParams::q_panel_width`] that never straddle a row of the
//!   PSD table (where `C` has a kink); `G` at every node from the rule's
//!   running-integral matrix (no extra evaluations), so that `P(q)` is known
//!   at the nodes of the friction integral. Near `qL`, `G` grows from 0 and
//!   `P = erf(1/(2 sqrt G))` falls from 1 over a short range of `q` when the
//!   pressure is low: the first panel is graded geometrically towards `qL`
//!   (ratio [`PerssonParams::grading_ratio`]) until `G` on the last
//!   sub-panel is below [`PerssonParams::grading_floor`], where `P = 1` to
//!   `1e-12`.
//!
//! Measured accuracy (tests `persson_theory::quadrature_converges` and
//! `persson_theory::sls_narrow_band_matches_brute_force`): the default
//! parameters agree with a rule of about twice the resolution in every
//! direction to `8e-10` relative in `mu` and `1e-14` in `A/A0` (34-term
//! spectrum, 251 scales, speeds over 11 decades; SLS at 3 kPa and 30 Pa),
//! and with an independent brute-force 2-D trapezoidal quadrature to
//! `5e-9` (the brute force's own error).
//!
//! # Parts
//!
//! * [`Persson`]: material, PSD and pressure; [`Persson::curve`] over many
//!   speeds (parallel over speeds with rayon), [`Persson::point`] for one;
//! * [`psd`]: the three PSD sources as [`TabulatedPsd`] (continuum
//!   self-affine PSD of `[surface.generate]`, radial average of a height
//!   map, a `q, C` CSV).

mod angular;
pub mod psd;
mod quad;

use rayon::prelude::*;
use serde::Serialize;

use crate::material::{CreepSpectrum, Material};
use crate::surface::{SurfaceError, TabulatedPsd};

use quad::{ChebTable, GaussRule};

/// Errors of Persson's theory; each is one line and says what to fix.
#[derive(Debug, thiserror::Error)]
pub enum PerssonError {
    /// An input the theory cannot use.
    #[error("Persson's theory: {0}")]
    Invalid(String),
    /// The surface statistics could not be computed.
    #[error(transparent)]
    Surface(#[from] SurfaceError),
}

/// Quadrature controls (defaults reach about `1e-9` relative; see the
/// module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PerssonParams {
    /// Widest panel in `ln q` (default 0.5).
    pub q_panel_width: f64,
    /// Gauss-Legendre nodes per `q` panel (default 8).
    pub q_nodes: usize,
    /// Ratio of the geometric grading towards the lowest wavenumber
    /// (default 0.25).
    pub grading_ratio: f64,
    /// Grading stops where `G` on the last sub-panel is below this
    /// (default 0.01, where `1 - P < 2e-12`).
    pub grading_floor: f64,
    /// Gauss-Legendre nodes per angular panel (default 8).
    pub phi_nodes: usize,
    /// Width in `ln(q v)` of the panels of the angular table (default 1).
    pub table_width: f64,
    /// Chebyshev points per table panel (default 16).
    pub table_points: usize,
}

impl Default for PerssonParams {
    fn default() -> Self {
        Self {
            q_panel_width: 0.5,
            q_nodes: 8,
            grading_ratio: 0.25,
            grading_floor: 0.01,
            phi_nodes: 8,
            table_width: 1.0,
            table_points: 16,
        }
    }
}

impl PerssonParams {
    fn check(&self) -> Result<(), PerssonError> {
        let ok = self.q_panel_width > 0.0
            && self.q_panel_width.is_finite()
            && (1..=64).contains(&self.q_nodes)
            && self.grading_ratio > 0.0
            && self.grading_ratio < 1.0
            && self.grading_floor > 0.0
            && (1..=64).contains(&self.phi_nodes)
            && self.table_width > 0.0
            && self.table_width.is_finite()
            && (2..=64).contains(&self.table_points);
        if ok {
            Ok(())
        } else {
            Err(PerssonError::Invalid(format!(
                "quadrature parameters out of range: {self:?}"
            )))
        }
    }
}

/// The theory's result at one speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PerssonPoint {
    /// Sliding speed `v` \[m/s\].
    pub speed: f64,
    /// Friction coefficient `mu`.
    pub friction_coefficient: f64,
    /// Contact area fraction `A/A0 = P(q1)`.
    pub contact_area_fraction: f64,
    /// `G(q1)`, the normalised mean square stress at full magnification.
    pub g_q1: f64,
}

impl PerssonPoint {
    /// Whether `mu`, `A/A0` and `G(q1)` are all finite numbers.
    pub fn is_finite(&self) -> bool {
        self.friction_coefficient.is_finite()
            && self.contact_area_fraction.is_finite()
            && self.g_q1.is_finite()
    }
}

/// Persson's theory for one material, one PSD and one nominal pressure
/// (plan once, then evaluate at any speeds).
#[derive(Debug, Clone)]
pub struct Persson {
    spectrum: CreepSpectrum,
    /// `(1 - nu^2) sigma0` \[Pa\]: `E / sigma_star = E* / sigma0`.
    sigma_star: f64,
    nominal_pressure: f64,
    poisson: f64,
    psd: TabulatedPsd,
    params: PerssonParams,
    /// Panels `[a, b]` in `ln q`, ascending, none straddling a PSD row.
    panels: Vec<(f64, f64)>,
    q_rule: GaussRule,
    phi_rule: GaussRule,
}

impl Persson {
    /// Check and plan: `nominal_pressure` \[Pa\] finite and positive.
    pub fn new(
        material: &Material,
        psd: &TabulatedPsd,
        nominal_pressure: f64,
        params: PerssonParams,
    ) -> Result<Self, PerssonError> {
        params.check()?;
        if !(nominal_pressure.is_finite() && nominal_pressure > 0.0) {
            return Err(PerssonError::Invalid(format!(
                "the nominal pressure must be finite and positive, got {nominal_pressure} Pa"
            )));
        }
        let mut panels = Vec::new();
        for w in psd.q().windows(2) {
            let (a, b) = (w[0].ln(), w[1].ln());
            let n = ((b - a) / params.q_panel_width).ceil().max(1.0) as usize;
            for i in 0..n {
                let lo = if i == 0 {
                    a
                } else {
                    a + (b - a) * i as f64 / n as f64
                };
                let hi = if i + 1 == n {
                    b
                } else {
                    a + (b - a) * (i + 1) as f64 / n as f64
                };
                panels.push((lo, hi));
            }
        }
        Ok(Self {
            spectrum: material.spectrum.clone(),
            sigma_star: material.composite_factor() * nominal_pressure,
            nominal_pressure,
            poisson: material.poisson,
            psd: psd.clone(),
            params,
            panels,
            q_rule: GaussRule::new(params.q_nodes),
            phi_rule: GaussRule::new(params.phi_nodes),
        })
    }

    /// Nominal pressure `sigma0` \[Pa\].
    pub fn nominal_pressure(&self) -> f64 {
        self.nominal_pressure
    }

    /// Poisson ratio of the material.
    pub fn poisson(&self) -> f64 {
        self.poisson
    }

    /// The PSD the theory integrates.
    pub fn psd(&self) -> &TabulatedPsd {
        &self.psd
    }

    /// The quadrature controls.
    pub fn params(&self) -> PerssonParams {
        self.params
    }

    /// Lowest wavenumber of the integrals \[1/m\].
    pub fn q_min(&self) -> f64 {
        self.psd.q_min()
    }

    /// Highest wavenumber of the integrals (the full magnification) \[1/m\].
    pub fn q_max(&self) -> f64 {
        self.psd.q_max()
    }

    /// `[F(Q), K(Q)]` by direct angular quadrature (no table), with
    /// `F(Q) = Int_0^2pi dphi cos(phi) Im E(Q cos phi)` \[Pa\] and
    /// `K(Q) = Int_0^2pi dphi |E(Q cos phi)|^2` \[Pa^2\], `Q = q v` \[rad/s\].
    pub fn angular_integrals(&self, q_v: f64) -> [f64; 2] {
        angular::angular_integrals(&self.spectrum, q_v, &self.phi_rule)
    }

    /// The theory at one speed `v >= 0` \[m/s\].
    pub fn point(&self, speed: f64) -> Result<PerssonPoint, PerssonError> {
        Ok(self.curve(&[speed])?[0])
    }

    /// The theory at every speed of `speeds` (m/s, finite, `>= 0`, any
    /// order), in parallel over speeds. The angular integrals are tabulated
    /// once over the range of `q v` the speeds need.
    pub fn curve(&self, speeds: &[f64]) -> Result<Vec<PerssonPoint>, PerssonError> {
        if let Some(v) = speeds.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(PerssonError::Invalid(format!(
                "speeds must be finite and >= 0 m/s, got {v}"
            )));
        }
        let positive = speeds.iter().copied().filter(|v| *v > 0.0);
        let v_lo = positive.clone().fold(f64::INFINITY, f64::min);
        let v_hi = positive.fold(0.0, f64::max);
        let (qv_lo, qv_hi) = (self.q_min() * v_lo, self.q_max() * v_hi);
        if v_hi > 0.0 && !(qv_lo > 0.0 && qv_hi.is_finite()) {
            return Err(PerssonError::Invalid(format!(
                "the frequencies q v of the speeds {v_lo:e} to {v_hi:e} m/s over the PSD's wavenumbers {:e} to {:e} 1/m leave double precision (from {qv_lo:e} to {qv_hi:e} rad/s); give speeds nearer the material's loss peak",
                self.q_min(),
                self.q_max()
            )));
        }
        let table = (v_hi > 0.0).then(|| {
            let lo = qv_lo.ln();
            let hi = qv_hi.ln();
            // At least one panel around a single point.
            let (lo, hi) = if hi - lo < 1e-3 {
                (lo - 0.5, hi + 0.5)
            } else {
                (lo, hi)
            };
            ChebTable::new(
                lo,
                hi,
                self.params.table_width,
                self.params.table_points,
                |x| self.angular_integrals(x.exp()),
            )
        });
        let at_rest = self.angular_integrals(0.0);
        let kernel = |q_v: f64| -> [f64; 2] {
            match &table {
                Some(t) if q_v > 0.0 => t.eval(q_v.ln()),
                _ => at_rest,
            }
        };
        let points: Vec<PerssonPoint> = speeds
            .par_iter()
            .map(|&v| self.point_with(v, &kernel))
            .collect();
        match points.iter().find(|p| !p.is_finite()) {
            Some(p) => Err(self.beyond_f64(p)),
            None => Ok(points),
        }
    }

    /// The error of a point whose integrals left double precision: a
    /// nominal pressure so small (or a PSD so large) that `G(q1)`, of order
    /// `(E*/sigma0)^2` times the mean square slope, overflows.
    fn beyond_f64(&self, p: &PerssonPoint) -> PerssonError {
        PerssonError::Invalid(format!(
            "at sigma0 = {:.4e} Pa and v = {:.4e} m/s the integrals leave double precision (G(q1) = {:e}, mu = {:e}): E*/sigma0 reaches {:.3e} and the PSD's mean square slope is {:.3e}; check the units of the nominal pressure and of the PSD",
            self.nominal_pressure,
            p.speed,
            p.g_q1,
            p.friction_coefficient,
            self.spectrum.glassy_modulus / self.sigma_star,
            self.psd.moment(2),
        ))
    }

    /// One speed, with the angular integrals from `kernel(q v)`.
    fn point_with(&self, v: f64, kernel: &(impl Fn(f64) -> [f64; 2] + Sync)) -> PerssonPoint {
        let s2 = self.sigma_star * self.sigma_star;
        let n = self.q_rule.len();
        let (nodes, weights, running) = (
            &self.q_rule.nodes,
            &self.q_rule.weights,
            &self.q_rule.running,
        );
        // Grading of the first panel towards q_min (module docs).
        let q_min = self.q_min();
        let (a0, b0) = self.panels[0];
        let slope0 = q_min.powi(3) * self.psd.eval(q_min) * kernel(q_min * v)[1] / (8.0 * s2);
        let delta = b0.exp() - q_min;
        let mut graded = Vec::new();
        if slope0 * delta > self.params.grading_floor {
            let r = self.params.grading_ratio;
            let levels = ((slope0 * delta / self.params.grading_floor).ln() / (1.0 / r).ln())
                .ceil()
                .clamp(1.0, 200.0) as i32;
            let mut hi = b0;
            for k in 1..=levels {
                let lo = a0 + (delta * r.powi(k) / q_min).ln_1p();
                graded.push((lo, hi));
                hi = lo;
            }
            graded.push((a0, hi));
            graded.reverse();
        }
        let panels = graded.iter().chain(if graded.is_empty() {
            &self.panels[..]
        } else {
            &self.panels[1..]
        });
        let mut g_acc = 0.0;
        let mut mu = 0.0;
        let mut g = vec![0.0; n];
        let mut f = vec![0.0; n];
        for &(a, b) in panels {
            let half = 0.5 * (b - a);
            for j in 0..n {
                let q = (a + half * (nodes[j] + 1.0)).exp();
                let q4c = q.powi(4) * self.psd.eval(q);
                let [fq, kq] = kernel(q * v);
                g[j] = q4c * kq / (8.0 * s2);
                f[j] = q4c * fq / (2.0 * self.sigma_star);
            }
            let mut panel_mu = 0.0;
            for i in 0..n {
                let gi = g_acc
                    + half
                        * running[i * n..(i + 1) * n]
                            .iter()
                            .zip(&g)
                            .map(|(s, x)| s * x)
                            .sum::<f64>();
                panel_mu += weights[i] * f[i] * contact_probability(gi);
            }
            mu += half * panel_mu;
            g_acc += half * weights.iter().zip(&g).map(|(w, x)| w * x).sum::<f64>();
        }
        PerssonPoint {
            speed: v,
            friction_coefficient: mu,
            contact_area_fraction: contact_probability(g_acc),
            g_q1: g_acc,
        }
    }

    /// `exp(<ln q>)` weighted by the slope spectrum `q^3 C(q)`: the
    /// wavenumber that dominates the rms slope \[1/m\].
    pub fn slope_wavenumber(&self) -> f64 {
        let (mut num, mut den) = (0.0, 0.0);
        for &(a, b) in &self.panels {
            let half = 0.5 * (b - a);
            for (t, w) in self.q_rule.nodes.iter().zip(&self.q_rule.weights) {
                let s = a + half * (t + 1.0);
                let q = s.exp();
                let m = half * w * q.powi(4) * self.psd.eval(q);
                num += m * s;
                den += m;
            }
        }
        (num / den).exp()
    }

    /// Centre of the default speed range: the loss peak of `E2` divided by
    /// [`Self::slope_wavenumber`] \[m/s\]; `None` for an elastic material.
    pub fn peak_speed_estimate(&self) -> Option<f64> {
        loss_peak(&self.spectrum).map(|w| w / self.slope_wavenumber())
    }
}

/// `P = erf(1 / (2 sqrt G))`, 1 at `G = 0`.
fn contact_probability(g: f64) -> f64 {
    if g > 0.0 {
        libm::erf(0.5 / g.sqrt())
    } else {
        1.0
    }
}

/// Angular frequency \[rad/s\] of the maximum of the loss modulus `E2(w)`, or
/// `None` when `E2` vanishes (no creep terms): a scan at 20 points per decade
/// from `1e-3 / tau_max` to `1e3 / tau_min`, refined by golden sections in
/// `ln w`.
pub fn loss_peak(spectrum: &CreepSpectrum) -> Option<f64> {
    let times = spectrum.terms.iter().filter(|t| t.compliance > 0.0);
    let tau_max = times.clone().map(|t| t.time).fold(0.0, f64::max);
    let tau_min = times.map(|t| t.time).fold(f64::INFINITY, f64::min);
    if tau_max <= 0.0 {
        return None;
    }
    let (lo, hi) = ((1e-3 / tau_max).ln(), (1e3 / tau_min).ln());
    let steps = ((hi - lo) / (std::f64::consts::LN_10 / 20.0)).ceil() as usize;
    let e2 = |x: f64| spectrum.modulus(x.exp()).im;
    let at = |i: usize| lo + (hi - lo) * i as f64 / steps as f64;
    let best = (0..=steps)
        .max_by(|&i, &j| e2(at(i)).total_cmp(&e2(at(j))))
        .unwrap_or(0);
    let (mut a, mut b) = (at(best.saturating_sub(1)), at((best + 1).min(steps)));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..100 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if e2(c) >= e2(d) {
            b = d;
        } else {
            a = c;
        }
    }
    Some((0.5 * (a + b)).exp())
}

/// `count` speeds evenly spaced in `ln v` from `from` to `to` inclusive.
pub fn log_speeds(from: f64, to: f64, count: usize) -> Vec<f64> {
    crate::material::eval::log_space(from, to, count)
}
