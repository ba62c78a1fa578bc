//! Relaxation (generalized Maxwell, Prony) form and the exact conversions
//! between it and the creep (retardation) spectrum of Eq. 2
//! (physics.md section 2, route (b)).
//!
//! With the Laplace variable `s` (`s = i w` for the `exp(+i w t)` convention),
//!
//! * relaxation form: `E(s) = E0 + sum_j E_j s theta_j / (1 + s theta_j)`,
//!   poles at `s = -1/theta_j`, `E_inf = E0 + sum_j E_j`;
//! * creep form: `J(s) = 1/E_inf + sum_k C_k / (1 + s tau_k)`,
//!   poles at `s = -1/tau_k`, `1/E0 = 1/E_inf + sum_k C_k`;
//!
//! and `E(s) J(s) = 1`. The retardation times are therefore the zeros of
//! `E(s)` and the relaxation times the zeros of `J(s)`, all on the negative real
//! axis. Writing `s = -1/u` (`u` a time), both functions become sums of simple
//! poles in `u` that are monotonic between consecutive poles, so each zero is
//! bracketed by two poles (interlacing) and found by bisection to the last
//! bit. The coefficients follow from the residues:
//! `C_k = 1 / (tau_k f'(tau_k))` with `f(u) = E(-1/u)`, and
//! `E_j = 1 / (theta_j |g'(theta_j)|)` with `g(u) = J(-1/u)`.

use num_complex::Complex64;

use super::{CreepSpectrum, CreepTerm, MaterialError};

/// One Maxwell arm `E_j` with relaxation time `theta_j`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PronyTerm {
    /// Arm modulus `E_j` \[Pa\], non-negative.
    pub modulus: f64,
    /// Relaxation time `theta_j` \[s\], positive.
    pub time: f64,
}

/// Generalized Maxwell solid
/// `E(w) = E0 + sum_j E_j i w theta_j / (1 + i w theta_j)` (physics.md section 2).
#[derive(Debug, Clone, PartialEq)]
pub struct PronySeries {
    /// Relaxed (zero-frequency) modulus `E0` \[Pa\].
    pub relaxed_modulus: f64,
    pub terms: Vec<PronyTerm>,
}

/// Terms whose weight is below this fraction of the reference modulus
/// (compliance) are dropped before a conversion: their effect on `E(w)` is
/// below that relative size, and a zero that close to a pole cannot be
/// separated from it in double precision.
const NEGLIGIBLE: f64 = 1e-14;

impl PronySeries {
    /// Validate and build: `E0 > 0`, every `E_j >= 0` and `theta_j > 0`, all finite.
    pub fn new(relaxed_modulus: f64, terms: Vec<PronyTerm>) -> Result<Self, MaterialError> {
        if !(relaxed_modulus.is_finite() && relaxed_modulus > 0.0) {
            return Err(MaterialError::Invalid(format!(
                "relaxed_modulus = {relaxed_modulus} Pa must be positive and finite"
            )));
        }
        for (j, t) in terms.iter().enumerate() {
            if !(t.modulus.is_finite() && t.modulus >= 0.0) {
                return Err(MaterialError::Invalid(format!(
                    "prony term {j}: modulus E = {} Pa must be >= 0 and finite",
                    t.modulus
                )));
            }
            if !(t.time.is_finite() && t.time > 0.0) {
                return Err(MaterialError::Invalid(format!(
                    "prony term {j}: time theta = {} s must be positive and finite",
                    t.time
                )));
            }
        }
        Ok(Self {
            relaxed_modulus,
            terms,
        })
    }

    /// Glassy modulus `E_inf = E0 + sum_j E_j` \[Pa\].
    pub fn glassy_modulus(&self) -> f64 {
        self.relaxed_modulus + self.terms.iter().map(|t| t.modulus).sum::<f64>()
    }

    /// Complex modulus `E(w) = E1 + i E2`.
    pub fn modulus(&self, omega: f64) -> Complex64 {
        let mut e = Complex64::new(self.relaxed_modulus, 0.0);
        for t in &self.terms {
            let wt = omega * t.time;
            if wt.abs() > super::spectrum::SQUARE_SAFE {
                let (_, loss, stored) = super::spectrum::far_debye(wt);
                e += Complex64::new(t.modulus * stored, t.modulus * loss);
                continue;
            }
            let d = 1.0 + wt * wt;
            e += Complex64::new(t.modulus * wt * wt / d, t.modulus * wt / d);
        }
        e
    }

    /// Relaxation function `E(t) = E0 + sum_j E_j exp(-t/theta_j)` for `t >= 0`.
    pub fn relaxation_function(&self, t: f64) -> f64 {
        self.relaxed_modulus
            + self
                .terms
                .iter()
                .map(|k| k.modulus * (-t / k.time).exp())
                .sum::<f64>()
    }

    /// The equivalent creep spectrum (Eq. 2): retardation times are the zeros
    /// of `E(s)` on the negative real axis, one between each pair of
    /// consecutive relaxation poles and one above the longest relaxation time;
    /// `C_k` are the residues of `1/E(s)` there (physics.md section 2, route (b)).
    pub fn to_creep(&self) -> Result<CreepSpectrum, MaterialError> {
        let e0 = self.relaxed_modulus;
        let poles = merged_sorted(&self.terms_as_pairs(), NEGLIGIBLE * e0);
        // f(u) = E(-1/u) = E0 - sum_j E_j theta_j / (u - theta_j); increasing
        // on each interval between poles.
        let f = |u: f64| e0 - poles.iter().map(|&(a, th)| a * th / (u - th)).sum::<f64>();
        let df = |u: f64| {
            poles
                .iter()
                .map(|&(a, th)| {
                    let d = u - th;
                    a * th / (d * d)
                })
                .sum::<f64>()
        };
        let n = poles.len();
        let mut terms = Vec::with_capacity(n);
        for k in 0..n {
            let lo = poles[k].1;
            let hi = if k + 1 < n {
                poles[k + 1].1
            } else {
                // f(u) >= E0 - sum_j E_j theta_j / (u - theta_n) >= 0 here.
                let s: f64 = poles.iter().map(|&(a, th)| a * th).sum();
                lo + 2.0 * s / e0
            };
            let tau = bisect_between_poles(&f, lo, hi, true, k + 1 < n)?;
            let c = 1.0 / (tau * df(tau));
            terms.push(CreepTerm {
                compliance: c,
                time: tau,
            });
        }
        CreepSpectrum::new(self.glassy_modulus(), terms)
    }

    fn terms_as_pairs(&self) -> Vec<(f64, f64)> {
        self.terms.iter().map(|t| (t.modulus, t.time)).collect()
    }
}

impl CreepSpectrum {
    /// The equivalent generalized Maxwell (Prony) series: relaxation times are
    /// the zeros of `J(s)` on the negative real axis, one below the shortest
    /// retardation time and one between each pair of consecutive retardation
    /// poles; `E_j` are the residues of `1/J(s)` (physics.md section 2).
    pub fn to_prony(&self) -> Result<PronySeries, MaterialError> {
        let jg = self.glassy_compliance();
        let j0 = self.relaxed_compliance();
        let pairs: Vec<(f64, f64)> = self.terms.iter().map(|t| (t.compliance, t.time)).collect();
        let poles = merged_sorted(&pairs, NEGLIGIBLE * jg);
        // g(u) = J(-1/u) = 1/E0 + sum_k C_k tau_k / (u - tau_k); decreasing on
        // each interval between poles, g(0) = 1/E_inf > 0.
        let g = |u: f64| j0 + poles.iter().map(|&(c, t)| c * t / (u - t)).sum::<f64>();
        let dg = |u: f64| {
            poles
                .iter()
                .map(|&(c, t)| {
                    let d = u - t;
                    c * t / (d * d)
                })
                .sum::<f64>()
        };
        let n = poles.len();
        let sum_c: f64 = poles.iter().map(|p| p.0).sum();
        let mut terms = Vec::with_capacity(n);
        for k in 0..n {
            let hi = poles[k].1;
            let lo = if k == 0 {
                // For u < tau_1: g(u) >= 1/E_inf - u sum C / (tau_1 - u) > 0
                // when u < tau_1 / (1 + E_inf sum C); halve it for margin.
                0.5 * hi / (1.0 + sum_c / jg)
            } else {
                poles[k - 1].1
            };
            // -g is increasing: bisect that.
            let theta = bisect_between_poles(&|u| -g(u), lo, hi, k > 0, true)?;
            let e = 1.0 / (theta * dg(theta));
            terms.push(PronyTerm {
                modulus: e,
                time: theta,
            });
        }
        PronySeries::new(1.0 / j0, terms)
    }
}

/// Sort `(weight, time)` pairs by time, drop weights `<= floor`, and merge
/// equal times (their poles coincide) by adding their weights.
fn merged_sorted(pairs: &[(f64, f64)], floor: f64) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = pairs.iter().copied().filter(|p| p.0 > floor).collect();
    v.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(v.len());
    for p in v {
        match out.last_mut() {
            Some(last) if last.1 == p.1 => last.0 += p.0,
            _ => out.push(p),
        }
    }
    out
}

/// Zero of an increasing function `h` on `(lo, hi)`. When `lo_is_pole`, `h`
/// tends to `-inf` at `lo`; otherwise `h(lo) < 0` must hold. Likewise
/// `hi_is_pole` (`h -> +inf`) or `h(hi) > 0`. Bisects in log space first (the
/// times span many decades), then to adjacent floating-point numbers, and
/// returns the end of the final bracket with the smaller `|h|`.
fn bisect_between_poles(
    h: &dyn Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    lo_is_pole: bool,
    hi_is_pole: bool,
) -> Result<f64, MaterialError> {
    let fail =
        || MaterialError::Conversion(format!("no separable zero between {lo:e} s and {hi:e} s"));
    let (mut a, mut b) = (lo, hi);
    let mut ha = if lo_is_pole { None } else { Some(h(lo)) };
    let mut hb = if hi_is_pole { None } else { Some(h(hi)) };
    if ha.is_some_and(|v| v.is_nan() || v >= 0.0) || hb.is_some_and(|v| v.is_nan() || v <= 0.0) {
        return Err(fail());
    }
    loop {
        let m = if b / a > 1.01 {
            (a * b).sqrt()
        } else {
            a + 0.5 * (b - a)
        };
        if !(m > a && m < b) {
            break;
        }
        let v = h(m);
        if v.is_nan() {
            return Err(fail());
        }
        if v < 0.0 {
            (a, ha) = (m, Some(v));
        } else if v > 0.0 {
            (b, hb) = (m, Some(v));
        } else {
            return Ok(m);
        }
    }
    match (ha, hb) {
        (Some(x), Some(y)) => Ok(if x.abs() <= y.abs() { a } else { b }),
        (Some(_), None) => Ok(a),
        (None, Some(_)) => Ok(b),
        (None, None) => Err(fail()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sls_relaxation_time_is_creep_time_times_e0_over_einf() {
        let s = CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap();
        let p = s.to_prony().unwrap();
        assert_eq!(p.terms.len(), 1);
        // Single-term conversion is a closed-form root: round-off only.
        assert!((p.terms[0].time - 0.01 / 3.0).abs() < 1e-15);
        assert!((p.glassy_modulus() - 1e7).abs() < 1e-6);
        let back = p.to_creep().unwrap();
        assert!((back.terms[0].time - 0.01).abs() < 1e-15);
        assert!((back.terms[0].compliance - 2e-7).abs() < 1e-20);
    }
}
