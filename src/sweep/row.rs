//! One row of a merged sweep (`sweep.csv`): the data type shared by the
//! merge, its theory curves and the master curve.

use std::collections::BTreeMap;

/// One row of `sweep.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct MergedRow {
    /// The `[sweep.vary]` values of the row (empty without them).
    pub vary: BTreeMap<String, toml::Value>,
    /// Temperature \[C\] and WLF shift factor `a_T` of the row's
    /// material, when it has WLF constants (physics.md section 12).
    pub temperature: Option<f64>,
    pub shift_factor: Option<f64>,
    pub normal_load: f64,
    pub speed: f64,
    pub xi: Option<f64>,
    pub realisations: usize,
    /// `(mean, standard deviation)` of each quantity.
    pub friction: (f64, f64),
    pub friction_dissipation: (f64, f64),
    pub area_fraction: (f64, f64),
    /// `A / A(v = 0)` of the same realisation and load, when the static point exists.
    pub area_ratio: Option<(f64, f64)>,
    pub gamma: Option<(f64, f64)>,
    pub lambda: Option<(f64, f64)>,
    /// Persson's `mu` at this speed and load.
    pub persson_friction: Option<f64>,
    /// Persson's `A/A0` at this speed and load.
    pub persson_area_fraction: Option<f64>,
    /// Persson's `A(v) / A(0)` at this load.
    pub persson_area_ratio: Option<f64>,
    /// The heated solve's numbers, when every realisation was heated.
    pub heating: Option<HeatedRow>,
}

/// A merged row's heating: `(mean, standard deviation)` over its
/// realisations.
#[derive(Debug, Clone, PartialEq)]
pub struct HeatedRow {
    /// `T_eff` \[C\].
    pub effective_temperature: (f64, f64),
    /// The effective rise `Theta(T_eff)` \[K\].
    pub temperature_rise: (f64, f64),
    /// The highest surface rise \[K\].
    pub peak_surface_rise: (f64, f64),
    /// The isothermal friction at `T0` beside.
    pub isothermal_friction: (f64, f64),
    /// The most self-consistent temperatures any realisation found.
    pub branches_max: usize,
    /// Full-grid isothermal solves per realisation, on average.
    pub fixed_point_evaluations_mean: f64,
}

/// `(mean, standard deviation)` of `v` (the sample deviation; 0 for one
/// value).
pub(super) fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = if v.len() > 1 {
        v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
}

impl MergedRow {
    /// The label of the curve the row lies on: its `[sweep.vary]` values
    /// and its load as planned (to the precision a user types it).
    pub fn curve_label(&self) -> String {
        let vary = vary_text(&self.vary);
        let load = format!("F_N = {:.4e} N", self.normal_load);
        if vary.is_empty() {
            load
        } else {
            format!("{vary}, {load}")
        }
    }
}

/// `key = value, ...` of a row's `[sweep.vary]` values (empty without them).
fn vary_text(vary: &BTreeMap<String, toml::Value>) -> String {
    vary.iter()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}
