//! Linear viscoelastic materials (physics.md section 2; paper Eq. 2).
//!
//! The engine works with the creep (retardation) form of Eq. 2,
//! `J(t) = 1/E0 - sum_k C_k exp(-t/tau_k)`, whose complex compliance is
//! `J*(w) = 1/E_inf + sum_k C_k / (1 + i w tau_k)` (time factor `exp(+i w t)`),
//! and `E(w) = 1/J*(w)`. Names are unambiguous: `relaxed_modulus` is `E0`
//! (zero frequency, rubbery), `glassy_modulus` is `E_inf`.
//!
//! Parts:
//! * [`CreepSpectrum`] (Eq. 2) and [`PronySeries`] (generalized Maxwell), with
//!   exact conversions both ways ([`PronySeries::to_creep`],
//!   [`CreepSpectrum::to_prony`]; physics.md section 2, route (b));
//! * `eval`: `E(w)`, `J*(w)`, `E1`, `E2`, `tan delta` over frequency arrays;
//! * `dma`: DMA data from CSV, WLF shift ([`Wlf`]), NNLS spectrum fit
//!   ([`fit_spectrum`], solver in `nnls`);
//! * [`mod@file`]: the `material.toml` written by `viscoslide material fit`;
//! * [`MaterialConfig`]: the `[material]` section of a run config;
//! * `temperature`: the WLF shift of every creep time to a temperature
//!   ([`Material::at_temperature`], physics.md section 12).

mod columns;
mod config;
mod dma;
pub(crate) mod eval;
pub mod file;
pub mod fit;
mod fit_checks;
pub(crate) mod nnls;
mod prony;
mod spectrum;
mod temperature;
mod wlf;

pub use crate::config::{MaterialConfig, MaterialModel};
pub use dma::{DmaData, DmaPoint};
pub use eval::{ComplexModulus, DynamicModuli};
pub use file::{load_material_file, material_toml, FitRecord};
pub use fit::{fit_spectrum, FitInfo, FitParams, SpectrumFit};
pub use fit_checks::fit_warnings;
pub use prony::{PronySeries, PronyTerm};
pub use spectrum::{CreepSpectrum, CreepTerm};
pub use temperature::TemperatureShift;
pub use wlf::{Wlf, LOG10_SHIFT_MAX};

/// Errors building or fitting a material; each names the offending value.
#[derive(Debug, thiserror::Error)]
pub enum MaterialError {
    /// A value or combination of values is not acceptable.
    #[error("{0}")]
    Invalid(String),
    /// A data or material file cannot be read or has a bad line.
    #[error("{source_name}: {message}")]
    Data {
        source_name: String,
        message: String,
    },
    /// A spectrum fit cannot be done.
    #[error("fit: {0}")]
    Fit(String),
    /// An exact creep <-> relaxation conversion failed.
    #[error("spectrum conversion: {0}")]
    Conversion(String),
}

/// A linear viscoelastic, isotropic solid: creep spectrum and Poisson ratio.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub spectrum: CreepSpectrum,
    /// Poisson ratio `nu` (rubber: 0.5).
    pub poisson: f64,
    /// WLF constants of its time-temperature shift, when known
    /// (`[material] wlf`, or a `material.toml` fitted with `--wlf`).
    pub wlf: Option<Wlf>,
    /// Temperature \[C\] the spectrum describes, when known
    /// ([`Material::at_temperature`]).
    pub temperature: Option<f64>,
    /// The lowest and highest angular frequency \[rad/s\] of the DMA data
    /// the spectrum was fitted to, at the temperature it describes (a
    /// `material.toml` from `material fit` records them; shifted with the
    /// creep times by [`Material::at_temperature`]): beyond them its
    /// moduli are the fitted spectrum's extrapolation.
    pub frequency_range: Option<[f64; 2]>,
}

impl Material {
    /// Build a material after checking `-1 < nu <= 0.5`.
    pub fn new(spectrum: CreepSpectrum, poisson: f64) -> Result<Self, MaterialError> {
        if !(poisson > -1.0 && poisson <= 0.5) {
            return Err(MaterialError::Invalid(format!(
                "poisson = {poisson} is outside (-1, 0.5]"
            )));
        }
        Ok(Self {
            spectrum,
            poisson,
            wlf: None,
            temperature: None,
            frequency_range: None,
        })
    }

    /// The composite factor `1 - nu^2` of Eq. 4.
    pub fn composite_factor(&self) -> f64 {
        1.0 - self.poisson * self.poisson
    }
}
