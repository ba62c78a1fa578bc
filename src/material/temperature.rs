//! Time-temperature superposition of an isothermal solve (physics.md
//! sections 2 and 12): with the WLF shift factor
//! `log10 a_T = -C1 (T - T_ref) / (C2 + T - T_ref)` every creep time scales
//! as `tau_k(T) = a_T tau_k(T_ref)`, so `E(w, T) = E(a_T w, T_ref)`. The
//! material is shifted once, where a problem is built, so every consumer
//! of its spectrum (the kernel of both formulations, the GPU coefficient
//! tables, Persson's theory) sees the same rubber. No vertical shift `b_T`:
//! with it the exact collapse `mu(v, T) = mu(a_T v, T_ref)` would not hold.

use super::{Material, MaterialError, Wlf};

/// Decades beyond the data's frequencies that a sliding may excite before
/// [`Material::extrapolated_frequencies_warnings`] warns: a fitted
/// spectrum's plateaus carry about a decade past its data.
pub(crate) const FREQUENCY_MARGIN_DECADES: f64 = 1.0;

/// The temperature a material describes and its WLF shift, as reported in
/// `summary.json`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TemperatureShift {
    /// Temperature \[C\].
    pub temperature: f64,
    /// WLF reference temperature `T_ref` \[C\].
    pub reference_temperature: f64,
    /// `a_T` relative to `T_ref`: `mu(v, T) = mu(a_T v, T_ref)`.
    pub shift_factor: f64,
}

impl Material {
    /// The same material with WLF constants: its spectrum is taken to
    /// describe `temperature` \[C\], or `T_ref` when `None`. A temperature
    /// outside the validity range of the constants ([`Wlf::log10_shift`])
    /// is refused.
    pub fn with_wlf(mut self, wlf: Wlf, temperature: Option<f64>) -> Result<Self, MaterialError> {
        let t = temperature.unwrap_or(wlf.reference_temperature);
        wlf.log10_shift(t)
            .map_err(|e| MaterialError::Invalid(format!("the spectrum's own temperature: {e}")))?;
        self.wlf = Some(wlf);
        self.temperature = Some(t);
        Ok(self)
    }

    /// The temperature this material describes and its shift factor, when
    /// it has WLF constants (its temperature is in their validity range:
    /// [`Material::with_wlf`] and [`Material::at_temperature`] see to it).
    pub fn temperature_shift(&self) -> Option<TemperatureShift> {
        let wlf = self.wlf?;
        let t = self.temperature?;
        Some(TemperatureShift {
            temperature: t,
            reference_temperature: wlf.reference_temperature,
            shift_factor: wlf.shift_factor(t).ok()?,
        })
    }

    /// The material at `temperature` \[C\]: every creep time multiplied by
    /// `a_T(T) / a_T(T0)`, `T0` the temperature its spectrum describes
    /// (usually `T_ref`, where the factor is `a_T(T)` itself), computed from
    /// `log10 a_T` ([`Wlf::shift_ratio`]). Moduli are unchanged (no `b_T`).
    /// A material without WLF constants, a temperature outside the validity
    /// range of the constants (`|log10 a_T| <= 50`, strictly above the pole
    /// `T_ref - C2`: [`Wlf`], physics.md section 12), or one that takes a
    /// creep time out of double precision's range, is refused in one line
    /// naming the remedy or the bound.
    pub fn at_temperature(&self, temperature: f64) -> Result<Material, MaterialError> {
        let wlf = self.wlf.ok_or_else(|| {
            MaterialError::Invalid(format!(
                "[loading] temperature = {temperature} C needs the material's WLF constants: give [material] wlf = [C1, C2 (K), T_ref (C)] or a material.toml fitted with `material fit --wlf`"
            ))
        })?;
        let from = self.temperature.unwrap_or(wlf.reference_temperature);
        let ratio = wlf
            .shift_ratio(from, temperature)
            .map_err(|e| MaterialError::Invalid(format!("[loading] {e}")))?;
        let mut shifted = self.clone();
        for (k, term) in shifted.spectrum.terms.iter_mut().enumerate() {
            let time = term.time * ratio;
            if !(time.is_finite() && time > 0.0) {
                return Err(MaterialError::Invalid(format!(
                    "[loading] temperature = {temperature} C shifts creep time {} of {} s by a_T = {ratio:e} to {time} s, outside the range of double precision; give a temperature nearer {from} C",
                    k + 1,
                    term.time
                )));
            }
            term.time = time;
        }
        shifted.temperature = Some(temperature);
        // `E_T(w) = E_from(w a_T(T) / a_T(from))`: the data's frequencies
        // divide by the ratio.
        shifted.frequency_range = self
            .frequency_range
            .map(|[lo, hi]| [lo / ratio, hi / ratio]);
        Ok(shifted)
    }

    /// A warning when the temperature this material describes lies beyond
    /// the data its WLF constants were fitted to ([`Wlf::extrapolation`]):
    /// the solve and Persson's theory there rest on an extrapolated shift.
    pub fn extrapolated_shift_warning(&self) -> Option<String> {
        let phrase = self.wlf?.extrapolation(self.temperature?)?;
        Some(format!(
            "the material's temperature {phrase}: the friction is an estimate there; DMA data nearer this temperature would confirm it"
        ))
    }

    /// The same material with the angular frequencies `[lowest, highest]`
    /// \[rad/s\] of the data its spectrum was fitted to, at the temperature
    /// it describes ([`Material::frequency_range`]): both positive and
    /// finite, the lowest first.
    pub fn with_frequency_range(mut self, range: [f64; 2]) -> Result<Self, MaterialError> {
        let [lo, hi] = range;
        if !(lo > 0.0 && lo <= hi && hi.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "[{lo}, {hi}] rad/s must be two positive finite frequencies, the lowest first"
            )));
        }
        self.frequency_range = Some(range);
        Ok(self)
    }

    /// Warnings where the frequencies `[w_lo, w_hi]` \[rad/s\] a sliding
    /// excites reach more than a decade beyond the
    /// data the spectrum was fitted to ([`Material::frequency_range`], at
    /// the temperature it describes): one for each end, naming the
    /// decades.
    pub fn extrapolated_frequencies_warnings(&self, w_lo: f64, w_hi: f64) -> Vec<String> {
        let Some([lo, hi]) = self.frequency_range else {
            return Vec::new();
        };
        let margin = 10f64.powf(FREQUENCY_MARGIN_DECADES);
        let mut out = Vec::new();
        if w_hi > margin * hi {
            out.push(format!(
                "the sliding excites frequencies v q up to {w_hi:.3e} rad/s, {:.1} decades above the highest of the DMA data the spectrum was fitted to ({hi:.3e} rad/s at this temperature): the moduli there are the fit's extrapolation (its glassy end), and the friction rests on them; data at higher frequencies or lower temperatures would measure them",
                (w_hi / hi).log10()
            ));
        }
        if w_lo > 0.0 && w_lo < lo / margin {
            out.push(format!(
                "the sliding excites frequencies v q down to {w_lo:.3e} rad/s, {:.1} decades below the lowest of the DMA data the spectrum was fitted to ({lo:.3e} rad/s at this temperature): the moduli there are the fit's extrapolation (its relaxed end); data at lower frequencies or higher temperatures would measure them",
                (lo / w_lo).log10()
            ));
        }
        out
    }

    /// [`Material::at_temperature`] when a temperature is given, else the
    /// material unchanged.
    pub fn at(&self, temperature: Option<f64>) -> Result<Material, MaterialError> {
        match temperature {
            Some(t) => self.at_temperature(t),
            None => Ok(self.clone()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::CreepSpectrum;

    fn sls() -> Material {
        Material::new(
            CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
            0.5,
        )
        .unwrap()
    }

    #[test]
    fn times_scale_by_the_wlf_factor() {
        let wlf = Wlf::new(8.86, 101.6, 17.0).unwrap();
        let m = sls().with_wlf(wlf, None).unwrap();
        let cold = m.at_temperature(7.0).unwrap();
        // log10 a_T = -8.86 (-10) / (101.6 - 10), computed independently.
        let a = 10f64.powf(88.6 / 91.6);
        assert!((cold.spectrum.terms[0].time / 0.01 / a - 1.0).abs() < 1e-14);
        let s = cold.temperature_shift().unwrap();
        assert_eq!(s.temperature, 7.0);
        assert!((s.shift_factor / a - 1.0).abs() < 1e-14);
        // Moduli unchanged (no vertical shift).
        assert_eq!(
            cold.spectrum.terms[0].compliance,
            m.spectrum.terms[0].compliance
        );
        assert_eq!(cold.spectrum.glassy_modulus, m.spectrum.glassy_modulus);
        // From a spectrum at another temperature: the ratio of the factors.
        let warm = m.at_temperature(27.0).unwrap();
        let back = warm.at_temperature(7.0).unwrap();
        assert!((back.spectrum.terms[0].time / cold.spectrum.terms[0].time - 1.0).abs() < 1e-13);
    }

    #[test]
    fn refusals_are_one_line_and_name_the_bound() {
        let e = sls().at_temperature(20.0).unwrap_err().to_string();
        assert!(e.contains("WLF") && !e.contains('\n'), "{e}");
        let m = sls()
            .with_wlf(Wlf::new(8.86, 101.6, 17.0).unwrap(), None)
            .unwrap();
        let e = m.at_temperature(17.0 - 101.6).unwrap_err().to_string();
        assert!(e.contains("-84.6") && !e.contains('\n'), "{e}");
        // Just above the pole a_T would overflow: below the validity range
        // T >= 17 - 101.6 * 50 / 58.86 = -69.306 C.
        let e = m.at_temperature(-84.5).unwrap_err().to_string();
        assert!(e.contains("-84.5 C") && e.contains("-69.3 C"), "{e}");
        assert!(m.at_temperature(-69.3).is_ok());
        assert!(m.at_temperature(-69.31).is_err());
        assert!(m.at_temperature(f64::NAN).is_err());
        // The spectrum's own temperature is checked where it is set.
        let e = sls()
            .with_wlf(Wlf::new(8.86, 101.6, 17.0).unwrap(), Some(-80.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("-80 C") && e.contains("-69.3 C"), "{e}");
        // A creep time that the factor would take out of range.
        let long = Material::new(
            CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 1e270).unwrap(),
            0.5,
        )
        .unwrap()
        .with_wlf(Wlf::new(8.86, 101.6, 17.0).unwrap(), None)
        .unwrap();
        let e = long.at_temperature(-69.0).unwrap_err().to_string();
        assert!(e.contains("-69 C") && e.contains("creep time"), "{e}");
    }
}
