//! The discrete creep (retardation) spectrum of Eq. 2.

use num_complex::Complex64;

use super::MaterialError;

/// One term `C_k exp(-t / tau_k)` of the creep function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepTerm {
    /// Creep compliance `C_k` [1/Pa], positive.
    pub compliance: f64,
    /// Creep (retardation) time `tau_k` \[s\], positive.
    pub time: f64,
}

/// `J(t) = 1/E0 - sum_k C_k exp(-t/tau_k)`, `J(0+) = 1/E_inf` (Eq. 2).
#[derive(Debug, Clone, PartialEq)]
pub struct CreepSpectrum {
    /// Glassy (instantaneous, high-frequency) modulus `E_inf` \[Pa\].
    pub glassy_modulus: f64,
    pub terms: Vec<CreepTerm>,
}

impl CreepSpectrum {
    /// Validate and build: `E_inf > 0`, every `C_k >= 0` and `tau_k > 0`, all finite.
    pub fn new(glassy_modulus: f64, terms: Vec<CreepTerm>) -> Result<Self, MaterialError> {
        if !(glassy_modulus.is_finite() && glassy_modulus > 0.0) {
            return Err(MaterialError::Invalid(format!(
                "glassy_modulus = {glassy_modulus} Pa must be positive and finite"
            )));
        }
        for (k, t) in terms.iter().enumerate() {
            if !(t.compliance.is_finite() && t.compliance >= 0.0) {
                return Err(MaterialError::Invalid(format!(
                    "creep term {k}: compliance C = {} 1/Pa must be >= 0 and finite",
                    t.compliance
                )));
            }
            if !(t.time.is_finite() && t.time > 0.0) {
                return Err(MaterialError::Invalid(format!(
                    "creep term {k}: time tau = {} s must be positive and finite",
                    t.time
                )));
            }
        }
        Ok(Self {
            glassy_modulus,
            terms,
        })
    }

    /// Standard linear solid from `E0`, `E_inf` and its creep (retardation)
    /// time: a single term with `C = 1/E0 - 1/E_inf`.
    pub fn standard_linear_solid(
        relaxed_modulus: f64,
        glassy_modulus: f64,
        creep_time: f64,
    ) -> Result<Self, MaterialError> {
        if !(relaxed_modulus.is_finite() && relaxed_modulus > 0.0) {
            return Err(MaterialError::Invalid(format!(
                "relaxed_modulus = {relaxed_modulus} Pa must be positive and finite"
            )));
        }
        if glassy_modulus.is_nan() || glassy_modulus < relaxed_modulus {
            return Err(MaterialError::Invalid(format!(
                "glassy_modulus = {glassy_modulus} Pa must be >= relaxed_modulus = {relaxed_modulus} Pa"
            )));
        }
        Self::new(
            glassy_modulus,
            vec![CreepTerm {
                compliance: 1.0 / relaxed_modulus - 1.0 / glassy_modulus,
                time: creep_time,
            }],
        )
    }

    /// Glassy compliance `1/E_inf` [1/Pa].
    pub fn glassy_compliance(&self) -> f64 {
        1.0 / self.glassy_modulus
    }

    /// Relaxed compliance `1/E0 = 1/E_inf + sum C_k` [1/Pa].
    pub fn relaxed_compliance(&self) -> f64 {
        self.glassy_compliance() + self.terms.iter().map(|t| t.compliance).sum::<f64>()
    }

    /// Relaxed (zero-frequency) modulus `E0` \[Pa\].
    pub fn relaxed_modulus(&self) -> f64 {
        1.0 / self.relaxed_compliance()
    }

    /// Creep function `J(t)` for `t >= 0` (Eq. 2).
    pub fn creep_function(&self, t: f64) -> f64 {
        self.relaxed_compliance()
            - self
                .terms
                .iter()
                .map(|k| k.compliance * (-t / k.time).exp())
                .sum::<f64>()
    }

    /// Complex compliance `J*(w) = 1/E_inf + sum_k C_k / (1 + i w tau_k)`;
    /// a term whose `(w tau_k)^2` would overflow is taken as `C_k (y^2, -y)
    /// / (1 + y^2)`, `y = 1 / (w tau_k)` (`far_debye`).
    pub fn compliance(&self, omega: f64) -> Complex64 {
        let mut j = Complex64::new(self.glassy_compliance(), 0.0);
        for k in &self.terms {
            let wt = omega * k.time;
            if wt.abs() > SQUARE_SAFE {
                let (re, im, _) = far_debye(wt);
                j += Complex64::new(k.compliance * re, -k.compliance * im);
                continue;
            }
            let d = 1.0 + wt * wt;
            j += Complex64::new(k.compliance / d, -k.compliance * wt / d);
        }
        j
    }

    /// Complex modulus `E(w) = 1/J*(w) = E1 + i E2`.
    pub fn modulus(&self, omega: f64) -> Complex64 {
        1.0 / self.compliance(omega)
    }
}

/// Beyond this `|x|`, `x^2` is within a few decades of f64's largest value.
pub(crate) const SQUARE_SAFE: f64 = 1e150;

/// `(1, x, x^2) / (1 + x^2)`, the parts of a Debye term with `x = w tau`
/// (`1 / (1 - i x)` is the first two), for `|x| >` [`SQUARE_SAFE`], where
/// `x^2` would overflow (a creep time of 1e300 s met at 1e100 rad/s gave
/// NaN): as `(y^2, y, 1) / (1 + y^2)`, `y = 1 / x`.
pub(crate) fn far_debye(x: f64) -> (f64, f64, f64) {
    let y = 1.0 / x;
    let d = 1.0 + y * y;
    (y * y / d, y / d, 1.0 / d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Creep times and frequencies whose product squared leaves f64: the
    /// glassy limit, not NaN.
    #[test]
    fn long_creep_times_meet_high_frequencies_without_overflow() {
        let s = CreepSpectrum::new(
            1e7,
            vec![
                CreepTerm {
                    compliance: 1e-7,
                    time: 1e-2,
                },
                CreepTerm {
                    compliance: 1e-7,
                    time: 1e300,
                },
            ],
        )
        .unwrap();
        for w in [1e100, 1e160, 1e200] {
            let e = s.modulus(w);
            assert!(
                (e.re / 1e7 - 1.0).abs() < 1e-12 && e.im >= 0.0 && e.im < 1e-3,
                "{w}: {e}"
            );
        }
        let (re, im, glassy) = far_debye(-1e200);
        assert!(re < 1e-300 && (im + 1e-200).abs() < 1e-215 && glassy == 1.0);
    }

    #[test]
    fn sls_limits_and_loss_sign() {
        let s = CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap();
        assert!((s.relaxed_modulus() - 1e7 / 3.0).abs() < 1e-6);
        assert!((s.modulus(0.0).re - 1e7 / 3.0).abs() < 1e-6);
        assert!((s.modulus(1e12).re - 1e7).abs() / 1e7 < 1e-9);
        let e = s.modulus(100.0);
        assert!(e.im > 0.0, "E2 must be positive for w > 0");
        assert!((s.modulus(-100.0) - e.conj()).norm() < 1e-9 * e.norm());
        assert!((s.creep_function(0.0) - 1e-7).abs() < 1e-20);
    }

    #[test]
    fn rejects_bad_values() {
        assert!(CreepSpectrum::standard_linear_solid(-1.0, 1e7, 0.01).is_err());
        assert!(CreepSpectrum::standard_linear_solid(2e7, 1e7, 0.01).is_err());
        assert!(CreepSpectrum::new(f64::NAN, vec![]).is_err());
    }
}
