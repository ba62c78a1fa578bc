//! Persson's theory beside a merged sweep (physics.md section 10): read
//! back from the pinned configuration per `[sweep.vary]` combination, or
//! from the values each point recorded.

use std::collections::BTreeMap;
use std::path::Path;

use super::row::MergedRow;
use crate::config::{self, LoadedConfig};
use crate::error::Result;
use crate::persson::{self, Persson, PerssonParams};
use crate::problem::persson::{theory_inputs, TheoryInputs};

/// Persson's theory for the sweep in `dir` at one combination of its
/// `[sweep.vary]` values: its pinned configuration read back with the
/// recorded directory for relative paths (the sweep directory itself when
/// none is recorded). `Err` says why not.
pub(super) fn theory_for(
    dir: &Path,
    vary: &BTreeMap<String, toml::Value>,
) -> std::result::Result<TheoryInputs, String> {
    let path = dir.join(super::CONFIG_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut document: toml::Table =
        toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let base_dir = std::fs::read_to_string(dir.join(super::CONFIG_DIR_FILE))
        .map(|t| Path::new(t.trim()).to_path_buf())
        .unwrap_or_else(|_| dir.to_path_buf());
    // The files the points were solved with, unchanged since (else the
    // theory would be another surface's or material's).
    super::files::check_unchanged(&document, &base_dir)?;
    document.remove(super::files::FILES_KEY);
    // The combination's `[sweep.vary]` values, set as the sweep set them.
    let mut given = Vec::new();
    for (key, value) in vary {
        config::set_replacing(&mut document, key, value.clone(), &mut given)?;
    }
    let name = path.display().to_string();
    let config = config::parse_document(&document, &name).map_err(|e| e.to_string())?;
    let cfg = LoadedConfig {
        config,
        path,
        base_dir,
        document,
    };
    theory_inputs(&cfg, None, None).map_err(|e| e.to_string())
}

/// The theory's curves per load label: `(x, mu, A/A0, A/A(0))` at 100
/// speeds over the positive speeds of its rows.
pub(super) type Curve = Vec<(f64, f64, f64, f64)>;

/// Fill the Persson columns of `rows` from `inputs` (each load at its
/// measured nominal pressure) and return the smooth curves per load.
pub(super) fn theory_curves(
    inputs: &TheoryInputs,
    rows: &mut [MergedRow],
    label: &dyn Fn(&MergedRow) -> String,
    use_xi: bool,
) -> Result<Vec<(String, Curve)>> {
    let area = inputs.area;
    let mut loads: Vec<String> = rows.iter().map(label).collect();
    loads.dedup();
    let mut curves = Vec::new();
    for load in loads {
        let idx: Vec<usize> = (0..rows.len())
            .filter(|&i| label(&rows[i]) == load)
            .collect();
        let sigma0 = match area {
            Some(a) => idx.iter().map(|&i| rows[i].normal_load).sum::<f64>() / idx.len() as f64 / a,
            None => inputs.nominal_pressure,
        };
        let theory = Persson::new(
            &inputs.material,
            &inputs.psd,
            sigma0,
            PerssonParams::default(),
        )?;
        let a0 = theory.point(0.0)?.contact_area_fraction;
        let speeds: Vec<f64> = idx.iter().map(|&i| rows[i].speed).collect();
        for (&i, p) in idx.iter().zip(theory.curve(&speeds)?) {
            let r = &mut rows[i];
            r.persson_friction.get_or_insert(p.friction_coefficient);
            r.persson_area_fraction
                .get_or_insert(p.contact_area_fraction);
            r.persson_area_ratio = Some(p.contact_area_fraction / a0);
        }
        let pos = speeds.iter().copied().filter(|v| *v > 0.0);
        let (lo, hi) = (
            pos.clone().fold(f64::INFINITY, f64::min),
            pos.fold(0.0, f64::max),
        );
        if hi <= 0.0 {
            continue;
        }
        let xi_scale = inputs.xi_scale();
        let curve = theory
            .curve(&persson::log_speeds(lo, hi, 100))?
            .into_iter()
            .map(|p| {
                let x = match (use_xi, xi_scale) {
                    (true, Some(s)) => s.xi(p.speed),
                    _ => p.speed,
                };
                (
                    x,
                    p.friction_coefficient,
                    p.contact_area_fraction,
                    p.contact_area_fraction / a0,
                )
            })
            .collect();
        curves.push((load, curve));
    }
    Ok(curves)
}

/// Persson's curves from the values each point recorded (the pinned
/// configuration cannot be read back), `A/A(0)` from the static point's.
pub(super) fn recorded_curves(
    rows: &mut [MergedRow],
    label: &dyn Fn(&MergedRow) -> String,
    x_of: &dyn Fn(&MergedRow) -> f64,
) -> Vec<(String, Curve)> {
    let statics: BTreeMap<String, f64> = rows
        .iter()
        .filter(|r| r.speed == 0.0)
        .filter_map(|r| r.persson_area_fraction.map(|a| (label(r), a)))
        .collect();
    for r in rows.iter_mut() {
        if let (Some(a), Some(a0)) = (r.persson_area_fraction, statics.get(&label(r))) {
            r.persson_area_ratio = Some(a / a0);
        }
    }
    let mut labels: Vec<String> = rows.iter().map(label).collect();
    labels.dedup();
    labels
        .iter()
        .map(|l| {
            let c: Curve = rows
                .iter()
                .filter(|r| label(r) == *l && x_of(r) > 0.0)
                .filter_map(|r| {
                    Some((
                        x_of(r),
                        r.persson_friction?,
                        r.persson_area_fraction?,
                        r.persson_area_ratio.unwrap_or(f64::NAN),
                    ))
                })
                .collect();
            (l.clone(), c)
        })
        .filter(|(_, c)| !c.is_empty())
        .collect()
}
