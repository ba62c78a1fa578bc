//! What a merge adds for heated points (`[heating]`, physics.md section
//! 14): each row's effective temperature, rises, isothermal friction at
//! `T0`, branches and fixed-point solves, aggregated over its
//! realisations as the other columns are, so that `sweep.csv` carries the
//! numbers Python's `sweep` gives as `HEATING_COLUMNS`.

use serde::Deserialize;

use super::row::{mean_std, HeatedRow, MergedRow};

/// The headline of a heated point's `heating` report (`points/*.json`).
#[derive(Debug, Clone, Deserialize)]
pub(super) struct HeatedPoint {
    effective_temperature: f64,
    temperature_rise: PointRises,
    isothermal_friction_coefficient: f64,
    branches: Vec<serde::de::IgnoredAny>,
    fixed_point_evaluations: usize,
}

#[derive(Debug, Clone, Deserialize)]
struct PointRises {
    effective: f64,
    peak_surface: f64,
}

/// The heating of a row whose realisations are `points`; `None` unless
/// every one of them was heated (a `heating.enabled = false` row is
/// isothermal).
pub(super) fn aggregate(points: &[Option<&HeatedPoint>]) -> Option<HeatedRow> {
    let heated: Vec<&HeatedPoint> = points.iter().copied().collect::<Option<_>>()?;
    if heated.is_empty() {
        return None;
    }
    let col = |f: &dyn Fn(&HeatedPoint) -> f64| {
        mean_std(&heated.iter().map(|h| f(h)).collect::<Vec<_>>())
    };
    Some(HeatedRow {
        effective_temperature: col(&|h| h.effective_temperature),
        temperature_rise: col(&|h| h.temperature_rise.effective),
        peak_surface_rise: col(&|h| h.temperature_rise.peak_surface),
        isothermal_friction: col(&|h| h.isothermal_friction_coefficient),
        branches_max: heated.iter().map(|h| h.branches.len()).max().unwrap_or(0),
        fixed_point_evaluations_mean: col(&|h| h.fixed_point_evaluations as f64).0,
    })
}

/// The columns `sweep.csv` gains when any row is heated (after the varied
/// keys and temperatures); empty otherwise, so an isothermal sweep's table
/// is unchanged.
pub const COLUMNS: [&str; 10] = [
    "effective_temperature_c_mean",
    "effective_temperature_c_std",
    "temperature_rise_k_mean",
    "temperature_rise_k_std",
    "peak_surface_rise_k_mean",
    "peak_surface_rise_k_std",
    "isothermal_friction_mean",
    "isothermal_friction_std",
    "branches_max",
    "fixed_point_evaluations_mean",
];

fn any_heated(rows: &[MergedRow]) -> bool {
    rows.iter().any(|r| r.heating.is_some())
}

/// The header of [`COLUMNS`] for `rows` (each with a leading comma).
pub fn extra_header(rows: &[MergedRow]) -> String {
    if !any_heated(rows) {
        return String::new();
    }
    COLUMNS.iter().map(|c| format!(",{c}")).collect()
}

/// The fields of [`extra_header`] for `row`: empty for an isothermal row
/// of a heated sweep.
pub fn extra_fields(rows: &[MergedRow], row: &MergedRow) -> String {
    if !any_heated(rows) {
        return String::new();
    }
    let Some(h) = &row.heating else {
        return ",".repeat(COLUMNS.len());
    };
    let pair = |(m, s): (f64, f64)| format!(",{m:.8e},{s:.8e}");
    format!(
        "{}{}{}{},{},{:.8e}",
        pair(h.effective_temperature),
        pair(h.temperature_rise),
        pair(h.peak_surface_rise),
        pair(h.isothermal_friction),
        h.branches_max,
        h.fixed_point_evaluations_mean
    )
}
