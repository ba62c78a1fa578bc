//! `viscoslide.Material`'s native half: a material built by the library
//! from `[material]` keys (`MaterialConfig::build`), from a TOML file, or
//! fitted to DMA data (`fit_spectrum`), with the `[material]` section that
//! reproduces it (recorded in a solve's `summary.json`).

use std::path::{Path, PathBuf};

use num_complex::Complex64;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use viscoslide::material::{
    fit_spectrum, fit_warnings, DmaData, DmaPoint, FitParams, Material, MaterialConfig,
    MaterialModel, Wlf,
};

use crate::errors::value_error;

/// A linear viscoelastic material (built by the library).
#[pyclass(name = "Material", module = "viscoslide._native", frozen)]
#[derive(Clone)]
pub struct NativeMaterial {
    pub material: Material,
    /// The `[material]` section that builds this material.
    pub section: MaterialConfig,
}

/// A `[material]` section as a TOML table.
pub fn section_table(section: &MaterialConfig) -> toml::Table {
    toml::Table::try_from(section).unwrap_or_default()
}

impl NativeMaterial {
    pub(crate) fn build(section: MaterialConfig, base_dir: &Path) -> PyResult<Self> {
        let material = section.build(base_dir).map_err(value_error)?;
        Self::finish(material, section, base_dir)
    }

    fn finish(material: Material, mut section: MaterialConfig, base_dir: &Path) -> PyResult<Self> {
        if let Some(file) = &section.file {
            section.file = Some(base_dir.join(file));
        }
        Ok(Self { material, section })
    }
}

#[pymethods]
impl NativeMaterial {
    /// A material from the keys of a `[material]` section given as JSON,
    /// relative files resolved against `base_dir`.
    #[staticmethod]
    fn from_section(section_json: &str, base_dir: PathBuf) -> PyResult<Self> {
        let section: MaterialConfig = serde_json::from_str(section_json)
            .map_err(|e| value_error(format!("[material] {e}")))?;
        Self::build(section, &base_dir)
    }

    /// The `[material]` section of a TOML file (a configuration, or a
    /// `material.toml` written by `viscoslide material fit`), relative
    /// files resolved against the file's directory.
    #[staticmethod]
    fn from_toml(path: PathBuf) -> PyResult<Self> {
        let text = std::fs::read_to_string(&path).map_err(|e| {
            pyo3::exceptions::PyOSError::new_err(format!("{}: {e}", path.display()))
        })?;
        let doc: toml::Table = toml::from_str(&text)
            .map_err(|e| value_error(format!("{}: {}", path.display(), e.message())))?;
        let base_dir = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        if !matches!(doc.get("material"), Some(toml::Value::Table(_))) {
            return Err(value_error(format!(
                "{}: no [material] section (a configuration or a material.toml from `viscoslide material fit`)",
                path.display()
            )));
        }
        // A material.toml written by `material fit` (its `[fit]` table
        // records the data's frequencies, WLF constants and temperature)
        // is read as `model = "file"` reads it, and that is the section
        // that rebuilds it.
        if doc.contains_key("fit") {
            // Absolute, so that the section rebuilds it from any directory.
            let file = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
            let section = MaterialConfig {
                file: Some(file),
                ..bare_section(MaterialModel::File)
            };
            return Self::build(section, Path::new(""));
        }
        let section: MaterialConfig = doc["material"]
            .clone()
            .try_into()
            .map_err(|e| value_error(format!("{}: [material] {e}", path.display())))?;
        Self::build(section, &base_dir)
    }

    /// WLF constants `(C1, C2 [K], T_ref [C])` of the material, if any.
    #[getter]
    fn wlf(&self) -> Option<(f64, f64, f64)> {
        self.material
            .wlf
            .map(|w| (w.c1, w.c2, w.reference_temperature))
    }

    /// The lowest and highest angular frequency \[rad/s\] of the data
    /// its spectrum was fitted to, if recorded.
    #[getter]
    fn frequency_range(&self) -> Option<(f64, f64)> {
        self.material.frequency_range.map(|[lo, hi]| (lo, hi))
    }

    /// The lowest and highest temperature \[C\] of the data its WLF
    /// constants were fitted to, if recorded.
    #[getter]
    fn wlf_range(&self) -> Option<(f64, f64)> {
        self.material
            .wlf
            .and_then(|w| w.data_range)
            .map(|[lo, hi]| (lo, hi))
    }

    /// Fit a creep spectrum to DMA data (as `viscoslide material fit`):
    /// angular frequencies `omega` \[rad/s\], storage and loss moduli \[Pa\],
    /// optional test temperatures \[C\] shifted by `wlf = (C1, C2, T_ref)`
    /// to `temperature`. Returns the material and the fit's quality.
    #[staticmethod]
    #[pyo3(signature = (omega, storage, loss, temperatures, wlf, temperature, terms, ratio, poisson))]
    #[allow(clippy::too_many_arguments)]
    fn fit_dma<'py>(
        py: Python<'py>,
        omega: Vec<f64>,
        storage: Vec<f64>,
        loss: Vec<f64>,
        temperatures: Option<Vec<f64>>,
        wlf: Option<(f64, f64, f64)>,
        temperature: Option<f64>,
        terms: usize,
        ratio: f64,
        poisson: f64,
    ) -> PyResult<(Self, Bound<'py, PyDict>)> {
        let n = omega.len();
        if storage.len() != n
            || loss.len() != n
            || temperatures.as_ref().is_some_and(|t| t.len() != n)
        {
            return Err(value_error(format!(
                "frequency, storage, loss (and temperatures) need one value per point: got {n}, {}, {}{}",
                storage.len(),
                loss.len(),
                temperatures.as_ref().map(|t| format!(", {}", t.len())).unwrap_or_default()
            )));
        }
        let data = DmaData::from_points(
            "DMA arrays",
            (0..n)
                .map(|i| DmaPoint {
                    omega: omega[i],
                    storage: storage[i],
                    loss: loss[i],
                    temperature: temperatures.as_ref().map(|t| t[i]),
                })
                .collect(),
        )
        .map_err(value_error)?;
        let wlf = wlf
            .map(|(c1, c2, t)| Wlf::new(c1, c2, t))
            .transpose()
            .map_err(|e| value_error(format!("wlf: {e}")))?;
        // Data at several temperatures: the constants' fitted range.
        let wlf = match (wlf, data.temperature_span()) {
            (Some(w), Some(span)) => Some(
                w.with_data_range(span)
                    .map_err(|e| value_error(format!("temperatures: {e}")))?,
            ),
            (w, _) => w,
        };
        let (points, at) = data
            .reduced(wlf.as_ref(), temperature)
            .map_err(value_error)?;
        let omega: Vec<f64> = points.iter().map(|p| p.omega).collect();
        let measured: Vec<Complex64> = points
            .iter()
            .map(|p| Complex64::new(p.storage, p.loss))
            .collect();
        let params = FitParams {
            terms,
            ratio,
            shortest_time: None,
        };
        let fit = fit_spectrum(&omega, &measured, &params).map_err(value_error)?;
        let mut material = Material::new(fit.creep.clone(), poisson).map_err(value_error)?;
        material.frequency_range = Some(fit.info.frequency_range);
        let frequency_range = material.frequency_range;
        if let Some(w) = wlf {
            // The fitted spectrum describes `at` (T_ref unless shifted).
            material = material.with_wlf(w, at).map_err(value_error)?;
        }
        let info = PyDict::new(py);
        let i = &fit.info;
        info.set_item("points", i.points)?;
        info.set_item("nonzero_terms", i.nonzero_terms)?;
        info.set_item("shortest_time", i.shortest_time)?;
        info.set_item("longest_time", i.longest_time)?;
        info.set_item("rms_relative_error_e1", i.rms_relative_storage)?;
        info.set_item("rms_relative_error_e2", i.rms_relative_loss)?;
        info.set_item("max_relative_error_e1", i.max_relative_storage)?;
        info.set_item("max_relative_error_e2", i.max_relative_loss)?;
        info.set_item("temperature", at)?;
        info.set_item("warnings", fit_warnings(&data, &fit))?;
        let mut section = creep_section(&material);
        section.frequency_range = frequency_range;
        if let Some(w) = wlf {
            // The spectrum describes `at`: the constants referred to it
            // rebuild the same material at every temperature.
            let w = match at {
                Some(t) => w
                    .referenced_to(t)
                    .map_err(|e| value_error(format!("temperature: {e}")))?,
                None => w,
            };
            section.wlf = Some([w.c1, w.c2, w.reference_temperature]);
            section.wlf_range = w.data_range;
        }
        Ok((Self { material, section }, info))
    }

    /// `E(w)` \[Pa\] at angular frequencies `omega` \[rad/s\] (paper Eq. 2).
    fn complex_modulus<'py>(
        &self,
        py: Python<'py>,
        omega: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<Complex64>>> {
        let s = &self.material.spectrum;
        let values: Vec<Complex64> = omega.as_array().iter().map(|&w| s.modulus(w)).collect();
        Ok(values.into_pyarray(py))
    }

    /// Relaxed (zero-frequency) modulus `E0` \[Pa\].
    #[getter]
    fn relaxed_modulus(&self) -> f64 {
        self.material.spectrum.relaxed_modulus()
    }

    /// Glassy (high-frequency) modulus `E_inf` \[Pa\].
    #[getter]
    fn glassy_modulus(&self) -> f64 {
        self.material.spectrum.glassy_modulus
    }

    /// Poisson ratio.
    #[getter]
    fn poisson(&self) -> f64 {
        self.material.poisson
    }

    /// Creep spectrum `[(C_k [1/Pa], tau_k [s]), ...]` (paper Eq. 2).
    #[getter]
    fn creep_spectrum(&self) -> Vec<(f64, f64)> {
        self.material
            .spectrum
            .terms
            .iter()
            .map(|t| (t.compliance, t.time))
            .collect()
    }

    /// The `[material]` section that builds this material, as JSON.
    fn section_json(&self) -> String {
        serde_json::to_string(&self.section).unwrap_or_default()
    }
}

/// The exact `creep_spectrum` section of a material.
fn creep_section(m: &Material) -> MaterialConfig {
    MaterialConfig {
        glassy_modulus: Some(m.spectrum.glassy_modulus),
        creep_spectrum: Some(
            m.spectrum
                .terms
                .iter()
                .map(|t| [t.compliance, t.time])
                .collect(),
        ),
        poisson: Some(m.poisson),
        ..bare_section(MaterialModel::CreepSpectrum)
    }
}

/// A `[material]` section of `model` with no keys yet.
fn bare_section(model: MaterialModel) -> MaterialConfig {
    MaterialConfig {
        model,
        relaxed_modulus: None,
        glassy_modulus: None,
        creep_time: None,
        relaxation_time: None,
        creep_spectrum: None,
        prony: None,
        poisson: None,
        file: None,
        wlf: None,
        wlf_range: None,
        frequency_range: None,
    }
}
