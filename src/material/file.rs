//! The `material.toml` file written by `viscoslide material fit` and read by
//! `model = "file"`: a `[material]` table in the config's own key names
//! (`model = "creep_spectrum"`, Eq. 2) plus a `[fit]` table of provenance.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::{Material, Wlf};
use super::{MaterialConfig, MaterialError, MaterialModel};

/// Provenance of a fitted material, stored as `[fit]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitRecord {
    /// The DMA data file as given on the command line.
    pub data: String,
    /// Data points used.
    pub points: usize,
    /// Number and ratio of the relaxation-time grid.
    pub terms: usize,
    pub ratio: f64,
    /// Shortest and longest relaxation time of the grid \[s\].
    pub shortest_time: f64,
    pub longest_time: f64,
    /// Terms of the fitted relaxation spectrum with positive weight.
    pub nonzero_terms: usize,
    /// WLF constants used to build the master curve, if any.
    pub wlf_c1: Option<f64>,
    pub wlf_c2: Option<f64>,
    pub wlf_reference_temperature: Option<f64>,
    /// The lowest and highest temperature \[C\] of the data the WLF
    /// constants shifted (data at several temperatures only): beyond them
    /// a solve's shift is extrapolated ([`Wlf::data_range`]).
    pub wlf_range: Option<[f64; 2]>,
    /// The lowest and highest angular frequency \[rad/s\] of the data,
    /// shifted to `temperature` when WLF constants shifted them: beyond
    /// them the spectrum's moduli are extrapolated
    /// ([`Material::frequency_range`]).
    pub frequency_range: Option<[f64; 2]>,
    /// Temperature the material describes \[C\], if known.
    pub temperature: Option<f64>,
    /// How residuals were weighted.
    pub weighting: String,
    /// RMS and largest relative error of `E1` and `E2` over the data.
    pub rms_relative_error_e1: f64,
    pub rms_relative_error_e2: f64,
    pub max_relative_error_e1: f64,
    pub max_relative_error_e2: f64,
    /// `E0` \[Pa\] of the fit (also implied by the spectrum).
    pub relaxed_modulus: f64,
    /// What may make the fit mislead (`material::fit_warnings`): unread
    /// columns, merged temperatures, a large error, a plateau the data do
    /// not reach. Absent when there is none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// viscoslide version that wrote the file.
    pub version: String,
}

/// The file as written.
#[derive(Debug, Serialize)]
struct MaterialFileOut<'a> {
    material: MaterialConfig,
    fit: Option<&'a FitRecord>,
}

/// The file as read: `[material]` is checked strictly; `[fit]` is provenance
/// for people and is not interpreted but for its WLF constants (see
/// `fit_wlf`), so files from other versions load.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFileIn {
    material: MaterialConfig,
    fit: Option<toml::Value>,
}

/// The text of a `material.toml` for `material` with optional provenance.
pub fn material_toml(
    material: &Material,
    fit: Option<&FitRecord>,
) -> Result<String, MaterialError> {
    let config = MaterialConfig {
        model: MaterialModel::CreepSpectrum,
        relaxed_modulus: None,
        glassy_modulus: Some(material.spectrum.glassy_modulus),
        creep_time: None,
        relaxation_time: None,
        creep_spectrum: Some(
            material
                .spectrum
                .terms
                .iter()
                .map(|t| [t.compliance, t.time])
                .collect(),
        ),
        prony: None,
        poisson: Some(material.poisson),
        file: None,
        wlf: None,
        wlf_range: None,
        frequency_range: None,
    };
    let doc = MaterialFileOut {
        material: config,
        fit,
    };
    let body = toml::to_string(&doc).map_err(|e| MaterialError::Invalid(e.to_string()))?;
    Ok(format!(
        "# Material written by viscoslide {}: creep spectrum of Eq. 2\n\
         # (Carbone & Putignano, PRE 89, 032408, 2014), SI units:\n\
         # creep_spectrum = [[C_k (1/Pa), tau_k (s)], ...], glassy_modulus = E_inf (Pa).\n\
         # Load it from a config with [material] model = \"file\", file = \"<this path>\".\n\n{body}",
        crate::version::VERSION
    ))
}

/// Read a `material.toml` and build its material. `poisson`, when given,
/// replaces the file's Poisson ratio.
pub fn load_material_file(path: &Path, poisson: Option<f64>) -> Result<Material, MaterialError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| MaterialError::Data {
        source_name: name.clone(),
        message: e.to_string(),
    })?;
    let doc: MaterialFileIn = toml::from_str(&text).map_err(|e| MaterialError::Data {
        source_name: name.clone(),
        message: e.message().replace('\n', " "),
    })?;
    let mut cfg = doc.material;
    if cfg.model == MaterialModel::File {
        return Err(MaterialError::Data {
            source_name: name,
            message: "a material file may not itself use model = \"file\"".into(),
        });
    }
    if poisson.is_some() {
        cfg.poisson = poisson;
    }
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut material = cfg.build(dir).map_err(|e| MaterialError::Data {
        source_name: name.clone(),
        message: e.to_string(),
    })?;
    // The file's own `[material] frequency_range` wins over its provenance.
    if material.frequency_range.is_none() {
        let data = |message| MaterialError::Data {
            source_name: name.clone(),
            message,
        };
        if let Some(range) = fit_frequency_range(doc.fit.as_ref()).map_err(data)? {
            material = material
                .with_frequency_range(range)
                .map_err(|e| data(format!("[fit] frequency_range: {e}")))?;
        }
    }
    if material.wlf.is_some() {
        // The file's own `[material] wlf` wins over its provenance.
        return Ok(material);
    }
    let data = |message| MaterialError::Data {
        source_name: name.clone(),
        message,
    };
    match fit_wlf(doc.fit.as_ref()).map_err(data)? {
        Some((wlf, t)) => material.with_wlf(wlf, t).map_err(|e| MaterialError::Data {
            source_name: name,
            message: format!("[fit] {e}"),
        }),
        None => {
            // Without constants the fit still says which temperature its
            // spectrum describes: constants given later (a config's `wlf`)
            // shift from there, not from their reference temperature.
            material.temperature = fit_temperature(doc.fit.as_ref()).map_err(data)?;
            Ok(material)
        }
    }
}

/// The WLF constants a `[fit]` table records (`wlf_c1`, `wlf_c2`,
/// `wlf_reference_temperature`, written by `material fit --wlf`, with the
/// data's temperatures `wlf_range` when there were several) and the
/// temperature the fitted spectrum describes (`temperature`), when all
/// three constants are there. Other keys of `[fit]` are not interpreted.
pub fn fit_wlf(fit: Option<&toml::Value>) -> Result<Option<(Wlf, Option<f64>)>, String> {
    let Some(fit) = fit else { return Ok(None) };
    let number = |key: &str| -> Result<Option<f64>, String> {
        match fit.get(key) {
            None => Ok(None),
            Some(toml::Value::Float(x)) => Ok(Some(*x)),
            Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
            Some(v) => Err(format!("[fit] {key} = {v} is not a number")),
        }
    };
    let (c1, c2, t_ref) = match (
        number("wlf_c1")?,
        number("wlf_c2")?,
        number("wlf_reference_temperature")?,
    ) {
        (Some(c1), Some(c2), Some(t)) => (c1, c2, t),
        (None, None, None) => return Ok(None),
        _ => {
            return Err(
                "[fit] gives only some of wlf_c1, wlf_c2, wlf_reference_temperature: give all three or none"
                    .into(),
            )
        }
    };
    let mut wlf = Wlf::new(c1, c2, t_ref).map_err(|e| format!("[fit] wlf_c1, wlf_c2: {e}"))?;
    if let Some(pair) = two_numbers(fit, "wlf_range", "two temperatures [lowest, highest] (C)")? {
        wlf = wlf
            .with_data_range(pair)
            .map_err(|e| format!("[fit] wlf_range: {e}"))?;
    }
    let t = fit_temperature(Some(fit))?;
    if let Some(t) = t {
        wlf.log10_shift(t)
            .map_err(|e| format!("[fit] temperature = {t}: {e}"))?;
    }
    Ok(Some((wlf, t)))
}

/// The temperature \[C\] a `[fit]` table says its spectrum describes
/// (`temperature`, written by `material fit` from data at one
/// temperature or shifted to one), if recorded.
pub fn fit_temperature(fit: Option<&toml::Value>) -> Result<Option<f64>, String> {
    match fit.and_then(|f| f.get("temperature")) {
        None => Ok(None),
        Some(toml::Value::Float(x)) if x.is_finite() => Ok(Some(*x)),
        Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
        Some(v) => Err(format!(
            "[fit] temperature = {v} is not a finite number (C)"
        )),
    }
}

/// The data's angular frequencies a `[fit]` table records
/// (`frequency_range`, written by `material fit`) as two numbers;
/// [`Material::with_frequency_range`] checks them.
pub fn fit_frequency_range(fit: Option<&toml::Value>) -> Result<Option<[f64; 2]>, String> {
    let Some(fit) = fit else { return Ok(None) };
    two_numbers(
        fit,
        "frequency_range",
        "two angular frequencies [lowest, highest] (rad/s)",
    )
}

/// `[fit] key = [a, b]` as two numbers, if present.
fn two_numbers(fit: &toml::Value, key: &str, what: &str) -> Result<Option<[f64; 2]>, String> {
    let Some(value) = fit.get(key) else {
        return Ok(None);
    };
    let bad = || format!("[fit] {key} = {value} is not {what}");
    let numbers: Vec<f64> = value
        .as_array()
        .ok_or_else(bad)?
        .iter()
        .map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
        .collect::<Option<_>>()
        .ok_or_else(bad)?;
    numbers.try_into().map(Some).map_err(|_| bad())
}
