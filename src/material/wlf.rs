//! The WLF time-temperature shift (physics.md sections 2 and 12): its
//! constants, validity range and shift factors.

use super::MaterialError;

/// The largest `|log10 a_T|` accepted: 50 decades (physics.md section 12).
///
/// WLF describes a rubber above its glass transition, where `log10 a_T`
/// relative to any reference in that range spans some 20 decades at most
/// (the universal constants give 17.44 from `T_g` to infinite
/// temperature), and measured master curves cover fewer; 50 leaves that
/// range whole for any constants. Nearer the pole `T = T_ref - C2` the form
/// diverges (`a_T` overflows f64 within 0.02 K of it for the universal
/// constants), which no rubber does. Numerically, the shifted creep times
/// `a_T tau_k`, speeds `a_T v` and `xi = v a_T tau / L` stay within 50
/// decades of the unshifted ones, leaving over 250 decades of f64's normal
/// range (1e-308 to 1e308) for the products the kernel and Persson's
/// theory form with wavenumbers; the shifted quantities are checked as
/// well ([`crate::material::Material::at_temperature`]), for inputs that
/// are themselves extreme.
pub const LOG10_SHIFT_MAX: f64 = 50.0;

/// WLF time-temperature shift
/// `log10 a_T = -C1 (T - T_ref) / (C2 + T - T_ref)`, with
/// `E(w, T) = E(w a_T, T_ref)` (physics.md sections 2 and 12). Temperatures
/// in C (only differences enter).
///
/// Validity range: `a_T` is computed in log space and only where
/// `|log10 a_T| <= LOG10_SHIFT_MAX`, which (with `|C1| <= LOG10_SHIFT_MAX`)
/// is the half-line `T >= T_ref - C2 L / (|C1| + L)`, `L` =
/// [`LOG10_SHIFT_MAX`]: strictly above the pole `T_ref - C2` by
/// `C2 |C1| / (|C1| + L)` (physics.md section 12: "`T - T_ref > -C2` at
/// the very least"). Every shift factor of the library comes from
/// [`Wlf::log10_shift`], through [`Wlf::shift_ratio`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wlf {
    /// `C1` (dimensionless).
    pub c1: f64,
    /// `C2` \[K\].
    pub c2: f64,
    /// Reference temperature `T_ref` \[C\].
    pub reference_temperature: f64,
    /// The lowest and highest temperature \[C\] of the DMA data the
    /// constants shifted onto one master curve, when recorded
    /// (`material fit --wlf` on data at several temperatures, or
    /// `[material] wlf_range`): beyond them the shift is an extrapolation
    /// of the form, however well it fits inside ([`Wlf::extrapolation`]).
    pub data_range: Option<[f64; 2]>,
}

impl Wlf {
    /// Check the constants: all finite, `C2 > 0` and
    /// `|C1| <= LOG10_SHIFT_MAX` (`log10 a_T` tends to `-C1` at high
    /// temperature, so a larger `C1` makes `a_T` leave the representable
    /// range above some temperature, `C1 = 1e300` at any `T != T_ref`).
    pub fn new(c1: f64, c2: f64, reference_temperature: f64) -> Result<Self, MaterialError> {
        if !(c1.is_finite() && c2.is_finite() && c2 > 0.0 && reference_temperature.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "WLF constants C1 = {c1}, C2 = {c2} K, T_ref = {reference_temperature} C must be finite with C2 > 0"
            )));
        }
        if c1.abs() > LOG10_SHIFT_MAX {
            return Err(MaterialError::Invalid(format!(
                "WLF constant C1 = {c1:e} must satisfy |C1| <= {LOG10_SHIFT_MAX}: log10 a_T tends to -C1 at high temperature and is bounded by {LOG10_SHIFT_MAX} decades (rubbers' C1 are 5 to 40)"
            )));
        }
        Ok(Self {
            c1,
            c2,
            reference_temperature,
            data_range: None,
        })
    }

    /// The same constants with the temperatures of the data they were
    /// fitted to, `[lowest, highest]` \[C\]: both finite, in order, and
    /// inside the validity range ([`Wlf::log10_shift`]).
    pub fn with_data_range(mut self, range: [f64; 2]) -> Result<Self, MaterialError> {
        let [lo, hi] = range;
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(MaterialError::Invalid(format!(
                "WLF data range [{lo}, {hi}] C must be two finite temperatures, the lowest first"
            )));
        }
        for t in range {
            self.log10_shift(t)
                .map_err(|e| MaterialError::Invalid(format!("WLF data range: {e}")))?;
        }
        self.data_range = Some(range);
        Ok(self)
    }

    /// Where temperature `t` \[C\] lies beyond the recorded data range
    /// ([`Wlf::data_range`]), a phrase saying by how much and that the
    /// shift there is extrapolated; `None` inside it or without a record.
    pub fn extrapolation(&self, t: f64) -> Option<String> {
        let [lo, hi] = self.data_range?;
        let (side, by) = if t > hi {
            ("above", t - hi)
        } else if t < lo {
            ("below", lo - t)
        } else {
            return None;
        };
        Some(format!(
            "{t:.4} C lies {by:.3} K {side} the DMA data ({lo} to {hi} C) that the WLF constants were fitted to, so its shift factor a_T, and with it every modulus, is extrapolated"
        ))
    }

    /// The lowest temperature of the validity range \[C\]:
    /// `T_ref - C2 L / (|C1| + L)`, where `|log10 a_T|` reaches
    /// `L = LOG10_SHIFT_MAX` (for `C1 = 0`, the pole `T_ref - C2` itself,
    /// excluded).
    pub fn lowest_temperature(&self) -> f64 {
        let l = LOG10_SHIFT_MAX;
        self.reference_temperature - self.c2 * l / (self.c1.abs() + l)
    }

    /// [`Wlf::lowest_temperature`] rounded up to 0.01 C, as messages quote
    /// it: the value quoted is itself accepted.
    pub fn lowest_temperature_quoted(&self) -> f64 {
        let lowest = self.lowest_temperature();
        let cents = (lowest * 100.0).ceil();
        if cents / 100.0 < lowest {
            (cents + 1.0) / 100.0
        } else {
            cents / 100.0
        }
    }

    /// `log10 a_T` at temperature `t` \[C\], the one evaluation of the WLF
    /// form. A temperature outside the validity range (below
    /// [`Wlf::lowest_temperature`], at or below the pole `T_ref - C2`, or
    /// not finite) is a one-line error naming it and the bound.
    pub fn log10_shift(&self, t: f64) -> Result<f64, MaterialError> {
        let dt = t - self.reference_temperature;
        let den = self.c2 + dt;
        let lowest = self.lowest_temperature();
        if !(t.is_finite() && den > 0.0 && t >= lowest) {
            let quoted = self.lowest_temperature_quoted();
            let pole = self.reference_temperature - self.c2;
            return Err(MaterialError::Invalid(format!(
                "temperature {t} C is outside the WLF range of C1 = {}, C2 = {} K, T_ref = {} C: give T >= {quoted} C, where |log10 a_T| reaches {LOG10_SHIFT_MAX} (T_ref - C2 = {pole} C is the pole of the WLF form; physics.md section 12)",
                self.c1, self.c2, self.reference_temperature
            )));
        }
        Ok(-self.c1 * dt / den)
    }

    /// `a_T(to) / a_T(from)`, from the logarithms: the ratio of two
    /// factors in the validity range lies within `1e±2 LOG10_SHIFT_MAX`.
    pub fn shift_ratio(&self, from: f64, to: f64) -> Result<f64, MaterialError> {
        Ok(10f64.powf(self.log10_shift(to)? - self.log10_shift(from)?))
    }

    /// The same shift referred to temperature `t` \[C\] (in the validity
    /// range): `C2' = C2 + t - T_ref`, `C1' = C1 C2 / C2'`, `T_ref' = t`,
    /// whose factors are `a_T(T) / a_T(t)` exactly
    /// (`-C1 (T - T_ref) / (C2 + T - T_ref) + C1 (t - T_ref) / (C2 + t -
    /// T_ref) = -C1' (T - t) / (C2' + T - t)`), so the pole stays where it
    /// was; the data range is kept. A spectrum that describes `t`, with
    /// these constants, describes every temperature as the original
    /// constants do.
    pub fn referenced_to(&self, t: f64) -> Result<Self, MaterialError> {
        self.log10_shift(t)?;
        let c2 = self.c2 + (t - self.reference_temperature);
        let mut shifted = Self::new(self.c1 * self.c2 / c2, c2, t)?;
        shifted.data_range = self.data_range;
        Ok(shifted)
    }

    /// Shift factor `a_T` at temperature `t` \[C\] (relative to `T_ref`).
    pub fn shift_factor(&self, t: f64) -> Result<f64, MaterialError> {
        self.shift_ratio(self.reference_temperature, t)
    }

    /// The frequency at temperature `to` with the same response as `omega` at
    /// temperature `from`: `omega a_T(from) / a_T(to)`.
    pub fn shift_frequency(&self, omega: f64, from: f64, to: f64) -> Result<f64, MaterialError> {
        Ok(omega * self.shift_ratio(to, from)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wlf_is_zero_at_reference_and_composes() {
        let w = Wlf::new(8.86, 101.6, 17.0).unwrap();
        assert_eq!(w.log10_shift(17.0).unwrap(), 0.0);
        assert!(w.log10_shift(0.0).unwrap() > 0.0, "colder is slower");
        assert!(w.log10_shift(17.0 - 101.6).is_err());
    }

    /// Referred to another temperature, the constants give the same
    /// ratio between any two temperatures (to rounding) and 1 at their new
    /// reference.
    #[test]
    fn referenced_constants_shift_alike() {
        let w = Wlf::new(8.86, 101.6, 17.0)
            .unwrap()
            .with_data_range([0.0, 40.0])
            .unwrap();
        for t in [30.0, -20.0, 17.0] {
            let r = w.referenced_to(t).unwrap();
            assert_eq!(r.reference_temperature, t);
            assert_eq!(r.data_range, Some([0.0, 40.0]));
            assert_eq!(r.shift_factor(t).unwrap(), 1.0);
            assert!((r.reference_temperature - r.c2 - (17.0 - 101.6)).abs() < 1e-12);
            for (a, b) in [(-10.0, 60.0), (30.0, 5.0), (17.0, 100.0)] {
                let (x, y) = (w.shift_ratio(a, b).unwrap(), r.shift_ratio(a, b).unwrap());
                assert!(
                    (x / y - 1.0).abs() < 1e-13,
                    "{t}: {a} -> {b}: {x} against {y}"
                );
            }
        }
        assert!(w.referenced_to(17.0 - 101.6).is_err());
    }

    /// The validity range `|log10 a_T| <= 50`: its lowest temperature has
    /// `log10 a_T = 50` (to rounding), the quoted bound is accepted and
    /// the ratio of any two factors in it is finite and nonzero.
    #[test]
    fn wlf_validity_range() {
        let w = Wlf::new(8.86, 101.6, 17.0).unwrap();
        let lowest = w.lowest_temperature();
        assert!((lowest - (17.0 - 101.6 * 50.0 / 58.86)).abs() < 1e-12);
        assert!((w.log10_shift(lowest).unwrap() - LOG10_SHIFT_MAX).abs() < 1e-12);
        assert_eq!(w.lowest_temperature_quoted(), -69.3);
        assert!(w.log10_shift(-69.3).is_ok());
        assert!(w.log10_shift(lowest - 1e-9).is_err());
        let r = w.shift_ratio(1e300, lowest).unwrap();
        assert!(r.is_finite() && r > 0.0, "{r}");
        // C1 = 0: no shift, but the pole stays excluded.
        let flat = Wlf::new(0.0, 101.6, 17.0).unwrap();
        assert_eq!(flat.shift_factor(-84.5).unwrap(), 1.0);
        assert!(flat.log10_shift(-84.6).is_err());
        // Negative C1 (hotter is slower, unphysical but representable):
        // the same bound from below.
        let neg = Wlf::new(-8.86, 101.6, 17.0).unwrap();
        assert!((neg.log10_shift(lowest).unwrap() + LOG10_SHIFT_MAX).abs() < 1e-12);
        assert!(neg.log10_shift(-70.0).is_err());
        // |C1| above the bound: a_T would leave the range at high temperature.
        assert!(Wlf::new(50.0, 101.6, 17.0).is_ok());
        for c1 in [50.5, -51.0, 1e300] {
            let e = Wlf::new(c1, 101.6, 17.0).unwrap_err().to_string();
            assert!(e.contains("C1") && e.contains("50"), "{e}");
        }
    }
}
