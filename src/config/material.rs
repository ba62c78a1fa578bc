//! `[material]`: the viscoelastic solid (key names fixed by the project);
//! built into a material by `MaterialConfig::build` in [`crate::material`].

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::exact::{exact_rows, exactly};

/// Which material description a config gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialModel {
    /// Standard linear solid: `relaxed_modulus`, `glassy_modulus`, and
    /// `creep_time` or `relaxation_time`.
    Sls,
    /// `creep_spectrum = [[C_k, tau_k], ...]` with `glassy_modulus`.
    CreepSpectrum,
    /// Generalized Maxwell `prony = [[E_j, theta_j], ...]` with `relaxed_modulus`.
    Prony,
    /// A `material.toml` written by `viscoslide material fit`.
    File,
}

/// `[material]`: SI units (Pa, 1/Pa, s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialConfig {
    pub model: MaterialModel,
    /// `E0` \[Pa\].
    pub relaxed_modulus: Option<f64>,
    /// `E_inf` \[Pa\].
    pub glassy_modulus: Option<f64>,
    /// Creep (retardation) time of the SLS \[s\].
    pub creep_time: Option<f64>,
    /// Stress-relaxation time of the SLS \[s\] (`creep_time * E0 / E_inf`).
    pub relaxation_time: Option<f64>,
    /// `[[C_k (1/Pa), tau_k (s)], ...]`.
    #[serde(default, deserialize_with = "exact_rows::<2, _>")]
    pub creep_spectrum: Option<Vec<[f64; 2]>>,
    /// `[[E_j (Pa), theta_j (s)], ...]`.
    #[serde(default, deserialize_with = "exact_rows::<2, _>")]
    pub prony: Option<Vec<[f64; 2]>>,
    /// Poisson ratio (default 0.5).
    pub poisson: Option<f64>,
    /// Path of a `material.toml` (relative to the config file).
    pub file: Option<PathBuf>,
    /// WLF constants `[C1, C2 (K), T_ref (C)]` of the time-temperature
    /// shift (any model; for `file`, replaces the file's `[fit]` ones): the
    /// spectrum is taken at `T_ref` unless the file records its own
    /// temperature. Needed by `[loading] temperature`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exactly::<3, _>"
    )]
    pub wlf: Option<[f64; 3]>,
    /// The lowest and highest temperature \[C\] of the data the WLF
    /// constants were fitted to (for `file`, replaces the `[fit]` table's
    /// `wlf_range`): a solve at a temperature beyond them warns that its
    /// shift is extrapolated. Needs WLF constants.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exactly::<2, _>"
    )]
    pub wlf_range: Option<[f64; 2]>,
    /// The lowest and highest angular frequency \[rad/s\] of the data the
    /// spectrum was fitted to, at the temperature it describes (for
    /// `file`, replaces the `[fit]` table's `frequency_range`): a solve
    /// that excites frequencies a decade beyond them warns that its moduli
    /// there are extrapolated.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exactly::<2, _>"
    )]
    pub frequency_range: Option<[f64; 2]>,
}
