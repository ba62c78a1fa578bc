//! `[sweep]`: the axes of a sweep (expanded into points by
//! `crate::sweep::SweepPlan`).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::exact::exactly;

/// `[sweep]`: the axes of a sweep. Exactly one speed axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SweepConfig {
    /// Sliding speeds [m/s].
    pub speed: Option<Vec<f64>>,
    /// Dimensionless speeds `xi = v tau / L`.
    pub xi: Option<Vec<f64>>,
    /// Log-spaced speeds `[from, to, points]` [m/s].
    #[serde(default, deserialize_with = "exactly::<3, _>")]
    pub speed_range: Option<[f64; 3]>,
    /// Log-spaced `xi`: `[from, to, points]`.
    #[serde(default, deserialize_with = "exactly::<3, _>")]
    pub xi_range: Option<[f64; 3]>,
    /// Add the static point (`v = 0`, fully relaxed), the reference of
    /// `A / A(xi = 0)` (default true).
    pub include_static: Option<bool>,
    /// Normal loads \[N\] (default: the `[loading]` one).
    pub normal_load: Option<Vec<f64>>,
    /// Surface realisations: seeds of `[surface.generate]` (default: its own).
    pub seeds: Option<Vec<u64>>,
    /// Any other config key, by its dotted name, and the values it takes
    /// (`"loading.temperature" = [7.0, 17.0, 27.0]`), each applied as
    /// `--set` applies it; crossed with the other axes (outermost, keys in
    /// name order).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vary: Option<BTreeMap<String, Vec<toml::Value>>>,
}
