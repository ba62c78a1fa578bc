//! `[heating]`: frictional heating of the rubber and its feedback on the
//! friction (physics.md section 14).

use serde::{Deserialize, Serialize};

/// `[heating]`: the rubber's thermal properties and how the heated contact
/// is closed. Needs a WLF material and `[loading] temperature` (the
/// ambient `T0`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct HeatingConfig {
    /// Solve the heated contact (default true when the section is given;
    /// `false` gives the isothermal solve at `T0`, for sweeps over it).
    pub enabled: Option<bool>,
    /// Thermal conductivity `lam` \[W/(m K)\].
    pub conductivity: Option<f64>,
    /// Thermal diffusivity `kappa` \[m^2/s\]; or `density` and
    /// `specific_heat`, `kappa = lam / (rho c)`.
    pub diffusivity: Option<f64>,
    /// Density `rho` \[kg/m^3\].
    pub density: Option<f64>,
    /// Specific heat `c` \[J/(kg K)\].
    pub specific_heat: Option<f64>,
    /// Length of the rubber block along the sliding direction \[m\]: the
    /// time `L_b / v` each element spends in the nominal contact, for the
    /// periodic cell's background heating.
    pub block_length: Option<f64>,
    /// Where the dissipated power enters: `"volume"` (the creep elements'
    /// dissipation on depth layers, default) or `"surface"` (the work of
    /// the contact pressure as a surface flux).
    pub source: Option<String>,
    /// The feedback on the modulus: `"effective"` (one temperature, the
    /// dissipation-weighted mean; the only closure so far).
    pub closure: Option<String>,
    /// Branch reported as the answer when several temperatures are
    /// self-consistent: `"cold"` (default) or `"hot"`.
    pub branch: Option<String>,
    /// The bracket searched for effective temperatures is `[T0, T0 +
    /// max_rise]` \[K\] (default 100).
    pub max_rise: Option<f64>,
    /// An effective temperature is accepted where `|T0 + Theta(T) - T|`
    /// is at most this \[K\] (default 1e-3).
    pub tolerance: Option<f64>,
}
