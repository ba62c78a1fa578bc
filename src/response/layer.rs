//! A viscoelastic layer of finite thickness on a rigid base (paper Eq. 5,
//! physics.md section 3, "Finite thickness"): its data and its exact
//! Fourier response, the compliance ratio `S(qh)` of the layer to the
//! half-space, which the periodic multiplier, the dissipation sum and the
//! real-space `Theta` of [`crate::kernel::thickness`] all take.
//!
//! * bonded to a rigid base:
//!   `1/S = [(3-4nu) cosh 2u + 2u^2 + 5 - 12nu + 8nu^2] / [(3-4nu) sinh 2u - 2u]`;
//! * sliding frictionlessly on a rigid base:
//!   `S = (cosh 2u - 1) / (sinh 2u + 2u)`, independent of `nu`.

use serde::{Deserialize, Serialize};

use super::ResponseError;
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
    pub fn build(&self) -> Result<Layer, ResponseError> {
        let l = Layer {
            thickness: self.thickness,
            base: self.base,
        };
        l.validate()?;
        Ok(l)
    }
}

impl Layer {
    /// A warning when the layer is thinner than one cell of side `cell`
    /// \[m\]: the grid does not resolve it (its coefficients stay the cell
    /// integrals of Eq. 5, but the pressure varies on a scale the cells do
    /// not follow).
    pub fn resolution_warning(&self, cell: f64) -> Option<String> {
        (self.thickness < cell).then(|| {
            format!(
                "[layer] thickness = {} m is thinner than one cell ({} m, {:.3e} cells): the grid does not resolve the layer; refine the grid to at least one cell per thickness",
                self.thickness,
                cell,
                self.thickness / cell
            )
        })
    }

    /// Thickness must be positive and finite.
    pub fn validate(&self) -> Result<(), ResponseError> {
        if !(self.thickness.is_finite() && self.thickness > 0.0) {
            return Err(ResponseError::Invalid(format!(
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
                // (cosh 2u - 1)/(sinh 2u + 2u) = u/2 - u^5/90 + ... (the
                // u^3 terms of numerator and denominator cancel).
                return u / 2.0 - u.powi(5) / 90.0;
            }
            ((2.0 * u).cosh() - 1.0) / ((2.0 * u).sinh() + 2.0 * u)
        }
    }
}

/// `S(u) - 1` without cancellation for large `u` (written with `e^{-2u}`).
pub(crate) fn compliance_ratio_minus_one(base: LayerBase, nu: f64, u: f64) -> f64 {
    if u < 2.0 {
        return compliance_ratio(base, nu, u) - 1.0;
    }
    let e = (-2.0 * u).exp();
    if e == 0.0 {
        // `u > 372`: the difference is below every f64 relative to 1 (and
        // `u^2 e` would be `inf * 0` beyond `u ~ 1e154`).
        return 0.0;
    }
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
