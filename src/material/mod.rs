//! Linear viscoelastic materials (physics.md section 2; paper Eq. 2).
//!
//! The engine works with the creep (retardation) form of Eq. 2,
//! `J(t) = 1/E0 - sum_k C_k exp(-t/tau_k)`, whose complex compliance is
//! `J*(w) = 1/E_inf + sum_k C_k / (1 + i w tau_k)` (time factor `exp(+i w t)`),
//! and `E(w) = 1/J*(w)`. Names are unambiguous: `relaxed_modulus` is `E0`
//! (zero frequency, rubbery), `glassy_modulus` is `E_inf`.

mod config;
mod spectrum;

pub use config::{MaterialConfig, MaterialModel};
pub use spectrum::{CreepSpectrum, CreepTerm};

/// Errors building or fitting a material; each names the offending value.
#[derive(Debug, thiserror::Error)]
pub enum MaterialError {
    #[error("{0}")]
    Invalid(String),
}

/// A linear viscoelastic, isotropic solid: creep spectrum and Poisson ratio.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub spectrum: CreepSpectrum,
    /// Poisson ratio `nu` (rubber: 0.5).
    pub poisson: f64,
}

impl Material {
    /// Build a material after checking `-1 < nu <= 0.5`.
    pub fn new(spectrum: CreepSpectrum, poisson: f64) -> Result<Self, MaterialError> {
        if !(poisson > -1.0 && poisson <= 0.5) {
            return Err(MaterialError::Invalid(format!(
                "poisson = {poisson} is outside (-1, 0.5]"
            )));
        }
        Ok(Self { spectrum, poisson })
    }

    /// The composite factor `1 - nu^2` of Eq. 4.
    pub fn composite_factor(&self) -> f64 {
        1.0 - self.poisson * self.poisson
    }
}
