//! `[analysis]`: the contact analysis run after each solve.

use serde::{Deserialize, Serialize};

/// `[analysis]`: the anisotropy analysis that `solve` runs after each solve
/// (paper Eq. 11-13 and the contact-area PSD).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct AnalysisConfig {
    /// Run it (default true).
    pub enabled: Option<bool>,
    /// Lower band factor `zeta1` (default 1).
    pub zeta1: Option<f64>,
    /// Upper band factor `zeta2` (default: the surface's number of scales).
    pub zeta2: Option<f64>,
    /// Levels of `C_chi / C_chi(0)` for the ellipse fits (default [0.5, 0.3]).
    pub chi_levels: Option<Vec<f64>>,
}
